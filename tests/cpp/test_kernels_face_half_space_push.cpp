// The half-space face operator's time loop (FaceHalfSpaceHistory::push, its
// exponentials advanced as real rotations in contiguous arrays) against the
// explicit convolution with its own coefficients (mode_kernel: the stored lags,
// then 2 Re sum w z^i) for complex white-noise inputs on both components, all
// four entries at once, several modes.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <random>
#include <vector>

#include "kernels/face_half_space.hpp"

namespace {
using cd = std::complex<double>;
}

TEST_CASE("half-space face operator: push() is the convolution with its coefficients (complex inputs)") {
  // Tolerance 1e-12 of the largest history value: the recursions z^i and the
  // sums over ~300 exponentials and up to 600 lags round at ~1e-15 each.
  slipstrip::ElasticMaterial m;
  m.poisson_ratio = 0.3;
  const int nodes = 16, steps = 600;
  const double length = 0.2, dt = 0.3 * (length / nodes) / m.shear_wave_speed();
  slipstrip::FaceHalfSpaceHistory op(m, length, nodes, dt);
  const cd i(0.0, 1.0);
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::vector<std::vector<cd>> vx(steps, std::vector<cd>(op.modes())), vy = vx;
  for (int n = 0; n < steps; ++n)
    for (int q = 0; q < op.modes(); ++q) {
      vx[n][q] = cd(noise(rng), noise(rng));
      vy[n][q] = cd(noise(rng), noise(rng));
    }
  std::vector<std::vector<cd>> hx(steps), hy(steps);
  for (int n = 0; n < steps; ++n) {
    op.push(vx[n], vy[n]);
    hx[n].assign(op.history_x().begin(), op.history_x().end());
    hy[n].assign(op.history_y().begin(), op.history_y().end());
  }
  int checked = 0;
  for (int q : {1, 2, 5, 8}) {
    const auto k = op.mode_kernel(q);
    const std::size_t window = k.lag_weight[0].size();
    std::vector<double> kernel[3];
    for (std::size_t e = 0; e < 3; ++e)
      for (std::size_t j = 1; j <= static_cast<std::size_t>(steps); ++j) {
        if (j <= window) {
          kernel[e].push_back(k.static_weight[e] + k.lag_weight[e][j - 1]);
          continue;
        }
        cd acc = 0.0;
        for (std::size_t p = 0; p < k.pole.size(); ++p)
          acc += k.pole_weight[e][p] * std::pow(k.pole[p], double(j - window));
        kernel[e].push_back(k.static_weight[e] + 2.0 * acc.real());
      }
    double worst = 0.0, scale = 0.0;
    for (int n = 0; n < steps; ++n) {
      // h_{n+1} = sum_{j>=1} K_j v_{n+1-j}, K = [[K0, -i K1], [i K1, K2]].
      cd rx = 0.0, ry = 0.0;
      for (int j = 1; j <= n + 1; ++j) {
        const cd ux = vx[n + 1 - j][q], uy = vy[n + 1 - j][q];
        rx += kernel[0][j - 1] * ux - i * kernel[1][j - 1] * uy;
        ry += i * kernel[1][j - 1] * ux + kernel[2][j - 1] * uy;
      }
      worst = std::max({worst, std::abs(hx[n][q] - rx), std::abs(hy[n][q] - ry)});
      scale = std::max({scale, std::abs(rx), std::abs(ry)});
    }
    CAPTURE(q);
    MESSAGE("q = ", q, ": push vs convolution ", worst / scale);
    CHECK(worst <= 1e-12 * scale);
    ++checked;
  }
  CHECK(checked == 4);
}
