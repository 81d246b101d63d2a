// The half-space body operator's slow exponentials advanced once per block
// (FaceHalfSpaceHistory, docs/theory.md §8.7, kernels/slow_block.hpp) against
// the same operator rotating every exponential every step (design.slow_block =
// 0, itself checked against the explicit convolution in
// test_kernels_face_half_space_push.cpp):
//   - the two hold the same coefficients (mode_kernel, bit for bit), and most
//     exponentials are slow;
//   - the same histories on both components for random complex inputs with a
//     slowly varying part, over many blocks, for several block lengths;
//   - a restart in the middle of a block continues bit for bit, and a restart
//     point of another block length is refused with the reason;
//   - the far field worked in batches of 8 steps gives the histories of the
//     same operator working it every step, bit for bit, also after resuming a
//     restart point that holds the far field at its own step (format 2) in the
//     middle of a batch.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <memory>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "kernels/face_half_space.hpp"
#include "kernels/fft.hpp"
#include "kernels/inplane_pair_history.hpp"

using namespace slipstrip;
using cplx = std::complex<double>;

namespace {

// One half-space body of Poisson ratio nu, `nodes` nodes 1.25 cm apart,
// beta = 0.3, slow block B (0: every exponential every step).
FaceHalfSpaceHistory body(double nu, int nodes, int slow_block) {
  const ElasticMaterial m{.poisson_ratio = nu};
  const double length = 0.0125 * nodes, dt = 0.3 * 0.0125 / m.shear_wave_speed();
  HalfSpaceOperatorDesign design;
  design.slow_block = slow_block;
  return FaceHalfSpaceHistory(m, length, nodes, dt, design);
}

// White noise plus a slowly varying part, so that the slow (long-memory)
// exponentials carry most of the history.
void random_inputs(std::mt19937& rng, int step, std::vector<cplx>& vx, std::vector<cplx>& vy) {
  std::normal_distribution<double> normal;
  for (std::size_t q = 0; q < vx.size(); ++q) {
    vx[q] = cplx(normal(rng), normal(rng)) + cplx(std::cos(1e-3 * step * (q + 1)), std::sin(7e-4 * step));
    vy[q] = cplx(normal(rng), normal(rng)) + cplx(std::sin(9e-4 * step), std::cos(5e-4 * step * (q + 1)));
  }
}

// max |a - b| over modes, steps and both components, relative to max |b|.
double compare(FaceHalfSpaceHistory& a, FaceHalfSpaceHistory& b, int steps, unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<cplx> vx(a.modes()), vy(a.modes());
  double worst = 0.0, largest = 0.0;
  for (int n = 0; n < steps; ++n) {
    random_inputs(rng, n, vx, vy);
    a.push(vx, vy);
    b.push(vx, vy);
    for (int q = 0; q < a.modes(); ++q) {
      worst = std::max({worst, std::abs(a.history_x()[q] - b.history_x()[q]), std::abs(a.history_y()[q] - b.history_y()[q])});
      largest = std::max({largest, std::abs(b.history_x()[q]), std::abs(b.history_y()[q])});
    }
  }
  return worst / largest;
}

}  // namespace

TEST_CASE("half-space face operator, slow block: same coefficients as rotating every exponential") {
  const int nodes = 32;
  const FaceHalfSpaceHistory blocked = body(0.3, nodes, HalfSpaceOperatorDesign{}.slow_block),
                             reference = body(0.3, nodes, 0);
  CHECK(reference.slow_exponentials() == 0);
  CHECK(blocked.slow_block() == HalfSpaceOperatorDesign{}.slow_block);
  CHECK(blocked.discrete_modes() == reference.discrete_modes());
  // Most exponentials reach down to decay rates far below 1/B per step.
  MESSAGE("slow exponentials: " << blocked.slow_exponentials() << " of " << blocked.discrete_modes());
  CHECK(blocked.slow_exponentials() > blocked.discrete_modes() / 2);
  for (int q : {1, 5, nodes / 2}) {
    const auto a = blocked.mode_kernel(q), b = reference.mode_kernel(q);
    CHECK(a.pole == b.pole);
    for (std::size_t e = 0; e < 3; ++e) {
      CHECK(a.static_weight[e] == b.static_weight[e]);
      CHECK(a.lag_weight[e] == b.lag_weight[e]);
      CHECK(a.pole_weight[e] == b.pole_weight[e]);
    }
  }
}

TEST_CASE("half-space face operator, slow block: same histories as rotating every exponential") {
  // Tolerance 1e-13 of the largest history value: the Taylor factor's
  // truncation is below 1.7e-16 relative (slow_taylor_error_bound), and the
  // two algorithms round differently (polynomials and moments over ~300
  // exponentials against one recursion each), each at ~1e-16 per operation;
  // the scalar operator's same comparison measures 1.8-2.6e-16.
  for (double nu : {0.25, 0.35})
    for (int block : {16, 64, 128}) {
      FaceHalfSpaceHistory blocked = body(nu, 32, block), reference = body(nu, 32, 0);
      REQUIRE(blocked.slow_exponentials() > 0);
      const double relative = compare(blocked, reference, 12 * 128 + 37, 17);
      CAPTURE(nu);
      CAPTURE(block);
      MESSAGE("nu = " << nu << ", B = " << block << ": blocked vs every step " << relative);
      CHECK(relative <= 1e-13);
    }
}

TEST_CASE("half-space face operator, slow block: a restart in the middle of a block continues bit for bit") {
  FaceHalfSpaceHistory a = body(0.3, 16, 32), b = body(0.3, 16, 32);
  std::mt19937 rng(5);
  std::vector<cplx> vx(a.modes()), vy(a.modes());
  int n = 0;
  for (; n < 3 * 32 + 11; ++n) {
    random_inputs(rng, n, vx, vy);
    a.push(vx, vy);
  }
  HistoryOperatorState state;
  a.save_into(state, "top.");
  b.restore_from(state, "top.");
  bool identical = true;
  for (; n < 6 * 32 + 5; ++n) {
    random_inputs(rng, n, vx, vy);
    a.push(vx, vy);
    b.push(vx, vy);
    for (int q = 0; q < a.modes(); ++q)
      identical = identical && a.history_x()[q] == b.history_x()[q] && a.history_y()[q] == b.history_y()[q];
  }
  CHECK(identical);
  // Another block length holds other states: refused, naming both lengths.
  FaceHalfSpaceHistory c = body(0.3, 16, 64);
  CHECK_THROWS_WITH_AS(c.restore_from(state, "top."),
                       doctest::Contains("slow block 32, this operator 64"), std::invalid_argument);
}

TEST_CASE("half-space face operator, slow block: a pair of different half-spaces in a closed loop") {
  // Two half-spaces of different materials coupled as the solver couples them
  // (InplanePairHistory: continuous tractions, slip = jump of u_x), the slip
  // rate at each step a nonlinear function of the pair's shear history and
  // normal stress (a stand-in for the friction solve), so that any difference
  // between the schemes feeds back.  The blocked pair against the every-step
  // pair over 6 blocks of 128 steps.  Tolerances: each step adds the
  // operators' round-off (~4e-16 of the largest value, test above), and the
  // static running sum integrates every slip-rate difference, so the history
  // difference grows like steps x 4e-16 = 3e-13 (768 steps; measured 4.2e-13):
  // 1e-11 of the largest shear history and normal stress.  The slip rate sees
  // these differences through tanh(./scale) with gain 1.5 (0.2 + 0.1), on
  // histories up to ~|h|/scale times the scale: at most 0.45 times their
  // relative difference times the largest |h|/scale (reported), with the same
  // 1e-11.
  const ElasticMaterial top{.poisson_ratio = 0.3};
  const ElasticMaterial bottom{.shear_modulus = 4.5e9, .poisson_ratio = 0.25, .density = 2400.0};
  const int nodes = 32, modes = nodes / 2 + 1, steps = 6 * 128;
  const double length = 0.4, dt = 0.25 * (length / nodes) / top.shear_wave_speed();
  HalfSpaceOperatorDesign every_step;
  every_step.slow_block = 0;
  InplanePairHistory blocked(std::make_unique<FaceHalfSpaceHistory>(top, length, nodes, dt),
                             std::make_unique<FaceHalfSpaceHistory>(bottom, length, nodes, dt));
  InplanePairHistory reference(std::make_unique<FaceHalfSpaceHistory>(top, length, nodes, dt, every_step),
                               std::make_unique<FaceHalfSpaceHistory>(bottom, length, nodes, dt, every_step));
  REQUIRE(blocked.period() == HalfSpaceOperatorDesign{}.slow_block);
  const double v0 = 1e-3, scale = blocked.radiation_damping() * v0;  // Pa
  struct Loop {
    InplanePairHistory& pair;
    std::vector<double> slip_rate, shear, normal;
    std::vector<cplx> spectrum;
  };
  const auto make = [&](InplanePairHistory& pair) {
    return Loop{pair, std::vector<double>(nodes, v0), std::vector<double>(nodes), std::vector<double>(nodes),
                std::vector<cplx>(modes)};
  };
  Loop a = make(blocked), b = make(reference);
  RealFft fft(nodes);
  double worst_shear = 0.0, largest_shear = 0.0, worst_normal = 0.0, largest_normal = 0.0, worst_rate = 0.0;
  for (int n = 0; n < steps; ++n) {
    for (Loop* loop : {&a, &b}) {
      fft.forward(loop->slip_rate, loop->spectrum);
      loop->pair.push(loop->spectrum);
      fft.inverse(loop->pair.history(), loop->shear);
      fft.inverse(loop->pair.normal_stress(), loop->normal);
      for (int i = 0; i < nodes; ++i) {
        const double x = length * i / nodes;
        loop->slip_rate[i] = v0 * (1.0 + 0.5 * std::sin(2.0 * std::numbers::pi * x / length + 0.01 * n)) *
                             (1.0 + 0.2 * std::tanh(loop->shear[i] / scale) + 0.1 * std::tanh(loop->normal[i] / scale));
      }
    }
    for (int i = 0; i < nodes; ++i) {
      worst_shear = std::max(worst_shear, std::abs(a.shear[i] - b.shear[i]));
      largest_shear = std::max(largest_shear, std::abs(b.shear[i]));
      worst_normal = std::max(worst_normal, std::abs(a.normal[i] - b.normal[i]));
      largest_normal = std::max(largest_normal, std::abs(b.normal[i]));
      worst_rate = std::max(worst_rate, std::abs(a.slip_rate[i] - b.slip_rate[i]));
    }
  }
  const double reach = std::max(largest_shear, largest_normal) / scale;
  MESSAGE("closed-loop pair, blocked vs every step: shear history " << worst_shear / largest_shear
          << ", normal stress " << worst_normal / largest_normal << ", slip rate " << worst_rate / v0
          << " v0; largest history / scale " << reach);
  // The normal stress did move (the bodies differ), so its coupling ran.
  CHECK(largest_normal > 1e-3 * scale);
  CHECK(worst_shear <= 1e-11 * largest_shear);
  CHECK(worst_normal <= 1e-11 * largest_normal);
  CHECK(worst_rate <= 0.45 * 1e-11 * reach * v0);
}

TEST_CASE("half-space face operator, far field in batches: every step's arithmetic, and format-2 restart points") {
  const ElasticMaterial m{.poisson_ratio = 0.3};
  const int nodes = 16;
  const double length = 0.0125 * nodes, dt = 0.3 * 0.0125 / m.shear_wave_speed();
  HalfSpaceOperatorDesign every_step;
  every_step.slow_block = 32;
  every_step.far_batch = 1;
  HalfSpaceOperatorDesign batched = every_step;
  batched.far_batch = 8;
  FaceHalfSpaceHistory a(m, length, nodes, dt, every_step), b(m, length, nodes, dt, batched);
  REQUIRE(a.far_batch() == 1);
  REQUIRE(b.far_batch() == 8);
  std::mt19937 rng(11);
  std::vector<cplx> vx(a.modes()), vy(a.modes());
  const auto same = [&] {
    for (int q = 0; q < a.modes(); ++q)
      if (a.history_x()[q] != b.history_x()[q] || a.history_y()[q] != b.history_y()[q]) return false;
    return true;
  };
  bool identical = true;
  int n = 0;
  for (; n < 2 * 32 + 19; ++n) {  // ends in the middle of a batch and of a block
    random_inputs(rng, n, vx, vy);
    a.push(vx, vy);
    b.push(vx, vy);
    identical = identical && same();
  }
  CHECK(identical);
  // Every step, the far field is at the current step: the state as format 2
  // held it (no batch outputs).
  HistoryOperatorState saved;
  a.save_into(saved, "top.");
  HistoryOperatorState format2;
  format2.kind = saved.kind;
  for (const auto& [name, value] : saved.counters)
    if (name != "top.far_batch") format2.counters.emplace_back(name, name == "top.format" ? 2 : value);
  for (const auto& array : saved.arrays)
    if (array.first.rfind("top.far_batch", 0) != 0) format2.arrays.push_back(array);
  FaceHalfSpaceHistory c(m, length, nodes, dt, batched);
  c.restore_from(format2, "top.");
  bool resumed = true;
  for (; n < 5 * 32 + 3; ++n) {
    random_inputs(rng, n, vx, vy);
    a.push(vx, vy);
    c.push(vx, vy);
    for (int q = 0; q < a.modes(); ++q)
      resumed = resumed && a.history_x()[q] == c.history_x()[q] && a.history_y()[q] == c.history_y()[q];
  }
  CHECK(resumed);
}
