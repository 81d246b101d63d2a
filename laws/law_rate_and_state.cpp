// interface.law = "rate_and_state": the paper's friction (Eq. S1, S2) with
// parameters per node.  The initial state is steady sliding at v0 at every
// node with that node's parameters (phi = phi_ss,i(v0), tau_0,i = strength_i),
// plus the [initial] perturbations; every step solves the local friction law
// at all nodes with the batch predictor-corrector (friction/batch_solve.hpp).
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

#include "laws/initial_state.hpp"
#include "laws/interface_law.hpp"
#include "laws/interface_pulse.hpp"
#include "config/simulation_config.hpp"
#include "friction/batch_solve.hpp"
#include "friction/friction_law.hpp"
#include "friction/normal_stress_response.hpp"
#include "friction/parameter_profile.hpp"
#include "simd/parallel_for.hpp"

namespace slipstrip {
namespace {

// loading.drive = "mean_slip_rate": |mean slip rate - v0| <= this times v0, and
// the most trials of the uniform shear stress per level (a bracket halves at
// least every other trial, so ~100 reach the rounding of a double from any
// finite bracket).
constexpr double kMeanSlipRateTolerance = 1e-9;
constexpr int kMeanSlipRateIterations = 200;

class RateAndStateLaw final : public InterfaceLaw {
 public:
  explicit RateAndStateLaw(const InterfaceSetup& setup)
      : config_(setup.config), eta_(setup.eta),
        driving_velocity_(setup.config.loading.driving_velocity),
        normal_stress_slip_(setup.config.interface.normal_stress_slip > 0.0
                                ? setup.config.interface.normal_stress_slip
                                : setup.config.friction.characteristic_slip),
        tau_history_(setup.x.size(), 0.0), previous_effective_(setup.x.size(), 0.0),
        reference_(setup.x.size(), 0.0) {
    // Simulation refuses the drive where it does not apply (dissimilar bodies).
    if (config_.loading.drive == LoadingDrive::mean_slip_rate) load_without_shift_.assign(setup.x.size(), 0.0);
    const auto n = setup.x.size();
    const auto& f = config_.friction;
    const double sigma = config_.loading.normal_stress;
    const double v0 = driving_velocity_;
    // Uniform parameters: one steady state for every node, computed once (the
    // same bits at every node); per-node spans stay empty, so the batch solve
    // takes its uniform path.
    if (config_.friction_profiles.any()) {
      nodes_ = resolve_friction_nodes(f, config_.friction_profiles, n,
                                      config_.geometry.length / static_cast<double>(n));
      per_node_ = {nodes_.f0, nodes_.a, nodes_.b, nodes_.characteristic_slip};
      phi_ss_.resize(n);
      for (std::size_t i = 0; i < n; ++i) {
        const FrictionParameters p = friction_at_node(f, nodes_, i);
        phi_ss_[i] = steady_state(p, v0);
        reference_[i] = frictional_strength(p, sigma, v0, phi_ss_[i]);
      }
    } else {
      const double phi_ss = steady_state(f, v0);
      phi_ss_.assign(n, phi_ss);
      std::fill(reference_.begin(), reference_.end(), frictional_strength(f, sigma, v0, phi_ss));
    }
    mean_reference_ = 0.0;
    for (double t : reference_) mean_reference_ += t;
    mean_reference_ /= static_cast<double>(n);
    loading_shear_stress_ = mean_reference_;
  }

  double driving_velocity() const override { return driving_velocity_; }
  std::span<const double> reference_shear_stress() const override { return reference_; }
  double loading_shear_stress() const override {
    return load_without_shift_.empty() ? InterfaceLaw::loading_shear_stress() : loading_shear_stress_;
  }

  void initialise(InterfaceFields& fields) override {
    const std::vector<double> phi =
        perturbed_steady_state(config_.initial, fields.x, config_.geometry.length, phi_ss_);
    std::copy(phi.begin(), phi.end(), fields.state.begin());
    // At t = 0 the history is empty: tau_0 + eta v0 - eta v = strength(v, phi).
    solve(fields, 0.0, 0.0, /*initial=*/true);
  }

  void advance(const InterfaceStep& step, InterfaceFields& fields) override {
    solve(fields, step.time + step.dt, step.dt, /*initial=*/false);
    integrate_slip(fields, step.dt);
  }

 private:
  // Second-order predictor-corrector on the state; the slip rate is always
  // the exact local solution at the new time level.  The batch routines
  // (friction/batch_solve.hpp) run the scheme over all nodes, vectorised, in an
  // OpenMP loop over fixed chunks of nodes.
  void solve(InterfaceFields& fields, double t_load, double dt, bool initial) {
    const LocalSolveParameters params{config_.friction, config_.loading.normal_stress, eta_,
                                      per_node_};
    const auto& in = config_.interface;
    const double length = config_.geometry.length;
    const double drive = eta_ * driving_velocity_;
    const int n = static_cast<int>(fields.x.size());
    // The loads: a few flops per node unless a load pulse is imposed (an exp
    // per node); only then is it worth a parallel region of its own.
    const auto load = [&](long long i) {
      tau_history_[i] = reference_[i] + drive - fields.history_stress[i] +
                        imposed_stress(in, in.load_pulse_amplitude, length, fields.x[i], t_load);
    };
    if (in.load_pulse_amplitude != 0.0) {
      simd::parallel_for(n, load);
    } else {
      for (int i = 0; i < n; ++i) load(i);
    }
    if (!fields.normal_stress.empty()) {
      solve_with_normal_stress(fields, dt, initial);
      return;
    }
    if (!load_without_shift_.empty()) {
      solve_mean_slip_rate(params, fields, dt, initial);
      return;
    }
    try {
      if (initial) {
        std::fill(fields.slip_rate.begin(), fields.slip_rate.end(), driving_velocity_);  // the guess
        solve_slip_rate_parallel(params, tau_history_, fields.state, fields.slip_rate,
                                 fields.slip_rate);
      } else {
        predictor_corrector_parallel(params, dt, tau_history_, fields.previous_slip_rate,
                                     fields.previous_state, fields.slip_rate, fields.state);
      }
    } catch (const BatchFailure& e) {
      throw InterfaceFailure("local friction solve failed", e.index, e.what());
    }
    for (int i = 0; i < n; ++i) fields.shear_stress[i] = tau_history_[i] - eta_ * fields.slip_rate[i];
  }

  // loading.drive = "mean_slip_rate" (docs/transition.md): the load of node i
  // is load_without_shift_[i] + s, with one uniform shift s of the shear
  // stress chosen so that the mean slip rate over the nodes is v0 at the level
  // solved for; tau_0 = mean(reference) + s.  Each node's slip rate is a
  // nondecreasing function of its load (the predictor-corrector's state
  // moves the same way: more slip, a younger contact, a weaker one), so the
  // mean is nondecreasing in s and the root is found by a scalar search around
  // the whole batch step: a first Newton step with the nodes' d v/d tau at
  // fixed state, then secant steps, each kept inside the bracket found so
  // far (bisection otherwise), with the bracket grown by doubling while one
  // side is missing.  Every trial recomputes the slip rate and the state from
  // the previous level; slip is integrated once, after.
  void solve_mean_slip_rate(const LocalSolveParameters& params, InterfaceFields& fields, double dt, bool initial) {
    const int n = static_cast<int>(fields.x.size());
    const double v0 = driving_velocity_;
    const double sigma = config_.loading.normal_stress;
    std::copy(tau_history_.begin(), tau_history_.end(), load_without_shift_.begin());
    // Mean slip rate minus v0 for the shift s; sets slip_rate and state.
    const auto residual = [&](double shift) {
      for (int i = 0; i < n; ++i) tau_history_[i] = load_without_shift_[i] + shift;
      try {
        if (initial)
          solve_slip_rate_parallel(params, tau_history_, fields.state, fields.slip_rate, fields.slip_rate);
        else
          predictor_corrector_parallel(params, dt, tau_history_, fields.previous_slip_rate, fields.previous_state,
                                       fields.slip_rate, fields.state);
      } catch (const BatchFailure& e) {
        throw InterfaceFailure("local friction solve failed", e.index, e.what());
      }
      double sum = 0.0;
      for (int i = 0; i < n; ++i) sum += fields.slip_rate[i];
      return sum / n - v0;
    };
    // d(mean v)/ds with every node's state held: sum of 1 / (eta + d strength/dv)
    // over the slipping nodes (a sticking node's slip rate stays 0 until its
    // load reaches its static strength).
    const auto slope = [&] {
      double sum = 0.0;
      for (int i = 0; i < n; ++i) {
        const double v = fields.slip_rate[i];
        if (v == 0.0) continue;
        const FrictionParameters p = params.at(static_cast<std::size_t>(i));
        sum += 1.0 / (eta_ + frictional_strength_dv(p, sigma, std::abs(v), fields.state[i]));
      }
      return sum / n;
    };
    if (initial) std::fill(fields.slip_rate.begin(), fields.slip_rate.end(), v0);  // the first guess
    // The first trial: the shift of the previous level, as its fields give it
    // (mean shear stress = tau_0 - eta (mean v - v0), the history having no
    // uniform part under this drive).  Computed from the fields, not kept, so
    // a restored Simulation takes the same trials as the one it was saved from.
    double shift = 0.0;
    if (!initial) {
      double stress = 0.0, rate = 0.0;
      for (int i = 0; i < n; ++i) {
        stress += fields.shear_stress[i];
        rate += fields.previous_slip_rate[i];
      }
      shift = stress / n + eta_ * (rate / n - v0) - mean_reference_;
    }
    // The mean's noise floor is the local solves' (each slip rate within 1e-12
    // relative, so the mean within ~1e-12 v0 when it is v0): the tolerance sits
    // three orders above it.
    const double tolerance = kMeanSlipRateTolerance * v0;
    double low = -std::numeric_limits<double>::infinity(), high = std::numeric_limits<double>::infinity();
    double previous_shift = 0.0, previous_residual = 0.0;
    // A first expansion step: the stress that changes a uniform slip rate by v0
    // through the radiation damping, or the direct effect sigma a.
    double expansion = eta_ * v0 + sigma * std::abs(config_.friction.a);
    if (!(expansion > 0.0)) expansion = eta_ * v0;
    double r = 0.0;
    int trials = 0;
    for (int iteration = 0; iteration < kMeanSlipRateIterations; ++iteration) {
      r = residual(shift);
      ++trials;
      if (!std::isfinite(r)) break;
      if (std::abs(r) <= tolerance) {
        loading_shear_stress_ = mean_reference_ + shift;
        for (int i = 0; i < n; ++i) fields.shear_stress[i] = tau_history_[i] - eta_ * fields.slip_rate[i];
        return;
      }
      (r < 0.0 ? low : high) = shift;
      // The bracket is down to rounding and the mean still misses v0: the
      // mean jumps there (it should not: each slip rate is continuous in its
      // load), a failure to report, not to accept.
      if (std::isfinite(low) && std::isfinite(high) &&
          high - low <= 4.0 * std::numeric_limits<double>::epsilon() * std::max(std::abs(low), std::abs(high)))
        break;
      double next = std::numeric_limits<double>::quiet_NaN();
      if (iteration > 0 && r != previous_residual) {
        next = shift - r * (shift - previous_shift) / (r - previous_residual);  // secant
      } else {
        const double d = slope();
        if (d > 0.0) next = shift - r / d;  // Newton with the held-state slope
      }
      previous_shift = shift;
      previous_residual = r;
      if (!(next > low && next < high)) {
        if (std::isfinite(low) && std::isfinite(high)) {
          next = 0.5 * (low + high);
        } else {
          next = r < 0.0 ? shift + expansion : shift - expansion;
          expansion *= 2.0;
        }
      }
      shift = next;
    }
    std::ostringstream msg;
    msg << "the mean slip rate is " << r + v0 << " m/s after " << trials
        << " trials of the uniform shear stress (last tau_0 = " << mean_reference_ + shift
        << " Pa, bracket [" << mean_reference_ + low << ", " << mean_reference_ + high
        << "] Pa), loading.driving_velocity = " << v0 << " m/s";
    throw InterfaceFailure("mean slip rate drive failed", InterfaceFailure::kWholeInterface, msg.str());
  }

  // In-plane dissimilar bodies: sigma varies, and the friction sees
  // sigma_eff, which relaxes towards it (Prakash & Clifton 1993; Cochard &
  // Rice 2000; docs/bodies.md §4), advanced like the state in the
  // predictor-corrector, with the optional Linker-Dieterich response (the
  // scheme of normal_stress_node_step, friction/normal_stress_response.hpp).
  // The batch routines solve all nodes vectorised with their own sigma_eff;
  // where the faces are open (sigma = 0 exactly, Simulation's contact step)
  // the shear traction is zero instead of the friction.
  void solve_with_normal_stress(InterfaceFields& fields, double dt, bool initial) {
    LocalSolveParameters params{config_.friction, config_.loading.normal_stress, eta_, per_node_};
    const NormalStressMemory memory{config_.interface.normal_stress_time, normal_stress_slip_,
                                    config_.friction.v_star};
    try {
      if (initial) {
        std::copy(fields.normal_stress.begin(), fields.normal_stress.end(),
                  fields.effective_normal_stress.begin());
        params.normal_stress_per_node = fields.normal_stress;
        std::fill(fields.slip_rate.begin(), fields.slip_rate.end(), driving_velocity_);  // the guess
        solve_slip_rate_parallel(params, tau_history_, fields.state, fields.slip_rate, fields.slip_rate);
      } else {
        // sigma_eff at t_n, kept while the step writes the new level in place.
        std::copy(fields.effective_normal_stress.begin(), fields.effective_normal_stress.end(),
                  previous_effective_.begin());
        const NormalStressStep normal{fields.previous_normal_stress, fields.normal_stress, previous_effective_,
                                      fields.effective_normal_stress};
        predictor_corrector_normal_stress_parallel(params, memory, dt, tau_history_, fields.previous_slip_rate,
                                                   fields.previous_state, normal, fields.slip_rate, fields.state);
      }
    } catch (const BatchFailure& e) {
      throw InterfaceFailure("local friction solve failed", e.index, e.what());
    }
    const std::size_t n = fields.x.size();
    for (std::size_t j = 0; j < n; ++j) fields.shear_stress[j] = tau_history_[j] - eta_ * fields.slip_rate[j];
  }

  SimulationConfig config_;  // a copy: the law must not depend on where Simulation keeps its own
  double eta_;
  double driving_velocity_;
  double normal_stress_slip_;  // L_sigma [m]
  FrictionNodeValues nodes_;   // per-node parameters (only with profiles)
  FrictionNodeSpans per_node_; // views of nodes_, or empty (uniform)
  std::vector<double> phi_ss_;
  std::vector<double> tau_history_;  // load on the local solve at the level solved for [Pa]
  std::vector<double> previous_effective_;  // sigma_eff at t_n during a step [Pa]
  std::vector<double> reference_;    // tau_0 per node [Pa]
  double mean_reference_ = 0.0;      // its mean over the nodes [Pa]
  // loading.drive = "mean_slip_rate" only (empty otherwise): the load before
  // the uniform shift, and tau_0 at the level last solved [Pa].
  std::vector<double> load_without_shift_;
  double loading_shear_stress_ = 0.0;
};

}  // namespace

std::unique_ptr<InterfaceLaw> make_rate_and_state_law(const InterfaceSetup& setup) {
  return std::make_unique<RateAndStateLaw>(setup);
}

}  // namespace slipstrip
