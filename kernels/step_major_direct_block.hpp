#pragma once
// The current direct block of a scalar block history operator
// (BlockStripHistory; docs/theory.md "block algorithm"), stored step-major:
// for each of its D steps the values of all Fourier modes are contiguous
// ([j][q], real and imaginary parts apart).  It holds, per mode, the direct
// block's inputs so far, the rows' part of its D outputs (the FFT levels' and
// the far field's, copied from BlockRows when the direct block opens) and the
// lag kernel O_1..O_{D-1} of the mode's design.
//
// The direct part of output p, at place `slot` of its direct block, is
// gathered when p is due:
//   y_p = part_p + sum_{i < slot} O_{slot-i} v_i,
// summed over a range of modes in vector lanes, the inputs in the order they
// came.  That is the order in which scattering each input into the later
// outputs of a per-mode record (BlockRows' direct blocks) adds them, so the
// outputs are bit for bit the scatter's.  Why step-major: on a 2D interface
// of 512 x 512 nodes the per-step loop over ~1.3e5 Fourier modes per operator
// is bound by memory traffic.  The scatter read and wrote the D - slot later
// outputs of every mode at every step (~0.5 KiB per mode), each mode's record
// one more cache-line stream; the gather reads slot inputs and kernel values
// per mode from 3 slot contiguous rows and writes only the new input, and the
// per-step arrays (inputs, running sums, outputs) are walked contiguously.
// The strided copies into and out of BlockRows happen once per direct block.
//
// Row layout: each row starts on a 64-byte boundary, and consecutive rows are
// 64 bytes more than a multiple of 4 KiB apart.  With rows a whole number of
// pages apart (or nearly: 1025 modes are 8200 bytes) the D entries of one mode
// that close() and open() walk would fall into one cache set and evict each
// other before the neighbouring modes reuse their lines.
#include <algorithm>
#include <array>
#include <complex>
#include <cstdint>
#include <cstddef>
#include <span>
#include <vector>

#include "kernels/block_rows.hpp"
#include "kernels/huge_pages.hpp"

namespace slipstrip {

class StepMajorDirectBlock {
 public:
  using cplx = std::complex<double>;

  StepMajorDirectBlock() = default;
  // lag_kernel(q, j): O_j of mode q, 1 <= j < direct_block.
  template <class LagKernel>
  StepMajorDirectBlock(std::size_t modes, int direct_block, LagKernel&& lag_kernel)
      : modes_(modes), direct_(static_cast<std::size_t>(direct_block)),
        stride_((modes + kPageDoubles - 1) / kPageDoubles * kPageDoubles + kLineDoubles) {
    for (int a = 0; a < kArrays; ++a) {
      assign_on_huge_pages(storage_[a], direct_ * stride_ + kLineDoubles, 0.0);
      const auto address = reinterpret_cast<std::uintptr_t>(storage_[a].data());
      const std::size_t skip = (kLineBytes - address % kLineBytes) % kLineBytes / sizeof(double);
      row0_[a] = storage_[a].data() + skip;
    }
    for (std::size_t j = 1; j < direct_; ++j)
      for (std::size_t q = 0; q < modes_; ++q) row(kKernel, j)[q] = lag_kernel(q, static_cast<int>(j));
  }
  StepMajorDirectBlock(const StepMajorDirectBlock&) = delete;
  StepMajorDirectBlock& operator=(const StepMajorDirectBlock&) = delete;
  StepMajorDirectBlock(StepMajorDirectBlock&&) = default;
  StepMajorDirectBlock& operator=(StepMajorDirectBlock&&) = default;

  int direct_block() const { return static_cast<int>(direct_); }

  // Input v of mode q at `slot` of the direct block.
  void set_input(std::size_t q, std::size_t slot, cplx v) {
    row(kInputRe, slot)[q] = v.real();
    row(kInputIm, slot)[q] = v.imag();
  }

  // Outputs of modes q0 <= q < q1 at `slot` (>= 1) of the direct block into
  // out_re/out_im[q - q0]: the rows' part plus the direct part of inputs
  // 0..slot-1.
  void gather(std::size_t q0, std::size_t q1, std::size_t slot, double* out_re, double* out_im) const {
    const std::size_t count = q1 - q0;
    const double* part_re = row(kPartRe, slot) + q0;
    const double* part_im = row(kPartIm, slot) + q0;
    for (std::size_t k = 0; k < count; ++k) {
      out_re[k] = part_re[k];
      out_im[k] = part_im[k];
    }
    for (std::size_t i = 0; i < slot; ++i) {
      const double* kernel = row(kKernel, slot - i) + q0;
      const double* in_re = row(kInputRe, i) + q0;
      const double* in_im = row(kInputIm, i) + q0;
#pragma omp simd
      for (std::size_t k = 0; k < count; ++k) {
        out_re[k] += kernel[k] * in_re[k];
        out_im[k] += kernel[k] * in_im[k];
      }
    }
  }

  // The output at slot 0 of a direct block just opened: the rows' part alone.
  cplx first_output(std::size_t q) const { return {row(kPartRe, 0)[q], row(kPartIm, 0)[q]}; }

  // Input tau completed the direct block, whose outputs are all used: its
  // inputs into mode q's input row (before the levels and the far field read
  // them), the used outputs' accumulator entries zeroed (the far field adds
  // into every entry).
  void close(std::size_t q, int tau, BlockRows<1>& rows) const {
    const std::size_t done = static_cast<std::size_t>(tau) + 1 - direct_;
    cplx* in = rows.input_row(0, q) + done;
    cplx* acc = rows.accumulator(0, q) + done;
    for (std::size_t j = 0; j < direct_; ++j) {
      in[j] = cplx(row(kInputRe, j)[q], row(kInputIm, j)[q]);
      acc[j] = 0.0;
    }
  }
  // Every contribution of earlier direct blocks to outputs p..p+D-1 of mode q
  // is in its accumulator row: the direct block opens with them.
  void open(std::size_t q, int p, const BlockRows<1>& rows) {
    const cplx* acc = rows.accumulator(0, q) + p;
    for (std::size_t j = 0; j < direct_; ++j) {
      row(kPartRe, j)[q] = acc[j].real();
      row(kPartIm, j)[q] = acc[j].imag();
    }
  }

  // The state as rows alone: the input rows with the current direct block's
  // inputs so far (position - position % D .. position - 1) written in.
  std::vector<cplx> saved_input(const BlockRows<1>& rows, int position) const {
    const std::span<const cplx> saved = rows.input_rows(0);
    std::vector<cplx> input(saved.begin(), saved.end());
    const std::size_t block = input.size() / std::max<std::size_t>(modes_, 1);
    const std::size_t start = static_cast<std::size_t>(position) - static_cast<std::size_t>(position) % direct_;
    for (std::size_t q = 0; q < modes_; ++q)
      for (std::size_t t = start; t < static_cast<std::size_t>(position); ++t)
        input[q * block + t] = cplx(row(kInputRe, t - start)[q], row(kInputIm, t - start)[q]);
    return input;
  }
  // After the rows were restored and the next push takes input `position`:
  // the direct block as push() left it (its inputs so far and, when the next
  // output is in the same direct block, the rows' part of its outputs).
  void rebuild(const BlockRows<1>& rows, int position) {
    for (int a : {kInputRe, kInputIm, kPartRe, kPartIm}) std::fill(storage_[a].begin(), storage_[a].end(), 0.0);
    const std::size_t start = static_cast<std::size_t>(position) - static_cast<std::size_t>(position) % direct_;
    const bool same_block = (static_cast<std::size_t>(position) + 1) % direct_ != 0;
    for (std::size_t q = 0; q < modes_; ++q) {
      for (std::size_t t = start; t < static_cast<std::size_t>(position); ++t)
        set_input(q, t - start, rows.input(0, q)[t]);
      if (same_block) open(q, static_cast<int>(start), rows);
    }
  }

  std::size_t memory_bytes() const { return sizeof(double) * kArrays * (direct_ * stride_ + kLineDoubles); }

 private:
  // The arrays, each D rows of `stride_` doubles ([j][q]): the inputs so far,
  // the rows' part of the outputs, and O_j of q's design (row 0 unused).
  enum : int { kInputRe, kInputIm, kPartRe, kPartIm, kKernel, kArrays };
  static constexpr std::size_t kLineBytes = 64, kLineDoubles = kLineBytes / sizeof(double);
  static constexpr std::size_t kPageDoubles = 4096 / sizeof(double);
  double* row(int array, std::size_t j) { return row0_[array] + j * stride_; }
  const double* row(int array, std::size_t j) const { return row0_[array] + j * stride_; }

  std::size_t modes_ = 0, direct_ = 0, stride_ = 0;
  std::array<std::vector<double>, kArrays> storage_;
  std::array<double*, kArrays> row0_{};  // row 0 of each array, on a 64-byte boundary
};

}  // namespace slipstrip
