#include "kernels/half_space_design.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>

#include "kernels/half_space_kernel.hpp"
#include "kernels/mode_parallel.hpp"
#include "kernels/passivity.hpp"

namespace slipstrip {
namespace {

// W = ceil(near_field_tau / h) less this slack, so that a ratio a rounding
// error above a whole number does not add a lag.
constexpr double kWindowSlack = 1e-12;
// Gauss-Legendre nodes per panel of the exponential sums
// (kernels/half_space_kernel.hpp): 10 for the near field, which is evaluated
// at every stored lag, 8 for the far field's exponentials, whose count sets
// the cost per step (both measured in test_kernels_half_space_kernel.cpp).
constexpr int kNearNodesPerPanel = 10;
constexpr int kFarNodesPerPanel = 8;
// An antiplane pair of different speeds: its sums refine each panel until 4
// more nodes change it by at most 1e-12 (kernels/half_space_kernel.hpp), so the
// far field's panels start from 2 nodes and take only what they need: 228
// exponentials for the bench's pair (c_b = 2 c_t) against 368 from 8, as
// accurate (~3e-11 from Durbin's inverse on tau in [1, 40], measured).
constexpr int kPairFarNodesPerPanel = 2;
// A far-field exponential whose amplitude at the first far lag is below this
// is dropped: negligible at every lag >= W + 1, where the kernel is O(1).
constexpr double kNegligibleAmplitude = 1e-17;

}  // namespace

double slow_taylor_error_bound(const HalfSpaceOperatorDesign& design) {
  // Lagrange remainder of e^{-y}, |y| <= r, after n terms: r^n / n! e^r.
  const double r = design.slow_taylor_radius;
  double bound = std::exp(r);
  for (int n = 1; n <= design.taylor_terms; ++n) bound *= r / n;
  return bound;
}

double slow_decay_limit(int block, double radius) { return block > 0 ? 2.0 * radius / (block - 1) : -1.0; }

void check_half_space_design(const HalfSpaceOperatorDesign& design) {
  if (design.slow_block == 0) return;
  if (design.slow_block < 2 || design.taylor_terms < 1 || design.taylor_terms > kMaxTaylorTerms ||
      !(design.slow_taylor_radius > 0))
    throw std::invalid_argument("HalfSpaceHistory: slow_block must be 0 or >= 2, taylor_terms in [1, " +
                                std::to_string(kMaxTaylorTerms) + "], slow_taylor_radius > 0");
  if (!(slow_taylor_error_bound(design) <= kMaxSlowTaylorError))
    throw std::invalid_argument("HalfSpaceHistory: the slow exponentials' Taylor error bound " +
                                std::to_string(slow_taylor_error_bound(design)) +
                                " exceeds 1e-14 (raise taylor_terms or lower slow_taylor_radius)");
}

std::vector<int> half_space_windows(std::span<const double> h, const HalfSpaceOperatorDesign& design) {
  std::vector<int> window(h.size(), 0);
  for (std::size_t q = 1; q < h.size(); ++q)
    window[q] = std::max(design.corrected_lags,
                         static_cast<int>(std::ceil(design.near_field_tau / h[q] - kWindowSlack)));
  return window;
}

void set_near_field_range(HalfSpaceOperatorDesign& design, std::span<const double> h) {
  std::vector<double> moving;  // the modes that move (h > 0), as half_space_windows sees them
  moving.push_back(0.0);
  for (double value : h)
    if (value > 0.0) moving.push_back(value);
  const std::vector<int> window = half_space_windows(moving, design);
  double tau_max = 0.0, h_min = std::numeric_limits<double>::infinity();
  for (std::size_t q = 1; q < moving.size(); ++q) {
    tau_max = std::max(tau_max, window[q] * moving[q]);
    h_min = std::min(h_min, moving[q]);
  }
  design.near_field_tau_max = tau_max;
  design.near_field_h_min = moving.size() > 1 ? h_min : 0.0;
}

std::vector<HalfSpaceModeTerms> half_space_mode_terms(const ElasticMaterial& material, double time_step,
                                                      std::span<const double> h_of, std::span<const int> window,
                                                      int block, const HalfSpaceOperatorDesign& design,
                                                      const CancelCheck& cancelled) {
  // In-plane or antiplane (SH) kernel: the same machinery, another universal
  // function g (kernels/half_space_kernel.hpp); antiplane has no P branch.
  return half_space_mode_terms(half_space_shape(material), material.shear_modulus, material.shear_wave_speed(),
                               time_step, h_of, window, block, design, cancelled);
}

std::vector<HalfSpaceModeTerms> half_space_mode_terms(const HalfSpaceShape& shape, double modulus, double speed,
                                                      double time_step, std::span<const double> h_of,
                                                      std::span<const int> window, int block,
                                                      const HalfSpaceOperatorDesign& design,
                                                      const CancelCheck& cancelled) {
  const int n_modes = static_cast<int>(h_of.size());
  const int lags = design.corrected_lags;
  const double mu = modulus, cs = speed;
  const double static_value = half_space_static_value(shape);
  // Stored lags reach tau = W h <= near_field_tau + lags h_max; the far field
  // starts at tau = W h >= near_field_tau.
  double tau_near_max = design.near_field_tau_max;
  for (int q = 1; q < n_modes; ++q) tau_near_max = std::max(tau_near_max, window[q] * h_of[q]);
  // The near-field sum must reach down to the smallest h (h_of[1] on a
  // one-dimensional interface, whose wavenumbers increase with q).
  double h_min = design.near_field_h_min > 0.0 ? design.near_field_h_min : std::numeric_limits<double>::infinity();
  for (int q = 1; q < n_modes; ++q) h_min = std::min(h_min, h_of[q]);
  const ExponentialSum near =
      n_modes > 1
          ? half_space_exponential_sum(shape, h_min, 2.0 * tau_near_max + 1.0, kNearNodesPerPanel)
          : ExponentialSum{};
  // Modes of equal h (equal |k|: the modes +-kz of a 2D interface) share one
  // design: design_of[q] is the first mode with q's h, computed once and copied.
  std::vector<int> design_of(n_modes, 0);
  {
    std::map<double, int> first_of;
    for (int q = 1; q < n_modes; ++q) design_of[q] = first_of.emplace(h_of[q], q).first->second;
  }
  const ExponentialSum far =
      half_space_exponential_sum(shape, design.near_field_tau, design.horizon_tau,
                                 shape.antiplane_pair() ? kPairFarNodesPerPanel : kFarNodesPerPanel);
  // Slow when lambda (B - 1) / 2 <= radius, lambda = x h (x = -Re rate).
  const double slow_lambda_max = slow_decay_limit(block, design.slow_taylor_radius);

  std::vector<HalfSpaceModeTerms> terms(n_modes);
  const std::string failure = for_each_mode_in_parallel(
      1, n_modes, cancelled, "the half-space history operator", [&](int q) {
    if (design_of[q] != q) return;  // copied below from the mode of equal h
    HalfSpaceModeTerms& t = terms[q];
    const double h = h_of[q];
    const double scale = mu / cs * h;  // dt mu |k|
    t.static_weight = scale * static_value;
    const auto e = half_space_passivity_correction(shape, h, lags, design.passivity_margin);
    t.correction = e;
    auto& w = t.lag_weight;
    w.resize(window[q]);
    for (int j = 1; j <= window[q]; ++j) {
      w[j - 1] = scale * (evaluate(near, j * h) - static_value);
      if (j <= lags) w[j - 1] += mu / cs * e[j - 1];
    }
    const double shift_tau = window[q] * h;
    for (std::size_t m = 0; m < far.rate.size(); ++m) {
      const std::complex<double> shifted = far.amplitude[m] * std::exp(far.rate[m] * shift_tau);
      if (std::abs(shifted) < kNegligibleAmplitude) continue;
      if (-far.rate[m].real() * h <= slow_lambda_max) {
        t.slow_rate.push_back(far.rate[m]);
        t.slow_weight.push_back(scale * shifted);
        // Shear-branch (reference-branch) rates have imaginary part exactly 1
        // and come first (half_space_exponential_sum), so this counts them;
        // every other rate lies on the second branch (no pole exponentials:
        // kernels/half_space_kernel.hpp).
        if (far.rate[m].imag() == 1.0) t.slow_shear = t.slow_rate.size();
        continue;
      }
      t.pole.push_back(std::exp(far.rate[m] * h));
      t.pole_weight.push_back(scale * shifted);
    }
  });
  if (!failure.empty()) {
    std::ostringstream msg;
    msg << "half-space history operator (dt = " << time_step << " s, c_s k_max dt = "
        << *std::max_element(h_of.begin(), h_of.end()) << "): " << failure;
    throw HalfSpaceNotPassive(msg.str());
  }
  for (int q = 1; q < n_modes; ++q)
    if (design_of[q] != q) terms[q] = terms[design_of[q]];
  return terms;
}

}  // namespace slipstrip
