// Dissimilar bodies on a 2D interface (kernels/interface_2d_history.hpp,
// InterfaceHistory2d::build_pair): an oblique single Fourier mode of the slip
// rate (and of the opening stress) against the rotated combination of the 1D
// pairs' responses at |k|, the in-plane pair (InplanePairHistory over each
// body's 2x2 FaceModalHistory) fed with the slip along k-hat and the antiplane
// pair (TwoBodyHistory) fed with the slip across it.  Those 1D operators are
// verified on their own (test_kernels_face_history, test_kernels_two_body,
// test_solver_inplane_bodies).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <memory>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "kernels/face_history.hpp"
#include "kernels/history_convolution.hpp"
#include "kernels/inplane_pair_history.hpp"
#include "kernels/interface_2d_history.hpp"
#include "kernels/two_body_history.hpp"
#include "single_mode_drive.hpp"

using namespace slipstrip;
using cd = std::complex<double>;

TEST_CASE("dissimilar bodies, oblique single mode: traction and normal stress = rotated 1D in-plane and antiplane pairs") {
  ElasticMaterial top_material;  // Table S1
  ElasticMaterial bottom_material = top_material;
  bottom_material.shear_modulus = 4.5e9;
  bottom_material.density = 2400.0;
  bottom_material.poisson_ratio = 0.25;
  const InterfaceGrid2d grid{0.8, 0.4, 8, 8};  // dx = 0.1 m, dz = 0.05 m
  const TwoBodyTiming timing = two_body_time_step(top_material, 0.1, bottom_material, 0.05, 0.05, 0.2);
  const double dt = timing.time_step;
  for (const bool rigid : {false, true}) {
    const InterfaceBody top{top_material, 0.1, OuterFace::driven};
    std::optional<InterfaceBody> bottom;
    if (!rigid) bottom = InterfaceBody{bottom_material, timing.bottom_height, OuterFace::clamped};
    InterfaceHistory2d op = InterfaceHistory2d::build_pair(top, bottom, grid, dt);
    REQUIRE(op.variable_normal_stress());
    const InterfaceWavevectors k = interface_wavevectors(grid);
    // Modes (qx, qz) = (1, 1): 26.6 deg from x; (2, 7): kz < 0, -14 deg.
    for (const auto& [qx, qz] : {std::pair{1, 1}, std::pair{2, 7}}) {
      const std::size_t slot = static_cast<std::size_t>(qz) * (grid.nodes_x / 2 + 1) + qx;
      const double magnitude = k.magnitude[slot], c = k.kx[slot] / magnitude, s = k.kz[slot] / magnitude;
      const std::vector<double> wavenumbers{0.0, magnitude};
      // The 1D pairs at this |k| (mode 1 of each).
      ElasticMaterial strain_top = testing::with_plane(top_material, PlaneCondition::strain);
      ElasticMaterial strain_bottom = testing::with_plane(bottom_material, PlaneCondition::strain);
      ElasticMaterial sh_top = testing::with_plane(top_material, PlaneCondition::antiplane);
      ElasticMaterial sh_bottom = testing::with_plane(bottom_material, PlaneCondition::antiplane);
      InplanePairHistory inplane(
          std::make_unique<FaceModalHistory>(strain_top, 0.1, OuterFace::driven, wavenumbers, dt),
          rigid ? nullptr
                : std::make_unique<FaceModalHistory>(strain_bottom, timing.bottom_height, OuterFace::clamped,
                                                     wavenumbers, dt));
      auto sh_operator = [&](const ElasticMaterial& m, double height) {
        return std::make_unique<StripHistory>(m, compute_strip_kernels(m, height, wavenumbers, dt));
      };
      TwoBodyHistory antiplane(sh_operator(sh_top, 0.1),
                               rigid ? nullptr : sh_operator(sh_bottom, timing.bottom_height));
      REQUIRE(op.radiation_damping() == inplane.radiation_damping());
      REQUIRE(op.normal_radiation_damping() == inplane.normal_radiation_damping());

      std::vector<cd> vx(grid.modes(), 0.0), vz(grid.modes(), 0.0), opening(grid.modes(), 0.0);
      std::vector<cd> along(2, 0.0), across(2, 0.0), opening_1d(2, 0.0);
      const double rise = 60 * dt;
      double worst_x = 0.0, worst_z = 0.0, worst_normal = 0.0, largest = 0.0, largest_normal = 0.0;
      double other_modes = 0.0;
      for (int n = 0; n < 400; ++n) {
        const double v = testing::bump_rate(n * dt, rise);
        vx[slot] = v * cd(1.0, 0.3);
        vz[slot] = v * cd(-0.5, 0.2);
        // An opening stress for part of the run (the faces pushed apart), else none.
        const bool opens = n >= 100 && n < 160;
        opening[slot] = opens ? cd(2e4 * testing::bump_rate((n - 100) * dt, 60 * dt) * dt, 0.0) : cd(0.0);
        if (opens) op.push(vx, vz, opening);
        else op.push(vx, vz, {});
        along[1] = c * vx[slot] + s * vz[slot];
        across[1] = c * vz[slot] - s * vx[slot];
        opening_1d[1] = opening[slot];
        if (opens) inplane.push(along, opening_1d);
        else inplane.push(along);
        antiplane.push(across);
        const cd hx = c * inplane.history()[1] - s * antiplane.history()[1];
        const cd hz = s * inplane.history()[1] + c * antiplane.history()[1];
        worst_x = std::max(worst_x, std::abs(op.history_x()[slot] - hx));
        worst_z = std::max(worst_z, std::abs(op.history_z()[slot] - hz));
        worst_normal = std::max(worst_normal, std::abs(op.normal_stress()[slot] - inplane.normal_stress()[1]));
        largest = std::max({largest, std::abs(hx), std::abs(hz)});
        largest_normal = std::max(largest_normal, std::abs(inplane.normal_stress()[1]));
        for (std::size_t m = 0; m < grid.modes(); ++m)
          if (m != slot)
            other_modes = std::max({other_modes, std::abs(op.history_x()[m]), std::abs(op.history_z()[m]),
                                    std::abs(op.normal_stress()[m])});
      }
      MESSAGE(std::string(rigid ? "rigid base" : "dissimilar strips") << ", mode (" << qx << ", " << qz << "), |k| = "
              << magnitude << " 1/m: max |h| = " << largest << " Pa, max |sigma| = " << largest_normal
              << " Pa; differences " << worst_x / largest << ", " << worst_z / largest << " (of max |h|), "
              << worst_normal / largest_normal << " (of max |sigma|); other modes " << other_modes);
      REQUIRE(largest > 0.0);
      REQUIRE(largest_normal > 0.0);
      // The same discrete operators (the designs of this |k| bit for bit), the
      // same rotations: only the order of a few products may differ; 1e-13 is
      // ~500 ulps.
      CHECK(worst_x <= 1e-13 * largest);
      CHECK(worst_z <= 1e-13 * largest);
      CHECK(worst_normal <= 1e-13 * largest_normal);
      CHECK(other_modes == 0.0);  // modes do not couple
      for (auto* f : {&vx, &vz, &opening}) std::fill(f->begin(), f->end(), 0.0);
      // Reset the operator between modes: a fresh one for the next mode.
      op = InterfaceHistory2d::build_pair(top, bottom, grid, dt);
    }
  }
}

TEST_CASE("dissimilar bodies: a half-space's 2x2 operator over a 2D interface is refused") {
  ElasticMaterial m;
  const InterfaceGrid2d grid{0.8, 0.4, 8, 8};
  const InterfaceBody top{m, 0.1, OuterFace::driven};
  const InterfaceBody half_space{m, std::numeric_limits<double>::infinity(), OuterFace::driven};
  CHECK_THROWS_AS(InterfaceHistory2d::build_pair(top, half_space, grid, 1e-6), std::invalid_argument);
}
