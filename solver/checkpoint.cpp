#include "solver/checkpoint.hpp"

#include <fcntl.h>
#include <hdf5.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "io/attributes.hpp"
#include "io/datasets.hpp"
#include "io/hdf5.hpp"
#include "slipstrip/version.hpp"

namespace slipstrip {
namespace {

using io::Handle;

// Identifies the layout below; a reader refuses any other.
constexpr const char* kFormat = "slipstrip restart point";
constexpr double kFormatVersion = 1.0;

// fsync of a file or directory by path; throws with errno's text.
void sync_path(const std::string& path, int flags) {
  const int fd = ::open(path.c_str(), flags);
  if (fd < 0) throw std::runtime_error("open(" + path + ") for fsync: " + std::strerror(errno));
  const int status = ::fsync(fd);
  const int err = errno;
  ::close(fd);
  if (status != 0) throw std::runtime_error("fsync(" + path + "): " + std::strerror(err));
}

std::string directory_of(const std::string& path) {
  const std::filesystem::path p(path);
  return p.has_parent_path() ? p.parent_path().string() : ".";
}

std::size_t state_bytes(const RunCheckpoint& c) {
  const auto& s = c.simulation;
  std::size_t doubles = s.slip.size() + s.slip_rate.size() + s.state.size() + s.shear_stress.size() +
                        s.history_stress.size() + s.normal_stress.size() + s.effective_normal_stress.size() +
                        c.output.levels_reached.size() +
                        c.output.next_threshold.size() + c.output.rupture_front.size();
  for (const auto& [name, values] : s.history.arrays) doubles += values.size();
  return 8 * doubles;
}

void write_file(const std::string& path, const RunCheckpoint& c) {
  Handle file = io::create_file(path);
  io::write_attribute(file, "format", kFormat);
  io::write_attribute(file, "format_version", kFormatVersion);
  io::write_attribute(file, "config", c.config_toml);
  io::write_attribute(file, "code_version", slipstrip::code_version);
  io::write_attribute(file, "git_hash", c.git_hash);
  io::write_attribute(file, "written_at", utc_now_iso8601());
  {
    const auto& s = c.simulation;
    Handle group = io::create_group(file, "simulation");
    io::write_attribute(group, "time", s.time);
    io::write_attribute(group, "step_index", static_cast<std::int64_t>(s.step_index));
    io::write_vector(group, "slip", s.slip);
    io::write_vector(group, "slip_rate", s.slip_rate);
    io::write_vector(group, "state", s.state);
    io::write_vector(group, "shear_stress", s.shear_stress);
    io::write_vector(group, "history_stress", s.history_stress);
    // In-plane dissimilar bodies only (a varying normal stress).
    if (!s.normal_stress.empty()) {
      io::write_vector(group, "normal_stress", s.normal_stress);
      io::write_vector(group, "effective_normal_stress", s.effective_normal_stress);
    }
  }
  {
    const auto& h = c.simulation.history;
    Handle group = io::create_group(file, "history");
    io::write_attribute(group, "kind", h.kind);
    Handle counters = io::create_group(group, "counters");
    for (const auto& [name, value] : h.counters) io::write_attribute(counters, name, static_cast<std::int64_t>(value));
    Handle arrays = io::create_group(group, "arrays");
    for (const auto& [name, values] : h.arrays) io::write_vector(arrays, name, values);
  }
  {
    const auto& o = c.output;
    Handle group = io::create_group(file, "output");
    io::write_attribute(group, "timeseries_rows", static_cast<std::int64_t>(o.timeseries_rows));
    io::write_attribute(group, "snapshots", static_cast<std::int64_t>(o.snapshots));
    io::write_attribute(group, "station_rows", static_cast<std::int64_t>(o.station_rows));
    io::write_attribute(group, "crossing_rows", static_cast<std::int64_t>(o.crossing_rows));
    io::write_attribute(group, "slip_recorded", std::int64_t{o.slip_recorded ? 1 : 0});
    io::write_vector(group, "levels_reached", o.levels_reached);
    io::write_vector(group, "next_threshold", o.next_threshold);
    io::write_vector(group, "rupture_front", o.rupture_front);
  }
  {
    Handle group = io::create_group(file, "run");
    io::write_attribute(group, "next_timeseries", c.next_timeseries);
    io::write_attribute(group, "next_snapshot", c.next_snapshot);
    io::write_attribute(group, "next_snapshot_slip", c.next_snapshot_slip);
    io::write_attribute(group, "next_station", c.next_station);
  }
  io::close_file(file);
}

RunCheckpoint read_file(const std::string& path) {
  const Handle file = io::open_file(path, io::FileAccess::read_only);
  if (!io::has_attribute(file, "format") || io::read_string_attribute(file, "format") != kFormat)
    throw std::runtime_error("not a slipstrip restart point (no 'format' attribute \"" + std::string(kFormat) + "\")");
  const double version = io::read_attribute<double>(file, "format_version");
  if (version != kFormatVersion)
    throw std::runtime_error("format_version " + std::to_string(version) + ", this binary reads " +
                             std::to_string(kFormatVersion));
  RunCheckpoint c;
  c.config_toml = io::read_string_attribute(file, "config");
  c.git_hash = io::read_string_attribute(file, "git_hash");
  {
    auto& s = c.simulation;
    Handle group = io::open_group(file, "simulation");
    s.time = io::read_attribute<double>(group, "time");
    s.step_index = io::read_attribute<std::int64_t>(group, "step_index");
    s.slip = io::read_vector<double>(group, "slip");
    s.slip_rate = io::read_vector<double>(group, "slip_rate");
    s.state = io::read_vector<double>(group, "state");
    s.shear_stress = io::read_vector<double>(group, "shear_stress");
    s.history_stress = io::read_vector<double>(group, "history_stress");
    if (io::has_member(group, "normal_stress")) {
      s.normal_stress = io::read_vector<double>(group, "normal_stress");
      s.effective_normal_stress = io::read_vector<double>(group, "effective_normal_stress");
    }
  }
  {
    auto& h = c.simulation.history;
    Handle group = io::open_group(file, "history");
    h.kind = io::read_string_attribute(group, "kind");
    Handle counters = io::open_group(group, "counters");
    for (const auto& name : io::attribute_names(counters))
      h.counters.emplace_back(name, io::read_attribute<std::int64_t>(counters, name));
    Handle arrays = io::open_group(group, "arrays");
    for (const auto& name : io::member_names(arrays)) h.arrays.emplace_back(name, io::read_vector<double>(arrays, name));
  }
  {
    auto& o = c.output;
    Handle group = io::open_group(file, "output");
    const auto count = [&](const char* name) {
      const std::int64_t v = io::read_attribute<std::int64_t>(group, name);
      if (v < 0) throw std::runtime_error(std::string("output/") + name + " = " + std::to_string(v) + " < 0");
      return static_cast<std::uint64_t>(v);
    };
    o.timeseries_rows = count("timeseries_rows");
    o.snapshots = count("snapshots");
    o.station_rows = count("station_rows");
    o.crossing_rows = count("crossing_rows");
    o.slip_recorded = count("slip_recorded") != 0;
    o.levels_reached = io::read_vector<std::uint64_t>(group, "levels_reached");
    o.next_threshold = io::read_vector<double>(group, "next_threshold");
    o.rupture_front = io::read_vector<double>(group, "rupture_front");
  }
  {
    Handle group = io::open_group(file, "run");
    c.next_timeseries = io::read_attribute<double>(group, "next_timeseries");
    c.next_snapshot = io::read_attribute<double>(group, "next_snapshot");
    c.next_snapshot_slip = io::read_attribute<double>(group, "next_snapshot_slip");
    c.next_station = io::read_attribute<double>(group, "next_station");
  }
  return c;
}

}  // namespace

std::string checkpoint_path(const std::string& run_path) { return run_path + ".restart"; }

void write_checkpoint(const std::string& run_path, const RunCheckpoint& checkpoint) {
  const std::string target = checkpoint_path(run_path);
  const std::string temporary = target + ".tmp";
  try {
    // The records the cursors point to reach the disk before the restart
    // point that names them (matters for a power loss, not for a kill: the
    // page cache survives a killed process).
    sync_path(run_path, O_RDONLY);
    // Refused before writing: HDF5 running out of space half-way is what
    // crashed at exit before (docs/reliability.md).
    require_free_space(target, static_cast<double>(state_bytes(checkpoint)) + 1024.0 * 1024.0,
                       "the restart point");
    write_file(temporary, checkpoint);
    sync_path(temporary, O_RDONLY);
    if (std::rename(temporary.c_str(), target.c_str()) != 0)
      throw std::runtime_error("rename(" + temporary + ", " + target + "): " + std::strerror(errno));
    sync_path(directory_of(target), O_RDONLY | O_DIRECTORY);
  } catch (const std::runtime_error& e) {
    std::remove(temporary.c_str());
    throw OutputError("writing the restart point '" + target + "' failed: " + e.what() +
                      "; the previous restart point (if any) is kept");
  }
}

RunCheckpoint read_checkpoint(const std::string& run_path) {
  const std::string path = checkpoint_path(run_path);
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw std::invalid_argument("'" + run_path + "' has no restart point: '" + path +
                                "' does not exist (written every output.checkpoint_interval s of wall "
                                "time and when SIGTERM/SIGINT stops a run)");
  const auto unreadable = [&](const std::exception& e) {
    return std::invalid_argument("restart point '" + path + "' cannot be read: " + e.what());
  };
  try {
    return read_file(path);
  } catch (const std::runtime_error& e) {
    throw unreadable(e);  // HDF5 cannot read it, or it is not a restart point
  } catch (const std::invalid_argument& e) {
    throw unreadable(e);  // a record is missing or has the wrong shape or type
  }
}

RunFileHeader read_run_file_header(const std::string& run_path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(run_path, ec))
    throw std::invalid_argument("run file '" + run_path + "' does not exist or is not a regular file");
  const auto unreadable = [&](const std::exception& e) {
    return std::invalid_argument("run file '" + run_path + "' cannot be read: " + e.what());
  };
  try {
    const Handle file = io::open_file(run_path, io::FileAccess::read_only);
    return {io::read_string_attribute(file, "status"), io::read_string_attribute(file, "config")};
  } catch (const std::runtime_error& e) {
    throw unreadable(e);
  } catch (const std::invalid_argument& e) {
    throw unreadable(e);
  }
}

void remove_checkpoint(const std::string& run_path) {
  const std::string path = checkpoint_path(run_path);
  std::remove(path.c_str());
  std::remove((path + ".tmp").c_str());
}

}  // namespace slipstrip
