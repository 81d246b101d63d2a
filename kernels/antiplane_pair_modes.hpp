#pragma once
// One scalar history operator for a bonded pair of two DIFFERENT finite
// antiplane (SH) strips (docs/bodies.md, "the combined operator of two
// different strips").  Body i (top t, bottom b) of height H_i has the face
// stiffness K_i = mu_i alpha_i coth(alpha_i H_i), alpha_i = sqrt(k^2 + s^2/c_i^2)
// (kernels/antiplane_response.hpp); the slip is shared between the faces so
// that the traction is continuous, hence
//     tau^ = -K_c slip^,   K_c = K_t K_b / (K_t + K_b)   (= S = K/2 for identical bodies).
// Its poles (history modes) are the bonded bilayer's SH modes with u_z
// prescribed on both outer faces: on s = i omega the zeros of
//     D(omega) = K_t + K_b = mu_t gamma_t cot(gamma_t H_t) + mu_b gamma_b cot(gamma_b H_b),
// gamma_i = sqrt(omega^2/c_i^2 - k^2), plus the common poles of K_t and K_b
// (equal echo frequencies, e.g. identical bodies).  D decreases between its
// poles, so there is exactly one root between consecutive poles: found by a
// bracketed Newton iteration.
//
// The discrete operator is the identical strip's (docs/theory.md 6.2) with the
// bilayer's constants: per Fourier mode q >= 1
//     history_q = c0 R_n - dt sum_j O_j v_{n-j},   O_j = sum_m w_m cos(phi_m j),
// over the bilayer modes below Nyquist, c0 = 2 eta_c + dt sum_m w_m, because
// the k = 0 kernel K_c(0, s)/s is a rational function of z^{-1} when both
// echoes 2H_i/c_i are whole numbers of steps and its comb of poles adds to the
// constant kernel 2 eta_c (the comb identity of two different strips).  The
// uniform mode q = 0 is that rational function itself (UniformModeEchoes), so
// StripHistory and BlockStripHistory carry the pair unchanged, from
// StripKernels and StripPairConstants.
#include <vector>

#include "kernels/elastic_material.hpp"
#include "kernels/history_convolution.hpp"
#include "kernels/strip_response.hpp"

namespace slipstrip {

// One finite antiplane body: its material and height [m].
struct AntiplaneStrip {
  ElasticMaterial material;
  double height = 0.0;
};

// K_i(k, s) = mu alpha coth(alpha H) of one body (twice antiplane_strip_response).
complex antiplane_body_stiffness(const AntiplaneStrip& body, double wavenumber, complex s);

// K_c(k, s) = K_t K_b / (K_t + K_b), Re s >= 0.
complex antiplane_pair_response(const AntiplaneStrip& top, const AntiplaneStrip& bottom, double wavenumber,
                                complex s);

// K_c(k, 0): the static stiffness (mu_i k coth(k H_i), mu_i / H_i at k = 0, combined).
double antiplane_pair_static_stiffness(const AntiplaneStrip& top, const AntiplaneStrip& bottom,
                                       double wavenumber);

// D(omega) = K_t(k, i omega) + K_b(k, i omega) (real; +-inf at the bodies' poles)
// and dD/d(s^2) (> 0 between the poles): for the tests' residue checks.
double antiplane_pair_dispersion(const AntiplaneStrip& top, const AntiplaneStrip& bottom, double wavenumber,
                                 double omega);

// The poles of D below max_frequency (the bodies' echo modes
// c_i sqrt(k^2 + (m pi/H_i)^2), merged where they coincide to 1e-10 relative).
std::vector<double> antiplane_pair_dispersion_poles(const AntiplaneStrip& top, const AntiplaneStrip& bottom,
                                                    double wavenumber, double max_frequency);

// The modes of K_c up to max_frequency, in increasing frequency:
//   K_c = ... + A_n / (s^2 + omega_n^2),  weight = A_n / omega_n^2 < 0 (passive),
// A_n = K_t K_b / (dD/d(s^2)) at a root of D, A = R_t R_b / (R_t + R_b) at a
// common pole (R_i the bodies' residues).  Roots where K_t = K_b = 0 (no pole
// of K_c: identical or proportional bodies) are left out.  All family shear;
// index counts the roots and common poles of D from 1.  Any k >= 0: at k = 0
// they are the poles of the comb K_c(0, s)/s.
std::vector<StripMode> antiplane_pair_modes(const AntiplaneStrip& top, const AntiplaneStrip& bottom,
                                            double wavenumber, double max_frequency);

// The constants of the combined operator at this time step (both echoes
// 2H_i/c_i must be whole numbers of steps: two_body_time_step).
StripPairConstants antiplane_pair_constants(const AntiplaneStrip& top, const AntiplaneStrip& bottom,
                                            double time_step);

// The discrete modes of wavenumber k > 0 (as discrete_modes for one strip):
// the bilayer modes below Nyquist, and the static stiffness of those above
// placed passively (place_truncated_stiffness).  Empty for k = 0.
std::vector<DiscreteMode> antiplane_pair_discrete_modes(const AntiplaneStrip& top, const AntiplaneStrip& bottom,
                                                        double wavenumber, double time_step);

// The kernels of all Fourier modes q = 0..nodes/2 (k_q = 2 pi q / length);
// echo_steps is M_t + M_b (the uniform mode's recursion length; M for equal echoes).
StripKernels compute_antiplane_pair_kernels(const AntiplaneStrip& top, const AntiplaneStrip& bottom,
                                            double length, int nodes, double time_step,
                                            const CancelCheck& cancelled = {});

}  // namespace slipstrip
