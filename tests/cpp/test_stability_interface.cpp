// Linear stability of steady sliding between two bodies (stability/interface_stability.*):
// the identical pair against today's theory, two half-spaces against the published
// bimaterial results (Weertman's generalised Rayleigh wave; Ranjith & Rice 2001:
// Coulomb friction is ill-posed for arbitrarily small f when that wave exists, and a
// fading memory of normal stress makes the problem well-posed).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <limits>
#include <numbers>
#include <vector>

#include "stability/interface_stability.hpp"
#include "stability/linear_stability.hpp"
#include "stability/root_search.hpp"

using namespace slipstrip;

namespace {

using cd = std::complex<double>;
constexpr double pi = std::numbers::pi;
constexpr double inf = std::numeric_limits<double>::infinity();

ElasticMaterial material(double mu, double nu, double rho, PlaneCondition plane) { return {mu, nu, rho, plane}; }

// Dynamic properties of the photoelastic polymers of bimaterial rupture experiments
// (plane stress, thin plates): PMMA and Homalite-100 (mu 1.9 GPa, nu 0.34, rho 1230).
const ElasticMaterial kPmma = material(2.1e9, 0.35, 1170.0, PlaneCondition::stress);
const ElasticMaterial kHomalite = material(1.9e9, 0.34, 1230.0, PlaneCondition::stress);

PairSliding half_spaces(const ElasticMaterial& top, const ElasticMaterial& bottom) {
  PairSliding p;
  p.top = {top, inf, OuterFace::driven, false};
  p.bottom = {bottom, inf, OuterFace::driven, false};
  return p;
}

// Coulomb friction with friction coefficient f and an optional normal-stress memory T.
LinearisedInterfaceFriction coulomb(double f, double relaxation_time = 0.0) {
  LinearisedInterfaceFriction lin;
  lin.friction_coefficient = f;
  lin.state_rate_dstate = -1.0;  // unused (no state dependence), kept off Re > 0
  lin.normal_relaxation_time = relaxation_time;
  return lin;
}

// Weertman's (1963) equation for the generalised Rayleigh (slip) wave of two
// half-spaces in frictionless contact, written independently of kernels/: the normal
// surface compliances under zero shear traction add to zero,
//   sum_i (c^2/c_si^2) sqrt(1 - c^2/c_di^2) / (mu_i R_i(c)) = 0,
//   R_i(c) = (2 - c^2/c_si^2)^2 - 4 sqrt(1 - c^2/c_si^2) sqrt(1 - c^2/c_di^2).
double weertman(const ElasticMaterial& a, const ElasticMaterial& b, double c) {
  double sum = 0.0;
  for (const ElasticMaterial* m : {&a, &b}) {
    const double cs = m->shear_wave_speed(), cdil = m->dilatational_wave_speed();
    const double x = c * c / (cs * cs), y = c * c / (cdil * cdil);
    const double R = (2 - x) * (2 - x) - 4 * std::sqrt(1 - x) * std::sqrt(1 - y);
    sum += x * std::sqrt(1 - y) / (m->shear_modulus * R);
  }
  return sum;
}

// The zero of `f` in (lo, hi) by bisection, given a sign change; NaN if the bracket
// holds a pole (|f| grows as it shrinks) rather than a zero.
template <class F>
double bisect_zero(F&& f, double lo, double hi) {
  double flo = f(lo);
  const double start = std::max(std::abs(flo), std::abs(f(hi)));
  for (int i = 0; i < 200 && hi - lo > 1e-15 * hi; ++i) {
    const double mid = 0.5 * (lo + hi), fm = f(mid);
    if ((fm < 0) == (flo < 0)) {
      lo = mid;
      flo = fm;
    } else {
      hi = mid;
    }
  }
  return std::abs(f(0.5 * (lo + hi))) < start ? 0.5 * (lo + hi) : std::nan("");
}

// Generalised Rayleigh speed from Weertman's equation: the zero below min(c_s1, c_s2).
double weertman_speed(const ElasticMaterial& a, const ElasticMaterial& b) {
  const double cmax = std::min(a.shear_wave_speed(), b.shear_wave_speed()) * (1 - 1e-9);
  const auto f = [&](double c) { return weertman(a, b, c); };
  const int n = 4000;
  for (int i = n - 1; i > 0; --i) {  // the zero nearest below c_s, if any
    const double lo = cmax * i / n, hi = cmax * (i + 1) / n;
    if ((f(lo) < 0) != (f(hi) < 0)) {
      const double z = bisect_zero(f, lo, hi);
      if (!std::isnan(z)) return z;
    }
  }
  return std::nan("");
}

}  // namespace

TEST_CASE("identical driven bodies: today's roots bit for bit, and the general F agrees") {
  SteadySliding today;  // Table S1
  today.material = material(9e9, 0.33, 1200.0, PlaneCondition::strain);
  for (double H : {0.1, inf}) {
    today.strip_height = H;
    PairSliding pair;
    pair.top = {today.material, H, OuterFace::driven, false};
    pair.bottom = pair.top;
    pair.friction = today.friction;
    pair.normal_stress = today.normal_stress;
    pair.driving_velocity = today.driving_velocity;
    CHECK(is_mirror_pair(pair));
    const LinearisedInterfaceFriction lin = linearise_interface_friction(pair);
    const SearchBox box = unstable_search_box(today);
    for (double L : {0.3, 1.0, 3.0}) {
      const double k = 2 * pi / L;
      const auto expected = characteristic_roots(today, L, box);
      const auto got = pair_characteristic_roots(pair, lin, k, {box.min_re, box.max_re, box.max_im});
      REQUIRE(got.size() == expected.size());
      for (std::size_t i = 0; i < got.size(); ++i) CHECK(got[i] == expected[i]);  // exactly
      // The general route (series stiffness of two mirrored bodies, normal coupling
      // included) without the fast path: F agrees to rounding (1e-12 of its terms:
      // two cancellation-free closed forms), and the generic root search finds the
      // same roots to the Newton tolerance (1e-14 of the box size, 1e-9 allowed).
      const AnalyticFunction g = [&](cd z) { return pair_characteristic_function(pair, lin, k, z); };
      for (cd z : {cd(0.5 * box.max_re, 0.3 * box.max_im), cd(box.min_re, -0.7 * box.max_im)}) {
        const cd a = g(z), b = characteristic_function(today, k, z);
        CHECK(std::abs(a - b) <= 1e-12 * std::abs(strip_response(today.material, H, k, z)));
      }
      const Rectangle r{box.min_re, box.max_re, -box.max_im, box.max_im};
      const int n = count_zeros(g, r);
      REQUIRE(n == int(expected.size()));
      auto general = locate_zeros(g, r, n, 1e-9 * 2 * box.max_im);
      for (cd e : expected) {
        double best = inf;
        for (cd z : general) best = std::min(best, std::abs(z - e));
        CHECK(best <= 1e-9 * box.max_im);
      }
    }
  }
}

TEST_CASE("two half-spaces: the generalised Rayleigh wave is the root of Weertman's equation") {
  // Frictionless contact (tau = 0) admits a slip wave where K_ser,xx(k, i c k) = 0.
  // K_ser,xx is real on the imaginary axis below both shear speeds; its zero and
  // Weertman's zero are found by bisection to 1e-15; tolerance 1e-10 relative (the
  // closed forms are evaluated near a pole of each body's normal compliance).
  const double k = 2 * pi / 0.1;
  for (double speed_ratio : {1.0 / 0.95, 0.9, 0.8}) {
    const ElasticMaterial top = kPmma;
    ElasticMaterial bottom = speed_ratio == 1.0 / 0.95 ? kHomalite : kPmma;
    if (bottom.shear_modulus == top.shear_modulus) bottom.shear_modulus *= speed_ratio * speed_ratio;
    const PairSliding p = half_spaces(top, bottom);
    const double c_w = weertman_speed(top, bottom);
    REQUIRE(std::isfinite(c_w));
    const auto kxx = [&](double c) {
      return interface_slip_response(p.top, p.bottom, k, cd(0.0, c * k)).shear.real();
    };
    const double c_k = bisect_zero(kxx, 0.98 * c_w, std::min(1.02 * c_w, 0.999999 * bottom.shear_wave_speed()));
    CAPTURE(speed_ratio);
    CHECK(std::abs(c_k - c_w) <= 1e-10 * c_w);
    std::printf("[pair stability] c_s ratio %.3f: generalised Rayleigh speed %.6f m/s (Weertman %.6f)\n",
                bottom.shear_wave_speed() / top.shear_wave_speed(), c_k, c_w);
  }
  // A strong contrast (c_s ratio 0.6) has no such wave: Weertman's function keeps its
  // sign between the slower Rayleigh speed and the slower shear speed.
  ElasticMaterial slow = kPmma;
  slow.shear_modulus *= 0.36;
  CHECK(std::isnan(weertman_speed(kPmma, slow)));
}

TEST_CASE("Coulomb friction between half-spaces is ill-posed for arbitrarily small f (Ranjith & Rice 2001)") {
  // PMMA on Homalite: the generalised Rayleigh wave exists.  With Coulomb friction
  // (tau = f sigma, sigma instantaneous) F = K_xx + f K_yx is homogeneous of degree 1
  // in (k, Lambda), so a root Lambda(k) = k Lambda(1): growth proportional to k, i.e.
  // unbounded as the wavelength shrinks.  For small f the root is the slip wave
  // perturbed: Lambda = i c_GR k + f Lambda_1 + O(f^2), with Lambda_1 = -K_yx / dK_xx/dLambda
  // real (K_yx is imaginary and K_xx real on the imaginary axis below c_s).
  const PairSliding p = half_spaces(kPmma, kHomalite);
  const double c_gr = weertman_speed(kPmma, kHomalite);
  const double k = 2 * pi / 0.1;
  const cd z0(0.0, c_gr * k);
  const double h = 1e-6 * c_gr * k;
  const cd dkxx = (interface_slip_response(p.top, p.bottom, k, z0 + cd(0, h)).shear -
                   interface_slip_response(p.top, p.bottom, k, z0 - cd(0, h)).shear) /
                  cd(0.0, 2 * h);
  const cd lambda1 = -interface_slip_response(p.top, p.bottom, k, z0).normal / dkxx;
  CHECK(std::abs(lambda1.imag()) <= 1e-6 * std::abs(lambda1));
  CHECK(lambda1.real() > 0.0);
  for (double f : {1e-3, 1e-2, 0.1}) {
    const LinearisedInterfaceFriction lin = coulomb(f);
    const auto roots = pair_characteristic_roots(p, lin, k, pair_search_box(p, lin, k));
    REQUIRE(roots.size() == 1);
    const cd z = roots[0];
    CAPTURE(f);
    CAPTURE(z);
    // First-order perturbation: relative error O(f) (measured 1e-3 f), tolerance 0.05 f
    // plus the central difference's 1e-10.
    CHECK(std::abs(z.real() / f - lambda1.real()) <= (0.05 * f + 1e-8) * lambda1.real());
    // The imaginary shift is O(f^2): |Im Lambda / k - c_GR| <= f^2 c_GR.
    CHECK(std::abs(z.imag() / k - c_gr) <= f * f * c_gr);
    // Travels along -x (phase velocity -Im Lambda / k < 0): the direction in which the
    // compliant bottom body (Homalite) slides relative to the top one.
    CHECK(z.imag() > 0.0);
    // Ill-posed: the growth rate scales with k exactly (root polishing 1e-14; 1e-9 allowed).
    for (double factor : {10.0, 1000.0}) {
      const auto r = pair_characteristic_roots(p, lin, factor * k, pair_search_box(p, lin, factor * k));
      REQUIRE(r.size() == 1);
      CHECK(std::abs(r[0] - factor * z) <= 1e-9 * std::abs(factor * z));
    }
  }
  std::printf("[pair stability] PMMA/Homalite, Coulomb: Re Lambda = %.6g f c_s k, slip wave at %.2f m/s\n",
              lambda1.real() / (kPmma.shear_wave_speed() * k), c_gr);
  // Without the slip wave (c_s ratio 0.6) small friction leaves steady sliding stable.
  ElasticMaterial slow = kPmma;
  slow.shear_modulus *= 0.36;
  const PairSliding contrast = half_spaces(kPmma, slow);
  for (double f : {1e-2, 0.1}) {
    const LinearisedInterfaceFriction lin = coulomb(f);
    CHECK(pair_characteristic_roots(contrast, lin, k, pair_search_box(contrast, lin, k)).empty());
  }
}

TEST_CASE("a fading memory of normal stress makes the bimaterial problem well-posed (Ranjith & Rice 2001)") {
  // Same pair, f = 0.3, sigma_eff relaxing over T = 1e-5 s.  Without memory the growth
  // rate grows like k without bound; with it, it has a maximum at k ~ 1/(c T) and then
  // falls (like 1/k): bounded over all wavelengths.
  const PairSliding p = half_spaces(kPmma, kHomalite);
  double largest = 0.0, previous = inf;
  for (double k : {1.0, 10.0, 100.0, 1e3, 1e4, 1e5}) {
    const LinearisedInterfaceFriction lin = coulomb(0.3, 1e-5), bare = coulomb(0.3);
    const auto r = pair_characteristic_roots(p, lin, k, pair_search_box(p, lin, k));
    const auto b = pair_characteristic_roots(p, bare, k, pair_search_box(p, bare, k));
    REQUIRE(r.size() == 1);
    REQUIRE(b.size() == 1);
    CHECK(r[0].real() <= b[0].real());  // the memory only slows the growth
    largest = std::max(largest, r[0].real());
    if (k >= 1e3) {
      CHECK(r[0].real() < previous);
      previous = r[0].real();
    }
    std::printf("[pair stability] k = %g 1/m: growth %.4g 1/s with memory, %.4g 1/s without\n", k,
                r[0].real(), b[0].real());
  }
  CHECK(largest < 1e3);  // vs 8.6e5 1/s without memory at k = 1e5
}

TEST_CASE("rate-and-state between dissimilar strips: roots are zeros; a stiff base tends to a rigid one") {
  // A 1 cm PMMA slider on a 5 cm PMMA base (heights differ), Table S1 friction: the two
  // unstable roots are not complex conjugates (a direction is preferred).  Each root is
  // a zero of F to 1e-9 of its terms (Newton polish to 1e-14 in Lambda).
  PairSliding p;
  p.top = {kPmma, 0.01, OuterFace::driven, false};
  p.bottom = {kPmma, 0.05, OuterFace::driven, false};
  const LinearisedInterfaceFriction lin = linearise_interface_friction(p);
  const double k = 2 * pi / 0.3;
  const auto roots = pair_characteristic_roots(p, lin, k, pair_search_box(p, lin, k));
  REQUIRE(roots.size() == 2);
  CHECK(std::abs(roots[0] - std::conj(roots[1])) > 1e-3 * std::abs(roots[0]));
  for (cd z : roots) {
    const SlipResponse K = interface_slip_response(p.top, p.bottom, k, z);
    const double scale = std::abs(K.shear) + std::abs(z) * lin.strength_dv + std::abs(K.normal);
    CHECK(std::abs(pair_characteristic_function(p, lin, k, z)) <= 1e-9 * scale);
  }
  // A base 1e8 times stiffer (same wave speeds) changes the roots by O(1e-8).
  PairSliding rigid = p, stiff = p;
  rigid.bottom.rigid = true;
  stiff.bottom.material.shear_modulus *= 1e8;
  stiff.bottom.material.density *= 1e8;
  rigid.top.height = stiff.top.height = 0.1;
  const double kr = 2 * pi / 3.0;
  const auto a = pair_characteristic_roots(rigid, lin, kr, pair_search_box(rigid, lin, kr));
  const auto b = pair_characteristic_roots(stiff, lin, kr, pair_search_box(stiff, lin, kr));
  REQUIRE(!a.empty());
  REQUIRE(a.size() == b.size());
  for (std::size_t i = 0; i < a.size(); ++i) CHECK(std::abs(a[i] - b[i]) <= 1e-6 * std::abs(a[i]));
}
