// The history operator of a two-dimensional interface (x and z) between two
// identical bodies (kernels/interface_2d_history.hpp, docs/3d.md):
//   * wavevectors: the kz = 0 modes carry the 1-D wavenumbers bit for bit, and
//     modes of equal |k| share one design, bit for bit;
//   * an oblique single-mode prescribed slip (along x, and along z) against
//     the numerical inverse Laplace transform of the rotated combination
//     cos^2 S_P-SV + sin^2 S_SH (and of the cross term cos sin (S_P-SV - S_SH))
//     of the closed-form 2D responses at |k|, finite strips and half-spaces;
//   * passivity per mode as in 2D: every weight <= 0, Re Z_d > 0 outside the
//     unit circle, and the time-step limit scaled by |k|_max;
//   * the block strip operators (BlockStripHistory, designs shared by equal
//     |k|) against the modal ones on the same grid, white input.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "inverse_laplace.hpp"
#include "kernels/antiplane_response.hpp"
#include "kernels/block_strip_history.hpp"
#include "kernels/interface_2d_history.hpp"
#include "kernels/passivity.hpp"
#include "kernels/strip_response.hpp"
#include "single_mode_drive.hpp"

using namespace slipstrip;
using testing::with_plane;
using cplx = std::complex<double>;
constexpr double pi = std::numbers::pi;
constexpr double kInf = std::numeric_limits<double>::infinity();

namespace {

// Z_d(z) of one mode's discrete operator (docs/theory.md 6.3), built directly
// from the kernels' weights and phases.
cplx discrete_impedance(const StripKernels& kernels, std::size_t q, double eta, double echo_weight, cplx z) {
  cplx sum = eta + echo_weight / (z - 1.0);
  for (std::size_t m = kernels.first_oscillator[q]; m < kernels.first_oscillator[q + 1]; ++m) {
    const double c = std::cos(kernels.phase[m]);
    sum += kernels.time_step * kernels.weight[m] *
           (1.0 / (z - 1.0) - (z * c - 1.0) / (z * z - 2.0 * z * c + 1.0));
  }
  return sum;
}

}  // namespace

TEST_CASE("interface wavevectors: kz = 0 modes are the 1-D wavenumbers; equal |k| shares one design") {
  const InterfaceGrid2d grid{4.0, 4.0, 16, 8};
  const auto k = interface_wavevectors(grid);
  const int half = grid.nodes_x / 2 + 1;
  REQUIRE(k.magnitude.size() == static_cast<std::size_t>(half * grid.nodes_z));
  for (int qx = 0; qx < half; ++qx) CHECK(k.magnitude[qx] == 2.0 * pi * qx / grid.length_x);
  for (int qz = 1; qz < grid.nodes_z; ++qz)
    for (int qx = 0; qx < half; ++qx) {
      // z -> -z mirror: qz and N_z - qz (bit for bit, so they share one design).
      CHECK(k.magnitude[qz * half + qx] == k.magnitude[(grid.nodes_z - qz) * half + qx]);
      if (2 * qz != grid.nodes_z)  // the z-Nyquist row is its own mirror image
        CHECK(k.kz[qz * half + qx] == -k.kz[(grid.nodes_z - qz) * half + qx]);
    }
  const ElasticMaterial material;
  const double H = 0.1, dt = strip_time_step(material, H, grid.length_x / grid.nodes_x, 0.25);
  const StripKernels list = compute_strip_kernels(material, H, k.magnitude, dt);
  const StripKernels one_d = compute_strip_kernels(material, H, grid.length_x, grid.nodes_x, dt);
  // The kz = 0 row is the 1-D design, bit for bit.
  for (int qx = 0; qx <= half; ++qx) CHECK(list.first_oscillator[qx] == one_d.first_oscillator[qx]);
  for (std::size_t m = 0; m < one_d.weight.size(); ++m) {
    CHECK(list.weight[m] == one_d.weight[m]);
    CHECK(list.phase[m] == one_d.phase[m]);
  }
  // Equal |k| (the mirror pairs, and (qx, qz) = (2, 0), (0, 4) here since
  // L_x = L_z... only the mirror pairs are guaranteed bit-equal): same design.
  for (int qz = 1; qz < grid.nodes_z; ++qz)
    for (int qx = 0; qx < half; ++qx) {
      const std::size_t a = qz * half + qx, b = (grid.nodes_z - qz) * half + qx;
      REQUIRE(list.first_oscillator[a + 1] - list.first_oscillator[a] ==
              list.first_oscillator[b + 1] - list.first_oscillator[b]);
      for (std::size_t i = 0; i < list.first_oscillator[a + 1] - list.first_oscillator[a]; ++i)
        CHECK(list.weight[list.first_oscillator[a] + i] == list.weight[list.first_oscillator[b] + i]);
    }
}

TEST_CASE("oblique prescribed slip: traction = rotated in-plane and antiplane responses at |k| (inverse Laplace)") {
  const ElasticMaterial material;
  const ElasticMaterial strain = with_plane(material, PlaneCondition::strain),
                        sh = with_plane(material, PlaneCondition::antiplane);
  const double cs = material.shear_wave_speed();
  for (double H : {0.1, kInf}) {
    for (double kH : {0.5, 5.0}) {
      for (double angle : {pi / 6, 0.3 * pi}) {
        const double k = kH / 0.1, kx = k * std::cos(angle), kz = k * std::sin(angle);
        // Mode (qx, qz) = (1, 1) of a 4 x 4 grid.
        const InterfaceGrid2d grid{2 * pi / kx, 2 * pi / kz, 4, 4};
        const auto wv = interface_wavevectors(grid);
        const std::size_t mode = 1 * (grid.nodes_x / 2 + 1) + 1;
        const double c = wv.kx[mode] / wv.magnitude[mode], s = wv.kz[mode] / wv.magnitude[mode];
        const double km = wv.magnitude[mode];
        // About 128 steps per round trip 2 (0.1 m)/c_s, as the 2D tests (the
        // half-space: the same dt; c_s |k| dt <= 0.03).
        const double echo = 2 * 0.1 / cs;
        const double dmin = std::min(grid.length_x, grid.length_z) / 4;
        const double dt = strip_time_step(material, H, dmin, echo / 128 * cs / dmin);
        const double rise = 2 * echo;
        const int steps = static_cast<int>(30 * echo / dt);
        // The in-plane and antiplane responses to the slip bump, each inverted
        // once; the rotated combinations are linear in them.
        auto inverted = [&](bool inplane) {
          return testing::inverse_laplace(
              [&](cplx p) {
                const cplx S = inplane ? strip_response(strain, H, km, p) : antiplane_strip_response(sh, H, km, p);
                return -S * testing::bump_laplace(p, rise);
              },
              dt, 1 << 19, steps + 1);
        };
        const auto tau_P = inverted(true), tau_SH = inverted(false);
        for (int direction = 0; direction < 2; ++direction) {
          InterfaceHistory2d op = InterfaceHistory2d::build(material, H, grid, dt);
          std::vector<cplx> vx(op.modes(), 0.0), vz(op.modes(), 0.0);
          std::vector<double> stress_x(steps + 1), stress_z(steps + 1);
          const double eta = op.radiation_damping();
          for (int n = 0; n <= steps; ++n) {
            const double v = testing::bump_rate(n * dt, rise);
            const cplx hx = n == 0 ? cplx(0) : op.history_x()[mode];
            const cplx hz = n == 0 ? cplx(0) : op.history_z()[mode];
            const double v_x = direction == 0 ? v : 0.0, v_z = direction == 0 ? 0.0 : v;
            stress_x[n] = (-eta * v_x - hx).real();
            stress_z[n] = (-eta * v_z - hz).real();
            vx[mode] = v_x;
            vz[mode] = v_z;
            op.push(vx, vz);
          }
          // tau = -[c^2 S_P + s^2 S_SH, c s (S_P - S_SH); c s (S_P - S_SH), s^2 S_P + c^2 S_SH] delta.
          std::vector<double> ref_x(steps + 1), ref_z(steps + 1);
          for (int n = 0; n <= steps; ++n) {
            const double xx = c * c * tau_P[n] + s * s * tau_SH[n], zz = s * s * tau_P[n] + c * c * tau_SH[n];
            const double xz = c * s * (tau_P[n] - tau_SH[n]);
            ref_x[n] = direction == 0 ? xx : xz;
            ref_z[n] = direction == 0 ? xz : zz;
          }
          const double err_x = testing::relative_l2_difference(stress_x, ref_x);
          const double err_z = testing::relative_l2_difference(stress_z, ref_z);
          MESSAGE("H = " << H << ", kH = " << kH << ", angle = " << angle << ", slip along "
                         << (direction == 0 ? "x" : "z") << ": relative L2 error x " << err_x << ", z " << err_z);
          // The 2D operators' own error at this resolution: 1e-6 at kH = 5 with
          // 128 steps per echo for strips (test_kernels_time_domain, second
          // order in dt); for the half-space 1.1e-4 at h = c_s |k| dt = 1/8 and
          // 1.2e-5 at 1/16 over c_s |k| t <= 300 (docs/theory.md 8.4), here
          // h = 1/13 at kH = 5, i.e. ~4e-5.  The rotation adds round-off.
          // 1e-4 bounds every case, as in the two-body test.
          CHECK(err_x < 1e-4);
          CHECK(err_z < 1e-4);
        }
      }
    }
  }
}

TEST_CASE("passivity per mode on a 2D interface: weights <= 0, Re Z_d > 0 outside |z| = 1, beta limit scaled by |k|_max") {
  const ElasticMaterial material;
  // H / dx = 16: ~100 steps per echo 2H/c_s, so rounding dt down to a whole
  // number of steps per echo moves beta by <= 1 % (the limit is tested to 2-5 %).
  const double H = 1.0;
  for (const InterfaceGrid2d grid : {InterfaceGrid2d{1.0, 1.0, 16, 16}, InterfaceGrid2d{1.0, 0.5, 16, 4}}) {
    const double dmin = std::min(grid.length_x / grid.nodes_x, grid.length_z / grid.nodes_z);
    const double limit_1d = strip_passivity_beta_limit(material.wave_speed_ratio_squared());
    const double limit = interface_2d_beta_limit(grid, limit_1d);
    INFO("grid " << grid.nodes_x << " x " << grid.nodes_z << ": beta limit " << limit << " (1-D " << limit_1d << ")");
    CHECK(limit < limit_1d);
    const auto k = interface_wavevectors(grid).magnitude;
    // beta_eff = c_s dt / dmin <= beta: a beta 2 % below the limit is passive ...
    const double dt = strip_time_step(material, H, dmin, 0.98 * limit);
    const double eta = material.radiation_damping(), echo_weight = material.shear_modulus / material.shear_wave_speed();
    for (PlaneCondition plane : {PlaneCondition::strain, PlaneCondition::antiplane}) {
      const StripKernels kernels = compute_strip_kernels(with_plane(material, plane), H, k, dt);
      double worst = 1e300;
      for (std::size_t q = 1; q < k.size(); ++q) {
        for (std::size_t m = kernels.first_oscillator[q]; m < kernels.first_oscillator[q + 1]; ++m)
          CHECK(kernels.weight[m] <= 0.0);
        for (double r : {1.0005, 1.01, 1.2})
          for (int i = 1; i < 400; ++i) {
            const cplx z = std::polar(r, pi * i / 400.0);
            const cplx Z = discrete_impedance(kernels, q, eta, echo_weight, z);
            // Relative to the terms' scale: each term is computed to a few ulp.
            worst = std::min(worst, Z.real() / (eta + echo_weight));
          }
      }
      MESSAGE("min Re Z_d / (eta + mu/c_s) = " << worst);
      CHECK(worst > 0.0);
    }
    // ... and one above it (that still passes the 1-D limit) is refused: the
    // truncated static stiffness of the mode at |k|_max cannot be placed passively.
    // The sharp condition is dt S(|k|_max, 0)/2 <= eta (docs/theory.md 6.4;
    // the finite strip's S is ~1 % below the half-space's used for the limit).
    const double dt_above = strip_time_step(material, H, dmin, 1.05 * limit);
    double k_max = 0.0;
    for (double kk : k) k_max = std::max(k_max, kk);
    const double margin = dt_above * strip_static_stiffness(material, H, k_max) / 2 / eta - 1.0;
    INFO("dt S(k_max, 0) / (2 eta) - 1 = " << margin);
    REQUIRE(margin > 0.01);
    CHECK_THROWS(compute_strip_kernels(with_plane(material, PlaneCondition::strain), H, k, dt_above));
  }
}

TEST_CASE("2D interface: the block operator = the modal operator (white input, many blocks); equal |k| share designs") {
  // Both algorithms apply the same discrete operator (docs/theory.md 11.1) to
  // the same rotated inputs, so the reference is the modal InterfaceHistory2d
  // and the tolerance is test_kernels_block_history's: 1e-10 of the largest
  // history value.  The block operator's only approximation is the NUFFT that
  // moves the normal-mode states across a block (<= 2e-14 of sum |input| per
  // update at half width 14, kernels/nufft.hpp), and the modal recursions' rotation round-off
  // over these run lengths is of the same order; 1e-10 leaves two orders of
  // magnitude for 3000 steps.  White input in x and z excites every normal
  // mode of every Fourier mode, both operators and the Nyquist row and column.
  // Small blocks (B = 64, 32) put ~50-100 far-field updates and every level
  // boundary into the run; the automatic B (the power of two >= the most
  // normal modes, here 64) is checked too.
  const ElasticMaterial material;
  const double H = 0.4;
  for (const InterfaceGrid2d grid : {InterfaceGrid2d{0.8, 0.4, 16, 8}, InterfaceGrid2d{0.8, 0.75, 16, 15}}) {
    const double dx = std::min(grid.length_x / grid.nodes_x, grid.length_z / grid.nodes_z);
    const double dt = strip_time_step(material, H, dx, 0.25);
    for (BlockHistoryDesign design : {BlockHistoryDesign{8, 64, 14}, BlockHistoryDesign{4, 32, 14},
                                      BlockHistoryDesign{8, 0, 14}}) {
      const InterfaceHistory2d::StripOperatorFactory make_block = [&](const ElasticMaterial& body,
                                                                      const StripKernels& kernels) {
        return std::unique_ptr<HistoryOperator>(std::make_unique<BlockStripHistory>(body, kernels, design));
      };
      InterfaceHistory2d fresh_modal = InterfaceHistory2d::build(material, H, grid, dt);
      InterfaceHistory2d block = InterfaceHistory2d::build(material, H, grid, dt, {}, make_block);
      REQUIRE(block.modes() == fresh_modal.modes());
      // Normal modes in flight: one state per normal mode of every Fourier
      // mode in both (the block operator shares only the designs).
      CHECK(block.stats().oscillators == fresh_modal.stats().oscillators);
      std::mt19937_64 rng(7);
      std::normal_distribution<double> normal(0.0, 1.0);
      std::vector<cplx> vx(grid.modes()), vz(grid.modes());
      double worst = 0.0, scale = 0.0;
      for (int n = 0; n < 3000; ++n) {
        for (std::size_t m = 0; m < vx.size(); ++m) {
          vx[m] = cplx(normal(rng), normal(rng));
          vz[m] = cplx(normal(rng), normal(rng));
        }
        fresh_modal.push(vx, vz);
        block.push(vx, vz);
        for (std::size_t m = 0; m < vx.size(); ++m) {
          worst = std::max({worst, std::abs(block.history_x()[m] - fresh_modal.history_x()[m]),
                            std::abs(block.history_z()[m] - fresh_modal.history_z()[m])});
          scale = std::max({scale, std::abs(fresh_modal.history_x()[m]), std::abs(fresh_modal.history_z()[m])});
        }
      }
      const auto* inplane = dynamic_cast<const BlockStripHistory*>(&block.inplane());
      REQUIRE(inplane != nullptr);
      MESSAGE("grid " << grid.nodes_x << " x " << grid.nodes_z << ", direct " << design.direct_block << ", B = "
                      << inplane->block() << ": max |block - modal| / max |modal| = " << worst / scale
                      << "; designs " << inplane->designs() << " for " << block.modes() << " modes");
      CHECK(worst <= 1e-10 * scale);
      // Modes of equal |k| share one design: +-kz always (the 16 x 8 grid
      // also has |(qx, 0)| = |(0, 2 qz)| coincidences), so at most about half.
      CHECK(inplane->designs() <= block.modes() / 2 + grid.nodes_x / 2 + 2);
    }
  }
}
