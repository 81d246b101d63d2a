#include "solver/run_output.hpp"

#include <sstream>

#include <fcntl.h>
#include <hdf5.h>
#include <sys/file.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <limits>
#include <stdexcept>

#include "events/catalog_io.hpp"
#include "io/attributes.hpp"
#include "io/datasets.hpp"
#include "io/hdf5.hpp"
#include "io/xdmf.hpp"
#include "slipstrip/version.hpp"

namespace slipstrip {
namespace {

using io::Handle;

constexpr double nan_value = std::numeric_limits<double>::quiet_NaN();

// The sixth, opening, only with RunOutputOptions::normal_stress_snapshots.
constexpr const char* station_field_names[6] = {"slip", "slip_rate", "shear_stress", "state",
                                                "normal_stress", "opening"};
constexpr const char* station_field_units[6] = {"m", "m/s", "Pa", "s", "Pa", "m"};
constexpr std::size_t station_buffer_rows = 1024;
// The fifth, loading_shear_stress, only with RunOutputOptions::loading_shear_stress.
constexpr const char* timeseries_names[5] = {"time", "max_slip_rate", "mean_slip",
                                             "mean_shear_stress", "loading_shear_stress"};
constexpr const char* timeseries_units[5] = {"s", "m/s", "m", "Pa", "Pa"};
// The fifth and sixth, normal_stress and opening (the gap), only with
// RunOutputOptions::normal_stress_snapshots.
constexpr const char* snapshot_names[6] = {"slip", "slip_rate", "state", "shear_stress", "normal_stress",
                                           "opening"};
constexpr const char* snapshot_units[6] = {"m", "m/s", "s", "Pa", "Pa", "m"};

constexpr const char* units_table =
    "SI units throughout; every dataset also carries a 'units' attribute.\n"
    "time, crossing_time: s\n"
    "slip, mean_slip, x, delta_th, dx, D, L: m\n"
    "slip_rate, max_slip_rate, v0: m/s\n"
    "state (contact age phi): s\n"
    "shear_stress, mean_shear_stress, loading_shear_stress, mu: Pa\n";

}  // namespace

std::string utc_now_iso8601() {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm utc{};
  gmtime_r(&now, &utc);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return text;
}

namespace {

// True if another process holds a lock on `path` (a reader has it open).
bool locked_by_other_process(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY);
  if (fd < 0) return false;
  const bool busy = ::flock(fd, LOCK_EX | LOCK_NB) != 0 && errno == EWOULDBLOCK;
  ::close(fd);  // also drops our lock if we got it
  return busy;
}

// Opens for appending; an invalid Handle means a reader holds the file (only
// possible with use_locking).  Any other failure throws.  File locks are what
// keep a reader consistent: h5py holds a shared lock on the file while it is
// open, and the writer asks for an exclusive one, so it never changes the
// file under an open reader.
Handle open_for_append(const std::string& path, bool use_locking) {
  const Handle fapl = io::file_access_list(use_locking);
  hid_t id = H5I_INVALID_HID;
  H5E_BEGIN_TRY { id = H5Fopen(path.c_str(), H5F_ACC_RDWR, fapl); }
  H5E_END_TRY;
  if (id >= 0) return Handle(id);
  if (use_locking && locked_by_other_process(path)) return Handle();
  return io::open_file(path, io::FileAccess::read_write, fapl);
}

// Every dataset of the run file carries a "units" attribute.
void write_units(hid_t group, const std::string& name, const std::string& units) {
  io::write_attribute(io::open_dataset(group, name), "units", units);
}

// Extendible float64 dataset (io::ExtendibleLayout) with its units.  The
// time series, stations and crossing times are uncompressed, because every
// write-out rewrites the last, partial chunk: a compressed chunk would be
// reallocated and the old space lost once the file is closed.
void create_extendible(hid_t group, const std::string& name, const io::ExtendibleLayout& layout,
                       const std::string& units) {
  const io::Handle dataset = io::create_extendible(group, name, layout);
  io::write_attribute(dataset, "units", units);
}

void write_fixed_vector(hid_t group, const std::string& name, std::span<const double> values,
                        const std::string& units) {
  io::write_vector(group, name, values);
  write_units(group, name, units);
}

// The names and the units of fields given as (name, units) pairs.
void split_fields(const std::vector<std::pair<std::string, std::string>>& fields, std::vector<std::string>& names,
                  std::vector<std::string>& units) {
  for (const auto& [name, unit] : fields) {
    names.push_back(name);
    units.push_back(unit);
  }
}

void require_positive(int value, const char* name) {
  if (value < 1)
    throw std::invalid_argument(std::string("RunOutputOptions.") + name + " = " +
                                std::to_string(value) + ": must be >= 1");
}

}  // namespace

RunOutput::RunOutput(const std::string& path, const std::string& config_toml,
                     const SlipSamplingSetup& slip_sampling, RunOutputOptions options)
    : path_(path), node_count_(slip_sampling.x.size()), options_(options) {
  initialise_buffers(slip_sampling);
  try {
    create_file(config_toml, slip_sampling);
  } catch (const std::runtime_error& e) {
    failed_ = closed_ = true;
    throw OutputError("cannot create the run file '" + path + "': " + e.what());
  }
}

RunOutput::RunOutput(const std::string& path, const RunOutputCursor& cursor,
                     const SlipSamplingSetup& slip_sampling, RunOutputOptions options)
    : path_(path), node_count_(slip_sampling.x.size()), options_(options) {
  initialise_buffers(slip_sampling);
  const auto per_node = [&](std::size_t size, std::size_t expected, const char* what) {
    if (size != expected)
      throw std::invalid_argument("restart point: " + std::string(what) + " has " + std::to_string(size) +
                                  " values, the run has " + std::to_string(expected));
  };
  per_node(cursor.levels_reached.size(), slip_sampler_ ? node_count_ : 0, "levels_reached");
  per_node(cursor.next_threshold.size(), slip_sampler_ ? node_count_ : 0, "next_threshold");
  per_node(cursor.rupture_front.size(), rupture_front_.size(), "rupture_front");
  const auto refuse = [&](const std::exception& e) {
    failed_ = closed_ = true;
    return std::invalid_argument("cannot resume the run file '" + path + "': " + e.what());
  };
  try {
    reopen_file(cursor);
  } catch (const std::runtime_error& e) {
    throw refuse(e);  // an HDF5 failure
  } catch (const std::invalid_argument& e) {
    throw refuse(e);  // a missing or malformed record
  }
}

void RunOutput::initialise_buffers(const SlipSamplingSetup& slip_sampling) {
  if (node_count_ == 0)
    throw std::invalid_argument("SlipSamplingSetup.x: node positions are empty; need N >= 1 nodes");
  if (!(slip_sampling.delta_th >= 0.0) || !std::isfinite(slip_sampling.delta_th))
    throw std::invalid_argument("output.delta_th = " + std::to_string(slip_sampling.delta_th) +
                                ": must be finite and >= 0 (0 = slip sampling off)");
  require_positive(options_.timeseries_buffer_rows, "timeseries_buffer_rows");
  require_positive(options_.snapshot_chunk, "snapshot_chunk");
  require_positive(options_.slip_buffer_crossings, "slip_buffer_crossings");
  if (!(options_.reader_lock_timeout >= 0.0))
    throw std::invalid_argument("RunOutputOptions.reader_lock_timeout = " +
                                std::to_string(options_.reader_lock_timeout) +
                                ": must be >= 0 seconds (inf = wait for readers forever)");
  if (options_.gzip_level < 0 || options_.gzip_level > 9)
    throw std::invalid_argument("RunOutputOptions.gzip_level = " +
                                std::to_string(options_.gzip_level) + ": allowed 0..9");

  timeseries_columns_ = options_.loading_shear_stress ? 5 : 4;
  timeseries_buffer_.reserve(timeseries_columns_ * static_cast<std::size_t>(options_.timeseries_buffer_rows));
  snapshot_time_buffer_.reserve(static_cast<std::size_t>(options_.snapshot_chunk));
  nodes_z_ = slip_sampling.nodes_z;
  if (nodes_z_ < 1 || node_count_ % static_cast<std::size_t>(nodes_z_) != 0)
    throw std::invalid_argument("SlipSamplingSetup.nodes_z = " + std::to_string(nodes_z_) + ": must be >= 1 and divide N = " +
                                std::to_string(node_count_));
  nodes_x_ = static_cast<int>(node_count_ / static_cast<std::size_t>(nodes_z_));
  if ((nodes_z_ > 1) != !options_.interface_2d_fields.empty() || (nodes_z_ > 1 && slip_sampling.z.size() != node_count_))
    throw std::invalid_argument("RunOutputOptions.interface_2d_fields and SlipSamplingSetup.z are given exactly "
                                "for a 2D interface (nodes_z > 1), z with one value per node");
  if (nodes_z_ > 1) {
    split_fields(options_.interface_2d_fields, snapshot_names_, snapshot_units_);
  } else {
    snapshot_names_.assign(std::begin(snapshot_names), std::end(snapshot_names));
    snapshot_units_.assign(std::begin(snapshot_units), std::end(snapshot_units));
    if (!options_.normal_stress_snapshots) {
      snapshot_names_.resize(4);
      snapshot_units_.resize(4);
    }
  }
  snapshot_fields_ = snapshot_names_.size();
  snapshot_field_buffer_.reserve(snapshot_fields_ * node_count_ * static_cast<std::size_t>(options_.snapshot_chunk));
  station_count_ = options_.station_x.size();
  if ((nodes_z_ > 1) != !options_.station_fields.empty() ||
      options_.station_z.size() != (nodes_z_ > 1 ? station_count_ : 0))
    throw std::invalid_argument("RunOutputOptions.station_fields and station_z are given exactly for a 2D interface "
                                "(nodes_z > 1), station_z with one value per station");
  if (nodes_z_ > 1) {
    split_fields(options_.station_fields, station_names_, station_units_);
  } else {
    // A line: five fields, six (the opening) with normal_stress_snapshots.
    const std::size_t fields = options_.normal_stress_snapshots ? 6 : 5;
    station_names_.assign(std::begin(station_field_names), std::begin(station_field_names) + fields);
    station_units_.assign(std::begin(station_field_units), std::begin(station_field_units) + fields);
  }
  if (station_count_ > 0) station_buffer_.reserve(station_buffer_rows * (3 + station_names_.size() * station_count_));
  if (options_.front_slip_rate > 0.0) rupture_front_.assign(node_count_, nan_value);
  if (slip_sampling.delta_th > 0.0) slip_sampler_.emplace(slip_sampling.delta_th, node_count_);

}

void RunOutput::create_file(const std::string& config_toml, const SlipSamplingSetup& slip_sampling) {
  const hsize_t n = node_count_;
  const Handle fapl = io::file_access_list(true);
  Handle file = io::create_file(path_, io::FileCreation::truncate, fapl);
  io::write_attribute(file, "config", config_toml);
  io::write_attribute(file, "code_version", slipstrip::code_version);
  io::write_attribute(file, "git_hash", slipstrip::git_hash);
  io::write_attribute(file, "units", units_table);
  io::write_attribute(file, "start_time", utc_now_iso8601());
  io::write_attribute(file, "end_time", "");
  io::write_attribute(file, "status", "running");
  if (nodes_z_ > 1) io::write_attribute(file, "format", "slipstrip interface_2d");
  if (options_.processes > 0) io::write_attribute(file, "processes", static_cast<long long>(options_.processes));
  // Node positions next to every per-node record: x, and z on a 2D interface.
  const auto write_positions = [&](hid_t group) {
    write_fixed_vector(group, "x", slip_sampling.x, "m");
    if (nodes_z_ > 1) write_fixed_vector(group, "z", slip_sampling.z, "m");
  };

  {
    const Handle group = io::create_group(file, "timeseries");
    const io::ExtendibleLayout layout{.chunk_rows = static_cast<hsize_t>(options_.timeseries_buffer_rows)};
    for (std::size_t c = 0; c < timeseries_columns_; ++c)
      create_extendible(group, timeseries_names[c], layout, timeseries_units[c]);
  }
  {
    const Handle group = io::create_group(file, "snapshots");
    io::write_attribute(group, "trigger", options_.snapshots_by_slip ? "slip_increment" : "time");
    create_extendible(group, "time", {.chunk_rows = 256}, "s");
    // One snapshot per chunk: each chunk is written exactly once, so the
    // compressed fields never leave dead space behind when a flush ends
    // mid-chunk (see create_extendible).
    // A 2D interface: [snapshots, nodes_z, nodes_x].
    const io::ExtendibleLayout layout =
        nodes_z_ > 1 ? io::ExtendibleLayout{.columns = static_cast<hsize_t>(nodes_x_),
                                            .planes = static_cast<hsize_t>(nodes_z_),
                                            .chunk_rows = 1,
                                            .deflate = options_.gzip_level}
                     : io::ExtendibleLayout{.columns = n, .chunk_rows = 1, .deflate = options_.gzip_level};
    for (std::size_t f = 0; f < snapshot_fields_; ++f)
      create_extendible(group, snapshot_names_[f], layout, snapshot_units_[f]);
    if (nodes_z_ == 1) write_fixed_vector(group, "x", slip_sampling.x, "m");
  }
  if (nodes_z_ > 1) {
    // The axes of the 2D interface's snapshots: x along a row, z across rows.
    const Handle group = io::create_group(file, "grid");
    write_fixed_vector(group, "x", std::span<const double>(slip_sampling.x).first(static_cast<std::size_t>(nodes_x_)),
                       "m");
    std::vector<double> z(static_cast<std::size_t>(nodes_z_));
    for (int iz = 0; iz < nodes_z_; ++iz) z[iz] = slip_sampling.z[static_cast<std::size_t>(iz) * nodes_x_];
    write_fixed_vector(group, "z", z, "m");
  }
  if (!options_.node_parameters.empty()) {
    const Handle group = io::create_group(file, "friction");
    write_positions(group);
    for (const auto& p : options_.node_parameters) write_fixed_vector(group, p.name, p.values, p.units);
  }
  if (station_count_ > 0) {
    const Handle group = io::create_group(file, "stations");
    write_fixed_vector(group, "x", options_.station_x, "m");
    if (nodes_z_ > 1) write_fixed_vector(group, "z", options_.station_z, "m");
    const io::ExtendibleLayout series{.chunk_rows = station_buffer_rows};
    create_extendible(group, "time", series, "s");
    create_extendible(group, "max_slip_rate", series, "m/s");
    create_extendible(group, "moment_rate", series,
                      nodes_z_ > 1 ? "N m/s (mu * sum(v_x) dx dz)" : "N/s per m (mu * sum(v) dx)");
    const io::ExtendibleLayout fields{.columns = station_count_, .chunk_rows = station_buffer_rows};
    for (std::size_t f = 0; f < station_names_.size(); ++f)
      create_extendible(group, station_names_[f], fields, station_units_[f]);
  }
  if (!rupture_front_.empty()) {
    const Handle group = io::create_group(file, "rupture_front");
    io::write_attribute(group, "slip_rate_threshold", options_.front_slip_rate);
    write_positions(group);
    write_fixed_vector(group, "arrival_time", rupture_front_, "s");
  }
  if (slip_sampler_) {
    const Handle group = io::create_group(file, "slip_sampling");
    // The attributes the event detection reads back (events/catalog_io.hpp).
    events::SlipSamplingInfo info;
    info.delta_th = slip_sampling.delta_th;
    info.dx = slip_sampling.dx;
    info.v0 = slip_sampling.v0;
    info.mu = slip_sampling.mu;
    info.D = slip_sampling.D;
    info.L = slip_sampling.L;
    info.nodes_z = slip_sampling.nodes_z;
    info.dz = slip_sampling.dz;
    info.W = slip_sampling.W;
    events::write_slip_sampling_attributes(group, info);
    write_positions(group);
    // Uncompressed, so that chunks updated by several write-outs stay in
    // place.  64 levels x 256 nodes (128 KiB): a write-out touches the chunks
    // around the levels the nodes are currently crossing, not whole rows.
    // Fill NaN: a level a node has not reached yet.
    create_extendible(group, "crossing_time",
                      {.columns = n, .chunk_rows = 64, .chunk_columns = std::min<hsize_t>(n, 256), .fill = nan_value},
                      "s");
  }
  io::close_file(file);
}

RunOutput::~RunOutput() {
  if (failed_) return;
  try {
    close("interrupted");
  } catch (...) {
    // A destructor may run during unwinding; the file keeps its last flush.
  }
}

void RunOutput::append_timeseries(double time, double max_slip_rate, double mean_slip,
                                  double mean_shear_stress) {
  if (closed_) throw std::logic_error("RunOutput::append_timeseries after close: " + path_);
  if (options_.loading_shear_stress)
    throw std::logic_error("RunOutput::append_timeseries without the loading shear stress the file records: " + path_);
  timeseries_buffer_.insert(timeseries_buffer_.end(),
                            {time, max_slip_rate, mean_slip, mean_shear_stress});
  if (timeseries_buffer_.size() >= timeseries_columns_ * static_cast<std::size_t>(options_.timeseries_buffer_rows))
    write_out(WriteTrigger::buffer_full);
}

void RunOutput::append_timeseries(double time, double max_slip_rate, double mean_slip, double mean_shear_stress,
                                  double loading_shear_stress) {
  if (closed_) throw std::logic_error("RunOutput::append_timeseries after close: " + path_);
  if (!options_.loading_shear_stress)
    throw std::logic_error("RunOutput::append_timeseries with a loading shear stress the file does not record: " +
                           path_);
  timeseries_buffer_.insert(timeseries_buffer_.end(),
                            {time, max_slip_rate, mean_slip, mean_shear_stress, loading_shear_stress});
  if (timeseries_buffer_.size() >= timeseries_columns_ * static_cast<std::size_t>(options_.timeseries_buffer_rows))
    write_out(WriteTrigger::buffer_full);
}

void RunOutput::append_stations(double time, std::span<const double> slip,
                                std::span<const double> slip_rate, std::span<const double> shear_stress,
                                std::span<const double> state, double normal_stress,
                                double max_slip_rate, double moment_rate) {
  if (options_.normal_stress_snapshots)
    throw std::invalid_argument("append_stations: the file records the normal stress and opening per station");
  // The normal stress of identical bodies: the same value at every station.
  station_uniform_.assign(station_count_, normal_stress);
  const std::span<const double> fields[] = {slip, slip_rate, shear_stress, state, station_uniform_};
  append_stations(time, fields, max_slip_rate, moment_rate);
}

void RunOutput::append_stations(double time, std::span<const double> slip,
                                std::span<const double> slip_rate, std::span<const double> shear_stress,
                                std::span<const double> state, std::span<const double> normal_stress,
                                std::span<const double> opening, double max_slip_rate, double moment_rate) {
  if (!options_.normal_stress_snapshots)
    throw std::invalid_argument("append_stations: per-station normal stress and opening given but "
                                "normal_stress_snapshots is not set");
  const std::span<const double> fields[] = {slip, slip_rate, shear_stress, state, normal_stress, opening};
  append_stations(time, fields, max_slip_rate, moment_rate);
}

void RunOutput::append_stations(double time, std::span<const std::span<const double>> fields, double max_slip_rate,
                                double moment_rate) {
  if (closed_) throw std::logic_error("RunOutput::append_stations after close: " + path_);
  if (station_count_ == 0) throw std::logic_error("RunOutput::append_stations without stations");
  if (fields.size() != station_names_.size())
    throw std::invalid_argument("append_stations: " + std::to_string(fields.size()) + " fields, the file has " +
                                std::to_string(station_names_.size()));
  for (std::size_t f = 0; f < fields.size(); ++f)
    if (fields[f].size() < station_count_)
      throw std::invalid_argument("append_stations: " + station_names_[f] + " has " +
                                  std::to_string(fields[f].size()) + " values, expected one per station (" +
                                  std::to_string(station_count_) + ")");
  station_buffer_.insert(station_buffer_.end(), {time, max_slip_rate, moment_rate});
  for (const auto field : fields)
    station_buffer_.insert(station_buffer_.end(), field.begin(), field.begin() + station_count_);
  if (station_buffer_.size() >= station_buffer_rows * (3 + station_names_.size() * station_count_))
    write_out(WriteTrigger::buffer_full);
}

void RunOutput::set_rupture_front(std::span<const double> arrival_time) {
  if (rupture_front_.empty()) throw std::logic_error("RunOutput::set_rupture_front without front_slip_rate");
  std::copy(arrival_time.begin(), arrival_time.end(), rupture_front_.begin());
  rupture_front_dirty_ = true;
}

void RunOutput::write_snapshot(double time, std::span<const double> slip,
                               std::span<const double> slip_rate, std::span<const double> state,
                               std::span<const double> shear_stress, std::span<const double> normal_stress,
                               std::span<const double> opening) {
  if (closed_) throw std::logic_error("RunOutput::write_snapshot after close: " + path_);
  if (normal_stress.empty() == options_.normal_stress_snapshots || opening.empty() != normal_stress.empty())
    throw std::invalid_argument(std::string("write_snapshot: normal_stress and opening ") +
                                (options_.normal_stress_snapshots ? "missing (normal_stress_snapshots is set)"
                                                                  : "given but normal_stress_snapshots is not set"));
  const std::span<const double> fields[] = {slip, slip_rate, state, shear_stress, normal_stress, opening};
  write_snapshot(time, std::span<const std::span<const double>>(fields, normal_stress.empty() ? 4 : 6));
}

void RunOutput::write_snapshot(double time, std::span<const std::span<const double>> fields) {
  if (closed_) throw std::logic_error("RunOutput::write_snapshot after close: " + path_);
  if (fields.size() != snapshot_fields_)
    throw std::invalid_argument("write_snapshot: " + std::to_string(fields.size()) + " fields, the file has " +
                                std::to_string(snapshot_fields_));
  for (std::size_t f = 0; f < snapshot_fields_; ++f)
    if (fields[f].size() != node_count_)
      throw std::invalid_argument("write_snapshot: " + snapshot_names_[f] + " has " +
                                  std::to_string(fields[f].size()) + " values, expected N = " +
                                  std::to_string(node_count_));
  snapshot_time_buffer_.push_back(time);
  for (std::size_t f = 0; f < snapshot_fields_; ++f)
    snapshot_field_buffer_.insert(snapshot_field_buffer_.end(), fields[f].begin(), fields[f].end());
  if (snapshot_time_buffer_.size() >= static_cast<std::size_t>(options_.snapshot_chunk))
    write_out(WriteTrigger::buffer_full);
}

void RunOutput::record_slip(double t_old, double t_new, std::span<const double> slip_old,
                            std::span<const double> slip_new) {
  if (!slip_sampler_) return;
  if (closed_) throw std::logic_error("RunOutput::record_slip after close: " + path_);
  if (slip_old.size() != node_count_ || slip_new.size() != node_count_)
    throw std::invalid_argument("record_slip: slip_old has " + std::to_string(slip_old.size()) +
                                " and slip_new " + std::to_string(slip_new.size()) +
                                " values, expected N = " + std::to_string(node_count_));
  if (!(t_new >= t_old))
    throw std::invalid_argument("record_slip: t_new = " + std::to_string(t_new) +
                                " < t_old = " + std::to_string(t_old) + "; time must not go back");
  const bool crossed = slip_sampler_->record(t_old, t_new, slip_old, slip_new);
  if (crossed && slip_sampler_->pending() >= static_cast<std::size_t>(options_.slip_buffer_crossings))
    write_out(WriteTrigger::buffer_full);
}

void RunOutput::record_crossings(std::span<const hsize_t> coordinates, std::span<const double> times) {
  if (!slip_sampler_) return;
  if (closed_) throw std::logic_error("RunOutput::record_crossings after close: " + path_);
  slip_sampler_->add_found(coordinates, times);
  if (!times.empty() && slip_sampler_->pending() >= static_cast<std::size_t>(options_.slip_buffer_crossings))
    write_out(WriteTrigger::buffer_full);
}

bool RunOutput::flush() {
  if (closed_) return true;
  return write_out(WriteTrigger::flush);
}

std::optional<RunOutputCursor> RunOutput::flush_for_checkpoint(bool force) {
  if (closed_) throw std::logic_error("RunOutput::flush_for_checkpoint after close: " + path_);
  if (!write_out(force ? WriteTrigger::forced : WriteTrigger::flush)) return std::nullopt;
  RunOutputCursor cursor;
  cursor.timeseries_rows = timeseries_rows_in_file_;
  cursor.snapshots = snapshots_in_file_;
  cursor.station_rows = station_rows_in_file_;
  if (slip_sampler_) {
    cursor.crossing_rows = slip_sampler_->levels_max();
    cursor.slip_recorded = slip_sampler_->started();
    cursor.levels_reached.assign(slip_sampler_->levels_reached().begin(), slip_sampler_->levels_reached().end());
    cursor.next_threshold.assign(slip_sampler_->next_threshold().begin(), slip_sampler_->next_threshold().end());
  }
  cursor.rupture_front = rupture_front_;
  return cursor;
}

void RunOutput::reopen_file(const RunOutputCursor& cursor) {
  Handle file = open_for_append(path_, false);
  // Cuts an extendible dataset back to `rows`; fewer rows than the cursor
  // means the file is not the one the restart point was taken from.
  const auto cut = [](hid_t group, const char* name, hsize_t rows) {
    const Handle dset = io::open_dataset(group, name);
    const hsize_t in_file = io::rows_of(dset);
    if (in_file < rows)
      throw std::runtime_error(std::string(name) + " has " + std::to_string(in_file) +
                               " rows, fewer than the " + std::to_string(rows) +
                               " of the restart point (not the file the restart point belongs to)");
    io::set_rows(dset, rows);
  };
  {
    const Handle group = io::open_group(file, "timeseries");
    for (std::size_t c = 0; c < timeseries_columns_; ++c) cut(group, timeseries_names[c], cursor.timeseries_rows);
  }
  {
    const Handle group = io::open_group(file, "snapshots");
    cut(group, "time", cursor.snapshots);
    if (nodes_z_ > 1) {  // the times the XDMF sidecar lists
      snapshot_times_.resize(cursor.snapshots);
      if (cursor.snapshots > 0)
        io::read_rows(io::open_dataset(group, "time"), 0, cursor.snapshots, snapshot_times_.data());
    }
    for (const std::string& name : snapshot_names_) cut(group, name.c_str(), cursor.snapshots);
  }
  if (station_count_ > 0) {
    const Handle group = io::open_group(file, "stations");
    for (const char* name : {"time", "max_slip_rate", "moment_rate"}) cut(group, name, cursor.station_rows);
    for (const std::string& name : station_names_) cut(group, name.c_str(), cursor.station_rows);
  }
  if (slip_sampler_) {
    // Crossings are single elements (NaN = not reached): those of levels a
    // node reached after the restart point are reset to NaN before the rows
    // are cut, so no value of the lost steps survives in a chunk that stays.
    const Handle dset = io::open_dataset(io::open_group(file, "slip_sampling"), "crossing_time");
    const hsize_t in_file = io::rows_of(dset), n = node_count_;
    if (in_file < cursor.crossing_rows)
      throw std::runtime_error("crossing_time has " + std::to_string(in_file) + " rows, fewer than the " +
                               std::to_string(cursor.crossing_rows) + " of the restart point");
    const hsize_t first = *std::min_element(cursor.levels_reached.begin(), cursor.levels_reached.end());
    if (in_file > first) {
      const hsize_t rows = in_file - first;
      std::vector<double> block(rows * n);
      io::read_rows(dset, first, rows, block.data());
      for (hsize_t r = 0; r < rows; ++r)
        for (hsize_t i = 0; i < n; ++i)
          if (first + r >= cursor.levels_reached[i]) block[r * n + i] = nan_value;
      io::write_rows(dset, first, rows, block.data());
    }
    io::set_rows(dset, cursor.crossing_rows);
  }
  if (!rupture_front_.empty())
    io::overwrite(io::open_dataset(io::open_group(file, "rupture_front"), "arrival_time"),
                  std::span<const double>(cursor.rupture_front));
  // An event catalog (`slipstrip events`, `analyze --write-events`) of the
  // interrupted part describes a record that is about to change: dropped, as
  // an uninterrupted run has none.
  io::remove_member_if_present(file, "events");
  io::write_attribute(file, "status", "running");
  io::write_attribute(file, "end_time", "");
  io::close_file(file);

  timeseries_rows_in_file_ = cursor.timeseries_rows;
  snapshots_in_file_ = cursor.snapshots;
  station_rows_in_file_ = cursor.station_rows;
  crossing_rows_in_file_ = cursor.crossing_rows;
  if (slip_sampler_)
    slip_sampler_->restore(cursor.crossing_rows, cursor.slip_recorded, cursor.levels_reached,
                           cursor.next_threshold);
  rupture_front_ = cursor.rupture_front;
}

void RunOutput::close(const std::string& status) {
  if (closed_) return;
  const bool allowed = status == "completed" || status == "interrupted" ||
                       (status.rfind("diverged: ", 0) == 0 && status.size() > 10);
  if (!allowed)
    throw std::invalid_argument("RunOutput::close status = \"" + status +
                                "\": allowed \"completed\", \"interrupted\", "
                                "\"diverged: <diagnostic>\"");
  write_out(WriteTrigger::close, &status);
  closed_ = true;
}

Handle RunOutput::open_unless_reader_holds(WriteTrigger trigger) {
  const auto now = std::chrono::steady_clock::now();
  const auto timeout = std::chrono::duration<double>(options_.reader_lock_timeout);
  const bool waited_too_long = reader_holds_since_ && now - *reader_holds_since_ >= timeout;
  // While a reader holds the file, a full buffer does not retry the lock at
  // every step; it waits for the next flush() (or the timeout).
  if (trigger == WriteTrigger::buffer_full && reader_holds_since_ && !waited_too_long) return {};
  Handle file = open_for_append(path_, true);
  if (file.valid()) {
    reader_holds_since_.reset();
    return file;
  }
  if (!reader_holds_since_) reader_holds_since_ = now;
  // The run must not hang on a forgotten reader: past the timeout, and at
  // close, write anyway (that reader may see a mix of old and new data).
  if (trigger == WriteTrigger::close || trigger == WriteTrigger::forced ||
      now - *reader_holds_since_ >= timeout)
    return open_for_append(path_, false);
  ++deferred_writes_;
  return {};
}

bool RunOutput::write_out(WriteTrigger trigger, const std::string* final_status) {
  if (failed_) throw OutputError("the run file '" + path_ + "' could not be written earlier");
  // Never retried (a full disk stays full; HDF5 may hold half-written
  // metadata): the file keeps what the earlier write-outs wrote.
  const auto fail = [&](const std::exception& e) {
    failed_ = closed_ = true;
    return OutputError("writing the run file '" + path_ + "' failed: " + e.what() +
                       "; it keeps the data of the previous flush");
  };
  try {
    const bool written = write_out_unchecked(trigger, final_status);
    update_xdmf_sidecar();
    return written;
  } catch (const std::runtime_error& e) {
    throw fail(e);  // an HDF5 failure
  } catch (const std::invalid_argument& e) {
    throw fail(e);  // a group or dataset of the file vanished while the run went on
  }
}

void RunOutput::update_xdmf_sidecar() {
  // After the snapshots are in the file, so the sidecar never points past them.
  if (snapshots_in_file_ == snapshots_in_sidecar_) return;
  io::XdmfSpaceTime description;
  description.h5_file_name = std::filesystem::path(path_).filename().string();
  description.snapshot_count = snapshots_in_file_;
  description.node_count = node_count_;
  description.nodes_z = static_cast<std::size_t>(nodes_z_);
  description.fields = snapshot_names_;
  description.times = snapshot_times_;
  io::write_xdmf_sidecar(io::xdmf_sidecar_path(path_), description);
  snapshots_in_sidecar_ = snapshots_in_file_;
}

void require_free_space(const std::string& path, double bytes_needed, const std::string& what) {
  const std::filesystem::path file(path);
  const std::string dir = file.has_parent_path() ? file.parent_path().string() : ".";
  struct statvfs fs {};
  if (::statvfs(dir.c_str(), &fs) != 0) return;  // cannot tell: let the write itself report
  const double available = static_cast<double>(fs.f_bavail) * static_cast<double>(fs.f_frsize);
  if (available < bytes_needed) {
    char text[300];
    std::snprintf(text, sizeof text, "No space left on device (%.0f bytes free in '%s', %s needs about %.0f)",
                  available, dir.c_str(), what.c_str(), bytes_needed);
    throw std::runtime_error(text);
  }
}

void RunOutput::check_free_space() const {
  // A write-out that runs out of space half-way leaves HDF5 metadata that
  // points past the end of the file (measured on a full tmpfs: the status
  // attribute became unreadable and the process crashed at exit).  Refusing
  // before writing keeps the file exactly as the previous write-out left it.
  double needed = 8.0 * (timeseries_buffer_.size() + snapshot_time_buffer_.size() +
                         snapshot_field_buffer_.size() + station_buffer_.size());
  const std::size_t levels_max = slip_levels_reached();
  if (levels_max > crossing_rows_in_file_) {
    // New rows of [64, min(N, 256)] chunks, allocated whole (NaN fill).
    const double chunk_rows = std::ceil(levels_max / 64.0) - std::floor(crossing_rows_in_file_ / 64.0);
    needed += chunk_rows * std::ceil(node_count_ / 256.0) * 64.0 * std::min<double>(node_count_, 256) * 8.0;
  }
  needed += 256.0 * 1024.0;  // metadata, B-tree nodes, attributes
  require_free_space(path_, needed, "a write-out");
}

bool RunOutput::write_out_unchecked(WriteTrigger trigger, const std::string* final_status) {
  check_free_space();
  Handle file = open_unless_reader_holds(trigger);
  if (!file.valid()) return false;

  const std::size_t timeseries_rows = timeseries_buffer_.size() / timeseries_columns_;
  if (timeseries_rows > 0) {
    const Handle group = io::open_group(file, "timeseries");
    for (std::size_t c = 0; c < timeseries_columns_; ++c) {
      const Handle dset = io::open_dataset(group, timeseries_names[c]);
      io::grow_rows(dset, timeseries_rows_in_file_ + timeseries_rows);
      // Column c of the interleaved rows (time, max slip rate, mean slip, mean stress[, load]).
      io::write_rows(dset, timeseries_rows_in_file_, timeseries_rows, timeseries_buffer_.data() + c,
                     timeseries_columns_);
    }
    timeseries_rows_in_file_ += timeseries_rows;
    timeseries_buffer_.clear();
  }

  const std::size_t snapshots = snapshot_time_buffer_.size();
  if (snapshots > 0) {
    const Handle group = io::open_group(file, "snapshots");
    const Handle time = io::open_dataset(group, "time");
    io::grow_rows(time, snapshots_in_file_ + snapshots);
    io::write_rows(time, snapshots_in_file_, snapshots, snapshot_time_buffer_.data());
    for (std::size_t f = 0; f < snapshot_fields_; ++f) {
      const Handle dset = io::open_dataset(group, snapshot_names_[f]);
      io::grow_rows(dset, snapshots_in_file_ + snapshots);
      for (std::size_t s = 0; s < snapshots; ++s)
        io::write_rows(dset, snapshots_in_file_ + s, 1, snapshot_field_buffer_.data() + (snapshot_fields_ * s + f) * node_count_);
    }
    snapshots_in_file_ += snapshots;
    if (nodes_z_ > 1)
      snapshot_times_.insert(snapshot_times_.end(), snapshot_time_buffer_.begin(), snapshot_time_buffer_.end());
    snapshot_time_buffer_.clear();
    snapshot_field_buffer_.clear();
  }

  if (slip_sampler_ && slip_sampler_->pending() > 0) {
    const Handle dset = io::open_dataset(io::open_group(file, "slip_sampling"), "crossing_time");
    io::grow_rows(dset, slip_sampler_->levels_max());
    crossing_rows_in_file_ = std::max(crossing_rows_in_file_, slip_sampler_->levels_max());
    // Element writes: entries not yet reached keep the NaN fill value, so the
    // partially filled rows in the file are always up to date.
    io::write_elements(dset, slip_sampler_->pending_coordinates(), slip_sampler_->pending_times());
    slip_sampler_->clear_pending();
  }

  const std::size_t station_fields = station_names_.size();
  const std::size_t row_width = 3 + station_fields * station_count_;
  const std::size_t station_rows = station_count_ ? station_buffer_.size() / row_width : 0;
  if (station_rows > 0) {
    const Handle group = io::open_group(file, "stations");
    const char* series[3] = {"time", "max_slip_rate", "moment_rate"};
    for (int c = 0; c < 3; ++c) {
      const Handle dset = io::open_dataset(group, series[c]);
      io::grow_rows(dset, station_rows_in_file_ + station_rows);
      io::write_rows(dset, station_rows_in_file_, station_rows, station_buffer_.data() + c, row_width);
    }
    for (std::size_t f = 0; f < station_fields; ++f) {
      const Handle dset = io::open_dataset(group, station_names_[f]);
      io::grow_rows(dset, station_rows_in_file_ + station_rows);
      for (std::size_t r = 0; r < station_rows; ++r)
        io::write_rows(dset, station_rows_in_file_ + r, 1,
                       station_buffer_.data() + r * row_width + 3 + f * station_count_);
    }
    station_rows_in_file_ += station_rows;
    station_buffer_.clear();
  }
  if (rupture_front_dirty_) {
    io::overwrite(io::open_dataset(io::open_group(file, "rupture_front"), "arrival_time"),
                  std::span<const double>(rupture_front_));
    rupture_front_dirty_ = false;
  }

  if (final_status) {
    io::write_attribute(file, "status", *final_status);
    io::write_attribute(file, "end_time", utc_now_iso8601());
  }
  io::close_file(file);
  return true;
}

}  // namespace slipstrip
