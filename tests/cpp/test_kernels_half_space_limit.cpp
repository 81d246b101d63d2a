// Before the first reflection can come back (t < 2H/c_d, the P echo), a strip
// of height H must respond exactly like a half-space.  Both operators are
// built at the same time step; the half-space one is the solver's: a strip so
// tall (height Hv) that its own first reflection arrives after the compared
// window.  Input: a prescribed single-mode slip bump that fits in the window.
#include <doctest/doctest.h>

#include <cmath>
#include <complex>
#include <numbers>
#include <vector>

#include "kernels/history_convolution.hpp"
#include "single_mode_drive.hpp"

using namespace slipstrip;
using cplx = std::complex<double>;

namespace {

std::vector<double> stress_history(const ElasticMaterial& m, double height, double k, double dt,
                                   double rise, int steps) {
  const double length = 2 * std::numbers::pi / k;
  StripHistory history(m, height, length, 4, dt);
  return testing::single_mode_stress(history, rise, steps);
}

}  // namespace

TEST_CASE("strip and half-space responses agree before the first reflection") {
  for (auto plane : {PlaneCondition::strain, PlaneCondition::stress}) {
    ElasticMaterial m;
    m.plane = plane;
    const double H = 0.1, cs = m.shear_wave_speed(), cd = m.dilatational_wave_speed();
    const int steps_per_echo = 256;  // 2H/c_s = 256 dt
    const double dt = 2 * H / cs / steps_per_echo;
    const int window = static_cast<int>(std::floor(2 * H / cd / dt));  // t < 2H/c_d
    const double rise = 0.6 * window * dt;
    // Virtual height for the half-space: 8 times taller, same dt (2Hv/c_s = 8 * 256 dt).
    const double Hv = 8 * H;
    for (double kH : {0.05, 0.5, 5.0}) {
      const double k = kH / H;
      const auto strip = stress_history(m, H, k, dt, rise, window - 1);
      const auto half = stress_history(m, Hv, k, dt, rise, window - 1);
      double num = 0, den = 0;
      for (int n = 0; n < window; ++n) {
        num += (strip[n] - half[n]) * (strip[n] - half[n]);
        den += half[n] * half[n];
      }
      const double err = std::sqrt(num / den);
      MESSAGE((plane == PlaneCondition::strain ? "strain" : "stress")
              << " kH = " << kH << ": " << window << " steps before 2H/c_d, relative L2 difference " << err);
      CHECK(err < 1e-6);  // issue requirement
    }
  }
}
