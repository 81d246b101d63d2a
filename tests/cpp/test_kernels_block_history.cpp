// The block history operator applies the same discrete operator as
// StripHistory (verified against the exact strip response, for passivity and
// for free ringing in the other kernel tests) by a different algorithm: FFT
// block convolutions for recent lags and NUFFT-moved normal-mode states for
// old ones.  So the reference here is StripHistory itself, driven by the same
// input, and the tolerance is the NUFFT's accuracy: 1e-10 relative to the
// largest history value (measured ~1e-13; round-off of the step-by-step
// rotations in StripHistory is of the same order over these run lengths).
// A second check goes around StripHistory: the prescribed-slip response
// against the numerical inverse Laplace transform of S(k, s; H).
#include <doctest/doctest.h>

#include <cmath>
#include <complex>
#include <numbers>
#include <random>
#include <vector>

#include "inverse_laplace.hpp"
#include "kernels/block_strip_history.hpp"
#include "kernels/history_convolution.hpp"
#include "kernels/strip_response.hpp"
#include "single_mode_drive.hpp"

using namespace slipstrip;
using cplx = std::complex<double>;
constexpr double pi = std::numbers::pi;

namespace {

struct Geometry {
  PlaneCondition plane;
  double height, length;
  int nodes;
  double beta;
};

// Max over all modes and steps of |block - modal|, relative to the largest
// |modal| seen, for a random (white) slip-rate spectrum: white input excites
// every normal mode, the hardest case for the far-field states.
double max_relative_difference(const Geometry& g, const BlockHistoryDesign& design, int steps,
                               int* block_out = nullptr) {
  ElasticMaterial material;
  material.plane = g.plane;
  const double dx = g.length / g.nodes;
  const double dt = strip_time_step(material, g.height, dx, g.beta);
  const auto kernels = compute_strip_kernels(material, g.height, g.length, g.nodes, dt);
  StripHistory modal(material, kernels);
  BlockStripHistory block(material, kernels, design);
  if (block_out) *block_out = block.block();
  REQUIRE(block.modes() == modal.modes());
  std::mt19937_64 rng(42);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<cplx> v(modal.modes());
  double worst = 0.0, scale = 0.0;
  for (int n = 0; n < steps; ++n) {
    for (auto& x : v) x = cplx(normal(rng), normal(rng));
    v[0] = v[0].real();
    modal.push(v);
    block.push(v);
    for (int q = 0; q < modal.modes(); ++q) {
      worst = std::max(worst, std::abs(block.history()[q] - modal.history()[q]));
      scale = std::max(scale, std::abs(modal.history()[q]));
    }
  }
  return worst / scale;
}

}  // namespace

TEST_CASE("block operator = modal operator, white input, many blocks") {
  // Small blocks (B = 64, 32, 16) put thousands of far-field updates and every
  // level boundary into a short run; the automatic block size is checked too.
  const std::vector<Geometry> cases = {
      {PlaneCondition::strain, 0.1, 0.8, 32, 0.25},
      {PlaneCondition::strain, 0.4, 0.8, 16, 0.3},
      {PlaneCondition::stress, 0.05, 1.0, 32, 0.25},
      {PlaneCondition::antiplane, 0.2, 0.8, 16, 0.3},
  };
  for (const auto& g : cases) {
    for (BlockHistoryDesign design : {BlockHistoryDesign{8, 64, 14}, BlockHistoryDesign{4, 16, 14},
                                      BlockHistoryDesign{8, 0, 14}}) {
      int block = 0;
      const double d = max_relative_difference(g, design, 6000, &block);
      MESSAGE("H = " << g.height << " N = " << g.nodes << " direct " << design.direct_block
                     << " B = " << block << ": max |block - modal| / max |modal| = " << d);
      CHECK(d < 1e-10);
    }
  }
}

TEST_CASE("block operator: prescribed single-mode slip vs the exact strip response") {
  // Same problem and tolerance as test_kernels_time_domain (50 round trips,
  // kH = 0.05, 0.5, 5, 128 steps per round trip, relative L2 <= 1e-3), now
  // through the block operator, with blocks small enough that the far field
  // carries most of the history.
  ElasticMaterial material;
  const double H = 0.1;
  for (double kH : {0.05, 0.5, 5.0}) {
    const double k = kH / H;
    const double length = 2 * pi / k;
    const double echo = 2 * H / material.shear_wave_speed();
    const double dt = echo / 128;
    const int steps = 50 * 128;
    const double rise = 2 * echo;
    const auto kernels = compute_strip_kernels(material, H, length, 4, dt);
    BlockStripHistory history(material, kernels, {8, 128, 14});
    const auto stress = testing::single_mode_stress(history, rise, steps);
    const auto reference = testing::inverse_laplace(
        [&](cplx s) { return -strip_response(material, H, k, s) * testing::bump_laplace(s, rise); },
        dt, 1 << 18, steps + 1);
    const double error = testing::relative_l2_difference(stress, reference);
    MESSAGE("kH = " << kH << ": relative L2 error " << error);
    CHECK(error < 1e-3);
  }
}

TEST_CASE("block operator rejects bad designs") {
  ElasticMaterial material;
  const double dt = strip_time_step(material, 0.1, 0.8 / 16, 0.25);
  const auto kernels = compute_strip_kernels(material, 0.1, 0.8, 16, dt);
  CHECK_THROWS_AS(BlockStripHistory(material, kernels, {6, 0, 14}), std::invalid_argument);
  CHECK_THROWS_AS(BlockStripHistory(material, kernels, {8, 8, 14}), std::invalid_argument);
  CHECK_THROWS_AS(BlockStripHistory(material, kernels, {8, 96, 14}), std::invalid_argument);
}
