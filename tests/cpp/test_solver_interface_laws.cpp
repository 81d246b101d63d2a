// The interface-law registry (laws/interface_law.hpp): Simulation runs
// whatever law the config names, including one it has never heard of.
#include <doctest/doctest.h>

#include <cmath>
#include <string>

#include "config/config.hpp"
#include "solver/simulation.hpp"
#include "toy_interface_law.hpp"

using namespace slipstrip;

namespace {

SimulationConfig pulse_config(InterfaceLawName law) {
  SimulationConfig c;
  c.geometry = {0.4, 0.1, 32};
  c.interface.law = law;
  c.interface.profile = TimeProfile::bump;
  c.interface.stress_amplitude = 1e5;
  c.interface.pulse_width = 0.05;
  c.interface.pulse_center = 0.2;
  return c;
}

double rms(std::span<const double> v) {
  double s = 0.0;
  for (double x : v) s += x * x;
  return std::sqrt(s / static_cast<double>(v.size()));
}

}  // namespace

TEST_CASE("the built-in laws are registered under their config names") {
  const auto laws = builtin_interface_laws();
  REQUIRE(laws.names().size() == 3);
  CHECK(laws.find("rate_and_state") != nullptr);
  CHECK(laws.find("prescribed_slip") != nullptr);
  CHECK(laws.find("free") != nullptr);
  CHECK(laws.find("viscous") == nullptr);
  CHECK(load_config_string("[interface]\nlaw = \"free\"\n").interface.law == InterfaceLawName::free);
  CHECK_THROWS_WITH_AS(Simulation(pulse_config(InterfaceLawName{"viscous"})),
                       doctest::Contains("interface.law = 'viscous' is not a registered interface "
                                         "law: expected one of rate_and_state, prescribed_slip, free"),
                       std::invalid_argument);
  auto twice = builtin_interface_laws();
  CHECK_THROWS_AS(twice.add({"free", twice.find("free")->make}), std::invalid_argument);
}

TEST_CASE("a toy law added by one registration line runs, and behaves as a viscous interface") {
  auto laws = builtin_interface_laws();
  laws.add({"viscous", &testing::make_viscous_law});  // the registration line

  auto c_viscous = pulse_config(InterfaceLawName{"viscous"});
  auto c_free = pulse_config(InterfaceLawName::free);
  {
    const Simulation probe(c_free);
    c_viscous.interface.rise_time = c_free.interface.rise_time = 40 * probe.time_step();
  }
  Simulation viscous(c_viscous, {}, laws), free(c_free, {}, laws);
  // First step: the history is still empty (v = 0 at t = 0), so the viscous
  // slip rate is the free one times eta / (eta + 4 eta) = 1/5.
  viscous.step();
  free.step();
  for (std::size_t i = 0; i < viscous.x().size(); ++i)
    CHECK(viscous.slip_rate()[i] == doctest::Approx(free.slip_rate()[i] / 5.0).epsilon(1e-14));
  // The free strips ring without loss; the viscous interface dissipates
  // (shear_stress * slip_rate = -4 eta v^2 < 0).  After ~6 round trips 2H/c_s
  // past the pulse, its motion is a small fraction of the free ringing.
  for (int n = 1; n < 440; ++n) {
    viscous.step();
    free.step();
  }
  const double ratio = rms(viscous.slip_rate()) / rms(free.slip_rate());
  MESSAGE("rms slip rate, viscous / free, after 440 steps: " << ratio);
  CHECK(ratio < 0.05);
  for (std::size_t i = 0; i < viscous.x().size(); ++i)
    CHECK(viscous.shear_stress()[i] == -4.0 * viscous.radiation_damping() * viscous.slip_rate()[i]);
}
