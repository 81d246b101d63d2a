// SlipSampler on its own (RunOutput's file round trips are in
// test_solver_run_output.cpp).  The slips and times below are binary
// fractions, so every crossing time of the linear interpolation is exact and
// compared with ==.
#include <doctest/doctest.h>

#include <cstdint>
#include <limits>
#include <stdexcept>
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

TEST_CASE("crossings found by samplers of parts of the nodes, added to a whole one, are the whole one's") {
  // Nodes 0-1 sampled by one part, node 2 by another (a run split over
  // processes, parallel/distributed_run.hpp), their crossings renumbered and
  // added to a sampler of all three: its pending crossings, levels and next
  // thresholds are those of a sampler that recorded all three itself.
  SlipSampler whole(0.25, 3), first(0.25, 2), second(0.25, 1), gathered(0.25, 3);
  const std::vector<double> before = {0.0, 0.0, 0.0}, after = {1.0, 0.125, 0.5};
  whole.record(2.0, 4.0, before, after);
  first.record(2.0, 4.0, std::vector<double>{0.0, 0.0}, std::vector<double>{1.0, 0.125});
  second.record(2.0, 4.0, std::vector<double>{0.0}, std::vector<double>{0.5});
  gathered.add_found(first.pending_coordinates(), first.pending_times());
  std::vector<hsize_t> renumbered(second.pending_coordinates().begin(), second.pending_coordinates().end());
  for (std::size_t c = 1; c < renumbered.size(); c += 2) renumbered[c] += 2;
  gathered.add_found(renumbered, second.pending_times());
  CHECK(pending(gathered) == pending(whole));
  CHECK(gathered.levels_max() == whole.levels_max());
  CHECK(std::vector<std::size_t>(gathered.levels_reached().begin(), gathered.levels_reached().end()) ==
        std::vector<std::size_t>(whole.levels_reached().begin(), whole.levels_reached().end()));
  CHECK(std::vector<double>(gathered.next_threshold().begin(), gathered.next_threshold().end()) ==
        std::vector<double>(whole.next_threshold().begin(), whole.next_threshold().end()));
  CHECK(gathered.started());
  // A level that is not its node's next one, a node out of range, and a
  // count mismatch are refused.
  const std::vector<double> one_time = {5.0};
  CHECK_THROWS_AS(gathered.add_found(std::vector<hsize_t>{1, 2}, one_time), std::invalid_argument);
  CHECK_THROWS_AS(gathered.add_found(std::vector<hsize_t>{0, 3}, one_time), std::invalid_argument);
  CHECK_THROWS_AS(gathered.add_found(std::vector<hsize_t>{0}, one_time), std::invalid_argument);
}
