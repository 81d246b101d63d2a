#pragma once
// The self-describing HDF5 file of one run (layout and guarantees: docs/output.md).
//
// Crash safety by construction: the HDF5 file is open only while buffered
// rows are written out (flush(), a full buffer, close()).  The rest of the
// time every new row lives in memory and the file on disk is a closed,
// consistent HDF5 file, so any reader (plain h5py.File(path, "r")) can open it
// while the run goes on, and a SIGKILL loses at most the rows added since the
// last write-out.  The writer respects the shared lock an open reader holds:
// it postpones the write-out (up to reader_lock_timeout) rather than change
// the file under that reader.
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/hdf5.hpp"
#include "solver/slip_sampler.hpp"

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
  // A 2D interface (docs/3d.md) of nodes_z > 1 rows: node i is (i % nodes_x,
  // i / nodes_x), at (x[i], z[i]); dz [m] the spacing across, W [m] the width.
  int nodes_z = 1;
  double dz = 0.0, W = 0.0;
  std::vector<double> z;   // [m] size N when nodes_z > 1, else empty
};

// The run file could not be created or written (full disk, read-only or
// vanished directory, I/O error): the message names the path and the
// operating system's cause.  After it the writer is closed for good; the
// file keeps what earlier write-outs put there.
struct OutputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Wall-clock time now, ISO-8601 UTC ("2026-11-23T07:33:23Z"): the start_time
// and end_time of a run file, the written_at of a restart point.
std::string utc_now_iso8601();

// Throws std::runtime_error "No space left on device (<free> bytes free in
// '<directory>', <what> needs about <bytes_needed>)" if the file system that
// holds `path` has less free space; does nothing if it cannot tell.  Writers
// refuse before writing: HDF5 running out of space half-way leaves metadata
// pointing past the end of the file (docs/reliability.md).
void require_free_space(const std::string& path, double bytes_needed, const std::string& what);

// One per-node parameter of the interface law (e.g. friction.a at every
// node), written once when the file is created.
struct NodeParameter {
  std::string name;   // dataset name in /friction
  std::string units;  // its "units" attribute
  std::vector<double> values;
};

struct RunOutputOptions {
  // Per-node friction parameters: datasets of /friction (docs/output.md); none = no group.
  std::vector<NodeParameter> node_parameters;
  bool snapshots_by_slip = false;     // trigger attribute: "slip_increment" instead of "time"
  std::vector<double> station_x;      // [m] on-fault stations (/stations); empty = none
  // A 2D interface: the stations' z [m] (one per station_x) and their fields
  // by name and units, given to append_stations in this order; /stations/z
  // is written and moment_rate is mu * sum(v_x) dx dz [N m/s].
  std::vector<double> station_z;
  std::vector<std::pair<std::string, std::string>> station_fields;
  double front_slip_rate = 0.0;       // [m/s] /rupture_front threshold; 0 = no /rupture_front
  int timeseries_buffer_rows = 1024;  // rows held before a forced write-out; also the chunk length
  int snapshot_chunk = 8;             // snapshots held in memory before a forced write-out
  int gzip_level = 4;                 // deflate level 0..9 for the snapshot fields
  int slip_buffer_crossings = 1 << 20;  // level crossings held (24 B each) before a forced write-out
  // [s wall] how long writes are deferred while a reader holds the file open
  // (h5py's shared lock) before writing anyway; see docs/output.md.
  double reader_lock_timeout = 30.0;
  // /snapshots/normal_stress and /snapshots/opening (the gap) as a fifth and
  // sixth field, and /stations/opening as a sixth station field (in-plane
  // dissimilar bodies, whose normal stress varies and whose faces may open;
  // otherwise the normal stress is loading.normal_stress and the gap 0).
  bool normal_stress_snapshots = false;
  // /timeseries/loading_shear_stress [Pa] as a fifth time series: the uniform
  // shear stress tau_0(t) of loading.drive = "mean_slip_rate".
  bool loading_shear_stress = false;
  // A 2D interface (SlipSamplingSetup.nodes_z > 1): the snapshot fields by
  // name and units, each stored as [snapshots, nodes_z, nodes_x] (one chunk
  // per snapshot), given to write_snapshot in this order; the root attribute
  // `format` is "slipstrip interface_2d", the node positions along each axis
  // are /grid/x and /grid/z, and the XDMF sidecar is a temporal collection of
  // (z, x) grids (io/xdmf.hpp).
  std::vector<std::pair<std::string, std::string>> interface_2d_fields;
  // > 0: the root attribute `processes`, the MPI processes the run was split
  // over (slipstrip-mpi run); 0: not written (a run in one process).
  int processes = 0;
};

// Where the run file's records stand after a complete write-out: what a
// restart point stores (solver/checkpoint.hpp) so that a resumed run can cut the
// file back to exactly this point, whatever was written after it.
struct RunOutputCursor {
  std::uint64_t timeseries_rows = 0;
  std::uint64_t snapshots = 0;
  std::uint64_t station_rows = 0;
  std::uint64_t crossing_rows = 0;            // rows of crossing_time = highest level reached + 1
  bool slip_recorded = false;                 // record_slip has checked the initial slip
  std::vector<std::uint64_t> levels_reached;  // per node (slip sampling; empty when off)
  std::vector<double> next_threshold;         // per node [m]
  std::vector<double> rupture_front;          // per node [s] (empty without /rupture_front)
};

class RunOutput {
 public:
  // Creates (truncates) `path`, writes the root attributes (status "running")
  // and the empty groups, then closes the file again.
  RunOutput(const std::string& path, const std::string& config_toml,
            const SlipSamplingSetup& slip_sampling, RunOutputOptions options = {});
  // Resumes writing an existing run file from a restart point: every record
  // is cut back to `cursor` (rows appended after it are removed, crossing
  // times recorded after it are reset to the NaN fill, the rupture front is
  // rewritten), status is set back to "running".  `slip_sampling` and
  // `options` must be those of the run (same config).  A file that does not
  // fit the cursor (missing datasets, fewer rows) throws std::invalid_argument.
  RunOutput(const std::string& path, const RunOutputCursor& cursor,
            const SlipSamplingSetup& slip_sampling, RunOutputOptions options = {});
  RunOutput(const RunOutput&) = delete;
  RunOutput& operator=(const RunOutput&) = delete;
  // Closes with status "interrupted" if close() was never called (e.g. the
  // solver is unwinding from an exception).  Never throws.
  ~RunOutput();

  void append_timeseries(double time, double max_slip_rate, double mean_slip,
                         double mean_shear_stress);
  // The same with /timeseries/loading_shear_stress [Pa]: exactly when
  // RunOutputOptions::loading_shear_stress (the other form throws std::logic_error then).
  void append_timeseries(double time, double max_slip_rate, double mean_slip, double mean_shear_stress,
                         double loading_shear_stress);
  // normal_stress and opening: given exactly when RunOutputOptions::normal_stress_snapshots.
  void write_snapshot(double time, std::span<const double> slip, std::span<const double> slip_rate,
                      std::span<const double> state, std::span<const double> shear_stress,
                      std::span<const double> normal_stress = {}, std::span<const double> opening = {});
  // Any snapshot: one span of N values per field, in the file's field order
  // (the one above, or RunOutputOptions::interface_2d_fields).
  void write_snapshot(double time, std::span<const std::span<const double>> fields);
  // One row of every station's fields (values at the stations, in the order
  // of station_x) and the global max slip rate [m/s] and moment rate
  // [N/s per m: mu * sum(v) dx].  Only with stations.
  void append_stations(double time, std::span<const double> slip, std::span<const double> slip_rate,
                       std::span<const double> shear_stress, std::span<const double> state,
                       double normal_stress, double max_slip_rate, double moment_rate);
  // The same with the normal stress and the opening at each station (in-plane
  // dissimilar bodies: only with RunOutputOptions::normal_stress_snapshots).
  void append_stations(double time, std::span<const double> slip, std::span<const double> slip_rate,
                       std::span<const double> shear_stress, std::span<const double> state,
                       std::span<const double> normal_stress, std::span<const double> opening,
                       double max_slip_rate, double moment_rate);
  // Any station row: one span of (at least) one value per station for each
  // field, in the file's station field order (the five or six above, or
  // RunOutputOptions::station_fields).
  void append_stations(double time, std::span<const std::span<const double>> fields, double max_slip_rate,
                       double moment_rate);
  // The per-node rupture-front arrival times [s] (NaN = not yet), written whole
  // at every write-out.  Only with front_slip_rate > 0.
  void set_rupture_front(std::span<const double> arrival_time);
  // Called once per time step with the slip before and after the step
  // (slip sampling, solver/slip_sampler.hpp).
  void record_slip(double t_old, double t_new, std::span<const double> slip_old,
                   std::span<const double> slip_new);
  // Instead of record_slip, for a run split over processes whose samplers
  // run on each process's nodes: the level crossings they found in a step,
  // (level, node) pairs in this file's node numbering and their times
  // (SlipSampler::add_found).
  void record_crossings(std::span<const hsize_t> coordinates, std::span<const double> times);

  // Writes every buffered row and closes the file again.  Returns false if
  // the write was deferred because a reader holds the file open (the rows stay
  // buffered for the next flush).
  bool flush();
  // Writes every buffered row and returns the cursors of what the file now
  // holds (for a restart point).  force = false behaves like flush() (nothing
  // if a reader holds the file: returns no cursor); force = true writes anyway,
  // as close() does.
  std::optional<RunOutputCursor> flush_for_checkpoint(bool force);
  // status: "completed", "interrupted" or "diverged: <diagnostic>".  Flushes,
  // records status and end_time.  A second call is a no-op.
  void close(const std::string& status);

  bool is_closed() const { return closed_; }
  std::size_t node_count() const { return node_count_; }
  // Level crossings recorded but not yet written: all the slip-sampling data
  // held in memory (<= slip_buffer_crossings), however far apart the nodes' slips are.
  std::size_t buffered_crossings() const { return slip_sampler_ ? slip_sampler_->pending() : 0; }
  // Highest slip level any node has reached + 1 (= rows of crossing_time after a write-out).
  std::size_t slip_levels_reached() const { return slip_sampler_ ? slip_sampler_->levels_max() : 0; }
  // Write-outs postponed so far because a reader held the file.
  std::size_t deferred_writes() const { return deferred_writes_; }

 private:
  enum class WriteTrigger { buffer_full, flush, forced, close };
  void initialise_buffers(const SlipSamplingSetup& slip_sampling);
  void reopen_file(const RunOutputCursor& cursor);
  // Opens, appends every buffer (and at close the final status), closes.
  // Returns false if deferred because a reader holds the file.
  // Rewrites RUN.xdmf (io/xdmf.hpp) when the file holds more snapshots than it describes.
  void update_xdmf_sidecar();
  bool write_out(WriteTrigger trigger, const std::string* final_status = nullptr);
  bool write_out_unchecked(WriteTrigger trigger, const std::string* final_status);
  // Throws if the file system of the run file has less free space than the
  // next write-out needs (with a margin for HDF5 metadata).
  void check_free_space() const;
  void create_file(const std::string& config_toml, const SlipSamplingSetup& slip_sampling);
  io::Handle open_unless_reader_holds(WriteTrigger trigger);

  std::string path_;
  std::size_t node_count_ = 0;
  RunOutputOptions options_;
  bool closed_ = false;
  bool failed_ = false;  // a write-out failed: no further attempt (OutputError)
  std::optional<std::chrono::steady_clock::time_point> reader_holds_since_;
  std::size_t deferred_writes_ = 0;

  // Rows written to the file so far.
  std::size_t timeseries_rows_in_file_ = 0;
  std::size_t snapshots_in_file_ = 0;
  std::size_t snapshots_in_sidecar_ = 0;  // rows the XDMF sidecar (RUN.xdmf) describes
  std::vector<double> snapshot_times_;    // a 2D interface: the times of the snapshots in the file (its sidecar lists them)
  std::size_t crossing_rows_in_file_ = 0;

  // Buffered rows, row-major.
  std::vector<double> timeseries_buffer_;  // timeseries_columns_ values per row
  std::size_t timeseries_columns_ = 4;     // 5 with loading_shear_stress
  std::vector<double> snapshot_time_buffer_;
  std::vector<std::string> snapshot_names_, snapshot_units_;  // the fields, in order
  std::size_t snapshot_fields_ = 4;              // 6 with normal_stress_snapshots
  int nodes_x_ = 0, nodes_z_ = 1;                // nodes_z_ > 1: a 2D interface
  std::vector<double> snapshot_field_buffer_;  // fields x N per snapshot, field-major per snapshot
  // Stations: per row, time, max slip rate, moment rate, then fields x
  // stations (a line: 5, 6 with normal_stress_snapshots: the opening).
  std::size_t station_count_ = 0;
  std::vector<std::string> station_names_, station_units_;  // the fields, in order
  std::vector<double> station_uniform_;                      // a uniform normal stress per station
  std::size_t station_rows_in_file_ = 0;
  std::vector<double> station_buffer_;
  std::vector<double> rupture_front_;  // per node; written whole at each write-out
  bool rupture_front_dirty_ = false;

  // Slip sampling; none when delta_th = 0.
  std::optional<SlipSampler> slip_sampler_;
};

}  // namespace slipstrip
