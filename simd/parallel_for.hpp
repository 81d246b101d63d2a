#pragma once
// The hot loops' OpenMP threads: body(i) for every work item, in a parallel
// loop when more than one thread may run, else in a plain loop.  libgomp (GCC)
// allocates a new team at every parallel region that runs one thread (it keeps
// a team for the next region only when it has more than one), and the time
// loop does not allocate (tests/cpp/test_solver_step_allocation.cpp), so a
// one-thread run opens no region at all.  The items must be independent: the
// order in which threads take them is not the serial order.
//
// Both paths run the items through one compiled function (run_items, never
// inlined).  Were the body inlined into the plain loop and compiled again
// inside the parallel region, the compiler could contract a*b + c into a fused
// multiply-add in one copy and not in the other (GCC's default
// -ffp-contract=fast), and a run's last bits would depend on the thread count
// (measured: the modal strip operator's push differed in 189 of 200 modes
// between one and two threads).
#include <omp.h>

#include <algorithm>

namespace slipstrip::simd {

namespace detail {

template <class Body>
[[gnu::noinline]] void run_items(long long begin, long long end, Body& body) {
  for (long long i = begin; i < end; ++i) body(i);
}

}  // namespace detail

// Calls body(i) for i = 0, ..., count - 1: statically scheduled in chunks of
// `chunk` items handed to the threads in turn (0: one contiguous share per
// thread).
template <class Body>
void parallel_for(long long count, Body&& body, long long chunk = 0) {
  const int threads = omp_get_max_threads();
  if (threads <= 1 || count <= 1) {
    detail::run_items(0, count, body);
    return;
  }
  if (chunk <= 0) chunk = (count + threads - 1) / threads;
  const long long chunks = (count + chunk - 1) / chunk;
#pragma omp parallel for schedule(static, 1)
  for (long long c = 0; c < chunks; ++c) detail::run_items(c * chunk, std::min(count, (c + 1) * chunk), body);
}

}  // namespace slipstrip::simd
