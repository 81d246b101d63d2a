#pragma once
// The oblique Fourier mode (q_x, q_z) = (1, 1) of a square grid on a 2D
// interface, seeded in the state and recorded from the slip rates: the growth
// rates measured against linear stability (test_solver_interface_2d for
// identical bodies, test_solver_interface_2d_bodies for a dissimilar pair).
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstddef>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "config/simulation_config.hpp"
#include "friction/friction_law.hpp"
#include "kernels/fft.hpp"
#include "solver/simulation_3d.hpp"

namespace slipstrip::testing {

// phi = phi_ss (1 + eps cos(2 pi (ix + iz) / n)) on the n x n grid of `c`:
// the modes (1, 1) and (-1, -1) only.
inline std::vector<double> oblique_mode_state(const SimulationConfig& c, double eps) {
  const int n = c.geometry.nodes;
  if (c.geometry.nodes_z != n) throw std::invalid_argument("oblique_mode_state: a square grid");
  const double phi_ss = steady_state(c.friction, c.loading.driving_velocity);
  std::vector<double> phi(static_cast<std::size_t>(n) * n);
  for (int iz = 0; iz < n; ++iz)
    for (int ix = 0; ix < n; ++ix)
      phi[iz * n + ix] = phi_ss * (1 + eps * std::cos(2 * std::numbers::pi * (ix + iz) / static_cast<double>(n)));
  return phi;
}

// Complex amplitudes c(t_n) = (2/N) FFT[(1, 1)] / v0 of v_x - v0 and of v_z:
// the coefficients of exp(+i (kx x + kz z)), ~ exp(Lambda t) with the roots at
// (kx, kz).  Taken before each of up to `steps` steps; the record stops where
// max |v_x - v0| exceeds 1e-2 v0 (the linear regime ends).
struct ObliqueModeRecord {
  std::vector<std::complex<double>> x, z;
};
inline ObliqueModeRecord record_oblique_mode(Simulation3d& sim, const SimulationConfig& c, long long steps) {
  const int nx = c.geometry.nodes, nz = c.geometry.nodes_z;
  const double v0 = c.loading.driving_velocity;
  RealFft2d fft(nx, nz);
  std::vector<double> field(static_cast<std::size_t>(nx) * nz);
  std::vector<std::complex<double>> spectrum(fft.modes());
  const std::size_t mode = 1 * (nx / 2 + 1) + 1;
  ObliqueModeRecord record;
  for (long long n = 0; n < steps; ++n) {
    double largest = 0.0;
    for (std::size_t i = 0; i < field.size(); ++i) {
      field[i] = sim.slip_rate_x()[i] - v0;
      largest = std::max(largest, std::abs(field[i]) / v0);
    }
    if (largest > 1e-2) break;
    fft.forward(field, spectrum);
    record.x.push_back(2.0 / field.size() * spectrum[mode] / v0);
    fft.forward(sim.slip_rate_z(), spectrum);
    record.z.push_back(2.0 / field.size() * spectrum[mode] / v0);
    sim.step();
  }
  return record;
}

}  // namespace slipstrip::testing
