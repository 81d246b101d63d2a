// The solver of a 2D interface between 3D bodies (solver/simulation_3d.hpp,
// docs/3d.md) against independent references:
//   (a) a field independent of z = the 2D plane-strain solver (round-off);
//   (b) a field independent of x, slip along x = the 2D antiplane solver (round-off);
//   (c) the z -> -z mirror symmetry and translation invariance in x and z (round-off);
//   (d) growth rate of an oblique mode = the roots of the 2x2 oblique
//       characteristic function (stability/oblique_stability.hpp) within 2 %.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <vector>

#include "friction/friction_law.hpp"
#include "kernels/block_strip_history.hpp"
#include "kernels/fft.hpp"
#include "solver/simulation.hpp"
#include "solver/simulation_3d.hpp"
#include "stability/oblique_stability.hpp"
#include "stability/steady_sliding.hpp"
#include "field_test_helpers.hpp"
#include "oblique_mode.hpp"
#include "solver_test_configs.hpp"

using namespace slipstrip;
constexpr double pi = std::numbers::pi;

namespace {

// Table S1 defaults, a short strip pair, a few nodes.
SimulationConfig small_config(double length, int nodes) { return testing::short_strip_pair(length, nodes, 0.25); }

}  // namespace

namespace {
// (a) with the strip history operators of `history` in both solvers.
void check_z_independent_equals_plane_strain(HistoryAlgorithm history) {
  SimulationConfig c2 = small_config(0.8, 32);
  c2.time.history = history;
  testing::add_large_perturbation(c2, 0.3);
  Simulation flat(c2);
  for (int nodes_z : {1, 4}) {
    SimulationConfig c3 = c2;
    c3.geometry.nodes_z = nodes_z;
    c3.geometry.width = nodes_z * c2.geometry.length / c2.geometry.nodes;  // dz = dx
    Simulation3d sim(c3);
    REQUIRE(sim.time_step() == flat.time_step());
  }
  SimulationConfig c3 = c2;
  c3.geometry.nodes_z = 4;
  c3.geometry.width = 0.1;
  Simulation3d sim(c3);
  REQUIRE(sim.time_step() == flat.time_step());
  const bool block = history == HistoryAlgorithm::block;
  REQUIRE((dynamic_cast<const BlockStripHistory*>(&flat.history_operator()) != nullptr) == block);
  REQUIRE((dynamic_cast<const BlockStripHistory*>(&sim.history_operator().inplane()) != nullptr) == block);
  const double v0 = c2.loading.driving_velocity;
  double worst_x = 0.0, worst_z = 0.0, worst_phi = 0.0, largest = 0.0;
  for (int n = 0; n < 600; ++n) {
    for (int iz = 0; iz < 4; ++iz)
      for (int ix = 0; ix < 32; ++ix) {
        const std::size_t i = iz * 32 + ix;
        worst_x = std::max(worst_x, std::abs(sim.slip_rate_x()[i] - flat.slip_rate()[ix]));
        worst_z = std::max(worst_z, std::abs(sim.slip_rate_z()[i]));
        worst_phi = std::max(worst_phi, std::abs(sim.state()[i] - flat.state()[ix]) / flat.state()[ix]);
      }
    largest = std::max(largest, max_abs(flat.slip_rate()));
    flat.step();
    sim.step();
  }
  MESSAGE("max |v| = " << largest / v0 << " v0; max |v_x - v_2D| = " << worst_x / largest
                       << " max|v|, max |v_z| = " << worst_z / largest << ", max rel. state diff " << worst_phi);
  REQUIRE(largest > 2 * v0);  // the run is nonlinear, not a trivially small perturbation
  // Only the FFTs differ (a 2D transform of identical rows against a 1-D one):
  // rounding of ~1e-16 relative per step, carried by 600 steps of a growing
  // perturbation; 1e-11 is 1e5 times the unit round-off.
  CHECK(worst_x <= 1e-11 * largest);
  CHECK(worst_z <= 1e-11 * largest);
  CHECK(worst_phi <= 1e-11);
}
}  // namespace

TEST_CASE("2D interface, field independent of z = the 2D plane-strain solver (round-off)") {
  check_z_independent_equals_plane_strain(HistoryAlgorithm::automatic);  // modal at this height
}

TEST_CASE("2D interface, field independent of z = the 2D plane-strain solver, block history in both (round-off)") {
  // The block operator (docs/theory.md 11.1) on the 2D interface: its kz = 0
  // modes have the 2D designs bit for bit and the same block size (B = 64
  // here: 600 steps cross 9 far-field updates), so again only the FFTs differ.
  check_z_independent_equals_plane_strain(HistoryAlgorithm::block);
}

TEST_CASE("2D interface, field independent of x with slip along x = the 2D antiplane solver (round-off)") {
  SimulationConfig c2 = small_config(0.8, 32);
  c2.material.plane = PlaneCondition::antiplane;
  testing::add_large_perturbation(c2, 0.5);
  Simulation flat(c2);
  // The 3D run: z takes the 2D run's x; two nodes along x, dx = L_z >= dz.
  SimulationConfig c3 = small_config(1.6, 2);
  c3.geometry.width = c2.geometry.length;
  c3.geometry.nodes_z = c2.geometry.nodes;
  std::vector<double> phi(64);
  for (int iz = 0; iz < 32; ++iz) phi[iz * 2] = phi[iz * 2 + 1] = flat.state()[iz];
  Simulation3d sim(c3, phi);
  REQUIRE(sim.time_step() == flat.time_step());
  const double v0 = c2.loading.driving_velocity;
  double worst_x = 0.0, worst_z = 0.0, worst_tau = 0.0, largest = 0.0, largest_tau = 0.0;
  for (int n = 0; n < 600; ++n) {
    for (int iz = 0; iz < 32; ++iz)
      for (int ix = 0; ix < 2; ++ix) {
        const std::size_t i = iz * 2 + ix;
        worst_x = std::max(worst_x, std::abs(sim.slip_rate_x()[i] - flat.slip_rate()[iz]));
        worst_z = std::max(worst_z, std::abs(sim.slip_rate_z()[i]));
        worst_tau = std::max(worst_tau, std::abs(sim.shear_stress_x()[i] - flat.shear_stress()[iz]));
      }
    largest = std::max(largest, max_abs(flat.slip_rate()));
    largest_tau = std::max(largest_tau, max_abs(flat.shear_stress()));
    flat.step();
    sim.step();
  }
  MESSAGE("max |v| = " << largest / v0 << " v0; max |v_x - v_SH| = " << worst_x / largest
                       << " max|v|, max |v_z| = " << worst_z / largest << ", shear stress " << worst_tau / largest_tau);
  REQUIRE(largest > 2 * v0);
  // As above: only the FFTs and the rotation (c = 0, s = +-1: exact) differ.
  CHECK(worst_x <= 1e-11 * largest);
  CHECK(worst_z <= 1e-11 * largest);
  CHECK(worst_tau <= 1e-11 * largest_tau);
}

namespace {

// A smooth initial state on a 16 x 8 grid without symmetry in x, and with
// f(x, z) = f(x, -z) when `mirror_symmetric`, shifted by (sx, sz) nodes.
std::vector<double> initial_state(const SimulationConfig& c, bool mirror_symmetric, int sx, int sz) {
  const int nx = c.geometry.nodes, nz = c.geometry.nodes_z;
  const double phi_ss = steady_state(c.friction, c.loading.driving_velocity);
  std::vector<double> phi(static_cast<std::size_t>(nx * nz));
  for (int iz = 0; iz < nz; ++iz)
    for (int ix = 0; ix < nx; ++ix) {
      const double x = 2 * pi * (ix - sx) / nx, z = 2 * pi * (iz - sz) / nz;
      double f = 0.8 * std::exp(std::cos(x - 0.4) + 0.7 * std::cos(z)) / std::exp(1.7) +
                 0.2 * std::sin(x) * std::cos(2 * z) + 0.15 * std::cos(x + z) + 0.15 * std::cos(x - z);
      if (!mirror_symmetric) f += 0.2 * std::sin(z + 0.3) * std::cos(x);
      phi[iz * nx + ix] = phi_ss * (1.0 + f);
    }
  return phi;
}

}  // namespace

TEST_CASE("2D interface: z -> -z mirror symmetry and translation invariance (round-off)") {
  SimulationConfig c = small_config(0.8, 16);
  c.geometry.width = 0.4;
  c.geometry.nodes_z = 8;
  const int nx = 16, nz = 8;
  Simulation3d mirror(c, initial_state(c, true, 0, 0));
  Simulation3d plain(c, initial_state(c, false, 0, 0));
  Simulation3d shifted(c, initial_state(c, false, 5, 3));
  double mirror_x = 0.0, mirror_z = 0.0, shift = 0.0, largest = 0.0, largest_z = 0.0;
  for (int n = 0; n < 500; ++n) {
    for (int iz = 0; iz < nz; ++iz)
      for (int ix = 0; ix < nx; ++ix) {
        const std::size_t i = iz * nx + ix, m = ((nz - iz) % nz) * nx + ix;
        const std::size_t s = ((iz + 3) % nz) * nx + (ix + 5) % nx;
        mirror_x = std::max(mirror_x, std::abs(mirror.slip_rate_x()[i] - mirror.slip_rate_x()[m]));
        mirror_z = std::max(mirror_z, std::abs(mirror.slip_rate_z()[i] + mirror.slip_rate_z()[m]));
        shift = std::max({shift, std::abs(plain.slip_rate_x()[i] - shifted.slip_rate_x()[s]),
                          std::abs(plain.slip_rate_z()[i] - shifted.slip_rate_z()[s])});
      }
    largest = std::max(largest, mirror.max_slip_rate());
    largest_z = std::max({largest_z, max_abs(mirror.slip_rate_z()), max_abs(plain.slip_rate_z())});
    mirror.step();
    plain.step();
    shifted.step();
  }
  const double v0 = c.loading.driving_velocity;
  MESSAGE("max |v| = " << largest / v0 << " v0, max |v_z| = " << largest_z / v0 << " v0; mirror: v_x "
                       << mirror_x / largest << ", v_z " << mirror_z / largest << "; translation " << shift / largest);
  REQUIRE(largest > 2 * v0);
  // Slip across x is really excited (~4e-3 v0 here), so the check on v_z is not vacuous.
  REQUIRE(largest_z > 1e-3 * v0);
  // Mirror and shifted fields differ by the rounding of their FFTs only
  // (~1e-16 per step), carried by 500 steps of nonlinear growth.
  CHECK(mirror_x <= 1e-11 * largest);
  CHECK(mirror_z <= 1e-11 * largest);
  CHECK(shift <= 1e-11 * largest);
}

namespace {

// Rates present in y[first..last) (uniform step dt): order-2 linear prediction
// y[n+2d] = a1 y[n+d] + a0 y[n] by least squares on samples d apart; the
// roots of z^2 - a1 z - a0 are exp(Lambda d dt) of the dominant conjugate pair
// (exact for y = e^{sigma t}(A cos wt + B sin wt)).  Returns Lambda with Im >= 0.
std::complex<double> dominant_rate(const std::vector<double>& y, double dt, std::size_t first,
                                   std::size_t last, std::size_t d) {
  double s11 = 0, s12 = 0, s22 = 0, r1 = 0, r2 = 0;
  for (std::size_t n = first; n + 2 * d < last; ++n) {
    const double p = y[n + d], q = y[n], t = y[n + 2 * d];
    s11 += p * p;
    s12 += p * q;
    s22 += q * q;
    r1 += p * t;
    r2 += q * t;
  }
  const double det = s11 * s22 - s12 * s12;
  const double a1 = (r1 * s22 - r2 * s12) / det, a0 = (s11 * r2 - s12 * r1) / det;
  const std::complex<double> disc = std::sqrt(std::complex<double>(a1 * a1 + 4 * a0));
  const std::complex<double> z1 = 0.5 * (a1 + disc), z2 = 0.5 * (a1 - disc);
  const std::complex<double> z = std::abs(z1) >= std::abs(z2) ? z1 : z2;
  std::complex<double> rate = std::log(z) / (static_cast<double>(d) * dt);
  return {rate.real(), std::abs(rate.imag())};
}

}  // namespace

TEST_CASE("oblique mode: growth rate from the simulation = linear stability of the 2x2 problem (2 %)") {
  const double wavelength = 2.4, angle = pi / 6;  // 2.4 m is unstable in 2D (test_solver_growth_rates)
  const double k = 2 * pi / wavelength, kx = k * std::cos(angle), kz = k * std::sin(angle);
  SimulationConfig c = small_config(2 * pi / kx, 8);
  c.geometry.width = 2 * pi / kz;
  c.geometry.nodes_z = 8;
  // The time step of the 2D growth-rate test (N = 64 over 2.4 m, beta = 0.25):
  // ~1000 steps per e-fold; the mode itself is exact on any grid.
  const double dmin = std::min(c.geometry.length, c.geometry.width) / 8;
  c.time.beta = 0.25 * (2.4 / 64) / dmin;
  const SteadySliding sliding = steady_sliding_of(c);

  // Theory.  The box of the 2D search, its left edge moved off the strip's
  // resonances on the imaginary axis (roots closer to neutral are not sought).
  SearchBox box = unstable_search_box(sliding);
  box.min_re = 1e-4 * box.max_im;
  const auto roots = oblique_characteristic_roots(sliding, kx, kz, box);
  REQUIRE(!roots.empty());
  const std::complex<double> theory = roots.front();
  // kz = 0 recovers the 2D roots (the determinant factorises).
  const auto flat = oblique_characteristic_roots(sliding, k, 0.0, box);
  const auto flat_2d = most_unstable_root(sliding, wavelength);
  REQUIRE(!flat.empty());
  REQUIRE(flat_2d.has_value());
  CHECK(std::abs(flat.front() - *flat_2d) <= 1e-8 * std::abs(*flat_2d));  // Newton-polished roots

  // Simulation: phi = phi_ss (1 + eps cos(kx x + kz z)).
  const double eps = 1e-6;
  Simulation3d sim(c, testing::oblique_mode_state(c, eps));
  const double dt = sim.time_step();
  const auto steps = static_cast<long long>(25.0 / theory.real() / dt);
  const testing::ObliqueModeRecord record = testing::record_oblique_mode(sim, c, steps);
  std::vector<double> vx_mode, vz_mode;  // standing modes (identical bodies): the real parts
  for (const auto& a : record.x) vx_mode.push_back(a.real());
  for (const auto& a : record.z) vz_mode.push_back(a.real());
  const std::size_t first = vx_mode.size() / 2, last = vx_mode.size();
  const std::size_t d = std::max<std::size_t>(1, (last - first) / 200);
  const std::complex<double> measured = dominant_rate(vx_mode, dt, first, last, d);
  const std::complex<double> measured_z = dominant_rate(vz_mode, dt, first, last, d);
  MESSAGE("lambda = " << wavelength << " m at " << angle * 180 / pi << " deg: theory " << theory << " (2D: "
                      << *flat_2d << "); simulated " << measured << " from v_x, " << measured_z << " from v_z over "
                      << last << " steps (dt = " << dt << " s); relative error "
                      << (measured.real() - theory.real()) / theory.real() << ", |v_z|/|v_x| at the end "
                      << std::abs(vz_mode.back() / vx_mode.back()));
  // The 2 %; the 2D solver measures ~1e-4 at this dt (docs/verification_growth.md).
  CHECK(std::abs(measured.real() - theory.real()) <= 0.02 * theory.real());
  CHECK(std::abs(measured_z.real() - theory.real()) <= 0.02 * theory.real());
  CHECK(std::abs(measured.imag() - std::abs(theory.imag())) <= 0.02 * std::abs(theory.imag()));
  // And the 3D rate differs from the 2D one at the same |k| by more than that
  // tolerance, so the test can tell the coupling from its absence.
  MESSAGE("3D vs 2D growth at |k|: " << (theory.real() - flat_2d->real()) / flat_2d->real());
}
