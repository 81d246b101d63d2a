// The whole solver with the block history algorithm against the whole solver
// with the modal one (time.history = "block" vs "modal").  The modal solver is
// the verified one (growth rates, Lc, dt^2 convergence, free ringing: the other
// test_solver_* files); the two apply the same discrete operator, so every field
// must agree to the block operator's round-off (~1e-13 per history value,
// tests/cpp/test_kernels_block_history.cpp) amplified by the dynamics.
// Tolerance 1e-8 relative to the field's maximum: over these runs the unstable
// modes grow by at most ~e^6, so 1e-13 differences stay below ~1e-10; a wrong
// lag, block boundary or far-field phase would show up at O(1).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "solver/simulation.hpp"
#include "kernels/block_strip_history.hpp"
#include "field_test_helpers.hpp"

using namespace slipstrip;

namespace {

// Largest difference over the whole run, relative to the largest value over
// the whole run (a field that passes through zero has no per-step scale).
struct RunDifference {
  double difference = 0, scale = 0;
  void add(std::span<const double> block, std::span<const double> modal) {
    difference = std::max(difference, max_abs_difference(block, modal));
    scale = std::max(scale, max_abs(modal));
  }
  double relative() const { return difference / scale; }
};

struct Differences {
  double slip_rate, shear_stress, slip, state;
};

Differences run_both(SimulationConfig config, int steps) {
  config.time.history = HistoryAlgorithm::modal;
  Simulation modal(config);
  config.time.history = HistoryAlgorithm::block;
  Simulation block(config);
  REQUIRE(dynamic_cast<const BlockStripHistory*>(&block.history_operator()) != nullptr);
  REQUIRE(dynamic_cast<const BlockStripHistory*>(&modal.history_operator()) == nullptr);
  RunDifference slip_rate, shear_stress, slip, state;
  for (int n = 0; n < steps; ++n) {
    modal.step();
    block.step();
    slip_rate.add(block.slip_rate(), modal.slip_rate());
    shear_stress.add(block.shear_stress(), modal.shear_stress());
    slip.add(block.slip(), modal.slip());
    state.add(block.state(), modal.state());
  }
  return {slip_rate.relative(), shear_stress.relative(), slip.relative(), state.relative()};
}

}  // namespace

TEST_CASE("rate-and-state run: block and modal history give the same fields") {
  // Table S1 friction, H = 0.1 m, L = 0.8 m (above Lc: unstable modes grow),
  // noisy initial state; 4000 steps span ~8 blocks of the automatic size.
  SimulationConfig c;
  c.geometry = {0.8, 0.1, 64};
  c.initial.noise_amplitude = 1e-3;
  c.time.beta = 0.25;
  const auto d = run_both(c, 4000);
  MESSAGE("max relative differences: slip_rate " << d.slip_rate << ", shear_stress " << d.shear_stress
                                                 << ", slip " << d.slip << ", state " << d.state);
  CHECK(d.slip_rate < 1e-8);
  CHECK(d.shear_stress < 1e-8);
  CHECK(d.slip < 1e-8);
  CHECK(d.state < 1e-8);
}

TEST_CASE("free interface, thick strip: block and modal history give the same ringing") {
  // A frictionless interface rings forever (lossless strips): the far-field
  // normal-mode states carry the whole history after the first block.
  SimulationConfig c;
  c.geometry = {0.4, 0.4, 32};
  c.interface.law = InterfaceLawName::free;
  c.interface.profile = TimeProfile::bump;
  c.interface.stress_amplitude = 1e5;
  c.interface.pulse_width = 0.05;
  c.time.beta = 0.25;
  const auto d = run_both(c, 20000);
  MESSAGE("max relative differences: slip_rate " << d.slip_rate << ", shear_stress "
                                                 << d.shear_stress << ", slip " << d.slip);
  CHECK(d.slip_rate < 1e-8);
  CHECK(d.shear_stress < 1e-8);
  CHECK(d.slip < 1e-8);
}

TEST_CASE("in-plane dissimilar pair: block and modal body operators give the same fields") {
  // Each finite body's 2x2 operator (kernels/face_block_history.hpp vs
  // kernels/face_history.hpp), inside the pair's normal-stress coupling: the
  // shear fields and the varying normal stress agree to the block operator's
  // round-off (~2e-12 per history value, test_kernels_face_block_history)
  // amplified by the growing modes, as above.  A thin slider (H = 0.05 m) on a
  // stiffer, denser base (H = 0.1 m, 2 mu, 2 rho) with a noisy initial state;
  // 3000 steps span ~24 blocks of 64 and ~12 of 128.
  SimulationConfig c;
  c.geometry = {0.8, 0.05, 64};
  c.initial.noise_amplitude = 1e-3;
  c.time.beta = 0.25;
  c.bottom.body = BodyKind::elastic;
  c.bottom.shear_modulus = 2.0 * c.material.shear_modulus;
  c.bottom.density = 2.0 * c.material.density;
  c.bottom.poisson_ratio = c.material.poisson_ratio;
  c.bottom.height = 0.1;
  c.time.history = HistoryAlgorithm::modal;
  Simulation modal(c);
  c.time.history = HistoryAlgorithm::block;
  Simulation block(c);
  REQUIRE(block.variable_normal_stress());
  RunDifference slip_rate, shear_stress, normal_stress, state;
  for (int n = 0; n < 3000; ++n) {
    modal.step();
    block.step();
    slip_rate.add(block.slip_rate(), modal.slip_rate());
    shear_stress.add(block.shear_stress(), modal.shear_stress());
    state.add(block.state(), modal.state());
    // The perturbation of sigma (sigma0 = 2 MPa would hide it).
    std::vector<double> sb(block.normal_stress().begin(), block.normal_stress().end());
    std::vector<double> sm(modal.normal_stress().begin(), modal.normal_stress().end());
    for (auto& s : sb) s -= c.loading.normal_stress;
    for (auto& s : sm) s -= c.loading.normal_stress;
    normal_stress.add(sb, sm);
  }
  MESSAGE("max relative differences: slip_rate " << slip_rate.relative() << ", shear_stress "
                                                 << shear_stress.relative() << ", normal stress perturbation "
                                                 << normal_stress.relative() << ", state " << state.relative());
  CHECK(normal_stress.scale > 0.0);
  CHECK(slip_rate.relative() < 1e-8);
  CHECK(shear_stress.relative() < 1e-8);
  CHECK(normal_stress.relative() < 1e-8);
  CHECK(state.relative() < 1e-8);
}
