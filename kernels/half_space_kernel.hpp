#pragma once
// The half-space (H -> infinity) relaxation kernel in dimensionless form, and
// its representation as a sum of decaying exponentials (docs/theory.md,
// "bounded-memory half-space").
//
// For Fourier mode k the history part of the traction is
//     tau^_k(t) = - eta v^_k(t) - int_0^t g_k(t') v^_k(t - t') dt',   eta = mu / (2 c_s),
// and for a half-space  g_k(t) = mu |k| g(c_s |k| t)  with one universal
// function g(tau) of tau = c_s |k| t that depends on the material only through
// r^2 = c_s^2 / c_d^2.  Its Laplace transform in p = s / (c_s |k|) is
//     G(p) = 2 (1 - r^2) / (p (a_s + a_d)) + p / (2 a_s) - 1/2,
//     a_s = sqrt(1 + p^2),  a_d = sqrt(1 + r^2 p^2),
// i.e. G = S_inf / (s mu / c_s) - 1/2 with S_inf the half-space response.
// g(0) = 0, g'(0) = 7/4 - 2 r and g(inf) = 1 - r^2 (the static stiffness
// mu |k| (1 - r^2)).  The approach to g(inf) is an oscillating tau^(-1/2) tail
// (branch points of a_s, a_d at p = +-i, +-i/r), so no finite recursion
// reproduces g exactly; a sum of exponentials does, to a chosen accuracy, on
// any interval [tau_min, tau_max].
#include <complex>
#include <functional>
#include <span>
#include <vector>

#include "kernels/elastic_material.hpp"

namespace slipstrip {

// Which universal relaxation function: the in-plane one above (material
// through r^2 = c_s^2/c_d^2) or the antiplane (SH) one of two identical
// half-spaces (docs/bodies.md),
//     G(p) = (sqrt(1 + p^2) / p - 1) / 2,   g(tau) = (int_0^tau J0 - J1(tau)) / 2,
// with the shear branch points p = +-i only, g(inf) = 1/2 (static stiffness
// mu |k| / 2), g'(0) = 1/4.
//
// The antiplane pair of two half-spaces of DIFFERENT shear speeds has its own
// function (docs/bodies.md §3): with the faster body as reference (c_ref its
// shear speed, p = s / (c_ref |k|)), b = c_slow / c_ref < 1 and
// w = mu_fast / (mu_t + mu_b), the combined stiffness
// K_c = K_t K_b / (K_t + K_b), K_i = mu_i alpha_i, in units of mu_u |k| with
// mu_u = 2 mu_t mu_b / (mu_t + mu_b) (mu for identical bodies), is
//     K_c / (mu_u |k|) = (1/2) a_f a_s / (w a_f + (1 - w) a_s),
//     a_f = sqrt(1 + p^2),  a_s = sqrt(1 + p^2 / b^2),
// and G(p) = K_c / (s mu_u / c_ref) - E, E = 1 / (2 (w b + 1 - w)) the series
// radiation impedance eta_c = eta_t eta_b / (eta_t + eta_b) in units
// mu_u / c_ref.  Two branch points, p = +-i (the faster body) and +-i b;
// g(inf) = 1/2 (static stiffness mu_u |k| / 2).  Equal shear speeds make it
// the identical pair's function above (b = 1), so such a pair is the plain
// antiplane shape (slow_speed = 0) in units of mu_u.
struct HalfSpaceShape {
  double speed_ratio_squared = 0.0;  // r^2 (in-plane only)
  bool antiplane = false;
  double slow_speed = 0.0;   // b (antiplane pair of different speeds), else 0
  double fast_weight = 0.5;  // w (antiplane pair of different speeds)
  bool antiplane_pair() const { return antiplane && slow_speed > 0.0; }
};
HalfSpaceShape half_space_shape(const ElasticMaterial& material);

// Two antiplane half-spaces as one scalar operator: the shape of K_c above
// and its units.  Throws std::invalid_argument unless both bodies are
// antiplane with positive moduli and densities.
struct AntiplaneHalfSpacePair {
  HalfSpaceShape shape;
  double modulus = 0.0;            // mu_u = 2 mu_t mu_b / (mu_t + mu_b) [Pa]
  double reference_speed = 0.0;    // c_ref = max(c_t, c_b) [m/s]
  double radiation_damping = 0.0;  // eta_c [Pa s/m]
};
AntiplaneHalfSpacePair antiplane_half_space_pair(const ElasticMaterial& top, const ElasticMaterial& bottom);

// E: the instantaneous part of K / s in the shape's units (1/2 but for an
// antiplane pair of different speeds).
double half_space_instantaneous_value(const HalfSpaceShape& shape);
// The height b of the second branch point p = +-i b, at which the slow
// exponentials' second branch rotates (kernels/half_space_history.hpp):
// c_d / c_s in-plane (and for the identical antiplane pair, whose sums have no
// such exponential), c_slow / c_ref for an antiplane pair of different
// speeds.  The first (reference) branch point is p = +-i.
double half_space_second_branch(const HalfSpaceShape& shape);

// G(p) above, for Re p >= 0 (on the imaginary axis: the limit from Re p > 0).
std::complex<double> half_space_relaxation_transform(double speed_ratio_squared,
                                                     std::complex<double> p);
std::complex<double> half_space_relaxation_transform(const HalfSpaceShape& shape,
                                                     std::complex<double> p);
// g(inf): the residue of G at p = 0 (1 - r^2 in-plane, 1/2 antiplane).
double half_space_static_value(const HalfSpaceShape& shape);
// G(p) = c2/p^2 + c4/p^4 + O(p^-6) for large p: c2 = g'(0), c4.
double half_space_initial_slope(const HalfSpaceShape& shape);
double half_space_fourth_coefficient(const HalfSpaceShape& shape);

// g(tau) ~= static_value + 2 Re sum_j amplitude_j exp(rate_j tau)  for
// tau in [tau_min, tau_max].  Obtained by deforming the Bromwich contour onto
// branch cuts that leave p = i and p = i/r horizontally into Re p < 0 and
// integrating the jump across each cut with Gauss-Legendre panels in u =
// sqrt(distance from the branch point) (which removes the inverse square-root
// singularity).  Every rate has Re < 0.
struct ExponentialSum {
  double static_value = 0.0;  // 1 - r^2 (the residue of G at p = 0)
  std::vector<std::complex<double>> rate;
  std::vector<std::complex<double>> amplitude;
};

// nodes_per_panel = 10 gives |error| < ~1e-11 for tau in [tau_min, tau_max]
// (tests/cpp/test_kernels_half_space_kernel.cpp measures it).
ExponentialSum half_space_exponential_sum(double speed_ratio_squared, double tau_min,
                                          double tau_max, int nodes_per_panel = 10);
// The same for any shape (antiplane: the shear branch only; an antiplane pair
// of different speeds: the cuts from p = i, then from p = i b, by
// branch_cut_exponential_sums below with nodes_per_panel nodes to start and a
// panel tolerance of 1e-12 (units mu_u |k|), which leaves the sums ~1e-11
// from a numerical inverse Laplace transform, as the other shapes'
// (tests/cpp/test_kernels_antiplane_half_space_pair.cpp)).
ExponentialSum half_space_exponential_sum(const HalfSpaceShape& shape, double tau_min,
                                          double tau_max, int nodes_per_panel = 10);

// The same construction for any transform G(p) of the in-plane half-space
// whose only singularities are a simple pole at p = 0 (residue
// static_value = g(inf)) and the branch points of a_s = sqrt(1 + p^2) and
// a_d = sqrt(1 + r^2 p^2), real on the real axis and vanishing as |p| -> inf:
// `transform(p, a_s, a_d)` is G written through its roots, which the cut
// integration continues across each cut (kernels/face_half_space.hpp).
using InPlaneTransform =
    std::function<std::complex<double>(std::complex<double>, std::complex<double>, std::complex<double>)>;
ExponentialSum in_plane_exponential_sum(double speed_ratio_squared, double static_value,
                                        const InPlaneTransform& transform, double tau_min, double tau_max,
                                        int nodes_per_panel = 10);

double evaluate(const ExponentialSum& sum, double tau);

// The same construction for several transforms G_e(p) (e = 0..entries-1) that
// share any set of branch points p = +-i b_k (b_k > 0, distinct) and are real
// on the real axis: each singular only through the factors sqrt(zeta - i b_k)
// (and the regular sqrt(zeta + i b_k)), with a simple pole at p = 0 of residue
// static_values[e] = g_e(inf), no other singularity in the plane cut
// horizontally from each i b_k into Re p < 0 (and its mirror image), and
// bounded as |p| -> inf there.  `on_cut(zeta, factor, out)` writes G_e(zeta)
// into out[e] given factor[k] = sqrt(zeta - i b_k) continued as
// roots_on_cut does for one body: on the cut leaving i b_j, factor[j] =
// +i sqrt(x) on the upper side and -i sqrt(x) on the lower, every other factor
// principal (only the root that branches at b_j jumps there).  The panels in
// u = sqrt(x) are those of in_plane_exponential_sum; a panel's rule of n nodes
// is kept when the rule of n + 4 nodes agrees with it to `tolerance` in every
// entry's contribution e^{-x tau} at tau = tau_min 2^m <= tau_max and at
// tau_max, else the panel takes 4 more nodes (up to 32; then it is split in
// halves, up to 12 times): a transform of several bodies has singular points
// near its cuts on the other sheets (the continuation of one side of a cut),
// which nodes_per_panel nodes do not resolve.  Every sum gets the same rates.
using CutTransform = std::function<void(std::complex<double> zeta, std::span<const std::complex<double>> factor,
                                        std::span<std::complex<double>> out)>;
std::vector<ExponentialSum> branch_cut_exponential_sums(std::span<const double> branch_heights,
                                                        std::span<const double> static_values,
                                                        const CutTransform& on_cut, double tau_min, double tau_max,
                                                        int nodes_per_panel, double tolerance);

// g'(0) = 7/4 - 2 r: the initial slope that makes the high-frequency tail of
// G(i w) ~ -g'(0) / w^2 (the source of aliasing when g is sampled).
double half_space_initial_slope(double speed_ratio_squared);

}  // namespace slipstrip
