// Friction parameters per node (friction/parameter_profile.hpp) and the batch
// solve with per-node spans (friction/batch_solve.hpp).
//
// * Per-node spans that hold the scalar at every node give the same results
//   bit for bit as the scalar parameters: every lane computes from the same
//   values with the same operations (docs/friction.md, "Parameters along x").
// * Nodes with different parameters in one batch each agree with the scalar
//   solve of that node's own parameters, with the tolerance of
//   test_friction_batch_solve.cpp (1e-12 relative plus 16 eps of the terms
//   over the slope): the batch must not mix up lanes.
// * A normal stress per node (in-plane pairs of different bodies): the same
//   two checks (a span holding sigma0 everywhere is bit for bit the scalar;
//   different values agree node by node with the scalar solve at that node's
//   sigma), and the predictor-corrector with sigma_eff advanced like the state
//   (relaxation over a slip or a time scale, Linker-Dieterich on and off, open
//   nodes) against its scalar scheme node by node; tolerances at the test.
// * Profiles: sampling at the nodes and the per-node checks.
#include <doctest/doctest.h>

#include <cfloat>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "friction_test_parameters.hpp"
#include <omp.h>

#include "friction/batch_solve.hpp"
#include "friction/friction_law.hpp"
#include "friction/parameter_profile.hpp"

using namespace slipstrip;

namespace {

constexpr double sigma0 = 1e6;                           // [Pa]
const double eta = 9e9 / (2 * std::sqrt(9e9 / 1200.0));  // mu / (2 c_s), Table S1 [Pa s/m]

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

// Loads around steady sliding at v0 = 2e-3 m/s for parameters p: a spread of
// states and loads so that some nodes stick, most slide.
struct Fields {
  std::vector<double> tau, v_old, phi_old;
};
Fields fields_for(const std::vector<FrictionParameters>& params, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> spread(-1.0, 1.0);
  Fields f;
  for (const auto& p : params) {
    const double v = 2e-3 * std::exp(3.0 * spread(rng));
    const double phi = steady_state(p, v) * std::exp(0.5 * spread(rng));
    f.tau.push_back(frictional_strength(p, sigma0, v, phi) + eta * v * (1.0 + 0.3 * spread(rng)));
    f.v_old.push_back(v);
    f.phi_old.push_back(phi);
  }
  return f;
}

}  // namespace

TEST_CASE("per-node spans holding the scalar values: bit for bit the scalar batch, all laws") {
  for (StrengthLaw law : {StrengthLaw::paper, StrengthLaw::dieterich_ruina, StrengthLaw::regularized}) {
    for (StateLaw state_law : {StateLaw::aging, StateLaw::slip}) {
      FrictionParameters p;
      p.strength_law = law;
      p.state_law = state_law;
      if (law != StrengthLaw::paper) p.f0 = 0.6, p.b = 0.01, p.a = 0.008;  // DR meaning of f0, b
      const std::size_t n = 203;  // not a multiple of the batch width: a padded block too
      const Fields f = fields_for(std::vector<FrictionParameters>(n, p), 7);
      const std::vector<double> f0(n, p.f0), a(n, p.a), b(n, p.b), D(n, p.characteristic_slip);
      const LocalSolveParameters scalar{p, sigma0, eta};
      const LocalSolveParameters spans{p, sigma0, eta, {f0, a, b, D}};
      std::vector<double> v1(n), phi1(n), v2(n), phi2(n);
      const double dt = 1.78e-7;
      predictor_corrector_parallel(scalar, dt, f.tau, f.v_old, f.phi_old, v1, phi1);
      predictor_corrector_parallel(spans, dt, f.tau, f.v_old, f.phi_old, v2, phi2);
      CAPTURE(to_string(law));
      CAPTURE(to_string(state_law));
      CHECK(same_bits(v1, v2));
      CHECK(same_bits(phi1, phi2));
      solve_slip_rate_parallel(scalar, f.tau, f.phi_old, f.v_old, v1);
      solve_slip_rate_parallel(spans, f.tau, f.phi_old, f.v_old, v2);
      CHECK(same_bits(v1, v2));
    }
  }
}

TEST_CASE("different parameters at every node: each node agrees with its own scalar solve") {
  const std::size_t n = 300;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  FrictionParameters base;  // Table S1, paper law, aging
  std::vector<FrictionParameters> params(n, base);
  std::vector<double> f0(n), a(n), b(n), D(n);
  for (std::size_t i = 0; i < n; ++i) {
    auto& p = params[i];
    p.f0 = 0.2 + 0.2 * unit(rng);
    p.a = i % 37 == 0 ? 0.0 : 0.002 + 0.03 * unit(rng);  // a = 0: the closed form (scalar path)
    p.b = 0.03 + 0.1 * unit(rng);
    p.characteristic_slip = 5e-7 * std::exp(2.0 * (unit(rng) - 0.5));
    f0[i] = p.f0, a[i] = p.a, b[i] = p.b, D[i] = p.characteristic_slip;
  }
  const Fields f = fields_for(params, 11);
  const LocalSolveParameters spans{base, sigma0, eta, {f0, a, b, D}};
  std::vector<double> v(n);
  solve_slip_rate_parallel(spans, f.tau, f.phi_old, f.v_old, v);
  int sticking = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const auto& p = params[i];
    const double expected = solve_slip_rate(p, sigma0, eta, f.tau[i], f.phi_old[i], f.v_old[i]);
    CAPTURE(i);
    if (expected == 0.0) {
      ++sticking;
      CHECK(v[i] == 0.0);
      continue;
    }
    const double u = std::fabs(expected);
    const double slope = eta + frictional_strength_dv(p, sigma0, u, f.phi_old[i]);
    const double terms =
        std::fabs(f.tau[i]) + std::fabs(frictional_strength(p, sigma0, u, f.phi_old[i])) + eta * u;
    CHECK(std::fabs(v[i] - expected) <= 2e-12 * u + 16 * DBL_EPSILON * terms / slope);
  }
  MESSAGE("nodes sticking: " << sticking << " of " << n);

  // The state update with per-node D against evolve_state node by node.
  std::vector<double> v_new(n), phi_new(n);
  predictor_corrector_parallel(spans, 1.78e-7, f.tau, f.v_old, f.phi_old, v_new, phi_new);
  for (std::size_t i = 0; i < n; ++i) {
    const auto& p = params[i];
    // The scheme at node i with the scalar routines (predictor-corrector).
    const double phi_p = evolve_state(p, f.phi_old[i], f.v_old[i], 1.78e-7);
    const double v_p = solve_slip_rate(p, sigma0, eta, f.tau[i], phi_p, f.v_old[i]);
    const double phi_c = evolve_state(p, f.phi_old[i], 0.5 * (f.v_old[i] + v_p), 1.78e-7);
    CAPTURE(i);
    // The corrector's state depends on v_p (1e-12 relative, times d phi / d v
    // over one step: tiny) and on the update's own rounding (a few ulp).
    CHECK(std::fabs(phi_new[i] - phi_c) <= 1e-12 * phi_c);
  }
}

namespace {

// The batch-solve tolerance of test_friction_batch_solve.cpp at normal stress
// sigma: 2e-12 relative (both solves stop within 1e-12 of the root) plus
// 16 eps of the terms of g over |dg/du| (xsimd's 1-2 ulp exp/log/log1p).
double solve_tolerance(const FrictionParameters& p, double sigma, double T, double u, double phi) {
  const double slope = eta + frictional_strength_dv(p, sigma, u, phi);
  const double terms = T + std::fabs(frictional_strength(p, sigma, u, phi)) + eta * u;
  return 2e-12 * u + 16 * DBL_EPSILON * terms / slope;
}

const std::vector<StrengthLaw> all_laws = {StrengthLaw::paper, StrengthLaw::dieterich_ruina,
                                           StrengthLaw::regularized};

}  // namespace

TEST_CASE("a normal stress per node: sigma0 everywhere is bit for bit the scalar, others node by node") {
  for (StrengthLaw law : all_laws) {
    const FrictionParameters p = testing::parameters_for(law);
    const std::size_t n = 203;
    const Fields f = fields_for(std::vector<FrictionParameters>(n, p), 5);
    const std::vector<double> same(n, sigma0);
    LocalSolveParameters scalar{p, sigma0, eta};
    LocalSolveParameters spans{p, 0.0, eta};  // its scalar sigma must not be used
    spans.normal_stress_per_node = same;
    std::vector<double> v1(n), v2(n), phi1(n), phi2(n);
    CAPTURE(to_string(law));
    solve_slip_rate_parallel(scalar, f.tau, f.phi_old, f.v_old, v1);
    solve_slip_rate_parallel(spans, f.tau, f.phi_old, f.v_old, v2);
    CHECK(same_bits(v1, v2));
    predictor_corrector_parallel(scalar, 1.78e-7, f.tau, f.v_old, f.phi_old, v1, phi1);
    predictor_corrector_parallel(spans, 1.78e-7, f.tau, f.v_old, f.phi_old, v2, phi2);
    CHECK(same_bits(v1, v2));
    CHECK(same_bits(phi1, phi2));

    // sigma from 0.5 to 1.5 sigma0, with the loads unchanged: some nodes now
    // stick, others slide faster; nodes with sigma = 0 or < 0 go to the scalar
    // solve (which reports them) and are checked to fail there too.
    std::mt19937_64 rng(9);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<double> sigma(n);
    for (auto& s : sigma) s = sigma0 * (0.5 + unit(rng));
    spans.normal_stress_per_node = sigma;
    solve_slip_rate_parallel(spans, f.tau, f.phi_old, f.v_old, v2);
    int sticking = 0;
    for (std::size_t i = 0; i < n; ++i) {
      const double expected = solve_slip_rate(p, sigma[i], eta, f.tau[i], f.phi_old[i], f.v_old[i]);
      CAPTURE(i);
      if (expected == 0.0) {
        ++sticking;
        CHECK(v2[i] == 0.0);
        continue;
      }
      CHECK(std::fabs(v2[i] - expected) <=
            solve_tolerance(p, sigma[i], std::fabs(f.tau[i]), std::fabs(expected), f.phi_old[i]));
    }
    MESSAGE(to_string(law) << ": nodes sticking " << sticking << " of " << n);
    sigma[17] = 0.0;
    try {
      solve_slip_rate_parallel(spans, f.tau, f.phi_old, f.v_old, v2);
      // The regularized law has strength(0) = 0 at sigma = 0: the scalar solve
      // may return; the node must then have the scalar solve's value.
      CHECK(v2[17] == solve_slip_rate(p, 0.0, eta, f.tau[17], f.phi_old[17], f.v_old[17]));
    } catch (const BatchFailure& e) {
      CHECK(e.index == 17);
    }
  }
}

namespace {

// One step's inputs with a normal stress that varies: around steady sliding
// at sigma_old, with sigma changing by up to +-5 % over the step, sigma_eff
// lagging sigma by up to +-2 %, a few nodes open at the new level (sigma = 0)
// and, when asked, a few with sigma_eff = 0 (after a long opening).
struct NormalFields {
  std::vector<double> tau, v_old, phi_old, s_old, s_new, e_old;
};
NormalFields normal_fields_for(const FrictionParameters& p, std::size_t n, unsigned seed, bool zero_effective) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  NormalFields f;
  for (std::size_t i = 0; i < n; ++i) {
    const double u = std::pow(10.0, -8.0 + 8.0 * unit(rng));
    const double phi = steady_state(p, u) * std::exp(0.5 * (unit(rng) - 0.5));
    const double s_old = sigma0 * (0.5 + unit(rng));
    const double s_new = i % 23 == 5 ? 0.0 : s_old * (1.0 + 0.1 * (unit(rng) - 0.5));
    const double e_old = zero_effective && i % 29 == 3 ? 0.0 : s_old * (1.0 + 0.04 * (unit(rng) - 0.5));
    double t = (eta * u + frictional_strength(p, e_old > 0.0 ? e_old : s_old, u, phi)) *
               (1.0 + 0.02 * (unit(rng) - 0.5));
    if (i % 17 == 0) t = -t;
    f.tau.push_back(t);
    f.v_old.push_back(i % 11 == 0 ? 0.0 : (i % 19 == 0 ? -u : u));
    f.phi_old.push_back(phi);
    f.s_old.push_back(s_old);
    f.s_new.push_back(s_new);
    f.e_old.push_back(e_old);
  }
  return f;
}

}  // namespace

namespace {

// Node i of a batch step (v, phi, e) against the scalar scheme,
// predictor_corrector_normal_stress_node:
// (a) v is the scalar solve at the batch's own phi and sigma_eff, started
//     from the scalar v_p: the batch-solve tolerance.
// (b) sigma_eff and phi: the batch's v_p differs from the scalar's by dv (the
//     batch-solve tolerance at sigma_eff_p); both move by their derivative in
//     v_p (finite difference, allowance 2x) times dv.  Besides, sigma_eff has
//     the rounding of its closed form: xsimd's exp/expm1 are 1-2 ulp, so 16 eps
//     of the magnitudes it sums (sigma_new, |e_old - s_old|, |s_new - s_old|);
//     phi the state update's few ulp (1e-13 relative, as for
//     predictor_corrector_batch), plus, with Linker-Dieterich, the factor
//     (e/e_old)^(-alpha/(2B)) twice: relative change (alpha/B) de/e from
//     sigma_eff's rounding, and 16 eps for xsimd's pow.
// Open nodes and nodes with sigma_eff = 0 take the scalar routine: bit for bit.
void check_against_scheme(const FrictionParameters& p, const NormalStressMemory& response, double dt,
                          const NormalFields& f, std::size_t i, double v, double phi, double e) {
  CAPTURE(i);
  double v_ref = 0.0, phi_ref = 0.0, e_ref = 0.0;
  predictor_corrector_normal_stress_node(p, eta, response, dt, f.tau[i], f.v_old[i], f.phi_old[i], f.s_old[i],
                                         f.s_new[i], f.e_old[i], v_ref, phi_ref, e_ref);
  if (f.s_new[i] == 0.0 || (p.linker_dieterich > 0.0 && f.e_old[i] == 0.0)) {
    CHECK(v == v_ref);
    CHECK(phi == phi_ref);
    CHECK(e == e_ref);
    return;
  }
  const double T = std::fabs(f.tau[i]);
  // The scalar predictor, and the corrector's state and sigma_eff as
  // functions of v_p.
  const double e_p =
      response.relaxed(f.e_old[i], f.s_old[i], f.s_new[i], f.v_old[i], dt);
  const double phi_p = evolve_state_with_normal_stress(p, f.phi_old[i], f.v_old[i], dt, f.e_old[i], e_p);
  const double v_p = solve_slip_rate(p, e_p, eta, f.tau[i], phi_p, f.v_old[i]);
  const auto corrector = [&](double vp, double& e_c, double& phi_c) {
    const double v_mid = 0.5 * (f.v_old[i] + vp);
    e_c = response.relaxed(f.e_old[i], f.s_old[i], f.s_new[i], v_mid, dt);
    phi_c = evolve_state_with_normal_stress(p, f.phi_old[i], v_mid, dt, f.e_old[i], e_c);
  };
  double e_c = 0.0, phi_c = 0.0, e_h = 0.0, phi_h = 0.0;
  corrector(v_p, e_c, phi_c);
  REQUIRE(e_c == e_ref);  // the reference is this scheme
  REQUIRE(phi_c == phi_ref);
  const double dv = v_p == 0.0 ? 0.0 : solve_tolerance(p, e_p, T, std::fabs(v_p), phi_p);
  const double h = 1e-6 * std::fabs(v_p) + 1e-30;
  corrector(v_p + h, e_h, phi_h);
  const double e_rounding = 16 * DBL_EPSILON *
                            (std::fabs(f.s_new[i]) + std::fabs(f.e_old[i] - f.s_old[i]) +
                             std::fabs(f.s_new[i] - f.s_old[i]));
  const double e_tolerance = 2.0 * std::fabs(e_h - e_ref) / h * dv + e_rounding;
  CHECK(std::fabs(e - e_ref) <= e_tolerance);
  const double c = p.linker_dieterich > 0.0 ? p.linker_dieterich / state_log_coefficient(p) : 0.0;
  const double ld_rounding = c > 0.0 ? c * e_tolerance / e_ref + 16 * DBL_EPSILON : 0.0;
  CHECK(std::fabs(phi - phi_ref) <= 2.0 * std::fabs(phi_h - phi_ref) / h * dv + (1e-13 + ld_rounding) * phi_ref);
  // (a)
  const double v_own = solve_slip_rate(p, e, eta, f.tau[i], phi, v_p);
  if (v_own == 0.0) {
    CHECK(v == 0.0);
  } else {
    CHECK(std::fabs(v - v_own) <= solve_tolerance(p, e, T, std::fabs(v_own), phi));
  }
}

}  // namespace

TEST_CASE("predictor-corrector with a varying normal stress: the scalar scheme node by node") {
  // Every strength and state law, Linker-Dieterich off and on, sigma_eff
  // relaxing over the slip D or over a time (check_against_scheme).
  const double dt = 2.5e-6;
  const std::size_t n = 331;
  int cases = 0;
  for (StrengthLaw law : all_laws)
    for (StateLaw state_law : {StateLaw::aging, StateLaw::slip})
      for (double alpha : {0.0, 0.3})
        for (double relaxation_time : {0.0, 1e-5}) {
          FrictionParameters p = testing::parameters_for(law, state_law);
          p.linker_dieterich = alpha;
          const NormalStressMemory response{relaxation_time, p.characteristic_slip, p.v_star};
          const NormalFields f = normal_fields_for(p, n, 13 + cases, alpha > 0.0);
          const LocalSolveParameters params{p, sigma0, eta};
          std::vector<double> v(n), phi(n), e(n);
          const NormalStressStep step{f.s_old, f.s_new, f.e_old, e};
          const BatchCounts counts =
              predictor_corrector_normal_stress_parallel(params, response, dt, f.tau, f.v_old, f.phi_old, step, v, phi);
          CAPTURE(to_string(law));
          CAPTURE(to_string(state_law));
          CAPTURE(alpha);
          CAPTURE(relaxation_time);
          // Most nodes are solved by the vector code (else this tests nothing).
          CHECK(counts.scalar_nodes < static_cast<long long>(n) / 5);
          MESSAGE(to_string(law) << "/" << to_string(state_law) << " alpha " << alpha << " t_sigma "
                                 << relaxation_time << ": scalar nodes " << counts.scalar_nodes << " of " << n
                                 << ", evaluations per solve "
                                 << static_cast<double>(counts.evaluations) / static_cast<double>(counts.solves));
          for (std::size_t i = 0; i < n; ++i) check_against_scheme(p, response, dt, f, i, v[i], phi[i], e[i]);
          ++cases;
        }
  CHECK(cases == 24);
}

TEST_CASE("predictor-corrector with a varying normal stress: per-node friction, threads, failures") {
  const double dt = 2.5e-6;
  const std::size_t n = 1000;  // several parallel chunks and a partial vector block
  FrictionParameters p = testing::parameters_for(StrengthLaw::paper);
  p.linker_dieterich = 0.2;
  const NormalStressMemory response{0.0, p.characteristic_slip, p.v_star};
  NormalFields f = normal_fields_for(p, n, 21, false);
  std::vector<double> a(n, p.a);
  for (std::size_t i = 0; i < n; ++i) a[i] *= 1.0 + 0.5 * std::sin(0.01 * static_cast<double>(i));
  const LocalSolveParameters params{p, sigma0, eta, {{}, a, {}, {}}};
  const auto run = [&](int threads) {
    omp_set_num_threads(threads);
    std::vector<double> v(n), phi(n), e(n);
    predictor_corrector_normal_stress_parallel(params, response, dt, f.tau, f.v_old, f.phi_old,
                                               {f.s_old, f.s_new, f.e_old, e}, v, phi);
    return std::vector<std::vector<double>>{v, phi, e};
  };
  const auto one = run(1), two = run(2);
  CHECK(one == two);
  // Per-node a: each node as the scalar scheme with its own a.
  for (std::size_t i = 0; i < n; ++i) {
    FrictionParameters pi = p;
    pi.a = a[i];
    check_against_scheme(pi, response, dt, f, i, one[0][i], one[1][i], one[2][i]);
  }
  // The lowest failing node is reported, with the scalar routine's message.
  f.tau[700] = std::numeric_limits<double>::quiet_NaN();
  f.phi_old[300] = -1.0;
  omp_set_num_threads(2);
  std::vector<double> v(n), phi(n), e(n);
  try {
    predictor_corrector_normal_stress_parallel(params, response, dt, f.tau, f.v_old, f.phi_old,
                                               {f.s_old, f.s_new, f.e_old, e}, v, phi);
    FAIL("expected BatchFailure");
  } catch (const BatchFailure& err) {
    CHECK(err.index == 300);
    // The scalar state update's message (its state is the one scaled by the
    // Linker-Dieterich factor, so not exactly -1).
    CHECK(std::string(err.what()).find("evolve_state: state = -") != std::string::npos);
  }
}

TEST_CASE("per-node spans of the wrong length are refused") {
  FrictionParameters p;
  const std::vector<double> two(2, 0.01), tau(3, 1e5), phi(3, 1e-4), guess(3, 2e-3);
  std::vector<double> out(3);
  const LocalSolveParameters bad{p, sigma0, eta, {{}, two, {}, {}}};
  CHECK_THROWS_AS(solve_slip_rate_parallel(bad, tau, phi, guess, out), std::invalid_argument);
}

TEST_CASE("profiles sampled at the nodes") {
  ParameterProfile linear{ParameterProfile::Kind::piecewise_linear, {0.0, 1.0, 1.2, 4.0},
                          {0.005, 0.005, 0.02, 0.02}, ""};
  CHECK(linear.at(0.5) == 0.005);
  CHECK(linear.at(1.1) == doctest::Approx(0.0125).epsilon(1e-14));
  CHECK(linear.at(1.2) == 0.02);
  CHECK(linear.at(5.0) == 0.02);   // constant beyond the last point
  CHECK(linear.at(-1.0) == 0.005);  // and before the first
  ParameterProfile steps{ParameterProfile::Kind::piecewise_constant, {1.0, 2.0}, {0.1, 0.2}, ""};
  CHECK(steps.at(0.0) == 0.1);
  CHECK(steps.at(1.0) == 0.1);
  CHECK(steps.at(1.9999) == 0.1);
  CHECK(steps.at(2.0) == 0.2);
  const auto nodes = linear.at_nodes(8, 0.5, "friction.a");  // x = 0, 0.5, ..., 3.5
  CHECK(nodes == std::vector<double>{0.005, 0.005, 0.005 + 0.0, 0.02, 0.02, 0.02, 0.02, 0.02});

  ParameterProfile file{ParameterProfile::Kind::node_file, {}, {1e-7, 2e-7}, "/some/file"};
  CHECK_THROWS_WITH_AS(file.at_nodes(3, 0.1, "friction.characteristic_slip"),
                       doctest::Contains("2 values, expected one per node (3 = geometry.nodes)"),
                       std::invalid_argument);
}

TEST_CASE("per-node checks name the key, the node, its x and the value") {
  FrictionParameters scalars;
  FrictionProfiles profiles;
  profiles.a = ParameterProfile{ParameterProfile::Kind::piecewise_constant, {0.0, 1.0},
                                {0.01, -0.001}, ""};
  // 16 nodes over 4 m: node 4 is the first at x >= 1.
  try {
    resolve_friction_nodes(scalars, profiles, 16, 0.25);
    FAIL("no error");
  } catch (const std::invalid_argument& e) {
    CHECK(std::string(e.what()) ==
          "friction.a at node 4 (x = 1 m) = -0.001 is out of range: expected 0 <= a <= 10 "
          "(dimensionless)");
  }
  profiles.a.reset();
  profiles.characteristic_slip = ParameterProfile{ParameterProfile::Kind::piecewise_linear,
                                                  {0.0, 4.0}, {5e-7, 2.0}, ""};
  CHECK_THROWS_WITH_AS(resolve_friction_nodes(scalars, profiles, 16, 0.25),
                       doctest::Contains("friction.characteristic_slip at node 8 (x = 2 m) = "),
                       std::invalid_argument);
}

TEST_CASE("uniform_friction: constant profiles are uniform, varying ones are refused by name") {
  FrictionParameters scalars;
  FrictionProfiles profiles;
  profiles.b = ParameterProfile{ParameterProfile::Kind::piecewise_linear, {0.0, 4.0},
                                {0.06, 0.06}, ""};
  scalars.b = std::nan("");  // as the config leaves it
  const FrictionParameters u = uniform_friction(scalars, profiles, 16, 0.25, "Lc");
  CHECK(u.b == 0.06);
  CHECK(u.a == scalars.a);
  profiles.a = ParameterProfile{ParameterProfile::Kind::piecewise_constant, {0.0, 2.0},
                                {0.005, 0.03}, ""};
  CHECK_THROWS_WITH_AS(uniform_friction(scalars, profiles, 16, 0.25, "linear stability"),
                       doctest::Contains("linear stability needs friction parameters that are "
                                         "the same at every node, but friction.a vary"),
                       std::invalid_argument);
}
