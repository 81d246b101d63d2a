// Linear stability theory (stability/linear_stability.hpp) verified with the
// solver itself: a small sinusoidal state perturbation of steady sliding is
// simulated, the exponential rates present in the Fourier mode of the
// perturbation are measured from the simulated time series, and compared with
// the roots of the characteristic function F(Lambda) computed at test time.
//
// Why the comparison is independent: the theory is a root search on the
// closed-form strip response S(k, Lambda; H) with the analytic friction
// derivatives; the simulation is the explicit time stepper with the discrete
// history operator (delay line + normal-mode recursions) and the nonlinear
// local friction solve.  They share only the friction law and the material.
//
// Measurement (see docs/verification_growth.md):
//  * Mode amplitude: c(t) = 2/N * FFT(field)[1] of slip_rate - v0 (divided by v0)
//    and of state (divided by phi_ss).  The initial condition is
//    phi_ss (1 + eps cos(2 pi x / L)) and the problem is invariant under
//    x -> -x, so the mode stays a standing cosine: Re c carries it, Im c is
//    round-off.
//  * The roots are complex (|Im Lambda| ~ 3e3-9e3 rad/s), so Re c(t)
//    oscillates and has too few extrema per e-fold (0.5-1.1) for a peak fit.
//    Two estimators are used instead:
//    (a) envelope ("Wronskian"): if one root pair dominates, the vector
//        y(t) = (Re c_v, Re c_phi) = e^{sigma t} M (cos wt, sin wt) for a
//        constant real 2x2 matrix M, hence
//        W(t) = y1(t) y2(t+tau) - y1(t+tau) y2(t) = e^{sigma (2t+tau)} det M sin(w tau)
//        exactly: ln|W|/2 is a straight line of slope sigma = Re Lambda, with
//        no oscillation and no nonlinear fit.
//    (b) matrix pencil: all damped exponentials present in Re c_v(t) (SVD of
//        the Hankel matrix, poles = eigenvalues of the shifted signal
//        subspace).  This separates several modes when none dominates (the
//        stable case, where a weakly damped thickness resonance coexists with
//        the frictional mode).
//  * Linear regime: the record stops before max_x |v - v0| / v0 exceeds 1e-2.
//
// Resolution: in the linear regime each Fourier mode evolves independently
// and mode 1 is represented exactly by the spectral method, so the node count
// only sets the time step dt = beta dx / c_s.  N = 64 (dt ~ 1e-6 s, 1000+
// steps per e-fold and per period) is used; N = 128 and N = 256 are compared
// in the tests below and in the "slow" suite.
//
// Tolerance: 2% relative on Re Lambda, from the issue (the scheme's dt error
// and the fit error are measured here to be ~1e-4 relative, see the doc).
//
// Run: ./test_solver_growth_rates -tse=slow  (default set, ~3 s on one core)
//      ./test_solver_growth_rates -ts=slow   (refinement and linearity, ~6 s)
//      ./test_solver_growth_rates            (both; what ctest runs)
#include <doctest/doctest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <span>
#include <type_traits>
#include <vector>

#include "stability/steady_sliding.hpp"
#include "solver/simulation.hpp"
#include "stability/interface_stability.hpp"
#include "stability/linear_stability.hpp"
#include "kernels/fft.hpp"
#include "kernels/two_body_history.hpp"
#include "matrix_pencil.hpp"

using namespace slipstrip;
using testing::matrix_pencil;
using testing::Pole;

namespace {

constexpr double pi = std::numbers::pi;
constexpr double linear_limit = 1e-2;  // max |v - v0| / v0 kept in the record
constexpr double tolerance = 0.02;     // relative, on Re Lambda (issue requirement)

struct Case {
  double strip_height;  // H [m]
  double length;        // L [m] = wavelength of the perturbation (sine_mode 1)
  PlaneCondition plane = PlaneCondition::strain;
  StateLaw state_law = StateLaw::aging;
  int nodes = 64;
  double beta = 0.25;
  double sine_amplitude = 1e-4;
  int sine_mode = 1;  // 0 = uniform perturbation (k = 0, wavelength +inf)
  // A different bottom body (docs/bodies.md; antiplane): mirror = identical.
  BodyKind bottom = BodyKind::mirror;
  double bottom_shear_modulus = 9e9, bottom_density = 1200.0, bottom_height = 0.1;
  double linker_dieterich = 0.0;  // friction.linker_dieterich (in-plane dissimilar pairs)
  // time.antiplane_pair: an antiplane pair of two different strips or half-spaces
  // by one combined operator or by each body's own.
  AntiplanePairOperator antiplane_pair = AntiplanePairOperator::combined;
};

SimulationConfig make_config(const Case& c) {
  SimulationConfig config;  // defaults: Table S1, plane strain, aging law
  config.geometry.length = c.length;
  config.geometry.height = c.strip_height;
  config.geometry.nodes = c.nodes;
  config.material.plane = c.plane;
  config.friction.state_law = c.state_law;
  config.time.beta = c.beta;
  config.initial.sine_amplitude = c.sine_amplitude;
  config.initial.sine_mode = c.sine_mode;
  config.bottom.body = c.bottom;
  config.bottom.shear_modulus = c.bottom_shear_modulus;
  config.bottom.density = c.bottom_density;
  config.bottom.height = c.bottom_height;
  config.friction.linker_dieterich = c.linker_dieterich;
  config.time.antiplane_pair = c.antiplane_pair;
  return config;
}

// Wavelength of the perturbed Fourier mode (+inf for the uniform mode).
double wavelength(const Case& c) {
  return c.sine_mode == 0 ? std::numeric_limits<double>::infinity() : c.length / c.sine_mode;
}

// History of Fourier mode c.sine_mode of one simulation, stopped at max_duration or just before the
// perturbation leaves the linear regime.
struct ModeRecord {
  double dt = 0.0;
  std::vector<double> slip_rate;  // Re c_v(t_n) / v0
  std::vector<std::complex<double>> slip_rate_complex;  // c_v(t_n) / v0
  std::vector<double> state;      // Re c_phi(t_n) / phi_ss
  bool left_linear_regime = false;
  double time(std::size_t n) const { return static_cast<double>(n) * dt; }
};

ModeRecord simulate_mode(const Case& c, double max_duration) {
  const SimulationConfig config = make_config(c);
  Simulation sim(config);
  const int n = c.nodes;
  const double v0 = config.loading.driving_velocity;
  const double phi_ss = steady_state(config.friction, v0);
  RealFft fft(n);
  std::vector<double> field(static_cast<std::size_t>(n));
  std::vector<std::complex<double>> spectrum(static_cast<std::size_t>(n / 2 + 1));
  const auto mode = static_cast<std::size_t>(c.sine_mode);
  // c_q = (2/N) FFT[q] is the cosine amplitude for q >= 1; the mean for q = 0
  const double scale = (mode == 0 ? 1.0 : 2.0) / n;
  ModeRecord record;
  record.dt = sim.time_step();
  const auto steps = static_cast<long long>(std::ceil(max_duration / record.dt));
  record.slip_rate.reserve(static_cast<std::size_t>(steps + 1));
  record.state.reserve(static_cast<std::size_t>(steps + 1));
  for (long long step = 0; step <= steps; ++step) {
    double largest = 0.0;
    for (int i = 0; i < n; ++i) {
      field[i] = sim.slip_rate()[i] - v0;
      largest = std::max(largest, std::abs(field[i]) / v0);
    }
    if (largest > linear_limit) {
      record.left_linear_regime = true;
      break;
    }
    fft.forward(field, spectrum);
    record.slip_rate.push_back(scale * spectrum[mode].real() / v0);
    record.slip_rate_complex.push_back(scale * spectrum[mode] / v0);
    for (int i = 0; i < n; ++i) field[i] = sim.state()[i] - phi_ss;
    fft.forward(field, spectrum);
    record.state.push_back(scale * spectrum[mode].real() / phi_ss);
    sim.step();
  }
  return record;
}

// Estimator (a): slope of ln|W|/2 by least squares over samples [first, last).
double envelope_growth_rate(const ModeRecord& r, std::size_t first, std::size_t last, double lag) {
  const auto shift = static_cast<std::size_t>(std::max(1.0, std::round(lag / r.dt)));
  REQUIRE(last > first + shift + 10);
  double st = 0, sy = 0, stt = 0, sty = 0;
  std::size_t count = 0;
  for (std::size_t n = first; n + shift < last; ++n) {
    const double w = r.slip_rate[n] * r.state[n + shift] - r.slip_rate[n + shift] * r.state[n];
    const double y = 0.5 * std::log(std::abs(w));
    const double t = r.time(n);
    st += t;
    sy += y;
    stt += t * t;
    sty += t * y;
    ++count;
  }
  const double c = static_cast<double>(count);
  return (c * sty - st * sy) / (c * stt - st * st);
}

// The pole dominating the end of the window (data-driven identification).
Pole dominant_pole(const std::vector<Pole>& poles) {
  REQUIRE(!poles.empty());
  return *std::max_element(poles.begin(), poles.end(), [](const Pole& a, const Pole& b) {
    return a.final_amplitude < b.final_amplitude;
  });
}

// The measured pole whose frequency is nearest to a theoretical root, among the
// poles carrying at least 1e-3 of the largest initial amplitude (the pencil
// also returns tiny spurious poles that fit round-off).
std::optional<Pole> pole_near(const std::vector<Pole>& poles, std::complex<double> root) {
  double largest = 0.0;
  for (const auto& p : poles) largest = std::max(largest, p.initial_amplitude);
  std::optional<Pole> best;
  for (const auto& p : poles) {
    if (p.initial_amplitude < 1e-3 * largest) continue;
    if (!best || std::abs(p.rate.imag() - std::abs(root.imag())) <
                     std::abs(best->rate.imag() - std::abs(root.imag())))
      best = p;
  }
  return best;
}

struct GrowthMeasurement {
  double theory;    // Re Lambda of the most unstable / least-damped root in the box [1/s]
  double frequency; // its |Im Lambda| [rad/s]
  double envelope;  // estimator (a) [1/s]
  double pencil;    // estimator (b): dominant pole [1/s]
  double pencil_frequency;
  double fit_start, fit_end;  // window [s]
  double dt;
};

// Growing case: run until the linear limit, fit over the second half of the
// record (the first half contains the transient of the other roots).
GrowthMeasurement measure_unstable(const Case& c, double max_duration) {
  const SimulationConfig config = make_config(c);
  const auto theory = growth_rates(steady_sliding_of(config), {wavelength(c)}).at(0);
  const ModeRecord r = simulate_mode(c, max_duration);
  const std::size_t last = r.slip_rate.size();
  const std::size_t first = last / 2;
  // lag 1e-4 s: w tau = 0.3-0.9 rad for these roots, far from sin(w tau) = 0
  const double envelope = envelope_growth_rate(r, first, last, 1e-4);
  const std::size_t decimation = std::max<std::size_t>(1, (last - first) / 600);
  const auto poles = matrix_pencil(r.slip_rate, r.dt, first, last, decimation, 1e-8);
  const Pole dominant = dominant_pole(poles);
  return {theory.growth_rate,   theory.frequency, envelope, dominant.rate.real(),
          std::abs(dominant.rate.imag()), r.time(first), r.time(last - 1), r.dt};
}

void report(const char* label, const Case& c, const GrowthMeasurement& m) {
  std::printf(
      "%-28s H=%.3f L=%.4f N=%d beta=%.3f dt=%.3e window=[%.3e,%.3e] s  theory Re=%.3f Im=%.1f  "
      "envelope=%.3f (%.2e)  pencil=%.3f (%.2e) Im=%.1f\n",
      label, c.strip_height, c.length, c.nodes, c.beta, m.dt, m.fit_start, m.fit_end, m.theory,
      m.frequency, m.envelope, (m.envelope - m.theory) / std::abs(m.theory), m.pencil,
      (m.pencil - m.theory) / std::abs(m.theory), m.pencil_frequency);
}

void check_unstable(const char* label, const Case& c, double max_duration = 8e-3) {
  const GrowthMeasurement m = measure_unstable(c, max_duration);
  report(label, c, m);
  REQUIRE(m.theory > 0.0);
  CHECK(std::abs(m.envelope - m.theory) <= tolerance * m.theory);
  CHECK(std::abs(m.pencil - m.theory) <= tolerance * m.theory);
  // the dominant measured oscillation is the theory's root, not another one
  CHECK(std::abs(m.pencil_frequency - m.frequency) <= tolerance * m.frequency);
}

}  // namespace

TEST_CASE("growth rate of the unstable mode matches linear stability, plane strain") {
  // Table S1, plane strain (SimulationConfig defaults), eps = 1e-4, sine_mode 1.
  check_unstable("strain H=0.1 L=0.8", {0.1, 0.8});
  check_unstable("strain H=0.1 L=1.0", {0.1, 1.0});
  check_unstable("strain H=0.05 L=0.6", {0.05, 0.6});
  check_unstable("strain H=0.2 L=1.2", {0.2, 1.2});
}

TEST_CASE("half-space (bounded-memory operator): growth rates match linear stability") {
  // Lc(inf) = 1.187 m (plane strain); the exact S_inf enters the theory, the
  // passive sampled operator (kernels/half_space_history.hpp) the simulation.
  // A half-space's initial-value response also has branch-point (continuous
  // spectrum) parts that decay only algebraically; with eps = 1e-4 the linear
  // window is short and they bias the fit by 0.4-3 % (measured, independent of
  // dt and N).  eps = 1e-8 gives a window ~4x longer, where they have died out.
  const double inf = std::numeric_limits<double>::infinity();
  for (double L : {1.6, 2.4}) {
    Case c{inf, L};
    c.sine_amplitude = 1e-8;
    check_unstable(L == 1.6 ? "half-space L=1.6" : "half-space L=2.4", c, 2e-2);
  }
}

TEST_CASE("antiplane: growth rates of identical and dissimilar pairs match linear stability") {
  // SH kernels (docs/bodies.md): the theory uses the closed-form S (pair) or
  // (1/K_t + 1/K_b)^-1 (two bodies), the simulation the discrete operators.
  // H = 0.4 m: an antiplane strip's static stiffness is at least mu/(2H), so
  // thinner strips of Table S1 are stable at every wavelength.
  Case identical{0.4, 1.0, PlaneCondition::antiplane};
  check_unstable("antiplane H=0.4 L=1.0", identical, 2e-2);
  // Re Lambda = 2220/s: with eps = 1e-4 the linear window (0.75 ms) still
  // holds the transient of the other roots and the pencil's dominant pole is
  // one of them (measured); eps = 1e-7 lengthens the window 2.5x.
  identical.length = 1.5;
  identical.sine_amplitude = 1e-7;
  check_unstable("antiplane H=0.4 L=1.5", identical, 2e-2);
  // A stiffer, thicker bottom body with the same shear echo time (c_b = 2 c_t,
  // H_b = 2 H_t: no height rounding).
  // Both operators of the pair: the bodies' (time.antiplane_pair = "bodies")
  // and the combined one (the default).
  for (const auto op : {AntiplanePairOperator::bodies, AntiplanePairOperator::combined}) {
    const std::string name = op == AntiplanePairOperator::bodies ? " (bodies)" : " (combined)";
    Case dissimilar{0.4, 2.0, PlaneCondition::antiplane};
    dissimilar.bottom = BodyKind::elastic;
    dissimilar.bottom_shear_modulus = 36e9;
    dissimilar.bottom_height = 0.8;
    dissimilar.antiplane_pair = op;
    check_unstable(("antiplane 0.4 on 4x stiffer 0.8 L=2.0" + name).c_str(), dissimilar, 2e-2);
    dissimilar.length = 1.5;
    check_unstable(("antiplane 0.4 on 4x stiffer 0.8 L=1.5" + name).c_str(), dissimilar, 2e-2);
  }
  // A strip on a rigid base.
  Case rigid{0.4, 2.0, PlaneCondition::antiplane};
  rigid.bottom = BodyKind::rigid;
  check_unstable("antiplane 0.4 on rigid base L=2.0", rigid, 2e-2);
}

TEST_CASE("antiplane half-spaces of different speeds: growth rates by the combined and the bodies' operators") {
  // A half-space on a half-space of 4x mu and the same rho (c_b = 2 c_t, the
  // bench's pair): the theory uses the closed-form (1/K_t + 1/K_b)^-1, the
  // simulation the combined operator of K_c (time.antiplane_pair = "combined",
  // HalfSpaceHistory's pair constructor) and the two bodies' operators
  // (TwoBodyHistory).  eps = 1e-8 as for the in-plane half-space above (the
  // branch points' algebraic tails die out in the longer linear window).
  // Tolerance 2 % on Re Lambda and its frequency, as every case here.
  const double inf = std::numeric_limits<double>::infinity();
  for (const AntiplanePairOperator op : {AntiplanePairOperator::combined, AntiplanePairOperator::bodies})
    for (double L : {2.0, 3.0}) {
      Case c{inf, L, PlaneCondition::antiplane};
      c.bottom = BodyKind::elastic;
      c.bottom_shear_modulus = 36e9;
      c.bottom_density = 1200.0;
      c.bottom_height = inf;
      c.sine_amplitude = 1e-8;
      c.antiplane_pair = op;
      {
        Simulation sim(make_config(c));
        const bool combined = dynamic_cast<const TwoBodyHistory*>(&sim.history_operator()) == nullptr;
        CHECK(combined == (op == AntiplanePairOperator::combined));
      }
      const std::string label = std::string(op == AntiplanePairOperator::combined ? "SH hs pair combined L="
                                                                                  : "SH hs pair bodies L=") +
                                (L == 2.0 ? "2" : "3");
      check_unstable(label.c_str(), c, 2e-2);
    }
}

// In-plane dissimilar pair: the theory is stability/interface_stability (the
// series stiffness K_ser of the two closed-form 2x2 face responses, with the
// normal-stress coupling K_yx and the Cochard-Rice memory), the simulation the
// per-body 2x2 modal operators (kernels/inplane_pair_history.hpp) and the
// node-by-node solve with the effective normal stress.  The pair is not
// symmetric under x -> -x: at k > 0 the unstable roots are waves travelling
// one way or the other (Im Lambda of either sign), with different growth
// rates and nearly the same |Im Lambda|.  Re c(t) cannot separate them over a
// linear window (measured: both estimators land between the two roots), so
// the pencil runs on the complex amplitude c(t) of mode +k (~ exp(Lambda t)),
// and every unstable root of the theory must be found, Re and Im, within 2 %.
void check_unstable_pair(const char* label, const Case& c, double max_duration) {
  const SimulationConfig config = make_config(c);
  const PairSliding pair = pair_sliding_of(config);
  const LinearisedInterfaceFriction lin = linearise_interface_friction(pair);
  const double k = 2.0 * pi / wavelength(c);
  const auto roots = pair_characteristic_roots(pair, lin, k, pair_search_box(pair, lin, k));
  std::printf("%-32s theory roots:", label);
  for (const auto& z : roots) std::printf(" (%.3f, %.1f)", z.real(), z.imag());
  std::printf("\n");
  REQUIRE(!roots.empty());
  REQUIRE(roots.front().real() > 0.0);
  const ModeRecord r = simulate_mode(c, max_duration);
  const std::size_t last = r.slip_rate_complex.size();
  const std::size_t first = last / 2;
  const std::size_t decimation = std::max<std::size_t>(1, (last - first) / 600);
  const auto poles = matrix_pencil(r.slip_rate_complex, r.dt, first, last, decimation, 1e-8);
  double largest = 0.0;
  for (const auto& p : poles) largest = std::max(largest, p.final_amplitude);
  for (const auto& root : roots) {
    if (root.real() <= 0.0) continue;
    // The measured pole nearest to the root among those that matter at the
    // window end (the pencil also fits tiny spurious poles to round-off).
    const Pole* best = nullptr;
    for (const auto& p : poles)
      if (p.final_amplitude >= 1e-3 * largest && (!best || std::abs(p.rate - root) < std::abs(best->rate - root)))
        best = &p;
    REQUIRE(best != nullptr);
    std::printf("%-32s window=[%.3e,%.3e] s dt=%.3e  root (%.3f, %.1f)  pencil (%.3f, %.1f)  rel %.2e, %.2e\n",
                label, r.time(first), r.time(last - 1), r.dt, root.real(), root.imag(), best->rate.real(),
                best->rate.imag(), (best->rate.real() - root.real()) / root.real(),
                (best->rate.imag() - root.imag()) / std::abs(root.imag()));
    CHECK(std::abs(best->rate.real() - root.real()) <= tolerance * root.real());
    CHECK(std::abs(best->rate.imag() - root.imag()) <= tolerance * std::abs(root.imag()));
  }
}

TEST_CASE("in-plane dissimilar pairs: growth rates match the pair stability theory") {
  // Table S1 top strip H = 0.1 m on a more compliant bottom strip (mu_b = mu/2,
  // the same rho and nu: c_b = c_t / sqrt 2), H_b = 0.2 m, and on a rigid base.
  Case compliant{0.1, 1.0};
  compliant.bottom = BodyKind::elastic;
  compliant.bottom_shear_modulus = 4.5e9;
  compliant.bottom_height = 0.2;
  check_unstable_pair("strain 0.1 on mu/2 0.2 L=1.0", compliant, 2e-2);
  // A strip on a rigid base: K_ser = K_t, twice the identical pair's S, so a
  // thicker strip and a longer wavelength (H = 0.1 m is stable up to L = 6 m).
  Case rigid{0.4, 4.0};
  rigid.bottom = BodyKind::rigid;
  check_unstable_pair("strain 0.4 on rigid L=4.0", rigid, 5e-2);
}

TEST_CASE("in-plane dissimilar half-spaces: growth rates match the pair stability theory") {
  // Two half-spaces (kernels/face_half_space.hpp for each body): Table S1 on top,
  // a bottom half-space of mu/2 (same rho, nu), L = 2.4 m (Lc(inf) = 1.19 m for
  // identical half-spaces).  As for identical half-spaces the branch-point
  // transients decay only algebraically, so eps = 1e-8 (a longer linear window).
  const double inf = std::numeric_limits<double>::infinity();
  Case pair{inf, 2.4};
  pair.bottom = BodyKind::elastic;
  pair.bottom_shear_modulus = 4.5e9;
  pair.bottom_height = inf;
  pair.sine_amplitude = 1e-8;
  check_unstable_pair("strain half-space on mu/2 half-space L=2.4", pair, 2e-2);
}

TEST_CASE("in-plane pair with the Linker-Dieterich response: growth rates match the pair theory") {
  // The strip on a rigid base of the dissimilar case above (H = 0.4 m, L = 4 m)
  // with alpha_LD = 0.3 and 0.6: the solver's state response to sigma_eff
  // (laws/law_rate_and_state.cpp, an exact factor Strang-split around the state
  // update) against its linearisation in stability/interface_stability.  On a
  // rigid base the strip's own shear-normal coupling makes sigma vary.  The
  // response must move every unstable root's Re Lambda by more than 5x the 2 %
  // tolerance (measured: 16-70 %), or the check could not tell it from alpha_LD = 0.
  for (double alpha : {0.3, 0.6}) {
    Case c{0.4, 4.0};
    c.bottom = BodyKind::rigid;
    const auto roots_of = [&c](double a) {
      Case d = c;
      d.linker_dieterich = a;
      return pair_unstable_roots(pair_sliding_of(make_config(d)), wavelength(d));
    };
    const auto without = roots_of(0.0), with = roots_of(alpha);
    REQUIRE(!without.empty());
    REQUIRE(!with.empty());
    for (const auto& z : with) {
      const auto nearest = *std::min_element(without.begin(), without.end(), [&z](auto x, auto y) {
        return std::abs(x - z) < std::abs(y - z);
      });
      std::printf("alpha_LD = %.1f: root (%.1f, %.1f), nearest at alpha_LD = 0 (%.1f, %.1f)\n", alpha, z.real(),
                  z.imag(), nearest.real(), nearest.imag());
      CHECK(std::abs(z.real() - nearest.real()) > 5.0 * tolerance * z.real());
    }
    c.linker_dieterich = alpha;
    check_unstable_pair(alpha == 0.3 ? "strain 0.4 on rigid L=4.0 LD 0.3" : "strain 0.4 on rigid L=4.0 LD 0.6", c,
                        5e-2);
  }
}

TEST_CASE("growth rate of the unstable mode matches linear stability, plane stress") {
  Case c{0.1, 0.8};
  c.plane = PlaneCondition::stress;
  check_unstable("stress H=0.1 L=0.8", c);
  c.length = 1.0;
  check_unstable("stress H=0.1 L=1.0", c);
}

TEST_CASE("stable wavelength H=0.1 L=0.5: the simulated decay rates are the theory's roots") {
  // The decaying signal contains several roots at once, so only the pencil
  // (estimator b) applies.  Two roots are checked:
  //  * the least-damped root that growth_rates() reports (in damped_search_box,
  //    |Im| <= 1.0137 R_f ~ 1.7e4 rad/s): Re ~ -4811, dominant up to ~1 ms;
  //  * the truly least-damped root, outside that box: the first dilatational
  //    thickness resonance (omega ~ c_d sqrt(k^2 + (pi/H)^2) ~ 1.83e5 rad/s),
  //    Re ~ -439, which dominates Re c_v after ~1.2 ms.  It is found here by
  //    the theory's root finder in an extended box.
  const Case c{0.1, 0.5};
  const SimulationConfig config = make_config(c);
  const SteadySliding sliding = steady_sliding_of(config);
  const auto reported = growth_rates(sliding, {c.length}).at(0);
  REQUIRE_FALSE(reported.unstable);
  const auto extended = characteristic_roots(sliding, c.length, SearchBox{-2.0e4, -1.0, 2.0e5});
  REQUIRE(!extended.empty());
  const std::complex<double> least_damped = extended.front();  // sorted by decreasing Re
  const std::complex<double> frictional{reported.growth_rate, reported.frequency};

  const ModeRecord r = simulate_mode(c, 2.5e-3);
  REQUIRE_FALSE(r.left_linear_regime);
  // from 0.2 ms (the fast roots with Re < -2e4 have decayed by e^-4) to the end;
  // decimation 4: sample interval 2.8e-6 s resolves 1.8e5 rad/s (0.5 rad/sample).
  const auto first = static_cast<std::size_t>(2e-4 / r.dt);
  const auto poles = matrix_pencil(r.slip_rate, r.dt, first, r.slip_rate.size(), 4, 1e-8);
  for (const auto root : {frictional, least_damped}) {
    const auto p = pole_near(poles, root);
    REQUIRE(p.has_value());
    std::printf(
        "stable H=0.1 L=0.5 N=%d dt=%.3e: theory root %.3f%+.1fi  measured %.3f%+.1fi (Re rel "
        "err %.2e)\n",
        c.nodes, r.dt, root.real(), std::abs(root.imag()), p->rate.real(), p->rate.imag(),
        (p->rate.real() - root.real()) / std::abs(root.real()));
    CHECK(p->rate.real() < 0.0);
    CHECK(std::abs(p->rate.real() - root.real()) <= tolerance * std::abs(root.real()));
    CHECK(std::abs(p->rate.imag() - std::abs(root.imag())) <= tolerance * std::abs(root.imag()));
  }
  // and no measured pole of significant amplitude grows
  double largest = 0.0;
  for (const auto& p : poles) largest = std::max(largest, p.initial_amplitude);
  for (const auto& p : poles)
    if (p.initial_amplitude >= 1e-3 * largest) CHECK(p.rate.real() < 0.0);
}

TEST_CASE("wavelengths 5% below / above Lc decay / grow (H = 0.05, 0.1, 0.2)") {
  SteadySliding sliding = steady_sliding_of(make_config({0.1, 1.0}));
  const std::vector<double> heights{0.05, 0.1, 0.2};
  const auto lc = critical_wavelength_vs_height(sliding, heights);
  for (std::size_t h = 0; h < heights.size(); ++h) {
    for (const double factor : {0.95, 1.05}) {
      const Case c{heights[h], factor * lc[h]};
      sliding.strip_height = c.strip_height;
      const auto theory = growth_rates(sliding, {c.length}).at(0);
      const std::complex<double> root{theory.growth_rate, theory.frequency};
      // |Re Lambda| is a few hundred 1/s here: a long record gives several e-folds
      const ModeRecord r = simulate_mode(c, 12e-3);
      // skip 1 ms of transient (other frictional roots have Re < -3000 1/s)
      const auto first = static_cast<std::size_t>(1e-3 / r.dt);
      const std::size_t last = r.slip_rate.size();
      const auto poles =
          matrix_pencil(r.slip_rate, r.dt, first, last, std::max<std::size_t>(1, (last - first) / 800), 1e-8);
      const auto p = pole_near(poles, root);
      REQUIRE(p.has_value());
      std::printf(
          "bracket H=%.2f L=%.4f (%.2f Lc, Lc=%.4f) N=%d: theory %.3f%+.1fi measured %.3f%+.1fi "
          "(Re rel err %.2e)%s\n",
          c.strip_height, c.length, factor, lc[h], c.nodes, root.real(), root.imag(),
          p->rate.real(), p->rate.imag(), (p->rate.real() - root.real()) / std::abs(root.real()),
          r.left_linear_regime ? " [stopped at linear limit]" : "");
      if (factor < 1.0) {
        CHECK_FALSE(theory.unstable);
        CHECK(p->rate.real() < 0.0);
        // nothing in the signal grows
        double largest = 0.0;
        for (const auto& q : poles) largest = std::max(largest, q.initial_amplitude);
        for (const auto& q : poles)
          if (q.initial_amplitude >= 1e-3 * largest) CHECK(q.rate.real() < 0.0);
      } else {
        CHECK(theory.unstable);
        CHECK(p->rate.real() > 0.0);
        CHECK(dominant_pole(poles).rate.real() > 0.0);
      }
      // the rates themselves (a few hundred 1/s) also agree with the theory
      CHECK(std::abs(p->rate.real() - root.real()) <= tolerance * std::abs(root.real()));
    }
  }
}

TEST_CASE("uniform mode k = 0: grows at H = 0.2, decays at H = 0.1, at the theory's rates") {
  // k = 0 is uniform slip of the strip pair against the driven boundaries.
  // Quasi-statically its stiffness mu/(2H) (2.25e10 Pa/m at H = 0.2) is below
  // K_c = tau_v g_phi - tau_phi g_v ~ 3.2e10 Pa/m for H > ~0.14 m, so at H = 0.2
  // steady sliding is unstable at k = 0 whatever L is: a wavelength below Lc
  // decays on its own, but the uniform mode (seeded at O(eps^2) by the
  // nonlinearity) eventually grows.  sine_mode = 0 seeds it directly
  // (phi = phi_ss (1 + eps)); theory: growth_rates at wavelength +inf.
  Case grows{0.2, 0.8};
  grows.sine_mode = 0;
  check_unstable("k=0 H=0.2", grows);

  Case decays{0.1, 0.8};
  decays.sine_mode = 0;
  const SteadySliding sliding = steady_sliding_of(make_config(decays));
  const auto theory = growth_rates(sliding, {wavelength(decays)}).at(0);
  REQUIRE_FALSE(theory.unstable);
  const std::complex<double> root{theory.growth_rate, theory.frequency};
  const ModeRecord r = simulate_mode(decays, 3e-3);
  REQUIRE_FALSE(r.left_linear_regime);
  const auto first = static_cast<std::size_t>(2e-4 / r.dt);
  const auto poles = matrix_pencil(r.slip_rate, r.dt, first, r.slip_rate.size(), 4, 1e-8);
  const auto p = pole_near(poles, root);
  REQUIRE(p.has_value());
  std::printf("k=0 H=0.1 N=%d dt=%.3e: theory %.3f%+.1fi measured %.3f%+.1fi (Re rel err %.2e)\n",
              decays.nodes, r.dt, root.real(), root.imag(), p->rate.real(), p->rate.imag(),
              (p->rate.real() - root.real()) / std::abs(root.real()));
  CHECK(std::abs(p->rate.real() - root.real()) <= tolerance * std::abs(root.real()));
  double largest = 0.0;
  for (const auto& q : poles) largest = std::max(largest, q.initial_amplitude);
  for (const auto& q : poles)
    if (q.initial_amplitude >= 1e-3 * largest) CHECK(q.rate.real() < 0.0);
}

TEST_CASE("aging and slip laws: same Lc in theory, same simulated growth rates") {
  // At steady state the two laws have the same linearisation up to
  // O((v*/v0)^2) = 2.5e-9, so Lc agrees to ~1e-8 (bisection tolerance 1e-10).
  SteadySliding aging = steady_sliding_of(make_config({0.1, 1.0}));
  SteadySliding slip = aging;
  slip.friction.state_law = StateLaw::slip;
  const double lc_aging = critical_wavelength(aging, 0.4, 1.0);
  const double lc_slip = critical_wavelength(slip, 0.4, 1.0);
  std::printf("Lc(H=0.1): aging %.10f m, slip %.10f m\n", lc_aging, lc_slip);
  CHECK(std::abs(lc_aging - lc_slip) <= 1e-7 * lc_aging);

  for (const Case base : {Case{0.1, 0.8}, Case{0.1, 1.0}, Case{0.05, 0.6}}) {
    Case c_slip = base;
    c_slip.state_law = StateLaw::slip;
    const GrowthMeasurement m_aging = measure_unstable(base, 8e-3);
    const GrowthMeasurement m_slip = measure_unstable(c_slip, 8e-3);
    report("aging law", base, m_aging);
    report("slip law", c_slip, m_slip);
    CHECK(std::abs(m_slip.envelope - m_aging.envelope) <= tolerance * m_aging.envelope);
    CHECK(std::abs(m_slip.pencil - m_aging.pencil) <= tolerance * m_aging.pencil);
    CHECK(std::abs(m_slip.envelope - m_slip.theory) <= tolerance * m_slip.theory);
  }
}

TEST_CASE("resolution: N = 64 and N = 128 give the same growth rate (H=0.1, L=0.8)") {
  // Only dt = beta dx / c_s changes with N for mode 1; a second-order scheme
  // halves dt and should change the rate by far less than the 2% tolerance.
  const GrowthMeasurement coarse = measure_unstable({0.1, 0.8, PlaneCondition::strain,
                                                     StateLaw::aging, 64},
                                                    8e-3);
  const GrowthMeasurement fine = measure_unstable({0.1, 0.8, PlaneCondition::strain,
                                                   StateLaw::aging, 128},
                                                  8e-3);
  report("N=64", {0.1, 0.8, PlaneCondition::strain, StateLaw::aging, 64}, coarse);
  report("N=128", {0.1, 0.8, PlaneCondition::strain, StateLaw::aging, 128}, fine);
  CHECK(std::abs(fine.envelope - coarse.envelope) <= 0.1 * tolerance * fine.theory);
  CHECK(std::abs(fine.envelope - fine.theory) <= tolerance * fine.theory);
}

TEST_CASE("convergence in dt and linearity (all plane-strain cases)" * doctest::test_suite("slow")) {
  // N = 256 (4x smaller dt than the default) and beta = 0.125 at N = 128
  // (the same dt: for mode 1 only dt matters, so the two must agree to
  // round-off).  The pencil error against theory must shrink under refinement.
  for (const Case base :
       {Case{0.1, 0.8}, Case{0.1, 1.0}, Case{0.05, 0.6}, Case{0.2, 1.2}}) {
    const GrowthMeasurement m_coarse = measure_unstable(base, 8e-3);
    Case fine = base;
    fine.nodes = 256;
    const GrowthMeasurement m_fine = measure_unstable(fine, 8e-3);
    report("slow N=256", fine, m_fine);
    CHECK(std::abs(m_fine.envelope - m_fine.theory) <= tolerance * m_fine.theory);
    CHECK(std::abs(m_fine.pencil - m_fine.theory) <= tolerance * m_fine.theory);
    Case small_beta = base;
    small_beta.nodes = 128;
    small_beta.beta = 0.125;
    const GrowthMeasurement m_beta = measure_unstable(small_beta, 8e-3);
    report("slow N=128 beta=0.125", small_beta, m_beta);
    CHECK(std::abs(m_beta.envelope - m_beta.theory) <= tolerance * m_beta.theory);
    CHECK(std::abs(m_beta.pencil - m_fine.pencil) <= 1e-6 * m_fine.theory);
    CHECK(std::abs(m_fine.pencil - m_fine.theory) < std::abs(m_coarse.pencil - m_coarse.theory));
  }
  // Linearity: eps = 1e-6 gives ~4.6 more e-folds before the limit; the rate
  // must not depend on eps (nonlinear corrections to mode 1 are O(amplitude^2)).
  Case tiny{0.1, 0.8};
  tiny.sine_amplitude = 1e-6;
  const GrowthMeasurement m_tiny = measure_unstable(tiny, 12e-3);
  report("slow eps=1e-6", tiny, m_tiny);
  CHECK(std::abs(m_tiny.envelope - m_tiny.theory) <= tolerance * m_tiny.theory);
}
