#pragma once
// The strip's exact discrete history operator (the same one as StripHistory,
// built from the same StripKernels), applied with a cost per step that grows
// only like log^2 of the strip height instead of linearly
// (docs/theory.md, "block algorithm"; docs/performance.md).
//
// Per Fourier mode q >= 1 the history part is
//   history_q(t_n) = c0 R_n - dt y_n,   R_n = sum_{j>=1} v_{n-j},
//   y_n = sum_{j>=1} O_j v_{n-j},       O_j = sum_m w_m cos(phi_m j),
// with c0 = mu/c_s + dt sum_m w_m (comb identity plus static completion,
// docs/theory.md 6.2; 2 eta + dt sum_m w_m for two different antiplane strips,
// docs/bodies.md §3).  StripHistory advances one rotation per normal mode
// and step: O(P) per step with P ~ 0.75 * 2H/(c_s dt) modes.  Here the
// convolution y is split by lag, exactly (every pair of input i and output t
// is counted once):
//   - i and t in the same aligned block of `direct_block` steps: direct sum;
//   - i in the first and t in the second half of an aligned block of 2s steps
//     (s = direct_block, 2 direct_block, ..., B/2): one FFT convolution of s
//     inputs with the kernel prefix O_1..O_{2s-1} when the s inputs are
//     complete (binary partition of the lag plane, like Gardner's
//     non-uniformly partitioned convolution);
//   - i in an earlier block of B steps: the normal-mode states
//     A_k = sum_i exp(-i theta_k (i - n0)) v_i (theta_k = +-phi_m), moved
//     across a whole block at once by a non-uniform FFT (kernels/nufft.hpp)
//     and evaluated for the next B outputs by its adjoint.
// Per step this costs O(log^2 B + P/B log) with B ~ P: the normal modes are
// never rotated step by step.  The result equals StripHistory's to the NUFFT's
// accuracy (~1e-12 relative; tests/cpp/test_kernels_block_history.cpp), so the
// operator inherits its passivity and every verification of it.  Memory
// (~64 P + 48 B bytes per mode) is fixed at construction; modes with identical
// normal modes (equal |k| on a 2D interface) share the design part (frequencies,
// weights, kernel spectra: 32 P + 16 B), so such a mode costs 32 P + 32 B bytes
// (its states, inputs and outputs).  The uniform mode q = 0 keeps the exact
// shear delay line.
#include <complex>
#include <cstddef>
#include <memory>
#include <span>
#include <vector>

#include "kernels/block_rows.hpp"
#include "kernels/elastic_material.hpp"
#include "kernels/fft.hpp"
#include "kernels/history_convolution.hpp"
#include "kernels/nufft.hpp"
#include "kernels/step_major_direct_block.hpp"

namespace slipstrip {

struct BlockHistoryDesign {
  int direct_block = 32;  // lags inside aligned blocks of this many steps are summed directly
  int block = 0;          // B, a power of two; 0: the smallest power of two >= the most modes
                          // of any Fourier mode (and >= 2 direct_block)
  // NUFFT grid points on each side of a frequency: 7, 14 in all (the
  // exponential-of-semicircle kernel), accuracy <= 5e-13 (kernels/nufft.hpp).
  int nufft_half_width = 7;
};

// The block length B of BlockHistoryDesign::block = 0: the smallest power of
// two >= `most_normal_modes` (of any Fourier mode) and >= 2 direct_block.
int automatic_block_length(std::size_t most_normal_modes, int direct_block);

// The B Simulation gives the operator of a body of two different ones (an
// antiplane pair, kernels/two_body_history.hpp): automatic_block_length,
// doubled when the block arrays at twice that B (kBodyBlockBytesPerStep per
// Fourier mode and step of B) stay within kBlockDoublingBytes
// (kernels/block_rows.hpp), and at least kBodyBlockLength.  The far field's
// cost per step goes like the frequencies over B and the FFT levels' like
// log B; at N = 2048 one body's push took, CPU us at B = 256 / 512 / 1024 / 2048
// (bench_kernels_history, docs/performance.md): H = 0.05 m 123 / 99 / 94 / 73,
// H = 0.2 m 238 / 167 / 101 / 128, and H = 0.1 m 98 at 512 against 79 at 1024
// and 83 at 2048; H = 1 m 151 / 120 / 109 at 2048 / 4096 / 8192.
inline constexpr int kBodyBlockLength = 1024;
inline constexpr double kBodyBlockBytesPerStep = 3.0 * 16.0;  // 2 complex rows, 1 complex spectrum
int body_block_length(std::size_t most_normal_modes, int direct_block, std::size_t fourier_modes);

class BlockStripHistory final : public HistoryOperator {
 public:
  BlockStripHistory(const ElasticMaterial& material, const StripKernels& kernels,
                    const BlockHistoryDesign& design = {}, const CancelCheck& cancelled = {});
  // From kernels and the bodies' constants (two different antiplane strips,
  // kernels/antiplane_pair_modes.hpp).
  BlockStripHistory(const StripPairConstants& constants, const StripKernels& kernels,
                    const BlockHistoryDesign& design = {}, const CancelCheck& cancelled = {});
  ~BlockStripHistory() override;
  BlockStripHistory(const BlockStripHistory&) = delete;
  BlockStripHistory& operator=(const BlockStripHistory&) = delete;

  double time_step() const override { return dt_; }
  double radiation_damping() const override { return eta_; }
  int modes() const override { return n_modes_; }
  ModeOperatorStats stats() const override;
  void push(std::span<const std::complex<double>> slip_rate_spectrum) override;
  std::span<const std::complex<double>> history() const override { return history_; }
  // The normal-mode states, the inputs and partial outputs of the current
  // block, the running sums and the delay line (the per-thread scratch and
  // the kernel spectra are not state: rebuilt from the config).
  HistoryOperatorState save_state() const override;
  void restore_state(const HistoryOperatorState& state) override;
  HistoryStateLayout state_layout() const override;

  int block() const { return block_; }
  std::size_t designs() const { return c0_.size(); }  // distinct normal-mode sets (<= modes())

 private:
  struct Scratch;
  void convolve_level(int q, std::size_t level, int start, Scratch& scratch);
  // The far field's phases p_k = e^{i theta_k B/2} of a design, and with them
  // its NUFFT kernel weights (locate_design, for the modes of a shared design).
  void design_phases(std::size_t design, Scratch& scratch) const;
  void locate_design(std::size_t design, Scratch& scratch) const;
  // Mode q's far field across the block, with its design's weights located.
  void advance_far_field(int q, Scratch& scratch);
  // The same for the one mode of a design: in one pass over its frequencies
  // (Nufft::forward_map_adjoint), no weights stored.
  void advance_far_field_in_one_pass(int q, Scratch& scratch);

  double dt_, eta_, echo_weight_;  // echo_weight_: the running sum's weight, 2 eta (mu / c_s for identical bodies)
  std::size_t kernels_echo_steps_;  // stats
  int n_modes_, block_, direct_block_;
  UniformModeEchoes echo_;  // q = 0
  int position_ = 0;  // index of the next input inside the current block

  // Designs: the normal modes of a Fourier mode as frequencies theta = +phi
  // and -phi, shared by all modes q with identical normal modes (design_[q];
  // design 0 is the uniform mode's, which has none).
  std::vector<std::size_t> design_;           // per q
  std::vector<std::size_t> first_frequency_;  // per design, size designs + 1
  std::vector<double> theta_;
  std::vector<double> half_weight_;           // w_m / 2 for both +phi_m and -phi_m
  std::vector<double> c0_;                    // per design
  std::vector<std::size_t> design_first_mode_, design_modes_;  // the modes of each design (CSR)
  std::vector<std::size_t> first_state_;      // per q, size n_modes + 1
  std::vector<std::complex<double>> state_;   // A_k of mode q at the start of the current block

  struct Level {
    int size;  // s: inputs per convolution; FFT length 2s
    FftwPlan forward, backward;
    std::size_t first_spectrum;  // into spectrum_, (s + 1) per design
  };
  std::vector<Level> levels_;
  std::vector<std::complex<double>> spectrum_;  // FFT of [0, O_1, .., O_{2s-1}], bins 0..s

  std::unique_ptr<Nufft> nufft_;
  std::vector<Scratch> scratch_;  // one per OpenMP thread

  // State.
  // The block's inputs and outputs (kernels/block_rows.hpp; the saved state
  // is the rows), and the current direct block of every mode, step-major
  // (kernels/step_major_direct_block.hpp).
  BlockRows<1> rows_;
  StepMajorDirectBlock direct_blocks_;
  std::vector<std::complex<double>> running_sum_;  // per q
  std::vector<std::complex<double>> history_;
};

}  // namespace slipstrip
