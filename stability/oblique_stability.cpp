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
  const complex along_x = rotated_response(c, s, F_P, F_SH).xx;
  const RotatedResponse elastic = rotated_response(c, s, S_P, S_SH);
  const complex along_z = elastic.zz + growth * (tau0 / v0);
  const complex cross = elastic.xz;
  return along_x * along_z - cross * cross;
}

RotatedResponse rotated_response(double c, double s, complex along, complex across) {
  return {c * c * along + s * s * across, c * s * (along - across), s * s * along + c * c * across};
}

SteadySliding antiplane_pair_sliding(const PairSliding& pair) {
  if (pair.top.rigid) throw std::invalid_argument("oblique pair stability: the top body must be deformable");
  SteadySliding s;
  s.material = pair.top.material;
  s.material.plane = PlaneCondition::antiplane;
  s.strip_height = pair.top.height;
  s.friction = pair.friction;
  s.normal_stress = pair.normal_stress;
  s.driving_velocity = pair.driving_velocity;
  s.two_bodies = true;
  s.bottom_rigid = pair.bottom.rigid;
  s.bottom_material = pair.bottom.material;
  s.bottom_material.plane = PlaneCondition::antiplane;
  s.bottom_height = pair.bottom.height;
  return s;
}

namespace {

// Everything of D that does not depend on Lambda, made once per wavevector.
struct ObliquePair {
  const PairSliding& pair;
  const LinearisedInterfaceFriction& friction;
  SteadySliding antiplane;
  double k, c, s;
  double damping;  // tau_0 / v0 [Pa s/m]

  ObliquePair(const PairSliding& p, const LinearisedInterfaceFriction& lin, double kx, double kz)
      : pair(p), friction(lin), antiplane(antiplane_pair_sliding(p)), k(std::hypot(kx, kz)) {
    if (!(k > 0.0)) throw std::invalid_argument("oblique pair stability: the wavevector must not be zero");
    c = kx / k;
    s = kz / k;
    // tau_0 = sigma_0 f(v0, phi_ss): the friction coefficient of the linearisation times sigma_0.
    damping = lin.friction_coefficient * p.normal_stress / p.driving_velocity;
  }

  complex operator()(complex z) const {
    const SlipResponse inplane = interface_slip_response(pair.top, pair.bottom, k, z);
    const complex across = slip_response(antiplane, k, z);
    const RotatedResponse elastic = rotated_response(c, s, inplane.shear, across);
    // The friction along x per unit normal-stress change, times K_n: fed by delta_k.
    const complex normal = inplane.normal != 0.0 ? normal_stress_response(friction, z, inplane.normal) : 0.0;
    const complex xx = elastic.xx + rate_and_state_response(friction, z) + c * normal;
    const complex xz = elastic.xz + s * normal;
    const complex zz = elastic.zz + z * damping;
    return xx * zz - xz * elastic.xz;
  }
};

}  // namespace

complex oblique_pair_characteristic_function(const PairSliding& pair, const LinearisedInterfaceFriction& friction,
                                             double kx, double kz, complex growth) {
  return ObliquePair(pair, friction, kx, kz)(growth);
}

std::vector<complex> oblique_pair_characteristic_roots(const PairSliding& pair,
                                                       const LinearisedInterfaceFriction& friction, double kx,
                                                       double kz, const PairSearchBox& box) {
  if (!(box.min_re > 0.0) || !(box.max_re > box.min_re) || !(box.max_im > 0.0))
    throw std::invalid_argument("oblique_pair_characteristic_roots: need 0 < min_re < max_re and max_im > 0");
  // Poles of D: those of K_ser and of the antiplane pair on Re = 0, g_phi and
  // -1/T on the negative real axis; none inside the box.
  const ObliquePair D(pair, friction, kx, kz);
  return pair_zeros_in([&D](complex z) { return D(z); }, box);
}

std::vector<complex> oblique_pair_roots(const PairSliding& pair, double kx, double kz) {
  const LinearisedInterfaceFriction lin = linearise_interface_friction(pair);
  const double k = std::hypot(kx, kz);
  return oblique_pair_characteristic_roots(pair, lin, kx, kz, pair_search_box(pair, lin, k));
}

std::vector<complex> oblique_characteristic_roots(const SteadySliding& sliding, double kx, double kz,
                                                  const SearchBox& box) {
  const AnalyticFunction D = [&](complex z) { return oblique_characteristic_function(sliding, kx, kz, z); };
  const Rectangle rectangle{box.min_re, box.max_re, -box.max_im, box.max_im};
  return sorted_zeros_in(D, rectangle);
}

}  // namespace slipstrip
