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
// * Profiles: sampling at the nodes and the per-node checks.
#include <doctest/doctest.h>

#include <cfloat>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

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
