// Before the first reflection can come back (t < 2H/c_d, the P echo), a strip
// of height H must respond exactly like a half-space.  Compared: the solver's
// strip operator (StripHistory, exact Mittag-Leffler modes) and the solver's
// half-space operator (HalfSpaceHistory, sampled exact half-space kernel made
// passive), two independent constructions, at the same time step.  Their
// difference is the sum of two O(dt^2) discretisation errors, so the check is
// made at two time steps (256 and 2048 steps per 2H/c_s): it must fall at
// least like dt^2 and be below 1e-6 at the finer one.  Input: a prescribed single-mode slip bump that fits in the window.
#include <doctest/doctest.h>

#include <cmath>
#include <complex>
#include <numbers>
#include <vector>

#include "kernels/half_space_history.hpp"
#include "kernels/history_convolution.hpp"
#include "single_mode_drive.hpp"

using namespace slipstrip;
using cplx = std::complex<double>;

namespace {

double relative_difference(const ElasticMaterial& m, double H, double kH, int steps_per_echo) {
  const double cs = m.shear_wave_speed(), cd = m.dilatational_wave_speed();
  const double dt = 2 * H / cs / steps_per_echo;
  const int window = static_cast<int>(std::floor(2 * H / cd / dt));  // t < 2H/c_d
  const double rise = 0.6 * window * dt;
  const double k = kH / H;
  const double length = 2 * std::numbers::pi / k;
  StripHistory strip(m, H, length, 4, dt);
  HalfSpaceHistory half(m, length, 4, dt);
  const auto a = testing::single_mode_stress(strip, rise, window - 1);
  const auto b = testing::single_mode_stress(half, rise, window - 1);
  return testing::relative_l2_difference(a, b, window);
}

}  // namespace

TEST_CASE("strip and half-space responses agree before the first reflection") {
  for (auto plane : {PlaneCondition::strain, PlaneCondition::stress}) {
    ElasticMaterial m;
    m.plane = plane;
    const double H = 0.1;
    for (double kH : {0.05, 0.5, 5.0}) {
      const double coarse = relative_difference(m, H, kH, 256);
      const double fine = relative_difference(m, H, kH, 2048);
      MESSAGE((plane == PlaneCondition::strain ? "strain" : "stress")
              << " kH = " << kH << ": relative L2 difference before 2H/c_d " << coarse
              << " (256 steps per 2H/c_s), " << fine << " (2048), ratio " << coarse / fine);
      CHECK(fine < 1e-6);  // issue requirement
      // Both discretisations are at least second order: dividing dt by 8
      // divides the difference by >= 64 (observed ~500), unless it has reached
      // the 1e-9 floor set by the accuracy of the half-space exponentials.
      CHECK((coarse / fine > 32.0 || fine < 1e-8));
    }
  }
}
