// Restart points of a 2D interface (solver/simulation_3d.hpp, docs/3d.md): a
// Simulation3d restored from a saved state, directly or through
// RUN.h5.restart (solver/checkpoint.hpp), steps bit for bit as the one it was
// saved from, for strips and half-spaces, identical bodies or a dissimilar
// pair with a half-space; a state of another grid is refused
// naming the field.  The CLI-level tests (interrupt, resume, compare whole
// files) are in tests/python/test_interface_2d_restart.py.
#include <doctest/doctest.h>
#include <unistd.h>

#include <bit>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <span>
#include <string>
#include <utility>

#include "config/config.hpp"
#include "solver/checkpoint.hpp"
#include "kernels/block_strip_history.hpp"
#include "solver/simulation_3d.hpp"

using namespace slipstrip;

namespace {

std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() /
          ("slipstrip_interface_2d_checkpoint_" + std::to_string(getpid()) + "_" + name))
      .string();
}

bool same_bits(std::span<const double> a, std::span<const double> b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size_bytes()) == 0;
}

bool same_bits(const Simulation3d& a, const Simulation3d& b) {
  return a.step_index() == b.step_index() &&
         std::bit_cast<std::uint64_t>(a.time()) == std::bit_cast<std::uint64_t>(b.time()) &&
         same_bits(a.slip_x(), b.slip_x()) && same_bits(a.slip_z(), b.slip_z()) &&
         same_bits(a.slip_rate_x(), b.slip_rate_x()) && same_bits(a.slip_rate_z(), b.slip_rate_z()) &&
         same_bits(a.state(), b.state()) && same_bits(a.shear_stress_x(), b.shear_stress_x()) &&
         same_bits(a.shear_stress_z(), b.shear_stress_z()) && same_bits(a.speed(), b.speed());
}

// configs/3d/tiny.toml's physics on 16 x 8 nodes: white noise node by node
// plus a bump along x, so the slip has x and z parts.  `history`: the strip
// operators' algorithm (time.history).
SimulationConfig small_config(const std::string& height, int nodes_z, const std::string& history = "auto") {
  return load_config_string(
      "[geometry]\nlength = 0.25\nwidth = " + std::to_string(0.25 * nodes_z / 16) + "\nheight = " + height +
      "\nnodes = 16\nnodes_z = " + std::to_string(nodes_z) +
      "\n[friction]\ncharacteristic_slip = 1.667e-7\n"
      "[loading]\ndriving_velocity = 2e-3\n"
      "[initial]\nnoise_amplitude = 1e-2\nnoise_seed = 1\nlocal_amplitude = 0.5\nlocal_center = 0.125\n"
      "local_width = 0.02\n"
      "[time]\nbeta = 0.24\nhistory = \"" + history + "\"\n");
}

// The restart point of `saved` (with `config`'s TOML) written beside a
// stand-in run file at `run_path` and read back: {written, read}.
std::pair<RunCheckpoint, RunCheckpoint> write_and_read_back(const std::string& run_path, const SimulationConfig& config,
                                                            const SimulationState& saved) {
  std::ofstream(run_path) << "stand-in for the run file (write_checkpoint syncs it)";
  RunCheckpoint checkpoint;
  checkpoint.config_toml = to_toml(config);
  checkpoint.simulation = saved;
  write_checkpoint(run_path, checkpoint);
  return {checkpoint, read_checkpoint(run_path)};
}

}  // namespace

TEST_CASE("a restored 2D-interface simulation steps bit for bit as the one it was saved from") {
  // Modal strips, half-spaces, and block strips (B = 64 steps: saved at step
  // 40 inside the first block, so the restored operators carry partial
  // blocks, level outputs and the normal-mode states across the far-field
  // update at step 64).
  struct Case {
    const char* height;
    const char* history;
  };
  for (const Case& operators : {Case{"0.025", "modal"}, Case{"\"inf\"", "auto"}, Case{"0.025", "block"}}) {
    const char* height = operators.height;
    CAPTURE(height);
    CAPTURE(operators.history);
    const SimulationConfig config = small_config(height, 8, operators.history);
    Simulation3d original(config);
    for (int n = 0; n < 40; ++n) original.step();
    const SimulationState saved = original.save_state();
    CHECK(saved.history.kind == "interface 2d");
    const bool block = std::string(operators.history) == "block";
    CHECK((dynamic_cast<const BlockStripHistory*>(&original.history_operator().inplane()) != nullptr) == block);
    CHECK((dynamic_cast<const BlockStripHistory*>(&original.history_operator().antiplane()) != nullptr) == block);
    CHECK(saved.step_index == 40);
    CHECK(saved.slip_z.size() == 128);
    CHECK(saved.speed.size() == 128);

    // Through the restart-point file as well: the HDF5 round trip is exact,
    // and the checksum covers the 2D-interface fields.
    const std::string run_path = temp_path("run.h5");
    const auto [checkpoint, read] = write_and_read_back(run_path, config, saved);
    CHECK(read.checksum_verified);
    CHECK(checkpoint_checksum(read) == checkpoint_checksum(checkpoint));
    RunCheckpoint changed = checkpoint;
    changed.simulation.slip_rate_z[3] = std::nextafter(changed.simulation.slip_rate_z[3], 1.0);
    CHECK(checkpoint_checksum(changed) != checkpoint_checksum(checkpoint));
    remove_checkpoint(run_path);
    std::filesystem::remove(run_path);

    Simulation3d direct(config), from_file(config);
    direct.restore_state(saved);
    from_file.restore_state(read.simulation);
    CHECK(same_bits(original, direct));
    CHECK(same_bits(original, from_file));
    for (int n = 0; n < 60; ++n) {
      original.step();
      direct.step();
      from_file.step();
    }
    CHECK(same_bits(original, direct));
    CHECK(same_bits(original, from_file));
    // The run moved on, and across x: not a comparison of resting states.
    CHECK(original.slip_x()[0] > saved.slip[0]);
    double max_rate_z = 0.0;
    for (double v : original.slip_rate_z()) max_rate_z = std::max(max_rate_z, std::abs(v));
    CHECK(max_rate_z > 0.0);
  }
}

TEST_CASE("a restored 2D-interface simulation with a half-space in a dissimilar pair steps bit for bit") {
  // A strip on a half-space of another material and two different
  // half-spaces (the in-plane half-space operators over the grid's |k|,
  // kernels/face_half_space.hpp, and the antiplane ones): saved at step 43,
  // inside a far-field batch (8 steps) and the first slow block (128 steps),
  // restored directly and through the restart-point file, then 100 steps
  // across the block end; every field, the normal stresses included, bit for
  // bit.
  for (const char* height : {"0.025", "\"inf\""}) {
    CAPTURE(height);
    SimulationConfig config = small_config(height, 8);
    config.time.beta = 0.2;  // a half-space body's operator needs c_s |k|_max dt <= ~1.1
    config.bottom.body = BodyKind::elastic;
    config.bottom.shear_modulus = 4.5e9;
    config.bottom.density = 2400.0;
    config.bottom.poisson_ratio = 0.25;
    config.bottom.height = std::numeric_limits<double>::infinity();
    Simulation3d original(config);
    REQUIRE(original.variable_normal_stress());
    for (int n = 0; n < 43; ++n) original.step();
    const SimulationState saved = original.save_state();
    const std::string run_path = temp_path("pair_run.h5");
    const RunCheckpoint read = write_and_read_back(run_path, config, saved).second;
    CHECK(read.checksum_verified);
    remove_checkpoint(run_path);
    std::filesystem::remove(run_path);
    Simulation3d direct(config), from_file(config);
    direct.restore_state(saved);
    from_file.restore_state(read.simulation);
    const auto same = [](const Simulation3d& a, const Simulation3d& b) {
      return same_bits(a, b) && same_bits(a.normal_stress(), b.normal_stress()) &&
             same_bits(a.effective_normal_stress(), b.effective_normal_stress());
    };
    CHECK(same(original, direct));
    CHECK(same(original, from_file));
    double largest_change = 0.0;
    for (int n = 0; n < 100; ++n) {
      original.step();
      direct.step();
      from_file.step();
    }
    for (double s : original.normal_stress())
      largest_change = std::max(largest_change, std::abs(s - config.loading.normal_stress));
    CHECK(same(original, direct));
    CHECK(same(original, from_file));
    CHECK(largest_change > 0.0);  // the pair's normal stress moves
  }
}

TEST_CASE("a saved 2D-interface state is refused by a simulation of another grid") {
  Simulation3d eight_rows(small_config("0.025", 8));
  eight_rows.step();
  const SimulationState saved = eight_rows.save_state();
  Simulation3d four_rows(small_config("0.025", 4));
  CHECK_THROWS_WITH_AS(four_rows.restore_state(saved),
                       doctest::Contains("slip has 128 values, this config has 64 nodes"), std::invalid_argument);
  SimulationState no_speed = saved;
  no_speed.speed.clear();
  Simulation3d same(small_config("0.025", 8));
  CHECK_THROWS_WITH_AS(same.restore_state(no_speed), doctest::Contains("speed has 0 values"),
                       std::invalid_argument);
}
