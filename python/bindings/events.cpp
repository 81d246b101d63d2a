// Slip-event identification (events/event_detection.hpp, events/catalog_io.hpp).
// Catalogs cross the boundary as dicts of NumPy arrays (field names of
// EventCatalog, not the HDF5 dataset names: duration, extent, mean_slip,
// moment rather than T, L_s, u_mean, M0) plus scalar metadata.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <hdf5.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "events/catalog_io.hpp"
#include "events/event_detection.hpp"

namespace py = pybind11;
namespace ev = slipstrip::events;

namespace {

// Hands a vector's buffer to NumPy without copying: the vector moves onto the
// heap and a capsule deletes it when the array dies.
template <class T>
py::array_t<T> to_numpy(std::vector<T>&& v) {
  auto* owned = new std::vector<T>(std::move(v));
  py::capsule free_when_done(owned, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  return py::array_t<T>({static_cast<py::ssize_t>(owned->size())}, {static_cast<py::ssize_t>(sizeof(T))},
                        owned->data(), free_when_done);
}

template <class T>
std::vector<T> from_numpy(const py::dict& d, const char* key) {
  if (!d.contains(key))
    throw std::invalid_argument(std::string("catalog['") + key + "'] is missing: a catalog dict needs t_start, "
                                "duration, x_start, extent, mean_slip, moment, max_slip_rate, n_clusters");
  auto a = py::array_t<T, py::array::c_style | py::array::forcecast>::ensure(d[key]);
  if (!a || a.ndim() != 1)
    throw std::invalid_argument(std::string("catalog['") + key + "'] is invalid: expected a 1-D numeric array");
  return std::vector<T>(a.data(), a.data() + a.size());
}

ev::EventDetectionOptions make_options(double alpha, double min_extent_dx, double min_mean_slip_dth,
                                       bool exclude_first_last, std::size_t block_rows, double min_slip_rate_v0) {
  ev::EventDetectionOptions o;
  o.alpha = alpha;
  o.min_slip_rate_v0 = min_slip_rate_v0;
  o.min_extent_dx = min_extent_dx;
  o.min_mean_slip_dth = min_mean_slip_dth;
  o.exclude_first_last = exclude_first_last;
  o.block_rows = block_rows;
  return o;
}

py::dict catalog_to_dict(ev::EventCatalog&& c) {
  py::dict d;
  d["t_start"] = to_numpy(std::move(c.t_start));
  d["duration"] = to_numpy(std::move(c.duration));
  d["x_start"] = to_numpy(std::move(c.x_start));
  d["extent"] = to_numpy(std::move(c.extent));
  d["mean_slip"] = to_numpy(std::move(c.mean_slip));
  d["moment"] = to_numpy(std::move(c.moment));
  d["max_slip_rate"] = to_numpy(std::move(c.max_slip_rate));
  d["n_clusters"] = to_numpy(std::move(c.n_clusters));
  if (c.nodes_z > 1) {
    // A 2D interface (docs/3d.md): each event a connected patch in (x, z).
    d["z_start"] = to_numpy(std::move(c.z_start));
    d["extent_z"] = to_numpy(std::move(c.extent_z));
    d["area"] = to_numpy(std::move(c.area));
    d["nodes_z"] = c.nodes_z;
    d["dz"] = c.dz;
  }
  py::dict options;
  options["alpha"] = c.options.alpha;
  options["min_extent_dx"] = c.options.min_extent_dx;
  options["min_mean_slip_dth"] = c.options.min_mean_slip_dth;
  options["exclude_first_last"] = c.options.exclude_first_last;
  options["block_rows"] = c.options.block_rows;
  options["min_slip_rate_v0"] = c.options.min_slip_rate_v0;
  d["options"] = options;
  d["min_slip_rate"] = c.min_slip_rate;
  d["n_nodal_slips_below_min_slip_rate"] = c.n_nodal_slips_below_min_slip_rate;
  d["delta_th"] = c.delta_th;
  d["dx"] = c.dx;
  d["v0"] = c.v0;
  d["mu"] = c.mu;
  d["n_nodes"] = c.n_nodes;
  d["waiting_time_threshold"] = c.waiting_time_threshold;
  d["min_extent"] = c.min_extent;
  d["min_mean_slip"] = c.min_mean_slip;
  d["n_nodal_slips"] = c.n_nodal_slips;
  d["n_events_detected"] = c.n_events_detected;
  d["n_events_excluded_first_last"] = c.n_events_excluded_first_last;
  d["n_events_below_thresholds"] = c.n_events_below_thresholds;
  d["peak_window_rows"] = c.peak_window_rows;
  return d;
}

template <class T>
T scalar_or(const py::dict& d, const char* key, T fallback) {
  return d.contains(key) ? d[key].cast<T>() : fallback;
}

ev::EventCatalog catalog_from_dict(const py::dict& d) {
  ev::EventCatalog c;
  c.t_start = from_numpy<double>(d, "t_start");
  c.duration = from_numpy<double>(d, "duration");
  c.x_start = from_numpy<double>(d, "x_start");
  c.extent = from_numpy<double>(d, "extent");
  c.mean_slip = from_numpy<double>(d, "mean_slip");
  c.moment = from_numpy<double>(d, "moment");
  c.max_slip_rate = from_numpy<double>(d, "max_slip_rate");
  c.n_clusters = from_numpy<int>(d, "n_clusters");
  const std::size_t n = c.t_start.size();
  for (const auto* v : {&c.duration, &c.x_start, &c.extent, &c.mean_slip, &c.moment, &c.max_slip_rate})
    if (v->size() != n)
      throw std::invalid_argument("catalog arrays have different lengths: every array must have len(t_start) = " +
                                  std::to_string(n) + " entries");
  if (c.n_clusters.size() != n)
    throw std::invalid_argument("catalog['n_clusters'] has " + std::to_string(c.n_clusters.size()) +
                                " entries: expected len(t_start) = " + std::to_string(n));
  if (d.contains("options")) {
    const py::dict o = d["options"];
    c.options = make_options(scalar_or(o, "alpha", c.options.alpha), scalar_or(o, "min_extent_dx", c.options.min_extent_dx),
                             scalar_or(o, "min_mean_slip_dth", c.options.min_mean_slip_dth),
                             scalar_or(o, "exclude_first_last", c.options.exclude_first_last),
                             scalar_or(o, "block_rows", c.options.block_rows),
                             scalar_or(o, "min_slip_rate_v0", c.options.min_slip_rate_v0));
  }
  c.delta_th = scalar_or(d, "delta_th", 0.0);
  c.dx = scalar_or(d, "dx", 0.0);
  c.v0 = scalar_or(d, "v0", 0.0);
  c.mu = scalar_or(d, "mu", 0.0);
  c.n_nodes = scalar_or<std::size_t>(d, "n_nodes", 0);
  c.waiting_time_threshold = scalar_or(d, "waiting_time_threshold", 0.0);
  c.min_extent = scalar_or(d, "min_extent", 0.0);
  c.min_mean_slip = scalar_or(d, "min_mean_slip", 0.0);
  c.n_nodal_slips = scalar_or<std::uint64_t>(d, "n_nodal_slips", 0);
  c.min_slip_rate = scalar_or(d, "min_slip_rate", 0.0);
  c.n_nodal_slips_below_min_slip_rate = scalar_or<std::uint64_t>(d, "n_nodal_slips_below_min_slip_rate", 0);
  c.n_events_detected = scalar_or<std::uint64_t>(d, "n_events_detected", n);
  c.n_events_excluded_first_last = scalar_or<std::uint64_t>(d, "n_events_excluded_first_last", 0);
  c.n_events_below_thresholds = scalar_or<std::uint64_t>(d, "n_events_below_thresholds", 0);
  c.peak_window_rows = scalar_or<std::size_t>(d, "peak_window_rows", 0);
  return c;
}

ev::SlipSamplingInfo make_info(std::size_t n_nodes, double delta_th, double dx, double v0, double mu,
                               const py::object& x, double D, double L) {
  ev::SlipSamplingInfo info;
  info.delta_th = delta_th;
  info.dx = dx;
  info.v0 = v0;
  info.mu = mu;
  info.D = D;
  info.L = L;
  if (x.is_none()) {
    info.x.resize(n_nodes);
    for (std::size_t i = 0; i < n_nodes; ++i) info.x[i] = static_cast<double>(i) * dx;
  } else {
    info.x = x.cast<std::vector<double>>();
    if (info.x.size() != n_nodes)
      throw std::invalid_argument("x has " + std::to_string(info.x.size()) +
                                  " entries: expected one per column of crossing_time (" + std::to_string(n_nodes) + ")");
  }
  return info;
}

// HDF5 prints its error stack to stderr on every thread that has not turned
// that off (h5py turns it off on the main thread only), so a damaged run file
// read from a scan's worker thread would bury the one-line cause that our
// exception already carries.  For the duration of one call, on the calling
// thread, the printing is off (as in the CLI, apps/slipstrip_main.cpp); the
// thread's previous setting is restored afterwards.
class QuietHdf5Errors {
 public:
  QuietHdf5Errors() {
    H5Eget_auto2(H5E_DEFAULT, &print_, &client_data_);
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  }
  ~QuietHdf5Errors() { H5Eset_auto2(H5E_DEFAULT, print_, client_data_); }
  QuietHdf5Errors(const QuietHdf5Errors&) = delete;
  QuietHdf5Errors& operator=(const QuietHdf5Errors&) = delete;

 private:
  H5E_auto2_t print_ = nullptr;
  void* client_data_ = nullptr;
};

using CrossingArray = py::array_t<double, py::array::c_style | py::array::forcecast>;

void check_matrix(const CrossingArray& a) {
  if (a.ndim() != 2)
    throw std::invalid_argument("crossing_time has " + std::to_string(a.ndim()) +
                                " dimensions: expected a 2-D array [n_levels, N]");
}

}  // namespace

void bind_events(py::module_& m) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  m.def(
      "detect_events_in_file",
      [](const std::filesystem::path& path, double alpha, double min_extent_dx, double min_mean_slip_dth,
         bool exclude_first_last, std::size_t block_rows, double min_slip_rate_v0) {
        const auto options =
            make_options(alpha, min_extent_dx, min_mean_slip_dth, exclude_first_last, block_rows, min_slip_rate_v0);
        ev::EventCatalog c;
        {
          py::gil_scoped_release release;
          const QuietHdf5Errors quiet;
          c = ev::detect_events_in_file(path.string(), options);
        }
        return catalog_to_dict(std::move(c));
      },
      py::arg("path"), py::arg("alpha") = 15.0, py::arg("min_extent_dx") = 2.0, py::arg("min_mean_slip_dth") = 2.0,
      py::arg("exclude_first_last") = true, py::arg("block_rows") = 256, py::arg("min_slip_rate_v0") = 0.0,
      "Detect slip events from /slip_sampling of an HDF5 file (streamed); nodal slips slower than "
      "min_slip_rate_v0 * v0 are ignored (0: none).  Returns a catalog dict.");
  // What `slipstrip events RUN [--out OUT]` does (apps/slipstrip_main.cpp),
  // in-process: detection and the /events write both in C++, so the file
  // written is the CLI's byte for byte and the arrays never cross into Python
  // and back.
  m.def(
      "detect_events_into_file",
      [](const std::filesystem::path& run_path, const std::optional<std::filesystem::path>& out_path, double alpha,
         double min_extent_dx, double min_mean_slip_dth, bool exclude_first_last, std::size_t block_rows,
         double min_slip_rate_v0) {
        const auto options =
            make_options(alpha, min_extent_dx, min_mean_slip_dth, exclude_first_last, block_rows, min_slip_rate_v0);
        const std::string target = out_path ? out_path->string() : run_path.string();
        ev::EventCatalog c;
        {
          py::gil_scoped_release release;
          const QuietHdf5Errors quiet;
          c = ev::detect_events_in_file(run_path.string(), options);
          ev::write_event_catalog(target, c);
        }
        return catalog_to_dict(std::move(c));
      },
      py::arg("run_path"), py::arg("out_path") = py::none(), py::arg("alpha") = 15.0, py::arg("min_extent_dx") = 2.0,
      py::arg("min_mean_slip_dth") = 2.0, py::arg("exclude_first_last") = true, py::arg("block_rows") = 256,
      py::arg("min_slip_rate_v0") = 0.0,
      "Detect slip events from /slip_sampling of run_path and write the catalog as /events of out_path "
      "(default: the run file itself, replacing its /events), as `slipstrip events` does.  Returns the "
      "catalog dict.");
  m.def(
      "detect_events",
      [](CrossingArray crossing_time, double delta_th, double dx, double v0, double mu, py::object x, double D,
         double L, double alpha, double min_extent_dx, double min_mean_slip_dth, bool exclude_first_last,
         std::size_t block_rows, double min_slip_rate_v0) {
        check_matrix(crossing_time);
        const auto n_levels = static_cast<std::size_t>(crossing_time.shape(0));
        const auto n_nodes = static_cast<std::size_t>(crossing_time.shape(1));
        const auto info = make_info(n_nodes, delta_th, dx, v0, mu, x, D, L);
        const auto options =
            make_options(alpha, min_extent_dx, min_mean_slip_dth, exclude_first_last, block_rows, min_slip_rate_v0);
        const ev::RowMajorCrossingTimes source({crossing_time.data(), n_levels * n_nodes}, n_levels, n_nodes);
        ev::EventCatalog c;
        {
          py::gil_scoped_release release;  // `crossing_time` keeps the buffer alive
          c = ev::detect_events(source, info, options);
        }
        return catalog_to_dict(std::move(c));
      },
      py::arg("crossing_time"), py::arg("delta_th"), py::arg("dx"), py::arg("v0"), py::arg("mu"),
      py::arg("x") = py::none(), py::arg("D") = nan, py::arg("L") = nan, py::arg("alpha") = 15.0,
      py::arg("min_extent_dx") = 2.0, py::arg("min_mean_slip_dth") = 2.0, py::arg("exclude_first_last") = true,
      py::arg("block_rows") = 256, py::arg("min_slip_rate_v0") = 0.0,
      "Detect slip events from an in-memory crossing_time [n_levels, N] (NaN = not reached); nodal slips "
      "slower than min_slip_rate_v0 * v0 are ignored (0: none).");
  m.def(
      "read_event_catalog", [](const std::filesystem::path& path) { return catalog_to_dict(ev::read_event_catalog(path.string())); },
      py::arg("path"), "Read /events of an HDF5 file as a catalog dict.");
  m.def(
      "write_event_catalog",
      [](const std::filesystem::path& path, const py::dict& catalog) { ev::write_event_catalog(path.string(), catalog_from_dict(catalog)); },
      py::arg("path"), py::arg("catalog"), "Write a catalog dict as /events (replacing an existing one).");
  m.def(
      "write_event_catalog_csv",
      [](const std::filesystem::path& path, const py::dict& catalog) {
        ev::write_event_catalog_csv(path.string(), catalog_from_dict(catalog));
      },
      py::arg("path"), py::arg("catalog"));
  m.def(
      "write_slip_sampling",
      [](const std::filesystem::path& path, CrossingArray crossing_time, double delta_th, double dx, double v0, double mu,
         py::object x, double D, double L) {
        check_matrix(crossing_time);
        const auto n_levels = static_cast<std::size_t>(crossing_time.shape(0));
        const auto n_nodes = static_cast<std::size_t>(crossing_time.shape(1));
        const auto info = make_info(n_nodes, delta_th, dx, v0, mu, x, D, L);
        ev::write_slip_sampling(path.string(), info, {crossing_time.data(), n_levels * n_nodes}, n_levels);
      },
      py::arg("path"), py::arg("crossing_time"), py::arg("delta_th"), py::arg("dx"), py::arg("v0"), py::arg("mu"),
      py::arg("x") = py::none(), py::arg("D") = nan, py::arg("L") = nan,
      "Create (truncate) an HDF5 file holding only /slip_sampling (synthetic input).");
  m.def(
      "read_slip_sampling_info",
      [](const std::filesystem::path& path) {
        auto info = ev::read_slip_sampling_info(path.string());
        py::dict d;
        d["delta_th"] = info.delta_th;
        d["dx"] = info.dx;
        d["v0"] = info.v0;
        d["mu"] = info.mu;
        d["D"] = info.D;
        d["L"] = info.L;
        d["x"] = to_numpy(std::move(info.x));
        return d;
      },
      py::arg("path"));
  m.def("waiting_time_threshold", &ev::waiting_time_threshold, py::arg("alpha"), py::arg("delta_th"), py::arg("v0"),
        py::arg("n_nodes"), "alpha * delta_th / (v0 * n_nodes) [s]");
  m.def(
      "empty_catalog_reason",
      [](const py::dict& attrs, double run_duration) -> std::string {
        if (scalar_or<std::uint64_t>(attrs, "n_events", 0) > 0) return "";
        ev::EventCatalog c;  // only the counts and scales the reason quotes
        c.options.alpha = scalar_or(attrs, "alpha", c.options.alpha);
        c.options.min_extent_dx = scalar_or(attrs, "min_extent_dx", c.options.min_extent_dx);
        c.options.min_mean_slip_dth = scalar_or(attrs, "min_mean_slip_dth", c.options.min_mean_slip_dth);
        c.options.min_slip_rate_v0 = scalar_or(attrs, "min_slip_rate_v0", 0.0);
        c.nodes_z = static_cast<int>(scalar_or<std::int64_t>(attrs, "nodes_z", 1));
        c.n_nodal_slips_below_min_slip_rate = scalar_or<std::uint64_t>(attrs, "n_nodal_slips_below_min_slip_rate", 0);
        c.delta_th = scalar_or(attrs, "delta_th", 0.0);
        c.v0 = scalar_or(attrs, "v0", 0.0);
        c.n_nodal_slips = scalar_or<std::uint64_t>(attrs, "n_nodal_slips", 0);
        c.n_events_detected = scalar_or<std::uint64_t>(attrs, "n_events_detected", 0);
        c.n_events_below_thresholds = scalar_or<std::uint64_t>(attrs, "n_events_below_thresholds", 0);
        return ev::empty_catalog_reason(c, run_duration);
      },
      py::arg("attrs"), py::arg("run_duration") = 0.0,
      "Why a catalog keeps no event and what to change (one line; '' if it keeps events), from the "
      "attributes of its /events group (docs/events.md); run_duration [s] is quoted when > 0.");
}
