#pragma once
// The steady-sliding problem that linear stability analyses, read off a run's
// config: one definition, so the CLI, Python and the tests analyse exactly the
// problem the solver simulates.
#include "core/simulation_config.hpp"
#include "friction/linear_stability.hpp"

namespace slipstrip {

inline SteadySliding steady_sliding_of(const SimulationConfig& config) {
  SteadySliding sliding;
  sliding.material = config.material;
  sliding.strip_height = config.geometry.height;
  sliding.friction = config.friction;
  sliding.normal_stress = config.loading.normal_stress;
  sliding.driving_velocity = config.loading.driving_velocity;
  return sliding;
}

}  // namespace slipstrip
