#include "solver/run.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <vector>

#include "io/file_lock.hpp"
#include "io/output_paths.hpp"
#include "solver/checkpoint.hpp"
#include "config/config.hpp"
#include "solver/run_output.hpp"
#include "solver/simulation_3d.hpp"
#include "solver/simulation.hpp"
#include "solver/stations.hpp"
#include "slipstrip/version.hpp"

namespace slipstrip {

double next_slip_trigger(double next, double mean_slip, double increment) {
  // The usual case: step the trigger by whole increments past the slip (the
  // historical rule, kept so that existing runs take the same snapshots).
  if ((mean_slip - next) / increment < 1e6) {
    while (next <= mean_slip) {
      const double advanced = next + increment;
      if (!(advanced > next)) break;  // increment below the rounding of next
      next = advanced;
    }
  } else {
    next = (std::floor(mean_slip / increment) + 1.0) * increment;
  }
  // An increment lost in the rounding of the slip (e.g. 1e-30 m on 1e-6 m)
  // would leave the trigger at or below the slip forever: move it just past
  // the slip, so at most one snapshot is taken per step.
  if (!(next > mean_slip)) next = std::nextafter(mean_slip, std::numeric_limits<double>::infinity());
  return next;
}

namespace {

// What the time loop (drive, below) needs of a simulation beyond stepping and
// saving it: its output records.  One interface line (Simulation) or a 2D
// interface (Simulation3d, docs/3d.md).
class LineRun {
 public:
  using Sim = Simulation;
  LineRun(const SimulationConfig& config, const Simulation& sim)
      : config_(config), sim_(sim),
        station_slip_(config.output.stations, sim.dx(), sim.x().size()),
        station_rate_(config.output.stations, sim.dx(), sim.x().size()),
        station_stress_(config.output.stations, sim.dx(), sim.x().size()),
        station_state_(config.output.stations, sim.dx(), sim.x().size()),
        station_normal_(config.output.stations, sim.dx(), sim.x().size()),
        station_opening_(config.output.stations, sim.dx(), sim.x().size()) {}

  SlipSamplingSetup sampling() const {
    SlipSamplingSetup sampling = common_sampling(config_, sim_.dx());
    sampling.x.assign(sim_.x().begin(), sim_.x().end());
    return sampling;
  }
  RunOutputOptions options() const {
    RunOutputOptions options = common_options(config_);
    options.station_x = config_.output.stations;
    options.normal_stress_snapshots = sim_.variable_normal_stress();
    options.loading_shear_stress = config_.loading.drive == LoadingDrive::mean_slip_rate;
    if (config_.interface.law == InterfaceLawName::rate_and_state) {
      // The parameters every node ran with (profiles resolved), so the file is
      // interpretable without the profile files the config may name.
      options.node_parameters = node_parameters(resolve_friction_nodes(
          config_.friction, config_.friction_profiles, sim_.x().size(), sim_.dx()));
    }
    return options;
  }
  // The /friction datasets: the parameters every node ran with.
  static std::vector<NodeParameter> node_parameters(const FrictionNodeValues& nodes) {
    return {{"f0", "1", nodes.f0},
            {"a", "1", nodes.a},
            {"b", "1", nodes.b},
            {"characteristic_slip", "m", nodes.characteristic_slip}};
  }
  // The slip the slip sampling records, and the slip rate whose magnitude
  // dates the rupture front.
  std::span<const double> sampled_slip() const { return sim_.slip(); }
  std::span<const double> front_slip_rate() const { return sim_.slip_rate(); }
  double mean_slip() const { return sim_.mean_slip(); }
  void append_timeseries(RunOutput& output) const {
    if (config_.loading.drive == LoadingDrive::mean_slip_rate)
      output.append_timeseries(sim_.time(), sim_.max_slip_rate(), sim_.mean_slip(), sim_.mean_shear_stress(),
                               sim_.loading_shear_stress());
    else
      output.append_timeseries(sim_.time(), sim_.max_slip_rate(), sim_.mean_slip(), sim_.mean_shear_stress());
  }
  void write_snapshot(RunOutput& output) const {
    output.write_snapshot(sim_.time(), sim_.slip(), sim_.slip_rate(), sim_.state(), sim_.shear_stress(),
                          sim_.normal_stress(), sim_.opening());
  }
  bool has_stations() const { return !station_slip_.empty(); }
  void record_stations(RunOutput& output) {
    if (station_slip_.empty()) return;
    double sum_rate = 0.0;
    for (double v : sim_.slip_rate()) sum_rate += v;
    const double mu_dx = config_.material.shear_modulus * sim_.dx();
    if (sim_.variable_normal_stress())
      output.append_stations(sim_.time(), station_slip_.sample(sim_.slip()), station_rate_.sample(sim_.slip_rate()),
                             station_stress_.sample(sim_.shear_stress()), station_state_.sample(sim_.state()),
                             station_normal_.sample(sim_.normal_stress()), station_opening_.sample(sim_.opening()),
                             sim_.max_slip_rate(), mu_dx * sum_rate);
    else
      output.append_stations(sim_.time(), station_slip_.sample(sim_.slip()), station_rate_.sample(sim_.slip_rate()),
                             station_stress_.sample(sim_.shear_stress()), station_state_.sample(sim_.state()),
                             config_.loading.normal_stress, sim_.max_slip_rate(), mu_dx * sum_rate);
  }

  // Shared with InterfaceRun: the records' scalars from the config.
  static SlipSamplingSetup common_sampling(const SimulationConfig& config, double dx) {
    SlipSamplingSetup sampling;
    sampling.delta_th = config.output.delta_th;
    sampling.dx = dx;
    sampling.v0 = config.loading.driving_velocity;
    sampling.mu = config.material.shear_modulus;
    sampling.D = config.friction.characteristic_slip;
    sampling.L = config.geometry.length;
    return sampling;
  }
  static RunOutputOptions common_options(const SimulationConfig& config) {
    RunOutputOptions options;
    options.snapshots_by_slip = config.output.snapshot_slip_increment > 0.0;
    options.front_slip_rate = config.output.front_slip_rate;
    return options;
  }

 private:
  const SimulationConfig& config_;
  const Simulation& sim_;
  // Stations (one buffer per field, sampled in turn).
  StationSampler station_slip_, station_rate_, station_stress_, station_state_, station_normal_, station_opening_;
};

// A 2D interface (docs/3d.md): the x component of the slip is sampled (the
// loading direction), the front is dated by |v|, the time series holds
// max |v|, the mean slip and shear stress along x; snapshots are the seven
// fields below as [nodes_z, nodes_x] maps; stations are points (x, z) with the
// same seven fields.
class InterfaceRun {
 public:
  using Sim = Simulation3d;
  InterfaceRun(const SimulationConfig& config, const Simulation3d& sim)
      : config_(config), sim_(sim),
        stations_(config.output.stations, config.output.stations_z, sim.dx(), sim.dz(),
                  static_cast<std::size_t>(sim.nodes_x()), static_cast<std::size_t>(sim.nodes_z())) {
    station_values_.assign(fields().size() * stations_.size(), 0.0);
  }

  SlipSamplingSetup sampling() const { return interface_2d_sampling(config_); }
  RunOutputOptions options() const { return interface_2d_output_options(config_, sim_.variable_normal_stress()); }
  std::span<const double> sampled_slip() const { return sim_.slip_x(); }
  std::span<const double> front_slip_rate() const { return sim_.speed(); }
  double mean_slip() const { return sim_.mean_slip_x(); }
  void append_timeseries(RunOutput& output) const {
    output.append_timeseries(sim_.time(), sim_.max_slip_rate(), sim_.mean_slip_x(), sim_.mean_shear_stress_x());
  }
  void write_snapshot(RunOutput& output) const { output.write_snapshot(sim_.time(), fields()); }
  bool has_stations() const { return !stations_.empty(); }
  // The seven fields at the stations, the max |v| and the moment rate
  // mu sum(v_x) dx dz [N m/s] (the slip along x, as the events' moment).
  void record_stations(RunOutput& output) {
    if (stations_.empty()) return;
    const auto all = fields();
    const std::size_t count = stations_.size();
    std::array<std::span<const double>, 9> at_stations;
    for (std::size_t f = 0; f < all.size(); ++f) {
      const auto values = stations_.sample(all[f]);
      std::copy(values.begin(), values.end(), station_values_.begin() + static_cast<std::ptrdiff_t>(f * count));
      at_stations[f] = std::span<const double>(station_values_).subspan(f * count, count);
    }
    double sum_rate = 0.0;
    for (double v : sim_.slip_rate_x()) sum_rate += v;
    const double mu_dxdz = config_.material.shear_modulus * sim_.dx() * sim_.dz();
    output.append_stations(sim_.time(), std::span<const std::span<const double>>(at_stations.data(), all.size()),
                           sim_.max_slip_rate(), mu_dxdz * sum_rate);
  }

 private:
  Interface2dFields fields() const { return interface_2d_fields(sim_); }

  const SimulationConfig& config_;
  const Simulation3d& sim_;
  StationSampler2d stations_;
  std::vector<double> station_values_;  // fields x stations, field-major
};

// The time loop of a new run (resume_from == nullptr) or of a resumed one.
template <class Run>
RunResult drive(const SimulationConfig& config, const std::string& output_path, const RunHooks& hooks,
                const RunCheckpoint* resume_from) {
  using clock = std::chrono::steady_clock;
  // The set-up polls the same stop request as the time loop: a signal during
  // a long kernel set-up ends it with SetupCancelled, before any file exists
  // (or, on resume, before the run file is touched).
  // A local friction solve that fails already at t = 0 is not a divergence of
  // the run but a combination of [friction], [loading] and [initial] values
  // without a steady state to start from: an input error (exit code 2).
  const auto sim_owner = [&] {
    try {
      return std::make_unique<typename Run::Sim>(config, hooks.stop_requested);
    } catch (const SimulationError& e) {
      throw std::invalid_argument(
          std::string("the initial state (t = 0) cannot be solved for this combination of "
                      "[friction], [loading] and [initial] values: ") + e.what());
    }
  }();
  auto& sim = *sim_owner;
  // Half a step of slack so rounding never adds or drops a final step.  The
  // count must fit a long long (a huge duration once overflowed to "0 steps").
  const double step_count = std::ceil(config.time.duration / sim.time_step() - 0.5);
  if (!(step_count < 0.5 * static_cast<double>(std::numeric_limits<long long>::max())))
    throw std::invalid_argument("time.duration = " + std::to_string(config.time.duration) +
                                " s is " + std::to_string(step_count) + " time steps of dt = " +
                                std::to_string(sim.time_step()) +
                                " s: the step count does not fit a 64-bit integer");
  const long long total_steps = static_cast<long long>(step_count);
  if (resume_from) {
    validate_checkpoint(*resume_from, config, sim.time_step(), total_steps, output_path);
    if (!resume_from->checksum_verified && hooks.warning) {
      hooks.warning("restart point '" + checkpoint_path(output_path) +
                    "' has no checksum (written before restart points carried one): its fields are checked, "
                    "but damage to its data cannot be found");
      // A caller that turns the warning into a stop (Python's -W error)
      // stops here, before the run file is touched.
      throw_if_cancelled(hooks.stop_requested, "the checks of the restart point");
    }
    sim.restore_state(resume_from->simulation);
  }
  const auto& out_cfg = config.output;
  const std::string config_toml = to_toml(config);
  Run run(config, sim);

  // A resumed run cuts every record of the file back to the restart point:
  // whatever was written after it (before the kill) is written again, the same.
  std::unique_ptr<RunOutput> output_owner =
      resume_from ? std::make_unique<RunOutput>(output_path, resume_from->output, run.sampling(), run.options())
                  : std::make_unique<RunOutput>(output_path, config_toml, run.sampling(), run.options());
  RunOutput& output = *output_owner;

  // Rupture-front arrival times.
  const std::size_t nodes = run.sampled_slip().size();
  std::vector<double> front_arrival(out_cfg.front_slip_rate > 0.0 ? nodes : 0,
                                    std::numeric_limits<double>::quiet_NaN());
  if (resume_from) front_arrival = resume_from->output.rupture_front;  // sizes checked by RunOutput
  auto record_front = [&] {
    bool changed = false;
    const auto v = run.front_slip_rate();
    for (std::size_t i = 0; i < front_arrival.size(); ++i)
      if (std::isnan(front_arrival[i]) && std::abs(v[i]) > out_cfg.front_slip_rate) {
        front_arrival[i] = sim.time();
        changed = true;
      }
    if (changed) output.set_rupture_front(front_arrival);
  };

  RunResult result;
  result.time_step = sim.time_step();
  const double duration = config.time.duration;
  std::vector<double> previous_slip(run.sampled_slip().begin(), run.sampled_slip().end());
  auto write_snapshot = [&] { run.write_snapshot(output); };
  double next_station = out_cfg.station_interval;
  double next_timeseries = out_cfg.timeseries_interval;
  double next_snapshot = out_cfg.snapshot_interval;
  double next_snapshot_slip = out_cfg.snapshot_slip_increment;
  if (resume_from) {
    // The records of t = 0 are in the file already; the triggers continue.
    next_station = resume_from->next_station;
    next_timeseries = resume_from->next_timeseries;
    next_snapshot = resume_from->next_snapshot;
    next_snapshot_slip = resume_from->next_snapshot_slip;
    result.resumed_from_step = sim.step_index();
  } else {
    run.record_stations(output);
    record_front();
    run.append_timeseries(output);
    const bool snapshots_on = out_cfg.snapshot_interval > 0.0 || out_cfg.snapshot_slip_increment > 0.0;
    if (snapshots_on) write_snapshot();
  }

  // A restart point: the run file flushed (so its records end exactly at the
  // cursors), then the state after the current step.  force: also when a
  // reader holds the file (the run is stopping); otherwise a held file
  // postpones the restart point to the next interval check.  Allocates: only
  // every checkpoint_interval seconds and at the stop, never per step.
  auto write_restart_point = [&](bool force) {
    auto cursor = output.flush_for_checkpoint(force);
    if (!cursor) return false;
    RunCheckpoint checkpoint;
    checkpoint.config_toml = config_toml;
    checkpoint.git_hash = slipstrip::git_hash;
    checkpoint.simulation = sim.save_state();
    checkpoint.output = std::move(*cursor);
    checkpoint.next_timeseries = next_timeseries;
    checkpoint.next_snapshot = next_snapshot;
    checkpoint.next_snapshot_slip = next_snapshot_slip;
    checkpoint.next_station = next_station;
    write_checkpoint(output_path, checkpoint);
    result.restart_point = checkpoint_path(output_path);
    return true;
  };

  const auto start = clock::now();
  auto last_flush = start, last_progress = start, last_checkpoint = start;
  auto seconds_since = [](clock::time_point t) {
    return std::chrono::duration<double>(clock::now() - t).count();
  };
  try {
    while (sim.step_index() < total_steps) {
      std::copy(run.sampled_slip().begin(), run.sampled_slip().end(), previous_slip.begin());
      const double t_old = sim.time();
      sim.step();
      output.record_slip(t_old, sim.time(), previous_slip, run.sampled_slip());
      if (run.has_stations() && sim.time() >= next_station * (1 - 1e-12)) {
        run.record_stations(output);
        next_station += out_cfg.station_interval;
      }
      if (!front_arrival.empty()) record_front();
      if (sim.time() >= next_timeseries * (1 - 1e-12)) {
        run.append_timeseries(output);
        next_timeseries += out_cfg.timeseries_interval;
      }
      if (out_cfg.snapshot_interval > 0.0 && sim.time() >= next_snapshot * (1 - 1e-12)) {
        write_snapshot();
        next_snapshot += out_cfg.snapshot_interval;
      } else if (out_cfg.snapshot_slip_increment > 0.0 && run.mean_slip() >= next_snapshot_slip) {
        write_snapshot();
        next_snapshot_slip = next_slip_trigger(next_snapshot_slip, run.mean_slip(),
                                               out_cfg.snapshot_slip_increment);
      }
      // Wall-clock checks are cheap but not free: every 16 steps is plenty.
      if ((sim.step_index() & 15) == 0) {
        if (out_cfg.checkpoint_interval > 0.0 && seconds_since(last_checkpoint) >= out_cfg.checkpoint_interval &&
            write_restart_point(false))
          last_checkpoint = last_flush = clock::now();
        if (seconds_since(last_flush) >= out_cfg.flush_interval) {
          output.flush();
          last_flush = clock::now();
        }
        if (hooks.progress && seconds_since(last_progress) >= hooks.progress_interval) {
          hooks.progress({sim.time(), duration, sim.step_index(), sim.max_slip_rate(), seconds_since(start)});
          last_progress = clock::now();
        }
      }
      if ((hooks.stop_requested && hooks.stop_requested()) ||
          (hooks.stop_after_steps >= 0 && sim.step_index() >= hooks.stop_after_steps)) {
        write_restart_point(/*force=*/true);
        result.status = "interrupted";
        break;
      }
    }
    if (result.status.empty()) result.status = "completed";
  } catch (const SimulationError& e) {
    result.status = std::string("diverged: ") + e.what();
  } catch (const SlipSamplingOverflow& e) {
    result.status = std::string("diverged: ") + e.what();
  }
  result.simulated_time = sim.time();
  result.steps = sim.step_index();
  result.wall_seconds = seconds_since(start);
  if (hooks.progress)
    hooks.progress({sim.time(), duration, sim.step_index(), sim.max_slip_rate(), result.wall_seconds});
  output.close(result.status);
  if (result.status != "interrupted") {
    // Completed: nothing left to resume.  Diverged: a resume would diverge
    // again, bit for bit.  Either way the restart point is dead weight.
    remove_checkpoint(output_path);
    result.restart_point.clear();
  }
  return result;
}

// A 2D interface (geometry.nodes_z > 1) or a line.
RunResult drive_any(const SimulationConfig& config, const std::string& output_path, const RunHooks& hooks,
                    const RunCheckpoint* resume_from) {
  return config.geometry.nodes_z > 1 ? drive<InterfaceRun>(config, output_path, hooks, resume_from)
                                     : drive<LineRun>(config, output_path, hooks, resume_from);
}

}  // namespace

RunResult run_simulation(const SimulationConfig& config, const std::string& output_path,
                         const RunHooks& hooks, bool overwrite) {
  const io::FileLock lock = lock_run_file(output_path);
  if (overwrite) {
    remove_checkpoint(output_path);
  } else {
    // Again under the lock: the caller's check may be minutes old (the
    // set-up), and another process may have started this run since.
    const io::OutputPath outputs[] = {{"output", output_path}, {"restart point", checkpoint_path(output_path)}};
    io::check_output_paths(outputs, {}, false);
  }
  return drive_any(config, output_path, hooks, nullptr);
}

io::FileLock lock_run_file(const std::string& output_path) {
  return io::FileLock(run_lock_path(output_path), "run file '" + output_path + "' (or its restart point)");
}

RunResult resume_simulation(const std::string& output_path, const RunHooks& hooks) {
  const io::FileLock lock = lock_run_file(output_path);
  return resume_simulation(output_path, hooks, lock);
}

RunResult resume_simulation(const std::string& output_path, const RunHooks& hooks, const io::FileLock& held) {
  if (held.path() != run_lock_path(output_path))
    throw std::logic_error("resume_simulation: the lock held is '" + held.path() + "', not the lock of run file '" +
                           output_path + "'");
  const RunFileHeader header = read_run_file_header(output_path);
  if (header.status == "completed")
    throw std::invalid_argument("run file '" + output_path + "' is completed: nothing to resume");
  if (header.status.rfind("diverged", 0) == 0)
    throw std::invalid_argument("run file '" + output_path + "' has status '" + header.status +
                                "': a resumed run would diverge again; nothing to resume");
  const RunCheckpoint checkpoint = read_checkpoint(output_path);
  if (checkpoint.config_toml != header.config_toml)
    throw std::invalid_argument("restart point '" + checkpoint_path(output_path) +
                                "' was written for another config than the run file '" + output_path +
                                "' holds (not its restart point)");
  if (const int processes = restart_point_processes(checkpoint); processes > 0)
    throw std::invalid_argument("restart point '" + checkpoint_path(output_path) + "' was written by " +
                                "slipstrip-mpi run on " + std::to_string(processes) +
                                (processes == 1 ? " process" : " processes") +
                                " in the per-process layout of earlier versions (history kind '" +
                                kSplitHistoryKind + "'): it holds each process's history operator state, so it "
                                "is resumed on as many processes (`mpirun -np " + std::to_string(processes) +
                                " slipstrip-mpi run --resume " + output_path + "`); its next restart points "
                                "are in the one-process layout, which `slipstrip run --resume` takes");
  const SimulationConfig config = load_config_string(header.config_toml);
  return drive_any(config, output_path, hooks, &checkpoint);
}

SlipSamplingSetup interface_2d_sampling(const SimulationConfig& config) {
  const auto& g = config.geometry;
  // The node spacings as Simulation3d computes them.
  const double dx = g.length / g.nodes, dz = g.width / g.nodes_z;
  SlipSamplingSetup sampling = LineRun::common_sampling(config, dx);
  sampling.nodes_z = g.nodes_z;
  sampling.dz = dz;
  sampling.W = g.width;
  const std::size_t nodes = static_cast<std::size_t>(g.nodes) * static_cast<std::size_t>(g.nodes_z);
  sampling.x.resize(nodes);
  sampling.z.resize(nodes);
  for (std::size_t i = 0; i < nodes; ++i) {
    sampling.x[i] = static_cast<double>(i % static_cast<std::size_t>(g.nodes)) * dx;
    sampling.z[i] = static_cast<double>(i / static_cast<std::size_t>(g.nodes)) * dz;
  }
  return sampling;
}

RunOutputOptions interface_2d_output_options(const SimulationConfig& config, bool variable_normal_stress) {
  RunOutputOptions options = LineRun::common_options(config);
  options.interface_2d_fields = interface_2d_field_units(variable_normal_stress);
  options.station_x = config.output.stations;
  options.station_z = config.output.stations_z;
  options.station_fields = interface_2d_field_units(variable_normal_stress);
  // The parameters every node ran with, flattened as the slip sampling (x
  // fastest), so the file is interpretable without the config's profiles.
  options.node_parameters = LineRun::node_parameters(
      resolve_friction_nodes(config.friction, config.friction_profiles, friction_node_grid(config)));
  return options;
}

std::vector<std::pair<std::string, std::string>> interface_2d_field_units(bool variable_normal_stress) {
  std::vector<std::pair<std::string, std::string>> units = {
      {"slip_x", "m"}, {"slip_z", "m"}, {"slip_rate_x", "m/s"}, {"slip_rate_z", "m/s"},
      {"state", "s"},  {"shear_stress_x", "Pa"}, {"shear_stress_z", "Pa"}};
  if (variable_normal_stress) {
    units.emplace_back("normal_stress", "Pa");
    units.emplace_back("opening", "m");
  }
  return units;
}

Interface2dFields interface_2d_fields(const Simulation3d& sim) {
  return {{sim.slip_x(), sim.slip_z(), sim.slip_rate_x(), sim.slip_rate_z(), sim.state(), sim.shear_stress_x(),
           sim.shear_stress_z(), sim.normal_stress(), sim.opening()},
          sim.variable_normal_stress() ? 9u : 7u};
}

}  // namespace slipstrip
