// [friction] parameters that vary over a 2D interface (docs/3d.md, docs/config.md
// "Parameters along x or z"): profiles along z, along x and per node on a
// 2D interface, sampled at every node; the Simulation3d's steady state and
// tau_0 node by node; constant profiles step bit for bit as the scalars; the
// refusals name the key, the value and what is allowed.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <fstream>
#include <string>
#include <vector>

#include "config_test_helpers.hpp"
#include "config/config.hpp"
#include "solver/simulation_3d.hpp"
#include "stability/steady_sliding.hpp"

using namespace slipstrip;
using slipstrip::testing::contains;
using slipstrip::testing::error_of;
using slipstrip::testing::same_bits;
using slipstrip::testing::TempFile;

namespace {

// 16 x 8 nodes over 0.25 m x 0.125 m (dx = dz = 15.625 mm), Table S1 friction
// with D / 3 (configs/3d/demo.toml), a little white noise.
const std::string kGrid =
    "[geometry]\nlength = 0.25\nwidth = 0.125\nheight = 0.025\nnodes = 16\nnodes_z = 8\n"
    "[loading]\ndriving_velocity = 2e-3\n[time]\nbeta = 0.24\n"
    "[initial]\nnoise_amplitude = 1e-2\nnoise_seed = 3\n";
constexpr int kNx = 16, kNz = 8;
constexpr double kDx = 0.25 / kNx, kDz = 0.125 / kNz;

// The piecewise-linear formula of docs/config.md, written out: constant end
// values outside the points, linear between them.
double piecewise_linear(const std::vector<double>& s, const std::vector<double>& v, double at) {
  if (at <= s.front()) return v.front();
  if (at >= s.back()) return v.back();
  std::size_t k = 0;
  while (!(at < s[k + 1])) ++k;
  return v[k] + (at - s[k]) / (s[k + 1] - s[k]) * (v[k + 1] - v[k]);
}

// Every field of two runs, bit for bit (the normal-stress fields too for
// dissimilar bodies).
void check_same_fields(const Simulation3d& one, const Simulation3d& other) {
  CHECK(same_bits(one.slip_x(), other.slip_x()));
  CHECK(same_bits(one.slip_z(), other.slip_z()));
  CHECK(same_bits(one.speed(), other.speed()));
  CHECK(same_bits(one.state(), other.state()));
  CHECK(same_bits(one.shear_stress_x(), other.shear_stress_x()));
  CHECK(same_bits(one.shear_stress_z(), other.shear_stress_z()));
  CHECK(same_bits(one.reference_shear_stress(), other.reference_shear_stress()));
  REQUIRE(one.variable_normal_stress() == other.variable_normal_stress());
  CHECK(same_bits(one.normal_stress(), other.normal_stress()));
  CHECK(same_bits(one.effective_normal_stress(), other.effective_normal_stress()));
  CHECK(same_bits(one.opening(), other.opening()));
}

}  // namespace

TEST_CASE("profiles along z, along x and per node: every node's parameters are the formula's") {
  // a along z (a rate-weakening band 0.04 <= z <= 0.08 between rate-strengthening
  // rows, points between nodes), b along x (two steps), f0 per node from a file
  // (x fastest), D a number.
  const std::vector<double> za = {0.0, 0.02, 0.04, 0.08, 0.1, 0.125};
  const std::vector<double> va = {0.03, 0.03, 0.005, 0.005, 0.03, 0.03};
  std::string f0_text;
  std::vector<double> f0_nodes;
  for (int i = 0; i < kNx * kNz; ++i) {
    f0_nodes.push_back(0.25 + 1e-4 * static_cast<double>((i * 37) % 101));
    f0_text += std::to_string(f0_nodes.back()) + "\n";
  }
  for (double& f : f0_nodes) f = std::stod(std::to_string(f));  // the values as written
  const TempFile f0_file("slipstrip_test_f0_2d.txt", f0_text);
  const std::string config_text =
      kGrid +
      "[friction]\n"
      "a = { profile = \"piecewise_linear\", z = [0.0, 0.02, 0.04, 0.08, 0.1, 0.125], "
      "values = [0.03, 0.03, 0.005, 0.005, 0.03, 0.03] }\n"
      "b = { profile = \"piecewise_constant\", x = [0.0, 0.1, 0.2], values = [0.075, 0.06, 0.075] }\n"
      "f0 = { profile = \"node_file\", path = \"" + f0_file.path.string() + "\" }\n";
  const SimulationConfig c = load_config_string(config_text);
  REQUIRE(c.friction_profiles.a);
  CHECK(c.friction_profiles.a->axis == ParameterProfile::Axis::z);
  CHECK(c.friction_profiles.b->axis == ParameterProfile::Axis::x);
  CHECK(std::isnan(c.friction.a));
  // The resolved config writes the profile back along z and reloads to the same nodes.
  const std::string written = to_toml(c);
  CHECK(contains(written, "z = [0.0, 0.02, 0.04, 0.08, 0.1, 0.125]"));
  const SimulationConfig again = load_config_string(written);

  const FrictionNodeValues nodes = resolve_friction_nodes(c.friction, c.friction_profiles, friction_node_grid(c));
  const FrictionNodeValues reloaded =
      resolve_friction_nodes(again.friction, again.friction_profiles, friction_node_grid(again));
  CHECK(same_bits(nodes.a, reloaded.a));
  CHECK(same_bits(nodes.b, reloaded.b));
  CHECK(same_bits(nodes.f0, reloaded.f0));
  REQUIRE(nodes.a.size() == static_cast<std::size_t>(kNx * kNz));
  const Simulation3d sim(c);
  const double v0 = c.loading.driving_velocity, sigma = c.loading.normal_stress;
  double worst_a = 0.0;
  for (int iz = 0; iz < kNz; ++iz)
    for (int ix = 0; ix < kNx; ++ix) {
      const std::size_t i = static_cast<std::size_t>(ix + kNx * iz);
      const double x = ix * kDx, z = iz * kDz;
      // a(z): the same arithmetic in another order of branches; 1e-14 absolute
      // (a ~ 0.03: a few roundings of the interpolation).
      worst_a = std::max(worst_a, std::abs(nodes.a[i] - piecewise_linear(za, va, z)));
      CHECK(std::abs(nodes.a[i] - piecewise_linear(za, va, z)) <= 1e-14);
      // b(x): a value of the table, exactly.
      CHECK(nodes.b[i] == (x < 0.1 ? 0.075 : x < 0.2 ? 0.06 : 0.075));
      CHECK(nodes.f0[i] == f0_nodes[i]);
      CHECK(nodes.characteristic_slip[i] == c.friction.characteristic_slip);
      // The simulation's tau_0 is the steady strength at v0 with these
      // parameters, bit for bit (the same routine on the same inputs).
      const FrictionParameters p = friction_at_node(c.friction, nodes, i);
      CHECK(sim.reference_shear_stress()[i] == frictional_strength(p, sigma, v0, steady_state(p, v0)));
    }
  MESSAGE("worst |a - formula| = " << worst_a);
  // Rows in the band have a = 0.005, rows outside 0.03, the same along x.
  CHECK(nodes.a[static_cast<std::size_t>(kNx * 3)] == 0.005);  // z = 0.046875
  CHECK(nodes.a[static_cast<std::size_t>(kNx * 3 + 11)] == 0.005);
  CHECK(nodes.a[0] == 0.03);
}

TEST_CASE("the initial state is each node's steady state; the run steps and stays finite") {
  const std::string no_noise =
      "[geometry]\nlength = 0.25\nwidth = 0.125\nheight = 0.025\nnodes = 16\nnodes_z = 8\n"
      "[loading]\ndriving_velocity = 2e-3\n[time]\nbeta = 0.24\n"
      "[friction]\na = { profile = \"piecewise_constant\", z = [0.0, 0.04, 0.08], values = [0.03, 0.005, 0.03] }\n";
  const SimulationConfig c = load_config_string(no_noise);
  Simulation3d sim(c);
  const FrictionNodeValues nodes = resolve_friction_nodes(c.friction, c.friction_profiles, friction_node_grid(c));
  for (std::size_t i = 0; i < sim.nodes(); ++i) {
    const FrictionParameters p = friction_at_node(c.friction, nodes, i);
    CHECK(sim.state()[i] == steady_state(p, c.loading.driving_velocity));
  }
  // Steady sliding with each node's own tau_0 is an equilibrium: after 200
  // steps every node still slides at v0.  1e-9 relative: the local solve's
  // tolerance (friction/local_solve_tolerances.hpp) carried through the history.
  for (int s = 0; s < 200; ++s) sim.step();
  double worst = 0.0;
  for (double v : sim.speed()) worst = std::max(worst, std::abs(v / c.loading.driving_velocity - 1.0));
  MESSAGE("steady sliding with a band in z, 200 steps: max |v/v0 - 1| = " << worst);
  CHECK(worst <= 1e-9);
}

TEST_CASE("constant profiles along z or x step bit for bit as the same numbers") {
  // The per-node path of the batch solve and of tau_0 against the uniform one.
  const SimulationConfig scalars = load_config_string(kGrid);
  const SimulationConfig profiles = load_config_string(
      kGrid +
      "[friction]\n"
      "a = { profile = \"piecewise_linear\", z = [0.0, 0.125], values = [0.005, 0.005] }\n"
      "b = { profile = \"piecewise_constant\", x = [0.0], values = [0.075] }\n");
  Simulation3d one(scalars), other(profiles);
  for (int s = 0; s < 300; ++s) {
    one.step();
    other.step();
  }
  // The noise makes the fields vary from node to node (1e-3 of v0 here, far
  // above round-off): the comparison is away from steady sliding.
  MESSAGE("max |v| / v0 after 300 steps = " << one.max_slip_rate() / scalars.loading.driving_velocity);
  CHECK(one.max_slip_rate() > 1.0005 * scalars.loading.driving_velocity);
  check_same_fields(one, other);
  // A profile whose values are all equal is uniform for linear stability too.
  CHECK(steady_sliding_of(profiles).friction.a == 0.005);
}

TEST_CASE("refusals name the key, the value and what is allowed") {
  // Along z on a one-dimensional interface.
  CHECK(contains(error_of("[friction]\na = { profile = \"piecewise_linear\", z = [0.0, 1.0], values = [0.01, 0.02] }\n"),
                 "friction.a = {...}: a profile along z (z = [...]) on a one-dimensional interface "
                 "(geometry.nodes_z = 1): expected a profile along x (x = [...]) or a number"));
  // Both axes in one profile.
  CHECK(contains(error_of(kGrid + "[friction]\nb = { profile = \"piecewise_linear\", x = [0.0], z = [0.0], "
                                  "values = [0.07] }\n"),
                 "friction.b = {...}: both 'x' and 'z' given: expected one of them"));
  CHECK(contains(error_of(kGrid + "[friction]\nb = { profile = \"piecewise_linear\", values = [0.07] }\n"),
                 "friction.b = {...}: missing 'x' (or 'z' on a 2D interface)"));
  // z not increasing.
  CHECK(contains(error_of(kGrid + "[friction]\na = { profile = \"piecewise_linear\", z = [0.0, 0.1, 0.05], "
                                  "values = [0.01, 0.02, 0.03] }\n"),
                 "'z' must be strictly increasing, but z[2] = 0.05 <= z[1] = 0.1"));
  // A value out of range, named by its node (ix, iz) and position.
  CHECK(contains(error_of(kGrid + "[friction]\na = { profile = \"piecewise_constant\", z = [0.0, 0.04], "
                                  "values = [0.01, -0.001] }\n"),
                 "friction.a at node (ix, iz) = (0, 3) (x = 0 m, z = 0.046875 m) = -0.001 is out of range: "
                 "expected 0 <= a <= 10 (dimensionless)"));
  // A node file of a line's length on a 2D interface.
  std::string sixteen;
  for (int i = 0; i < kNx; ++i) sixteen += "0.28\n";
  const TempFile file("slipstrip_test_f0_line.txt", sixteen);
  CHECK(contains(error_of(kGrid + "[friction]\nf0 = { profile = \"node_file\", path = \"" + file.path.string() +
                          "\" }\n"),
                 "has 16 values, expected one per node (128 = geometry.nodes x geometry.nodes_z, x fastest)"));
  // Linear stability refuses parameters that vary over the interface.
  const SimulationConfig band = load_config_string(
      kGrid + "[friction]\na = { profile = \"piecewise_constant\", z = [0.0, 0.04], values = [0.03, 0.005] }\n");
  CHECK_THROWS_WITH_AS(steady_sliding_of(band),
                       doctest::Contains("friction.a vary over the interface (a profile in [friction])"),
                       std::invalid_argument);
}

namespace {

// The grid above between dissimilar bodies: the top strip on a stiffer,
// denser base of twice its height with a clamped outer face
// (configs/3d/tiny_bodies.toml), sigma_eff relaxing over L_sigma = D.
const std::string kDissimilar =
    "[bottom]\nbody = \"elastic\"\nshear_modulus = 18e9\npoisson_ratio = 0.25\ndensity = 2400.0\n"
    "height = 0.05\nouter_face = \"clamped\"\n"
    "[interface]\nnormal_stress_slip = 1.667e-7\n";

// A rate-weakening band in z (a), two steps of b along x, D in two steps
// along z: the values of the formula at (x, z).
const std::string kBandFriction =
    "[friction]\ncharacteristic_slip = { profile = \"piecewise_constant\", z = [0.0, 0.06], "
    "values = [1.667e-7, 2.5e-7] }\n"
    "a = { profile = \"piecewise_linear\", z = [0.0, 0.02, 0.04, 0.08, 0.1, 0.125], "
    "values = [0.03, 0.03, 0.005, 0.005, 0.03, 0.03] }\n"
    "b = { profile = \"piecewise_constant\", x = [0.0, 0.1, 0.2], values = [0.075, 0.06, 0.075] }\n";
FrictionParameters band_formula(const FrictionParameters& scalars, double x, double z) {
  FrictionParameters p = scalars;
  p.a = piecewise_linear({0.0, 0.02, 0.04, 0.08, 0.1, 0.125}, {0.03, 0.03, 0.005, 0.005, 0.03, 0.03}, z);
  p.b = x < 0.1 ? 0.075 : x < 0.2 ? 0.06 : 0.075;
  p.characteristic_slip = z < 0.06 ? 1.667e-7 : 2.5e-7;
  return p;
}

}  // namespace

TEST_CASE("dissimilar bodies: constant profiles step bit for bit as the same numbers") {
  // The pair's path: the batch predictor-corrector with a normal stress per
  // node, per-node parameter spans against the uniform path.  A bump patch
  // and the noise make the normal stress change.
  const std::string bump = "local_amplitude = 1.0\nlocal_center = 0.125\nlocal_width = 0.02\n";
  const std::string base = kGrid + bump + kDissimilar;
  const SimulationConfig scalars = load_config_string(base);
  const SimulationConfig profiles = load_config_string(
      base +
      "[friction]\n"
      "a = { profile = \"piecewise_linear\", z = [0.0, 0.125], values = [0.005, 0.005] }\n"
      "b = { profile = \"piecewise_constant\", x = [0.0], values = [0.075] }\n"
      "characteristic_slip = { profile = \"piecewise_constant\", z = [0.0], values = [5e-7] }\n");
  REQUIRE(std::isnan(profiles.friction.characteristic_slip));
  REQUIRE(scalars.friction.characteristic_slip == 5e-7);
  Simulation3d one(scalars), other(profiles);
  REQUIRE(one.variable_normal_stress());
  REQUIRE(other.variable_normal_stress());
  for (int s = 0; s < 300; ++s) {
    one.step();
    other.step();
  }
  // Away from steady sliding and with a normal stress that varies node by node
  // (far above round-off), so every part of the pair's step is exercised.
  double sigma_change = 0.0;
  for (double s : one.normal_stress()) sigma_change = std::max(sigma_change, std::abs(s / 1e6 - 1.0));
  MESSAGE("dissimilar, 300 steps: max |v| / v0 = " << one.max_slip_rate() / scalars.loading.driving_velocity
                                                   << ", max |sigma / sigma0 - 1| = " << sigma_change);
  CHECK(one.max_slip_rate() > 1.01 * scalars.loading.driving_velocity);
  CHECK(sigma_change > 1e-5);  // far above round-off (1e-16)
  check_same_fields(one, other);
}

TEST_CASE("dissimilar bodies: every node runs with the formula's parameters") {
  const double v0 = 2e-3, sigma0 = 1e6;
  // Steady sliding, no perturbation: each node's state and tau_0 are those of
  // the formula's parameters, bit for bit (the same routines on the same
  // inputs), and sliding at v0 stays an equilibrium of the pair.
  const std::string steady =
      "[geometry]\nlength = 0.25\nwidth = 0.125\nheight = 0.025\nnodes = 16\nnodes_z = 8\n"
      "[loading]\ndriving_velocity = 2e-3\n[time]\nbeta = 0.24\n" +
      kDissimilar + kBandFriction;
  const SimulationConfig c = load_config_string(steady);
  Simulation3d sim(c);
  REQUIRE(sim.variable_normal_stress());
  for (int iz = 0; iz < kNz; ++iz)
    for (int ix = 0; ix < kNx; ++ix) {
      const std::size_t i = static_cast<std::size_t>(ix + kNx * iz);
      const FrictionParameters p = band_formula(c.friction, ix * kDx, iz * kDz);
      const double phi = steady_state(p, v0);
      CHECK(sim.state()[i] == phi);
      CHECK(sim.reference_shear_stress()[i] == frictional_strength(p, sigma0, v0, phi));
    }
  // tau_0 differs between the rows (the test would see a uniform tau_0).
  CHECK(sim.reference_shear_stress()[0] != sim.reference_shear_stress()[static_cast<std::size_t>(kNx * 3)]);
  for (int s = 0; s < 200; ++s) sim.step();
  double worst = 0.0, worst_sigma = 0.0;
  for (double v : sim.speed()) worst = std::max(worst, std::abs(v / v0 - 1.0));
  for (double s : sim.normal_stress()) worst_sigma = std::max(worst_sigma, std::abs(s / sigma0 - 1.0));
  MESSAGE("dissimilar, band, steady sliding 200 steps: max |v/v0 - 1| = " << worst
                                                                          << ", max |sigma/sigma0 - 1| = " << worst_sigma);
  // 1e-9: the local solve's tolerance carried through the history, as above.
  CHECK(worst <= 1e-9);
  CHECK(worst_sigma <= 1e-9);

  // Perturbed (a patch and noise): after 300 steps every node's traction is
  // its friction with the formula's parameters at its own sigma_eff,
  // |tau| = sigma_eff f_i(|v|, phi), to the local solve's tolerance: the slip
  // rate within 2e-12 relative of the root (friction/batch_solve.hpp), i.e.
  // (eta + d strength/d|v|) 2e-12 |v| in stress, plus 32 eps of the stresses
  // |tau| and eta |v| that tau = tau_h - eta v subtracts.
  const SimulationConfig perturbed = load_config_string(
      steady + "[initial]\nnoise_amplitude = 1e-2\nnoise_seed = 3\nlocal_amplitude = 1.0\nlocal_center = 0.125\n"
               "local_width = 0.02\nlocal_center_z = 0.06\nlocal_width_z = 0.02\n");
  Simulation3d run(perturbed);
  for (int s = 0; s < 300; ++s) run.step();
  const double eta = run.radiation_damping();
  double worst_residual = 0.0, smallest_wrong = std::numeric_limits<double>::infinity(), sigma_eff_change = 0.0;
  for (int iz = 0; iz < kNz; ++iz)
    for (int ix = 0; ix < kNx; ++ix) {
      const std::size_t i = static_cast<std::size_t>(ix + kNx * iz);
      const FrictionParameters p = band_formula(perturbed.friction, ix * kDx, iz * kDz);
      const double v = run.speed()[i], phi = run.state()[i], e = run.effective_normal_stress()[i];
      sigma_eff_change = std::max(sigma_eff_change, std::abs(e / sigma0 - 1.0));
      const double tau = std::hypot(run.shear_stress_x()[i], run.shear_stress_z()[i]);
      const double tolerance = (eta + frictional_strength_dv(p, e, v, phi)) * 2e-12 * v +
                               32.0 * std::numeric_limits<double>::epsilon() * (tau + eta * v);
      const double residual = std::abs(tau - frictional_strength(p, e, v, phi));
      worst_residual = std::max(worst_residual, residual / tolerance);
      CHECK(residual <= tolerance);
      // The same check with the band's a = 0.005 at the nodes outside it
      // (a = 0.03) misses by far: it sees each node's own parameters.
      if (p.a == 0.03) {
        FrictionParameters wrong = p;
        wrong.a = 0.005;
        smallest_wrong = std::min(smallest_wrong, std::abs(tau - frictional_strength(wrong, e, v, phi)) / tolerance);
      }
    }
  MESSAGE("dissimilar, band, perturbed 300 steps: max |v| / v0 = " << run.max_slip_rate() / v0
                                                                   << ", max |sigma_eff/sigma0 - 1| = " << sigma_eff_change
                                                                   << ", worst residual / tolerance = " << worst_residual
                                                                   << ", smallest residual / tolerance with a = 0.005 "
                                                                      "outside the band = "
                                                                   << smallest_wrong);
  CHECK(sigma_eff_change > 1e-5);  // far above round-off (1e-16)
  CHECK(smallest_wrong > 1e3);
}

TEST_CASE("dissimilar bodies: a profiled characteristic_slip needs a normal-stress memory of its own") {
  const std::string text =
      kGrid + "[bottom]\nbody = \"elastic\"\nshear_modulus = 18e9\nheight = 0.05\nouter_face = \"clamped\"\n"
              "[friction]\ncharacteristic_slip = { profile = \"piecewise_constant\", z = [0.0], values = [1e-7] }\n";
  CHECK(contains(error_of(text),
                 "interface.normal_stress_slip = 0 takes friction.characteristic_slip, which is a profile here: "
                 "expected interface.normal_stress_slip > 0 or interface.normal_stress_time > 0"));
  // Either memory key, or identical bodies, runs.
  CHECK_NOTHROW(load_config_string(text + "[interface]\nnormal_stress_time = 1e-4\n"));
  CHECK_NOTHROW(load_config_string(kGrid + "[friction]\ncharacteristic_slip = { profile = \"piecewise_constant\", "
                                           "z = [0.0], values = [1e-7] }\n"));
}
