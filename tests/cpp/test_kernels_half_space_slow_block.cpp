// The half-space operator's slow exponentials (docs/theory.md §8.7): they are
// advanced once per block of B steps through Taylor moments instead of being
// rotated every step.  This must be the same discrete operator as rotating
// every exponential every step (design.slow_block = 0, the original algorithm,
// itself verified in test_kernels_half_space_operator.cpp), to the stated
// Taylor bound plus rounding.  Checked here:
//   - the Taylor bound is a true bound of the truncated series of e^{-y};
//   - the two algorithms hold the same poles and weights (mode_kernel);
//   - the same history, to 1e-12 of its largest value, on random input over
//     many blocks, for several block designs and both plane conditions;
//   - a restart in the middle of a block continues bit for bit, and restart
//     points of the every-step operator are refused with the reason;
//   - designs whose Taylor bound is too loose are refused with a message.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "kernels/half_space_history.hpp"

using namespace slipstrip;
using cplx = std::complex<double>;

namespace {

ElasticMaterial material(PlaneCondition plane) {
  ElasticMaterial m;
  m.plane = plane;
  return m;
}

// White noise plus a slowly varying part, so that both the fast and the slow
// (long-memory) exponentials are exercised.
std::vector<cplx> random_spectrum(std::mt19937& rng, int modes, int step) {
  std::normal_distribution<double> normal;
  std::vector<cplx> v(modes);
  for (int q = 0; q < modes; ++q)
    v[q] = cplx(normal(rng), normal(rng)) + cplx(std::cos(1e-3 * step * (q + 1)), std::sin(7e-4 * step));
  return v;
}

// max |a - b| over modes and steps, relative to max |a|.
struct Comparison {
  double worst_difference = 0.0, largest_value = 0.0;
  double relative() const { return worst_difference / largest_value; }
};

Comparison compare(HalfSpaceHistory& a, HalfSpaceHistory& b, int steps, unsigned seed) {
  std::mt19937 rng(seed);
  Comparison c;
  for (int n = 0; n < steps; ++n) {
    const auto v = random_spectrum(rng, a.modes(), n);
    a.push(v);
    b.push(v);
    for (int q = 0; q < a.modes(); ++q) {
      c.worst_difference = std::max(c.worst_difference, std::abs(a.history()[q] - b.history()[q]));
      c.largest_value = std::max(c.largest_value, std::abs(a.history()[q]));
    }
  }
  return c;
}

}  // namespace

TEST_CASE("slow exponentials: the Taylor bound bounds the truncated series of e^{-y}") {
  for (auto [radius, terms] : {std::pair{0.25, 12}, std::pair{0.5, 16}, std::pair{1.0, 20}}) {
    HalfSpaceOperatorDesign d;
    d.slow_taylor_radius = radius;
    d.taylor_terms = terms;
    double worst = 0.0;
    for (int i = -1000; i <= 1000; ++i) {
      const long double y = radius * i / 1000.0L;
      long double term = 1.0L, sum = 0.0L;
      for (int p = 0; p < terms; ++p) {
        sum += term;
        term *= -y / (p + 1);
      }
      worst = std::max(worst, static_cast<double>(std::abs(sum - std::exp(-y)) / std::exp(-y)));
    }
    MESSAGE("radius " << radius << ", " << terms << " terms: max relative error " << worst << ", bound "
                      << slow_taylor_error_bound(d));
    CHECK(worst <= slow_taylor_error_bound(d));
  }
  CHECK(slow_taylor_error_bound(HalfSpaceOperatorDesign{}) < 2e-16);
}

TEST_CASE("slow exponentials: same poles and weights as rotating every exponential") {
  const auto m = material(PlaneCondition::strain);
  const int N = 128;
  const double L = 1.0, dt = 0.25 * (L / N) / m.shear_wave_speed();
  HalfSpaceOperatorDesign every_step;
  every_step.slow_block = 0;
  const HalfSpaceHistory blocked(m, L, N, dt), reference(m, L, N, dt, every_step);
  CHECK(reference.slow_exponentials() == 0);
  // Most of the ~300 exponentials per mode are slow: that is the point.
  CHECK(blocked.slow_exponentials() > reference.stats().oscillators / 2);
  CHECK(blocked.stats().oscillators == reference.stats().oscillators);
  for (int q : {1, 7, 40, N / 2}) {
    auto a = blocked.mode_kernel(q), b = reference.mode_kernel(q);
    REQUIRE(a.pole.size() == b.pole.size());
    CHECK(a.lag_weight == b.lag_weight);
    CHECK(a.static_weight == b.static_weight);
    auto by_value = [](const auto& x, const auto& y) {
      return x.first.real() != y.first.real() ? x.first.real() < y.first.real() : x.first.imag() < y.first.imag();
    };
    std::vector<std::pair<cplx, cplx>> pa, pb;
    for (std::size_t i = 0; i < a.pole.size(); ++i) pa.emplace_back(a.pole[i], a.pole_weight[i]);
    for (std::size_t i = 0; i < b.pole.size(); ++i) pb.emplace_back(b.pole[i], b.pole_weight[i]);
    std::sort(pa.begin(), pa.end(), by_value);
    std::sort(pb.begin(), pb.end(), by_value);
    // Weights: the slow ones are stored as w, the fast ones as 2 Re w, -2 Im w
    // and halved back, so equal to the last bit.
    for (std::size_t i = 0; i < pa.size(); ++i) {
      CHECK(pa[i].first == pb[i].first);
      CHECK(pa[i].second == pb[i].second);
    }
  }
}

TEST_CASE("slow exponentials: the same history as rotating every exponential, over many blocks") {
  // Tolerance 1e-13 of the largest history value: the Taylor truncation is
  // 1.7e-16 relative per slow exponential; what remains is rounding in the
  // moment sums over a block (B terms) and in the two algorithms' different
  // summation orders over ~300 exponentials: measured 1.8-2.6e-16, so 1e-13
  // leaves room for other compilers and machines without hiding an error in
  // the algorithm (a wrong index or sign gives O(1e-3) or more).
  struct Case {
    PlaneCondition plane;
    int block, terms;
    double radius, beta;
  };
  for (const Case c : {Case{PlaneCondition::strain, 128, 12, 0.25, 0.25}, Case{PlaneCondition::stress, 64, 12, 0.25, 0.35},
                       Case{PlaneCondition::strain, 16, 16, 0.5, 0.3}, Case{PlaneCondition::strain, 256, 20, 1.0, 0.25},
                       Case{PlaneCondition::antiplane, 128, 12, 0.25, 0.35}}) {
    const auto m = material(c.plane);
    const int N = 128;
    const double L = 4.0, dt = c.beta * (L / N) / m.shear_wave_speed();
    HalfSpaceOperatorDesign blocked_design, every_step;
    blocked_design.slow_block = c.block;
    blocked_design.taylor_terms = c.terms;
    blocked_design.slow_taylor_radius = c.radius;
    every_step.slow_block = 0;
    HalfSpaceHistory blocked(m, L, N, dt, blocked_design), reference(m, L, N, dt, every_step);
    const int steps = 20 * c.block + c.block / 2 + 3;  // ends inside a block
    const auto result = compare(reference, blocked, steps, 11);
    MESSAGE("B = " << c.block << ", " << c.terms << " terms, radius " << c.radius << ", beta " << c.beta << ": "
                   << blocked.slow_exponentials() << " of " << blocked.stats().oscillators
                   << " exponentials slow; max |difference| / max |history| = " << result.relative()
                   << " over " << steps << " steps");
    CHECK(blocked.slow_exponentials() > 0);
    CHECK(result.relative() < 1e-13);
  }
}

TEST_CASE("slow exponentials: a restart in the middle of a block continues bit for bit") {
  const auto m = material(PlaneCondition::strain);
  const int N = 64;
  const double L = 1.0, dt = 0.25 * (L / N) / m.shear_wave_speed();
  HalfSpaceHistory first(m, L, N, dt);
  std::mt19937 rng(3);
  const int before = 3 * first.slow_block() + 17;
  for (int n = 0; n < before; ++n) first.push(random_spectrum(rng, first.modes(), n));
  HalfSpaceHistory second(m, L, N, dt);
  second.restore_state(first.save_state());
  for (int n = before; n < before + 2 * first.slow_block(); ++n) {
    const auto v = random_spectrum(rng, first.modes(), n);
    first.push(v);
    second.push(v);
    for (int q = 0; q < first.modes(); ++q) REQUIRE(first.history()[q] == second.history()[q]);
  }
}

TEST_CASE("slow exponentials: a restart point of the every-step operator is refused with the reason") {
  const auto m = material(PlaneCondition::strain);
  const double dt = 0.25 * (1.0 / 32) / m.shear_wave_speed();
  HalfSpaceHistory op(m, 1.0, 32, dt);
  HistoryOperatorState old_format = op.save_state();
  std::erase_if(old_format.counters, [](const auto& c) { return c.first == "format"; });
  try {
    op.restore_state(old_format);
    FAIL("a restart point without the format counter was accepted");
  } catch (const std::invalid_argument& e) {
    CHECK(std::string(e.what()).find("older than the blocked half-space operator") != std::string::npos);
  }
  op.restore_state(op.save_state());  // the current format is accepted
}

TEST_CASE("far field in batches: every step's arithmetic, and restarts in the middle of a batch") {
  // The far field worked for 8 steps at once is the every-step far field bit
  // for bit (the same arithmetic per step, in the same order), with and
  // without slow exponentials, in plane strain and antiplane; a restart point
  // of either (format 3 in the middle of a batch, format 2 as the every-step
  // operator wrote it) continues bit for bit.
  for (const PlaneCondition plane : {PlaneCondition::strain, PlaneCondition::antiplane})
    for (const int block : {32, 0}) {
      CAPTURE(static_cast<int>(plane));
      CAPTURE(block);
      const auto m = material(plane);
      const int N = 32;
      const double L = 1.0, dt = 0.3 * (L / N) / m.shear_wave_speed();
      HalfSpaceOperatorDesign every_step;
      every_step.slow_block = block;
      every_step.far_batch = 1;
      HalfSpaceOperatorDesign batched = every_step;
      batched.far_batch = 8;
      HalfSpaceHistory a(m, L, N, dt, every_step), b(m, L, N, dt, batched);
      REQUIRE(a.far_batch() == 1);
      REQUIRE(b.far_batch() == 8);
      CHECK(b.period() == (block > 0 ? block : 8));
      std::mt19937 rng(5);
      bool identical = true;
      int n = 0;
      for (; n < 3 * 32 + 21; ++n) {  // ends in the middle of a batch and of a block
        const auto v = random_spectrum(rng, a.modes(), n);
        a.push(v);
        b.push(v);
        for (int q = 0; q < a.modes(); ++q) identical = identical && a.history()[q] == b.history()[q];
      }
      CHECK(identical);
      // Format 3, in the middle of a batch.
      HalfSpaceHistory c(m, L, N, dt, batched);
      c.restore_state(b.save_state());
      // Every step, the far field is at the current step: the state as format
      // 2 held it (no batch outputs).
      const HistoryOperatorState saved = a.save_state();
      HistoryOperatorState format2;
      format2.kind = saved.kind;
      for (const auto& [name, value] : saved.counters)
        if (name != "far_batch") format2.counters.emplace_back(name, name == "format" ? 2 : value);
      for (const auto& array : saved.arrays)
        if (array.first != "far_out" && array.first != "slow_out") format2.arrays.push_back(array);
      HalfSpaceHistory d(m, L, N, dt, batched);
      d.restore_state(format2);
      bool resumed = true;
      for (; n < 6 * 32 + 3; ++n) {
        const auto v = random_spectrum(rng, a.modes(), n);
        a.push(v);
        c.push(v);
        d.push(v);
        for (int q = 0; q < a.modes(); ++q)
          resumed = resumed && a.history()[q] == c.history()[q] && a.history()[q] == d.history()[q];
      }
      CHECK(resumed);
      // A format-3 restart point of another batch is refused by name.
      CHECK_THROWS_WITH_AS(a.restore_state(c.save_state()), doctest::Contains("far-field batch"),
                           std::invalid_argument);
    }
}

TEST_CASE("slow exponentials: designs with a loose Taylor bound are refused") {
  const auto m = material(PlaneCondition::strain);
  const double dt = 0.25 * (1.0 / 64) / m.shear_wave_speed();
  HalfSpaceOperatorDesign loose;
  loose.slow_taylor_radius = 1.0;
  loose.taylor_terms = 8;  // bound 6.7e-5
  try {
    HalfSpaceHistory op(m, 1.0, 64, dt, loose);
    FAIL("a loose design was accepted");
  } catch (const std::invalid_argument& e) {
    CHECK(std::string(e.what()).find("taylor_terms") != std::string::npos);
  }
  HalfSpaceOperatorDesign one_step_block;
  one_step_block.slow_block = 1;
  CHECK_THROWS_AS(HalfSpaceHistory(m, 1.0, 64, dt, one_step_block), std::invalid_argument);
}
