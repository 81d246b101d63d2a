// SlipSampler on its own (RunOutput's file round trips are in
// test_solver_run_output.cpp).  The slips and times below are binary
// fractions, so every crossing time of the linear interpolation is exact and
// compared with ==.
#include <doctest/doctest.h>

#include <cstdint>
#include <limits>
#include <vector>

#include "solver/slip_sampler.hpp"

using slipstrip::SlipSampler;

namespace {
struct Crossing {
  hsize_t level, node;
  double time;
  friend bool operator==(const Crossing&, const Crossing&) = default;
};

std::vector<Crossing> pending(const SlipSampler& s) {
  std::vector<Crossing> out;
  const auto coords = s.pending_coordinates();
  const auto times = s.pending_times();
  for (std::size_t i = 0; i < times.size(); ++i) out.push_back({coords[2 * i], coords[2 * i + 1], times[i]});
  return out;
}
}  // namespace

TEST_CASE("each level a node's slip reaches is dated by the slip taken linear inside the step") {
  SlipSampler s(0.25, 3);
  const std::vector<double> before = {0.0, 0.0, 0.0}, after = {1.0, 0.125, 0.25};
  CHECK(s.record(2.0, 4.0, before, after));
  // Node 0 passes 0.25, 0.5, 0.75, 1.0 at a quarter, half, ... of the step;
  // node 2 ends exactly on its first level; node 1 reaches none.
  CHECK(pending(s) == std::vector<Crossing>{{0, 0, 2.5}, {1, 0, 3.0}, {2, 0, 3.5}, {3, 0, 4.0}, {0, 2, 4.0}});
  CHECK(s.levels_max() == 4);
  CHECK(std::vector<std::size_t>(s.levels_reached().begin(), s.levels_reached().end()) ==
        std::vector<std::size_t>{4, 0, 1});
  s.clear_pending();
  CHECK(s.pending() == 0);
  CHECK_FALSE(s.record(4.0, 5.0, after, after));  // no slip, no crossing
}

TEST_CASE("levels the initial slip already passed count as reached at the first step's start") {
  SlipSampler s(0.25, 1);
  CHECK(s.record(1.0, 2.0, std::vector<double>{0.5}, std::vector<double>{0.5}));
  CHECK(pending(s) == std::vector<Crossing>{{0, 0, 1.0}, {1, 0, 1.0}});
  CHECK(s.started());
}

TEST_CASE("a restored sampler continues exactly as the one it was saved from") {
  SlipSampler a(0.25, 2);
  a.record(0.0, 1.0, std::vector<double>{0.0, 0.0}, std::vector<double>{0.5, 0.25});
  const std::vector<std::uint64_t> levels(a.levels_reached().begin(), a.levels_reached().end());
  SlipSampler b(0.25, 2);
  b.restore(a.levels_max(), a.started(), levels,
            std::vector<double>(a.next_threshold().begin(), a.next_threshold().end()));
  a.clear_pending();
  const std::vector<double> from = {0.5, 0.25}, to = {1.0, 0.75};
  a.record(1.0, 2.0, from, to);
  b.record(1.0, 2.0, from, to);
  CHECK(pending(a) == pending(b));
  CHECK(b.levels_max() == a.levels_max());
}

TEST_CASE("a jump of more than kMaxLevelsPerStep levels in one step is reported as divergence") {
  SlipSampler s(1e-8, 1);
  CHECK_THROWS_AS(s.record(0.0, 1e-6, std::vector<double>{0.0}, std::vector<double>{1.0}),
                  slipstrip::SlipSamplingOverflow);
  // +inf is the solver's to report (non-finite check), not a crossing.
  s.record(0.0, 1e-6, std::vector<double>{0.0}, std::vector<double>{std::numeric_limits<double>::infinity()});
  CHECK(s.pending() == 0);
}
