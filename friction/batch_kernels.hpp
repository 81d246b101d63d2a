#pragma once
// The vectorised batch routines, compiled once per instruction set
// (simd/instruction_set.hpp).
//
// friction/batch_kernels.inc holds the vector code.  It is compiled into the
// binary several times: with the build's own flags ("baseline": SSE2 in a
// portable x86-64 build) and, on x86-64, with AVX2 + FMA and with AVX-512
// switched on for that file only (friction/batch_kernels_<set>.cpp).  The
// routines of batch_solve.hpp go through batch_kernels(), the copy for
// simd::instruction_set().
#include <cstddef>
#include <span>

#include "friction/batch_solve.hpp"
#include "simd/instruction_set.hpp"

namespace slipstrip {

// One compiled copy of the vector code.  Callers check the spans' sizes (all
// equal, per-node parameters empty or one per node) before calling.
struct BatchKernels {
  simd::InstructionSet set;
  std::size_t width;  // doubles per vector register (nodes solved at once)
  BatchCounts (*solve_slip_rate)(const LocalSolveParameters& params,
                                 std::span<const double> tau_history, std::span<const double> state,
                                 std::span<const double> initial_guess, std::span<double> slip_rate);
  void (*evolve_state)(const FrictionParameters& friction, std::span<const double> state,
                       std::span<const double> slip_rate, double dt, std::span<double> out);
  BatchCounts (*predictor_corrector)(const LocalSolveParameters& params, double dt,
                                     std::span<const double> tau_history,
                                     std::span<const double> slip_rate_old,
                                     std::span<const double> state_old,
                                     std::span<double> slip_rate_new, std::span<double> state_new);
  BatchCounts (*predictor_corrector_normal_stress)(const LocalSolveParameters& params,
                                                   const NormalStressMemory& response, double dt,
                                                   std::span<const double> tau_history,
                                                   std::span<const double> slip_rate_old,
                                                   std::span<const double> state_old,
                                                   const NormalStressStep& normal,
                                                   std::span<double> slip_rate_new,
                                                   std::span<double> state_new);
};

// The scalar routines at one node, for the nodes the vector code hands over;
// any failure is rethrown as BatchFailure(node, the scalar routine's message).
// Defined in batch_solve.cpp, with the build's own flags: the kernel files
// call them instead of building exceptions and strings themselves, so that
// they emit no copy of a shared inline function (a destructor, a string
// constructor) compiled for a wider instruction set, which the linker might
// keep for every caller (the test simd_kernel_objects checks this).
double solve_slip_rate_node(const LocalSolveParameters& params, std::size_t node, double tau_history,
                            double state, double initial_guess);
double evolve_state_node(const FrictionParameters& friction, std::size_t node, double state,
                         double slip_rate, double dt);
// The time loop's scalar predictor-corrector at one node:
//   phi_p = evolve(phi_old, v_old); v_p = solve(phi_p, guess v_old);
//   phi_new = evolve(phi_old, (v_old + v_p) / 2); v_new = solve(phi_new, guess v_p).
void predictor_corrector_node(const LocalSolveParameters& params, std::size_t node, double dt,
                              double tau_history, double slip_rate_old, double state_old,
                              double& slip_rate_new, double& state_new);
// predictor_corrector_normal_stress_node (batch_solve.hpp) at node `node` of
// the spans (its normal stresses from `normal`, sigma_eff written there).
void predictor_corrector_normal_stress_node(const LocalSolveParameters& params,
                                            const NormalStressMemory& response, std::size_t node,
                                            double dt, double tau_history, double slip_rate_old,
                                            double state_old, const NormalStressStep& normal,
                                            double& slip_rate_new, double& state_new);

// The copy compiled for `set` (throws std::invalid_argument when this build
// has none).  The caller makes sure the CPU can run it
// (simd::usable_instruction_sets()).
const BatchKernels& batch_kernels_for(simd::InstructionSet set);

// The copy the batch routines use: batch_kernels_for(simd::instruction_set()).
const BatchKernels& batch_kernels();

// The compiled copies (defined in batch_kernels_<name>.cpp; the AVX ones only
// in x86-64 builds).  Data only: the dispatcher reads them without running any
// code compiled for a wider instruction set than the CPU may have.
extern const BatchKernels kBaselineBatchKernels;
extern const BatchKernels kAvx2BatchKernels;
extern const BatchKernels kAvx512BatchKernels;

}  // namespace slipstrip
