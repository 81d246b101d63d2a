#pragma once
// Linear stability of steady sliding on a 2D interface (x and z) between two
// identical bodies, and below between two different ones, for an oblique
// perturbation ~ exp(i (kx x + kz z) + Lambda t) (docs/3d.md §2).
//
// Steady sliding at v0 along x.  A perturbation of the slip rate (u_x, u_z)
// changes the friction traction, collinear with the slip rate, as
//   |v| = v0 + u_x + O(u^2),  v/|v| = x + (u_z / v0) z + O(u^2):
//   tau_x^ = tau_v u_x^ + tau_phi phi^  (the 2D linearisation; the state sees |v|),
//   tau_z^ = (tau_0 / v0) u_z^          (the friction force turning with the slip).
// Elasticity at |k| with k-hat = (c, s): in-plane S_P along k-hat, antiplane
// S_SH across it (kernels/interface_2d_history.hpp):
//   [tau_x; tau_z] = -[c^2 S_P + s^2 S_SH, c s (S_P - S_SH); c s (S_P - S_SH), s^2 S_P + c^2 S_SH] [delta_x; delta_z].
// With u = Lambda delta the characteristic function is the 2x2 determinant
//   D(Lambda) = (c^2 F_P + s^2 F_SH)(s^2 S_P + c^2 S_SH + Lambda tau_0/v0) - c^2 s^2 (S_P - S_SH)^2,
// F_P, F_SH the 2D characteristic functions (stability/linear_stability.hpp) of
// the in-plane (plane strain) and antiplane problems at |k|.  So a perturbation
// of slip along x is coupled to slip along z through the difference of the
// in-plane and antiplane responses, weighted c s; for kz = 0 (s = 0) D is F_P
// times a factor without unstable roots, and the 2D theory is recovered.
//
// Unstable roots obey the 2D bound: with a positive-real elastic matrix and
// tau_0/v0 > 0, a root with Re Lambda > 0 needs Re[tau_v + tau_phi g_v/(Lambda - g_phi)] <= 0,
// so unstable_search_box() contains them all.
#include <complex>
#include <optional>
#include <vector>

#include "stability/interface_stability.hpp"
#include "stability/linear_stability.hpp"

namespace slipstrip {

// The elastic matrix above for responses P (in-plane, along k-hat) and A
// (antiplane, across it), k-hat = (c, s): xx = c^2 P + s^2 A, xz = zx =
// c s (P - A), zz = s^2 P + c^2 A.
struct RotatedResponse {
  complex xx, xz, zz;
};
RotatedResponse rotated_response(double c, double s, complex along, complex across);

// D(Lambda) for the wavevector (kx, kz) [1/m]; sliding.material's plane is
// replaced by strain (in-plane part) and antiplane (antiplane part).
complex oblique_characteristic_function(const SteadySliding& sliding, double kx, double kz, complex growth);

// The zeros of D in the box, by decreasing Re Lambda.
std::vector<complex> oblique_characteristic_roots(const SteadySliding& sliding, double kx, double kz,
                                                  const SearchBox& box);

// ---- Two different bodies (docs/3d.md §2, "Dissimilar bodies") ----
//
// Per mode the 1D pair problems at |k|: the in-plane pair along k-hat, whose
// slip delta_k = c delta_x + s delta_z changes the compressive normal stress,
//   tau_k^ = -K_s delta_k^,  sigma^ = K_n delta_k^   ((K_s, K_n) = interface_slip_response at |k|),
// and the antiplane pair across k-hat, tau_perp^ = -A delta_perp^ (A = slip_response of
// the antiplane pair, antiplane_pair_sliding).  The friction |tau| = sigma_eff f(|v|, phi)
// collinear with v, linearised at v = (v0, 0), sigma_eff = sigma0:
//   tau_x^ = Lambda Phi delta_x^ + N(Lambda) sigma^      (|tau| to first order),
//   tau_z^ = (tau_0 / v0) u_z^                          (the normal stress enters at second order),
// Lambda Phi = rate_and_state_response, N sigma^ = normal_stress_response
// (stability/interface_stability.hpp: sigma_eff's memory and Linker-Dieterich).  So
//   D(Lambda) = (xx + Lambda Phi + c N K_n)(zz + Lambda tau_0/v0) - (xz + s N K_n) xz,
// with (xx, xz, zz) = rotated_response(c, s, K_s, A).  kz = 0: D = F_pair (A + Lambda tau_0/v0),
// F_pair the 1D pair's function (pair_characteristic_function); kx = 0: the matrix
// is triangular, D = (A + Lambda Phi)(K_s + Lambda tau_0/v0): the 1D antiplane pair's
// F times a factor without unstable roots (slip across x feeds the normal stress,
// which does not feed back).  Identical bodies: K_n = 0, and D is the identical
// bodies' function above to rounding.

// The antiplane pair of `pair`'s two bodies (their materials with plane =
// antiplane; the outer faces do not enter the antiplane problem).
SteadySliding antiplane_pair_sliding(const PairSliding& pair);

// D(Lambda) for the wavevector (kx, kz) [1/m].
complex oblique_pair_characteristic_function(const PairSliding& pair, const LinearisedInterfaceFriction& friction,
                                             double kx, double kz, complex growth);

// The zeros of D in the box (pair_zeros_in: the graded search of the 1D pair),
// by decreasing Re Lambda.  For a dissimilar pair the roots at (kx, kz) are not
// conjugate to each other: those at (-kx, -kz) are their conjugates.
std::vector<complex> oblique_pair_characteristic_roots(const PairSliding& pair,
                                                       const LinearisedInterfaceFriction& friction, double kx,
                                                       double kz, const PairSearchBox& box);

// The roots in pair_search_box at |k| (the 1D pair's search region: not a
// proof that no unstable root lies outside it), with Re Lambda > 0 first.
std::vector<complex> oblique_pair_roots(const PairSliding& pair, double kx, double kz);

}  // namespace slipstrip
