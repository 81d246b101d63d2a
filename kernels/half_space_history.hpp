#pragma once
// Bounded-memory history operator of two half-spaces (docs/theory.md,
// "bounded-memory half-space").  Per Fourier mode q >= 1, with h = c_s |k| dt,
// the discrete kernel is
//
//   K_j = (mu/c_s) h g(j h) + (mu/c_s) e_j          (e_j = 0 for j > lags),
//
// i.e. the exact half-space kernel sampled at every lag (trapezoidal rule,
// g(0) = 0) plus the smallest correction of the first `lags` weights that
// makes the operator passive (kernels/passivity.hpp).  It is applied as
//   - a running sum with the static weight dt mu |k| (1 - r^2)  (exact static stiffness);
//   - the weights K_j - static of lags 1..W (W h >= 1) from a ring buffer;
//   - lags > W by damped rotations, one per exponential of g (half_space_kernel.hpp),
//     fed with the slip rate delayed by W steps.  The "fast" exponentials rotate
//     every step.  The "slow" ones (decay over a block of B steps below the Taylor
//     radius) are advanced once per block through Taylor moments of the block's
//     inputs, and their output inside a block is a short polynomial per branch
//     plus a direct sum over the block's own inputs (docs/theory.md §8.7): the
//     same operator to ~1e-16 relative, at a fraction of the memory traffic.
//   - the far field (both kinds of exponentials) is worked for a batch of up to
//     design.far_batch steps at once, its inputs being delayed by W steps
//     (docs/theory.md §8.8): the same arithmetic per step, in the same order.
// The design constants and the per-mode terms: kernels/half_space_design.hpp.
// Memory and cost per step are fixed at construction, whatever the run length;
// the kernel is accurate to ~1e-9 (absolute, in units of mu |k|) for
// c_s |k| t up to 1e10.  The uniform mode q = 0 of a half-space has no
// history (only radiation damping).
#include <complex>
#include <cstddef>
#include <optional>
#include <span>
#include <vector>

#include "kernels/elastic_material.hpp"
#include "kernels/half_space_design.hpp"
#include "kernels/half_space_kernel.hpp"
#include "kernels/history_convolution.hpp"
#include "simd/instruction_set.hpp"

namespace slipstrip {


// The operator's coefficients for one mode (a plain value, for tests and
// diagnostics).  Units: weights in Pa s/m (so that weight * slip rate = Pa).
struct HalfSpaceModeKernel {
  double wavenumber = 0.0;   // |k| [1/m]
  double h = 0.0;            // c_s |k| dt
  double static_weight = 0.0;
  std::vector<double> lag_weight;   // K_j - static_weight, j = 1..W
  std::vector<double> correction;   // e_j (mu/c_s) already included in lag_weight, j = 1..lags
  std::vector<std::complex<double>> pole;        // e^{rate h} per exponential (|pole| < 1)
  std::vector<std::complex<double>> pole_weight; // kernel at lag W + i is 2 Re sum pole_weight pole^i
};

// Largest h = c_s |k| dt for which the correction exists with the design's
// lags is ~1.11 (plane strain, nu = 0.33), i.e. time.beta <= 0.35 at the
// Nyquist mode; the constructor below throws with a clear message otherwise.
class HalfSpaceHistory final : public HistoryOperator {
 public:
  HalfSpaceHistory(const ElasticMaterial& material, double length, int nodes, double time_step,
                   const HalfSpaceOperatorDesign& design = {}, const CancelCheck& cancelled = {});
  // Any list of wavenumbers (mode q has |k| = wavenumbers[q]; the uniform mode
  // 0 first and only there).  Modes of equal |k| share one design, computed once.
  HalfSpaceHistory(const ElasticMaterial& material, std::span<const double> wavenumbers,
                   double time_step, const HalfSpaceOperatorDesign& design = {},
                   const CancelCheck& cancelled = {});
  // The antiplane pair of two half-spaces, top and bottom, as ONE operator of
  // the slip rate: the combined kernel K_c = K_t K_b / (K_t + K_b)
  // (kernels/half_space_kernel.hpp, AntiplaneHalfSpacePair) in units of
  // mu_u / c_ref, h = c_ref |k| dt with c_ref the faster body's shear speed
  // (the solver's step is beta dx / c_ref, so h spans the range the scalar
  // operator is designed for, and the stored lags W h >= 1 are those of the
  // faster body alone), radiation damping eta_c = eta_t eta_b / (eta_t + eta_b).
  // Equal shear speeds (identical bodies among them) give the identical pair's
  // operator of modulus mu_u (identical bodies: the one-material operator bit
  // for bit).  Different speeds are checked first (verify_antiplane_half_space_pair:
  // throws HalfSpacePairCheckFailed); a mode without a passive correction
  // throws HalfSpaceNotPassive.
  HalfSpaceHistory(const ElasticMaterial& top, const ElasticMaterial& bottom, double length, int nodes,
                   double time_step, const HalfSpaceOperatorDesign& design = {}, const CancelCheck& cancelled = {});
  HalfSpaceHistory(const ElasticMaterial& top, const ElasticMaterial& bottom, std::span<const double> wavenumbers,
                   double time_step, const HalfSpaceOperatorDesign& design = {}, const CancelCheck& cancelled = {});

  double time_step() const override { return dt_; }
  double radiation_damping() const override { return eta_; }
  int modes() const override { return static_cast<int>(history_.size()); }
  ModeOperatorStats stats() const override;
  void push(std::span<const std::complex<double>> slip_rate_spectrum) override;
  std::span<const std::complex<double>> history() const override { return history_; }
  HistoryOperatorState save_state() const override;
  void restore_state(const HistoryOperatorState& state) override;
  HistoryStateLayout state_layout() const override;

  // Coefficients of mode q >= 1, as used by push() (fast exponentials first,
  // then the slow ones).
  HalfSpaceModeKernel mode_kernel(int q) const;
  // Number of slow exponentials in all modes (0 when design.slow_block = 0),
  // and the block length B.
  std::size_t slow_exponentials() const { return slow_decay_.size(); }
  int slow_block() const { return block_; }
  // Steps of the far field worked at once (design.far_batch, at most the
  // shortest window, a divisor of the slow block).
  int far_batch() const { return batch_; }
  // Steps after which the per-step work repeats (the slow block, else the batch).
  int period() const { return block_ > 0 ? block_ : batch_; }
  // The kernel's shape (an antiplane pair of different speeds: antiplane_pair()).
  const HalfSpaceShape& shape() const { return shape_; }

 private:
  // Every constructor: the kernel `shape` in units of modulus / speed, h =
  // speed |k| dt, radiation damping eta.
  HalfSpaceHistory(const HalfSpaceShape& shape, double modulus, double speed, double eta,
                   std::span<const double> wavenumbers, double time_step, const HalfSpaceOperatorDesign& design,
                   const CancelCheck& cancelled);
  HalfSpaceHistory(const AntiplaneHalfSpacePair& pair, std::span<const double> wavenumbers, double time_step,
                   const HalfSpaceOperatorDesign& design, const CancelCheck& cancelled)
      : HalfSpaceHistory(pair.shape, pair.modulus, pair.reference_speed, pair.radiation_damping, wavenumbers,
                         time_step, design, cancelled) {}
  HalfSpaceShape shape_;
  double dt_, eta_;
  simd::InstructionSet instruction_set_;  // of push()'s mode loop
  long long step_ = 0;
  std::vector<double> wavenumber_, h_;
  std::vector<double> static_weight_;          // per q
  std::vector<std::size_t> first_lag_;         // size modes+1
  std::vector<double> lag_weight_;             // flat; K_j - static for j = 1..W_q
  std::vector<double> correction_;             // flat, `lags` per mode q >= 1 (diagnostics)
  int lags_;
  std::vector<std::size_t> first_pole_;        // size modes+1
  std::vector<double> pole_cos_, pole_sin_;    // rho cos(phi), rho sin(phi)
  std::vector<double> weight_cos_, weight_sin_;
  // State.
  std::vector<std::complex<double>> ring_;     // flat; last W_q slip rates of mode q
  std::vector<double> c_re_, c_im_, s_re_, s_im_;
  std::vector<std::complex<double>> running_sum_;

  // Set-up: the per-mode terms (kernels/half_space_design.hpp) laid out flat
  // for the time loop, contiguous per mode.
  void flatten_fast_terms(const std::vector<HalfSpaceModeTerms>& terms);
  void build_slow_tables(const std::vector<HalfSpaceModeTerms>& terms);

  // Slow exponentials (docs/theory.md §8.7).  Pole z = rho_b d with b in
  // {shear, P}, rho_b = e^{i b h}, d = e^{-lambda}.  Per mode q the slow poles
  // [first_slow_[q], slow_shear_end_[q]) are on the shear branch, the rest up to
  // first_slow_[q+1] on the P branch.
  void push_slow_block_end(int q);
  // push()'s work for mode q >= 1 fed with slip rate v, and its loop over the
  // modes [q_begin, q_end): compiled once per instruction set (the wider ones
  // with target attributes, simd/instruction_set.hpp); push() calls the one
  // for instruction_set_.  advance_mode and push_slow_block_end are inlined
  // into each.
  void advance_mode(int q, std::complex<double> v);
  // The far field of mode q (fast rotations, the slow block's outputs and
  // in-block sums, block ends) at steps batch_step + d, d in [first, last),
  // into far_out_ and slow_out_: its inputs v_{n-W} are in the ring batch_
  // steps ahead, so the mode's rows are read from memory once per batch
  // instead of once per step.  Each step's arithmetic is the every-step
  // operator's, in the same order.
  void advance_far(int q, long long batch_step, int first, int last);
  void advance_modes_baseline(int q_begin, int q_end, const std::complex<double>* slip_rate);
  void advance_modes_avx2(int q_begin, int q_end, const std::complex<double>* slip_rate);
  void advance_modes_avx512(int q_begin, int q_end, const std::complex<double>* slip_rate);
  int block_ = 0, terms_ = 0;
  double block_centre_ = 0.0;                      // t_c = (B + 1) / 2
  std::vector<std::size_t> first_slow_, slow_shear_end_;
  std::vector<double> slow_decay_;                 // lambda = x h
  std::vector<double> slow_centre_factor_;         // e^{-lambda t_c}
  std::vector<std::complex<double>> slow_pole_;    // z (diagnostics: mode_kernel)
  std::vector<std::complex<double>> slow_weight_;  // w (kernel at lag W + i: 2 Re w z^i)
  std::vector<std::complex<double>> slow_block_pole_;  // z^B
  std::vector<double> slow_lag_weight_;            // per mode, B: 2 Re sum_slow w z^{i+1}, i = 0..B-1
  std::vector<std::complex<double>> rotation_;     // [(t' - 1) * modes + q] * 2 + b: rho_b^{t'}, t' = 1..B
  // Slow state.
  // Y at the block start, fed with the Re and with the Im part of the slip rate.
  std::vector<std::complex<double>> slow_state_re_, slow_state_im_;
  std::vector<std::complex<double>> block_input_;  // per mode, B: this block's delayed slip rates
  std::vector<std::complex<double>> block_moment_; // per mode, 4 * terms: M_{beta,p}, beta = 2 b + (0 Re, 1 Im)
  // The far field's batch: per mode, batch_ steps of the fast exponentials'
  // output and of the slow ones' (kept apart: push() adds them to the near
  // field in the every-step operator's order).
  int batch_ = 1;
  int position_ = 0;  // this step's position in its batch (push())
  std::vector<std::complex<double>> far_out_, slow_out_;
  std::vector<std::complex<double>> history_;
};

}  // namespace slipstrip
