#pragma once
// Slip sampling (docs/output.md, /slip_sampling): for every node, the time
// its cumulative slip first reaches each level (j+1) delta_th, j = 0, 1, ...
// The sampler keeps each node's progress and the crossings found since they
// were last written; RunOutput writes them into crossing_time[level, node].
#include <cstddef>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <vector>

#include "io/hdf5.hpp"

namespace slipstrip {

// record() saw a slip increment of more than kMaxLevelsPerStep levels in one
// step at one node: the solution is diverging (while still finite).
struct SlipSamplingOverflow : std::runtime_error {
  using std::runtime_error::runtime_error;
};
inline constexpr double kMaxLevelsPerStep = 1e6;

class SlipSampler {
 public:
  // delta_th > 0 [m], nodes >= 1 (RunOutput checks both).
  SlipSampler(double delta_th, std::size_t nodes);

  // One time step, slip before and after it at every node: each level a
  // node's slip reaches is dated by taking the slip linear inside the step.
  // The first call also records the levels the initial slip already passed,
  // dated t_old.  Returns true if any crossing was added.  Throws
  // SlipSamplingOverflow when a node jumps more than kMaxLevelsPerStep levels.
  // The common case (no node reaches its next level) is one comparison per node.
  bool record(double t_old, double t_new, std::span<const double> slip_old,
              std::span<const double> slip_new);

  // Crossings found by other samplers (a run split over processes samples each
  // process's nodes there, parallel/distributed_run.hpp): (level, node) pairs
  // in this sampler's node numbering and their times, each the next level of
  // its node in order, as record() would have found them.  Throws
  // std::invalid_argument for a node out of range or a level that is not its
  // node's next one.
  void add_found(std::span<const hsize_t> coordinates, std::span<const double> times);

  // Crossings since the last clear_pending(): (level, node) pairs, and their times [s].
  std::span<const hsize_t> pending_coordinates() const { return pending_coords_; }
  std::span<const double> pending_times() const { return pending_time_; }
  std::size_t pending() const { return pending_time_.size(); }
  void clear_pending();

  // Highest level any node has reached + 1 (the rows crossing_time needs).
  std::size_t levels_max() const { return levels_max_; }

  // The progress a restart point stores, and its restoration (the sizes are
  // checked by the caller).  Pending crossings are not part of it: a restart
  // point is taken right after a write-out.
  bool started() const { return started_; }
  std::span<const std::size_t> levels_reached() const { return levels_reached_; }
  std::span<const double> next_threshold() const { return next_threshold_; }
  void restore(std::size_t levels_max, bool started, std::span<const std::uint64_t> levels_reached,
               std::span<const double> next_threshold);

 private:
  void add_crossings(std::size_t node, double t_old, double t_new, double slip_old, double slip_new);

  double delta_th_;
  bool started_ = false;  // record() has been called (initial slip checked)
  // levels_reached_[i] = number of levels node i has reached; next_threshold_[i]
  // = (levels_reached_[i] + 1) * delta_th, precomputed so the common
  // no-crossing step is a single comparison per node.
  std::vector<std::size_t> levels_reached_;
  std::vector<double> next_threshold_;
  // Crossings since the last write-out, written as individual elements of
  // crossing_time (whose fill value is NaN): pending_coords_ holds (level,
  // node) pairs, pending_time_ the times.  Not rows: a locked node lagging a
  // creeping one by 1e5 levels would otherwise pin 1e5 rows x N in memory.
  std::vector<hsize_t> pending_coords_;
  std::vector<double> pending_time_;
  std::size_t levels_max_ = 0;
};

}  // namespace slipstrip
