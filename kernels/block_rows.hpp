#pragma once
// The inputs and outputs of the current block of B steps of a block history
// operator (docs/theory.md "block algorithm"), with C input components per
// Fourier mode: BlockStripHistory has one (the slip rate), FaceBlockHistory
// two (a body's face velocities).
//
// Per mode q and component c, two rows of B values: the block's inputs, which
// the FFT levels and the far field read, and its outputs so far, into which
// they add.  The per-step loop over the Fourier modes does not touch the rows:
// it works on the current direct block (direct_block steps) of every mode.
// Here it is held per mode, contiguously -- its inputs so far ([q][j][c]),
// copied into the rows when the direct block is complete (close), and its
// outputs ([q][c][re, im][j]): the levels' and the far field's part copied
// from the rows when it starts (open).  FaceBlockHistory sums an output's
// direct part from the inputs when it is due, and its outputs keep the rows'
// part alone.  BlockStripHistory keeps its direct blocks step-major instead
// (kernels/step_major_direct_block.hpp) and uses the rows alone.  Either way
// a step streams through memory instead of reading 2C rows B apart per mode
// (one page each at B = 1024), and the rows are touched once per direct block.
#include <algorithm>
#include <array>
#include <complex>
#include <cstddef>
#include <span>
#include <vector>

#include "kernels/huge_pages.hpp"

namespace slipstrip {

// The most a body of a pair of different bodies spends on doubling its block
// length (face_block_length, body_block_length): B is doubled only while the
// block arrays at the doubled B (rows and kernel spectra, per Fourier mode and
// step of B) stay within this.  A longer block makes the far field run less
// often (its cost per step goes like the normal modes over B) for one more FFT
// level, and costs memory in proportion to B; at N = 2048, H = 1 m a body's
// push is 16 % (in-plane) and 20 % (antiplane) cheaper at twice the smallest B
// (docs/performance.md), where the in-plane body's block arrays take 0.94 GB.
inline constexpr double kBlockDoublingBytes = 1024.0 * 1024.0 * 1024.0;

template <int C>
class BlockRows {
 public:
  using cplx = std::complex<double>;

  BlockRows() = default;
  // With `per_mode_direct_blocks` false the direct-block arrays are not
  // allocated: the caller keeps its direct blocks itself
  // (kernels/step_major_direct_block.hpp) and uses the rows alone.
  BlockRows(std::size_t modes, int block, int direct_block, bool per_mode_direct_blocks = true)
      : modes_(modes), block_(static_cast<std::size_t>(block)), direct_(static_cast<std::size_t>(direct_block)) {
    // On huge pages (kernels/huge_pages.hpp): each mode's rows are on pages
    // of their own, and the direct blocks are streamed through every step.
    for (int c = 0; c < C; ++c) {
      assign_on_huge_pages(input_[c], modes * block_, cplx(0.0));
      assign_on_huge_pages(accumulator_[c], modes * block_, cplx(0.0));
    }
    if (!per_mode_direct_blocks) return;
    assign_on_huge_pages(direct_inputs_, C * modes * direct_, cplx(0.0));
    assign_on_huge_pages(direct_outputs_, 2 * C * modes * direct_, 0.0);
  }

  // Mode q's row of component c: the block's inputs (complete up to the last
  // closed direct block) and its outputs so far.
  const cplx* input(int c, std::size_t q) const { return input_[c].data() + q * block_; }
  cplx* input_row(int c, std::size_t q) { return input_[c].data() + q * block_; }
  cplx* accumulator(int c, std::size_t q) { return accumulator_[c].data() + q * block_; }
  const cplx* accumulator(int c, std::size_t q) const { return accumulator_[c].data() + q * block_; }

  // Input `tau` (of the block) of mode q, component c, into its direct block.
  void set_input(std::size_t q, int tau, int c, cplx v) {
    set_direct_input(q, static_cast<std::size_t>(tau) % direct_, c, v);
  }
  // The same at the input's place in its direct block, slot = tau % direct_block,
  // for a caller that computes it once per step rather than once per mode.
  void set_direct_input(std::size_t q, std::size_t slot, int c, cplx v) {
    direct_inputs_[(q * direct_ + slot) * C + c] = v;
  }
  // Mode q's direct block inputs so far, [j][c] (C direct_block values).
  const cplx* direct_inputs(std::size_t q) const { return direct_inputs_.data() + q * direct_ * C; }
  // Mode q's direct block outputs, [c][re, im][j] (2 C direct_block values).
  double* outputs(std::size_t q) { return direct_outputs_.data() + 2 * C * q * direct_; }
  const double* outputs(std::size_t q) const { return direct_outputs_.data() + 2 * C * q * direct_; }

  // Input tau completed its direct block, whose outputs are all used: its
  // inputs into the rows (before the levels and the far field read them),
  // the used outputs' rows zeroed (the far field adds into every entry).
  void close(std::size_t q, int tau) {
    const std::size_t done = static_cast<std::size_t>(tau) + 1 - direct_;
    const cplx* in = direct_inputs_.data() + q * direct_ * C;
    for (int c = 0; c < C; ++c) {
      cplx* row = input_[c].data() + q * block_ + done;
      cplx* acc = accumulator_[c].data() + q * block_ + done;
      for (std::size_t j = 0; j < direct_; ++j) {
        row[j] = in[j * C + c];
        acc[j] = 0.0;
      }
    }
  }
  // Every contribution of earlier direct blocks to outputs p..p+D-1 is in the
  // rows (after the levels and the far field): they start the direct block.
  void open(std::size_t q, int p) {
    double* out = outputs(q);
    for (int c = 0; c < C; ++c) {
      const cplx* acc = accumulator_[c].data() + q * block_ + p;
      double* re = out + 2 * c * direct_;
      double* im = re + direct_;
      for (std::size_t j = 0; j < direct_; ++j) {
        re[j] = acc[j].real();
        im[j] = acc[j].imag();
      }
    }
  }

  // The state as rows alone: component c's input rows with the current direct
  // block's inputs so far (inputs position - position % D .. position - 1,
  // still only in the direct block) written in, and the output rows.
  std::vector<cplx> saved_input(int c, int position) const {
    std::vector<cplx> rows = input_[c];
    const std::size_t start = static_cast<std::size_t>(position) - static_cast<std::size_t>(position) % direct_;
    for (std::size_t q = 0; q < modes_; ++q)
      for (std::size_t t = start; t < static_cast<std::size_t>(position); ++t)
        rows[q * block_ + t] = direct_inputs_[(q * direct_ + t - start) * C + c];
    return rows;
  }
  std::span<cplx> input_rows(int c) { return input_[c]; }
  std::span<const cplx> input_rows(int c) const { return input_[c]; }
  std::span<const cplx> accumulator_rows(int c) const { return accumulator_[c]; }
  std::span<cplx> accumulator_rows(int c) { return accumulator_[c]; }

  // After the rows were restored (saved_input, accumulator_rows) and the next
  // push takes input `position`: its direct block as push() built it -- the
  // inputs so far (position - position % D .. position - 1), and, when the
  // next output position + 1 is in the same direct block, the rows' part of
  // its outputs (the caller sums the direct part when an output is due).
  void rebuild(int position) {
    std::fill(direct_inputs_.begin(), direct_inputs_.end(), cplx(0.0));
    std::fill(direct_outputs_.begin(), direct_outputs_.end(), 0.0);
    const std::size_t start = static_cast<std::size_t>(position) - static_cast<std::size_t>(position) % direct_;
    const bool same_block = (static_cast<std::size_t>(position) + 1) % direct_ != 0;
    for (std::size_t q = 0; q < modes_; ++q) {
      if (same_block) open(q, static_cast<int>(start));
      for (std::size_t t = start; t < static_cast<std::size_t>(position); ++t)
        for (int c = 0; c < C; ++c) set_input(q, static_cast<int>(t), c, input_[c][q * block_ + t]);
    }
  }

  std::size_t memory_bytes() const {
    return sizeof(cplx) * 2 * C * modes_ * block_ + sizeof(cplx) * direct_inputs_.size() +
           sizeof(double) * direct_outputs_.size();
  }

 private:
  std::size_t modes_ = 0, block_ = 0, direct_ = 0;
  std::array<std::vector<cplx>, C> input_, accumulator_;
  std::vector<cplx> direct_inputs_;
  std::vector<double> direct_outputs_;
};

// The FFT levels (sizes s = direct_block, 2 direct_block, .., B/2) whose
// convolution input `tau` makes ready: those whose s inputs start..start+s-1
// (the first half of an aligned block of 2s steps) end with tau;
// convolve(level, start) adds them into the outputs start+s..start+2s-1.  No
// level fires at the block's last input ((tau + 1) % 2s = 0 != s).
template <class Levels, class Convolve>
void for_completed_levels(const Levels& levels, int tau, Convolve&& convolve) {
  for (std::size_t l = 0; l < levels.size(); ++l) {
    const int s = levels[l].size;
    if ((tau + 1) % (2 * s) == s) convolve(l, tau + 1 - s);
  }
}

}  // namespace slipstrip
