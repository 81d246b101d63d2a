#pragma once
// Bounded-memory history operator for the half-space (strip_height = inf),
// per Fourier mode q of the interface (standard spectral-BIM truncation, cf.
// Lapusta et al. 2000).  Same convention as StripHistory:
//
//   tau^_q(t_n) = load - eta v^_q(t_n) - history_q(t_n),        eta = mu / (2 c_s),
//   history_q(t_n) = dt S_static(k) sum_{j>=1} v_{n-j}          (running sum: the static stiffness)
//                  + sum_{j=1}^{W_q} w_{q,j} v_{n-j}            (windowed, decaying part)
//
// with S_static(k) = mu k (1 - c_s^2/c_d^2).  The half-space kernel on slip rate
// tends to S_static like (k c_s t)^{-3/2} (oscillating), so the remainder
// w_{q,j} is dropped after W_q = min(ceil(tau_cut / (k c_s dt)), max_window)
// steps, optionally with a smooth taper over the last taper_fraction of the
// window.  The samples w_{q,j} are the discrete impulse response of a
// StripHistory of virtual height Hv, chosen so that its first reflection
// (2 Hv / c_d) comes after the longest window: inside the window they are the
// verified strip operator's to round-off.  The uniform mode q = 0 has no
// memory at all for a half-space (S_inf(0, s) = eta s): history_0 = 0.
//
// Memory and cost per step (sum_q W_q) are fixed at construction and do not
// grow with simulated time.
#include <complex>
#include <cstddef>
#include <span>
#include <vector>

#include "kernels/elastic_material.hpp"

namespace slipstrip {

class HalfSpaceHistory {
 public:
  // length: period of the interface [m]; nodes: grid points (modes q = 0..nodes/2);
  // time_step [s]; tau_cut: window in units of 1/(k c_s) (> 0); max_window: cap on
  // W_q in steps (>= 1); taper_fraction in [0, 1): the last part of each window
  // over which the kept kernel is brought smoothly (cos^2) to zero.
  HalfSpaceHistory(const ElasticMaterial& material, double length, int nodes, double time_step,
                   double tau_cut, std::size_t max_window, double taper_fraction = 0.0);

  double time_step() const { return dt_; }
  double radiation_damping() const { return eta_; }
  int modes() const { return static_cast<int>(window_.size()); }
  // W_q in steps (0 for q = 0).
  std::size_t window(int q) const { return window_.at(static_cast<std::size_t>(q)); }
  // Height of the virtual strip whose impulse response supplied the samples.
  double virtual_height() const { return virtual_height_; }
  // Kept samples w_{q,j}, j = 1..W_q (after the taper), in Pa s/m.
  std::span<const double> window_weights(int q) const;
  // Coefficients + state, fixed at construction.
  std::size_t memory_bytes() const { return memory_bytes_; }

  // Feed the slip-rate perturbation spectrum at the newest level t_n; afterwards
  // history() holds history_q(t_{n+1}).  No allocation.
  void push(std::span<const std::complex<double>> slip_rate_spectrum);
  std::span<const std::complex<double>> history() const { return history_; }

 private:
  double dt_;
  double eta_;
  double virtual_height_ = 0.0;
  std::vector<std::size_t> window_;        // W_q
  std::vector<std::size_t> first_sample_;  // offsets into weight_ / rate_buffer_, size modes+1
  std::vector<double> integrator_weight_;  // dt S_static(k_q)
  std::vector<double> weight_;             // w_{q,j}, j = 1..W_q, contiguous per q
  // State.
  std::vector<std::complex<double>> rate_buffer_;  // per q: circular, last W_q slip rates
  std::vector<std::size_t> newest_;                // per q: slot of v_{n}
  std::vector<std::complex<double>> running_sum_;
  std::vector<std::complex<double>> history_;
  std::size_t memory_bytes_ = 0;
};

}  // namespace slipstrip
