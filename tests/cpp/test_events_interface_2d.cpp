// Slip events on a 2D interface (events/event_detection.hpp,
// detect_interface_2d_events) on hand-built slip-sampled records whose
// catalog is known by construction: two patches slipping at the same time,
// a patch wrapping across both periodic boundaries, a patch one row wide
// (below the size filter), and a line's record repeated along z, which must
// give the line's catalog with area = extent * width; and the creep filter
// (min_slip_rate_v0) on a band record and on a line.
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

// A line of `nodes` nodes with plane_info's spacing and scales.
SlipSamplingInfo line_info(std::size_t nodes) {
  SlipSamplingInfo line;
  line.delta_th = 1e-8;
  line.dx = 0.01;
  line.v0 = 2e-3;
  line.mu = 9e9;
  for (std::size_t i = 0; i < nodes; ++i) line.x.push_back(static_cast<double>(i) * line.dx);
  return line;
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
  const SlipSamplingInfo line = line_info(nx);
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

// ---------------------------------------------------------------------------
// The creep filter (EventDetectionOptions::min_slip_rate_v0).  A record as
// configs/3d/band.toml's: rate-strengthening rows that creep at v0 all the
// time (their nodal slips, staggered across the nodes, never leave a gap as
// long as the waiting time) and a band of rows that stick between fast
// patches.  Unfiltered, the creep joins the whole record into one time group
// (first and last: nothing kept); with the filter the creep and each node's
// first crossing of a patch (its Delta t reaches back to the node's previous
// patch, or t = 0) are dropped, and the catalog is exactly that of the record
// without those nodal slips.
namespace {

// A patch as `patch` above but only its levels first_level.. (the crossing
// times are those of `patch`'s formula, bit for bit).
void patch_levels(std::vector<std::vector<double>>& columns, std::size_t nx, std::size_t nz, std::size_t x0,
                  std::size_t z0, std::size_t wx, std::size_t wz, int first_level, int levels, double t0) {
  for (std::size_t a = 0; a < wz; ++a)
    for (std::size_t b = 0; b < wx; ++b) {
      const std::size_t node = ((z0 + a) % nz) * nx + (x0 + b) % nx;
      const double r = static_cast<double>(std::max(a, b));
      for (int k = first_level; k < levels; ++k) columns[node].push_back(t0 + (r + k) * kStep);
    }
}

std::vector<double> to_matrix(std::vector<std::vector<double>> columns, std::size_t& n_levels) {
  History h(columns.size());
  for (std::size_t i = 0; i < columns.size(); ++i) {
    std::sort(columns[i].begin(), columns[i].end());
    for (const double t : columns[i]) h.slip(i, t);
  }
  n_levels = h.n_levels();
  return h.matrix();
}

constexpr double kPatchTimes[] = {1e-3, 2e-3, 3e-3, 4e-3};

// The band's patches (rows 5..10 of 16; 4 levels each at 50 v0), all nodes
// of a patch slipping again at each time; with_first = false leaves out
// every node's first crossing of each patch.  `creep`: rows 0..3 and 12..15
// cross a level every delta_th / v0, the c-th of these C nodes offset by
// c delta_th / (v0 C).
std::vector<double> band_record(std::size_t nx, std::size_t nz, const SlipSamplingInfo& info, bool creep,
                                bool with_first, std::size_t& n_levels, std::uint64_t& n_creep) {
  std::vector<std::vector<double>> columns(nx * nz);
  const double period = info.delta_th / info.v0, end = 5e-3, creepers = 8.0 * static_cast<double>(nx);
  n_creep = 0;
  std::size_t c = 0;
  if (creep)
    for (std::size_t i = 0; i < nx * nz; ++i) {
      const std::size_t row = i / nx;
      if (row >= 4 && row < 12) continue;
      for (double t = period * (1.0 + static_cast<double>(c) / creepers); t < end; t += period) {
        columns[i].push_back(t);
        ++n_creep;
      }
      ++c;
    }
  for (const double t0 : kPatchTimes) patch_levels(columns, nx, nz, 8, 5, 12, 6, with_first ? 0 : 1, 4, t0);
  return to_matrix(std::move(columns), n_levels);
}

bool same_catalog(const EventCatalog& a, const EventCatalog& b) {
  return a.t_start == b.t_start && a.duration == b.duration && a.x_start == b.x_start && a.z_start == b.z_start &&
         a.extent == b.extent && a.extent_z == b.extent_z && a.area == b.area && a.mean_slip == b.mean_slip &&
         a.moment == b.moment && a.max_slip_rate == b.max_slip_rate && a.n_clusters == b.n_clusters &&
         a.n_events_detected == b.n_events_detected && a.n_events_below_thresholds == b.n_events_below_thresholds &&
         a.n_events_excluded_first_last == b.n_events_excluded_first_last;
}

}  // namespace

TEST_CASE("2D interface: min_slip_rate_v0 drops the creep and the slow first crossings, keeps the fast ones") {
  const std::size_t nx = 32, nz = 16;
  const SlipSamplingInfo info = plane_info(nx, nz);
  std::size_t nl = 0, nl_fast = 0;
  std::uint64_t n_creep = 0, none = 0;
  const std::vector<double> m = band_record(nx, nz, info, true, true, nl, n_creep);
  const RowMajorCrossingTimes record(m, nl, nx * nz);
  // Creep gaps: delta_th / (v0 C) = 2e-8 s between successive nodal slips
  // (C = 256 creeping nodes), far below the waiting time 15 delta_th / (v0
  // nx) = 2.3e-6 s.
  REQUIRE(n_creep > 0);

  // Unfiltered: one time group (the first and the last), nothing kept.
  const EventCatalog off = detect_events(record, info);
  CHECK(off.n_events() == 0);
  CHECK(off.n_events_detected == 2);  // the creep rows (joined across z = W) and the band's patches, not touching
  CHECK(off.n_nodal_slips_below_min_slip_rate == 0);
  CHECK(off.min_slip_rate == 0.0);

  // K = 8: creep (rate v0) and each patch node's first crossing (Delta t
  // ~1e-3 s, or from t = 0) are below 8 v0; the later crossings, kStep
  // apart (delta_th / kStep = 50 v0), are kept.
  EventDetectionOptions o;
  o.min_slip_rate_v0 = 8.0;
  const EventCatalog on = detect_events(record, info, o);
  const std::uint64_t patch_nodes = 12 * 6, n_patches = std::size(kPatchTimes);
  CHECK(on.min_slip_rate == 8.0 * info.v0);
  CHECK(on.n_nodal_slips == off.n_nodal_slips);
  CHECK(on.n_nodal_slips_below_min_slip_rate == n_creep + n_patches * patch_nodes);
  CHECK(on.n_events_detected == n_patches);
  REQUIRE(on.n_events() == n_patches - 2);
  for (std::size_t e = 0; e < on.n_events(); ++e) {
    CAPTURE(e);
    // The hypocentre's second crossing, at the corner (8, 5); 3 of 4 levels.
    CHECK(on.t_start[e] == kPatchTimes[e + 1] + 1.0 * kStep);
    CHECK(on.x_start[e] == info.x[5 * nx + 8]);
    CHECK(on.z_start[e] == info.z[5 * nx + 8]);
    CHECK(on.area[e] == doctest::Approx(72 * info.dx * info.dz).epsilon(1e-15));  // a product of 3 numbers
    CHECK(on.mean_slip[e] == doctest::Approx(3 * info.delta_th).epsilon(1e-15));  // 216 dth / 72
    CHECK(on.max_slip_rate[e] == doctest::Approx(info.delta_th / kStep).epsilon(1e-6));  // kStep differences at t ~ 1e-3 s
  }

  // The filter is the record without those nodal slips: bit for bit.
  const std::vector<double> m_fast = band_record(nx, nz, info, false, false, nl_fast, none);
  const EventCatalog without = detect_events(RowMajorCrossingTimes(m_fast, nl_fast, nx * nz), info);
  CHECK(same_catalog(on, without));

  // A threshold below every nodal slip's rate (the slowest: the first
  // patch's first crossings, Delta t ~1e-3 s from t = 0, rate ~5e-3 v0)
  // drops nothing and is bit for bit the unfiltered catalog.
  o.min_slip_rate_v0 = 1e-4;
  const EventCatalog tiny = detect_events(record, info, o);
  CHECK(tiny.n_nodal_slips_below_min_slip_rate == 0);
  CHECK(same_catalog(tiny, off));
  // K = 0 explicitly is the default.
  o.min_slip_rate_v0 = 0.0;
  CHECK(same_catalog(detect_events(record, info, o), off));
}

TEST_CASE("A line: min_slip_rate_v0 = the record without the slow nodal slips, bit for bit; 0 changes nothing") {
  // 32 nodes: nodes 0..7 creep at v0 (staggered), a fast 10-node event
  // (nodes 14..23, 3 levels, kStep apart) at 1, 2, 3 and 4 ms.
  const std::size_t n = 32;
  const SlipSamplingInfo line = line_info(n);
  const auto record = [&](bool creep, int first_level, std::size_t& nl) {
    std::vector<std::vector<double>> columns(n);
    const double period = line.delta_th / line.v0;
    if (creep)
      for (std::size_t i = 0; i < 8; ++i)
        for (double t = period * (1.0 + static_cast<double>(i) / 8.0); t < 5e-3; t += period) columns[i].push_back(t);
    for (const double t0 : kPatchTimes)
      for (std::size_t b = 0; b < 10; ++b)
        for (int k = first_level; k < 3; ++k)
          columns[14 + b].push_back(t0 + (std::abs(static_cast<double>(b) - 5.0) + k) * kStep);
    return to_matrix(std::move(columns), nl);
  };
  std::size_t nl = 0, nl_fast = 0;
  const std::vector<double> m = record(true, 0, nl), m_fast = record(false, 1, nl_fast);
  const RowMajorCrossingTimes source(m, nl, n);
  const EventCatalog off = detect_events(source, line);
  CHECK(off.n_events_detected == 1);  // the creep fills every gap
  CHECK(off.n_events() == 0);
  EventDetectionOptions o;
  o.min_slip_rate_v0 = 8.0;
  const EventCatalog on = detect_events(source, line, o);
  const EventCatalog without = detect_events(RowMajorCrossingTimes(m_fast, nl_fast, n), line);
  REQUIRE(on.n_events() == 2);
  CHECK(same_catalog(on, without));
  CHECK(on.mean_slip[0] == doctest::Approx(2 * line.delta_th).epsilon(1e-15));
  CHECK(on.extent[0] == doctest::Approx(10 * line.dx).epsilon(1e-15));
  CHECK(on.n_nodal_slips_below_min_slip_rate == off.n_nodal_slips - without.n_nodal_slips);
  o.min_slip_rate_v0 = 0.0;
  CHECK(same_catalog(detect_events(source, line, o), off));
}

TEST_CASE("min_slip_rate_v0: a negative or non-finite value is refused naming it") {
  const SlipSamplingInfo info = plane_info(8, 4);
  const std::vector<double> m(32, 1e-3);
  EventDetectionOptions o;
  for (const double bad : {-1.0, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    CAPTURE(bad);
    o.min_slip_rate_v0 = bad;
    CHECK_THROWS_WITH_AS(detect_events(RowMajorCrossingTimes(m, 1, 32), info, o),
                         doctest::Contains("min_slip_rate_v0 = "), std::invalid_argument);
    SlipSamplingInfo line = info;
    line.nodes_z = 1;
    CHECK_THROWS_WITH_AS(detect_events(RowMajorCrossingTimes(m, 1, 32), line, o),
                         doctest::Contains("min_slip_rate_v0 = "), std::invalid_argument);
  }
}
