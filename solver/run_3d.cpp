#include "solver/run_3d.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "config/config.hpp"
#include "io/attributes.hpp"
#include "io/datasets.hpp"
#include "io/hdf5.hpp"
#include "io/xdmf.hpp"
#include "slipstrip/version.hpp"
#include "solver/simulation_3d.hpp"

namespace slipstrip {
namespace {

constexpr const char* kFields[] = {"slip_x", "slip_z", "slip_rate_x", "slip_rate_z",
                                   "state", "shear_stress_x", "shear_stress_z"};

std::span<const double> field(const Simulation3d& sim, int f) {
  switch (f) {
    case 0: return sim.slip_x();
    case 1: return sim.slip_z();
    case 2: return sim.slip_rate_x();
    case 3: return sim.slip_rate_z();
    case 4: return sim.state();
    case 5: return sim.shear_stress_x();
    default: return sim.shear_stress_z();
  }
}

std::string snapshot_name(std::size_t index) {
  char name[32];
  std::snprintf(name, sizeof name, "%06zu", index);
  return name;
}

// One 2D snapshot: /snapshots/NNNNNN/<field>, each [nodes_z, nodes_x] (one
// contiguous dataset per field: a snapshot reads in one call).
void write_snapshot(hid_t snapshots, std::size_t index, const Simulation3d& sim) {
  const io::Handle group = io::create_group(snapshots, snapshot_name(index));
  io::write_attribute(group, "time", sim.time());
  io::write_attribute(group, "step", static_cast<long long>(sim.step_index()));
  const hsize_t dims[2] = {static_cast<hsize_t>(sim.nodes_z()), static_cast<hsize_t>(sim.nodes_x())};
  for (int f = 0; f < static_cast<int>(std::size(kFields)); ++f)
    io::write_array<double>(group, kFields[f], dims, field(sim, f));
}

// XDMF 3: a temporal collection of 2DCoRectMesh grids (z slow, x fast), one
// per snapshot, whose attributes point into the run file.
std::string xdmf_text(const std::string& h5_name, const Simulation3d& sim, const std::vector<double>& times) {
  std::ostringstream x;
  x.precision(17);
  const std::string dims = std::to_string(sim.nodes_z()) + " " + std::to_string(sim.nodes_x());
  x << "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n <Domain>\n"
    << "  <Grid Name=\"interface\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (std::size_t s = 0; s < times.size(); ++s) {
    x << "   <Grid Name=\"snapshot " << s << "\" GridType=\"Uniform\">\n"
      << "    <Time Value=\"" << times[s] << "\"/>\n"
      << "    <Topology TopologyType=\"2DCoRectMesh\" Dimensions=\"" << dims << "\"/>\n"
      << "    <Geometry GeometryType=\"ORIGIN_DXDY\">\n"
      << "     <DataItem Dimensions=\"2\" Format=\"XML\">0 0</DataItem>\n"
      << "     <DataItem Dimensions=\"2\" Format=\"XML\">" << sim.dz() << " " << sim.dx() << "</DataItem>\n"
      << "    </Geometry>\n";
    for (const char* f : kFields)
      x << "    <Attribute Name=\"" << f << "\" AttributeType=\"Scalar\" Center=\"Node\">\n"
        << "     <DataItem Dimensions=\"" << dims << "\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">"
        << h5_name << ":/snapshots/" << snapshot_name(s) << "/" << f << "</DataItem>\n    </Attribute>\n";
    x << "   </Grid>\n";
  }
  x << "  </Grid>\n </Domain>\n</Xdmf>\n";
  return x.str();
}

void write_text_atomically(const std::string& path, const std::string& text) {
  const std::string temporary = path + ".tmp";
  {
    std::ofstream out(temporary, std::ios::trunc);
    out << text;
    if (!out) throw std::runtime_error("cannot write '" + temporary + "'");
  }
  if (std::rename(temporary.c_str(), path.c_str()) != 0)
    throw std::runtime_error("cannot rename '" + temporary + "' to '" + path + "'");
}

}  // namespace

RunResult run_simulation_3d(const SimulationConfig& config, const std::string& output_path,
                            const RunHooks& hooks) {
  using clock = std::chrono::steady_clock;
  Simulation3d sim(config, hooks.stop_requested ? CancelCheck(hooks.stop_requested) : CancelCheck{});
  io::Handle file = io::create_file(output_path);
  io::write_attribute(file, "format", "slipstrip interface_2d");
  io::write_attribute(file, "code_version", code_version);
  io::write_attribute(file, "config", to_toml(config));
  io::write_attribute(file, "status", "running");
  {
    const io::Handle grid = io::create_group(file, "grid");
    std::vector<double> x(sim.nodes_x()), z(sim.nodes_z());
    for (int i = 0; i < sim.nodes_x(); ++i) x[i] = i * sim.dx();
    for (int i = 0; i < sim.nodes_z(); ++i) z[i] = i * sim.dz();
    io::write_vector<double>(grid, "x", x);
    io::write_vector<double>(grid, "z", z);
  }
  io::Handle snapshots = io::create_group(file, "snapshots");
  const auto& out = config.output;
  const double duration = config.time.duration;
  const auto total_steps = static_cast<long long>(std::ceil(duration / sim.time_step() - 1e-9));
  // Time series: one row per timeseries_interval (every step for 0).
  const auto series_every = std::max<long long>(1, std::llround(out.timeseries_interval / sim.time_step()));
  const auto snapshot_every =
      out.snapshot_interval > 0 ? std::max<long long>(1, std::llround(out.snapshot_interval / sim.time_step())) : 0;
  std::vector<double> series_time, series_max_rate, series_mean_slip;
  series_time.reserve(static_cast<std::size_t>(total_steps / series_every + 2));
  series_max_rate.reserve(series_time.capacity());
  series_mean_slip.reserve(series_time.capacity());
  std::vector<double> snapshot_times;
  RunResult result;
  result.time_step = sim.time_step();
  result.status = "completed";
  const auto t0 = clock::now();
  auto last_progress = t0;
  auto record = [&] {
    if (sim.step_index() % series_every == 0) {
      series_time.push_back(sim.time());
      series_max_rate.push_back(sim.max_slip_rate());
      series_mean_slip.push_back(sim.mean_slip_x());
    }
    if (sim.step_index() == 0 || (snapshot_every > 0 && sim.step_index() % snapshot_every == 0)) {
      write_snapshot(snapshots, snapshot_times.size(), sim);
      snapshot_times.push_back(sim.time());
    }
  };
  record();
  while (sim.step_index() < total_steps) {
    if ((hooks.stop_requested && hooks.stop_requested()) ||
        (hooks.stop_after_steps >= 0 && sim.step_index() >= hooks.stop_after_steps)) {
      result.status = "interrupted";
      break;
    }
    try {
      sim.step();
    } catch (const std::runtime_error& e) {
      result.status = std::string("diverged: ") + e.what();
      break;
    }
    record();
    if (hooks.progress) {
      const auto now = clock::now();
      if (std::chrono::duration<double>(now - last_progress).count() >= hooks.progress_interval) {
        last_progress = now;
        hooks.progress({sim.time(), duration, sim.step_index(), sim.max_slip_rate(),
                        std::chrono::duration<double>(now - t0).count()});
      }
    }
  }
  {
    const io::Handle series = io::create_group(file, "timeseries");
    io::write_vector<double>(series, "time", series_time);
    io::write_vector<double>(series, "max_slip_rate", series_max_rate);
    io::write_vector<double>(series, "mean_slip_x", series_mean_slip);
  }
  io::write_vector<double>(snapshots, "time", snapshot_times);
  snapshots.reset();
  io::remove_attribute_if_present(file, "status");
  io::write_attribute(file, "status", result.status);
  io::close_file(file);
  const std::string h5_name = output_path.substr(output_path.find_last_of('/') + 1);
  write_text_atomically(io::xdmf_sidecar_path(output_path), xdmf_text(h5_name, sim, snapshot_times));
  result.steps = sim.step_index();
  result.simulated_time = sim.time();
  result.wall_seconds = std::chrono::duration<double>(clock::now() - t0).count();
  return result;
}

}  // namespace slipstrip
