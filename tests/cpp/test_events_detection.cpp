// Slip-event detection on synthetic slip histories whose catalog is known by
// construction, plus a brute-force reference (materialise all NS, sort,
// group, walk the ring) for a random stick-slip history.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "events/event_detection.hpp"
#include "events_test_support.hpp"

using namespace slipstrip::events;
using events_test::History;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// N = 64 nodes, dx = 1 cm, delta_th = 1e-8 m, v0 = 2e-3 m/s:
// waiting-time threshold = 15 * 1e-8 / (2e-3 * 64) = 1.171875e-6 s.
struct Setup {
  std::size_t n = 64;
  SlipSamplingInfo info;
  Setup() {
    info.delta_th = 1e-8;
    info.dx = 0.01;
    info.v0 = 2e-3;
    info.mu = 9e9;
    info.L = info.dx * static_cast<double>(n);
    info.x.resize(n);
    for (std::size_t i = 0; i < n; ++i) info.x[i] = static_cast<double>(i) * info.dx;
  }
};


// A crack-like event: the front leaves `first` at t0 and reaches a node at
// ring distance d (towards higher indices, wrapping) at t0 + d * dt_front;
// that node then crosses levels every dt_slip, `levels[d]` times.
struct Crack {
  std::size_t first;
  std::vector<int> levels;
  double t0;
  double dt_front = 1e-7;  // both < threshold 1.17e-6 s, so the NS stream has no gap
  double dt_slip = 2e-7;
  void add_to(History& h) const {
    for (std::size_t d = 0; d < levels.size(); ++d)
      for (int m = 0; m < levels[d]; ++m)
        h.slip(first + d, t0 + static_cast<double>(d) * dt_front + m * dt_slip);
  }
  double duration() const {
    double t = 0.0;
    for (std::size_t d = 0; d < levels.size(); ++d)
      if (levels[d] > 0) t = std::max(t, static_cast<double>(d) * dt_front + (levels[d] - 1) * dt_slip);
    return t;
  }
  int n_ns() const {
    int s = 0;
    for (int l : levels) s += l;
    return s;
  }
};

EventCatalog run(const History& h, const Setup& s, EventDetectionOptions o = {}) {
  const std::vector<double> m = h.matrix();
  const RowMajorCrossingTimes source(m, h.n_levels(), s.n);
  return detect_events(source, s.info, o);
}

EventDetectionOptions keep_all_events() {
  EventDetectionOptions o;
  o.exclude_first_last = false;
  return o;
}

// Times are of order 1e-3 s and are built by adding a few terms, so derived
// quantities carry ~1e-16 * 1e-3 s absolute rounding; durations and slip
// rates (differences of such times over ~1e-7 s) are compared at 1e-8
// relative, which is far above that error and far below any real mistake
// (one dt_slip or one node would change them by >= 1e-2 relative).
constexpr double kRel = 1e-8;

}  // namespace

TEST_CASE("nodal-slip stream equals a full sort of all finite crossing times") {
  // Reference: materialise every NS and sort by (time, node).  Times are
  // drawn on a coarse grid so that ties occur; block sizes 1, 3 and 1000
  // exercise the row window (loading, release, single block).
  std::mt19937_64 rng(7);
  const std::size_t n = 37, nl = 50;
  std::vector<double> m(nl * n, kNaN);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t len = rng() % (nl + 1);  // includes empty columns and full columns
    double t = 0.0;
    for (std::size_t j = 0; j < len; ++j) {
      t += static_cast<double>(rng() % 4) * 0.5;  // steps 0, 0.5, 1, 1.5: ties and equal successive times
      m[j * n + i] = t;
    }
  }
  struct Ref { double t; int node, level; double duration; };
  std::vector<Ref> ref;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < nl && !std::isnan(m[j * n + i]); ++j)
      ref.push_back({m[j * n + i], static_cast<int>(i), static_cast<int>(j),
                     m[j * n + i] - (j == 0 ? 0.0 : m[(j - 1) * n + i])});
  // Order (time, node, level): a column's equal successive times keep level order.
  std::sort(ref.begin(), ref.end(), [](const Ref& a, const Ref& b) {
    return a.t < b.t || (a.t == b.t && (a.node < b.node || (a.node == b.node && a.level < b.level)));
  });

  const RowMajorCrossingTimes source(m, nl, n);
  for (std::size_t block : {std::size_t{1}, std::size_t{3}, std::size_t{1000}}) {
    NodalSlipStream stream(source, block);
    NodalSlip s;
    std::size_t k = 0;
    while (stream.next(s)) {
      REQUIRE(k < ref.size());
      // Exact: the stream only copies and subtracts the same doubles.
      CHECK(s.time == ref[k].t);
      CHECK(s.node == ref[k].node);
      CHECK(s.level == ref[k].level);
      CHECK(s.duration == ref[k].duration);
      ++k;
    }
    CHECK(k == ref.size());
  }
}

TEST_CASE("isolated crack-like events: exact extent, slip, duration, start position") {
  Setup s;
  History h(s.n);
  // Elliptical-ish slip profiles, in levels (units of delta_th).
  const Crack a{10, {3, 5, 6, 5, 3}, 1.0e-3};
  const Crack b{30, {2, 4, 7, 8, 7, 4, 2}, 2.0e-3};
  const Crack c{50, {4, 4}, 3.0e-3};
  for (const Crack* e : {&a, &b, &c}) e->add_to(h);

  const EventCatalog cat = run(h, s, keep_all_events());
  REQUIRE(cat.n_events() == 3);
  CHECK(cat.n_events_detected == 3);
  CHECK(cat.n_nodal_slips == static_cast<std::uint64_t>(a.n_ns() + b.n_ns() + c.n_ns()));
  CHECK(cat.waiting_time_threshold == doctest::Approx(1.171875e-6).epsilon(1e-14));
  std::size_t k = 0;
  for (const Crack* e : {&a, &b, &c}) {
    const double nodes = static_cast<double>(e->levels.size());
    CHECK(cat.t_start[k] == e->t0);
    CHECK(cat.x_start[k] == s.info.x[e->first]);
    CHECK(cat.duration[k] == doctest::Approx(e->duration()).epsilon(kRel));
    CHECK(cat.extent[k] == doctest::Approx(nodes * s.info.dx).epsilon(1e-14));
    CHECK(cat.mean_slip[k] == doctest::Approx(s.info.delta_th * e->n_ns() / nodes).epsilon(1e-14));
    // M0 = mu L_s u_mean = mu dx delta_th n_NS
    CHECK(cat.moment[k] == doctest::Approx(s.info.mu * s.info.dx * s.info.delta_th * e->n_ns()).epsilon(1e-13));
    CHECK(cat.max_slip_rate[k] == doctest::Approx(s.info.delta_th / e->dt_slip).epsilon(kRel));
    CHECK(cat.n_clusters[k] == 1);
    ++k;
  }
}

TEST_CASE("two simultaneous events far apart merge into one event with two clusters") {
  // The paper groups NS by the global waiting time only, so two patches that
  // slip at the same time anywhere on the interface are one event.
  Setup s;
  History h(s.n);
  const Crack left{5, {3, 4, 3}, 1.0e-3};
  const Crack right{40, {2, 5, 5, 2}, 1.0e-3 + 3e-7};
  // Interleave the two patches' NS in each column (different columns, so the
  // builder order does not matter).
  left.add_to(h);
  right.add_to(h);
  const EventCatalog cat = run(h, s, keep_all_events());
  REQUIRE(cat.n_events() == 1);
  CHECK(cat.n_clusters[0] == 2);
  CHECK(cat.t_start[0] == left.t0);
  CHECK(cat.x_start[0] == s.info.x[5]);
  CHECK(cat.extent[0] == doctest::Approx(7 * s.info.dx).epsilon(1e-14));
  CHECK(cat.mean_slip[0] == doctest::Approx(s.info.delta_th * (10 + 14) / 7.0).epsilon(1e-14));
  CHECK(cat.duration[0] == doctest::Approx(3e-7 + right.duration()).epsilon(kRel));
}

TEST_CASE("an event crossing the periodic boundary is one cluster with the full extent") {
  Setup s;
  History h(s.n);
  // Nodes 61, 62, 63, 0, 1, 2 (first = 61).
  const Crack wrap{61, {3, 4, 5, 5, 4, 3}, 1.0e-3};
  wrap.add_to(h);
  const EventCatalog cat = run(h, s, keep_all_events());
  REQUIRE(cat.n_events() == 1);
  CHECK(cat.n_clusters[0] == 1);
  CHECK(cat.extent[0] == doctest::Approx(6 * s.info.dx).epsilon(1e-14));
  CHECK(cat.x_start[0] == s.info.x[61]);
  CHECK(cat.mean_slip[0] == doctest::Approx(s.info.delta_th * 24 / 6.0).epsilon(1e-14));

  // Same patch plus a separate patch touching node 0 only from the other
  // side would be a second cluster: nodes 60..63,0 and 5..7.
  History h2(s.n);
  const Crack wrap2{60, {3, 3, 3, 3, 3}, 1.0e-3};
  const Crack other{5, {3, 3, 3}, 1.0e-3 + 1e-7};
  wrap2.add_to(h2);
  other.add_to(h2);
  const EventCatalog cat2 = run(h2, s, keep_all_events());
  REQUIRE(cat2.n_events() == 1);
  CHECK(cat2.n_clusters[0] == 2);
  CHECK(cat2.extent[0] == doctest::Approx(8 * s.info.dx).epsilon(1e-14));

  // A patch covering the whole ring is one cluster.
  History h3(s.n);
  Crack all{17, std::vector<int>(s.n, 2), 1.0e-3};
  all.add_to(h3);
  const EventCatalog cat3 = run(h3, s, keep_all_events());
  REQUIRE(cat3.n_events() == 1);
  CHECK(cat3.n_clusters[0] == 1);
  CHECK(cat3.extent[0] == doctest::Approx(s.info.L).epsilon(1e-14));
}

TEST_CASE("multi-cluster event: small clusters are dropped from n_clusters, not from L_s") {
  Setup s;
  History h(s.n);
  const Crack big1{2, {3, 6, 6, 3}, 1.0e-3};
  const Crack big2{20, {4, 4, 4}, 1.0e-3 + 2e-7};
  const Crack big3{45, {2, 2}, 1.0e-3 + 4e-7};        // exactly at both thresholds: kept
  const Crack one_node{30, {9}, 1.0e-3 + 1e-7};       // extent dx < 2 dx: dropped
  const Crack low_slip{55, {1, 1, 1}, 1.0e-3 + 3e-7}; // mean slip delta_th < 2 delta_th: dropped
  for (const Crack* e : {&big1, &big2, &big3, &one_node, &low_slip}) e->add_to(h);
  const EventCatalog cat = run(h, s, keep_all_events());
  REQUIRE(cat.n_events() == 1);
  CHECK(cat.n_clusters[0] == 3);
  const int n_ns = big1.n_ns() + big2.n_ns() + big3.n_ns() + one_node.n_ns() + low_slip.n_ns();
  CHECK(cat.extent[0] == doctest::Approx(13 * s.info.dx).epsilon(1e-14));
  CHECK(cat.mean_slip[0] == doctest::Approx(s.info.delta_th * n_ns / 13.0).epsilon(1e-14));
  // The shortest per-node interval is dt_slip; the one-node cluster also has dt_slip.
  CHECK(cat.max_slip_rate[0] == doctest::Approx(s.info.delta_th / 2e-7).epsilon(kRel));
}

TEST_CASE("creep below threshold: unreached levels are NaN, tiny creep events are filtered") {
  Setup s;
  History h(s.n);
  const Crack a{10, {3, 5, 5, 3}, 1.0e-3};
  const Crack b{40, {2, 6, 6, 6, 2}, 5.0e-3};
  a.add_to(h);
  b.add_to(h);
  // Node 25 creeps: one NS every 0.5 ms, isolated in time, so each is its own
  // one-node, one-delta_th event (0.2 ms from any crack, >> threshold).
  int creep_events = 0;
  for (double t = 0.2e-3; t < 6e-3; t += 0.5e-3) {
    if (std::abs(t - 1.0e-3) < 0.1e-3 || std::abs(t - 5.0e-3) < 0.1e-3) continue;
    h.slip(25, t);
    ++creep_events;
  }
  // Nodes 60..63 never reach delta_th: their columns stay all-NaN.  A pair of
  // neighbours each reaching delta_th once, together: extent 2 dx passes, mean
  // slip delta_th does not.
  h.slip(50, 3.3e-3);
  h.slip(51, 3.3e-3 + 1e-7);
  const EventCatalog cat = run(h, s, keep_all_events());
  CHECK(cat.n_events_detected == static_cast<std::uint64_t>(2 + creep_events + 1));
  CHECK(cat.n_events_below_thresholds == static_cast<std::uint64_t>(creep_events + 1));
  REQUIRE(cat.n_events() == 2);
  CHECK(cat.t_start[0] == a.t0);
  CHECK(cat.t_start[1] == b.t0);
  CHECK(cat.extent[1] == doctest::Approx(5 * s.info.dx).epsilon(1e-14));

  // Relaxing the filters keeps them all.
  EventDetectionOptions o = keep_all_events();
  o.min_extent_dx = 0.0;
  o.min_mean_slip_dth = 0.0;
  const EventCatalog all = run(h, s, o);
  CHECK(all.n_events() == static_cast<std::size_t>(2 + creep_events + 1));
  // A one-node, one-NS event: zero duration, no pair of crossings -> NaN rate.
  CHECK(all.duration[0] == 0.0);
  CHECK(std::isnan(all.max_slip_rate[0]));
}

TEST_CASE("first and last events are excluded by default") {
  Setup s;
  History h(s.n);
  // First: whole interface, triggered by the initial state.  Last: cut by the end.
  const Crack first{0, std::vector<int>(s.n, 3), 0.1e-3};
  const Crack mid1{10, {3, 4, 3}, 1.0e-3};
  const Crack mid2{30, {5, 5}, 2.0e-3};
  const Crack last{50, {2, 2, 2}, 3.0e-3};
  for (const Crack* e : {&first, &mid1, &mid2, &last}) e->add_to(h);

  const EventCatalog cat = run(h, s);
  CHECK(cat.n_events_detected == 4);
  CHECK(cat.n_events_excluded_first_last == 2);
  CHECK(cat.n_events_below_thresholds == 0);
  REQUIRE(cat.n_events() == 2);
  CHECK(cat.t_start[0] == mid1.t0);
  CHECK(cat.t_start[1] == mid2.t0);

  const EventCatalog all = run(h, s, keep_all_events());
  REQUIRE(all.n_events() == 4);
  CHECK(all.t_start[0] == first.t0);
  CHECK(all.t_start[3] == last.t0);
  CHECK(all.extent[0] == doctest::Approx(s.info.L).epsilon(1e-14));

  // A single event is both first and last: excluded once.
  History one(s.n);
  mid1.add_to(one);
  const EventCatalog c1 = run(one, s);
  CHECK(c1.n_events_detected == 1);
  CHECK(c1.n_events_excluded_first_last == 1);
  CHECK(c1.n_events() == 0);

  // No slip at all.
  const EventCatalog c0 = run(History(s.n), s);
  CHECK(c0.n_events_detected == 0);
  CHECK(c0.n_nodal_slips == 0);
}

TEST_CASE("waiting-time threshold: a gap equal to the threshold continues the event, a larger one splits") {
  Setup s;
  const double thr = waiting_time_threshold(15.0, s.info.delta_th, s.info.v0, s.n);
  History h(s.n);
  h.slip(3, 1e-3);
  h.slip(4, 1e-3 + thr);  // may differ from thr by rounding of the sum; see below
  const double gap = (1e-3 + thr) - 1e-3;
  const EventCatalog cat = run(h, s, keep_all_events());
  CHECK(cat.n_events_detected == (gap > thr ? 2u : 1u));
  History h2(s.n);
  h2.slip(3, 1e-3);
  h2.slip(4, 1e-3 + 1.01 * thr);
  CHECK(run(h2, s, keep_all_events()).n_events_detected == 2);
  History h3(s.n);
  h3.slip(3, 1e-3);
  h3.slip(4, 1e-3 + 0.99 * thr);
  CHECK(run(h3, s, keep_all_events()).n_events_detected == 1);
}

namespace {

// Brute-force reference: all NS materialised and sorted; clusters found by
// walking the ring from an unslipped node.
EventCatalog reference_catalog(const std::vector<double>& m, std::size_t nl, std::size_t n,
                               const SlipSamplingInfo& info, const EventDetectionOptions& o) {
  struct NS { double t; int node; };
  std::vector<NS> all;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < nl && !std::isnan(m[j * n + i]); ++j) all.push_back({m[j * n + i], static_cast<int>(i)});
  std::sort(all.begin(), all.end(), [](const NS& a, const NS& b) { return a.t < b.t || (a.t == b.t && a.node < b.node); });
  const double thr = o.alpha * info.delta_th / (info.v0 * static_cast<double>(n));
  std::vector<std::pair<std::size_t, std::size_t>> groups;
  std::size_t begin = 0;
  for (std::size_t k = 1; k <= all.size(); ++k)
    if (k == all.size() || all[k].t - all[k - 1].t > thr) {
      if (k > begin) groups.push_back({begin, k});
      begin = k;
    }
  EventCatalog c;
  auto passes = [&](double nodes, double ns) { return nodes >= o.min_extent_dx && ns >= o.min_mean_slip_dth * nodes; };
  for (std::size_t g = 0; g < groups.size(); ++g) {
    if (o.exclude_first_last && (g == 0 || g + 1 == groups.size())) continue;
    std::vector<int> count(n, 0);
    std::vector<std::vector<double>> times(n);
    for (std::size_t k = groups[g].first; k < groups[g].second; ++k) {
      ++count[all[k].node];
      times[all[k].node].push_back(all[k].t);
    }
    double nodes = 0, ns = 0, min_dt = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < n; ++i) {
      nodes += count[i] > 0;
      ns += count[i];
      for (std::size_t q = 1; q < times[i].size(); ++q) min_dt = std::min(min_dt, times[i][q] - times[i][q - 1]);
    }
    if (!passes(nodes, ns)) continue;
    int clusters = 0;
    std::size_t start = n;
    for (std::size_t i = 0; i < n; ++i)
      if (count[i] == 0) { start = i; break; }
    if (start == n) {
      clusters = passes(nodes, ns) ? 1 : 0;
    } else {
      double run_nodes = 0, run_ns = 0;
      for (std::size_t q = 1; q <= n; ++q) {
        const std::size_t i = (start + q) % n;
        if (count[i] > 0) { run_nodes += 1; run_ns += count[i]; }
        else {
          if (run_nodes > 0 && passes(run_nodes, run_ns)) ++clusters;
          run_nodes = run_ns = 0;
        }
      }
    }
    const NS& first = all[groups[g].first];
    c.t_start.push_back(first.t);
    c.duration.push_back(all[groups[g].second - 1].t - first.t);
    c.x_start.push_back(info.x[first.node]);
    c.extent.push_back(nodes * info.dx);
    c.mean_slip.push_back(info.delta_th * ns / nodes);
    c.moment.push_back(info.mu * nodes * info.dx * info.delta_th * ns / nodes);
    c.max_slip_rate.push_back(std::isinf(min_dt) ? kNaN : info.delta_th / min_dt);
    c.n_clusters.push_back(clusters);
  }
  return c;
}

}  // namespace

TEST_CASE("random stick-slip history: streaming catalog equals the brute-force reference") {
  Setup s;
  s.n = 128;
  s.info.x.resize(s.n);
  for (std::size_t i = 0; i < s.n; ++i) s.info.x[i] = static_cast<double>(i) * s.info.dx;
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  History h(s.n);
  double t = 0.0;
  for (int e = 0; e < 400; ++e) {
    // Gaps straddle the threshold (1.17e-6 s at N = 64, 5.9e-7 s here) so some
    // events merge; patches may wrap around and may be simultaneous.
    t += u(rng) < 0.2 ? 2e-7 + 1e-6 * u(rng) : 1e-5 * (1 + u(rng));
    const int patches = u(rng) < 0.2 ? 2 : 1;
    double t_end = t;
    for (int p = 0; p < patches; ++p) {
      const std::size_t first = rng() % s.n;
      const std::size_t width = 1 + rng() % 40;
      const double slip = 1 + 8 * u(rng);
      for (std::size_t d = 0; d < width; ++d) {
        const double r = (2.0 * static_cast<double>(d) + 1.0) / static_cast<double>(width) - 1.0;
        const int levels = static_cast<int>(slip * std::sqrt(1 - r * r) + u(rng));
        const double arrival = t + static_cast<double>(d) * 5e-8 * (1 + u(rng));
        for (int q = 0; q < levels; ++q) {
          const double tq = arrival + q * 1e-7 * (0.5 + u(rng));
          auto& col = h.columns[(first + d) % s.n];
          col.push_back(std::max(tq, col.empty() ? 0.0 : col.back() + 1e-8));
          t_end = std::max(t_end, col.back());
        }
      }
    }
    t = t_end;
  }
  const std::vector<double> m = h.matrix();
  const RowMajorCrossingTimes source(m, h.n_levels(), s.n);
  for (bool exclude : {true, false}) {
    EventDetectionOptions o;
    o.exclude_first_last = exclude;
    o.block_rows = 4;  // small blocks: the window is released and refilled many times
    const EventCatalog got = detect_events(source, s.info, o);
    const EventCatalog ref = reference_catalog(m, h.n_levels(), s.n, s.info, o);
    REQUIRE(got.n_events() == ref.n_events());
    CHECK(got.n_events() > 100);
    int multi = 0;
    for (std::size_t k = 0; k < ref.n_events(); ++k) {
      // Same doubles, same operations up to summation order: 1e-12 relative.
      CHECK(got.t_start[k] == ref.t_start[k]);
      CHECK(got.duration[k] == ref.duration[k]);
      CHECK(got.x_start[k] == ref.x_start[k]);
      CHECK(got.extent[k] == doctest::Approx(ref.extent[k]).epsilon(1e-12));
      CHECK(got.mean_slip[k] == doctest::Approx(ref.mean_slip[k]).epsilon(1e-12));
      CHECK(got.moment[k] == doctest::Approx(ref.moment[k]).epsilon(1e-12));
      if (std::isnan(ref.max_slip_rate[k])) CHECK(std::isnan(got.max_slip_rate[k]));
      else if (std::isinf(ref.max_slip_rate[k])) CHECK(std::isinf(got.max_slip_rate[k]));
      else CHECK(got.max_slip_rate[k] == doctest::Approx(ref.max_slip_rate[k]).epsilon(1e-12));
      CHECK(got.n_clusters[k] == ref.n_clusters[k]);
      multi += got.n_clusters[k] > 1;
    }
    CHECK(multi > 0);  // the comparison covered multi-cluster events
    CHECK(got.n_events_detected ==
          got.n_events_excluded_first_last + got.n_events_below_thresholds + got.n_events());
  }
}

TEST_CASE("bad input throws std::invalid_argument naming the parameter") {
  Setup s;
  History h(s.n);
  Crack{3, {3, 3}, 1e-3}.add_to(h);
  std::vector<double> m = h.matrix();
  {
    SlipSamplingInfo bad = s.info;
    bad.v0 = 0.0;
    const RowMajorCrossingTimes src(m, h.n_levels(), s.n);
    CHECK_THROWS_WITH_AS(detect_events(src, bad), doctest::Contains("v0"), std::invalid_argument);
    bad = s.info;
    bad.x.pop_back();
    CHECK_THROWS_WITH_AS(detect_events(src, bad), doctest::Contains("x size"), std::invalid_argument);
    EventDetectionOptions o;
    o.alpha = -1;
    CHECK_THROWS_WITH_AS(detect_events(src, s.info, o), doctest::Contains("alpha"), std::invalid_argument);
  }
  // Column 3 decreasing in time.
  m[1 * s.n + 3] = 0.5e-3;
  const RowMajorCrossingTimes src(m, h.n_levels(), s.n);
  CHECK_THROWS_WITH_AS(detect_events(src, s.info), doctest::Contains("crossing_time[1, 3]"), std::invalid_argument);
}

TEST_CASE("MatrixCrossingTimes adapter gives the same catalog as the row-major view") {
  // Column-major storage behind operator()(j, i), like an Eigen matrix.
  struct ColMajor {
    std::vector<double> data;
    long r, c;
    long rows() const { return r; }
    long cols() const { return c; }
    double operator()(long j, long i) const { return data[static_cast<std::size_t>(i * r + j)]; }
  };
  Setup s;
  History h(s.n);
  for (const Crack& e : {Crack{3, {2, 3, 2}, 1e-3}, Crack{20, {4, 4, 4, 4}, 2e-3}, Crack{40, {2, 2}, 3e-3},
                         Crack{60, {3, 3, 3, 3, 3, 3, 3}, 4e-3}})
    e.add_to(h);
  const std::vector<double> m = h.matrix();
  const std::size_t nl = h.n_levels();
  ColMajor cm{std::vector<double>(m.size()), static_cast<long>(nl), static_cast<long>(s.n)};
  for (std::size_t j = 0; j < nl; ++j)
    for (std::size_t i = 0; i < s.n; ++i) cm.data[i * nl + j] = m[j * s.n + i];
  const EventCatalog a = detect_events(MatrixCrossingTimes<ColMajor>(cm), s.info);
  const EventCatalog b = detect_events(RowMajorCrossingTimes(m, nl, s.n), s.info);
  REQUIRE(a.n_events() == 2);
  CHECK(a.t_start == b.t_start);
  CHECK(a.extent == b.extent);
  CHECK(a.moment == b.moment);
  CHECK(a.extent[1] == doctest::Approx(2 * s.info.dx).epsilon(1e-14));
}

TEST_CASE("empty_catalog_reason says which count left the catalog empty and what to change") {
  const Setup s;
  const Crack big_a{0, {3, 3, 3, 3}, 0.0}, big_b{20, {3, 3, 3, 3}, 1e-5};
  const Crack tiny_a{40, {1}, 2e-5}, tiny_b{50, {1}, 3e-5}, big_c{30, {3, 3, 3, 3}, 4e-5};

  SUBCASE("no nodal slip: delta_th above the slip of the run") {
    EventCatalog c;  // what detection gives for a slip history without a crossing
    c.delta_th = s.info.delta_th;
    c.v0 = s.info.v0;
    const std::string why = empty_catalog_reason(c, 1e-6);
    CHECK(why.find("0 nodal slips") != std::string::npos);
    CHECK(why.find("lower output.delta_th") != std::string::npos);
    CHECK(why.find("v0 t = 2e-09 m") != std::string::npos);  // 2e-3 m/s * 1e-6 s, printed to 3 digits
  }
  SUBCASE("only the first and the last event, which are always excluded") {
    History h(s.n);
    big_a.add_to(h);
    big_b.add_to(h);
    const EventCatalog c = run(h, s);
    REQUIRE(c.n_events() == 0);
    REQUIRE(c.n_events_detected == 2);
    const std::string why = empty_catalog_reason(c);
    CHECK(why.find("2 events detected") != std::string::npos);
    CHECK(why.find("always excluded") != std::string::npos);
    CHECK(why.find("--alpha") != std::string::npos);
  }
  SUBCASE("every other event below the size filters") {
    History h(s.n);
    big_a.add_to(h);
    tiny_a.add_to(h);
    tiny_b.add_to(h);
    big_c.add_to(h);
    const EventCatalog c = run(h, s);
    REQUIRE(c.n_events() == 0);
    REQUIRE(c.n_events_below_thresholds == 2);
    const std::string why = empty_catalog_reason(c);
    CHECK(why.find("all 2 events between the first and the last are below the size thresholds") !=
          std::string::npos);
    CHECK(why.find("lower output.delta_th (now 1e-08 m)") != std::string::npos);
  }
  SUBCASE("a catalog that keeps events has no reason") {
    History h(s.n);
    big_a.add_to(h);
    big_b.add_to(h);
    big_c.add_to(h);
    const EventCatalog c = run(h, s);
    REQUIRE(c.n_events() == 1);
    CHECK(empty_catalog_reason(c).empty());
  }
}
