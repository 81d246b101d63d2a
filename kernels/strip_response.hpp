#pragma once
// Elastodynamic response of two identical strips of height H bonded by a
// frictional interface, for the antisymmetric (mode-II) perturbation about
// steady sliding.  See docs/theory.md for the derivation and the symbols.
// For an antiplane material (PlaneCondition::antiplane) strip_response,
// strip_static_stiffness and strip_modes give the antiplane (mode-III) pair
// instead (kernels/antiplane_response.hpp, docs/bodies.md), so every operator
// built from them serves both.
//
// Convention: the Fourier-Laplace shear-traction perturbation on the interface is
//     tau^(k, s) = - S(k, s; H) * slip^(k, s),
// with k the wavenumber [1/m] and s the Laplace variable [1/s].  S has units Pa/m.
#include <complex>
#include <vector>

#include "kernels/elastic_material.hpp"

namespace slipstrip {

using complex = std::complex<double>;

// Closed form  S = A_d(s) alpha_d coth(alpha_d H) + A_s(s) coth(alpha_s H)/alpha_s
// (strip) or the same with coth -> 1 (half-space, strip_height = +inf).
// Valid for Re s >= 0 (including the imaginary axis away from poles).
complex strip_response(const ElasticMaterial& material, double strip_height, double wavenumber,
                       complex s);

// Half-space (H -> infinity) response S_inf(k, s).
complex half_space_response(const ElasticMaterial& material, double wavenumber, complex s);

// Static limit S(k, 0; H) = mu k (1 - c_s^2/c_d^2) (coth kH - kH / sinh^2 kH)  for k > 0,
// and mu / (2H) for k = 0 (uniform slip of the strip pair).
double strip_static_stiffness(const ElasticMaterial& material, double strip_height,
                              double wavenumber);

// One undamped normal-mode term rho / (s^2 + omega^2) of S(k, s; H).
// In the time domain it contributes  -weight * int_0^t (1 - cos(omega (t - t'))) v(t') dt'
// to the traction, with weight = rho / omega^2 [Pa/m].
// The three families of poles (docs/theory.md): the m = 0 and m >= 1 shear
// modes and the P (dilatational) modes are physical resonances of the strip
// with prescribed slip (weight < 0: passive); the comb modes (weight > 0)
// cancel the poles of the shear-echo comb, which the solver carries exactly.
enum class ModeFamily { shear, comb, dilatational };

struct StripMode {
  double frequency;  // omega [rad/s]
  double weight;     // rho / omega^2 [Pa/m]
  ModeFamily family;
  int index;         // m: kappa = m pi / H
};

// Exact partial-fraction (Mittag-Leffler) expansion of the finite-height response:
//   S(k, s; H) = S_shear_comb(s; H) + sum_modes rho_m / (s^2 + omega_m^2)
// where S_shear_comb(s; H) = (mu s / 2 c_s) coth(s H / c_s) is the k-independent
// part (instantaneous radiation damping + shear echoes every 2H/c_s) that the
// solver carries with an exact delay line.  Returns every mode with
// omega_m <= max_frequency, in order of the family index m.
std::vector<StripMode> strip_modes(const ElasticMaterial& material, double strip_height,
                                   double wavenumber, double max_frequency);

// The shear-echo comb part  (mu s / 2 c_s) coth(s H / c_s).
complex shear_comb_response(const ElasticMaterial& material, double strip_height, complex s);

}  // namespace slipstrip
