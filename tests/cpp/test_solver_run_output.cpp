// RunOutput: the HDF5 run file.  Everything is read back with the plain HDF5
// C API (not through RunOutput) and compared with values computed here.
#include <doctest/doctest.h>
#include <hdf5.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "solver/run_output.hpp"
#include "io/attributes.hpp"
#include "io/hdf5.hpp"
#include "slipstrip/version.hpp"

using slipstrip::RunOutput;
using slipstrip::RunOutputOptions;
using slipstrip::SlipSamplingSetup;
using slipstrip::io::Handle;

namespace {

std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() /
          ("slipstrip_" + std::to_string(getpid()) + "_" + name + ".h5"))
      .string();
}

struct Array {
  std::vector<double> values;
  std::vector<hsize_t> dims;
  double at(hsize_t row, hsize_t col) const { return values[row * dims[1] + col]; }
};

Array read_array(hid_t file, const std::string& name) {
  Handle dset(H5Dopen2(file, name.c_str(), H5P_DEFAULT), "open " + name);
  Handle space(H5Dget_space(dset), "space");
  const int rank = H5Sget_simple_extent_ndims(space);
  Array a;
  a.dims.resize(static_cast<std::size_t>(rank));
  H5Sget_simple_extent_dims(space, a.dims.data(), nullptr);
  hsize_t total = 1;
  for (hsize_t d : a.dims) total *= d;
  a.values.resize(total);
  if (total > 0)
    slipstrip::io::check(
        H5Dread(dset, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, a.values.data()),
        "read " + name);
  return a;
}

double read_double_attribute(hid_t object, const std::string& name) {
  Handle attr(H5Aopen(object, name.c_str(), H5P_DEFAULT), "open attribute " + name);
  double value = 0.0;
  slipstrip::io::check(H5Aread(attr, H5T_NATIVE_DOUBLE, &value), "read attribute " + name);
  return value;
}

std::string dataset_units(hid_t file, const std::string& name) {
  Handle dset(H5Dopen2(file, name.c_str(), H5P_DEFAULT), "open " + name);
  return read_string_attribute(dset, "units");
}

Handle open_read_only(const std::string& path) {
  return Handle(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), "open " + path);
}

bool looks_iso8601_utc(const std::string& s) {  // YYYY-MM-DDTHH:MM:SSZ
  return s.size() == 20 && s[4] == '-' && s[7] == '-' && s[10] == 'T' && s[13] == ':' &&
         s[16] == ':' && s[19] == 'Z';
}

// Independent reference for one node's crossing times: scan the whole
// trajectory (no band, no buffering), a level is reached at the first step
// whose end slip is >= (j+1) delta_th, dated by linear interpolation in that
// step; a level already passed by the initial slip is dated at the first time.
std::vector<double> reference_crossings(const std::vector<double>& times,
                                        const std::vector<double>& slip, double delta_th,
                                        std::size_t levels) {
  std::vector<double> out(levels, std::nan(""));
  for (std::size_t j = 0; j < levels; ++j) {
    const double threshold = static_cast<double>(j + 1) * delta_th;
    if (slip[0] >= threshold) {  // already passed when recording starts
      out[j] = times[0];
      continue;
    }
    for (std::size_t k = 1; k < times.size(); ++k) {
      if (slip[k] >= threshold) {
        double fraction = (threshold - slip[k - 1]) / (slip[k] - slip[k - 1]);
        fraction = std::min(1.0, std::max(0.0, fraction));
        out[j] = times[k - 1] + fraction * (times[k] - times[k - 1]);
        break;
      }
    }
  }
  return out;
}

// --- the writer used by the kill tests (C++ fork test and tests/python) -----
// A deterministic run: step k at time k*dt, node i slips at rate (1 + i/N) so
// slip_i(k) = k dt (1 + 0.1 i/N) * 1e-3; timeseries every step, a snapshot every
// 10 steps, a flush every 50 steps, reported via on_flush(steps done, written)
// (written = false: deferred because a reader held the file).
constexpr int writer_nodes = 16;
constexpr double writer_dt = 1e-3;
constexpr double writer_delta_th = 1e-6;

double writer_rate(int i) {  // [m/s]
  return (1.0 + 0.1 * static_cast<double>(i) / writer_nodes) * 1e-3;
}

double writer_slip(long k, int i) {
  return static_cast<double>(k) * writer_dt * writer_rate(i);
}

[[noreturn]] void write_until_killed(const std::string& path,
                                     const std::function<void(long, bool)>& on_flush) {
  SlipSamplingSetup setup;
  setup.delta_th = writer_delta_th;
  setup.dx = 1.0 / writer_nodes;
  setup.v0 = 1e-3;
  setup.mu = 30e9;
  setup.D = 5e-7;
  setup.L = 1.0;
  for (int i = 0; i < writer_nodes; ++i) setup.x.push_back(i * setup.dx);
  RunOutput out(path, "[geometry]\nnodes = 16\n", setup);
  std::vector<double> slip_old(writer_nodes), slip_new(writer_nodes), field(writer_nodes);
  for (int i = 0; i < writer_nodes; ++i) slip_old[i] = writer_slip(0, i);
  for (long k = 1;; ++k) {
    for (int i = 0; i < writer_nodes; ++i) slip_new[i] = writer_slip(k, i);
    out.record_slip((k - 1) * writer_dt, k * writer_dt, slip_old, slip_new);
    out.append_timeseries(k * writer_dt, static_cast<double>(k), slip_new[0], -static_cast<double>(k));
    if (k % 10 == 0) {
      for (int i = 0; i < writer_nodes; ++i) field[i] = static_cast<double>(k * 100 + i);
      out.write_snapshot(k * writer_dt, slip_new, field, field, field);
    }
    slip_old.swap(slip_new);
    if (k % 50 == 0) {
      const bool written = out.flush();
      on_flush(k, written);
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  }
}

// Checks a file written by write_until_killed holds at least `steps` steps,
// all with the exact values written.
void check_writer_file(hid_t file, long steps) {
  const Array time = read_array(file, "timeseries/time");
  const Array max_slip_rate = read_array(file, "timeseries/max_slip_rate");
  const Array mean_shear_stress = read_array(file, "timeseries/mean_shear_stress");
  REQUIRE(time.dims[0] >= static_cast<hsize_t>(steps));
  REQUIRE(max_slip_rate.dims[0] == time.dims[0]);
  REQUIRE(mean_shear_stress.dims[0] == time.dims[0]);
  for (hsize_t r = 0; r < time.dims[0]; ++r) {
    const long k = static_cast<long>(r) + 1;
    REQUIRE(time.values[r] == k * writer_dt);
    REQUIRE(max_slip_rate.values[r] == static_cast<double>(k));
    REQUIRE(mean_shear_stress.values[r] == -static_cast<double>(k));
  }
  const Array snap_time = read_array(file, "snapshots/time");
  const Array snap_rate = read_array(file, "snapshots/slip_rate");
  REQUIRE(snap_time.dims[0] >= static_cast<hsize_t>(steps / 10));
  REQUIRE(snap_rate.dims[0] == snap_time.dims[0]);
  for (hsize_t s = 0; s < snap_time.dims[0]; ++s) {
    const long k = 10 * (static_cast<long>(s) + 1);
    REQUIRE(snap_time.values[s] == k * writer_dt);
    for (int i = 0; i < writer_nodes; ++i) REQUIRE(snap_rate.at(s, i) == k * 100.0 + i);
  }
  // Every level reached by step `steps` must be in the file with its time.
  const Array crossing = read_array(file, "slip_sampling/crossing_time");
  for (int i = 0; i < writer_nodes; ++i) {
    const auto levels_by_steps =
        static_cast<hsize_t>(std::floor(writer_slip(steps, i) / writer_delta_th * (1 - 1e-12)));
    REQUIRE(crossing.dims[0] >= levels_by_steps);
    for (hsize_t j = 0; j < levels_by_steps; ++j) {
      // Node i crosses level j inside step k with (k-1) s < (j+1) delta <= k s;
      // linear slip means the interpolated time is (j+1) delta / s (s = slip per
      // unit time).  Tolerance 1e-9 s: rounding of k*dt products, far below dt = 1e-3 s.
      REQUIRE(crossing.at(j, i) ==
              doctest::Approx((j + 1) * writer_delta_th / writer_rate(i)).epsilon(1e-9));
    }
  }
}

}  // namespace

TEST_CASE("round trip: attributes, timeseries, snapshots and crossing times read back exactly") {
  const std::string path = temp_path("roundtrip");
  const std::string config = "[geometry]\nlength = 4.0\nnodes = 3\n\n[output]\ndelta_th = 0.25\n";
  SlipSamplingSetup setup{0.25, 0.5, 2e-3, 30e9, 5e-7, 1.5, {0.0, 0.5, 1.0}};
  RunOutputOptions options;
  options.timeseries_buffer_rows = 3;  // forces write-outs between flushes
  options.snapshot_chunk = 2;
  {
    RunOutput out(path, config, setup, options);
    {
      Handle file = open_read_only(path);
      CHECK(read_string_attribute(file, "status") == "running");
    }
    for (int r = 0; r < 7; ++r) out.append_timeseries(r * 0.5, r + 0.25, r * 2.0, -r * 1e6);

    const std::vector<double> a{1, 2, 3}, b{4, 5, 6}, c{7, 8, 9}, d{10, 11, 12};
    for (int s = 0; s < 3; ++s) out.write_snapshot(s * 2.0, a, b, c, d);

    // Powers of two throughout so the interpolated times are exact in binary.
    // Node 0 slips forward, back (0.5 -> 0.375) and forward again: its levels
    // 0.25 and 0.5 must not be crossed a second time.
    out.record_slip(0.0, 1.0, std::vector<double>{0, 0, 0}, std::vector<double>{0.5, 0.125, 1.0});
    out.flush();
    {
      // After a flush the partially filled rows are in the file, NaN where not reached.
      Handle file = open_read_only(path);
      const Array ct = read_array(file, "slip_sampling/crossing_time");
      REQUIRE(ct.dims == std::vector<hsize_t>{4, 3});
      CHECK(ct.at(0, 0) == 0.5);
      CHECK(std::isnan(ct.at(0, 1)));
      CHECK(ct.at(3, 2) == 1.0);
    }
    out.record_slip(1.0, 2.0, std::vector<double>{0.5, 0.125, 1.0},
                    std::vector<double>{0.375, 0.375, 1.0});
    out.record_slip(2.0, 4.0, std::vector<double>{0.375, 0.375, 1.0},
                    std::vector<double>{0.625, 0.375, 1.0});
    out.record_slip(4.0, 5.0, std::vector<double>{0.625, 0.375, 1.0},
                    std::vector<double>{0.875, 0.375, 1.0});
    out.close("diverged: NaN in slip_rate at node 1, t = 5 s");
    out.close("completed");  // second close: no-op
  }

  Handle file = open_read_only(path);
  CHECK(read_string_attribute(file, "config") == config);
  CHECK(read_string_attribute(file, "code_version") == slipstrip::code_version);
  CHECK(read_string_attribute(file, "git_hash") == slipstrip::git_hash);
  CHECK(read_string_attribute(file, "status") == "diverged: NaN in slip_rate at node 1, t = 5 s");
  CHECK(looks_iso8601_utc(read_string_attribute(file, "start_time")));
  CHECK(looks_iso8601_utc(read_string_attribute(file, "end_time")));
  CHECK(read_string_attribute(file, "units").find("shear_stress") != std::string::npos);

  const char* ts_names[4] = {"time", "max_slip_rate", "mean_slip", "mean_shear_stress"};
  const char* ts_units[4] = {"s", "m/s", "m", "Pa"};
  for (int c = 0; c < 4; ++c) {
    const Array col = read_array(file, std::string("timeseries/") + ts_names[c]);
    REQUIRE(col.dims == std::vector<hsize_t>{7});
    for (int r = 0; r < 7; ++r) {
      const double expected[4] = {r * 0.5, r + 0.25, r * 2.0, -r * 1e6};
      CHECK(col.values[r] == expected[c]);
    }
    CHECK(dataset_units(file, std::string("timeseries/") + ts_names[c]) == ts_units[c]);
  }

  {
    Handle group(H5Gopen2(file, "snapshots", H5P_DEFAULT), "snapshots");
    CHECK(read_string_attribute(group, "trigger") == "time");
  }
  const Array snap_time = read_array(file, "snapshots/time");
  CHECK(snap_time.values == std::vector<double>{0.0, 2.0, 4.0});
  const char* fields[4] = {"slip", "slip_rate", "state", "shear_stress"};
  const char* field_units[4] = {"m", "m/s", "s", "Pa"};
  for (int f = 0; f < 4; ++f) {
    const Array field = read_array(file, std::string("snapshots/") + fields[f]);
    REQUIRE(field.dims == std::vector<hsize_t>{3, 3});
    for (int s = 0; s < 3; ++s)
      for (int i = 0; i < 3; ++i) CHECK(field.at(s, i) == 3.0 * f + i + 1);
    CHECK(dataset_units(file, std::string("snapshots/") + fields[f]) == field_units[f]);
  }
  CHECK(read_array(file, "snapshots/x").values == setup.x);

  {
    Handle group(H5Gopen2(file, "slip_sampling", H5P_DEFAULT), "slip_sampling");
    CHECK(read_double_attribute(group, "delta_th") == 0.25);
    CHECK(read_double_attribute(group, "dx") == 0.5);
    CHECK(read_double_attribute(group, "v0") == 2e-3);
    CHECK(read_double_attribute(group, "mu") == 30e9);
    CHECK(read_double_attribute(group, "D") == 5e-7);
    CHECK(read_double_attribute(group, "L") == 1.5);
  }
  CHECK(read_array(file, "slip_sampling/x").values == setup.x);
  CHECK(dataset_units(file, "slip_sampling/crossing_time") == "s");
  // Hand-computed crossing times (level j = slip (j+1)*0.25):
  //   node 0: 0->0.5 in [0,1] gives 0.5, 1.0; back-slip; 0.625->0.875 in [4,5] gives 4.5
  //   node 1: 0->0.125 nothing; 0.125->0.375 in [1,2] crosses 0.25 at 1.5
  //   node 2: 0->1.0 in [0,1] crosses every level, at 0.25, 0.5, 0.75, 1.0
  const double nan = std::nan("");
  const double expected[4][3] = {{0.5, 1.5, 0.25}, {1.0, nan, 0.5}, {4.5, nan, 0.75}, {nan, nan, 1.0}};
  const Array ct = read_array(file, "slip_sampling/crossing_time");
  REQUIRE(ct.dims == std::vector<hsize_t>{4, 3});
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 3; ++i) {
      CAPTURE(j);
      CAPTURE(i);
      if (std::isnan(expected[j][i]))
        CHECK(std::isnan(ct.at(j, i)));
      else
        CHECK(ct.at(j, i) == expected[j][i]);
    }
  file.reset();
  std::filesystem::remove(path);
}

TEST_CASE("delta_th = 0 switches slip sampling off; snapshots by slip increment") {
  const std::string path = temp_path("nosampling");
  SlipSamplingSetup setup{0.0, 1.0, 1.0, 1.0, 1.0, 2.0, {0.0, 1.0}};
  RunOutputOptions options;
  options.snapshots_by_slip = true;
  {
    RunOutput out(path, "", setup, options);
    out.record_slip(0.0, 1.0, std::vector<double>{0, 0}, std::vector<double>{1, 1});
    CHECK(out.buffered_crossings() == 0);
    out.close("completed");
  }
  Handle file = open_read_only(path);
  CHECK(H5Lexists(file, "slip_sampling", H5P_DEFAULT) == 0);
  Handle group(H5Gopen2(file, "snapshots", H5P_DEFAULT), "snapshots");
  CHECK(read_string_attribute(group, "trigger") == "slip_increment");
  CHECK(read_string_attribute(file, "status") == "completed");
  group.reset();
  file.reset();
  std::filesystem::remove(path);
}

TEST_CASE("bad input throws std::invalid_argument naming the parameter") {
  const std::string path = temp_path("bad");
  SlipSamplingSetup setup{1e-8, 1.0, 1.0, 1.0, 1.0, 2.0, {0.0, 1.0}};
  SlipSamplingSetup empty = setup;
  empty.x.clear();
  CHECK_THROWS_WITH_AS(RunOutput(path, "", empty), doctest::Contains("SlipSamplingSetup.x"),
                       std::invalid_argument);
  SlipSamplingSetup negative = setup;
  negative.delta_th = -1.0;
  CHECK_THROWS_WITH_AS(RunOutput(path, "", negative), doctest::Contains("delta_th"),
                       std::invalid_argument);
  RunOutputOptions options;
  options.gzip_level = 12;
  CHECK_THROWS_WITH_AS(RunOutput(path, "", setup, options), doctest::Contains("gzip_level"),
                       std::invalid_argument);
  RunOutput out(path, "", setup);
  CHECK_THROWS_WITH_AS(out.write_snapshot(0.0, std::vector<double>{1}, std::vector<double>{1, 2},
                                          std::vector<double>{1, 2}, std::vector<double>{1, 2}),
                       doctest::Contains("slip"), std::invalid_argument);
  CHECK_THROWS_WITH_AS(out.close("finished"), doctest::Contains("finished"), std::invalid_argument);
  CHECK_FALSE(out.is_closed());
  out.close("completed");
  std::filesystem::remove(path);
}

TEST_CASE("destruction during an exception records status interrupted") {
  const std::string path = temp_path("unwind");
  SlipSamplingSetup setup{1e-8, 1.0, 1.0, 1.0, 1.0, 2.0, {0.0, 1.0}};
  try {
    RunOutput out(path, "", setup);
    out.append_timeseries(1.0, 2.0, 3.0, 4.0);  // buffered only
    throw std::runtime_error("solver failed");
  } catch (const std::runtime_error&) {
  }
  Handle file = open_read_only(path);
  CHECK(read_string_attribute(file, "status") == "interrupted");
  CHECK(read_array(file, "timeseries/mean_shear_stress").values == std::vector<double>{4.0});
  file.reset();
  std::filesystem::remove(path);
}

TEST_CASE("an open reader's shared lock defers write-outs; past reader_lock_timeout they go ahead") {
  const std::string path = temp_path("locked");
  SlipSamplingSetup setup{0.0, 1.0, 1.0, 1.0, 1.0, 2.0, {0.0, 1.0}};
  auto rows_in_file = [&] {
    Handle file = open_read_only(path);
    return read_array(file, "timeseries/time").values.size();
  };
  // A reader is emulated by the shared flock h5py/HDF5 take on open.
  auto hold_shared_lock = [&] {
    const int fd = ::open(path.c_str(), O_RDONLY);
    REQUIRE(fd >= 0);
    REQUIRE(flock(fd, LOCK_SH | LOCK_NB) == 0);
    return fd;
  };
  {
    RunOutput out(path, "", setup);  // default timeout: 30 s
    out.append_timeseries(1.0, 0.0, 0.0, 0.0);
    CHECK(out.flush());
    const int reader = hold_shared_lock();
    out.append_timeseries(2.0, 0.0, 0.0, 0.0);
    CHECK_FALSE(out.flush());
    CHECK(out.deferred_writes() == 1);
    ::close(reader);
    CHECK(rows_in_file() == 1);  // the deferred row did not reach the file
    CHECK(out.flush());
    CHECK(rows_in_file() == 2);
    const int reader_at_close = hold_shared_lock();
    out.append_timeseries(3.0, 0.0, 0.0, 0.0);
    out.close("completed");  // close never waits: it writes anyway
    ::close(reader_at_close);
  }
  CHECK(rows_in_file() == 3);
  {
    RunOutputOptions options;
    options.reader_lock_timeout = 0.0;
    RunOutput out(path, "", setup, options);
    const int reader = hold_shared_lock();
    out.append_timeseries(1.0, 0.0, 0.0, 0.0);
    CHECK(out.flush());  // timeout 0: written despite the reader
    CHECK(out.deferred_writes() == 0);
    ::close(reader);
    CHECK(rows_in_file() == 1);
    out.close("completed");
  }
  std::filesystem::remove(path);
}

TEST_CASE("incremental slip sampling: bounded memory, times match a full-trajectory reference") {
  // Slip slip_i(t) = t + a sin(2 pi x_i + w t) with a w = 2 > 1: the slip rate
  // changes sign, so back-slip happens at every moving node.  Node 0 is locked
  // (slip 0 throughout), so the lowest level not reached by every node stays 0
  // while the others reach ~2000 levels: a buffer of rows would have to hold
  // all 2000; the pending-crossing buffer stays below slip_buffer_crossings.
  const std::string path = temp_path("incremental");
  const int n = 64, steps = 4000;
  const double delta_th = 0.01, a = 0.05, w = 40.0, dt = 0.005;
  SlipSamplingSetup setup{delta_th, 1.0 / n, 1.0, 1.0, 1.0, 1.0, {}};
  for (int i = 0; i < n; ++i) setup.x.push_back(i * setup.dx);
  RunOutputOptions options;
  options.slip_buffer_crossings = 500;
  auto slip_at = [&](int k, int i) {
    const double t = k * dt;
    return i == 0 ? 0.0 : t + a * std::sin(2 * M_PI * setup.x[i] + w * t);
  };
  std::vector<double> times(steps + 1);
  std::vector<std::vector<double>> trajectory(n, std::vector<double>(steps + 1));
  for (int k = 0; k <= steps; ++k) {
    times[k] = k * dt;
    for (int i = 0; i < n; ++i) trajectory[i][k] = slip_at(k, i);
  }
  std::size_t max_buffered = 0;
  std::size_t levels = 0;
  {
    RunOutput out(path, "", setup, options);
    std::vector<double> slip_old(n), slip_new(n);
    for (int i = 0; i < n; ++i) slip_old[i] = trajectory[i][0];
    for (int k = 1; k <= steps; ++k) {
      for (int i = 0; i < n; ++i) slip_new[i] = trajectory[i][k];
      out.record_slip(times[k - 1], times[k], slip_old, slip_new);
      max_buffered = std::max(max_buffered, out.buffered_crossings());
      slip_old.swap(slip_new);
    }
    levels = out.slip_levels_reached();
    out.close("completed");
  }
  MESSAGE("levels reached: " << levels << ", max crossings held in memory: " << max_buffered);
  CHECK(levels > 1900);
  // The write-out triggers at 500; a step adds at most 2 crossings per node
  // (|d slip| <= (1 + a w) dt = 0.015 < 2 delta_th).
  CHECK(max_buffered < 500 + 2 * n);

  Handle file = open_read_only(path);
  const Array ct = read_array(file, "slip_sampling/crossing_time");
  REQUIRE(ct.dims == std::vector<hsize_t>{levels, static_cast<hsize_t>(n)});
  int mismatches = 0;
  for (int i = 0; i < n; ++i) {
    const auto reference = reference_crossings(times, trajectory[i], delta_th, levels);
    for (std::size_t j = 0; j < levels; ++j) {
      const double got = ct.at(j, i);
      // Same interpolation formula; 1e-12 s absolute (t <= 20 s) allows the
      // last-bit difference a fused multiply-add in one of the two can make.
      const bool same = std::isnan(reference[j]) ? std::isnan(got)
                                                 : std::abs(got - reference[j]) <= 1e-12;
      if (!same && mismatches < 5)
        MESSAGE("node " << i << " level " << j << ": file " << got << ", reference " << reference[j]);
      if (!same) ++mismatches;
    }
  }
  CHECK(mismatches == 0);
  file.reset();
  std::filesystem::remove(path);
}

TEST_CASE("a writer killed with SIGKILL leaves a readable file holding every flushed row") {
  const std::string path = temp_path("killed");
  int report[2];
  REQUIRE(pipe(report) == 0);
  const pid_t child = fork();
  REQUIRE(child >= 0);
  if (child == 0) {
    close(report[0]);
    try {
      write_until_killed(path, [&](long steps, bool written) {
        if (written && write(report[1], &steps, sizeof steps) != sizeof steps) _exit(3);
      });
    } catch (...) {
      _exit(2);
    }
  }
  close(report[1]);
  long flushed = 0;
  for (int flushes = 0; flushes < 6; ++flushes)
    REQUIRE(read(report[0], &flushed, sizeof flushed) == sizeof flushed);

  // Readable while the child keeps writing.  The file is open in the child only
  // during a flush (~ms every ~5 ms here); an open that lands inside one may
  // fail, so allow a few attempts.
  bool read_while_running = false;
  for (int attempt = 0; attempt < 20 && !read_while_running; ++attempt) {
    hid_t id = H5I_INVALID_HID;
    H5E_BEGIN_TRY { id = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT); }
    H5E_END_TRY;
    if (id >= 0) {
      Handle file(id);
      check_writer_file(file, flushed);
      CHECK(read_string_attribute(file, "status") == "running");
      read_while_running = true;
    }
    if (!read_while_running) std::this_thread::sleep_for(std::chrono::milliseconds(3));
  }
  CHECK(read_while_running);

  for (int flushes = 0; flushes < 2; ++flushes)
    REQUIRE(read(report[0], &flushed, sizeof flushed) == sizeof flushed);
  REQUIRE(kill(child, SIGKILL) == 0);
  int status = 0;
  REQUIRE(waitpid(child, &status, 0) == child);
  REQUIRE(WIFSIGNALED(status));
  CHECK(WTERMSIG(status) == SIGKILL);
  // Flushes reported after our last read may have happened too.
  long more = 0;
  while (read(report[0], &more, sizeof more) == sizeof more) flushed = more;
  close(report[0]);

  MESSAGE("child killed after " << flushed << " flushed steps");
  Handle file = open_read_only(path);
  check_writer_file(file, flushed);
  CHECK(read_string_attribute(file, "status") == "running");  // killed: never closed
  file.reset();
  std::filesystem::remove(path);
}

// Helper for tests/python/test_output_readable.py, skipped in normal runs:
//   test_solver_run_output -tc="writer child*" --no-skip=true
// with SLIPSTRIP_WRITER_CHILD_PATH set writes that file until killed and prints
// "flushed <steps>" after every flush ("deferred <steps>" if a reader held the file).
TEST_CASE("writer child (runs until killed; for tests/python)" * doctest::skip()) {
  const char* path = std::getenv("SLIPSTRIP_WRITER_CHILD_PATH");
  REQUIRE(path != nullptr);
  write_until_killed(path, [](long steps, bool written) {
    std::printf("%s %ld\n", written ? "flushed" : "deferred", steps);
    std::fflush(stdout);
  });
}
