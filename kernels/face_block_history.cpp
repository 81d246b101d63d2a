#include "kernels/face_block_history.hpp"

#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace slipstrip {
namespace {
using cplx = std::complex<double>;

bool is_power_of_two(int n) { return n > 0 && (n & (n - 1)) == 0; }

// The real entries (a, b, d) of a Hermitian weight [[a, i b], [-i b, d]]; throws
// if the weight is not of that form (to rounding), since the block operator
// keeps only these three real kernels.
void check_structure(const FaceMatrix& w) {
  const double scale = w.max_abs();
  const double off = std::max({std::abs(w.xx.imag()), std::abs(w.yy.imag()), std::abs(w.xy.real()),
                               std::abs(w.yx.real()), std::abs(w.xy.imag() + w.yx.imag())});
  if (off > 1e-14 * scale)
    throw std::logic_error("FaceBlockHistory: a discrete mode weight is not of the form [[a, i b], [-i b, d]]");
}

// (x, y) * (k, l) written out (std::complex's operator* calls a NaN/inf check).
inline void multiply_add(double kr, double ki, double xr, double xi, double& out_r, double& out_i) {
  out_r += kr * xr - ki * xi;
  out_i += kr * xi + ki * xr;
}

// Bin k of the length-2s spectra of the three real kernels (stored for bins
// 0..s; bins s+1..2s-1 are the conjugates of s-1..1) times the input spectra's
// values x[j], y[j], in place: out_x = A X + i B Y,  out_y = -i B X + D Y.
inline void spectral_product(const double* ka, const double* kb, const double* kd, int s, int k, double* x,
                             double* y, int j) {
  const int bin = k <= s ? k : 2 * s - k;
  const double sign = k <= s ? 1.0 : -1.0;
  const double ar = ka[2 * bin], ai = sign * ka[2 * bin + 1];
  const double br = kb[2 * bin], bi = sign * kb[2 * bin + 1];
  const double dr = kd[2 * bin], di = sign * kd[2 * bin + 1];
  const double xr = x[2 * j], xi = x[2 * j + 1], yr = y[2 * j], yi = y[2 * j + 1];
  double ox_r = 0.0, ox_i = 0.0, oy_r = 0.0, oy_i = 0.0;
  multiply_add(ar, ai, xr, xi, ox_r, ox_i);
  multiply_add(-bi, br, yr, yi, ox_r, ox_i);  // i B
  multiply_add(bi, -br, xr, xi, oy_r, oy_i);  // -i B
  multiply_add(dr, di, yr, yi, oy_r, oy_i);
  x[2 * j] = ox_r;
  x[2 * j + 1] = ox_i;
  y[2 * j] = oy_r;
  y[2 * j + 1] = oy_i;
}
}  // namespace

struct FaceBlockHistory::Scratch {
  FftwBuffer<fftw_complex> level_x, level_y;        // 2s <= B inputs, then outputs, each
  FftwBuffer<fftw_complex> spectrum_x, spectrum_y;  // their spectra (out-of-place transforms)
  Nufft::PassScratch far;                           // the far field's NUFFT grids, both components
};

FaceBlockHistory::FaceBlockHistory(const ElasticMaterial& m, double height, OuterFace face, double length,
                                   int nodes, double time_step, const FaceBlockDesign& design,
                                   const CancelCheck& cancelled)
    : dt_(time_step),
      impedance_x_(m.shear_modulus / m.shear_wave_speed()),
      impedance_y_(m.density * m.dilatational_wave_speed()),
      direct_block_(design.direct_block) {
  if (!is_power_of_two(direct_block_))
    throw std::invalid_argument("FaceBlockHistory: direct_block = " + std::to_string(direct_block_) +
                                " must be a power of two");
  n_modes_ = nodes / 2 + 1;
  // The discrete modes of every Fourier mode, as FaceModalHistory has them.
  std::vector<double> phase;
  std::vector<FaceMatrix> weight;
  std::vector<std::size_t> first(1, 0);
  for (int q = 0; q < n_modes_; ++q) {
    throw_if_cancelled(cancelled, "the block face history operator");
    const auto d = face_discrete_modes(m, height, face, 2.0 * std::numbers::pi * q / length, dt_);
    phase.insert(phase.end(), d.phase.begin(), d.phase.end());
    weight.insert(weight.end(), d.weight.begin(), d.weight.end());
    first.push_back(phase.size());
  }
  std::size_t most = 0;
  for (int q = 0; q < n_modes_; ++q) most = std::max(most, first[q + 1] - first[q]);
  block_ = design.block;
  if (block_ == 0) {
    block_ = 2 * direct_block_;
    while (static_cast<std::size_t>(block_) < most) block_ *= 2;
  }
  if (!is_power_of_two(design.split_level))
    throw std::invalid_argument("FaceBlockHistory: split_level = " + std::to_string(design.split_level) +
                                " must be a power of two");
  if (!is_power_of_two(design.bin_order_level))
    throw std::invalid_argument("FaceBlockHistory: bin_order_level = " + std::to_string(design.bin_order_level) +
                                " must be a power of two");
  if (!is_power_of_two(block_) || block_ < 2 * direct_block_)
    throw std::invalid_argument("FaceBlockHistory: block = " + std::to_string(block_) +
                                " must be a power of two >= 2 direct_block");
  const std::size_t B = block_;

  // Frequencies +-phi_m with half weights: sum_m W_m cos(phi_m j) = sum_k (W_k/2) e^{i theta_k j}.
  // C0 = 2E + dt sum_m W_m, summed in FaceModalHistory's order.
  first_frequency_.assign(1, 0);
  c0_a_.assign(n_modes_, 0.0);
  c0_b_ = c0_d_ = c0_a_;
  for (int q = 0; q < n_modes_; ++q) {
    FaceMatrix sum;
    for (std::size_t i = first[q]; i < first[q + 1]; ++i) {
      check_structure(weight[i]);
      for (double sign : {1.0, -1.0}) {
        theta_.push_back(sign * phase[i]);
        half_a_.push_back(0.5 * weight[i].xx.real());
        half_b_.push_back(0.5 * weight[i].xy.imag());
        half_d_.push_back(0.5 * weight[i].yy.real());
      }
      sum = sum + weight[i];
    }
    first_frequency_.push_back(theta_.size());
    c0_a_[q] = 2.0 * impedance_x_ + dt_ * sum.xx.real();
    c0_b_[q] = dt_ * sum.xy.imag();
    c0_d_[q] = 2.0 * impedance_y_ + dt_ * sum.yy.real();
  }
  state_x_.assign(theta_.size(), 0.0);
  state_y_ = state_x_;
  // p_k = e^{i theta_k B/2}, once (the far field needs it at every block end).
  for (double theta : theta_) {
    half_block_phase_re_.push_back(std::cos(theta * 0.5 * static_cast<double>(B)));
    half_block_phase_im_.push_back(std::sin(theta * 0.5 * static_cast<double>(B)));
  }

  nufft_ = std::make_unique<Nufft>(block_, design.nufft_half_width, design.nufft_interleave_from);
  const int threads = std::max(1, omp_get_max_threads());
  for (int t = 0; t < threads; ++t)
    scratch_.push_back({make_fftw_buffer<fftw_complex>(B), make_fftw_buffer<fftw_complex>(B),
                        make_fftw_buffer<fftw_complex>(B), make_fftw_buffer<fftw_complex>(B),
                        nufft_->make_pass_scratch(2)});

  // Per level: its transforms (length 2s, or s for a split level), a split
  // level's twiddles e^{-i pi j / s}, j < s, and the length-2s forward
  // transform that gives the kernels' spectra here (construction only).
  std::size_t spectrum_size = 0, twiddle_size = 0;
  std::vector<FftwPlan> kernel_plans;
  for (int s = direct_block_; s < block_; s *= 2) {
    const bool split = s >= design.split_level;
    const bool bin_order = split && s >= design.bin_order_level;
    const int length = split ? s : 2 * s;
    if (bin_order)
      // Forward: the two halves (even and odd bins, contiguous inputs s apart)
      // into one spectrum of 2s points in bin order (stride 2); backward: from
      // it into the two halves' outputs interleaved (stride 2 both sides).
      levels_.push_back({s, true, true,
                         strided_pair_dft_plan(s, 1, s, 2, 1, FFTW_FORWARD, "FaceBlockHistory"),
                         strided_pair_dft_plan(s, 2, 1, 2, 1, FFTW_BACKWARD, "FaceBlockHistory"), spectrum_size,
                         twiddle_size});
    else
      levels_.push_back({s, split, false, complex_dft_plan(length, FFTW_FORWARD, "FaceBlockHistory"),
                         complex_dft_plan(length, FFTW_BACKWARD, "FaceBlockHistory"), spectrum_size,
                         twiddle_size});
    kernel_plans.push_back(complex_dft_plan(2 * s, FFTW_FORWARD, "FaceBlockHistory"));
    spectrum_size += static_cast<std::size_t>(n_modes_) * (s + 1);
    if (!split) continue;
    for (int j = 0; j < s; ++j) {
      const double angle = -std::numbers::pi * j / s;
      twiddle_.emplace_back(std::cos(angle), std::sin(angle));
    }
    twiddle_size += static_cast<std::size_t>(s);
  }
  spectrum_a_.assign(spectrum_size, 0.0);
  spectrum_b_ = spectrum_d_ = spectrum_a_;

  // Per mode and kernel: the lags K_j, j < B, by the adjoint NUFFT; the first
  // direct_block lags for the direct sums, and per level the spectrum of
  // [0, K_1..K_{2s-1}].
  lags_.assign(3 * static_cast<std::size_t>(n_modes_) * direct_block_, 0.0);
  auto& work = scratch_[0];
  Nufft::Scratch lag_nufft = nufft_->make_scratch(2 * most);
  std::vector<cplx> half_weights(2 * most), lag_series(B);
  auto* buffer = reinterpret_cast<cplx*>(work.level_x.get());
  const auto* transformed = reinterpret_cast<const cplx*>(work.spectrum_x.get());
  const struct {
    const std::vector<double>* half;
    std::size_t lag;  // its place in lags_' [a, b, d]
    std::vector<cplx>* spectrum;
  } kernels[3] = {{&half_a_, 0, &spectrum_a_}, {&half_b_, 1, &spectrum_b_}, {&half_d_, 2, &spectrum_d_}};
  for (int q = 0; q < n_modes_; ++q) {
    throw_if_cancelled(cancelled, "the block face history operator");
    const std::size_t f0 = first_frequency_[q], f1 = first_frequency_[q + 1];
    for (const auto& kernel : kernels) {
      for (std::size_t k = f0; k < f1; ++k) half_weights[k - f0] = (*kernel.half)[k];
      std::fill(lag_series.begin(), lag_series.end(), cplx(0.0));
      if (f1 > f0)
        nufft_->adjoint({theta_.data() + f0, f1 - f0}, {half_weights.data(), f1 - f0}, lag_series, lag_nufft);
      for (int j = 1; j < direct_block_; ++j)
        lags_[(3 * static_cast<std::size_t>(q) + kernel.lag) * direct_block_ + j] = lag_series[j].real();
      for (std::size_t l = 0; l < levels_.size(); ++l) {
        const Level& level = levels_[l];
        const int s = level.size;
        buffer[0] = 0.0;
        for (int j = 1; j < 2 * s; ++j) buffer[j] = lag_series[j].real();
        fftw_execute_dft(kernel_plans[l].get(), work.level_x.get(), work.spectrum_x.get());
        std::copy(transformed, transformed + s + 1,
                  kernel.spectrum->begin() + level.first_spectrum + q * (s + 1));
      }
    }
  }

  rows_ = BlockRows<2>(static_cast<std::size_t>(n_modes_), block_, direct_block_);
  running_x_.assign(n_modes_, 0.0);
  running_y_ = history_x_ = history_y_ = running_x_;
}

FaceBlockHistory::~FaceBlockHistory() = default;

std::size_t FaceBlockHistory::memory_bytes() const {
  const std::size_t doubles = 2 * twiddle_.size() + theta_.size() + half_a_.size() + half_b_.size() + half_d_.size() +
                              half_block_phase_re_.size() + half_block_phase_im_.size() + c0_a_.size() +
                              c0_b_.size() + c0_d_.size() + lags_.size();
  const std::size_t complexes = spectrum_a_.size() + spectrum_b_.size() + spectrum_d_.size() + state_x_.size() +
                                state_y_.size() + running_x_.size() + running_y_.size() +
                                history_x_.size() + history_y_.size();
  // Per thread: the levels' 4 buffers of B points, the far field's time grid
  // of 2B points (of both components when interleaved) and its 4 grids of
  // 2B + 2w points.
  const std::size_t grid = 2 * static_cast<std::size_t>(block_) + 2 * Nufft::max_half_width;
  const std::size_t time_grid = (nufft_->interleaves_pairs() ? 4 : 2) * static_cast<std::size_t>(block_);
  const std::size_t scratch = scratch_.size() * sizeof(cplx) * (4 * static_cast<std::size_t>(block_) + time_grid + 4 * grid);
  return sizeof(double) * doubles + sizeof(cplx) * complexes + rows_.memory_bytes() + scratch;
}

void FaceBlockHistory::convolve_level(int q, std::size_t l, int start, Scratch& scratch) {
  // Inputs start..start+s-1 to outputs start+s..start+2s-1 (lags 1..2s-1, no
  // wrap-around in a circular convolution of length 2s), both components.
  const Level& level = levels_[l];
  if (level.split) return convolve_split_level(q, level, start, scratch);
  const int s = level.size;
  auto* bx = reinterpret_cast<cplx*>(scratch.level_x.get());
  auto* by = reinterpret_cast<cplx*>(scratch.level_y.get());
  const cplx* in_x = rows_.input(0, q) + start;
  const cplx* in_y = rows_.input(1, q) + start;
  for (int j = 0; j < s; ++j) {
    bx[j] = in_x[j];
    by[j] = in_y[j];
  }
  for (int j = s; j < 2 * s; ++j) bx[j] = by[j] = 0.0;
  fftw_execute_dft(level.forward.get(), scratch.level_x.get(), scratch.spectrum_x.get());
  fftw_execute_dft(level.forward.get(), scratch.level_y.get(), scratch.spectrum_y.get());
  const std::size_t at = level.first_spectrum + q * (s + 1);
  const auto* ka = reinterpret_cast<const double*>(spectrum_a_.data() + at);
  const auto* kb = reinterpret_cast<const double*>(spectrum_b_.data() + at);
  const auto* kd = reinterpret_cast<const double*>(spectrum_d_.data() + at);
  auto* x = reinterpret_cast<double*>(scratch.spectrum_x.get());
  auto* y = reinterpret_cast<double*>(scratch.spectrum_y.get());
  for (int j = 0; j < 2 * s; ++j) spectral_product(ka, kb, kd, s, j, x, y, j);
  fftw_execute_dft(level.backward.get(), scratch.spectrum_x.get(), scratch.level_x.get());
  fftw_execute_dft(level.backward.get(), scratch.spectrum_y.get(), scratch.level_y.get());
  cplx* out_x = rows_.accumulator(0, q) + start + s;
  cplx* out_y = rows_.accumulator(1, q) + start + s;
  const double scale = 1.0 / (2.0 * s);
  for (int j = 0; j < s; ++j) {
    out_x[j] += bx[s + j] * scale;
    out_y[j] += by[s + j] * scale;
  }
}

void FaceBlockHistory::convolve_split_level(int q, const Level& level, int start, Scratch& scratch) {
  // As convolve_level, with each length-2s transform taken as two of length s
  // (the inputs fill half of the length 2s and only the later half of the
  // outputs is wanted; w = e^{-i pi / s}):
  //   U[2m] = DFT_s(u)[m],  U[2m+1] = DFT_s(u_j w^j)[m],
  //   z[s+j] = IDFT_s(Z[2m])[j] - conj(w^j) IDFT_s(Z[2m+1])[j].
  // The same arithmetic but for the twiddles, and FFTW_ESTIMATE's plans of
  // 4096 and 8192 points take ~3.5x and ~4.5x the time of those of half the
  // length (docs/notes/2026-11-27-pair-levels.md).
  const int s = level.size;
  auto* bx = reinterpret_cast<cplx*>(scratch.level_x.get());
  auto* by = reinterpret_cast<cplx*>(scratch.level_y.get());
  const auto* w = reinterpret_cast<const double*>(twiddle_.data() + level.first_twiddle);
  {
    const auto* in_x = reinterpret_cast<const double*>(rows_.input(0, q) + start);
    const auto* in_y = reinterpret_cast<const double*>(rows_.input(1, q) + start);
    auto* ex = reinterpret_cast<double*>(bx);
    auto* ey = reinterpret_cast<double*>(by);
    double* ox = ex + 2 * s;
    double* oy = ey + 2 * s;
    for (int j = 0; j < s; ++j) {
      const double wr = w[2 * j], wi = w[2 * j + 1];
      const double xr = in_x[2 * j], xi = in_x[2 * j + 1], yr = in_y[2 * j], yi = in_y[2 * j + 1];
      ex[2 * j] = xr;
      ex[2 * j + 1] = xi;
      ey[2 * j] = yr;
      ey[2 * j + 1] = yi;
      ox[2 * j] = wr * xr - wi * xi;
      ox[2 * j + 1] = wr * xi + wi * xr;
      oy[2 * j] = wr * yr - wi * yi;
      oy[2 * j + 1] = wr * yi + wi * yr;
    }
  }
  fftw_complex* fx = scratch.level_x.get();
  fftw_complex* fy = scratch.level_y.get();
  fftw_complex* sx = scratch.spectrum_x.get();
  fftw_complex* sy = scratch.spectrum_y.get();
  const std::size_t at = level.first_spectrum + q * (s + 1);
  const auto* ka = reinterpret_cast<const double*>(spectrum_a_.data() + at);
  const auto* kb = reinterpret_cast<const double*>(spectrum_b_.data() + at);
  const auto* kd = reinterpret_cast<const double*>(spectrum_d_.data() + at);
  auto* x = reinterpret_cast<double*>(sx);
  auto* y = reinterpret_cast<double*>(sy);
  const double scale = 1.0 / (2.0 * s);
  if (level.bin_order) {
    // The same sums through the stride-2 plans: bin k of the length-2s
    // spectrum at index k, and each half's output j at 2j (even bins) and
    // 2j + 1 (odd bins).
    fftw_execute_dft(level.forward.get(), fx, sx);
    fftw_execute_dft(level.forward.get(), fy, sy);
    for (int k = 0; k < 2 * s; ++k) spectral_product(ka, kb, kd, s, k, x, y, k);
    fftw_execute_dft(level.backward.get(), sx, fx);
    fftw_execute_dft(level.backward.get(), sy, fy);
    auto* out_x = reinterpret_cast<double*>(rows_.accumulator(0, q) + start + s);
    auto* out_y = reinterpret_cast<double*>(rows_.accumulator(1, q) + start + s);
    const auto* zx = reinterpret_cast<const double*>(bx);
    const auto* zy = reinterpret_cast<const double*>(by);
    for (int j = 0; j < s; ++j) {
      // E - conj(w) O
      const double wr = w[2 * j], wi = w[2 * j + 1];
      const double* ex = zx + 4 * j;
      const double* ey = zy + 4 * j;
      out_x[2 * j] += (ex[0] - (wr * ex[2] + wi * ex[3])) * scale;
      out_x[2 * j + 1] += (ex[1] - (wr * ex[3] - wi * ex[2])) * scale;
      out_y[2 * j] += (ey[0] - (wr * ey[2] + wi * ey[3])) * scale;
      out_y[2 * j + 1] += (ey[1] - (wr * ey[3] - wi * ey[2])) * scale;
    }
    return;
  }
  fftw_execute_dft(level.forward.get(), fx, sx);
  fftw_execute_dft(level.forward.get(), fx + s, sx + s);
  fftw_execute_dft(level.forward.get(), fy, sy);
  fftw_execute_dft(level.forward.get(), fy + s, sy + s);
  // Bin k at index k/2 (even k) or s + k/2 (odd k).
  for (int m = 0; m < s; ++m) {
    spectral_product(ka, kb, kd, s, 2 * m, x, y, m);
    spectral_product(ka, kb, kd, s, 2 * m + 1, x, y, s + m);
  }
  fftw_execute_dft(level.backward.get(), sx, fx);
  fftw_execute_dft(level.backward.get(), sx + s, fx + s);
  fftw_execute_dft(level.backward.get(), sy, fy);
  fftw_execute_dft(level.backward.get(), sy + s, fy + s);
  auto* out_x = reinterpret_cast<double*>(rows_.accumulator(0, q) + start + s);
  auto* out_y = reinterpret_cast<double*>(rows_.accumulator(1, q) + start + s);
  const auto* ex = reinterpret_cast<const double*>(bx);
  const auto* ey = reinterpret_cast<const double*>(by);
  const double* ox = ex + 2 * s;
  const double* oy = ey + 2 * s;
  for (int j = 0; j < s; ++j) {
    // E - conj(w) O
    const double wr = w[2 * j], wi = w[2 * j + 1];
    out_x[2 * j] += (ex[2 * j] - (wr * ox[2 * j] + wi * ox[2 * j + 1])) * scale;
    out_x[2 * j + 1] += (ex[2 * j + 1] - (wr * ox[2 * j + 1] - wi * ox[2 * j])) * scale;
    out_y[2 * j] += (ey[2 * j] - (wr * oy[2 * j] + wi * oy[2 * j + 1])) * scale;
    out_y[2 * j + 1] += (ey[2 * j + 1] - (wr * oy[2 * j + 1] - wi * oy[2 * j])) * scale;
  }
}

void FaceBlockHistory::advance_far_field(int q, Scratch& scratch) {
  // As BlockStripHistory::advance_far_field, per input component:
  //   A <- p^2 A + p F,  F = forward_centred(v),  p = e^{i theta B/2},
  // then per output component the coefficients (W/2) A p and their adjoint,
  // added into the block's outputs -- frequency by frequency in one pass
  // (Nufft::forward_map_adjoint), both components through each
  // frequency's kernel weights at once.
  const std::size_t f0 = first_frequency_[q], count = first_frequency_[q + 1] - f0;
  if (count == 0) return;
  cplx* sx = state_x_.data() + f0;
  cplx* sy = state_y_.data() + f0;
  const double *a = half_a_.data() + f0, *b = half_b_.data() + f0, *d = half_d_.data() + f0;
  const double *phase_re = half_block_phase_re_.data() + f0, *phase_im = half_block_phase_im_.data() + f0;
  const auto far = [&](std::size_t k, std::array<cplx, 2>& value) {
    const double pr = phase_re[k], pi_ = phase_im[k];
    // p A + F, then times p, for each component; and (A p).
    const auto advance = [&](cplx& state, cplx f, double& out_r, double& out_i) {
      const double ar = state.real(), ai = state.imag();
      const double ur = pr * ar - pi_ * ai + f.real(), ui = pr * ai + pi_ * ar + f.imag();
      const double nr = pr * ur - pi_ * ui, ni = pr * ui + pi_ * ur;
      state = cplx(nr, ni);
      out_r = pr * nr - pi_ * ni;
      out_i = pr * ni + pi_ * nr;
    };
    double xr, xi, yr, yi;
    advance(sx[k], value[0], xr, xi);
    advance(sy[k], value[1], yr, yi);
    // [[a, i b], [-i b, d]] (A_x p, A_y p)
    value[0] = cplx(a[k] * xr - b[k] * yi, a[k] * xi + b[k] * yr);
    value[1] = cplx(b[k] * xi + d[k] * yr, -b[k] * xr + d[k] * yi);
  };
  nufft_->forward_map_adjoint<2>({theta_.data() + f0, count}, {rows_.input(0, q), rows_.input(1, q)},
                                 {rows_.accumulator(0, q), rows_.accumulator(1, q)}, scratch.far, far);
}

std::array<double, 4> FaceBlockHistory::direct_part(int q, int slot) const {
  // Output `slot` of mode q's direct block from that block's inputs i < slot,
  // lag j = slot - i: y_x = sum A_j v_x + i B_j v_y, y_y = sum -i B_j v_x + D_j v_y.
  // Gathered when the output is due rather than scattered into every later
  // output when an input arrives: a step then reads the inputs so far instead
  // of reading and writing the direct block's later outputs (memory traffic,
  // 2 C direct_block values per mode and step).  Summed in vector lanes.
  const int D = direct_block_;
  const double* a = lags_.data() + 3 * static_cast<std::size_t>(q) * D;
  const double* b = a + D;
  const double* d = b + D;
  const double* in = reinterpret_cast<const double*>(rows_.direct_inputs(q));  // [i][x re, x im, y re, y im]
  double xr = 0.0, xi = 0.0, yr = 0.0, yi = 0.0;
#pragma omp simd reduction(+ : xr, xi, yr, yi)
  for (int i = 0; i < slot; ++i) {
    const int j = slot - i;
    const double ur = in[4 * i], ui = in[4 * i + 1], vr = in[4 * i + 2], vi = in[4 * i + 3];
    xr += a[j] * ur - b[j] * vi;
    xi += a[j] * ui + b[j] * vr;
    yr += b[j] * ui + d[j] * vr;
    yi += -b[j] * ur + d[j] * vi;
  }
  return {xr, xi, yr, yi};
}

void FaceBlockHistory::prefetch_levels(int q, int tau) const {
  // Each level's convolution streams its rows (inputs start..start+s-1,
  // outputs start+s..start+2s-1, both components) and the mode's three
  // kernel spectra (s + 1 bins each), untouched since long before (rows of
  // B steps per mode, spectra of every mode): at s <= kPrefetchLevel each
  // stream is a few cache lines, too short for the hardware prefetcher, so
  // the convolution waits on every line.  Asked during the previous mode's
  // work, the lines arrive meanwhile.  close()'s rows (the direct block's
  // inputs, its used outputs) are among them.
  constexpr int kPrefetchLevel = 256;
  constexpr std::size_t per_line = 64 / sizeof(cplx);
  const auto ahead = [](const void* p, std::size_t values, bool write) {
    const auto* c = static_cast<const cplx*>(p);
    for (std::size_t j = 0; j < values; j += per_line)
      if (write)
        __builtin_prefetch(c + j, 1, 2);
      else
        __builtin_prefetch(c + j, 0, 2);
  };
  const int done = tau + 1 - direct_block_;
  for (int c = 0; c < 2; ++c) {
    ahead(rows_.input(c, q) + done, direct_block_, true);
    ahead(rows_.accumulator(c, q) + done, direct_block_, true);
  }
  for (const Level& level : levels_) {
    const int s = level.size;
    if (s > kPrefetchLevel) break;
    if ((tau + 1) % (2 * s) != s) continue;
    const int start = tau + 1 - s;
    for (int c = 0; c < 2; ++c) {
      ahead(rows_.input(c, q) + start, static_cast<std::size_t>(s - direct_block_), false);
      ahead(rows_.accumulator(c, q) + start + s, static_cast<std::size_t>(s), true);
    }
    const std::size_t at = level.first_spectrum + static_cast<std::size_t>(q) * (s + 1);
    for (const auto* spectrum : {&spectrum_a_, &spectrum_b_, &spectrum_d_})
      ahead(spectrum->data() + at, static_cast<std::size_t>(s) + 1, false);
  }
}

void FaceBlockHistory::push_mode(int q, const Step& step, cplx vx, cplx vy, Scratch& scratch) {
  const int tau = step.input, p = step.output, slot = step.output_slot, D = direct_block_;
  rows_.set_direct_input(q, step.input_slot, 0, vx);
  rows_.set_direct_input(q, step.input_slot, 1, vy);
  running_x_[q] += vx;
  running_y_[q] += vy;
  if (slot == 0) {
    if (q + 1 < n_modes_) prefetch_levels(q + 1, tau);
    rows_.close(q, tau);
    for_completed_levels(levels_, tau, [&](std::size_t l, int start) { convolve_level(q, l, start, scratch); });
    if (step.block_done) advance_far_field(q, scratch);
    rows_.open(q, p);
  }
  // The levels' and the far field's part of the output, then the direct block's.
  const double* rows_part = rows_.outputs(q);
  const std::array<double, 4> direct = direct_part(q, slot);
  const double yx_r = rows_part[slot] + direct[0], yx_i = rows_part[D + slot] + direct[1];
  const double yy_r = rows_part[2 * D + slot] + direct[2], yy_i = rows_part[3 * D + slot] + direct[3];
  // h = C0 R - dt y, C0 = [[c0_a, i c0_b], [-i c0_b, c0_d]].
  const double rx_r = running_x_[q].real(), rx_i = running_x_[q].imag();
  const double ry_r = running_y_[q].real(), ry_i = running_y_[q].imag();
  history_x_[q] = cplx(c0_a_[q] * rx_r - c0_b_[q] * ry_i - dt_ * yx_r,
                       c0_a_[q] * rx_i + c0_b_[q] * ry_r - dt_ * yx_i);
  history_y_[q] = cplx(c0_b_[q] * rx_i + c0_d_[q] * ry_r - dt_ * yy_r,
                       -c0_b_[q] * rx_r + c0_d_[q] * ry_i - dt_ * yy_i);
}

void FaceBlockHistory::push(std::span<const cplx> velocity_x, std::span<const cplx> velocity_y) {
  const int tau = position_;
  const bool block_done = tau + 1 == block_;
  const int p = block_done ? 0 : tau + 1;  // the output this push produces
  // The places in their direct blocks once per step: an integer division per
  // mode was a measurable part of the mode loop.
  const Step step{tau, p, tau % direct_block_, p % direct_block_, block_done};
  const int threads = static_cast<int>(scratch_.size());
  if (threads == 1) {
    // No parallel region for one thread: libgomp takes a team of one from the
    // heap (and frees it) at every region, and push() must not allocate.
    for (int q = 0; q < n_modes_; ++q) push_mode(q, step, velocity_x[q], velocity_y[q], scratch_[0]);
  } else {
#pragma omp parallel num_threads(threads)
    {
      Scratch& scratch = scratch_[omp_get_thread_num()];
#pragma omp for schedule(static)
      for (int q = 0; q < n_modes_; ++q) push_mode(q, step, velocity_x[q], velocity_y[q], scratch);
    }
  }
  position_ = p;
}

void FaceBlockHistory::save_into(HistoryOperatorState& state, const std::string& prefix) const {
  state.counters.emplace_back(prefix + "position", position_);
  state.counters.emplace_back(prefix + "block", block_);
  state.add(prefix + "state_x", state_x_);
  state.add(prefix + "state_y", state_y_);
  state.add(prefix + "input_x", rows_.saved_input(0, position_));
  state.add(prefix + "input_y", rows_.saved_input(1, position_));
  state.add(prefix + "accumulator_x", rows_.accumulator_rows(0));
  state.add(prefix + "accumulator_y", rows_.accumulator_rows(1));
  state.add(prefix + "running_x", running_x_);
  state.add(prefix + "running_y", running_y_);
  state.add(prefix + "history_x", history_x_);
  state.add(prefix + "history_y", history_y_);
}

void FaceBlockHistory::state_layout_into(HistoryStateLayout& layout, const std::string& prefix) const {
  const auto n = static_cast<std::size_t>(n_modes_), block = static_cast<std::size_t>(block_);
  layout.add(prefix + "state_x", first_frequency_, 2);
  layout.add(prefix + "state_y", first_frequency_, 2);
  for (const char* name : {"input_x", "input_y", "accumulator_x", "accumulator_y"})
    layout.add_uniform(prefix + name, n, 2 * block);
  for (const char* name : {"running_x", "running_y", "history_x", "history_y"}) layout.add_uniform(prefix + name, n, 2);
}

void FaceBlockHistory::restore_from(const HistoryOperatorState& state, const std::string& prefix) {
  if (state.counter(prefix + "block") != block_)
    throw std::invalid_argument("block face history state: block = " +
                                std::to_string(state.counter(prefix + "block")) + ", this operator's is " +
                                std::to_string(block_));
  const long long position = state.counter(prefix + "position");
  if (position < 0 || position >= block_)
    throw std::invalid_argument("block face history state: position = " + std::to_string(position) +
                                " out of range");
  state.copy_to(prefix + "state_x", std::span<cplx>(state_x_));
  state.copy_to(prefix + "state_y", std::span<cplx>(state_y_));
  state.copy_to(prefix + "input_x", rows_.input_rows(0));
  state.copy_to(prefix + "input_y", rows_.input_rows(1));
  state.copy_to(prefix + "accumulator_x", rows_.accumulator_rows(0));
  state.copy_to(prefix + "accumulator_y", rows_.accumulator_rows(1));
  state.copy_to(prefix + "running_x", std::span<cplx>(running_x_));
  state.copy_to(prefix + "running_y", std::span<cplx>(running_y_));
  state.copy_to(prefix + "history_x", std::span<cplx>(history_x_));
  state.copy_to(prefix + "history_y", std::span<cplx>(history_y_));
  position_ = static_cast<int>(position);
  // The direct block's outputs hold the rows' part alone (direct_part sums
  // its inputs when an output is due): nothing to add per input.
  rows_.rebuild(position_);
}

}  // namespace slipstrip
