#pragma once
// One-dimensional non-uniform discrete Fourier transforms between B uniform
// time samples and arbitrary frequencies theta_k in [-pi, pi], by Gaussian
// gridding (Dutt & Rokhlin 1993; Greengard & Lee, SIAM Review 46, 2004):
//
//   forward (type 2):  out[k]   = sum_{t=0}^{B-1} in[t] exp(-i theta_k t)
//   adjoint (type 1):  out[t]   = sum_k  c[k] exp(+i theta_k t),   t = 0..B-1
//
// Cost O(B log B + K w) instead of O(B K) (K frequencies, w = 2 * half_width
// grid points per frequency).  Used by the block history operator
// (kernels/block_strip_history.hpp) to move the normal-mode states of a strip
// across a block of B time steps in one go.
//
// Accuracy: the Gaussian's width is chosen so that its truncation to
// 2*half_width grid points and the aliasing of the 2x oversampled grid err
// by the same amount, ~exp(-pi half_width / sqrt 2) relative to sum |c|
// (half_width = 14: ~3e-14; measured in tests/cpp/test_kernels_nufft.cpp).
// FFTW plans are made once, with FFTW_ESTIMATE so that results are identical
// run after run; execution uses caller-owned scratch (one per thread).
#include <fftw3.h>

#include <complex>
#include <cstddef>
#include <span>
#include <vector>

#include "kernels/fft.hpp"

namespace slipstrip {

class GaussianNufft {
 public:
  // samples: B (even, >= 2).  half_width: grid points on each side of a frequency.
  static constexpr int max_half_width = 32;
  explicit GaussianNufft(int samples, int half_width = 12);
  GaussianNufft(const GaussianNufft&) = delete;
  GaussianNufft& operator=(const GaussianNufft&) = delete;

  int samples() const { return samples_; }
  int grid_size() const { return grid_; }

  // Working memory of one caller (one per thread): the oversampled grid and
  // the Gaussian weights of up to `frequencies` frequencies.
  struct Scratch {
    FftwBuffer<fftw_complex> grid;     // spectrum side: G points and a copy of the first 2w
    FftwBuffer<fftw_complex> samples;  // time side: the G-point grid of the deconvolved samples
    std::vector<long> window_start;  // first grid point of each frequency's window
    std::vector<double> weight;      // 2w weights per frequency
    std::vector<std::complex<double>> phased;  // used by the convenience adjoint() only
  };
  Scratch make_scratch(std::size_t frequencies) const;

  // The transforms in two halves, for callers that transform the same
  // frequencies both ways: locate() computes the Gaussian weights once, and
  // the *_centred transforms use time measured from the block's centre,
  // t' = t - B/2 (callers fold the phase e^{i theta B/2} into their own data):
  //   forward_centred: out[k] = sum_t in[t] exp(-i theta_k (t - B/2))
  //   adjoint_centred: out[t] = sum_k c[k] exp(+i theta_k (t - B/2))
  void locate(std::span<const double> theta, Scratch& scratch) const;
  void forward_centred(std::span<const std::complex<double>> in, std::span<std::complex<double>> out,
                       Scratch& scratch) const;
  void adjoint_centred(std::span<const std::complex<double>> c, std::span<std::complex<double>> out,
                       Scratch& scratch) const;

  // Convenience forms of the definitions at the top (locate + centred + phase).
  void forward(std::span<const std::complex<double>> in, std::span<const double> theta,
               std::span<std::complex<double>> out, Scratch& scratch) const;
  void adjoint(std::span<const double> theta, std::span<const std::complex<double>> c,
               std::span<std::complex<double>> out, Scratch& scratch) const;

 private:
  int samples_, grid_, half_width_;
  double variance_;                   // T in exp(-x^2 / (4 T))
  std::vector<double> deconvolution_; // 1 / ghat(t - B/2), t = 0..B-1, divided by G
  std::vector<double> tail_;          // exp(-(j dx)^2 / (4T)), j = 0..half_width
  FftwPlan forward_plan_;   // samples -> grid, e^{-i} (out of place: complex_dft_plan)
  FftwPlan backward_plan_;  // grid -> samples, e^{+i}
};

}  // namespace slipstrip
