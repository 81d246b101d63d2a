#pragma once
// CPU time of the whole process [s]: on a machine shared with other jobs the
// wall clock also counts the time spent waiting for a core, the CPU time of a
// one-thread run does not (it still feels shared caches).
#include <time.h>

namespace slipstrip::bench {

inline double process_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

}  // namespace slipstrip::bench
