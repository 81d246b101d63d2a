#pragma once
// Shared by the kernel tests: drive Fourier mode q = 1 of a history operator
// with a prescribed slip bump and record the shear-stress history.
#include <cmath>
#include <complex>
#include <numbers>
#include <vector>

#include "kernels/history_convolution.hpp"

namespace slipstrip::testing {

// Slip rate of the slip profile g(t) = sin^4(pi t / T) on [0, T] (C^3, so its
// Laplace transform decays like s^-5 and numerical inversions converge fast).
inline double bump_rate(double t, double T) {
  if (t <= 0 || t >= T) return 0;
  const double pi = std::numbers::pi;
  const double s = std::sin(pi * t / T), c = std::cos(pi * t / T);
  return 4 * s * s * s * c * pi / T;
}

// tau^_1(t_n) = -eta v_n - history_1(t_n), n = 0..steps, for v_n = bump_rate(n dt, rise)
// on mode q = 1 of `history` (which must have at least 2 modes).
inline std::vector<double> single_mode_stress(HistoryOperator& history, double rise, int steps) {
  const double dt = history.time_step();
  std::vector<std::complex<double>> spectrum(history.modes() + 1, 0.0);
  std::vector<double> stress(steps + 1);
  for (int n = 0; n <= steps; ++n) {
    const double v = bump_rate(n * dt, rise);
    // history() holds the history part at t_n built from v_0..v_{n-1}
    const std::complex<double> h = n == 0 ? std::complex<double>(0) : history.history()[1];
    stress[n] = (-history.radiation_damping() * v - h).real();
    spectrum[1] = v;
    history.push(spectrum);
  }
  return stress;
}

}  // namespace slipstrip::testing
