// Two different in-plane half-spaces in the solver through the combined
// operator of the interface (time.half_space_pair = "combined", the default;
// docs/inplane_bodies.md §7) against the two bodies' operators ("bodies"):
//   * the same continuum problem, different discretisations: a prescribed
//     slip history's shear and normal stresses agree to the discretisations'
//     accuracy, the difference shrinking at second order with dt;
//   * opening: zero traction on open nodes, closing again, as with the bodies;
//   * save and restore continue bit for bit (through an open phase);
//   * a pair with a Stoneley wave, and "bodies", take the bodies' operators.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "config/config.hpp"
#include "kernels/inplane_pair_history.hpp"
#include "solver/simulation.hpp"

using namespace slipstrip;

namespace {

// PMMA over Homalite (plane stress), both half-spaces.
const char* kPair = R"(
[geometry]
length = 0.1
height = "inf"
nodes = 32
[material]
shear_modulus = 2.1e9
poisson_ratio = 0.35
density = 1170.0
plane = "stress"
[bottom]
body = "elastic"
shear_modulus = 1.9e9
poisson_ratio = 0.34
density = 1230.0
height = "inf"
)";

bool combined(const Simulation& sim) {
  const auto* pair = dynamic_cast<const InplanePairHistory*>(&sim.history_operator());
  return pair && pair->combined();
}

std::string with_operator(std::string config, const char* op) {
  return config + "[time]\nhalf_space_pair = \"" + op + "\"\n";
}

// Table S1's material over a softer half-space (a ninth of its mu, the same
// rho), a shear-load pulse of 8 sigma0 on rate and state: the slip it drives
// loads the normal stress through the dissimilarity until the faces part (as
// the strips of test_solver_interface_opening).
const char* kOpeningPair = R"(
[geometry]
length = 1.0
height = "inf"
nodes = 32
[bottom]
body = "elastic"
shear_modulus = 1e9
height = "inf"
[interface]
load_pulse_amplitude = 8e6
pulse_center = 0.5
pulse_width = 0.05
profile = "bump"
rise_time = 1e-4
)";

}  // namespace

TEST_CASE("combined pair operator vs the bodies' operators: the same problem, second order in dt") {
  // slip = 1 um cos(2 pi x/L) sin^4(pi t/T), T = 8 L/c_s (prescribed_slip, mode
  // 1), over 1.5 T: the shear and normal stresses of the two operators at every
  // common time, the largest difference over the largest stress change, at
  // beta = 0.3 and 0.15 (the time step halved, the same times).  Each operator
  // is second order (test_kernels_half_space_pair_operator,
  // test_kernels_face_half_space), so their difference is O(dt^2): required a
  // ratio > 3 per halving and < 2e-3 at beta = 0.15.
  double previous = 0.0;
  for (double beta : {0.3, 0.15}) {
    std::string base = std::string(kPair) + "[interface]\nlaw = \"prescribed_slip\"\nslip_amplitude = 1e-6\n"
                                            "mode = 1\nprofile = \"bump\"\nrise_time = " +
                       std::to_string(8 * 0.1 / std::sqrt(1.9e9 / 1230.0)) + "\n";
    const auto config = [&](const char* op) {
      return load_config_string(base + "[time]\nhalf_space_pair = \"" + op + "\"\nbeta = " + std::to_string(beta) +
                                "\n");
    };
    Simulation a(config("combined")), b(config("bodies"));
    REQUIRE(combined(a));
    REQUIRE(!combined(b));
    REQUIRE(a.time_step() == b.time_step());
    const int steps = static_cast<int>(std::round(1.5 * a.config().interface.rise_time / a.time_step()));
    const double tau0 = a.shear_stress()[0], sigma0 = a.config().loading.normal_stress;
    double worst = 0.0, largest = 0.0;
    for (int n = 0; n < steps; ++n) {
      a.step();
      b.step();
      for (std::size_t i = 0; i < a.x().size(); ++i) {
        worst = std::max({worst, std::abs(a.shear_stress()[i] - b.shear_stress()[i]),
                          std::abs(a.normal_stress()[i] - b.normal_stress()[i])});
        largest = std::max({largest, std::abs(b.shear_stress()[i] - tau0), std::abs(b.normal_stress()[i] - sigma0)});
      }
    }
    const double relative = worst / largest;
    MESSAGE("beta = " << beta << ": " << steps << " steps, largest stress change " << largest
                      << " Pa, combined vs bodies " << relative);
    CHECK(largest > 0.0);
    if (previous > 0.0) {
      CHECK(previous / relative > 3.0);
      CHECK(relative < 2e-3);
    }
    previous = relative;
  }
}

TEST_CASE("combined pair operator: the interface opens with zero traction and closes again") {
  // kOpeningPair over 1500 steps.  On an open node the normal stress is 0 exactly and the shear traction 0 to
  // rounding (a few ulps of the load); in contact the gap is 0 exactly.
  const std::string c = with_operator(kOpeningPair, "combined");
  Simulation sim(load_config_string(c));
  REQUIRE(combined(sim));
  const double rounding = 8.0 * std::numeric_limits<double>::epsilon() *
                          (sim.reference_shear_stress() + sim.radiation_damping() * sim.config().loading.driving_velocity);
  const std::size_t n = sim.x().size();
  std::vector<char> was_open(n, 0);
  int open_steps = 0, closings = 0, invalid = 0;
  double largest_gap = 0.0, worst_open_shear = 0.0;
  for (int s = 0; s < 1500; ++s) {
    sim.step();
    const auto sigma = sim.normal_stress(), gap = sim.opening(), tau = sim.shear_stress();
    bool any = false;
    for (std::size_t i = 0; i < n; ++i) {
      invalid += !std::isfinite(sigma[i]) || !std::isfinite(gap[i]) || !(gap[i] >= 0.0);
      const bool open = sigma[i] == 0.0;
      any = any || open;
      if (open) {
        worst_open_shear = std::max(worst_open_shear, std::abs(tau[i]));
      } else {
        if (was_open[i]) ++closings;
        invalid += gap[i] != 0.0;
      }
      largest_gap = std::max(largest_gap, gap[i]);
      was_open[i] = open;
    }
    open_steps += any;
  }
  MESSAGE(open_steps << " steps with an open node, " << closings << " closings, largest gap " << largest_gap
                     << " m, worst |shear traction| on an open node " << worst_open_shear << " Pa (bound "
                     << rounding << ")");
  CHECK(invalid == 0);
  CHECK(open_steps > 0);
  CHECK(closings > 0);
  CHECK(largest_gap > 0.0);
  CHECK(worst_open_shear <= rounding);
}

TEST_CASE("combined pair operator: save and restore through an open phase continue bit for bit") {
  const std::string c = with_operator(kOpeningPair, "combined");
  const SimulationConfig config = load_config_string(c);
  Simulation a(config);
  int steps = 0;
  while (a.open_nodes() == 0 && steps < 3000) {
    a.step();
    ++steps;
  }
  REQUIRE(a.open_nodes() > 0);
  for (int n = 0; n < 7; ++n) a.step();
  const SimulationState saved = a.save_state();
  Simulation b(config);
  b.restore_state(saved);
  std::size_t differing = 0;
  for (int n = 0; n < 300; ++n) {
    a.step();
    b.step();
    for (std::size_t i = 0; i < a.x().size(); ++i)
      differing += a.slip_rate()[i] != b.slip_rate()[i] || a.normal_stress()[i] != b.normal_stress()[i] ||
                   a.opening()[i] != b.opening()[i] || a.shear_stress()[i] != b.shear_stress()[i];
  }
  CHECK(differing == 0);
  // The bodies' operators do not resume the combined one's restart point.
  Simulation bodies(load_config_string(with_operator(std::string(kPair), "bodies")));
  CHECK_THROWS_WITH_AS(bodies.restore_state(saved), doctest::Contains("time.half_space_pair"), std::invalid_argument);
}

TEST_CASE("a pair with a Stoneley wave takes the bodies' operators; so does \"bodies\"") {
  // PMMA over PMMA at twice the density (the same wave speeds): a Stoneley
  // wave at 0.995 c_s (test_kernels_half_space_pair), which the combined
  // operator refuses.
  std::string stoneley = kPair;
  stoneley.replace(stoneley.find("shear_modulus = 1.9e9"), 21, "shear_modulus = 4.2e9");
  stoneley.replace(stoneley.find("poisson_ratio = 0.34"), 20, "poisson_ratio = 0.35");
  stoneley.replace(stoneley.find("density = 1230.0"), 16, "density = 2340.0");
  CHECK(!combined(Simulation(load_config_string(stoneley))));
  CHECK(!combined(Simulation(load_config_string(with_operator(kPair, "bodies")))));
  CHECK(combined(Simulation(load_config_string(kPair))));
}
