// Microbenchmark of the half-space history operator alone (not a test):
// HalfSpaceHistory::push on a random slip-rate spectrum, L = 4 m, beta = 0.25,
// Table S1 material, as `slipstrip bench --heights inf` builds it.
//   bench_kernels_half_space [N] [threads] [steps] [slow_block] [taylor_terms] [slow_taylor_radius]
// (slow_block 0 = every exponential rotated every step; default: the reference design).
// Prints set-up time, us per push (wall clock and process CPU time divided by
// the thread count), exponentials per mode and operator memory.  On a shared
// machine the wall-clock figure includes time spent waiting for a core; the
// minimum over 5 repetitions is reported next to the median.
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <complex>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <random>
#include <vector>

#include "kernels/half_space_history.hpp"
#include "kernels/history_convolution.hpp"

using namespace slipstrip;

int main(int argc, char** argv) {
  const int nodes = argc > 1 ? std::atoi(argv[1]) : 2048;
  const int threads = argc > 2 ? std::atoi(argv[2]) : 1;
  const int steps = argc > 3 ? std::atoi(argv[3]) : 200;
  omp_set_num_threads(threads);
  const ElasticMaterial material;
  const double length = 4.0;
  const double dt = strip_time_step(material, HUGE_VAL, length / nodes, 0.25);
  HalfSpaceOperatorDesign design;  // the reference design, unless given
  if (argc > 4) design.slow_block = std::atoi(argv[4]);
  if (argc > 5) design.taylor_terms = std::atoi(argv[5]);
  if (argc > 6) design.slow_taylor_radius = std::atof(argv[6]);
  using clock = std::chrono::steady_clock;
  const auto t0 = clock::now();
  HalfSpaceHistory op(material, length, nodes, dt, design);
  const double setup_ms = std::chrono::duration<double, std::milli>(clock::now() - t0).count();
  std::mt19937 rng(1);
  std::normal_distribution<double> normal;
  std::vector<std::complex<double>> spectrum(op.modes());
  for (auto& s : spectrum) s = {normal(rng), normal(rng)};
  for (int i = 0; i < 20; ++i) op.push(spectrum);
  // Whole blocks: the slow exponentials are advanced once per block.
  const int block = std::max(1, op.slow_block());
  const int steps_timed = ((steps + block - 1) / block) * block;
  auto cpu_seconds = [] {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
  };
  std::vector<double> reps, cpu;
  for (int rep = 0; rep < 5; ++rep) {
    const auto t1 = clock::now();
    const double c1 = cpu_seconds();
    for (int i = 0; i < steps_timed; ++i) op.push(spectrum);
    reps.push_back(std::chrono::duration<double, std::micro>(clock::now() - t1).count() / steps_timed);
    cpu.push_back((cpu_seconds() - c1) * 1e6 / steps_timed / threads);
  }
  std::sort(reps.begin(), reps.end());
  std::sort(cpu.begin(), cpu.end());
  const auto s = op.stats();
  std::printf("N %d threads %d dt %.4g s, B %d, %d terms, radius %.3g: setup %.0f ms, push %.1f us (min) %.1f us (median), "
              "CPU/thread %.1f us (min), %zu exponentials (%.1f per mode, %zu slow), %zu stored lags, operator %.2f MiB\n",
              nodes, threads, dt, design.slow_block, design.taylor_terms, design.slow_taylor_radius, setup_ms,
              reps.front(), reps[2], cpu.front(), s.oscillators, double(s.oscillators) / (s.modes - 1),
              op.slow_exponentials(), s.direct_lags, s.memory_bytes / 1048576.0);
  return 0;
}
