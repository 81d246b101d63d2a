// Slip events on a 2D interface (events/event_detection.hpp,
// detect_interface_2d_events) on hand-built slip-sampled records whose
// catalog is known by construction: two patches slipping at the same time,
// a patch wrapping across both periodic boundaries, a patch one row wide
// (below the size filter), and a line's record repeated along z, which must
// give the line's catalog with area = extent * width.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <vector>

#include "events/event_detection.hpp"
#include "events_test_support.hpp"

using namespace slipstrip::events;
using events_test::History;

namespace {

constexpr double kStep = 1e-7;  // [s] between crossings inside a patch


// nodes_x x nodes_z nodes, dx = dz = 1 cm, delta_th = 1e-8 m, v0 = 2e-3 m/s,
// mu = 9 GPa: waiting-time threshold 15 * 1e-8 / (2e-3 * nodes_x).
SlipSamplingInfo plane_info(std::size_t nx, std::size_t nz) {
  SlipSamplingInfo info;
  info.delta_th = 1e-8;
  info.dx = info.dz = 0.01;
  info.v0 = 2e-3;
  info.mu = 9e9;
  info.nodes_z = static_cast<int>(nz);
  info.L = info.dx * static_cast<double>(nx);
  info.W = info.dz * static_cast<double>(nz);
  for (std::size_t i = 0; i < nx * nz; ++i) {
    info.x.push_back(static_cast<double>(i % nx) * info.dx);
    info.z.push_back(static_cast<double>(i / nx) * info.dz);
  }
  return info;
}

// A rectangular patch [x0, x0 + wx) x [z0, z0 + wz) (periodic) nucleating at
// its corner (x0, z0) at t0: node at Chebyshev distance r from it crosses
// `levels` levels at t0 + (r + k) kStep.  Returns the patch's duration.
double patch(History& record, std::size_t nx, std::size_t nz, std::size_t x0, std::size_t z0, std::size_t wx,
             std::size_t wz, int levels, double t0) {
  double last = t0;
  for (std::size_t a = 0; a < wz; ++a)
    for (std::size_t b = 0; b < wx; ++b) {
      const std::size_t node = ((z0 + a) % nz) * nx + (x0 + b) % nx;
      const double r = static_cast<double>(std::max(a, b));
      for (int k = 0; k < levels; ++k) {
        last = std::max(last, t0 + (r + k) * kStep);
        record.slip(node, t0 + (r + k) * kStep);
      }
    }
  return last - t0;
}

}  // namespace

TEST_CASE("2D interface: separate patches at the same time, a wrapping patch, a one-row patch, first/last groups") {
  const std::size_t nx = 32, nz = 16;
  const SlipSamplingInfo info = plane_info(nx, nz);
  const double cell = info.dx * info.dz, dth = info.delta_th;
  History r(nx * nz);
  patch(r, nx, nz, 10, 10, 3, 3, 2, 1e-4);  // the first group: excluded
  // One time group, three patches that do not touch: 5 x 5 with 3 levels,
  // 3 x 4 with 4 levels starting 2 steps later, and 6 x 1 (one row: filtered).
  const double d1 = patch(r, nx, nz, 3, 1, 5, 5, 3, 1e-3);
  const double d2 = patch(r, nx, nz, 18, 8, 3, 4, 4, 1e-3 + 2 * kStep);
  patch(r, nx, nz, 20, 3, 6, 1, 3, 1e-3 + kStep);
  // The next group: a 5 x 4 patch nucleating at (30, 14), wrapping across
  // x = L and z = W, 2 levels.
  const double d3 = patch(r, nx, nz, 30, 14, 5, 4, 2, 2e-3);
  patch(r, nx, nz, 10, 10, 3, 3, 2, 3e-3);  // the last group: excluded

  const std::vector<double> m = r.matrix();
  const EventCatalog c = detect_interface_2d_events(RowMajorCrossingTimes(m, r.n_levels(), nx * nz), info);
  CHECK(c.waiting_time_threshold == doctest::Approx(15 * dth / (info.v0 * nx)).epsilon(1e-15));
  CHECK(c.n_events_detected == 6);
  CHECK(c.n_events_excluded_first_last == 2);
  CHECK(c.n_events_below_thresholds == 1);
  REQUIRE(c.n_events() == 3);
  // In order of their first nodal slip; exact values (sums of a few
  // multiples of dx, dz, delta_th: the tolerance of doctest's Approx, 1e-15
  // relative, only absorbs the rounding of those products).
  const double t_start[] = {1e-3, 1e-3 + 2 * kStep, 2e-3}, duration[] = {d1, d2, d3};
  const double x0[] = {0.03, 0.18, 0.30}, z0[] = {0.01, 0.08, 0.14};
  const double nodes[] = {25, 12, 20}, slip[] = {3 * dth, 4 * dth, 2 * dth};
  const double lx[] = {0.05, 0.03, 0.05}, lz[] = {0.05, 0.04, 0.04};
  for (std::size_t e = 0; e < 3; ++e) {
    CAPTURE(e);
    CHECK(c.t_start[e] == t_start[e]);
    CHECK(c.duration[e] == doctest::Approx(duration[e]).epsilon(1e-12));  // differences of times near 1e-3 s
    CHECK(c.x_start[e] == doctest::Approx(x0[e]).epsilon(1e-15));
    CHECK(c.z_start[e] == doctest::Approx(z0[e]).epsilon(1e-15));
    CHECK(c.area[e] == doctest::Approx(nodes[e] * cell).epsilon(1e-15));
    CHECK(c.mean_slip[e] == doctest::Approx(slip[e]).epsilon(1e-15));
    CHECK(c.moment[e] == doctest::Approx(info.mu * nodes[e] * cell * slip[e]).epsilon(1e-15));
    CHECK(c.extent[e] == doctest::Approx(lx[e]).epsilon(1e-15));
    CHECK(c.extent_z[e] == doctest::Approx(lz[e]).epsilon(1e-15));
    CHECK(c.max_slip_rate[e] == doctest::Approx(dth / kStep).epsilon(1e-6));  // kStep differences at t ~ 1e-3 s
    CHECK(c.n_clusters[e] == 1);
  }
  // The same patches found through detect_events (dispatch on nodes_z).
  const EventCatalog via = detect_events(RowMajorCrossingTimes(m, r.n_levels(), nx * nz), info);
  CHECK(via.area == c.area);
}

TEST_CASE("2D interface: a line's record repeated along z gives the line's catalog, area = L_s W") {
  // A line of 32 nodes with crack-like events of one connected cluster each
  // (two wrapping across x = L), separated in time.
  const std::size_t nx = 32, nz = 4;
  SlipSamplingInfo line;
  line.delta_th = 1e-8;
  line.dx = 0.01;
  line.v0 = 2e-3;
  line.mu = 9e9;
  for (std::size_t i = 0; i < nx; ++i) line.x.push_back(static_cast<double>(i) * line.dx);
  History r(nx);
  const struct {
    std::size_t x0, width;
    int levels;
  } events[] = {{4, 6, 2}, {28, 9, 5}, {10, 3, 3}, {0, 32, 2}, {15, 12, 4}, {30, 5, 2}};
  double t0 = 1e-4;
  for (const auto& e : events) {
    // Nucleation in the middle, a bilateral front at one node per kStep.
    const std::size_t mid = e.width / 2;
    for (std::size_t b = 0; b < e.width; ++b) {
      const double d = std::abs(static_cast<double>(b) - static_cast<double>(mid));
      for (int k = 0; k < e.levels; ++k) r.slip((e.x0 + b) % nx, t0 + (d + k) * kStep);
    }
    t0 += 1e-3;
  }
  const std::vector<double> m1 = r.matrix();
  const EventCatalog c1 = detect_events(RowMajorCrossingTimes(m1, r.n_levels(), nx), line);
  REQUIRE(c1.n_events() == 4);  // six events, the first and the last excluded
  for (int clusters : c1.n_clusters) REQUIRE(clusters == 1);

  SlipSamplingInfo plane = plane_info(nx, nz);
  std::vector<double> m2(r.n_levels() * nx * nz);
  for (std::size_t j = 0; j < r.n_levels(); ++j)
    for (std::size_t i = 0; i < nx * nz; ++i) m2[j * nx * nz + i] = m1[j * nx + i % nx];
  const EventCatalog c2 = detect_events(RowMajorCrossingTimes(m2, r.n_levels(), nx * nz), plane);
  REQUIRE(c2.n_events() == c1.n_events());
  CHECK(c2.n_events_detected == c1.n_events_detected);
  CHECK(c2.n_nodal_slips == nz * c1.n_nodal_slips);
  const double width = plane.dz * nz;
  for (std::size_t e = 0; e < c1.n_events(); ++e) {
    CAPTURE(e);
    // The same nodal slips, the same arithmetic: bit for bit.
    CHECK(c2.t_start[e] == c1.t_start[e]);
    CHECK(c2.duration[e] == c1.duration[e]);
    CHECK(c2.mean_slip[e] == c1.mean_slip[e]);
    CHECK(c2.x_start[e] == c1.x_start[e]);
    CHECK(c2.z_start[e] == 0.0);
    CHECK(c2.extent[e] == c1.extent[e]);
    CHECK(c2.max_slip_rate[e] == c1.max_slip_rate[e]);
    // area = (k nz) dx dz against L_s W = (k dx)(nz dz): the same product in
    // another order, 1e-15 relative.
    CHECK(c2.area[e] == doctest::Approx(c1.extent[e] * width).epsilon(1e-15));
    CHECK(c2.moment[e] == doctest::Approx(c1.moment[e] * width).epsilon(1e-15));  // N/m * m = N m
  }
}

TEST_CASE("2D interface: bad metadata is refused naming it") {
  const SlipSamplingInfo info = plane_info(8, 4);
  const std::vector<double> m(32, 1e-3);
  SlipSamplingInfo bad = info;
  bad.nodes_z = 5;
  CHECK_THROWS_WITH_AS(detect_interface_2d_events(RowMajorCrossingTimes(m, 1, 32), bad),
                       doctest::Contains("nodes_z = 5 is invalid"), std::invalid_argument);
  bad = info;
  bad.dz = 0.0;
  CHECK_THROWS_WITH_AS(detect_interface_2d_events(RowMajorCrossingTimes(m, 1, 32), bad),
                       doctest::Contains("dz = 0"), std::invalid_argument);
  bad = info;
  bad.z.pop_back();
  CHECK_THROWS_WITH_AS(detect_interface_2d_events(RowMajorCrossingTimes(m, 1, 32), bad),
                       doctest::Contains("x, z sizes = 32, 31"), std::invalid_argument);
}
