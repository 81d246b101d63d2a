#pragma once
// Passivity of a discrete history operator (docs/theory.md, "passivity" and
// "bounded-memory half-space").
//
// A discrete operator  tau_n = -eta v_n - sum_{j>=1} K_j v_{n-j}  per Fourier
// mode is passive (it can only absorb energy, so free ringing cannot grow) iff
// its symbol Z_d(theta) = eta + sum_j K_j e^{-i j theta} has Re Z_d >= 0 on
// the whole unit circle.  Sampling the exact half-space kernel is NOT passive:
// the aliased high-frequency tail of G(i w) ~ -g'(0)/w^2 lowers Re Z_d by
// ~ g'(0) (c_s k dt)^2 / 12 where the exact Re Z is zero (below the shear-wave
// frequency c_s |k| and at w = sqrt(2) c_s |k|), and free ringing then grows.
// The fix here is the smallest change of the first few kernel weights (in the
// Euclidean norm) that restores Re Z_d >= 0: a tiny quadratic programme.
#include <span>
#include <vector>

#include "kernels/half_space_kernel.hpp"

namespace slipstrip {

// --- Time-step limits of passivity (beta = c_s dt / dx) ----------------------
//
// Strip operator: the static stiffness of the strip's normal modes above the
// Nyquist frequency pi/dt must be absorbed by the resolved passive modes.  The
// exact condition (docs/theory.md section 6.4) is dt S(k,0)/2 <= eta at the
// grid's Nyquist wavenumber, i.e. beta <= 1 / (pi (1 - c_s^2/c_d^2)).
double strip_passivity_beta_limit(double speed_ratio_squared);
// Measured limit for every H/dx tried (0.5 ... 200): beta = 0.45 fails in
// plane strain at nu = 0.33 and 0.4 never does; the config applies the smaller
// of this and strip_passivity_beta_limit.
inline constexpr double kStripBetaLimit = 0.4;
// Half-space operator: the correction of the first 8 sampled weights that
// restores Re Z_d >= 0 exists up to c_s k dt ~ 1.11 at the Nyquist mode (plane
// strain, nu = 0.33), i.e. beta ~ 0.355 (docs/theory.md section 8.4).
inline constexpr double kHalfSpaceBetaLimit = 0.35;

// x minimising |x|^2 subject to  C x >= b  (C: rows x n, row-major, n small).
// Dual active-set method of Goldfarb and Idnani specialised to an identity
// Hessian.  Throws std::runtime_error if the constraints are inconsistent.
std::vector<double> minimum_norm_point(std::span<const double> C, std::span<const double> b,
                                       int n);

// Re Z_d(theta) / (mu / c_s) of the half-space kernel sampled exactly at the
// lags j h (h = c_s |k| dt, theta in (0, pi]), by the Poisson summation
// formula: Re Z(i theta / h) plus the aliases Re G(i (theta + 2 pi m) / h),
// m != 0 (|m| <= 64 summed, the rest from the asymptotic tail).
double sampled_half_space_real_part(double speed_ratio_squared, double h, double theta);
double sampled_half_space_real_part(const HalfSpaceShape& shape, double h, double theta);

// Corrections e_1..e_lags (units mu / c_s) to add to the sampled weights
// K_j / (mu / c_s) = h g(j h) so that Re Z_d >= margin on a grid that resolves
// the lossless band (0, 2.5 h) and the whole circle.  Throws
// std::runtime_error when no such correction exists (h too large).
std::vector<double> half_space_passivity_correction(double speed_ratio_squared, double h,
                                                    int lags, double margin);
// The same for either shape (in-plane or antiplane, kernels/half_space_kernel.hpp).
std::vector<double> half_space_passivity_correction(const HalfSpaceShape& shape, double h,
                                                    int lags, double margin);

}  // namespace slipstrip
