// RealFft2d against a direct discrete Fourier transform, and its paired
// transforms (two components at once, each on a thread of its own) against
// the single ones, bit for bit with one and with two OpenMP threads.
#include <doctest/doctest.h>
#include <omp.h>

#include <cmath>
#include <complex>
#include <numbers>
#include <random>
#include <vector>

#include "allocation_counter.hpp"
#include "kernels/fft.hpp"

using namespace slipstrip;
using slipstrip_test::with_threads;

namespace {

std::vector<double> random_field(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<double> f(n);
  for (auto& v : f) v = unit(rng);
  return f;
}

}  // namespace

TEST_CASE("RealFft2d: forward = the direct DFT over [qz][qx], inverse(forward(f)) = f") {
  const int nx = 12, nz = 6;
  RealFft2d fft(nx, nz);
  REQUIRE(fft.modes() == static_cast<std::size_t>(nx / 2 + 1) * nz);
  const auto f = random_field(fft.nodes(), 3);
  std::vector<std::complex<double>> spectrum(fft.modes());
  fft.forward(f, spectrum);
  // Direct sum, O(N^2): the independent reference.  Each term is O(1) and
  // there are 72 of them, so 1e-12 absolute leaves a margin of ~100 over the
  // round-off of either evaluation.
  double worst = 0.0;
  for (int qz = 0; qz < nz; ++qz)
    for (int qx = 0; qx <= nx / 2; ++qx) {
      std::complex<double> sum = 0.0;
      for (int iz = 0; iz < nz; ++iz)
        for (int ix = 0; ix < nx; ++ix) {
          const double phase = -2.0 * std::numbers::pi * (static_cast<double>(qx * ix) / nx +
                                                          static_cast<double>(qz * iz) / nz);
          sum += f[iz * nx + ix] * std::complex<double>(std::cos(phase), std::sin(phase));
        }
      worst = std::max(worst, std::abs(sum - spectrum[qz * (nx / 2 + 1) + qx]));
    }
  CHECK(worst < 1e-12);
  std::vector<double> back(fft.nodes());
  fft.inverse(spectrum, back);
  double round_trip = 0.0;
  for (std::size_t i = 0; i < back.size(); ++i) round_trip = std::max(round_trip, std::abs(back[i] - f[i]));
  CHECK(round_trip < 1e-14);
}

TEST_CASE("RealFft2d: the paired transforms equal the single ones bit for bit, one and two threads") {
  for (int threads : {1, 2}) {
    with_threads(threads, [] {
      // 64 x 32: large enough for FFTW to pick SIMD codelets, whose alignment
      // both buffer sets must meet.
      const int nx = 64, nz = 32;
      RealFft2d fft(nx, nz);
      const auto a = random_field(fft.nodes(), 1), b = random_field(fft.nodes(), 2);
      std::vector<std::complex<double>> single_a(fft.modes()), single_b(fft.modes()), pair_a(fft.modes()),
          pair_b(fft.modes());
      fft.forward(a, single_a);
      fft.forward(b, single_b);
      fft.forward_pair(a, pair_a, b, pair_b);
      CHECK(pair_a == single_a);
      CHECK(pair_b == single_b);

      std::vector<double> back_a(fft.nodes()), back_b(fft.nodes()), pair_back_a(fft.nodes()),
          pair_back_b(fft.nodes());
      fft.inverse(single_a, back_a);
      fft.inverse(single_b, back_b);
      fft.inverse_pair(single_a, pair_back_a, single_b, pair_back_b);
      CHECK(pair_back_a == back_a);
      CHECK(pair_back_b == back_b);
      // The inputs of the inverse are not touched (c2r works on a copy).
      CHECK(single_a == pair_a);
    });
  }
}
