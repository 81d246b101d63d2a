#pragma once
// The materials of the combined half-space pair's tests
// (test_kernels_half_space_pair, test_kernels_half_space_pair_operator):
// PMMA and Homalite in plane stress, a stronger plane-strain contrast (density
// ratio 2, shear-speed ratio 2), and PMMA's wave speeds at twice its density
// (a pair with a Stoneley wave).
#include "kernels/elastic_material.hpp"

namespace slipstrip::testing {

inline const ElasticMaterial kPmma{2.1e9, 0.35, 1170.0, PlaneCondition::stress};
inline const ElasticMaterial kHomalite{1.9e9, 0.34, 1230.0, PlaneCondition::stress};
inline const ElasticMaterial kStiff{2.1e9, 0.35, 1170.0, PlaneCondition::strain};
inline const ElasticMaterial kDenseSlow{1.05e9, 0.25, 2340.0, PlaneCondition::strain};
inline const ElasticMaterial kPmmaDense{4.2e9, 0.35, 2340.0, PlaneCondition::stress};

struct MaterialPair {
  const char* name;
  ElasticMaterial top, bottom;
};

}  // namespace slipstrip::testing
