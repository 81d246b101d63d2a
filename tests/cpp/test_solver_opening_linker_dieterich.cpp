// Interface opening with the Linker-Dieterich state response on
// (friction.linker_dieterich > 0, interface.opening = "open"): docs/bodies.md §4,
// "Friction while open and on closing".  What the doc says and this test checks:
//   * never a NaN: slip rate, state, normal and effective normal stress finite,
//     state > 0, through opening and reclosure;
//   * while a node is open the state evolves by the state law alone with the
//     actual slip rate (no Linker-Dieterich part: no contact whose state could
//     respond): phi_{n+1} = Phi_dt(phi_n; (V_n + V_{n+1})/2), the exact aging-law
//     update, written out here;
//   * the effective normal stress relaxes towards 0 while open and stays > 0;
//   * in contact the response is on: a twin run with alpha_LD = 0 differs.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "config/config.hpp"
#include "solver/simulation.hpp"

using namespace slipstrip;

namespace {

// The strip on a rigid base of test_solver_interface_opening (Table S1, H = 0.1 m,
// a shear-load pulse of 2 sigma0 that opens the interface), with alpha_LD.
std::string opening_config(double alpha) {
  return std::string(R"(
[geometry]
length = 1.0
height = 0.1
nodes = 64
[friction]
linker_dieterich = )") + std::to_string(alpha) + R"(
[interface]
load_pulse_amplitude = 2e6
pulse_center = 0.5
pulse_width = 0.05
profile = "bump"
rise_time = 1e-4
[bottom]
body = "rigid"
)";
}

// The aging law over dt at a constant slip rate v, exactly (written out here):
// d phi/dt = 1 - hypot(v, v*) phi / D.
double aging_update(double phi, double v, double dt, double D, double v_star) {
  const double h = std::hypot(v, v_star);
  return D / h + (phi - D / h) * std::exp(-dt * h / D);
}

}  // namespace

TEST_CASE("Linker-Dieterich with opening: finite through opening and reclosure, state law alone while open") {
  const double alpha = 0.3;
  Simulation sim(load_config_string(opening_config(alpha)));
  Simulation plain(load_config_string(opening_config(0.0)));
  const auto& f = sim.config().friction;
  const std::size_t n = sim.x().size();
  std::vector<char> was_open(n, 0);
  int invalid = 0, open_checks = 0, closings = 0, open_steps = 0;
  double worst_open_state = 0.0, smallest_effective_open = 1e300, largest_difference = 0.0;
  double smallest_state = 1e300, largest_state = 0.0;
  for (int step = 0; step < 1500; ++step) {
    const std::vector<double> phi_before(sim.state().begin(), sim.state().end());
    const std::vector<double> v_before(sim.slip_rate().begin(), sim.slip_rate().end());
    const double t0 = sim.time();
    sim.step();
    plain.step();
    const double dt = sim.time() - t0;
    const auto sigma = sim.normal_stress(), eff = sim.effective_normal_stress(), phi = sim.state(),
               v = sim.slip_rate();
    bool any = false;
    for (std::size_t i = 0; i < n; ++i) {
      invalid += !std::isfinite(sigma[i]) || !std::isfinite(eff[i]) || !std::isfinite(phi[i]) ||
                 !std::isfinite(v[i]) || !(phi[i] > 0.0);
      smallest_state = std::min(smallest_state, phi[i]);
      largest_state = std::max(largest_state, phi[i]);
      const bool open = sigma[i] == 0.0;
      any = any || open;
      if (open) {
        // The state law alone over the step, at the mean of the two levels' slip
        // rates.  Tolerance 1e-12 relative: the same closed form evaluated in
        // another order (exp vs expm1), a few ulps.  A Linker-Dieterich factor
        // would change it by (sigma_eff ratio)^(-alpha/B), alpha/B = 14 here.
        const double expected = aging_update(phi_before[i], 0.5 * (v_before[i] + v[i]), dt, f.characteristic_slip, f.v_star);
        const double error = std::abs(phi[i] - expected) / expected;
        CHECK(error <= 1e-12);
        worst_open_state = std::max(worst_open_state, error);
        ++open_checks;
        smallest_effective_open = std::min(smallest_effective_open, eff[i]);
      } else if (was_open[i]) {
        ++closings;
      }
      was_open[i] = open;
      largest_difference = std::max(largest_difference, std::abs(std::log(phi[i] / plain.state()[i])));
    }
    open_steps += any;
  }
  std::printf("[opening + LD] alpha_LD = %.2f: %d steps with an open node, %d closings, %d open-node state checks "
              "(worst %.2e); state in [%.3e, %.3e] s; smallest sigma_eff while open %.3e Pa; max |ln(phi / "
              "phi(alpha = 0))| %.3f\n",
              alpha, open_steps, closings, open_checks, worst_open_state, smallest_state, largest_state,
              smallest_effective_open, largest_difference);
  CHECK(invalid == 0);
  REQUIRE(open_steps > 0);  // the pulse opens the interface ...
  CHECK(closings > 0);      // ... and it closes again
  CHECK(smallest_effective_open > 0.0);
  // The response is on in contact: the run differs from alpha_LD = 0 by more
  // than rounding (ln phi differs by > 1e-6).
  CHECK(largest_difference > 1e-6);
}
