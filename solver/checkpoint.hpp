#pragma once
// Restart points of a run (docs/output.md "Restart point", docs/reliability.md).
//
// A restart point is a sidecar HDF5 file RUN.h5.restart next to the run file:
// the simulation state after a step (fields and history operator), the
// cursors of every record of RUN.h5 (rows, slip-sampling levels, rupture
// front) and the run loop's next output times.  It is written to
// RUN.h5.restart.tmp, synced, and renamed over the previous one, so a kill at
// any moment leaves either the previous or the new restart point, never a
// half-written one; the run file's records up to the cursors are synced
// before the rename, so a restart point never points past the data on disk.
#include <string>

#include "solver/run_output.hpp"
#include "solver/simulation.hpp"

namespace slipstrip {

struct RunCheckpoint {
  std::string config_toml;  // the run's resolved config (= the run file's `config` attribute)
  std::string git_hash;     // of the binary that wrote it
  SimulationState simulation;
  RunOutputCursor output;
  // The run loop's next output triggers (solver/run.cpp): time [s] of the next
  // time-series row, snapshot and station row, mean slip [m] of the next
  // slip-triggered snapshot.
  double next_timeseries = 0.0, next_snapshot = 0.0, next_snapshot_slip = 0.0, next_station = 0.0;
  // read_checkpoint: false if the restart point carries no checksum (written
  // before restart points had one); it is then resumed with a warning.
  bool checksum_verified = false;
};

// RUN.h5 -> RUN.h5.restart
std::string checkpoint_path(const std::string& run_path);

// A restart point of a 2D interface split over P processes (slipstrip-mpi
// run, parallel/distributed_run.hpp) is in the one-process layout, its
// history operator state included (regrouped by Fourier mode), and is resumed
// on any number of processes.  Earlier versions wrote each process's history
// operator state as its own: the history kind below, the counter
// `processes` = P, and process r's state (kind "interface 2d", over its own
// Fourier modes, with the counters first_row and rows of its slab) under the
// prefix "rank<r>.".  Such a restart point is resumed on P processes only.
inline constexpr const char* kSplitHistoryKind = "interface 2d split over processes";
// P for a restart point in an earlier version's per-process layout of a run
// split over P processes, 0 for one in the one-process layout.
int restart_point_processes(const RunCheckpoint& checkpoint);

// RUN.h5 -> RUN.h5.lock: the lock file of "one process per run"
// (io/file_lock.hpp), held by whoever writes the run file or its restart
// point (a run, a resume, `slipstrip events` into the run file).
std::string run_lock_path(const std::string& run_path);

// The checksum of every value a resume reads ("crc64-xz:<16 hex digits>",
// io/checksum.hpp), in a fixed order (history counters and arrays by name).
// Stored as the root attribute `checksum`; not covered: the informational
// attributes code_version and written_at.
std::string checkpoint_checksum(const RunCheckpoint& checkpoint);

// Syncs the run file, then writes the restart point atomically (temporary
// file, fsync, rename, fsync of the directory).  Throws OutputError naming
// the path and the cause (the previous restart point stays valid).
void write_checkpoint(const std::string& run_path, const RunCheckpoint& checkpoint);

// Reads RUN.h5.restart.  A missing, damaged or foreign file throws
// std::invalid_argument naming the path and what is wrong: what is in its
// place if it is not a regular file (a directory, a device, a dangling
// link), and "damaged" if its content does not match its checksum.
RunCheckpoint read_checkpoint(const std::string& run_path);

// Refuses (std::invalid_argument naming the restart point, the field, its
// value and what it should be) a restart point whose time, step or next
// output times are not finite or not consistent with each other, with its
// record counts and with `config` run at `time_step` for `total_steps`
// steps.  A checksum finds damage after writing; this finds values that were
// never a state of this run (an edited restart point, or one without a
// checksum).
void validate_checkpoint(const RunCheckpoint& checkpoint, const SimulationConfig& config, double time_step,
                         long long total_steps, const std::string& run_path);

// What a resume needs to know of the run file itself: its root attributes
// `status` and `config` (docs/output.md).  A missing or unreadable file, or
// one without these attributes, throws std::invalid_argument naming the path.
struct RunFileHeader {
  std::string status;
  std::string config_toml;
};
RunFileHeader read_run_file_header(const std::string& run_path);

// Removes RUN.h5.restart (and a leftover .tmp), e.g. once the run completed.
void remove_checkpoint(const std::string& run_path);

}  // namespace slipstrip
