#include "solver/half_space_time_step.hpp"

#include <iomanip>
#include <sstream>

#include "kernels/face_half_space.hpp"

namespace slipstrip {

HalfSpaceTimeStepBound half_space_time_step_bound(const ElasticMaterial& m, double k_max, double time_step,
                                                  double beta, double failed_h) {
  HalfSpaceTimeStepBound b;
  b.h = m.shear_wave_speed() * k_max * time_step;
  b.limit = face_half_space_passive_limit(1.0 / m.wave_speed_ratio_squared(), HalfSpaceOperatorDesign{},
                                          failed_h > 0.0 ? failed_h : b.h);
  b.beta_max = beta * b.limit / b.h;
  return b;
}

std::string half_space_time_step_message(double beta, const std::string& body, const ElasticMaterial& m,
                                         double k_max, const HalfSpaceTimeStepBound& bound, bool interface_2d) {
  const char* key = body == "top" ? "material.poisson_ratio" : "bottom.poisson_ratio";
  std::ostringstream msg;
  msg << "time.beta = " << beta << " is too large for the " << body << " body, a half-space with " << key << " = "
      << m.poisson_ratio;
  if (interface_2d)
    msg << " on a 2D interface";
  else
    msg << " (plane " << (m.plane == PlaneCondition::stress ? "stress" : "strain") << ")";
  msg << ": its passive 2x2 operator needs c_s " << (interface_2d ? "|k|" : "k") << " dt <= " << std::setprecision(4)
      << bound.limit;
  if (interface_2d)
    msg << " at the grid's largest |k| = " << k_max << " 1/m";
  else
    msg << " at the shortest wavelength";
  msg << ", i.e. time.beta <= " << bound.beta_max << " here (" << (interface_2d ? "docs/3d.md" : "docs/bodies.md §4")
      << ")";
  return msg.str();
}

}  // namespace slipstrip
