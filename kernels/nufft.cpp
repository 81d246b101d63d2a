#include "kernels/nufft.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace slipstrip {
namespace {
constexpr double pi = std::numbers::pi;
using cplx = std::complex<double>;

// Grid coordinate of a frequency: theta = (base + frac) dx, base integer.
struct GridPosition {
  long base;
  double offset;  // theta - base dx, in [0, dx)
};
GridPosition locate_on_grid(double theta, double dx) {
  const double u = theta / dx;
  const double base = std::floor(u);
  return {static_cast<long>(base), theta - base * dx};
}
}  // namespace

GaussianNufft::GaussianNufft(int samples, int half_width)
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
}

GaussianNufft::Scratch GaussianNufft::make_scratch(std::size_t frequencies) const {
  // The grid is followed by a copy of its first 2w points, so that every
  // frequency's window is one contiguous (vectorisable) run.
  return {make_fftw_buffer<fftw_complex>(grid_ + 2 * half_width_), make_fftw_buffer<fftw_complex>(grid_),
          std::vector<long>(frequencies), std::vector<double>(frequencies * 2 * half_width_), {}};
}

// Gaussian weights of the 2w grid points base-w+1 .. base+w around each
// frequency, by fast Gaussian gridding: exp(-(d - j dx)^2/4T) =
// exp(-d^2/4T) * exp(d dx/2T)^j * exp(-(j dx)^2/4T), two exponentials per frequency.
void GaussianNufft::locate(std::span<const double> theta, Scratch& scratch) const {
  if (theta.size() > scratch.window_start.size())
    throw std::invalid_argument("GaussianNufft: scratch holds " +
                                std::to_string(scratch.window_start.size()) + " frequencies, " +
                                std::to_string(theta.size()) + " given");
  const int G = grid_, w = half_width_;
  const double dx = 2.0 * pi / G;
  for (std::size_t k = 0; k < theta.size(); ++k) {
    const auto [base, offset] = locate_on_grid(theta[k], dx);
    scratch.window_start[k] = ((base - w + 1) % G + G) % G;
    double* out = scratch.weight.data() + k * 2 * w;
    const double e1 = std::exp(-offset * offset / (4.0 * variance_));
    const double e2 = std::exp(offset * dx / (2.0 * variance_));
    const double inv_e2 = 1.0 / e2;
    double up = e1;
    for (int j = 0; j <= w; ++j) {  // points base + j
      out[w - 1 + j] = up * tail_[j];
      up *= e2;
    }
    double down = e1;
    for (int j = 1; j < w; ++j) {  // points base - j
      down *= inv_e2;
      out[w - 1 - j] = down * tail_[j];
    }
  }
}

void GaussianNufft::forward_centred(std::span<const cplx> in, std::span<cplx> out,
                                    Scratch& scratch) const {
  auto* samples = reinterpret_cast<cplx*>(scratch.samples.get());
  auto* grid = reinterpret_cast<cplx*>(scratch.grid.get());
  const int G = grid_, B = samples_, half = samples_ / 2, w = half_width_;
  for (int l = 0; l < G; ++l) samples[l] = 0.0;
  // Deconvolve, centred on t' = t - B/2, so the Gaussian's spectrum is
  // symmetric over the samples and the amplification is smallest.
  for (int t = 0; t < B; ++t) {
    const int shifted = t - half;
    samples[shifted < 0 ? shifted + G : shifted] = in[t] * deconvolution_[t];
  }
  fftw_execute_dft(forward_plan_.get(), scratch.samples.get(), scratch.grid.get());
  for (int j = 0; j < 2 * w; ++j) grid[G + j] = grid[j];
  const double* values = reinterpret_cast<const double*>(grid);
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
  const int G = grid_, B = samples_, half = samples_ / 2, w = half_width_;
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
  for (int j = 0; j < 2 * w; ++j) grid[j] += grid[G + j];  // fold the periodic copy back
  fftw_execute_dft(backward_plan_.get(), scratch.grid.get(), scratch.samples.get());
  const auto* samples = reinterpret_cast<const cplx*>(scratch.samples.get());
  for (int t = 0; t < B; ++t) {
    const int shifted = t - half;
    out[t] = samples[shifted < 0 ? shifted + G : shifted] * deconvolution_[t];
  }
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
