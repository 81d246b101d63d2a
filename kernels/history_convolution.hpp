#pragma once
// History part of the elastodynamic traction, per Fourier mode of the
// interface, for two strips of height H (see docs/theory.md, "time
// discretisation").  For the slip-rate perturbation v^_q(t) of mode q,
//
//   tau^_q(t_n) = load - eta v^_q(t_n) - history_q(t_n),        eta = mu / (2 c_s),
//   history_q(t_n) = (mu/c_s) sum_{p>=1} v^_q(t_n - p T_s)                   (shear echoes)
//                  + dt sum_m w_m sum_{j>=1} (1 - cos(omega_m j dt)) v^_q(t_{n-j})  (normal modes)
//
// T_s = 2H/c_s is a whole number of steps, so the echoes are an exact delay
// line (kept as such for the uniform mode q = 0); for q >= 1 the delay line and
// the comb modes combine into one running sum (docs/theory.md).  The
// normal-mode sums are updated recursively (a rotation per mode and step).  Memory and cost per step are fixed when the operator is built and do
// not grow with simulated time, yet no reflection is ever dropped.
#include <complex>
#include <cstddef>
#include <functional>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "kernels/elastic_material.hpp"
#include "kernels/strip_response.hpp"

namespace slipstrip {

// Largest time step <= beta dx / c_s for which 2H/c_s is a whole number of
// steps (so every shear echo lands exactly on a time level).  For a half-space
// it is beta dx / c_s.
double strip_time_step(const ElasticMaterial& material, double strip_height, double dx,
                       double beta);

// One recursion of the discrete operator: kernel weight * (1 - cos(phase j)),
// phase = omega dt in [0, pi].
struct DiscreteMode {
  double phase;
  double weight;  // [Pa/m]
  ModeFamily family;
};

// The discrete normal modes for wavenumber k > 0 (docs/theory.md, "passivity"):
// the shear and P strip modes up to Nyquist, with the static stiffness of the
// truncated modes placed so that the discrete operator stays passive (free
// ringing neither grows nor decays).  The comb modes are not listed: with the
// delay line they form the running-sum kernel mu/c_s (the "comb identity").
// Empty for k = 0.
std::vector<DiscreteMode> discrete_modes(const ElasticMaterial& material, double strip_height,
                                         double wavenumber, double time_step,
                                         std::size_t echo_steps);

// Places the static stiffness `truncated` of the modes above Nyquist into
// `modes` so that the discrete operator stays passive (docs/theory.md,
// "passivity"): a negative one as a passive element at Nyquist, a positive
// one absorbed into the highest-frequency passive modes (each weight kept
// <= 0).  Throws std::runtime_error when it cannot (refine the time step).
// Shared by the strip (discrete_modes) and the antiplane bilayer.
void place_truncated_stiffness(std::vector<DiscreteMode>& modes, double truncated);

// Everything the history operator needs, per Fourier mode q = 0..N/2: the
// discrete normal modes (phase = omega dt, weight) flattened, with
// first_oscillator[q] .. first_oscillator[q+1] the modes of q.  A plain value:
// computed in closed form (compute_strip_kernels) or read from a cache
// (kernels/kernel_cache.hpp).
struct StripKernels {
  double time_step = 0.0;
  std::size_t echo_steps = 0;
  std::vector<std::size_t> first_oscillator;
  std::vector<double> phase, weight;
};

// Polled by the long set-up loops (kernels, operator construction) about once
// per Fourier mode; returning true abandons the set-up by throwing
// SetupCancelled, so a SIGTERM/SIGINT during a set-up of many seconds is
// honoured within a fraction of a second.  An empty function never cancels.
using CancelCheck = std::function<bool()>;
struct SetupCancelled : std::runtime_error {
  using std::runtime_error::runtime_error;
};
inline void throw_if_cancelled(const CancelCheck& cancelled, const char* where) {
  if (cancelled && cancelled()) throw SetupCancelled(std::string("set-up cancelled during ") + where);
}

StripKernels compute_strip_kernels(const ElasticMaterial& material, double strip_height,
                                   double length, int nodes, double time_step,
                                   const CancelCheck& cancelled = {});
// The same for any list of wavenumbers (mode q has wavenumber wavenumbers[q];
// the uniform mode, wavenumbers[0] == 0, must come first and only there: the
// operators carry it as the shear-echo delay line).  Equal wavenumbers share
// one design: the modes of each distinct |k| are computed once and copied
// (an interface periodic in x and z has many Fourier modes of equal |k|).
StripKernels compute_strip_kernels(const ElasticMaterial& material, double strip_height,
                                   std::span<const double> wavenumbers, double time_step,
                                   const CancelCheck& cancelled = {});

struct ModeOperatorStats {
  std::size_t modes = 0;            // Fourier modes q = 0..N/2
  std::size_t oscillators = 0;      // recursions in total (normal modes, or exponentials)
  std::size_t echo_steps = 0;       // T_s / dt (0 for the half-space)
  std::size_t direct_lags = 0;      // explicitly stored kernel weights in total (half-space)
  std::size_t memory_bytes = 0;     // state + coefficients
};

// Everything push() changes in a history operator, as named arrays and
// counters: what a restart point (checkpoint) must hold so that the restored
// operator continues bit for bit.  Complex arrays are stored as interleaved
// (re, im) doubles.  `kind` names the operator; restoring into another kind,
// or arrays of another size (a different config), is refused.
struct HistoryOperatorState {
  std::string kind;
  std::vector<std::pair<std::string, std::vector<double>>> arrays;
  std::vector<std::pair<std::string, long long>> counters;

  void add(const std::string& name, std::span<const double> values);
  void add(const std::string& name, std::span<const std::complex<double>> values);
  // Copies the array `name` into `target`; throws std::invalid_argument if it
  // is missing or of another size.
  void copy_to(const std::string& name, std::span<double> target) const;
  void copy_to(const std::string& name, std::span<std::complex<double>> target) const;
  long long counter(const std::string& name) const;
  bool has(const std::string& name) const;  // an array of that name
  void require_kind(const std::string& expected) const;
  // An operator made of parts (two bodies, the in-plane and antiplane parts
  // of a 2D interface): each part's arrays and counters under `prefix`, and
  // the part back out of them, with the kind of the part that restores it
  // (which then checks every array it needs by name and size).
  void add_part(const std::string& prefix, const HistoryOperatorState& part);
  HistoryOperatorState part(const std::string& prefix, const std::string& part_kind) const;
};

// Where each mode's values lie in the arrays of a state (save_state): for
// each array, by name, the offsets in doubles of operator mode q's values,
// [first[q], first[q + 1]) (first has modes() + 1 entries, starts at 0 and
// ends at the array's size).  Every array of these operators is contiguous
// per mode and in mode order, and a mode's values depend on that mode's input
// alone, so a state can be regrouped by mode: the parts of an operator split
// over processes (each over its own modes) make the whole operator's state by
// concatenating each array's per-mode values in the whole operator's mode
// order (kernels/interface_2d_history.hpp).  The counters (step counts,
// cursors, block lengths) are the same for every mode, but for the flags in
// any_counters.
struct HistoryStateLayout {
  std::vector<std::pair<std::string, std::vector<std::size_t>>> arrays;
  // Counters that are flags of the whole operator which its parts over
  // different modes may hold differently (0 or 1): the whole operator's is
  // whether any part's is set.
  std::vector<std::string> any_counters;

  // Offsets of elements of `doubles_per_element` doubles (2: complex), from a
  // per-mode element offset table (size modes + 1).
  void add(const std::string& name, std::span<const std::size_t> first_element, std::size_t doubles_per_element);
  // `values_per_mode` doubles per mode, for `modes` modes.
  void add_uniform(const std::string& name, std::size_t modes, std::size_t values_per_mode);
  // All `values` doubles belong to mode 0 (the uniform mode's delay line).
  void add_first_mode(const std::string& name, std::size_t modes, std::size_t values);
  void add_part(const std::string& prefix, const HistoryStateLayout& part);
  // The offsets of array `name`; throws std::invalid_argument if it has none.
  const std::vector<std::size_t>& of(const std::string& name) const;
};

// The history part of the traction per Fourier mode, as the time loop sees it:
// feed the slip-rate perturbation spectrum at t_n, read the history part at
// t_{n+1}.  Two implementations: StripHistory (finite H, exact) and
// HalfSpaceHistory (kernels/half_space_history.hpp).  One virtual call per
// step; the per-mode work behind it is what costs.
class HistoryOperator {
 public:
  virtual ~HistoryOperator() = default;
  virtual double time_step() const = 0;
  virtual double radiation_damping() const = 0;  // eta = mu / (2 c_s) (two different bodies: eta_t eta_b / (eta_t + eta_b))
  virtual int modes() const = 0;
  virtual ModeOperatorStats stats() const = 0;
  // Feed v^_q(t_n); afterwards history() holds history_q(t_{n+1}).  No allocation.
  virtual void push(std::span<const std::complex<double>> slip_rate_spectrum) = 0;
  virtual std::span<const std::complex<double>> history() const = 0;
  // The state after the last push (for checkpoints; allocates, so never in the
  // time loop), and its restoration into an operator built from the same
  // config: afterwards push() continues exactly as the saved operator would.
  virtual HistoryOperatorState save_state() const = 0;
  virtual void restore_state(const HistoryOperatorState& state) = 0;
  // Where each mode's values lie in save_state()'s arrays (allocates).
  virtual HistoryStateLayout state_layout() const = 0;
};

// The constants a strip history operator takes from the bodies, besides the
// kernels' normal modes: the instantaneous part eta, the constant kernel of
// every mode q >= 1 (the comb identity: 2 eta) and the uniform mode's exact
// echoes.  Two identical bodies (identical_strip_pair) have equal echoes
// (top_echo_steps == bottom_echo_steps) and eta = mu/(2 c_s); two different
// antiplane strips (kernels/antiplane_pair_modes.hpp) have the impedances
// eta_i = mu_i/c_i of both and their own echo steps M_i = 2 H_i/(c_i dt).
struct StripPairConstants {
  double radiation_damping = 0.0;   // eta [Pa s/m]
  double running_sum_weight = 0.0;  // c0 - dt sum_m w_m [Pa s/m]
  std::size_t top_echo_steps = 0, bottom_echo_steps = 0;
  double top_impedance = 0.0, bottom_impedance = 0.0;  // [Pa s/m], used when the echoes differ
};
// Two identical bodies of this material: eta = material.radiation_damping(),
// running sum weight mu/c_s (the same expressions the operators always used).
StripPairConstants identical_strip_pair(const ElasticMaterial& material, std::size_t echo_steps);

// The uniform mode q = 0 of a strip: exact shear echoes between the two
// faces.  Its history is (mu/c_s) R_{n+1} with R_{n+1} = v_{n+1-M} + R_{n+1-M}
// (M = 2H/(c_s dt) steps), kept in a delay line of M slots: the slot at the
// cursor holds R_n (written M steps ago) and becomes R_{n+M}.  Used by both
// strip operators (modal and block).
class ShearEchoLine {
 public:
  ShearEchoLine(std::size_t steps, double weight) : weight_(weight), line_(steps, 0.0) {}

  // Feeds v^_0(t_n); returns the history part of mode 0 at t_{n+1}.  No allocation.
  std::complex<double> push(std::complex<double> slip_rate) {
    const std::size_t slot = cursor_;
    const std::size_t next_slot = slot + 1 == line_.size() ? 0 : slot + 1;
    line_[slot] += slip_rate;
    cursor_ = next_slot;
    return weight_ * line_[next_slot];
  }

  std::size_t steps() const { return line_.size(); }
  // The state, for save_state/restore_state (set_cursor checks nothing: the
  // operator checks the range and reports it in its own terms).
  std::size_t cursor() const { return cursor_; }
  void set_cursor(std::size_t cursor) { cursor_ = cursor; }
  std::span<const std::complex<double>> slots() const { return line_; }
  std::span<std::complex<double>> slots() { return line_; }

 private:
  double weight_;  // mu / c_s
  std::vector<std::complex<double>> line_;
  std::size_t cursor_ = 0;
};

// The uniform mode q = 0 of a pair of strips, exactly.  Equal echoes (M_t =
// M_b = M): the ShearEchoLine of weight 2 eta.  Different ones: with z = e^{s dt}
// and x_i = z^{-M_i}, the kernel K_c(0, s)/s of two strips is the rational function
//   G = eta_t eta_b (1 + x_t)(1 + x_b) / [(eta_t + eta_b)(1 - x_t x_b) + (eta_b - eta_t)(x_b - x_t)]
// (docs/bodies.md), i.e. the sparse recursion
//   (eta_t + eta_b)(y_n - y_{n-L}) + (eta_b - eta_t)(y_{n-M_b} - y_{n-M_t})
//       = eta_t eta_b (v_n + v_{n-M_t} + v_{n-M_b} + v_{n-L}),    L = M_t + M_b,
// with y = G v (whose instantaneous part is eta v): O(1) per step, L slots of
// v and y, every echo of the two bodies kept exactly.  Its poles lie on the
// unit circle (lossless), as the single echo line's integrator does.
class UniformModeEchoes {
 public:
  explicit UniformModeEchoes(const StripPairConstants& constants);

  // Feeds v^_0(t_n); returns the history part of mode 0 at t_{n+1}.  No allocation.
  std::complex<double> push(std::complex<double> slip_rate) {
    if (!recursion_) return line_.push(slip_rate);
    const std::size_t L = input_.size();
    const std::size_t n = cursor_;  // slot of t_n, holding t_{n-L}
    const std::complex<double> y = (eta_product_ * (slip_rate + input_[(n + L - top_) % L] +
                                                    input_[(n + L - bottom_) % L] + input_[n]) -
                                    eta_difference_ * (output_[(n + L - bottom_) % L] - output_[(n + L - top_) % L])) /
                                       eta_sum_ +
                                   output_[n];
    input_[n] = slip_rate;
    output_[n] = y;
    const std::size_t next = n + 1 == L ? 0 : n + 1;  // slot of t_{n+1}, holding t_{n+1-L}
    cursor_ = next;
    return (eta_product_ * (input_[(next + L - top_) % L] + input_[(next + L - bottom_) % L] + input_[next]) -
            eta_difference_ * (output_[(next + L - bottom_) % L] - output_[(next + L - top_) % L])) /
               eta_sum_ +
           output_[next];
  }

  // Delay slots held (M, or 2 L for different echoes): the memory.
  std::size_t slots() const { return recursion_ ? 2 * input_.size() : line_.steps(); }
  // The state as arrays of the operator's (equal echoes: "echo_line" and
  // "echo_cursor", as the strip operators always wrote them).
  void save_counters(HistoryOperatorState& state) const;
  void save_arrays(HistoryOperatorState& state) const;
  // Throws std::invalid_argument for a cursor outside the slots (before an
  // operator copies anything); restore checks it again and copies.
  void check_cursor(const HistoryOperatorState& state) const;
  void restore(const HistoryOperatorState& state);
  void add_layout(HistoryStateLayout& layout, std::size_t modes) const;

 private:
  bool recursion_;
  ShearEchoLine line_;  // equal echoes
  std::size_t top_ = 0, bottom_ = 0;  // M_t, M_b
  double eta_product_ = 0.0, eta_sum_ = 0.0, eta_difference_ = 0.0;  // eta_t eta_b, eta_t + eta_b, eta_b - eta_t
  std::vector<std::complex<double>> input_, output_;  // v and y, L slots each
  std::size_t cursor_ = 0;
};

class StripHistory final : public HistoryOperator {
 public:
  StripHistory(const ElasticMaterial& material, double strip_height, double length, int nodes,
               double time_step);
  // From precomputed (or cached) kernels of this material and strip height.
  StripHistory(const ElasticMaterial& material, const StripKernels& kernels,
               const CancelCheck& cancelled = {});
  // From kernels and the bodies' constants (two different antiplane strips).
  StripHistory(const StripPairConstants& constants, const StripKernels& kernels,
               const CancelCheck& cancelled = {});

  double time_step() const override { return dt_; }
  double radiation_damping() const override { return eta_; }
  int modes() const override { return static_cast<int>(first_oscillator_.size()) - 1; }
  ModeOperatorStats stats() const override;
  void push(std::span<const std::complex<double>> slip_rate_spectrum) override;
  std::span<const std::complex<double>> history() const override { return history_; }
  HistoryOperatorState save_state() const override;
  void restore_state(const HistoryOperatorState& state) override;
  HistoryStateLayout state_layout() const override;

 private:
  double dt_;
  double eta_;
  double echo_weight_;       // the running sum's weight: mu / c_s for identical bodies, 2 eta
  std::size_t kernels_echo_steps_;  // stats

  // Coefficients, flat over (mode q, oscillator m): contiguous per q.
  std::vector<std::size_t> first_oscillator_;  // size modes+1
  std::vector<double> cos_step_, sin_step_, weight_;
  std::vector<double> weight_sum_;             // per q: sum of weights
  std::vector<double> integrator_weight_;      // per q >= 1: mu/c_s (delay line + comb modes)
  // State.
  std::vector<double> c_re_, c_im_, s_re_, s_im_;
  std::vector<std::complex<double>> running_sum_;  // per q: sum_{j>=1} v_{n-j}
  UniformModeEchoes echo_;                         // q = 0
  std::vector<std::complex<double>> history_;
};

}  // namespace slipstrip
