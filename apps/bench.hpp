#pragma once
#include <limits>
#include <vector>

#include "config/simulation_config.hpp"

namespace slipstrip {

struct BenchOptions {
  bool json = false;
  std::vector<int> nodes = {256, 512, 1024, 2048, 4096, 8192, 16384};
  int steps = 200;
  int threads = 1;
  std::vector<double> heights = {0.1, 1.0, std::numeric_limits<double>::infinity()};  // [m]; inf = half-space
  double max_operator_gib = 6.0;
  // Plane conditions timed at each N and height (--planes strain,antiplane
  // adds the antiplane rows and a line with the antiplane/in-plane ratio).
  std::vector<PlaneCondition> planes = {PlaneCondition::strain};
  HistoryAlgorithm history = HistoryAlgorithm::automatic;  // strip history algorithm  // cases whose estimated operator memory exceeds this are reported as skipped
};

// Times the full time step (history operator + FFTs + local friction solve)
// and the floor cost (two FFTs + the elementwise interface work) for each N
// and H/L = 0.025, 0.25 and the half-space (L = 4 m, beta = 0.25, Table S1
// friction).  Each case runs in a forked child so its peak resident memory
// (VmHWM) is its own.
int run_bench(const BenchOptions& options);

}  // namespace slipstrip
