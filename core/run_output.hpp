#pragma once
// The self-describing HDF5 file of one run (layout and guarantees: docs/output.md).
//
// Crash safety by construction: the HDF5 file is open only inside flush().
// Between flushes every new row lives in memory and the file on disk is a
// closed, consistent HDF5 file, so any reader (plain h5py.File(path, "r"))
// can open it while the run goes on, and a SIGKILL loses at most the rows
// added since the last flush.
#include <cstddef>
#include <deque>
#include <span>
#include <string>
#include <vector>

namespace slipstrip {

// Parameters of the slip-sampling record: the time node i's cumulative slip
// first reaches (j+1)*delta_th, for every level j.  The scalars are stored as
// attributes so the record is interpretable without the config.
struct SlipSamplingSetup {
  double delta_th = 1e-8;  // [m] slip level spacing; 0 = slip sampling off
  double dx = 0.0;         // [m] node spacing
  double v0 = 0.0;         // [m/s] driving velocity
  double mu = 0.0;         // [Pa] shear modulus
  double D = 0.0;          // [m] characteristic slip
  double L = 0.0;          // [m] period length
  std::vector<double> x;   // [m] node positions; x.size() is the node count N
};

struct RunOutputOptions {
  bool snapshots_by_slip = false;     // trigger attribute: "slip_increment" instead of "time"
  int timeseries_buffer_rows = 1024;  // rows held before a forced write-out; also the chunk length
  int snapshot_chunk = 8;             // snapshots held in memory before a forced write-out
  int gzip_level = 4;                 // deflate level 0..9 for the snapshot fields
  int slip_buffer_rows = 256;         // completed slip-sampling rows held before a forced write-out
};

class RunOutput {
 public:
  // Creates (truncates) `path`, writes the root attributes (status "running")
  // and the empty groups, then closes the file again.
  RunOutput(const std::string& path, const std::string& config_toml,
            const SlipSamplingSetup& slip_sampling, RunOutputOptions options = {});
  RunOutput(const RunOutput&) = delete;
  RunOutput& operator=(const RunOutput&) = delete;
  // Closes with status "interrupted" if close() was never called (e.g. the
  // solver is unwinding from an exception).  Never throws.
  ~RunOutput();

  void append_timeseries(double time, double max_slip_rate, double mean_slip,
                         double mean_shear_stress);
  void write_snapshot(double time, std::span<const double> slip, std::span<const double> slip_rate,
                      std::span<const double> state, std::span<const double> shear_stress);
  // Called once per time step with the slip before and after the step.
  void record_slip(double t_old, double t_new, std::span<const double> slip_old,
                   std::span<const double> slip_new);

  // Writes every buffered row and closes the file again.
  void flush();
  // status: "completed", "interrupted" or "diverged: <diagnostic>".  Flushes,
  // records status and end_time.  A second call is a no-op.
  void close(const std::string& status);

  bool is_closed() const { return closed_; }
  std::size_t node_count() const { return node_count_; }
  // Slip-sampling rows currently held in memory (completed-but-unwritten plus
  // the partially filled band): the memory bound of the incremental writer.
  std::size_t buffered_slip_rows() const { return band_.size(); }
  // Highest slip level any node has reached + 1 (= rows of crossing_time after a flush).
  std::size_t slip_levels_reached() const { return band_base_ + band_.size(); }

 private:
  void write_out();  // opens, appends every buffer, closes
  void add_crossings(std::size_t node, double t_old, double t_new, double slip_old, double slip_new);

  std::string path_;
  std::size_t node_count_ = 0;
  RunOutputOptions options_;
  bool slip_sampling_on_ = false;
  bool closed_ = false;

  // Rows written to the file so far.
  std::size_t timeseries_rows_in_file_ = 0;
  std::size_t snapshots_in_file_ = 0;

  // Buffered rows, row-major.
  std::vector<double> timeseries_buffer_;  // 4 values per row
  std::vector<double> snapshot_time_buffer_;
  std::vector<double> snapshot_field_buffer_;  // 4 fields x N per snapshot, field-major per snapshot

  // Slip sampling.  levels_reached_[i] = number of levels node i has reached;
  // next_threshold_[i] = (levels_reached_[i] + 1) * delta_th, precomputed so the
  // common no-crossing step is a single comparison per node.
  double delta_th_ = 0.0;
  bool slip_recorded_ = false;  // record_slip has been called (initial slip checked)
  std::vector<std::size_t> levels_reached_;
  std::vector<double> next_threshold_;
  // Rows band_base_ .. band_base_ + band_.size() - 1 of crossing_time, NaN where
  // not reached.  Rows below band_base_ are complete and in the file for good;
  // the lowest level not yet reached by every node is >= band_base_.
  std::size_t band_base_ = 0;
  std::deque<std::vector<double>> band_;
  std::vector<std::vector<double>> spare_rows_;  // recycled rows: no allocation in steady state
};

}  // namespace slipstrip
