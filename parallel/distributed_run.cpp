#include "parallel/distributed_run.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <optional>
#include <span>
#include <sstream>
#include <vector>

#include "config/config.hpp"
#include "io/output_paths.hpp"
#include "parallel/distributed_interface.hpp"
#include "parallel/mpi_session.hpp"
#include "solver/checkpoint.hpp"
#include "solver/run_output.hpp"
#include "solver/simulation_3d.hpp"
#include "solver/slip_sampler.hpp"

namespace slipstrip {

static_assert(sizeof(hsize_t) == sizeof(unsigned long long), "crossings are sent as MPI_UNSIGNED_LONG_LONG");

namespace {
std::string format_number(double value) {
  std::ostringstream text;
  text << value;
  return text.str();
}
}  // namespace

void check_distributed_run(const SimulationConfig& config) {
  const auto refuse = [](const std::string& what) {
    throw CollectiveError(what + " (slipstrip-mpi run; docs/3d.md, \"Across machines\")", 0);
  };
  if (config.geometry.nodes_z < 2)
    refuse("geometry.nodes_z = " + std::to_string(config.geometry.nodes_z) +
           ": a run split over processes is a 2D interface only (nodes_z > 1); a line runs with `slipstrip run`");
  if (!config.output.stations.empty())
    refuse("output.stations is not allowed on several processes: expected [] (stations are recorded by "
           "`slipstrip run` on one process)");
  if (config.output.checkpoint_interval != 0.0)
    refuse("output.checkpoint_interval = " + format_number(config.output.checkpoint_interval) +
           " s: restart points are not written on several processes; set output.checkpoint_interval = 0 (a "
           "stop then closes the run file with status \"interrupted\", without a restart point)");
}

namespace {

// `text` of process `root` on every process.  Collective.
std::string broadcast_string(std::string text, int root, MPI_Comm comm) {
  unsigned long long size = text.size();
  MPI_Bcast(&size, 1, MPI_UNSIGNED_LONG_LONG, root, comm);
  text.resize(size);
  MPI_Bcast(text.data(), static_cast<int>(size), MPI_CHAR, root, comm);
  return text;
}

// What each process passes to rank 0 in a step: coordinates (for the slip
// sampling (level, node) pairs, for the rupture front nodes) and values,
// concatenated in rank order.  The buffers are kept between steps, so a step
// allocates only when more crossings than ever before arrive.
class RecordGather {
 public:
  RecordGather(MPI_Comm comm) : comm_(comm), rank_(mpi_rank(comm)), size_(mpi_size(comm)) {
    if (rank_ == 0) {
      counts_.resize(size_);
      offsets_.resize(size_);
    }
  }
  // Collective.  coordinates_per_value coordinates per value (2: crossings; 1: front nodes).
  void gather(std::span<const hsize_t> coordinates, std::span<const double> values, int coordinates_per_value) {
    const int count = static_cast<int>(values.size());
    MPI_Gather(&count, 1, MPI_INT, counts_.data(), 1, MPI_INT, 0, comm_);
    if (rank_ == 0) {
      std::exclusive_scan(counts_.begin(), counts_.end(), offsets_.begin(), 0);
      values_.resize(static_cast<std::size_t>(offsets_.back()) + counts_.back());
    }
    MPI_Gatherv(values.data(), count, MPI_DOUBLE, values_.data(), counts_.data(), offsets_.data(), MPI_DOUBLE, 0,
                comm_);
    if (rank_ == 0) {
      for (int r = 0; r < size_; ++r) {
        counts_[r] *= coordinates_per_value;
        offsets_[r] *= coordinates_per_value;
      }
      coordinates_.resize(values_.size() * static_cast<std::size_t>(coordinates_per_value));
    }
    MPI_Gatherv(coordinates.data(), count * coordinates_per_value, MPI_UNSIGNED_LONG_LONG, coordinates_.data(),
                counts_.data(), offsets_.data(), MPI_UNSIGNED_LONG_LONG, 0, comm_);
  }
  // On rank 0 after gather().
  std::span<const hsize_t> coordinates() const { return coordinates_; }
  std::span<const double> values() const { return values_; }

 private:
  MPI_Comm comm_;
  int rank_, size_;
  std::vector<int> counts_, offsets_;
  std::vector<hsize_t> coordinates_;
  std::vector<double> values_;
};

// The per-step control reduction (MPI_MAX over the processes): whether some
// process diverged, rank 0's stop request, whether some process has level
// crossings or front arrivals to pass, and the largest |v| (for the progress).
constexpr std::size_t kDiverged = 0, kStop = 1, kCrossings = 2, kFront = 3, kMaxSpeed = 4, kControlSize = 5;

}  // namespace

RunResult run_distributed(const SimulationConfig& config, const std::string& output_path, const RunHooks& hooks,
                          bool overwrite, MPI_Comm comm) {
  using clock = std::chrono::steady_clock;
  const int rank = mpi_rank(comm), processes = mpi_size(comm);
  check_distributed_run(config);

  // The run's lock and the output paths, on rank 0 (the one process that
  // writes), before any process starts the set-up: as run_simulation's.
  std::optional<io::FileLock> lock;
  std::string refusal;
  if (rank == 0) {
    try {
      lock.emplace(lock_run_file(output_path));
      if (overwrite) {
        remove_checkpoint(output_path);
      } else {
        const io::OutputPath outputs[] = {{"output", output_path},
                                          {"restart point", checkpoint_path(output_path)}};
        io::check_output_paths(outputs, {}, false);
      }
    } catch (const std::exception& e) {
      refusal = e.what();
    }
  }
  refusal = broadcast_string(refusal, 0, comm);
  if (!refusal.empty()) throw CollectiveError(refusal, 0);

  // The set-up is collective (the distributed operator's choices are made
  // over all processes), so it is not cancelled half-way on one process: a
  // stop requested on rank 0 during it is honoured right after, before the
  // file exists.  A friction solve that fails at t = 0 on some process is an
  // input error there (as run_simulation's).
  const auto sim_owner = [&] {
    try {
      return std::make_unique<Simulation3d>(config, std::span<const double>(), CancelCheck{},
                                            distributed_spectral_step(comm));
    } catch (const SimulationError& e) {
      throw std::invalid_argument(
          std::string("the initial state (t = 0) cannot be solved for this combination of "
                      "[friction], [loading] and [initial] values: ") + e.what());
    }
  }();
  Simulation3d& sim = *sim_owner;
  int stop_in_setup = rank == 0 && hooks.stop_requested && hooks.stop_requested() ? 1 : 0;
  MPI_Bcast(&stop_in_setup, 1, MPI_INT, 0, comm);
  if (stop_in_setup) throw SetupCancelled("set-up cancelled (the stop was seen when the set-up ended)");

  const double step_count = std::ceil(config.time.duration / sim.time_step() - 0.5);
  if (!(step_count < 0.5 * static_cast<double>(std::numeric_limits<long long>::max())))
    throw CollectiveError("time.duration = " + std::to_string(config.time.duration) + " s is " +
                              std::to_string(step_count) + " time steps of dt = " + std::to_string(sim.time_step()) +
                              " s: the step count does not fit a 64-bit integer",
                          0);
  const long long total_steps = static_cast<long long>(step_count);
  const auto& out_cfg = config.output;
  const std::size_t first_node = static_cast<std::size_t>(sim.nodes_x()) * sim.slab().first_row;
  const std::size_t nodes = sim.nodes();  // this process's

  // Rank 0 writes the file with run_simulation's writer and records.
  std::unique_ptr<RunOutput> output;
  std::vector<double> front_arrival;  // rank 0: the whole interface's
  if (rank == 0) {
    RunOutputOptions options = interface_2d_output_options(config, sim.variable_normal_stress());
    options.processes = processes;
    output = std::make_unique<RunOutput>(output_path, to_toml(config), interface_2d_sampling(config), options);
    if (out_cfg.front_slip_rate > 0.0)
      front_arrival.assign(static_cast<std::size_t>(sim.nodes_x()) * sim.nodes_z(),
                           std::numeric_limits<double>::quiet_NaN());
  }

  // Each process dates the level crossings and the front arrivals of its own
  // nodes, numbered as the whole interface's.
  std::optional<SlipSampler> sampler;
  if (out_cfg.delta_th > 0.0) sampler.emplace(out_cfg.delta_th, nodes);
  std::vector<hsize_t> crossing_coordinates;
  std::vector<bool> front_reached(out_cfg.front_slip_rate > 0.0 ? nodes : 0, false);
  std::vector<hsize_t> front_nodes;
  std::vector<double> front_times;
  const auto find_front = [&] {
    front_nodes.clear();
    front_times.clear();
    const auto v = sim.speed();
    for (std::size_t i = 0; i < front_reached.size(); ++i)
      if (!front_reached[i] && std::abs(v[i]) > out_cfg.front_slip_rate) {
        front_reached[i] = true;
        front_nodes.push_back(first_node + i);
        front_times.push_back(sim.time());
      }
  };
  RecordGather gathered(comm);
  const auto pass_crossings = [&] {
    const auto local = sampler->pending_coordinates();
    crossing_coordinates.assign(local.begin(), local.end());
    for (std::size_t c = 1; c < crossing_coordinates.size(); c += 2) crossing_coordinates[c] += first_node;
    gathered.gather(crossing_coordinates, sampler->pending_times(), 2);
    sampler->clear_pending();
    if (rank == 0) output->record_crossings(gathered.coordinates(), gathered.values());
  };
  const auto pass_front = [&] {
    gathered.gather(front_nodes, front_times, 1);
    if (rank != 0) return;
    const auto where = gathered.coordinates();
    const auto when = gathered.values();
    for (std::size_t c = 0; c < when.size(); ++c) front_arrival[where[c]] = when[c];
    output->set_rupture_front(front_arrival);
  };
  // Collective: the time series' reductions, in this order on every process.
  const auto append_timeseries = [&] {
    const double max_rate = sim.max_slip_rate();
    const double mean_slip = sim.mean_slip_x();
    const double mean_stress = sim.mean_shear_stress_x();
    if (rank == 0) output->append_timeseries(sim.time(), max_rate, mean_slip, mean_stress);
  };
  // Collective: every field gathered on rank 0, in the file's order.
  const auto write_snapshot = [&] {
    const Interface2dFields local = interface_2d_fields(sim);
    std::array<std::vector<double>, 9> whole;
    std::array<std::span<const double>, 9> spans;
    for (std::size_t f = 0; f < local.size(); ++f) {
      whole[f] = gather_rows(local[f], comm);
      spans[f] = whole[f];
    }
    if (rank == 0) output->write_snapshot(sim.time(), std::span<const std::span<const double>>(spans.data(), local.size()));
  };
  std::array<double, kControlSize> control{};
  const auto reduce_control = [&] {
    MPI_Allreduce(MPI_IN_PLACE, control.data(), kControlSize, MPI_DOUBLE, MPI_MAX, comm);
  };

  RunResult result;
  result.time_step = sim.time_step();
  std::vector<double> previous_slip(sim.slip_x().begin(), sim.slip_x().end());
  double next_timeseries = out_cfg.timeseries_interval;
  double next_snapshot = out_cfg.snapshot_interval;
  double next_snapshot_slip = out_cfg.snapshot_slip_increment;  // rank 0's decides
  // t = 0, as run_simulation records it.
  find_front();
  control = {0.0, 0.0, 0.0, front_nodes.empty() ? 0.0 : 1.0, 0.0};
  reduce_control();
  if (control[kFront] > 0.0) pass_front();
  append_timeseries();
  if (out_cfg.snapshot_interval > 0.0 || out_cfg.snapshot_slip_increment > 0.0) write_snapshot();

  const auto start = clock::now();
  auto last_flush = start, last_progress = start;
  const auto seconds_since = [](clock::time_point t) {
    return std::chrono::duration<double>(clock::now() - t).count();
  };
  std::string divergence;  // this process's
  while (sim.step_index() < total_steps) {
    std::copy(sim.slip_x().begin(), sim.slip_x().end(), previous_slip.begin());
    const double t_old = sim.time();
    bool crossed = false;
    try {
      sim.step();
      if (sampler) crossed = sampler->record(t_old, sim.time(), previous_slip, sim.slip_x());
      if (!front_reached.empty()) find_front();
    } catch (const SimulationError& e) {
      divergence = e.what();
    } catch (const SlipSamplingOverflow& e) {
      divergence = std::string(e.what()) + " (node numbered from node (0, " + std::to_string(sim.slab().first_row) +
                   "))";
    }
    control[kDiverged] = divergence.empty() ? 0.0 : 1.0;
    control[kStop] = rank == 0 && ((hooks.stop_requested && hooks.stop_requested()) ||
                                           (hooks.stop_after_steps >= 0 && sim.step_index() >= hooks.stop_after_steps))
                                 ? 1.0
                                 : 0.0;
    control[kCrossings] = crossed ? 1.0 : 0.0;
    control[kFront] = divergence.empty() && !front_nodes.empty() ? 1.0 : 0.0;
    control[kMaxSpeed] = divergence.empty() ? *std::max_element(sim.speed().begin(), sim.speed().end()) : 0.0;
    reduce_control();
    if (control[kDiverged] > 0.0) {
      // The diagnostic of the lowest process that diverged (the first node
      // in the file's order, as one process would name).
      int first = divergence.empty() ? processes : rank;
      MPI_Allreduce(MPI_IN_PLACE, &first, 1, MPI_INT, MPI_MIN, comm);
      result.status = "diverged: " + broadcast_string(divergence, first, comm);
      break;
    }
    if (control[kCrossings] > 0.0) pass_crossings();
    if (control[kFront] > 0.0) pass_front();
    if (sim.time() >= next_timeseries * (1 - 1e-12)) {
      append_timeseries();
      next_timeseries += out_cfg.timeseries_interval;
    }
    if (out_cfg.snapshot_interval > 0.0 && sim.time() >= next_snapshot * (1 - 1e-12)) {
      write_snapshot();
      next_snapshot += out_cfg.snapshot_interval;
    } else if (out_cfg.snapshot_slip_increment > 0.0) {
      // The sum over processes may round differently on each: rank 0's
      // decides, as its mean is the one the file's time series holds.
      const double mean_slip = sim.mean_slip_x();
      int take = rank == 0 && mean_slip >= next_snapshot_slip ? 1 : 0;
      MPI_Bcast(&take, 1, MPI_INT, 0, comm);
      if (take) {
        write_snapshot();
        if (rank == 0)
          next_snapshot_slip = next_slip_trigger(next_snapshot_slip, mean_slip, out_cfg.snapshot_slip_increment);
      }
    }
    if (rank == 0 && (sim.step_index() & 15) == 0) {
      if (seconds_since(last_flush) >= out_cfg.flush_interval) {
        output->flush();
        last_flush = clock::now();
      }
      if (hooks.progress && seconds_since(last_progress) >= hooks.progress_interval) {
        hooks.progress({sim.time(), config.time.duration, sim.step_index(), control[kMaxSpeed],
                        seconds_since(start)});
        last_progress = clock::now();
      }
    }
    if (control[kStop] > 0.0) {
      result.status = "interrupted";
      break;
    }
  }
  if (result.status.empty()) result.status = "completed";
  result.simulated_time = sim.time();
  result.steps = sim.step_index();
  result.wall_seconds = seconds_since(start);
  if (rank == 0) {
    if (hooks.progress)
      hooks.progress({sim.time(), config.time.duration, sim.step_index(), control[kMaxSpeed],
                      result.wall_seconds});
    output->close(result.status);
  }
  return result;
}

}  // namespace slipstrip
