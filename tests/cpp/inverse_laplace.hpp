#pragma once
// Numerical inverse Laplace transform for the kernel tests (an independent
// route to time-domain references): Durbin's Fourier-series method, evaluated
// with an FFT.
#include <fftw3.h>

#include <cmath>
#include <complex>
#include <numbers>
#include <vector>

namespace slipstrip::testing {

// f(t_j), t_j = j dt, j < count, from its Laplace transform F by Durbin's
// formula with period 2 T_p = K dt:
//   f(t) = e^{sigma t}/T_p [ -F(sigma)/2 + Re sum_{k<K} F(sigma + i k pi/T_p) e^{i k pi t/T_p} ].
// The aliasing error is ~ e^{-2 sigma T_p} |f|max; sigma T_p = 12 gives ~4e-11
// times the growth-free amplitude of f.  The truncation at K terms is accurate
// when F decays fast (callers subtract slowly decaying parts they know in
// closed form).  Keep t_j <= T_p so that e^{sigma t} does not amplify rounding.
template <class F>
std::vector<double> inverse_laplace(F&& transform, double dt, int K, int count) {
  constexpr double pi = std::numbers::pi;
  const double Tp = 0.5 * K * dt;
  const double sigma = 12.0 / Tp;
  std::vector<fftw_complex> buf(K);
  for (int k = 0; k < K; ++k) {
    const std::complex<double> v = transform(std::complex<double>(sigma, k * pi / Tp));
    buf[k][0] = v.real();
    buf[k][1] = v.imag();
  }
  const double f0 = transform(std::complex<double>(sigma, 0)).real();
  fftw_plan plan = fftw_plan_dft_1d(K, buf.data(), buf.data(), FFTW_BACKWARD, FFTW_ESTIMATE);
  fftw_execute(plan);
  fftw_destroy_plan(plan);
  std::vector<double> f(count);
  for (int j = 0; j < count; ++j) f[j] = std::exp(sigma * j * dt) / Tp * (buf[j][0] - 0.5 * f0);
  return f;
}

}  // namespace slipstrip::testing
