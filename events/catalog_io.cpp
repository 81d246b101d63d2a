#include "events/catalog_io.hpp"

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <stdexcept>
#include <vector>

namespace slipstrip::events {

namespace {

using hdf5::Handle;

constexpr const char* kSlipGroup = "slip_sampling";
constexpr const char* kEventsGroup = "events";

bool file_exists(const std::string& path) { return std::filesystem::exists(path); }

Handle open_file_read(const std::string& path) {
  if (!file_exists(path))
    throw std::invalid_argument("path = '" + path + "' is invalid: file does not exist");
  if (H5Fis_hdf5(path.c_str()) <= 0)
    throw std::invalid_argument("path = '" + path + "' is invalid: not an HDF5 file");
  return Handle(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), "H5Fopen(" + path + ")");
}

bool has_link(hid_t loc, const char* name) { return H5Lexists(loc, name, H5P_DEFAULT) > 0; }

Handle open_group(hid_t file, const char* name, const std::string& path) {
  if (!has_link(file, name))
    throw std::invalid_argument("path = '" + path + "' is invalid: group /" + name + " is missing");
  return Handle(H5Gopen2(file, name, H5P_DEFAULT), std::string("H5Gopen /") + name);
}

// A damaged or hand-made file may hold an array, a string or a bool (an HDF5
// enum) where a number belongs: reading it into one double would overrun the
// buffer (issue 15: a segfault), so shape and type are checked first.
void require_scalar_number(hid_t attr, const char* name, const std::string& where) {
  Handle space(H5Aget_space(attr), std::string("H5Aget_space ") + name);
  const H5S_class_t shape = H5Sget_simple_extent_type(space);
  const hssize_t count = H5Sget_simple_extent_npoints(space);
  if (shape != H5S_SCALAR)
    throw std::invalid_argument(where + " attribute '" + name + "' is invalid: it is " +
                                (shape == H5S_SIMPLE ? "an array of " + std::to_string(count) + " values"
                                                     : std::string("empty")) +
                                ", expected a scalar number");
  Handle type(H5Aget_type(attr), std::string("H5Aget_type ") + name);
  const H5T_class_t kind = H5Tget_class(type);
  if (kind != H5T_FLOAT && kind != H5T_INTEGER)
    throw std::invalid_argument(where + " attribute '" + name + "' is invalid: its type is " +
                                (kind == H5T_ENUM ? "boolean/enum" : kind == H5T_STRING ? "a string" : "not a number") +
                                ", expected a scalar float");
}

double read_double_attribute(hid_t obj, const char* name, const std::string& where) {
  if (H5Aexists(obj, name) <= 0)
    throw std::invalid_argument(where + " attribute '" + name + "' is missing");
  Handle attr(H5Aopen(obj, name, H5P_DEFAULT), std::string("H5Aopen ") + name);
  require_scalar_number(attr, name, where);
  double value = 0.0;
  hdf5::check(H5Aread(attr, H5T_NATIVE_DOUBLE, &value), std::string("H5Aread ") + name);
  return value;
}

double read_optional_double_attribute(hid_t obj, const char* name, const std::string& where) {
  if (H5Aexists(obj, name) <= 0) return std::numeric_limits<double>::quiet_NaN();
  return read_double_attribute(obj, name, where);
}

std::uint64_t read_u64_attribute(hid_t obj, const char* name, const std::string& where) {
  if (H5Aexists(obj, name) <= 0)
    throw std::invalid_argument(where + " attribute '" + name + "' is missing");
  Handle attr(H5Aopen(obj, name, H5P_DEFAULT), std::string("H5Aopen ") + name);
  require_scalar_number(attr, name, where);
  std::uint64_t value = 0;
  hdf5::check(H5Aread(attr, H5T_NATIVE_UINT64, &value), std::string("H5Aread ") + name);
  return value;
}

void write_scalar_attribute(hid_t obj, const char* name, hid_t mem_type, hid_t file_type, const void* value) {
  Handle space(H5Screate(H5S_SCALAR), "H5Screate");
  Handle attr(H5Acreate2(obj, name, file_type, space, H5P_DEFAULT, H5P_DEFAULT),
              std::string("H5Acreate ") + name);
  hdf5::check(H5Awrite(attr, mem_type, value), std::string("H5Awrite ") + name);
}

void write_double_attribute(hid_t obj, const char* name, double value) {
  write_scalar_attribute(obj, name, H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, &value);
}

void write_u64_attribute(hid_t obj, const char* name, std::uint64_t value) {
  write_scalar_attribute(obj, name, H5T_NATIVE_UINT64, H5T_STD_U64LE, &value);
}

void write_string_attribute(hid_t obj, const char* name, const std::string& value) {
  Handle type(H5Tcopy(H5T_C_S1), "H5Tcopy");
  hdf5::check(H5Tset_size(type, value.size() + 1), "H5Tset_size");
  hdf5::check(H5Tset_strpad(type, H5T_STR_NULLTERM), "H5Tset_strpad");
  write_scalar_attribute(obj, name, type, type, value.c_str());
}

template <class T>
void write_vector(hid_t group, const char* name, const std::vector<T>& data, hid_t mem_type,
                  hid_t file_type, const char* units) {
  const hsize_t dims[1] = {static_cast<hsize_t>(data.size())};
  Handle space(H5Screate_simple(1, dims, nullptr), "H5Screate_simple");
  Handle dset(H5Dcreate2(group, name, file_type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
              std::string("H5Dcreate ") + name);
  if (!data.empty())
    hdf5::check(H5Dwrite(dset, mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data()),
                std::string("H5Dwrite ") + name);
  write_string_attribute(dset, "units", units);
}

template <class T>
std::vector<T> read_vector(hid_t group, const char* name, hid_t mem_type, const std::string& where) {
  if (!has_link(group, name))
    throw std::invalid_argument(where + " dataset '" + name + "' is missing");
  Handle dset(H5Dopen2(group, name, H5P_DEFAULT), std::string("H5Dopen ") + name);
  Handle space(H5Dget_space(dset), "H5Dget_space");
  if (H5Sget_simple_extent_ndims(space) != 1)
    throw std::invalid_argument(where + " dataset '" + name + "' is invalid: must be 1-D");
  hsize_t dims[1] = {0};
  H5Sget_simple_extent_dims(space, dims, nullptr);
  std::vector<T> data(static_cast<std::size_t>(dims[0]));
  if (!data.empty())
    hdf5::check(H5Dread(dset, mem_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data()),
                std::string("H5Dread ") + name);
  return data;
}

}  // namespace

// ---------------------------------------------------------------------------

Hdf5CrossingTimes::Hdf5CrossingTimes(const std::string& path) : path_(path) {
  file_ = open_file_read(path);
  Handle group = open_group(file_, kSlipGroup, path);
  if (!has_link(group, "crossing_time"))
    throw std::invalid_argument("path = '" + path + "' is invalid: dataset /slip_sampling/crossing_time is missing");
  dataset_ = Handle(H5Dopen2(group, "crossing_time", H5P_DEFAULT), "H5Dopen crossing_time");
  file_space_ = Handle(H5Dget_space(dataset_), "H5Dget_space crossing_time");
  {
    Handle type(H5Dget_type(dataset_), "H5Dget_type crossing_time");
    if (H5Tget_class(type) != H5T_FLOAT)
      throw std::invalid_argument("path = '" + path + "' is invalid: /slip_sampling/crossing_time must hold "
                                  "floating-point times [s] (NaN = level not reached), not integers, "
                                  "booleans or strings");
  }
  const int rank = H5Sget_simple_extent_ndims(file_space_);
  if (rank != 2)
    throw std::invalid_argument("/slip_sampling/crossing_time rank = " + std::to_string(rank) +
                                " is invalid: must be 2 ([n_levels, N])");
  hsize_t dims[2] = {0, 0};
  H5Sget_simple_extent_dims(file_space_, dims, nullptr);
  n_levels_ = static_cast<std::size_t>(dims[0]);
  n_nodes_ = static_cast<std::size_t>(dims[1]);
}

void Hdf5CrossingTimes::read_rows(std::size_t j0, std::size_t j1, std::span<double> block) const {
  if (j1 <= j0) return;
  const hsize_t start[2] = {static_cast<hsize_t>(j0), 0};
  const hsize_t count[2] = {static_cast<hsize_t>(j1 - j0), static_cast<hsize_t>(n_nodes_)};
  hdf5::check(H5Sselect_hyperslab(file_space_, H5S_SELECT_SET, start, nullptr, count, nullptr),
              "H5Sselect_hyperslab crossing_time");
  Handle mem_space(H5Screate_simple(2, count, nullptr), "H5Screate_simple");
  hdf5::check(H5Dread(dataset_, H5T_NATIVE_DOUBLE, mem_space, file_space_, H5P_DEFAULT, block.data()),
              "H5Dread crossing_time rows [" + std::to_string(j0) + ", " + std::to_string(j1) + ") of " + path_);
}

SlipSamplingInfo read_slip_sampling_info(const std::string& path) {
  Handle file = open_file_read(path);
  Handle group = open_group(file, kSlipGroup, path);
  const std::string where = path + ":/slip_sampling";
  SlipSamplingInfo info;
  info.delta_th = read_double_attribute(group, "delta_th", where);
  info.dx = read_double_attribute(group, "dx", where);
  info.v0 = read_double_attribute(group, "v0", where);
  info.mu = read_double_attribute(group, "mu", where);
  info.D = read_optional_double_attribute(group, "D", where);
  info.L = read_optional_double_attribute(group, "L", where);
  if (has_link(group, "x")) {
    info.x = read_vector<double>(group, "x", H5T_NATIVE_DOUBLE, where);
  } else {
    // Older or minimal files: nodes are equally spaced from x = 0.
    Handle dset(H5Dopen2(group, "crossing_time", H5P_DEFAULT), "H5Dopen crossing_time");
    Handle space(H5Dget_space(dset), "H5Dget_space");
    hsize_t dims[2] = {0, 0};
    H5Sget_simple_extent_dims(space, dims, nullptr);
    info.x.resize(static_cast<std::size_t>(dims[1]));
    for (std::size_t i = 0; i < info.x.size(); ++i) info.x[i] = static_cast<double>(i) * info.dx;
  }
  return info;
}

EventCatalog detect_events_in_file(const std::string& path, const EventDetectionOptions& options) {
  const SlipSamplingInfo info = read_slip_sampling_info(path);
  const Hdf5CrossingTimes source(path);
  return detect_events(source, info, options);
}

void write_slip_sampling(const std::string& path, const SlipSamplingInfo& info,
                         std::span<const double> crossing_time, std::size_t n_levels) {
  const std::size_t n = info.x.size();
  if (crossing_time.size() != n_levels * n)
    throw std::invalid_argument("crossing_time size = " + std::to_string(crossing_time.size()) +
                                " is invalid: must equal n_levels * x.size() = " + std::to_string(n_levels) +
                                " * " + std::to_string(n));
  Handle file(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), "H5Fcreate(" + path + ")");
  Handle group(H5Gcreate2(file, kSlipGroup, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), "H5Gcreate /slip_sampling");
  write_double_attribute(group, "delta_th", info.delta_th);
  write_double_attribute(group, "dx", info.dx);
  write_double_attribute(group, "v0", info.v0);
  write_double_attribute(group, "mu", info.mu);
  write_double_attribute(group, "D", info.D);
  write_double_attribute(group, "L", info.L);
  write_vector(group, "x", info.x, H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, "m");

  // Chunked by whole rows, like the solver appends them, so row-block reads
  // touch contiguous chunks.
  const hsize_t dims[2] = {static_cast<hsize_t>(n_levels), static_cast<hsize_t>(n)};
  Handle space(H5Screate_simple(2, dims, nullptr), "H5Screate_simple");
  Handle dcpl(H5Pcreate(H5P_DATASET_CREATE), "H5Pcreate");
  if (n_levels > 0 && n > 0) {
    const hsize_t chunk_rows = std::max<hsize_t>(1, std::min<hsize_t>(dims[0], (1u << 17) / dims[1] + 1));
    const hsize_t chunk[2] = {chunk_rows, dims[1]};
    hdf5::check(H5Pset_chunk(dcpl, 2, chunk), "H5Pset_chunk");
  }
  Handle dset(H5Dcreate2(group, "crossing_time", H5T_IEEE_F64LE, space, H5P_DEFAULT, dcpl, H5P_DEFAULT),
              "H5Dcreate crossing_time");
  if (!crossing_time.empty())
    hdf5::check(H5Dwrite(dset, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, crossing_time.data()),
                "H5Dwrite crossing_time");
  write_string_attribute(dset, "units", "s");
}

void write_event_catalog(const std::string& path, const EventCatalog& c) {
  Handle file;
  if (file_exists(path)) {
    if (H5Fis_hdf5(path.c_str()) <= 0)
      throw std::invalid_argument("path = '" + path + "' is invalid: exists but is not an HDF5 file");
    file = Handle(H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT), "H5Fopen(" + path + ")");
    if (has_link(file, kEventsGroup))
      hdf5::check(H5Ldelete(file, kEventsGroup, H5P_DEFAULT), "H5Ldelete /events");
  } else {
    file = Handle(H5Fcreate(path.c_str(), H5F_ACC_EXCL, H5P_DEFAULT, H5P_DEFAULT), "H5Fcreate(" + path + ")");
  }
  Handle g(H5Gcreate2(file, kEventsGroup, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), "H5Gcreate /events");

  write_vector(g, "t_start", c.t_start, H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, "s");
  write_vector(g, "T", c.duration, H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, "s");
  write_vector(g, "x_start", c.x_start, H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, "m");
  write_vector(g, "L_s", c.extent, H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, "m");
  write_vector(g, "u_mean", c.mean_slip, H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, "m");
  write_vector(g, "M0", c.moment, H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, "N/m");
  write_vector(g, "max_slip_rate", c.max_slip_rate, H5T_NATIVE_DOUBLE, H5T_IEEE_F64LE, "m/s");
  write_vector(g, "n_clusters", c.n_clusters, H5T_NATIVE_INT, H5T_STD_I32LE, "1");

  write_double_attribute(g, "alpha", c.options.alpha);
  write_double_attribute(g, "waiting_time_threshold", c.waiting_time_threshold);
  write_double_attribute(g, "min_extent_dx", c.options.min_extent_dx);
  write_double_attribute(g, "min_mean_slip_dth", c.options.min_mean_slip_dth);
  write_double_attribute(g, "min_extent", c.min_extent);
  write_double_attribute(g, "min_mean_slip", c.min_mean_slip);
  write_u64_attribute(g, "exclude_first_last", c.options.exclude_first_last ? 1 : 0);
  write_double_attribute(g, "delta_th", c.delta_th);
  write_double_attribute(g, "dx", c.dx);
  write_double_attribute(g, "v0", c.v0);
  write_double_attribute(g, "mu", c.mu);
  write_u64_attribute(g, "n_nodes", c.n_nodes);
  write_u64_attribute(g, "n_nodal_slips", c.n_nodal_slips);
  write_u64_attribute(g, "n_events_detected", c.n_events_detected);
  write_u64_attribute(g, "n_events_excluded_first_last", c.n_events_excluded_first_last);
  write_u64_attribute(g, "n_events_below_thresholds", c.n_events_below_thresholds);
  write_u64_attribute(g, "n_events", c.n_events());
  write_string_attribute(g, "units",
                         "alpha, *_dx, *_dth: 1; waiting_time_threshold: s; min_extent, min_mean_slip, "
                         "delta_th, dx: m; v0: m/s; mu: Pa");
}

EventCatalog read_event_catalog(const std::string& path) {
  Handle file = open_file_read(path);
  Handle g = open_group(file, kEventsGroup, path);
  const std::string where = path + ":/events";
  EventCatalog c;
  c.t_start = read_vector<double>(g, "t_start", H5T_NATIVE_DOUBLE, where);
  c.duration = read_vector<double>(g, "T", H5T_NATIVE_DOUBLE, where);
  c.x_start = read_vector<double>(g, "x_start", H5T_NATIVE_DOUBLE, where);
  c.extent = read_vector<double>(g, "L_s", H5T_NATIVE_DOUBLE, where);
  c.mean_slip = read_vector<double>(g, "u_mean", H5T_NATIVE_DOUBLE, where);
  c.moment = read_vector<double>(g, "M0", H5T_NATIVE_DOUBLE, where);
  c.max_slip_rate = read_vector<double>(g, "max_slip_rate", H5T_NATIVE_DOUBLE, where);
  c.n_clusters = read_vector<int>(g, "n_clusters", H5T_NATIVE_INT, where);
  c.options.alpha = read_double_attribute(g, "alpha", where);
  c.waiting_time_threshold = read_double_attribute(g, "waiting_time_threshold", where);
  c.options.min_extent_dx = read_double_attribute(g, "min_extent_dx", where);
  c.options.min_mean_slip_dth = read_double_attribute(g, "min_mean_slip_dth", where);
  c.min_extent = read_double_attribute(g, "min_extent", where);
  c.min_mean_slip = read_double_attribute(g, "min_mean_slip", where);
  c.options.exclude_first_last = read_u64_attribute(g, "exclude_first_last", where) != 0;
  c.delta_th = read_double_attribute(g, "delta_th", where);
  c.dx = read_double_attribute(g, "dx", where);
  c.v0 = read_double_attribute(g, "v0", where);
  c.mu = read_double_attribute(g, "mu", where);
  c.n_nodes = read_u64_attribute(g, "n_nodes", where);
  c.n_nodal_slips = read_u64_attribute(g, "n_nodal_slips", where);
  c.n_events_detected = read_u64_attribute(g, "n_events_detected", where);
  c.n_events_excluded_first_last = read_u64_attribute(g, "n_events_excluded_first_last", where);
  c.n_events_below_thresholds = read_u64_attribute(g, "n_events_below_thresholds", where);
  return c;
}

void write_event_catalog_csv(const std::string& path, const EventCatalog& c) {
  std::ofstream out(path);
  if (!out) throw std::invalid_argument("path = '" + path + "' is invalid: cannot open for writing");
  out << "t_start_s,T_s,x_start_m,L_s_m,u_mean_m,M0_N_per_m,max_slip_rate_m_per_s,n_clusters\n";
  out << std::setprecision(17);
  for (std::size_t e = 0; e < c.n_events(); ++e)
    out << c.t_start[e] << ',' << c.duration[e] << ',' << c.x_start[e] << ',' << c.extent[e] << ','
        << c.mean_slip[e] << ',' << c.moment[e] << ',' << c.max_slip_rate[e] << ',' << c.n_clusters[e] << '\n';
  if (!out) throw std::runtime_error("writing CSV '" + path + "' failed");
}

}  // namespace slipstrip::events
