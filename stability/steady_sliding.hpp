#pragma once
// The steady-sliding problem that linear stability analyses, read off a run's
// config: one definition, so the CLI, Python and the tests analyse exactly the
// problem the solver simulates.  Throws std::invalid_argument when the
// [friction] parameters vary along x.
#include "config/simulation_config.hpp"
#include <stdexcept>
#include <string>

#include "stability/interface_stability.hpp"
#include "stability/linear_stability.hpp"

namespace slipstrip {

inline SteadySliding steady_sliding_of(const SimulationConfig& config) {
  SteadySliding sliding;
  sliding.material = config.material;
  sliding.strip_height = config.geometry.height;
  // Linear stability perturbs *homogeneous* steady sliding: with parameters
  // that vary along x it does not apply, and node 0's values must not stand in.
  sliding.friction = uniform_friction(config.friction, config.friction_profiles, friction_node_grid(config),
                                      "linear stability (growth rates, Lc(H))");
  sliding.normal_stress = config.loading.normal_stress;
  sliding.driving_velocity = config.loading.driving_velocity;
  sliding.two_bodies = config.bottom.body != BodyKind::mirror;
  // In-plane dissimilar pairs couple slip to the normal stress: the scalar
  // series stiffness used here would omit it.  Their theory is pair_sliding_of
  // + stability/interface_stability.hpp.
  if (sliding.two_bodies && !config.material.antiplane())
    throw std::invalid_argument(
        "bottom.body = \"" + std::string(kBodyKindNames[static_cast<std::size_t>(config.bottom.body)]) +
        "\" in-plane: growth_rates/Lc(H) here are for identical or antiplane pairs; in-plane dissimilar "
        "pairs are analysed by stability/interface_stability (pair_sliding_of)");
  sliding.bottom_rigid = config.bottom.body == BodyKind::rigid;
  sliding.bottom_material = bottom_material(config);
  sliding.bottom_height = config.bottom.height;
  return sliding;
}

// The same problem for stability/interface_stability (any pair, in-plane):
// both bodies with their outer faces, and the normal-stress memory the solver
// uses (interface.normal_stress_slip / normal_stress_time).
inline PairSliding pair_sliding_of(const SimulationConfig& config) {
  PairSliding pair;
  pair.top = ElasticBody{config.material, config.geometry.height, config.top.outer_face, false};
  pair.bottom = ElasticBody{bottom_material(config), bottom_height(config), config.bottom.outer_face,
                            config.bottom.body == BodyKind::rigid};
  pair.friction = uniform_friction(config.friction, config.friction_profiles, friction_node_grid(config),
                                   "linear stability (growth rates, Lc(H))");
  const auto& in = config.interface;
  if (in.normal_stress_time > 0.0) {
    pair.normal_response.kind = NormalStressResponse::time;
    pair.normal_response.time = in.normal_stress_time;
  } else {
    pair.normal_response.kind = NormalStressResponse::slip;
    pair.normal_response.slip = in.normal_stress_slip > 0.0 ? in.normal_stress_slip : config.friction.characteristic_slip;
  }
  pair.normal_stress = config.loading.normal_stress;
  pair.driving_velocity = config.loading.driving_velocity;
  return pair;
}

}  // namespace slipstrip
