#pragma once
// One-dimensional non-uniform discrete Fourier transforms between B uniform
// time samples and arbitrary frequencies theta_k in [-pi, pi], by gridding on
// a 2x oversampled grid with the "exponential of semicircle" (ES) kernel of
// Barnett, Magland & af Klinteberg (SIAM J. Sci. Comput. 41, 2019):
//
//   forward (type 2):  out[k]   = sum_{t=0}^{B-1} in[t] exp(-i theta_k t)
//   adjoint (type 1):  out[t]   = sum_k  c[k] exp(+i theta_k t),   t = 0..B-1
//
// Cost O(B log B + K w) instead of O(B K) (K frequencies, w = 2 * half_width
// grid points per frequency).  Used by the block history operators
// (kernels/block_strip_history.hpp, kernels/face_block_history.hpp) to move the
// normal-mode states of a strip across a block of B time steps in one go.
//
// Kernel: phi(z) = exp(beta (sqrt(1 - z^2) - 1)), |z| <= 1, spread over the
// w = 2 half_width grid points nearest a frequency (z = distance /
// (half_width grid spacings)), beta = 2.30 w.  Its error on the 2x grid falls
// as exp(-pi w / sqrt 2), ~9x per grid point of width, against ~3x for the
// Gaussian of Dutt & Rokhlin (Greengard & Lee 2004) this class used before,
// which took 24 points for less accuracy than 14 give here
// (docs/notes/2026-11-27-nufft-kernel.md).  Accuracy, relative to
// sum |input|: half_width = 7 (the default, 14 points) measured <= 1.5e-13
// (tests/cpp/test_kernels_nufft.cpp, which checks 5e-13).  The kernel's
// Fourier transform, needed for the deconvolution, has no closed form: it is
// integrated once at construction by Gauss-Legendre quadrature.  The weights
// of a frequency are polynomials in its offset from the grid, one per grid
// point of its window (fitted at construction, evaluated by Horner's rule,
// several frequencies in vector lanes).
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

class Nufft {
 public:
  // samples: B (even, >= 2).  half_width: grid points on each side of a
  // frequency.  Beyond ~8 the error is round-off (~1e-14); at 32 (beta = 147)
  // the deconvolution's range costs accuracy again (measured 3e-13).
  static constexpr int max_half_width = 32;
  // Grids of at least this many points (G = 2B) are interleaved in a pass of
  // two series (PassScratch).
  static constexpr int interleaved_grid = 8192;
  // The weights' polynomials: the highest degree tried and the error sought
  // (fit_taps).
  static constexpr int max_degree = 24;
  static constexpr double fit_tolerance = 1e-15;
  explicit Nufft(int samples, int half_width = 7, int interleave_from = interleaved_grid);
  Nufft(const Nufft&) = delete;
  Nufft& operator=(const Nufft&) = delete;

  int samples() const { return samples_; }
  int grid_size() const { return grid_; }
  // A pass of two series interleaves their grids (PassScratch).
  bool interleaves_pairs() const { return interleaved_; }
  // The largest error of the weights' polynomials (fit_taps) against the
  // kernel, whose largest value is 1.
  double weight_fit_error() const { return fit_error_; }
  int weight_fit_degree() const { return degree_; }

  // Working memory of one caller (one per thread): the oversampled grid and
  // the kernel weights of up to `frequencies` frequencies.
  struct Scratch {
    FftwBuffer<fftw_complex> grid;     // spectrum side: G points and a copy of the first 2w
    FftwBuffer<fftw_complex> samples;  // time side: the G-point grid of the deconvolved samples
    std::vector<long> window_start;  // first grid point of each frequency's window
    std::vector<double> weight;      // 2w weights per frequency, each twice (kernel_windows<2>)
    std::vector<std::complex<double>> phased;  // used by the convenience adjoint() only
  };
  Scratch make_scratch(std::size_t frequencies) const;

  // The transforms in two halves, for callers that transform the same
  // frequencies both ways: locate() computes the kernel weights once, and
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
  // coefficients c_c(k), and add_out_c += adjoint_centred(c_c).  The kernel
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
  // Frequencies' kernel windows: first grid point start[k] and the 2w
  // weights of theta[k], k < n, each `copies` times in a row: weight j's
  // copies at weight[(k * 2w + j) * copies ..].  The passes below take a
  // window's weights once per double of its grid points (re, im of each
  // series) as whole vectors, stored here well before they are loaded
  // (built per frequency from single weights just before its loads, the
  // vector loads waited for the narrower stores).
  template <int copies>
  void kernel_windows(const double* theta, std::size_t n, long* start, double* weight) const;
  // in (B samples) deconvolved onto the time grid, transformed into `grid`,
  // whose first 2w points are copied after its G.
  void to_grid(const std::complex<double>* in, fftw_complex* samples, fftw_complex* grid) const;
  // `grid` (G + 2w points, its tail folded back here) transformed and
  // deconvolved into out (B samples), assigned or added.
  void from_grid(fftw_complex* grid, fftw_complex* samples, std::complex<double>* out, bool add) const;
  // One frequency's window of 2 half_width grid points (re, im: a run of
  // 4 half_width doubles) against its weights, each twice (kernel_windows<2>):
  // the forward sum, and the adjoint's spread of `value` added into it.  The
  // forward sum in vector lanes, even lanes Re and odd lanes Im
  // (reassociated: the in-order sum is a chain of 2w dependent additions).
  // An odd half_width leaves a tail of 4 doubles after whole vectors, done in
  // lanes of its own of fixed count: a tail loop of half_width-dependent
  // count kept the partial sums in memory (seen in the one pass at
  // half_width = 7; docs/notes/2026-11-27-nufft-kernel.md).
  static std::complex<double> gather(const double* window, const double* tap, int half_width) {
    constexpr int lanes = 8;
    const int run = 4 * half_width, whole = run - run % lanes;  // run - whole: 0 or 4
    double part[lanes] = {}, rest[4] = {};
    for (int l0 = 0; l0 < whole; l0 += lanes)
      for (int l = 0; l < lanes; ++l) part[l] += window[l0 + l] * tap[l0 + l];
    if (whole < run)
      for (int l = 0; l < 4; ++l) rest[l] = window[whole + l] * tap[whole + l];
    double re = rest[0] + rest[2], im = rest[1] + rest[3];
    for (int l = 0; l < lanes; l += 2) {
      re += part[l];
      im += part[l + 1];
    }
    return {re, im};
  }
  static void spread(std::complex<double> value, double* window, const double* tap, int half_width) {
    constexpr int lanes = 8;
    const int run = 4 * half_width, whole = run - run % lanes;
    double repeated[lanes];
    for (int l = 0; l < lanes; l += 2) {
      repeated[l] = value.real();
      repeated[l + 1] = value.imag();
    }
    for (int l0 = 0; l0 < whole; l0 += lanes)
      for (int l = 0; l < lanes; ++l) window[l0 + l] += repeated[l] * tap[l0 + l];
    if (whole < run)
      for (int l = 0; l < 4; ++l) window[whole + l] += repeated[l] * tap[whole + l];
  }
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
  double beta_;                       // phi(z) = exp(beta (sqrt(1 - z^2) - 1))
  std::vector<double> deconvolution_; // 1 / phihat(t - B/2), t = 0..B-1, divided by G
  // Tap j of a window, phi((j - half_width + 1 - d) / half_width) for the
  // frequency's offset d in [0, 1) grid spacings, as a polynomial in
  // s = 2d - 1: coefficient of s^m at horner_[m * half_width + j],
  // j < half_width, m <= degree_ (tap 2 half_width - 1 - j is tap j at -s).
  int degree_;
  std::vector<double> horner_;
  double fit_error_;  // the fitted weights' largest error, phi(0) = 1
  void fit_taps();
  FftwPlan forward_plan_;   // samples -> grid, e^{-i} (out of place: complex_dft_plan)
  FftwPlan backward_plan_;  // grid -> samples, e^{+i}
  bool interleaved_;  // a pass of two series interleaves their grids
  FftwPlan pair_forward_plan_, pair_backward_plan_;  // then: as above, for two series interleaved
};

template <int C, class Map>
void Nufft::forward_map_adjoint(std::span<const double> theta,
                                        const std::array<const std::complex<double>*, C>& in,
                                        const std::array<std::complex<double>*, C>& add_out, PassScratch& scratch,
                                        Map&& map) const {
  static_assert(C == 1 || C == 2, "Nufft::forward_map_adjoint: one or two series");
  if constexpr (C > 1) {
    if (interleaved_) {
      pass_interleaved<C>(theta, in, add_out, scratch, map);
      return;
    }
  }
  pass_separate<C>(theta, in, add_out, scratch, map);
}

template <int C, class Map>
void Nufft::pass_separate(std::span<const double> theta,
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
  // Windows a batch of frequencies at a time: their weight polynomials are
  // evaluated side by side in vector lanes.
  constexpr std::size_t batch = 16;
  // One frequency's weights each twice (re, im), so that its window of 2w
  // complex grid points is one contiguous run of 4w doubles both ways.
  alignas(64) double weight[batch * 4 * max_half_width];
  long start[batch];
  const int run = 4 * w;
  std::array<std::complex<double>, C> values;
  for (std::size_t k0 = 0; k0 < theta.size(); k0 += batch) {
    const std::size_t n = std::min(batch, theta.size() - k0);
    kernel_windows<2>(theta.data() + k0, n, start, weight);
    for (std::size_t i = 0; i < n; ++i) {
      const long at = 2 * start[i];
      const double* tap = weight + i * run;
      for (int c = 0; c < C; ++c) values[c] = gather(forward[c] + at, tap, w);
      map(k0 + i, values);
      for (int c = 0; c < C; ++c) spread(values[c], adjoint[c] + at, tap, w);
    }
  }
  for (int c = 0; c < C; ++c) from_grid(scratch.grid[2 * c + 1].get(), scratch.samples.get(), add_out[c], true);
}

template <int C, class Map>
void Nufft::pass_interleaved(std::span<const double> theta,
                                        const std::array<const std::complex<double>*, C>& in,
                                        const std::array<std::complex<double>*, C>& add_out, PassScratch& scratch,
                                        Map&& map) const {
  constexpr int lanes = 8;
  static_assert(lanes % (2 * C) == 0, "a lane holds one series' Re or Im");
  // A window's run of 4Cw doubles is then whole vectors of `lanes`, for any w
  // (a tail loop of w-dependent count would keep the partial sums in memory).
  static_assert(4 * C % lanes == 0, "whole vectors");
  const int G = grid_, w = half_width_;
  to_grids(in.data(), C, scratch.samples.get(), scratch.grid[0].get());
  const auto* forward = reinterpret_cast<const double*>(scratch.grid[0].get());
  auto* adjoint = reinterpret_cast<double*>(scratch.grid[1].get());
  for (int l = 0; l < 2 * C * (G + 2 * w); ++l) adjoint[l] = 0.0;
  // Windows a batch of frequencies at a time: their weight polynomials are
  // evaluated side by side in vector lanes.
  constexpr std::size_t batch = 16;
  // One frequency's weights each 2C times (re, im of every series), so that
  // its window of 2w grid points is one contiguous run of 4Cw doubles both ways.
  alignas(64) double weight[batch * 4 * C * max_half_width];
  long start[batch];
  const int run = 4 * C * w;
  std::array<std::complex<double>, C> values;
  for (std::size_t k0 = 0; k0 < theta.size(); k0 += batch) {
    const std::size_t n = std::min(batch, theta.size() - k0);
    kernel_windows<2 * C>(theta.data() + k0, n, start, weight);
    for (std::size_t i = 0; i < n; ++i) {
      const long at = 2 * C * start[i];
      const double* tap = weight + i * run;
      // Partial sums in `lanes` lanes, lane l holding series (l / 2) % C, Re
      // for even l and Im for odd (reassociated: the in-order sum is a chain
      // of 2w dependent additions), in two sets taking alternate runs of
      // `lanes` values: two dependent chains of half the length, which
      // overlap (with one set, the chain of 12 additions at w = 12, C = 2 was
      // the forward sum's cost).
      const double* window = forward + at;
      double part[lanes] = {}, other[lanes] = {};
      int l0 = 0;
      for (; l0 + 2 * lanes <= run; l0 += 2 * lanes) {
        for (int l = 0; l < lanes; ++l) part[l] += window[l0 + l] * tap[l0 + l];
        for (int l = 0; l < lanes; ++l) other[l] += window[l0 + lanes + l] * tap[l0 + lanes + l];
      }
      for (; l0 < run; l0 += lanes)
        for (int l = 0; l < lanes; ++l) part[l] += window[l0 + l] * tap[l0 + l];
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
      for (int m0 = 0; m0 < run; m0 += lanes)
        for (int l = 0; l < lanes; ++l) out[m0 + l] += repeated[l] * tap[m0 + l];
    }
  }
  from_grids(scratch.grid[1].get(), C, scratch.samples.get(), add_out.data());
}

}  // namespace slipstrip
