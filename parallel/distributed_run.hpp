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
//   * stopping: one reduction per step carries rank 0's stop request (SIGTERM,
//     --stop-after-steps), whether any process diverged and whether any has
//     crossings to pass, so every process leaves the time loop in the same step.
// Restart points are not written on several processes (each process's history
// state is its own Fourier modes'), so a config that asks for them
// (output.checkpoint_interval > 0) is refused, as are stations.
#include <mpi.h>

#include <stdexcept>
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

// Throws CollectiveError (on every process, origin 0) naming the key of what a
// run split over processes does not do: a line (geometry.nodes_z = 1),
// stations, restart points.
void check_distributed_run(const SimulationConfig& config);

// Runs `config` split over `comm` and writes `output_path` on rank 0.
// Collective.  Before the set-up, rank 0 takes the run's lock and checks the
// output paths as run_simulation does (overwrite: an old restart point of this
// name is removed); a refusal is a CollectiveError on every process.
// hooks.stop_requested and hooks.progress are used on rank 0 only;
// stop_after_steps on every process.  A stop requested during the set-up
// throws SetupCancelled on every process before the file is created.  A stop
// in the time loop closes the file with status "interrupted" (no restart
// point).  A divergence on any process ends the run on all with status
// "diverged: <the lowest such rank's diagnostic>".  Other errors (a file that
// cannot be written) are thrown on the process that met them only: the caller
// must end the job (MPI_Abort).  The result is the same on every process.
RunResult run_distributed(const SimulationConfig& config, const std::string& output_path, const RunHooks& hooks,
                          bool overwrite, MPI_Comm comm);

}  // namespace slipstrip
