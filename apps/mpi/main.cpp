// slipstrip-mpi: a 2D interface (geometry.nodes_z > 1) split over the
// processes of an MPI job (parallel/, docs/3d.md "Across machines").
//
//   mpirun -np 4 slipstrip-mpi run CONFIG.toml [--out RUN.h5] [--set key=value ...]
//
// runs CONFIG and writes the run file `slipstrip run` writes (rank 0 writes
// it, parallel/distributed_run.hpp), with the root attribute `processes`, and
// its restart points RUN.h5.restart (every output.checkpoint_interval s, and
// when SIGTERM or --stop-after-steps stops it).
//
//   mpirun -np 4 slipstrip-mpi run --resume RUN.h5 [CONFIG [--set ...]]
//
// continues it from its restart point on as many processes as wrote it (a
// config given is only checked against the stored one).  Stations are
// refused.
//
//   mpirun -np 4 slipstrip-mpi bench CONFIG.toml [--steps N] [--set key=value ...]
//
// times the distributed time step of CONFIG's interface: set-up, wall and CPU
// time per step, and the parts (the step's distributed FFTs with their
// transposes: four, five for dissimilar bodies; this process's history
// operator alone), with the rows, Fourier modes and FFT message bytes per process.  An error found on every process
// (the run's lock or output path on rank 0, a refused config key) prints
// "rank R: message" once and ends every process with exit code 2; any other
// error on any process prints "rank R: message" and aborts the whole job
// (MPI_Abort), so no process waits forever in a collective call another one
// has left.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <complex>
#include <cstdio>
#include <ctime>
#include <exception>
#include <optional>
#include <string>
#include <vector>

#include <unistd.h>

#include "apps/cli.hpp"
#include "config/config.hpp"
#include "config/resource_estimate.hpp"
#include "kernels/history_convolution.hpp"
#include "parallel/distributed_fft.hpp"
#include "parallel/distributed_interface.hpp"
#include "parallel/distributed_run.hpp"
#include "parallel/mpi_session.hpp"
#include "slipstrip/version.hpp"
#include "solver/simulation_3d.hpp"

namespace {

using namespace slipstrip;

double process_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

// Largest and summed value over the processes (on every process).
struct Spread {
  double max, sum;
};
Spread spread(double local, MPI_Comm comm) {
  Spread s{local, local};
  MPI_Allreduce(MPI_IN_PLACE, &s.max, 1, MPI_DOUBLE, MPI_MAX, comm);
  MPI_Allreduce(MPI_IN_PLACE, &s.sum, 1, MPI_DOUBLE, MPI_SUM, comm);
  return s;
}

int bench(const std::string& config_path, const std::vector<std::string>& overrides, int steps) {
  const MPI_Comm world = MPI_COMM_WORLD;
  const int rank = mpi_rank(world), processes = mpi_size(world);
  const SimulationConfig config = load_config_file(config_path, overrides);
  if (config.geometry.nodes_z < 2)
    throw std::invalid_argument("geometry.nodes_z = " + std::to_string(config.geometry.nodes_z) +
                                ": slipstrip-mpi runs a 2D interface only (nodes_z > 1); a line runs with "
                                "`slipstrip run` on one process");
  MPI_Barrier(world);
  const double t_setup = MPI_Wtime();
  Simulation3d sim(config, {}, {}, distributed_spectral_step(world));
  const Spread setup = spread(MPI_Wtime() - t_setup, world);

  // The whole step.
  MPI_Barrier(world);
  double t0 = MPI_Wtime(), cpu0 = process_cpu_seconds();
  for (int s = 0; s < steps; ++s) sim.step();
  const Spread wall = spread((MPI_Wtime() - t0) / steps, world);
  const Spread cpu = spread((process_cpu_seconds() - cpu0) / steps, world);

  // The distributed FFTs of a step (with their transposes), alone: the slip
  // rate's two components and the history's, and for dissimilar bodies the
  // normal stress's inverse and the opening stress's forward transform (the
  // latter only in steps where some node opens: not counted).
  const int transforms = sim.variable_normal_stress() ? 5 : 4;
  DistributedRealFft2d fft(config.geometry.nodes, config.geometry.nodes_z, world);
  std::vector<double> field(sim.slip_rate_x().begin(), sim.slip_rate_x().end()), back(field.size());
  std::vector<std::complex<double>> spectrum(fft.local_modes());
  MPI_Barrier(world);
  t0 = MPI_Wtime();
  cpu0 = process_cpu_seconds();
  for (int s = 0; s < steps; ++s)
    for (int t = 0; t < transforms; ++t) {
      if (t < 2) fft.forward(field, spectrum);
      else fft.inverse(spectrum, back);
    }
  const Spread fft_wall = spread((MPI_Wtime() - t0) / steps, world);
  const Spread fft_cpu = spread((process_cpu_seconds() - cpu0) / steps, world);

  // This process's history operator alone (pushing its current spectra again
  // changes the run's history: timing only, after the run).
  auto& history = sim.history_operator_for_timing();
  std::vector<std::complex<double>> sx(history.history_x().begin(), history.history_x().end());
  std::vector<std::complex<double>> sz(history.history_z().begin(), history.history_z().end());
  t0 = MPI_Wtime();
  cpu0 = process_cpu_seconds();
  for (int s = 0; s < steps; ++s) history.push(sx, sz);
  const Spread operator_wall = spread((MPI_Wtime() - t0) / steps, world);
  const Spread operator_cpu = spread((process_cpu_seconds() - cpu0) / steps, world);

  // Bytes one process sends per step in the FFTs' transposes: each transform
  // moves its share of the nodes_z x (nodes_x/2 + 1) complex array, all but
  // the part it keeps.
  const double complex_bytes = 16.0 * config.geometry.nodes_z * (config.geometry.nodes / 2 + 1);
  const double sent = transforms * complex_bytes / processes * (processes - 1) / processes;
  const Spread modes = spread(static_cast<double>(history.modes()), world);
  const Spread oscillators = spread(static_cast<double>(history.stats().oscillators), world);
  if (rank == 0) {
    std::printf("processes %d, interface %d x %d nodes, %d steps\n", processes, config.geometry.nodes,
                config.geometry.nodes_z, steps);
    std::printf("rows per process: %d (rank 0); Fourier modes per process: max %.0f of %.0f; normal modes in "
                "flight: max %.0f of %.0f\n",
                sim.slab().rows, modes.max, modes.sum, oscillators.max, oscillators.sum);
    std::printf("set-up wall: %.3f s (slowest process)\n", setup.max);
    std::printf("step: wall %.1f us (slowest process), CPU %.1f us (slowest), %.1f us (all processes)\n",
                1e6 * wall.max, 1e6 * cpu.max, 1e6 * cpu.sum);
    std::printf("parts (slowest process): %d distributed FFTs wall %.1f us, CPU %.1f us; history operator wall "
                "%.1f us, CPU %.1f us\n",
                transforms, 1e6 * fft_wall.max, 1e6 * fft_cpu.max, 1e6 * operator_wall.max, 1e6 * operator_cpu.max);
    std::printf("FFT transposes: %.0f bytes sent per process per step (%d all-to-alls of %.0f bytes each)\n",
                sent, transforms, sent / transforms);
  }
  return 0;
}

struct RunArguments {
  std::string config_path, out_path, resume_path;
  std::vector<std::string> overrides;
  bool quiet = false, overwrite = false;
  long long stop_after_steps = -1;
  ResourceLimits limits;  // max_operator_gib per process
};

// The last lines of a run or a resumed run (rank 0) and the exit code (every process).
int report(const RunResult& result, const std::string& out_path, int processes, bool quiet, bool tty) {
  if (mpi_rank(MPI_COMM_WORLD) == 0) {
    if (!quiet && tty) std::fprintf(stderr, "\n");
    std::fprintf(stderr,
                 "%s after %lld steps (dt = %.6g s), simulated %.6g s in %.2f s wall on %d process%s; output %s\n",
                 result.status.c_str(), result.steps, result.time_step, result.simulated_time, result.wall_seconds,
                 processes, processes == 1 ? "" : "es", out_path.c_str());
    if (!result.restart_point.empty())
      std::fprintf(stderr, "restart point %s: continue with `mpirun -np %d slipstrip-mpi run --resume %s`\n",
                   result.restart_point.c_str(), processes, out_path.c_str());
  }
  if (result.status == "completed") return 0;
  if (result.status == "interrupted") return cli::signal_exit_code();
  return 3;  // diverged
}

// `slipstrip-mpi run --resume RUN.h5 [CONFIG [--set ...]]`, as `slipstrip run
// --resume`: the run continues with the config stored in RUN.h5; a config
// given as well is only checked.
int resume(const RunArguments& a) {
  const MPI_Comm world = MPI_COMM_WORLD;
  const int rank = mpi_rank(world), processes = mpi_size(world);
  if (!a.out_path.empty() || a.overwrite)
    throw CollectiveError("--resume '" + a.resume_path +
                              "' continues writing that file: --out and --overwrite do not apply",
                          0);
  std::string given, config_error;
  if (!a.config_path.empty()) {
    try {
      given = to_toml(load_config_file(a.config_path, a.overrides));
    } catch (const std::invalid_argument& e) {
      config_error = e.what();  // agreed on below: one process may fail alone
    }
    throw_if_any_failed(config_error, "", world);
  } else if (!a.overrides.empty()) {
    throw CollectiveError("--resume '" + a.resume_path +
                              "' with --set but no config: a resumed run continues with its stored config and "
                              "cannot change it (give the original config and --set only to have them checked)",
                          0);
  }
  const bool tty = rank == 0 && isatty(fileno(stderr));
  const RunHooks hooks = cli::run_hooks(a.quiet || rank != 0, tty, a.stop_after_steps);
  if (rank == 0) {
    std::fprintf(stderr, "slipstrip-mpi %s (%s): resuming %s on %d process%s\n", code_version, git_hash,
                 a.resume_path.c_str(), processes, processes == 1 ? "" : "es");
  }
  std::optional<RunResult> result;
  try {
    result = resume_distributed(a.resume_path, given, hooks, world);
  } catch (const SetupCancelled& e) {
    if (rank == 0)
      std::fprintf(stderr, "interrupted by %s during the set-up (%s); %s and its restart point are unchanged\n",
                   cli::interrupt_name(), e.what(), a.resume_path.c_str());
    return cli::signal_exit_code();
  }
  if (!result) {
    if (rank == 0)
      std::fprintf(stderr, "%s: the run is already completed; nothing to resume\n", a.resume_path.c_str());
    return 0;
  }
  if (rank == 0) std::fprintf(stderr, "resumed from step %lld\n", result->resumed_from_step);
  return report(*result, a.resume_path, processes, a.quiet, tty);
}

// `slipstrip-mpi run`: the CLI of `slipstrip run` (apps/command_run.cpp) for a
// run split over the processes; rank 0 prints.
int run(const RunArguments& a) {
  cli::catch_interrupts();
  const MPI_Comm world = MPI_COMM_WORLD;
  const int rank = mpi_rank(world), processes = mpi_size(world);
  if (!a.resume_path.empty()) return resume(a);
  if (a.config_path.empty())
    throw CollectiveError("run: config is required (a TOML config file; see --help)", 0);
  // Every process reads the config.  A refusal is normally the same on each,
  // but a process that cannot read the file (another mount) fails alone, so
  // the processes agree on it before any other collective.
  SimulationConfig config;
  std::string config_error;
  try {
    config = load_config_file(a.config_path, a.overrides);
  } catch (const std::invalid_argument& e) {
    config_error = e.what();
  }
  throw_if_any_failed(config_error, "", world);
  std::string out_path = a.out_path;
  if (out_path.empty()) {
    auto base = a.config_path.substr(a.config_path.find_last_of('/') + 1);
    if (auto dot = base.rfind('.'); dot != std::string::npos) base = base.substr(0, dot);
    out_path = base + ".h5";
  }
  // What the run will cost, and the limits, before the set-up, as `slipstrip
  // run`.  The history operator is split over the processes (each holds the
  // Fourier modes of its own rows), so its limit is per process: the whole
  // operator is held against P times --max-memory-gib.  Rank 0 writes the
  // whole output file, so the output limit is the serial run's.
  if (rank == 0) std::fputs(run_header(config).c_str(), stderr);
  ResourceLimits limits = a.limits;
  limits.max_operator_gib *= processes;
  std::string limits_error;
  try {
    check_resources(config, limits);
  } catch (const std::invalid_argument& e) {
    limits_error = e.what();
  }
  throw_if_any_failed(limits_error, "", world);
  if (rank == 0) cli::warn_if_disk_too_small(config, out_path);
  const bool tty = rank == 0 && isatty(fileno(stderr));
  const RunHooks hooks = cli::run_hooks(a.quiet || rank != 0, tty, a.stop_after_steps);
  if (rank == 0)
    std::fprintf(stderr, "slipstrip-mpi %s (%s): %s -> %s on %d process%s\n", code_version, git_hash,
                 a.config_path.c_str(), out_path.c_str(), processes, processes == 1 ? "" : "es");
  RunResult result;
  try {
    const std::string inputs[] = {a.config_path};
    result = run_distributed(config, out_path, hooks, a.overwrite, inputs, world);
  } catch (const SetupCancelled& e) {
    if (rank == 0)
      std::fprintf(stderr, "interrupted by %s during the set-up (%s); no output written\n", cli::interrupt_name(),
                   e.what());
    return cli::signal_exit_code();
  }
  return report(result, out_path, processes, a.quiet, tty);
}

}  // namespace

int main(int argc, char** argv) {
  MpiSession mpi(argc, argv);
  const int rank = mpi_rank(MPI_COMM_WORLD);
  CLI::App app{"slipstrip-mpi: a 2D interface split over MPI processes (docs/3d.md)"};
  app.require_subcommand(1);
  std::string config_path;
  std::vector<std::string> overrides;
  int steps = 100;
  auto* bench_command = app.add_subcommand("bench", "Time the distributed step of CONFIG's 2D interface");
  bench_command->add_option("config", config_path, "TOML config (geometry.nodes_z > 1)")->required();
  bench_command->add_option("--steps", steps, "Time steps to time")->check(CLI::PositiveNumber);
  bench_command->add_option("--set", overrides, "Override a config key: section.key=value (repeatable)");
  RunArguments run_arguments;
  auto* run_command = app.add_subcommand(
      "run", "Run CONFIG's 2D interface split over the processes; rank 0 writes the run file of `slipstrip run` "
             "(docs/3d.md, docs/output.md). SIGTERM stops cleanly (status interrupted) with a restart point.");
  run_command->add_option("config", run_arguments.config_path, "TOML config (geometry.nodes_z > 1)");
  run_command->add_option("--out", run_arguments.out_path, "Output HDF5 file (default: <config name>.h5)");
  run_command->add_option("--set", run_arguments.overrides, "Override a config key: section.key=value (repeatable)");
  run_command->add_flag("--quiet", run_arguments.quiet, "No progress bar");
  run_command->add_flag("--overwrite", run_arguments.overwrite,
                        "Replace an existing --out file (never the config file itself)");
  run_command->add_option("--stop-after-steps", run_arguments.stop_after_steps,
                          "Stop as SIGTERM does (status interrupted, exit 143) once this many time steps are done")
      ->check(cli::finite_positive());
  run_command->add_option("--max-memory-gib", run_arguments.limits.max_operator_gib,
                          "Refuse runs whose estimated history-operator memory per process exceeds this [GiB]")
      ->capture_default_str()->check(cli::finite_positive());
  run_command->add_option("--max-steps", run_arguments.limits.max_steps, "Refuse runs of more time steps than this")
      ->capture_default_str()->check(cli::finite_positive());
  run_command->add_option("--max-output-gib", run_arguments.limits.max_output_gib,
                          "Refuse runs whose estimated output file exceeds this [GiB]")
      ->capture_default_str()->check(cli::finite_positive());
  run_command->add_option("--resume", run_arguments.resume_path,
                          "Continue RUN.h5 from its restart point, on as many processes as wrote it (CONFIG, "
                          "if given, is only checked against the stored config)");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = rank == 0 ? app.exit(e) : e.get_exit_code();
    if (code != 0) MPI_Abort(MPI_COMM_WORLD, code);
    return 0;
  }
  try {
    if (run_command->parsed()) return run(run_arguments);
    return bench(config_path, overrides, steps);
  } catch (const CollectiveError& e) {
    // Every process has it: one line, and every process ends normally.
    if (rank == 0) std::fprintf(stderr, "rank %d: %s\n", e.origin_rank, e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rank %d: %s\n", rank, e.what());
    MPI_Abort(MPI_COMM_WORLD, 1);
  }
  return 1;
}
