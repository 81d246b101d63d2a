#pragma once
// The in-plane 2x2 face response of ONE half-space and its discrete,
// bounded-memory history operator (docs/inplane_bodies.md §6).
//
// Per Fourier mode k > 0 and p = s / (c_s k), with a = sqrt(1 + p^2),
// d = sqrt(1 + r^2 p^2) (principal roots), r^2 = c_s^2 / c_d^2 and R = r^2 a + d,
//     K(k, s) = mu k [[A, -i B], [i B, D]],
//     A = d (a + d) / R,   B = ((2 r^2 - 1) a + d) / R,   D = a (a + d) / R,
// in the convention of kernels/face_response.hpp (t = K u, the body above its
// face); k < 0 flips the sign of the off-diagonal (K(-k) = K(k)^T).  This is
// face_stiffness(material, inf, ...) simplified: Q = a (r^2 a + d) / (a + d)
// (in units of k).  R has no zero on the principal sheet (its zeros
// p = +-i sqrt(1 + r^2) / r lie on the other one), so K has only the branch
// points p = +-i, +-i/r: the Rayleigh denominator belongs to the compliance
// K^{-1} (a free surface), not to the stiffness; two bodies in contact meet it
// again through K_t + K_b' (the generalised Rayleigh wave).
//
// Time domain: K / s = (mu / c_s) [E' + G(p)], E' = diag(1, 1/r) (radiation
// impedances diag(mu/c_s, rho c_d) in units of mu/c_s), with the history
// transforms G_A = A/p - 1, G_B = B/p, G_D = D/p - 1/r and their inverses
// g_e(tau), tau = c_s k t:
//     g_e(inf) = A(0), B(0), D(0) = 2/(1+r^2), 2 r^2/(1+r^2), 2/(1+r^2),
//     g_e(0+)  = 0, (2r - 1)/r, 0
// (the coupling starts with a step: its transform falls like 1/p, the diagonal
// ones like 1/p^2).  The traction on the body through its face is
//     t(t) = E v(t) + mu k int_0^t g(c_s k t') v(t - t') dt'    (2x2 g).
#include <algorithm>
#include <array>
#include <complex>
#include <cstddef>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "kernels/elastic_material.hpp"
#include "kernels/face_history.hpp"
#include "kernels/face_response.hpp"
#include "kernels/half_space_design.hpp"
#include "kernels/half_space_kernel.hpp"
#include "kernels/half_space_pair_kernel.hpp"

namespace slipstrip {

// The three distinct entries: shear (xx), coupling (the real B of
// xy = -i B, yx = +i B) and normal (yy).
enum class FaceEntry { shear = 0, coupling = 1, normal = 2 };
inline constexpr std::array<FaceEntry, 3> kFaceEntries = {FaceEntry::shear, FaceEntry::coupling,
                                                          FaceEntry::normal};

// A, B or D above at p (Re p >= 0; on the imaginary axis the limit from Re p > 0).
std::complex<double> half_space_face_entry(double speed_ratio_squared, FaceEntry entry, std::complex<double> p);
// K(k, s) of a half-space body from the entries (k of either sign; k = 0:
// diag(mu s / c_s, rho c_d s)).  Pa/m.
FaceMatrix half_space_face_stiffness(const ElasticMaterial& material, double wavenumber, std::complex<double> s);
// G_e(p) above.
std::complex<double> half_space_face_history_transform(double speed_ratio_squared, FaceEntry entry,
                                                       std::complex<double> p);
double half_space_face_static_value(double speed_ratio_squared, FaceEntry entry);   // g_e(inf)
double half_space_face_initial_value(double speed_ratio_squared, FaceEntry entry);  // g_e(0+)
// g_e(tau) ~= g_e(inf) + 2 Re sum amplitude e^{rate tau} for tau in [tau_min,
// tau_max] (the branch-cut construction of kernels/half_space_kernel.hpp).
ExponentialSum half_space_face_exponential_sum(double speed_ratio_squared, FaceEntry entry, double tau_min,
                                               double tau_max, int nodes_per_panel = 10);

// The coefficients of one Fourier mode q >= 1 of the discrete operator, per
// entry e (index 0, 1, 2 = shear, coupling, normal), in Pa s/m:
//     K_j^e = static_weight[e] + lag_weight[e][j-1]           (1 <= j <= W),
//     K_{W+i}^e = static_weight[e] + 2 Re sum_m pole_weight[e][m] pole[m]^i   (i >= 1),
// and the mode's 2x2 kernel is [[K^0, -i K^1], [i K^1, K^2]] (k > 0).
struct FaceHalfSpaceModeKernel {
  double wavenumber = 0.0, h = 0.0;  // |k|, c_s |k| dt
  std::array<double, 3> static_weight{};
  std::array<std::vector<double>, 3> lag_weight;
  std::array<std::vector<double>, 3> correction;  // passivity corrections (units mu/c_s), lags 1..L
  std::vector<std::complex<double>> pole;
  std::array<std::vector<std::complex<double>>, 3> pole_weight;
};

// Per Fourier mode, t_n = E v_n + h_n with h_n = sum_{j>=1} K_j v_{n-j} (2x2
// K_j).  K_j samples mu k g(c_s k t) by the trapezoidal rule (dt mu k g(j h));
// the coupling's half weight at j = 0 (its step g_B(0+) != 0) is moved to j = 1,
// which keeps the rule second order for smooth inputs (the change is
// (dt/2) mu k g_B(0) (v_n - v_{n-1}) = O(dt^2)) and keeps the operator strictly
// causal with the diagonal instantaneous impedance E the interface needs.  Lags
// beyond W (c_s k W dt >= near_field_tau) use the exponential sum, fed with the
// input delayed by W steps: known W steps ahead, so the exponentials (and the
// slow ones' block outputs) are advanced for a batch of up to design.far_batch
// = 8 steps at once (W >= corrected_lags = 8 by default), each mode's rows read from memory once
// per batch (docs/inplane_bodies.md §6); the static part is a running sum
// (exact static stiffness).  The first
// `corrected_lags` weights of each entry get the smallest correction (Euclidean
// norm) that makes the operator passive as a matrix: the Hermitian part of its
// symbol Z_d(theta) = E + sum_j K_j e^{-i j theta} positive semidefinite on a
// grid of theta (cutting planes along the binding eigenvectors;
// docs/inplane_bodies.md §6), with a margin of at least 1e-6 mu/c_s.  Uses
// HalfSpaceOperatorDesign's corrected_lags, near_field_tau, horizon_tau and
// passivity_margin.  The modes are designed in parallel (OpenMP); the set-up
// throws SetupCancelled when `cancelled` says so.
// Thrown by FaceHalfSpaceHistory when some mode's passivity correction does not
// exist (the time step is too long for this Poisson ratio); `h` is the largest
// c_s |k| dt that failed.  An std::invalid_argument with the kernel's message.
struct FaceHalfSpaceNotPassive : std::invalid_argument {
  FaceHalfSpaceNotPassive(const std::string& message, double failed_h)
      : std::invalid_argument(message), h(failed_h) {}
  double h;
};

// Whether one mode's passivity correction exists at h = c_s |k| dt, for
// r^2 = c_s^2/c_d^2 and `design` (the mode designed alone, as
// face_half_space_passive_limit tries it; ~0.1 s).
bool face_half_space_mode_passive(double speed_ratio_squared, const HalfSpaceOperatorDesign& design, double h);

// The largest c_s |k| dt at which a mode's passivity correction exists, for
// r^2 = c_s^2/c_d^2 and `design`: bisection (to 1e-3 relative) between
// `failed` (a value where it does not) and the largest smaller value found by
// halving where it does.  Each trial designs one mode (~0.1 s).  The operator
// of a run exists when the shortest wavelength's c_s k_max dt is at most this;
// docs/bodies.md §4 turns it into the bound on time.beta.
double face_half_space_passive_limit(double speed_ratio_squared, const HalfSpaceOperatorDesign& design,
                                     double failed);

// What an operator's kernels are: one half-space body's (r^2 = c_s^2/c_d^2)
// or the combined pair's (docs/inplane_bodies.md §7), the instantaneous
// impedances E' and the coupling's step g_B(0+) in the kernels' units, and the
// branch heights (the rates' imaginary parts on the cuts, units speed |k|).
struct FaceKernelShape {
  bool pair = false;
  double r2 = 0.0;                   // one body
  HalfSpacePairShape pair_shape;     // the pair
  std::array<double, 3> instantaneous{};  // E'_A, 0, E'_D
  double coupling_initial = 0.0;
  std::vector<double> heights;
};

class FaceHalfSpaceHistory final : public FaceHistory {
 public:
  // The modes of a line of `length` and `nodes` nodes: |k| = 2 pi q / length,
  // q = 0..nodes/2.
  FaceHalfSpaceHistory(const ElasticMaterial& material, double length, int nodes, double time_step,
                       const HalfSpaceOperatorDesign& design = {}, const CancelCheck& cancelled = {});
  // Any list of |k| (mode q has |k| = wavenumbers[q]; the uniform mode 0
  // first and only there), e.g. the in-plane operator of a 2D interface's
  // mode at |k| = hypot(kx, kz) (kernels/interface_2d_history.hpp).  The
  // near-field sums span the list's h = c_s |k| dt (and design.near_field_h_min,
  // near_field_tau_max when set); each mode gets its own passivity correction,
  // and modes of equal |k| share one design, computed once.  On a line's
  // wavenumbers this is the constructor above, bit for bit.
  FaceHalfSpaceHistory(const ElasticMaterial& material, std::span<const double> wavenumbers, double time_step,
                       const HalfSpaceOperatorDesign& design = {}, const CancelCheck& cancelled = {});
  // The combined operator of two different half-spaces in contact
  // (docs/inplane_bodies.md §7): its inputs are the slip rate V and the
  // opening rate Omega (velocity_x, velocity_y), its outputs the history parts
  // h_x, h_y of -(sigma_xy, sigma_yy) = E_c [V, Omega] + h (k > 0), with the
  // kernels of half_space_pair_exponential_sums in units mu_ref / c_ref and
  // h = c_ref |k| dt (the slower shear wave's).  shear_impedance() and
  // normal_impedance() are the series impedances eta and eta_y.  Throws
  // HalfSpacePairHasInterfaceWave for a pair with a Stoneley wave, and
  // HalfSpacePairCheckFailed when the set-up check against a numerical inverse
  // Laplace transform (verify_half_space_pair_sums) fails.
  FaceHalfSpaceHistory(const ElasticMaterial& top, const ElasticMaterial& bottom, double length, int nodes,
                       double time_step, const HalfSpaceOperatorDesign& design = {},
                       const CancelCheck& cancelled = {});

  double time_step() const override { return dt_; }
  double shear_impedance() const override { return impedance_x_; }
  double normal_impedance() const override { return impedance_y_; }
  int modes() const override { return static_cast<int>(history_x_.size()); }
  void push(std::span<const std::complex<double>> velocity_x,
            std::span<const std::complex<double>> velocity_y) override;
  std::span<const std::complex<double>> history_x() const override { return history_x_; }
  std::span<const std::complex<double>> history_y() const override { return history_y_; }
  void save_into(HistoryOperatorState& state, const std::string& prefix) const override;
  void restore_from(const HistoryOperatorState& state, const std::string& prefix) override;
  void state_layout_into(HistoryStateLayout& layout, const std::string& prefix) const override;
  std::size_t memory_bytes() const override;
  std::size_t discrete_modes() const override { return pole_.size(); }
  const char* algorithm() const override { return shape_.pair ? "half-space pair" : "half-space"; }
  // Whether some input of the second component (v_y; the combined pair's
  // opening rate) so far was nonzero.  Until then its states are exactly zero
  // and push() neither rotates nor sums them: the same histories, bit for bit,
  // at half the far field's work (the pair's interface while it is closed).
  bool normal_channel_active() const { return normal_active_; }
  // Work the second channel from the start (the reference the skipping is
  // compared with).
  void keep_normal_channel_active() { normal_active_ = true; }
  // Exponentials advanced once per block (0 when design.slow_block = 0), and
  // the block length B.
  std::size_t slow_exponentials() const { return slow_decay_.size(); }
  int slow_block() const { return block_; }
  // The per-step work repeats every block (the slow exponentials' block end).
  int period() const override { return block_ > 0 ? block_ : batch_; }
  // Steps of the far field (exponentials, slow block outputs) computed together.
  int far_batch() const { return batch_; }

  // The coefficients of mode q >= 1, and its symbol Z_d(e^{i theta}) (Pa s/m,
  // E included; the static running sum contributes its finite part for
  // theta in (0, 2 pi)).
  FaceHalfSpaceModeKernel mode_kernel(int q) const;
  FaceMatrix symbol(int q, double theta) const;

 private:
  FaceHalfSpaceHistory(FaceKernelShape shape, double unit, double speed, std::span<const double> wavenumbers,
                       double time_step, const HalfSpaceOperatorDesign& design, const CancelCheck& cancelled);
  FaceKernelShape shape_;
  bool normal_active_ = false;
  double dt_, impedance_x_, impedance_y_;
  double unit_ = 0.0;  // the coefficients' unit, Pa s/m: mu/c_s (one body), mu_ref/c_ref (the pair)
  long long step_ = 0;
  std::vector<double> wavenumber_, h_;
  std::vector<std::array<double, 3>> static_weight_;
  std::vector<std::size_t> first_lag_, first_pole_;  // size modes + 1
  std::vector<std::array<double, 3>> lag_weight_;
  std::vector<std::array<double, 3>> correction_;    // corrected_lags per mode q >= 1
  int lags_;
  std::vector<std::complex<double>> pole_;
  std::vector<std::array<std::complex<double>, 3>> pole_weight_;
  // State.
  std::vector<std::complex<double>> ring_x_, ring_y_;  // last W_q inputs of mode q
  std::vector<std::complex<double>> running_x_, running_y_;
  // The exponentials as push() reads them, one array per real quantity
  // (contiguous, so the loop over a mode's exponentials vectorises): z, and
  // per entry e the kernel 2 Re(w z^i) = weight_cos[e] Re z^i + weight_sin[e] Im z^i.
  std::vector<double> pole_re_, pole_im_;
  std::array<std::vector<double>, 3> weight_cos_, weight_sin_;
  // State per exponential and input component (x, y): C = sum_i Re(z^i) v and
  // S = sum_i Im(z^i) v of the delayed inputs, real and imaginary parts.
  std::array<std::vector<double>, 8> far_;  // C_re, C_im, S_re, S_im of x, then of y
  std::vector<std::complex<double>> history_x_, history_y_;

  // The fast exponentials of mode q are [first_fast_[q], first_fast_[q+1]) of
  // pole_re_ ... far_; the slow ones (docs/theory.md §8.7, kernels/slow_block.hpp)
  // [first_slow_[q], first_slow_[q+1]) of slow_decay_ ..., shear branch first
  // (up to slow_shear_end_[q]).  Set up from the exponentials' rates (units c_s |k|,
  // in pole_'s order) by build_exponentials.
  void build_exponentials(std::span<const std::complex<double>> rates, const HalfSpaceOperatorDesign& design);
  void push_slow_block_end(std::size_t q);
  // The slow polynomials' four output channels of mode q at steps batch_step +
  // d, d in [first, last), into slow_batch_out_[o * batch_ + d].
  void slow_batch_outputs(std::size_t q, long long batch_step, int first, int last);
  // The fast exponentials' outputs of mode q's x input (entries A and B: Re,
  // Im of each) at the same steps, into fast_batch_out_, while the normal
  // channel is inactive.
  void fast_batch_outputs(std::size_t q, long long batch_step, int first, int last);
  // The far field's part of mode q's history (every exponential, the slow
  // block's outputs and in-block sums, block ends) at steps batch_step + d,
  // d in [first, last), into far_batch_x_/y_: its inputs v_{n-W} are in the
  // ring batch_ steps ahead, so the mode's rows are read from memory once per
  // batch instead of once per step.
  void advance_far(std::size_t q, long long batch_step, int first, int last);
  int batch_ = 1;
  std::vector<std::complex<double>> far_batch_x_, far_batch_y_;  // per mode, batch_ steps
  std::vector<double> slow_batch_out_;                            // 4 channels x batch_ steps, one mode
  std::vector<double> fast_batch_out_;                            // the same
  // Output channels of the slow polynomials: Re, Im of history x, then of y;
  // per mode and group of two branches (slow_block.hpp works on two), 2
  // branches x 4 channels.  One body has one group (shear, P); the pair's up
  // to four branch heights make two.
  static constexpr std::size_t kSlowPolynomials = 8;
  std::size_t groups_ = 1;
  // The slow exponentials of mode q and branch b (the index of its height) are
  // [slow_branch_start_[q * (branches + 1) + b], ... + b + 1).
  std::size_t branches_ = 2;
  std::vector<std::size_t> slow_branch_start_;
  int block_ = 0, terms_ = 0;
  double block_centre_ = 0.0;  // t_c = (B + 1) / 2
  std::vector<std::size_t> first_fast_, first_slow_;
  std::vector<double> slow_decay_;                          // lambda = x h
  std::vector<double> slow_centre_factor_;                  // e^{-lambda t_c}
  std::vector<std::complex<double>> slow_block_pole_;       // z^B
  std::vector<std::array<std::complex<double>, 3>> slow_weight_;  // w per entry (Pa s/m)
  // Per mode and entry, B: 2 Re sum_slow w z^{i+1} at [B - 1 - i], i = 0..B-1.
  std::vector<double> slow_lag_weight_;
  std::vector<std::vector<std::complex<double>>> rotation_;  // slow_block_rotations, per group
  // Slow state: Y at the block start fed with Re x, Im x, Re y, Im y.
  std::array<std::vector<std::complex<double>>, 4> slow_state_;
  // This block's delayed inputs, per mode B values of Re x, Im x, Re y, Im y
  // (separate arrays: the in-block sums read them as vectors).
  std::array<std::vector<double>, 4> block_input_;
  std::vector<std::complex<double>> block_moment_;  // per mode, groups * kSlowPolynomials * terms
  // Block end's work arrays, per slow exponential of one mode: the Taylor
  // factor of the current term and the four weighted states (Re, Im).
  std::array<std::vector<double>, 9> slow_scratch_;
};

}  // namespace slipstrip
