#pragma once
// Drive one Simulation to the end of its duration, writing the HDF5 run file.
#include <array>
#include <functional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "config/simulation_config.hpp"
#include "io/file_lock.hpp"
#include "solver/run_output.hpp"

namespace slipstrip {

struct RunProgress {
  double time;            // simulated time [s]
  double duration;        // target [s]
  long long step;
  double max_slip_rate;   // [m/s]
  double wall_seconds;    // since the start of the time loop
};

struct RunHooks {
  // Called about every progress_interval seconds of wall time.
  std::function<void(const RunProgress&)> progress;
  double progress_interval = 0.5;
  // Polled every step; true stops the run cleanly ("interrupted") after
  // writing a restart point.
  std::function<bool()> stop_requested;
  // >= 0: stop as stop_requested does once this many steps (counted from
  // t = 0) are done.  A deterministic interruption for tests (`slipstrip run
  // --stop-after-steps`).
  long long stop_after_steps = -1;
  // Called with a one-line warning that does not stop the run (a restart
  // point written before restart points carried a checksum).
  std::function<void(const std::string&)> warning;
};

struct RunResult {
  std::string status;  // "completed", "interrupted" or "diverged: ..."
  double simulated_time = 0.0;
  long long steps = 0;
  double wall_seconds = 0.0;
  double time_step = 0.0;
  long long resumed_from_step = -1;  // resume_simulation: the restart point's step
  std::string restart_point;         // path of the restart point left behind ("" if none)
};

// The next mean-slip level at which a snapshot is taken after one was taken at
// mean slip `mean_slip` with the previous trigger `next`: the smallest
// next + m increment above mean_slip, and always > mean_slip, so a tiny
// increment gives at most one snapshot per step and never loops forever.
double next_slip_trigger(double next, double mean_slip, double increment);

// Runs `config` and writes `output_path`.  hooks.stop_requested is also polled
// during the set-up of the history operator; a stop there throws
// SetupCancelled (kernels/history_convolution.hpp) before the file is created.  A divergence (non-finite field,
// failed local solve) ends the run with status "diverged: <diagnostic>" and a
// readable file; it is reported in the result, not thrown.
//
// Restart points (solver/checkpoint.hpp): every output.checkpoint_interval
// seconds of wall time (0: never on a timer) and whenever stop_requested
// stops the run, the run file is flushed and RUN.h5.restart written.  A run
// that completes or diverges removes it.
//
// One process per run: the lock RUN.h5.lock (run_lock_path, io/file_lock.hpp)
// is held from before the set-up to the end; if another process holds it,
// io::LockHeldError (a std::invalid_argument) is thrown and nothing is
// touched.  Under the lock, RUN.h5 and RUN.h5.restart are checked again
// (io/output_paths.hpp): without `overwrite` neither may exist; with it, an
// old restart point is removed, so it is never taken for this run's.
// geometry.nodes_z > 1 (a 2D interface, solver/simulation_3d.hpp, docs/3d.md)
// runs in the same loop, with the same lock, restart points and records
// (except stations); its file layout is in docs/3d.md.
RunResult run_simulation(const SimulationConfig& config, const std::string& output_path,
                         const RunHooks& hooks = {}, bool overwrite = false);

// Continues the run of `output_path` (a line or a 2D interface) from its restart point, appending to the
// same file, with the config stored in it; the result is bitwise the file an
// uninterrupted run writes (docs/reliability.md).  Throws std::invalid_argument
// if there is no usable restart point, or it does not belong to this file
// (other config), or the run is not resumable (status "completed" or
// "diverged: ...").  The restart point is checked against its checksum and
// field by field (validate_checkpoint) before anything is written; one
// without a checksum is resumed after hooks.warning.  The set-up polls
// hooks.stop_requested as run_simulation's, and the run's lock is held as
// there.
RunResult resume_simulation(const std::string& output_path, const RunHooks& hooks = {});

// The run's lock (one process per run, as above), for a caller that must read
// the run file before resuming it: the CLI compares a given config with the
// stored one.  Reading first and locking after would race a writer that holds
// the file open (HDF5 refuses the read with "Resource temporarily
// unavailable" instead of the lock's clear "in use by another process").
io::FileLock lock_run_file(const std::string& output_path);

// resume_simulation under a lock the caller already holds (lock_run_file of
// the same `output_path`; another lock is a std::logic_error).
RunResult resume_simulation(const std::string& output_path, const RunHooks& hooks, const io::FileLock& held);

// The records of a 2D interface (geometry.nodes_z > 1, docs/3d.md) as
// run_simulation writes them, for a writer that gathers the fields of a run
// split over processes (parallel/distributed_run.hpp): the slip sampling's
// setup over the whole interface (node i at (i % nodes_x, i / nodes_x)), the
// writer's options (variable_normal_stress: dissimilar in-plane bodies, whose
// normal stress and opening are two more fields), and the snapshot fields by
// name and units in the file's order.
SlipSamplingSetup interface_2d_sampling(const SimulationConfig& config);
RunOutputOptions interface_2d_output_options(const SimulationConfig& config, bool variable_normal_stress);
std::vector<std::pair<std::string, std::string>> interface_2d_field_units(bool variable_normal_stress);

class Simulation3d;
// The snapshot and station fields of a 2D interface, in the file's order (the
// seven of interface_2d_field_units, and the normal stress and opening for
// dissimilar bodies): this process's nodes of each.
struct Interface2dFields {
  std::array<std::span<const double>, 9> spans;
  std::size_t count;
  std::size_t size() const { return count; }
  std::span<const double> operator[](std::size_t f) const { return spans[f]; }
  operator std::span<const std::span<const double>>() const { return {spans.data(), count}; }
};
Interface2dFields interface_2d_fields(const Simulation3d& sim);

}  // namespace slipstrip
