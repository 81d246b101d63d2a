#include "laws/initial_state.hpp"

#include "laws/portable_normal.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace slipstrip {
namespace {

constexpr double pi = std::numbers::pi;

// Standard-normal noise per node, or the band-limited field of noise_modes
// modes with unit pointwise variance: sum_k (c_k cos + s_k sin)(2 pi k x/L) / sqrt(M)
// has variance (1/M) sum_k (cos^2 + sin^2) = 1 at every x.  The coefficients are
// drawn before any node is visited, in the order of k, so they do not depend on N.
std::vector<double> unit_noise(const InitialConfig& init, std::span<const double> x, double length) {
  std::vector<double> noise(x.size());
  PortableNormal normal(init.noise_seed);
  if (init.noise_modes == 0) {
    for (double& value : noise) value = normal();
    return noise;
  }
  const auto modes = static_cast<std::size_t>(init.noise_modes);
  std::vector<double> cosine(modes), sine(modes);
  for (std::size_t k = 0; k < modes; ++k) {
    cosine[k] = normal();
    sine[k] = normal();
  }
  const double scale = 1.0 / std::sqrt(static_cast<double>(modes));
  for (std::size_t i = 0; i < x.size(); ++i) {
    double sum = 0.0;
    for (std::size_t k = 0; k < modes; ++k) {
      const double phase = 2.0 * pi * static_cast<double>(k + 1) * x[i] / length;
      sum += cosine[k] * std::cos(phase) + sine[k] * std::sin(phase);
    }
    noise[i] = scale * sum;
  }
  return noise;
}

}  // namespace

std::vector<double> perturbed_steady_state(const InitialConfig& init, std::span<const double> x,
                                           double length, std::span<const double> phi_ss) {
  return perturbed_steady_state(init, x, {}, length, 0.0, phi_ss);
}

std::vector<double> perturbed_steady_state(const InitialConfig& init, std::span<const double> x,
                                           std::span<const double> z, double length, double width,
                                           std::span<const double> phi_ss) {
  const bool patch = init.local_width_z > 0.0 && !z.empty();
  const std::vector<double> noise =
      init.noise_amplitude != 0.0 ? unit_noise(init, x, length) : std::vector<double>(x.size(), 0.0);
  std::vector<double> state(x.size());
  // The terms are added in this order, each as phi_ss * amplitude * shape, so
  // runs made before this function existed are reproduced bit for bit.
  for (std::size_t i = 0; i < x.size(); ++i) {
    double phi = phi_ss[i];
    if (init.noise_amplitude != 0.0) phi += phi_ss[i] * init.noise_amplitude * noise[i];
    if (init.sine_amplitude != 0.0)
      phi += phi_ss[i] * init.sine_amplitude * std::sin(2.0 * pi * init.sine_mode * x[i] / length + pi / 2.0);
    if (init.local_amplitude != 0.0 && init.local_width > 0.0) {
      const double d = std::remainder(x[i] - init.local_center, length);  // periodic distance to the centre
      double shape = std::exp(-0.5 * (d / init.local_width) * (d / init.local_width));
      if (patch) {
        const double dz = std::remainder(z[i] - init.local_center_z, width);
        shape *= std::exp(-0.5 * (dz / init.local_width_z) * (dz / init.local_width_z));
      }
      phi += phi_ss[i] * init.local_amplitude * shape;
    }
    if (!(phi > 0.0))
      throw std::invalid_argument(
          "initial state phi <= 0 at x = " + std::to_string(x[i]) +
          " m: reduce initial.noise_amplitude, initial.sine_amplitude or initial.local_amplitude");
    state[i] = phi;
  }
  return state;
}

}  // namespace slipstrip
