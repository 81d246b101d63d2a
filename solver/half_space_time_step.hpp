#pragma once
// The refusal of a time step too long for a half-space body's in-plane 2x2
// operator (kernels/face_half_space.hpp), shared by the line (Simulation,
// docs/bodies.md §4) and the 2D interface (Simulation3d, docs/3d.md).  The
// operator exists only while c_s |k| dt stays at most
// face_half_space_passive_limit (a function of the Poisson ratio) at the
// grid's largest |k|; as the step is proportional to time.beta, the bound on
// time.beta is time.beta * limit / (c_s |k|_max dt).
#include <string>

#include "kernels/elastic_material.hpp"

namespace slipstrip {

struct HalfSpaceTimeStepBound {
  double h = 0.0;         // c_s |k|_max dt at the run's step
  double limit = 0.0;     // the largest passive c_s |k| dt (0: none found)
  double beta_max = 0.0;  // time.beta * limit / h
};

// The bound for a body of material `m` (its plane condition as the operator
// takes it) on a grid whose largest |k| is `k_max` [1/m], at `time_step` [s]
// and `beta` = time.beta.  `failed_h` > 0: the c_s |k| dt at which the
// operator failed, where the bisection for the limit starts (default: h).
HalfSpaceTimeStepBound half_space_time_step_bound(const ElasticMaterial& m, double k_max, double time_step,
                                                  double beta, double failed_h = 0.0);

// The one-line refusal naming time.beta, the body ("top" or "bottom", its
// key material.poisson_ratio or bottom.poisson_ratio and value) and the
// bound.  `interface_2d`: the 2D interface's wording (the grid's largest |k|,
// docs/3d.md); otherwise the line's (the shortest wavelength, the plane
// condition, docs/bodies.md §4).
std::string half_space_time_step_message(double beta, const std::string& body, const ElasticMaterial& m,
                                         double k_max, const HalfSpaceTimeStepBound& bound, bool interface_2d);

}  // namespace slipstrip
