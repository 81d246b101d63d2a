// Checks of the normal-mode (Mittag-Leffler) expansion returned by strip_modes:
//   S(k, s; H) = (mu s / 2 c_s) coth(s H / c_s) + sum_m rho_m / (s^2 + omega_m^2),
// weight_m = rho_m / omega_m^2, against strip_response itself (which is checked
// against an independent direct solve in test_kernels_transfer_function.cpp).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <numbers>
#include <vector>

#include "kernels/elastic_material.hpp"
#include "kernels/strip_response.hpp"

namespace {

using cd = std::complex<double>;
using slipstrip::ElasticMaterial;

cd truncated_sum(const ElasticMaterial& m, double H, const std::vector<slipstrip::StripMode>& modes,
                 cd s) {
  cd sum = slipstrip::shear_comb_response(m, H, s);
  for (const auto& md : modes) {
    const double rho = md.weight * md.frequency * md.frequency;
    sum += rho / (s * s + md.frequency * md.frequency);
  }
  return sum;
}

// Least-squares slope of log(err) against log(M).
double loglog_slope(const std::vector<double>& M, const std::vector<double>& err) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double n = static_cast<double>(M.size());
  for (std::size_t i = 0; i < M.size(); ++i) {
    const double x = std::log(M[i]), y = std::log(err[i]);
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

}  // namespace

// Both convergence tests sweep max_frequency = c_s (m + 1/2) pi / H, i.e.
// midway between consecutive comb frequencies c_s m pi/H, and separately at
// generic values (see the second test case).
TEST_CASE("truncated mode sum converges to strip_response like 1/M") {
  const ElasticMaterial m;
  const double H = 0.1, cs = m.shear_wave_speed();
  for (double kH : {0.3, 2.7}) {
    const double k = kH / H;
    const std::vector<cd> s_list{cd(0.7, 0.0) * cs / H, cd(0.2, 3.1) * cs / H,
                                 cd(1.5, -0.4) * cs / H};
    std::vector<double> Ms, errs, static_errs;
    for (int mmax : {8, 16, 32, 64, 128, 256, 512}) {
      const double omega_max = cs * (mmax + 0.5) * std::numbers::pi / H;
      const auto modes = slipstrip::strip_modes(m, H, k, omega_max);
      double err = 0.0;
      for (cd s : s_list) {
        const cd exact = slipstrip::strip_response(m, H, k, s);
        err = std::max(err, std::abs(truncated_sum(m, H, modes, s) - exact) / std::abs(exact));
      }
      // (b) static: comb(0) + sum of weights must approach the static stiffness.
      double weights = 0.0;
      for (const auto& md : modes) weights += md.weight;
      const double stat = slipstrip::strip_static_stiffness(m, H, k);
      const double static_err = std::abs(m.shear_modulus / (2.0 * H) + weights - stat) / stat;
      Ms.push_back(static_cast<double>(modes.size()));
      errs.push_back(err);
      static_errs.push_back(static_err);
      std::printf("[modes] kH=%.1f M=%5zu  dynamic rel err %.3e  static rel err %.3e\n", kH,
                  modes.size(), err, static_err);
    }
    const double slope = loglog_slope(Ms, errs), static_slope = loglog_slope(Ms, static_errs);
    std::printf("[modes] kH=%.1f fitted rates: dynamic M^%.3f, static M^%.3f\n", kH, slope,
                static_slope);
    // The tail of the expansion is sum_{m>M} O(1/m^2) (docs/theory.md), so the
    // error must fall like 1/M: slope -1 within 0.1 (the fit includes the
    // pre-asymptotic small-M points), and the error must keep falling.
    CHECK(slope == doctest::Approx(-1.0).epsilon(0.1));
    CHECK(static_slope == doctest::Approx(-1.0).epsilon(0.1));
    for (std::size_t i = 1; i < errs.size(); ++i) {
      CHECK(errs[i] < errs[i - 1]);
      CHECK(static_errs[i] < static_errs[i - 1]);
    }
  }
}

TEST_CASE("truncation at a generic max_frequency does not leave a comb mode unpaired") {
  // A comb mode (omega = c_s kappa, rho = +mu c_s^2 kappa^2/H) cancels a pole of
  // the comb; its shear partner (omega = c_s sqrt(k^2 + kappa^2)) carries
  // rho ~ -mu c_s^2 kappa^2/H.  If max_frequency falls between the two, the
  // truncated sum is off by ~ mu/H at low frequency, which does not decrease
  // with M.  Requirement checked here: at ANY max_frequency the truncated
  // static sum is within the 1/M tail bound, 4 mu k^2 H (1 - c_s^2/c_d^2)/(pi^2 m)
  // (doubled for margin), of the static stiffness.
  const ElasticMaterial m;
  const double H = 0.1, cs = m.shear_wave_speed();
  const double r = 1.0 - 1.0 / m.wave_speed_ratio_squared();
  const double k = 27.0;  // kH = 2.7
  const double stat = slipstrip::strip_static_stiffness(m, H, k);
  int violations = 0;
  double worst_ratio = 0.0;
  for (int mm = 20; mm <= 60; ++mm) {
    const double kappa = mm * std::numbers::pi / H;
    // A frequency just above the comb frequency, below its shear partner.
    const double omega_max = cs * kappa * (1.0 + 0.25 * (std::sqrt(1.0 + k * k / (kappa * kappa)) - 1.0));
    const auto modes = slipstrip::strip_modes(m, H, k, omega_max);
    double weights = 0.0;
    for (const auto& md : modes) weights += md.weight;
    const double err = std::abs(m.shear_modulus / (2.0 * H) + weights - stat);
    const double bound = 2.0 * 4.0 * m.shear_modulus * k * k * H * r / (std::numbers::pi * std::numbers::pi * mm);
    worst_ratio = std::max(worst_ratio, err / bound);
    if (err > bound) ++violations;
  }
  std::printf("[modes] unpaired-comb truncation: %d of 41 cut-offs exceed the tail bound, worst err/bound %.1f\n",
              violations, worst_ratio);
  CHECK(violations == 0);
}

TEST_CASE("every returned frequency is a pole of S - comb, with the returned residue") {
  const ElasticMaterial m;
  const double H = 0.1, cs = m.shear_wave_speed(), cdl = m.dilatational_wave_speed();
  for (double kH : {0.3, 2.7}) {
    const double k = kH / H;
    const double omega_max = cs * 12.5 * std::numbers::pi / H;
    const auto modes = slipstrip::strip_modes(m, H, k, omega_max);
    REQUIRE(modes.size() > 10);
    // S - comb, the function the expansion claims equals the mode sum.
    auto F = [&](cd s) {
      return slipstrip::strip_response(m, H, k, s) - slipstrip::shear_comb_response(m, H, s);
    };
    // All candidate poles: shear/P poles of S (sinh(alpha H) = 0) and the comb's poles.
    std::vector<double> poles;
    for (int n = 0; n < 40; ++n) {
      const double kappa = n * std::numbers::pi / H;
      poles.push_back(cs * std::sqrt(k * k + kappa * kappa));
      if (n > 0) poles.push_back(cdl * std::sqrt(k * k + kappa * kappa));
      if (n > 0) poles.push_back(cs * kappa);
    }
    double worst_res = 0.0, min_blowup = 1e300;
    int shear_or_p = 0;
    for (const auto& md : modes) {
      const double w = md.frequency;
      const double rho = md.weight * w * w;
      double gap = 1e300;
      for (double p : poles)
        if (std::abs(p - w) > 1e-9 * w) gap = std::min(gap, std::abs(p - w));
      // (c) blow-up: |F| at a distance 1e-8 gap from i w (gap = distance to the
      // nearest other pole) vs |F| midway to that pole.  Scaled with the gap,
      // not with w, because at high m the shear pole sits within
      // ~ k^2/(2 kappa^2) w of the comb pole; 1e-8 (not 1e-7) because a P
      // mode's residue is ~ 4 k^2/kappa^2 times its neighbours'.
      const double d = 1e-8 * gap;
      const cd near = cd(1e-3 * d, w + d);
      const cd mid = cd(0.0, w + 0.5 * gap);
      const double blowup = std::abs(F(near)) / std::abs(F(mid));
      min_blowup = std::min(min_blowup, blowup);
      CAPTURE(w);
      CHECK(blowup > 1e3);
      // (d) residue: P(h) = (s^2 + w^2) F(s) at s = i w + h, h real > 0 (stays in
      // Re s > 0), is analytic in h with P(0) = rho; three-level Richardson
      // extrapolation (h, h/2, h/4) leaves O(h^3).  h = 1e-3 gap gives a
      // truncation ~ (1e-3)^3 relative and round-off ~ 1e-16 w/h ~ 1e-11, so
      // 1e-6 (the required accuracy) has a wide margin.
      const double h = 1e-3 * gap;
      auto P = [&](double hh) {
        const cd s(hh, w);
        return ((s * s + w * w) * F(s)).real();
      };
      const double p1 = P(h), p2 = P(h / 2), p3 = P(h / 4);
      const double r12 = 2 * p2 - p1, r23 = 2 * p3 - p2;
      const double rho_num = (4 * r23 - r12) / 3;
      const double rel = std::abs(rho_num - rho) / std::abs(rho);
      CAPTURE(rho);
      CAPTURE(rho_num);
      CHECK(rel <= 1e-6);
      worst_res = std::max(worst_res, rel);
      // Shear and P families are poles of S itself; the comb family (omega =
      // c_s n pi/H) is not: there S stays finite and F's pole is the comb's.
      const double ncomb = w * H / (cs * std::numbers::pi);
      const bool comb_family = std::abs(ncomb - std::round(ncomb)) < 1e-9;
      const double blowup_S = std::abs(slipstrip::strip_response(m, H, k, near)) /
                              std::abs(slipstrip::strip_response(m, H, k, mid));
      if (comb_family) {
        CHECK(blowup_S < 1e2);
      } else {
        CHECK(blowup_S > 1e3);
        ++shear_or_p;
      }
    }
    // Conversely every pole of S below omega_max is returned.
    for (double p : poles) {
      const double ncomb = p * H / (cs * std::numbers::pi);
      if (p > omega_max || std::abs(ncomb - std::round(ncomb)) < 1e-9) continue;
      const bool found = std::any_of(modes.begin(), modes.end(),
                                     [&](const auto& md) { return std::abs(md.frequency - p) < 1e-9 * p; });
      CAPTURE(p);
      CHECK(found);
    }
    std::printf("[modes] kH=%.1f: %zu modes (%d poles of S), min blow-up ratio %.2e, max residue rel err %.2e\n",
                kH, modes.size(), shear_or_p, min_blowup, worst_res);
  }
}
