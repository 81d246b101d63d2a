#include "solver/slip_sampler.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

namespace slipstrip {

SlipSampler::SlipSampler(double delta_th, std::size_t nodes)
    : delta_th_(delta_th), levels_reached_(nodes, 0), next_threshold_(nodes, delta_th) {
  pending_coords_.reserve(2 * 4096);
  pending_time_.reserve(4096);
}

bool SlipSampler::record(double t_old, double t_new, std::span<const double> slip_old,
                         std::span<const double> slip_new) {
  const std::size_t nodes = levels_reached_.size();
  bool crossed = false;
  if (!started_) {
    // Levels the initial slip already passed count as reached at t_old.
    for (std::size_t i = 0; i < nodes; ++i)
      if (slip_old[i] >= next_threshold_[i]) {
        add_crossings(i, t_old, t_old, slip_old[i], slip_old[i]);
        crossed = true;
      }
    started_ = true;
  }
  for (std::size_t i = 0; i < nodes; ++i) {
    if (slip_new[i] >= next_threshold_[i]) {
      add_crossings(i, t_old, t_new, slip_old[i], slip_new[i]);
      crossed = true;
    }
  }
  return crossed;
}

void SlipSampler::add_crossings(std::size_t node, double t_old, double t_new, double slip_old,
                                double slip_new) {
  // +inf would mean infinitely many levels; divergence is the solver's to report.
  if (!std::isfinite(slip_new)) return;
  const double slip_step = slip_new - slip_old;
  // A physical step crosses a handful of levels (v dt / delta_th ~ 10 at
  // 1 m/s).  Millions mean the solution is blowing up while still finite;
  // recording them would exhaust memory before the non-finite check fires.
  const double levels_in_step = (slip_new - next_threshold_[node]) / delta_th_;
  if (levels_in_step > kMaxLevelsPerStep) {
    std::ostringstream msg;
    msg << "slip at node " << node << " jumped from " << slip_old << " m to " << slip_new
        << " m between t = " << t_old << " s and " << t_new << " s (" << levels_in_step
        << " levels of delta_th = " << delta_th_ << " m in one step): the run is diverging";
    throw SlipSamplingOverflow(msg.str());
  }
  while (slip_new >= next_threshold_[node]) {
    const std::size_t level = levels_reached_[node];
    const double threshold = next_threshold_[node];
    // Slip is taken linear inside the step.  A threshold at or below slip_old
    // (only possible if the caller's slip_old is not the previous slip_new)
    // is dated at the start of the step.
    const double fraction =
        slip_step > 0.0 ? std::clamp((threshold - slip_old) / slip_step, 0.0, 1.0) : 0.0;
    pending_coords_.push_back(level);
    pending_coords_.push_back(node);
    pending_time_.push_back(t_old + fraction * (t_new - t_old));
    levels_reached_[node] = level + 1;
    levels_max_ = std::max(levels_max_, level + 1);
    next_threshold_[node] = static_cast<double>(level + 2) * delta_th_;
  }
}

void SlipSampler::add_found(std::span<const hsize_t> coordinates, std::span<const double> times) {
  if (coordinates.size() != 2 * times.size())
    throw std::invalid_argument("SlipSampler::add_found: " + std::to_string(coordinates.size()) +
                                " coordinates for " + std::to_string(times.size()) + " crossings");
  for (std::size_t c = 0; c < times.size(); ++c) {
    const std::size_t level = coordinates[2 * c], node = coordinates[2 * c + 1];
    if (node >= levels_reached_.size() || level != levels_reached_[node])
      throw std::invalid_argument("SlipSampler::add_found: crossing of level " + std::to_string(level) +
                                  " at node " + std::to_string(node) + " is not that node's next level");
    pending_coords_.push_back(level);
    pending_coords_.push_back(node);
    pending_time_.push_back(times[c]);
    levels_reached_[node] = level + 1;
    levels_max_ = std::max(levels_max_, level + 1);
    next_threshold_[node] = static_cast<double>(level + 2) * delta_th_;
  }
  // The samplers that found them have checked the initial slip.
  started_ = true;
}

void SlipSampler::clear_pending() {
  pending_coords_.clear();
  pending_time_.clear();
}

void SlipSampler::restore(std::size_t levels_max, bool started, std::span<const std::uint64_t> levels_reached,
                          std::span<const double> next_threshold) {
  levels_max_ = levels_max;
  started_ = started;
  std::copy(levels_reached.begin(), levels_reached.end(), levels_reached_.begin());
  next_threshold_.assign(next_threshold.begin(), next_threshold.end());
}

}  // namespace slipstrip
