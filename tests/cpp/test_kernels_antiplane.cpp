// Antiplane (SH) kernels (kernels/antiplane_response.hpp, docs/bodies.md):
//   * the closed form mu alpha coth(alpha H) against a direct solve of the
//     body's two-point boundary-value problem (2x2 per k, s), finite and large H;
//   * the normal-mode expansion against the closed form (truncation error ~1/M);
//   * the sharp time-step limit of a passive discrete operator (beta ~ 2/pi);
//   * the half-space SH relaxation function: its exponential sum against the
//     closed form g = (int_0^tau J0 - J1)/2 in Bessel functions.
// The discrete operator's passivity, static limit, prescribed-slip history and
// the half-space operator are checked by the shared kernel tests, whose plane
// loops include antiplane (test_kernels_passivity, test_kernels_time_domain,
// test_kernels_half_space_operator, test_kernels_block_history,
// test_kernels_half_space_slow_block).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "kernels/antiplane_response.hpp"
#include "kernels/half_space_kernel.hpp"
#include "kernels/history_convolution.hpp"
#include "kernels/strip_response.hpp"

using namespace slipstrip;
using cplx = std::complex<double>;
constexpr double pi = std::numbers::pi;

namespace {

ElasticMaterial antiplane_material() {
  ElasticMaterial m;  // Table S1: mu 9 GPa, rho 1200 (nu plays no part in SH)
  m.plane = PlaneCondition::antiplane;
  return m;
}

// Face stiffness K = sigma_yz(0) / (-u(0)) of ONE body 0 < y < H with u(H) = 0,
// from the general solution u = A e^{-alpha y} + B e^{-alpha (H - y)} of
// u'' = alpha^2 u (both exponentials bounded on [0, H], so the 2x2 system is
// well conditioned for any alpha H), solved by Cramer's rule:
//   u(0) = A + B e^{-alpha H} = 1,   u(H) = A e^{-alpha H} + B = 0.
// A half-space keeps the decaying solution only: u = e^{-alpha y}.
cplx direct_body_stiffness(double mu, double cs, double H, double k, cplx s) {
  const cplx alpha = std::sqrt(k * k + s * s / (cs * cs));
  if (std::isinf(H)) return mu * alpha;
  const cplx e = std::exp(-alpha * H);
  const cplx det = 1.0 - e * e;
  const cplx A = 1.0 / det, B = -e / det;
  const cplx du0 = -alpha * A + alpha * B * e;  // u'(0)
  return -mu * du0;
}

}  // namespace

TEST_CASE("antiplane body response = direct solve of the two-point boundary-value problem") {
  const auto m = antiplane_material();
  const double mu = m.shear_modulus, cs = m.shear_wave_speed();
  double worst = 0.0;
  int checked = 0;
  for (double H : {0.01, 0.1, 1.0, 30.0, std::numeric_limits<double>::infinity()}) {
    for (double kH : {0.0, 1e-5, 1e-2, 0.5, 3.0, 40.0}) {
      const double k = std::isinf(H) ? kH / 0.1 : kH / H;
      const double scale = std::isinf(H) ? 0.1 : H;
      for (cplx sT : {cplx(1e-3, 0), cplx(0.3, 0.2), cplx(2.0, -5.0), cplx(0.0, 0.7), cplx(0.0, 13.0),
                      cplx(1e-2, 100.0), cplx(50.0, 1.0)}) {
        const cplx s = sT * cs / scale;  // s in units of c_s / H
        if (k == 0.0 && std::isinf(H)) continue;
        const cplx exact = 2.0 * antiplane_strip_response(m, H, k, s);  // body = 2 x pair
        const cplx direct = direct_body_stiffness(mu, cs, H, k, s);
        const double err = std::abs(exact - direct) / std::abs(direct);
        INFO("H = " << H << " kH = " << kH << " s H/c_s = " << sT << ": closed " << exact << " direct "
                    << direct);
        // Both are a few complex operations on the same exponentials: agreement
        // to 1e-12 relative leaves room only for rounding (the 2x2 solve's
        // determinant 1 - e^{-2 alpha H} is well conditioned except near a
        // pole, and none of these s is within 1e-3 of one).
        CHECK(err < 1e-12);
        worst = std::max(worst, err);
        ++checked;
      }
    }
  }
  MESSAGE(checked << " (H, k, s) points: max relative |closed form - direct| = " << worst);
}

TEST_CASE("antiplane: static stiffness, k = 0 comb and large-H limit") {
  const auto m = antiplane_material();
  const double mu = m.shear_modulus, cs = m.shear_wave_speed();
  for (double H : {0.01, 0.1, 2.0}) {
    for (double kH : {0.0, 1e-6, 1e-3, 0.3, 5.0, 60.0}) {
      const double k = kH / H;
      const double S0 = antiplane_static_stiffness(m, H, k);
      // s -> 0 along the real axis: S(k, s) = S(k, 0) + O(s^2).
      const cplx s(1e-6 * cs / H, 0.0);
      INFO("H = " << H << " kH = " << kH);
      // O((sH/c_s)^2) = 1e-12 relative, plus rounding.
      CHECK(std::abs(antiplane_strip_response(m, H, k, s) - S0) <= 1e-11 * S0);
      if (kH > 0.0 && kH < 40.0)  // the closed form mu k coth(kH) / 2 directly
        CHECK(std::abs(S0 - 0.5 * mu * k / std::tanh(kH)) <= 1e-14 * S0);
    }
    // k = 0: the shear comb, identical to the in-plane uniform mode.
    const cplx s(0.2 * cs / H, 1.7 * cs / H);
    CHECK(std::abs(antiplane_strip_response(m, H, 0.0, s) - shear_comb_response(m, H, s)) <=
          1e-15 * std::abs(shear_comb_response(m, H, s)));
    // A thick strip approaches the half-space for Re s > 0 as e^{-2 Re(alpha) H}.
    const double k = 3.0 / H;
    const cplx s2(2.0 * cs / H, 0.5 * cs / H);
    const double thick = 20.0 * H;  // Re(alpha) thick >= 60: e^{-120}
    CHECK(std::abs(antiplane_strip_response(m, thick, k, s2) - antiplane_strip_response(m, INFINITY, k, s2)) <=
          1e-14 * std::abs(antiplane_strip_response(m, INFINITY, k, s2)));
  }
}

TEST_CASE("antiplane normal modes: comb + truncated mode sum -> closed form like 1/M") {
  // S = comb(s) + sum_{m<=M} [comb mode + shear mode], whose tail beyond M is
  // sum_{m>M} (mu/H) c^2 kappa^2 c^2 k^2 / ((s^2 + c^2 kappa^2)(s^2 + omega_m^2))
  //   ~ (mu/H) k^2 sum_{m>M} 1/kappa^2 = mu k^2 H / (pi^2 M)   (|s| << c kappa_M):
  // the truncation error must be within 1.5x that estimate and fall like 1/M.
  const auto m = antiplane_material();
  const double mu = m.shear_modulus, cs = m.shear_wave_speed();
  const double H = 0.1;
  for (double kH : {0.05, 1.0, 7.0}) {
    const double k = kH / H;
    for (cplx sT : {cplx(0.4, 0.3), cplx(0.05, 3.0), cplx(2.0, -1.0)}) {
      const cplx s = sT * cs / H;
      const cplx exact = antiplane_strip_response(m, H, k, s);
      double previous = 0.0;
      for (int M : {400, 1600, 6400}) {
        const double max_frequency = cs * (M + 0.5) * pi / H;
        cplx sum = shear_comb_response(m, H, s);
        int shear = 0;
        for (const auto& mode : antiplane_strip_modes(m, H, k, max_frequency)) {
          sum += mode.weight * mode.frequency * mode.frequency / (s * s + mode.frequency * mode.frequency);
          if (mode.family == ModeFamily::shear) ++shear;
          CHECK(mode.family != ModeFamily::dilatational);
          if (mode.family == ModeFamily::shear) CHECK(mode.weight < 0.0);
        }
        const double err = std::abs(sum - exact);
        const double estimate = mu * k * k * H / (pi * pi * M);
        INFO("kH = " << kH << " sH/c_s = " << sT << " M = " << M << " (" << shear << " shear modes): error "
                     << err << ", estimate " << estimate);
        CHECK(err <= 1.5 * estimate);
        if (previous > 0.0) CHECK(previous / err > 3.5);  // 1/M: x4 per step
        previous = err;
      }
    }
  }
}

TEST_CASE("antiplane: a passive discrete operator exists exactly when dt S(k,0)/2 <= eta (beta ~ 2/pi)") {
  // As for in-plane strips (test_kernels_passivity): the z = 1 Foster
  // coefficient is dt S(k,0)/2 and all coefficients add up to eta, so
  // dt S(k,0) <= mu/c_s is necessary, and discrete_modes' placement achieves
  // it whenever it holds.  For SH, S(k_N, 0) = (mu/2) k_N coth(k_N H), so the
  // limit is beta = 2/(pi coth(pi H/dx)) ~ 2/pi, above the in-plane 0.4265.
  const auto m = antiplane_material();
  const double mu = m.shear_modulus, cs = m.shear_wave_speed();
  const double H = 0.1, L = 4.0;
  const int N = 256;
  int built = 0, refused = 0;
  for (double beta = 0.55; beta <= 0.75 + 1e-9; beta += 0.01) {
    const double dt = strip_time_step(m, H, L / N, beta);
    const auto M = static_cast<std::size_t>(std::llround(2 * H / (cs * dt)));
    for (int q = N / 4; q <= N / 2; q += 3) {
      const double k = 2 * pi * q / L;
      const double margin = strip_static_stiffness(m, H, k) / (mu / (cs * dt)) - 1.0;
      if (std::abs(margin) < 1e-9) continue;
      bool ok = true;
      try {
        for (const auto& mode : discrete_modes(m, H, k, dt, M)) ok = ok && mode.weight <= 0.0;
      } catch (const std::runtime_error&) {
        ok = false;
      }
      INFO("beta " << beta << " M " << M << " q " << q << " dt S/(2 eta) - 1 = " << margin);
      CHECK(ok == (margin < 0));
      (ok ? built : refused) += 1;
    }
  }
  MESSAGE("antiplane: built " << built << ", refused " << refused << "; limit 2/pi = "
                              << antiplane_strip_passivity_beta_limit());
  CHECK(built > 0);
  CHECK(refused > 0);
}

namespace {

// int_0^tau J0(u) du by Gauss-Legendre (16 nodes) on unit panels: J0 is
// entire and |J0^(32)| <= 1, so each panel's error is < 1e-30.
double integral_of_j0(double tau) {
  // 16-point Gauss-Legendre nodes/weights on [-1, 1] by Newton on P_16.
  static const auto rule = [] {
    std::vector<std::pair<double, double>> r;
    const int n = 16;
    for (int i = 0; i < n; ++i) {
      double x = std::cos(pi * (i + 0.75) / (n + 0.5)), dp = 0;
      for (int it = 0; it < 100; ++it) {
        double p0 = 1, p1 = x;
        for (int j = 2; j <= n; ++j) {
          const double p2 = ((2.0 * j - 1) * x * p1 - (j - 1.0) * p0) / j;
          p0 = p1;
          p1 = p2;
        }
        dp = n * (x * p1 - p0) / (x * x - 1);
        const double step = p1 / dp;
        x -= step;
        if (std::abs(step) < 1e-16) break;
      }
      r.emplace_back(x, 2.0 / ((1 - x * x) * dp * dp));
    }
    return r;
  }();
  double total = 0.0;
  for (double a = 0.0; a < tau; a += 1.0) {
    const double b = std::min(tau, a + 1.0);
    for (const auto& [x, w] : rule) total += 0.5 * (b - a) * w * std::cyl_bessel_j(0.0, 0.5 * (b - a) * x + 0.5 * (a + b));
  }
  return total;
}

}  // namespace

TEST_CASE("SH half-space relaxation: exponential sum = (int_0^tau J0 - J1)/2 (Bessel closed form)") {
  const HalfSpaceShape shape{0.0, true};
  // The transform itself: G(p) = (sqrt(1 + p^2)/p - 1)/2 against the pair
  // response (mu/2) alpha / (s mu / c_s) - 1/2 at k = 1.
  const auto m = antiplane_material();
  const double cs = m.shear_wave_speed(), mu = m.shear_modulus;
  for (cplx p : {cplx(0.3, 0.1), cplx(0, 0.5), cplx(0, 2.0), cplx(1e-3, 50.0), cplx(7.0, -3.0)}) {
    const cplx via_response = antiplane_strip_response(m, INFINITY, 1.0, cs * p) / (cs * p * mu / cs) - 0.5;
    // two roundings of O(1) terms that cancel to G ~ 1/(4 p^2): 1e-15/|G|.
    CHECK(std::abs(half_space_relaxation_transform(shape, p) - via_response) <=
          4e-16 * (1.0 + std::abs(p)) * (1.0 + std::abs(p)));
  }
  CHECK(half_space_static_value(shape) == 0.5);
  CHECK(half_space_initial_slope(shape) == 0.25);
  // Sums as the operator builds them: near field from tau_min = 0.005, far field from 1.
  const auto near = half_space_exponential_sum(shape, 0.005, 1e4, 10);
  const auto far = half_space_exponential_sum(shape, 1.0, 1e10, 8);
  double worst_near = 0.0, worst_far = 0.0;
  for (double tau = 0.005; tau <= 2000.0; tau *= 1.013) {
    const double exact = 0.5 * (integral_of_j0(tau) - std::cyl_bessel_j(1.0, tau));
    worst_near = std::max(worst_near, std::abs(evaluate(near, tau) - exact));
    if (tau >= 1.0) worst_far = std::max(worst_far, std::abs(evaluate(far, tau) - exact));
  }
  MESSAGE("SH exponential sums: " << near.rate.size() << " (near) and " << far.rate.size()
                                  << " (far) exponentials; max |g_sum - g_Bessel| = " << worst_near
                                  << " (tau in [0.005, 2000]), " << worst_far << " (tau in [1, 2000])");
  // The in-plane sums reach 3e-10 (8 nodes) and ~1e-11 (10 nodes) against
  // refined sums (test_kernels_half_space_kernel); the SH density has the
  // same inverse-square-root branch point, so the same bounds apply.
  CHECK(worst_near < 1e-10);
  CHECK(worst_far < 1e-9);
  // Only the shear branch: every rate has imaginary part 1.
  for (const auto& r : far.rate) CHECK(r.imag() == 1.0);
}
