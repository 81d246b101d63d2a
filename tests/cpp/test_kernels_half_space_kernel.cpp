// The half-space relaxation kernel g(tau) and its sum-of-exponentials
// representation (kernels/half_space_kernel.hpp) against independent
// references:
//   - a numerical inverse Laplace transform (Durbin) of the closed-form
//     half-space response S_inf(k, s) (strip_response with H = inf, itself
//     checked against a 4x4 boundary-value solve in
//     test_kernels_transfer_function.cpp) -- a different route to g;
//   - the exact limits g(0) = 0, g'(0) = 7/4 - 2 r, g(inf) = 1 - r^2 (with the
//     tau^(-1/2) approach), and the
//     high-frequency expansion of G used by the passivity correction;
//   - convergence of the representation under refinement, over 1e9 in tau.
#include <doctest/doctest.h>

#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <vector>

#include "inverse_laplace.hpp"
#include "kernels/half_space_kernel.hpp"
#include "kernels/strip_response.hpp"

using namespace slipstrip;
using cplx = std::complex<double>;

namespace {

ElasticMaterial material_for(PlaneCondition plane) {
  ElasticMaterial m;  // Table S1: mu 9 GPa, nu 0.33, rho 1200
  m.plane = plane;
  return m;
}

double speed_ratio_squared(const ElasticMaterial& m) { return 1.0 / m.wave_speed_ratio_squared(); }

}  // namespace

TEST_CASE("half-space kernel: exponential sum matches the inverse Laplace transform of S_inf") {
  for (auto plane : {PlaneCondition::strain, PlaneCondition::stress}) {
    const auto m = material_for(plane);
    const double r2 = speed_ratio_squared(m), r = std::sqrt(r2);
    const double cs = m.shear_wave_speed(), mu = m.shear_modulus;
    const double c2 = 1.75 - 2 * r, c4 = 1.1875 - 1 / r;
    // G(p) from the half-space response at k = 1/m, s = c_s p; minus the two
    // leading high-frequency terms c2/p^2 + c4/p^4, carried by
    // c2/(p^2+1) + (c4+c2)/(p^2+1)^2 whose inverses are known, so that the
    // Durbin series converges fast (remainder O(p^-6)).
    auto transform = [&](cplx p) {
      const cplx G = half_space_response(m, 1.0, cs * p) / (cs * p * mu / cs) - 0.5;
      const cplx q = p * p + 1.0;
      return G - c2 / q - (c4 + c2) / (q * q);
    };
    const double dtau = 0.005;
    const int count = 20001;  // tau up to 100 (T_p = 164)
    const auto remainder = testing::inverse_laplace(transform, dtau, 1 << 16, count);
    const auto sum = half_space_exponential_sum(r2, dtau, 1e10, 10);
    double worst = 0.0, worst_tau = 0.0;
    for (int j = 1; j < count; ++j) {
      const double tau = j * dtau;
      const double reference = remainder[j] + c2 * std::sin(tau) +
                               0.5 * (c4 + c2) * (std::sin(tau) - tau * std::cos(tau));
      const double err = std::abs(evaluate(sum, tau) - reference);
      if (err > worst) {
        worst = err;
        worst_tau = tau;
      }
    }
    MESSAGE((plane == PlaneCondition::strain ? "strain" : "stress")
            << ": " << sum.rate.size() << " exponentials, max |g_sum - g_Durbin| = " << worst
            << " at tau = " << worst_tau << " (g(inf) = " << 1 - r2 << ")");
    // g is O(1); both routes are accurate to ~1e-10 (Durbin: aliasing e^-24,
    // series remainder O(dtau^5)); 1e-8 leaves room for rounding in e^{sigma t}.
    CHECK(worst < 1e-8);
  }
}

TEST_CASE("half-space kernel: exact limits g(0)=0, g'(0)=7/4-2r, g(inf)=1-r^2") {
  const auto m = material_for(PlaneCondition::strain);
  const double r2 = speed_ratio_squared(m);
  const auto sum = half_space_exponential_sum(r2, 1e-6, 1e12, 10);
  const double tau = 1e-5;
  // g(tau) = g'(0) tau + O(tau^2)
  CHECK(evaluate(sum, tau) / tau == doctest::Approx(half_space_initial_slope(r2)).epsilon(1e-4));
  // The oscillating tail decays like tau^(-1/2) about the static value (the
  // -J_1(tau)/2 part of g): this slow decay is why the kernel cannot be cut off.
  for (double t : {1e4, 1e6, 1e8}) {
    const double deviation = std::abs(evaluate(sum, t) - (1 - r2));
    INFO("tau = " << t << ": |g - g(inf)| sqrt(tau) = " << deviation * std::sqrt(t));
    CHECK(deviation * std::sqrt(t) < 1.0);
  }
  // High-frequency expansion used by the aliasing sums (kernels/passivity.cpp):
  // Re G(i w) = -c2/w^2 + c4/w^4 + O(w^-6).
  const double r = std::sqrt(r2), c2 = 1.75 - 2 * r, c4 = 1.1875 - 1 / r;
  for (double w : {50.0, 200.0}) {
    const double re = half_space_relaxation_transform(r2, cplx(0, w)).real();
    const double remainder = (re + c2 / (w * w) - c4 / (w * w * w * w)) * std::pow(w, 6);
    INFO("w = " << w << ": w^6 * remainder = " << remainder);
    CHECK(std::abs(remainder) < 10.0);  // O(1): the expansion is right to O(w^-6)
  }
}

TEST_CASE("half-space kernel: the representation converges over tau in [1, 1e9]") {
  // The solver's far field (tau >= 1, 8 nodes per panel, horizon 1e10) against
  // a much finer representation (16 nodes, horizon 1e14).
  const auto m = material_for(PlaneCondition::strain);
  const double r2 = speed_ratio_squared(m);
  const auto solver = half_space_exponential_sum(r2, 1.0, 1e10, 8);
  const auto fine = half_space_exponential_sum(r2, 0.5, 1e14, 16);
  double worst = 0.0;
  for (int i = 0; i <= 4000; ++i) {
    const double tau = i < 2000 ? 1.0 + i * 0.025 : std::pow(10.0, 1.7 + (i - 2000) * 7.3 / 2000);
    worst = std::max(worst, std::abs(evaluate(solver, tau) - evaluate(fine, tau)));
  }
  MESSAGE(solver.rate.size() << " exponentials: max deviation from the refined sum " << worst);
  CHECK(worst < 1e-9);
}
