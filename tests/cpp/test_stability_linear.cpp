// Linear stability of steady sliding: root finder, critical length Lc(H).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "stability/linear_stability.hpp"

using namespace slipstrip;

namespace {

constexpr double pi = std::numbers::pi;
constexpr double inf = std::numeric_limits<double>::infinity();

SteadySliding table_s1(double H) {
  SteadySliding s;  // defaults are Table S1 (mu 9e9, nu 0.33, rho 1200, plane strain, ...)
  s.material = ElasticMaterial{9e9, 0.33, 1200.0, PlaneCondition::strain};
  s.friction = FrictionParameters{};
  s.friction.f0 = 0.28;
  s.friction.a = 0.005;
  s.friction.b = 0.075;
  s.friction.characteristic_slip = 5e-7;
  s.friction.v_star = 1e-7;
  s.friction.phi_star = 3.3e-4;
  s.normal_stress = 1e6;
  s.driving_velocity = 2e-3;
  s.strip_height = H;
  return s;
}

// Scale of the terms of F at Lambda, to judge a residual |F| against.
double term_scale(const SteadySliding& s, double k, complex z) {
  const LinearisedFriction lin = linearise_friction(s);
  return std::abs(strip_response(s.material, s.strip_height, k, z)) +
         std::abs(z) * (lin.strength_dv + std::abs(lin.strength_dstate * lin.state_rate_dv /
                                                   (z - lin.state_rate_dstate)));
}

// Independent brute force: dense grid of |F| / term_scale over the box, every
// strict local minimum refined by repeated grid zooming (no derivatives, no
// argument principle); returns the minima that reach |F|/scale < 1e-9 (zeros).
struct Rect {
  double re0, re1, im0, im1;
  bool contains(complex z) const {
    return z.real() > re0 && z.real() < re1 && z.imag() > im0 && z.imag() < im1;
  }
};

std::vector<complex> brute_force_zeros(const SteadySliding& s, double wavelength, Rect g, int n) {
  const double k = 2.0 * pi / wavelength;
  auto merit = [&](complex z) {
    return std::abs(characteristic_function(s, k, z)) / term_scale(s, k, z);
  };
  const double dre = (g.re1 - g.re0) / n;
  const double dim = (g.im1 - g.im0) / n;
  std::vector<double> grid((n + 1) * (n + 1));
  auto at = [&](int i, int j) { return complex(g.re0 + i * dre, g.im0 + j * dim); };
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) grid[i * (n + 1) + j] = merit(at(i, j));
  std::vector<complex> zeros;
  for (int i = 1; i < n; ++i)
    for (int j = 1; j < n; ++j) {
      const double v = grid[i * (n + 1) + j];
      bool is_min = true;
      for (int di = -1; di <= 1; ++di)
        for (int dj = -1; dj <= 1; ++dj)
          if ((di || dj) && grid[(i + di) * (n + 1) + j + dj] <= v) is_min = false;
      if (!is_min) continue;
      // Derivative-free refinement: repeated 21 x 21 grid zoom by a factor 4.
      complex c = at(i, j);
      double hr = dre, hi = dim;
      for (int level = 0; level < 40; ++level) {
        complex best = c;
        double best_value = merit(c);
        for (int p = -10; p <= 10; ++p)
          for (int q = -10; q <= 10; ++q) {
            const complex z = c + complex(p * hr / 5.0, q * hi / 5.0);
            const double m = merit(z);
            if (m < best_value) best_value = m, best = z;
          }
        c = best;
        hr /= 4.0;
        hi /= 4.0;
      }
      if (merit(c) < 1e-9) zeros.push_back(c);  // a zero, not just a dip of |F|
    }
  return zeros;
}

// Roots of the argument-principle finder inside `r` versus brute-force zeros of a
// grid overhanging `r` by 5% on each side (so roots near the edges of r, e.g. nearly
// neutral ones, are interior grid minima).
void check_roots_against_brute_force(const SteadySliding& s, double wavelength, int n,
                                     std::optional<Rect> region = std::nullopt) {
  const SearchBox box = unstable_search_box(s);
  const Rect r = region.value_or(Rect{box.min_re, box.max_re, -box.max_im, box.max_im});
  const double mr = 0.05 * (r.re1 - r.re0), mi = 0.05 * (r.im1 - r.im0);
  const auto all_zeros = brute_force_zeros(s, wavelength, Rect{r.re0 - mr, r.re1 + mr, r.im0 - mi, r.im1 + mi}, n);
  std::vector<complex> zeros, roots;
  for (complex z : all_zeros)
    if (r.contains(z)) zeros.push_back(z);
  for (complex z : characteristic_roots(s, wavelength))
    if (r.contains(z)) roots.push_back(z);
  INFO("H = " << s.strip_height << ", L = " << wavelength << ", roots " << roots.size());
  CHECK(zeros.size() == roots.size());
  for (complex z : zeros) {
    double nearest = inf;
    for (complex root : roots) nearest = std::min(nearest, std::abs(root - z));
    // The zoom reaches ~1e-20 of the grid; 1e-7 of the region size allows for the
    // flat |F| near a zero stopping the derivative-free zoom early.
    CHECK(nearest < 1e-7 * std::max(r.re1 - r.re0, r.im1 - r.im0));
  }
}

}  // namespace

TEST_CASE("linearisation of Eq. S1 + regularised aging law matches the hand derivation") {
  const SteadySliding s = table_s1(0.1);
  const auto& f = s.friction;
  const double v0 = s.driving_velocity, vs = f.v_star, D = f.characteristic_slip, sg = s.normal_stress;
  const double r = std::hypot(v0, vs);
  const LinearisedFriction lin = linearise_friction(s);
  // Independent closed forms: phi0 = D / sqrt(v0^2 + v*^2); round-off only.
  CHECK(lin.state == doctest::Approx(D / r).epsilon(1e-14));
  CHECK(lin.strength_dv == doctest::Approx(sg * f.a / (v0 + vs)).epsilon(1e-14));
  CHECK(lin.strength_dstate == doctest::Approx(sg * f.f0 * f.b * r / D).epsilon(1e-14));
  CHECK(lin.state_rate_dv == doctest::Approx(-v0 / (r * r)).epsilon(1e-14));
  CHECK(lin.state_rate_dstate == doctest::Approx(-r / D).epsilon(1e-14));
}

TEST_CASE("S / s is positive real in Re s > 0 (passivity: the search-box bound rests on it)") {
  for (double H : {0.02, 0.1, 1.0, inf})
    for (PlaneCondition plane : {PlaneCondition::strain, PlaneCondition::stress}) {
      const ElasticMaterial m{9e9, 0.33, 1200.0, plane};
      for (double k : {0.3, 3.0, 30.0})
        for (double re : {1e-3, 1.0, 1e2, 1e4, 1e5})
          for (double im = -2e5; im <= 2e5; im += 977.0) {
            const complex s(re, im);
            const complex ratio = strip_response(m, H, k, s) / s;
            // Strictly >= 0 in exact arithmetic; allow round-off relative to |S/s|.
            CHECK(ratio.real() >= -1e-10 * std::abs(ratio));
          }
    }
}

TEST_CASE("listed strip resonances are the poles of S and the comb frequencies are not") {
  const ElasticMaterial m{9e9, 0.33, 1200.0, PlaneCondition::strain};
  const double H = 0.1, k = 2.0 * pi / 0.7;
  const double cs = m.shear_wave_speed(), cd = m.dilatational_wave_speed();
  const double kappa = pi / H;
  // delta * S(i w + delta) -> residue (nonzero, finite) at a pole; -> 0 elsewhere.
  auto residue_ratio = [&](double w) {
    const complex a = 1e-4 * strip_response(m, H, k, complex(1e-4, w));
    const complex b = 1e-6 * strip_response(m, H, k, complex(1e-6, w));
    return std::abs(a - b) / std::abs(b);
  };
  for (double w : {cs * k, cs * std::hypot(k, kappa), cd * std::hypot(k, kappa),
                   cs * std::hypot(k, 2 * kappa)}) {
    INFO("omega = " << w);
    // Residue estimate converges linearly in delta: O(1e-4 * |S'|/|residue|) ~ 1e-6.
    CHECK(residue_ratio(w) < 1e-5);
    CHECK(std::abs(1e-6 * strip_response(m, H, k, complex(1e-6, w))) > 1.0);
  }
  // Comb frequency c_s kappa: S stays finite there, so delta * S -> 0 (the coth pole of
  // the shear comb is cancelled by the k-dependent part).  At a true pole delta * S is
  // the residue, > 1 here; at the comb frequency it is ~ delta * |S| ~ 1e-6 * 1e10.
  const double w_comb = cs * kappa;
  const double comb = std::abs(1e-6 * strip_response(m, H, k, complex(1e-6, w_comb)));
  const double comb_smaller = std::abs(1e-8 * strip_response(m, H, k, complex(1e-8, w_comb)));
  CHECK(comb_smaller < 0.02 * comb);  // shrinks ~ linearly with delta: no pole
  CHECK(std::isfinite(std::abs(strip_response(m, H, k, complex(0.0, w_comb)))));
}

TEST_CASE("quasi-static half-space Lc: closed form for Eq. S1 + regularised Eq. S2") {
  SteadySliding s = table_s1(inf);
  const auto& f = s.friction;
  const double v0 = s.driving_velocity, vs = f.v_star, D = f.characteristic_slip;
  const double r = std::hypot(v0, vs);
  // Hand derivation (docs/stability.md): S = mu* k, neutral at
  //   mu* k_c = (sigma0 / D) [ f0 b v0 / sqrt(v0^2+v*^2) - a sqrt(v0^2+v*^2) / (v0 + v*) ].
  const double mu_star = 9e9 / (2.0 * (1.0 - 0.33));  // plane strain: mu (1 - cs^2/cd^2)
  const double kc = s.normal_stress / D * (f.f0 * f.b * v0 / r - f.a * r / (v0 + vs)) / mu_star;
  const double closed_form = 2.0 * pi / kc;
  CHECK(quasi_static_critical_wavelength(s) == doctest::Approx(closed_form).epsilon(1e-13));

  // The full dynamic root finder converges to it as inertia vanishes (tiny density,
  // c_s -> inf).  Near neutrality |Lambda| << c_s k: the half-space S has no term
  // linear in Lambda there (no radiation below the shear speed), S = mu* k + O(Lambda^2 /
  // (k c_s^2)), so the error must fall like 1/c_s^2 = rho/mu: a factor 100 per factor 100
  // in density (until the min_re ~ 1e-9 resolution of the bisection is reached).
  std::vector<double> errors;
  for (double density : {1200e-2, 1200e-4, 1200e-6}) {
    s.material.density = density;
    const double lc = critical_wavelength(s, 0.5 * closed_form, 2.0 * closed_form, 1e-13);
    errors.push_back(std::abs(lc / closed_form - 1.0));
  }
  MESSAGE("relative errors vs quasi-static closed form: " << errors[0] << " " << errors[1] << " "
                                                          << errors[2]);
  CHECK(errors[2] < 1e-6);
  CHECK(errors[0] / errors[1] == doctest::Approx(100.0).epsilon(0.05));  // rho rate, +-5%
  CHECK(errors[1] / errors[2] == doctest::Approx(100.0).epsilon(0.05));
}

TEST_CASE("quasi-static finite-H Lc: dynamic solver with negligible inertia converges to it") {
  for (double H : {0.05, 0.2}) {
    SteadySliding s = table_s1(H);
    const double qs = quasi_static_critical_wavelength(s);
    s.material.density = 1200e-8;  // c_s 1e4 times larger
    const double lc = critical_wavelength(s, 0.5 * qs, 2.0 * qs, 1e-12);
    INFO("H = " << H);
    // Same O(rho) inertia correction as for the half-space (~1e-9 here).
    CHECK(lc == doctest::Approx(qs).epsilon(1e-6));
  }
}

// The reference material (Table S1's 9 GPa read as Young's modulus) as an
// antiplane body: mu/(2 K_c) = 0.0529 m, so strips from 0.06 m up have a root.
SteadySliding antiplane_reference(double H) {
  SteadySliding s = table_s1(H);
  s.material = ElasticMaterial{9e9 / (2.0 * 1.33), 0.33, 1200.0, PlaneCondition::antiplane};
  return s;
}

double critical_stiffness(const SteadySliding& s) {
  const LinearisedFriction lin = linearise_friction(s);
  return lin.strength_dv * lin.state_rate_dstate - lin.strength_dstate * lin.state_rate_dv;
}

TEST_CASE("quasi-static finite-H Lc, antiplane: longer than the half-space's, dynamic solver with negligible inertia converges to it") {
  const double half_space = quasi_static_critical_wavelength(antiplane_reference(inf));
  for (double H : {0.06, 0.1, 0.2}) {
    SteadySliding s = antiplane_reference(H);
    const double qs = quasi_static_critical_wavelength(s);
    INFO("H = " << H);
    // (mu k / 2) coth(kH) > mu k / 2: the strip is stiffer than the half-space,
    // so its neutral k is smaller (in-plane it is the other way round).
    CHECK(qs > half_space);
    // The neutral condition itself; the bisection in k stops at 1e-15.
    CHECK(strip_static_stiffness(s.material, H, 2.0 * pi / qs) ==
          doctest::Approx(critical_stiffness(s)).epsilon(1e-13));
    s.material.density = 1200e-8;  // c_s 1e4 times larger
    const double lc = critical_wavelength(s, 0.5 * qs, 2.0 * qs, 1e-12);
    // The O(rho) inertia correction, as in-plane.
    MESSAGE("antiplane H = " << H << ": dynamic Lc at rho = 1.2e-5 vs quasi-static " << lc / qs - 1.0);
    CHECK(lc == doctest::Approx(qs).epsilon(1e-6));
  }
}

TEST_CASE("quasi-static finite-H Lc, antiplane: the dynamic Lc converges to it like rho") {
  // A finite strip's S is analytic and even in Lambda (lossless), S = S0 + O(Lambda^2 / c_s^2),
  // so the error falls like 1/c_s^2 = rho/mu: a factor 100 per factor 100 in density.
  SteadySliding s = antiplane_reference(0.1);
  const double qs = quasi_static_critical_wavelength(s);
  std::vector<double> errors;
  for (double density : {1200e-1, 1200e-3, 1200e-5}) {
    s.material.density = density;
    const double lc = critical_wavelength(s, 0.5 * qs, 2.0 * qs, 1e-13);
    errors.push_back(std::abs(lc / qs - 1.0));
  }
  MESSAGE("antiplane H = 0.1: relative errors vs quasi-static: " << errors[0] << " " << errors[1] << " " << errors[2]);
  CHECK(errors[2] < 1e-6);
  CHECK(errors[0] / errors[1] == doctest::Approx(100.0).epsilon(0.05));
  CHECK(errors[1] / errors[2] == doctest::Approx(100.0).epsilon(0.05));
}

TEST_CASE("quasi-static Lc of antiplane pairs of different bodies: dynamic solver with negligible inertia converges to it") {
  struct Case {
    const char* name;
    double top_height;
    bool rigid;
    double bottom_height;
  };
  for (const Case c : {Case{"strip on a rigid base", 0.2, true, 0.1}, Case{"strip on a 4x stiffer strip", 0.1, false, 0.2},
                       Case{"strip on a 4x stiffer half-space", 0.1, false, inf}}) {
    SteadySliding s = antiplane_reference(c.top_height);
    s.two_bodies = true;
    s.bottom_rigid = c.rigid;
    s.bottom_material = s.material;
    s.bottom_material.shear_modulus *= 4.0;
    s.bottom_material.density *= 4.0;
    s.bottom_height = c.bottom_height;
    const double qs = quasi_static_critical_wavelength(s);
    INFO(c.name);
    const double k = 2.0 * pi / qs;
    const double top = 2.0 * strip_static_stiffness(s.material, s.strip_height, k);
    const double bottom = 2.0 * strip_static_stiffness(s.bottom_material, s.bottom_height, k);
    CHECK((c.rigid ? top : top * bottom / (top + bottom)) == doctest::Approx(critical_stiffness(s)).epsilon(1e-13));
    s.material.density = 1200e-8;
    s.bottom_material.density = 4800e-8;
    const double lc = critical_wavelength(s, 0.5 * qs, 2.0 * qs, 1e-12);
    MESSAGE(std::string(c.name) << ": dynamic Lc at negligible inertia vs quasi-static " << lc / qs - 1.0);
    CHECK(lc == doctest::Approx(qs).epsilon(1e-6));
  }
  // Lc(H) of a pair brackets around this function's value for a top half-space
  // (it refused pairs before); at negligible inertia it is this function's.
  SteadySliding pair = antiplane_reference(0.2);
  pair.two_bodies = true;
  pair.bottom_rigid = true;
  pair.material.density = 1200e-8;
  const auto lc = critical_wavelength_vs_height(pair, {0.2});
  CHECK(lc[0] == doctest::Approx(quasi_static_critical_wavelength(pair)).epsilon(1e-6));
}

TEST_CASE("a thin antiplane strip has no unstable wavelength: both Lc functions say so naming H") {
  // mu/(2H) = 3.38e10 Pa/m at H = 0.05 m, above K_c = 3.20e10 Pa/m.
  const SteadySliding s = antiplane_reference(0.05);
  CHECK_THROWS_WITH_AS(quasi_static_critical_wavelength(s),
                       doctest::Contains("H = 0.05 m: no unstable wavelength; the antiplane strip's static "
                                         "stiffness (mu k/2) coth(kH) exceeds mu/(2H) = 3.38346e+10 Pa/m"),
                       std::invalid_argument);
  CHECK_THROWS_WITH_AS(quasi_static_critical_wavelength(s), doctest::Contains("H > mu/(2 K_c) = 0.0528657 m"),
                       std::invalid_argument);
  CHECK_THROWS_WITH_AS(critical_wavelength_vs_height(antiplane_reference(0.1), {0.05}),
                       doctest::Contains("H = 0.05 m: no unstable wavelength"), std::invalid_argument);
  SteadySliding on_rigid = antiplane_reference(0.1);  // mu/H = 3.38e10 Pa/m
  on_rigid.two_bodies = true;
  on_rigid.bottom_rigid = true;
  CHECK_THROWS_WITH_AS(quasi_static_critical_wavelength(on_rigid),
                       doctest::Contains("H = 0.1 m on a rigid base: no unstable wavelength"), std::invalid_argument);
  // In-plane strips bend: no such limit (Lc ~ sqrt(H), tested above).
  CHECK(std::isfinite(quasi_static_critical_wavelength(table_s1(0.001))));
}

TEST_CASE("root finder agrees with a brute-force grid search of |F|") {
  check_roots_against_brute_force(table_s1(0.1), 1.0, 300);   // complex pair
  check_roots_against_brute_force(table_s1(0.1), 2.0, 300);   // two real roots
  check_roots_against_brute_force(table_s1(inf), 1.5, 300);   // half-space
  check_roots_against_brute_force(table_s1(0.02), 3.0, 300);  // kH small (plate bending)
}

TEST_CASE("argument-principle count equals the roots found; roots are zeros and conjugate-closed") {
  struct Case {
    double H, L, sigma;
  };
  // Last two: sigma0 = 1e9 makes the friction impedance large compared with the
  // strip residues, so roots sit right next to the lossless resonance poles.
  for (const Case c : {Case{0.1, 1.0, 1e6}, Case{0.05, 0.6, 1e6}, Case{inf, 3.0, 1e6},
                       Case{10.0, 2.0, 1e6}, Case{0.01, 5.0, 1e6}, Case{0.1, 2.0, 1e9},
                       Case{0.1, 3.0, 1e9}}) {
    SteadySliding s = table_s1(c.H);
    s.normal_stress = c.sigma;
    const SearchBox box = unstable_search_box(s);
    const auto roots = characteristic_roots(s, c.L, box);
    INFO("H = " << c.H << " L = " << c.L << " sigma0 = " << c.sigma);
    CHECK(static_cast<int>(roots.size()) == count_roots(s, c.L, box));
    CHECK(!roots.empty());
    const double k = 2.0 * pi / c.L;
    for (complex z : roots) {
      // Newton stops at ~1e-14 relative step; residual is round-off of the terms.
      CHECK(std::abs(characteristic_function(s, k, z)) < 1e-8 * term_scale(s, k, z));
      double nearest = inf;
      for (complex w : roots) nearest = std::min(nearest, std::abs(w - std::conj(z)));
      CHECK(nearest < 1e-8 * std::abs(z));  // F has real coefficients
    }
  }
}

TEST_CASE("roots next to the strip resonances are resolved") {
  SteadySliding s = table_s1(0.1);
  s.normal_stress = 1e9;
  const double L = 3.0, k = 2.0 * pi / L;
  const double pole = s.material.shear_wave_speed() * k;  // m = 0 shear resonance
  const auto roots = characteristic_roots(s, L);
  double nearest = inf;
  for (complex z : roots) nearest = std::min(nearest, std::abs(z - complex(0.0, pole)));
  MESSAGE("distance of nearest root to the c_s k resonance: " << nearest << " 1/s (pole at " << pole
                                                             << ")");
  // Perturbation estimate: shift = rho_0 / (2 w^2 Z_f) with rho_0 = -mu c_s^2 k^2/(2H),
  // Z_f ~ sigma0-proportional impedance ~ 1e9 * 2.5 => ~ a few 1/s; require it to be
  // found within 1% of the pole frequency.
  CHECK(nearest < 1e-2 * pole);
  // Brute force on a fine local grid (spacing ~0.1 1/s) around the pole, where |F|
  // varies on the scale of the root-pole distance; a coarse global grid cannot see it.
  check_roots_against_brute_force(s, L, 300, Rect{1e-3, 30.0, pole - 15.0, pole + 15.0});
  // And the global box (the real roots, one nearly neutral at Re ~ 0.2 1/s).
  check_roots_against_brute_force(s, L, 300);
}

TEST_CASE("nearly neutral roots: Re Lambda crosses zero linearly at Lc") {
  const SteadySliding s = table_s1(0.1);
  const double lc = critical_wavelength(s, 0.3, 1.0, 1e-13);
  CHECK(!most_unstable_root(s, lc * (1.0 - 1e-6)).has_value());
  const auto r1 = most_unstable_root(s, lc * (1.0 + 1e-6));
  const auto r2 = most_unstable_root(s, lc * (1.0 + 2e-6));
  REQUIRE(r1.has_value());
  REQUIRE(r2.has_value());
  CHECK(r1->real() > 0.0);
  // Linear crossing: Re doubles when the distance to Lc doubles (curvature O(1e-6)).
  CHECK(r2->real() / r1->real() == doctest::Approx(2.0).epsilon(1e-3));
  CHECK(std::abs(r1->imag()) > 0.0);  // oscillatory (Hopf) crossing
}

TEST_CASE("aging and slip laws share the linearisation at steady state") {
  SteadySliding aging = table_s1(0.1);
  SteadySliding slip = aging;
  slip.friction.state_law = StateLaw::slip;
  const LinearisedFriction a = linearise_friction(aging), b = linearise_friction(slip);
  // Slip law: phi0 = D/v0, g_v = -1/v0, g_phi = -v0/D exactly.  The regularised aging
  // law differs by factors sqrt(1 + (v*/v0)^2) = 1 + 1.25e-9: tau_v identical, the
  // products that enter F (tau_phi g_v, g_phi) equal to O((v*/v0)^2).
  const double eps = std::pow(aging.friction.v_star / aging.driving_velocity, 2);
  CHECK(a.strength_dv == b.strength_dv);
  CHECK(std::abs(a.strength_dstate * a.state_rate_dv / (b.strength_dstate * b.state_rate_dv) - 1.0) <
        eps);
  CHECK(std::abs(a.state_rate_dstate / b.state_rate_dstate - 1.0) < eps);
  for (double L : {0.8, 1.5}) {
    const auto ra = characteristic_roots(aging, L), rb = characteristic_roots(slip, L);
    REQUIRE(ra.size() == rb.size());
    for (std::size_t i = 0; i < ra.size(); ++i)
      CHECK(std::abs(ra[i] - rb[i]) < 1e-7 * std::abs(ra[i]));  // O(eps) plus Newton round-off
  }
  CHECK(critical_wavelength(aging, 0.3, 1.0) ==
        doctest::Approx(critical_wavelength(slip, 0.3, 1.0)).epsilon(1e-7));
}

TEST_CASE("Lc(H) increases with H and tends to the half-space value") {
  const std::vector<double> heights{0.025, 0.05, 0.1, 0.2, 0.4, 0.8, 1.6, inf};
  const auto lc = critical_wavelength_vs_height(table_s1(0.1), heights);
  for (std::size_t i = 0; i + 1 < lc.size(); ++i) CHECK(lc[i] < lc[i + 1]);
  // Image contributions decay like exp(-2 alpha H), alpha >= k sqrt(1 - w^2/(c_s k)^2):
  // at H = 1.6 m, kH ~ 8.5, the difference is far below 1e-3.
  CHECK(lc[6] == doctest::Approx(lc[7]).epsilon(1e-3));
  // Plate-bending limit: S0 ~ E' k^2 H / 6 makes the quasi-static Lc ~ sqrt(H) for kH << 1.
  SteadySliding thin = table_s1(0.001);
  SteadySliding thinner = table_s1(0.00025);
  CHECK(quasi_static_critical_wavelength(thin) / quasi_static_critical_wavelength(thinner) ==
        doctest::Approx(2.0).epsilon(1e-2));  // O((kH)^2) corrections, kH ~ 0.05
}

TEST_CASE("growth_rates reports the most unstable root, or the least-damped one if stable") {
  const SteadySliding s = table_s1(0.1);
  const auto table = growth_rates(s, {0.5, 1.0});
  REQUIRE(table.size() == 2);
  const auto r = most_unstable_root(s, 1.0);
  REQUIRE(r.has_value());
  CHECK(table[1].unstable);
  CHECK(table[1].growth_rate == r->real());
  CHECK(table[1].frequency == std::abs(r->imag()));
  CHECK(!table[0].unstable);
  CHECK(table[0].growth_rate < 0.0);  // L = 0.5 m < Lc(0.1 m): damped
  // The damped root is a genuine zero of F.
  const complex z(table[0].growth_rate, table[0].frequency);
  CHECK(std::abs(characteristic_function(s, 2.0 * pi / 0.5, z)) <
        1e-8 * term_scale(s, 2.0 * pi / 0.5, z));
}

TEST_CASE("bad input throws std::invalid_argument naming the parameter") {
  SteadySliding s = table_s1(0.1);
  CHECK_THROWS_AS(most_unstable_root(s, -1.0), std::invalid_argument);
  s.driving_velocity = 0.0;
  CHECK_THROWS_WITH_AS(linearise_friction(s), doctest::Contains("driving_velocity"),
                       std::invalid_argument);
  s = table_s1(0.1);
  CHECK_THROWS_WITH_AS(critical_wavelength(s, 2.0, 3.0), doctest::Contains("lower"),
                       std::invalid_argument);
  CHECK_THROWS_AS(damped_search_box(table_s1(inf)), std::invalid_argument);
}
