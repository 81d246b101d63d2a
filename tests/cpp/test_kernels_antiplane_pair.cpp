// One combined history operator for a bonded pair of two different finite
// antiplane strips (kernels/antiplane_pair_modes.hpp, docs/bodies.md):
//   * the mode finder: identical bodies give antiplane_strip_modes' shear
//     family; every root is a sign change of D; one root between consecutive
//     poles; residues against a finite-difference limit of (s^2 + omega^2) K_c;
//   * the comb identity of two strips: the uniform mode's exact kernel plus
//     the k = 0 modes below Nyquist = the constant 2 eta at every lag;
//   * identical bodies: the combined operator = the identical pair's (modal, block);
//   * a general pair under prescribed slip against the inverse Laplace
//     transform of K_c (converging with dt), and against TwoBodyHistory;
//   * passivity (Re Z_d > 0 outside |z| = 1, weights <= 0, free ringing);
//   * a restart in the middle of a block, bit for bit; no allocation in push().
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <memory>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "allocation_counter.hpp"
#include "inverse_laplace.hpp"
#include "kernels/antiplane_pair_modes.hpp"
#include "kernels/antiplane_response.hpp"
#include "kernels/block_strip_history.hpp"
#include "kernels/history_convolution.hpp"
#include "kernels/two_body_history.hpp"
#include "single_mode_drive.hpp"
#include "white_noise.hpp"

using namespace slipstrip;
using cplx = std::complex<double>;
constexpr double pi = std::numbers::pi;

namespace {

ElasticMaterial sh(double mu, double rho) {
  ElasticMaterial m;
  m.shear_modulus = mu;
  m.density = rho;
  m.plane = PlaneCondition::antiplane;
  return m;
}

// A general pair: top mu = 3e9, rho = 1200, H = 0.1 m; bottom
// 2x mu, 1.3x rho, H = 0.23 m (different wave speeds, impedances, heights).
const ElasticMaterial kTop = sh(3e9, 1200), kBottom = sh(6e9, 1560);
constexpr double kTopHeight = 0.1, kBottomHeight = 0.23;

struct Pair {
  AntiplaneStrip top, bottom;
  double dt;
  double length;
  int nodes;
  StripKernels kernels() const { return compute_antiplane_pair_kernels(top, bottom, length, nodes, dt); }
  StripPairConstants constants() const { return antiplane_pair_constants(top, bottom, dt); }
};

// The general pair at a common step (two_body_time_step rounds the bottom height).
Pair general_pair(double length, int nodes, double beta) {
  // Up to 5 % rounding of the bottom height: the tests need a common step, not this exact height.
  const auto timing = two_body_time_step(kTop, kTopHeight, kBottom, kBottomHeight, length / nodes, beta, 0.05);
  return {{kTop, kTopHeight}, {kBottom, timing.bottom_height}, timing.time_step, length, nodes};
}

std::unique_ptr<HistoryOperator> combined(const Pair& p, bool block, BlockHistoryDesign design = {}) {
  if (block) return std::make_unique<BlockStripHistory>(p.constants(), p.kernels(), design);
  return std::make_unique<StripHistory>(p.constants(), p.kernels());
}

TwoBodyHistory bodies(const Pair& p) {
  return TwoBodyHistory(
      std::make_unique<StripHistory>(p.top.material, p.top.height, p.length, p.nodes, p.dt),
      std::make_unique<StripHistory>(p.bottom.material, p.bottom.height, p.length, p.nodes, p.dt));
}

}  // namespace

TEST_CASE("antiplane pair modes: identical bodies give antiplane_strip_modes' shear family") {
  const auto m = sh(9e9, 1200);
  const double H = 0.1;
  const AntiplaneStrip body{m, H};
  const double max_frequency = 300 * m.shear_wave_speed() / H;
  double worst_frequency = 0, worst_weight = 0;
  for (double k : {0.0, 1.0, 30.0, 400.0, 3000.0}) {
    std::vector<StripMode> expected;
    for (const auto& mode : antiplane_strip_modes(m, H, k, max_frequency))
      if (mode.family == ModeFamily::shear) expected.push_back(mode);
    if (k == 0.0)  // antiplane_strip_modes lists none at k = 0 (the comb alone): the shear family's limit
      for (int j = 1; m.shear_wave_speed() * j * pi / H <= max_frequency; ++j)
        expected.push_back({m.shear_wave_speed() * j * pi / H, -(m.shear_modulus / H), ModeFamily::shear, j});
    const auto found = antiplane_pair_modes(body, body, k, max_frequency);
    REQUIRE(found.size() == expected.size());
    for (std::size_t i = 0; i < found.size(); ++i) {
      worst_frequency = std::max(worst_frequency, std::abs(found[i].frequency / expected[i].frequency - 1));
      worst_weight = std::max(worst_weight, std::abs(found[i].weight / expected[i].weight - 1));
    }
  }
  MESSAGE("identical bodies: worst relative frequency " << worst_frequency << ", weight " << worst_weight);
  // The same closed forms (the common poles and their residues), to rounding.
  CHECK(worst_frequency <= 1e-12);
  CHECK(worst_weight <= 1e-12);
}

TEST_CASE("antiplane pair modes: roots of D, one between consecutive poles, residues by finite differences") {
  const AntiplaneStrip top{kTop, kTopHeight}, bottom{kBottom, kBottomHeight};
  const double max_frequency = 200 * kTop.shear_wave_speed() / kTopHeight;
  double worst_residue = 0;
  std::size_t total = 0;
  for (double k : {0.0, 2.0, 25.0, 300.0, 4000.0}) {
    const auto modes = antiplane_pair_modes(top, bottom, k, max_frequency);
    const auto poles = antiplane_pair_dispersion_poles(top, bottom, k, max_frequency);
    INFO("k = " << k << ": " << modes.size() << " modes, " << poles.size() << " poles of D");
    // No two echo frequencies of these bodies coincide (c_t/H_t : c_b/H_b is
    // irrational here), so every mode is a root of D, one per bracket.
    CHECK((modes.size() == poles.size() || modes.size() == poles.size() + 1));
    for (std::size_t i = 0; i < poles.size(); ++i) {
      const double below = i == 0 ? 0.0 : poles[i - 1];
      const auto inside = std::count_if(modes.begin(), modes.end(), [&](const StripMode& m) {
        return m.frequency > below && m.frequency < poles[i];
      });
      CHECK(inside == 1);
    }
    double largest = 0;
    for (const auto& mode : modes) largest = std::max(largest, std::abs(mode.weight) * mode.frequency * mode.frequency);
    for (const auto& mode : modes) {
      // A sign change of D across the root (D decreases): the root is exact to
      // far better than 1e-9 relative, and no pole is that close.
      const double w = mode.frequency;
      CHECK(antiplane_pair_dispersion(top, bottom, k, w * (1 - 1e-9)) > 0.0);
      CHECK(antiplane_pair_dispersion(top, bottom, k, w * (1 + 1e-9)) < 0.0);
      CHECK(mode.weight < 0.0);  // passive
      // Residue A = lim (s^2 + omega^2) K_c, central in s = i omega (1 +- delta)
      // and Richardson-extrapolated from delta and delta/2: truncation
      // O(delta^4) times the regular part's scale (up to ~1e6 |A| for the
      // weakest modes), rounding ~eps/delta; both < 1e-9 at delta <= 1e-4.
      // delta well inside the distance to the nearest other mode or pole.
      double gap = 1.0;
      for (const auto& other : modes)
        if (other.frequency != w) gap = std::min(gap, std::abs(other.frequency / w - 1));
      for (double pole : poles) gap = std::min(gap, std::abs(pole / w - 1));
      const auto central = [&](double delta) {
        cplx sum = 0.0;
        for (double sign : {1.0, -1.0}) {
          const cplx s(0.0, w * (1 + sign * delta));
          sum += 0.5 * (s * s + w * w) * antiplane_pair_response(top, bottom, k, s);
        }
        return sum;
      };
      const double delta = std::min(1e-4, 1e-3 * gap);
      const cplx estimate = (4.0 * central(0.5 * delta) - central(delta)) / 3.0;
      const double amplitude = mode.weight * w * w;
      INFO("mode at " << w << ", delta " << delta << ": estimate " << estimate << ", A " << amplitude);
      // Relative to the mode's own A, and to the largest A of this k for the
      // weakest modes (down to 1e-6 of their neighbours): their estimate
      // carries the neighbours' rounding, ~eps/delta of those.
      const double error = std::abs(estimate - amplitude) / (std::abs(amplitude) + 1e-3 * largest);
      CHECK(error <= 1e-7);
      worst_residue = std::max(worst_residue, error);
      ++total;
    }
  }
  MESSAGE(total << " modes: worst relative residue against the finite-difference limit " << worst_residue);
  CHECK(worst_residue <= 1e-7);
}

TEST_CASE("comb identity of two strips: uniform-mode kernel + k = 0 modes below Nyquist = 2 eta at every lag") {
  // Steps with M_t, M_b of both parities (a pole at Nyquist when both are even: half weight).
  const AntiplaneStrip top{kTop, kTopHeight};
  const double ct = kTop.shear_wave_speed(), cb = kBottom.shear_wave_speed();
  for (auto [mt, mb] : {std::pair{7, 11}, std::pair{12, 20}, std::pair{40, 31}, std::pair{64, 150}}) {
    const double dt = 2 * kTopHeight / ct / mt;
    const AntiplaneStrip bottom{kBottom, mb * dt * cb / 2};
    const StripPairConstants constants = antiplane_pair_constants(top, bottom, dt);
    REQUIRE(constants.top_echo_steps == static_cast<std::size_t>(mt));
    REQUIRE(constants.bottom_echo_steps == static_cast<std::size_t>(mb));
    UniformModeEchoes echoes(constants);
    const auto modes = antiplane_pair_modes(top, bottom, 0.0, pi / dt * (1 + 1e-9));
    double worst = 0;
    cplx h = echoes.push(1.0);
    for (int j = 1; j <= 3 * (mt + mb); ++j) {
      double comb = 0;
      for (const auto& m : modes) {
        const double phase = m.frequency * dt;
        const double half = std::abs(phase - pi) < 1e-7 ? 0.5 : 1.0;
        comb += half * dt * m.weight * (1 - std::cos(phase * j));
      }
      worst = std::max(worst, std::abs(h.real() - comb - constants.running_sum_weight));
      h = echoes.push(0.0);
    }
    MESSAGE("M_t = " << mt << ", M_b = " << mb << ": " << modes.size()
                     << " modes; max |kernel - comb - 2 eta| / 2 eta = " << worst / constants.running_sum_weight);
    // Every term is O(2 eta / M) and computed to ~1e-15: rounding of a sum of
    // M terms, and the residues to ~1e-13 (the mode finder's roots).
    CHECK(worst <= 1e-10 * constants.running_sum_weight);
  }
}

TEST_CASE("identical bodies: the combined operator = the identical pair's (modal and block, round-off)") {
  const auto m = sh(9e9, 1200);
  const double H = 0.1, L = 0.8;
  const int N = 32;
  const double dt = strip_time_step(m, H, L / N, 0.3);
  const AntiplaneStrip body{m, H};
  const Pair p{body, body, dt, L, N};
  const auto kernels = compute_strip_kernels(m, H, L, N, dt);
  for (bool block : {false, true}) {
    std::unique_ptr<HistoryOperator> pair;
    if (block)
      pair = std::make_unique<BlockStripHistory>(m, kernels, BlockHistoryDesign{8, 64, 12});
    else
      pair = std::make_unique<StripHistory>(m, kernels);
    auto mine = combined(p, block, BlockHistoryDesign{8, 64, 12});
    CHECK(mine->radiation_damping() == pair->radiation_damping());
    const auto input = slipstrip_test::white_noise_spectra(N / 2 + 1, 3000, 5);
    double worst = 0, largest = 0;
    for (const auto& v : input) {
      pair->push(v);
      mine->push(v);
      for (int q = 0; q <= N / 2; ++q) {
        worst = std::max(worst, std::abs(pair->history()[q] - mine->history()[q]));
        largest = std::max(largest, std::abs(pair->history()[q]));
      }
    }
    MESSAGE((block ? "block" : "modal") << ": max |combined - pair| / max |history| = " << worst / largest);
    // The same modes; the weights and the truncated static stiffness differ in
    // rounding (other expressions of the same numbers), which a lossless
    // operator carries linearly: 3000 steps x a few ulps.
    CHECK(worst <= 1e-12 * largest);
  }
}

TEST_CASE("general pair: prescribed slip against the inverse Laplace transform of K_c, and against TwoBodyHistory") {
  // Mode 1 at k H_t = 0.5 and 5; about 32, 64, 128 steps per top echo (beta as
  // the two-body test sets it); a sin^4 bump over 2 echoes; 30 echoes of history.
  const double echo = 2 * kTopHeight / kTop.shear_wave_speed();
  const double c_max = std::max(kTop.shear_wave_speed(), kBottom.shear_wave_speed());
  for (double kH : {0.5, 5.0}) {
    const double k = kH / kTopHeight, length = 2 * pi / k;
    double previous = 0;
    for (int per_echo : {32, 64, 128}) {
      const double beta = echo / per_echo * c_max / (length / 4);
      const Pair p = general_pair(length, 4, beta);
      const int steps = static_cast<int>(30 * echo / p.dt);
      const double rise = 2 * echo;
      auto op = combined(p, false);
      auto two = bodies(p);
      const auto stress = testing::single_mode_stress(*op, rise, steps);
      const auto stress_bodies = testing::single_mode_stress(two, rise, steps);
      const auto reference = testing::inverse_laplace(
          [&](cplx s) { return -antiplane_pair_response(p.top, p.bottom, k, s) * testing::bump_laplace(s, rise); },
          p.dt, 1 << 19, steps + 1);
      const double err = testing::relative_l2_difference(stress, reference);
      const double err_bodies = testing::relative_l2_difference(stress_bodies, reference);
      const double apart = testing::relative_l2_difference(stress, stress_bodies);
      MESSAGE("kH = " << kH << ", " << per_echo << " steps per top echo (M_t, M_b = "
                      << p.constants().top_echo_steps << ", " << p.constants().bottom_echo_steps
                      << "): combined " << err << ", bodies " << err_bodies << ", combined vs bodies " << apart);
      // The identical strips' scheme: second order, ~1e-6 at 128 steps per
      // echo and kH = 5 (test_kernels_time_domain, test_kernels_two_body's 1e-4).
      CHECK(err < 1e-4);
      // Both discretise K_c; they differ where each truncates its modes
      // (the bodies' at each body's Nyquist, the combined at the pair's), at
      // the order of their errors against the reference.
      CHECK(apart <= 2 * std::max(err, err_bodies) + 1e-9);
      if (previous > 0) CHECK(err < 0.5 * previous);  // converging (second order: ~x4)
      previous = err;
    }
  }
}

TEST_CASE("general pair: the uniform mode = TwoBodyHistory's (both exact, round-off)") {
  const Pair p = general_pair(0.8, 16, 0.3);
  REQUIRE(p.constants().top_echo_steps != p.constants().bottom_echo_steps);
  auto op = combined(p, false);
  auto two = bodies(p);
  const auto input = slipstrip_test::white_noise_spectra(p.nodes / 2 + 1, 4000, 8);
  double worst = 0, largest = 0;
  for (const auto& v : input) {
    op->push(v);
    two.push(v);
    worst = std::max(worst, std::abs(op->history()[0] - two.history()[0]));
    largest = std::max(largest, std::abs(two.history()[0]));
  }
  MESSAGE("uniform mode, 4000 white-noise steps: max |combined - bodies| / max = " << worst / largest);
  // Both apply the exact rational kernel G(z) (the bodies' echo lines combined
  // step by step through the impedances): rounding only, growing at most
  // linearly in a lossless operator.
  CHECK(worst <= 1e-12 * largest);
  CHECK(op->radiation_damping() == doctest::Approx(two.radiation_damping()).epsilon(1e-15));
}

TEST_CASE("general pair: the discrete operator is passive (weights <= 0, Re Z_d > 0 outside |z| = 1, free ringing)") {
  const Pair p = general_pair(0.8, 64, 0.3);
  const auto kernels = p.kernels();
  const auto constants = p.constants();
  const double eta = constants.radiation_damping, dt = p.dt;
  for (double w : kernels.weight) CHECK(w <= 0.0);
  double worst = 1e300;
  for (double r : {1.001, 1.01, 1.2}) {
    for (int q = 0; q <= p.nodes / 2; ++q) {
      const auto first = kernels.first_oscillator;
      for (int i = 0; i < 720; ++i) {
        const cplx z = std::polar(r, pi * (i + 0.5) / 720);
        cplx Z;
        if (q == 0) {
          // The exact G(z) of the uniform mode (UniformModeEchoes).
          const double et = constants.top_impedance, eb = constants.bottom_impedance;
          const cplx xt = std::pow(z, -static_cast<double>(constants.top_echo_steps));
          const cplx xb = std::pow(z, -static_cast<double>(constants.bottom_echo_steps));
          Z = et * eb * (1.0 + xt) * (1.0 + xb) / ((et + eb) * (1.0 - xt * xb) + (eb - et) * (xb - xt));
        } else {
          // eta + c0/(z - 1) - dt sum_m w_m (z cos phi - 1)/(z^2 - 2 z cos phi + 1).
          double weight_sum = 0;
          cplx modes = 0.0;
          for (std::size_t m = first[q]; m < first[q + 1]; ++m) {
            const double c = std::cos(kernels.phase[m]);
            weight_sum += kernels.weight[m];
            modes += kernels.weight[m] * (z * c - 1.0) / (z * z - 2.0 * z * c + 1.0);
          }
          Z = eta + (constants.running_sum_weight + dt * weight_sum) / (z - 1.0) - dt * modes;
        }
        worst = std::min(worst, Z.real() / eta);
      }
    }
  }
  MESSAGE("min Re Z_d / eta over q and |z| = 1.001, 1.01, 1.2: " << worst);
  CHECK(worst > 0.0);
  for (bool block : {false, true}) {
    for (int q : {0, 1, 20}) {
      auto op = combined(p, block, BlockHistoryDesign{8, 64, 12});
      const auto mean_square = testing::free_ringing_mean_square(*op, q, 200000, 4000, 40);
      const double early = *std::max_element(mean_square.begin() + 1, mean_square.begin() + 11);
      const double late = *std::max_element(mean_square.end() - 10, mean_square.end());
      MESSAGE((block ? "block" : "modal") << " q = " << q << ": largest mean-square slip rate, windows 2-11 "
                                         << early << ", last 10 " << late);
      // A lossless pair beats between its incommensurate modes, so windows of
      // 4000 steps differ by a few % (up to 5 % here); a growing mode would
      // be exponential: at 1e-6 per step it gains 22 % over the run.
      CHECK(late <= 1.1 * early);
    }
  }
}

TEST_CASE("general pair, block operator: a restart in the middle of a block continues bit for bit") {
  const Pair p = general_pair(0.8, 16, 0.3);
  const BlockHistoryDesign design{8, 64, 12};
  const int modes = p.nodes / 2 + 1;
  const auto input = slipstrip_test::white_noise_spectra(modes, 200, 22);
  std::vector<std::vector<cplx>> straight;
  {
    auto op = combined(p, true, design);
    for (const auto& v : input) {
      op->push(v);
      straight.emplace_back(op->history().begin(), op->history().end());
    }
  }
  for (bool block : {true, false}) {
    auto saver = combined(p, block, design);
    auto reference = combined(p, block, design);
    std::vector<std::vector<cplx>> expected;
    for (const auto& v : input) {
      reference->push(v);
      expected.emplace_back(reference->history().begin(), reference->history().end());
    }
    for (int n = 0; n < 100; ++n) saver->push(input[n]);
    for (int stop = 100; stop < 130; ++stop) {
      auto resumed = combined(p, block, design);
      resumed->restore_state(saver->save_state());
      int differing = 0;
      for (int n = stop; n < stop + 70; ++n) {
        resumed->push(input[n]);
        for (int q = 0; q < modes; ++q) differing += resumed->history()[q] != expected[n][q];
      }
      INFO((block ? "block" : "modal") << ": saved after " << stop << " steps (position " << stop % 64 << ")");
      CHECK(differing == 0);
      saver->push(input[stop]);
    }
  }
  // The layout names every saved array.
  auto op = combined(p, true, design);
  const auto state = op->save_state();
  const auto layout = op->state_layout();
  for (const auto& [name, values] : state.arrays) CHECK(layout.of(name).back() == values.size());
}

TEST_CASE("general pair: push() does not allocate (block, B = 2048; modal)") {
  const Pair p = general_pair(0.1, 16, 0.25);
  const auto input = slipstrip_test::white_noise_spectra(p.nodes / 2 + 1, 2 * 2048 + 3, 14);
  for (int threads : {1, 2}) {
    slipstrip_test::with_threads(threads, [&] {
      for (bool block : {true, false}) {
        auto op = combined(p, block, BlockHistoryDesign{32, 2048, 12});
        const long before = slipstrip_test::allocations();
        for (const auto& v : input) op->push(v);
        const long during = slipstrip_test::allocations() - before;
        MESSAGE(threads << " thread(s), " << (block ? "block" : "modal") << ": allocations in " << input.size()
                        << " pushes: " << during);
        CHECK(during == 0);
      }
    });
  }
}
