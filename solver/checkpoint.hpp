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
};

// RUN.h5 -> RUN.h5.restart
std::string checkpoint_path(const std::string& run_path);

// Syncs the run file, then writes the restart point atomically (temporary
// file, fsync, rename, fsync of the directory).  Throws OutputError naming
// the path and the cause (the previous restart point stays valid).
void write_checkpoint(const std::string& run_path, const RunCheckpoint& checkpoint);

// Reads RUN.h5.restart.  A missing, damaged or foreign file throws
// std::invalid_argument naming the path and what is wrong.
RunCheckpoint read_checkpoint(const std::string& run_path);

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
