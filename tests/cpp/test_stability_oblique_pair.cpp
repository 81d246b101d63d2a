// Linear stability of an oblique mode of two different bodies on a 2D interface
// (stability/oblique_stability.hpp, docs/3d.md §2) in its limits, each against
// an independent function of the 1D theory:
//   (a) kz = 0: the roots are the 1D in-plane pair's (pair_characteristic_roots),
//       with the normal-stress memory and with Linker-Dieterich;
//   (b) identical bodies: the roots are those of the identical bodies' oblique
//       function (oblique_characteristic_roots);
//   (c) kx = 0: the roots are the 1D antiplane pair's (characteristic_roots of
//       antiplane_pair_sliding), whatever the normal-stress memory, because slip
//       along z feeds the normal stress but nothing feeds back;
// and the roots at -k are the conjugates of those at k.  The growth rates
// against 2D-interface simulations are in test_solver_interface_2d_bodies.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <string>
#include <vector>

#include "solver_test_configs.hpp"
#include "stability/interface_stability.hpp"
#include "stability/oblique_stability.hpp"
#include "stability/steady_sliding.hpp"

using namespace slipstrip;

namespace {

using cd = std::complex<double>;
constexpr double pi = std::numbers::pi;

// The pair of the simulation test (testing::with_compliant_bottom).
SimulationConfig dissimilar_pair(double length) {
  return testing::with_compliant_bottom(testing::short_strip_pair(length, 8, 0.2));
}

// Each root of `expected` has one in `roots` within `tolerance` of |root|
// (Newton-polished roots of two functions equal to rounding), and the counts agree.
void check_same_roots(const std::vector<cd>& roots, const std::vector<cd>& expected, double tolerance) {
  REQUIRE(roots.size() == expected.size());
  for (const cd z : expected) {
    const cd nearest = *std::min_element(roots.begin(), roots.end(), [z](cd a, cd b) {
      return std::abs(a - z) < std::abs(b - z);
    });
    MESSAGE("root " << z << ", found " << nearest << ", relative " << std::abs(nearest - z) / std::abs(z));
    CHECK(std::abs(nearest - z) <= tolerance * std::abs(z));
  }
}

std::vector<cd> unstable(std::vector<cd> roots) {
  std::erase_if(roots, [](cd z) { return !(z.real() > 0.0); });
  return roots;
}

}  // namespace

TEST_CASE("oblique pair, kz = 0: the 1D in-plane pair's roots and function (memory, Linker-Dieterich, rigid base)") {
  SimulationConfig rigid = dissimilar_pair(4.0);
  rigid.geometry.height = 0.4;
  rigid.bottom.body = BodyKind::rigid;
  SimulationConfig ld = rigid;
  ld.friction.linker_dieterich = 0.3;
  struct Case {
    const char* name;
    SimulationConfig config;
    double wavelength;
  };
  for (const Case& c : {Case{"strips", dissimilar_pair(1.0), 1.0}, Case{"rigid base", rigid, 4.0},
                        Case{"rigid base, LD 0.3", ld, 4.0}}) {
    CAPTURE(c.name);
    const PairSliding pair = pair_sliding_of(c.config);
    const LinearisedInterfaceFriction lin = linearise_interface_friction(pair);
    const double k = 2 * pi / c.wavelength;
    const PairSearchBox box = pair_search_box(pair, lin, k);
    // The function: D = F_pair (A + Lambda tau_0/v0), A the antiplane pair's response.
    const SteadySliding antiplane = antiplane_pair_sliding(pair);
    const double damping = lin.friction_coefficient * pair.normal_stress / pair.driving_velocity;
    double worst = 0.0;
    for (const cd z : {cd(30.0, 2e3), cd(500.0, -7e3), cd(2e3, 100.0), cd(1e-3, 4e4)}) {
      const cd expected = pair_characteristic_function(pair, lin, k, z) * (slip_response(antiplane, k, z) + z * damping);
      worst = std::max(worst, std::abs(oblique_pair_characteristic_function(pair, lin, k, 0.0, z) - expected) /
                                  std::abs(expected));
    }
    MESSAGE(std::string(c.name) << ": D against F_pair (A + Lambda tau_0/v0), worst relative " << worst);
    CHECK(worst <= 1e-13);  // the same products, in another order
    const auto roots = unstable(oblique_pair_characteristic_roots(pair, lin, k, 0.0, box));
    const auto expected = unstable(pair_characteristic_roots(pair, lin, k, box));
    REQUIRE(!expected.empty());
    check_same_roots(roots, expected, 1e-8);
  }
}

TEST_CASE("oblique pair, identical bodies: the identical oblique roots (30 deg, lambda = 2.4 m)") {
  // The case of the identical bodies' simulation test (test_solver_interface_2d).
  const double wavelength = 2.4, angle = pi / 6;
  const double k = 2 * pi / wavelength, kx = k * std::cos(angle), kz = k * std::sin(angle);
  SimulationConfig c = testing::short_strip_pair(2 * pi / kx, 8, 0.25);
  c.bottom.body = BodyKind::elastic;  // the same material and height: identical, through the pair path
  c.bottom.shear_modulus = c.material.shear_modulus;
  c.bottom.density = c.material.density;
  c.bottom.poisson_ratio = c.material.poisson_ratio;
  c.bottom.height = c.geometry.height;
  const PairSliding pair = pair_sliding_of(c);
  REQUIRE(is_mirror_pair(pair));
  SimulationConfig mirror = c;
  mirror.bottom.body = BodyKind::mirror;
  const SteadySliding sliding = steady_sliding_of(mirror);
  const LinearisedInterfaceFriction lin = linearise_interface_friction(pair);
  double worst = 0.0;
  for (const cd z : {cd(30.0, 2e3), cd(500.0, -7e3), cd(1388.0, 4e3), cd(1e-3, 4e4)}) {
    const cd expected = oblique_characteristic_function(sliding, kx, kz, z);
    worst = std::max(worst, std::abs(oblique_pair_characteristic_function(pair, lin, kx, kz, z) - expected) /
                                std::abs(expected));
  }
  MESSAGE("D of the pair against the identical bodies' D, worst relative " << worst);
  CHECK(worst <= 1e-12);  // K_ser = S and the series antiplane pair = S_SH to rounding
  // The identical test's box (its left edge off the strip's resonances).
  SearchBox box = unstable_search_box(sliding);
  box.min_re = 1e-4 * box.max_im;
  const auto expected = oblique_characteristic_roots(sliding, kx, kz, box);
  REQUIRE(!expected.empty());
  const auto roots = oblique_pair_characteristic_roots(pair, lin, kx, kz, {box.min_re, box.max_re, box.max_im});
  check_same_roots(roots, expected, 1e-8);
}

TEST_CASE("oblique pair, kx = 0: the 1D antiplane pair's roots, the normal stress does not feed back") {
  // The pair is unstable at kz = 2 pi / sqrt(2) m as an antiplane pair (slip along x
  // across k-hat = z).
  const double wavelength = std::sqrt(2.0), k = 2 * pi / wavelength;
  for (double memory : {0.0, 1e-3}) {
    SimulationConfig c = dissimilar_pair(1.0);
    c.interface.normal_stress_time = memory;  // 0: the slip memory over D
    c.friction.linker_dieterich = memory > 0 ? 0.3 : 0.0;
    const PairSliding pair = pair_sliding_of(c);
    const LinearisedInterfaceFriction lin = linearise_interface_friction(pair);
    const SteadySliding antiplane = antiplane_pair_sliding(pair);
    const auto expected = unstable(characteristic_roots(antiplane, wavelength));
    REQUIRE(!expected.empty());
    for (double kz : {k, -k}) {
      CAPTURE(kz);
      const auto roots = unstable(oblique_pair_characteristic_roots(pair, lin, 0.0, kz, pair_search_box(pair, lin, k)));
      check_same_roots(roots, expected, 1e-8);
    }
  }
}

TEST_CASE("oblique pair: the roots at -k are the conjugates of those at k, and differ from them") {
  const PairSliding pair = pair_sliding_of(dissimilar_pair(1.0));
  const double k = 2 * pi;  // the (1, 1) mode of a 1 m x 1 m cell
  const auto roots = unstable(oblique_pair_roots(pair, k, k));
  auto conjugates = unstable(oblique_pair_roots(pair, -k, -k));
  REQUIRE(roots.size() == 2);
  for (cd& z : conjugates) z = std::conj(z);
  check_same_roots(conjugates, roots, 1e-8);
  // The pair is not symmetric under x -> -x: the two waves grow at different rates.
  CHECK(std::abs(roots[0].real() - roots[1].real()) > 0.1 * roots[0].real());
  // An oblique mode grows more slowly than the in-plane mode at the same |k|.
  const auto flat = unstable(oblique_pair_roots(pair, std::sqrt(2.0) * k, 0.0));
  REQUIRE(!flat.empty());
  MESSAGE("(1, 1): " << roots[0] << ", " << roots[1] << "; in-plane at |k|: " << flat.front());
  CHECK(roots.front().real() < flat.front().real());
}
