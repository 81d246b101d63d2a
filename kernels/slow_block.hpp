#pragma once
// The slow exponentials of a half-space operator advanced once per block of B
// steps (docs/theory.md §8.7), the part shared by the scalar operator
// (HalfSpaceHistory) and the in-plane body's 2x2 one (FaceHalfSpaceHistory).
//
// A slow pole z = rho_b d (branch b: shear or P, rho_b = e^{i b h}, d =
// e^{-lambda}) holds a state Y per real input channel c (the Re and the Im
// part of a complex input), taken at the block start.  Inside a block, at
// position t' = 1..B, the slow poles' output on a real output channel o is
//     2 Re sum_b rho_b^{t'} sum_p (t' - t_c)^p M_{b,o,p},   t_c = (B + 1) / 2,
// plus the slow kernel's lags 0..t'-1 applied to the block's own inputs; at
// the block end each state is advanced with the block's input moments
//     mu_{b,c,p} = sum_{j=1..B} (j - t_c)^p rho_b^j u_c(B - j)
// and the next block's polynomial coefficients M are summed over the poles.
// The helpers are inline so that they compile into each instruction-set copy
// of an operator's mode loop.
#include <complex>
#include <cstddef>
#include <span>
#include <vector>

namespace slipstrip {

// rho_b^{t'} for t' = 1..B, both branches, every mode: [(t' - 1) * modes + q] * 2
// + b, computed with std::polar so that nothing drifts over a run.  b_pressure
// is c_d / c_s (the P branch's frequency in units of c_s |k|).
std::vector<std::complex<double>> slow_block_rotations(std::span<const double> h, double b_pressure, int block);

// Moments mu[(2 b + c) * terms + p] of one complex block input (c = 0: its Re
// part, 1: its Im part), the block's input at position s being
// (input_re[s * stride], input_im[s * stride]): a complex array (stride 2 over
// its doubles) or separate arrays of the real and imaginary parts (stride 1).
[[gnu::always_inline]] inline void slow_input_moments(const double* input_re, const double* input_im,
                                                      std::size_t stride, const std::complex<double>* rotation,
                                                      std::size_t modes, std::size_t q, int block, double centre,
                                                      int terms, std::complex<double>* mu) {
  for (int j = 1; j <= block; ++j) {
    const double x = j - centre;
    const std::size_t s = static_cast<std::size_t>(block - j) * stride;
    const double u_re = input_re[s], u_im = input_im[s];
    const std::size_t at = ((static_cast<std::size_t>(j) - 1) * modes + q) * 2;
    const std::complex<double> in[4] = {rotation[at] * u_re, rotation[at] * u_im, rotation[at + 1] * u_re,
                                        rotation[at + 1] * u_im};
    double power = 1.0;
    for (int p = 0; p < terms; ++p, power *= x)
      for (int beta = 0; beta < 4; ++beta) mu[beta * terms + p] += power * in[beta];
  }
}

[[gnu::always_inline]] inline void slow_input_moments(const std::complex<double>* input, const std::complex<double>* rotation,
                                                      std::size_t modes, std::size_t q, int block, double centre,
                                                      int terms, std::complex<double>* mu) {
  const double* parts = reinterpret_cast<const double*>(input);
  slow_input_moments(parts, parts + 1, 2, rotation, modes, q, block, centre, terms, mu);
}

// factor[p] = e^{-lambda t_c} (-lambda)^p / p!, p < terms.
[[gnu::always_inline]] inline void slow_taylor_factors(double centre_factor, double decay, int terms, double* factor) {
  factor[0] = centre_factor;
  for (int p = 1; p < terms; ++p) factor[p] = factor[p - 1] * (-decay / p);
}

// One slow pole's state of a complex input at the block end:
//   Y_c <- z^B Y_c + sum_p factor[p] mu_{b,c,p}   (c = Re, Im; mu of that input, branch b).
[[gnu::always_inline]] inline void advance_slow_state(const double* factor, const std::complex<double>* mu, int branch,
                                                      int terms, std::complex<double> block_pole,
                                                      std::complex<double>& state_re, std::complex<double>& state_im) {
  const std::complex<double>* mu_re = mu + (2 * branch) * terms;
  const std::complex<double>* mu_im = mu_re + terms;
  std::complex<double> feed_re = 0.0, feed_im = 0.0;
  for (int p = 0; p < terms; ++p) {
    feed_re += factor[p] * mu_re[p];
    feed_im += factor[p] * mu_im[p];
  }
  state_re = block_pole * state_re + feed_re;
  state_im = block_pole * state_im + feed_im;
}

// moment[p] += factor[p] w Y: one pole's share of one output channel's polynomial.
[[gnu::always_inline]] inline void add_slow_moment(const double* factor, std::complex<double> weighted_state, int terms,
                                                   std::complex<double>* moment) {
  for (int p = 0; p < terms; ++p) moment[p] += factor[p] * weighted_state;
}

// The slow poles' output on Channels real output channels at block position
// t' (x = t' - t_c): polynomial (b, o) at moment[(b * Channels + o) * terms].
template <int Channels>
[[gnu::always_inline]] inline void slow_block_output(const std::complex<double>* moment, int terms, double x,
                                                     std::complex<double> rho_shear, std::complex<double> rho_pressure,
                                                     double* out) {
  // Horner's rule on the 2 Channels polynomials side by side: independent
  // chains, so they overlap instead of waiting on each other's latency.
  std::complex<double> branch[2 * Channels];
  for (int beta = 0; beta < 2 * Channels; ++beta) branch[beta] = moment[beta * terms + terms - 1];
  for (int p = terms - 2; p >= 0; --p)
    for (int beta = 0; beta < 2 * Channels; ++beta) branch[beta] = branch[beta] * x + moment[beta * terms + p];
  for (int o = 0; o < Channels; ++o) out[o] = 2.0 * (rho_shear * branch[o] + rho_pressure * branch[Channels + o]).real();
}

// sum_{j<=t} lag[t - j] input[j]: the slow kernel's lags applied to the
// block's own inputs (input j of the block sits at lag t - j).
[[gnu::always_inline]] inline std::complex<double> slow_in_block_sum(const double* lag, const std::complex<double>* input,
                                                                      int t) {
  double in_r = 0.0, in_i = 0.0;
  for (int j = 0; j <= t; ++j) {
    in_r += lag[t - j] * input[j].real();
    in_i += lag[t - j] * input[j].imag();
  }
  return {in_r, in_i};
}

}  // namespace slipstrip
