// Time per push() of the two exact strip history operators, modal
// (StripHistory, O(H/dx) per mode) and block (BlockStripHistory, O(log^2)),
// on the same kernels, white-noise input.  Usage:
//   bench_kernels_history NODES HEIGHT [STEPS] [DIRECT_BLOCK] [BLOCK] [PLANE]
// L = 4 m, beta = 0.25, Table S1 material, PLANE strain (default) or
// antiplane; prints one JSON line: wall and CPU time per push (the CPU time
// of the process is the figure to read on a shared machine).  Threads:
// OMP_NUM_THREADS.  Steps default to two blocks so the far-field update is
// included at its average rate.
#include <chrono>
#include <complex>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "bench/process_cpu_time.hpp"
#include "kernels/block_strip_history.hpp"
#include "kernels/history_convolution.hpp"

using namespace slipstrip;

namespace {
struct PushTimes {
  double wall_us, cpu_us;
};

PushTimes time_pushes(HistoryOperator& op, int steps) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<std::complex<double>> v(op.modes());
  std::vector<std::vector<std::complex<double>>> inputs(16, v);
  for (auto& in : inputs)
    for (auto& x : in) x = {normal(rng), normal(rng)};
  const auto t0 = std::chrono::steady_clock::now();
  const double cpu0 = bench::process_cpu_seconds();
  for (int n = 0; n < steps; ++n) op.push(inputs[n % inputs.size()]);
  return {std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count() / steps,
          1e6 * (bench::process_cpu_seconds() - cpu0) / steps};
}
}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s NODES HEIGHT [STEPS] [DIRECT_BLOCK] [BLOCK] [PLANE]\n", argv[0]);
    return 2;
  }
  const int nodes = std::atoi(argv[1]);
  const double height = std::atof(argv[2]);
  int steps = argc > 3 ? std::atoi(argv[3]) : 0;
  BlockHistoryDesign design;
  if (argc > 4) design.direct_block = std::atoi(argv[4]);
  if (argc > 5) design.block = std::atoi(argv[5]);
  ElasticMaterial material;
  if (argc > 6 && std::string(argv[6]) == "antiplane") material.plane = PlaneCondition::antiplane;
  const double length = 4.0, dx = length / nodes;
  const double dt = strip_time_step(material, height, dx, 0.25);
  const auto kernels = compute_strip_kernels(material, height, length, nodes, dt);
  auto t0 = std::chrono::steady_clock::now();
  BlockStripHistory block(material, kernels, design);
  const double block_setup = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (steps == 0) steps = 2 * block.block();
  const PushTimes block_us = time_pushes(block, steps);
  const auto block_stats = block.stats();
  StripHistory modal(material, kernels);
  const PushTimes modal_us = time_pushes(modal, std::min(steps, 400));
  std::printf("{\"N\": %d, \"height\": %g, \"oscillators\": %zu, \"block\": %d, \"direct_block\": %d, "
              "\"steps\": %d, \"block_us_per_push\": %.2f, \"modal_us_per_push\": %.2f, "
              "\"block_cpu_us_per_push\": %.2f, \"modal_cpu_us_per_push\": %.2f, "
              "\"block_operator_mib\": %.1f, \"modal_operator_mib\": %.1f, \"block_setup_s\": %.2f}\n",
              nodes, height, block_stats.oscillators, block.block(), design.direct_block, steps, block_us.wall_us,
              modal_us.wall_us, block_us.cpu_us, modal_us.cpu_us, block_stats.memory_bytes / 1048576.0, modal.stats().memory_bytes / 1048576.0,
              block_setup);
  return 0;
}
