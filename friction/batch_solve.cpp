// Batch local solve and state update: W nodes at a time (W = 8 with AVX-512)
// with xsimd's vectorised exp/log/log1p/expm1 (1-2 ulp), and the scalar
// routines of friction_law.cpp for every node the vector path does not settle.
// See docs/friction.md, "Batch solve".
//
// Determinism: every node goes through exactly the same vector code whatever
// its position (a partial block is padded to W lanes), and the parallel loop
// hands out fixed chunks of nodes, so results do not depend on the thread
// count and are the same run to run.
#include "friction/batch_solve.hpp"

// GCC 12 reports false -W(maybe-)uninitialized inside its own AVX-512
// intrinsics (_mm512_undefined_* operands of masked instructions) as xsimd
// uses them; this translation unit is compiled without those two warnings.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#include <xsimd/xsimd.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>

namespace slipstrip {

namespace {

using B = xsimd::batch<double>;
using M = B::batch_bool_type;
constexpr std::size_t W = B::size;
static_assert(W <= 32, "lane flags are kept in 32 bits");
constexpr double kEps = std::numeric_limits<double>::epsilon();

// The scalar solve's constants (friction_law.cpp), restated for the vector path.
constexpr double kMargin = 1e-3;       // bracket margin in ln u
constexpr double kAcceptStep = 1e-6;   // accept when the Newton step |dw| <= this
constexpr double kFloorFactor = 8.0;   // round-off floor |g| <= 8 eps * scale
// Lanes still iterating after this many residual evaluations are handed to the
// scalar solve (with its bisection safeguards) from their original guess.
constexpr int kMaxVectorEvaluations = 12;
// Nodes per parallel work item (a multiple of W): small enough that two
// threads share even a 256-node interface, large enough to amortise the call.
constexpr std::size_t kChunk = 64;

struct alignas(64) Lanes {
  double v[W];
};

B load(std::span<const double> s, std::size_t begin, std::size_t count) {
  if (count == W) return B::load_unaligned(s.data() + begin);
  // Partial block: pad with copies of the first node, so the padding lanes
  // compute something harmless; their results are discarded.
  Lanes b;
  for (std::size_t i = 0; i < W; ++i) b.v[i] = s[begin + (i < count ? i : 0)];
  return B::load_aligned(b.v);
}

void store(const B& x, std::span<double> s, std::size_t begin, std::size_t count) {
  if (count == W) {
    x.store_unaligned(s.data() + begin);
    return;
  }
  Lanes b;
  x.store_aligned(b.v);
  for (std::size_t i = 0; i < count; ++i) s[begin + i] = b.v[i];
}

B ones(const M& m) { return xsimd::select(m, B(1.0), B(0.0)); }

// Lane flags as bits (lane i -> bit i).
std::uint32_t bits(const M& m) {
  Lanes b;
  ones(m).store_aligned(b.v);
  std::uint32_t r = 0;
  for (std::size_t i = 0; i < W; ++i)
    if (b.v[i] != 0.0) r |= 1u << i;
  return r;
}

// --- friction parameters of a block of nodes ---------------------------------------

// f0, a, b, D of W nodes (LocalSolveParameters::per_node, or the scalar when a
// parameter has no per-node values), and what the lanes derive from D.
struct NodeLanes {
  B f0, a, b, D;
  B log_D;       // ln D (slip law)
  M invalid_D;   // D not finite and > 0: the scalar routines report it
};

B lanes_of(std::span<const double> per_node, double scalar, std::size_t begin, std::size_t count) {
  return per_node.empty() ? B(scalar) : load(per_node, begin, count);
}

NodeLanes node_lanes(const LocalSolveParameters& params, std::size_t begin, std::size_t count) {
  const auto& p = params.friction;
  const auto& n = params.per_node;
  NodeLanes lanes{lanes_of(n.f0, p.f0, begin, count), lanes_of(n.a, p.a, begin, count),
                  lanes_of(n.b, p.b, begin, count),
                  lanes_of(n.characteristic_slip, p.characteristic_slip, begin, count), B(0.0),
                  M(false)};
  lanes.log_D = xsimd::log(lanes.D);
  lanes.invalid_D = (!(lanes.D > B(0.0))) | (!xsimd::isfinite(lanes.D));
  return lanes;
}

bool has_per_node(const LocalSolveParameters& params) {
  const auto& n = params.per_node;
  return !(n.f0.empty() && n.a.empty() && n.b.empty() && n.characteristic_slip.empty());
}

// Lanes no vector law takes: a = 0 (closed form) and non-finite values go to
// the scalar solve.
M unusable(const NodeLanes& n) {
  return (!(n.a > B(0.0))) | (!xsimd::isfinite(n.a)) | (!xsimd::isfinite(n.b)) |
         (!xsimd::isfinite(n.f0));
}

// --- state update -------------------------------------------------------------

bool vector_state_update_applies(const FrictionParameters& p, double dt) {
  // v*^2 must neither underflow nor overflow in sqrt(v^2 + v*^2).  (D is
  // checked per lane: NodeLanes::invalid_D.)
  return std::isfinite(dt) && dt >= 0.0 && p.v_star >= 1e-150 && p.v_star <= 1e150;
}

// evolve_state on W lanes.  Lanes the scalar routine rejects (state <= 0 or
// not finite) or treats specially (non-finite slip rate) are flagged in
// `to_scalar` (as are lanes with an invalid D); their values here are meaningless.
B evolve_lanes(const FrictionParameters& p, const NodeLanes& n, const B& state, const B& v,
               double dt, M& to_scalar) {
  to_scalar = to_scalar | !(state > B(0.0)) | !xsimd::isfinite(state) | !xsimd::isfinite(v) |
              n.invalid_D;
  const B& D = n.D;
  const B u = xsimd::abs(v);
  if (p.state_law == StateLaw::aging) {
    // hypot(v, v*): above 1e150 m/s, v*^2 is far below the rounding of u^2.
    const B h = xsimd::select(u > B(1e150), u, xsimd::sqrt(u * u + B(p.v_star * p.v_star)));
    const B x = B(-dt) * h / D;
    const B phi_ss = D / h;
    return state * xsimd::exp(x) + phi_ss * (-xsimd::expm1(x));
  }
  // Slip law: psi = ln(u phi / D) decays as exp(-u dt / D); unchanged at rest.
  const B log_scale = n.log_D - xsimd::log(u);
  const B psi0 = xsimd::log(state) - log_scale;
  const B evolved = xsimd::exp(log_scale + psi0 * xsimd::exp((-u) * B(dt) / D));
  return xsimd::select(u == B(0.0), state, evolved);
}

// --- local solve ----------------------------------------------------------------
//
// With u = |v| and w = ln u the residual is
//   paper:            g = excess - eta u - A ln(1 + u/v*),  excess = |tau| - strength(0, phi),
//                     dg/dw = -(eta u + A u / (u + v*));
//   dieterich_ruina:  g = c - eta u - A w,  c = |tau| - sigma psi(phi) + A ln v*,
//                     dg/dw = -(eta u + A);
//   regularized:      g = |tau| - eta u - A asinh(e^(w - ln u_c(phi))),
// all concave and decreasing in w (docs/friction.md), so plain Newton in w
// from any start converges: from the left it lands right of the root, from the
// right it is monotone.  The iterate is carried as u (u <- u e^dw; DR also
// and regularized also carry w <- w + dw), so one evaluation costs one exp
// and, for the paper law, one log1p (regularized: another exp, a sqrt, a log1p).  Start and acceptance are the scalar solve's: the guess capped at
// its upper bound, its lower bound for a zero or non-finite guess; accept when
// |dw| <= 1e-6 (result u (1 + dw), relative error <= 1e-12) or at the round-off
// floor.  The scalar solve's bracket and bisection only guard against round-off
// and slow starts far from the root; here any lane that is not accepted within
// kMaxVectorEvaluations, or meets a non-finite value, goes to the scalar solve.
// For the paper and DR laws the state enters g only through `excess` (c),
// which the corrector's start uses (predictor_corrector_batch).

struct Prepared {
  B excess;  // paper: |tau| - strength(0, phi);  DR: c;  regularized: |tau|
  B scale;   // magnitude of the terms summed into excess (round-off floor)
  B T;       // |tau|
  M stuck;   // |tau| <= strength(0, phi): v = 0 exactly
  B shift;   // regularized: ln u_c(phi);  otherwise unused
};

struct Solved {
  B magnitude;                    // |v|; 0 when stuck
  B u_last, g_last, slope_last;   // last evaluated point of each converged lane
  M newton;                       // lanes settled by the Newton loop
};

// Each law: the scalars every node shares (shared(), once per batch call;
// nullopt when they have no vector path) and the per-lane values of a block of nodes
// (with_lanes; lanes it cannot take are flagged in `invalid` and go to the
// scalar solve).  The lane values are computed with the same operations, in
// the same order, as the scalar constants they replaced, so a node's result
// does not depend on whether its parameters came from a span or a scalar.
struct PaperLaw {
  static constexpr bool carries_w = false;
  double sigma, phi_star, v_star, eta;
  double hi_factor;   // u_hi = excess * hi_factor: the scalar solve's cap ln(excess/eta) + margin
  double exp_minus_margin;
  B f0, b, A;
  B lo_factor;   // u_lo = excess * lo_factor: its cold start ln(excess) - ln(eta + A/v*) - margin
  B tie_factor;  // see prepare()
  M invalid;

  static std::optional<PaperLaw> shared(const LocalSolveParameters& params) {
    const auto& p = params.friction;
    const double sigma = params.normal_stress, eta = params.eta;
    if (!(p.v_star >= 1e-150 && p.v_star <= 1e150 && std::isfinite(p.phi_star) && p.phi_star > 0.0))
      return std::nullopt;
    PaperLaw c{sigma, p.phi_star, p.v_star, eta, std::exp(kMargin) / eta, std::exp(-kMargin),
               B(0.0), B(0.0), B(0.0), B(0.0), B(0.0), M(true)};
    if (!std::isfinite(c.hi_factor)) return std::nullopt;
    return c;
  }

  PaperLaw with_lanes(const NodeLanes& n) const {
    PaperLaw c = *this;
    c.f0 = n.f0;
    c.b = n.b;
    c.A = B(sigma) * n.a;
    c.lo_factor = B(exp_minus_margin) / (B(eta) + c.A / B(v_star));
    c.tie_factor = B(32.0 * kEps * sigma) * xsimd::abs(n.f0);
    // a = 0 (closed form) and odd values: scalar solve.
    c.invalid = unusable(n) | (!xsimd::isfinite(c.lo_factor)) | (!(c.lo_factor > B(0.0)));
    return c;
  }

  // Strength at rest and the sticking decision.  The scalar solve compares
  // |tau| with s0 = sigma (f0 (1 + b L)), L = ln(phi/phi*), evaluated with
  // libm's log (< 0.5 ulp); xsimd's log is within 1 ulp, so the two L differ by
  // at most 3 eps |L|, and the remaining operations (possibly contracted
  // differently) by a few roundings: |s0 - s0_libm| <= 7 eps sigma |f0|
  // (1 + b |L|).  Lanes whose |tau| lies within 32 eps sigma |f0| (1 + b |L|)
  // of s0 (> 4x that bound; it would still hold with an 8-ulp log) are ties:
  // they go to the scalar solve, so the decision is always the scalar solve's.
  Prepared prepare(const B& T, const B& state, M& to_scalar) const {
    const B L = xsimd::log(state / B(phi_star));
    const B s0 = B(sigma) * (B(f0) * (B(1.0) + B(b) * L));
    const B band = B(tie_factor) * (B(1.0) + B(b) * xsimd::abs(L));
    const M tie = xsimd::abs(T - s0) <= band;
    const M stuck = (T <= s0) & !tie;
    // Zero load with a negative strength at rest: no slip direction; the
    // scalar solve throws.  Non-finite s0 (state not usable): scalar.
    to_scalar = to_scalar | tie | ((T == B(0.0)) & !stuck) | !xsimd::isfinite(s0);
    const B excess = T - s0;
    return {excess, excess, T, stuck, B(0.0)};
  }

  // Change of g at a fixed u when the state changes from `from` to `to`: exact.
  B state_change(const Prepared& from, const Prepared& to, const Solved&) const {
    return to.excess - from.excess;
  }

  void start(const Prepared& pr, const B& guess, B& u, B& /*w*/) const {
    const M warm = (guess > B(0.0)) & xsimd::isfinite(guess);
    u = xsimd::select(warm, xsimd::min(guess, pr.excess * B(hi_factor)), pr.excess * B(lo_factor));
  }

  // g, dg/dw and the rate term (for the round-off floor) at u.
  void residual(const Prepared& pr, const B& u, const B& /*w*/, B& g, B& slope, B& scale) const {
    const B rate_term = B(A) * xsimd::log1p(u / B(v_star));
    const B radiation = B(eta) * u;
    g = pr.excess - radiation - rate_term;
    slope = -(radiation + B(A) * (u / (u + B(v_star))));
    scale = pr.scale + radiation + rate_term;
  }
};

struct DieterichRuinaLaw {
  static constexpr bool carries_w = true;
  double sigma, v_star, eta, log_v_star;
  B f0, b, D, A, reference_part;
  M invalid;

  static std::optional<DieterichRuinaLaw> shared(const LocalSolveParameters& params) {
    const double v_star = params.friction.v_star;
    if (!(std::isfinite(v_star) && v_star > 0.0)) return std::nullopt;
    return DieterichRuinaLaw{params.normal_stress, v_star, params.eta, std::log(v_star),
                             B(0.0), B(0.0), B(0.0), B(0.0), B(0.0), M(true)};
  }

  DieterichRuinaLaw with_lanes(const NodeLanes& n) const {
    DieterichRuinaLaw c = *this;
    c.f0 = n.f0;
    c.b = n.b;
    c.D = n.D;
    c.A = B(sigma) * n.a;
    c.reference_part = c.A * B(log_v_star);
    c.invalid = unusable(n) | n.invalid_D;
    return c;
  }

  // Never sticks (strength -> -inf at rest); zero load has no slip direction
  // and the scalar solve throws.
  Prepared prepare(const B& T, const B& state, M& to_scalar) const {
    const B state_part = B(sigma) * (B(f0) + B(b) * xsimd::log(B(v_star) * state / B(D)));
    const B c = T - state_part + B(reference_part);
    to_scalar = to_scalar | (T == B(0.0)) | !xsimd::isfinite(c);
    return {c, T + xsimd::abs(state_part) + xsimd::abs(reference_part), T, M(false), B(0.0)};
  }

  // Change of g at a fixed u when the state changes from `from` to `to`: exact.
  B state_change(const Prepared& from, const Prepared& to, const Solved&) const {
    return to.excess - from.excess;
  }

  // The scalar solve's bounds: at hi, g <= -A; at lo, g >= A.
  void start(const Prepared& pr, const B& guess, B& u, B& w) const {
    const M warm = (guess > B(0.0)) & xsimd::isfinite(guess);
    const B hi = xsimd::max(xsimd::log(pr.T / B(eta)), (pr.excess - pr.T) / B(A) + B(1.0)) + B(kMargin);
    const B lo = xsimd::min(xsimd::log(B(0.5) * pr.T / B(eta)), (pr.excess - B(0.5) * pr.T) / B(A) - B(1.0)) -
                 B(kMargin);
    w = xsimd::select(warm, xsimd::min(xsimd::log(guess), hi), lo);
    u = xsimd::exp(w);
  }

  void residual(const Prepared& pr, const B& u, const B& w, B& g, B& slope, B& scale) const {
    const B radiation = B(eta) * u;
    const B rate_term = B(A) * w;
    g = pr.excess - radiation - rate_term;
    slope = -(radiation + B(A));
    scale = pr.scale + radiation + xsimd::abs(rate_term);
  }
};

struct RegularizedLaw {
  static constexpr bool carries_w = true;
  double sigma, v_star, eta, log_two_v_star, log_eta;
  B f0, b, a, D, A, log_A;
  M invalid;

  static std::optional<RegularizedLaw> shared(const LocalSolveParameters& params) {
    const double v_star = params.friction.v_star;
    if (!(std::isfinite(v_star) && v_star > 0.0)) return std::nullopt;
    return RegularizedLaw{params.normal_stress, v_star, params.eta, std::log(2.0 * v_star),
                          std::log(params.eta), B(0.0), B(0.0), B(0.0), B(0.0), B(0.0), B(0.0),
                          M(true)};
  }

  RegularizedLaw with_lanes(const NodeLanes& n) const {
    RegularizedLaw c = *this;
    c.f0 = n.f0;
    c.b = n.b;
    c.a = n.a;
    c.D = n.D;
    c.A = B(sigma) * n.a;
    c.log_A = xsimd::log(c.A);
    c.invalid = unusable(n) | n.invalid_D;
    return c;
  }

  // strength(0) = 0: only zero load sticks.  ln u_c = ln(2 v*) - psi/a.
  Prepared prepare(const B& T, const B& state, M& to_scalar) const {
    const B psi = B(f0) + B(b) * xsimd::log(B(v_star) * state / B(D));
    const B log_crossover = B(log_two_v_star) - psi / B(a);
    to_scalar = to_scalar | !xsimd::isfinite(log_crossover);
    return {T, T, T, T <= B(0.0), log_crossover};
  }

  // The scalar solve's bounds: hi from asinh >= 0, lo from asinh x < x.
  void start(const Prepared& pr, const B& guess, B& u, B& w) const {
    const M warm = (guess > B(0.0)) & xsimd::isfinite(guess);
    const B hi = xsimd::log(pr.T / B(eta)) + B(kMargin);
    const B log_b = B(log_A) - pr.shift;
    const B log_sum = xsimd::max(B(log_eta), log_b) +
                      xsimd::log1p(xsimd::exp(-xsimd::abs(B(log_eta) - log_b)));
    const B lo = xsimd::log(pr.T) - log_sum - B(kMargin);
    w = xsimd::select(warm, xsimd::min(xsimd::log(guess), hi), lo);
    u = xsimd::exp(w);
  }

  // Rate term A asinh(e^y), y = w - ln u_c, from e = e^{-|y|} (never overflows):
  //   y > 0:  asinh(e^y) = y + ln(1 + sqrt(1 + e^2)),  slope 1 / sqrt(1 + e^2);
  //   y <= 0: asinh(e^y) = ln(1 + e + e^2 / (1 + sqrt(1 + e^2))),  slope e / sqrt(1 + e^2).
  void residual(const Prepared& pr, const B& u, const B& w, B& g, B& slope, B& scale) const {
    const B y = w - pr.shift;
    const M right = y > B(0.0);
    const B e = xsimd::exp(-xsimd::abs(y));
    const B root = xsimd::sqrt(B(1.0) + e * e);
    const B asinh_exp =
        xsimd::select(right, y, B(0.0)) +
        xsimd::log1p(xsimd::select(right, root, e + e * e / (B(1.0) + root)));
    const B radiation = B(eta) * u;
    const B rate_term = B(A) * asinh_exp;
    g = pr.excess - radiation - rate_term;
    slope = -(radiation + B(A) * xsimd::select(right, B(1.0), e) / root);
    scale = pr.scale + radiation + rate_term;
  }

  // Change of g at a fixed u when ln u_c changes: to first order
  // A asinh_exp'(y) d(ln u_c), with A asinh_exp'(y) = -slope - eta u.
  B state_change(const Prepared& from, const Prepared& to, const Solved& s) const {
    return (-s.slope_last - B(eta) * s.u_last) * (to.shift - from.shift);
  }
};

template <class Law>
Solved iterate(const Law& law, const Prepared& pr, const B& guess, M& to_scalar, B& evaluations) {
  B u(0.0), w(0.0);
  law.start(pr, guess, u, w);
  Solved s{B(0.0), u, B(0.0), B(-1.0), M(false)};
  M open = !(pr.stuck | to_scalar);
  for (int k = 0; k < kMaxVectorEvaluations && xsimd::any(open); ++k) {
    B g(0.0), slope(0.0), scale(0.0);
    law.residual(pr, u, w, g, slope, scale);
    const B step = -g / slope;
    evaluations += ones(open);
    const M usable = xsimd::isfinite(step) & (u > B(0.0)) & xsimd::isfinite(u);
    to_scalar = to_scalar | (open & !usable);
    open = open & usable;
    const M by_step = open & (xsimd::abs(step) <= B(kAcceptStep));
    const M by_floor = open & !by_step & (xsimd::abs(g) <= B(kFloorFactor * kEps) * scale);
    s.magnitude = xsimd::select(by_step, u + u * step, s.magnitude);
    s.magnitude = xsimd::select(by_floor, u, s.magnitude);
    s.u_last = xsimd::select(open, u, s.u_last);
    s.g_last = xsimd::select(open, g, s.g_last);
    s.slope_last = xsimd::select(open, slope, s.slope_last);
    s.newton = s.newton | by_step | by_floor;
    open = open & !(by_step | by_floor);
    u = xsimd::select(open, u * xsimd::exp(step), u);
    if constexpr (Law::carries_w) w = xsimd::select(open, w + step, w);
  }
  to_scalar = to_scalar | open;  // not settled within the cap
  return s;
}

// sign(tau) |v|, and +0 exactly for sticking lanes (as the scalar solve).
B signed_rate(const B& tau, const Solved& s, const Prepared& pr) {
  const B v = xsimd::select(tau < B(0.0), -s.magnitude, s.magnitude);
  return xsimd::select(pr.stuck, B(0.0), v);
}

template <class F>
void for_each_lane(std::uint32_t lanes, std::size_t count, F&& f) {
  for (std::size_t i = 0; i < count; ++i)
    if (lanes & (1u << i)) f(i);
}

// The time loop's scalar predictor-corrector at one node (the code the batch
// replaces, used for the nodes the vector path hands over).
void predictor_corrector_scalar(const LocalSolveParameters& params, std::size_t node, double dt,
                                double tau, double v_old, double phi_old, double& v_new,
                                double& phi_new) {
  const FrictionParameters f = params.at(node);
  const double phi_pred = evolve_state(f, phi_old, v_old, dt);
  const double v_pred = solve_slip_rate(f, params.normal_stress, params.eta, tau, phi_pred, v_old);
  phi_new = evolve_state(f, phi_old, 0.5 * (v_old + v_pred), dt);
  v_new = solve_slip_rate(f, params.normal_stress, params.eta, tau, phi_new, v_pred);
}

void check_sizes(std::size_t n, std::initializer_list<std::size_t> sizes) {
  for (std::size_t s : sizes)
    if (s != n) throw std::invalid_argument("batch friction solve: spans of different lengths");
}

void check_per_node_sizes(const LocalSolveParameters& params, std::size_t n) {
  const auto& p = params.per_node;
  for (std::size_t s : {p.f0.size(), p.a.size(), p.b.size(), p.characteristic_slip.size()})
    if (s != 0 && s != n)
      throw std::invalid_argument(
          "batch friction solve: per-node parameters must be empty or one value per node");
}

}  // namespace

std::size_t batch_width() { return W; }

namespace {

// The law of each block of nodes: built once when every node shares the
// parameters (the uniform case costs nothing per block), rebuilt from the
// block's per-node values otherwise.
template <class Law>
class BlockLaw {
 public:
  BlockLaw(const LocalSolveParameters& params, const Law& law, const NodeLanes& lanes)
      : params_(params), per_node_(has_per_node(params)), law_(law), lanes_(lanes) {}

  void load(std::size_t begin, std::size_t count) {
    if (!per_node_) return;
    lanes_ = node_lanes(params_, begin, count);
    law_ = law_.with_lanes(lanes_);
  }
  const Law& law() const { return law_; }
  const NodeLanes& lanes() const { return lanes_; }

 private:
  const LocalSolveParameters& params_;
  bool per_node_;
  Law law_;
  NodeLanes lanes_;
};

// Calls f(block_law) with the vector-path description of params' strength
// law, or returns false when that law (or these shared values) has no vector path.
template <class F>
bool with_vector_law(const LocalSolveParameters& params, F&& f) {
  const double sigma = params.normal_stress, eta = params.eta;
  if (!(std::isfinite(sigma) && sigma > 0.0 && std::isfinite(eta) && eta > 0.0)) return false;
  // The first node's lanes (all lanes when uniform); per-node blocks reload theirs.
  const NodeLanes first = node_lanes(params, 0, 1);
  const auto run = [&](const auto& shared) {
    if (!shared) return false;
    BlockLaw block(params, shared->with_lanes(first), first);
    f(block);
    return true;
  };
  switch (params.friction.strength_law) {
    case StrengthLaw::paper:
      return run(PaperLaw::shared(params));
    case StrengthLaw::dieterich_ruina:
      return run(DieterichRuinaLaw::shared(params));
    case StrengthLaw::regularized:
      return run(RegularizedLaw::shared(params));
  }
  return false;
}

}  // namespace

LocalSolveParameters LocalSolveParameters::slice(std::size_t begin, std::size_t count) const {
  LocalSolveParameters out = *this;
  const auto cut = [&](std::span<const double>& s) {
    if (!s.empty()) s = s.subspan(begin, count);
  };
  cut(out.per_node.f0);
  cut(out.per_node.a);
  cut(out.per_node.b);
  cut(out.per_node.characteristic_slip);
  return out;
}

FrictionParameters LocalSolveParameters::at(std::size_t i) const {
  FrictionParameters p = friction;
  if (!per_node.f0.empty()) p.f0 = per_node.f0[i];
  if (!per_node.a.empty()) p.a = per_node.a[i];
  if (!per_node.b.empty()) p.b = per_node.b[i];
  if (!per_node.characteristic_slip.empty()) p.characteristic_slip = per_node.characteristic_slip[i];
  return p;
}

BatchCounts solve_slip_rate_batch(const LocalSolveParameters& params,
                                  std::span<const double> tau_history, std::span<const double> state,
                                  std::span<const double> initial_guess, std::span<double> slip_rate) {
  const std::size_t n = tau_history.size();
  check_sizes(n, {state.size(), initial_guess.size(), slip_rate.size()});
  check_per_node_sizes(params, n);
  BatchCounts counts;
  counts.solves = static_cast<long long>(n);
  const auto scalar_node = [&](std::size_t i) {
    try {
      return solve_slip_rate(params.at(i), params.normal_stress, params.eta, tau_history[i],
                             state[i], initial_guess[i]);
    } catch (const std::exception& e) {
      throw BatchFailure(i, e.what());
    }
  };
  B evaluations(0.0);
  const bool vectorised = n > 0 && with_vector_law(params, [&](auto& block) {
    for (std::size_t begin = 0; begin < n; begin += W) {
      const std::size_t count = std::min(W, n - begin);
      block.load(begin, count);
      const auto& law = block.law();
      const B tau = load(tau_history, begin, count);
      const B phi = load(state, begin, count);
      const B guess = xsimd::abs(load(initial_guess, begin, count));
      M to_scalar =
          (!xsimd::isfinite(tau)) | (!(phi > B(0.0))) | (!xsimd::isfinite(phi)) | law.invalid;
      const Prepared pr = law.prepare(xsimd::abs(tau), phi, to_scalar);
      const Solved s = iterate(law, pr, guess, to_scalar, evaluations);
      // Scalar nodes before the store: slip_rate may alias initial_guess.
      Lanes result;
      signed_rate(tau, s, pr).store_aligned(result.v);
      for_each_lane(bits(to_scalar), count, [&](std::size_t i) {
        result.v[i] = scalar_node(begin + i);
        ++counts.scalar_nodes;
      });
      store(B::load_aligned(result.v), slip_rate, begin, count);
    }
  });
  if (!vectorised) {
    for (std::size_t i = 0; i < n; ++i) slip_rate[i] = scalar_node(i);
    counts.scalar_nodes = static_cast<long long>(n);
  }
  counts.evaluations = static_cast<long long>(xsimd::hadd(evaluations));
  return counts;
}

void evolve_state_batch(const FrictionParameters& friction, std::span<const double> state,
                        std::span<const double> slip_rate, double dt, std::span<double> out) {
  const std::size_t n = state.size();
  check_sizes(n, {slip_rate.size(), out.size()});
  const auto scalar_node = [&](std::size_t i) {
    try {
      out[i] = evolve_state(friction, state[i], slip_rate[i], dt);
    } catch (const std::exception& e) {
      throw BatchFailure(i, e.what());
    }
  };
  if (!vector_state_update_applies(friction, dt)) {
    for (std::size_t i = 0; i < n; ++i) scalar_node(i);
    return;
  }
  const NodeLanes lanes = node_lanes(LocalSolveParameters{friction, 0.0, 0.0, {}}, 0, W);
  for (std::size_t begin = 0; begin < n; begin += W) {
    const std::size_t count = std::min(W, n - begin);
    M to_scalar(false);
    const B phi = load(state, begin, count);
    const B result = evolve_lanes(friction, lanes, phi, load(slip_rate, begin, count), dt, to_scalar);
    // Scalar nodes before the store: out may alias state.
    Lanes scalar_values;
    result.store_aligned(scalar_values.v);
    for_each_lane(bits(to_scalar), count, [&](std::size_t i) {
      try {
        scalar_values.v[i] = evolve_state(friction, state[begin + i], slip_rate[begin + i], dt);
      } catch (const std::exception& e) {
        throw BatchFailure(begin + i, e.what());
      }
    });
    store(B::load_aligned(scalar_values.v), out, begin, count);
  }
}

BatchCounts predictor_corrector_batch(const LocalSolveParameters& params, double dt,
                                      std::span<const double> tau_history,
                                      std::span<const double> slip_rate_old,
                                      std::span<const double> state_old,
                                      std::span<double> slip_rate_new,
                                      std::span<double> state_new) {
  const std::size_t n = tau_history.size();
  check_sizes(n, {slip_rate_old.size(), state_old.size(), slip_rate_new.size(), state_new.size()});
  check_per_node_sizes(params, n);
  BatchCounts counts;
  counts.solves = 2 * static_cast<long long>(n);
  const auto scalar_node = [&](std::size_t i) {
    try {
      predictor_corrector_scalar(params, i, dt, tau_history[i], slip_rate_old[i], state_old[i],
                                 slip_rate_new[i], state_new[i]);
    } catch (const std::exception& e) {
      throw BatchFailure(i, e.what());
    }
  };
  const auto& f = params.friction;
  B evaluations(0.0);
  const auto vector_blocks = [&](auto& block) {
    for (std::size_t begin = 0; begin < n; begin += W) {
      const std::size_t count = std::min(W, n - begin);
      block.load(begin, count);
      const auto& law = block.law();
      const NodeLanes& lanes = block.lanes();
      const B tau = load(tau_history, begin, count);
      const B v_old = load(slip_rate_old, begin, count);
      const B phi_old = load(state_old, begin, count);
      const B T = xsimd::abs(tau);
      M to_scalar = (!xsimd::isfinite(tau)) | law.invalid;

      // Predictor: state from v_old, slip rate warm-started from |v_old|.
      const B phi_pred = evolve_lanes(f, lanes, phi_old, v_old, dt, to_scalar);
      const Prepared pp = law.prepare(T, phi_pred, to_scalar);
      const Solved sp = iterate(law, pp, xsimd::abs(v_old), to_scalar, evaluations);
      const B v_pred = signed_rate(tau, sp, pp);

      // Corrector: state from the mean slip rate.  Only the state changed; for
      // the paper and DR laws it enters g only through `excess`, so g at the
      // predictor's last point is known exactly: g_last + (excess_c - excess_p)
      // (regularized law: to first order).  One Newton step from there is the
      // start (no residual evaluation).
      const B phi_new = evolve_lanes(f, lanes, phi_old, B(0.5) * (v_old + v_pred), dt, to_scalar);
      const Prepared pc = law.prepare(T, phi_new, to_scalar);
      const B extrapolated =
          sp.u_last * xsimd::exp(-(sp.g_last + law.state_change(pp, pc, sp)) / sp.slope_last);
      const B guess = xsimd::select(sp.newton, extrapolated, sp.magnitude);
      const Solved sc = iterate(law, pc, guess, to_scalar, evaluations);

      store(phi_new, state_new, begin, count);
      store(signed_rate(tau, sc, pc), slip_rate_new, begin, count);
      for_each_lane(bits(to_scalar), count, [&](std::size_t i) {
        scalar_node(begin + i);
        ++counts.scalar_nodes;
      });
    }
  };
  const bool vectorised =
      n > 0 && vector_state_update_applies(f, dt) && with_vector_law(params, vector_blocks);
  if (!vectorised) {
    for (std::size_t i = 0; i < n; ++i) scalar_node(i);
    counts.scalar_nodes = static_cast<long long>(n);
  }
  counts.evaluations = static_cast<long long>(xsimd::hadd(evaluations));
  return counts;
}

namespace {

// Runs body(begin, count) over fixed chunks of kChunk nodes in an OpenMP
// parallel loop; rethrows the BatchFailure with the lowest node index.
template <class Body>
BatchCounts parallel_chunks(std::size_t n, Body&& body) {
  const long long chunks = static_cast<long long>((n + kChunk - 1) / kChunk);
  BatchCounts total;
  long long solves = 0, evaluations = 0, scalar_nodes = 0;
  std::optional<BatchFailure> failure;
#pragma omp parallel for schedule(static) reduction(+ : solves, evaluations, scalar_nodes)
  for (long long k = 0; k < chunks; ++k) {
    const std::size_t begin = static_cast<std::size_t>(k) * kChunk;
    const std::size_t count = std::min(kChunk, n - begin);
    try {
      const BatchCounts c = body(begin, count);
      solves += c.solves;
      evaluations += c.evaluations;
      scalar_nodes += c.scalar_nodes;
    } catch (const BatchFailure& e) {
#pragma omp critical(slipstrip_batch_failure)
      if (!failure || begin + e.index < failure->index) failure.emplace(begin + e.index, e.what());
    } catch (const std::exception& e) {
#pragma omp critical(slipstrip_batch_failure)
      if (!failure || begin < failure->index) failure.emplace(begin, e.what());
    }
  }
  if (failure) throw *failure;
  total.solves = solves;
  total.evaluations = evaluations;
  total.scalar_nodes = scalar_nodes;
  return total;
}

}  // namespace

BatchCounts predictor_corrector_parallel(const LocalSolveParameters& params, double dt,
                                         std::span<const double> tau_history,
                                         std::span<const double> slip_rate_old,
                                         std::span<const double> state_old,
                                         std::span<double> slip_rate_new,
                                         std::span<double> state_new) {
  const std::size_t n = tau_history.size();
  check_sizes(n, {slip_rate_old.size(), state_old.size(), slip_rate_new.size(), state_new.size()});
  check_per_node_sizes(params, n);  // before slicing them
  return parallel_chunks(n, [&](std::size_t begin, std::size_t count) {
    return predictor_corrector_batch(params.slice(begin, count), dt,
                                     tau_history.subspan(begin, count),
                                     slip_rate_old.subspan(begin, count),
                                     state_old.subspan(begin, count),
                                     slip_rate_new.subspan(begin, count),
                                     state_new.subspan(begin, count));
  });
}

BatchCounts solve_slip_rate_parallel(const LocalSolveParameters& params,
                                     std::span<const double> tau_history,
                                     std::span<const double> state,
                                     std::span<const double> initial_guess,
                                     std::span<double> slip_rate) {
  const std::size_t n = tau_history.size();
  check_sizes(n, {state.size(), initial_guess.size(), slip_rate.size()});
  check_per_node_sizes(params, n);  // before slicing them
  return parallel_chunks(n, [&](std::size_t begin, std::size_t count) {
    return solve_slip_rate_batch(params.slice(begin, count), tau_history.subspan(begin, count),
                                 state.subspan(begin, count), initial_guess.subspan(begin, count),
                                 slip_rate.subspan(begin, count));
  });
}

}  // namespace slipstrip
