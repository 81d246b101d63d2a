#pragma once
// Counts every heap allocation a test program makes, on any thread: operator
// new (libstdc++ takes it from malloc), malloc, calloc, realloc and the aligned
// forms FFTW's fftw_malloc and its internal work buffers use (memalign,
// posix_memalign, aligned_alloc).  A program replaces these C entry points by
// defining them, and the dynamic linker then binds every library's calls (FFTW,
// libgomp, libstdc++) to them; each counts and forwards to glibc's allocator.
// Under AddressSanitizer, whose runtime owns these symbols, its allocation hook
// counts instead.
//
// Include in exactly one source file of a test program (it defines the entry
// points).  The counter is the program's one static: allocation calls reach a
// test only through these global entry points, so it cannot live anywhere else.
#include <doctest/doctest.h>
#include <omp.h>

#include <atomic>
#include <cerrno>
#include <cstddef>
#include <cstdlib>

namespace slipstrip_test {
// Constant-initialised, so safe to touch from the first allocation before main.
inline std::atomic<long>& allocation_counter() {
  static std::atomic<long> count{0};
  return count;
}
inline long allocations() { return allocation_counter().load(std::memory_order_relaxed); }
inline void count_allocation() { allocation_counter().fetch_add(1, std::memory_order_relaxed); }

// Runs `body` with `threads` OpenMP threads, the runtime's thread pool already
// started (its one start per process is not the code under test's).  Code that
// sizes per-thread memory at construction must be built inside body.
template <class Body>
void with_threads(int threads, Body body) {
  const int saved = omp_get_max_threads();
  omp_set_num_threads(threads);
  int started = 0;
#pragma omp parallel num_threads(threads) reduction(+ : started)
  started += 1;
  REQUIRE(started == threads);
  body();
  omp_set_num_threads(saved);
}
}  // namespace slipstrip_test

#if defined(__SANITIZE_ADDRESS__)
extern "C" void __sanitizer_malloc_hook(const volatile void*, std::size_t) { slipstrip_test::count_allocation(); }
#else
extern "C" {
// glibc's own allocator under its internal names (exported by libc.so.6).
void* __libc_malloc(std::size_t size);
void* __libc_calloc(std::size_t count, std::size_t size);
void* __libc_realloc(void* pointer, std::size_t size);
void* __libc_memalign(std::size_t alignment, std::size_t size);
void __libc_free(void* pointer);

void* malloc(std::size_t size) noexcept {
  slipstrip_test::count_allocation();
  return __libc_malloc(size);
}
void* calloc(std::size_t count, std::size_t size) noexcept {
  slipstrip_test::count_allocation();
  return __libc_calloc(count, size);
}
void* realloc(void* pointer, std::size_t size) noexcept {
  slipstrip_test::count_allocation();
  return __libc_realloc(pointer, size);
}
void* memalign(std::size_t alignment, std::size_t size) noexcept {
  slipstrip_test::count_allocation();
  return __libc_memalign(alignment, size);
}
void* aligned_alloc(std::size_t alignment, std::size_t size) noexcept {
  slipstrip_test::count_allocation();
  return __libc_memalign(alignment, size);
}
int posix_memalign(void** pointer, std::size_t alignment, std::size_t size) noexcept {
  slipstrip_test::count_allocation();
  void* p = __libc_memalign(alignment, size);
  if (!p) return ENOMEM;
  *pointer = p;
  return 0;
}
void free(void* pointer) noexcept { __libc_free(pointer); }
}
#endif
