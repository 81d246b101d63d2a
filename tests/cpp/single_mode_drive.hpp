#pragma once
// Shared by the kernel tests: drive Fourier mode q = 1 of a history operator
// with a prescribed slip bump and record the shear-stress history.
#include <cmath>
#include <complex>
#include <numbers>
#include <vector>

#include "kernels/elastic_material.hpp"
#include "kernels/history_convolution.hpp"

namespace slipstrip::testing {

// A material with another plane condition: the rotated 2D-interface tests drive
// the in-plane and antiplane operators of one material.
inline ElasticMaterial with_plane(ElasticMaterial m, PlaneCondition plane) {
  m.plane = plane;
  return m;
}

// Slip rate of the slip profile g(t) = sin^4(pi t / T) on [0, T] (C^3, so its
// Laplace transform decays like s^-5 and numerical inversions converge fast).
inline double bump_rate(double t, double T) {
  if (t <= 0 || t >= T) return 0;
  const double pi = std::numbers::pi;
  const double s = std::sin(pi * t / T), c = std::cos(pi * t / T);
  return 4 * s * s * s * c * pi / T;
}

// Laplace transform of that slip profile: sin^4 x = 3/8 - cos(2x)/2 + cos(4x)/8,
// and int_0^T e^{-st} cos(w t) dt = s (1 - e^{-sT}) / (s^2 + w^2) when w T is a
// multiple of 2 pi.
inline std::complex<double> bump_laplace(std::complex<double> s, double T) {
  const double pi = std::numbers::pi;
  const double w1 = 2 * pi / T, w2 = 4 * pi / T;
  return (1.0 - std::exp(-s * T)) *
         (3.0 / (8.0 * s) - s / (2.0 * (s * s + w1 * w1)) + s / (8.0 * (s * s + w2 * w2)));
}

// |a - b|_2 / |b|_2 over the first `count` samples (all of them if count < 0).
inline double relative_l2_difference(const std::vector<double>& a, const std::vector<double>& b,
                                      long count = -1) {
  const std::size_t n = count < 0 ? b.size() : static_cast<std::size_t>(count);
  double num = 0, den = 0;
  for (std::size_t i = 0; i < n; ++i) {
    num += (a[i] - b[i]) * (a[i] - b[i]);
    den += b[i] * b[i];
  }
  return std::sqrt(num / den);
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

// Free ringing of mode q after a short smooth load pulse (sin^4 over `pulse`
// steps, amplitude 1e6 Pa): a free interface, eta v_n = load_n - history_q(t_n).
// Returns the mean square of v_n over consecutive windows of `window` steps.
inline std::vector<double> free_ringing_mean_square(HistoryOperator& op, int q, int steps, int window,
                                                    int pulse) {
  const double pi = std::numbers::pi;
  const double eta = op.radiation_damping();
  std::vector<std::complex<double>> spectrum(op.modes(), 0.0);
  std::vector<double> mean_square(steps / window, 0.0);
  for (int n = 0; n < steps; ++n) {
    const double load = n < pulse ? std::pow(std::sin(pi * n / pulse), 4) * 1e6 : 0.0;
    const double history = n == 0 ? 0.0 : op.history()[q].real();
    const double v = (load - history) / eta;
    mean_square[n / window] += v * v / window;
    spectrum[q] = v;
    op.push(spectrum);
  }
  return mean_square;
}

}  // namespace slipstrip::testing
