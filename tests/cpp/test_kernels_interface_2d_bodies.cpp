// Dissimilar bodies on a 2D interface (kernels/interface_2d_history.hpp,
// InterfaceHistory2d::build_pair): an oblique single Fourier mode of the slip
// rate (and of the opening stress) against the rotated combination of the 1D
// pairs' responses at |k|, the in-plane pair (InplanePairHistory over each
// body's 2x2 FaceModalHistory) fed with the slip along k-hat and the antiplane
// pair (TwoBodyHistory) fed with the slip across it.  Those 1D operators are
// verified on their own (test_kernels_face_history, test_kernels_two_body,
// test_solver_inplane_bodies).  A second case checks the same path against an
// independent reference: the closed-form Laplace-domain responses of the pair
// (kernels/face_response.hpp, kernels/antiplane_response.hpp), rotated and
// inverted numerically (tests/cpp/inverse_laplace.hpp).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <memory>
#include <limits>
#include <map>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "kernels/antiplane_response.hpp"
#include "kernels/face_half_space.hpp"
#include "kernels/face_history.hpp"
#include "kernels/face_response.hpp"
#include "kernels/half_space_history.hpp"
#include "kernels/history_convolution.hpp"
#include "kernels/inplane_pair_history.hpp"
#include "kernels/interface_2d_history.hpp"
#include "kernels/two_body_history.hpp"
#include "face_drive.hpp"
#include "inverse_laplace.hpp"
#include "single_mode_drive.hpp"

using namespace slipstrip;
using cd = std::complex<double>;

namespace {

// The bottom body of every dissimilar pair here: slower and denser than
// Table S1 (c_s 1369 against 1679 m/s) with another Poisson ratio, so each of
// the pair's wave speeds and impedances differs from the top body's.
ElasticMaterial slower_denser_bottom(ElasticMaterial top) {
  top.shear_modulus = 4.5e9;
  top.density = 2400.0;
  top.poisson_ratio = 0.25;
  return top;
}

}  // namespace

TEST_CASE("dissimilar bodies, oblique single mode: traction and normal stress = rotated 1D in-plane and antiplane pairs") {
  const ElasticMaterial top_material;  // Table S1
  const ElasticMaterial bottom_material = slower_denser_bottom(top_material);
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

TEST_CASE("dissimilar bodies, oblique prescribed slip: traction and normal stress = inverse Laplace transform of the "
          "rotated closed-form pair responses") {
  const ElasticMaterial top_material;  // Table S1
  const ElasticMaterial bottom_material = slower_denser_bottom(top_material);
  const ElasticMaterial strain_top = testing::with_plane(top_material, PlaneCondition::strain),
                        strain_bottom = testing::with_plane(bottom_material, PlaneCondition::strain),
                        sh_top = testing::with_plane(top_material, PlaneCondition::antiplane),
                        sh_bottom = testing::with_plane(bottom_material, PlaneCondition::antiplane);
  const InterfaceGrid2d grid{0.8, 0.4, 8, 8};  // dx = 0.1 m, dz = 0.05 m
  const double top_height = 0.1;
  // About 256 steps per top round trip 2 H_t / c_t, the slip bump over 2 round
  // trips, 20 round trips of history.  The operator's error is its time
  // discretisation, O(dt^2): relative L2 errors of the dissimilar pair 4.0e-5 to
  // 1.9e-4 at 128 steps per echo and 1.0e-5 to 5.0e-5 at 256 (ratio 3.8-4.0); the
  // rigid base 2.0e-7 to 8.1e-7 and 2.5e-8 to 2.0e-7.  So 256 steps keep the
  // deterministic discretisation error at half the 1e-4 bound or less, while a
  // wrong mode weight of one body shows at the mode whose |k| H_t = pi / sqrt(2)
  // (mode (2, 7): both vertical wavenumbers of a top-body mode are multiples of
  // pi / H_t there, test_kernels_face_modes), where it gave 7.8e-4 to 2.6e-2.
  const double cs_top = strain_top.shear_wave_speed();
  const double echo = 2 * top_height / cs_top;
  const double dmin = 0.05;
  const double c_max = std::max(cs_top, strain_bottom.shear_wave_speed());
  const TwoBodyTiming timing =
      two_body_time_step(strain_top, top_height, strain_bottom, 0.05, dmin, echo / 256 * c_max / dmin);
  const double dt = timing.time_step;
  const double rise = 2 * echo;
  const int steps = static_cast<int>(20 * echo / dt);
  const InterfaceWavevectors k = interface_wavevectors(grid);
  for (const bool rigid : {false, true}) {
    const InterfaceBody top{top_material, top_height, OuterFace::driven};
    std::optional<InterfaceBody> bottom;
    if (!rigid) bottom = InterfaceBody{bottom_material, timing.bottom_height, OuterFace::clamped};
    // The closed-form bodies: each body's 2x2 face stiffness (in-plane, plane
    // strain) in series, and the antiplane pair's S_eff = (1/K_t + 1/K_b)^-1,
    // K_b = 2 x the antiplane pair response of body b.
    const ElasticBody top_body{strain_top, top_height, OuterFace::driven, false};
    const ElasticBody bottom_body{strain_bottom, timing.bottom_height, OuterFace::clamped, rigid};
    auto antiplane_stiffness = [&](double km, cd p) {
      const cd kt = 2.0 * antiplane_strip_response(sh_top, top_height, km, p);
      if (rigid) return kt;
      const cd kb = 2.0 * antiplane_strip_response(sh_bottom, timing.bottom_height, km, p);
      return kt * kb / (kt + kb);
    };
    for (const auto& [qx, qz] : {std::pair{1, 1}, std::pair{2, 7}}) {
      const std::size_t slot = static_cast<std::size_t>(qz) * (grid.nodes_x / 2 + 1) + qx;
      const double km = k.magnitude[slot], c = k.kx[slot] / km, s = k.kz[slot] / km;
      // Slip delta along k-hat (no opening) gives, in the Laplace domain,
      //   sigma_xy = -shear delta (the shear traction along k-hat) and
      //   sigma = -sigma_yy = normal delta (compressive), (shear, normal) the
      //   first column of K_ser = (K_t^-1 + mirrored(K_b)^-1)^-1;
      // slip across k-hat gives the antiplane traction -S_eff delta.  With
      // g^(p) the transform of the slip bump, each is inverted once; the
      // rotated combinations are linear in them.
      auto inverted = [&](int part) {
        return testing::inverse_laplace(
            [&](cd p) {
              const cd g = testing::bump_laplace(p, rise);
              if (part == 2) return -antiplane_stiffness(km, p) * g;
              const SlipResponse r = interface_slip_response(top_body, bottom_body, km, p);
              return part == 0 ? -r.shear * g : cd(0.0, -1.0) * r.normal * g;
            },
            dt, 1 << 19, steps + 1);
      };
      const auto tau_P = inverted(0), sigma_P = inverted(1), tau_SH = inverted(2);
      for (int direction = 0; direction < 2; ++direction) {
        InterfaceHistory2d op = InterfaceHistory2d::build_pair(top, bottom, grid, dt);
        const double eta = op.radiation_damping();
        std::vector<cd> vx(op.modes(), 0.0), vz(op.modes(), 0.0);
        std::vector<double> stress_x(steps + 1), stress_z(steps + 1), normal(steps + 1);
        for (int n = 0; n <= steps; ++n) {
          // The history parts at t_n, from the slip rates up to t_{n-1}; the
          // normal stress has no instantaneous term.
          const double v = testing::bump_rate(n * dt, rise);
          const double v_x = direction == 0 ? v : 0.0, v_z = direction == 0 ? 0.0 : v;
          const cd hx = n == 0 ? cd(0) : op.history_x()[slot];
          const cd hz = n == 0 ? cd(0) : op.history_z()[slot];
          stress_x[n] = (-eta * v_x - hx).real();
          stress_z[n] = (-eta * v_z - hz).real();
          normal[n] = n == 0 ? 0.0 : op.normal_stress()[slot].imag();
          vx[slot] = v_x;
          vz[slot] = v_z;
          op.push(vx, vz, {});  // no opening
        }
        // Slip along x: delta_along = c, delta_across = -s; along z: s and c.
        //   tau_x = c tau_along - s tau_across, tau_z = s tau_along + c tau_across.
        std::vector<double> ref_x(steps + 1), ref_z(steps + 1), ref_normal(steps + 1);
        const double along = direction == 0 ? c : s;
        for (int n = 0; n <= steps; ++n) {
          const double xx = c * c * tau_P[n] + s * s * tau_SH[n], zz = s * s * tau_P[n] + c * c * tau_SH[n];
          const double xz = c * s * (tau_P[n] - tau_SH[n]);
          ref_x[n] = direction == 0 ? xx : xz;
          ref_z[n] = direction == 0 ? xz : zz;
          ref_normal[n] = along * sigma_P[n];
        }
        const double err_x = testing::relative_l2_difference(stress_x, ref_x);
        const double err_z = testing::relative_l2_difference(stress_z, ref_z);
        const double err_normal = testing::relative_l2_difference(normal, ref_normal);
        MESSAGE(std::string(rigid ? "rigid base" : "dissimilar strips") << ", mode (" << qx << ", " << qz
                << "), |k| H_t = " << km * top_height << ", slip along " << (direction == 0 ? "x" : "z")
                << ", " << echo / dt << " steps per echo: relative L2 error x " << err_x << ", z " << err_z
                << ", normal " << err_normal);
        CHECK(err_x < 1e-4);
        CHECK(err_z < 1e-4);
        CHECK(err_normal < 1e-4);
      }
    }
  }
}

namespace {

// One body of the half-space cases: a half-space (height inf), a finite strip or,
// as the bottom, a rigid base (nullopt).
constexpr double kInf = std::numeric_limits<double>::infinity();
struct PairCase {
  const char* name;
  double top_height;
  std::optional<double> bottom_height;  // nullopt: rigid base
};

// The half-space's near-field range on a grid (set_near_field_range over the
// grid operator modes' h = c_s |k| dt), for a 1D operator that must share it.
HalfSpaceOperatorDesign near_field_of(const ElasticMaterial& m, const InterfaceGrid2d& grid, double dt) {
  std::vector<double> h;
  for (double k : interface_operator_wavevectors(grid).magnitude) h.push_back(m.shear_wave_speed() * k * dt);
  HalfSpaceOperatorDesign design;
  set_near_field_range(design, h);
  return design;
}

}  // namespace

TEST_CASE("dissimilar bodies with a half-space, oblique single mode: = rotated 1D pairs on a line holding |k|") {
  // As above, for the pairs with a half-space (kernels/face_half_space.hpp over
  // the grid's |k|): a strip on a half-space of another material, a half-space
  // on a strip, a half-space on a rigid base and two different half-spaces.
  // The 1D references are built for a line of length 2 pi/|k| and 2 nodes (its
  // mode 1 is |k|, to an ulp), each half-space once with the 2D operator's
  // near-field range (the same design: round-off) and once with its own
  // (the line's near-field sums fitted over its single mode: the difference is
  // the fit's accuracy).
  const ElasticMaterial top_material;  // Table S1
  const ElasticMaterial bottom_material = slower_denser_bottom(top_material);
  const InterfaceGrid2d grid{0.8, 0.4, 8, 8};  // dx = 0.1 m, dz = 0.05 m
  const PairCase cases[] = {{"strip on a half-space", 0.1, kInf},
                            {"half-space on a strip", kInf, 0.05},
                            {"half-space on a rigid base", kInf, std::nullopt},
                            {"two half-spaces", kInf, kInf}};
  for (const PairCase& pc : cases) {
    const bool rigid = !pc.bottom_height;
    const TwoBodyTiming timing = two_body_time_step(top_material, pc.top_height, bottom_material,
                                                    rigid ? kInf : *pc.bottom_height, 0.05, 0.2);
    const double dt = timing.time_step;
    const InterfaceBody top{top_material, pc.top_height, OuterFace::driven};
    std::optional<InterfaceBody> bottom;
    if (!rigid) bottom = InterfaceBody{bottom_material, timing.bottom_height, OuterFace::clamped};
    const ElasticMaterial strain_top = testing::with_plane(top_material, PlaneCondition::strain);
    const ElasticMaterial strain_bottom = testing::with_plane(bottom_material, PlaneCondition::strain);
    const ElasticMaterial sh_top = testing::with_plane(top_material, PlaneCondition::antiplane);
    const ElasticMaterial sh_bottom = testing::with_plane(bottom_material, PlaneCondition::antiplane);
    const InterfaceWavevectors k = interface_wavevectors(grid);
    // One build (the half-space designs take most of the test's time), reset
    // to its zero state before each run.
    InterfaceHistory2d op = InterfaceHistory2d::build_pair(top, bottom, grid, dt);
    const HistoryOperatorState zero = op.save_state();
    // Modes (1, 1), (2, 7) as above and (3, 3), 63 deg (not a Nyquist mode:
    // those are averaged over +-k, kernels/interface_2d_history.hpp).
    for (const auto& [qx, qz] : {std::pair{1, 1}, std::pair{2, 7}, std::pair{3, 3}}) {
      const std::size_t slot = static_cast<std::size_t>(qz) * (grid.nodes_x / 2 + 1) + qx;
      const double magnitude = k.magnitude[slot], c = k.kx[slot] / magnitude, s = k.kz[slot] / magnitude;
      const double line = 2.0 * std::numbers::pi / magnitude;
      double worst_of[2] = {0.0, 0.0}, worst_normal_of[2] = {0.0, 0.0};
      for (const bool shared_range : {true, false}) {
        op.restore_state(zero);
        auto face = [&](const ElasticMaterial& m, double height, OuterFace outer) -> std::unique_ptr<FaceHistory> {
          if (height == kInf)
            return std::make_unique<FaceHalfSpaceHistory>(
                m, line, 2, dt, shared_range ? near_field_of(m, grid, dt) : HalfSpaceOperatorDesign{});
          return std::make_unique<FaceModalHistory>(m, height, outer, line, 2, dt);
        };
        auto sh_operator = [&](const ElasticMaterial& m, double height) -> std::unique_ptr<HistoryOperator> {
          if (height == kInf)
            return std::make_unique<HalfSpaceHistory>(
                m, line, 2, dt, shared_range ? near_field_of(m, grid, dt) : HalfSpaceOperatorDesign{});
          return std::make_unique<StripHistory>(m, compute_strip_kernels(m, height, line, 2, dt));
        };
        InplanePairHistory inplane(face(strain_top, pc.top_height, OuterFace::driven),
                                   rigid ? nullptr : face(strain_bottom, timing.bottom_height, OuterFace::clamped));
        TwoBodyHistory antiplane(sh_operator(sh_top, pc.top_height),
                                 rigid ? nullptr : sh_operator(sh_bottom, timing.bottom_height));
        REQUIRE(op.radiation_damping() == inplane.radiation_damping());
        REQUIRE(op.normal_radiation_damping() == inplane.normal_radiation_damping());
        std::vector<cd> vx(grid.modes(), 0.0), vz(grid.modes(), 0.0), opening(grid.modes(), 0.0);
        std::vector<cd> along(2, 0.0), across(2, 0.0), opening_1d(2, 0.0);
        const double rise = 60 * dt;
        double worst = 0.0, worst_normal = 0.0, largest = 0.0, largest_normal = 0.0, other_modes = 0.0;
        for (int n = 0; n < 400; ++n) {
          const double v = testing::bump_rate(n * dt, rise);
          vx[slot] = v * cd(1.0, 0.3);
          vz[slot] = v * cd(-0.5, 0.2);
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
          const cd normal = inplane.normal_stress()[1];
          worst = std::max({worst, std::abs(op.history_x()[slot] - hx), std::abs(op.history_z()[slot] - hz)});
          worst_normal = std::max(worst_normal, std::abs(op.normal_stress()[slot] - normal));
          largest = std::max({largest, std::abs(hx), std::abs(hz)});
          largest_normal = std::max(largest_normal, std::abs(normal));
          for (std::size_t m = 0; m < grid.modes(); ++m)
            if (m != slot)
              other_modes = std::max({other_modes, std::abs(op.history_x()[m]), std::abs(op.history_z()[m]),
                                      std::abs(op.normal_stress()[m])});
        }
        REQUIRE(largest > 0.0);
        REQUIRE(largest_normal > 0.0);
        CHECK(other_modes == 0.0);
        worst_of[shared_range ? 0 : 1] = worst / largest;
        worst_normal_of[shared_range ? 0 : 1] = worst_normal / largest_normal;
      }
      MESSAGE(std::string(pc.name) << ", mode (" << qx << ", " << qz << "), |k| = " << magnitude
                      << " 1/m: shared near-field range: h " << worst_of[0] << ", sigma " << worst_normal_of[0]
                      << "; the line's own range: h " << worst_of[1] << ", sigma " << worst_normal_of[1]);
      // Shared range: the same designs (|k| to an ulp), the same rotations:
      // round-off, 1e-13 as above.  Own range: the near-field sums (|error|
      // < ~1e-11 of the O(1) kernel each, kernels/half_space_kernel.hpp) fitted
      // over another interval, which moves every stored lag and with them the
      // passivity correction at that level; the responses sum ~1/h ~ 10-40
      // such lags and the normal stress is the difference of the two bodies'
      // (measured at most 1.3e-10 of max |sigma|, 2.4e-11 of max |h|).  1e-9.
      CHECK(worst_of[0] <= 1e-13);
      CHECK(worst_normal_of[0] <= 1e-13);
      CHECK(worst_of[1] <= 1e-9);
      CHECK(worst_normal_of[1] <= 1e-9);
    }
  }
}

TEST_CASE("half-space face operator over a 2D interface's |k|: an oblique mode vs the inverse Laplace transform of K") {
  // FaceHalfSpaceHistory over the operator modes of a 4 x 4 grid whose mode
  // (1, 1) has |k| = 10 1/m at 30 deg (PMMA, plane strain, as
  // test_kernels_face_half_space's prescribed displacement on a line's mode
  // 1), driven at that mode with u = g(t) e_x, then e_y (sin^4 bump over
  // c_s |k| t = 4), up to c_s |k| t = 40; reference: Durbin's inverse of K(|k|, s)
  // g^(s) (half_space_face_stiffness).  Tolerance as there: 1e-3 relative L2 at
  // h = c_s |k| dt = 1/32 and an error ratio > 3 per halving (second order).
  ElasticMaterial m{2.1e9, 0.35, 1170.0, PlaneCondition::strain};
  const double k = 10.0, angle = std::numbers::pi / 6, cs = m.shear_wave_speed();
  const InterfaceGrid2d grid{2 * std::numbers::pi / (k * std::cos(angle)), 2 * std::numbers::pi / (k * std::sin(angle)),
                             4, 4};
  const std::size_t slot = 1 * (grid.nodes_x / 2 + 1) + 1;
  const std::vector<double> magnitude = interface_operator_wavevectors(grid).magnitude;
  const double km = magnitude[slot];
  REQUIRE(std::abs(km - k) <= 1e-12 * k);
  const double rise = 4.0 / (cs * km);
  double previous[4] = {0, 0, 0, 0};
  for (double h : {1.0 / 16, 1.0 / 32}) {
    const double dt = h / (cs * km);
    const int steps = static_cast<int>(std::round(40.0 / h));
    const auto e = testing::prescribed_face_errors(
        [&] { return FaceHalfSpaceHistory(m, magnitude, dt); },
        [&](cd s) { return half_space_face_stiffness(m, km, s); }, dt, rise, steps, slot);
    const double err[4] = {e.xx, e.yx, e.xy, e.yy};
    MESSAGE("h = " << h << ": relative L2 error xx " << err[0] << ", yx " << err[1] << ", xy " << err[2] << ", yy "
                   << err[3]);
    for (int i = 0; i < 4; ++i) {
      CAPTURE(i);
      CAPTURE(h);
      if (h < 0.05) CHECK(err[i] < 1e-3);
      if (previous[i] > 0.0) CHECK(previous[i] / err[i] > 3.0);
      previous[i] = err[i];
    }
  }
}

namespace {
// Smallest eigenvalue of the Hermitian part of a 2x2 matrix.
double min_hermitian_eigenvalue(const FaceMatrix& z) {
  const double a = z.xx.real(), d = z.yy.real();
  const cd b = 0.5 * (z.xy + std::conj(z.yx));
  return 0.5 * (a + d) - std::sqrt(0.25 * (a - d) * (a - d) + std::norm(b));
}
}  // namespace

TEST_CASE("half-space face operator over a 2D interface's |k|: passive per mode; modes of equal |k| share one design") {
  // Every operator mode of a 16 x 8 grid (dx = dz) at time.beta = 0.2, PMMA
  // plane strain (c_s |k|_max dt = 0.2 pi sqrt 2 = 0.89), and a nearly
  // incompressible solid (nu = 0.45) at beta = 0.15 (0.67): the Hermitian part
  // of Z_d(theta) positive semidefinite on 4096 phases over (0, pi] plus 2048 in
  // the band below 2.5 times the P-wave frequency (test_kernels_face_half_space's
  // check, 8 times finer than the design's grid; required >= 0).  Modes of equal
  // |k| (+-kz, and the extra z-Nyquist row) have identical coefficients.
  const InterfaceGrid2d grid{1.0, 0.5, 16, 8};
  const std::vector<double> magnitude = interface_operator_wavevectors(grid).magnitude;
  for (const auto& [m, beta] : {std::pair{ElasticMaterial{2.1e9, 0.35, 1170.0, PlaneCondition::strain}, 0.2},
                                std::pair{ElasticMaterial{1e9, 0.45, 1000.0, PlaneCondition::strain}, 0.15}}) {
    const double dt = beta * (1.0 / 16) / m.shear_wave_speed();
    const FaceHalfSpaceHistory op(m, magnitude, dt);
    REQUIRE(op.modes() == static_cast<int>(magnitude.size()));
    const double unit = op.shear_impedance(), r = std::sqrt(1.0 / m.wave_speed_ratio_squared());
    double lowest = 1e300, h_max = 0.0;
    std::map<double, int> first_of;
    int distinct = 0, shared = 0;
    for (int q = 1; q < op.modes(); ++q) {
      const FaceHalfSpaceModeKernel kq = op.mode_kernel(q);
      const auto [at, added] = first_of.emplace(magnitude[q], q);
      if (!added) {
        const FaceHalfSpaceModeKernel kp = op.mode_kernel(at->second);
        for (std::size_t e = 0; e < 3; ++e) {
          CHECK(kq.static_weight[e] == kp.static_weight[e]);
          CHECK(kq.lag_weight[e] == kp.lag_weight[e]);
          CHECK(kq.pole_weight[e] == kp.pole_weight[e]);
        }
        ++shared;
        continue;
      }
      ++distinct;
      h_max = std::max(h_max, kq.h);
      double mode_lowest = 1e300;
      for (int i = 1; i <= 4096; ++i)
        mode_lowest = std::min(mode_lowest, min_hermitian_eigenvalue(op.symbol(q, std::numbers::pi * i / 4096)));
      const double band = std::min(std::numbers::pi, 2.5 * kq.h / r);
      for (int i = 1; i <= 2048; ++i)
        mode_lowest = std::min(mode_lowest, min_hermitian_eigenvalue(op.symbol(q, band * (i - 0.5) / 2048)));
      CAPTURE(q);
      CHECK(mode_lowest >= 0.0);
      lowest = std::min(lowest, mode_lowest);
    }
    MESSAGE("nu = " << m.poisson_ratio << ", beta = " << beta << ": " << distinct << " distinct |k| (" << shared
                    << " modes sharing a design), c_s |k|_max dt = " << h_max
                    << ", min eigenvalue of Re Z_d / (mu/c_s) " << lowest / unit);
    CHECK(shared > 0);
  }
}

TEST_CASE("dissimilar half-spaces, oblique prescribed slip: traction and normal stress vs the inverse Laplace transform") {
  // Two different half-spaces (and a half-space on a rigid base) on a 4 x 4
  // grid whose mode (1, 1) has |k| = 10 1/m at 30 deg, driven with a prescribed
  // slip bump along x (over c_s |k| t = 4; c_s of the top body) up to c_s |k| t
  // = 40.  Reference, independent of the discrete operators: the rotated
  // closed forms, along k-hat the in-plane pair's series stiffness
  // (interface_slip_response, kernels/face_response.hpp: sigma_xy = -shear
  // delta, compressive sigma = normal delta) and across it the SH pair's
  // S_t S_b / (S_t + S_b), S = mu alpha_s (a rigid base: the top body's alone),
  // inverted by Durbin's method.  Tolerance: the operators' own second-order
  // error, as the single-body test above (1e-3 relative L2 at h = 1/32; the
  // pair adds the generalised Rayleigh wave of two half-spaces, undamped, whose
  // phase error grows over the record).
  const ElasticMaterial top_material;  // Table S1
  const ElasticMaterial bottom_material = slower_denser_bottom(top_material);
  const ElasticMaterial strain_top = testing::with_plane(top_material, PlaneCondition::strain);
  const ElasticMaterial strain_bottom = testing::with_plane(bottom_material, PlaneCondition::strain);
  const double k = 10.0, angle = std::numbers::pi / 6, cs = top_material.shear_wave_speed();
  const InterfaceGrid2d grid{2 * std::numbers::pi / (k * std::cos(angle)), 2 * std::numbers::pi / (k * std::sin(angle)),
                             4, 4};
  const std::size_t slot = 1 * (grid.nodes_x / 2 + 1) + 1;
  const InterfaceWavevectors wv = interface_wavevectors(grid);
  const double km = wv.magnitude[slot], c = wv.kx[slot] / km, s = wv.kz[slot] / km;
  for (const bool rigid : {false, true}) {
    double previous[3] = {0, 0, 0};
    for (double h : {1.0 / 16, 1.0 / 32}) {
      const double dt = h / (cs * km);
      const double rise = 4.0 / (cs * km);
      const int steps = static_cast<int>(std::round(40.0 / h));
      const InterfaceBody top{top_material, kInf, OuterFace::driven};
      std::optional<InterfaceBody> bottom;
      if (!rigid) bottom = InterfaceBody{bottom_material, kInf, OuterFace::driven};
      InterfaceHistory2d op = InterfaceHistory2d::build_pair(top, bottom, grid, dt);
      const double eta = op.radiation_damping();
      std::vector<cd> vx(grid.modes(), 0.0), vz(grid.modes(), 0.0);
      std::vector<double> stress_x(steps + 1), stress_z(steps + 1), normal(steps + 1);
      for (int n = 0; n <= steps; ++n) {
        const double v = testing::bump_rate(n * dt, rise);
        // Before this step's push: the history and the normal stress at t_n.
        stress_x[n] = (-eta * v - (n == 0 ? cd(0.0) : op.history_x()[slot])).real();
        stress_z[n] = (n == 0 ? cd(0.0) : -op.history_z()[slot]).real();
        normal[n] = (n == 0 ? cd(0.0) : op.normal_stress()[slot]).imag();
        vx[slot] = v;
        op.push(vx, vz, {});
      }
      // Laplace-domain responses to the slip delta = g(t) along k-hat (and across).
      const ElasticBody top_body{strain_top, kInf, OuterFace::driven, false};
      const ElasticBody bottom_body{strain_bottom, kInf, OuterFace::driven, rigid};
      const auto inverted = [&](auto response) {
        return testing::inverse_laplace([&](cd p) { return response(p) * testing::bump_laplace(p, rise); }, dt,
                                        1 << 19, steps + 1);
      };
      const auto shear_P = inverted([&](cd p) { return -interface_slip_response(top_body, bottom_body, km, p).shear; });
      // sigma_yy = -normal delta; the compressive normal stress is -sigma_yy,
      // i times a real function for k > 0.
      const auto normal_P = inverted(
          [&](cd p) { return interface_slip_response(top_body, bottom_body, km, p).normal / cd(0.0, 1.0); });
      const auto shear_SH = inverted([&](cd p) {
        const auto alpha = [&](const ElasticMaterial& mm) {
          const double c_s = mm.shear_wave_speed();
          return mm.shear_modulus * std::sqrt(km * km + p * p / (c_s * c_s));
        };
        const cd st = alpha(top_material);
        if (rigid) return -st;
        const cd sb = alpha(bottom_material);
        return -st * sb / (st + sb);
      });
      std::vector<double> ref_x(steps + 1), ref_z(steps + 1), ref_n(steps + 1);
      for (int n = 0; n <= steps; ++n) {
        // Slip along x: along = c delta, across = -s delta.
        ref_x[n] = c * c * shear_P[n] + s * s * shear_SH[n];
        ref_z[n] = c * s * (shear_P[n] - shear_SH[n]);
        ref_n[n] = c * normal_P[n];
      }
      const double err[3] = {testing::relative_l2_difference(stress_x, ref_x),
                             testing::relative_l2_difference(stress_z, ref_z),
                             testing::relative_l2_difference(normal, ref_n)};
      MESSAGE(std::string(rigid ? "half-space on a rigid base" : "two half-spaces") << ", h = " << h << ": relative L2 error x "
                                                                         << err[0] << ", z " << err[1] << ", sigma "
                                                                         << err[2]);
      for (int i = 0; i < 3; ++i) {
        CAPTURE(i);
        CAPTURE(h);
        if (h < 0.05) CHECK(err[i] < 1e-3);
        if (previous[i] > 0.0) CHECK(previous[i] / err[i] > 3.0);
        previous[i] = err[i];
      }
    }
  }
}
