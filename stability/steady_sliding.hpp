#pragma once
// The steady-sliding problem that linear stability analyses, read off a run's
// config: one definition, so the CLI, Python and the tests analyse exactly the
// problem the solver simulates.  Throws std::invalid_argument when the
// [friction] parameters vary along x.
#include "config/simulation_config.hpp"
#include "stability/linear_stability.hpp"

namespace slipstrip {

inline SteadySliding steady_sliding_of(const SimulationConfig& config) {
  SteadySliding sliding;
  sliding.material = config.material;
  sliding.strip_height = config.geometry.height;
  // Linear stability perturbs *homogeneous* steady sliding: with parameters
  // that vary along x it does not apply, and node 0's values must not stand in.
  sliding.friction = uniform_friction(config.friction, config.friction_along_x,
                                      static_cast<std::size_t>(config.geometry.nodes),
                                      config.geometry.length / config.geometry.nodes,
                                      "linear stability (growth rates, Lc(H))");
  sliding.normal_stress = config.loading.normal_stress;
  sliding.driving_velocity = config.loading.driving_velocity;
  sliding.two_bodies = config.bottom.body != BodyKind::mirror;
  sliding.bottom_rigid = config.bottom.body == BodyKind::rigid;
  sliding.bottom_material = bottom_material(config);
  sliding.bottom_height = config.bottom.height;
  return sliding;
}

}  // namespace slipstrip
