#include "kernels/fft.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace slipstrip {

FftwPlan owned_plan(fftw_plan plan, const char* who) {
  if (!plan) throw std::runtime_error(std::string(who) + ": FFTW planning failed");
  return FftwPlan(plan);
}

RealFft::RealFft(int nodes)
    : nodes_(nodes),
      real_(make_fftw_buffer<double>(nodes)),
      spectral_(make_fftw_buffer<fftw_complex>(nodes / 2 + 1)) {
  if (nodes < 2) throw std::invalid_argument("RealFft: nodes = " + std::to_string(nodes) + " must be >= 2");
  // FFTW_ESTIMATE, not FFTW_MEASURE: MEASURE picks the plan by timing it, so
  // two runs of the same config could use different plans and differ in the
  // last bits (issue 15: 8e-14 relative after ~30 steps).  ESTIMATE gives the
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

}  // namespace slipstrip
