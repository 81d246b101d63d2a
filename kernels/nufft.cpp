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

GaussianNufft::GaussianNufft(int samples, int half_width, int interleave_from)
    : samples_(samples), grid_(2 * samples), half_width_(half_width) {
  if (samples < 2 || samples % 2 != 0)
    throw std::invalid_argument("GaussianNufft: samples = " + std::to_string(samples) +
                                " must be even and >= 2");
  if (half_width < 2 || half_width > max_half_width || 2 * half_width > grid_)
    throw std::invalid_argument("GaussianNufft: half_width = " + std::to_string(half_width) +
                                " must be in [2, min(samples, " + std::to_string(max_half_width) +
                                ")]");
  const double B = samples_;
  // Truncation error exp(-(w dx)^2 / 4T) = aliasing error exp(-T G (G - B))
  // with G = 2B, dx = 2 pi / G  =>  T = w pi / (2 sqrt2 B^2).
  variance_ = half_width_ * pi / (2.0 * std::numbers::sqrt2 * B * B);
  deconvolution_.resize(samples_);
  for (int t = 0; t < samples_; ++t) {
    const double n = t - samples_ / 2;
    const double ghat = std::sqrt(variance_ / pi) * std::exp(-n * n * variance_);
    deconvolution_[t] = 1.0 / (grid_ * ghat);
  }
  const double dx = 2.0 * pi / grid_;
  tail_.resize(half_width_ + 1);
  for (int j = 0; j <= half_width_; ++j) tail_[j] = std::exp(-(j * dx) * (j * dx) / (4.0 * variance_));
  forward_plan_ = complex_dft_plan(grid_, FFTW_FORWARD, "GaussianNufft");
  backward_plan_ = complex_dft_plan(grid_, FFTW_BACKWARD, "GaussianNufft");
  interleaved_ = grid_ >= interleave_from;
  if (interleaved_) {
    pair_forward_plan_ = interleaved_dft_plan(grid_, 2, FFTW_FORWARD, "GaussianNufft");
    pair_backward_plan_ = interleaved_dft_plan(grid_, 2, FFTW_BACKWARD, "GaussianNufft");
  }
}

GaussianNufft::Scratch GaussianNufft::make_scratch(std::size_t frequencies) const {
  // The grid is followed by a copy of its first 2w points, so that every
  // frequency's window is one contiguous (vectorisable) run.
  return {make_fftw_buffer<fftw_complex>(grid_ + 2 * half_width_), make_fftw_buffer<fftw_complex>(grid_),
          std::vector<long>(frequencies), std::vector<double>(frequencies * 2 * half_width_), {}};
}

void GaussianNufft::locate(std::span<const double> theta, Scratch& scratch) const {
  if (theta.size() > scratch.window_start.size())
    throw std::invalid_argument("GaussianNufft: scratch holds " +
                                std::to_string(scratch.window_start.size()) + " frequencies, " +
                                std::to_string(theta.size()) + " given");
  gaussian_windows(theta.data(), theta.size(), scratch.window_start.data(), scratch.weight.data());
}

// Gaussian weights of the 2w grid points base-w+1 .. base+w around each
// frequency, by fast Gaussian gridding: exp(-(d - j dx)^2/4T) =
// exp(-d^2/4T) * exp(d dx/2T)^j * exp(-(j dx)^2/4T), two exponentials per
// frequency.  Lanes of frequencies side by side: one frequency's powers are a
// chain of dependent products, several frequencies' chains overlap.
//
// A frequency followed by its negative (the block operators list each normal
// mode as +phi, -phi) shares its window mirrored: with theta = (u + d/dx) dx,
// 0 < d < dx, -theta has base -u-1 and offset dx - d, so its weight at point
// -u-1+j is exp(-(d - (1-j) dx)^2/4T), theta's at u+1-j: its 2w weights are
// theta's in reverse order.  The pair's exponentials and products are
// computed once (the mirrored weights equal the directly computed ones to
// rounding; the windows' first points are the same integers).  A frequency on
// a grid point (d = 0) has no mirror of this form and is computed directly.
void GaussianNufft::gaussian_windows(const double* theta, std::size_t n, long* start, double* weight) const {
  constexpr std::size_t lanes = 8;
  const int G = grid_, w = half_width_;
  const double dx = 2.0 * pi / G;
  std::size_t k = 0;
  while (k < n) {
    // Up to `lanes` frequencies computed directly, each perhaps with its mirror.
    std::size_t index[lanes];
    bool mirrored[lanes];
    double up[lanes], down[lanes], e2[lanes], inv_e2[lanes];
    std::size_t m = 0;
    for (; m < lanes && k < n; ++m) {
      const double u = std::floor(theta[k] / dx);
      const long base = static_cast<long>(u);
      const double offset = theta[k] - u * dx;  // in [0, dx)
      index[m] = k;
      start[k] = ((base - w + 1) % G + G) % G;
      up[m] = down[m] = std::exp(-offset * offset / (4.0 * variance_));
      e2[m] = std::exp(offset * dx / (2.0 * variance_));
      inv_e2[m] = 1.0 / e2[m];
      mirrored[m] = k + 1 < n && theta[k + 1] == -theta[k] && u != theta[k] / dx;
      if (mirrored[m]) start[k + 1] = ((-base - 1 - w + 1) % G + G) % G;
      k += mirrored[m] ? 2 : 1;
    }
    for (int j = 0; j <= w; ++j)  // points base + j
      for (std::size_t i = 0; i < m; ++i) {
        weight[index[i] * 2 * w + w - 1 + j] = up[i] * tail_[j];
        up[i] *= e2[i];
      }
    for (int j = 1; j < w; ++j)  // points base - j
      for (std::size_t i = 0; i < m; ++i) {
        down[i] *= inv_e2[i];
        weight[index[i] * 2 * w + w - 1 - j] = down[i] * tail_[j];
      }
    for (std::size_t i = 0; i < m; ++i)
      if (mirrored[i]) {
        const double* from = weight + index[i] * 2 * w;
        double* to = weight + (index[i] + 1) * 2 * w;
        for (int j = 0; j < 2 * w; ++j) to[j] = from[2 * w - 1 - j];
      }
  }
}

GaussianNufft::PassScratch GaussianNufft::make_pass_scratch(int series) const {
  if (series < 1 || series > 2)
    throw std::invalid_argument("GaussianNufft: a pass of " + std::to_string(series) + " series (1 or 2)");
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

void GaussianNufft::to_grids(const cplx* const* in, int series, fftw_complex* samples_buffer,
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

void GaussianNufft::from_grids(fftw_complex* grid_buffer, int series, fftw_complex* samples_buffer,
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

void GaussianNufft::to_grid(const cplx* in, fftw_complex* samples_buffer, fftw_complex* grid_buffer) const {
  auto* samples = reinterpret_cast<cplx*>(samples_buffer);
  auto* grid = reinterpret_cast<cplx*>(grid_buffer);
  const int G = grid_, B = samples_, half = samples_ / 2, w = half_width_;
  for (int l = 0; l < G; ++l) samples[l] = 0.0;
  // Deconvolve, centred on t' = t - B/2, so the Gaussian's spectrum is
  // symmetric over the samples and the amplification is smallest.
  for (int t = 0; t < B; ++t) {
    const int shifted = t - half;
    samples[shifted < 0 ? shifted + G : shifted] = in[t] * deconvolution_[t];
  }
  fftw_execute_dft(forward_plan_.get(), samples_buffer, grid_buffer);
  for (int j = 0; j < 2 * w; ++j) grid[G + j] = grid[j];
}

void GaussianNufft::from_grid(fftw_complex* grid_buffer, fftw_complex* samples_buffer, cplx* out, bool add) const {
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

void GaussianNufft::forward_centred(std::span<const cplx> in, std::span<cplx> out,
                                    Scratch& scratch) const {
  to_grid(in.data(), scratch.samples.get(), scratch.grid.get());
  const double* values = reinterpret_cast<const double*>(scratch.grid.get());
  const int w = half_width_;
  for (std::size_t k = 0; k < out.size(); ++k) {
    const double* window = values + 2 * scratch.window_start[k];
    const double* weight = scratch.weight.data() + k * 2 * w;
    double re = 0.0, im = 0.0;
    for (int j = 0; j < 2 * w; ++j) {
      re += window[2 * j] * weight[j];
      im += window[2 * j + 1] * weight[j];
    }
    out[k] = cplx(re, im);
  }
}

void GaussianNufft::adjoint_centred(std::span<const cplx> c, std::span<cplx> out,
                                    Scratch& scratch) const {
  auto* grid = reinterpret_cast<cplx*>(scratch.grid.get());
  const int G = grid_, w = half_width_;
  for (int l = 0; l < G + 2 * w; ++l) grid[l] = 0.0;
  auto* values = reinterpret_cast<double*>(grid);
  for (std::size_t k = 0; k < c.size(); ++k) {
    double* window = values + 2 * scratch.window_start[k];
    const double* weight = scratch.weight.data() + k * 2 * w;
    const double re = c[k].real(), im = c[k].imag();
    for (int j = 0; j < 2 * w; ++j) {
      window[2 * j] += re * weight[j];
      window[2 * j + 1] += im * weight[j];
    }
  }
  from_grid(scratch.grid.get(), scratch.samples.get(), out.data(), false);
}

void GaussianNufft::forward(std::span<const cplx> in, std::span<const double> theta,
                            std::span<cplx> out, Scratch& scratch) const {
  locate(theta, scratch);
  forward_centred(in, out.first(theta.size()), scratch);
  const int half = samples_ / 2;
  for (std::size_t k = 0; k < theta.size(); ++k) out[k] *= std::polar(1.0, -theta[k] * half);
}

void GaussianNufft::adjoint(std::span<const double> theta, std::span<const cplx> c,
                            std::span<cplx> out, Scratch& scratch) const {
  locate(theta, scratch);
  const int half = samples_ / 2;
  std::vector<cplx>& phased = scratch.phased;
  phased.resize(c.size());
  for (std::size_t k = 0; k < c.size(); ++k) phased[k] = c[k] * std::polar(1.0, theta[k] * half);
  adjoint_centred(phased, out, scratch);
}

}  // namespace slipstrip
