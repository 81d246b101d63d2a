#pragma once
// Batch (structure-of-arrays, vectorised) versions of the local interface
// solve and the exact state update, and the predictor-corrector step of the
// time loop built on them.  Same equations, same guarantees and the same
// failures as the scalar solve_slip_rate / evolve_state (friction_law.hpp):
// see docs/friction.md, "Batch solve".
#include <cstddef>
#include <span>
#include <stdexcept>
#include <string>

#include "friction/friction_law.hpp"
#include "friction/normal_stress_response.hpp"

namespace slipstrip {

// Friction parameters that differ from node to node (tandem-style: the law is
// parameterised per node).  Each span is either empty -- every node uses the
// scalar of LocalSolveParameters::friction -- or holds one value per node,
// aligned with the field spans passed to the batch routines.
struct FrictionNodeSpans {
  std::span<const double> f0, a, b, characteristic_slip;
};

// Everything the batch loops read besides the per-node fields: the scalars
// every node shares, and the per-node parameters (if any).  With all spans
// empty and with spans holding the scalar at every node, the results are the
// same bit for bit (each lane computes from the same values either way).
struct LocalSolveParameters {
  LocalSolveParameters(const FrictionParameters& friction_, double normal_stress_, double eta_,
                       FrictionNodeSpans per_node_ = {})
      : friction(friction_), normal_stress(normal_stress_), eta(eta_), per_node(per_node_) {}

  FrictionParameters friction;  // strength and state law, v*, phi*; f0, a, b, D unless per node
  double normal_stress = 0.0;  // sigma0 [Pa], > 0, unless per node
  double eta = 0.0;            // radiation damping mu / (2 c_s) [Pa s/m], > 0
  FrictionNodeSpans per_node;
  // The normal stress the friction sees at each node [Pa] (in-plane pairs of
  // different bodies), or empty: normal_stress at every node.  Nodes where it
  // is not finite and > 0 go to the scalar routines (which report them).
  std::span<const double> normal_stress_per_node = {};

  // The same parameters for nodes [begin, begin + count) of the spans.
  LocalSolveParameters slice(std::size_t begin, std::size_t count) const;
  // Node i's parameters for the scalar routines.
  FrictionParameters at(std::size_t i) const;
  // Node i's normal stress [Pa].
  double normal_stress_at(std::size_t i) const {
    return normal_stress_per_node.empty() ? normal_stress : normal_stress_per_node[i];
  }
};

// A failed node in a batch: `index` is the node's position in the spans passed
// in; what() is exactly the scalar routine's message (LocalSolveFailure or the
// std::invalid_argument of evolve_state) for that node's inputs.
struct BatchFailure : std::runtime_error {
  BatchFailure(std::size_t node_index, const std::string& message)
      : std::runtime_error(message), index(node_index) {}
  std::size_t index;
};

// Work counts, for benchmarks and tests.
struct BatchCounts {
  long long solves = 0;       // local solves attempted (sticking included)
  long long evaluations = 0;  // residual evaluations in the vector path
  long long scalar_nodes = 0; // nodes handed to the scalar routines (see docs)
  BatchCounts& operator+=(const BatchCounts& o) {
    solves += o.solves;
    evaluations += o.evaluations;
    scalar_nodes += o.scalar_nodes;
    return *this;
  }
};

// Number of nodes the vector code processes at once with the instruction set
// chosen for this CPU (simd/instruction_set.hpp): 8 with AVX-512, 4 with
// AVX2, 2 with SSE2.
std::size_t batch_width();

// slip_rate[i] = solve_slip_rate(friction, sigma0, eta, tau_history[i], state[i],
// initial_guess[i]) to within that solve's tolerance (each result is within
// 1e-12 relative of the root, or at the residual's round-off floor); sticking
// gives exactly 0.0 with the same decision as the scalar solve.  All spans have
// the same length; slip_rate may alias initial_guess.  Throws BatchFailure.
BatchCounts solve_slip_rate_batch(const LocalSolveParameters& params,
                                  std::span<const double> tau_history, std::span<const double> state,
                                  std::span<const double> initial_guess, std::span<double> slip_rate);

// out[i] = evolve_state(friction, state[i], slip_rate[i], dt) (to a few ulp).
// out may alias state.  Throws BatchFailure for invalid input.
void evolve_state_batch(const FrictionParameters& friction, std::span<const double> state,
                        std::span<const double> slip_rate, double dt, std::span<double> out);

// One second-order predictor-corrector step at every node, the scheme of
// Simulation::step:
//   phi_p   = evolve_state(phi_old, v_old, dt)
//   v_p     = solve_slip_rate(tau_history, phi_p, guess v_old)
//   phi_new = evolve_state(phi_old, (v_old + v_p) / 2, dt)
//   v_new   = solve_slip_rate(tau_history, phi_new, guess v_p)
// The corrector's Newton iteration starts from the predictor's last residual
// evaluation moved by the change of the state (one Newton step for free), so a
// smooth history usually needs one evaluation per solve.  Outputs must not
// alias inputs.  Single-threaded; see predictor_corrector_parallel.
BatchCounts predictor_corrector_batch(const LocalSolveParameters& params, double dt,
                                      std::span<const double> tau_history,
                                      std::span<const double> slip_rate_old,
                                      std::span<const double> state_old,
                                      std::span<double> slip_rate_new,
                                      std::span<double> state_new);

// The same over all nodes with an OpenMP parallel loop over fixed chunks of
// nodes (results do not depend on the thread count).  On failure throws the
// BatchFailure of the lowest failing node index (deterministic).
BatchCounts predictor_corrector_parallel(const LocalSolveParameters& params, double dt,
                                         std::span<const double> tau_history,
                                         std::span<const double> slip_rate_old,
                                         std::span<const double> state_old,
                                         std::span<double> slip_rate_new,
                                         std::span<double> state_new);

// The normal stress over a step at every node, for the step below: sigma at
// t_n and t_{n+1} (compressive; exactly 0 where the faces are open at t_{n+1},
// docs/bodies.md §4), sigma_eff at t_n, and sigma_eff at t_{n+1} (set).
struct NormalStressStep {
  std::span<const double> sigma_old, sigma_new, effective_old;
  std::span<double> effective_new;
};

// The predictor-corrector step with a normal stress that varies from node to
// node and in time, sigma_eff advanced like the state (the scheme of
// predictor_corrector_normal_stress_node below; params.normal_stress and
// params.normal_stress_per_node are not used: sigma_eff is the normal stress):
//   e_p = relax(e_old, v_old); phi_p = evolve_LD(phi_old, v_old, e_old -> e_p);
//   v_p = solve(sigma = e_p, phi_p, guess v_old);
//   e = relax(e_old, (v_old + v_p)/2); phi = evolve_LD(phi_old, (v_old + v_p)/2, e_old -> e);
//   v = solve(sigma = e, phi, guess v_p).
// Nodes whose faces are open (sigma_new = 0) get the slip rate of zero shear
// traction, v = tau_history / eta, from the scalar routine.  The corrector
// starts from the predictor's last evaluation moved by the change of state
// and of sigma_eff (one Newton step for free), as predictor_corrector_batch.
// Outputs must not alias inputs.  Throws BatchFailure.
BatchCounts predictor_corrector_normal_stress_batch(const LocalSolveParameters& params,
                                                    const NormalStressMemory& response, double dt,
                                                    std::span<const double> tau_history,
                                                    std::span<const double> slip_rate_old,
                                                    std::span<const double> state_old,
                                                    const NormalStressStep& normal,
                                                    std::span<double> slip_rate_new,
                                                    std::span<double> state_new);

// The same over all nodes with the parallel loop of predictor_corrector_parallel.
BatchCounts predictor_corrector_normal_stress_parallel(const LocalSolveParameters& params,
                                                       const NormalStressMemory& response, double dt,
                                                       std::span<const double> tau_history,
                                                       std::span<const double> slip_rate_old,
                                                       std::span<const double> state_old,
                                                       const NormalStressStep& normal,
                                                       std::span<double> slip_rate_new,
                                                       std::span<double> state_new);

// The scheme above at node i with the scalar routines (the reference of the
// batch step and its fallback); failures as std::invalid_argument (state
// update) or LocalSolveFailure (solve), not wrapped.
void predictor_corrector_normal_stress_node(const FrictionParameters& friction, double eta,
                                            const NormalStressMemory& response, double dt,
                                            double tau_history, double slip_rate_old, double state_old,
                                            double sigma_old, double sigma_new, double effective_old,
                                            double& slip_rate_new, double& state_new,
                                            double& effective_new);

// solve_slip_rate_batch over all nodes with the same parallel loop.
BatchCounts solve_slip_rate_parallel(const LocalSolveParameters& params,
                                     std::span<const double> tau_history,
                                     std::span<const double> state,
                                     std::span<const double> initial_guess,
                                     std::span<double> slip_rate);

}  // namespace slipstrip
