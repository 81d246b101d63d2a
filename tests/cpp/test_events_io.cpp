// HDF5 round trips of /slip_sampling and /events, and streaming detection
// from a file that holds only /slip_sampling.
#include <doctest/doctest.h>
#include <hdf5.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "events/catalog_io.hpp"
#include "io/attributes.hpp"

using namespace slipstrip::events;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// A unique scratch file, removed on scope exit.
struct TempFile {
  std::string path;
  explicit TempFile(const std::string& tag)
      : path((std::filesystem::temp_directory_path() /
              ("slipstrip_test_events_" + tag + "_" + std::to_string(::getpid()) + ".h5")).string()) {
    std::filesystem::remove(path);
  }
  ~TempFile() { std::filesystem::remove(path); }
};

struct Sample {
  SlipSamplingInfo info;
  std::vector<double> crossing_time;
  std::size_t n_levels = 0;
};

// Random stick-slip history on N = 96 nodes: bursts of NS on random patches
// separated by long sticking periods, with NaN tails of different lengths.
Sample make_sample() {
  Sample s;
  const std::size_t n = 96;
  s.info.delta_th = 1e-8;
  s.info.dx = 4.0 / 1600;
  s.info.v0 = 2e-3;
  s.info.mu = 9.0e9;
  s.info.D = 5e-7;
  s.info.L = s.info.dx * n;
  s.info.x.resize(n);
  for (std::size_t i = 0; i < n; ++i) s.info.x[i] = (static_cast<double>(i) + 0.5) * s.info.dx;
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<std::vector<double>> cols(n);
  double t = 0.0;
  for (int e = 0; e < 60; ++e) {
    t += 1e-4 * (1 + u(rng));
    const std::size_t first = rng() % n, width = 1 + rng() % 30;
    for (std::size_t d = 0; d < width; ++d) {
      const int levels = 1 + static_cast<int>(6 * u(rng));
      for (int q = 0; q < levels; ++q) {
        auto& c = cols[(first + d) % n];
        c.push_back(std::max(t + d * 1e-8 + q * 5e-8, c.empty() ? 0.0 : c.back()));
      }
    }
  }
  for (const auto& c : cols) s.n_levels = std::max(s.n_levels, c.size());
  s.crossing_time.assign(s.n_levels * n, kNaN);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < cols[i].size(); ++j) s.crossing_time[j * n + i] = cols[i][j];
  return s;
}

std::string read_units(const std::string& path, const std::string& dataset) {
  const slipstrip::io::Handle f = slipstrip::io::open_file(path, slipstrip::io::FileAccess::read_only);
  const slipstrip::io::Handle d(H5Dopen2(f, dataset.c_str(), H5P_DEFAULT), "open dataset");
  return slipstrip::io::read_string_attribute(d, "units");
}

void check_same(const std::vector<double>& a, const std::vector<double>& b) {
  REQUIRE(a.size() == b.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    if (std::isnan(a[k])) CHECK(std::isnan(b[k]));
    else CHECK(a[k] == b[k]);  // binary float64 round trip: exact
  }
}

}  // namespace

TEST_CASE("/slip_sampling round trip: metadata, x and row-block reads are exact") {
  const Sample s = make_sample();
  TempFile tmp("slip");
  write_slip_sampling(tmp.path, s.info, s.crossing_time, s.n_levels);

  const SlipSamplingInfo info = read_slip_sampling_info(tmp.path);
  CHECK(info.delta_th == s.info.delta_th);
  CHECK(info.dx == s.info.dx);
  CHECK(info.v0 == s.info.v0);
  CHECK(info.mu == s.info.mu);
  CHECK(info.D == s.info.D);
  CHECK(info.L == s.info.L);
  check_same(info.x, s.info.x);

  const Hdf5CrossingTimes src(tmp.path);
  REQUIRE(src.n_levels() == s.n_levels);
  REQUIRE(src.n_nodes() == s.info.x.size());
  // Read in uneven blocks and compare element by element (NaN tails included).
  std::vector<double> back(s.crossing_time.size());
  const std::size_t n = src.n_nodes();
  for (std::size_t j0 = 0; j0 < s.n_levels; j0 += 7) {
    const std::size_t j1 = std::min(s.n_levels, j0 + 7);
    src.read_rows(j0, j1, std::span<double>(back.data() + j0 * n, (j1 - j0) * n));
  }
  check_same(back, s.crossing_time);
}

TEST_CASE("detection from a file holding only /slip_sampling equals in-memory detection") {
  const Sample s = make_sample();
  TempFile tmp("detect");
  write_slip_sampling(tmp.path, s.info, s.crossing_time, s.n_levels);
  EventDetectionOptions o;
  o.block_rows = 3;
  const EventCatalog from_file = detect_events_in_file(tmp.path, o);
  const RowMajorCrossingTimes mem(s.crossing_time, s.n_levels, s.info.x.size());
  const EventCatalog in_memory = detect_events(mem, s.info, o);
  REQUIRE(in_memory.n_events() > 10);
  CHECK(from_file.n_nodal_slips == in_memory.n_nodal_slips);
  CHECK(from_file.n_events_detected == in_memory.n_events_detected);
  check_same(from_file.t_start, in_memory.t_start);
  check_same(from_file.duration, in_memory.duration);
  check_same(from_file.extent, in_memory.extent);
  check_same(from_file.moment, in_memory.moment);
  CHECK(from_file.n_clusters == in_memory.n_clusters);
}

TEST_CASE("/events round trip, units attributes, replacement of an existing /events, CSV") {
  const Sample s = make_sample();
  TempFile tmp("events");
  write_slip_sampling(tmp.path, s.info, s.crossing_time, s.n_levels);
  EventDetectionOptions o;
  o.alpha = 8.0;
  o.min_extent_dx = 3.0;
  const EventCatalog cat = detect_events_in_file(tmp.path, o);
  REQUIRE(cat.n_events() > 0);

  // First write a dummy catalog, then the real one: /events is replaced.
  EventCatalog dummy = cat;
  dummy.t_start.assign(1, 1.0);
  dummy.duration.assign(1, 1.0);
  dummy.x_start.assign(1, 1.0);
  dummy.extent.assign(1, 1.0);
  dummy.mean_slip.assign(1, 1.0);
  dummy.moment.assign(1, 1.0);
  dummy.max_slip_rate.assign(1, 1.0);
  dummy.n_clusters.assign(1, 1);
  write_event_catalog(tmp.path, dummy);
  write_event_catalog(tmp.path, cat);

  const EventCatalog back = read_event_catalog(tmp.path);
  check_same(back.t_start, cat.t_start);
  check_same(back.duration, cat.duration);
  check_same(back.x_start, cat.x_start);
  check_same(back.extent, cat.extent);
  check_same(back.mean_slip, cat.mean_slip);
  check_same(back.moment, cat.moment);
  check_same(back.max_slip_rate, cat.max_slip_rate);
  CHECK(back.n_clusters == cat.n_clusters);
  CHECK(back.options.alpha == 8.0);
  CHECK(back.options.min_extent_dx == 3.0);
  CHECK(back.options.min_mean_slip_dth == 2.0);
  CHECK(back.options.exclude_first_last);
  CHECK(back.waiting_time_threshold == cat.waiting_time_threshold);
  CHECK(back.min_extent == cat.min_extent);
  CHECK(back.delta_th == cat.delta_th);
  CHECK(back.n_nodes == cat.n_nodes);
  CHECK(back.n_nodal_slips == cat.n_nodal_slips);
  CHECK(back.n_events_detected == cat.n_events_detected);
  CHECK(back.n_events_excluded_first_last == 2);
  CHECK(back.n_events_below_thresholds == cat.n_events_below_thresholds);

  // /slip_sampling is untouched by the append.
  const Hdf5CrossingTimes src(tmp.path);
  CHECK(src.n_levels() == s.n_levels);

  CHECK(read_units(tmp.path, "/events/t_start") == "s");
  CHECK(read_units(tmp.path, "/events/T") == "s");
  CHECK(read_units(tmp.path, "/events/x_start") == "m");
  CHECK(read_units(tmp.path, "/events/L_s") == "m");
  CHECK(read_units(tmp.path, "/events/u_mean") == "m");
  CHECK(read_units(tmp.path, "/events/M0") == "N/m");
  CHECK(read_units(tmp.path, "/events/max_slip_rate") == "m/s");
  CHECK(read_units(tmp.path, "/events/n_clusters") == "1");

  // A new file holding only /events; an empty catalog is written too.
  TempFile fresh("fresh");
  EventCatalog empty;
  write_event_catalog(fresh.path, empty);
  CHECK(read_event_catalog(fresh.path).n_events() == 0);

  TempFile csv("csv");
  write_event_catalog_csv(csv.path, cat);
  std::ifstream in(csv.path);
  std::size_t lines = 0;
  for (std::string line; std::getline(in, line);) ++lines;
  CHECK(lines == cat.n_events() + 1);
}

TEST_CASE("missing input is reported with the path and the missing item") {
  TempFile tmp("missing");
  CHECK_THROWS_WITH_AS(detect_events_in_file(tmp.path), doctest::Contains("does not exist"), std::invalid_argument);
  write_event_catalog(tmp.path, EventCatalog{});  // HDF5 file without /slip_sampling
  CHECK_THROWS_WITH_AS(detect_events_in_file(tmp.path), doctest::Contains("/slip_sampling"), std::invalid_argument);
}
