#pragma once
// Linear stability of steady sliding between ANY two bodies (docs/inplane_bodies.md §3):
// the dispersion relation of stability/linear_stability.hpp generalised to a pair
// whose slip changes the normal stress.
//
// Perturbations ~ exp(i k x + Lambda t).  Elastodynamics (kernels/face_response.hpp):
//   sigma_xy^ = -K_xx delta^,   compressive normal stress sigma^ = -sigma_yy^ = K_yx delta^,
// K = K_ser(k, Lambda) the series stiffness of the two bodies.  Friction, linearised
// at (v0, phi0, sigma0), strength tau = sigma_eff f(v, phi):
//   tau^ = tau_v v^ + tau_phi phi^ + f0 sigma_eff^,           f0 = tau0 / sigma0,
//   Lambda phi^ = g_v v^ + g_phi phi^ - (alpha_LD phi0 / (B sigma0)) Lambda sigma_eff^   (Linker-Dieterich),
//   sigma_eff^ = sigma^ / (1 + Lambda T)                       (Prakash-Clifton / Cochard-Rice),
// so that
//   F(Lambda) = K_xx + Lambda [tau_v + tau_phi g_v / (Lambda - g_phi)]
//             + [f0 - a_LD Lambda / (Lambda - g_phi)] K_yx / (1 + Lambda T),
// a_LD = alpha_LD tau_phi phi0 / (B sigma0), B = state_log_coefficient: the
// linearisation of the solver's d ln(phi)/dt = ... - (alpha_LD/B) d ln(sigma_eff)/dt
// (laws/law_rate_and_state.cpp); a_LD = alpha_LD for the paper and DR laws.
// For identical bodies K_yx = 0 and K_xx = S(k, Lambda; H): F is then the function of
// stability/linear_stability.hpp, and pair_characteristic_roots uses that very
// function (the roots are today's, bit for bit).
#include <complex>
#include <vector>

#include "friction/friction_law.hpp"
#include "kernels/face_response.hpp"
#include "stability/root_search.hpp"

namespace slipstrip {

// How the friction sees a changing normal stress sigma (docs/inplane_bodies.md §3):
//   instantaneous : sigma_eff = sigma (ill-posed for many bimaterial pairs);
//   slip          : d sigma_eff/dt = -((|v| + v*) / slip) (sigma_eff - sigma)  (Cochard & Rice 2000);
//   time          : d sigma_eff/dt = -(sigma_eff - sigma) / time              (Prakash-Clifton, fixed time).
// The Linker & Dieterich (1992) state response is friction.linker_dieterich
// (FrictionParameters): it follows sigma_eff, as the strength does.
enum class NormalStressResponse { instantaneous, slip, time };
struct NormalStressRegularisation {
  NormalStressResponse kind = NormalStressResponse::instantaneous;
  double slip = 0.0;  // L_sigma [m]
  double time = 0.0;  // t_sigma [s]
};

struct PairSliding {
  ElasticBody top, bottom;
  FrictionParameters friction;
  NormalStressRegularisation normal_response;
  double normal_stress = 1e6;      // sigma0 [Pa], compressive
  double driving_velocity = 2e-3;  // v0 [m/s]: top body relative to bottom, along +x
};

// Everything of the friction that enters F (the rate-and-state part as in
// LinearisedFriction, plus the normal-stress response).
struct LinearisedInterfaceFriction {
  double strength_dv = 0.0;        // tau_v   [Pa s/m]
  double strength_dstate = 0.0;    // tau_phi [Pa/s]
  double state_rate_dv = 0.0;      // g_v     [s/m]
  double state_rate_dstate = 0.0;  // g_phi   [1/s]
  double friction_coefficient = 0.0;     // f0 = d tau / d sigma_eff at steady state
  double normal_relaxation_time = 0.0;   // T [s] (0: instantaneous)
  double linker_dieterich = 0.0;         // a_LD = alpha_LD tau_phi phi0 / (B sigma0)
};
LinearisedInterfaceFriction linearise_interface_friction(const PairSliding& sliding);

// True when the pair is two identical deformable bodies with driven outer faces
// (the mirror-symmetric problem of docs/theory.md §1).
bool is_mirror_pair(const PairSliding& sliding);

// F(Lambda) above, for a signed wavenumber k [1/m].
std::complex<double> pair_characteristic_function(const PairSliding& sliding,
                                                  const LinearisedInterfaceFriction& friction,
                                                  double wavenumber, std::complex<double> growth);

// The friction's two terms of F, shared with the oblique modes of a pair
// (stability/oblique_stability.hpp):
//   rate_and_state_response = Lambda [tau_v + tau_phi g_v / (Lambda - g_phi)],
// the strength's response to a slip perturbation of unit amplitude, and
//   normal_stress_response  = [f0 - a_LD Lambda / (Lambda - g_phi)] sigma^ / (1 + Lambda T),
// its response to a perturbation sigma^ [Pa] of the compressive normal stress
// through sigma_eff (and the Linker-Dieterich state response) [Pa].
std::complex<double> rate_and_state_response(const LinearisedInterfaceFriction& friction,
                                             std::complex<double> growth);
std::complex<double> normal_stress_response(const LinearisedInterfaceFriction& friction,
                                            std::complex<double> growth, std::complex<double> normal_stress);

// Rectangle min_re <= Re Lambda <= max_re, |Im Lambda| <= max_im [1/s].
struct PairSearchBox {
  double min_re, max_re, max_im;
};

// The zeros of a pair's dispersion function g in the box, sorted by decreasing
// Re Lambda: the graded search of pair_characteristic_roots (its reasons there),
// for any g whose poles are those of the pair's responses and friction (none
// with Re Lambda > 0).
std::vector<std::complex<double>> pair_zeros_in(const AnalyticFunction& g, const PairSearchBox& box);

// A box for the unstable roots at wavenumber k: the rate-and-state bound of
// unstable_search_box (which is a proof for identical bodies only) united with the
// elastic wave scale 2 c_d,max |k| in both directions.  For dissimilar bodies this is
// a search region, not a proof that no unstable root lies outside it.
PairSearchBox pair_search_box(const PairSliding& sliding, const LinearisedInterfaceFriction& friction,
                              double wavenumber);

// All zeros of F in the box (argument principle; F has no poles for Re Lambda > 0
// when g_phi < 0 and T >= 0, because the bodies are passive and lossless or
// radiating), sorted by decreasing Re Lambda.  k > 0 suffices: the roots at -k are
// the complex conjugates (real fields).  A root travels along x at -Im(Lambda)/k.
// Identical driven bodies use stability/linear_stability's F itself.
std::vector<std::complex<double>> pair_characteristic_roots(
    const PairSliding& sliding, const LinearisedInterfaceFriction& friction, double wavenumber,
    const PairSearchBox& box);

// The unstable roots at one wavelength [m] (pair_characteristic_roots in
// pair_search_box), fastest first; empty when steady sliding is stable there
// (within that box: a search region, not a proof, for dissimilar bodies).
std::vector<std::complex<double>> pair_unstable_roots(const PairSliding& sliding, double wavelength);

// The critical wavelength: the shortest wavelength in [shortest, longest] [m]
// with an unstable root, located to a relative 1e-6 by bisection between
// the last stable and the first unstable of 64 log-spaced wavelengths.  NaN
// when every sampled wavelength is stable, `shortest` when all are unstable.
double pair_critical_wavelength(const PairSliding& sliding, double shortest, double longest);

// Lc(H) of a pair (docs/bodies.md §5): the top body's height set to each of
// `heights` [m] (inf: a top half-space), the bottom body kept as given; each
// Lc by pair_critical_wavelength over [shortest, longest].  The scan a
// slider-on-base experiment asks (how thick a slider must be), defined for
// every bottom body: a strip, a half-space or a rigid base.
std::vector<double> pair_critical_wavelength_vs_top_height(const PairSliding& sliding,
                                                           const std::vector<double>& heights, double shortest,
                                                           double longest);

}  // namespace slipstrip
