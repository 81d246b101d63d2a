// The batch routines of batch_solve.hpp: argument checks, the choice of the
// compiled vector code for this CPU (friction/batch_kernels.hpp), and the
// OpenMP loop over fixed chunks of nodes.  The vector code itself is in
// friction/batch_kernels.inc.  See docs/friction.md, "Batch solve".
#include "friction/batch_solve.hpp"

#include <algorithm>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "friction/batch_kernels.hpp"
#include "simd/parallel_for.hpp"

namespace slipstrip {

namespace {

void check_sizes(std::size_t n, std::initializer_list<std::size_t> sizes) {
  for (std::size_t s : sizes)
    if (s != n) throw std::invalid_argument("batch friction solve: spans of different lengths");
}

void check_per_node_sizes(const LocalSolveParameters& params, std::size_t n) {
  const auto& p = params.per_node;
  for (std::size_t s : {p.f0.size(), p.a.size(), p.b.size(), p.characteristic_slip.size(),
                        params.normal_stress_per_node.size()})
    if (s != 0 && s != n)
      throw std::invalid_argument(
          "batch friction solve: per-node parameters must be empty or one value per node");
}

}  // namespace

double solve_slip_rate_node(const LocalSolveParameters& params, std::size_t node, double tau_history,
                            double state, double initial_guess) {
  try {
    return solve_slip_rate(params.at(node), params.normal_stress_at(node), params.eta, tau_history, state,
                           initial_guess);
  } catch (const std::exception& e) {
    throw BatchFailure(node, e.what());
  }
}

double evolve_state_node(const FrictionParameters& friction, std::size_t node, double state,
                         double slip_rate, double dt) {
  try {
    return evolve_state(friction, state, slip_rate, dt);
  } catch (const std::exception& e) {
    throw BatchFailure(node, e.what());
  }
}

void predictor_corrector_node(const LocalSolveParameters& params, std::size_t node, double dt,
                              double tau, double v_old, double phi_old, double& v_new,
                              double& phi_new) {
  try {
    const FrictionParameters f = params.at(node);
    const double sigma = params.normal_stress_at(node);
    const double phi_pred = evolve_state(f, phi_old, v_old, dt);
    const double v_pred = solve_slip_rate(f, sigma, params.eta, tau, phi_pred, v_old);
    phi_new = evolve_state(f, phi_old, 0.5 * (v_old + v_pred), dt);
    v_new = solve_slip_rate(f, sigma, params.eta, tau, phi_new, v_pred);
  } catch (const std::exception& e) {
    throw BatchFailure(node, e.what());
  }
}

void predictor_corrector_normal_stress_node(const FrictionParameters& p, double eta,
                                            const NormalStressMemory& response, double dt, double tau,
                                            double v_old, double phi_old, double s_old, double s_new,
                                            double e_old, double& v_new, double& phi_new, double& e_new) {
  // The scheme of normal_stress_node_step (friction/normal_stress_response.hpp),
  // shared with the 2D interface's friction.
  const NormalStressNodeStep step =
      normal_stress_node_step(p, response, eta, tau, v_old, phi_old, s_old, s_new, e_old, dt);
  v_new = step.slip_rate;
  phi_new = step.state;
  e_new = step.effective_normal_stress;
}

void predictor_corrector_normal_stress_node(const LocalSolveParameters& params,
                                            const NormalStressMemory& response, std::size_t node,
                                            double dt, double tau, double v_old, double phi_old,
                                            const NormalStressStep& normal, double& v_new, double& phi_new) {
  try {
    predictor_corrector_normal_stress_node(params.at(node), params.eta, response, dt, tau, v_old, phi_old,
                                           normal.sigma_old[node], normal.sigma_new[node],
                                           normal.effective_old[node], v_new, phi_new,
                                           normal.effective_new[node]);
  } catch (const std::exception& e) {
    throw BatchFailure(node, e.what());
  }
}

const BatchKernels& batch_kernels_for(simd::InstructionSet set) {
  switch (set) {
    case simd::InstructionSet::baseline:
      return kBaselineBatchKernels;
#if SLIPSTRIP_X86_DISPATCH
    case simd::InstructionSet::avx2:
      return kAvx2BatchKernels;
    case simd::InstructionSet::avx512:
      return kAvx512BatchKernels;
#endif
    default:
      break;
  }
  throw std::invalid_argument("batch friction solve: no kernels for the instruction set " +
                              std::string(simd::to_string(set)) + " in this build");
}

const BatchKernels& batch_kernels() { return batch_kernels_for(simd::instruction_set()); }

std::size_t batch_width() { return batch_kernels().width; }

LocalSolveParameters LocalSolveParameters::slice(std::size_t begin, std::size_t count) const {
  LocalSolveParameters out = *this;
  const auto cut = [&](std::span<const double>& s) {
    if (!s.empty()) s = s.subspan(begin, count);
  };
  cut(out.per_node.f0);
  cut(out.per_node.a);
  cut(out.per_node.b);
  cut(out.per_node.characteristic_slip);
  cut(out.normal_stress_per_node);
  return out;
}

FrictionParameters LocalSolveParameters::at(std::size_t i) const {
  FrictionParameters p = friction;
  if (!per_node.f0.empty()) p.f0 = per_node.f0[i];
  if (!per_node.a.empty()) p.a = per_node.a[i];
  if (!per_node.b.empty()) p.b = per_node.b[i];
  if (!per_node.characteristic_slip.empty()) p.characteristic_slip = per_node.characteristic_slip[i];
  return p;
}

BatchCounts solve_slip_rate_batch(const LocalSolveParameters& params,
                                  std::span<const double> tau_history, std::span<const double> state,
                                  std::span<const double> initial_guess, std::span<double> slip_rate) {
  const std::size_t n = tau_history.size();
  check_sizes(n, {state.size(), initial_guess.size(), slip_rate.size()});
  check_per_node_sizes(params, n);
  return batch_kernels().solve_slip_rate(params, tau_history, state, initial_guess, slip_rate);
}

void evolve_state_batch(const FrictionParameters& friction, std::span<const double> state,
                        std::span<const double> slip_rate, double dt, std::span<double> out) {
  check_sizes(state.size(), {slip_rate.size(), out.size()});
  batch_kernels().evolve_state(friction, state, slip_rate, dt, out);
}

BatchCounts predictor_corrector_batch(const LocalSolveParameters& params, double dt,
                                      std::span<const double> tau_history,
                                      std::span<const double> slip_rate_old,
                                      std::span<const double> state_old,
                                      std::span<double> slip_rate_new,
                                      std::span<double> state_new) {
  const std::size_t n = tau_history.size();
  check_sizes(n, {slip_rate_old.size(), state_old.size(), slip_rate_new.size(), state_new.size()});
  check_per_node_sizes(params, n);
  return batch_kernels().predictor_corrector(params, dt, tau_history, slip_rate_old, state_old,
                                             slip_rate_new, state_new);
}

namespace {

// The inputs of a step with a per-node normal stress: the fields, the four
// normal stresses and the per-node parameters all have n values (checked in
// this order; std::invalid_argument otherwise).
void check_normal_stress_inputs(const LocalSolveParameters& params, std::size_t n,
                                std::span<const double> slip_rate_old, std::span<const double> state_old,
                                const NormalStressStep& normal, std::span<const double> slip_rate_new,
                                std::span<const double> state_new) {
  check_sizes(n, {slip_rate_old.size(), state_old.size(), slip_rate_new.size(), state_new.size()});
  check_sizes(n, {normal.sigma_old.size(), normal.sigma_new.size(), normal.effective_old.size(),
                  normal.effective_new.size()});
  check_per_node_sizes(params, n);
}

NormalStressStep slice(const NormalStressStep& normal, std::size_t begin, std::size_t count) {
  return {normal.sigma_old.subspan(begin, count), normal.sigma_new.subspan(begin, count),
          normal.effective_old.subspan(begin, count), normal.effective_new.subspan(begin, count)};
}

}  // namespace

BatchCounts predictor_corrector_normal_stress_batch(const LocalSolveParameters& params,
                                                    const NormalStressMemory& response, double dt,
                                                    std::span<const double> tau_history,
                                                    std::span<const double> slip_rate_old,
                                                    std::span<const double> state_old,
                                                    const NormalStressStep& normal,
                                                    std::span<double> slip_rate_new,
                                                    std::span<double> state_new) {
  const std::size_t n = tau_history.size();
  check_normal_stress_inputs(params, n, slip_rate_old, state_old, normal, slip_rate_new, state_new);
  return batch_kernels().predictor_corrector_normal_stress(params, response, dt, tau_history, slip_rate_old,
                                                           state_old, normal, slip_rate_new, state_new);
}

namespace {

// Nodes per parallel work item (a multiple of every kernel width): small enough
// that two threads share even a 256-node interface, large enough to amortise
// the call.
constexpr std::size_t kChunk = 64;

// Runs body(begin, count) over fixed chunks of kChunk nodes on the OpenMP
// threads (simd::parallel_for); rethrows the BatchFailure with the lowest node
// index.  The counts are integers: their sum does not depend on the order.
template <class Body>
BatchCounts parallel_chunks(std::size_t n, Body&& body) {
  const long long chunks = static_cast<long long>((n + kChunk - 1) / kChunk);
  BatchCounts total;
  long long solves = 0, evaluations = 0, scalar_nodes = 0;
  std::optional<BatchFailure> failure;
  simd::parallel_for(chunks, [&](long long k) {
    const std::size_t begin = static_cast<std::size_t>(k) * kChunk;
    const std::size_t count = std::min(kChunk, n - begin);
    try {
      const BatchCounts c = body(begin, count);
#pragma omp atomic
      solves += c.solves;
#pragma omp atomic
      evaluations += c.evaluations;
#pragma omp atomic
      scalar_nodes += c.scalar_nodes;
    } catch (const BatchFailure& e) {
#pragma omp critical(slipstrip_batch_failure)
      if (!failure || begin + e.index < failure->index) failure.emplace(begin + e.index, e.what());
    } catch (const std::exception& e) {
#pragma omp critical(slipstrip_batch_failure)
      if (!failure || begin < failure->index) failure.emplace(begin, e.what());
    }
  });
  if (failure) throw *failure;
  total.solves = solves;
  total.evaluations = evaluations;
  total.scalar_nodes = scalar_nodes;
  return total;
}

}  // namespace

BatchCounts predictor_corrector_parallel(const LocalSolveParameters& params, double dt,
                                         std::span<const double> tau_history,
                                         std::span<const double> slip_rate_old,
                                         std::span<const double> state_old,
                                         std::span<double> slip_rate_new,
                                         std::span<double> state_new) {
  const std::size_t n = tau_history.size();
  check_sizes(n, {slip_rate_old.size(), state_old.size(), slip_rate_new.size(), state_new.size()});
  check_per_node_sizes(params, n);  // before slicing them
  return parallel_chunks(n, [&](std::size_t begin, std::size_t count) {
    return predictor_corrector_batch(params.slice(begin, count), dt,
                                     tau_history.subspan(begin, count),
                                     slip_rate_old.subspan(begin, count),
                                     state_old.subspan(begin, count),
                                     slip_rate_new.subspan(begin, count),
                                     state_new.subspan(begin, count));
  });
}

BatchCounts predictor_corrector_normal_stress_parallel(const LocalSolveParameters& params,
                                                       const NormalStressMemory& response, double dt,
                                                       std::span<const double> tau_history,
                                                       std::span<const double> slip_rate_old,
                                                       std::span<const double> state_old,
                                                       const NormalStressStep& normal,
                                                       std::span<double> slip_rate_new,
                                                       std::span<double> state_new) {
  const std::size_t n = tau_history.size();
  // Every input, before the chunks slice them.
  check_normal_stress_inputs(params, n, slip_rate_old, state_old, normal, slip_rate_new, state_new);
  return parallel_chunks(n, [&](std::size_t begin, std::size_t count) {
    return predictor_corrector_normal_stress_batch(
        params.slice(begin, count), response, dt, tau_history.subspan(begin, count),
        slip_rate_old.subspan(begin, count), state_old.subspan(begin, count), slice(normal, begin, count),
        slip_rate_new.subspan(begin, count), state_new.subspan(begin, count));
  });
}

BatchCounts solve_slip_rate_parallel(const LocalSolveParameters& params,
                                     std::span<const double> tau_history,
                                     std::span<const double> state,
                                     std::span<const double> initial_guess,
                                     std::span<double> slip_rate) {
  const std::size_t n = tau_history.size();
  check_sizes(n, {state.size(), initial_guess.size(), slip_rate.size()});
  check_per_node_sizes(params, n);  // before slicing them
  return parallel_chunks(n, [&](std::size_t begin, std::size_t count) {
    return solve_slip_rate_batch(params.slice(begin, count), tau_history.subspan(begin, count),
                                 state.subspan(begin, count), initial_guess.subspan(begin, count),
                                 slip_rate.subspan(begin, count));
  });
}

}  // namespace slipstrip
