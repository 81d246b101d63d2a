#pragma once
// A run of a 2D interface (Simulation3d, docs/3d.md) split over the processes
// of an MPI communicator (distributed_spectral_step), writing the same run file
// as run_simulation (solver/run.hpp): rank 0 holds the run's lock and writes
// the file with the serial writer (RunOutput); the other processes send it
// what it records.
//   * snapshots: each field gathered on rank 0 (gather_rows);
//   * time series: the reductions over the interface (every process takes
//     part, rank 0 appends the row);
//   * slip sampling and rupture front: each process dates the crossings of its
//     own nodes and passes them to rank 0 in the step they happen;
//   * stations: each process interpolates along x in the stations' rows it
//     holds, rank 0 gathers these row terms and combines each station's two
//     along z (a station between rows of two processes is taken as on one
//     process); the moment rate's sum runs through the processes in row
//     order, as one process adds;
//   * stopping: one reduction per step carries rank 0's stop request (SIGTERM,
//     --stop-after-steps), whether any process diverged and whether any has
//     crossings to pass, so every process leaves the time loop in the same step.
//   * restart points (RUN.h5.restart, solver/checkpoint.hpp): rank 0's
//     wall-clock timer (output.checkpoint_interval) and its stop request ride
//     on that reduction, so every process takes part in the same step; the
//     fields are gathered into the one-process layout, each process sends
//     its history operator state by Fourier mode (its modes' records,
//     InterfaceHistory2d::save_mode_records), which rank 0 merges into the
//     one-process operator's state, and rank 0 writes the one file with
//     run_simulation's writer (temporary file, fsync, rename).  So the
//     restart point is run_simulation's: resumed on any number of processes
//     (resume_distributed cuts the state by mode for each process) or by
//     `slipstrip run --resume`, and a restart point of `slipstrip run` on
//     several processes.  It carries the station trigger (next_station) as
//     run_simulation's does.  A restart point of an earlier version's
//     per-process layout (kSplitHistoryKind) is resumed on as many processes.
#include <mpi.h>

#include <optional>
#include <stdexcept>
#include <span>
#include <string>

#include "config/simulation_config.hpp"
#include "solver/run.hpp"

namespace slipstrip {

// An error found on one process and passed to all (the lock or an output
// path on rank 0, a config the distributed run refuses): every process throws
// it, so the job ends without MPI_Abort.  origin_rank names where it was found.
struct CollectiveError : std::invalid_argument {
  CollectiveError(const std::string& message, int origin_rank)
      : std::invalid_argument(message), origin_rank(origin_rank) {}
  int origin_rank;
};

// An error met by some processes (`error` non-empty there) thrown on every
// process as a CollectiveError carrying the lowest such rank's message,
// prefixed by `context`.  Collective: every process calls it, failed or not.
void throw_if_any_failed(const std::string& error, const std::string& context, MPI_Comm comm);

// Throws CollectiveError (on every process, origin 0) naming the key of what a
// run split over processes does not do: a line (geometry.nodes_z = 1).
void check_distributed_run(const SimulationConfig& config);

// Runs `config` split over `comm` and writes `output_path` on rank 0.
// Collective.  Before the set-up, rank 0 checks the output paths as
// `slipstrip run` does (io::check_output_paths: the run file and its restart
// point are outputs, `inputs`, the config file, never one of them, even with
// overwrite) and takes the run's lock (overwrite: an old restart point of
// this name is removed); a refusal is a CollectiveError on every process.
// hooks.stop_requested, hooks.progress and hooks.warning are used on rank 0
// only (the stop_after_steps count is read there too, and the stop is passed
// to every process in the step's control reduction).  A stop requested during the
// set-up throws SetupCancelled on every process before the file is created.
// A stop in the time loop writes a restart point and closes the file with
// status "interrupted"; restart points are also written every
// output.checkpoint_interval s of rank 0's wall time.  A divergence on any
// process ends the run on all with status "diverged: <the lowest such rank's
// diagnostic>"; a run that completes or diverges removes its restart point.
// Other errors (a file that cannot be written) are thrown on the process that
// met them only: the caller must end the job (MPI_Abort).  The result's
// status and restart point are the same on every process; its step count and
// simulated time are rank 0's there (a process that diverged stopped a step
// short), its wall time each process's own.
RunResult run_distributed(const SimulationConfig& config, const std::string& output_path, const RunHooks& hooks,
                          bool overwrite, std::span<const std::string> inputs, MPI_Comm comm);

// Continues the run of `run_path` from its restart point, written on any
// number of processes or by run_simulation, with the config stored in the run
// file; the file is the one an uninterrupted run on these processes writes,
// bit for bit where the uninterrupted runs on the writing and the resuming
// process counts agree (docs/3d.md section 6).  Collective.  Rank 0 takes
// the run's lock and makes resume_simulation's checks (status, checksum, the
// restart point's config against the run file's, validate_checkpoint, and
// given_config_toml, if not empty, against the stored config), and that a
// restart point of an earlier version's per-process layout was written on
// this many processes; the stored history state is cut by Fourier mode for
// the processes (a state that does not fit their operators is refused).  A
// refusal is a CollectiveError on every process.  nullopt (on every process)
// if the run is completed.  The rest is as run_distributed.
std::optional<RunResult> resume_distributed(const std::string& run_path, const std::string& given_config_toml,
                                            const RunHooks& hooks, MPI_Comm comm);

}  // namespace slipstrip
