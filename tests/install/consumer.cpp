// Runs a few steps of the default (Table S1) problem through the installed
// library and prints the time step and the maximum slip rate.
#include <cstdio>

#include "solver/simulation.hpp"
#include "slipstrip/version.hpp"

int main() {
  slipstrip::SimulationConfig config;
  config.geometry.nodes = 64;
  config.geometry.length = 0.8;
  config.initial.noise_amplitude = 1e-3;
  slipstrip::Simulation simulation(config);
  for (int i = 0; i < 10; ++i) simulation.step();
  std::printf("dt %.6e max_slip_rate %.6e\n", simulation.time_step(), simulation.max_slip_rate());
  return simulation.step_index() == 10 ? 0 : 1;
}
