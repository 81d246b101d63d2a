#pragma once
// Slip-event identification from slip-sampled data (paper supplement,
// "The identification of slip events").  The solver records, for every node i
// and level j, the time crossing_time[j, i] at which the cumulative slip of
// node i first reached (j+1) delta_th.  Every finite entry is one nodal slip
// (NS).  All NS are visited in time order with a k-way merge over the N
// columns (each column is already sorted), grouped into slip events by the
// global waiting time between successive NS, and reduced on the fly to one
// row of an EventCatalog per event.  See docs/events.md.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <limits>
#include <span>
#include <string>
#include <vector>

namespace slipstrip::events {

// ---------------------------------------------------------------------------
// Input: where crossing_time comes from.
// ---------------------------------------------------------------------------

// Delivers crossing_time in row blocks so that a caller may stream rows from
// disk: the detector never needs the whole [n_levels, N] matrix at once.
class CrossingTimeSource {
 public:
  virtual ~CrossingTimeSource() = default;
  virtual std::size_t n_levels() const = 0;
  virtual std::size_t n_nodes() const = 0;
  // Copies rows [j0, j1) into `block`, row-major: block[(j - j0) * N + i].
  // `block.size()` is exactly (j1 - j0) * N.  NaN means "level not reached".
  virtual void read_rows(std::size_t j0, std::size_t j1, std::span<double> block) const = 0;
};

// A row-major [n_levels, n_nodes] array held in memory (not owned).
class RowMajorCrossingTimes final : public CrossingTimeSource {
 public:
  RowMajorCrossingTimes(std::span<const double> crossing_time, std::size_t n_levels,
                        std::size_t n_nodes);
  std::size_t n_levels() const override { return n_levels_; }
  std::size_t n_nodes() const override { return n_nodes_; }
  void read_rows(std::size_t j0, std::size_t j1, std::span<double> block) const override;

 private:
  std::span<const double> data_;
  std::size_t n_levels_;
  std::size_t n_nodes_;
};

// Any matrix type with rows(), cols() and operator()(j, i) (e.g. an
// Eigen::MatrixXd of shape [n_levels, N]); kept as a template so this header
// does not depend on Eigen.  The matrix is referenced, not copied.
template <class Matrix>
class MatrixCrossingTimes final : public CrossingTimeSource {
 public:
  explicit MatrixCrossingTimes(const Matrix& crossing_time) : m_(crossing_time) {}
  std::size_t n_levels() const override { return static_cast<std::size_t>(m_.rows()); }
  std::size_t n_nodes() const override { return static_cast<std::size_t>(m_.cols()); }
  void read_rows(std::size_t j0, std::size_t j1, std::span<double> block) const override {
    const std::size_t n = n_nodes();
    for (std::size_t j = j0; j < j1; ++j)
      for (std::size_t i = 0; i < n; ++i)
        block[(j - j0) * n + i] = static_cast<double>(m_(static_cast<long>(j), static_cast<long>(i)));
  }

 private:
  const Matrix& m_;
};

// The scalar metadata stored next to crossing_time (group /slip_sampling).
struct SlipSamplingInfo {
  double delta_th = 1e-8;  // slip threshold [m]
  double dx = 0.0;         // node spacing [m]
  double v0 = 0.0;         // driving velocity [m/s]
  double mu = 0.0;         // shear modulus [Pa]
  double D = std::numeric_limits<double>::quiet_NaN();  // characteristic slip [m] (informative)
  double L = std::numeric_limits<double>::quiet_NaN();  // interface length [m] (informative)
  std::vector<double> x;   // node positions [m], size N
  // A 2D interface (docs/3d.md): nodes_z > 1 rows of N / nodes_z nodes, node
  // i at (i % nodes_x, i / nodes_x) and at (x[i], z[i]); dz the spacing
  // across and W the width (period along z) [m].  nodes_z = 1: a line.
  int nodes_z = 1;
  double dz = 0.0;
  double W = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> z;   // node positions across [m], size N when nodes_z > 1
};

// ---------------------------------------------------------------------------
// Nodal slips in time order.
// ---------------------------------------------------------------------------

struct NodalSlip {
  double time = 0.0;      // crossing_time[level, node] [s]
  double duration = 0.0;  // Delta t(x, delta): time since the node's previous crossing [s]
                          // (level 0: measured from t = 0, the start of the run)
  std::int32_t node = 0;
  std::int32_t level = 0;  // slip reached (level + 1) * delta_th
};

// K-way merge of the N sorted columns.  Memory: a heap of N entries plus a
// window of row blocks spanning from the least-advanced still-active column
// to the most-advanced one (see docs/events.md).  Ties in time are emitted in
// increasing node order (then level) so the output is deterministic.
class NodalSlipStream {
 public:
  NodalSlipStream(const CrossingTimeSource& source, std::size_t block_rows = 256);
  // Writes the next NS into `slip`; returns false when all NS were emitted.
  // Throws std::invalid_argument if a column decreases in time.
  bool next(NodalSlip& slip);
  // Largest number of crossing_time rows held in memory so far.
  std::size_t peak_window_rows() const { return peak_window_rows_; }

 private:
  struct HeapEntry {
    double time;
    std::int32_t node;
  };
  double at(std::size_t level, std::size_t node);
  void load_next_block();
  void release_passed_blocks();
  void sift_down(std::size_t pos);
  static bool before(const HeapEntry& a, const HeapEntry& b) {
    return a.time < b.time || (a.time == b.time && a.node < b.node);
  }

  const CrossingTimeSource& source_;
  std::size_t n_levels_;
  std::size_t n_nodes_;
  std::size_t block_rows_;
  std::deque<std::vector<double>> blocks_;  // rows [window_begin_, window_end_)
  std::vector<std::vector<double>> spare_blocks_;  // recycled, so loading does not allocate
  std::size_t window_begin_ = 0;
  std::size_t window_end_ = 0;
  std::size_t peak_window_rows_ = 0;
  std::vector<HeapEntry> heap_;
  std::vector<std::int32_t> level_;  // level of the column's entry in the heap; -1 = finished
  std::vector<double> previous_time_;
};

// ---------------------------------------------------------------------------
// Event detection.
// ---------------------------------------------------------------------------

struct EventDetectionOptions {
  // Waiting-time threshold alpha * delta_th / (v0 N); a new event starts when
  // the time between two successive NS anywhere on the interface exceeds it.
  double alpha = 15.0;
  // Events (and clusters) with L_s < min_extent_dx * dx are removed.
  double min_extent_dx = 2.0;
  // Events (and clusters) with mean slip < min_mean_slip_dth * delta_th are removed.
  double min_mean_slip_dth = 2.0;
  // The first event (triggered by the initial state) and the last one
  // (possibly cut by the end of the run) are excluded.
  bool exclude_first_last = true;
  // Nodal slips slower than min_slip_rate_v0 * v0 (rate delta_th / Delta t,
  // Delta t the time since the node's previous crossing) are ignored before
  // the grouping: creep then leaves gaps in the stream instead of filling
  // them.  0 (the default) keeps every nodal slip, and the catalog is bit for
  // bit the unfiltered one.  The waiting-time threshold is the same with and
  // without the filter (docs/events.md "Ignoring creep").
  double min_slip_rate_v0 = 0.0;
  // Rows of crossing_time read per block from the source.
  std::size_t block_rows = 256;
};

struct EventCatalog {
  // One entry per kept event, in time order.
  std::vector<double> t_start;        // time of the first NS [s]
  std::vector<double> duration;       // T = t(last NS) - t(first NS) [s]
  std::vector<double> x_start;        // position of the first NS (nucleation) [m]
  std::vector<double> extent;         // L_s = (distinct slipped nodes) * dx [m]
  std::vector<double> mean_slip;      // u_mean = delta_th * n_NS / (distinct slipped nodes) [m]
  std::vector<double> moment;         // M0 = mu L_s u_mean [N/m] (per unit thickness)
  std::vector<double> max_slip_rate;  // delta_th / min Delta t of the event's nodal slips (each node's
                                      // first one in the event excepted) [m/s]
  std::vector<int> n_clusters;        // connected slipped patches kept by the filters [1]
  // A 2D interface (nodes_z > 1, docs/3d.md) only, else empty: each event is
  // one connected patch of nodes in (x, z); extent is the patch's extent along
  // x (distinct columns * dx), moment mu * area * mean_slip [N m], n_clusters 1.
  std::vector<double> z_start;        // hypocentre z (x_start, z_start: the first NS) [m]
  std::vector<double> extent_z;       // distinct rows * dz [m]
  std::vector<double> area;           // slipped nodes * dx dz [m^2]

  // What produced it.
  EventDetectionOptions options;
  double delta_th = 0.0;                // [m]
  double dx = 0.0;                      // [m]
  double v0 = 0.0;                      // [m/s]
  double mu = 0.0;                      // [Pa]
  std::size_t n_nodes = 0;              // all nodes (nodes_x * nodes_z on a 2D interface)
  int nodes_z = 1;                      // > 1: a 2D interface
  double dz = 0.0;                      // [m] (2D interface)
  double waiting_time_threshold = 0.0;  // alpha delta_th / (v0 N) [s]; N = nodes_x on a 2D interface
  double min_extent = 0.0;              // min_extent_dx * dx [m]
  double min_mean_slip = 0.0;           // min_mean_slip_dth * delta_th [m]
  double min_slip_rate = 0.0;           // min_slip_rate_v0 * v0 [m/s]; 0: every nodal slip counts

  // Counts.
  std::uint64_t n_nodal_slips = 0;                  // all of them, the ignored ones included
  std::uint64_t n_nodal_slips_below_min_slip_rate = 0;  // ignored: slower than min_slip_rate
  std::uint64_t n_events_detected = 0;             // before any exclusion
  std::uint64_t n_events_excluded_first_last = 0;  // 0, 1 or 2
  std::uint64_t n_events_below_thresholds = 0;     // removed by the size filters
  std::size_t n_events() const { return t_start.size(); }
  std::size_t peak_window_rows = 0;                // memory diagnostic of the merge
};

// alpha * delta_th / (v0 * n_nodes) [s]
double waiting_time_threshold(double alpha, double delta_th, double v0, std::size_t n_nodes);

// True if the nodal slip's rate delta_th / s.duration is below min_slip_rate
// [m/s]; never when min_slip_rate = 0 (s.duration is finite), so the filter
// off changes nothing.  A slip at exactly min_slip_rate is kept.
inline bool below_min_slip_rate(const NodalSlip& s, double delta_th, double min_slip_rate) {
  return delta_th < min_slip_rate * s.duration;
}

// A catalog without events: the options, the scales of `info` and the
// thresholds, for n_nodes nodes of which threshold_nodes set the waiting time
// (all of them on a line, one row on a 2D interface).
EventCatalog empty_catalog(const SlipSamplingInfo& info, const EventDetectionOptions& options, std::size_t n_nodes,
                           std::size_t threshold_nodes);

// Streams `source` once and returns the filtered catalog.  A 2D interface
// (info.nodes_z > 1) is detect_interface_2d_events.
// Throws std::invalid_argument on inconsistent metadata or options.
EventCatalog detect_events(const CrossingTimeSource& source, const SlipSamplingInfo& info,
                           const EventDetectionOptions& options = {});

// Slip events on a 2D interface (docs/3d.md, docs/events.md "2D interface"):
// the nodal slips are grouped in time as on a line, with the waiting-time
// threshold of one row, alpha delta_th / (v0 nodes_x) (a front spanning the
// width gives each row the NS of a line); within each time group, every
// connected set of slipped nodes in (x, z) (4 neighbours, periodic in both)
// is one event: patches that slip at overlapping times but do not touch are
// separate events.  Per event: t_start and the hypocentre (x_start, z_start)
// of its first NS, duration, area, mean slip, moment = mu area mean_slip,
// extents along x and z, max slip rate.  An event passes the filters if it
// spans >= min_extent_dx columns and >= min_extent_dx rows and its mean slip
// is >= min_mean_slip_dth delta_th; the events of the first and of the last
// time group are excluded (exclude_first_last).  A record uniform in z gives
// the line's catalog for events of one connected cluster, with area =
// extent * W and moment = line moment * W.
EventCatalog detect_interface_2d_events(const CrossingTimeSource& source, const SlipSamplingInfo& info,
                                        const EventDetectionOptions& options = {});

// Why `catalog` keeps no event and what to change, as one line from its
// counts (docs/events.md): no nodal slip at all (delta_th above the slip of
// the run), nothing but the first and the last event (always excluded), or
// every other event below the size filters.  run_duration [s] is the
// simulated time, quoted when known (> 0).  Empty if the catalog keeps events.
// `slipstrip events` and `analyze` both report it.
std::string empty_catalog_reason(const EventCatalog& catalog, double run_duration = 0.0);

}  // namespace slipstrip::events
