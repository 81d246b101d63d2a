#include "core/simulation.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <random>
#include <sstream>

#include "friction/batch_solve.hpp"
#include "friction/friction_law.hpp"
#include "kernels/block_strip_history.hpp"
#include "kernels/half_space_history.hpp"
#include "kernels/kernel_cache.hpp"

namespace slipstrip {
namespace {
constexpr double pi = std::numbers::pi;

// Both algorithms apply the same discrete operator (to ~1e-13,
// tests/cpp/test_kernels_block_history.cpp); the block one wins once a
// Fourier mode carries more than ~100 normal modes (bench_kernels_history:
// 1.8x faster at 150 modes per Fourier mode, 55x at 6000) but needs ~2-3x the
// memory, so below that the modal one is kept.
constexpr std::size_t block_history_threshold = 128;

std::unique_ptr<HistoryOperator> make_strip_history(const ElasticMaterial& material,
                                                    const StripKernels& kernels,
                                                    HistoryAlgorithm algorithm,
                                                    const CancelCheck& cancelled) {
  if (algorithm == HistoryAlgorithm::automatic) {
    std::size_t most = 0;
    for (std::size_t q = 0; q + 1 < kernels.first_oscillator.size(); ++q)
      most = std::max(most, kernels.first_oscillator[q + 1] - kernels.first_oscillator[q]);
    algorithm = most >= block_history_threshold ? HistoryAlgorithm::block : HistoryAlgorithm::modal;
  }
  if (algorithm == HistoryAlgorithm::block)
    return std::make_unique<BlockStripHistory>(material, kernels, BlockHistoryDesign{}, cancelled);
  return std::make_unique<StripHistory>(material, kernels, cancelled);
}
}

Simulation::Simulation(const SimulationConfig& config, const CancelCheck& cancelled)
    : config_(config), nodes_(config.geometry.nodes) {
  const auto& g = config_.geometry;
  dx_ = g.length / nodes_;
  dt_ = strip_time_step(config_.material, g.height, dx_, config_.time.beta);
  eta_ = config_.material.shear_modulus / (2.0 * config_.material.shear_wave_speed());
  fft_ = std::make_unique<RealFft>(nodes_);
  if (is_half_space(g.height)) {
    // Sampled exact half-space kernel, made passive, with bounded memory
    // (kernels/half_space_history.hpp, docs/theory.md "bounded-memory half-space").
    history_ = std::make_unique<HalfSpaceHistory>(config_.material, g.length, nodes_, dt_,
                                                  HalfSpaceOperatorDesign{}, cancelled);
  } else {
    const auto kernels =
        config_.output.kernel_cache.empty()
            ? compute_strip_kernels(config_.material, g.height, g.length, nodes_, dt_, cancelled)
            : load_or_compute_strip_kernels(config_.output.kernel_cache, config_.material,
                                            g.height, g.length, nodes_, dt_, nullptr, cancelled);
    history_ = make_strip_history(config_.material, kernels, config_.time.history, cancelled);
  }

  const auto n = static_cast<std::size_t>(nodes_);
  x_.resize(n);
  for (std::size_t i = 0; i < n; ++i) x_[i] = i * dx_;
  slip_.assign(n, 0.0);
  slip_rate_.assign(n, 0.0);
  state_.assign(n, 0.0);
  shear_stress_.assign(n, 0.0);
  previous_slip_rate_.assign(n, 0.0);
  previous_state_.assign(n, 0.0);
  history_stress_.assign(n, 0.0);
  tau_history_.assign(n, 0.0);
  work_real_.assign(n, 0.0);
  spectrum_.assign(n / 2 + 1, 0.0);

  const auto& in = config_.interface;
  switch (in.law) {
    case InterfaceLaw::rate_and_state: {
      const auto& f = config_.friction;
      driving_velocity_ = config_.loading.driving_velocity;
      const double phi_ss = steady_state(f, driving_velocity_);
      reference_shear_stress_ =
          frictional_strength(f, config_.loading.normal_stress, driving_velocity_, phi_ss);
      const auto& init = config_.initial;
      std::mt19937_64 rng(init.noise_seed);
      std::normal_distribution<double> normal(0.0, 1.0);
      for (std::size_t i = 0; i < n; ++i) {
        double phi = phi_ss;
        if (init.noise_amplitude != 0.0) phi += phi_ss * init.noise_amplitude * normal(rng);
        if (init.sine_amplitude != 0.0)
          phi += phi_ss * init.sine_amplitude *
                 std::sin(2.0 * pi * init.sine_mode * x_[i] / g.length + pi / 2.0);
        if (init.local_amplitude != 0.0 && init.local_width > 0.0) {
          // periodic distance to the perturbation centre
          double d = std::remainder(x_[i] - init.local_center, g.length);
          phi += phi_ss * init.local_amplitude *
                 std::exp(-0.5 * (d / init.local_width) * (d / init.local_width));
        }
        if (!(phi > 0.0))
          throw std::invalid_argument(
              "initial state phi <= 0 at x = " + std::to_string(x_[i]) +
              " m: reduce initial.noise_amplitude, initial.sine_amplitude or initial.local_amplitude");
        state_[i] = phi;
      }
      // At t = 0 the history is empty: tau_0 + eta v0 - eta v = strength(v, phi).
      for (std::size_t i = 0; i < n; ++i) history_stress_[i] = 0.0;
      solve_rate_and_state(/*initial=*/true);
      break;
    }
    case InterfaceLaw::prescribed_slip: {
      driving_velocity_ = 0.0;
      const double k = 2.0 * pi * in.mode / g.length;
      for (std::size_t i = 0; i < n; ++i) {
        slip_[i] = in.slip_amplitude * std::cos(k * x_[i]) * profile(0.0);
        slip_rate_[i] = in.slip_amplitude * std::cos(k * x_[i]) * profile_rate(0.0);
        shear_stress_[i] = -eta_ * slip_rate_[i];
      }
      break;
    }
    case InterfaceLaw::free: {
      driving_velocity_ = 0.0;
      for (std::size_t i = 0; i < n; ++i) {
        slip_rate_[i] = imposed_stress(x_[i], 0.0) / eta_;
        shear_stress_[i] = -eta_ * slip_rate_[i];
      }
      break;
    }
  }
  check_finite("initial fields");
}

double Simulation::profile(double t) const {
  const auto& in = config_.interface;
  const double T = in.rise_time;
  if (t <= 0.0) return 0.0;
  if (in.profile == TimeProfile::ramp) return t >= T ? 1.0 : 0.5 * (1.0 - std::cos(pi * t / T));
  if (t >= T) return 0.0;
  const double s = std::sin(pi * t / T);
  return s * s * s * s;
}

double Simulation::profile_rate(double t) const {
  const auto& in = config_.interface;
  const double T = in.rise_time;
  if (t <= 0.0 || t >= T) return 0.0;
  if (in.profile == TimeProfile::ramp) return 0.5 * pi / T * std::sin(pi * t / T);
  const double s = std::sin(pi * t / T), c = std::cos(pi * t / T);
  return 4.0 * s * s * s * c * pi / T;
}

double Simulation::imposed_stress(double x, double t) const {
  const auto& in = config_.interface;
  const double amplitude =
      in.law == InterfaceLaw::free ? in.stress_amplitude : in.load_pulse_amplitude;
  if (amplitude == 0.0) return 0.0;
  double shape = 1.0;
  if (std::isfinite(in.pulse_width) && in.pulse_width > 0.0) {
    const double d = std::remainder(x - in.pulse_center, config_.geometry.length);
    shape = std::exp(-0.5 * (d / in.pulse_width) * (d / in.pulse_width));
  }
  return amplitude * shape * profile(t);
}

void Simulation::solve_rate_and_state(bool initial) {
  // Second-order predictor-corrector on the state; the slip rate is always
  // the exact local solution at the new time level.  The batch routines
  // (friction/batch_solve.hpp) run the scheme over all nodes, vectorised, in an
  // OpenMP loop over fixed chunks of nodes.
  const LocalSolveParameters params{config_.friction, config_.loading.normal_stress, eta_};
  const double load = reference_shear_stress_ + eta_ * driving_velocity_;
  const double t_load = initial ? time_ : time_ + dt_;  // the level being solved for
  // The loads: a few flops per node unless a load pulse is imposed (an exp
  // per node); only then is it worth a parallel region of its own.
  const bool pulse = config_.interface.load_pulse_amplitude != 0.0;
#pragma omp parallel for schedule(static) if (pulse)
  for (int i = 0; i < nodes_; ++i)
    tau_history_[i] = load - history_stress_[i] + imposed_stress(x_[i], t_load);
  try {
    if (initial) {
      std::fill(slip_rate_.begin(), slip_rate_.end(), driving_velocity_);  // the initial guess
      solve_slip_rate_parallel(params, tau_history_, state_, slip_rate_, slip_rate_);
    } else {
      predictor_corrector_parallel(params, dt_, tau_history_, previous_slip_rate_,
                                   previous_state_, slip_rate_, state_);
    }
  } catch (const BatchFailure& e) {
    const std::size_t i = e.index;
    std::ostringstream msg;
    msg << "local friction solve failed at node " << i << " (x = " << x_[i]
        << " m), t = " << time_ << " s, step " << step_index_ << ": " << e.what();
    throw SimulationError(msg.str());
  }
  for (int i = 0; i < nodes_; ++i) shear_stress_[i] = tau_history_[i] - eta_ * slip_rate_[i];
}

void Simulation::step() {
  // 1. history stress at t_{n+1} from slip rates up to t_n.
  // The perturbation v - v0 is zero before t = 0 and may jump at t = 0+ (an
  // initial state perturbation changes v at once).  The trapezoidal rule over
  // the history puts weight 1/2 on that end point (equivalently: a delta of the
  // echo comb that lands on the jump samples its mean), so the first sample
  // enters the history at half weight.  Full weight costs an O(dt) error for
  // the whole run (tests/cpp/test_core_convergence.cpp).
  const double first_sample_weight = step_index_ == 0 ? 0.5 : 1.0;
  for (int i = 0; i < nodes_; ++i)
    work_real_[i] = first_sample_weight * (slip_rate_[i] - driving_velocity_);
  fft_->forward(work_real_, spectrum_);
  history_->push(spectrum_);
  fft_->inverse(history_->history(), history_stress_);

  std::copy(slip_rate_.begin(), slip_rate_.end(), previous_slip_rate_.begin());
  std::copy(state_.begin(), state_.end(), previous_state_.begin());
  const double t_new = time_ + dt_;

  // 2. interface law at t_{n+1}.
  const auto& in = config_.interface;
  switch (in.law) {
    case InterfaceLaw::rate_and_state:
      solve_rate_and_state(/*initial=*/false);
      break;
    case InterfaceLaw::prescribed_slip: {
      const double k = 2.0 * pi * in.mode / config_.geometry.length;
      const double g = profile(t_new), gdot = profile_rate(t_new);
      for (int i = 0; i < nodes_; ++i) {
        const double shape = in.slip_amplitude * std::cos(k * x_[i]);
        slip_rate_[i] = shape * gdot;
        shear_stress_[i] = -history_stress_[i] - eta_ * slip_rate_[i];
        slip_[i] = shape * g;
      }
      break;
    }
    case InterfaceLaw::free:
      for (int i = 0; i < nodes_; ++i) {
        slip_rate_[i] = (imposed_stress(x_[i], t_new) - history_stress_[i]) / eta_;
        shear_stress_[i] = -history_stress_[i] - eta_ * slip_rate_[i];
      }
      break;
  }
  if (in.law != InterfaceLaw::prescribed_slip)
    for (int i = 0; i < nodes_; ++i)
      slip_[i] += 0.5 * dt_ * (previous_slip_rate_[i] + slip_rate_[i]);
  time_ = t_new;
  ++step_index_;
  check_finite("interface fields");
}

void Simulation::check_finite(const char* what) const {
  for (int i = 0; i < nodes_; ++i) {
    if (!std::isfinite(slip_rate_[i]) || !std::isfinite(slip_[i]) ||
        !std::isfinite(shear_stress_[i]) || !std::isfinite(state_[i])) {
      std::ostringstream msg;
      msg << "non-finite " << what << " at node " << i << " (x = " << x_[i] << " m), t = "
          << time_ << " s, step " << step_index_ << ": slip = " << slip_[i]
          << " m, slip_rate = " << slip_rate_[i] << " m/s, state = " << state_[i]
          << " s, shear_stress = " << shear_stress_[i] << " Pa";
      throw SimulationError(msg.str());
    }
  }
}

double Simulation::max_slip_rate() const {
  return *std::max_element(slip_rate_.begin(), slip_rate_.end());
}
double Simulation::mean_slip() const {
  return std::accumulate(slip_.begin(), slip_.end(), 0.0) / nodes_;
}
double Simulation::mean_shear_stress() const {
  return std::accumulate(shear_stress_.begin(), shear_stress_.end(), 0.0) / nodes_;
}

}  // namespace slipstrip
