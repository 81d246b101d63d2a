// Gaussian-gridding NUFFT against the direct sums it replaces.  Errors are
// relative to the l1 norm of the input (the natural scale of every output:
// |out| <= sum |in|).  The bound checked is the design's own prediction
// (kernels/nufft.cpp): truncation = aliasing error exp(-pi w / sqrt 2), times
// the largest deconvolution factor ghat(0)/ghat(B/2) = exp(pi w / (8 sqrt 2)):
// 7e-11 for the default half-width w = 12, 1.5e-12 for w = 14.  Operators built
// on it (the block history operator) are checked separately at 1e-10.
#include <doctest/doctest.h>

#include <cmath>
#include <complex>
#include <numbers>
#include <random>
#include <vector>

#include "kernels/nufft.hpp"

using namespace slipstrip;
using cplx = std::complex<double>;
constexpr double pi = std::numbers::pi;

namespace {
struct Problem {
  std::vector<double> theta;
  std::vector<cplx> samples, coefficients;
};

Problem random_problem(int samples, int frequencies, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> angle(-pi, pi), value(-1.0, 1.0);
  Problem p;
  for (int k = 0; k < frequencies; ++k) {
    p.theta.push_back(angle(rng));
    p.coefficients.emplace_back(value(rng), value(rng));
  }
  // The operator uses the interval ends too: -pi, pi, 0, and a tiny frequency.
  p.theta[0] = -pi;
  p.theta[1] = pi;
  p.theta[2] = 0.0;
  p.theta[3] = 1e-9;
  for (int t = 0; t < samples; ++t) p.samples.emplace_back(value(rng), value(rng));
  return p;
}

double l1(const std::vector<cplx>& x) {
  double s = 0;
  for (auto v : x) s += std::abs(v);
  return s;
}
}  // namespace

TEST_CASE("NUFFT forward and adjoint match the direct sums") {
  for (int half_width : {8, 12, 14})
  for (int samples : {16, 64, 1024, 4096}) {
    const int frequencies = 3 * samples / 2 + 7;
    const auto p = random_problem(samples, frequencies, 1234u + samples);
    GaussianNufft nufft(samples, half_width);
    const double predicted = std::exp(-pi * half_width / std::numbers::sqrt2) *
                             std::exp(pi * half_width / (8 * std::numbers::sqrt2));
    auto scratch = nufft.make_scratch(frequencies);

    std::vector<cplx> out(frequencies);
    nufft.forward(p.samples, p.theta, out, scratch);
    double worst = 0;
    for (int k = 0; k < frequencies; ++k) {
      cplx direct = 0;
      for (int t = 0; t < samples; ++t) direct += p.samples[t] * std::polar(1.0, -p.theta[k] * t);
      worst = std::max(worst, std::abs(out[k] - direct));
    }
    const double forward_error = worst / l1(p.samples);

    std::vector<cplx> series(samples);
    nufft.adjoint(p.theta, p.coefficients, series, scratch);
    worst = 0;
    for (int t = 0; t < samples; ++t) {
      cplx direct = 0;
      for (int k = 0; k < frequencies; ++k) direct += p.coefficients[k] * std::polar(1.0, p.theta[k] * t);
      worst = std::max(worst, std::abs(series[t] - direct));
    }
    const double adjoint_error = worst / l1(p.coefficients);
    MESSAGE("w = " << half_width << ", B = " << samples << ": forward " << forward_error
                   << ", adjoint " << adjoint_error << " (max error / l1 norm of the input), predicted "
                   << predicted);
    CHECK(forward_error < predicted);
    CHECK(adjoint_error < predicted);
  }
}

TEST_CASE("NUFFT rejects sizes it cannot handle") {
  CHECK_THROWS_AS(GaussianNufft(7), std::invalid_argument);
  CHECK_THROWS_AS(GaussianNufft(0), std::invalid_argument);
  CHECK_THROWS_AS(GaussianNufft(64, 1), std::invalid_argument);
  CHECK_THROWS_AS(GaussianNufft(64, 100), std::invalid_argument);
}
