#pragma once
// Linear stability of homogeneous steady sliding of the two-strip system.
//
// Perturbations ~ exp(i k x + Lambda t) about steady sliding at v0, phi0 = phi_ss(v0).
// Elastodynamics (radiation damping included in S):  tau^ = -S(k, Lambda; H) slip^,
// slip_rate^ = Lambda slip^.  Friction, linearised at (v0, phi0):
//   tau^ = tau_v v^ + tau_phi phi^,     Lambda phi^ = g_v v^ + g_phi phi^,
// so the characteristic function is
//   F(Lambda) = S(k, Lambda; H) + Lambda [ tau_v + tau_phi g_v / (Lambda - g_phi) ].
// Roots are located with the argument principle on rectangles (recursive
// subdivision) and polished with Newton (stability/root_search.hpp).  See docs/stability.md for the bounds
// that make the unstable search region provably complete.
#include <complex>
#include <optional>
#include <vector>

#include "friction/friction_law.hpp"
#include "kernels/elastic_material.hpp"
#include "kernels/strip_response.hpp"

namespace slipstrip {

struct SteadySliding {
  ElasticMaterial material;
  double strip_height = 0.1;       // H [m] of each strip; +inf = half-space
  FrictionParameters friction;
  double normal_stress = 1e6;      // sigma0 [Pa]
  double driving_velocity = 2e-3;  // v0 [m/s]
  // A different bottom body (docs/bodies.md; antiplane): S is then the
  // series combination (1/K_t + 1/K_b)^-1 of the two face stiffnesses
  // K_b = 2 strip_response(body b) (a rigid bottom: K_b = inf, S = K_t).
  // two_bodies = false: the bottom body is the mirror image of the top one.
  bool two_bodies = false;
  bool bottom_rigid = false;
  ElasticMaterial bottom_material;
  double bottom_height = 0.1;
};

// Partial derivatives of the friction law at steady sliding (v0, phi_ss(v0)),
// regularisations included exactly (taken from friction_law.hpp).
struct LinearisedFriction {
  double state;              // phi0 = phi_ss(v0) [s]
  double strength_dv;        // tau_v   [Pa s/m]
  double strength_dstate;    // tau_phi [Pa/s]
  double state_rate_dv;      // g_v     [s/m]
  double state_rate_dstate;  // g_phi   [1/s]
};
LinearisedFriction linearise_friction(const SteadySliding& sliding);

// S(k, Lambda) of the sliding pair, tau^ = -S slip^ [Pa/m]: the strip's own
// response for identical bodies, else the series combination above.
complex slip_response(const SteadySliding& sliding, double wavenumber, complex growth);

// F(Lambda) for wavenumber k [1/m].
complex characteristic_function(const SteadySliding& sliding, double wavenumber, complex growth);

// Rectangle min_re <= Re Lambda <= max_re, |Im Lambda| <= max_im  [1/s].
struct SearchBox {
  double min_re;
  double max_re;
  double max_im;
};

// Box that provably contains every root with Re Lambda >= min_re > 0:
// passivity (Re[S/Lambda] >= 0 for Re Lambda > 0) forces |Lambda - g_phi| <= |tau_phi g_v| / tau_v.
// min_re defaults to 1e-9 of that rate scale (roots closer to neutral are not "unstable").
SearchBox unstable_search_box(const SteadySliding& sliding);

// Box reaching into the damped half plane (finite H only: S is meromorphic there),
// used to report the least-damped mode of a stable wavelength.  Not a proof that no
// root exists with Re Lambda < min_re outside |Im| <= max_im.
SearchBox damped_search_box(const SteadySliding& sliding);

// Number of zeros of F inside the box (argument principle; the poles of F are
// removed analytically, so this counts zeros only).  Throws std::runtime_error if
// the winding number is not resolved to an integer.
int count_roots(const SteadySliding& sliding, double wavelength, const SearchBox& box);

// All roots in the box, sorted by decreasing Re Lambda; the two roots of a
// conjugate pair adjacent, +i first (sort_fastest_first, stability/root_search.hpp).
std::vector<complex> characteristic_roots(const SteadySliding& sliding, double wavelength,
                                          const SearchBox& box);
// All roots with Re Lambda > unstable_search_box().min_re (complete set).
std::vector<complex> characteristic_roots(const SteadySliding& sliding, double wavelength);

// Root with max Re Lambda among the unstable ones; nullopt if the wavelength is stable.
std::optional<complex> most_unstable_root(const SteadySliding& sliding, double wavelength);

// Critical wavelength Lc: bisection on "an unstable root exists" between a stable
// lower wavelength and an unstable upper one (throws std::invalid_argument otherwise).
// Relative accuracy ~ relative_tolerance (plus min_re / |d Re Lambda / dL|).
double critical_wavelength(const SteadySliding& sliding, double lower, double upper,
                           double relative_tolerance = 1e-10);

// Lc(H) for each H (may be +inf): the bracket is found automatically by geometric
// expansion around the quasi-static half-space value.  Throws std::invalid_argument
// naming H when no wavelength up to 2^60 times that value is unstable (a thin
// antiplane strip: it does not bend).
std::vector<double> critical_wavelength_vs_height(const SteadySliding& sliding,
                                                  const std::vector<double>& heights);

// Quasi-static Lc (inertia dropped, S -> S(k, 0; H) real): the neutral condition of
// the quadratic tau_v L^2 + (S0 - tau_v g_phi + tau_phi g_v) L - S0 g_phi = 0 is
//   S(k, 0; H) = tau_v g_phi - tau_phi g_v.
// Half-space (closed form): Lc = 2 pi mu (1 - c_s^2/c_d^2) / (tau_v g_phi - tau_phi g_v).
// Finite H, or an antiplane pair of different bodies (S0 = the series static
// stiffness, a rigid base included): solved by bisection in k with
// strip_static_stiffness().  Returns +inf when tau_v g_phi - tau_phi g_v <= 0 (steady
// sliding stable at all k).  An antiplane strip is stiffer than its long-wave limit
// mu/(2H) at every k: when that limit (of the pair) is not below tau_v g_phi - tau_phi g_v
// there is no neutral wavelength and it throws std::invalid_argument naming H.
// In-plane pairs of different bodies throw (stability/interface_stability.hpp).
double quasi_static_critical_wavelength(const SteadySliding& sliding);

struct GrowthRate {
  double wavelength;   // [m]
  double growth_rate;  // Re Lambda of the least stable root [1/s] (NaN if none found)
  double frequency;    // |Im Lambda| of that root [rad/s]
  bool unstable;       // growth_rate > unstable_search_box().min_re
};
// For each wavelength: the most unstable root; if stable and H finite, the
// least-damped root in damped_search_box(); if stable and half-space, NaN.
std::vector<GrowthRate> growth_rates(const SteadySliding& sliding,
                                     const std::vector<double>& wavelengths);

}  // namespace slipstrip
