// Restart points (solver/checkpoint.hpp): a Simulation restored from a saved
// state, directly or through RUN.h5.restart, steps bit for bit as the one it
// was saved from, for the three history operators; foreign states are refused;
// a resumed RunOutput cuts the file back to the restart point exactly.
// The CLI-level tests (interrupt, resume, compare whole files) are in
// tests/python/test_restart.py.
#include <doctest/doctest.h>
#include <hdf5.h>
#include <unistd.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "solver/checkpoint.hpp"
#include "config/config.hpp"
#include "solver/run_output.hpp"
#include "solver/simulation.hpp"
#include "io/attributes.hpp"
#include "io/hdf5.hpp"

using namespace slipstrip;

namespace {

std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() /
          ("slipstrip_checkpoint_" + std::to_string(getpid()) + "_" + name))
      .string();
}

template <class T>
bool same_bits(std::span<const T> a, std::span<const T> b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size_bytes()) == 0;
}

bool same_bits(const Simulation& a, const Simulation& b) {
  return a.step_index() == b.step_index() &&
         std::bit_cast<std::uint64_t>(a.time()) == std::bit_cast<std::uint64_t>(b.time()) &&
         same_bits(a.slip(), b.slip()) && same_bits(a.slip_rate(), b.slip_rate()) &&
         same_bits(a.state(), b.state()) && same_bits(a.shear_stress(), b.shear_stress()) &&
         same_bits(a.history_operator().history(), b.history_operator().history());
}

// A small noisy run (N = 32, quickstart-like friction) with the given strip
// height and history algorithm.
SimulationConfig small_config(const std::string& height, const std::string& history) {
  return load_config_string(
      "[geometry]\nlength = 0.5\nheight = " + height + "\nnodes = 32\n"
      "[friction]\ncharacteristic_slip = 1.667e-7\n"
      "[loading]\ndriving_velocity = 2e-3\n"
      "[initial]\nnoise_amplitude = 1e-2\nnoise_seed = 3\n"
      "[time]\nhistory = \"" + history + "\"\n");
}

}  // namespace

TEST_CASE("a restored simulation steps bit for bit as the one it was saved from") {
  struct Case {
    const char* name;
    std::string height, history, kind;
  };
  for (const Case& c : {Case{"modal strip", "0.025", "modal", "modal strip"},
                        Case{"block strip", "0.025", "block", "block strip"},
                        Case{"half-space", "\"inf\"", "auto", "half-space"}}) {
    CAPTURE(c.name);
    const SimulationConfig config = small_config(c.height, c.history);
    Simulation original(config);
    // 45 steps: inside the block history's first block of B = 64 steps, so
    // its partial block (inputs, accumulated outputs) is part of the state.
    for (int n = 0; n < 45; ++n) original.step();
    const SimulationState saved = original.save_state();
    CHECK(saved.history.kind == c.kind);
    CHECK(saved.step_index == 45);

    // Through the restart-point file as well: the HDF5 round trip is exact.
    const std::string run_path = temp_path("run.h5");
    std::ofstream(run_path) << "stand-in for the run file (write_checkpoint syncs it)";
    RunCheckpoint checkpoint;
    checkpoint.config_toml = to_toml(config);
    checkpoint.simulation = saved;
    checkpoint.next_timeseries = 1.25e-5;
    write_checkpoint(run_path, checkpoint);
    CHECK_FALSE(std::filesystem::exists(checkpoint_path(run_path) + ".tmp"));
    const RunCheckpoint read = read_checkpoint(run_path);
    CHECK(read.config_toml == checkpoint.config_toml);
    CHECK(read.next_timeseries == 1.25e-5);
    remove_checkpoint(run_path);
    std::filesystem::remove(run_path);
    CHECK_FALSE(std::filesystem::exists(checkpoint_path(run_path)));

    Simulation direct(config), from_file(config);
    direct.restore_state(saved);
    from_file.restore_state(read.simulation);
    CHECK(same_bits(original, direct));
    CHECK(same_bits(original, from_file));
    // 150 more steps cross the block boundaries at 64, 128 and 192.
    for (int n = 0; n < 150; ++n) {
      original.step();
      direct.step();
      from_file.step();
    }
    CHECK(original.step_index() == 195);
    CHECK(same_bits(original, direct));
    CHECK(same_bits(original, from_file));
    // The run moved on: the comparison is not between two resting states.
    CHECK(original.slip()[0] > saved.slip[0]);
  }
}

TEST_CASE("a saved state is refused by a simulation of another config") {
  Simulation modal(small_config("0.025", "modal"));
  modal.step();
  const SimulationState saved = modal.save_state();

  Simulation block(small_config("0.025", "block"));
  CHECK_THROWS_WITH_AS(block.restore_state(saved),
                       doctest::Contains("of kind 'modal strip', this run's operator is 'block strip'"),
                       std::invalid_argument);
  SimulationConfig thicker = small_config("0.05", "modal");
  Simulation other_height(thicker);
  CHECK_THROWS_WITH_AS(other_height.restore_state(saved), doctest::Contains("array 'c_re' has"),
                       std::invalid_argument);
  SimulationConfig more_nodes = small_config("0.025", "modal");
  more_nodes.geometry.nodes = 64;
  Simulation finer(more_nodes);
  CHECK_THROWS_WITH_AS(finer.restore_state(saved), doctest::Contains("slip has 32 values, this config has 64 nodes"),
                       std::invalid_argument);
}

TEST_CASE("a missing or foreign restart point is an input error naming the file") {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // the garbage file's HDF5 error stack is expected
  const std::string run_path = temp_path("none.h5");
  CHECK_THROWS_WITH_AS(read_checkpoint(run_path), doctest::Contains("has no restart point"),
                       std::invalid_argument);
  std::ofstream(checkpoint_path(run_path)) << "garbage";
  CHECK_THROWS_WITH_AS(read_checkpoint(run_path), doctest::Contains("cannot be read"),
                       std::invalid_argument);
  remove_checkpoint(run_path);
}

namespace {

std::vector<double> read_all(hid_t file, const char* name, std::vector<hsize_t>* dims_out = nullptr) {
  io::Handle dset(H5Dopen2(file, name, H5P_DEFAULT), name);
  io::Handle space(H5Dget_space(dset), "space");
  std::vector<hsize_t> dims(H5Sget_simple_extent_ndims(space));
  H5Sget_simple_extent_dims(space, dims.data(), nullptr);
  hsize_t total = 1;
  for (hsize_t d : dims) total *= d;
  std::vector<double> values(total);
  if (total > 0) io::check(H5Dread(dset, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), name);
  if (dims_out) *dims_out = dims;
  return values;
}

// Feeds `steps` steps of a deterministic record to `out`: a time-series row,
// a snapshot every 3rd step, a station row, slip growing unevenly per node.
void feed(RunOutput& out, int first, int steps, std::vector<double>& slip) {
  for (int n = first; n < first + steps; ++n) {
    const double t0 = n * 1e-3, t1 = (n + 1) * 1e-3;
    std::vector<double> before = slip;
    for (std::size_t i = 0; i < slip.size(); ++i) slip[i] += (i + 1) * 0.7e-8;
    out.record_slip(t0, t1, before, slip);
    out.append_timeseries(t1, n, 2.0 * n, 3.0 * n);
    if (n % 3 == 0) out.write_snapshot(t1, slip, slip, slip, slip);
    const std::vector<double> station(1, n);
    out.append_stations(t1, station, station, station, station, 1e6, n, n);
  }
}

}  // namespace

TEST_CASE("a resumed run file is cut back to the restart point, crossing times included") {
  SlipSamplingSetup sampling;
  sampling.delta_th = 1e-8;
  sampling.dx = 0.1;
  sampling.x = {0.0, 0.1, 0.2, 0.3};
  RunOutputOptions options;
  options.station_x = {0.1};
  options.front_slip_rate = 1.0;
  const std::string reference = temp_path("reference.h5"), resumed = temp_path("resumed.h5");
  std::vector<double> front(4, std::numeric_limits<double>::quiet_NaN());

  // The resumed part (3 steps) is shorter than the part lost after the
  // restart point (9 steps), so anything of the lost steps that survived the
  // cut would show.
  {  // Reference: 11 steps at once.
    std::vector<double> slip(4, 0.0);
    RunOutput out(reference, "config", sampling, options);
    feed(out, 0, 11, slip);
    front[1] = 5e-3;
    out.set_rupture_front(front);
    out.close("completed");
  }
  RunOutputCursor cursor;
  std::vector<double> slip_at_cursor;
  {  // 8 steps, restart point, 9 more steps written out, then "killed".
    std::vector<double> slip(4, 0.0);
    RunOutput out(resumed, "config", sampling, options);
    feed(out, 0, 8, slip);
    cursor = *out.flush_for_checkpoint(true);
    slip_at_cursor = slip;
    feed(out, 8, 9, slip);
    std::vector<double> late_front = front;
    late_front[3] = 9e-3;  // set after the restart point: must not survive
    out.set_rupture_front(late_front);
    out.flush();
    out.close("interrupted");
  }
  CHECK(cursor.timeseries_rows == 8);
  CHECK(cursor.snapshots == 3);
  CHECK(cursor.levels_reached.size() == 4);
  {
    io::Handle file(H5Fopen(resumed.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), "open");
    CHECK(read_all(file, "timeseries/time").size() == 17);  // past the cursor before the resume
  }
  {  // Resume from the cursor and write 3 steps.
    RunOutput out(resumed, cursor, sampling, options);
    std::vector<double> slip = slip_at_cursor;
    feed(out, 8, 3, slip);
    out.set_rupture_front(front);
    out.close("completed");
  }
  io::Handle a(H5Fopen(reference.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), "open reference");
  io::Handle b(H5Fopen(resumed.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), "open resumed");
  for (const char* name : {"timeseries/time", "timeseries/max_slip_rate", "timeseries/mean_slip",
                           "timeseries/mean_shear_stress", "snapshots/time", "snapshots/slip",
                           "snapshots/state", "stations/time", "stations/slip", "stations/moment_rate",
                           "slip_sampling/crossing_time", "rupture_front/arrival_time"}) {
    CAPTURE(name);
    std::vector<hsize_t> dims_a, dims_b;
    const auto va = read_all(a, name, &dims_a), vb = read_all(b, name, &dims_b);
    CHECK(dims_a == dims_b);
    CHECK(same_bits(std::span<const double>(va), std::span<const double>(vb)));
  }
  CHECK(io::read_string_attribute(b, "status") == "completed");
  std::filesystem::remove(reference);
  std::filesystem::remove(resumed);
}

TEST_CASE("an antiplane pair of two different strips (one combined operator) restores bit for bit") {
  // Different wave speeds, impedances and heights (the uniform mode is the
  // two-echo recursion), block and modal history; saved inside the first block
  // (B = 1024, body_block_length's), run across its end, through the file too.
  for (const std::string history : {"block", "modal"}) {
    CAPTURE(history);
    const SimulationConfig config = load_config_string(
        "[geometry]\nlength = 0.5\nheight = 0.05\nnodes = 32\n"
        "[material]\nplane = \"antiplane\"\n"
        "[bottom]\nbody = \"elastic\"\nshear_modulus = 18e9\ndensity = 1560\nheight = 0.115\n"
        "[friction]\ncharacteristic_slip = 1.667e-7\n"
        "[loading]\ndriving_velocity = 2e-3\n"
        "[initial]\nnoise_amplitude = 1e-2\nnoise_seed = 3\n"
        "[time]\nhistory = \"" + history + "\"\n");
    REQUIRE(config.time.antiplane_pair == AntiplanePairOperator::combined);
    Simulation original(config);
    for (int n = 0; n < 700; ++n) original.step();
    const SimulationState saved = original.save_state();
    CHECK(saved.history.kind == (history == "block" ? "block strip" : "modal strip"));
    CHECK(saved.history.has("echo_input"));  // the two-echo recursion of the uniform mode
    const std::string run_path = temp_path("pair_run.h5");
    std::ofstream(run_path) << "stand-in for the run file (write_checkpoint syncs it)";
    RunCheckpoint checkpoint;
    checkpoint.config_toml = to_toml(config);
    checkpoint.simulation = saved;
    write_checkpoint(run_path, checkpoint);
    const RunCheckpoint read = read_checkpoint(run_path);
    remove_checkpoint(run_path);
    std::filesystem::remove(run_path);
    Simulation direct(config), from_file(config);
    direct.restore_state(saved);
    from_file.restore_state(read.simulation);
    CHECK(same_bits(original, direct));
    CHECK(same_bits(original, from_file));
    for (int n = 0; n < 700; ++n) {
      original.step();
      direct.step();
      from_file.step();
    }
    CHECK(same_bits(original, direct));
    CHECK(same_bits(original, from_file));
    CHECK(original.slip()[0] > saved.slip[0]);
  }
}
