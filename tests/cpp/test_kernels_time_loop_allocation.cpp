// The history operators' push() does not allocate (the time loop's contract,
// kernels/history_convolution.hpp): every heap allocation of this program is
// counted (allocation_counter.hpp) while the block operators of an identical
// strip pair (BlockStripHistory) and of a pair of different bodies
// (InplanePairHistory over two FaceBlockHistory) run whole blocks of steps.
// The block length B = 2048 puts the FFT levels at up to 2048 points and the
// NUFFT grid at 4096: the lengths at which FFTW's in-place complex plans take
// a work buffer from the heap at every execute (FFTW 3.3.10, FFTW_ESTIMATE:
// 2048..32768 points), which the operators avoid by transforming out of place.
// Each case runs with one OpenMP thread (no parallel region: libgomp allocates
// a team of one at every region) and with two (the thread pool is started
// before counting: the OpenMP runtime's one start per process).
#include <doctest/doctest.h>

#include <complex>
#include <memory>
#include <random>
#include <vector>

#include "allocation_counter.hpp"
#include "kernels/block_strip_history.hpp"
#include "kernels/face_block_history.hpp"
#include "kernels/fft.hpp"
#include "kernels/history_convolution.hpp"
#include "kernels/inplane_pair_history.hpp"

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
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<std::vector<cplx>> steps(kSteps, std::vector<cplx>(modes));
  for (auto& v : steps) {
    for (auto& x : v) x = cplx(normal(rng), normal(rng));
    v[0] = v[0].real();
  }
  return steps;
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
      const auto input = white_noise(history.modes(), 11);
      const long before = allocations();
      for (const auto& v : input) history.push(v);
      const long during = allocations() - before;
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
