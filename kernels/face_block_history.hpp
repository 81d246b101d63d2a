#pragma once
// One finite body's 2x2 history operator (the same discrete operator as
// FaceModalHistory, built from the same face_discrete_modes) applied with the
// block algorithm of the identical pair (kernels/block_strip_history.hpp,
// docs/theory.md "block algorithm"): per step O(log^2 B + (P/B)(w + log B))
// per Fourier mode instead of rotating all P normal modes.
//
// Per Fourier mode, FaceModalHistory's history is
//   h_n = C0 R_n - dt y_n,   R_n = sum_{j>=1} v_{n-j},   C0 = 2E + dt sum_m W_m,
//   y_n = sum_{j>=1} O_j v_{n-j},   O_j = sum_m W_m cos(phi_m j),
// with 2x2 weights W_m = [[a_m, i b_m], [-i b_m, d_m]] (real a, b, d: the
// Hermitian weights of kernels/face_modes.hpp, checked at construction).  So
// O_j = [[A_j, i B_j], [-i B_j, D_j]] with three real lag kernels, and the
// convolution y is split by lag exactly as for the scalar strip:
//   - inputs and outputs in the same aligned block of `direct_block` steps: direct sums;
//   - first to second half of an aligned block of 2s steps (s = direct_block .. B/2):
//     FFT convolutions (two input transforms, three kernel spectra, two output
//     transforms; at the largest levels each transform as two of length s);
//   - inputs of earlier blocks of B steps: the normal-mode states of both input
//     components, moved across a block by the non-uniform FFT (kernels/nufft.hpp)
//     and evaluated for the next B outputs by its adjoint.
// Equal to FaceModalHistory to the NUFFT's accuracy (~1e-12 of the largest
// history value; tests/cpp/test_kernels_face_block_history.cpp), so every
// verification of the modal face operator (statics, passivity, the
// prescribed-displacement histories) holds for it.
#include <array>
#include <complex>
#include <cstddef>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "kernels/block_rows.hpp"
#include "kernels/face_history.hpp"
#include "kernels/fft.hpp"
#include "kernels/nufft.hpp"

namespace slipstrip {

struct FaceBlockDesign {
  int direct_block = 32;      // a power of two
  int block = 0;              // B, a power of two >= 2 direct_block; 0: >= the most modes of any Fourier mode
  // NUFFT grid points on each side of a frequency: 7, 14 in all (the
  // exponential-of-semicircle kernel), accuracy <= 5e-13 (kernels/nufft.hpp).
  int nufft_half_width = 7;
  // Levels of s >= split_level (a power of two) take each length-2s transform
  // as two of length s (FaceBlockHistory::convolve_split_level).  Below 2048
  // the twiddles this needs cost more than FFTW_ESTIMATE's plans of length 2s
  // lose against those of s; at 2s = 4096 and 8192 those plans take ~3.5x and
  // ~4.5x the time of the half-length ones (one body at N = 2048, H = 1 m,
  // docs/notes/2026-11-27-pair-levels.md).
  int split_level = 2048;
  // Split levels of s >= bin_order_level (a power of two) write their two
  // half-length spectra interleaved, in bin order, and read them back so:
  // FFTW_ESTIMATE's plan of a contiguous transform of 8192 points takes ~38
  // us, the same transform written (or read and written) with stride 2
  // ~17-19 us; at 4096 points the two are equal and at 2048 the strided one is
  // the slower (docs/notes/2026-11-27-pair-bin-order.md).
  int bin_order_level = 8192;
  // The far field's two components share one interleaved grid from this many
  // grid points (2B) on (Nufft::PassScratch).
  int nufft_interleave_from = Nufft::interleaved_grid;
};

// The B Simulation gives a body of a pair of different bodies: the power of
// two >= max(the most normal modes of any Fourier mode, 2 direct_block) (the
// rule of FaceBlockDesign::block = 0 and of the identical pair,
// automatic_block_length), doubled when the block arrays at twice that B
// (kFaceBlockBytesPerStep per Fourier mode and step of B) stay within
// kBlockDoublingBytes.  The far field's cost per step goes like (frequencies /
// B) times the NUFFT width, and a body here transforms two components three
// kernels wide, so a block twice the modes pays: one body's push at N = 2048,
// H = 0.1 m, B = 1024 ~10-15 % faster than B = 512; H = 1 m, B = 8192 16 %
// faster than 4096 (docs/performance.md).  At larger heights or N the doubled
// arrays would pass the bound (N = 2048, H = 4 m: 3.8 GB at B = 32768), and B
// stays.
inline constexpr double kFaceBlockBytesPerStep = 7.0 * 16.0;  // 4 complex rows, 3 complex spectra
inline int face_block_length(std::size_t most_normal_modes, int direct_block, std::size_t fourier_modes) {
  int block = 2 * direct_block;
  while (static_cast<std::size_t>(block) < most_normal_modes) block *= 2;
  if (kFaceBlockBytesPerStep * 2.0 * block * static_cast<double>(fourier_modes) <= kBlockDoublingBytes) block *= 2;
  return block;
}

class FaceBlockHistory final : public FaceHistory {
 public:
  FaceBlockHistory(const ElasticMaterial& material, double height, OuterFace outer_face, double length,
                   int nodes, double time_step, const FaceBlockDesign& design = {},
                   const CancelCheck& cancelled = {});
  ~FaceBlockHistory() override;
  FaceBlockHistory(const FaceBlockHistory&) = delete;
  FaceBlockHistory& operator=(const FaceBlockHistory&) = delete;

  double time_step() const override { return dt_; }
  double shear_impedance() const override { return impedance_x_; }
  double normal_impedance() const override { return impedance_y_; }
  int modes() const override { return n_modes_; }
  void push(std::span<const std::complex<double>> velocity_x,
            std::span<const std::complex<double>> velocity_y) override;
  std::span<const std::complex<double>> history_x() const override { return history_x_; }
  std::span<const std::complex<double>> history_y() const override { return history_y_; }
  // The state is the rows alone (BlockRows::saved_input).
  void save_into(HistoryOperatorState& state, const std::string& prefix) const override;
  void restore_from(const HistoryOperatorState& state, const std::string& prefix) override;
  void state_layout_into(HistoryStateLayout& layout, const std::string& prefix) const override;
  std::size_t memory_bytes() const override;
  std::size_t discrete_modes() const override { return theta_.size() / 2; }
  const char* algorithm() const override { return "block"; }
  int period() const override { return block_; }

 private:
  struct Scratch;
  void convolve_level(int q, std::size_t level, int start, Scratch& scratch);
  struct Level;
  void convolve_split_level(int q, const Level& level, int start, Scratch& scratch);
  void advance_far_field(int q, Scratch& scratch);
  // One push: input `input` (tau) of the block, output `output`, and their
  // places in their direct blocks.
  struct Step {
    int input, output, input_slot, output_slot;
    bool block_done;
  };
  // The memory mode q's direct block end at input tau will read and write
  // (close's rows, the short levels' rows and kernel spectra), requested ahead.
  void prefetch_levels(int q, int tau) const;
  // Input tau (v_x, v_y) of mode q and its output for the next step.
  void push_mode(int q, const Step& step, std::complex<double> vx, std::complex<double> vy, Scratch& scratch);

  double dt_, impedance_x_, impedance_y_;
  int n_modes_, block_, direct_block_;
  int position_ = 0;  // index of the next input inside the current block

  // Normal modes as frequencies theta = +phi and -phi, with half weights (a, b, d) / 2.
  std::vector<std::size_t> first_frequency_;  // size n_modes + 1
  std::vector<double> theta_, half_a_, half_b_, half_d_;
  std::vector<double> half_block_phase_re_, half_block_phase_im_;  // e^{i theta B/2}
  std::vector<double> c0_a_, c0_b_, c0_d_;  // per q: C0 = [[c0_a, i c0_b], [-i c0_b, c0_d]]
  // [q][a, b, d][j], j < direct_block (lag 0 := 0): the three lag kernels of
  // the direct sums, one mode's next to each other.
  std::vector<double> lags_;

  struct Level {
    int size;    // s: inputs per convolution, a circular convolution of length 2s
    bool split;  // transforms of length s (convolve_split_level), else 2s
    bool bin_order;  // split, both halves' spectra interleaved in bin order (stride-2 plans of two)
    FftwPlan forward, backward;
    std::size_t first_spectrum;  // into the spectra, (s + 1) per mode q
    std::size_t first_twiddle;   // into twiddle_, s values
  };
  // Per split level, e^{-i pi j / s} for j < s.
  std::vector<std::complex<double>> twiddle_;
  std::vector<Level> levels_;
  // Spectra of [0, K_1, .., K_{2s-1}] for K = A, B, D, bins 0..s (real kernels).
  std::vector<std::complex<double>> spectrum_a_, spectrum_b_, spectrum_d_;

  std::unique_ptr<Nufft> nufft_;
  std::vector<Scratch> scratch_;  // one per OpenMP thread

  // State.
  std::vector<std::complex<double>> state_x_, state_y_;  // A_k of each input at the block start
  // The block's inputs and outputs of both components (x: 0, y: 1), and the
  // current direct block of every mode, contiguous (its inputs [q][j][x, y];
  // its outputs [q][x re, x im, y re, y im][j], the levels' and the far
  // field's part alone).
  BlockRows<2> rows_;
  // Output `slot` of mode q's current direct block from that block's inputs
  // so far: (x re, x im, y re, y im).
  std::array<double, 4> direct_part(int q, int slot) const;
  std::vector<std::complex<double>> running_x_, running_y_;
  std::vector<std::complex<double>> history_x_, history_y_;
};

}  // namespace slipstrip
