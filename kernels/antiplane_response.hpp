#pragma once
// Antiplane (mode III, SH) response of elastic bodies bonded by a frictional
// interface: slip along z, displacement u_z(x, y, t) only, so every body obeys
// the scalar wave equation  u_tt = c_s^2 (u_xx + u_yy)  and the interface
// traction is sigma_yz.  Derivation and symbols: docs/bodies.md.
//
// One body of height H (0 < y < H) whose outer face y = H has u_z prescribed
// (driven or clamped: for SH both prescribe u_z), with face displacement
// u^(k, s) at y = 0, carries the face traction
//     sigma_yz^(k, s) = - K(k, s; H) u^(k, s),   K = mu alpha_s coth(alpha_s H),
// alpha_s = sqrt(k^2 + s^2/c_s^2) (principal root); a half-space (H = inf) has
// K = mu alpha_s.  Two identical bodies carry half the slip each, so their
// pair response (the same convention as strip_response) is
//     S(k, s; H) = K / 2 = (mu / 2) alpha_s coth(alpha_s H).
// The functions below give S, the pair response, so that the in-plane
// machinery (StripKernels, StripHistory, BlockStripHistory, HalfSpaceHistory)
// applies unchanged; a single body is twice the pair.
#include <complex>
#include <vector>

#include "kernels/elastic_material.hpp"
#include "kernels/strip_response.hpp"

namespace slipstrip {

// S(k, s; H) = (mu/2) alpha_s coth(alpha_s H); (mu/2) alpha_s for H = inf.
// Valid for Re s >= 0 (on the imaginary axis: the limit from Re s > 0).
complex antiplane_strip_response(const ElasticMaterial& material, double strip_height,
                                 double wavenumber, complex s);

// S(k, 0; H) = (mu/2) k coth(kH) (k > 0), mu/(2H) (k = 0), mu |k| / 2 (H = inf).
double antiplane_static_stiffness(const ElasticMaterial& material, double strip_height,
                                  double wavenumber);

// Exact partial-fraction expansion (docs/bodies.md):
//   S = (mu s / 2 c_s) coth(s H / c_s)
//       + sum_{m>=1} (mu/H) c_s^2 kappa^2 [1/(s^2 + (c_s kappa)^2) - 1/(s^2 + omega_m^2)],
// kappa = m pi / H, omega_m = c_s sqrt(k^2 + kappa^2): one shear family
// (weight -(mu/H) kappa^2/(k^2 + kappa^2) < 0, physical) and the comb modes
// (weight +mu/H, cancelling the poles of the shear-echo comb).  As
// strip_modes: every mode up to max_frequency, a comb mode only with its
// shear partner; empty for k = 0 (S is the comb alone).
std::vector<StripMode> antiplane_strip_modes(const ElasticMaterial& material, double strip_height,
                                             double wavenumber, double max_frequency);

// beta limit of a passive discrete antiplane strip operator:
// dt S(k_N, 0)/2 <= eta  <=>  beta <= 2 / pi (for k_N H >> 1; docs/bodies.md).
double antiplane_strip_passivity_beta_limit();

}  // namespace slipstrip
