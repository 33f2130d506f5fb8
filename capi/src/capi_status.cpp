#include "capi_status.h"

#include <atomic>
#include <mutex>
#include <new>
#include <stdexcept>

namespace incise::capi {

namespace {

thread_local std::string last_error;

// The hook and its user pointer change together under the mutex; callers read them under it too (a copy,
// then the call outside the lock).
std::mutex hook_mutex;
incise_log_fn hook = nullptr;
void* hook_user = nullptr;

void sendToHook(incise_log_level level, const std::string& text) noexcept {
  incise_log_fn fn;
  void* user;
  {
    std::lock_guard lock(hook_mutex);
    fn = hook, user = hook_user;
  }
  if (fn) fn(static_cast<uint32_t>(level), text.c_str(), user);
}

}  // namespace

incise_status fail(const char* function, incise_status detail, const std::string& what) noexcept {
  try {
    last_error = std::string(function) + ": " + what;
  } catch (...) {  // no room for the message: keep a fixed one
    last_error.clear();
  }
  sendToHook(INCISE_LOG_ERROR, last_error);
  return INCISE_FAILURE | detail;
}

incise_status failWithCurrent(const char* function, InvalidArgument invalid) noexcept {
  try {
    throw;
  } catch (const std::bad_alloc&) {
    return fail(function, INCISE_OUT_OF_MEMORY, "out of memory");
  } catch (const std::invalid_argument& e) {
    return fail(function, invalid == InvalidArgument::Parameter ? INCISE_INVALID_PARAMETER : INCISE_BAD_INPUT,
                e.what());
  } catch (const std::runtime_error& e) {  // files, scenarios, meshes, traces: what and where
    return fail(function, INCISE_BAD_INPUT, e.what());
  } catch (const std::exception& e) {
    return fail(function, INCISE_INTERNAL_ERROR, e.what());
  } catch (...) {
    return fail(function, INCISE_INTERNAL_ERROR, "an unknown exception");
  }
}

void warn(const std::string& text) noexcept { sendToHook(INCISE_LOG_WARNING, text); }

}  // namespace incise::capi

extern "C" {

INCISE_API const char* incise_last_error(void) { return incise::capi::last_error.c_str(); }

INCISE_API void incise_set_log(incise_log_fn fn, void* user) {
  std::lock_guard lock(incise::capi::hook_mutex);
  incise::capi::hook = fn;
  incise::capi::hook_user = user;
}

}  // extern "C"
