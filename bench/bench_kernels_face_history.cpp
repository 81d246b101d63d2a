// CPU time per push() of one finite body's 2x2 history operator, block
// (FaceBlockHistory) and, optionally, modal (FaceModalHistory, the same
// operator), white-noise face velocities.  Usage:
//   bench_kernels_face_history NODES HEIGHT [STEPS] [DIRECT_BLOCK] [BLOCK] [MODAL_STEPS]
// L = 4 m, beta = 0.25, Table S1 material, driven outer face; one JSON line.
// Threads: OMP_NUM_THREADS.  Steps default to two blocks (the far-field update
// at its average rate); MODAL_STEPS = 0 (default) skips the modal operator.
// HEIGHT = inf: a half-space body (FaceHalfSpaceHistory) with its slow block
// BLOCK (default the design's; 0 rotates every exponential every step);
// DIRECT_BLOCK and MODAL_STEPS are then unused.
#include <chrono>
#include <cmath>
#include <complex>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

#include "bench/process_cpu_time.hpp"
#include "kernels/face_block_history.hpp"
#include "kernels/face_half_space.hpp"
#include "kernels/face_history.hpp"
#include "kernels/history_convolution.hpp"

using namespace slipstrip;

namespace {
double cpu_us_per_push(FaceHistory& op, int steps) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<std::vector<std::complex<double>>> inputs(16, std::vector<std::complex<double>>(op.modes()));
  for (auto& in : inputs)
    for (auto& x : in) x = {normal(rng), normal(rng)};
  const double t0 = bench::process_cpu_seconds();
  for (int n = 0; n < steps; ++n) op.push(inputs[n % inputs.size()], inputs[(n + 5) % inputs.size()]);
  return 1e6 * (bench::process_cpu_seconds() - t0) / steps;
}
}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s NODES HEIGHT [STEPS] [DIRECT_BLOCK] [BLOCK] [MODAL_STEPS]\n", argv[0]);
    return 2;
  }
  const int nodes = std::atoi(argv[1]);
  const double height = std::atof(argv[2]);
  int steps = argc > 3 ? std::atoi(argv[3]) : 0;
  FaceBlockDesign design;
  if (argc > 4) design.direct_block = std::atoi(argv[4]);
  if (argc > 5) design.block = std::atoi(argv[5]);
  const int modal_steps = argc > 6 ? std::atoi(argv[6]) : 0;
  ElasticMaterial material;
  const double length = 4.0, dx = length / nodes;
  const double dt = strip_time_step(material, height, dx, 0.25);
  const auto t0 = std::chrono::steady_clock::now();
  if (std::isinf(height)) {
    HalfSpaceOperatorDesign half_space;
    if (argc > 5) half_space.slow_block = std::atoi(argv[5]);
    FaceHalfSpaceHistory op(material, length, nodes, dt, half_space);
    const double setup = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (steps == 0) steps = 2 * op.period();
    const double us = cpu_us_per_push(op, steps);
    std::printf("{\"N\": %d, \"height\": null, \"exponentials\": %zu, \"slow_exponentials\": %zu, "
                "\"slow_block\": %d, \"steps\": %d, \"cpu_us_per_push\": %.2f, \"operator_mib\": %.1f, "
                "\"setup_s\": %.2f}\n",
                nodes, op.discrete_modes(), op.slow_exponentials(), op.slow_block(), steps, us,
                op.memory_bytes() / 1048576.0, setup);
    return 0;
  }
  FaceBlockHistory block(material, height, OuterFace::driven, length, nodes, dt, design);
  const double setup = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (steps == 0) steps = 2 * block.period();
  const double block_us = cpu_us_per_push(block, steps);
  double modal_us = 0.0;
  if (modal_steps > 0) {
    FaceModalHistory modal(material, height, OuterFace::driven, length, nodes, dt);
    modal_us = cpu_us_per_push(modal, modal_steps);
  }
  std::printf("{\"N\": %d, \"height\": %g, \"normal_modes\": %zu, \"block\": %d, \"direct_block\": %d, "
              "\"steps\": %d, \"block_cpu_us_per_push\": %.2f, \"modal_cpu_us_per_push\": %.2f, "
              "\"block_operator_mib\": %.1f, \"setup_s\": %.2f}\n",
              nodes, height, block.discrete_modes(), block.period(), design.direct_block, steps, block_us,
              modal_us, block.memory_bytes() / 1048576.0, setup);
  return 0;
}
