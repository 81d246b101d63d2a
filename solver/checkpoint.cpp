#include "solver/checkpoint.hpp"

#include <fcntl.h>
#include <hdf5.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <numeric>
#include <stdexcept>

#include "io/attributes.hpp"
#include "io/checksum.hpp"
#include "io/datasets.hpp"
#include "io/hdf5.hpp"
#include "io/messages.hpp"
#include "io/output_paths.hpp"
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
                        s.gap.size() + s.opening_stress.size() +
                        s.slip_z.size() + s.slip_rate_z.size() + s.shear_stress_z.size() + s.speed.size() +
                        c.output.levels_reached.size() +
                        c.output.next_threshold.size() + c.output.rupture_front.size();
  for (const auto& [name, values] : s.history.arrays) doubles += values.size();
  return 8 * doubles;
}

// The z components and the speed of a 2D interface (SimulationState), by
// name; absent (empty) for a one-dimensional interface, whose restart points
// (and their checksums) are unchanged by them.
struct NamedField {
  const char* name;
  std::vector<double> SimulationState::*field;
};
constexpr NamedField kInterface2dFields[] = {{"slip_z", &SimulationState::slip_z},
                                             {"slip_rate_z", &SimulationState::slip_rate_z},
                                             {"shear_stress_z", &SimulationState::shear_stress_z},
                                             {"speed", &SimulationState::speed}};

// A damaged restart point (checksum mismatch): told apart from one HDF5
// cannot read, for the message.
struct DamagedRestartPoint : std::runtime_error {
  using std::runtime_error::runtime_error;
};

void write_file(const std::string& path, const RunCheckpoint& c) {
  Handle file = io::create_file(path);
  io::write_attribute(file, "format", kFormat);
  io::write_attribute(file, "checksum", checkpoint_checksum(c));
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
      io::write_vector(group, "gap", s.gap);
      io::write_vector(group, "opening_stress", s.opening_stress);
    }
    for (const auto& [name, field] : kInterface2dFields)
      if (!(s.*field).empty()) io::write_vector(group, name, s.*field);
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
      // A restart point written before opening was modelled: such a run could
      // not have opened (it stopped), so every node was in contact.
      const bool opening = io::has_member(group, "gap");
      s.gap = opening ? io::read_vector<double>(group, "gap") : std::vector<double>(s.normal_stress.size(), 0.0);
      s.opening_stress = opening ? io::read_vector<double>(group, "opening_stress")
                                 : std::vector<double>(s.normal_stress.size(), 0.0);
    }
    for (const auto& [name, field] : kInterface2dFields)
      if (io::has_member(group, name)) s.*field = io::read_vector<double>(group, name);
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
    // As stored; a negative count is refused below, after the checksum (so
    // that damage is reported as damage).
    const auto count = [&](const char* name) {
      return static_cast<std::uint64_t>(io::read_attribute<std::int64_t>(group, name));
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
  if (io::has_attribute(file, "checksum")) {
    const std::string stored = io::read_string_attribute(file, "checksum");
    const std::string computed = checkpoint_checksum(c);
    if (stored != computed)
      throw DamagedRestartPoint("its content does not match its checksum (stored " + io::quoted_input(stored, 40) +
                                ", computed '" + computed + "'): it was changed after it was written");
    c.checksum_verified = true;
  }
  const auto& o = c.output;
  const std::pair<const char*, std::uint64_t> counts[] = {{"timeseries_rows", o.timeseries_rows},
                                                          {"snapshots", o.snapshots},
                                                          {"station_rows", o.station_rows},
                                                          {"crossing_rows", o.crossing_rows}};
  for (const auto& [name, value] : counts)
    if (static_cast<std::int64_t>(value) < 0)
      throw std::runtime_error(std::string("output/") + name + " = " +
                               std::to_string(static_cast<std::int64_t>(value)) + " < 0");
  return c;
}

// |value - count * step| within the rounding of `count` additions of `step`
// (each rounds by at most half an ulp of the running sum, <= count * step *
// 2^-53; doubled for the product count * step itself).
bool accumulated_sum_matches(double value, std::uint64_t count, double step) {
  const double n = static_cast<double>(count);
  return std::abs(value - n * step) <= (n * n + 1.0) * std::abs(step) * 0x1p-52;
}

std::string number(double value) {
  char buffer[40];
  std::snprintf(buffer, sizeof buffer, "%.10g", value);
  return buffer;
}

}  // namespace

std::string checkpoint_path(const std::string& run_path) { return run_path + ".restart"; }

std::string run_lock_path(const std::string& run_path) { return run_path + ".lock"; }

int restart_point_processes(const RunCheckpoint& checkpoint) {
  const auto& history = checkpoint.simulation.history;
  if (history.kind != kSplitHistoryKind) return 0;
  const long long processes = history.counter("processes");
  if (processes < 1 || processes > std::numeric_limits<int>::max())
    throw std::invalid_argument("restart point: history/counters/processes = " + std::to_string(processes) +
                                ": expected a process count >= 1");
  return static_cast<int>(processes);
}

std::string checkpoint_checksum(const RunCheckpoint& c) {
  io::Checksum sum;
  sum.add("format", std::string_view(kFormat));
  sum.add("config", std::string_view(c.config_toml));
  sum.add("git_hash", std::string_view(c.git_hash));
  const auto& s = c.simulation;
  sum.add("simulation/time", s.time);
  sum.add("simulation/step_index", static_cast<std::int64_t>(s.step_index));
  sum.add<double>("simulation/slip", s.slip);
  sum.add<double>("simulation/slip_rate", s.slip_rate);
  sum.add<double>("simulation/state", s.state);
  sum.add<double>("simulation/shear_stress", s.shear_stress);
  sum.add<double>("simulation/history_stress", s.history_stress);
  for (const auto& [name, field] : kInterface2dFields)
    if (!(s.*field).empty()) sum.add<double>(std::string("simulation/") + name, s.*field);
  const auto& h = s.history;
  sum.add("history/kind", std::string_view(h.kind));
  // By name: HDF5 lists attributes and members by name, not in the order written.
  auto counters = h.counters;
  std::sort(counters.begin(), counters.end());
  for (const auto& [name, value] : counters) sum.add("history/counters/" + name, static_cast<std::int64_t>(value));
  std::vector<const std::pair<std::string, std::vector<double>>*> arrays;
  for (const auto& a : h.arrays) arrays.push_back(&a);
  std::sort(arrays.begin(), arrays.end(), [](auto* a, auto* b) { return a->first < b->first; });
  for (const auto* a : arrays) sum.add<double>("history/arrays/" + a->first, a->second);
  const auto& o = c.output;
  sum.add("output/timeseries_rows", o.timeseries_rows);
  sum.add("output/snapshots", o.snapshots);
  sum.add("output/station_rows", o.station_rows);
  sum.add("output/crossing_rows", o.crossing_rows);
  sum.add("output/slip_recorded", std::int64_t{o.slip_recorded ? 1 : 0});
  sum.add<std::uint64_t>("output/levels_reached", o.levels_reached);
  sum.add<double>("output/next_threshold", o.next_threshold);
  sum.add<double>("output/rupture_front", o.rupture_front);
  sum.add("run/next_timeseries", c.next_timeseries);
  sum.add("run/next_snapshot", c.next_snapshot);
  sum.add("run/next_snapshot_slip", c.next_snapshot_slip);
  sum.add("run/next_station", c.next_station);
  return sum.text();
}

void validate_checkpoint(const RunCheckpoint& c, const SimulationConfig& config, double time_step,
                         long long total_steps, const std::string& run_path) {
  const auto refuse = [&](const std::string& what) {
    throw std::invalid_argument(io::one_line("restart point '" + checkpoint_path(run_path) + "': " + what +
                                             "; it cannot be resumed"));
  };
  const auto& s = c.simulation;
  const long long n = s.step_index;
  if (!std::isfinite(s.time) || s.time < 0.0)
    refuse("simulation/time = " + number(s.time) + " s: expected a finite time >= 0");
  if (n < 0 || n > total_steps)
    refuse("simulation/step_index = " + std::to_string(n) + ": expected 0 <= step <= " +
           std::to_string(total_steps) + " (the run's step count)");
  // t is advanced by t += dt each step (solver/simulation.cpp).
  if (!accumulated_sum_matches(s.time, static_cast<std::uint64_t>(n), time_step))
    refuse("simulation/time = " + number(s.time) + " s does not match simulation/step_index = " +
           std::to_string(n) + " (" + std::to_string(n) + " steps of dt = " + number(time_step) + " s make " +
           number(static_cast<double>(n) * time_step) + " s)");

  // A trigger that fired `rows - 1` times after the record of t = 0 stands at
  // rows * interval (interval 0: every step, and it stays 0); the last record
  // cannot be in the future, and with dt <= interval none can be missing.
  const auto check_trigger = [&](const char* name, double next, std::uint64_t rows, double interval,
                                 const char* rows_name, const char* key) {
    const auto expected = number(static_cast<double>(rows) * interval);
    const std::string why = std::string(" (output/") + rows_name + " = " + std::to_string(rows) + " records of " +
                            key + " = " + number(interval) + " s)";
    if (!std::isfinite(next) || !accumulated_sum_matches(next, rows, interval))
      refuse(std::string("run/") + name + " = " + number(next) + ": expected " + expected + why);
    // Interval 0: a record at t = 0 and one after every step.
    if (interval == 0.0 && rows != static_cast<std::uint64_t>(n) + 1)
      refuse(std::string("output/") + rows_name + " = " + std::to_string(rows) + ": expected " +
             std::to_string(n + 1) + " (a record at t = 0 and one per step with " + key + " = 0, at step " +
             std::to_string(n) + ")");
    if (interval > 0.0 && rows >= 1 && (next - interval) * (1 - 1e-12) > s.time * (1 + 0x1p-50))
      refuse(std::string("run/") + name + " = " + number(next) + ": its last record lies after simulation/time = " +
             number(s.time) + " s" + why);
    if (interval > 0.0 && time_step <= interval && next + time_step < s.time)
      refuse(std::string("run/") + name + " = " + number(next) + ": records are missing before simulation/time = " +
             number(s.time) + " s" + why);
  };
  const auto& out = config.output;
  const auto& o = c.output;
  check_trigger("next_timeseries", c.next_timeseries, o.timeseries_rows, out.timeseries_interval,
                "timeseries_rows", "output.timeseries_interval");
  if (out.snapshot_interval > 0.0 && out.snapshot_slip_increment == 0.0) {
    check_trigger("next_snapshot", c.next_snapshot, o.snapshots, out.snapshot_interval, "snapshots",
                  "output.snapshot_interval");
  } else if (out.snapshot_interval > 0.0) {
    // Snapshots by time and by slip share one count: only its bound is known.
    if (!std::isfinite(c.next_snapshot) || c.next_snapshot < out.snapshot_interval ||
        c.next_snapshot - static_cast<double>(o.snapshots) * out.snapshot_interval >
            (static_cast<double>(o.snapshots) * static_cast<double>(o.snapshots) + 1.0) * out.snapshot_interval *
                0x1p-52)  // the rounding bound of accumulated_sum_matches
      refuse("run/next_snapshot = " + number(c.next_snapshot) + ": expected a multiple of output.snapshot_interval = " +
             number(out.snapshot_interval) + " s between one and output/snapshots = " + std::to_string(o.snapshots));
  } else if (c.next_snapshot != out.snapshot_interval) {
    refuse("run/next_snapshot = " + number(c.next_snapshot) + ": expected " + number(out.snapshot_interval) +
           " (snapshots by time are off)");
  }
  if (out.snapshot_slip_increment > 0.0) {
    // The next slip level of a slip-triggered snapshot lies above the mean
    // slip (solver/run.cpp next_slip_trigger), computed as the solver does.
    const double mean_slip =
        s.slip.empty() ? 0.0 : std::accumulate(s.slip.begin(), s.slip.end(), 0.0) / static_cast<double>(s.slip.size());
    if (!std::isfinite(c.next_snapshot_slip) || (out.snapshot_interval == 0.0 && !(c.next_snapshot_slip > mean_slip)))
      refuse("run/next_snapshot_slip = " + number(c.next_snapshot_slip) +
             " m: expected a finite slip above the mean slip " + number(mean_slip) + " m");
  } else if (c.next_snapshot_slip != out.snapshot_slip_increment) {
    refuse("run/next_snapshot_slip = " + number(c.next_snapshot_slip) + ": expected " +
           number(out.snapshot_slip_increment) + " (snapshots by slip are off)");
  }
  if (!out.stations.empty()) {
    check_trigger("next_station", c.next_station, o.station_rows, out.station_interval, "station_rows",
                  "output.station_interval");
  } else if (c.next_station != out.station_interval) {
    refuse("run/next_station = " + number(c.next_station) + ": expected " + number(out.station_interval) +
           " (no stations)");
  }

  // Slip sampling (solver/slip_sampler.cpp): a node that reached k levels
  // waits for level k + 1 at exactly (k + 1) delta_th, which its slip has not
  // reached (else it would have been recorded in the step); crossing_time has
  // as many rows as the highest level reached; the initial slip is checked in
  // the first step.  Sizes are checked where they are used (RunOutput).
  const std::size_t nodes = s.slip.size();
  if (out.delta_th > 0.0 && o.levels_reached.size() == nodes && o.next_threshold.size() == nodes) {
    std::uint64_t highest = 0;
    for (std::size_t i = 0; i < nodes; ++i) {
      const std::uint64_t k = o.levels_reached[i];
      highest = std::max(highest, k);
      const double expected = static_cast<double>(k + 1) * out.delta_th;
      if (o.next_threshold[i] != expected)
        refuse("output/next_threshold[" + std::to_string(i) + "] = " + number(o.next_threshold[i]) +
               " m: expected " + number(expected) + " m (output/levels_reached[" + std::to_string(i) +
               "] = " + std::to_string(k) + " levels of output.delta_th = " + number(out.delta_th) + " m reached)");
      if (!(s.slip[i] < expected))
        refuse("output/levels_reached[" + std::to_string(i) + "] = " + std::to_string(k) +
               ": simulation/slip[" + std::to_string(i) + "] = " + number(s.slip[i]) + " m has passed level " +
               std::to_string(k + 1) + " at " + number(expected) + " m");
    }
    if (o.crossing_rows != highest)
      refuse("output/crossing_rows = " + std::to_string(o.crossing_rows) + ": expected " + std::to_string(highest) +
             " (the highest of output/levels_reached)");
    if (o.slip_recorded != (n > 0))
      refuse(std::string("output/slip_recorded = ") + (o.slip_recorded ? "1" : "0") + ": expected " +
             (n > 0 ? "1" : "0") + " at step " + std::to_string(n));
  } else if (out.delta_th == 0.0 && (o.crossing_rows != 0 || o.slip_recorded)) {
    refuse("output/crossing_rows = " + std::to_string(o.crossing_rows) + ", output/slip_recorded = " +
           (o.slip_recorded ? "1" : "0") + ": expected 0 and 0 (slip sampling is off, output.delta_th = 0)");
  }
  // First arrivals of the rupture front: never after the restart point's time.
  for (std::size_t i = 0; i < o.rupture_front.size(); ++i) {
    const double t = o.rupture_front[i];
    if (!std::isnan(t) && !(t >= 0.0 && t <= s.time))
      refuse("output/rupture_front[" + std::to_string(i) + "] = " + number(t) +
             " s: expected NaN (not arrived) or a time in [0, simulation/time = " + number(s.time) + " s]");
  }
}

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
  if (const std::string what = io::not_a_regular_file(path); !what.empty()) {
    throw std::invalid_argument(io::one_line(
        "'" + run_path + "' has no restart point: '" + path + "' " + what +
        (what == "does not exist" ? " (written every output.checkpoint_interval s of wall time and when "
                                    "SIGTERM/SIGINT stops a run)"
                                  : "")));
  }
  const auto unreadable = [&](const std::exception& e) {
    return std::invalid_argument(io::one_line("restart point '" + path + "' cannot be read: " + e.what()));
  };
  try {
    return read_file(path);
  } catch (const DamagedRestartPoint& e) {
    throw std::invalid_argument(io::one_line("restart point '" + path + "' is damaged: " + e.what() +
                                             "; it cannot be resumed (run again from t = 0)"));
  } catch (const std::runtime_error& e) {
    throw unreadable(e);  // HDF5 cannot read it, or it is not a restart point
  } catch (const std::invalid_argument& e) {
    throw unreadable(e);  // a record is missing or has the wrong shape or type
  }
}

RunFileHeader read_run_file_header(const std::string& run_path) {
  if (const std::string what = io::not_a_regular_file(run_path); !what.empty())
    throw std::invalid_argument(io::one_line("run file '" + run_path + "' " + what));
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
