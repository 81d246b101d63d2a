// Batch (vectorised) local solve and state update against the scalar
// solve_slip_rate / evolve_state, on the local-solve cases of
// test_friction_local_solve.cpp, and the predictor-corrector step built on them.
//
// Tolerances.  Both solves stop when the Newton step in ln u is <= 1e-6, which
// leaves each result within 1e-12 relative of the root (docs/friction.md), so
// they agree to 2e-12 relative.  The batch evaluates the residual with xsimd's
// exp/log/log1p (1-2 ulp, libm's are < 1 ulp), which perturbs the terms of
// g = |tau| - eta u - strength by a few eps times their magnitudes and moves the
// root by at most that over |dg/du|: the same condition-number allowance as in
// test_friction_local_solve.cpp (16 eps (T + |strength| + eta u) / |dg/du|).
// Sticking is decided exactly as by the scalar solve: 0.0, bit for bit.
// The state update is a closed form evaluated with the same operations; its
// tolerance is a few ulp of each term (see the test).
#include <doctest/doctest.h>

#include "friction_test_parameters.hpp"
#include <omp.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "friction/batch_solve.hpp"
#include "friction/friction_law.hpp"

using namespace slipstrip;

namespace {

constexpr double not_a_number = std::numeric_limits<double>::quiet_NaN();
constexpr double inf = std::numeric_limits<double>::infinity();
constexpr double sigma0 = 1e6;                           // [Pa]
const double eta = 9e9 / (2 * std::sqrt(9e9 / 1200.0));  // mu / (2 c_s), Table S1 [Pa s/m]

using testing::parameters_for;

LocalSolveParameters local(const FrictionParameters& p) { return {p, sigma0, eta}; }

const std::vector<StrengthLaw> all_laws = {StrengthLaw::paper, StrengthLaw::dieterich_ruina,
                                           StrengthLaw::regularized};

// Condition-number allowance (as in test_friction_local_solve.cpp).
double rounding_allowance(const FrictionParameters& p, double T, double u, double phi) {
  const double slope = eta + frictional_strength_dv(p, sigma0, u, phi);
  const double terms = T + std::fabs(frictional_strength(p, sigma0, u, phi)) + eta * u;
  return 16 * DBL_EPSILON * terms / slope;
}

// One batch over all cases against the scalar solve, case by case.
struct Case {
  double tau, state, guess;
};

double worst_relative = 0.0;  // reported, not asserted

BatchCounts check_against_scalar(const FrictionParameters& p, const std::vector<Case>& cases) {
  std::vector<double> tau, state, guess, v(cases.size());
  for (const auto& c : cases) {
    tau.push_back(c.tau);
    state.push_back(c.state);
    guess.push_back(c.guess);
  }
  const auto counts = solve_slip_rate_batch(local(p), tau, state, guess, v);
  CHECK(counts.solves == static_cast<long long>(cases.size()));
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const double ref = solve_slip_rate(p, sigma0, eta, tau[i], state[i], guess[i]);
    INFO(to_string(p.strength_law) << " i=" << i << " tau=" << tau[i] << " phi=" << state[i]
                                   << " guess=" << guess[i] << " batch=" << v[i] << " scalar=" << ref);
    if (ref == 0.0) {
      CHECK(v[i] == 0.0);
      CHECK(!std::signbit(v[i]));
      continue;
    }
    CHECK(std::signbit(v[i]) == std::signbit(ref));
    const double u = std::fabs(ref);
    CHECK(std::fabs(v[i] - ref) <= 2e-12 * u + rounding_allowance(p, std::fabs(tau[i]), u, state[i]));
    if (u > 0.0) worst_relative = std::max(worst_relative, std::fabs(v[i] - ref) / u);
  }
  return counts;
}

}  // namespace

TEST_CASE("batch solve: manufactured roots over 10 decades, cold and warm, both signs") {
  std::mt19937_64 rng(20261123);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (auto law : all_laws) {
    const auto p = parameters_for(law);
    std::vector<Case> cases;
    for (int i = 0; i < 403; ++i) {  // not a multiple of the vector width: a partial block too
      const double u = std::pow(10.0, -10.0 + 10.0 * unit(rng));
      const double phi = std::pow(10.0, -6.0 + 7.0 * unit(rng));
      const double sign = unit(rng) < 0.5 ? -1.0 : 1.0;
      const double tau = sign * (eta * u + frictional_strength(p, sigma0, u, phi));
      // Cold starts, rough warm starts, and warm starts of the wrong sign.
      const double guess = (i % 3 == 0) ? 0.0
                           : (i % 3 == 1) ? sign * u * std::exp(2.0 * (unit(rng) - 0.5))
                                          : -sign * u * 1.5;
      cases.push_back({tau, phi, guess});
    }
    const auto counts = check_against_scalar(p, cases);
    MESSAGE(to_string(law) << ": " << counts.scalar_nodes << " of " << counts.solves
                           << " nodes went to the scalar solve, "
                           << counts.evaluations << " vector residual evaluations");
    // All three laws have a vector path: these cases must exercise it.
    CHECK(counts.scalar_nodes * 10 < counts.solves);
  }
  MESSAGE("largest relative batch-scalar difference so far: " << worst_relative);
}

TEST_CASE("batch solve: sticking returns exactly 0, decided as the scalar solve") {
  const auto p = parameters_for(StrengthLaw::paper);
  std::vector<Case> cases;
  for (double phi : {2.5e-4, 1e-6, 3.3e-4, 0.7}) {
    const double s0 = frictional_strength(p, sigma0, 0.0, phi);
    REQUIRE(s0 > 0.0);
    // On the threshold, one ulp either side, and well inside.
    for (double tau : {s0, std::nextafter(s0, 0.0), std::nextafter(s0, inf), 0.999 * s0, 0.0,
                       -0.5 * s0, -s0, -std::nextafter(s0, inf)})
      for (double guess : {1e-3, 0.0, -2e-3}) cases.push_back({tau, phi, guess});
  }
  check_against_scalar(p, cases);
  std::vector<double> tau, state, guess, v;
  for (const auto& c : cases) {
    tau.push_back(c.tau);
    state.push_back(c.state);
    guess.push_back(c.guess);
  }
  v.resize(cases.size());
  solve_slip_rate_batch(local(p), tau, state, guess, v);
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const double s0 = frictional_strength(p, sigma0, 0.0, state[i]);
    INFO("tau=" << tau[i] << " s0=" << s0 << " v=" << v[i]);
    CHECK((v[i] == 0.0) == (std::fabs(tau[i]) <= s0));
  }
  // Regularized law: only zero load sticks.
  const auto reg = parameters_for(StrengthLaw::regularized);
  check_against_scalar(reg, {{0.0, 1.0, 1e-3}, {1e-3, 1.0, 1e-3}, {1e-300, 1.0, 1e-3}});
}

TEST_CASE("batch solve: sign changes mirror bit for bit") {
  for (auto law : all_laws) {
    const auto p = parameters_for(law);
    std::vector<double> tau, minus_tau, state, guess, minus_guess;
    for (double excess : {1e-3, 1e2, 1e5, 3e6}) {
      for (double phi : {0.01, 2.5e-4}) {
        const double t =
            (law == StrengthLaw::paper ? frictional_strength(p, sigma0, 0.0, phi) : 0.0) + excess;
        tau.push_back(t);
        minus_tau.push_back(-t);
        state.push_back(phi);
        guess.push_back(1e-4);
        minus_guess.push_back(-1e-4);
      }
    }
    std::vector<double> v(tau.size()), mirrored(tau.size());
    solve_slip_rate_batch(local(p), tau, state, guess, v);
    solve_slip_rate_batch(local(p), minus_tau, state, minus_guess, mirrored);
    for (std::size_t i = 0; i < v.size(); ++i) {
      INFO(to_string(law) << " tau=" << tau[i] << " v=" << v[i] << " mirrored=" << mirrored[i]);
      CHECK(v[i] > 0.0);
      CHECK(mirrored[i] == -v[i]);
    }
    // Load and guess of opposite signs (a node reversing): compared with the scalar solve.
    std::vector<Case> reversing;
    for (std::size_t i = 0; i < tau.size(); ++i) reversing.push_back({tau[i], state[i], -3e-3});
    check_against_scalar(p, reversing);
  }
}

TEST_CASE("batch solve: v -> 0, a tiny excess above the static strength") {
  const auto p = parameters_for(StrengthLaw::paper);
  const double phi = 2.5e-4;
  const double s0 = frictional_strength(p, sigma0, 0.0, phi);
  const double slope_at_rest = eta + sigma0 * p.a / p.v_star;
  std::vector<Case> cases;
  for (double tau : {std::nextafter(s0, INFINITY), s0 * (1 + 1e-12), s0 * (1 + 1e-8), s0 * (1 + 1e-4)})
    for (double guess : {0.0, 1e-3, not_a_number, 1e-25}) cases.push_back({tau, phi, guess});
  check_against_scalar(p, cases);
  std::vector<double> tau, state, guess, v(cases.size());
  for (const auto& c : cases) {
    tau.push_back(c.tau);
    state.push_back(c.state);
    guess.push_back(c.guess);
  }
  solve_slip_rate_batch(local(p), tau, state, guess, v);
  for (std::size_t i = 0; i + 4 < cases.size(); ++i) {  // the first three loads: linear regime
    const double excess = tau[i] - s0;
    INFO("excess=" << excess << " v=" << v[i]);
    CHECK(v[i] > 0.0);
    CHECK(std::fabs(v[i] - excess / slope_at_rest) <= 1e-6 * excess / slope_at_rest);
  }
}

TEST_CASE("batch solve: huge tau_history, bad guesses, rate-independent strength") {
  for (auto law : all_laws) {
    const auto p = parameters_for(law);
    std::vector<Case> cases;
    for (double tau : {1e12, -1e12, 1e100, 1e250}) cases.push_back({tau, 1e-3, 2e-3});
    const double phi = 2.5e-4;
    const double base = law == StrengthLaw::paper ? frictional_strength(p, sigma0, 0.0, phi) : 0.0;
    for (double excess : {1e-2, 1e3, 2e5, 5e6})
      for (double guess : {-1.0, 1e300, -1e300, not_a_number, inf, -inf, 0.0, 5e-324, 1e-200, 1e5})
        cases.push_back({base + excess, phi, guess});
    check_against_scalar(p, cases);
    std::vector<double> tau, state, guess, v(cases.size());
    for (const auto& c : cases) {
      tau.push_back(c.tau);
      state.push_back(c.state);
      guess.push_back(c.guess);
    }
    solve_slip_rate_batch(local(p), tau, state, guess, v);
    for (double x : v) CHECK(std::isfinite(x));
  }
  auto p = parameters_for(StrengthLaw::paper);
  p.a = 0.0;
  const double s0 = frictional_strength(p, sigma0, 0.0, 1e-3);
  check_against_scalar(p, {{s0 + 1e3, 1e-3, 0.0}, {-(s0 + 1e3), 1e-3, 1e-3}});
}

TEST_CASE("batch solve: failures name the node and carry the scalar solve's message") {
  const auto p = parameters_for(StrengthLaw::paper);
  const double phi_negative_s0 = p.phi_star * std::exp(-2.0 / p.b);  // strength at rest < 0
  const std::vector<std::pair<double, double>> bad = {
      {not_a_number, 2.5e-4}, {inf, 1.0}, {3e5, -1.0}, {3e5, not_a_number}, {0.0, phi_negative_s0}};
  for (const auto& [bad_tau, bad_state] : bad) {
    std::vector<double> tau(21, 3e5), state(21, 2.5e-4), guess(21, 1e-3), v(21);
    tau[13] = bad_tau;
    state[13] = bad_state;
    std::string scalar_message;
    try {
      solve_slip_rate(p, sigma0, eta, bad_tau, bad_state, 1e-3);
    } catch (const LocalSolveFailure& e) {
      scalar_message = e.what();
    }
    REQUIRE(!scalar_message.empty());
    try {
      solve_slip_rate_batch(local(p), tau, state, guess, v);
      FAIL("expected BatchFailure");
    } catch (const BatchFailure& e) {
      CHECK(e.index == 13);
      CHECK(std::string(e.what()) == scalar_message);
    }
  }
}

TEST_CASE("batch state update agrees with evolve_state (aging and slip laws)") {
  // Aging: phi e^{-x} + phi_ss (1 - e^{-x}), two positive terms; each factor is
  // within 2 ulp (exp, expm1), and h = sqrt(v^2 + v*^2) within 1.5 ulp of
  // hypot, which moves x and phi_ss by 1.5 ulp relative: in all a relative
  // error of (4 + 1.5 (1 + x)) eps per term, below 16 eps (1 + x).
  // Slip: exp of an argument z = ln(D/u) + psi0 e^{-u dt/D} made of terms
  // that each carry a few ulp of their size: relative error 8 eps (|ln(D/u)| +
  // |psi0| + 1).
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double dt = 2.5e-6;
  for (auto state_law : {StateLaw::aging, StateLaw::slip}) {
    const auto p = parameters_for(StrengthLaw::paper, state_law);
    std::vector<double> state, v, out;
    for (int i = 0; i < 1001; ++i) {
      state.push_back(std::pow(10.0, -8.0 + 9.0 * unit(rng)));
      const double u = i % 10 == 0 ? 0.0 : std::pow(10.0, -12.0 + 15.0 * unit(rng));  // up to 1e3 m/s
      v.push_back(i % 2 ? u : -u);
    }
    out.resize(state.size());
    evolve_state_batch(p, state, v, dt, out);
    double worst = 0.0;
    for (std::size_t i = 0; i < state.size(); ++i) {
      const double ref = evolve_state(p, state[i], v[i], dt);
      const double u = std::fabs(v[i]), D = p.characteristic_slip;
      double tolerance = 0.0;
      if (state_law == StateLaw::aging) {
        tolerance = 16 * DBL_EPSILON * (1 + std::hypot(u, p.v_star) * dt / D);
      } else {
        tolerance = u == 0.0 ? 0.0
                             : 8 * DBL_EPSILON *
                                   (std::fabs(std::log(D / u)) + std::fabs(std::log(u * state[i] / D)) + 1);
      }
      INFO(to_string(state_law) << " phi=" << state[i] << " v=" << v[i] << " batch=" << out[i]
                                << " scalar=" << ref);
      CHECK(out[i] > 0.0);
      CHECK(std::fabs(out[i] - ref) <= tolerance * ref);
      worst = std::max(worst, std::fabs(out[i] - ref) / ref / DBL_EPSILON);
    }
    MESSAGE(to_string(state_law) << ": largest batch-scalar difference " << worst << " eps");
    // In place (out aliases state) gives the same values.
    std::vector<double> in_place = state;
    evolve_state_batch(p, in_place, v, dt, in_place);
    CHECK(in_place == out);
  }
  // Invalid input fails loudly, naming the node.
  const auto p = parameters_for(StrengthLaw::paper);
  std::vector<double> state(9, 1e-3), v(9, 1e-3), out(9);
  state[4] = -1.0;
  try {
    evolve_state_batch(p, state, v, 1e-6, out);
    FAIL("expected BatchFailure");
  } catch (const BatchFailure& e) {
    CHECK(e.index == 4);
    CHECK(std::string(e.what()).find("state = -1") != std::string::npos);
  }
}

TEST_CASE("predictor-corrector batch: the scalar scheme, node by node, all laws") {
  // The scalar scheme of the time loop:
  //   phi_p = evolve(phi_old, v_old); v_p = solve(phi_p, v_old);
  //   phi_new = evolve(phi_old, (v_old + v_p)/2); v_new = solve(phi_new, v_p).
  // (a) v_new is the scalar solve at the batch's own phi_new: the batch-solve
  //     tolerance above.
  // (b) phi_new: the batch's v_p differs from the scalar's by the batch-solve
  //     tolerance dv; phi_new moves by (d phi_new / d v_p) dv (measured here by
  //     a finite difference, allowance 2x), plus the state update's own few-ulp
  //     error: 1e-13 relative, above both state-update tolerances of the test
  //     above for these inputs (u dt / D <= 5, |exponent| <= ~30).
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double dt = 2.5e-6;
  for (auto law : all_laws) {
    for (auto state_law : {StateLaw::aging, StateLaw::slip}) {
      const auto p = parameters_for(law, state_law);
      std::vector<double> tau, v_old, phi_old;
      for (int i = 0; i < 333; ++i) {
        const double u = std::pow(10.0, -9.0 + 9.0 * unit(rng));
        const double phi = std::pow(10.0, -5.0 + 5.0 * unit(rng));
        // Load near the steady value with a random change, sometimes reversed
        // or zero rate (stuck before); some paper-law nodes stick.
        double t = eta * u + frictional_strength(p, sigma0, u, phi);
        t *= 1.0 + 0.02 * (unit(rng) - 0.5);
        if (i % 17 == 0) t = -t;
        if (law == StrengthLaw::paper && i % 13 == 0) t = 0.9 * frictional_strength(p, sigma0, 0.0, phi);
        tau.push_back(t);
        v_old.push_back(i % 11 == 0 ? 0.0 : u);
        phi_old.push_back(phi);
      }
      std::vector<double> v_new(tau.size()), phi_new(tau.size());
      predictor_corrector_batch(local(p), dt, tau, v_old, phi_old, v_new, phi_new);
      for (std::size_t i = 0; i < tau.size(); ++i) {
        const double T = std::fabs(tau[i]);
        const double phi_p = evolve_state(p, phi_old[i], v_old[i], dt);
        const double v_p = solve_slip_rate(p, sigma0, eta, tau[i], phi_p, v_old[i]);
        const double phi_ref = evolve_state(p, phi_old[i], 0.5 * (v_old[i] + v_p), dt);
        INFO(to_string(law) << "/" << to_string(state_law) << " i=" << i << " tau=" << tau[i]
                            << " v_old=" << v_old[i] << " phi_old=" << phi_old[i]
                            << " v_new=" << v_new[i] << " phi_new=" << phi_new[i]
                            << " phi_ref=" << phi_ref);
        // (b)
        const double dv = 2e-12 * std::fabs(v_p) + rounding_allowance(p, T, std::fabs(v_p), phi_p);
        const double h = 1e-6 * std::fabs(v_p) + 1e-30;
        const double sensitivity =
            std::fabs(evolve_state(p, phi_old[i], 0.5 * (v_old[i] + v_p + h), dt) - phi_ref) / h;
        CHECK(std::fabs(phi_new[i] - phi_ref) <= 2.0 * sensitivity * dv + 1e-13 * phi_ref);
        // (a)
        const double v_ref = solve_slip_rate(p, sigma0, eta, tau[i], phi_new[i], v_p);
        if (v_ref == 0.0) {
          CHECK(v_new[i] == 0.0);
        } else {
          CHECK(std::fabs(v_new[i] - v_ref) <=
                2e-12 * std::fabs(v_ref) + rounding_allowance(p, T, std::fabs(v_ref), phi_new[i]));
        }
      }
    }
  }
}

TEST_CASE("predictor-corrector batch: deterministic, independent of threads and offsets") {
  const auto p = parameters_for(StrengthLaw::paper);
  const double dt = 2.5e-6;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const std::size_t n = 1000;  // several parallel chunks and a partial vector block
  std::vector<double> tau(n), v_old(n), phi_old(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double u = 2e-3 * std::pow(10.0, 2.0 * (unit(rng) - 0.5));
    phi_old[i] = p.characteristic_slip / u * (1 + 0.1 * (unit(rng) - 0.5));
    v_old[i] = u;
    tau[i] = (eta * u + frictional_strength(p, sigma0, u, phi_old[i])) * (1 + 1e-3 * (unit(rng) - 0.5));
  }
  const auto run = [&](int threads) {
    omp_set_num_threads(threads);
    std::vector<double> v(n), phi(n);
    predictor_corrector_parallel(local(p), dt, tau, v_old, phi_old, v, phi);
    return std::make_pair(v, phi);
  };
  const auto one = run(1), two = run(2), again = run(2);
  CHECK(one.first == two.first);
  CHECK(one.second == two.second);
  CHECK(two.first == again.first);
  // A node's result does not depend on where it sits in the span.
  std::vector<double> v(n - 3), phi(n - 3);
  predictor_corrector_batch(local(p), dt, std::span(tau).subspan(3), std::span(v_old).subspan(3),
                            std::span(phi_old).subspan(3), v, phi);
  for (std::size_t i = 0; i < n - 3; ++i) {
    CHECK(v[i] == one.first[i + 3]);
    CHECK(phi[i] == one.second[i + 3]);
  }
  // A failing node is reported with its index, the lowest one when several fail.
  tau[700] = not_a_number;
  tau[300] = inf;
  std::vector<double> v2(n), phi2(n);
  omp_set_num_threads(2);
  try {
    predictor_corrector_parallel(local(p), dt, tau, v_old, phi_old, v2, phi2);
    FAIL("expected BatchFailure");
  } catch (const BatchFailure& e) {
    CHECK(e.index == 300);
    CHECK(std::string(e.what()).find("tau_history = inf") != std::string::npos);
  }
}
