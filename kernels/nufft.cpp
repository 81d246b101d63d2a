#include "kernels/nufft.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace slipstrip {
namespace {
constexpr double pi = std::numbers::pi;
using cplx = std::complex<double>;
}  // namespace

namespace {
// The ES kernel exp(beta (sqrt(1 - z^2) - 1)) on |z| <= 1, in long double for
// the fit of its taps' polynomials.
long double es_kernel(long double z, long double beta) {
  const long double r = 1.0L - z * z;
  return r <= 0.0L ? std::exp(-beta) : std::exp(beta * (std::sqrt(r) - 1.0L));
}

// Gauss-Legendre nodes and weights on [-1, 1] (Newton's method on P_q from
// the asymptotic guesses), the nodes x_i > 0 of the symmetric pairs +-x_i only
// (q even).
void gauss_legendre_half(int q, std::vector<double>& node, std::vector<double>& weight) {
  node.clear();
  weight.clear();
  for (int i = 1; i <= q / 2; ++i) {
    double x = std::cos(pi * (i - 0.25) / (q + 0.5)), derivative = 1.0;
    for (int iteration = 0; iteration < 100; ++iteration) {
      double p0 = 1.0, p1 = x;
      for (int l = 2; l <= q; ++l) {
        const double p2 = ((2 * l - 1) * x * p1 - (l - 1) * p0) / l;
        p0 = p1;
        p1 = p2;
      }
      derivative = q * (x * p1 - p0) / (x * x - 1.0);
      const double step = p1 / derivative;
      x -= step;
      if (std::abs(step) < 1e-16) break;
    }
    node.push_back(x);
    weight.push_back(2.0 / ((1.0 - x * x) * derivative * derivative));
  }
}
}  // namespace

Nufft::Nufft(int samples, int half_width, int interleave_from)
    : samples_(samples), grid_(2 * samples), half_width_(half_width) {
  if (samples < 2 || samples % 2 != 0)
    throw std::invalid_argument("Nufft: samples = " + std::to_string(samples) + " must be even and >= 2");
  if (half_width < 2 || half_width > max_half_width || 2 * half_width > grid_)
    throw std::invalid_argument("Nufft: half_width = " + std::to_string(half_width) +
                                " must be in [2, min(samples, " + std::to_string(max_half_width) + ")]");
  const int w = 2 * half_width_;
  // beta / w = 2.30 for the 2x grid (Barnett, Magland & af Klinteberg 2019):
  // the truncation of the kernel's Fourier transform beyond the grid's band
  // and its aliasing then err by about the same.
  beta_ = 2.30 * w;
  const double dx = 2.0 * pi / grid_, support = half_width_ * dx;

  // The deconvolution: the kernel as a function of theta, phi(theta / support),
  // has phihat(n) = (1/2pi) int phi(theta/support) e^{-i n theta} dtheta =
  // (support / pi) int_0^1 phi(z) cos(n support z) dz, even in n, integrated
  // by Gauss-Legendre on [-1, 1] (both ends' square-root singularities are
  // damped by e^{-beta}; at |n| = B/2 the cosine's argument is
  // pi half_width / 2).
  std::vector<double> node, node_weight;
  gauss_legendre_half(2 * w + 20, node, node_weight);
  std::vector<double> kernel(node.size());
  for (std::size_t i = 0; i < node.size(); ++i)
    kernel[i] = node_weight[i] * std::exp(beta_ * (std::sqrt(1.0 - node[i] * node[i]) - 1.0));
  std::vector<double> phihat(samples_ / 2 + 1);
  for (int n = 0; n <= samples_ / 2; ++n) {
    double sum = 0.0;
    for (std::size_t i = 0; i < node.size(); ++i) sum += kernel[i] * std::cos(n * support * node[i]);
    phihat[n] = support / pi * sum;
  }
  deconvolution_.resize(samples_);
  for (int t = 0; t < samples_; ++t) deconvolution_[t] = 1.0 / (grid_ * phihat[std::abs(t - samples_ / 2)]);

  fit_taps();
  forward_plan_ = complex_dft_plan(grid_, FFTW_FORWARD, "Nufft");
  backward_plan_ = complex_dft_plan(grid_, FFTW_BACKWARD, "Nufft");
  interleaved_ = grid_ >= interleave_from;
  if (interleaved_) {
    pair_forward_plan_ = interleaved_dft_plan(grid_, 2, FFTW_FORWARD, "Nufft");
    pair_backward_plan_ = interleaved_dft_plan(grid_, 2, FFTW_BACKWARD, "Nufft");
  }
}

namespace {
// p(s) = E(s^2) + s O(s^2) for the powers' coefficients a[m * stride] of p,
// m <= degree, in double: the evaluation kernel_windows makes (p(-s) = E - s O).
struct EvenOdd {
  double even, odd;
};
EvenOdd even_odd(const double* a, std::size_t stride, int degree, double u) {
  const int top_even = degree / 2, top_odd = (degree - 1) / 2;
  double even = a[2 * top_even * stride], odd = top_odd >= 0 ? a[(2 * top_odd + 1) * stride] : 0.0;
  for (int m = top_even - 1; m >= 0; --m) even = even * u + a[2 * m * stride];
  for (int m = top_odd - 1; m >= 0; --m) odd = odd * u + a[(2 * m + 1) * stride];
  return {even, odd};
}
}  // namespace

void Nufft::fit_taps() {
  // Tap j's weight as a function of the offset d in [0, 1), in s = 2d - 1,
  // interpolated at Chebyshev points in long double and converted to powers
  // of s.  phi is even, so tap 2h-1-j at s is tap j at -s (h = half_width):
  // the first h taps are fitted, and kernel_windows evaluates each as
  // E(s^2) + s O(s^2), its mirror as E - s O (half the products).  Degrees
  // are tried upwards, each fit's error measured as kernel_windows evaluates
  // it (in double) at 8 points per coefficient, until it errs by
  // <= fit_tolerance of phi(0) = 1 or stalls: the window's end taps reach
  // z = +-1, where phi has a square root's singularity of size
  // ~beta e^{-beta} (about the kernel's own truncation error), which
  // polynomials approach only slowly; the degree before the first that gains
  // less than 2x is kept.  Measured (half_width 2..32): degree 5..13;
  // half_width 7, degree 12, error 6e-15.
  const int hw = half_width_;
  const long double beta = beta_, pi_l = std::numbers::pi_v<long double>;
  const auto exact = [&](int j, long double s) { return es_kernel((j - hw + 1 - (s + 1.0L) / 2.0L) / hw, beta); };
  std::vector<double> previous_fit;
  double previous_error = HUGE_VAL;
  int previous_degree = 0;
  for (int degree = 4; degree <= max_degree; ++degree) {
    const int N = degree + 1;
    std::vector<long double> cosine(static_cast<std::size_t>(N) * N);  // cos(pi l (k + 1/2) / N)
    for (int l = 0; l < N; ++l)
      for (int k = 0; k < N; ++k) cosine[l * N + k] = std::cos(pi_l * l * (k + 0.5L) / N);
    std::vector<double> fit(static_cast<std::size_t>(N) * hw, 0.0);
    std::vector<long double> value(N), power(N), previous(N), current(N), next(N);
    for (int j = 0; j < hw; ++j) {
      for (int k = 0; k < N; ++k) value[k] = exact(j, cosine[N + k]);  // at s_k = cos(pi (k + 1/2) / N)
      // Chebyshev coefficients, then powers of s through T_{l+1} = 2 s T_l - T_{l-1}.
      std::fill(power.begin(), power.end(), 0.0L);
      std::fill(previous.begin(), previous.end(), 0.0L);
      std::fill(current.begin(), current.end(), 0.0L);
      previous[0] = 1.0L;
      current[1] = 1.0L;
      for (int l = 0; l < N; ++l) {
        long double c = 0.0L;
        for (int k = 0; k < N; ++k) c += value[k] * cosine[l * N + k];
        c *= (l == 0 ? 1.0L : 2.0L) / N;
        const std::vector<long double>& T = l == 0 ? previous : current;
        for (int m = 0; m <= l; ++m) power[m] += c * T[m];
        if (l >= 1) {
          for (int m = 0; m < N; ++m) next[m] = (m > 0 ? 2.0L * current[m - 1] : 0.0L) - previous[m];
          std::swap(previous, current);
          std::swap(current, next);
        }
      }
      for (int m = 0; m < N; ++m) fit[static_cast<std::size_t>(m) * hw + j] = static_cast<double>(power[m]);
    }
    double error = 0.0;
    for (int j = 0; j < hw; ++j)
      for (int i = 0; i <= 8 * N; ++i) {
        const double s = -1.0 + 2.0 * i / (8 * N);
        const EvenOdd p = even_odd(fit.data() + j, hw, degree, s * s);
        error = std::max({error, static_cast<double>(std::abs(p.even + s * p.odd - exact(j, s))),
                          static_cast<double>(std::abs(p.even - s * p.odd - exact(2 * hw - 1 - j, s)))});
      }
    const bool stalled = error > 0.5 * previous_error;
    if (!stalled) {
      previous_fit = std::move(fit);
      previous_error = error;
      previous_degree = degree;
    }
    if (stalled || error <= fit_tolerance) break;
  }
  degree_ = previous_degree;
  horner_ = std::move(previous_fit);
  fit_error_ = previous_error;
}

Nufft::Scratch Nufft::make_scratch(std::size_t frequencies) const {
  // The grid is followed by a copy of its first 2w points, so that every
  // frequency's window is one contiguous (vectorisable) run.
  return {make_fftw_buffer<fftw_complex>(grid_ + 2 * half_width_), make_fftw_buffer<fftw_complex>(grid_),
          std::vector<long>(frequencies), std::vector<double>(frequencies * 4 * half_width_), {}};
}

void Nufft::locate(std::span<const double> theta, Scratch& scratch) const {
  if (theta.size() > scratch.window_start.size())
    throw std::invalid_argument("Nufft: scratch holds " +
                                std::to_string(scratch.window_start.size()) + " frequencies, " +
                                std::to_string(theta.size()) + " given");
  kernel_windows<2>(theta.data(), theta.size(), scratch.window_start.data(), scratch.weight.data());
}

// Kernel weights of the 2h grid points base-h+1 .. base+h (h = half_width)
// around each frequency (base = floor(theta / dx), offset
// d = theta / dx - base): with s = 2d - 1, tap j's polynomial
// E_j(s^2) + s O_j(s^2) and tap 2h-1-j's E_j - s O_j (fit_taps).  Lanes of
// frequencies side by side: one tap's polynomial is a chain of dependent
// multiply-adds, several frequencies' chains are one vector's.
//
// A frequency followed by its negative (the block operators list each normal
// mode as +phi, -phi) shares its window mirrored: with theta = (u + d) dx,
// 0 < d < 1, -theta has base -u-1 and offset 1 - d, so its tap j is
// phi((j - h + d) / h), theta's tap 2h-1-j is phi((h - j - d) / h), and phi
// is even: its 2h weights are theta's in reverse order.  The pair's polynomials are evaluated once (the mirrored
// weights equal the directly computed ones to rounding; the windows' first
// points are the same integers).  A frequency on a grid point (d = 0) has no
// mirror of this form and is computed directly.
template <int copies>
void Nufft::kernel_windows(const double* theta, std::size_t n, long* start, double* weight) const {
  constexpr std::size_t lanes = 8;
  const int G = grid_, hw = half_width_, w = 2 * hw, D = degree_;
  const int top_even = D / 2, top_odd = (D - 1) / 2;  // degree_ >= 4: top_odd >= 1
  const double dx = 2.0 * pi / G;
  const auto wrap = [G](long point) {  // into [0, G); one addition for theta in [-pi, pi]
    if (point < 0) point += G;
    return point >= 0 && point < G ? point : (point % G + G) % G;
  };
  std::size_t k = 0;
  while (k < n) {
    // Up to `lanes` frequencies computed directly, each perhaps with its mirror.
    std::size_t index[lanes];
    bool mirrored[lanes];
    alignas(64) double s[lanes], u[lanes];
    std::size_t m = 0;
    for (; m < lanes && k < n; ++m) {
      const double x = theta[k] / dx, floor_x = std::floor(x);
      const long base = static_cast<long>(floor_x);
      index[m] = k;
      start[k] = wrap(base - hw + 1);
      s[m] = 2.0 * (x - floor_x) - 1.0;
      mirrored[m] = k + 1 < n && theta[k + 1] == -theta[k] && floor_x != x;
      if (mirrored[m]) start[k + 1] = wrap(-base - 1 - hw + 1);
      k += mirrored[m] ? 2 : 1;
    }
    for (std::size_t i = m; i < lanes; ++i) s[i] = 0.0;  // idle lanes
    for (std::size_t i = 0; i < lanes; ++i) u[i] = s[i] * s[i];
    for (int j = 0; j < hw; ++j) {
      const double* a = horner_.data() + j;  // a[p * hw]: tap j's coefficient of s^p
      alignas(64) double even[lanes], odd[lanes];
      for (std::size_t i = 0; i < lanes; ++i) {
        even[i] = a[2 * top_even * hw];
        odd[i] = a[(2 * top_odd + 1) * hw];
      }
      for (int p = top_odd - 1; p >= 0; --p) {  // top_even is top_odd or top_odd + 1
        const double ce = a[(2 * p + 2 + 2 * (top_even - top_odd - 1)) * hw], co = a[(2 * p + 1) * hw];
        for (std::size_t i = 0; i < lanes; ++i) {
          even[i] = even[i] * u[i] + ce;
          odd[i] = odd[i] * u[i] + co;
        }
      }
      if (top_even > top_odd)
        for (std::size_t i = 0; i < lanes; ++i) even[i] = even[i] * u[i] + a[0];
      for (std::size_t i = 0; i < m; ++i) {
        double* to = weight + index[i] * w * copies;
        const double low = even[i] + s[i] * odd[i], high = even[i] - s[i] * odd[i];
        for (int l = 0; l < copies; ++l) {
          to[j * copies + l] = low;
          to[(w - 1 - j) * copies + l] = high;
        }
      }
    }
    for (std::size_t i = 0; i < m; ++i)
      if (mirrored[i]) {
        const double* from = weight + index[i] * w * copies;
        double* to = weight + (index[i] + 1) * w * copies;
        for (int j = 0; j < w; ++j)
          for (int l = 0; l < copies; ++l) to[j * copies + l] = from[(w - 1 - j) * copies + l];
      }
  }
}

template void Nufft::kernel_windows<2>(const double*, std::size_t, long*, double*) const;
template void Nufft::kernel_windows<4>(const double*, std::size_t, long*, double*) const;

Nufft::PassScratch Nufft::make_pass_scratch(int series) const {
  if (series < 1 || series > 2)
    throw std::invalid_argument("Nufft: a pass of " + std::to_string(series) + " series (1 or 2)");
  if (series == 1 || !interleaved_) {
    PassScratch scratch{make_fftw_buffer<fftw_complex>(grid_), {}};
    for (int c = 0; c < 2 * series; ++c)
      scratch.grid.push_back(make_fftw_buffer<fftw_complex>(grid_ + 2 * half_width_));
    return scratch;
  }
  const std::size_t C = static_cast<std::size_t>(series);
  PassScratch scratch{make_fftw_buffer<fftw_complex>(C * grid_), {}};
  for (int g = 0; g < 2; ++g) scratch.grid.push_back(make_fftw_buffer<fftw_complex>(C * (grid_ + 2 * half_width_)));
  return scratch;
}

void Nufft::to_grids(const cplx* const* in, int series, fftw_complex* samples_buffer,
                             fftw_complex* grid_buffer) const {
  auto* samples = reinterpret_cast<cplx*>(samples_buffer);
  auto* grid = reinterpret_cast<cplx*>(grid_buffer);
  const int G = grid_, B = samples_, half = samples_ / 2, w = half_width_, C = series;
  for (int l = 0; l < C * G; ++l) samples[l] = 0.0;
  for (int t = 0; t < B; ++t) {
    const int shifted = t - half;
    const int at = C * (shifted < 0 ? shifted + G : shifted);
    for (int c = 0; c < C; ++c) samples[at + c] = in[c][t] * deconvolution_[t];
  }
  fftw_execute_dft(C == 1 ? forward_plan_.get() : pair_forward_plan_.get(), samples_buffer, grid_buffer);
  for (int j = 0; j < C * 2 * w; ++j) grid[C * G + j] = grid[j];
}

void Nufft::from_grids(fftw_complex* grid_buffer, int series, fftw_complex* samples_buffer,
                               cplx* const* out) const {
  auto* grid = reinterpret_cast<cplx*>(grid_buffer);
  const int G = grid_, B = samples_, half = samples_ / 2, w = half_width_, C = series;
  for (int j = 0; j < C * 2 * w; ++j) grid[j] += grid[C * G + j];  // fold the periodic copy back
  fftw_execute_dft(C == 1 ? backward_plan_.get() : pair_backward_plan_.get(), grid_buffer, samples_buffer);
  const auto* samples = reinterpret_cast<const cplx*>(samples_buffer);
  for (int t = 0; t < B; ++t) {
    const int shifted = t - half;
    const int at = C * (shifted < 0 ? shifted + G : shifted);
    for (int c = 0; c < C; ++c) out[c][t] += samples[at + c] * deconvolution_[t];
  }
}

void Nufft::to_grid(const cplx* in, fftw_complex* samples_buffer, fftw_complex* grid_buffer) const {
  auto* samples = reinterpret_cast<cplx*>(samples_buffer);
  auto* grid = reinterpret_cast<cplx*>(grid_buffer);
  const int G = grid_, B = samples_, half = samples_ / 2, w = half_width_;
  for (int l = 0; l < G; ++l) samples[l] = 0.0;
  // Deconvolve, centred on t' = t - B/2, so the kernel's spectrum is
  // symmetric over the samples and the amplification is smallest.
  for (int t = 0; t < B; ++t) {
    const int shifted = t - half;
    samples[shifted < 0 ? shifted + G : shifted] = in[t] * deconvolution_[t];
  }
  fftw_execute_dft(forward_plan_.get(), samples_buffer, grid_buffer);
  for (int j = 0; j < 2 * w; ++j) grid[G + j] = grid[j];
}

void Nufft::from_grid(fftw_complex* grid_buffer, fftw_complex* samples_buffer, cplx* out, bool add) const {
  auto* grid = reinterpret_cast<cplx*>(grid_buffer);
  const int G = grid_, B = samples_, half = samples_ / 2, w = half_width_;
  for (int j = 0; j < 2 * w; ++j) grid[j] += grid[G + j];  // fold the periodic copy back
  fftw_execute_dft(backward_plan_.get(), grid_buffer, samples_buffer);
  const auto* samples = reinterpret_cast<const cplx*>(samples_buffer);
  for (int t = 0; t < B; ++t) {
    const int shifted = t - half;
    const cplx value = samples[shifted < 0 ? shifted + G : shifted] * deconvolution_[t];
    out[t] = add ? out[t] + value : value;
  }
}

void Nufft::forward_centred(std::span<const cplx> in, std::span<cplx> out, Scratch& scratch) const {
  to_grid(in.data(), scratch.samples.get(), scratch.grid.get());
  const double* values = reinterpret_cast<const double*>(scratch.grid.get());
  const int w = half_width_;
  for (std::size_t k = 0; k < out.size(); ++k)
    out[k] = gather(values + 2 * scratch.window_start[k], scratch.weight.data() + k * 4 * w, w);
}

void Nufft::adjoint_centred(std::span<const cplx> c, std::span<cplx> out, Scratch& scratch) const {
  auto* grid = reinterpret_cast<cplx*>(scratch.grid.get());
  const int G = grid_, w = half_width_;
  for (int l = 0; l < G + 2 * w; ++l) grid[l] = 0.0;
  auto* values = reinterpret_cast<double*>(grid);
  for (std::size_t k = 0; k < c.size(); ++k)
    spread(c[k], values + 2 * scratch.window_start[k], scratch.weight.data() + k * 4 * w, w);
  from_grid(scratch.grid.get(), scratch.samples.get(), out.data(), false);
}

void Nufft::forward(std::span<const cplx> in, std::span<const double> theta,
                            std::span<cplx> out, Scratch& scratch) const {
  locate(theta, scratch);
  forward_centred(in, out.first(theta.size()), scratch);
  const int half = samples_ / 2;
  for (std::size_t k = 0; k < theta.size(); ++k) out[k] *= std::polar(1.0, -theta[k] * half);
}

void Nufft::adjoint(std::span<const double> theta, std::span<const cplx> c,
                            std::span<cplx> out, Scratch& scratch) const {
  locate(theta, scratch);
  const int half = samples_ / 2;
  std::vector<cplx>& phased = scratch.phased;
  phased.resize(c.size());
  for (std::size_t k = 0; k < c.size(); ++k) phased[k] = c[k] * std::polar(1.0, theta[k] * half);
  adjoint_centred(phased, out, scratch);
}

}  // namespace slipstrip
