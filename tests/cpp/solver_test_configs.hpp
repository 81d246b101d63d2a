#pragma once
// Configs shared by the solver tests: a short strip pair, a dissimilar bottom
// body, and the nonlinear initial perturbation the comparison tests start from.
#include "config/simulation_config.hpp"

namespace slipstrip::testing {

// Table S1 defaults, strips of height 0.1 m, `length` [m] over `nodes` nodes,
// time step beta = `beta` (dt = beta dx / c_s).
inline SimulationConfig short_strip_pair(double length, int nodes, double beta) {
  SimulationConfig c;
  c.geometry.length = length;
  c.geometry.height = 0.1;
  c.geometry.nodes = nodes;
  c.time.beta = beta;
  return c;
}

// The top strip of `c` on a slower, denser bottom body of another Poisson
// ratio and half the height with a clamped outer face: c_s of the bottom is
// half the top's, so its echo 2 H_b / c_b equals the top's and the time step
// is the top strip's.
inline SimulationConfig with_dissimilar_bottom(SimulationConfig c) {
  c.bottom.body = BodyKind::elastic;
  c.bottom.shear_modulus = 4.5e9;
  c.bottom.density = 2400.0;
  c.bottom.poisson_ratio = 0.25;
  c.bottom.height = 0.05;
  c.bottom.outer_face = OuterFace::clamped;
  return c;
}

// The top strip of `c` on a strip of half its shear modulus and twice its
// density (c_b = c_t / 2), H_b = 0.1 m, driven: the bottom echo 2 H_b / c_b is
// a whole number of the top's, so the bottom height is used as given.  With the
// Table S1 top strip H = 0.1 m its oblique (1, 1) mode of a 1 m x 1 m interface
// is unstable (stability/oblique_stability.hpp).
inline SimulationConfig with_compliant_bottom(SimulationConfig c) {
  c.bottom.body = BodyKind::elastic;
  c.bottom.shear_modulus = 4.5e9;
  c.bottom.density = 2400.0;
  c.bottom.height = 0.1;
  return c;
}

// A large initial perturbation (a sine of amplitude 0.5 and a bump of 2 of
// width 0.05 m at `center` [m] in the state): the run leaves steady sliding
// (max |v| several v0) within a few hundred steps.
inline void add_large_perturbation(SimulationConfig& c, double center) {
  c.initial.sine_amplitude = 0.5;
  c.initial.local_amplitude = 2.0;
  c.initial.local_center = center;
  c.initial.local_width = 0.05;
}

}  // namespace slipstrip::testing
