// The block algorithm for one finite body's 2x2 history operator
// (kernels/face_block_history.hpp) applies the same discrete operator as the
// modal one (kernels/face_history.hpp): both are fed the same random face
// velocities over several blocks and their histories compared step by step.
// A pair's restart point names the body algorithm that wrote it.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <memory>
#include <numbers>
#include <random>
#include <stdexcept>
#include <vector>

#include "kernels/face_block_history.hpp"
#include "kernels/face_history.hpp"
#include "kernels/inplane_pair_history.hpp"

namespace {

using cd = std::complex<double>;
using slipstrip::ElasticMaterial;
using slipstrip::OuterFace;
using slipstrip::PlaneCondition;

// Largest |block - modal| over all modes, both components and `steps` steps,
// relative to the largest |modal| history value.
double block_vs_modal(const ElasticMaterial& m, double height, OuterFace face, double beta, int nodes,
                      int steps, const slipstrip::FaceBlockDesign& design, int* block = nullptr) {
  const double length = 1.0, dx = length / nodes, dt = beta * dx / m.shear_wave_speed();
  slipstrip::FaceModalHistory modal(m, height, face, length, nodes, dt);
  slipstrip::FaceBlockHistory fast(m, height, face, length, nodes, dt, design);
  if (block) *block = fast.period();
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::vector<cd> vx(modal.modes()), vy(modal.modes());
  double diff = 0.0, scale = 0.0;
  for (int n = 0; n < steps; ++n) {
    for (int q = 0; q < modal.modes(); ++q) {
      vx[q] = cd(noise(rng), q == 0 ? 0.0 : noise(rng));
      vy[q] = cd(noise(rng), q == 0 ? 0.0 : noise(rng));
    }
    modal.push(vx, vy);
    fast.push(vx, vy);
    for (int q = 0; q < modal.modes(); ++q) {
      diff = std::max({diff, std::abs(fast.history_x()[q] - modal.history_x()[q]),
                       std::abs(fast.history_y()[q] - modal.history_y()[q])});
      scale = std::max({scale, std::abs(modal.history_x()[q]), std::abs(modal.history_y()[q])});
    }
  }
  return diff / scale;
}

// Two operators fed the same random slip and opening rates for `steps` steps
// (seeded): the largest difference of their histories, and the largest
// history, over every step and mode.
struct HistoryDifference {
  double diff = 0.0, scale = 0.0;
};

HistoryDifference same_inputs_difference(slipstrip::FaceBlockHistory& a, slipstrip::FaceBlockHistory& b,
                                         unsigned seed, int steps) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::vector<cd> vx(a.modes()), vy(a.modes());
  HistoryDifference d;
  for (int n = 0; n < steps; ++n) {
    for (int q = 0; q < a.modes(); ++q) {
      vx[q] = cd(noise(rng), q == 0 ? 0.0 : noise(rng));
      vy[q] = cd(noise(rng), q == 0 ? 0.0 : noise(rng));
    }
    a.push(vx, vy);
    b.push(vx, vy);
    for (int q = 0; q < a.modes(); ++q) {
      d.diff = std::max({d.diff, std::abs(a.history_x()[q] - b.history_x()[q]),
                         std::abs(a.history_y()[q] - b.history_y()[q])});
      d.scale = std::max({d.scale, std::abs(a.history_x()[q]), std::abs(a.history_y()[q])});
    }
  }
  return d;
}

}  // namespace

TEST_CASE("block face history equals the modal face history (strain, stress; driven, clamped)") {
  // 2.5 blocks and more of white-noise input: every lag range is exercised
  // (direct sums, each FFT level, the NUFFT far field across block ends).
  // Tolerance 1e-11 of the largest history value: the NUFFT's truncation
  // (default half width 7, <= 5e-13 of sum |w|, kernels/nufft.hpp) accumulated over the
  // block's ~100 frequencies and a few block ends, as for the scalar strip's
  // block operator (tests/cpp/test_kernels_block_history.cpp).
  int cases = 0;
  for (PlaneCondition plane : {PlaneCondition::strain, PlaneCondition::stress})
    for (OuterFace face : {OuterFace::driven, OuterFace::clamped}) {
      ElasticMaterial m;
      m.plane = plane;
      int block = 0;
      // H = 1.5 L at beta = 0.25 and 16 nodes: ~150 normal modes per Fourier
      // mode, so B = 256 with the levels s = 32, 64, 128.
      const double error = block_vs_modal(m, 1.5, face, 0.25, 16, 700, {}, &block);
      CAPTURE(static_cast<int>(plane));
      CAPTURE(static_cast<int>(face));
      CHECK(block == 256);
      CHECK(error < 1e-11);
      MESSAGE("block vs modal: ", error);
      ++cases;
    }
  CHECK(cases == 4);
}

TEST_CASE("block face history: a block shorter than the modes and a different material") {
  // B = 64 < the ~150 modes per Fourier mode (the far field carries more
  // frequencies than a block has steps) and a softer, denser body.
  ElasticMaterial m;
  m.shear_modulus *= 0.5;
  m.density *= 2.0;
  m.poisson_ratio = 0.25;
  slipstrip::FaceBlockDesign design;
  design.block = 64;
  const double error = block_vs_modal(m, 0.75, OuterFace::driven, 0.3, 16, 400, design);
  MESSAGE("block vs modal (B = 64): ", error);
  CHECK(error < 1e-11);  // as above
}

TEST_CASE("block face history: levels split into transforms of half length equal the modal face history") {
  // The levels of s >= split_level take each length-2s transform as two of
  // length s (even and odd bins, twiddles); every level split (32) and some
  // (64: s = 64, 128 split, s = 32 whole), against the modal operator with the
  // tolerance of the unsplit test above, and against the unsplit block
  // operator to rounding.
  ElasticMaterial m;
  for (int split : {32, 64}) {
    slipstrip::FaceBlockDesign design;
    design.split_level = split;
    int block = 0;
    const double error = block_vs_modal(m, 1.5, OuterFace::driven, 0.25, 16, 700, design, &block);
    CAPTURE(split);
    CHECK(block == 256);
    CHECK(error < 1e-11);
    MESSAGE("split levels s >= ", split, ", block vs modal: ", error);
  }
  const double length = 1.0, dt = 0.25 * (length / 16) / m.shear_wave_speed();
  slipstrip::FaceBlockDesign whole, split;
  split.split_level = 32;
  slipstrip::FaceBlockHistory a(m, 1.5, OuterFace::driven, length, 16, dt, whole);
  slipstrip::FaceBlockHistory b(m, 1.5, OuterFace::driven, length, 16, dt, split);
  const auto [diff, scale] = same_inputs_difference(a, b, 3, 600);
  MESSAGE("split against whole levels: ", diff / scale);
  CHECK(diff < 1e-13 * scale);
  slipstrip::FaceBlockDesign odd;
  odd.split_level = 48;
  CHECK_THROWS_AS(slipstrip::FaceBlockHistory(m, 1.5, OuterFace::driven, length, 16, dt, odd),
                  std::invalid_argument);
}

TEST_CASE("block face history: split levels with spectra in bin order equal the modal face history") {
  // Split levels of s >= bin_order_level write both halves' spectra
  // interleaved in bin order and read them back with stride 2 (the layout of
  // s >= 8192 at full size), forced here at B = 256: every split level so (32)
  // and some (64), against the modal operator with the tolerance of the tests
  // above, and against the same split levels in halves to rounding.
  ElasticMaterial m;
  for (int from : {32, 64}) {
    slipstrip::FaceBlockDesign design;
    design.split_level = 32;
    design.bin_order_level = from;
    int block = 0;
    const double error = block_vs_modal(m, 1.5, OuterFace::driven, 0.25, 16, 700, design, &block);
    CAPTURE(from);
    CHECK(block == 256);
    CHECK(error < 1e-11);
    MESSAGE("split levels in bin order from s = ", from, ", block vs modal: ", error);
  }
  const double length = 1.0, dt = 0.25 * (length / 16) / m.shear_wave_speed();
  slipstrip::FaceBlockDesign halves, ordered;
  halves.split_level = ordered.split_level = 32;
  ordered.bin_order_level = 32;
  slipstrip::FaceBlockHistory a(m, 1.5, OuterFace::clamped, length, 16, dt, halves);
  slipstrip::FaceBlockHistory b(m, 1.5, OuterFace::clamped, length, 16, dt, ordered);
  const auto [diff, scale] = same_inputs_difference(a, b, 5, 600);
  MESSAGE("bin order against halves: ", diff / scale);
  CHECK(diff < 1e-13 * scale);
  slipstrip::FaceBlockDesign odd;
  odd.bin_order_level = 96;
  CHECK_THROWS_AS(slipstrip::FaceBlockHistory(m, 1.5, OuterFace::driven, length, 16, dt, odd),
                  std::invalid_argument);
}

TEST_CASE("block face history with the far field's grids interleaved equals the modal face history") {
  // The layout of B >= 4096 (Nufft::interleaved_grid), forced at B = 256,
  // with and without split levels; the tolerance of the tests above.
  ElasticMaterial m;
  for (int split : {2048, 32}) {
    slipstrip::FaceBlockDesign design;
    design.nufft_interleave_from = 0;
    design.split_level = split;
    int block = 0;
    const double error = block_vs_modal(m, 1.5, OuterFace::clamped, 0.25, 16, 700, design, &block);
    CAPTURE(split);
    CHECK(block == 256);
    CHECK(error < 1e-11);
    MESSAGE("interleaved grids, split levels s >= ", split, ": block vs modal ", error);
  }
}

TEST_CASE("block face history: save and restore continue bit for bit") {
  ElasticMaterial m;
  const double length = 1.0, nodes = 16, dt = 0.25 * (length / nodes) / m.shear_wave_speed();
  slipstrip::FaceBlockHistory a(m, 0.5, OuterFace::driven, length, nodes, dt);
  slipstrip::FaceBlockHistory b(m, 0.5, OuterFace::driven, length, nodes, dt);
  std::vector<cd> vx(a.modes()), vy(a.modes());
  const auto drive = [&](int n) {
    for (int q = 0; q < a.modes(); ++q) {
      vx[q] = cd(std::sin(0.3 * n + q), q == 0 ? 0.0 : std::cos(0.7 * n - q));
      vy[q] = cd(std::cos(0.11 * n * q), q == 0 ? 0.0 : std::sin(0.05 * n + 2 * q));
    }
  };
  for (int n = 0; n < 100; ++n) {
    drive(n);
    a.push(vx, vy);
  }
  slipstrip::HistoryOperatorState state;
  a.save_into(state, "top.");
  b.restore_from(state, "top.");
  for (int n = 100; n < 300; ++n) {
    drive(n);
    a.push(vx, vy);
    b.push(vx, vy);
  }
  for (int q = 0; q < a.modes(); ++q) {
    CHECK(a.history_x()[q] == b.history_x()[q]);
    CHECK(a.history_y()[q] == b.history_y()[q]);
  }
}

TEST_CASE("block face history: saved at every position of a direct block, it continues bit for bit") {
  // B = 64, direct block 8: saved after each step from 100 to 129 (every
  // position in a direct block, whose inputs so far and outputs a restore
  // rebuilds from the rows, including the last, and the block's end at 127),
  // then 70 steps on: the histories of the run that was never saved.
  ElasticMaterial m;
  const double length = 1.0, dt = 0.25 * (length / 16) / m.shear_wave_speed();
  const slipstrip::FaceBlockDesign design{8, 64, 12};
  const auto make = [&] { return slipstrip::FaceBlockHistory(m, 0.5, OuterFace::driven, length, 16, dt, design); };
  slipstrip::FaceBlockHistory straight_run = make();
  const int modes = straight_run.modes();
  std::vector<std::vector<cd>> vx(200, std::vector<cd>(modes)), vy = vx, straight_x, straight_y;
  for (int n = 0; n < 200; ++n)
    for (int q = 0; q < modes; ++q) {
      vx[n][q] = cd(std::sin(0.3 * n + q), q == 0 ? 0.0 : std::cos(0.7 * n - q));
      vy[n][q] = cd(std::cos(0.11 * n * q), q == 0 ? 0.0 : std::sin(0.05 * n + 2 * q));
    }
  for (int n = 0; n < 200; ++n) {
    straight_run.push(vx[n], vy[n]);
    straight_x.emplace_back(straight_run.history_x().begin(), straight_run.history_x().end());
    straight_y.emplace_back(straight_run.history_y().begin(), straight_run.history_y().end());
  }
  slipstrip::FaceBlockHistory saver = make();
  for (int n = 0; n < 100; ++n) saver.push(vx[n], vy[n]);
  for (int stop = 100; stop < 130; ++stop) {
    slipstrip::HistoryOperatorState state;
    saver.save_into(state, "top.");
    slipstrip::FaceBlockHistory resumed = make();
    resumed.restore_from(state, "top.");
    int differing = 0;
    for (int n = stop; n < stop + 70; ++n) {
      resumed.push(vx[n], vy[n]);
      for (int q = 0; q < modes; ++q)
        differing += (resumed.history_x()[q] != straight_x[n][q]) + (resumed.history_y()[q] != straight_y[n][q]);
    }
    INFO("saved after " << stop << " steps (position " << stop % 64 << " of the block)");
    CHECK(differing == 0);
    saver.push(vx[stop], vy[stop]);
  }
}

TEST_CASE("a pair restart point of another body algorithm is refused by name") {
  // A modal body's saved part restored into a block body (what resuming a
  // restart point of a version that chose the other algorithm would do), and
  // the half-space body's older complex layout: one message naming both.
  ElasticMaterial m;
  const double length = 1.0, dt = 0.25 * (length / 16) / m.shear_wave_speed();
  const auto modal_pair = [&] {
    return slipstrip::InplanePairHistory(
        std::make_unique<slipstrip::FaceModalHistory>(m, 0.5, OuterFace::driven, length, 16, dt), nullptr);
  };
  slipstrip::InplanePairHistory modal = modal_pair();
  slipstrip::InplanePairHistory block(
      std::make_unique<slipstrip::FaceBlockHistory>(m, 0.5, OuterFace::driven, length, 16, dt), nullptr);
  const std::vector<cd> slip_rate(modal.modes(), cd(1e-3, 0.0));
  modal.push(slip_rate);
  const slipstrip::HistoryOperatorState saved = modal.save_state();
  CHECK_THROWS_WITH_AS(block.restore_state(saved),
                       doctest::Contains("the top body's part was written by the modal operator, this run "
                                         "builds the block one"),
                       std::invalid_argument);
  slipstrip::HistoryOperatorState older = saved;
  for (auto& [name, values] : older.arrays)
    if (name == "top.cx") name = "top.far_x";
  slipstrip::InplanePairHistory again = modal_pair();
  CHECK_THROWS_WITH_AS(again.restore_state(older),
                       doctest::Contains("written by the half-space (the complex layout of an older slipstrip) "
                                         "operator"),
                       std::invalid_argument);
  // The same algorithm restores.
  slipstrip::InplanePairHistory same = modal_pair();
  same.restore_state(saved);
  modal.push(slip_rate);
  same.push(slip_rate);
  for (int q = 0; q < modal.modes(); ++q) CHECK(same.history()[q] == modal.history()[q]);
}
