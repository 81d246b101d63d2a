// interface.law = "rate_and_state": the paper's friction (Eq. S1, S2) with
// parameters per node.  The initial state is steady sliding at v0 at every
// node with that node's parameters (phi = phi_ss,i(v0), tau_0,i = strength_i),
// plus the [initial] perturbations; every step solves the local friction law
// at all nodes with the batch predictor-corrector (friction/batch_solve.hpp).
#include <algorithm>
#include <cmath>
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

namespace slipstrip {
namespace {

class RateAndStateLaw final : public InterfaceLaw {
 public:
  explicit RateAndStateLaw(const InterfaceSetup& setup)
      : config_(setup.config), eta_(setup.eta),
        driving_velocity_(setup.config.loading.driving_velocity),
        normal_stress_slip_(setup.config.interface.normal_stress_slip > 0.0
                                ? setup.config.interface.normal_stress_slip
                                : setup.config.friction.characteristic_slip),
        tau_history_(setup.x.size(), 0.0), reference_(setup.x.size(), 0.0) {
    const auto n = setup.x.size();
    const auto& f = config_.friction;
    const double sigma = config_.loading.normal_stress;
    const double v0 = driving_velocity_;
    // Uniform parameters: one steady state for every node, computed once (the
    // same bits at every node); per-node spans stay empty, so the batch solve
    // takes its uniform path.
    if (config_.friction_along_x.any()) {
      nodes_ = resolve_friction_nodes(f, config_.friction_along_x, n,
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
  }

  double driving_velocity() const override { return driving_velocity_; }
  std::span<const double> reference_shear_stress() const override { return reference_; }

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
    const bool pulse = in.load_pulse_amplitude != 0.0;
#pragma omp parallel for schedule(static) if (pulse)
    for (int i = 0; i < n; ++i)
      tau_history_[i] = reference_[i] + drive - fields.history_stress[i] +
                        imposed_stress(in, in.load_pulse_amplitude, length, fields.x[i], t_load);
    if (!fields.normal_stress.empty()) {
      solve_with_normal_stress(fields, dt, initial);
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

  // In-plane dissimilar bodies: sigma varies, and the friction sees
  // sigma_eff, which relaxes towards it (Prakash & Clifton 1993; Cochard &
  // Rice 2000; docs/bodies.md).  Node by node with the scalar routines (the
  // batch ones take one sigma for all nodes): the predictor-corrector of
  // friction/normal_stress_response.hpp.  Where the faces are open (sigma = 0
  // exactly, Simulation's contact step) the shear traction is zero instead of
  // the friction.
  void solve_with_normal_stress(InterfaceFields& fields, double dt, bool initial) {
    const LocalSolveParameters params{config_.friction, config_.loading.normal_stress, eta_, per_node_};
    const NormalStressMemory memory{config_.interface.normal_stress_time, normal_stress_slip_,
                                    config_.friction.v_star};
    const std::size_t n = fields.x.size();
    std::size_t i = 0;
    try {
      for (i = 0; i < n; ++i) {
        const FrictionParameters p = params.at(i);
        const double tau = tau_history_[i];
        if (initial) {
          fields.effective_normal_stress[i] = fields.normal_stress[i];
          fields.slip_rate[i] =
              solve_slip_rate(p, fields.normal_stress[i], eta_, tau, fields.state[i], driving_velocity_);
          continue;
        }
        const NormalStressNodeStep s = normal_stress_node_step(
            p, memory, eta_, tau, fields.previous_slip_rate[i], fields.previous_state[i],
            fields.previous_normal_stress[i], fields.normal_stress[i], fields.effective_normal_stress[i], dt);
        fields.state[i] = s.state;
        fields.effective_normal_stress[i] = s.effective_normal_stress;
        fields.slip_rate[i] = s.slip_rate;
      }
    } catch (const LocalSolveFailure& e) {
      throw InterfaceFailure("local friction solve failed", i, e.what());
    } catch (const std::invalid_argument& e) {
      throw InterfaceFailure("state update failed", i, e.what());
    }
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
  std::vector<double> reference_;    // tau_0 per node [Pa]
};

}  // namespace

std::unique_ptr<InterfaceLaw> make_rate_and_state_law(const InterfaceSetup& setup) {
  return std::make_unique<RateAndStateLaw>(setup);
}

}  // namespace slipstrip
