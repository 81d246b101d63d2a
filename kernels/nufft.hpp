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

#include <algorithm>
#include <array>
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
  // Grids of at least this many points (G = 2B) are interleaved in a pass of
  // two series (PassScratch).
  static constexpr int interleaved_grid = 8192;
  explicit GaussianNufft(int samples, int half_width = 12, int interleave_from = interleaved_grid);
  GaussianNufft(const GaussianNufft&) = delete;
  GaussianNufft& operator=(const GaussianNufft&) = delete;

  int samples() const { return samples_; }
  int grid_size() const { return grid_; }
  // A pass of two series interleaves their grids (PassScratch).
  bool interleaves_pairs() const { return interleaved_; }

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

  // Both halves at once for C series through the same frequencies, when each
  // frequency's adjoint coefficients follow from its forward values alone (a
  // block operator's far field): F_c = forward_centred(in_c) at theta_k, then
  // map(k, values) turns values = (F_1(k) .. F_C(k)) in place into the
  // coefficients c_c(k), and add_out_c += adjoint_centred(c_c).  The Gaussian
  // weights of a frequency are computed where they are used, shared by the C
  // series both ways, instead of stored by locate() and read back 2C times.
  // Equal to locate + forward_centred + map + adjoint_centred to rounding (the
  // forward sums are reassociated into vector lanes).  The frequencies need no
  // locate() beforehand.
  // C = 1 or 2.  With two series and a grid of G >= interleave_from points
  // (the constructor's; interleaved_grid unless a test sets it), their grids
  // are interleaved point by point ([point][series]) and transformed as one
  // FFTW plan of two strided transforms: FFTW_ESTIMATE's plan of one
  // contiguous transform of 8192, 16384 or 32768 points takes ~2, 1.7 and
  // 1.5x the time per transform of its plan for two interleaved ones, and a
  // frequency's window is then one contiguous run of 2w points of both series
  // both ways.  At 2048 and 4096 points the interleaved plan is the slower
  // (1.6x, 1.1x; docs/notes/2026-11-27-pair-levels.md), and each series keeps
  // its own grid.
  struct PassScratch {
    FftwBuffer<fftw_complex> samples;            // time side, G points (interleaved: 2G)
    std::vector<FftwBuffer<fftw_complex>> grid;  // per series: forward grid, then adjoint grid, G + 2w points
                                                 // each (interleaved: the two, 2 (G + 2w) points each)
  };
  PassScratch make_pass_scratch(int series) const;
  template <int C, class Map>
  void forward_map_adjoint(std::span<const double> theta, const std::array<const std::complex<double>*, C>& in,
                           const std::array<std::complex<double>*, C>& add_out, PassScratch& scratch,
                           Map&& map) const;

  // Convenience forms of the definitions at the top (locate + centred + phase).
  void forward(std::span<const std::complex<double>> in, std::span<const double> theta,
               std::span<std::complex<double>> out, Scratch& scratch) const;
  void adjoint(std::span<const double> theta, std::span<const std::complex<double>> c,
               std::span<std::complex<double>> out, Scratch& scratch) const;

 private:
  // Frequencies' Gaussian windows: first grid point start[k] and the 2w
  // weights weight[k * 2w ..] of theta[k], k < n.
  void gaussian_windows(const double* theta, std::size_t n, long* start, double* weight) const;
  // in (B samples) deconvolved onto the time grid, transformed into `grid`,
  // whose first 2w points are copied after its G.
  void to_grid(const std::complex<double>* in, fftw_complex* samples, fftw_complex* grid) const;
  // `grid` (G + 2w points, its tail folded back here) transformed and
  // deconvolved into out (B samples), assigned or added.
  void from_grid(fftw_complex* grid, fftw_complex* samples, std::complex<double>* out, bool add) const;
  // forward_map_adjoint on each series' own grid, and on the C series' grids
  // interleaved point by point (PassScratch).
  template <int C, class Map>
  void pass_separate(std::span<const double> theta, const std::array<const std::complex<double>*, C>& in,
                     const std::array<std::complex<double>*, C>& add_out, PassScratch& scratch, Map&& map) const;
  template <int C, class Map>
  void pass_interleaved(std::span<const double> theta, const std::array<const std::complex<double>*, C>& in,
                        const std::array<std::complex<double>*, C>& add_out, PassScratch& scratch, Map&& map) const;
  // The same for `series` (1 or 2) series interleaved point by point in
  // samples (series G points) and grid (series (G + 2w) points); from_grids adds.
  void to_grids(const std::complex<double>* const* in, int series, fftw_complex* samples,
                fftw_complex* grid) const;
  void from_grids(fftw_complex* grid, int series, fftw_complex* samples, std::complex<double>* const* out) const;

  int samples_, grid_, half_width_;
  double variance_;                   // T in exp(-x^2 / (4 T))
  std::vector<double> deconvolution_; // 1 / ghat(t - B/2), t = 0..B-1, divided by G
  std::vector<double> tail_;          // exp(-(j dx)^2 / (4T)), j = 0..half_width
  FftwPlan forward_plan_;   // samples -> grid, e^{-i} (out of place: complex_dft_plan)
  FftwPlan backward_plan_;  // grid -> samples, e^{+i}
  bool interleaved_;  // a pass of two series interleaves their grids
  FftwPlan pair_forward_plan_, pair_backward_plan_;  // then: as above, for two series interleaved
};

template <int C, class Map>
void GaussianNufft::forward_map_adjoint(std::span<const double> theta,
                                        const std::array<const std::complex<double>*, C>& in,
                                        const std::array<std::complex<double>*, C>& add_out, PassScratch& scratch,
                                        Map&& map) const {
  static_assert(C == 1 || C == 2, "GaussianNufft::forward_map_adjoint: one or two series");
  if (C > 1 && interleaved_)
    pass_interleaved<C>(theta, in, add_out, scratch, map);
  else
    pass_separate<C>(theta, in, add_out, scratch, map);
}

template <int C, class Map>
void GaussianNufft::pass_separate(std::span<const double> theta,
                                        const std::array<const std::complex<double>*, C>& in,
                                        const std::array<std::complex<double>*, C>& add_out, PassScratch& scratch,
                                        Map&& map) const {
  const int G = grid_, w = half_width_;
  std::array<const double*, C> forward;
  std::array<double*, C> adjoint;
  for (int c = 0; c < C; ++c) {
    to_grid(in[c], scratch.samples.get(), scratch.grid[2 * c].get());
    forward[c] = reinterpret_cast<const double*>(scratch.grid[2 * c].get());
    adjoint[c] = reinterpret_cast<double*>(scratch.grid[2 * c + 1].get());
    for (int l = 0; l < 2 * (G + 2 * w); ++l) adjoint[c][l] = 0.0;
  }
  // Windows a batch of frequencies at a time: their exponentials and
  // weight recurrences are independent chains that overlap.
  constexpr std::size_t batch = 16;
  constexpr int lanes = 8;
  double weight[batch * 2 * max_half_width];
  long start[batch];
  // One frequency's weights each twice (re, im), so that its window of 2w
  // complex grid points is one contiguous run of 4w doubles both ways.
  alignas(64) double tap[4 * max_half_width];
  alignas(64) double value[4 * max_half_width];
  const int run = 4 * w, whole = run - run % lanes;
  std::array<std::complex<double>, C> values;
  for (std::size_t k0 = 0; k0 < theta.size(); k0 += batch) {
    const std::size_t n = std::min(batch, theta.size() - k0);
    gaussian_windows(theta.data() + k0, n, start, weight);
    for (std::size_t i = 0; i < n; ++i) {
      const long at = 2 * start[i];
      for (int j = 0; j < 2 * w; ++j) tap[2 * j] = tap[2 * j + 1] = weight[i * 2 * w + j];
      for (int c = 0; c < C; ++c) {
        // Partial sums in `lanes` lanes, even lanes Re and odd lanes Im
        // (reassociated: the in-order sum is a chain of 2w dependent additions).
        const double* window = forward[c] + at;
        double part[lanes] = {};
        for (int l0 = 0; l0 < whole; l0 += lanes)
          for (int l = 0; l < lanes; ++l) part[l] += window[l0 + l] * tap[l0 + l];
        for (int l = 0; l < run - whole; ++l) part[l] += window[whole + l] * tap[whole + l];
        double re = 0.0, im = 0.0;
        for (int l = 0; l < lanes; l += 2) {
          re += part[l];
          im += part[l + 1];
        }
        values[c] = {re, im};
      }
      map(k0 + i, values);
      for (int c = 0; c < C; ++c) {
        double* window = adjoint[c] + at;
        for (int l = 0; l < run; l += 2) {
          value[l] = values[c].real();
          value[l + 1] = values[c].imag();
        }
        for (int l = 0; l < run; ++l) window[l] += value[l] * tap[l];
      }
    }
  }
  for (int c = 0; c < C; ++c) from_grid(scratch.grid[2 * c + 1].get(), scratch.samples.get(), add_out[c], true);
}

template <int C, class Map>
void GaussianNufft::pass_interleaved(std::span<const double> theta,
                                        const std::array<const std::complex<double>*, C>& in,
                                        const std::array<std::complex<double>*, C>& add_out, PassScratch& scratch,
                                        Map&& map) const {
  constexpr int lanes = 8;
  static_assert(lanes % (2 * C) == 0, "a lane holds one series' Re or Im");
  const int G = grid_, w = half_width_;
  to_grids(in.data(), C, scratch.samples.get(), scratch.grid[0].get());
  const auto* forward = reinterpret_cast<const double*>(scratch.grid[0].get());
  auto* adjoint = reinterpret_cast<double*>(scratch.grid[1].get());
  for (int l = 0; l < 2 * C * (G + 2 * w); ++l) adjoint[l] = 0.0;
  // Windows a batch of frequencies at a time: their exponentials and
  // weight recurrences are independent chains that overlap.
  constexpr std::size_t batch = 16;
  double weight[batch * 2 * max_half_width];
  long start[batch];
  // One frequency's weights each 2C times (re, im of every series), so that
  // its window of 2w grid points is one contiguous run of 4Cw doubles both ways.
  alignas(64) double tap[4 * C * max_half_width];
  const int run = 4 * C * w, whole = run - run % lanes;
  std::array<std::complex<double>, C> values;
  for (std::size_t k0 = 0; k0 < theta.size(); k0 += batch) {
    const std::size_t n = std::min(batch, theta.size() - k0);
    gaussian_windows(theta.data() + k0, n, start, weight);
    for (std::size_t i = 0; i < n; ++i) {
      const long at = 2 * C * start[i];
      const double* wi = weight + i * 2 * w;
      for (int j = 0; j < 2 * w; ++j) {
        const double g = wi[j];
        for (int l = 0; l < 2 * C; ++l) tap[2 * C * j + l] = g;
      }
      // Partial sums in `lanes` lanes, lane l holding series (l / 2) % C, Re
      // for even l and Im for odd (reassociated: the in-order sum is a chain
      // of 2w dependent additions), in two sets taking alternate runs of
      // `lanes` values: two dependent chains of half the length, which
      // overlap (with one set, the chain of 12 additions at w = 12, C = 2 was
      // the forward sum's cost).
      const double* window = forward + at;
      double part[lanes] = {}, other[lanes] = {};
      int l0 = 0;
      for (; l0 + 2 * lanes <= whole; l0 += 2 * lanes) {
        for (int l = 0; l < lanes; ++l) part[l] += window[l0 + l] * tap[l0 + l];
        for (int l = 0; l < lanes; ++l) other[l] += window[l0 + lanes + l] * tap[l0 + lanes + l];
      }
      for (; l0 < whole; l0 += lanes)
        for (int l = 0; l < lanes; ++l) part[l] += window[l0 + l] * tap[l0 + l];
      for (int l = 0; l < run - whole; ++l) part[l] += window[whole + l] * tap[whole + l];
      for (int l = 0; l < lanes; ++l) part[l] += other[l];
      for (int c = 0; c < C; ++c) {
        double re = 0.0, im = 0.0;
        for (int l = 2 * c; l < lanes; l += 2 * C) {
          re += part[l];
          im += part[l + 1];
        }
        values[c] = {re, im};
      }
      map(k0 + i, values);
      // The coefficients of every series repeated over the lanes once (a
      // register), instead of written over the whole run of 4Cw doubles and
      // read back: the window's stores are then its own additions alone (the
      // stores were where this loop waited; one body's push at N = 512,
      // H = 4 m ~4 % faster, docs/notes/2026-11-27-pair-bin-order.md).
      double* out = adjoint + at;
      double repeated[lanes];
      for (int l = 0; l < lanes; ++l) {
        const std::complex<double>& v = values[(l / 2) % C];
        repeated[l] = l % 2 == 0 ? v.real() : v.imag();
      }
      for (int m0 = 0; m0 < whole; m0 += lanes)
        for (int l = 0; l < lanes; ++l) out[m0 + l] += repeated[l] * tap[m0 + l];
      for (int l = 0; l < run - whole; ++l) out[whole + l] += repeated[l] * tap[whole + l];
    }
  }
  from_grids(scratch.grid[1].get(), C, scratch.samples.get(), add_out.data());
}

}  // namespace slipstrip
