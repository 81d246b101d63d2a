#pragma once
// Isotropic linear-elastic bulk of a body (SI units), and which deformation
// the interface problem poses: in-plane (plane strain or plane stress; slip
// along x, P and SV waves) or antiplane (slip along z, SH waves only;
// docs/bodies.md).
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <string_view>

namespace slipstrip {

enum class PlaneCondition { strain, stress, antiplane };
// The one spelling of each PlaneCondition (index = enumerator value), used by
// the config schema, the kernel cache key and the Python binding.
inline constexpr std::string_view kPlaneConditionNames[] = {"strain", "stress", "antiplane"};

// Allowed Poisson ratios: 0 < nu < 0.5 (both exclusive).  nu -> 0.5 makes the
// plane-strain c_d (and wave_speed_ratio_squared) infinite; nu <= 0 is
// excluded as unphysical for the rocks and polymers this models.  The config
// validator and linear stability both check this one range.
inline constexpr double kMinPoissonRatio = 0.0;
inline constexpr double kMaxPoissonRatio = 0.5;
inline bool poisson_ratio_allowed(double nu) { return nu > kMinPoissonRatio && nu < kMaxPoissonRatio; }

struct ElasticMaterial {
  double shear_modulus = 9e9;   // mu [Pa]
  double poisson_ratio = 0.33;  // nu [-]
  double density = 1200.0;      // rho [kg/m^3]
  PlaneCondition plane = PlaneCondition::strain;

  double shear_wave_speed() const { return std::sqrt(shear_modulus / density); }
  // eta = mu / (2 c_s) [Pa s/m], the radiation damping of two identical bodies
  // of this material: the instantaneous traction per unit slip rate (each face
  // moves at half the slip rate and radiates a plane shear wave, mu / c_s per
  // unit face velocity).  Every use of it (history operators, Simulation, the
  // local solve seen from Python) takes it from here.
  double radiation_damping() const { return shear_modulus / (2.0 * shear_wave_speed()); }
  // c_d^2/c_s^2: plane strain 2(1-nu)/(1-2nu); plane stress 2/(1-nu) (in-plane
  // P wave of a thin plate).  An antiplane body is a body invariant in z, so
  // its P wave (which the SH problem never excites) is the plane-strain one.
  double wave_speed_ratio_squared() const {
    const double nu = poisson_ratio;
    return plane == PlaneCondition::stress ? 2.0 / (1.0 - nu)
                                           : 2.0 * (1.0 - nu) / (1.0 - 2.0 * nu);
  }
  bool antiplane() const { return plane == PlaneCondition::antiplane; }
  double dilatational_wave_speed() const {
    return shear_wave_speed() * std::sqrt(wave_speed_ratio_squared());
  }
  // E' such that the static half-space stiffness is E'|k|/4 ... see docs/theory.md.
  double effective_modulus() const {
    const double nu = poisson_ratio;
    const double E = 2.0 * shear_modulus * (1.0 + nu);
    return plane == PlaneCondition::stress ? E : E / (1.0 - nu * nu);
  }
};

// Height H of each strip; +infinity means the half-space limit.
inline bool is_half_space(double strip_height) { return std::isinf(strip_height); }

}  // namespace slipstrip
