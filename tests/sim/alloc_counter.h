// Test support: counts the heap allocations the calling thread makes while a CountAllocations scope is
// open. The counting operator new / operator delete (every form) and, outside the sanitizer builds, malloc,
// calloc, realloc, aligned_alloc, posix_memalign and memalign are defined once, in alloc_counter.cpp, which
// only the allocation test's own executable links (they replace the C++ runtime's and glibc's for the whole
// process). A thread-local flag keeps other threads' allocations out of the count.
//
// With INCISE_ALLOC_TRACE=N in the environment, the stacks of the first N counted allocations are printed
// to stderr (glibc's backtrace_symbols_fd): where an allocation on the sim thread comes from.
#pragma once

#include <cstddef>
#include <cstdint>

namespace incise::test {

struct AllocationCount {
  std::int64_t calls = 0;  // operator new, malloc, calloc, realloc (growing or new), aligned forms
  std::int64_t bytes = 0;
};

// This thread's count so far (since the last reset).
AllocationCount allocationsOnThisThread() noexcept;
void resetAllocationCount() noexcept;
// Whether the malloc family is counted too (false under ASan/TSan, whose runtimes own malloc).
bool countsMalloc() noexcept;

// While alive (and `on`), this thread's allocations are counted.
class CountAllocations {
 public:
  explicit CountAllocations(bool on = true) noexcept;
  ~CountAllocations();
  CountAllocations(const CountAllocations&) = delete;
  CountAllocations& operator=(const CountAllocations&) = delete;

 private:
  bool was_;
};

}  // namespace incise::test
