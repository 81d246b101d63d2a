#pragma once
// The design of the bounded-memory half-space operator (kernels/half_space_history.hpp):
// its fixed constants, and per Fourier mode the terms of its discrete kernel
// -- static weight, stored lag weights with the passivity correction, fast
// and slow exponentials -- before HalfSpaceHistory lays them out for the
// time loop.  docs/theory.md, "bounded-memory half-space".
#include <complex>
#include <cstddef>
#include <optional>
#include <span>
#include <stdexcept>
#include <vector>

#include "kernels/elastic_material.hpp"
#include "kernels/half_space_kernel.hpp"
#include "kernels/history_convolution.hpp"
#include "simd/instruction_set.hpp"

namespace slipstrip {

// Design constants, fixed so that results do not depend on hidden knobs.
struct HalfSpaceOperatorDesign {
  int corrected_lags = 8;          // lags of the passivity correction
  double near_field_tau = 1.0;     // lags with c_s |k| t <= this are stored weights
  double horizon_tau = 1e10;       // c_s |k| t up to which the exponentials are accurate
  double passivity_margin = 1e-9;  // Re Z_d / (mu/c_s) >= margin on the check grid
  // Slow exponentials (docs/theory.md §8.7).  An exponential with decay lambda =
  // x h per step is slow when lambda (B - 1) / 2 <= slow_taylor_radius; its
  // block factor e^{-lambda j}, |j - (B+1)/2| <= (B-1)/2, is then a Taylor
  // polynomial of `taylor_terms` terms with relative truncation error
  //   radius^terms / terms! * e^radius = 1.7e-16 (0.25, 12).
  // slow_block = 0 rotates every exponential every step (the original algorithm;
  // kept for the equivalence tests).
  int slow_block = 128;
  double slow_taylor_radius = 0.25;
  int taylor_terms = 12;
  // Both operators (HalfSpaceHistory, at most 64; FaceHalfSpaceHistory) work
  // their far field for up to far_batch steps at once (its inputs are delayed
  // by W >= corrected_lags steps); 1: every step.  The same arithmetic per
  // step either way.
  int far_batch = 8;
  // Which compiled copy of push()'s mode loop runs (simd/instruction_set.hpp);
  // empty: simd::instruction_set(), the widest this CPU supports.  The copies
  // agree to rounding (FMA contraction); tests and benchmarks pick one here.
  std::optional<simd::InstructionSet> instruction_set;
  // The near-field exponential sum is fitted over h = c_s |k| dt from the
  // smallest h of the operator's modes up to their largest stored window
  // (HalfSpaceHistory and FaceHalfSpaceHistory alike).  An
  // operator holding part of a larger one's modes (one process of a 2D
  // interface split over processes) is given the whole one's range here
  // (set_near_field_range), so its modes get the same fit; 0: its own modes'.
  double near_field_h_min = 0.0, near_field_tau_max = 0.0;
};

// Sets design.near_field_h_min and near_field_tau_max to the range of the
// modes h (h = c_s |k| dt; entries 0, the uniform mode, are skipped).
void set_near_field_range(HalfSpaceOperatorDesign& design, std::span<const double> h);

// Most Taylor terms a design may ask for (the block-end update keeps them on the stack).
inline constexpr int kMaxTaylorTerms = 32;
// Largest relative Taylor error of the slow exponentials a design may have:
// far below the kernel's own accuracy (~1e-9), so blocking changes the
// operator only at round-off.
inline constexpr double kMaxSlowTaylorError = 1e-14;

// Relative truncation error bound of the slow exponentials' Taylor factor
// (above); the constructor refuses designs above kMaxSlowTaylorError.
double slow_taylor_error_bound(const HalfSpaceOperatorDesign& design);

// The largest decay per step lambda of a slow exponential in blocks of
// `block` steps: lambda (block - 1) / 2 <= radius; -1 (none) for block = 0.
double slow_decay_limit(int block, double radius);

// Throws std::invalid_argument (naming the limit) for a design whose slow
// block, Taylor terms or Taylor radius cannot be used.
void check_half_space_design(const HalfSpaceOperatorDesign& design);

// The terms of one mode q >= 1.  Weights in Pa s/m (weight * slip rate = Pa).
struct HalfSpaceModeTerms {
  double static_weight = 0.0;              // dt mu |k| * static value of g
  std::vector<double> lag_weight;          // K_j - static_weight, j = 1..W (correction included)
  std::vector<double> correction;          // e_j, j = 1..corrected_lags (units mu/c_s)
  std::vector<std::complex<double>> pole;         // fast exponentials: e^{rate h}
  std::vector<std::complex<double>> pole_weight;  // kernel at lag W + i: 2 Re sum weight pole^i
  std::vector<std::complex<double>> slow_rate;    // slow exponentials: rate (units c_s |k|), shear branch first
  std::vector<std::complex<double>> slow_weight;  // their weights, as pole_weight
  std::size_t slow_shear = 0;                     // how many slow exponentials are on the shear branch
};

// Where each mode's stored lags end: W_q >= corrected_lags with W_q h_q >=
// near_field_tau.  h[q] = c_s |k_q| dt (h[0] unused).
std::vector<int> half_space_windows(std::span<const double> h, const HalfSpaceOperatorDesign& design);

// The terms of every mode (index q; q = 0 has none: a half-space's uniform
// mode has no history).  Modes are independent and computed in parallel;
// `cancelled` is polled by the calling thread only (it may call into
// Python).  block = the slow block B (0: every exponential is fast).  Throws
// SetupCancelled, or std::invalid_argument naming dt and c_s k_max dt when a
// mode has no passive correction.
std::vector<HalfSpaceModeTerms> half_space_mode_terms(const ElasticMaterial& material, double time_step,
                                                      std::span<const double> h, std::span<const int> window,
                                                      int block, const HalfSpaceOperatorDesign& design,
                                                      const CancelCheck& cancelled);
// The same for any kernel shape (kernels/half_space_kernel.hpp) in units of
// modulus / speed (mu / c_s of one material; mu_u / c_ref of an antiplane
// pair), h = speed |k| dt.  Throws HalfSpaceNotPassive for a mode without a
// passive correction.
std::vector<HalfSpaceModeTerms> half_space_mode_terms(const HalfSpaceShape& shape, double modulus, double speed,
                                                      double time_step, std::span<const double> h,
                                                      std::span<const int> window, int block,
                                                      const HalfSpaceOperatorDesign& design,
                                                      const CancelCheck& cancelled);

// Thrown when some mode's passivity correction does not exist (the time step
// is too long): an std::invalid_argument naming dt and the largest h.
struct HalfSpaceNotPassive : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

}  // namespace slipstrip
