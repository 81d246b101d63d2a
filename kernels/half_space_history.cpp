#include "kernels/half_space_history.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "kernels/half_space_kernel.hpp"
#include "kernels/half_space_pair_kernel.hpp"
#include "kernels/slow_block.hpp"
#include "simd/instruction_set.hpp"
#include "simd/parallel_for.hpp"

namespace slipstrip {

namespace {
// Format 2: the slow exponentials in their own arrays (docs/theory.md §8.7),
// the far field at the current step.
constexpr long long kStateFormatPerStep = 2;
// Format 3: the far field advanced to the end of the current batch, its
// outputs for the batch's steps kept (docs/theory.md §8.8).
constexpr long long kStateFormat = 3;

// The fast exponentials' damped rotations [C; S] <- [[c, -s], [s, c]] [C + u; S]
// of poles [m0, m1) over Steps consecutive steps fed with u_d = (ur[d], ui[d]),
// and their outputs sum_m wc C + ws S per step into (out_r[d], out_i[d]).
// Poles in chunks: per step the chunk's rotations and terms wc C + ws S run
// as vectors (the poles are independent; the fused multiply-adds are written
// out, so that every lane and every code shape rounds alike), then the terms
// are summed pole by pole in their order, the steps' sums as independent
// chains.  Each step's arithmetic is therefore the same whatever Steps.
template <int Steps>
[[gnu::always_inline]] inline void rotate_fast(std::size_t m0, std::size_t m1, const double* pole_cos,
                                               const double* pole_sin, const double* weight_cos,
                                               const double* weight_sin, double* c_re, double* c_im, double* s_re,
                                               double* s_im, const double* ur, const double* ui, double* out_r,
                                               double* out_i) {
  constexpr std::size_t kChunk = 64;
  double far_r[Steps], far_i[Steps];
  for (int d = 0; d < Steps; ++d) far_r[d] = far_i[d] = 0.0;
  alignas(64) double term_r[Steps][kChunk], term_i[Steps][kChunk];
  for (std::size_t c0 = m0; c0 < m1; c0 += kChunk) {
    const std::size_t count = std::min(kChunk, m1 - c0);
    const double *pc = pole_cos + c0, *ps = pole_sin + c0, *wc = weight_cos + c0, *ws = weight_sin + c0;
    double *cr = c_re + c0, *ci = c_im + c0, *sr = s_re + c0, *si = s_im + c0;
    for (int d = 0; d < Steps; ++d) {
      const double u_r = ur[d], u_i = ui[d];
      double *tr = term_r[d], *ti = term_i[d];
#pragma omp simd
      for (std::size_t k = 0; k < count; ++k) {
        const double c = pc[k], s = ps[k];
        const double xr = cr[k] + u_r, xi = ci[k] + u_i;
        const double old_sr = sr[k], old_si = si[k];
        const double new_cr = std::fma(c, xr, -(s * old_sr)), new_ci = std::fma(c, xi, -(s * old_si));
        const double new_sr = std::fma(s, xr, c * old_sr), new_si = std::fma(s, xi, c * old_si);
        cr[k] = new_cr;
        ci[k] = new_ci;
        sr[k] = new_sr;
        si[k] = new_si;
        tr[k] = std::fma(wc[k], new_cr, ws[k] * new_sr);
        ti[k] = std::fma(wc[k], new_ci, ws[k] * new_si);
      }
    }
    for (std::size_t k = 0; k < count; ++k)
      for (int d = 0; d < Steps; ++d) {
        far_r[d] += term_r[d][k];
        far_i[d] += term_i[d][k];
      }
  }
  for (int d = 0; d < Steps; ++d) {
    out_r[d] = far_r[d];
    out_i[d] = far_i[d];
  }
}

// The slow kernel's lags applied to the block's own inputs for Steps
// consecutive block positions t0 .. t0 + Steps - 1:
//   acc[d] = sum_{j <= t0 + d} lag[t0 + d - j] input[j],
// each sum in ascending j with fused multiply-adds.  The steps' sums run side
// by side (one vector of Steps accumulators per component over the lags they
// share, then the few lags only the later steps have), so that their latency
// chains overlap instead of following one another: written step by step, each
// sum is one chain of dependent additions and a batch of them leaves the
// core waiting.  Each step's arithmetic is the same whatever Steps.
template <int Steps>
[[gnu::always_inline]] inline void slow_in_block_sums(const double* lag, const std::complex<double>* input, int t0,
                                                      double* out_r, double* out_i) {
  double acc_r[Steps], acc_i[Steps];
  for (int d = 0; d < Steps; ++d) acc_r[d] = acc_i[d] = 0.0;
  for (int j = 0; j <= t0; ++j) {
    const double u_r = input[j].real(), u_i = input[j].imag();
    const double* l = lag + (t0 - j);
#pragma omp simd
    for (int d = 0; d < Steps; ++d) {
      acc_r[d] = std::fma(l[d], u_r, acc_r[d]);
      acc_i[d] = std::fma(l[d], u_i, acc_i[d]);
    }
  }
  for (int e = 1; e < Steps; ++e) {  // input t0 + e: lag d - e of step d >= e
    const double u_r = input[t0 + e].real(), u_i = input[t0 + e].imag();
    for (int d = e; d < Steps; ++d) {
      acc_r[d] = std::fma(lag[d - e], u_r, acc_r[d]);
      acc_i[d] = std::fma(lag[d - e], u_i, acc_i[d]);
    }
  }
  for (int d = 0; d < Steps; ++d) {
    out_r[d] = acc_r[d];
    out_i[d] = acc_i[d];
  }
}

// Longest far-field batch (design.far_batch is clamped to it).
constexpr int kMaxFarBatch = 64;

// Bytes held by a set of vectors (stats().memory_bytes).
template <class... Vectors>
std::size_t bytes_of(const Vectors&... vectors) {
  return (std::size_t{0} + ... + (sizeof(typename Vectors::value_type) * vectors.size()));
}
}  // namespace

namespace {
std::vector<double> interface_wavenumbers(double length, int nodes) {
  if (!(length > 0) || nodes < 2)
    throw std::invalid_argument("HalfSpaceHistory: need length > 0, nodes >= 2, time_step > 0");
  std::vector<double> k(static_cast<std::size_t>(nodes / 2 + 1));
  for (std::size_t q = 0; q < k.size(); ++q) k[q] = 2.0 * std::numbers::pi * static_cast<double>(q) / length;
  return k;
}
}  // namespace

HalfSpaceHistory::HalfSpaceHistory(const ElasticMaterial& material, double length, int nodes,
                                   double time_step, const HalfSpaceOperatorDesign& design,
                                   const CancelCheck& cancelled)
    : HalfSpaceHistory(material, interface_wavenumbers(length, nodes), time_step, design, cancelled) {}

HalfSpaceHistory::HalfSpaceHistory(const ElasticMaterial& material, std::span<const double> wavenumbers,
                                   double time_step, const HalfSpaceOperatorDesign& design,
                                   const CancelCheck& cancelled)
    : HalfSpaceHistory(half_space_shape(material), material.shear_modulus, material.shear_wave_speed(),
                       material.radiation_damping(), wavenumbers, time_step, design, cancelled) {}

namespace {
// The pair's shape and units, its sums checked first when the speeds differ.
AntiplaneHalfSpacePair checked_antiplane_pair(const ElasticMaterial& top, const ElasticMaterial& bottom) {
  AntiplaneHalfSpacePair pair = antiplane_half_space_pair(top, bottom);
  if (pair.shape.antiplane_pair()) verify_antiplane_half_space_pair(pair.shape);
  return pair;
}
}  // namespace

HalfSpaceHistory::HalfSpaceHistory(const ElasticMaterial& top, const ElasticMaterial& bottom, double length,
                                   int nodes, double time_step, const HalfSpaceOperatorDesign& design,
                                   const CancelCheck& cancelled)
    : HalfSpaceHistory(top, bottom, interface_wavenumbers(length, nodes), time_step, design, cancelled) {}

HalfSpaceHistory::HalfSpaceHistory(const ElasticMaterial& top, const ElasticMaterial& bottom,
                                   std::span<const double> wavenumbers, double time_step,
                                   const HalfSpaceOperatorDesign& design, const CancelCheck& cancelled)
    : HalfSpaceHistory(checked_antiplane_pair(top, bottom), wavenumbers, time_step, design, cancelled) {}

HalfSpaceHistory::HalfSpaceHistory(const HalfSpaceShape& shape, double modulus, double speed, double eta,
                                   std::span<const double> wavenumbers, double time_step,
                                   const HalfSpaceOperatorDesign& design, const CancelCheck& cancelled)
    : shape_(shape),
      dt_(time_step),
      eta_(eta),
      instruction_set_(design.instruction_set.value_or(simd::instruction_set())),
      lags_(design.corrected_lags) {
  if (wavenumbers.size() < 2 || wavenumbers[0] != 0.0 || !(time_step > 0) ||
      std::any_of(wavenumbers.begin() + 1, wavenumbers.end(), [](double k) { return !(k > 0.0); }))
    throw std::invalid_argument(
        "HalfSpaceHistory: need the uniform mode 0 first, every other wavenumber > 0, time_step > 0");
  check_half_space_design(design);
  if (!simd::compiled(instruction_set_) || !simd::cpu_supports(instruction_set_))
    throw std::invalid_argument("HalfSpaceHistory: instruction set " +
                                std::string(simd::to_string(instruction_set_)) +
                                " is not compiled into this build or not supported by this CPU");
  if (design.slow_block != 0) {
    block_ = design.slow_block;
    terms_ = design.taylor_terms;
    block_centre_ = 0.5 * (block_ + 1);
  }
  const int n_modes = static_cast<int>(wavenumbers.size());
  const double cs = speed;
  wavenumber_.assign(wavenumbers.begin(), wavenumbers.end());
  h_.assign(n_modes, 0.0);
  for (int q = 1; q < n_modes; ++q) h_[q] = cs * wavenumber_[q] * dt_;
  const std::vector<int> window = half_space_windows(h_, design);
  const std::vector<HalfSpaceModeTerms> terms =
      half_space_mode_terms(shape_, modulus, speed, dt_, h_, window, block_, design, cancelled);
  flatten_fast_terms(terms);
  build_slow_tables(terms);
  // State, all zero: no slip rate before t = 0.
  slow_state_re_.assign(slow_decay_.size(), 0.0);
  slow_state_im_.assign(slow_decay_.size(), 0.0);
  block_input_.assign(static_cast<std::size_t>(n_modes) * block_, 0.0);
  block_moment_.assign(static_cast<std::size_t>(n_modes) * 4 * terms_, 0.0);
  ring_.assign(lag_weight_.size(), 0.0);
  c_re_.assign(pole_cos_.size(), 0.0);
  c_im_.assign(pole_cos_.size(), 0.0);
  s_re_.assign(pole_cos_.size(), 0.0);
  s_im_.assign(pole_cos_.size(), 0.0);
  running_sum_.assign(n_modes, 0.0);
  history_.assign(n_modes, 0.0);
  // The far field's batch: at most design.far_batch steps, at most the
  // shortest window (its inputs, delayed by W, must be in the ring when it
  // starts), and a divisor of the slow block (no batch straddles a block end).
  // At most kMaxFarBatch: the batch's inputs and fast sums live on the stack.
  if (design.far_batch < 1) throw std::invalid_argument("HalfSpaceHistory: need design.far_batch >= 1");
  std::size_t shortest = static_cast<std::size_t>(std::min(design.far_batch, kMaxFarBatch));
  for (int q = 1; q < n_modes; ++q) shortest = std::min(shortest, first_lag_[q + 1] - first_lag_[q]);
  batch_ = static_cast<int>(std::max<std::size_t>(shortest, 1));
  while (block_ > 0 && block_ % batch_ != 0) --batch_;
  far_out_.assign(static_cast<std::size_t>(n_modes) * batch_, 0.0);
  slow_out_.assign(static_cast<std::size_t>(n_modes) * batch_, 0.0);
}

void HalfSpaceHistory::flatten_fast_terms(const std::vector<HalfSpaceModeTerms>& terms) {
  // Per-mode vectors into flat arrays, contiguous per mode in q order.
  const int n_modes = static_cast<int>(terms.size());
  static_weight_.assign(n_modes, 0.0);
  first_lag_.assign(1, 0);
  first_pole_.assign(1, 0);
  correction_.assign(static_cast<std::size_t>(n_modes) * lags_, 0.0);
  for (int q = 0; q < n_modes; ++q) {
    const HalfSpaceModeTerms& t = terms[q];
    static_weight_[q] = t.static_weight;
    lag_weight_.insert(lag_weight_.end(), t.lag_weight.begin(), t.lag_weight.end());
    first_lag_.push_back(lag_weight_.size());
    for (std::size_t i = 0; i < t.correction.size(); ++i) correction_[q * lags_ + i] = t.correction[i];
    for (std::size_t m = 0; m < t.pole.size(); ++m) {
      pole_cos_.push_back(t.pole[m].real());
      pole_sin_.push_back(t.pole[m].imag());
      // 2 Re(w z^i) = 2 Re w Re z^i - 2 Im w Im z^i, with C = sum Re z^i u, S = sum Im z^i u.
      weight_cos_.push_back(2.0 * t.pole_weight[m].real());
      weight_sin_.push_back(-2.0 * t.pole_weight[m].imag());
    }
    first_pole_.push_back(pole_cos_.size());
  }
}

void HalfSpaceHistory::build_slow_tables(const std::vector<HalfSpaceModeTerms>& terms) {
  // docs/theory.md §8.7.
  const int n_modes = static_cast<int>(terms.size());
  first_slow_.assign(1, 0);
  slow_shear_end_.assign(n_modes, 0);
  slow_lag_weight_.assign(static_cast<std::size_t>(n_modes) * block_, 0.0);
  for (int q = 0; q < n_modes; ++q) {
    const HalfSpaceModeTerms& t = terms[q];
    const double h = h_[q];
    slow_shear_end_[q] = first_slow_.back() + t.slow_shear;
    for (std::size_t m = 0; m < t.slow_rate.size(); ++m) {
      const std::complex<double> rate = t.slow_rate[m], w = t.slow_weight[m];
      const std::complex<double> z = std::exp(rate * h);
      slow_decay_.push_back(-rate.real() * h);
      slow_centre_factor_.push_back(std::exp(rate.real() * h * block_centre_));
      slow_pole_.push_back(z);
      slow_weight_.push_back(w);
      slow_block_pole_.push_back(std::exp(rate * (h * block_)));
      // In-block lags: 2 Re w z^{i+1}, i = 0..B-1 (the exact powers).
      double* lag = slow_lag_weight_.data() + static_cast<std::size_t>(q) * block_;
      for (int i = 0; i < block_; ++i) lag[i] += 2.0 * (w * std::exp(rate * (h * (i + 1)))).real();
    }
    first_slow_.push_back(slow_decay_.size());
  }
  // The second branch's frequency: c_d / c_s (antiplane: no P poles, the
  // table's second column multiplies zero moments); an antiplane pair of
  // different speeds: c_slow / c_ref.
  rotation_ = slow_block_rotations(h_, half_space_second_branch(shape_), block_);
}

ModeOperatorStats HalfSpaceHistory::stats() const {
  ModeOperatorStats s;
  s.modes = history_.size();
  s.oscillators = pole_cos_.size() + slow_decay_.size();
  s.direct_lags = lag_weight_.size();
  s.memory_bytes = bytes_of(wavenumber_, h_, static_weight_, first_lag_, lag_weight_, correction_, first_pole_,
                            pole_cos_, pole_sin_, weight_cos_, weight_sin_, ring_, c_re_, c_im_, s_re_, s_im_,
                            running_sum_, first_slow_, slow_shear_end_, slow_decay_, slow_centre_factor_,
                            slow_pole_, slow_weight_, slow_block_pole_, slow_lag_weight_, rotation_,
                            slow_state_re_, slow_state_im_, block_input_, block_moment_, far_out_, slow_out_,
                            history_);
  return s;
}

HalfSpaceModeKernel HalfSpaceHistory::mode_kernel(int q) const {
  if (q < 1 || q >= modes()) throw std::out_of_range("HalfSpaceHistory::mode_kernel: q out of range");
  HalfSpaceModeKernel k;
  k.wavenumber = wavenumber_[q];
  k.h = h_[q];
  k.static_weight = static_weight_[q];
  k.lag_weight.assign(lag_weight_.begin() + first_lag_[q], lag_weight_.begin() + first_lag_[q + 1]);
  k.correction.assign(correction_.begin() + q * lags_, correction_.begin() + (q + 1) * lags_);
  for (std::size_t m = first_pole_[q]; m < first_pole_[q + 1]; ++m) {
    k.pole.emplace_back(pole_cos_[m], pole_sin_[m]);
    k.pole_weight.emplace_back(0.5 * weight_cos_[m], -0.5 * weight_sin_[m]);
  }
  for (std::size_t m = first_slow_[q]; m < first_slow_[q + 1]; ++m) {
    k.pole.push_back(slow_pole_[m]);
    k.pole_weight.push_back(slow_weight_[m]);
  }
  return k;
}

void HalfSpaceHistory::push(std::span<const std::complex<double>> slip_rate_spectrum) {
  const int n_modes = static_cast<int>(history_.size());
  history_[0] = 0.0;  // uniform mode: radiation damping only
  // Modes in chunks of 32 handed to the threads in turn: the cost per mode
  // grows with q, so contiguous halves would load one thread more.
  constexpr int kModeChunk = 32;
  const int chunks = (n_modes - 1 + kModeChunk - 1) / kModeChunk;
  const simd::InstructionSet set = instruction_set_;
  const std::complex<double>* v = slip_rate_spectrum.data();
  position_ = static_cast<int>(step_ % batch_);
  const auto advance_chunk = [&](long long k) {
    const int q_begin = 1 + static_cast<int>(k) * kModeChunk, q_end = std::min(n_modes, q_begin + kModeChunk);
    switch (set) {
#if SLIPSTRIP_X86_DISPATCH
      case simd::InstructionSet::avx512:
        advance_modes_avx512(q_begin, q_end, v);
        break;
      case simd::InstructionSet::avx2:
        advance_modes_avx2(q_begin, q_end, v);
        break;
#endif
      default:
        advance_modes_baseline(q_begin, q_end, v);
        break;
    }
  };
  simd::parallel_for(chunks, advance_chunk, 1);
  ++step_;
}

[[gnu::always_inline]] inline void HalfSpaceHistory::advance_mode(int q, const std::complex<double> v) {
  // Ring buffer of the last W slip rates: slot n mod W holds v_{n-W} (leaving
  // for the far field) and receives v_n.
  const std::size_t base = first_lag_[q];
  const std::size_t W = first_lag_[q + 1] - base;
  const int position = position_;
  // The far field of this batch, before this step's input replaces v_{n-W}.
  if (position == 0) advance_far(q, step_, 0, batch_);
  const std::size_t slot = static_cast<std::size_t>(step_ % static_cast<long long>(W));
  std::complex<double>* ring = ring_.data() + base;
  ring[slot] = v;
  // Stored lags: K_j v_{n+1-j}, j = 1..W; v_{n+1-j} sits in slot (n+1-j) mod W.
  const double* w = lag_weight_.data() + base;
  double near_r = 0.0, near_i = 0.0;
  std::size_t j = 0;
  for (std::size_t s = slot + 1; s-- > 0; ++j) {
    near_r += w[j] * ring[s].real();
    near_i += w[j] * ring[s].imag();
  }
  for (std::size_t s = W; s-- > slot + 1; ++j) {
    near_r += w[j] * ring[s].real();
    near_i += w[j] * ring[s].imag();
  }
  const std::size_t at = static_cast<std::size_t>(q) * batch_ + position;
  const std::complex<double> far = far_out_[at];
  running_sum_[q] += v;
  history_[q] = static_weight_[q] * running_sum_[q] + std::complex<double>(near_r + far.real(), near_i + far.imag()) +
                slow_out_[at];
}

[[gnu::always_inline]] inline void HalfSpaceHistory::advance_far(int q, long long batch_step, int first, int last) {
  const int n_modes = static_cast<int>(history_.size());
  const std::size_t base = first_lag_[q];
  const std::size_t W = first_lag_[q + 1] - base;
  const std::complex<double>* ring = ring_.data() + base;
  std::complex<double>* far_out = far_out_.data() + static_cast<std::size_t>(q) * batch_;
  std::complex<double>* slow_out = slow_out_.data() + static_cast<std::size_t>(q) * batch_;
  // v_{n-W} of the batch's steps, still in the ring (the batch is at most W
  // steps long).
  double ur[kMaxFarBatch], ui[kMaxFarBatch], far_r[kMaxFarBatch], far_i[kMaxFarBatch];
  // Slots and block positions counted on from the batch's first step (one
  // 64-bit division each per batch instead of per step).
  std::size_t slot = static_cast<std::size_t>((batch_step + first) % static_cast<long long>(W));
  for (int d = first; d < last; ++d) {
    ur[d] = ring[slot].real();
    ui[d] = ring[slot].imag();
    if (++slot == W) slot = 0;
  }
  // Fast exponentials: damped rotations fed with v_{n-W}, eight steps per pass
  // over the poles, the rest one at a time (the same arithmetic per step).
  const std::size_t m0 = first_pole_[q], m1 = first_pole_[q + 1];
  const auto fast = [&]<int Steps>(int d) {
    rotate_fast<Steps>(m0, m1, pole_cos_.data(), pole_sin_.data(), weight_cos_.data(), weight_sin_.data(),
                       c_re_.data(), c_im_.data(), s_re_.data(), s_im_.data(), ur + d, ui + d, far_r + d, far_i + d);
  };
  int d = first;
  for (; d + 8 <= last; d += 8) fast.template operator()<8>(d);
  for (; d < last; ++d) fast.template operator()<1>(d);
  const int t_first = block_ > 0 ? static_cast<int>((batch_step + first) % block_) : 0;
  // Slow exponentials: at block position t (t' = t + 1 steps after the block
  // start) their output is sum over branches of rho^{t'} P_beta(t' - t_c),
  // with P_beta the Taylor polynomial of the block-start states, plus the
  // slow kernel's lags 0..t applied to this block's inputs (the batch lies in
  // one block: its inputs are stored first, then its in-block sums worked
  // together).
  std::complex<double>* input = block_input_.data() + static_cast<std::size_t>(q) * block_;
  double in_r[kMaxFarBatch], in_i[kMaxFarBatch];
  if (block_ > 0) {
    for (int d = first; d < last; ++d) input[t_first + (d - first)] = std::complex<double>(ur[d], ui[d]);
    const double* lag = slow_lag_weight_.data() + static_cast<std::size_t>(q) * block_;
    const auto in_block = [&]<int Steps>(int d) {
      slow_in_block_sums<Steps>(lag, input, t_first + (d - first), in_r + d, in_i + d);
    };
    d = first;
    for (; d + 8 <= last; d += 8) in_block.template operator()<8>(d);
    for (; d < last; ++d) in_block.template operator()<1>(d);
  }
  for (int d = first; d < last; ++d) {
    far_out[d] = std::complex<double>(far_r[d], far_i[d]);
    std::complex<double> slow = 0.0;
    if (block_ > 0) {
      const int t = t_first + (d - first);
      const double x = (t + 1) - block_centre_;
      const std::complex<double>* moment = block_moment_.data() + static_cast<std::size_t>(q) * 4 * terms_;
      // Polynomial beta = 2 b + c: branch b (shear, P), component c (Re, Im of
      // the slip rate, kept apart so that a real kernel maps real to real exactly).
      const std::size_t at = (static_cast<std::size_t>(t) * n_modes + q) * 2;
      double out[2];
      slow_block_output<2>(moment, terms_, x, rotation_[at], rotation_[at + 1], out);
      slow = std::complex<double>(out[0], out[1]) + std::complex<double>(in_r[d], in_i[d]);
    }
    slow_out[d] = slow;
  }
  // A batch ends at a block end or before it (the batch divides the block):
  // the block's last step was this batch's last.
  if (block_ > 0 && last > first && (batch_step + last) % block_ == 0) push_slow_block_end(q);
}

void HalfSpaceHistory::advance_modes_baseline(int q_begin, int q_end, const std::complex<double>* v) {
  for (int q = q_begin; q < q_end; ++q) advance_mode(q, v[q]);
}

#if SLIPSTRIP_X86_DISPATCH
SLIPSTRIP_TARGET_AVX2 void HalfSpaceHistory::advance_modes_avx2(int q_begin, int q_end,
                                                                 const std::complex<double>* v) {
  for (int q = q_begin; q < q_end; ++q) advance_mode(q, v[q]);
}

SLIPSTRIP_TARGET_AVX512 void HalfSpaceHistory::advance_modes_avx512(int q_begin, int q_end,
                                                                     const std::complex<double>* v) {
  for (int q = q_begin; q < q_end; ++q) advance_mode(q, v[q]);
}
#endif

[[gnu::always_inline]] inline void HalfSpaceHistory::push_slow_block_end(int q) {
  // Per branch b and component c of the slip rate (Re, Im; polynomial beta = 2 b + c):
  //   mu_{beta,p} = sum_{j=1..B} (j - t_c)^p rho_b^j u_c(B - j)      (u(s) = block input s)
  // then per slow exponential and component
  //   Y_c <- z^B Y_c + e^{-lambda t_c} sum_p (-lambda)^p / p! mu_{beta,p}
  // and the next block's polynomial coefficients
  //   M_{beta,p} = sum_m w e^{-lambda t_c} (-lambda)^p / p! Y_c;
  // the kernel's contribution is then 2 Re sum_b rho_b^{t'} sum_p (t' - t_c)^p M_{beta,p}.
  const std::size_t n_modes = history_.size();
  const std::complex<double>* input = block_input_.data() + static_cast<std::size_t>(q) * block_;
  std::array<std::complex<double>, 4 * kMaxTaylorTerms> mu{};
  slow_input_moments(input, rotation_.data(), n_modes, static_cast<std::size_t>(q), block_, block_centre_, terms_,
                     mu.data());
  std::complex<double>* moment = block_moment_.data() + static_cast<std::size_t>(q) * 4 * terms_;
  std::fill(moment, moment + 4 * terms_, std::complex<double>(0.0));
  std::array<double, kMaxTaylorTerms> factor{};
  for (std::size_t m = first_slow_[q]; m < first_slow_[q + 1]; ++m) {
    const int branch = m < slow_shear_end_[q] ? 0 : 1;
    slow_taylor_factors(slow_centre_factor_[m], slow_decay_[m], terms_, factor.data());
    advance_slow_state(factor.data(), mu.data(), branch, terms_, slow_block_pole_[m], slow_state_re_[m],
                       slow_state_im_[m]);
    // Output channels Re, Im: polynomial beta = 2 b + c.
    add_slow_moment(factor.data(), slow_weight_[m] * slow_state_re_[m], terms_, moment + (2 * branch) * terms_);
    add_slow_moment(factor.data(), slow_weight_[m] * slow_state_im_[m], terms_, moment + (2 * branch + 1) * terms_);
  }
}

HistoryOperatorState HalfSpaceHistory::save_state() const {
  HistoryOperatorState state;
  state.kind = "half-space";
  // Format 3 (format 2 is still read); a restart point of the earlier
  // every-step operator has no format counter and is refused with that reason
  // instead of a confusing array size.
  state.counters.emplace_back("format", kStateFormat);
  // The far field is advanced to the end of the current batch (its states,
  // the block's inputs and polynomials), its outputs for the batch's steps
  // kept in far_out and slow_out.
  state.counters.emplace_back("far_batch", batch_);
  state.add("far_out", far_out_);
  state.add("slow_out", slow_out_);
  // The step count places the ring buffers' cursor (slot = step mod W_q).
  state.counters.emplace_back("step", step_);
  state.add("ring", ring_);
  state.add("c_re", c_re_);
  state.add("c_im", c_im_);
  state.add("s_re", s_re_);
  state.add("s_im", s_im_);
  state.add("running_sum", running_sum_);
  state.add("history", history_);
  state.add("slow_state_re", slow_state_re_);
  state.add("slow_state_im", slow_state_im_);
  state.add("block_input", block_input_);
  state.add("block_moment", block_moment_);
  return state;
}

HistoryStateLayout HalfSpaceHistory::state_layout() const {
  const std::size_t n = history_.size();
  HistoryStateLayout layout;
  layout.add("ring", first_lag_, 2);
  for (const char* name : {"c_re", "c_im", "s_re", "s_im"}) layout.add(name, first_pole_, 1);
  layout.add_uniform("running_sum", n, 2);
  layout.add_uniform("history", n, 2);
  layout.add("slow_state_re", first_slow_, 2);
  layout.add("slow_state_im", first_slow_, 2);
  layout.add_uniform("block_input", n, 2 * static_cast<std::size_t>(block_));
  layout.add_uniform("block_moment", n, 2 * 4 * static_cast<std::size_t>(terms_));
  layout.add_uniform("far_out", n, 2 * static_cast<std::size_t>(batch_));
  layout.add_uniform("slow_out", n, 2 * static_cast<std::size_t>(batch_));
  return layout;
}

void HalfSpaceHistory::restore_state(const HistoryOperatorState& state) {
  // An antiplane pair of half-spaces is one operator (time.antiplane_pair =
  // "combined") or TwoBodyHistory's two ("bodies"): name the setting.
  if (state.kind == "two bodies")
    throw std::invalid_argument("history operator state: the restart point holds the two bodies' operators, this "
                                "run one half-space operator (time.antiplane_pair = \"combined\"); resume it "
                                "with the setting that wrote it");
  state.require_kind("half-space");
  const bool has_format = std::any_of(state.counters.begin(), state.counters.end(),
                                      [](const auto& c) { return c.first == "format"; });
  const long long format = has_format ? state.counter("format") : 0;
  if (format != kStateFormat && format != kStateFormatPerStep)
    throw std::invalid_argument(
        "history operator state: this half-space restart point was written by a slipstrip older than the "
        "blocked half-space operator (docs/theory.md §8.7; its state has neither format " +
        std::to_string(kStateFormatPerStep) + " nor " + std::to_string(kStateFormat) +
        ") and cannot be resumed by this version; rerun the case from the start, or resume it with the "
        "version that wrote it");
  if (format == kStateFormat && state.counter("far_batch") != batch_)
    throw std::invalid_argument("history operator state: the half-space restart point has far-field batch " +
                                std::to_string(state.counter("far_batch")) + ", this operator " +
                                std::to_string(batch_) + "; it cannot be resumed with another far-field batch");
  const long long step = state.counter("step");
  if (step < 0) throw std::invalid_argument("half-space history state: step = " + std::to_string(step) + " < 0");
  state.copy_to("ring", std::span<std::complex<double>>(ring_));
  state.copy_to("c_re", std::span<double>(c_re_));
  state.copy_to("c_im", std::span<double>(c_im_));
  state.copy_to("s_re", std::span<double>(s_re_));
  state.copy_to("s_im", std::span<double>(s_im_));
  state.copy_to("running_sum", std::span<std::complex<double>>(running_sum_));
  state.copy_to("history", std::span<std::complex<double>>(history_));
  state.copy_to("slow_state_re", std::span<std::complex<double>>(slow_state_re_));
  state.copy_to("slow_state_im", std::span<std::complex<double>>(slow_state_im_));
  state.copy_to("block_input", std::span<std::complex<double>>(block_input_));
  state.copy_to("block_moment", std::span<std::complex<double>>(block_moment_));
  step_ = step;
  if (format == kStateFormat) {
    state.copy_to("far_out", std::span<std::complex<double>>(far_out_));
    state.copy_to("slow_out", std::span<std::complex<double>>(slow_out_));
    return;
  }
  // Format 2 holds the far field at this step: advanced here over the rest of
  // the current batch, as push() would have at the batch's start.
  const int position = static_cast<int>(step_ % batch_);
  if (position != 0)
    for (int q = 1; q < modes(); ++q) advance_far(q, step_ - position, position, batch_);
}

}  // namespace slipstrip
