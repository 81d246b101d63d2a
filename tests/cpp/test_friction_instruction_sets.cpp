// The batch friction kernels compiled for each instruction set
// (friction/batch_kernels.hpp) against the scalar routines, every set this CPU
// can run in one process: a portable binary runs baseline (SSE2), AVX2 or
// AVX-512 code depending on the machine, and each must give the scalar
// solve's results.
//
// Tolerances (the same reasoning as test_friction_batch_solve.cpp).  The
// scalar and batch solves share their start and acceptance
// (friction/local_solve_tolerances.hpp): both stop when the Newton step in
// ln u is <= 1e-6, which leaves each result within 1e-12 relative of the root,
// so they agree to 2e-12 relative.  The kernels evaluate the residual with
// xsimd's exp/log/log1p (1-2 ulp, differently rounded per instruction set, and
// contracted to FMA on AVX2/AVX-512), which moves the root by a few eps times
// the terms of g over |dg/du|: allowance 16 eps (T + |strength| + eta u) /
// |dg/du|.  Sticking is decided exactly as by the scalar solve: 0.0, bit for
// bit.  The state update is a closed form: aging 16 eps (1 + v dt / D)
// relative (each factor within 2 ulp, h = sqrt(v^2 + v*^2) within 1.5 ulp of
// hypot).
#include <doctest/doctest.h>

#include "friction_test_parameters.hpp"

#include <cfloat>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "friction/batch_kernels.hpp"
#include "friction/friction_law.hpp"
#include "simd/instruction_set.hpp"

using namespace slipstrip;

namespace {

constexpr double sigma0 = 1e6;                           // [Pa]
const double eta = 9e9 / (2 * std::sqrt(9e9 / 1200.0));  // mu / (2 c_s), Table S1 [Pa s/m]
constexpr double dt = 2.5e-6;                            // [s]

double solve_tolerance(const FrictionParameters& p, double T, double u, double phi) {
  const double slope = eta + frictional_strength_dv(p, sigma0, u, phi);
  const double terms = T + std::fabs(frictional_strength(p, sigma0, u, phi)) + eta * u;
  return 2e-12 * u + 16 * DBL_EPSILON * terms / slope;
}

// Loads near steady sliding over four decades of slip rate, some reversed,
// some sticking (paper law), some cold starts; 203 nodes (a partial block for
// every width).
struct Nodes {
  std::vector<double> tau, phi, v;
};
Nodes nodes_for(const FrictionParameters& p, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Nodes n;
  for (int i = 0; i < 203; ++i) {
    const double u = std::pow(10.0, -7.0 + 4.0 * unit(rng));
    const double phi = p.characteristic_slip / u * std::pow(10.0, unit(rng) - 0.5);
    double t = (eta * u + frictional_strength(p, sigma0, u, phi)) * (1.0 + 0.02 * (unit(rng) - 0.5));
    if (i % 17 == 0) t = -t;
    if (p.strength_law == StrengthLaw::paper && i % 13 == 0)
      t = 0.9 * frictional_strength(p, sigma0, 0.0, phi);
    n.tau.push_back(t);
    n.phi.push_back(phi);
    n.v.push_back(i % 11 == 0 ? 0.0 : u);
  }
  return n;
}

}  // namespace

TEST_CASE("every usable instruction set: local solve and predictor-corrector against the scalar routines") {
  const auto sets = simd::usable_instruction_sets();
  for (auto set : sets) {
    const BatchKernels& k = batch_kernels_for(set);
    CHECK(k.set == set);
    INFO("instruction set " << simd::to_string(set) << " (" << k.width << " doubles)");
    for (auto law : {StrengthLaw::paper, StrengthLaw::dieterich_ruina, StrengthLaw::regularized}) {
      for (auto state_law : {StateLaw::aging, StateLaw::slip}) {
        const auto p = testing::parameters_for(law, state_law);
        INFO(to_string(law) << "/" << to_string(state_law));
        const LocalSolveParameters params{p, sigma0, eta};
        const Nodes n = nodes_for(p, 7);
        const std::size_t count = n.tau.size();

        // Local solve, warm-started from v.
        std::vector<double> v(count);
        const BatchCounts counts = k.solve_slip_rate(params, n.tau, n.phi, n.v, v);
        CHECK(counts.scalar_nodes * 10 < counts.solves);  // the vector path did the work
        for (std::size_t i = 0; i < count; ++i) {
          const double ref = solve_slip_rate(p, sigma0, eta, n.tau[i], n.phi[i], n.v[i]);
          INFO("node " << i << " batch " << v[i] << " scalar " << ref);
          if (ref == 0.0) {
            CHECK(v[i] == 0.0);
          } else {
            CHECK(std::fabs(v[i] - ref) <= solve_tolerance(p, std::fabs(n.tau[i]), std::fabs(ref), n.phi[i]));
          }
        }

        // Predictor-corrector: v_new is the scalar solve at the kernel's own
        // phi_new, warm-started from the scalar predictor.
        std::vector<double> v_new(count), phi_new(count);
        k.predictor_corrector(params, dt, n.tau, n.v, n.phi, v_new, phi_new);
        for (std::size_t i = 0; i < count; ++i) {
          const double phi_p = evolve_state(p, n.phi[i], n.v[i], dt);
          const double v_p = solve_slip_rate(p, sigma0, eta, n.tau[i], phi_p, n.v[i]);
          const double ref = solve_slip_rate(p, sigma0, eta, n.tau[i], phi_new[i], v_p);
          INFO("node " << i << " v_new " << v_new[i] << " scalar " << ref);
          CHECK(phi_new[i] > 0.0);
          if (ref == 0.0) {
            CHECK(v_new[i] == 0.0);
          } else {
            CHECK(std::fabs(v_new[i] - ref) <=
                  solve_tolerance(p, std::fabs(n.tau[i]), std::fabs(ref), phi_new[i]));
          }
        }
      }
    }
  }
}

TEST_CASE("every usable instruction set: aging-law state update against evolve_state") {
  const auto p = testing::parameters_for(StrengthLaw::paper, StateLaw::aging);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<double> state, v;
  for (int i = 0; i < 301; ++i) {
    state.push_back(std::pow(10.0, -8.0 + 9.0 * unit(rng)));
    v.push_back((i % 2 ? 1.0 : -1.0) * std::pow(10.0, -12.0 + 15.0 * unit(rng)));
  }
  for (auto set : simd::usable_instruction_sets()) {
    INFO("instruction set " << simd::to_string(set));
    std::vector<double> out(state.size());
    batch_kernels_for(set).evolve_state(p, state, v, dt, out);
    for (std::size_t i = 0; i < state.size(); ++i) {
      const double ref = evolve_state(p, state[i], v[i], dt);
      const double x = std::hypot(v[i], p.v_star) * dt / p.characteristic_slip;
      CHECK(std::fabs(out[i] - ref) <= 16 * DBL_EPSILON * (1 + x) * ref);
    }
  }
}

TEST_CASE("batch_kernels() is the copy for the chosen instruction set") {
  CHECK(batch_kernels().set == simd::instruction_set());
  CHECK(batch_width() == batch_kernels().width);
  // Width: 8 doubles for AVX-512, 4 for AVX2; the baseline is the build's own
  // (2 for SSE2, more with SLIPSTRIP_NATIVE=ON on a wider CPU).
  for (auto set : simd::usable_instruction_sets()) {
    const std::size_t width = batch_kernels_for(set).width;
    if (set == simd::InstructionSet::avx512) CHECK(width == 8);
    if (set == simd::InstructionSet::avx2) CHECK(width == 4);
    if (set == simd::InstructionSet::baseline) CHECK(width >= 1);
  }
}
