#include "stability/oblique_stability.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "kernels/strip_response.hpp"
#include "stability/root_search.hpp"

namespace slipstrip {

complex oblique_characteristic_function(const SteadySliding& sliding, double kx, double kz, complex growth) {
  const double k = std::hypot(kx, kz);
  if (!(k > 0.0)) throw std::invalid_argument("oblique stability: the wavevector must not be zero");
  const double c = kx / k, s = kz / k;
  SteadySliding inplane = sliding, antiplane = sliding;
  inplane.material.plane = PlaneCondition::strain;
  antiplane.material.plane = PlaneCondition::antiplane;
  const complex F_P = characteristic_function(inplane, k, growth);
  const complex F_SH = characteristic_function(antiplane, k, growth);
  const complex S_P = strip_response(inplane.material, sliding.strip_height, k, growth);
  const complex S_SH = strip_response(antiplane.material, sliding.strip_height, k, growth);
  const double v0 = sliding.driving_velocity;
  const double tau0 = frictional_strength(sliding.friction, sliding.normal_stress, v0,
                                          linearise_friction(sliding).state);
  const complex along_x = c * c * F_P + s * s * F_SH;
  const complex along_z = s * s * S_P + c * c * S_SH + growth * (tau0 / v0);
  const complex cross = c * s * (S_P - S_SH);
  return along_x * along_z - cross * cross;
}

std::vector<complex> oblique_characteristic_roots(const SteadySliding& sliding, double kx, double kz,
                                                  const SearchBox& box) {
  const AnalyticFunction D = [&](complex z) { return oblique_characteristic_function(sliding, kx, kz, z); };
  const Rectangle rectangle{box.min_re, box.max_re, -box.max_im, box.max_im};
  return sorted_zeros_in(D, rectangle);
}

}  // namespace slipstrip
