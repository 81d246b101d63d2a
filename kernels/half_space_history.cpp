#include "kernels/half_space_history.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include "kernels/history_convolution.hpp"
#include "kernels/strip_response.hpp"

namespace slipstrip {

HalfSpaceHistory::HalfSpaceHistory(const ElasticMaterial& material, double length, int nodes,
                                   double time_step, double tau_cut, std::size_t max_window,
                                   double taper_fraction)
    : dt_(time_step) {
  if (!(length > 0) || !std::isfinite(length))
    throw std::invalid_argument("HalfSpaceHistory: length = " + std::to_string(length) +
                                " m; must be finite and > 0");
  if (nodes < 2)
    throw std::invalid_argument("HalfSpaceHistory: nodes = " + std::to_string(nodes) +
                                "; must be >= 2");
  if (!(time_step > 0) || !std::isfinite(time_step))
    throw std::invalid_argument("HalfSpaceHistory: time_step = " + std::to_string(time_step) +
                                " s; must be finite and > 0");
  if (!(tau_cut > 0) || !std::isfinite(tau_cut))
    throw std::invalid_argument("HalfSpaceHistory: tau_cut = " + std::to_string(tau_cut) +
                                "; must be finite and > 0 (window in units of 1/(k c_s))");
  if (max_window < 1)
    throw std::invalid_argument("HalfSpaceHistory: max_window = 0; must be >= 1 step");
  if (!(taper_fraction >= 0.0 && taper_fraction < 1.0))
    throw std::invalid_argument("HalfSpaceHistory: taper_fraction = " +
                                std::to_string(taper_fraction) + "; allowed: [0, 1)");

  const double mu = material.shear_modulus;
  const double cs = material.shear_wave_speed();
  const double cd = material.dilatational_wave_speed();
  eta_ = mu / (2.0 * cs);
  const int n_modes = nodes / 2 + 1;
  const double inf = std::numeric_limits<double>::infinity();

  // Windows.  q = 0: S_inf(0, s) = eta s exactly, so the half-space has no memory.
  window_.assign(n_modes, 0);
  integrator_weight_.assign(n_modes, 0.0);
  std::size_t longest = 0;
  for (int q = 1; q < n_modes; ++q) {
    const double k = 2.0 * std::numbers::pi * q / length;
    const double steps = std::ceil(tau_cut / (k * cs * dt_));
    window_[q] = steps >= static_cast<double>(max_window)
                     ? max_window
                     : std::max<std::size_t>(1, static_cast<std::size_t>(steps));
    integrator_weight_[q] = dt_ * strip_static_stiffness(material, inf, k);
    longest = std::max(longest, window_[q]);
  }
  first_sample_.assign(n_modes + 1, 0);
  for (int q = 0; q < n_modes; ++q) first_sample_[q + 1] = first_sample_[q] + window_[q];
  weight_.assign(first_sample_.back(), 0.0);

  if (longest > 0) {
    // Virtual strip: 2 Hv / c_s must be a whole number M of steps (exact
    // delay line), and its first reflection, the P wave back after 2 Hv / c_d,
    // must come after lag `longest` (two steps of margin).
    const auto echo_steps =
        static_cast<std::size_t>(std::ceil(cd / cs * static_cast<double>(longest + 2)));
    virtual_height_ = 0.5 * cs * static_cast<double>(echo_steps) * dt_;
    StripHistory strip(material, compute_strip_kernels(material, virtual_height_, length, nodes,
                                                       dt_));
    // Impulse response of every mode at once: a unit slip rate at t_0 in
    // every mode; after the j-th push history()[q] is the lag-j kernel.
    std::vector<std::complex<double>> impulse(n_modes, 1.0), zero(n_modes, 0.0);
    for (std::size_t j = 1; j <= longest; ++j) {
      strip.push(j == 1 ? impulse : zero);
      const auto h = strip.history();
      for (int q = 1; q < n_modes; ++q)
        if (j <= window_[q])
          weight_[first_sample_[q] + j - 1] = h[q].real() - integrator_weight_[q];
    }
    // Optional smooth taper of the last part of each window: the truncation
    // jump at W_q rings in frequency (sidelobes near the branch points c_s k,
    // c_d k); a cos^2 ramp spreads it.
    if (taper_fraction > 0.0) {
      for (int q = 1; q < n_modes; ++q) {
        const std::size_t W = window_[q];
        const auto ramp = static_cast<std::size_t>(std::floor(taper_fraction * W));
        for (std::size_t j = W - ramp + 1; j <= W && ramp > 0; ++j) {
          const double u = static_cast<double>(j - (W - ramp)) / static_cast<double>(ramp + 1);
          const double c = std::cos(0.5 * std::numbers::pi * u);
          weight_[first_sample_[q] + j - 1] *= c * c;
        }
      }
    }
  }

  rate_buffer_.assign(first_sample_.back(), 0.0);
  newest_.assign(n_modes, 0);
  running_sum_.assign(n_modes, 0.0);
  history_.assign(n_modes, 0.0);
  memory_bytes_ = sizeof(std::size_t) * (window_.size() + first_sample_.size() + newest_.size()) +
                  sizeof(double) * (integrator_weight_.size() + weight_.size()) +
                  sizeof(std::complex<double>) *
                      (rate_buffer_.size() + running_sum_.size() + history_.size());
}

std::span<const double> HalfSpaceHistory::window_weights(int q) const {
  const auto i = static_cast<std::size_t>(q);
  return std::span<const double>(weight_).subspan(first_sample_.at(i), window_.at(i));
}

void HalfSpaceHistory::push(std::span<const std::complex<double>> slip_rate_spectrum) {
  const int n_modes = static_cast<int>(history_.size());
  // history_0 = 0 always (no memory in the uniform mode of a half-space).
#pragma omp parallel for schedule(dynamic, 8)
  for (int q = 1; q < n_modes; ++q) {
    const std::complex<double> v = slip_rate_spectrum[q];
    const std::size_t W = window_[q];
    const std::size_t base = first_sample_[q];
    // Slot of v_n: one after the previous newest, wrapping.
    std::size_t c = newest_[q] + 1;
    if (c == W) c = 0;
    newest_[q] = c;
    std::complex<double>* buf = rate_buffer_.data() + base;
    const double* w = weight_.data() + base;
    buf[c] = v;
    // history_{n+1} window part: sum_{j=1}^{W} w_j v_{n+1-j}; v_{n+1-j} sits in
    // slot c - (j - 1) (mod W).  Two contiguous runs, no modulo in the loop.
    double acc_r = 0.0, acc_i = 0.0;
    for (std::size_t s = 0; s <= c; ++s) {
      const double wj = w[c - s];  // j - 1 = c - s
      acc_r += wj * buf[s].real();
      acc_i += wj * buf[s].imag();
    }
    for (std::size_t s = c + 1; s < W; ++s) {
      const double wj = w[c + W - s];  // j - 1 = c - s + W
      acc_r += wj * buf[s].real();
      acc_i += wj * buf[s].imag();
    }
    running_sum_[q] += v;
    history_[q] = integrator_weight_[q] * running_sum_[q] + std::complex<double>(acc_r, acc_i);
  }
}

}  // namespace slipstrip
