// The counting allocator of alloc_counter.h: replaces operator new / delete and (without sanitizers, whose
// runtimes own malloc) the malloc family for the whole test executable that links this file; counts only on
// threads inside a CountAllocations scope. Memory comes from glibc as before (__libc_malloc and friends,
// or the sanitizer's malloc), so nothing else changes.
#include "alloc_counter.h"

#include <execinfo.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <new>

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define INCISE_ALLOC_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
#define INCISE_ALLOC_SANITIZED 1
#endif
#endif

namespace incise::test {
namespace {

thread_local bool counting = false;
thread_local bool in_hook = false;  // inside a counted call (backtrace() may allocate; new calls malloc)
thread_local AllocationCount count;
int trace_left = -1;  // INCISE_ALLOC_TRACE, read at the first counted allocation

void traceStack(std::size_t bytes) noexcept {
  if (trace_left < 0) {
    const char* env = std::getenv("INCISE_ALLOC_TRACE");
    trace_left = env ? std::atoi(env) : 0;
  }
  if (trace_left == 0) return;
  --trace_left;
  void* frames[40];
  const int n = backtrace(frames, 40);
  char line[64];
  const int len = std::snprintf(line, sizeof line, "allocation of %zu bytes:\n", bytes);
  if (len > 0) (void)!write(2, line, static_cast<std::size_t>(len));
  backtrace_symbols_fd(frames, n, 2);
}

// Called by every hook before it allocates; returns whether the caller must clear in_hook afterwards.
bool enterAllocation(std::size_t bytes) noexcept {
  if (in_hook) return false;
  in_hook = true;
  if (counting) {
    ++count.calls;
    count.bytes += static_cast<std::int64_t>(bytes);
    traceStack(bytes);
  }
  return true;
}
void leaveAllocation(bool entered) noexcept {
  if (entered) in_hook = false;
}

}  // namespace

AllocationCount allocationsOnThisThread() noexcept { return count; }
void resetAllocationCount() noexcept { count = {}; }
bool countsMalloc() noexcept {
#ifdef INCISE_ALLOC_SANITIZED
  return false;
#else
  return true;
#endif
}

CountAllocations::CountAllocations(bool on) noexcept : was_(counting) { counting = on; }
CountAllocations::~CountAllocations() { counting = was_; }

}  // namespace incise::test

namespace {

using incise::test::enterAllocation;
using incise::test::leaveAllocation;

void* newBytes(std::size_t bytes, std::size_t alignment, bool nothrow) {
  const bool entered = enterAllocation(bytes);
  void* p = alignment > alignof(std::max_align_t)
                ? std::aligned_alloc(alignment, (bytes + alignment - 1) / alignment * alignment)
                : std::malloc(bytes ? bytes : 1);
  leaveAllocation(entered);
  if (!p && !nothrow) throw std::bad_alloc();
  return p;
}

}  // namespace

void* operator new(std::size_t n) { return newBytes(n, 0, false); }
void* operator new[](std::size_t n) { return newBytes(n, 0, false); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept { return newBytes(n, 0, true); }
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept { return newBytes(n, 0, true); }
void* operator new(std::size_t n, std::align_val_t a) { return newBytes(n, static_cast<std::size_t>(a), false); }
void* operator new[](std::size_t n, std::align_val_t a) { return newBytes(n, static_cast<std::size_t>(a), false); }
void* operator new(std::size_t n, std::align_val_t a, const std::nothrow_t&) noexcept {
  return newBytes(n, static_cast<std::size_t>(a), true);
}
void* operator new[](std::size_t n, std::align_val_t a, const std::nothrow_t&) noexcept {
  return newBytes(n, static_cast<std::size_t>(a), true);
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }

#ifndef INCISE_ALLOC_SANITIZED
// The malloc family (Eigen's aligned storage and C code call it directly): glibc's own entry points
// underneath.
extern "C" {
void* __libc_malloc(std::size_t size);
void* __libc_calloc(std::size_t count, std::size_t size);
void* __libc_realloc(void* p, std::size_t size);
void* __libc_memalign(std::size_t alignment, std::size_t size);

void* malloc(std::size_t size) {
  const bool entered = enterAllocation(size);
  void* p = __libc_malloc(size);
  leaveAllocation(entered);
  return p;
}
void* calloc(std::size_t count, std::size_t size) {
  const bool entered = enterAllocation(count * size);
  void* p = __libc_calloc(count, size);
  leaveAllocation(entered);
  return p;
}
void* realloc(void* old, std::size_t size) {
  const bool entered = enterAllocation(size);
  void* p = __libc_realloc(old, size);
  leaveAllocation(entered);
  return p;
}
void* memalign(std::size_t alignment, std::size_t size) {
  const bool entered = enterAllocation(size);
  void* p = __libc_memalign(alignment, size);
  leaveAllocation(entered);
  return p;
}
void* aligned_alloc(std::size_t alignment, std::size_t size) { return memalign(alignment, size); }
int posix_memalign(void** out, std::size_t alignment, std::size_t size) {
  void* p = memalign(alignment, size);
  if (!p) return ENOMEM;
  *out = p;
  return 0;
}
}
#endif
