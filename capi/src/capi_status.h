// The C API's errors (incise.h): every exported function runs its body through `guarded`, which catches
// every C++ exception and turns it into an incise_status with the message kept per thread for
// incise_last_error() and sent to the log hook. Threads: any (the message is thread-local, the hook an
// atomic pair). Failure: never throws.
#pragma once

#include <exception>
#include <string>

#include "incise/incise.h"

namespace incise::capi {

// What a std::invalid_argument means where it was thrown: a parameter of the call (a def's value), or input
// read from a file (a scenario's or a trace's contents).
enum class InvalidArgument : std::uint8_t { Parameter, Input };

// Records the failure (message "function: what") and returns INCISE_FAILURE | detail.
incise_status fail(const char* function, incise_status detail, const std::string& what) noexcept;
// The status and message for the exception in flight (called from a catch block).
incise_status failWithCurrent(const char* function, InvalidArgument invalid) noexcept;
// A warning to the log hook (no status).
void warn(const std::string& text) noexcept;

// Runs body() (which returns an incise_status) and turns any exception into a failure.
template <typename Body>
incise_status guarded(const char* function, InvalidArgument invalid, Body&& body) noexcept {
  try {
    return body();
  } catch (...) {
    return failWithCurrent(function, invalid);
  }
}

}  // namespace incise::capi
