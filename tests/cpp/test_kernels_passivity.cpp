// Passivity of the discrete history operator (docs/theory.md, "passivity").
//
// Per Fourier mode k != 0 the solver's traction is tau_n = load - Z_d(z) v_n
// with (v_n = z^n)
//   Z_d(z) = eta + (mu/c_s)/(z-1)
//          + dt sum_m w_m [1/(z-1) - (z cos phi_m - 1)/(z^2 - 2 z cos phi_m + 1)],
// built here directly from discrete_modes() (not from the Foster form the
// theory uses to argue about it).  Free ringing of the discrete system solves
// Z_d(z) = 0; if Re Z_d > 0 for |z| > 1 (discrete positive real) no root lies
// outside the unit circle and nothing grows.  We check that, losslessness on
// |z| = 1, the static limit, the comb identity, that StripHistory really
// applies this Z_d, and that the scheme this replaced fails the same check.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <vector>

#include "kernels/elastic_material.hpp"
#include "kernels/history_convolution.hpp"
#include "kernels/strip_response.hpp"

using namespace slipstrip;
using cplx = std::complex<double>;
constexpr double pi = std::numbers::pi;

namespace {

struct Case {
  double height, length;
  int nodes;
  double beta;
};

// Cases covering odd and even M = 2H/(c_s dt), small and large M, and kH at
// the x-Nyquist from ~0.3 up to ~200 (beyond the x > 40 branch of the static
// stiffness).  beta stays below the passivity limit
// beta_eff <= mu / (dx S(k_Nyquist, 0)) ~ 0.4265 (plane strain, nu = 0.33),
// tested separately below.
const Case cases[] = {
    {0.1, 4.0, 256, 0.4},      // M = 32 (even)
    {0.1, 4.0, 2048, 0.25},    // M = 410 (even), the benchmark configuration
    {0.01, 2 * pi * 0.01 / 0.05, 256, 0.25},  // M = 17 (odd), free-ringing test geometry
    {0.05, 1.0, 64, 0.35},     // M = 19 (odd)
    {0.01, 4.0, 256, 0.3},     // M = 5 (odd), very coarse in time
    {1.0, 4.0, 256, 0.41},     // M = 313 (odd), kH up to 201
};

struct Discrete {
  double dt, eta, echo_weight;
  std::size_t echo_steps;
};

Discrete discretise(const ElasticMaterial& material, const Case& c) {
  const double dt = strip_time_step(material, c.height, c.length / c.nodes, c.beta);
  // echo_steps exactly as the solver's operator counts it.
  const StripHistory history(material, c.height, c.length, c.nodes, dt);
  const double cs = material.shear_wave_speed();
  return {dt, material.shear_modulus / (2 * cs), material.shear_modulus / cs,
          history.stats().echo_steps};
}

// sin and cos of one angle from one argument reduction (glibc's sincos): the
// reductions are most of the cost of these checks, in long double above all.
void sin_cos(double x, double* s, double* c) { ::sincos(x, s, c); }

// In long double glibc's sincosl reduces every argument above pi/4 by its
// general (Payne-Hanek) reduction, which was most of the cost of the lossless
// check.  Every angle here is a half angle, |x| <= pi, so x = n pi/2 + r with
// |n| <= 2, |r| <= pi/4 is reduced with pi/2 in three long-double parts
// (Cody-Waite): x - n P1 is exact (Sterbenz: x/2 <= n P1 <= 2x), the two
// corrections each round once, so r is correct to about an ulp of itself,
// however close x is to a multiple of pi/2 (the rest of pi/2 beyond P3 is
// 2.5e-60).  sincosl(r) then takes no reduction, and the quadrant n only
// swaps and negates.
void sin_cos(long double x, long double* s, long double* c) {
  constexpr long double half_pi_1 = 0xc90fdaa22168c235p-63L;   // pi/2 to 64 bits
  constexpr long double half_pi_2 = -0xece675d1fc8f8cbbp-129L;  // pi/2 - half_pi_1
  constexpr long double half_pi_3 = -0xb7ed8fbbacc19c60p-194L;  // the rest
  constexpr long double two_over_pi = 1 / half_pi_1;
  if (!(std::abs(x) <= 2 * half_pi_1)) {  // outside |x| <= pi: the general reduction
    ::sincosl(x, s, c);
    return;
  }
  // n nearest to x / (pi/2), |n| <= 2 (a tie may go either way; both reduce
  // exactly).  Not std::nearbyint: it saves and restores the FPU state.
  const int n = static_cast<int>(x * two_over_pi + (x < 0 ? -0.5L : 0.5L));
  const long double r = ((x - n * half_pi_1) - n * half_pi_2) - n * half_pi_3;
  long double sin_r, cos_r;
  ::sincosl(r, &sin_r, &cos_r);
  switch (n & 3) {  // sin and cos of r + n pi/2
    case 0: *s = sin_r; *c = cos_r; break;
    case 1: *s = cos_r; *c = -sin_r; break;
    case 2: *s = -sin_r; *c = -cos_r; break;
    default: *s = -cos_r; *c = sin_r; break;
  }
}

// sin and cos of theta/2: all that r e^{i theta} - 1 needs of the angle, so
// one pair serves every radius r sampled at that angle.
template <class Real>
struct HalfAngle {
  Real s, c;
};

template <class Real>
HalfAngle<Real> half_angle(Real theta) {
  HalfAngle<Real> h;
  sin_cos(Real(0.5) * theta, &h.s, &h.c);
  return h;
}

// r e^{i theta} - 1 without the cancellation of cos(theta) - 1 near theta = 0
// (which would otherwise swamp the O(r - 1) real parts we are testing):
// cos(theta) - 1 = -2 sin^2(theta/2) and sin(theta) = 2 sin(theta/2) cos(theta/2),
// both from the sine and cosine of theta/2, so each part is correct to a few ulps.
template <class Real>
std::complex<Real> exp_minus_one(Real r, const HalfAngle<Real>& h) {
  return {(r - 1) - 2 * r * h.s * h.s, 2 * r * h.s * h.c};
}

// |z| for the rounding-error scale below: the square root of the squared
// norm, correct to a couple of ulps, which is all a scale needs.  std::abs
// (hypot) also guards against overflow of the squares, which these magnitudes
// (below ~1e20) cannot reach, at several times the cost.
template <class Real>
Real magnitude(const std::complex<Real>& z) {
  return std::sqrt(std::norm(z));
}

// What Z_d needs of one mode that does not depend on z: built once per mode
// list, not once per sample angle.
template <class Real>
struct ModeTerm {
  Real phase, weight;
  Real cos_phase;      // cos(phi)
  Real two_sin2_half;  // 2 sin^2(phi/2) = 1 - cos(phi), without its cancellation
};

template <class Real = double>
std::vector<ModeTerm<Real>> mode_terms(const std::vector<DiscreteMode>& modes) {
  std::vector<ModeTerm<Real>> terms;
  terms.reserve(modes.size());
  for (const auto& m : modes) {
    const Real phi = m.phase;
    const Real half = std::sin(Real(0.5) * phi);
    terms.push_back({phi, Real(m.weight), std::cos(phi), 2 * half * half});
  }
  return terms;
}

struct ZValue {
  cplx value;
  double scale;  // sum of the magnitudes of all terms: the rounding-error scale
};

// Z_d(r e^{i theta}) from the brief's formula, with the differences written
// out accurately.  The running-sum term is the delay line + comb modes (comb
// identity); `modes` are the recursions of the operator.  Real = long double
// is used where the real part must be resolved to ~1e-14 of the terms even
// next to z = -1: there theta + phi ~ 2 pi, and its rounding in double
// (~4e-16 absolute) is a relative error 4e-16/|2 pi - theta - phi| in
// z - e^{-i phi}; in long double the sum of two doubles is exact.
//
// Evaluated at several radii r for one angle theta at once: the sines and
// cosines of the half angles do not depend on r, and they are most of the
// cost (each radius's arithmetic is the same as if it were evaluated alone).
template <class Real, std::size_t R>
std::array<ZValue, R> z_operator(const Discrete& d, const std::vector<ModeTerm<Real>>& modes,
                                 const std::array<double, R>& radii, double theta_in) {
  using C = std::complex<Real>;
  const Real theta = theta_in, dt = d.dt;
  const HalfAngle<Real> half = half_angle(theta);
  std::array<C, R> zm1, inv_zm1, total;
  std::array<Real, R> scale, abs_inv_zm1;
  for (std::size_t i = 0; i < R; ++i) {
    zm1[i] = exp_minus_one(Real(radii[i]), half);
    inv_zm1[i] = Real(1) / zm1[i];
    total[i] = Real(d.eta) + Real(d.echo_weight) * inv_zm1[i];
    abs_inv_zm1[i] = std::abs(inv_zm1[i]);
    scale[i] = Real(d.eta) + Real(d.echo_weight) * abs_inv_zm1[i];
  }
  for (const auto& m : modes) {
    const HalfAngle<Real> below = half_angle(theta - m.phase), above = half_angle(theta + m.phase);
    for (std::size_t i = 0; i < R; ++i) {
      const Real r = radii[i];
      // z cos(phi) - 1 = cos(phi) (z - 1) - 2 sin^2(phi/2)
      const C numerator = m.cos_phase * zm1[i] - m.two_sin2_half;
      // z^2 - 2 z cos(phi) + 1 = (z - e^{i phi})(z - e^{-i phi})
      //                        = (r e^{i(theta-phi)} - 1)(r e^{i(theta+phi)} - 1)
      const C denominator = exp_minus_one(r, below) * exp_minus_one(r, above);
      const C ratio = numerator / denominator;
      total[i] += dt * m.weight * (inv_zm1[i] - ratio);
      scale[i] += dt * std::abs(m.weight) * (abs_inv_zm1[i] + magnitude(ratio));
    }
  }
  std::array<ZValue, R> out;
  for (std::size_t i = 0; i < R; ++i)
    out[i] = {cplx(static_cast<double>(total[i].real()), static_cast<double>(total[i].imag())),
              static_cast<double>(scale[i])};
  return out;
}

template <class Real = double>
ZValue z_operator(const Discrete& d, const std::vector<ModeTerm<Real>>& modes, double r,
                  double theta) {
  return z_operator(d, modes, std::array<double, 1>{r}, theta)[0];
}

// Wavenumber indices to test: all of them for small N, else a log-spaced set
// that always contains q = 1, 2 and the x-Nyquist N/2.
std::vector<int> wavenumber_indices(int nodes) {
  std::vector<int> q;
  const int top = nodes / 2;
  if (top <= 32) {
    for (int i = 1; i <= top; ++i) q.push_back(i);
    return q;
  }
  for (double x = 1; x < top; x *= 1.35) q.push_back(static_cast<int>(x));
  q.push_back(top - 1);
  q.push_back(top);
  std::sort(q.begin(), q.end());
  q.erase(std::unique(q.begin(), q.end()), q.end());
  return q;
}

// Angles on which Re Z_d is sampled: a uniform grid on (0, pi] plus every
// pole phase and its immediate neighbours (the narrow peaks of Re Z_d at
// r = 1.0005, of width ~5e-4, sit there; a negative Foster coefficient shows
// up first at its own phase).  Z_d(conj z) = conj Z_d(z), so (0, pi] suffices.
std::vector<double> sample_angles(const std::vector<DiscreteMode>& modes, std::size_t echo_steps) {
  std::vector<double> theta;
  const int uniform = 4096;
  for (int i = 1; i <= uniform; ++i) theta.push_back(pi * i / uniform);
  theta.push_back(1e-6);
  for (const auto& m : modes)
    for (double off : {-1e-4, 0.0, 1e-4}) theta.push_back(std::clamp(m.phase + off, 1e-6, pi));
  // The comb poles that the identity removed (z^M = 1) must not reappear.
  for (std::size_t j = 1; 2 * j <= echo_steps; ++j) theta.push_back(2 * pi * j / echo_steps);
  return theta;
}

struct PositivityResult {
  double min_re_over_scale = std::numeric_limits<double>::infinity();
  double min_re_over_abs = std::numeric_limits<double>::infinity();
  double theta_at_min = 0;
};

// The smallest Re Z_d on circles of radius r at the angles of sample_angles,
// for every radius of `radii` (from one pass over the angles).
template <std::size_t R>
std::array<PositivityResult, R> positivity(const Discrete& d, const std::vector<DiscreteMode>& modes,
                                           const std::array<double, R>& radii) {
  std::array<PositivityResult, R> out;
  const auto terms = mode_terms(modes);
  for (double theta : sample_angles(modes, d.echo_steps)) {
    const auto values = z_operator(d, terms, radii, theta);
    for (std::size_t i = 0; i < R; ++i) {
      const auto& zv = values[i];
      const double ratio = zv.value.real() / zv.scale;
      if (ratio < out[i].min_re_over_scale) {
        out[i].min_re_over_scale = ratio;
        out[i].theta_at_min = theta;
      }
      out[i].min_re_over_abs = std::min(out[i].min_re_over_abs, zv.value.real() / std::abs(zv.value));
    }
  }
  return out;
}

PositivityResult positivity(const Discrete& d, const std::vector<DiscreteMode>& modes, double r) {
  return positivity(d, modes, std::array<double, 1>{r})[0];
}

// The placement discrete_modes replaced (docs/theory.md, "The placement"): raw
// shear and P weights below Nyquist, the truncated static stiffness on ONE
// oscillator at phase pi whatever its sign.
std::vector<DiscreteMode> unfixed_modes(const ElasticMaterial& material, double H, double k,
                                        const Discrete& d, double* truncated_out) {
  std::vector<DiscreteMode> out;
  double kept = material.shear_modulus / H * 0.5 * (static_cast<double>(d.echo_steps) - 1.0);
  for (const auto& m : strip_modes(material, H, k, pi / d.dt)) {
    if (m.family == ModeFamily::comb) continue;
    out.push_back({m.frequency * d.dt, m.weight, m.family});
    kept += m.weight;
  }
  const double truncated =
      strip_static_stiffness(material, H, k) - material.shear_modulus / (2 * H) - kept;
  out.push_back({pi, truncated, ModeFamily::shear});
  *truncated_out = truncated;
  return out;
}

}  // namespace

TEST_CASE("the test cases cover odd and even echo step counts M") {
  ElasticMaterial material;
  bool odd = false, even = false;
  for (const auto& c : cases) {
    const auto d = discretise(material, c);
    MESSAGE("H = " << c.height << " L = " << c.length << " N = " << c.nodes << " beta = " << c.beta
                   << ": M = " << d.echo_steps << ", kH at x-Nyquist = "
                   << pi * c.nodes / c.length * c.height);
    (d.echo_steps % 2 ? odd : even) = true;
  }
  CHECK(odd);
  CHECK(even);
}

TEST_CASE("discrete operator is positive real: every weight <= 0 and Re Z_d > 0 outside |z| = 1") {
  for (auto plane : {PlaneCondition::strain, PlaneCondition::stress, PlaneCondition::antiplane}) {
    ElasticMaterial material;
    material.plane = plane;
    for (const auto& c : cases) {
      const auto d = discretise(material, c);
      double worst[3] = {1e300, 1e300, 1e300};
      for (int q : wavenumber_indices(c.nodes)) {
        const double k = 2 * pi * q / c.length;
        const auto modes = discrete_modes(material, c.height, k, d.dt, d.echo_steps);
        INFO("plane " << kPlaneConditionNames[static_cast<std::size_t>(plane)] << ", H = "
                      << c.height << ", N = " << c.nodes << ", M = " << d.echo_steps
                      << ", q = " << q << ", kH = " << k * c.height);
        // Foster coefficient -w dt/4 at e^{+-i phi} must be >= 0.
        for (const auto& m : modes) {
          CHECK(m.weight <= 0.0);
          CHECK(m.phase > 0.0);
          CHECK(m.phase <= pi);
        }
        const std::array<double, 3> radii = {1.0005, 1.01, 1.2};
        const auto at_radius = positivity(d, modes, radii);
        for (int i = 0; i < 3; ++i) {
          const auto& p = at_radius[i];
          INFO("r = " << radii[i] << ": min Re Z_d / scale = " << p.min_re_over_scale
                      << " at theta = " << p.theta_at_min);
          // Strictly positive, and by more than rounding: each term is computed
          // to a few ulps, so the rounding error of the sum is below ~1e-14 of
          // `scale` (the sum of the magnitudes of the terms).
          CHECK(p.min_re_over_scale > 1e-14);
          worst[i] = std::min(worst[i], p.min_re_over_scale);
        }
      }
      MESSAGE(kPlaneConditionNames[static_cast<std::size_t>(plane)]
              << " M = " << d.echo_steps << ": min Re Z_d / scale over q, theta: r=1.0005 "
              << worst[0] << ", r=1.01 " << worst[1] << ", r=1.2 " << worst[2]);
    }
  }
}

TEST_CASE("discrete operator is lossless: Re Z_d = 0 on |z| = 1 away from its poles") {
  ElasticMaterial material;
  for (const auto& c : cases) {
    const auto d = discretise(material, c);
    double worst_scale = 0, worst_abs = 0;
    for (int q : wavenumber_indices(c.nodes)) {
      const double k = 2 * pi * q / c.length;
      const auto modes = discrete_modes(material, c.height, k, d.dt, d.echo_steps);
      const auto terms = mode_terms<long double>(modes);
      for (double theta : sample_angles(modes, d.echo_steps)) {
        bool at_pole = theta < 1e-5;
        for (const auto& m : modes) at_pole = at_pole || std::abs(theta - m.phase) < 1e-9;
        if (at_pole) continue;
        const auto zv = z_operator<long double>(d, terms, 1.0, theta);
        worst_scale = std::max(worst_scale, std::abs(zv.value.real()) / zv.scale);
        // |Z_d| itself vanishes at the resonances (that is what they are), so
        // the ratio to |Z_d| is reported only where |Z_d| is not itself at the
        // rounding level.
        if (std::abs(zv.value) > 1e-6 * zv.scale)
          worst_abs = std::max(worst_abs, std::abs(zv.value.real()) / std::abs(zv.value));
      }
    }
    MESSAGE("M = " << d.echo_steps << ": max |Re Z_d| / scale = " << worst_scale
                   << ", max |Re Z_d| / |Z_d| (|Z_d| > 1e-6 scale) = " << worst_abs);
    // Exact zero in exact arithmetic; evaluated in long double, each term is
    // correct to a few long-double ulps (1e-19), so 1e-14 of the magnitude
    // scale leaves room for the double inputs' own rounding (phases, weights
    // change the value, not its realness).
    CHECK(worst_scale < 1e-14);
    CHECK(worst_abs < 1e-8);
  }
}

TEST_CASE("static limit of the discrete operator equals strip_static_stiffness") {
  // sum of recursion weights + comb-mode total (mu/H)(M-1)/2 + mu/(2H) == S(k, 0; H):
  // the z = 1 Foster coefficient of Z_d is then dt S(k,0)/2, the discrete
  // counterpart of the static pole of S(k, s)/s.  1e-12 relative: sums of
  // O(M) terms of mixed sign.  S(k,0) itself can be 1e-4 of the terms'
  // magnitudes (small kH: the comb total (mu/H)(M-1)/2 and the shear weights
  // cancel), so the rounding bound is on the magnitude: recursive summation of
  // n terms errs by at most n eps sum|terms|, and the sum is formed twice
  // (in discrete_modes and here).  The relative-to-S error is reported.
  for (auto plane : {PlaneCondition::strain, PlaneCondition::stress, PlaneCondition::antiplane}) {
    ElasticMaterial material;
    material.plane = plane;
    const double mu = material.shear_modulus;
    for (const auto& c : cases) {
      const auto d = discretise(material, c);
      double worst = 0;
      for (int q : wavenumber_indices(c.nodes)) {
        const double k = 2 * pi * q / c.length;
        double total = mu / (2 * c.height) + mu / c.height * 0.5 * (d.echo_steps - 1.0);
        double magnitude = std::abs(total);
        std::size_t terms = 2;
        for (const auto& m : discrete_modes(material, c.height, k, d.dt, d.echo_steps)) {
          total += m.weight;
          magnitude += std::abs(m.weight);
          ++terms;
        }
        const double exact = strip_static_stiffness(material, c.height, k);
        INFO("M = " << d.echo_steps << " q = " << q << " kH = " << k * c.height);
        const double err = std::abs(total - exact) / exact;
        magnitude += exact;
        CHECK(std::abs(total - exact) <=
              2.0 * terms * std::numeric_limits<double>::epsilon() * magnitude);
        worst = std::max(worst, err);
        // Same statement read off Z_d: (z - 1) Z_d(z) -> 2 x (z = 1 Foster
        // coefficient) = dt S(k, 0).  Taken at z = 1 + e with e ~ 1e-9, where
        // the O(e) correction is ~ eta e / (dt S) relative; checked to 1e-6
        // wherever that correction is below 1e-7.
        const auto modes = discrete_modes(material, c.height, k, d.dt, d.echo_steps);
        const double r = 1.0 + 1e-9;
        const double e = r - 1.0;  // exact (Sterbenz)
        const auto zv = z_operator(d, mode_terms(modes), r, 0.0);
        const double coefficient = (e * zv.value).real();
        if (d.eta * e / (d.dt * exact) < 1e-7)
          CHECK(std::abs(coefficient / (d.dt * exact) - 1.0) < 1e-6);
      }
      MESSAGE("M = " << d.echo_steps << ": max |sum - S(k,0)| / S(k,0) = " << worst);
    }
  }
}

TEST_CASE("comb identity: delay line + comb modes == running sum mu/c_s at every lag") {
  // (mu/c_s) [j = 0 mod M] + dt (mu/H) sum_{m=1}^{floor(M/2)} c_m (1 - cos(2 pi m j / M))
  //   == mu/c_s for j >= 1,  c_m = 1/2 at m = M/2 (M even), else 1.
  // The comb modes are taken from strip_modes (frequency * dt must be the
  // delay-line phase 2 pi m/M, weight mu/H).  Tolerance 1e-12 relative:
  // M/2 terms of size 2 mu/(c_s M) each with an ulp of rounding.
  ElasticMaterial material;
  const double mu = material.shear_modulus;
  for (const auto& c : cases) {
    const auto d = discretise(material, c);
    const std::size_t M = d.echo_steps;
    // Small k and a generous cut so that every comb mode m <= M/2 comes with
    // its shear partner and is listed.
    const double k = 1e-3 / c.height;
    std::vector<double> phase, weight;
    for (const auto& m : strip_modes(material, c.height, k, 2 * pi / d.dt)) {
      if (m.family != ModeFamily::comb || 2 * m.index > static_cast<int>(M)) continue;
      CHECK(std::abs(m.frequency * d.dt - 2 * pi * m.index / M) < 1e-12 * pi);
      CHECK(std::abs(m.weight - mu / c.height) < 1e-12 * mu / c.height);
      phase.push_back(2 * pi * m.index / M);
      weight.push_back(2 * m.index == static_cast<int>(M) ? 0.5 * m.weight : m.weight);
    }
    REQUIRE(phase.size() == M / 2);
    double worst = 0;
    for (std::size_t j = 1; j <= 3 * M; ++j) {
      double kernel = j % M == 0 ? d.echo_weight : 0.0;
      for (std::size_t i = 0; i < phase.size(); ++i)
        kernel += d.dt * weight[i] * (1.0 - std::cos(phase[i] * j));
      worst = std::max(worst, std::abs(kernel / d.echo_weight - 1.0));
    }
    MESSAGE("M = " << M << ": max |kernel/(mu/c_s) - 1| over lags 1..3M = " << worst);
    CHECK(worst < 1e-12);
  }
}

TEST_CASE("StripHistory applies exactly the kernel of Z_d (impulse response, lags 1..3M)") {
  // So the positivity proven above is that of the operator the solver runs.
  // Impulse v_0 = 1 in mode q; history after push n is K_{n+1} =
  // mu/c_s + dt sum_m w_m (1 - cos(phi_m (n+1))).  Tolerance 1e-11 of the
  // scale mu/c_s + dt sum |w_m|: the recursion rotates by cos/sin rounded to an
  // ulp, so its error grows ~ j ulps; 3M <= 1230 steps here.
  ElasticMaterial material;
  for (const auto& c : cases) {
    const auto d = discretise(material, c);
    StripHistory history(material, c.height, c.length, c.nodes, d.dt);
    const int n_modes = c.nodes / 2 + 1;
    std::vector<cplx> spectrum(n_modes, 0.0);
    std::vector<std::vector<DiscreteMode>> modes(n_modes);
    std::vector<double> scale(n_modes, d.echo_weight);
    for (int q = 1; q < n_modes; ++q) {
      modes[q] = discrete_modes(material, c.height, 2 * pi * q / c.length, d.dt, d.echo_steps);
      for (const auto& m : modes[q]) scale[q] += d.dt * std::abs(m.weight);
      spectrum[q] = 1.0;
    }
    double worst = 0;
    for (std::size_t n = 0; n < 3 * d.echo_steps; ++n) {
      history.push(spectrum);
      std::fill(spectrum.begin(), spectrum.end(), 0.0);
      const double j = static_cast<double>(n + 1);
      for (int q = 1; q < n_modes; ++q) {
        double kernel = d.echo_weight;
        for (const auto& m : modes[q]) kernel += d.dt * m.weight * (1.0 - std::cos(m.phase * j));
        worst = std::max(worst, std::abs(history.history()[q] - kernel) / scale[q]);
      }
    }
    MESSAGE("M = " << d.echo_steps << ": max |StripHistory - Z_d kernel| / scale = " << worst);
    CHECK(worst < 1e-11);
  }
}

TEST_CASE("the test can fail: the pre-fix placement (truncated stiffness at phase pi) is not PR") {
  // Before the fix, a positive truncated static stiffness was put on one
  // oscillator at phase pi: Foster coefficient -w dt/2 < 0 at z = -1, so
  // Re Z_d < 0 just outside the circle near z = -1.  Same check as above.
  ElasticMaterial material;
  int failing = 0, positive_truncated = 0;
  for (const auto& c : cases) {
    const auto d = discretise(material, c);
    for (int q : wavenumber_indices(c.nodes)) {
      const double k = 2 * pi * q / c.length;
      double truncated = 0;
      const auto modes = unfixed_modes(material, c.height, k, d, &truncated);
      if (truncated <= 0) continue;
      ++positive_truncated;
      const auto p = positivity(d, modes, 1.0005);
      if (p.min_re_over_scale < -1e-14) ++failing;
      else
        MESSAGE("not detected: M = " << d.echo_steps << " q = " << q << " truncated = " << truncated
                                     << " min Re/scale " << p.min_re_over_scale);
    }
  }
  MESSAGE("old placement: " << positive_truncated << " wavenumbers with positive truncated "
                            "stiffness, " << failing << " of them with Re Z_d < 0 at r = 1.0005");
  REQUIRE(positive_truncated > 0);
  // Every positive-truncation case must be caught (its Foster coefficient at
  // z = -1 is negative, and at r = 1.0005 that pole's peak dominates Re Z_d).
  CHECK(failing == positive_truncated);

  // The old comb scheme for even M: delay line plus a FULL-weight comb mode at
  // phase pi leaves a net Foster coefficient -eta/M at z = -1.  Build it as
  // running sum + an extra half-weight comb element at pi (the difference).
  const Case even{0.1, 4.0, 256, 0.4};
  const auto d = discretise(material, even);
  REQUIRE(d.echo_steps % 2 == 0);
  auto modes = discrete_modes(material, even.height, 2 * pi / even.length, d.dt, d.echo_steps);
  modes.push_back({pi, 0.5 * material.shear_modulus / even.height, ModeFamily::comb});
  const auto p = positivity(d, modes, 1.0005);
  MESSAGE("full-weight Nyquist comb mode: min Re Z_d / scale = " << p.min_re_over_scale
                                                                   << " at theta = " << p.theta_at_min);
  CHECK(p.min_re_over_scale < -1e-14);
}

TEST_CASE("passive placement exists exactly when dt S(k,0)/2 <= eta (sharp time-step limit)") {
  // All Foster coefficients are >= 0 and add up to Z_d(inf) = eta, and the
  // one at z = 1 is dt S(k,0)/2 whatever the placement: so dt S(k,0) <= 2 eta
  // = mu/c_s is necessary for ANY positive-real operator of this form, and
  // the absorption in discrete_modes achieves it whenever it holds
  // (docs/theory.md).  Check both directions across beta, through the
  // x-Nyquist, where S(k,0) is largest: discrete_modes must succeed iff
  // S(k,0) <= mu/(c_s dt) (to 1e-9 relative, a margin for the sums' rounding).
  for (auto plane : {PlaneCondition::strain, PlaneCondition::stress}) {
    ElasticMaterial material;
    material.plane = plane;
    const double mu = material.shear_modulus, cs = material.shear_wave_speed();
    const double H = 0.1, L = 4.0;
    const int N = 256;
    int built = 0, refused = 0;
    for (double beta = 0.30; beta <= 0.5 + 1e-9; beta += 0.01) {
      const double dt = strip_time_step(material, H, L / N, beta);
      const auto M = static_cast<std::size_t>(std::llround(2 * H / (cs * dt)));
      for (int q = N / 4; q <= N / 2; ++q) {
        const double k = 2 * pi * q / L;
        const double margin = strip_static_stiffness(material, H, k) / (mu / (cs * dt)) - 1.0;
        if (std::abs(margin) < 1e-9) continue;
        bool ok = true;
        try {
          const auto modes = discrete_modes(material, H, k, dt, M);
          for (const auto& m : modes) ok = ok && m.weight <= 0.0;
        } catch (const std::runtime_error&) {
          ok = false;
        }
        INFO("beta " << beta << " M " << M << " q " << q << " dt S/(2 eta) - 1 = " << margin);
        CHECK(ok == (margin < 0));
        (ok ? built : refused) += 1;
      }
    }
    const double r = 1.0 - 1.0 / material.wave_speed_ratio_squared();
    MESSAGE((plane == PlaneCondition::strain ? "strain" : "stress")
            << ": built " << built << ", refused " << refused
            << "; half-space estimate of the limit beta_eff = 1/(pi (1 - c_s^2/c_d^2)) = "
            << 1.0 / (pi * r));
    CHECK(built > 0);
    CHECK(refused > 0);
  }
}
