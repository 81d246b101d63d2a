#pragma once
// Linear stability of steady sliding on a 2D interface (x and z) between two
// identical bodies, for an oblique perturbation ~ exp(i (kx x + kz z) + Lambda t)
// (docs/3d.md, "Linear stability").
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

#include "stability/linear_stability.hpp"

namespace slipstrip {

// D(Lambda) for the wavevector (kx, kz) [1/m]; sliding.material's plane is
// replaced by strain (in-plane part) and antiplane (antiplane part).
complex oblique_characteristic_function(const SteadySliding& sliding, double kx, double kz, complex growth);

// The zeros of D in the box, by decreasing Re Lambda.
std::vector<complex> oblique_characteristic_roots(const SteadySliding& sliding, double kx, double kz,
                                                  const SearchBox& box);

}  // namespace slipstrip
