#include "events/catalog_io.hpp"

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <stdexcept>
#include <vector>

#include "io/attributes.hpp"
#include "io/datasets.hpp"

namespace slipstrip::events {

namespace {

constexpr const char* kSlipGroup = "slip_sampling";
constexpr const char* kEventsGroup = "events";

// A catalog field: 1-D dataset with its "units" attribute.
template <class T>
void write_field(hid_t group, const char* name, const std::vector<T>& values, const char* units) {
  io::write_vector(group, name, values);
  const io::Handle dataset = io::open_dataset(group, name);
  io::write_attribute(dataset, "units", units);
}

// /slip_sampling of a run file, or a message that says where it comes from:
// the run writes it only with output.delta_th > 0.
io::Handle open_slip_sampling(hid_t file, const std::string& path) {
  if (!io::has_member(file, kSlipGroup))
    throw std::invalid_argument(
        "'" + path + "' has no slip sampling (group /slip_sampling), from which events are detected: "
        "the run was made with output.delta_th = 0, which records none. Set [output] delta_th > 0 "
        "(e.g. 1e-8 m, a fraction of the characteristic slip D; docs/events.md) and run it again");
  return io::open_group(file, kSlipGroup);
}

// An optional scalar: NaN if absent (older files have no D and L).
double read_optional_double(hid_t object, const char* name) {
  if (!io::has_attribute(object, name)) return std::numeric_limits<double>::quiet_NaN();
  return io::read_attribute<double>(object, name);
}

}  // namespace

// ---------------------------------------------------------------------------

Hdf5CrossingTimes::Hdf5CrossingTimes(const std::string& path) {
  file_ = io::open_existing_file(path, io::FileAccess::read_only);
  const io::Handle group = open_slip_sampling(file_, path);
  dataset_ = io::open_dataset(group, "crossing_time");
  {
    io::Handle type(H5Dget_type(dataset_), "H5Dget_type crossing_time");
    if (H5Tget_class(type) != H5T_FLOAT)
      throw std::invalid_argument("path = '" + path + "' is invalid: /slip_sampling/crossing_time must hold "
                                  "floating-point times [s] (NaN = level not reached), not integers, "
                                  "booleans or strings");
  }
  const std::vector<hsize_t> dims = io::extent(dataset_);
  if (dims.size() != 2)
    throw std::invalid_argument("/slip_sampling/crossing_time rank = " + std::to_string(dims.size()) +
                                " is invalid: must be 2 ([n_levels, N])");
  n_levels_ = static_cast<std::size_t>(dims[0]);
  n_nodes_ = static_cast<std::size_t>(dims[1]);
}

void Hdf5CrossingTimes::read_rows(std::size_t j0, std::size_t j1, std::span<double> block) const {
  if (j1 <= j0) return;
  io::read_rows(dataset_, j0, j1 - j0, block.data());
}

SlipSamplingInfo read_slip_sampling_info(const std::string& path) {
  const io::Handle file = io::open_existing_file(path, io::FileAccess::read_only);
  const io::Handle group = open_slip_sampling(file, path);
  SlipSamplingInfo info;
  info.delta_th = io::read_attribute<double>(group, "delta_th");
  info.dx = io::read_attribute<double>(group, "dx");
  info.v0 = io::read_attribute<double>(group, "v0");
  info.mu = io::read_attribute<double>(group, "mu");
  info.D = read_optional_double(group, "D");
  info.L = read_optional_double(group, "L");
  if (io::has_member(group, "x")) {
    info.x = io::read_vector<double>(group, "x");
  } else {
    // Older or minimal files: nodes are equally spaced from x = 0.
    const std::vector<hsize_t> dims = io::extent(io::open_dataset(group, "crossing_time"));
    if (dims.size() != 2)
      throw std::invalid_argument("/slip_sampling/crossing_time rank = " + std::to_string(dims.size()) +
                                  " is invalid: must be 2 ([n_levels, N])");
    info.x.resize(static_cast<std::size_t>(dims[1]));
    for (std::size_t i = 0; i < info.x.size(); ++i) info.x[i] = static_cast<double>(i) * info.dx;
  }
  if (io::has_attribute(group, "nodes_z")) {
    info.nodes_z = static_cast<int>(io::read_attribute<std::int64_t>(group, "nodes_z"));
    info.dz = io::read_attribute<double>(group, "dz");
    info.W = io::read_attribute<double>(group, "W");
    info.z = io::read_vector<double>(group, "z");
  }
  return info;
}

EventCatalog detect_events_in_file(const std::string& path, const EventDetectionOptions& options) {
  const SlipSamplingInfo info = read_slip_sampling_info(path);
  const Hdf5CrossingTimes source(path);
  return detect_events(source, info, options);
}

void write_slip_sampling_attributes(hid_t group, const SlipSamplingInfo& info) {
  io::write_attribute(group, "delta_th", info.delta_th);
  io::write_attribute(group, "dx", info.dx);
  io::write_attribute(group, "v0", info.v0);
  io::write_attribute(group, "mu", info.mu);
  io::write_attribute(group, "D", info.D);
  io::write_attribute(group, "L", info.L);
  // A 2D interface only: one-dimensional files are unchanged.
  if (info.nodes_z > 1) {
    io::write_attribute(group, "nodes_z", static_cast<std::int64_t>(info.nodes_z));
    io::write_attribute(group, "dz", info.dz);
    io::write_attribute(group, "W", info.W);
  }
}

void write_slip_sampling(const std::string& path, const SlipSamplingInfo& info,
                         std::span<const double> crossing_time, std::size_t n_levels) {
  const std::size_t n = info.x.size();
  if (crossing_time.size() != n_levels * n)
    throw std::invalid_argument("crossing_time size = " + std::to_string(crossing_time.size()) +
                                " is invalid: must equal n_levels * x.size() = " + std::to_string(n_levels) +
                                " * " + std::to_string(n));
  io::Handle file = io::create_file(path);
  {
    const io::Handle group = io::create_group(file, kSlipGroup);
    write_slip_sampling_attributes(group, info);
    write_field(group, "x", info.x, "m");
    if (info.nodes_z > 1) write_field(group, "z", info.z, "m");

    // Chunked by whole rows, like the solver appends them, so row-block reads
    // touch contiguous chunks.
    const hsize_t dims[2] = {static_cast<hsize_t>(n_levels), static_cast<hsize_t>(n)};
    std::vector<hsize_t> chunk;
    if (n_levels > 0 && n > 0) chunk = {std::max<hsize_t>(1, std::min<hsize_t>(dims[0], (1u << 17) / dims[1] + 1)), dims[1]};
    io::write_array(group, "crossing_time", dims, crossing_time, chunk);
    io::write_attribute(io::open_dataset(group, "crossing_time"), "units", "s");
  }
  io::close_file(file);
}

void write_event_catalog(const std::string& path, const EventCatalog& c) {
  io::Handle file;
  if (std::filesystem::exists(path)) {
    if (H5Fis_hdf5(path.c_str()) <= 0)
      throw std::invalid_argument("path = '" + path + "' is invalid: exists but is not an HDF5 file");
    file = io::open_file(path, io::FileAccess::read_write);
    io::remove_member_if_present(file, kEventsGroup);
  } else {
    file = io::create_file(path, io::FileCreation::exclusive);
  }
  {
    const io::Handle g = io::create_group(file, kEventsGroup);
    write_field(g, "t_start", c.t_start, "s");
    write_field(g, "T", c.duration, "s");
    write_field(g, "x_start", c.x_start, "m");
    write_field(g, "L_s", c.extent, "m");
    write_field(g, "u_mean", c.mean_slip, "m");
    // A 2D interface: M0 = mu A u_mean is a moment [N m]; L_s the extent along x.
    write_field(g, "M0", c.moment, c.nodes_z > 1 ? "N m" : "N/m");
    write_field(g, "max_slip_rate", c.max_slip_rate, "m/s");
    write_field(g, "n_clusters", c.n_clusters, "1");  // int32
    if (c.nodes_z > 1) {
      write_field(g, "z_start", c.z_start, "m");
      write_field(g, "L_z", c.extent_z, "m");
      write_field(g, "A", c.area, "m^2");
      io::write_attribute(g, "nodes_z", static_cast<std::int64_t>(c.nodes_z));
      io::write_attribute(g, "dz", c.dz);
    }

    // Counts and flags are unsigned 64-bit integers in the file.
    const auto count = [&](const char* name, std::uint64_t value) { io::write_attribute(g, name, value); };
    io::write_attribute(g, "alpha", c.options.alpha);
    io::write_attribute(g, "waiting_time_threshold", c.waiting_time_threshold);
    io::write_attribute(g, "min_extent_dx", c.options.min_extent_dx);
    io::write_attribute(g, "min_mean_slip_dth", c.options.min_mean_slip_dth);
    io::write_attribute(g, "min_extent", c.min_extent);
    io::write_attribute(g, "min_mean_slip", c.min_mean_slip);
    // The creep filter (0: off, every nodal slip counted).
    io::write_attribute(g, "min_slip_rate_v0", c.options.min_slip_rate_v0);
    io::write_attribute(g, "min_slip_rate", c.min_slip_rate);
    count("exclude_first_last", c.options.exclude_first_last ? 1 : 0);
    io::write_attribute(g, "delta_th", c.delta_th);
    io::write_attribute(g, "dx", c.dx);
    io::write_attribute(g, "v0", c.v0);
    io::write_attribute(g, "mu", c.mu);
    count("n_nodes", c.n_nodes);
    count("n_nodal_slips", c.n_nodal_slips);
    count("n_nodal_slips_below_min_slip_rate", c.n_nodal_slips_below_min_slip_rate);
    count("n_events_detected", c.n_events_detected);
    count("n_events_excluded_first_last", c.n_events_excluded_first_last);
    count("n_events_below_thresholds", c.n_events_below_thresholds);
    count("n_events", c.n_events());
    io::write_attribute(g, "units",
                        "alpha, *_dx, *_dth, *_v0: 1; waiting_time_threshold: s; min_extent, min_mean_slip, "
                        "delta_th, dx: m; v0, min_slip_rate: m/s; mu: Pa");
  }
  io::close_file(file);
}

EventCatalog read_event_catalog(const std::string& path) {
  const io::Handle file = io::open_existing_file(path, io::FileAccess::read_only);
  const io::Handle g = io::open_group(file, kEventsGroup);
  EventCatalog c;
  c.t_start = io::read_vector<double>(g, "t_start");
  c.duration = io::read_vector<double>(g, "T");
  c.x_start = io::read_vector<double>(g, "x_start");
  c.extent = io::read_vector<double>(g, "L_s");
  c.mean_slip = io::read_vector<double>(g, "u_mean");
  c.moment = io::read_vector<double>(g, "M0");
  c.max_slip_rate = io::read_vector<double>(g, "max_slip_rate");
  c.n_clusters = io::read_vector<int>(g, "n_clusters");
  if (io::has_attribute(g, "nodes_z")) {
    c.nodes_z = static_cast<int>(io::read_attribute<std::int64_t>(g, "nodes_z"));
    c.dz = io::read_attribute<double>(g, "dz");
    c.z_start = io::read_vector<double>(g, "z_start");
    c.extent_z = io::read_vector<double>(g, "L_z");
    c.area = io::read_vector<double>(g, "A");
  }
  c.options.alpha = io::read_attribute<double>(g, "alpha");
  c.waiting_time_threshold = io::read_attribute<double>(g, "waiting_time_threshold");
  c.options.min_extent_dx = io::read_attribute<double>(g, "min_extent_dx");
  c.options.min_mean_slip_dth = io::read_attribute<double>(g, "min_mean_slip_dth");
  c.min_extent = io::read_attribute<double>(g, "min_extent");
  c.min_mean_slip = io::read_attribute<double>(g, "min_mean_slip");
  // Catalogs written before the creep filter existed have none: they are unfiltered.
  if (io::has_attribute(g, "min_slip_rate_v0")) {
    c.options.min_slip_rate_v0 = io::read_attribute<double>(g, "min_slip_rate_v0");
    c.min_slip_rate = io::read_attribute<double>(g, "min_slip_rate");
    c.n_nodal_slips_below_min_slip_rate = io::read_attribute<std::uint64_t>(g, "n_nodal_slips_below_min_slip_rate");
  }
  c.options.exclude_first_last = io::read_attribute<std::uint64_t>(g, "exclude_first_last") != 0;
  c.delta_th = io::read_attribute<double>(g, "delta_th");
  c.dx = io::read_attribute<double>(g, "dx");
  c.v0 = io::read_attribute<double>(g, "v0");
  c.mu = io::read_attribute<double>(g, "mu");
  c.n_nodes = io::read_attribute<std::uint64_t>(g, "n_nodes");
  c.n_nodal_slips = io::read_attribute<std::uint64_t>(g, "n_nodal_slips");
  c.n_events_detected = io::read_attribute<std::uint64_t>(g, "n_events_detected");
  c.n_events_excluded_first_last = io::read_attribute<std::uint64_t>(g, "n_events_excluded_first_last");
  c.n_events_below_thresholds = io::read_attribute<std::uint64_t>(g, "n_events_below_thresholds");
  return c;
}

void write_event_catalog_csv(const std::string& path, const EventCatalog& c) {
  std::ofstream out(path);
  if (!out) throw std::invalid_argument("path = '" + path + "' is invalid: cannot open for writing");
  const bool plane = c.nodes_z > 1;  // a 2D interface: three more columns, M0 in N m
  out << "t_start_s,T_s,x_start_m,L_s_m,u_mean_m," << (plane ? "M0_N_m" : "M0_N_per_m")
      << ",max_slip_rate_m_per_s,n_clusters" << (plane ? ",z_start_m,L_z_m,A_m2" : "") << "\n";
  out << std::setprecision(17);
  for (std::size_t e = 0; e < c.n_events(); ++e) {
    out << c.t_start[e] << ',' << c.duration[e] << ',' << c.x_start[e] << ',' << c.extent[e] << ','
        << c.mean_slip[e] << ',' << c.moment[e] << ',' << c.max_slip_rate[e] << ',' << c.n_clusters[e];
    if (plane) out << ',' << c.z_start[e] << ',' << c.extent_z[e] << ',' << c.area[e];
    out << '\n';
  }
  if (!out) throw std::runtime_error("writing CSV '" + path + "' failed");
}

}  // namespace slipstrip::events
