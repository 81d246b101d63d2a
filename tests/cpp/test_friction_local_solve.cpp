// Local interface solve  tau_history - eta v = sign(v) strength(|v|, phi).
#include <doctest/doctest.h>

#include "friction_test_parameters.hpp"

#include <cfloat>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "friction/friction_law.hpp"

using namespace slipstrip;

namespace {

constexpr double not_a_number = std::numeric_limits<double>::quiet_NaN();
constexpr double inf = std::numeric_limits<double>::infinity();
constexpr double sigma0 = 1e6;            // [Pa]
const double eta = 9e9 / (2 * std::sqrt(9e9 / 1200.0));  // mu / (2 c_s), Table S1 [Pa s/m]

using testing::parameters_for;

const std::vector<StrengthLaw> all_laws = {StrengthLaw::paper, StrengthLaw::dieterich_ruina,
                                           StrengthLaw::regularized};

// Independent reference: the strength written naively in long double, and a
// plain bisection in ln u (no Newton, no bounds from the library).
long double naive_strength(const FrictionParameters& p, long double u, long double phi) {
  const long double s = sigma0;
  switch (p.strength_law) {
    case StrengthLaw::paper:
      return s * (p.f0 * (1 + p.b * std::log(phi / p.phi_star)) + p.a * std::log1p(u / p.v_star));
    case StrengthLaw::dieterich_ruina:
      return s * (p.f0 + p.a * std::log(u / p.v_star) + p.b * std::log(p.v_star * phi / p.characteristic_slip));
    case StrengthLaw::regularized:
      return s * p.a *
             std::asinh(u / (2 * p.v_star) *
                        std::exp((p.f0 + p.b * std::log(p.v_star * phi / p.characteristic_slip)) / p.a));
  }
  return NAN;
}

long double bisection_slip_rate(const FrictionParameters& p, long double T, long double phi) {
  const auto g = [&](long double w) {
    const long double u = std::exp(w);
    return T - eta * u - naive_strength(p, u, phi);
  };
  long double lo = -300, hi = 300;  // ln u: 1e-130 .. 1e130 m/s
  while (g(hi) >= 0) hi += 100;
  for (int i = 0; i < 200; ++i) {
    const long double mid = 0.5L * (lo + hi);
    (g(mid) > 0 ? lo : hi) = mid;
  }
  return std::exp(0.5L * (lo + hi));
}

// Error in u caused by rounding T (and the terms of g) at the eps level:
// eps (T + |strength| + eta u) / |dg/du|.  Condition-number allowance.
double rounding_allowance(const FrictionParameters& p, double T, double u, double phi) {
  const double slope = eta + frictional_strength_dv(p, sigma0, u, phi);
  const double terms = T + std::fabs(frictional_strength(p, sigma0, u, phi)) + eta * u;
  return 16 * DBL_EPSILON * terms / slope;
}

// What the residual may be for a slip rate within the solver's relative
// tolerance 1e-12 of the root: 1e-12 u |dg/du|, plus round-off of the terms of
// tau_history - eta v - strength (16 eps times their sum of magnitudes).
double residual_allowance(const FrictionParameters& p, double T, double u, double phi) {
  double strength_terms = 0.0;
  if (p.strength_law == StrengthLaw::paper) {
    strength_terms = sigma0 * (p.f0 * (1 + p.b * std::fabs(std::log(phi / p.phi_star))) +
                               p.a * std::log1p(u / p.v_star));
  } else {
    strength_terms = sigma0 * (p.f0 + p.a * std::fabs(std::log(u / p.v_star)) +
                               p.b * std::fabs(std::log(p.v_star * phi / p.characteristic_slip)));
  }
  const double slope = eta + frictional_strength_dv(p, sigma0, u, phi);
  return 16 * DBL_EPSILON * (T + eta * u + strength_terms) + 1e-12 * u * slope;
}

double residual(const FrictionParameters& p, double tau, double v, double phi) {
  const double sign = v > 0 ? 1.0 : (v < 0 ? -1.0 : 0.0);
  return tau - eta * v - sign * frictional_strength(p, sigma0, v, phi);
}

}  // namespace

TEST_CASE("manufactured roots across 10 orders of magnitude of slip rate") {
  std::mt19937_64 rng(20261123);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (auto law : all_laws) {
    const auto p = parameters_for(law);
    int max_iterations = 0;
    for (int i = 0; i < 400; ++i) {
      const double u = std::pow(10.0, -10.0 + 10.0 * unit(rng));   // 1e-10 .. 1 m/s
      const double phi = std::pow(10.0, -6.0 + 7.0 * unit(rng));   // 1e-6 .. 10 s
      const double sign = unit(rng) < 0.5 ? -1.0 : 1.0;
      const double tau = sign * (eta * u + frictional_strength(p, sigma0, u, phi));
      // Half cold starts (guess 0, as after sticking), half rough warm starts.
      const double guess = (i % 2 == 0) ? 0.0 : sign * u * std::exp(2.0 * (unit(rng) - 0.5));
      const auto solution = solve_slip_rate_counted(p, sigma0, eta, tau, phi, guess);
      max_iterations = std::max(max_iterations, solution.iterations);
      const double v = solution.slip_rate;
      INFO(to_string(law) << " u=" << u << " phi=" << phi << " tau=" << tau << " guess=" << guess
                          << " v=" << v << " iterations=" << solution.iterations);
      // 1e-11 relative: the solver stops at 1e-12 in ln u; plus the error that
      // rounding the manufactured tau at eps level induces (condition number).
      CHECK(std::fabs(v - sign * u) <= 1e-11 * u + rounding_allowance(p, std::fabs(tau), u, phi));
      CHECK(std::fabs(residual(p, tau, v, phi)) <= residual_allowance(p, std::fabs(tau), u, phi));
    }
    MESSAGE(to_string(law) << ": max iterations over 400 manufactured solves = " << max_iterations);
  }
}

TEST_CASE("agrees with an independent long-double bisection at random (tau_history, state)") {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (auto law : all_laws) {
    const auto p = parameters_for(law);
    for (int i = 0; i < 200; ++i) {
      const double phi = std::pow(10.0, -6.0 + 7.0 * unit(rng));
      const double s0 = law == StrengthLaw::paper ? frictional_strength(p, sigma0, 0.0, phi) : 0.0;
      const double excess = std::pow(10.0, -2.0 + 9.0 * unit(rng));  // 0.01 Pa .. 10 MPa above rest
      const double tau = s0 + excess;
      const double v = solve_slip_rate(p, sigma0, eta, tau, phi, 0.0);
      const double reference = static_cast<double>(bisection_slip_rate(p, tau, phi));
      INFO(to_string(law) << " tau=" << tau << " phi=" << phi << " v=" << v << " ref=" << reference);
      CHECK(v > 0.0);
      CHECK(std::fabs(v - reference) <= 1e-11 * reference + rounding_allowance(p, tau, reference, phi));
    }
  }
}

TEST_CASE("sticking returns exactly zero") {
  const auto p = parameters_for(StrengthLaw::paper);
  const double phi = 2.5e-4;
  const double s0 = frictional_strength(p, sigma0, 0.0, phi);
  REQUIRE(s0 > 0.0);
  for (double tau : {s0, 0.999 * s0, 0.0, -0.5 * s0, -s0}) {
    const auto solution = solve_slip_rate_counted(p, sigma0, eta, tau, phi, 1e-3);
    CHECK(solution.slip_rate == 0.0);
    CHECK(solution.iterations == 0);
  }
  // Regularized law: strength(0) = 0, so only zero load sticks.
  const auto reg = parameters_for(StrengthLaw::regularized);
  CHECK(solve_slip_rate(reg, sigma0, eta, 0.0, 1.0, 1e-3) == 0.0);
  // Any load slides; 1e-3 Pa gives v ~ 1e-3 / (sigma a / u_c) ~ 6e-38 m/s.
  const double small = solve_slip_rate(reg, sigma0, eta, 1e-3, 1.0, 1e-3);
  CHECK(small > 0.0);
  CHECK(std::fabs(residual(reg, 1e-3, small, 1.0)) <= residual_allowance(reg, 1e-3, small, 1.0));
  // At 1e-300 Pa the root (~6e-335 m/s) is below the smallest double: it rounds to 0.
  CHECK(solve_slip_rate(reg, sigma0, eta, 1e-300, 1.0, 1e-3) < 1e-320);
}

TEST_CASE("paper law below its physical range: negative strength at rest") {
  // phi < phi* exp(-1/b) makes f0 [1 + b ln(phi/phi*)] < 0: no load can be held.
  const auto p = parameters_for(StrengthLaw::paper);
  const double phi = p.phi_star * std::exp(-2.0 / p.b);
  REQUIRE(frictional_strength(p, sigma0, 0.0, phi) < 0.0);
  const double v = solve_slip_rate(p, sigma0, eta, 10.0, phi, 0.0);
  CHECK(v > 0.0);
  CHECK(std::fabs(residual(p, 10.0, v, phi)) <= residual_allowance(p, 10.0, v, phi));
  // With zero load both slip directions solve the equation: refuse rather than pick one.
  CHECK_THROWS_AS(solve_slip_rate(p, sigma0, eta, 0.0, phi, 0.0), LocalSolveFailure);
}

TEST_CASE("Dieterich-Ruina law: never sticks; zero load has no slip direction") {
  const auto p = parameters_for(StrengthLaw::dieterich_ruina);
  // Any positive load slides (strength -> -inf as v -> 0), even a tiny one.
  const double v = solve_slip_rate(p, sigma0, eta, 1.0, 1.0, 0.0);
  CHECK(v > 0.0);
  CHECK(std::fabs(residual(p, 1.0, v, 1.0)) <= residual_allowance(p, 1.0, v, 1.0));
  CHECK_THROWS_AS(solve_slip_rate(p, sigma0, eta, 0.0, 1.0, 0.0), LocalSolveFailure);
}

TEST_CASE("negative tau_history mirrors the positive problem exactly") {
  for (auto law : all_laws) {
    const auto p = parameters_for(law);
    for (double excess : {1e-3, 1e2, 1e5, 3e6}) {
      const double phi = 0.01;
      const double tau = (law == StrengthLaw::paper ? frictional_strength(p, sigma0, 0.0, phi) : 0.0) + excess;
      const double v = solve_slip_rate(p, sigma0, eta, tau, phi, 1e-4);
      const double mirrored = solve_slip_rate(p, sigma0, eta, -tau, phi, -1e-4);
      INFO(to_string(law) << " tau=" << tau << " v=" << v << " mirrored=" << mirrored);
      CHECK(v > 0.0);
      CHECK(mirrored == -v);  // the algorithm works on |tau|, |guess|: bitwise symmetric
    }
  }
}

TEST_CASE("a tiny excess above the static strength gives a tiny positive slip rate") {
  const auto p = parameters_for(StrengthLaw::paper);
  const double phi = 2.5e-4;
  const double s0 = frictional_strength(p, sigma0, 0.0, phi);
  const double slope_at_rest = eta + sigma0 * p.a / p.v_star;
  for (double tau : {std::nextafter(s0, INFINITY), s0 * (1 + 1e-12), s0 * (1 + 1e-8)}) {
    const double excess = tau - s0;  // exact (Sterbenz)
    for (double guess : {0.0, 1e-3, not_a_number}) {
      const double v = solve_slip_rate(p, sigma0, eta, tau, phi, guess);
      INFO("tau - s0 = " << excess << " guess=" << guess << " v=" << v);
      CHECK(v > 0.0);
      // Linearisation about v = 0: v = excess / (eta + sigma a / v*) up to a
      // relative O(v / v*) <= 1e-7 correction here; tolerance 1e-6.
      CHECK(std::fabs(v - excess / slope_at_rest) <= 1e-6 * excess / slope_at_rest);
    }
  }
}

TEST_CASE("huge tau_history") {
  for (auto law : all_laws) {
    const auto p = parameters_for(law);
    for (double tau : {1e12, -1e12, 1e100, 1e250}) {
      const double v = solve_slip_rate(p, sigma0, eta, tau, 1e-3, 2e-3);
      INFO(to_string(law) << " tau=" << tau << " v=" << v);
      REQUIRE(std::isfinite(v));
      CHECK((v > 0) == (tau > 0));
      // strength >= 0 at these rates, so |v| <= |tau|/eta up to the solver's 1e-12
      CHECK(std::fabs(v) <= std::fabs(tau) / eta * (1 + 1e-12));
      CHECK(std::fabs(residual(p, tau, v, 1e-3)) <= residual_allowance(p, std::fabs(tau), std::fabs(v), 1e-3));
    }
  }
}

TEST_CASE("non-finite or invalid input throws LocalSolveFailure listing the values") {
  const auto p = parameters_for(StrengthLaw::paper);
  try {
    solve_slip_rate(p, sigma0, eta, NAN, 2.5e-4, 1e-3);
    FAIL("expected LocalSolveFailure");
  } catch (const LocalSolveFailure& e) {
    const std::string m = e.what();
    INFO(m);
    for (const char* piece : {"tau_history = nan", "state = 0.00025", "eta = ", "normal_stress = 1000000",
                              "initial_guess = 0.001", "bracket"}) {
      CHECK(m.find(piece) != std::string::npos);
    }
  }
  CHECK_THROWS_AS(solve_slip_rate(p, sigma0, eta, 3e5, NAN, 1e-3), LocalSolveFailure);
  CHECK_THROWS_AS(solve_slip_rate(p, sigma0, eta, 3e5, -1.0, 1e-3), LocalSolveFailure);
  CHECK_THROWS_AS(solve_slip_rate(p, sigma0, NAN, 3e5, 1.0, 1e-3), LocalSolveFailure);
  CHECK_THROWS_AS(solve_slip_rate(p, sigma0, 0.0, 3e5, 1.0, 1e-3), LocalSolveFailure);
  CHECK_THROWS_AS(solve_slip_rate(p, NAN, eta, 3e5, 1.0, 1e-3), LocalSolveFailure);
  CHECK_THROWS_AS(solve_slip_rate(p, -1e6, eta, 3e5, 1.0, 1e-3), LocalSolveFailure);
  CHECK_THROWS_AS(solve_slip_rate(p, sigma0, eta, INFINITY, 1.0, 1e-3), LocalSolveFailure);
}

TEST_CASE("bad initial guesses still converge to the same root") {
  for (auto law : all_laws) {
    const auto p = parameters_for(law);
    const double phi = 2.5e-4;
    const double base = law == StrengthLaw::paper ? frictional_strength(p, sigma0, 0.0, phi) : 0.0;
    for (double excess : {1e-2, 1e3, 2e5, 5e6}) {
      const double tau = base + excess;
      const double good = solve_slip_rate(p, sigma0, eta, tau, phi, 0.0);
      for (double guess : {-good, -1.0, 1e300, -1e300, not_a_number, inf, -inf, 0.0, 5e-324, 1e-200, 1e5}) {
        const auto solution = solve_slip_rate_counted(p, sigma0, eta, tau, phi, guess);
        INFO(to_string(law) << " tau=" << tau << " guess=" << guess << " v=" << solution.slip_rate
                            << " good=" << good << " iterations=" << solution.iterations);
        // Each solve meets 1e-12 in ln u (or the residual round-off floor):
        // two such errors plus round-off stay below 1e-11.
        CHECK(std::fabs(solution.slip_rate - good) <= 1e-11 * good + rounding_allowance(p, tau, good, phi));
        CHECK(solution.iterations <= 60);
      }
    }
  }
}

TEST_CASE("rate-independent strength (a = 0) is solved in closed form") {
  auto p = parameters_for(StrengthLaw::paper);
  p.a = 0.0;
  const double phi = 1e-3;
  const double s0 = frictional_strength(p, sigma0, 0.0, phi);
  CHECK(solve_slip_rate(p, sigma0, eta, s0 + 1e3, phi, 0.0) == (s0 + 1e3 - s0) / eta);
}

TEST_CASE("warm-started solves take 2-4 iterations along a smooth history") {
  // A node sliding near v0 = 2e-3 m/s whose load and state change by ~1e-3 per
  // step, as in a time-stepping run; the guess is the previous slip rate.
  for (auto law : all_laws) {
    const auto p = parameters_for(law);
    const double v0 = 2e-3;
    const double phi0 = law == StrengthLaw::paper ? p.characteristic_slip / v0 : 1e-2;
    const double tau0 = eta * v0 + frictional_strength(p, sigma0, v0, phi0);
    double v = v0;
    long total = 0;
    int worst = 0;
    const int steps = 2000;
    for (int k = 0; k < steps; ++k) {
      const double tau = tau0 * (1 + 2e-3 * std::sin(k / 30.0));
      const double phi = phi0 * (1 + 0.05 * std::sin(k / 70.0));
      const auto solution = solve_slip_rate_counted(p, sigma0, eta, tau, phi, v);
      v = solution.slip_rate;
      total += solution.iterations;
      worst = std::max(worst, solution.iterations);
      CHECK(std::fabs(residual(p, tau, v, phi)) <= residual_allowance(p, tau, v, phi));
    }
    const double mean = static_cast<double>(total) / steps;
    MESSAGE(to_string(law) << ": mean iterations " << mean << ", worst " << worst);
    CHECK(mean <= 4.0);
  }
}
