#include "kernels/block_strip_history.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <unordered_map>

#include "kernels/huge_pages.hpp"

namespace slipstrip {
namespace {
using cplx = std::complex<double>;

bool is_power_of_two(int n) { return n > 0 && (n & (n - 1)) == 0; }

// Modes per chunk of the per-step gather: its two output arrays (4 KiB) stay
// in L1 while the direct block's rows stream past.
constexpr std::size_t kModeChunk = 256;

// FNV-1a over the bits of a mode's phases and weights (candidates for a
// shared design are then compared exactly).
std::uint64_t hash_design(std::span<const double> phase, std::span<const double> weight) {
  std::uint64_t h = 14695981039346656037ull;
  for (auto values : {phase, weight})
    for (double x : values) {
      std::uint64_t bits;
      std::memcpy(&bits, &x, sizeof bits);
      h = (h ^ bits) * 1099511628211ull;
    }
  return h;
}
}  // namespace

struct BlockStripHistory::Scratch {
  FftwBuffer<fftw_complex> level;     // 2s <= B inputs, then outputs
  FftwBuffer<fftw_complex> spectrum;  // their spectrum (out-of-place transforms)
  Nufft::Scratch nufft;
  std::vector<cplx> frequency;     // one value per theta_k of a mode
  std::vector<cplx> series;        // B outputs
  std::vector<double> phase_re, phase_im;  // e^{i theta_k B/2} of the located design
  Nufft::PassScratch far;                  // the one-pass far field's grids
};

int automatic_block_length(std::size_t most_normal_modes, int direct_block) {
  int block = 2 * direct_block;
  while (static_cast<std::size_t>(block) < most_normal_modes) block *= 2;
  return block;
}

int body_block_length(std::size_t most_normal_modes, int direct_block, std::size_t fourier_modes) {
  int block = automatic_block_length(most_normal_modes, direct_block);
  if (kBodyBlockBytesPerStep * 2.0 * block * static_cast<double>(fourier_modes) <= kBlockDoublingBytes) block *= 2;
  return std::max(block, kBodyBlockLength);
}

BlockStripHistory::BlockStripHistory(const ElasticMaterial& material, const StripKernels& kernels,
                                     const BlockHistoryDesign& design, const CancelCheck& cancelled)
    : BlockStripHistory(identical_strip_pair(material, kernels.echo_steps), kernels, design, cancelled) {}

BlockStripHistory::BlockStripHistory(const StripPairConstants& constants, const StripKernels& kernels,
                                     const BlockHistoryDesign& design, const CancelCheck& cancelled)
    : dt_(kernels.time_step), eta_(constants.radiation_damping), echo_weight_(constants.running_sum_weight),
      kernels_echo_steps_(kernels.echo_steps), direct_block_(design.direct_block), echo_(constants) {
  const auto& first = kernels.first_oscillator;
  if (first.size() < 2 || first.back() != kernels.weight.size() ||
      kernels.phase.size() != kernels.weight.size() || kernels.echo_steps < 1)
    throw std::invalid_argument("BlockStripHistory: inconsistent kernels");
  if (!is_power_of_two(direct_block_))
    throw std::invalid_argument("BlockStripHistory: direct_block = " + std::to_string(direct_block_) +
                                " must be a power of two");
  n_modes_ = static_cast<int>(first.size()) - 1;

  std::size_t most = 0;
  for (int q = 0; q < n_modes_; ++q) most = std::max(most, first[q + 1] - first[q]);
  block_ = design.block == 0 ? automatic_block_length(most, direct_block_) : design.block;
  if (!is_power_of_two(block_) || block_ < 2 * direct_block_)
    throw std::invalid_argument("BlockStripHistory: block = " + std::to_string(block_) +
                                " must be a power of two >= 2 direct_block");
  const std::size_t B = block_;

  // Frequencies +-phi_m with half weights: sum_m w_m cos(phi_m j) = sum_k (w_k/2) e^{i theta_k j}.
  // Modes whose normal modes are identical (equal |k| on a 2D interface:
  // compute_strip_kernels copies one design to all of them) share one design:
  // frequencies, weights, c0, lag kernel and level spectra.  Only the
  // normal-mode states and the block's inputs and outputs are per mode.
  design_.assign(n_modes_, 0);
  first_frequency_.assign(1, 0);
  first_state_.assign(1, 0);
  std::unordered_map<std::uint64_t, std::vector<std::size_t>> designs_by_hash;
  std::vector<std::size_t> design_mode;  // a mode q of each design (its normal modes in kernels)
  for (int q = 0; q < n_modes_; ++q) {
    throw_if_cancelled(cancelled, "the block history operator");
    const std::size_t m0 = first[q], count = first[q + 1] - m0;
    std::span<const double> phase(kernels.phase.data() + m0, count), weight(kernels.weight.data() + m0, count);
    // q = 0 (no normal modes, its history is the delay line alone) is never shared.
    std::size_t d = design_mode.size();
    if (q > 0) {
      auto& candidates = designs_by_hash[hash_design(phase, weight)];
      for (std::size_t candidate : candidates) {
        const std::size_t c0 = first[design_mode[candidate]];
        if (first[design_mode[candidate] + 1] - c0 == count &&
            std::equal(phase.begin(), phase.end(), kernels.phase.begin() + c0) &&
            std::equal(weight.begin(), weight.end(), kernels.weight.begin() + c0)) {
          d = candidate;
          break;
        }
      }
      if (d == design_mode.size()) candidates.push_back(d);
    }
    design_[q] = d;
    first_state_.push_back(first_state_.back() + 2 * count);
    if (d < design_mode.size()) continue;
    design_mode.push_back(static_cast<std::size_t>(q));
    double weight_sum = 0.0;
    for (std::size_t m = m0; m < m0 + count; ++m) {
      for (double sign : {1.0, -1.0}) {
        theta_.push_back(sign * kernels.phase[m]);
        half_weight_.push_back(0.5 * kernels.weight[m]);
      }
      weight_sum += kernels.weight[m];
    }
    first_frequency_.push_back(theta_.size());
    c0_.push_back(q == 0 ? 0.0 : echo_weight_ + dt_ * weight_sum);
  }
  const std::size_t n_designs = design_mode.size();
  // The large arrays on huge pages (kernels/huge_pages.hpp): the states and
  // the kernel spectra are read per mode once per block or level, each
  // mode's on its own pages.
  assign_on_huge_pages(state_, first_state_.back(), cplx(0.0));
  // The modes of each design, in increasing q.
  design_first_mode_.assign(n_designs + 1, 0);
  for (int q = 0; q < n_modes_; ++q) ++design_first_mode_[design_[q] + 1];
  for (std::size_t d = 0; d < n_designs; ++d) design_first_mode_[d + 1] += design_first_mode_[d];
  design_modes_.resize(n_modes_);
  {
    std::vector<std::size_t> next(design_first_mode_.begin(), design_first_mode_.end() - 1);
    for (int q = 0; q < n_modes_; ++q) design_modes_[next[design_[q]]++] = static_cast<std::size_t>(q);
  }

  nufft_ = std::make_unique<Nufft>(block_, design.nufft_half_width);
  const int threads = std::max(1, omp_get_max_threads());
  for (int t = 0; t < threads; ++t)
    scratch_.push_back({make_fftw_buffer<fftw_complex>(B), make_fftw_buffer<fftw_complex>(B),
                        nufft_->make_scratch(2 * most),
                        std::vector<cplx>(2 * most), std::vector<cplx>(B), std::vector<double>(2 * most),
                        std::vector<double>(2 * most), nufft_->make_pass_scratch(1)});

  // Levels s = direct_block .. B/2.
  std::size_t spectrum_size = 0;
  for (int s = direct_block_; s < block_; s *= 2) {
    levels_.push_back({s, complex_dft_plan(2 * s, FFTW_FORWARD, "BlockStripHistory"),
                       complex_dft_plan(2 * s, FFTW_BACKWARD, "BlockStripHistory"), spectrum_size});
    spectrum_size += n_designs * (s + 1);
  }
  assign_on_huge_pages(spectrum_, spectrum_size, cplx(0.0));

  // Per mode: the lag kernel O_j, j < B, by the adjoint NUFFT (O(P w + B log B)
  // instead of O(P B) cosines); its first direct_block lags are kept for the
  // direct sums, and each level keeps the spectrum of [0, O_1..O_{2s-1}].
  std::vector<double> lag_kernel(n_designs * direct_block_, 0.0);  // [design][j], O_j for j < direct_block
  auto& work = scratch_[0];
  auto* buffer = reinterpret_cast<cplx*>(work.level.get());
  const auto* transformed = reinterpret_cast<const cplx*>(work.spectrum.get());
  for (std::size_t q = 1; q < n_designs; ++q) {  // design 0 is mode 0's (no normal modes)
    throw_if_cancelled(cancelled, "the block history operator");
    const std::size_t f0 = first_frequency_[q], f1 = first_frequency_[q + 1];
    for (std::size_t k = f0; k < f1; ++k) work.frequency[k - f0] = half_weight_[k];
    nufft_->adjoint({theta_.data() + f0, f1 - f0}, {work.frequency.data(), f1 - f0}, work.series,
                    work.nufft);
    for (int j = 1; j < direct_block_; ++j) lag_kernel[q * direct_block_ + j] = work.series[j].real();
    for (const auto& level : levels_) {
      const int s = level.size;
      buffer[0] = 0.0;
      for (int j = 1; j < 2 * s; ++j) buffer[j] = work.series[j].real();
      fftw_execute_dft(level.forward.get(), work.level.get(), work.spectrum.get());
      std::copy(transformed, transformed + s + 1, spectrum_.begin() + level.first_spectrum + q * (s + 1));
    }
  }

  rows_ = BlockRows<1>(static_cast<std::size_t>(n_modes_), block_, direct_block_, false);
  direct_blocks_ = StepMajorDirectBlock(static_cast<std::size_t>(n_modes_), direct_block_,
                                        [&](std::size_t q, int j) { return lag_kernel[design_[q] * direct_block_ + j]; });
  running_sum_.assign(n_modes_, 0.0);
  history_.assign(n_modes_, 0.0);
}

BlockStripHistory::~BlockStripHistory() = default;

ModeOperatorStats BlockStripHistory::stats() const {
  ModeOperatorStats s;
  s.modes = n_modes_;
  s.oscillators = state_.size() / 2;  // normal modes in flight (shared designs counted per mode)
  s.echo_steps = kernels_echo_steps_;
  s.memory_bytes = sizeof(double) * (theta_.size() + half_weight_.size() + c0_.size()) +
                   sizeof(std::size_t) * (design_.size() + first_frequency_.size() + first_state_.size() +
                                          design_first_mode_.size() + design_modes_.size()) +
                   sizeof(cplx) * (state_.size() + spectrum_.size() + running_sum_.size() + echo_.slots() +
                                   history_.size()) +
                   rows_.memory_bytes() + direct_blocks_.memory_bytes() +
                   scratch_.size() * sizeof(cplx) *
                       (4 * static_cast<std::size_t>(block_) + 2 * scratch_[0].frequency.size() +
                        3 * static_cast<std::size_t>(nufft_->grid_size()));
  return s;
}

void BlockStripHistory::convolve_level(int q, std::size_t l, int start, Scratch& scratch) {
  // Inputs start..start+s-1 (an even block of s) to outputs start+s..start+2s-1:
  // lags 1..2s-1, no wrap-around in a circular convolution of length 2s.
  const Level& level = levels_[l];
  const int s = level.size;
  auto* buffer = reinterpret_cast<cplx*>(scratch.level.get());
  const cplx* in = rows_.input(0, q) + start;
  for (int j = 0; j < s; ++j) buffer[j] = in[j];
  for (int j = s; j < 2 * s; ++j) buffer[j] = 0.0;
  fftw_execute_dft(level.forward.get(), scratch.level.get(), scratch.spectrum.get());
  // The kernel is real, so its spectrum is Hermitian: bins s+1..2s-1 are conjugates.
  const cplx* kernel = spectrum_.data() + level.first_spectrum + design_[q] * (s + 1);
  // (Written out: std::complex's operator* checks for NaN/inf in a library call.)
  auto* x = reinterpret_cast<double*>(scratch.spectrum.get());
  const auto* kv = reinterpret_cast<const double*>(kernel);
  for (int j = 0; j <= s; ++j) {
    const double xr = x[2 * j], xi = x[2 * j + 1], kr = kv[2 * j], ki = kv[2 * j + 1];
    x[2 * j] = xr * kr - xi * ki;
    x[2 * j + 1] = xr * ki + xi * kr;
  }
  for (int j = s + 1; j < 2 * s; ++j) {
    const double xr = x[2 * j], xi = x[2 * j + 1];
    const double kr = kv[2 * (2 * s - j)], ki = -kv[2 * (2 * s - j) + 1];
    x[2 * j] = xr * kr - xi * ki;
    x[2 * j + 1] = xr * ki + xi * kr;
  }
  fftw_execute_dft(level.backward.get(), scratch.spectrum.get(), scratch.level.get());
  cplx* out = rows_.accumulator(0, q) + start + s;
  const double scale = 1.0 / (2.0 * s);
  for (int j = 0; j < s; ++j) out[j] += buffer[s + j] * scale;
}

void BlockStripHistory::design_phases(std::size_t d, Scratch& scratch) const {
  // p_k = e^{i theta_k B/2}: once per design and block, for all its modes.
  // The frequencies come in pairs (+phi_m, -phi_m): the second phase of a
  // pair is the first's conjugate, bit for bit (cos is even and sin odd, and
  // (-phi) B/2 = -(phi B/2) exactly), so half the cosines and sines.
  const std::size_t f0 = first_frequency_[d], count = first_frequency_[d + 1] - f0;
  const double* theta = theta_.data() + f0;
  const double half_block = 0.5 * static_cast<double>(block_);
  for (std::size_t k = 0; k < count; k += 2) {
    const double c = std::cos(theta[k] * half_block), s = std::sin(theta[k] * half_block);
    scratch.phase_re[k] = scratch.phase_re[k + 1] = c;
    scratch.phase_im[k] = s;
    scratch.phase_im[k + 1] = -s;
  }
}

void BlockStripHistory::locate_design(std::size_t d, Scratch& scratch) const {
  // The NUFFT kernel weights of the design's frequencies (for both transforms of
  // each of its modes) and its phases.
  const std::size_t f0 = first_frequency_[d], count = first_frequency_[d + 1] - f0;
  nufft_->locate({theta_.data() + f0, count}, scratch.nufft);
  design_phases(d, scratch);
}

void BlockStripHistory::advance_far_field(int q, Scratch& scratch) {
  // A_k(n0 + B) = e^{i theta_k B} [A_k(n0) + sum_t e^{-i theta_k t} v_{n0+t}], then
  // y_far(n0 + B + t) = sum_k (w_k/2) A_k(n0 + B) e^{i theta_k t}, t = 0..B-1.
  // With p_k = e^{i theta_k B/2} and the NUFFT's centred time t - B/2:
  //   sum_t e^{-i theta t} v_t = conj(p) F,   F = forward_centred(v),
  //   A <- p^2 A + p F,   y_far = adjoint_centred(c p),  c = (w/2) A.
  // The kernel weights and p of q's design are in `scratch` (locate_design).
  const std::size_t B = block_;
  const std::size_t d = design_[q];
  const std::size_t f0 = first_frequency_[d], count = first_frequency_[d + 1] - f0;
  if (count == 0) return;
  std::span<cplx> transformed(scratch.frequency.data(), count);
  nufft_->forward_centred({rows_.input(0, q), B}, transformed, scratch.nufft);
  cplx* state = state_.data() + first_state_[q];
  const double* half_weight = half_weight_.data() + f0;
  for (std::size_t k = 0; k < count; ++k) {
    const double pr = scratch.phase_re[k], pi_ = scratch.phase_im[k];
    const double ar = state[k].real(), ai = state[k].imag();
    const double fr = transformed[k].real(), fi = transformed[k].imag();
    // p A + F, then times p
    const double ur = pr * ar - pi_ * ai + fr, ui = pr * ai + pi_ * ar + fi;
    const double nr = pr * ur - pi_ * ui, ni = pr * ui + pi_ * ur;
    state[k] = cplx(nr, ni);
    transformed[k] = cplx(half_weight[k] * (pr * nr - pi_ * ni), half_weight[k] * (pr * ni + pi_ * nr));
  }
  nufft_->adjoint_centred(transformed, scratch.series, scratch.nufft);
  cplx* out = rows_.accumulator(0, q);
  for (std::size_t t = 0; t < B; ++t) out[t] += scratch.series[t];
}

void BlockStripHistory::advance_far_field_in_one_pass(int q, Scratch& scratch) {
  // As advance_far_field, frequency by frequency: F_k from the kernel
  // weights computed there, the state update, and the coefficient spread into
  // the adjoint grid through the same weights.  The design is this mode's
  // alone, so storing its weights for the two transforms would be written and
  // read once each.  The same arithmetic but for the forward sums' order
  // (vector lanes, Nufft::forward_map_adjoint).
  const std::size_t d = design_[q];
  const std::size_t f0 = first_frequency_[d], count = first_frequency_[d + 1] - f0;
  if (count == 0) return;
  cplx* state = state_.data() + first_state_[q];
  const double* half_weight = half_weight_.data() + f0;
  const double *phase_re = scratch.phase_re.data(), *phase_im = scratch.phase_im.data();
  const auto far = [&](std::size_t k, std::array<cplx, 1>& value) {
    const double pr = phase_re[k], pi_ = phase_im[k];
    const double ar = state[k].real(), ai = state[k].imag();
    const double fr = value[0].real(), fi = value[0].imag();
    // p A + F, then times p
    const double ur = pr * ar - pi_ * ai + fr, ui = pr * ai + pi_ * ar + fi;
    const double nr = pr * ur - pi_ * ui, ni = pr * ui + pi_ * ur;
    state[k] = cplx(nr, ni);
    value[0] = cplx(half_weight[k] * (pr * nr - pi_ * ni), half_weight[k] * (pr * ni + pi_ * nr));
  };
  nufft_->forward_map_adjoint<1>({theta_.data() + f0, count}, {rows_.input(0, q)}, {rows_.accumulator(0, q)},
                                 scratch.far, far);
}

void BlockStripHistory::push(std::span<const cplx> slip_rate_spectrum) {
  history_[0] = echo_.push(slip_rate_spectrum[0]);  // uniform mode: exact shear echoes
  const int tau = position_;
  const bool block_done = tau + 1 == block_;
  const int p = block_done ? 0 : tau + 1;  // the output produced by this push
  const int threads = static_cast<int>(scratch_.size());
  const int D = direct_block_;
  // The places in their direct blocks once per step, not an integer division
  // per mode.
  const int slot = p % D;          // p's place in its direct block
  const int input_slot = tau % D;  // tau's
  const std::size_t first_mode = 1, end_mode = static_cast<std::size_t>(n_modes_);

  if (slot != 0) {
    // Inside a direct block: every mode's input into it, and its output
    // gathered from the rows' part and the direct block's inputs so far
    // (kernels/step_major_direct_block.hpp), a chunk of modes in vector lanes.
    // Chunks [c K, (c + 1) K), the first from mode 1: their rows start on
    // 64-byte boundaries (kernels/step_major_direct_block.hpp).
    const std::size_t chunks = (end_mode + kModeChunk - 1) / kModeChunk;
    auto chunk = [&](std::size_t c) {
      const std::size_t q0 = std::max(first_mode, c * kModeChunk), q1 = std::min(end_mode, (c + 1) * kModeChunk);
      for (std::size_t q = q0; q < q1; ++q) {
        const cplx v = slip_rate_spectrum[q];
        direct_blocks_.set_input(q, static_cast<std::size_t>(input_slot), v);
        running_sum_[q] += v;
      }
      double out_re[kModeChunk], out_im[kModeChunk];
      direct_blocks_.gather(q0, q1, static_cast<std::size_t>(slot), out_re, out_im);
      for (std::size_t q = q0; q < q1; ++q)
        history_[q] = c0_[design_[q]] * running_sum_[q] - dt_ * cplx(out_re[q - q0], out_im[q - q0]);
    };
    if (threads == 1) {
      // No parallel region for one thread: libgomp takes a team of one from
      // the heap (and frees it) at every region, and push() must not allocate.
      for (std::size_t c = 0; c < chunks; ++c) chunk(c);
    } else {
#pragma omp parallel for num_threads(threads) schedule(static)
      for (std::size_t c = 0; c < chunks; ++c) chunk(c);
    }
    position_ = p;
    return;
  }

  // Input tau completes its direct block: into the rows and the level
  // convolutions whose inputs it completes.
  auto take_input = [&](int q, Scratch& scratch) {
    const cplx v = slip_rate_spectrum[q];
    direct_blocks_.set_input(static_cast<std::size_t>(q), static_cast<std::size_t>(input_slot), v);
    running_sum_[q] += v;
    direct_blocks_.close(static_cast<std::size_t>(q), tau, rows_);
    for_completed_levels(levels_, tau, [&](std::size_t l, int start) { convolve_level(q, l, start, scratch); });
  };
  // Output p of mode q starts a direct block (after the levels and the far
  // field): the rows' part of its outputs opens it.
  auto give_output = [&](int q) {
    direct_blocks_.open(static_cast<std::size_t>(q), p, rows_);
    history_[q] = c0_[design_[q]] * running_sum_[q] - dt_ * direct_blocks_.first_output(static_cast<std::size_t>(q));
  };
  // The block is complete: every mode's far field moves across it, design by
  // design, so the modes of one design (equal |k|) share one set of NUFFT
  // weights and phases.  (No level fires at the block's end: (tau + 1) % 2s =
  // B % 2s = 0 != s.)  Per mode the same arithmetic as mode by mode.
  // A design of one mode (every design of a 1D interface) takes the one-pass
  // far field instead: its weights would be used by that mode alone.
  auto advance_design = [&](std::size_t d, Scratch& scratch) {
    const std::size_t first = design_first_mode_[d], end = design_first_mode_[d + 1];
    if (end - first == 1) {
      design_phases(d, scratch);
      advance_far_field_in_one_pass(static_cast<int>(design_modes_[first]), scratch);
      give_output(static_cast<int>(design_modes_[first]));
      return;
    }
    locate_design(d, scratch);
    for (std::size_t i = first; i < end; ++i) {
      const int q = static_cast<int>(design_modes_[i]);
      advance_far_field(q, scratch);
      give_output(q);
    }
  };
  const std::size_t designs_end = design_first_mode_.size() - 1;
  if (threads == 1) {
    Scratch& scratch = scratch_[0];
    for (int q = 1; q < n_modes_; ++q) {
      take_input(q, scratch);
      if (!block_done) give_output(q);
    }
    if (block_done)
      for (std::size_t d = 1; d < designs_end; ++d) advance_design(d, scratch);
  } else {
#pragma omp parallel num_threads(threads)
    {
      Scratch& scratch = scratch_[omp_get_thread_num()];
      if (!block_done) {
#pragma omp for schedule(static)
        for (int q = 1; q < n_modes_; ++q) {
          take_input(q, scratch);
          give_output(q);
        }
      } else {
#pragma omp for schedule(static)
        for (int q = 1; q < n_modes_; ++q) take_input(q, scratch);
#pragma omp for schedule(dynamic, 16)
        for (std::size_t d = 1; d < designs_end; ++d) advance_design(d, scratch);
      }
    }
  }
  position_ = p;
}

HistoryOperatorState BlockStripHistory::save_state() const {
  HistoryOperatorState state;
  state.kind = "block strip";
  echo_.save_counters(state);
  state.counters.emplace_back("position", position_);
  state.counters.emplace_back("block", block_);
  state.add("mode_state", state_);
  state.add("input", direct_blocks_.saved_input(rows_, position_));
  state.add("accumulator", rows_.accumulator_rows(0));
  state.add("running_sum", running_sum_);
  echo_.save_arrays(state);
  state.add("history", history_);
  return state;
}

HistoryStateLayout BlockStripHistory::state_layout() const {
  const auto n = static_cast<std::size_t>(n_modes_), block = static_cast<std::size_t>(block_);
  HistoryStateLayout layout;
  layout.add("mode_state", first_state_, 2);
  layout.add_uniform("input", n, 2 * block);
  layout.add_uniform("accumulator", n, 2 * block);
  layout.add_uniform("running_sum", n, 2);
  echo_.add_layout(layout, n);
  layout.add_uniform("history", n, 2);
  return layout;
}

void BlockStripHistory::restore_state(const HistoryOperatorState& state) {
  state.require_kind("block strip");
  const long long position = state.counter("position");
  if (state.counter("block") != block_)
    throw std::invalid_argument("block history state: block = " + std::to_string(state.counter("block")) +
                                ", this operator's is " + std::to_string(block_));
  if (position < 0 || position >= block_)
    throw std::invalid_argument("block history state: position = " + std::to_string(position) + " out of range");
  echo_.check_cursor(state);
  state.copy_to("mode_state", std::span<cplx>(state_));
  state.copy_to("input", rows_.input_rows(0));
  state.copy_to("accumulator", rows_.accumulator_rows(0));
  state.copy_to("running_sum", std::span<cplx>(running_sum_));
  echo_.restore(state);
  state.copy_to("history", std::span<cplx>(history_));
  position_ = static_cast<int>(position);
  direct_blocks_.rebuild(rows_, position_);
}

}  // namespace slipstrip
