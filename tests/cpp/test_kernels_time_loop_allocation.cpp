// The history operators' push() does not allocate (the time loop's contract,
// kernels/history_convolution.hpp): every heap allocation of this program is
// counted (allocation_counter.hpp) while the block operators of an identical
// strip pair (BlockStripHistory) and of pairs of different bodies
// (TwoBodyHistory over two BlockStripHistory, InplanePairHistory over two
// FaceBlockHistory; the combined operator of two half-spaces) run whole blocks
// of steps.
// The block length B = 2048 puts the FFT levels at up to 2048 points and the
// NUFFT grid at 4096: the lengths at which FFTW's in-place complex plans take
// a work buffer from the heap at every execute (FFTW 3.3.10, FFTW_ESTIMATE:
// 2048..32768 points), which the operators avoid by transforming out of place.
// Each case runs with one OpenMP thread (no parallel region: libgomp allocates
// a team of one at every region) and with two (the thread pool is started
// before counting: the OpenMP runtime's one start per process).
#include <doctest/doctest.h>

#include <algorithm>
#include <complex>
#include <memory>
#include <random>
#include <vector>

#include "allocation_counter.hpp"
#include "white_noise.hpp"
#include "kernels/block_strip_history.hpp"
#include "kernels/face_block_history.hpp"
#include "kernels/face_half_space.hpp"
#include "kernels/fft.hpp"
#include "kernels/half_space_history.hpp"
#include "kernels/history_convolution.hpp"
#include "kernels/inplane_pair_history.hpp"
#include "kernels/two_body_history.hpp"

namespace {

using cplx = std::complex<double>;
using slipstrip::ElasticMaterial;
using slipstrip_test::allocations;
using slipstrip_test::with_threads;

constexpr int kBlock = 2048;
// Two block ends and more: every FFT level and the far field (locate, the
// NUFFT both ways) run at least twice.
constexpr int kSteps = 2 * kBlock + 3;

// kSteps spectra of white noise (mode 0 real), made before counting.
std::vector<std::vector<cplx>> white_noise(int modes, unsigned seed) {
  return slipstrip_test::white_noise_spectra(modes, kSteps, seed);
}

// Allocations while `push` runs once per input.
template <class Inputs, class Push>
long allocations_in(const Inputs& inputs, Push&& push) {
  const long before = allocations();
  for (const auto& v : inputs) push(v);
  return allocations() - before;
}

}  // namespace

TEST_CASE("the allocation counter sees operator new and fftw_malloc") {
  // Without this the zero counts below could come from a counter that never counts.
  const long before = allocations();
  {
    auto values = std::make_unique<double[]>(1000);
    void* volatile escaped = values.get();  // the allocation cannot be elided
    (void)escaped;
    auto buffer = slipstrip::make_fftw_buffer<fftw_complex>(4096);
    void* volatile escaped_buffer = buffer.get();
    (void)escaped_buffer;
  }
  CHECK(allocations() - before >= 2);
}

TEST_CASE("identical strip pair: the block operator does not allocate in push (B = 2048)") {
  ElasticMaterial material;
  const double height = 0.05, length = 0.1;
  const int nodes = 16;
  const double dt = slipstrip::strip_time_step(material, height, length / nodes, 0.25);
  const auto kernels = slipstrip::compute_strip_kernels(material, height, length, nodes, dt);
  for (int threads : {1, 2}) {
    with_threads(threads, [&] {
      slipstrip::BlockStripHistory history(material, kernels, {32, kBlock, 12});
      REQUIRE(history.block() == kBlock);
      const long during = allocations_in(white_noise(history.modes(), 11), [&](const auto& v) { history.push(v); });
      MESSAGE(threads << " thread(s): allocations in " << kSteps << " pushes: " << during);
      CHECK(during == 0);
    });
  }
}

TEST_CASE("antiplane pair of different bodies: both block body operators do not allocate in push (B = 2048)") {
  // TwoBodyHistory over two BlockStripHistory bodies (the bottom one 2x mu
  // and rho), as Simulation builds an antiplane pair of different bodies.
  ElasticMaterial top, bottom;
  top.plane = bottom.plane = slipstrip::PlaneCondition::antiplane;
  bottom.shear_modulus = 2.0 * top.shear_modulus;
  bottom.density = 2.0 * top.density;
  const double height = 0.05, length = 0.1;
  const int nodes = 16;
  const double dt = slipstrip::strip_time_step(top, height, length / nodes, 0.25);
  for (int threads : {1, 2}) {
    with_threads(threads, [&] {
      const auto body = [&](const ElasticMaterial& m) {
        return std::make_unique<slipstrip::BlockStripHistory>(
            m, slipstrip::compute_strip_kernels(m, height, length, nodes, dt), slipstrip::BlockHistoryDesign{32, kBlock, 12});
      };
      slipstrip::TwoBodyHistory pair(body(top), body(bottom));
      REQUIRE(pair.period() == kBlock);
      const long during = allocations_in(white_noise(pair.modes(), 14), [&](const auto& v) { pair.push(v); });
      MESSAGE(threads << " thread(s): allocations in " << kSteps << " pushes: " << during);
      CHECK(during == 0);
    });
  }
}

TEST_CASE("pair of different bodies: both block body operators do not allocate in push (B = 2048)") {
  // A thin slider on a thicker base of twice its mu and rho, both finite and
  // driven, each by the block 2x2 operator; the opening stress is pushed too.
  ElasticMaterial top, bottom;
  bottom.shear_modulus = 2.0 * top.shear_modulus;
  bottom.density = 2.0 * top.density;
  const double length = 0.1;
  const int nodes = 16;
  const double dt = slipstrip::strip_time_step(top, 0.05, length / nodes, 0.25);
  const slipstrip::FaceBlockDesign design{32, kBlock, 12};
  for (int threads : {1, 2}) {
    with_threads(threads, [&] {
      auto top_body = std::make_unique<slipstrip::FaceBlockHistory>(top, 0.05, slipstrip::OuterFace::driven,
                                                                     length, nodes, dt, design);
      auto bottom_body = std::make_unique<slipstrip::FaceBlockHistory>(bottom, 0.1, slipstrip::OuterFace::driven,
                                                                        length, nodes, dt, design);
      REQUIRE(top_body->period() == kBlock);
      REQUIRE(bottom_body->period() == kBlock);
      slipstrip::InplanePairHistory pair(std::move(top_body), std::move(bottom_body));
      const auto slip_rate = white_noise(pair.modes(), 12);
      const auto opening_stress = white_noise(pair.modes(), 13);
      const long before = allocations();
      for (int n = 0; n < kSteps; ++n) pair.push(slip_rate[n], opening_stress[n]);
      const long during = allocations() - before;
      MESSAGE(threads << " thread(s): allocations in " << kSteps << " pushes: " << during);
      CHECK(during == 0);
    });
  }
}

// One block body operator of `design` (H = 0.05 m strip, 16 nodes over 0.1 m,
// beta = 0.25; period kBlock) pushed kSteps times, with one and with two
// threads, white-noise inputs from seeds `seed` and `seed` + 1: no allocation.
void check_body_push_does_not_allocate(const slipstrip::FaceBlockDesign& design, unsigned seed) {
  ElasticMaterial m;
  const double length = 0.1;
  const int nodes = 16;
  const double dt = slipstrip::strip_time_step(m, 0.05, length / nodes, 0.25);
  for (int threads : {1, 2}) {
    with_threads(threads, [&] {
      slipstrip::FaceBlockHistory body(m, 0.05, slipstrip::OuterFace::driven, length, nodes, dt, design);
      REQUIRE(body.period() == kBlock);
      const auto vx = white_noise(body.modes(), seed);
      const auto vy = white_noise(body.modes(), seed + 1);
      const long before = allocations();
      for (int n = 0; n < kSteps; ++n) body.push(vx[n], vy[n]);
      const long during = allocations() - before;
      MESSAGE(threads << " thread(s): allocations in " << kSteps << " pushes: " << during);
      CHECK(during == 0);
    });
  }
}

TEST_CASE("a block body operator with split levels and interleaved far-field grids does not allocate in push") {
  // The levels of s >= split_level by transforms of length s, and the far
  // field's two components on one interleaved grid (one FFTW plan of two
  // strided transforms): at full size from s = 2048 and 2B = 8192 points on,
  // forced here at B = 2048 (levels s = 512, 1024 split; grid 4096 points).
  slipstrip::FaceBlockDesign design{32, kBlock, 12};
  design.split_level = 512;
  design.nufft_interleave_from = 0;
  check_body_push_does_not_allocate(design, 14);
}

TEST_CASE("a block body operator with split levels in bin order does not allocate in push") {
  // The split levels of s >= bin_order_level through FFTW plans of two
  // transforms with stride 2 (at full size from s = 8192 on), forced here at
  // B = 2048 (levels s = 512, 1024).
  slipstrip::FaceBlockDesign design{32, kBlock, 12};
  design.split_level = 512;
  design.bin_order_level = 512;
  check_body_push_does_not_allocate(design, 16);
}

TEST_CASE("the combined half-space pair operator does not allocate in push") {
  // PMMA over Homalite (docs/inplane_bodies.md §7) through InplanePairHistory:
  // kSteps pushes (32 slow blocks of 128), the opening stress zero for the
  // first half (the opening channel skipped) and white noise after.
  const ElasticMaterial top{2.1e9, 0.35, 1170.0, slipstrip::PlaneCondition::stress};
  const ElasticMaterial bottom{1.9e9, 0.34, 1230.0, slipstrip::PlaneCondition::stress};
  const double length = 0.1;
  const int nodes = 16;
  const double dt = 0.3 * (length / nodes) / top.shear_wave_speed();
  for (int threads : {1, 2}) {
    with_threads(threads, [&] {
      slipstrip::InplanePairHistory pair(
          slipstrip::InplanePairHistory::Combined{},
          std::make_unique<slipstrip::FaceHalfSpaceHistory>(top, bottom, length, nodes, dt));
      const auto slip_rate = white_noise(pair.modes(), 14);
      auto opening_stress = white_noise(pair.modes(), 15);
      for (int n = 0; n < kSteps / 2; ++n) std::fill(opening_stress[n].begin(), opening_stress[n].end(), cplx(0.0));
      const long before = allocations();
      for (int n = 0; n < kSteps; ++n) pair.push(slip_rate[n], opening_stress[n]);
      const long during = allocations() - before;
      MESSAGE(threads << " thread(s): allocations in " << kSteps << " pushes: " << during);
      CHECK(during == 0);
    });
  }
}

TEST_CASE("the combined antiplane half-space pair operator does not allocate in push") {
  // The bench's pair (bottom 4x mu, same rho: c_b = 2 c_t) as one scalar
  // operator (HalfSpaceHistory's pair constructor): kSteps pushes of white
  // noise, 32 slow blocks of 128 steps and their far-field batches.
  const ElasticMaterial top{9e9, 0.33, 1200.0, slipstrip::PlaneCondition::antiplane};
  const ElasticMaterial bottom{36e9, 0.33, 1200.0, slipstrip::PlaneCondition::antiplane};
  const double length = 0.1;
  const int nodes = 16;
  const double dt = 0.3 * (length / nodes) / bottom.shear_wave_speed();
  for (int threads : {1, 2}) {
    with_threads(threads, [&] {
      slipstrip::HalfSpaceHistory pair(top, bottom, length, nodes, dt);
      REQUIRE(pair.shape().antiplane_pair());
      const auto slip_rate = white_noise(pair.modes(), 16);
      const long before = allocations();
      for (int n = 0; n < kSteps; ++n) pair.push(slip_rate[n]);
      const long during = allocations() - before;
      MESSAGE(threads << " thread(s): allocations in " << kSteps << " pushes: " << during);
      CHECK(during == 0);
    });
  }
}
