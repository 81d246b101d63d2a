#include "stability/interface_stability.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include "stability/linear_stability.hpp"
#include "stability/root_search.hpp"

namespace slipstrip {
namespace {

using complex = std::complex<double>;

bool same_material(const ElasticMaterial& a, const ElasticMaterial& b) {
  return a.shear_modulus == b.shear_modulus && a.poisson_ratio == b.poisson_ratio &&
         a.density == b.density && a.plane == b.plane;
}

SteadySliding mirror_problem(const PairSliding& p) {
  SteadySliding s;
  s.material = p.top.material;
  s.strip_height = p.top.height;
  s.friction = p.friction;
  s.normal_stress = p.normal_stress;
  s.driving_velocity = p.driving_velocity;
  return s;
}

void require_positive(double value, const char* name) {
  if (!(value > 0.0))
    throw std::invalid_argument(std::string("pair stability: ") + name + " = " + std::to_string(value) +
                                " is not allowed; it must be > 0");
}

// Half-side of the inner square of graded_tiling (stability/root_search.hpp):
// 1e3 min_re = 1e-6 of the box's scale, so that every contour is sampled at
// <= 1/64 of its distance from the origin, down to that size.  F has features
// at many scales below the box's (set by max(2 c_d k, rate-and-state radius)),
// and one contour of the whole box, 256 samples per edge, steps over them and
// can miss a full turn of the argument:
//  * the rate-and-state zeros and the poles g_phi, -1/T: bimaterial_rupture.toml
//    at v0 = 1 um/s, L = 1 m has roots at 1.43 - 0.023i and 3.26 + 0.023i 1/s,
//    poles at -6.0 and -6.6 1/s, sampled every 120 1/s along Re = 3e-5 1/s;
//  * a strip's lowest poles and zeros on Re = 0, near +-i c k (and +-i c k^2 H
//    for the flexural modes of a thin strip), far below the rate-and-state
//    radius at long wavelengths (pmma_homalite_pair.toml at L >= 1 m).
// Cost: log_4(1e6) = 10 rings, 31 contours instead of one.
double graded_inner(const PairSearchBox& box) { return 1e3 * box.min_re; }

}  // namespace

bool is_mirror_pair(const PairSliding& p) {
  // Outer faces matter only for finite bodies.
  const bool faces = is_half_space(p.top.height) ||
                     (p.top.outer_face == OuterFace::driven && p.bottom.outer_face == OuterFace::driven);
  return !p.top.rigid && !p.bottom.rigid && same_material(p.top.material, p.bottom.material) &&
         p.top.height == p.bottom.height && faces;
}

LinearisedInterfaceFriction linearise_interface_friction(const PairSliding& p) {
  require_positive(p.normal_stress, "normal_stress");
  require_positive(p.driving_velocity, "driving_velocity");
  validate(p.friction);
  const auto& f = p.friction;
  const double v0 = p.driving_velocity, s0 = p.normal_stress;
  const double phi0 = steady_state(f, v0);
  LinearisedInterfaceFriction lin;
  lin.strength_dv = frictional_strength_dv(f, s0, v0, phi0);
  lin.strength_dstate = frictional_strength_dstate(f, s0, v0, phi0);
  lin.state_rate_dv = state_rate_dv(f, v0, phi0);
  lin.state_rate_dstate = state_rate_dstate(f, v0, phi0);
  lin.friction_coefficient = frictional_strength(f, s0, v0, phi0) / s0;
  const auto& r = p.normal_response;
  switch (r.kind) {
    case NormalStressResponse::instantaneous: lin.normal_relaxation_time = 0.0; break;
    case NormalStressResponse::slip:
      require_positive(r.slip, "normal stress relaxation slip");
      lin.normal_relaxation_time = r.slip / (v0 + f.v_star);
      break;
    case NormalStressResponse::time:
      require_positive(r.time, "normal stress relaxation time");
      lin.normal_relaxation_time = r.time;
      break;
  }
  // d phi = -(alpha phi / (B sigma_eff)) d sigma_eff, linearised at (phi0, sigma0)
  // and multiplied by tau_phi (where it enters F).
  if (f.linker_dieterich != 0.0)
    lin.linker_dieterich = f.linker_dieterich * lin.strength_dstate * phi0 / (state_log_coefficient(f) * s0);
  return lin;
}

complex pair_characteristic_function(const PairSliding& p, const LinearisedInterfaceFriction& lin,
                                     double k, complex z) {
  const SlipResponse K = interface_slip_response(p.top, p.bottom, k, z);
  complex F = K.shear + rate_and_state_response(lin, z);
  if (K.normal != 0.0) F += normal_stress_response(lin, z, K.normal);
  return F;
}

complex rate_and_state_response(const LinearisedInterfaceFriction& lin, complex z) {
  const complex state_memory = z - lin.state_rate_dstate;
  return z * (lin.strength_dv + lin.strength_dstate * lin.state_rate_dv / state_memory);
}

complex normal_stress_response(const LinearisedInterfaceFriction& lin, complex z, complex normal_stress) {
  const complex state_memory = z - lin.state_rate_dstate;
  return (lin.friction_coefficient - lin.linker_dieterich * z / state_memory) * normal_stress /
         (1.0 + z * lin.normal_relaxation_time);
}

std::vector<complex> pair_zeros_in(const AnalyticFunction& g, const PairSearchBox& box) {
  const Rectangle r{box.min_re, box.max_re, -box.max_im, box.max_im};
  return sorted_zeros_graded(g, r, graded_inner(box));
}

PairSearchBox pair_search_box(const PairSliding& p, const LinearisedInterfaceFriction& lin, double k) {
  double radius = 0.0;
  if (lin.strength_dv > 0.0) radius = std::abs(lin.strength_dstate * lin.state_rate_dv) / lin.strength_dv;
  double cd = 0.0;
  for (const ElasticBody* b : {&p.top, &p.bottom})
    if (!b->rigid) cd = std::max(cd, b->material.dilatational_wave_speed());
  const double wave = 2.0 * cd * std::abs(k);
  const double scale = std::max(radius, wave);
  const double min_re = 1e-9 * scale;
  return {min_re, std::max(lin.state_rate_dstate + 1.0137 * radius, 1.0137 * wave),
          1.0137 * scale};
}

std::vector<complex> pair_characteristic_roots(const PairSliding& p, const LinearisedInterfaceFriction& lin,
                                               double k, const PairSearchBox& box) {
  if (!(k > 0.0)) throw std::invalid_argument("pair_characteristic_roots: wavenumber must be > 0");
  if (!(box.min_re > 0.0) || !(box.max_re > box.min_re) || !(box.max_im > 0.0))
    throw std::invalid_argument("pair_characteristic_roots: need 0 < min_re < max_re and max_im > 0");
  if (is_mirror_pair(p))
    return characteristic_roots(mirror_problem(p), 2.0 * std::numbers::pi / k,
                                SearchBox{box.min_re, box.max_re, box.max_im});
  // Poles of F: K_ser's lie on Re = 0 (lossless strips, radiating half-spaces),
  // g_phi and -1/T on the negative real axis, none inside the box.  The box is
  // tiled so that the contours resolve both the rate-and-state cluster near the
  // origin and the wave scale (graded_inner).
  return pair_zeros_in([&](complex z) { return pair_characteristic_function(p, lin, k, z); }, box);
}

std::vector<complex> pair_unstable_roots(const PairSliding& p, double wavelength) {
  if (!(wavelength > 0.0) || std::isinf(wavelength))
    throw std::invalid_argument("pair stability: wavelength = " + std::to_string(wavelength) +
                                " m is not allowed; it must be > 0 and finite");
  const LinearisedInterfaceFriction lin = linearise_interface_friction(p);
  const double k = 2.0 * std::numbers::pi / wavelength;
  return pair_characteristic_roots(p, lin, k, pair_search_box(p, lin, k));
}

namespace {

// Whether F has a zero in the search box at this wavelength, by the argument
// principle alone.  Near Lc the unstable root approaches Re Lambda = 0, where
// a strip's poles sit: locating it there (subdividing the box) can fail while
// the count of the whole box does not (measured: H = 0.1 m on a mu/2 strip,
// L = 0.617 m).  Identical bodies too go through the series stiffness here (equal
// to their S to rounding, docs/inplane_bodies.md §3): the identical-pair search
// with pole removal fails in this box below ~0.02 m and above ~100 m
// (measured, H = 0.1 m), and a scan over top heights passes through them.
bool pair_has_unstable_root(const PairSliding& p, double wavelength) {
  const LinearisedInterfaceFriction lin = linearise_interface_friction(p);
  const double k = 2.0 * std::numbers::pi / wavelength;
  const PairSearchBox box = pair_search_box(p, lin, k);
  const AnalyticFunction g = [&](complex z) { return pair_characteristic_function(p, lin, k, z); };
  // One contour of the whole box, not the graded, converged count of
  // pair_characteristic_roots: that count finds roots next
  // to a thick strip's standing waves (poles on Re = 0) that move Lc (a 6 m
  // strip on a rigid base: 1.98049 m instead of the half-space's 1.98104 m);
  // whether those roots are physical is not yet verified.
  return count_zeros(g, Rectangle{box.min_re, box.max_re, -box.max_im, box.max_im}) > 0;
}

}  // namespace

double pair_critical_wavelength(const PairSliding& p, double shortest, double longest) {
  if (!(shortest > 0.0 && longest > shortest) || std::isinf(longest))
    throw std::invalid_argument("pair_critical_wavelength: need 0 < shortest < longest < inf");
  const auto unstable = [&](double wavelength) { return pair_has_unstable_root(p, wavelength); };
  constexpr int samples = 64;
  double stable_below = 0.0;
  for (int i = 0; i < samples; ++i) {
    const double w = shortest * std::pow(longest / shortest, static_cast<double>(i) / (samples - 1));
    if (!unstable(w)) {
      stable_below = w;
      continue;
    }
    if (i == 0) return shortest;
    double lo = stable_below, hi = w;
    while (hi - lo > 1e-6 * hi) {
      const double mid = 0.5 * (lo + hi);
      (unstable(mid) ? hi : lo) = mid;
    }
    return hi;
  }
  return std::numeric_limits<double>::quiet_NaN();
}

std::vector<double> pair_critical_wavelength_vs_top_height(const PairSliding& p, const std::vector<double>& heights,
                                                           double shortest, double longest) {
  std::vector<double> lc;
  lc.reserve(heights.size());
  for (double h : heights) {
    if (!(h > 0.0))
      throw std::invalid_argument("pair stability: top body height = " + std::to_string(h) +
                                  " m is not allowed; it must be > 0 (or inf)");
    PairSliding scan = p;
    scan.top.height = h;
    lc.push_back(pair_critical_wavelength(scan, shortest, longest));
  }
  return lc;
}

}  // namespace slipstrip

