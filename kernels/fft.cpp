#include "kernels/fft.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "simd/parallel_for.hpp"

namespace slipstrip {

FftwPlan owned_plan(fftw_plan plan, const char* who) {
  if (!plan) throw std::runtime_error(std::string(who) + ": FFTW planning failed");
  return FftwPlan(plan);
}

FftwPlan complex_dft_plan(int n, int sign, const char* who) {
  auto in = make_fftw_buffer<fftw_complex>(n);
  auto out = make_fftw_buffer<fftw_complex>(n);
  return owned_plan(fftw_plan_dft_1d(n, in.get(), out.get(), sign, FFTW_ESTIMATE), who);
}

FftwPlan interleaved_dft_plan(int n, int howmany, int sign, const char* who) {
  auto in = make_fftw_buffer<fftw_complex>(static_cast<std::size_t>(n) * howmany);
  auto out = make_fftw_buffer<fftw_complex>(static_cast<std::size_t>(n) * howmany);
  return owned_plan(fftw_plan_many_dft(1, &n, howmany, in.get(), nullptr, howmany, 1, out.get(), nullptr, howmany, 1,
                                       sign, FFTW_ESTIMATE),
                    who);
}

FftwPlan strided_pair_dft_plan(int n, int in_stride, int in_dist, int out_stride, int out_dist, int sign,
                               const char* who) {
  const auto extent = [n](int stride, int dist) {
    return static_cast<std::size_t>(n - 1) * stride + static_cast<std::size_t>(dist) + 1;
  };
  auto in = make_fftw_buffer<fftw_complex>(extent(in_stride, in_dist));
  auto out = make_fftw_buffer<fftw_complex>(extent(out_stride, out_dist));
  return owned_plan(fftw_plan_many_dft(1, &n, 2, in.get(), nullptr, in_stride, in_dist, out.get(), nullptr,
                                       out_stride, out_dist, sign, FFTW_ESTIMATE),
                    who);
}

RealFft::RealFft(int nodes)
    : nodes_(nodes),
      real_(make_fftw_buffer<double>(nodes)),
      spectral_(make_fftw_buffer<fftw_complex>(nodes / 2 + 1)) {
  if (nodes < 2) throw std::invalid_argument("RealFft: nodes = " + std::to_string(nodes) + " must be >= 2");
  // FFTW_ESTIMATE, not FFTW_MEASURE: MEASURE picks the plan by timing it, so
  // two runs of the same config could use different plans and differ in the
  // last bits (measured: 8e-14 relative after ~30 steps).  ESTIMATE gives the
  // same plan every time; measured cost in docs/reliability.md.
  forward_plan_ = owned_plan(fftw_plan_dft_r2c_1d(nodes, real_.get(), spectral_.get(), FFTW_ESTIMATE),
                             "RealFft");
  inverse_plan_ = owned_plan(fftw_plan_dft_c2r_1d(nodes, spectral_.get(), real_.get(), FFTW_ESTIMATE),
                             "RealFft");
}

void RealFft::forward(std::span<const double> in, std::span<std::complex<double>> out) {
  std::copy(in.begin(), in.end(), real_.get());
  fftw_execute(forward_plan_.get());
  const auto* s = reinterpret_cast<const std::complex<double>*>(spectral_.get());
  std::copy(s, s + modes(), out.begin());
}

void RealFft::inverse(std::span<const std::complex<double>> in, std::span<double> out) {
  // c2r destroys its input, so transform a copy held in our own buffer.
  std::copy(in.begin(), in.end(), reinterpret_cast<std::complex<double>*>(spectral_.get()));
  fftw_execute(inverse_plan_.get());
  const double scale = 1.0 / nodes_;
  for (int j = 0; j < nodes_; ++j) out[j] = real_[j] * scale;
}

RealFft2d::RealFft2d(int nodes_x, int nodes_z) : nodes_x_(nodes_x), nodes_z_(nodes_z) {
  if (nodes_x < 1 || nodes_z < 1)
    throw std::invalid_argument("RealFft2d: nodes_x = " + std::to_string(nodes_x) + ", nodes_z = " +
                                std::to_string(nodes_z) + " must both be >= 1");
  for (int k = 0; k < 2; ++k) {
    real_[k] = make_fftw_buffer<double>(static_cast<std::size_t>(nodes_x) * nodes_z);
    spectral_[k] = make_fftw_buffer<fftw_complex>(static_cast<std::size_t>(nodes_x / 2 + 1) * nodes_z);
  }
  // FFTW_ESTIMATE for reproducible plans (see RealFft).
  forward_plan_ = owned_plan(
      fftw_plan_dft_r2c_2d(nodes_z, nodes_x, real_[0].get(), spectral_[0].get(), FFTW_ESTIMATE), "RealFft2d");
  inverse_plan_ = owned_plan(
      fftw_plan_dft_c2r_2d(nodes_z, nodes_x, spectral_[0].get(), real_[0].get(), FFTW_ESTIMATE), "RealFft2d");
}

void RealFft2d::forward_with(int buffers, std::span<const double> in, std::span<std::complex<double>> out) {
  double* real = real_[buffers].get();
  fftw_complex* spectral = spectral_[buffers].get();
  std::copy(in.begin(), in.end(), real);
  // The new-array execute: both sets are fftw_malloc'd, so they have the
  // alignment the plan was made for.
  fftw_execute_dft_r2c(forward_plan_.get(), real, spectral);
  const auto* s = reinterpret_cast<const std::complex<double>*>(spectral);
  std::copy(s, s + modes(), out.begin());
}

void RealFft2d::inverse_with(int buffers, std::span<const std::complex<double>> in, std::span<double> out) {
  double* real = real_[buffers].get();
  fftw_complex* spectral = spectral_[buffers].get();
  // c2r destroys its input: transform a copy in our own buffer.
  std::copy(in.begin(), in.end(), reinterpret_cast<std::complex<double>*>(spectral));
  fftw_execute_dft_c2r(inverse_plan_.get(), spectral, real);
  const double scale = 1.0 / static_cast<double>(nodes());
  for (std::size_t j = 0; j < nodes(); ++j) out[j] = real[j] * scale;
}

void RealFft2d::forward(std::span<const double> in, std::span<std::complex<double>> out) {
  forward_with(0, in, out);
}

void RealFft2d::inverse(std::span<const std::complex<double>> in, std::span<double> out) {
  inverse_with(0, in, out);
}

void RealFft2d::forward_pair(std::span<const double> in_a, std::span<std::complex<double>> out_a,
                             std::span<const double> in_b, std::span<std::complex<double>> out_b) {
  simd::parallel_for(
      2, [&](long long k) { forward_with(static_cast<int>(k), k == 0 ? in_a : in_b, k == 0 ? out_a : out_b); }, 1);
}

void RealFft2d::inverse_pair(std::span<const std::complex<double>> in_a, std::span<double> out_a,
                             std::span<const std::complex<double>> in_b, std::span<double> out_b) {
  simd::parallel_for(
      2, [&](long long k) { inverse_with(static_cast<int>(k), k == 0 ? in_a : in_b, k == 0 ? out_a : out_b); }, 1);
}

}  // namespace slipstrip
