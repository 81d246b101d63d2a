// Rate-and-state friction laws, state evolution and the local interface solve.
// See docs/friction.md for the formulas, units and the solver's guarantees.
#include "friction/friction_law.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <span>
#include <string>

#include "friction/local_solve_tolerances.hpp"

namespace slipstrip {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kLn2 = 0.69314718055994530942;

std::string format_double(double x) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.17g", x);
  return buffer;
}

void require_positive(double value, const char* key, const char* unit) {
  if (!(std::isfinite(value) && value > 0.0)) {
    throw std::invalid_argument(std::string(key) + " = " + format_double(value) +
                                " is invalid: must be finite and > 0 (" + unit + ")");
  }
}

void require_non_negative(double value, const char* key) {
  if (!(std::isfinite(value) && value >= 0.0)) {
    throw std::invalid_argument(std::string(key) + " = " + format_double(value) +
                                " is invalid: must be finite and >= 0 (dimensionless)");
  }
}

// ln(1 + e^y) without overflow for large y or loss of digits for very negative y.
double softplus(double y) { return y > 0.0 ? y + std::log1p(std::exp(-y)) : std::log1p(std::exp(y)); }

// 1 / (1 + e^-y), the derivative of softplus.
double logistic(double y) {
  if (y >= 0.0) return 1.0 / (1.0 + std::exp(-y));
  const double e = std::exp(y);
  return e / (1.0 + e);
}

// asinh(e^y): for y > 20 the correction to y + ln 2 is below e^-40/4, far under
// round-off, and e^y itself may overflow, so use the asymptote there.
double asinh_exp(double y) { return y > 20.0 ? y + kLn2 : std::asinh(std::exp(y)); }

// d asinh(e^y) / dy = e^y / sqrt(1 + e^2y), written so neither branch overflows.
double asinh_exp_slope(double y) {
  if (y > 0.0) return 1.0 / std::sqrt(1.0 + std::exp(-2.0 * y));
  const double e = std::exp(y);
  return e / std::sqrt(1.0 + e * e);
}

// Dieterich-Ruina state term psi = f0 + b ln(v* phi / D) (dimensionless).
double dr_state_term(const FrictionParameters& p, double state) {
  return p.f0 + p.b * std::log(p.v_star * state / p.characteristic_slip);
}

// ln u_c for the regularized law, where u_c = 2 v* exp(-psi/a) is the slip rate
// at which the asinh argument equals 1.  Kept as a logarithm because exp(-psi/a)
// underflows for small a.
double regularized_log_crossover(const FrictionParameters& p, double state) {
  return std::log(2.0 * p.v_star) - dr_state_term(p, state) / p.a;
}

}  // namespace

namespace {

std::string joined(std::span<const std::string_view> names) {
  std::string out;
  for (const auto name : names) out += (out.empty() ? "" : ", ") + std::string(name);
  return out;
}

template <typename Enum, std::size_t N>
Enum parse_enum(std::string_view name, const std::string_view (&names)[N], std::string_view key) {
  for (std::size_t i = 0; i < N; ++i)
    if (names[i] == name) return static_cast<Enum>(i);
  throw std::invalid_argument(std::string(key) + " = '" + std::string(name) +
                              "' is invalid: allowed values are " + joined(names));
}

template <typename Enum, std::size_t N>
std::string_view enum_text(Enum value, const std::string_view (&names)[N], std::string_view key) {
  const auto i = static_cast<std::size_t>(value);
  if (i >= N)
    throw std::invalid_argument(std::string(key) + ": unknown enumerator " + std::to_string(i));
  return names[i];
}

}  // namespace

StrengthLaw parse_strength_law(std::string_view name) {
  return parse_enum<StrengthLaw>(name, kStrengthLawNames, "friction.law");
}

StateLaw parse_state_law(std::string_view name) {
  return parse_enum<StateLaw>(name, kStateLawNames, "state.law");
}

std::string_view to_string(StrengthLaw law) { return enum_text(law, kStrengthLawNames, "friction.law"); }

std::string_view to_string(StateLaw law) { return enum_text(law, kStateLawNames, "state.law"); }

void validate(const FrictionParameters& friction) {
  // Enumerators outside the declared set (e.g. from a cast) are rejected here.
  (void)to_string(friction.strength_law);
  (void)to_string(friction.state_law);
  require_positive(friction.f0, "friction.f0", "dimensionless friction coefficient");
  require_non_negative(friction.a, "friction.a");
  require_non_negative(friction.b, "friction.b");
  if (friction.strength_law == StrengthLaw::regularized && !(friction.a > 0.0)) {
    throw std::invalid_argument("friction.a = " + format_double(friction.a) +
                                " is invalid for friction.law = regularized: must be > 0 "
                                "(it divides the state term in exp(psi/a))");
  }
  require_positive(friction.characteristic_slip, "friction.characteristic_slip", "metres");
  require_positive(friction.v_star, "friction.v_star", "m/s");
  require_positive(friction.phi_star, "friction.phi_star", "seconds");
  require_non_negative(friction.linker_dieterich, "friction.linker_dieterich");
  if (friction.linker_dieterich > 0.0 && !(state_log_coefficient(friction) > 0.0))
    throw std::invalid_argument("friction.linker_dieterich = " + format_double(friction.linker_dieterich) +
                                " needs friction.b > 0 (the state response divides by the state "
                                "effect B = " + format_double(state_log_coefficient(friction)) + ")");
}

double state_log_coefficient(const FrictionParameters& p) {
  return p.strength_law == StrengthLaw::paper ? p.f0 * p.b : p.b;
}

void validate_normal_stress(double normal_stress) {
  require_positive(normal_stress, "loading.normal_stress", "Pa, compressive");
}

double frictional_strength(const FrictionParameters& p, double normal_stress, double slip_rate,
                           double state) {
  const double u = std::fabs(slip_rate);
  switch (p.strength_law) {
    case StrengthLaw::paper:
      return normal_stress * (p.f0 * (1.0 + p.b * std::log(state / p.phi_star)) +
                              p.a * std::log1p(u / p.v_star));
    case StrengthLaw::dieterich_ruina:
      // ln(0) = -inf: a node under this law can never stick (see docs).
      if (p.a == 0.0) return normal_stress * dr_state_term(p, state);
      return normal_stress *
             (dr_state_term(p, state) + p.a * std::log(u / p.v_star));
    case StrengthLaw::regularized:
      if (u == 0.0) return 0.0;
      return normal_stress * p.a * asinh_exp(std::log(u) - regularized_log_crossover(p, state));
  }
  return std::numeric_limits<double>::quiet_NaN();
}

double frictional_strength_dv(const FrictionParameters& p, double normal_stress, double slip_rate,
                              double state) {
  const double u = std::fabs(slip_rate);
  switch (p.strength_law) {
    case StrengthLaw::paper:
      return normal_stress * p.a / (p.v_star + u);
    case StrengthLaw::dieterich_ruina:
      return p.a == 0.0 ? 0.0 : normal_stress * p.a / u;  // +inf at u = 0
    case StrengthLaw::regularized: {
      // sigma a / sqrt(u^2 + u_c^2); hypot copes with u_c underflowing to 0.
      const double uc = std::exp(regularized_log_crossover(p, state));
      return normal_stress * p.a / std::hypot(u, uc);
    }
  }
  return std::numeric_limits<double>::quiet_NaN();
}

double frictional_strength_dstate(const FrictionParameters& p, double normal_stress,
                                  double slip_rate, double state) {
  const double u = std::fabs(slip_rate);
  switch (p.strength_law) {
    case StrengthLaw::paper:
      return normal_stress * p.f0 * p.b / state;
    case StrengthLaw::dieterich_ruina:
      return normal_stress * p.b / state;
    case StrengthLaw::regularized: {
      // sigma b x / (phi sqrt(1 + x^2)) with x = u/u_c; x/sqrt(1+x^2) = slope of asinh(e^y).
      if (u == 0.0) return 0.0;
      const double y = std::log(u) - regularized_log_crossover(p, state);
      return normal_stress * p.b * asinh_exp_slope(y) / state;
    }
  }
  return std::numeric_limits<double>::quiet_NaN();
}

double state_rate(const FrictionParameters& p, double slip_rate, double state) {
  const double D = p.characteristic_slip;
  switch (p.state_law) {
    case StateLaw::aging:
      return 1.0 - std::hypot(slip_rate, p.v_star) * state / D;
    case StateLaw::slip: {
      const double r = std::fabs(slip_rate) * state / D;
      return r == 0.0 ? 0.0 : -r * std::log(r);  // r ln r -> 0: no evolution at rest
    }
  }
  return std::numeric_limits<double>::quiet_NaN();
}

double state_rate_dv(const FrictionParameters& p, double slip_rate, double state) {
  const double D = p.characteristic_slip;
  const double u = std::fabs(slip_rate);
  switch (p.state_law) {
    case StateLaw::aging:
      return -(u / std::hypot(u, p.v_star)) * state / D;
    case StateLaw::slip: {
      if (u == 0.0) return kInf;  // -(phi/D)(ln r + 1) with ln 0 = -inf
      const double r = u * state / D;
      return -(state / D) * (std::log(r) + 1.0);
    }
  }
  return std::numeric_limits<double>::quiet_NaN();
}

double state_rate_dstate(const FrictionParameters& p, double slip_rate, double state) {
  const double D = p.characteristic_slip;
  const double u = std::fabs(slip_rate);
  switch (p.state_law) {
    case StateLaw::aging:
      return -std::hypot(u, p.v_star) / D;
    case StateLaw::slip: {
      if (u == 0.0) return 0.0;
      const double r = u * state / D;
      return -(u / D) * (std::log(r) + 1.0);
    }
  }
  return std::numeric_limits<double>::quiet_NaN();
}

double steady_state(const FrictionParameters& p, double slip_rate) {
  const double D = p.characteristic_slip;
  switch (p.state_law) {
    case StateLaw::aging:
      return D / std::hypot(slip_rate, p.v_star);
    case StateLaw::slip:
      return D / std::fabs(slip_rate);  // +inf at rest: the slip law has no steady state there
  }
  return std::numeric_limits<double>::quiet_NaN();
}

double steady_state_friction(const FrictionParameters& p, double slip_rate) {
  return frictional_strength(p, 1.0, slip_rate, steady_state(p, slip_rate));
}

double evolve_state(const FrictionParameters& p, double state, double slip_rate, double dt) {
  if (!(state > 0.0) || !std::isfinite(state)) {
    throw std::invalid_argument("evolve_state: state = " + format_double(state) +
                                " is invalid: must be finite and > 0 (seconds)");
  }
  if (!(dt >= 0.0) || !std::isfinite(dt)) {
    throw std::invalid_argument("evolve_state: dt = " + format_double(dt) +
                                " is invalid: must be finite and >= 0 (seconds)");
  }
  const double D = p.characteristic_slip;
  switch (p.state_law) {
    case StateLaw::aging: {
      // Linear ODE with constant coefficients: a convex combination of the old
      // state and phi_ss, so it stays positive for any dt.
      const double h = std::hypot(slip_rate, p.v_star);
      const double phi_ss = D / h;
      const double decay = std::exp(-dt * h / D);
      const double approach = -std::expm1(-dt * h / D);
      return state * decay + phi_ss * approach;
    }
    case StateLaw::slip: {
      const double u = std::fabs(slip_rate);
      if (u == 0.0) return state;
      // psi = ln(u phi / D) decays exponentially with slip; logs avoid overflow.
      const double log_scale = std::log(D) - std::log(u);
      const double psi0 = std::log(state) - log_scale;
      return std::exp(log_scale + psi0 * std::exp(-u * dt / D));
    }
  }
  return std::numeric_limits<double>::quiet_NaN();
}

// ---------------------------------------------------------------------------
// Local solve.  With u = |v| and w = ln u the residual
//   g(w) = |tau_history| - eta e^w - strength(e^w, phi)
// is strictly decreasing and concave in w for all three laws (strength is
// softplus, linear and asinh(e^.) in w respectively, all convex), so a Newton
// step from any point lands at or right of the root, and from the right it
// converges monotonically.  The bracket only guards against round-off.

namespace {

// Everything about one node's residual that does not depend on w.
struct LocalProblem {
  StrengthLaw law;
  double excess;       // paper/regularized: |tau| - strength(0) (> 0);  DR: |tau| - sigma psi + A ln v*
  double excess_scale; // size of the terms that were summed into excess
  double eta;
  double rate_coef;    // A = sigma a [Pa]
  double log_scale;    // paper: ln v*;  regularized: ln u_c;  DR: unused
};

struct Residual {
  double g;      // [Pa]
  double slope;  // dg/dw [Pa]
  double scale;  // magnitude of the terms summed in g, for the round-off floor
};

Residual evaluate(const LocalProblem& lp, double w) {
  const double u = std::exp(w);
  const double radiation = lp.eta * u;
  double rate_term = 0.0;
  double rate_slope = 0.0;
  switch (lp.law) {
    case StrengthLaw::paper:
      rate_term = lp.rate_coef * softplus(w - lp.log_scale);
      rate_slope = lp.rate_coef * logistic(w - lp.log_scale);
      break;
    case StrengthLaw::regularized:
      rate_term = lp.rate_coef * asinh_exp(w - lp.log_scale);
      rate_slope = lp.rate_coef * asinh_exp_slope(w - lp.log_scale);
      break;
    case StrengthLaw::dieterich_ruina:
      rate_term = lp.rate_coef * w;
      rate_slope = lp.rate_coef;
      break;
  }
  return {lp.excess - radiation - rate_term, -(radiation + rate_slope),
          lp.excess_scale + radiation + std::fabs(rate_term)};
}

[[noreturn]] void fail(const char* reason, const FrictionParameters& p, double normal_stress,
                       double eta, double tau_history, double state, double initial_guess,
                       double lo, double hi, int iterations) {
  std::string message = std::string("solve_slip_rate failed (") + reason +
                        "): tau_history = " + format_double(tau_history) +
                        " Pa, state = " + format_double(state) + " s, eta = " + format_double(eta) +
                        " Pa s/m, normal_stress = " + format_double(normal_stress) +
                        " Pa, initial_guess = " + format_double(initial_guess) +
                        " m/s, strength law = " + std::string(to_string(p.strength_law)) +
                        ", last bracket |v| in [" + format_double(std::exp(lo)) + ", " +
                        format_double(std::exp(hi)) + "] m/s (ln: [" + format_double(lo) + ", " +
                        format_double(hi) + "]), iterations = " + std::to_string(iterations);
  throw LocalSolveFailure(message);
}

}  // namespace

SlipRateSolution solve_slip_rate_counted(const FrictionParameters& p, double normal_stress,
                                         double eta, double tau_history, double state,
                                         double initial_guess) {
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  if (!std::isfinite(tau_history) || !std::isfinite(state) || !(state > 0.0) ||
      !std::isfinite(eta) || !(eta > 0.0) || !std::isfinite(normal_stress) ||
      !(normal_stress > 0.0)) {
    fail("non-finite or out-of-range input: need finite tau_history, state > 0, eta > 0, "
         "normal_stress > 0",
         p, normal_stress, eta, tau_history, state, initial_guess, nan, nan, 0);
  }
  const double T = std::fabs(tau_history);
  const double sign = tau_history < 0.0 ? -1.0 : 1.0;
  const double A = normal_stress * p.a;

  // Per-law constants of g(w), the strength at rest, and bounds on the root in
  // w = ln u from simple bounds on the strength.  The upper bound is always
  // needed (it caps a wild initial guess); the lower bound costs two more
  // logarithms and is only needed by bisection or a cold start, so it is
  // computed lazily.  Both are widened by a small margin so round-off in them
  // can never put the root outside.
  constexpr double margin = local_solve::kBracketMargin;
  LocalProblem lp{p.strength_law, 0.0, T, eta, A, 0.0};
  double strength_at_rest = 0.0;
  switch (p.strength_law) {
    case StrengthLaw::paper:
      // Same expression (and rounding) as frictional_strength(p, sigma, 0, phi),
      // so "T <= strength at rest" agrees bit for bit with what callers compute.
      strength_at_rest = normal_stress * (p.f0 * (1.0 + p.b * std::log(state / p.phi_star)));
      lp.log_scale = std::log(p.v_star);
      break;
    case StrengthLaw::regularized:
      strength_at_rest = 0.0;
      break;
    case StrengthLaw::dieterich_ruina:
      // ln(0) = -inf: with a > 0 the strength at rest is -inf and the node never sticks.
      strength_at_rest = A == 0.0 ? normal_stress * dr_state_term(p, state) : -kInf;
      break;
  }

  // Sticking: the strength at rest can hold the whole load.
  if (T <= strength_at_rest) return {0.0, 0};
  if (tau_history == 0.0) {
    fail("strength at rest is negative, so the slip direction is undefined for zero load",
         p, normal_stress, eta, tau_history, state, initial_guess, nan, nan, 0);
  }
  // Rate-independent strength: closed form.
  if (A == 0.0) return {sign * (T - strength_at_rest) / eta, 1};

  double hi = 0.0;
  switch (p.strength_law) {
    case StrengthLaw::paper:
      // strength(u) - strength(0) = A ln(1 + u/v*) lies in (0, A u / v*).
      lp.excess = T - strength_at_rest;  // correctly rounded; exact when T is close (Sterbenz)
      lp.excess_scale = lp.excess;
      hi = std::log(lp.excess / eta) + margin;
      break;
    case StrengthLaw::regularized:
      // strength(u) = A asinh(u/u_c) lies in (0, A u / u_c).
      lp.excess = T;
      lp.excess_scale = T;
      lp.log_scale = regularized_log_crossover(p, state);
      hi = std::log(T / eta) + margin;
      break;
    case StrengthLaw::dieterich_ruina: {
      // g(w) = c - eta e^w - A w with c = T - sigma psi + A ln v*.
      const double state_part = normal_stress * dr_state_term(p, state);
      const double reference_part = A * std::log(p.v_star);
      lp.excess = T - state_part + reference_part;
      lp.excess_scale = T + std::fabs(state_part) + std::fabs(reference_part);
      // At hi: eta e^w >= T and A w >= c - T + A, so g <= -A < 0.
      hi = std::max(std::log(T / eta), (lp.excess - T) / A + 1.0) + margin;
      break;
    }
  }
  const auto lower_bound = [&]() {
    switch (p.strength_law) {
      case StrengthLaw::paper:
        return std::log(lp.excess) - std::log(eta + A / p.v_star) - margin;
      case StrengthLaw::regularized: {
        // ln(eta + A/u_c) without forming A/u_c, which overflows for small u_c.
        const double log_a = std::log(eta);
        const double log_b = std::log(A) - lp.log_scale;
        const double log_sum =
            std::max(log_a, log_b) + std::log1p(std::exp(-std::fabs(log_a - log_b)));
        return std::log(T) - log_sum - margin;
      }
      case StrengthLaw::dieterich_ruina:
        // At lo: eta e^w <= T/2 and A w <= c - T/2 - A, so g >= A > 0.
        return std::min(std::log(0.5 * T / eta), (lp.excess - 0.5 * T) / A - 1.0) - margin;
    }
    return nan;
  };
  double lo = -kInf;  // until needed; any evaluated point with g > 0 also tightens it
  bool lower_bound_known = false;
  const auto ensure_lower_bound = [&]() {
    if (!lower_bound_known) {
      lo = std::max(lo, lower_bound());
      lower_bound_known = true;
    }
    if (!(std::isfinite(lo) && std::isfinite(hi) && lo < hi)) {
      fail("could not bracket the root", p, normal_stress, eta, tau_history, state, initial_guess,
           lo, hi, 0);
    }
  };
  if (!std::isfinite(hi)) {
    fail("could not bound the root", p, normal_stress, eta, tau_history, state, initial_guess, lo,
         hi, 0);
  }

  // Warm start from the previous slip rate (its magnitude: the sign is set by
  // tau_history).  Without a usable guess start at the lower bound, which is
  // nearly exact when the load barely exceeds the strength at rest (the usual
  // way a stuck node starts to slide).
  const double guess = std::fabs(initial_guess);
  double w = 0.0;
  if (std::isfinite(guess) && guess > 0.0) {
    w = std::min(std::log(guess), hi);
  } else {
    ensure_lower_bound();
    w = lo;
  }

  // Acceptance (local_solve::kAcceptStep): |dw| <= 1e-6 leaves a relative
  // error <= 1e-12 in u.  The last step is taken in u, u (1 + dw), rather
  // than as exp(w + dw) because exp(w) carries the rounding of w itself
  // (|w| eps relative: 5e-14 at u ~ 1e94 m/s).
  constexpr int max_iterations = 200;
  constexpr double accept_step = local_solve::kAcceptStep;
  constexpr double bracket_tolerance = 1e-12;
  int slow_steps = 0;
  double previous_abs_g = kInf;
  for (int iteration = 1; iteration <= max_iterations; ++iteration) {
    const Residual r = evaluate(lp, w);
    if (!std::isfinite(r.g) || !std::isfinite(r.slope)) {
      fail("non-finite residual", p, normal_stress, eta, tau_history, state, initial_guess, lo, hi,
           iteration);
    }
    const double u = std::exp(w);
    const double step = -r.g / r.slope;  // Newton step in w
    if (std::fabs(step) <= accept_step) return {sign * (u + u * step), iteration};
    // Round-off floor: the root is only defined to within the rounding of the
    // terms of g (this is the absolute tolerance that matters near u = 0).
    if (std::fabs(r.g) <= local_solve::kRoundoffFloor * r.scale) return {sign * u, iteration};

    if (r.g > 0.0) {
      lo = w;
    } else {
      hi = w;
    }
    const double abs_g = std::fabs(r.g);
    slow_steps = abs_g > 0.5 * previous_abs_g ? slow_steps + 1 : 0;
    previous_abs_g = abs_g;

    double next = w + step;
    if (!(next > lo && next < hi) || slow_steps >= 2) {
      ensure_lower_bound();
      next = 0.5 * (lo + hi);
      slow_steps = 0;
    }
    if (hi - lo <= bracket_tolerance) return {sign * std::exp(next), iteration};
    w = next;
  }
  fail("no convergence within the iteration cap", p, normal_stress, eta, tau_history, state,
       initial_guess, lo, hi, max_iterations);
}

double solve_slip_rate(const FrictionParameters& friction, double normal_stress, double eta,
                       double tau_history, double state, double initial_guess) {
  return solve_slip_rate_counted(friction, normal_stress, eta, tau_history, state, initial_guess)
      .slip_rate;
}

}  // namespace slipstrip
