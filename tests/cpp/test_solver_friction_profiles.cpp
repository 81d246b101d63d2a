// [friction] parameters along x, end to end: TOML spelling -> resolved config
// (and back) -> Simulation -> uniform-only analyses.
#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "config_test_helpers.hpp"
#include "config/config.hpp"
#include "solver/simulation.hpp"
#include "stability/steady_sliding.hpp"

using namespace slipstrip;
using slipstrip::testing::contains;
using slipstrip::testing::error_of;
using slipstrip::testing::same_bits;
using slipstrip::testing::TempFile;

namespace {

const std::string kSmall = "[geometry]\nlength = 4.0\nnodes = 16\n";

}  // namespace

TEST_CASE("profile spelling: piecewise_linear, piecewise_constant, node_file") {
  const auto c = load_config_string(
      kSmall +
      "[friction]\n"
      "a = { profile = \"piecewise_linear\", x = [0.0, 1.0, 1.2, 4.0], values = [0.005, 0.005, 0.02, 0.02] }\n"
      "b = { profile = \"piecewise_constant\", x = [0.0, 2.0], values = [0.075, 0.05] }\n");
  REQUIRE(c.friction_profiles.a);
  REQUIRE(c.friction_profiles.b);
  CHECK(std::isnan(c.friction.a));  // no one value for the whole interface
  CHECK(std::isnan(c.friction.b));
  CHECK(c.friction.f0 == 0.28);     // untouched scalars keep their value
  const auto nodes = resolve_friction_nodes(c.friction, c.friction_profiles, 16, 0.25);
  CHECK(nodes.a[0] == 0.005);
  CHECK(nodes.a[4] == 0.005);  // x = 1.0
  CHECK(nodes.a[5] == 0.02);   // x = 1.25
  CHECK(nodes.b[7] == 0.075);  // x = 1.75
  CHECK(nodes.b[8] == 0.05);   // x = 2.0
  CHECK(nodes.f0 == std::vector<double>(16, 0.28));

  std::string values;
  for (int i = 0; i < 16; ++i) {
    char line[32];
    std::snprintf(line, sizeof line, "%.17g\n", 4e-7 + 1e-8 * i);
    values += line;
  }
  const TempFile file("slipstrip_test_D_nodes.txt", "# D per node [m]\n" + values);
  const auto d = load_config_string(kSmall + "[friction]\ncharacteristic_slip = { profile = "
                                             "\"node_file\", path = \"" +
                                    file.path.string() + "\" }\n");
  const auto dn = resolve_friction_nodes(d.friction, d.friction_profiles, 16, 0.25);
  CHECK(dn.characteristic_slip[0] == 4e-7);
  CHECK(dn.characteristic_slip[15] == doctest::Approx(4e-7 + 15e-8).epsilon(1e-15));
}

TEST_CASE("profiles round-trip through to_toml, and overrides accept them") {
  const auto c = load_config_string(
      kSmall + "[friction]\n"
               "f0 = { profile = \"piecewise_constant\", x = [0.0, 0.3], values = [0.28, 0.3] }\n",
      {"friction.a={ profile = \"piecewise_linear\", x = [0.0, 4.0], values = [0.004, 0.02] }"});
  const auto text = to_toml(c);
  CHECK(contains(text, "a = { profile = \"piecewise_linear\", x = [0.0, 4.0], values = [0.004, 0.02] }"));
  const auto back = load_config_string(text);
  REQUIRE(back.friction_profiles.a);
  REQUIRE(back.friction_profiles.f0);
  CHECK(back.friction_profiles.a->x == c.friction_profiles.a->x);
  CHECK(back.friction_profiles.a->values == c.friction_profiles.a->values);
  CHECK(back.friction_profiles.f0->values == c.friction_profiles.f0->values);
  CHECK(to_toml(back) == text);
}

TEST_CASE("profile errors name the key, and per-node errors the node, x and value") {
  CHECK(contains(error_of(kSmall + "[friction]\na = { profile = \"linear\", x = [0.0], values = [0.1] }\n"),
                 "friction.a = {...}: profile = \"linear\" is not allowed"));
  CHECK(contains(error_of(kSmall + "[friction]\na = { profile = \"piecewise_linear\", x = [0.0, 0.0], "
                                   "values = [0.1, 0.1] }\n"),
                 "'x' must be strictly increasing"));
  CHECK(contains(error_of(kSmall + "[friction]\nb = { profile = \"piecewise_linear\", x = [0.0], "
                                   "values = [0.1, 0.2] }\n"),
                 "'x' has 1 points but 'values' has 2"));
  CHECK(error_of(kSmall + "[friction]\na = { profile = \"piecewise_constant\", x = [0.0, 1.0], "
                          "values = [0.01, -0.5] }\n") ==
        "friction.a at node 4 (x = 1 m) = -0.5 is out of range: expected 0 <= a <= 10 (dimensionless)");
  CHECK(contains(error_of(kSmall + "[friction]\nlaw = \"regularized\"\na = { profile = "
                                   "\"piecewise_constant\", x = [0.0, 2.0], values = [0.01, 0.0] }\n"),
                 "friction.a at node 8 (x = 2 m) = 0 is out of range"));
  CHECK(contains(error_of(kSmall + "[friction]\na = { profile = \"node_file\", path = "
                                   "\"/nonexistent/a.txt\" }\n"),
                 "node file '/nonexistent/a.txt' does not exist"));
  const TempFile short_file("slipstrip_test_short.txt", "0.01\n0.02\n");
  CHECK(contains(error_of(kSmall + "[friction]\na = { profile = \"node_file\", path = \"" +
                          short_file.path.string() + "\" }\n"),
                 "has 2 values, expected one per node (16 = geometry.nodes)"));
  const TempFile bad_file("slipstrip_test_bad.txt", "0.01\nabc\n");
  CHECK(contains(error_of(kSmall + "[friction]\na = { profile = \"node_file\", path = \"" +
                          bad_file.path.string() + "\" }\n"),
                 "line 2: 'abc' is not one finite number"));
}

TEST_CASE("linear stability refuses parameters that vary along x, accepts constant profiles") {
  const auto varying = load_config_string(
      kSmall + "[friction]\na = { profile = \"piecewise_constant\", x = [0.0, 2.0], values = [0.005, 0.03] }\n");
  CHECK_THROWS_WITH_AS(steady_sliding_of(varying),
                       doctest::Contains("linear stability (growth rates, Lc(H)) needs friction "
                                         "parameters that are the same at every node, but "
                                         "friction.a vary along x"),
                       std::invalid_argument);
  const auto constant = load_config_string(
      kSmall + "[friction]\na = { profile = \"piecewise_linear\", x = [0.0, 4.0], values = [0.005, 0.005] }\n");
  CHECK(steady_sliding_of(constant).friction.a == 0.005);
  CHECK(steady_sliding_of(constant).friction.b == 0.075);
}

TEST_CASE("a spatially uniform profile gives bit for bit the scalar config's run") {
  // Every parameter as a profile (so the batch solve takes its per-node
  // path), with the scalar values of the reference run.
  const std::string base =
      "[geometry]\nlength = 0.5\nheight = 0.025\nnodes = 64\n"
      "[initial]\nnoise_amplitude = 0.05\n"
      "[time]\nduration = 1e-5\n";
  const auto scalar = load_config_string(base + "[friction]\ncharacteristic_slip = 1.667e-7\n");
  const auto profiled = load_config_string(
      base + "[friction]\n"
             "f0 = { profile = \"piecewise_constant\", x = [0.0, 0.2], values = [0.28, 0.28] }\n"
             "a = { profile = \"piecewise_linear\", x = [0.0, 0.25, 0.5], values = [0.005, 0.005, 0.005] }\n"
             "b = { profile = \"piecewise_linear\", x = [0.1, 0.4], values = [0.075, 0.075] }\n"
             "characteristic_slip = { profile = \"piecewise_constant\", x = [0.0], values = [1.667e-7] }\n");
  Simulation a(scalar), b(profiled);
  REQUIRE(same_bits(a.state(), b.state()));
  REQUIRE(same_bits(a.slip_rate(), b.slip_rate()));
  for (int n = 0; n < 400; ++n) {
    a.step();
    b.step();
  }
  CHECK(a.max_slip_rate() != 2e-3);  // the noise made something happen
  CHECK(same_bits(a.slip(), b.slip()));
  CHECK(same_bits(a.slip_rate(), b.slip_rate()));
  CHECK(same_bits(a.state(), b.state()));
  CHECK(same_bits(a.shear_stress(), b.shear_stress()));
}

TEST_CASE("steady sliding follows the per-node parameters") {
  const auto c = load_config_string(
      kSmall + "[friction]\ncharacteristic_slip = { profile = \"piecewise_constant\", x = [0.0, 2.0], "
               "values = [5e-7, 1e-6] }\n"
               "a = { profile = \"piecewise_constant\", x = [0.0, 2.0], values = [0.005, 0.03] }\n"
               "[time]\nduration = 1e-6\n");
  Simulation sim(c);
  FrictionParameters left = c.friction, right = c.friction;
  left.characteristic_slip = 5e-7, left.a = 0.005;
  right.characteristic_slip = 1e-6, right.a = 0.03;
  const double v0 = c.loading.driving_velocity;
  CHECK(sim.state()[0] == steady_state(left, v0));
  CHECK(sim.state()[15] == steady_state(right, v0));
  CHECK(sim.reference_shear_stresses()[0] ==
        frictional_strength(left, c.loading.normal_stress, v0, steady_state(left, v0)));
  CHECK(sim.reference_shear_stresses()[15] ==
        frictional_strength(right, c.loading.normal_stress, v0, steady_state(right, v0)));
  // Steady sliding is a solution at every node: v = v0 to the solve's accuracy.
  for (double v : sim.slip_rate()) CHECK(v == doctest::Approx(v0).epsilon(1e-11));
  for (int n = 0; n < 20; ++n) sim.step();
  for (double v : sim.slip_rate()) CHECK(v == doctest::Approx(v0).epsilon(1e-9));
}

// A rupture nucleated by a load pulse at x = 0.1 m on a thin-strip ring
// (L = 1 m, H = 0.025 m, strongly velocity-weakening: f0 b - a = 0.065)
// runs all the way round when friction is uniform.  Two velocity-
// strengthening bands (a = 0.12 > f0 b = 0.07, 0.2 m = 8 H wide each) on
// either side of the patch 0.4 m < x < 0.8 m stop it: the patch, identical in
// both runs, is never reached by a rupture front.
//
// Measures, in the inner patch 0.45 m < x < 0.75 m:
// * the peak slip rate over the run: a rupture front there means >= 10 v0 (the
//   front_slip_rate threshold of the examples); measured ~5000 v0 without the
//   barrier, < 2 v0 with it.
// * the coseismic slip slip(x, t) - v0 t at t = 0.3 ms.  Without the barrier
//   every node there slipped >= 1 um (measured 2.25-4.4 um, mean 2.9 um: the
//   rupture's full stress drop).  With it the patch slips *less* than the
//   steady creep (measured -0.25 to -0.36 um): the event's slip elsewhere
//   unloads the strips through the uniform mode (stiffness mu / 2H).  The bound
//   on the forward slip, 5 % of the no-barrier mean, is far above anything a
//   stopped rupture leaves (static stress transfer through a strip held at its
//   outer faces reaches a few H, the band is 8 H) and 20x below what a rupture
//   that got through leaves, so it separates "stopped" from "passed" without
//   depending on the details of either.
TEST_CASE("a velocity-strengthening barrier stops a rupture that runs through without it") {
  const std::string base =
      "[geometry]\nlength = 1.0\nheight = 0.025\nnodes = 512\n"
      "[interface]\nload_pulse_amplitude = 1e5\npulse_center = 0.1\npulse_width = 0.01\n"
      "profile = \"ramp\"\nrise_time = 2e-5\n"
      "[time]\nduration = 3e-4\n";
  const std::string weakening = "[friction]\nb = 0.25\ncharacteristic_slip = 1.667e-7\n";
  const auto uniform = load_config_string(base + weakening + "a = 0.005\n");
  const auto barrier = load_config_string(
      base + weakening +
      "a = { profile = \"piecewise_constant\", x = [0.0, 0.2, 0.4, 0.8], "
      "values = [0.005, 0.12, 0.005, 0.12] }\n");

  const double v0 = uniform.loading.driving_velocity;
  const auto in_patch = [](double x) { return x > 0.45 && x < 0.75; };
  // Coseismic slip in the patch at the end; peak slip rate there over the run.
  const auto run = [&](const SimulationConfig& c, double& peak_rate) {
    Simulation sim(c);
    const auto steps = std::lround(c.time.duration / sim.time_step());
    peak_rate = 0.0;
    for (long n = 0; n < steps; ++n) {
      sim.step();
      for (std::size_t i = 0; i < sim.x().size(); ++i)
        if (in_patch(sim.x()[i])) peak_rate = std::max(peak_rate, sim.slip_rate()[i]);
    }
    std::vector<double> slip;
    for (std::size_t i = 0; i < sim.x().size(); ++i)
      if (in_patch(sim.x()[i])) slip.push_back(sim.slip()[i] - v0 * sim.time());
    return slip;
  };
  double peak_through = 0.0, peak_stopped = 0.0;
  const auto through = run(uniform, peak_through);
  const auto stopped = run(barrier, peak_stopped);
  MESSAGE("peak slip rate in the patch: without barrier " << peak_through / v0
          << " v0, with barrier " << peak_stopped / v0 << " v0");
  CHECK(peak_through > 1000 * v0);
  CHECK(peak_stopped < 10 * v0);
  REQUIRE(through.size() == stopped.size());
  double mean_through = 0.0, min_through = 1e300, max_stopped = -1e300, min_stopped = 1e300;
  for (std::size_t k = 0; k < through.size(); ++k) {
    mean_through += through[k] / static_cast<double>(through.size());
    min_through = std::min(min_through, through[k]);
    max_stopped = std::max(max_stopped, stopped[k]);
    min_stopped = std::min(min_stopped, stopped[k]);
  }
  MESSAGE("coseismic slip in the patch: without barrier mean " << mean_through << " m, min "
          << min_through << " m; with barrier between " << min_stopped << " and " << max_stopped
          << " m");
  CHECK(min_through > 1e-6);                  // the rupture ran through the whole patch
  CHECK(max_stopped < 0.05 * mean_through);   // the barrier stopped it
}
