#pragma once
// A set-up loop over Fourier modes, run in parallel (OpenMP), that honours the
// cancel check (CancelCheck, kernels/history_convolution.hpp).
//
// The modes' designs are independent, so they are computed in parallel and
// laid out afterwards by the caller.  `cancelled` may call into Python (the
// bindings), which only the thread that called this function may do: that
// thread polls it, the others see an atomic flag, and once it is set the
// remaining modes are skipped.
#include <omp.h>

#include <atomic>
#include <exception>
#include <string>

#include "kernels/history_convolution.hpp"

namespace slipstrip {

// Calls body(q) for q = first, ..., count - 1 (dynamic schedule: the modes'
// costs differ).  Throws SetupCancelled("set-up cancelled during <where>") if
// `cancelled` said so.  An exception thrown by body is not rethrown: the text
// of the first one is returned (empty when every mode succeeded), for the
// caller to report with its own context.
template <class Body>
std::string for_each_mode_in_parallel(int first, int count, const CancelCheck& cancelled, const char* where,
                                      Body&& body) {
  std::string failure;
  std::atomic<bool> cancel_seen{false};
#pragma omp parallel for schedule(dynamic)
  for (int q = first; q < count; ++q) {
    if (omp_get_thread_num() == 0 && cancelled && !cancel_seen.load(std::memory_order_relaxed) && cancelled())
      cancel_seen.store(true);
    if (cancel_seen.load(std::memory_order_relaxed)) continue;
    try {
      body(q);
    } catch (const std::exception& ex) {
#pragma omp critical(slipstrip_mode_parallel_failure)
      if (failure.empty()) failure = ex.what();
    }
  }
  if (cancel_seen.load()) throw SetupCancelled(std::string("set-up cancelled during ") + where);
  return failure;
}

}  // namespace slipstrip
