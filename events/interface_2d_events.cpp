// Slip events on a 2D interface (event_detection.hpp, detect_interface_2d_events;
// docs/events.md "A 2D interface").
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "events/event_detection.hpp"

namespace slipstrip::events {

namespace {

// One connected patch of one time group.
struct PatchSummary {
  double t_start, duration;
  std::size_t hypocentre;  // node of the first NS
  std::size_t nodes, columns, rows;
  std::uint64_t n_ns;
  double min_dt;           // shortest time between successive crossings of one node inside the group
};

// The nodal slips of the open time group, per node (arrays of all nodes,
// reset only where touched), split into connected patches when it closes.
class OpenGroup {
 public:
  OpenGroup(std::size_t nodes_x, std::size_t nodes_z)
      : nx_(nodes_x), nz_(nodes_z), count_(nodes_x * nodes_z, 0), first_time_(count_.size(), 0.0),
        last_time_(count_.size(), 0.0), first_order_(count_.size(), 0),
        min_dt_(count_.size(), std::numeric_limits<double>::infinity()), patch_(count_.size(), -1),
        column_mark_(nodes_x, -1), row_mark_(nodes_z, -1) {}

  bool empty() const { return touched_.empty(); }
  double last_time() const { return t_last_; }

  void add(const NodalSlip& s) {
    const auto i = static_cast<std::size_t>(s.node);
    if (count_[i] == 0) {
      touched_.push_back(i);
      first_time_[i] = s.time;
      first_order_[i] = order_++;
    } else {
      // The crossing's own Delta t (s.time - last_time_[i] unless the
      // min_slip_rate filter dropped a crossing of the node in between).
      min_dt_[i] = std::min(min_dt_[i], s.duration);
    }
    ++count_[i];
    last_time_[i] = s.time;
    t_last_ = s.time;
  }

  // The group's patches (4 neighbours, periodic in x and z), in order of
  // their first NS; the group is empty afterwards.
  std::vector<PatchSummary> close() {
    std::vector<PatchSummary> patches;
    std::vector<std::size_t> stack;
    for (const std::size_t seed : touched_) {
      if (patch_[seed] >= 0) continue;
      const auto id = static_cast<std::int64_t>(patches.size());
      PatchSummary p{first_time_[seed], 0.0, seed, 0, 0, 0, 0, std::numeric_limits<double>::infinity()};
      double t_end = last_time_[seed];
      patch_[seed] = id;
      stack.assign(1, seed);
      while (!stack.empty()) {
        const std::size_t i = stack.back();
        stack.pop_back();
        ++p.nodes;
        p.n_ns += count_[i];
        p.min_dt = std::min(p.min_dt, min_dt_[i]);
        t_end = std::max(t_end, last_time_[i]);
        // The first NS of the patch in stream order (time, then node): its hypocentre.
        if (first_order_[i] < first_order_[p.hypocentre]) p.hypocentre = i;
        const std::size_t ix = i % nx_, iz = i / nx_;
        if (column_mark_[ix] != id) column_mark_[ix] = id, ++p.columns;
        if (row_mark_[iz] != id) row_mark_[iz] = id, ++p.rows;
        const std::size_t neighbours[4] = {iz * nx_ + (ix + 1) % nx_, iz * nx_ + (ix + nx_ - 1) % nx_,
                                           ((iz + 1) % nz_) * nx_ + ix, ((iz + nz_ - 1) % nz_) * nx_ + ix};
        for (const std::size_t j : neighbours)
          if (count_[j] > 0 && patch_[j] < 0) {
            patch_[j] = id;
            stack.push_back(j);
          }
      }
      p.t_start = first_time_[p.hypocentre];
      p.duration = t_end - p.t_start;
      patches.push_back(p);
    }
    std::sort(patches.begin(), patches.end(), [&](const PatchSummary& a, const PatchSummary& b) {
      return first_order_[a.hypocentre] < first_order_[b.hypocentre];
    });
    for (const std::size_t i : touched_) {
      count_[i] = 0;
      patch_[i] = -1;
      min_dt_[i] = std::numeric_limits<double>::infinity();
    }
    std::fill(column_mark_.begin(), column_mark_.end(), -1);
    std::fill(row_mark_.begin(), row_mark_.end(), -1);
    touched_.clear();
    return patches;
  }

 private:
  std::size_t nx_, nz_;
  std::vector<std::uint32_t> count_;  // NS of the node in the group
  std::vector<double> first_time_, last_time_;
  std::vector<std::uint64_t> first_order_;  // stream position of the node's first NS in the group
  std::vector<double> min_dt_;
  std::vector<std::int64_t> patch_;   // patch id while closing; -1 otherwise
  std::vector<std::int64_t> column_mark_, row_mark_;
  std::vector<std::size_t> touched_;
  std::uint64_t order_ = 0;
  double t_last_ = 0.0;
};

std::string to_string_g(double v) {
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}

void require_positive_value(const char* name, double value) {
  if (!(value > 0.0) || !std::isfinite(value))
    throw std::invalid_argument(std::string(name) + " = " + std::to_string(value) +
                                " is invalid: must be finite and > 0");
}

}  // namespace

EventCatalog detect_interface_2d_events(const CrossingTimeSource& source, const SlipSamplingInfo& info,
                                        const EventDetectionOptions& options) {
  const std::size_t n = source.n_nodes();
  if (info.nodes_z < 1 || n == 0 || n % static_cast<std::size_t>(info.nodes_z) != 0)
    throw std::invalid_argument("nodes_z = " + std::to_string(info.nodes_z) +
                                " is invalid: must be >= 1 and divide the number of crossing_time columns N = " +
                                std::to_string(n));
  const auto nz = static_cast<std::size_t>(info.nodes_z), nx = n / nz;
  for (const auto& [name, value] : {std::pair{"delta_th", info.delta_th}, {"dx", info.dx}, {"dz", info.dz},
                                    {"v0", info.v0}, {"mu", info.mu}, {"alpha", options.alpha}})
    require_positive_value(name, value);
  if (!(options.min_slip_rate_v0 >= 0.0) || !std::isfinite(options.min_slip_rate_v0))
    throw std::invalid_argument("min_slip_rate_v0 = " + to_string_g(options.min_slip_rate_v0) +
                                " is invalid: must be finite and >= 0 (0 keeps every nodal slip)");
  if (!(options.min_extent_dx >= 0.0) || !(options.min_mean_slip_dth >= 0.0))
    throw std::invalid_argument("min_extent_dx, min_mean_slip_dth = " + std::to_string(options.min_extent_dx) +
                                ", " + std::to_string(options.min_mean_slip_dth) + " are invalid: must be >= 0");
  if (info.x.size() != n || info.z.size() != n)
    throw std::invalid_argument("x, z sizes = " + std::to_string(info.x.size()) + ", " +
                                std::to_string(info.z.size()) +
                                " are invalid: must equal the number of crossing_time columns N = " + std::to_string(n));

  // The threshold of one row: a group ends when no node slipped for alpha
  // times the time a row takes to slip delta_th at v0 node by node.
  EventCatalog catalog = empty_catalog(info, options, n, nx);

  const double dth = info.delta_th, cell = info.dx * info.dz;
  const auto passes = [&](const PatchSummary& p) {
    return static_cast<double>(p.columns) >= options.min_extent_dx &&
           static_cast<double>(p.rows) >= options.min_extent_dx &&
           static_cast<double>(p.n_ns) >= options.min_mean_slip_dth * static_cast<double>(p.nodes);
  };
  const auto append_patch = [&](const PatchSummary& p) {
    catalog.t_start.push_back(p.t_start);
    catalog.duration.push_back(p.duration);
    catalog.x_start.push_back(info.x[p.hypocentre]);
    catalog.z_start.push_back(info.z[p.hypocentre]);
    catalog.extent.push_back(static_cast<double>(p.columns) * info.dx);
    catalog.extent_z.push_back(static_cast<double>(p.rows) * info.dz);
    catalog.area.push_back(static_cast<double>(p.nodes) * cell);
    const double mean_slip = dth * static_cast<double>(p.n_ns) / static_cast<double>(p.nodes);
    catalog.mean_slip.push_back(mean_slip);
    catalog.moment.push_back(info.mu * static_cast<double>(p.nodes) * cell * mean_slip);
    catalog.max_slip_rate.push_back(std::isinf(p.min_dt) ? std::numeric_limits<double>::quiet_NaN()
                                    : p.min_dt > 0.0     ? dth / p.min_dt
                                                         : std::numeric_limits<double>::infinity());
    catalog.n_clusters.push_back(1);
  };

  NodalSlipStream stream(source, options.block_rows);
  OpenGroup open(nx, nz);
  std::uint64_t groups = 0;
  // The most recent group's patches are held back: only at the end of the
  // stream is it known to be the last group.
  std::optional<std::vector<PatchSummary>> pending;
  const auto keep_or_filter = [&](const std::vector<PatchSummary>& patches) {
    for (const auto& p : patches)
      if (passes(p)) append_patch(p);
      else ++catalog.n_events_below_thresholds;
  };
  const auto close_group = [&] {
    std::vector<PatchSummary> patches = open.close();
    catalog.n_events_detected += patches.size();
    if (pending) keep_or_filter(*pending);
    pending.reset();
    if (groups++ == 0 && options.exclude_first_last) {
      catalog.n_events_excluded_first_last += patches.size();
      return;
    }
    pending = std::move(patches);
  };
  NodalSlip s;
  while (stream.next(s)) {
    ++catalog.n_nodal_slips;
    // Creep ignored (min_slip_rate_v0 > 0): the waiting time then measures
    // the gaps between the fast nodal slips only.
    if (below_min_slip_rate(s, dth, catalog.min_slip_rate)) {
      ++catalog.n_nodal_slips_below_min_slip_rate;
      continue;
    }
    if (!open.empty() && s.time - open.last_time() > catalog.waiting_time_threshold) close_group();
    open.add(s);
  }
  if (!open.empty()) close_group();
  if (pending) {
    if (options.exclude_first_last) catalog.n_events_excluded_first_last += pending->size();
    else keep_or_filter(*pending);
  }
  catalog.peak_window_rows = stream.peak_window_rows();
  return catalog;
}

}  // namespace slipstrip::events
