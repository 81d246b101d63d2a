#pragma once
// Rate-and-state friction: strength laws, state evolution laws and the
// derivatives that linear stability needs.  SI units: stress [Pa], slip rate
// [m/s], state phi [s] (contact age), slip [m].
#include <stdexcept>
#include <string>
#include <string_view>

namespace slipstrip {

// Strength law tau(v, phi):
//   paper           : tau/sigma0 = f0 [1 + b ln(phi/phi*)] + a ln(1 + |v|/v*)      (Eq. S1)
//   dieterich_ruina : tau/sigma0 = f0 + a ln(|v|/v*) + b ln(v* phi / D)           (classic log form)
//   regularized     : tau/sigma0 = a asinh( |v|/(2 v*) exp([f0 + b ln(v* phi/D)]/a) )
// (for the last two, f0 and b have their usual Dieterich-Ruina meaning, not the
//  paper's f0*b product; v_star plays the reference velocity.)
enum class StrengthLaw { paper, dieterich_ruina, regularized };
// State evolution law:
//   aging : dphi/dt = 1 - sqrt(v^2 + v*^2) phi / D                 (Eq. S2, regularised)
//   slip  : dphi/dt = -(|v| phi / D) ln(|v| phi / D)               (Eq. 2 of the paper)
enum class StateLaw { aging, slip };

// The one spelling of each enumerator (index = enumerator value), shared by
// parse/to_string below, the config schema (config/config_schema.cpp) and the
// Python binding.
inline constexpr std::string_view kStrengthLawNames[] = {"paper", "dieterich_ruina", "regularized"};
inline constexpr std::string_view kStateLawNames[] = {"aging", "slip"};

// Generous bounds of the dimensionless coefficients f0, a, b: real ones are
// O(0.01-1); beyond 10 the strength (and the local solve at t = 0) is
// meaningless.  Applied to scalar config keys and to every node of a profile.
inline constexpr double kMaxFrictionCoefficient = 10.0;
// Generous range of the characteristic slip D [m] (docs/config.md, "Ranges").
inline constexpr double kMinCharacteristicSlip = 1e-12;
inline constexpr double kMaxCharacteristicSlip = 1.0;

struct FrictionParameters {
  StrengthLaw strength_law = StrengthLaw::paper;
  StateLaw state_law = StateLaw::aging;
  double f0 = 0.28;
  double a = 0.005;
  double b = 0.075;
  double characteristic_slip = 5e-7;  // D [m]
  double v_star = 1e-7;               // v* [m/s]
  double phi_star = 3.3e-4;           // phi* [s]
  // alpha_LD of Linker & Dieterich (1992): where the normal stress changes
  // (in-plane pairs of different bodies) d ln(phi)/dt gains
  // -(alpha_LD / B) d ln(sigma_eff)/dt, B = state_log_coefficient; a step of
  // normal stress then changes the friction coefficient by -alpha_LD ln(sigma
  // ratio) through the state (docs/bodies.md §4).  0 = off.  The strength and
  // state-rate functions below do not use it.
  double linker_dieterich = 0.0;
};

StrengthLaw parse_strength_law(std::string_view name);  // throws, listing allowed names
StateLaw parse_state_law(std::string_view name);
std::string_view to_string(StrengthLaw law);
std::string_view to_string(StateLaw law);
void validate(const FrictionParameters& friction);  // throws std::invalid_argument naming the key

// Strength for slip rate magnitude |v| (the local solve applies sign(v)).
double frictional_strength(const FrictionParameters& friction, double normal_stress,
                           double slip_rate, double state);
double frictional_strength_dv(const FrictionParameters& friction, double normal_stress,
                              double slip_rate, double state);     // d tau / d|v|
double frictional_strength_dstate(const FrictionParameters& friction, double normal_stress,
                                  double slip_rate, double state);  // d tau / d phi

// The *_dv derivatives below are with respect to the slip-rate magnitude |v|
// (like frictional_strength_dv); at v = 0 the slip law's is +inf.
double state_rate(const FrictionParameters& friction, double slip_rate, double state);  // dphi/dt
double state_rate_dv(const FrictionParameters& friction, double slip_rate, double state);
double state_rate_dstate(const FrictionParameters& friction, double slip_rate, double state);
double steady_state(const FrictionParameters& friction, double slip_rate);  // phi_ss(v)
double steady_state_friction(const FrictionParameters& friction, double slip_rate);  // f_ss(v)
// B, the coefficient of ln(phi) in the friction coefficient: f0 b for the paper
// law (Eq. S1), b for the Dieterich-Ruina forms (for "regularized", inside the
// asinh: its d f / d ln(phi) tends to b for |v| >> v*).
double state_log_coefficient(const FrictionParameters& friction);

// phi(t + dt) for a slip rate held constant over the step: exact for both laws,
// so the update stays accurate (and positive) at large v dt / D.
double evolve_state(const FrictionParameters& friction, double state, double slip_rate, double dt);

// Local interface solve at one node:
//   tau_history - eta * v = sign(v) * strength(|v|, phi),
// with sticking (v = 0) when |tau_history| <= strength(0, phi).  eta = mu / (2 c_s).
// Safeguarded Newton (bracket + bisection fallback + iteration cap).  Never
// returns a silently wrong value: throws LocalSolveFailure with all inputs.
struct LocalSolveFailure : std::runtime_error {
  using std::runtime_error::runtime_error;
};
double solve_slip_rate(const FrictionParameters& friction, double normal_stress, double eta,
                       double tau_history, double state, double initial_guess);

// --- Additions (the declarations above are the shared contract) ---------------

// Throws std::invalid_argument naming loading.normal_stress unless it is finite
// and > 0 (compressive normal stress sigma0 [Pa]).
void validate_normal_stress(double normal_stress);

// The same solve as solve_slip_rate, also reporting how many residual
// evaluations it needed (0 when the node sticks); for tests and benchmarks.
struct SlipRateSolution {
  double slip_rate = 0.0;  // [m/s], signed like tau_history
  int iterations = 0;
};
SlipRateSolution solve_slip_rate_counted(const FrictionParameters& friction, double normal_stress,
                                         double eta, double tau_history, double state,
                                         double initial_guess);

}  // namespace slipstrip
