// The NUFFT against the direct sums it replaces.  Errors are relative to the
// l1 norm of the input (the natural scale of every output: |out| <= sum |in|).
// The first case's bound is the prediction for the Gaussian gridding the NUFFT
// had before its exponential-of-semicircle (ES) kernel, at the same half-width
// w: truncation = aliasing error exp(-pi w / sqrt 2), times the largest
// deconvolution factor ghat(0)/ghat(B/2) = exp(pi w / (8 sqrt 2)) (7e-11 at
// w = 12, 1.5e-12 at w = 14): the ES kernel must be at least as accurate at
// every half-width.  The second checks the default (w = 7, 14 grid points per
// frequency) against the accuracy the block operators were designed for.
// Operators built on it (the block history operator) are checked separately.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
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

// The largest errors of the forward and the adjoint transform against their
// direct sums, each over the l1 norm of its input.
std::array<double, 2> direct_sum_errors(const Nufft& nufft, const Problem& p) {
  const std::size_t samples = p.samples.size(), frequencies = p.theta.size();
  auto scratch = nufft.make_scratch(frequencies);
  std::vector<cplx> out(frequencies);
  nufft.forward(p.samples, p.theta, out, scratch);
  double worst = 0;
  for (std::size_t k = 0; k < frequencies; ++k) {
    cplx direct = 0;
    for (std::size_t t = 0; t < samples; ++t) direct += p.samples[t] * std::polar(1.0, -p.theta[k] * t);
    worst = std::max(worst, std::abs(out[k] - direct));
  }
  const double forward_error = worst / l1(p.samples);

  std::vector<cplx> series(samples);
  nufft.adjoint(p.theta, p.coefficients, series, scratch);
  worst = 0;
  for (std::size_t t = 0; t < samples; ++t) {
    cplx direct = 0;
    for (std::size_t k = 0; k < frequencies; ++k) direct += p.coefficients[k] * std::polar(1.0, p.theta[k] * t);
    worst = std::max(worst, std::abs(series[t] - direct));
  }
  return {forward_error, worst / l1(p.coefficients)};
}
}  // namespace

TEST_CASE("NUFFT forward and adjoint match the direct sums") {
  for (int half_width : {8, 12, 14})
  for (int samples : {16, 64, 1024, 4096}) {
    const int frequencies = 3 * samples / 2 + 7;
    const auto p = random_problem(samples, frequencies, 1234u + samples);
    Nufft nufft(samples, half_width);
    const double predicted = std::exp(-pi * half_width / std::numbers::sqrt2) *
                             std::exp(pi * half_width / (8 * std::numbers::sqrt2));
    const auto [forward_error, adjoint_error] = direct_sum_errors(nufft, p);
    MESSAGE("w = " << half_width << ", B = " << samples << ": forward " << forward_error
                   << ", adjoint " << adjoint_error << " (max error / l1 norm of the input), predicted "
                   << predicted);
    CHECK(forward_error < predicted);
    CHECK(adjoint_error < predicted);
  }
}

TEST_CASE("NUFFT at its default half-width: the ES kernel's 14 points per frequency meet 5e-13") {
  // The block operators' default (kernels/block_strip_history.hpp,
  // kernels/face_block_history.hpp) was the Gaussian at half-width 12 (24
  // points per frequency), measured <= 1.5e-12 of sum |input| (~2e-13 from
  // B = 1024 on).  The ES kernel's error on the 2x grid falls as
  // exp(-pi (2w) / sqrt 2), the Gaussian's rate per point squared: 3e-14 at
  // w = 7; measured <= 1.5e-13 (B = 64, adjoint; <= 7e-14 at the other B).
  // Bound 5e-13: the block operators' design accuracy, 3x the measurement.
  // Frequencies in +-pairs as the block operators list them (the mirrored
  // windows), random ones and the interval's ends; the kernel weights'
  // polynomials are checked against the kernel too.
  for (int samples : {16, 64, 256, 1024, 4096}) {
    const int frequencies = 3 * samples / 2 + 7;
    auto p = random_problem(samples, frequencies, 4321u + samples);
    for (int k = 4; k + 1 < frequencies; k += 4) p.theta[k + 1] = -p.theta[k];
    Nufft nufft(samples);
    CHECK(nufft.weight_fit_error() < 1e-14);
    const auto [forward_error, adjoint_error] = direct_sum_errors(nufft, p);
    MESSAGE("default, B = " << samples << ": forward " << forward_error << ", adjoint " << adjoint_error
                            << " (max error / l1 norm of the input); weights' fit " << nufft.weight_fit_error()
                            << " at degree " << nufft.weight_fit_degree());
    CHECK(forward_error < 5e-13);
    CHECK(adjoint_error < 5e-13);
  }
}

TEST_CASE("NUFFT rejects sizes it cannot handle") {
  CHECK_THROWS_AS(Nufft(7), std::invalid_argument);
  CHECK_THROWS_AS(Nufft(0), std::invalid_argument);
  CHECK_THROWS_AS(Nufft(64, 1), std::invalid_argument);
  CHECK_THROWS_AS(Nufft(64, 100), std::invalid_argument);
}

namespace {

// forward_map_adjoint of two random series, mixed per frequency as the 2x2
// operator mixes its components, against locate + forward_centred, the same
// map, adjoint_centred: the largest difference relative to the largest output.
double one_pass_against_two_halves(Nufft& nufft, int samples) {
  const int frequencies = 3 * samples / 2 + 7;
  const auto p = random_problem(samples, frequencies, 99u + samples);
  const auto q = random_problem(samples, frequencies, 7u + samples);
  const cplx m00(0.5, 0.1), m01(-0.2, 0.7), m10(0.3, -0.4), m11(1.1, 0.2);
  const auto mix = [&](std::size_t k, std::array<cplx, 2>& v) {
    const double g = 1.0 + 0.01 * static_cast<double>(k);
    v = {g * (m00 * v[0] + m01 * v[1]), g * (m10 * v[0] + m11 * v[1])};
  };

  auto scratch = nufft.make_scratch(frequencies);
  nufft.locate(p.theta, scratch);
  std::vector<cplx> fx(frequencies), fy(frequencies), ox(samples), oy(samples);
  nufft.forward_centred(p.samples, fx, scratch);
  nufft.forward_centred(q.samples, fy, scratch);
  for (int k = 0; k < frequencies; ++k) {
    std::array<cplx, 2> v{fx[k], fy[k]};
    mix(k, v);
    fx[k] = v[0];
    fy[k] = v[1];
  }
  nufft.adjoint_centred(fx, ox, scratch);
  nufft.adjoint_centred(fy, oy, scratch);

  // The one pass adds into its outputs: start them from a known value.
  std::vector<cplx> px(samples, cplx(1.0, -2.0)), py(samples, cplx(-0.5, 0.25));
  auto pass = nufft.make_pass_scratch(2);
  nufft.forward_map_adjoint<2>(p.theta, {p.samples.data(), q.samples.data()}, {px.data(), py.data()}, pass, mix);
  double worst = 0, scale = 0;
  for (int t = 0; t < samples; ++t) {
    worst = std::max({worst, std::abs(px[t] - cplx(1.0, -2.0) - ox[t]), std::abs(py[t] - cplx(-0.5, 0.25) - oy[t])});
    scale = std::max({scale, std::abs(ox[t]), std::abs(oy[t])});
  }
  return worst / scale;
}

}  // namespace

TEST_CASE("NUFFT one-pass forward, map and adjoint equals its two halves to round-off") {
  // forward_map_adjoint (the block face operator's far field) computes the
  // same weights as the two halves and reassociates only the forward sums, so
  // the two agree to rounding.  Odd and even half-widths (the gather's lane
  // tail), two series mixed by the map as the 2x2 operator mixes its components.
  for (int half_width : {7, 12})
    for (int samples : {16, 256}) {
      Nufft nufft(samples, half_width);
      const double relative = one_pass_against_two_halves(nufft, samples);
      MESSAGE("w = " << half_width << ", B = " << samples << ": one pass against two halves " << relative
                     << " of the largest output");
      CHECK(relative < 1e-13);
    }
}

TEST_CASE("NUFFT one pass of two series on interleaved grids equals its two halves to round-off") {
  // As above, with the two series' grids interleaved point by point and
  // transformed by one plan of two strided transforms (the layout of grids of
  // Nufft::interleaved_grid points and more, here forced at every size).
  for (int half_width : {7, 12})
    for (int samples : {16, 256}) {
      Nufft nufft(samples, half_width, 0);
      REQUIRE(nufft.interleaves_pairs());
      const double relative = one_pass_against_two_halves(nufft, samples);
      MESSAGE("interleaved, w = " << half_width << ", B = " << samples << ": one pass against two halves "
                                  << relative << " of the largest output");
      CHECK(relative < 1e-13);
    }
  CHECK_FALSE(Nufft(256).interleaves_pairs());
  CHECK(Nufft(4096).interleaves_pairs());
  CHECK_THROWS_AS(Nufft(16).make_pass_scratch(3), std::invalid_argument);
}

