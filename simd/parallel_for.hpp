#pragma once
// The hot loops' OpenMP threads: body(i) for every work item, in a parallel
// loop when more than one thread may run, else in a plain loop.  libgomp (GCC)
// allocates a new team at every parallel region that runs one thread (it keeps
// a team for the next region only when it has more than one), and the time
// loop does not allocate (tests/cpp/test_solver_step_allocation.cpp), so a
// one-thread run opens no region at all.  The items must be independent: the
// order in which threads take them is not the serial order.
#include <omp.h>

namespace slipstrip::simd {

// Calls body(i) for i = 0, ..., count - 1: statically scheduled in chunks of
// `chunk` items handed to the threads in turn (0: one contiguous share per
// thread).
template <class Body>
void parallel_for(long long count, Body&& body, long long chunk = 0) {
  const int threads = omp_get_max_threads();
  if (threads <= 1 || count <= 1) {
    for (long long i = 0; i < count; ++i) body(i);
    return;
  }
  if (chunk <= 0) chunk = (count + threads - 1) / threads;
#pragma omp parallel for schedule(static, chunk)
  for (long long i = 0; i < count; ++i) body(i);
}

}  // namespace slipstrip::simd
