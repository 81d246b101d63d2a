#include "core/checkpoint.hpp"

#include <fcntl.h>
#include <hdf5.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <stdexcept>

#include "core/hdf5_handle.hpp"
#include "slipstrip/version.hpp"

namespace slipstrip {
namespace {

using hdf5::check;
using hdf5::Handle;

// Identifies the layout below; a reader refuses any other.
constexpr const char* kFormat = "slipstrip restart point";
constexpr double kFormatVersion = 1.0;

void write_integer_attribute(hid_t object, const std::string& name, std::int64_t value) {
  hdf5::remove_attribute_if_present(object, name);
  Handle space(H5Screate(H5S_SCALAR), "H5Screate");
  Handle attr(H5Acreate2(object, name.c_str(), H5T_STD_I64LE, space, H5P_DEFAULT, H5P_DEFAULT),
              "H5Acreate2(" + name + ")");
  check(H5Awrite(attr, H5T_NATIVE_INT64, &value), "H5Awrite(" + name + ")");
}

std::int64_t read_integer_attribute(hid_t object, const std::string& name) {
  Handle attr(H5Aopen(object, name.c_str(), H5P_DEFAULT), "H5Aopen(" + name + ")");
  std::int64_t value = 0;
  check(H5Aread(attr, H5T_NATIVE_INT64, &value), "H5Aread(" + name + ")");
  return value;
}

double read_double_attribute(hid_t object, const std::string& name) {
  Handle attr(H5Aopen(object, name.c_str(), H5P_DEFAULT), "H5Aopen(" + name + ")");
  double value = 0.0;
  check(H5Aread(attr, H5T_NATIVE_DOUBLE, &value), "H5Aread(" + name + ")");
  return value;
}

template <class T>
hid_t file_type() {
  if constexpr (std::is_same_v<T, double>) return H5T_IEEE_F64LE;
  else return H5T_STD_U64LE;
}
template <class T>
hid_t memory_type() {
  if constexpr (std::is_same_v<T, double>) return H5T_NATIVE_DOUBLE;
  else return H5T_NATIVE_UINT64;
}

template <class T>
void write_vector(hid_t group, const std::string& name, const std::vector<T>& values) {
  const hsize_t dims[1] = {values.size()};
  Handle space(H5Screate_simple(1, dims, nullptr), "H5Screate_simple(" + name + ")");
  Handle dset(H5Dcreate2(group, name.c_str(), file_type<T>(), space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
              "H5Dcreate2(" + name + ")");
  if (!values.empty())
    check(H5Dwrite(dset, memory_type<T>(), H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()),
          "H5Dwrite(" + name + ")");
}

template <class T>
std::vector<T> read_vector(hid_t group, const std::string& name) {
  Handle dset(H5Dopen2(group, name.c_str(), H5P_DEFAULT), "H5Dopen2(" + name + ")");
  Handle space(H5Dget_space(dset), "H5Dget_space(" + name + ")");
  if (H5Sget_simple_extent_ndims(space) != 1) throw std::runtime_error(name + " is not a 1-D dataset");
  hsize_t dims[1] = {0};
  check(H5Sget_simple_extent_dims(space, dims, nullptr), "H5Sget_simple_extent_dims(" + name + ")");
  std::vector<T> values(dims[0]);
  if (!values.empty())
    check(H5Dread(dset, memory_type<T>(), H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()),
          "H5Dread(" + name + ")");
  return values;
}

Handle create_group(hid_t parent, const char* name) {
  return Handle(H5Gcreate2(parent, name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                std::string("H5Gcreate2(") + name + ")");
}
Handle open_group(hid_t parent, const char* name) {
  return Handle(H5Gopen2(parent, name, H5P_DEFAULT), std::string("H5Gopen2(") + name + ")");
}

std::string now_iso8601() {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm utc{};
  gmtime_r(&now, &utc);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return text;
}

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
                        s.history_stress.size() + c.output.levels_reached.size() +
                        c.output.next_threshold.size() + c.output.rupture_front.size();
  for (const auto& [name, values] : s.history.arrays) doubles += values.size();
  return 8 * doubles;
}

void write_file(const std::string& path, const RunCheckpoint& c) {
  Handle file(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), "H5Fcreate(" + path + ")");
  hdf5::write_attribute(file, "format", std::string(kFormat));
  hdf5::write_attribute(file, "format_version", kFormatVersion);
  hdf5::write_attribute(file, "config", c.config_toml);
  hdf5::write_attribute(file, "code_version", std::string(slipstrip::code_version));
  hdf5::write_attribute(file, "git_hash", c.git_hash);
  hdf5::write_attribute(file, "written_at", now_iso8601());
  {
    const auto& s = c.simulation;
    Handle group = create_group(file, "simulation");
    hdf5::write_attribute(group, "time", s.time);
    write_integer_attribute(group, "step_index", s.step_index);
    write_vector(group, "slip", s.slip);
    write_vector(group, "slip_rate", s.slip_rate);
    write_vector(group, "state", s.state);
    write_vector(group, "shear_stress", s.shear_stress);
    write_vector(group, "history_stress", s.history_stress);
  }
  {
    const auto& h = c.simulation.history;
    Handle group = create_group(file, "history");
    hdf5::write_attribute(group, "kind", h.kind);
    Handle counters = create_group(group, "counters");
    for (const auto& [name, value] : h.counters) write_integer_attribute(counters, name, value);
    Handle arrays = create_group(group, "arrays");
    for (const auto& [name, values] : h.arrays) write_vector(arrays, name, values);
  }
  {
    const auto& o = c.output;
    Handle group = create_group(file, "output");
    write_integer_attribute(group, "timeseries_rows", static_cast<std::int64_t>(o.timeseries_rows));
    write_integer_attribute(group, "snapshots", static_cast<std::int64_t>(o.snapshots));
    write_integer_attribute(group, "station_rows", static_cast<std::int64_t>(o.station_rows));
    write_integer_attribute(group, "crossing_rows", static_cast<std::int64_t>(o.crossing_rows));
    write_integer_attribute(group, "slip_recorded", o.slip_recorded ? 1 : 0);
    write_vector(group, "levels_reached", o.levels_reached);
    write_vector(group, "next_threshold", o.next_threshold);
    write_vector(group, "rupture_front", o.rupture_front);
  }
  {
    Handle group = create_group(file, "run");
    hdf5::write_attribute(group, "next_timeseries", c.next_timeseries);
    hdf5::write_attribute(group, "next_snapshot", c.next_snapshot);
    hdf5::write_attribute(group, "next_snapshot_slip", c.next_snapshot_slip);
    hdf5::write_attribute(group, "next_station", c.next_station);
  }
  // Closed explicitly: H5Fclose writes the metadata, and its failure must not go unnoticed.
  check(H5Fclose(file.release()), "H5Fclose(" + path + ")");
}

std::vector<std::string> member_names(hid_t group) {
  std::vector<std::string> names;
  check(H5Literate(group, H5_INDEX_NAME, H5_ITER_INC, nullptr,
                   [](hid_t, const char* name, const H5L_info_t*, void* data) -> herr_t {
                     static_cast<std::vector<std::string>*>(data)->emplace_back(name);
                     return 0;
                   },
                   &names),
        "H5Literate");
  return names;
}

std::vector<std::string> attribute_names(hid_t object) {
  std::vector<std::string> names;
  check(H5Aiterate2(object, H5_INDEX_NAME, H5_ITER_INC, nullptr,
                    [](hid_t, const char* name, const H5A_info_t*, void* data) -> herr_t {
                      static_cast<std::vector<std::string>*>(data)->emplace_back(name);
                      return 0;
                    },
                    &names),
        "H5Aiterate2");
  return names;
}

RunCheckpoint read_file(const std::string& path) {
  Handle file(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), "H5Fopen(" + path + ")");
  if (H5Aexists(file, "format") <= 0 || hdf5::read_string_attribute(file, "format") != kFormat)
    throw std::runtime_error("not a slipstrip restart point (no 'format' attribute \"" + std::string(kFormat) + "\")");
  const double version = read_double_attribute(file, "format_version");
  if (version != kFormatVersion)
    throw std::runtime_error("format_version " + std::to_string(version) + ", this binary reads " +
                             std::to_string(kFormatVersion));
  RunCheckpoint c;
  c.config_toml = hdf5::read_string_attribute(file, "config");
  c.git_hash = hdf5::read_string_attribute(file, "git_hash");
  {
    auto& s = c.simulation;
    Handle group = open_group(file, "simulation");
    s.time = read_double_attribute(group, "time");
    s.step_index = read_integer_attribute(group, "step_index");
    s.slip = read_vector<double>(group, "slip");
    s.slip_rate = read_vector<double>(group, "slip_rate");
    s.state = read_vector<double>(group, "state");
    s.shear_stress = read_vector<double>(group, "shear_stress");
    s.history_stress = read_vector<double>(group, "history_stress");
  }
  {
    auto& h = c.simulation.history;
    Handle group = open_group(file, "history");
    h.kind = hdf5::read_string_attribute(group, "kind");
    Handle counters = open_group(group, "counters");
    for (const auto& name : attribute_names(counters))
      h.counters.emplace_back(name, read_integer_attribute(counters, name));
    Handle arrays = open_group(group, "arrays");
    for (const auto& name : member_names(arrays)) h.arrays.emplace_back(name, read_vector<double>(arrays, name));
  }
  {
    auto& o = c.output;
    Handle group = open_group(file, "output");
    const auto count = [&](const char* name) {
      const std::int64_t v = read_integer_attribute(group, name);
      if (v < 0) throw std::runtime_error(std::string("output/") + name + " = " + std::to_string(v) + " < 0");
      return static_cast<std::uint64_t>(v);
    };
    o.timeseries_rows = count("timeseries_rows");
    o.snapshots = count("snapshots");
    o.station_rows = count("station_rows");
    o.crossing_rows = count("crossing_rows");
    o.slip_recorded = count("slip_recorded") != 0;
    o.levels_reached = read_vector<std::uint64_t>(group, "levels_reached");
    o.next_threshold = read_vector<double>(group, "next_threshold");
    o.rupture_front = read_vector<double>(group, "rupture_front");
  }
  {
    Handle group = open_group(file, "run");
    c.next_timeseries = read_double_attribute(group, "next_timeseries");
    c.next_snapshot = read_double_attribute(group, "next_snapshot");
    c.next_snapshot_slip = read_double_attribute(group, "next_snapshot_slip");
    c.next_station = read_double_attribute(group, "next_station");
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
    const std::string dir = directory_of(target);
    struct statvfs fs {};
    if (::statvfs(dir.c_str(), &fs) == 0) {
      // Refused before writing: HDF5 running out of space half-way is what
      // crashed at exit before (docs/reliability.md).
      const double available = static_cast<double>(fs.f_bavail) * static_cast<double>(fs.f_frsize);
      const double needed = static_cast<double>(state_bytes(checkpoint)) + 1024.0 * 1024.0;
      if (available < needed) {
        char text[200];
        std::snprintf(text, sizeof text,
                      "No space left on device (%.0f bytes free in '%s', the restart point needs about %.0f)",
                      available, dir.c_str(), needed);
        throw std::runtime_error(text);
      }
    }
    write_file(temporary, checkpoint);
    sync_path(temporary, O_RDONLY);
    if (std::rename(temporary.c_str(), target.c_str()) != 0)
      throw std::runtime_error("rename(" + temporary + ", " + target + "): " + std::strerror(errno));
    sync_path(dir, O_RDONLY | O_DIRECTORY);
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
  try {
    return read_file(path);
  } catch (const std::runtime_error& e) {
    throw std::invalid_argument("restart point '" + path + "' cannot be read: " + e.what());
  }
}

RunFileHeader read_run_file_header(const std::string& run_path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(run_path, ec))
    throw std::invalid_argument("run file '" + run_path + "' does not exist or is not a regular file");
  try {
    Handle file(H5Fopen(run_path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), "H5Fopen(" + run_path + ")");
    return {hdf5::read_string_attribute(file, "status"), hdf5::read_string_attribute(file, "config")};
  } catch (const std::runtime_error& e) {
    throw std::invalid_argument("run file '" + run_path + "' cannot be read: " + e.what());
  }
}

void remove_checkpoint(const std::string& run_path) {
  const std::string path = checkpoint_path(run_path);
  std::remove(path.c_str());
  std::remove((path + ".tmp").c_str());
}

}  // namespace slipstrip
