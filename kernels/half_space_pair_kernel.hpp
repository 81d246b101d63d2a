#pragma once
// The interface response of two different in-plane half-spaces in contact,
// combined into one 2x2 operator on the jumps across the interface, and its
// history kernels as sums of exponentials (docs/inplane_bodies.md §7).
//
// Per Fourier mode k > 0, with K_t the top body's face stiffness and K_b' =
// D K_b D the bottom one's seen from the top (kernels/face_half_space.hpp),
// traction continuity gives (sigma_xy, sigma_yy) = -K_c [slip, opening],
//     K_c = (K_t^{-1} + K_b'^{-1})^{-1},
// slip = u_x,top - u_x,bottom, opening = u_y,top - u_y,bottom.  K_c has the
// form mu_ref k [[A_c, -i B_c], [i B_c, D_c]] (real A_c, B_c, D_c on the real
// p axis; the form is closed under sums and inverses: the inverse of (A, B, D)
// is (D, -B, A) / (A D - B^2)), with p = s / (c_ref k).  The reference body is
// the one with the slower shear wave (the top one on a tie): mu_ref and c_ref
// are its shear modulus and shear speed, so every branch height is >= 1.
//
// Time domain: K_c / s = (mu_ref / c_ref) [E_c + G_c(p)], E_c = diag(E_A, E_D)
// the series radiation impedances (E_A = E_x,t E_x,b / (E_x,t + E_x,b) with
// E_x = mu / c_s, E_D the same of E_y = rho c_d, in units mu_ref / c_ref), and
// the history transforms G_A = A_c/p - E_A, G_B = B_c/p, G_D = D_c/p - E_D,
// inverses g_e(tau), tau = c_ref k t.  g_e(inf) = A_c(0), B_c(0), D_c(0);
// g_A(0+) = g_D(0+) = 0 and g_B(0+) = E_A E_D sum_i s_i m_i beta_i / (e_x,i e_y,i)
// (s = +1 top, -1 bottom; m_i = mu_i / mu_ref; beta_i = (2 r_i - 1) / r_i, one
// body's coupling step; e_x,i, e_y,i its impedances in units mu_ref / c_ref).
//
// Singularities: the branch points +-i b of both bodies' roots (b = c_s / c_ref
// and c_d / c_ref of each body, up to four distinct heights), and the zeros of
// det(K_t + K_b') (the interface waves of the welded pair).  On the principal
// sheet such a zero lies only on the imaginary axis below every branch point:
// the Stoneley wave, which exists for some pairs only (shear speeds close,
// densities different) and is undamped; the sums refuse a pair that has one
// (the two-body operator carries it).  In the plane cut horizontally into
// Re p < 0 (the continuation the branch-cut construction integrates around) a
// zero is a leaky interface wave, damped: its residue is one more exponential.
#include <array>
#include <complex>
#include <functional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "kernels/elastic_material.hpp"
#include "kernels/half_space_kernel.hpp"

namespace slipstrip {

struct HalfSpacePairShape {
  // Per body (0 top, 1 bottom): mu / mu_ref, c_ref / c_s, r^2 = c_s^2 / c_d^2,
  // and the indices of its shear and P branch heights in branch_heights.
  std::array<double, 2> modulus{}, slowness{}, speed_ratio_squared{};
  std::array<std::size_t, 2> shear_branch{}, pressure_branch{};
  double reference_modulus = 0.0, reference_speed = 0.0;  // mu_ref [Pa], c_ref [m/s]
  std::vector<double> branch_heights;                     // distinct, increasing; the smallest is 1
};
// Both bodies in-plane (plane strain or stress), of allowed Poisson ratios.
HalfSpacePairShape half_space_pair_shape(const ElasticMaterial& top, const ElasticMaterial& bottom);

// A_c, B_c, D_c at p (units mu_ref k; any p of the cut plane, the roots
// continued from Re p > 0 with every cut horizontal into Re p < 0; on the
// imaginary axis the limit from Re p > 0).
std::array<std::complex<double>, 3> half_space_pair_entries(const HalfSpacePairShape& shape, std::complex<double> p);
// G_A, G_B, G_D at p.
std::array<std::complex<double>, 3> half_space_pair_history_transforms(const HalfSpacePairShape& shape,
                                                                       std::complex<double> p);
// det(K_t + K_b') / (mu_ref k)^2 at p (the interface waves are its zeros).
std::complex<double> half_space_pair_determinant(const HalfSpacePairShape& shape, std::complex<double> p);
std::array<double, 3> half_space_pair_static_values(const HalfSpacePairShape& shape);   // g_e(inf)
std::array<double, 3> half_space_pair_initial_values(const HalfSpacePairShape& shape);  // g_e(0+)
std::array<double, 2> half_space_pair_impedances(const HalfSpacePairShape& shape);      // E_A, E_D

// The Stoneley wave: a sign change of det(K_t + K_b') on p = i y, 0 < y < 1
// (every root real there, so the determinant is real; it is positive at
// y = 0), located by bisection to 1e-14.  Returns y (the wave's speed over
// c_ref), or 0 when the determinant keeps its sign on the segment (scanned on
// 4000 points and on 1 - 10^-m, m = 2..15, towards the branch point, where
// the determinant of identical bodies vanishes).
double half_space_pair_stoneley_speed(const HalfSpacePairShape& shape);

// The zeros of det(K_t + K_b') in the cut plane with Im p >= 0 (Re p < 0:
// leaky interface waves), found by the argument principle on the rectangles
// between consecutive cuts (and below the lowest, above the highest) over
// -extent <= Re p <= 1/2, |Im p| <= extent, extent = 16 max(b) + 16, then
// located by subdivision and Newton's method; with the residues of G_A, G_B,
// G_D there (a circle of 64 points, a quarter of the distance to the nearest
// cut, pole or the origin).  A Stoneley wave shows here too (Re p = 0).
struct HalfSpacePairPole {
  std::complex<double> p;
  std::array<std::complex<double>, 3> residue;
};
std::vector<HalfSpacePairPole> half_space_pair_poles(const HalfSpacePairShape& shape);

// Thrown when the pair has an undamped interface wave (a pole of K_c with
// Re p = 0: the Stoneley wave); `speed` [m/s] is its phase speed.
struct HalfSpacePairHasInterfaceWave : std::invalid_argument {
  HalfSpacePairHasInterfaceWave(const std::string& message, double wave_speed)
      : std::invalid_argument(message), speed(wave_speed) {}
  double speed;
};

// g_e(tau) ~= g_e(inf) + 2 Re sum amplitude e^{rate tau} for tau in
// [tau_min, tau_max], e = A, B, D (the same rates): the branch-cut sums of
// branch_cut_exponential_sums over the pair's cuts, a panel's nodes increased
// while its rule changes by more than 1e-8 (absolute, units mu_ref k; the sums
// then agree with a numerical inverse Laplace transform to ~2e-8,
// tests/cpp/test_kernels_half_space_pair.cpp), plus one exponential per leaky
// pole (rate p, amplitude its residue; half of
// it for a real p).  Throws HalfSpacePairHasInterfaceWave for a pair with a
// Stoneley wave.
std::array<ExponentialSum, 3> half_space_pair_exponential_sums(const HalfSpacePairShape& shape, double tau_min,
                                                               double tau_max, int nodes_per_panel = 10);

// The set-up's check that no pole was missed: the sums on [1/2, 16] against
// Durbin's inverse Laplace transform of G_e (2^15 terms, period 2 T = 48, the
// coupling's step g_B(0+)/p and each entry's c_e / (p^2 + 1), c_e = p^2 G_e at
// p = 10^4, inverted in closed form) at tau = 1/2, 1, 2, 4, 8, 16.  Returns the
// largest difference (units mu_ref k); a missed pole p_0 shows as its residue
// times e^{Re p_0 tau}.  verify_half_space_pair_sums throws HalfSpacePairCheckFailed
// when it exceeds 1e-6 (the sums are accurate to ~1e-9, Durbin's truncation
// here to ~1e-8).
double half_space_pair_sum_check(const HalfSpacePairShape& shape, const std::array<ExponentialSum, 3>& sums);
struct HalfSpacePairCheckFailed : std::runtime_error {
  using std::runtime_error::runtime_error;
};
void verify_half_space_pair_sums(const HalfSpacePairShape& shape);

// The zeros of an analytic f in the plane cut horizontally into Re p < 0 from
// p = +-i b for every b in branch_heights (positive, any order), by the search
// half_space_pair_poles runs (the argument principle on the rectangles
// between consecutive cuts, subdivision, Newton's method), with Im p >= 0.
std::vector<std::complex<double>> cut_plane_zeros(const std::function<std::complex<double>(std::complex<double>)>& f,
                                                  std::span<const double> branch_heights);

// --- The antiplane pair of two half-spaces of different shear speeds --------
// (kernels/half_space_kernel.hpp, HalfSpaceShape::antiplane_pair()).  K_c has a
// pole where K_t + K_b = 0, i.e. where w a_f + (1 - w) a_s = 0; on the
// principal sheet (Re a > 0) there is none, and in the cut plane neither:
// between the cuts (b < Im p < 1, Re p < 0) arg a_s - arg a_f lies in
// (pi/4, pi), below both cuts both roots have Re > 0, above both arg a in
// (pi/2, pi) for both (docs/bodies.md §3).
// w a_f + (1 - w) a_s at p (units |k|; the principal roots of the cut plane).
std::complex<double> antiplane_pair_denominator(const HalfSpaceShape& shape, std::complex<double> p);
// The set-up check: no zero of that denominator in the cut plane
// (cut_plane_zeros), and the exponential sum on [1/2, 16] within 1e-6 (units
// mu_u |k|) of Durbin's inverse Laplace transform of G (2^15 terms, period
// 2 T = 48, c2 / (p^2 + 1) inverted in closed form) at tau = 1/2, 1, 2, 4, 8,
// 16 (the sums agree to ~1e-9).  Returns that largest difference; throws
// HalfSpacePairCheckFailed naming what failed.
double verify_antiplane_half_space_pair(const HalfSpaceShape& shape);

}  // namespace slipstrip
