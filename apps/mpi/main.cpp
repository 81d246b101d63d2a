// slipstrip-mpi: a 2D interface (geometry.nodes_z > 1) split over the
// processes of an MPI job (parallel/, docs/3d.md "Across machines").
//
//   mpirun -np 4 slipstrip-mpi bench CONFIG.toml [--steps N] [--set key=value ...]
//
// times the distributed time step of CONFIG's interface: set-up, wall and CPU
// time per step, and the parts (the four distributed FFTs with their
// transposes, this process's history operator alone), with the rows, Fourier
// modes and FFT message bytes per process.  It does not write a run file:
// `slipstrip run` (one process) does; a distributed run file is not built yet
// (docs/3d.md section 7).  Any error on any process prints "rank R: message"
// and aborts the whole job (MPI_Abort), so no process waits forever in a
// collective call another one has left.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <complex>
#include <cstdio>
#include <ctime>
#include <exception>
#include <string>
#include <vector>

#include "config/config.hpp"
#include "parallel/distributed_fft.hpp"
#include "parallel/distributed_interface.hpp"
#include "parallel/mpi_session.hpp"
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

  // The four distributed FFTs of a step (with their transposes), alone.
  DistributedRealFft2d fft(config.geometry.nodes, config.geometry.nodes_z, world);
  std::vector<double> field(sim.slip_rate_x().begin(), sim.slip_rate_x().end()), back(field.size());
  std::vector<std::complex<double>> spectrum(fft.local_modes());
  MPI_Barrier(world);
  t0 = MPI_Wtime();
  cpu0 = process_cpu_seconds();
  for (int s = 0; s < steps; ++s)
    for (int twice = 0; twice < 2; ++twice) {
      fft.forward(field, spectrum);
      fft.inverse(spectrum, back);
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

  // Bytes one process sends per step in the FFTs' transposes: each of the four
  // moves its share of the nodes_z x (nodes_x/2 + 1) complex array, all but
  // the part it keeps.
  const double complex_bytes = 16.0 * config.geometry.nodes_z * (config.geometry.nodes / 2 + 1);
  const double sent = 4.0 * complex_bytes / processes * (processes - 1) / processes;
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
    std::printf("parts (slowest process): 4 distributed FFTs wall %.1f us, CPU %.1f us; history operator wall "
                "%.1f us, CPU %.1f us\n",
                1e6 * fft_wall.max, 1e6 * fft_cpu.max, 1e6 * operator_wall.max, 1e6 * operator_cpu.max);
    std::printf("FFT transposes: %.0f bytes sent per process per step (4 all-to-alls of %.0f bytes each)\n",
                sent, sent / 4);
  }
  return 0;
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
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = rank == 0 ? app.exit(e) : e.get_exit_code();
    if (code != 0) MPI_Abort(MPI_COMM_WORLD, code);
    return 0;
  }
  try {
    return bench(config_path, overrides, steps);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rank %d: %s\n", rank, e.what());
    MPI_Abort(MPI_COMM_WORLD, 1);
  }
  return 1;
}
