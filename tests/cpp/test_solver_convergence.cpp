// Order of accuracy in time of the full scheme with rate-and-state friction
// (history operator + predictor-corrector state update + local solve).
//
// A smooth problem: exact steady sliding at v0, perturbed by a localized
// shear-load pulse that is C^3 in time ([interface] load_pulse_amplitude with
// the sin^4 bump profile).  Fixed spatial grid, dt halved three times.  With
// e(dt) = rms(v_dt - v_{dt/2}) at the same final time, a second-order scheme
// gives e(dt)/e(dt/2) -> 4.
//
// Why not the supplement's initial state perturbation: changing phi at t = 0
// makes v jump at t = 0+, and that jump comes back with every shear echo
// (t = 2H/c_s, 4H/c_s, ...).  At a jump any fixed-step scheme is first order
// locally, so such a run converges at first order (measured ratio ~2 after
// the first echo), which says nothing about the scheme on smooth solutions.
#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include "solver/simulation.hpp"

using namespace slipstrip;

namespace {

SimulationConfig smooth_problem(double beta, double pulse_amplitude) {
  SimulationConfig c;
  c.geometry = {0.4, 0.05, 64};  // 2H/dx = 16: beta = 0.4..0.05 -> exactly 40..320 steps per 2H/c_s
  c.time.beta = beta;
  c.interface.load_pulse_amplitude = pulse_amplitude;  // [Pa]
  c.interface.pulse_center = 0.2;
  c.interface.pulse_width = 0.04;
  c.interface.profile = TimeProfile::bump;
  c.interface.rise_time = 4 * 2 * c.geometry.height / c.material.shear_wave_speed();
  return c;
}

std::vector<double> slip_rate_at(double beta, double pulse_amplitude, double end_time) {
  Simulation sim(smooth_problem(beta, pulse_amplitude));
  const long steps = std::lround(end_time / sim.time_step());
  REQUIRE(std::abs(steps * sim.time_step() - end_time) < 1e-9 * end_time);
  for (long n = 0; n < steps; ++n) sim.step();
  return {sim.slip_rate().begin(), sim.slip_rate().end()};
}

double rms_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double s = 0;
  for (std::size_t i = 0; i < a.size(); ++i) s += (a[i] - b[i]) * (a[i] - b[i]);
  return std::sqrt(s / a.size());
}

}  // namespace

TEST_CASE("full scheme with rate-and-state friction is second order in dt") {
  const SimulationConfig probe;
  const double echo = 2 * 0.05 / probe.material.shear_wave_speed();
  // A weak pulse (near-linear response) and a strong one (slip rate reaches
  // ~4 v0: the friction law's nonlinearity matters), at 2 and 10 round trips.
  for (double amplitude : {1e3, 3e4}) {
    for (double trips : {2.0, 10.0}) {
      std::vector<std::vector<double>> v;
      for (double beta : {0.4, 0.2, 0.1, 0.05}) v.push_back(slip_rate_at(beta, amplitude, trips * echo));
      const double e1 = rms_difference(v[0], v[1]), e2 = rms_difference(v[1], v[2]),
                   e3 = rms_difference(v[2], v[3]);
      double signal = 0;
      for (double x : v[3]) signal = std::max(signal, std::abs(x - probe.loading.driving_velocity));
      MESSAGE("pulse " << amplitude << " Pa, " << trips << " round trips (max |v - v0| = " << signal
                       << " m/s): differences " << e1 << ", " << e2 << ", " << e3 << "; ratios "
                       << e1 / e2 << ", " << e2 / e3);
      CHECK(e3 < 1e-4 * signal);
      // "Halving dt divides the error by about 4": measured 3.9..4.3 here;
      // accept 3.5..4.5 (order 1.8..2.2) on the two finest pairs.
      CHECK(e2 / e3 > 3.5);
      CHECK(e2 / e3 < 4.5);
      CHECK(e1 / e2 > 3.5);
      CHECK(e1 / e2 < 4.5);
    }
  }
}
