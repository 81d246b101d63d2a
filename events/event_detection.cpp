#include "events/event_detection.hpp"

#include <algorithm>
#include <optional>
#include <sstream>
#include <stdexcept>

namespace slipstrip::events {

namespace {

std::string to_string_g(double v) {
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}

void require_positive(const char* name, double value) {
  if (!(value > 0.0) || !std::isfinite(value))
    throw std::invalid_argument(std::string(name) + " = " + to_string_g(value) +
                                " is invalid: must be finite and > 0");
}

// A crossing time is NaN (level not reached) or a finite time >= 0 [s].
void require_valid_time(double t, std::size_t level, std::size_t node) {
  if (std::isnan(t) || (std::isfinite(t) && t >= 0.0)) return;
  throw std::invalid_argument("crossing_time[" + std::to_string(level) + ", " + std::to_string(node) +
                              "] = " + to_string_g(t) +
                              " is invalid: crossing times must be finite and >= 0 s (NaN = level not reached)");
}

void require_non_negative(const char* name, double value) {
  if (!(value >= 0.0) || !std::isfinite(value))
    throw std::invalid_argument(std::string(name) + " = " + to_string_g(value) +
                                " is invalid: must be finite and >= 0");
}

}  // namespace

// ---------------------------------------------------------------------------

RowMajorCrossingTimes::RowMajorCrossingTimes(std::span<const double> crossing_time,
                                             std::size_t n_levels, std::size_t n_nodes)
    : data_(crossing_time), n_levels_(n_levels), n_nodes_(n_nodes) {
  if (crossing_time.size() != n_levels * n_nodes)
    throw std::invalid_argument("crossing_time size = " + std::to_string(crossing_time.size()) +
                                " is invalid: must equal n_levels * n_nodes = " +
                                std::to_string(n_levels) + " * " + std::to_string(n_nodes));
}

void RowMajorCrossingTimes::read_rows(std::size_t j0, std::size_t j1,
                                      std::span<double> block) const {
  std::copy(data_.begin() + static_cast<std::ptrdiff_t>(j0 * n_nodes_),
            data_.begin() + static_cast<std::ptrdiff_t>(j1 * n_nodes_), block.begin());
}

// ---------------------------------------------------------------------------

NodalSlipStream::NodalSlipStream(const CrossingTimeSource& source, std::size_t block_rows)
    : source_(source),
      n_levels_(source.n_levels()),
      n_nodes_(source.n_nodes()),
      block_rows_(block_rows),
      level_(n_nodes_, -1),
      previous_time_(n_nodes_, 0.0) {
  if (block_rows_ == 0)
    throw std::invalid_argument("block_rows = 0 is invalid: must be >= 1");
  if (n_levels_ > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()) ||
      n_nodes_ > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()))
    throw std::invalid_argument("crossing_time shape [" + std::to_string(n_levels_) + ", " +
                                std::to_string(n_nodes_) + "] is invalid: each dimension must fit in int32");
  heap_.reserve(n_nodes_);
  if (n_levels_ == 0) return;
  for (std::size_t i = 0; i < n_nodes_; ++i) {
    const double t = at(0, i);
    require_valid_time(t, 0, i);
    if (std::isnan(t)) continue;  // node never reached delta_th
    level_[i] = 0;
    heap_.push_back({t, static_cast<std::int32_t>(i)});
  }
  std::make_heap(heap_.begin(), heap_.end(),
                 [](const HeapEntry& a, const HeapEntry& b) { return before(b, a); });
}

double NodalSlipStream::at(std::size_t level, std::size_t node) {
  while (level >= window_end_) load_next_block();
  const std::size_t r = level - window_begin_;
  return blocks_[r / block_rows_][(r % block_rows_) * n_nodes_ + node];
}

void NodalSlipStream::release_passed_blocks() {
  // Rows below the least-advanced active column are never needed again.
  std::size_t lowest = window_end_;
  for (std::size_t i = 0; i < n_nodes_; ++i)
    if (level_[i] >= 0) lowest = std::min(lowest, static_cast<std::size_t>(level_[i]));
  while (!blocks_.empty() && window_begin_ + block_rows_ <= lowest) {
    spare_blocks_.push_back(std::move(blocks_.front()));
    blocks_.pop_front();
    window_begin_ += block_rows_;
  }
}

void NodalSlipStream::load_next_block() {
  release_passed_blocks();
  const std::size_t j0 = window_end_;
  const std::size_t j1 = std::min(n_levels_, j0 + block_rows_);
  std::vector<double> block;
  if (!spare_blocks_.empty()) {
    block = std::move(spare_blocks_.back());
    spare_blocks_.pop_back();
  }
  block.resize(block_rows_ * n_nodes_);
  source_.read_rows(j0, j1, std::span<double>(block.data(), (j1 - j0) * n_nodes_));
  blocks_.push_back(std::move(block));
  if (blocks_.size() == 1) window_begin_ = j0;
  window_end_ = j1;
  peak_window_rows_ = std::max(peak_window_rows_, window_end_ - window_begin_);
}

void NodalSlipStream::sift_down(std::size_t pos) {
  const std::size_t n = heap_.size();
  const HeapEntry moving = heap_[pos];
  while (true) {
    std::size_t child = 2 * pos + 1;
    if (child >= n) break;
    if (child + 1 < n && before(heap_[child + 1], heap_[child])) ++child;
    if (!before(heap_[child], moving)) break;
    heap_[pos] = heap_[child];
    pos = child;
  }
  heap_[pos] = moving;
}

bool NodalSlipStream::next(NodalSlip& slip) {
  if (heap_.empty()) return false;
  const HeapEntry top = heap_.front();
  const std::size_t i = static_cast<std::size_t>(top.node);
  const std::size_t j = static_cast<std::size_t>(level_[i]);
  slip.time = top.time;
  slip.node = top.node;
  slip.level = level_[i];
  slip.duration = top.time - previous_time_[i];
  previous_time_[i] = top.time;

  // Advance column i; a NaN (or the last row) ends it.
  const double t_next = (j + 1 < n_levels_) ? at(j + 1, i) : std::numeric_limits<double>::quiet_NaN();
  require_valid_time(t_next, j + 1, i);
  if (std::isnan(t_next)) {
    level_[i] = -1;
    heap_.front() = heap_.back();
    heap_.pop_back();
  } else {
    if (t_next < top.time)
      throw std::invalid_argument(
          "crossing_time[" + std::to_string(j + 1) + ", " + std::to_string(i) + "] = " +
          to_string_g(t_next) + " is invalid: each column must be non-decreasing, but crossing_time[" +
          std::to_string(j) + ", " + std::to_string(i) + "] = " + to_string_g(top.time));
    level_[i] = static_cast<std::int32_t>(j + 1);
    heap_.front() = {t_next, top.node};
  }
  if (!heap_.empty()) sift_down(0);
  return true;
}

// ---------------------------------------------------------------------------

double waiting_time_threshold(double alpha, double delta_th, double v0, std::size_t n_nodes) {
  return alpha * delta_th / (v0 * static_cast<double>(n_nodes));
}

namespace {

// Properties of one detected (unfiltered) event.
struct EventSummary {
  double t_start, duration, x_start, extent, mean_slip, moment, max_slip_rate;
  int n_clusters;
  bool passes;
};

// Accumulates the single open event.  All per-node arrays are O(N) and are
// reset only where touched, so closing an event costs O(k log k) for k
// slipped nodes, not O(N).
class OpenEvent {
 public:
  OpenEvent(std::size_t n_nodes, const SlipSamplingInfo& info, const EventDetectionOptions& options)
      : n_nodes_(n_nodes), info_(info), options_(options), count_(n_nodes, 0), last_time_(n_nodes, 0.0) {
    touched_.reserve(n_nodes);
  }

  bool empty() const { return n_ns_ == 0; }
  double last_time() const { return t_last_; }

  void add(const NodalSlip& s) {
    const auto i = static_cast<std::size_t>(s.node);
    if (n_ns_ == 0) {
      t_first_ = s.time;
      first_node_ = i;
      min_dt_ = std::numeric_limits<double>::infinity();
    }
    if (count_[i] == 0) {
      touched_.push_back(static_cast<std::int32_t>(i));
    } else {
      // A node's later crossing inside the event: its own Delta t (the time
      // since the node's previous crossing, equal to s.time - last_time_[i]
      // unless the min_slip_rate filter dropped a crossing in between).
      min_dt_ = std::min(min_dt_, s.duration);
    }
    ++count_[i];
    last_time_[i] = s.time;
    t_last_ = s.time;
    ++n_ns_;
  }

  EventSummary close() {
    std::sort(touched_.begin(), touched_.end());
    const std::size_t k = touched_.size();
    const double dth = info_.delta_th;

    // Clusters = maximal runs of consecutive slipped nodes on the periodic
    // ring.  A run touching node N-1 continues into a run starting at node 0.
    int n_clusters = 0;
    if (k == n_nodes_) {
      n_clusters = cluster_passes(k, n_ns_) ? 1 : 0;
    } else {
      const bool wraps = touched_.front() == 0 && touched_.back() == static_cast<std::int32_t>(n_nodes_ - 1);
      // Leading run (nodes 0, 1, ...) is held back when it wraps so it can be
      // joined with the trailing run.
      std::size_t run_nodes = 0;
      std::uint64_t run_ns = 0;
      std::size_t lead_nodes = 0;
      std::uint64_t lead_ns = 0;
      bool in_lead = wraps;
      for (std::size_t r = 0; r < k; ++r) {
        const bool starts_new = r > 0 && touched_[r] != touched_[r - 1] + 1;
        if (starts_new) {
          if (in_lead) {
            lead_nodes = run_nodes;
            lead_ns = run_ns;
            in_lead = false;
          } else if (cluster_passes(run_nodes, run_ns)) {
            ++n_clusters;
          }
          run_nodes = 0;
          run_ns = 0;
        }
        ++run_nodes;
        run_ns += static_cast<std::uint64_t>(count_[static_cast<std::size_t>(touched_[r])]);
      }
      // `in_lead` still true would mean one run covers 0..N-1, i.e. k == N.
      if (cluster_passes(run_nodes + lead_nodes, run_ns + lead_ns)) ++n_clusters;
    }

    EventSummary e{};
    e.t_start = t_first_;
    e.duration = t_last_ - t_first_;
    e.x_start = info_.x[first_node_];
    e.extent = static_cast<double>(k) * info_.dx;
    e.mean_slip = dth * static_cast<double>(n_ns_) / static_cast<double>(k);
    e.moment = info_.mu * e.extent * e.mean_slip;
    e.max_slip_rate = std::isinf(min_dt_) ? std::numeric_limits<double>::quiet_NaN()
                                          : (min_dt_ > 0.0 ? dth / min_dt_
                                                           : std::numeric_limits<double>::infinity());
    e.n_clusters = n_clusters;
    e.passes = cluster_passes(k, n_ns_);

    for (const auto i : touched_) count_[static_cast<std::size_t>(i)] = 0;
    touched_.clear();
    n_ns_ = 0;
    return e;
  }

 private:
  // Same thresholds for events and clusters; compared in units of dx and
  // delta_th so that L_s = 2 dx exactly passes min_extent_dx = 2 without
  // depending on rounding.
  bool cluster_passes(std::size_t nodes, std::uint64_t ns) const {
    return static_cast<double>(nodes) >= options_.min_extent_dx &&
           static_cast<double>(ns) >= options_.min_mean_slip_dth * static_cast<double>(nodes);
  }

  std::size_t n_nodes_;
  const SlipSamplingInfo& info_;
  const EventDetectionOptions& options_;
  std::vector<std::int32_t> count_;
  std::vector<double> last_time_;
  std::vector<std::int32_t> touched_;
  std::uint64_t n_ns_ = 0;
  double t_first_ = 0.0;
  double t_last_ = 0.0;
  std::size_t first_node_ = 0;
  double min_dt_ = 0.0;
};

void append(EventCatalog& c, const EventSummary& e) {
  c.t_start.push_back(e.t_start);
  c.duration.push_back(e.duration);
  c.x_start.push_back(e.x_start);
  c.extent.push_back(e.extent);
  c.mean_slip.push_back(e.mean_slip);
  c.moment.push_back(e.moment);
  c.max_slip_rate.push_back(e.max_slip_rate);
  c.n_clusters.push_back(e.n_clusters);
}

}  // namespace

EventCatalog empty_catalog(const SlipSamplingInfo& info, const EventDetectionOptions& options, std::size_t n_nodes,
                           std::size_t threshold_nodes) {
  EventCatalog catalog;
  catalog.options = options;
  catalog.delta_th = info.delta_th;
  catalog.dx = info.dx;
  catalog.dz = info.dz;
  catalog.nodes_z = info.nodes_z;
  catalog.v0 = info.v0;
  catalog.mu = info.mu;
  catalog.n_nodes = n_nodes;
  catalog.waiting_time_threshold = waiting_time_threshold(options.alpha, info.delta_th, info.v0, threshold_nodes);
  catalog.min_extent = options.min_extent_dx * info.dx;
  catalog.min_mean_slip = options.min_mean_slip_dth * info.delta_th;
  catalog.min_slip_rate = options.min_slip_rate_v0 * info.v0;
  return catalog;
}

EventCatalog detect_events(const CrossingTimeSource& source, const SlipSamplingInfo& info,
                           const EventDetectionOptions& options) {
  if (info.nodes_z > 1) return detect_interface_2d_events(source, info, options);
  const std::size_t n = source.n_nodes();
  if (n == 0) throw std::invalid_argument("n_nodes = 0 is invalid: crossing_time must have >= 1 column");
  require_positive("delta_th", info.delta_th);
  require_positive("dx", info.dx);
  require_positive("v0", info.v0);
  require_positive("mu", info.mu);
  require_positive("alpha", options.alpha);
  require_non_negative("min_extent_dx", options.min_extent_dx);
  require_non_negative("min_mean_slip_dth", options.min_mean_slip_dth);
  require_non_negative("min_slip_rate_v0", options.min_slip_rate_v0);
  if (info.x.size() != n)
    throw std::invalid_argument("x size = " + std::to_string(info.x.size()) +
                                " is invalid: must equal the number of crossing_time columns N = " +
                                std::to_string(n));

  EventCatalog catalog = empty_catalog(info, options, n, n);

  NodalSlipStream stream(source, options.block_rows);
  OpenEvent open(n, info, options);
  // The most recent closed event is held back: only at the end of the stream
  // is it known to be the last one.
  std::optional<EventSummary> pending;

  auto close_open_event = [&]() {
    const EventSummary e = open.close();
    const std::uint64_t index = catalog.n_events_detected++;
    if (pending) {
      if (pending->passes) append(catalog, *pending);
      else ++catalog.n_events_below_thresholds;
      pending.reset();
    }
    if (index == 0 && options.exclude_first_last) {
      ++catalog.n_events_excluded_first_last;
      return;
    }
    pending = e;
  };

  NodalSlip s;
  while (stream.next(s)) {
    ++catalog.n_nodal_slips;
    if (below_min_slip_rate(s, info.delta_th, catalog.min_slip_rate)) {
      ++catalog.n_nodal_slips_below_min_slip_rate;
      continue;
    }
    if (!open.empty() && s.time - open.last_time() > catalog.waiting_time_threshold) close_open_event();
    open.add(s);
  }
  if (!open.empty()) close_open_event();
  if (pending) {
    if (options.exclude_first_last) ++catalog.n_events_excluded_first_last;
    else if (pending->passes) append(catalog, *pending);
    else ++catalog.n_events_below_thresholds;
  }
  catalog.peak_window_rows = stream.peak_window_rows();
  return catalog;
}

std::string empty_catalog_reason(const EventCatalog& c, double run_duration) {
  if (c.n_events() > 0) return "";
  std::ostringstream s;
  s.precision(3);
  s << "0 events kept (" << c.n_nodal_slips << " nodal slips";
  if (c.options.min_slip_rate_v0 > 0.0)
    s << " of which " << c.n_nodal_slips_below_min_slip_rate << " slower than min_slip_rate_v0 = "
      << c.options.min_slip_rate_v0 << " v0 ignored";
  s << ", " << c.n_events_detected << " events detected with alpha = " << c.options.alpha << "): ";
  if (c.n_nodal_slips > 0 && c.n_nodal_slips_below_min_slip_rate == c.n_nodal_slips) {
    s << "every nodal slip is slower than " << c.options.min_slip_rate_v0
      << " v0: give a smaller --min-slip-rate (0 keeps every nodal slip)";
  } else if (c.n_nodal_slips == 0) {
    s << "no node slipped by output.delta_th = " << c.delta_th << " m";
    if (run_duration > 0.0 && c.v0 > 0.0) s << " (the mean slip of the run is v0 t = " << c.v0 * run_duration << " m)";
    s << ": run longer (time.duration) or lower output.delta_th";
  } else if (c.n_events_below_thresholds == 0) {
    s << "the first and the last event are always excluded (docs/events.md) and there were no others: the run "
      << "is too short";
    if (run_duration > 0.0) s << " (" << run_duration << " s)";
    s << " or slides steadily; run longer (time.duration_transits), or give a smaller --alpha to split the "
      << "slip into more events";
    // A 2D interface whose rate-strengthening part creeps fills every gap
    // of the stream (docs/events.md "Ignoring creep").
    if (c.nodes_z > 1 && c.options.min_slip_rate_v0 == 0.0)
      s << "; if part of the interface creeps, ignore its nodal slips with --min-slip-rate";
  } else {
    s << "all " << c.n_events_below_thresholds << " events between the first and the last are below the size "
      << "thresholds (" << c.options.min_extent_dx << " dx in extent, " << c.options.min_mean_slip_dth
      << " delta_th of mean slip; docs/events.md): lower output.delta_th (now " << c.delta_th
      << " m) to resolve smaller events, or run longer";
  }
  return s.str();
}

}  // namespace slipstrip::events
