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
  // > 1: time a 2D interface of nodes x nodes_z nodes (square spacing, L_x =
  // 4 m, L_z = 4 m nodes_z/nodes) instead (solver/simulation_3d.hpp).
  int nodes_z = 1;
  // --pairs: also a pair of different bodies at each height (inf: two
  // half-spaces) and plane, the in-plane one's time per step over the
  // identical pair's and the antiplane one's over the in-plane one's.
  bool dissimilar = false;
  // --half-space-pair: the operator of the pair of half-spaces (time.half_space_pair).
  HalfSpacePairOperator half_space_pair = HalfSpacePairOperator::combined;
  // --antiplane-pair: the operator of the antiplane pair of different finite strips or half-spaces
  // (time.antiplane_pair).
  AntiplanePairOperator antiplane_pair = AntiplanePairOperator::combined;
  HistoryAlgorithm history = HistoryAlgorithm::automatic;  // strip history algorithm  // cases whose estimated operator memory exceeds this are reported as skipped
};

// Times the full time step (history operator + FFTs + local friction solve)
// and the floor cost (two FFTs + the elementwise interface work) for each N
// and H/L = 0.025, 0.25 and the half-space (L = 4 m, beta = 0.25, Table S1
// friction).  Each case runs in a forked child so its peak resident memory
// (VmHWM) is its own.
// With options.nodes_z > 1 the rows are 2D interfaces: the full step of
// Simulation3d against its floor (two forward and two inverse 2D FFTs, the
// load magnitude, the batch predictor-corrector and the direction at every node).
int run_bench(const BenchOptions& options);

}  // namespace slipstrip
