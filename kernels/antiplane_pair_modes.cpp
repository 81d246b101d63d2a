#include "kernels/antiplane_pair_modes.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include "kernels/antiplane_response.hpp"

namespace slipstrip {
namespace {

// t cot t = sum_n a_n u^n, u = t^2 (and t coth t the same series with u = -t^2):
// a_n = (-1)^n 4^n B_2n / (2n)!.  Its radius is u = pi^2, so for |u| < 1/4 ten
// terms leave < 1e-16: used near gamma = 0 (omega = c k), where the closed
// forms of the derivative cancel.
constexpr std::array<double, 10> kCotSeries = {
    1.0,
    -1.0 / 3.0,
    -1.0 / 45.0,
    -2.0 / 945.0,
    -1.0 / 4725.0,
    -2.0 / 93555.0,
    -1382.0 / 638512875.0,
    -4.0 / 18243225.0,
    -65536.0 * 3617.0 / 510.0 / 20922789888000.0,
    -262144.0 * 43867.0 / 798.0 / 6402373705728000.0,
};

// One body on the imaginary axis s = i omega:  K = mu F(x),  x = omega^2/c^2 - k^2,
// F = g cot(g H) (g = sqrt(x), x > 0) or b coth(b H) (b = sqrt(-x), x < 0), and
// dK/d(s^2) = -mu F'(x) / c^2 (s^2 = -omega^2).  F decreases in x, with poles
// at g H = m pi.
struct AxisValue {
  double stiffness;        // K [Pa/m]
  double stiffness_slope;  // dK/d(s^2) [Pa s^2/m]
};

AxisValue body_on_axis(const AntiplaneStrip& body, double k, double omega) {
  const double mu = body.material.shear_modulus, c = body.material.shear_wave_speed(), H = body.height;
  const double x = omega * omega / (c * c) - k * k;
  const double u = x * H * H;
  double F, dF;
  if (std::abs(u) < 0.25) {
    double sum = 0.0, slope = 0.0;
    for (std::size_t n = kCotSeries.size(); n-- > 0;) {
      sum = sum * u + kCotSeries[n];
      if (n > 0) slope = slope * u + static_cast<double>(n) * kCotSeries[n];
    }
    F = sum / H;
    dF = slope * H;
  } else if (x > 0.0) {
    const double g = std::sqrt(x), t = g * H;
    const double sn = std::sin(t), cs = std::cos(t);
    F = g * cs / sn;
    dF = (sn * cs - t) / (2.0 * g * sn * sn);
  } else {
    // coth and csch^2 through e = e^{-2t} (no overflow for tall bodies).
    const double b = std::sqrt(-x), t = b * H;
    const double e = std::exp(-2.0 * t);
    const double coth = (1.0 + e) / (1.0 - e), csch2 = 4.0 * e / ((1.0 - e) * (1.0 - e));
    F = b * coth;
    dF = -(coth - t * csch2) / (2.0 * b);
  }
  return {mu * F, -mu * dF / (c * c)};
}

// The poles of body i's K on the axis: omega = c sqrt(k^2 + (m pi/H)^2), m >= 1,
// with their residues R in s^2: K ~ R / (s^2 + omega^2), R = -2 mu c^2 kappa^2 / H.
struct BodyPole {
  double omega;
  double residue;
};

double body_pole(const AntiplaneStrip& body, double k, int m) {
  const double c = body.material.shear_wave_speed(), kappa = m * std::numbers::pi / body.height;
  return c * std::sqrt(k * k + kappa * kappa);
}

double body_residue(const AntiplaneStrip& body, int m) {
  const double c = body.material.shear_wave_speed(), kappa = m * std::numbers::pi / body.height;
  return -2.0 * body.material.shear_modulus * c * c * kappa * kappa / body.height;
}

// A pole of D = K_t + K_b: a pole of one body, or of both (a common pole,
// which is a pole of K_c too).
struct DispersionPole {
  double omega;
  double residue_top = 0.0, residue_bottom = 0.0;  // 0: not a pole of that body
};

// Poles closer than this (relative) are one common pole: equal echo
// frequencies computed from different moduli and densities differ by round-off.
constexpr double kCommonPole = 1e-10;

// The poles of D in increasing order, all those <= max_frequency and the
// first one above it (the right end of the last bracket).
std::vector<DispersionPole> dispersion_poles(const AntiplaneStrip& top, const AntiplaneStrip& bottom, double k,
                                             double max_frequency) {
  std::vector<DispersionPole> poles;
  int mt = 1, mb = 1;
  for (;;) {
    const double wt = body_pole(top, k, mt), wb = body_pole(bottom, k, mb);
    DispersionPole p;
    if (std::abs(wt - wb) <= kCommonPole * std::max(wt, wb)) {
      p = {0.5 * (wt + wb), body_residue(top, mt), body_residue(bottom, mb)};
      ++mt;
      ++mb;
    } else if (wt < wb) {
      p = {wt, body_residue(top, mt), 0.0};
      ++mt;
    } else {
      p = {wb, 0.0, body_residue(bottom, mb)};
      ++mb;
    }
    poles.push_back(p);
    if (p.omega > max_frequency) return poles;
  }
}

double dispersion(const AntiplaneStrip& top, const AntiplaneStrip& bottom, double k, double omega,
                  double* slope_omega) {
  const AxisValue t = body_on_axis(top, k, omega), b = body_on_axis(bottom, k, omega);
  if (slope_omega) *slope_omega = -2.0 * omega * (t.stiffness_slope + b.stiffness_slope);
  return t.stiffness + b.stiffness;
}

// The one root of D in (a, b), where D decreases from > 0 (or +inf) to -inf:
// Newton's method kept inside the bracket, bisection where it would leave it.
double bracketed_root(const AntiplaneStrip& top, const AntiplaneStrip& bottom, double k, double a, double b) {
  double lo = a, hi = b, x = 0.5 * (a + b);
  for (int iteration = 0; iteration < 200; ++iteration) {
    double slope;
    const double d = dispersion(top, bottom, k, x, &slope);
    if (d == 0.0) return x;
    (d > 0.0 ? lo : hi) = x;
    double next = x - d / slope;
    if (!(next > lo && next < hi) || !std::isfinite(next)) next = 0.5 * (lo + hi);
    if (std::abs(next - x) <= 2.0 * std::numeric_limits<double>::epsilon() * x ||
        hi - lo <= 4.0 * std::numeric_limits<double>::epsilon() * hi)
      return next;
    x = next;
  }
  throw std::runtime_error("antiplane_pair_modes: the root of the dispersion relation did not converge");
}

}  // namespace

complex antiplane_body_stiffness(const AntiplaneStrip& body, double wavenumber, complex s) {
  return 2.0 * antiplane_strip_response(body.material, body.height, wavenumber, s);
}

complex antiplane_pair_response(const AntiplaneStrip& top, const AntiplaneStrip& bottom, double wavenumber,
                                complex s) {
  const complex kt = antiplane_body_stiffness(top, wavenumber, s), kb = antiplane_body_stiffness(bottom, wavenumber, s);
  return kt * kb / (kt + kb);
}

double antiplane_pair_static_stiffness(const AntiplaneStrip& top, const AntiplaneStrip& bottom,
                                       double wavenumber) {
  const double kt = 2.0 * antiplane_static_stiffness(top.material, top.height, wavenumber);
  const double kb = 2.0 * antiplane_static_stiffness(bottom.material, bottom.height, wavenumber);
  return kt * kb / (kt + kb);
}

double antiplane_pair_dispersion(const AntiplaneStrip& top, const AntiplaneStrip& bottom, double wavenumber,
                                 double omega) {
  return dispersion(top, bottom, std::abs(wavenumber), omega, nullptr);
}

std::vector<double> antiplane_pair_dispersion_poles(const AntiplaneStrip& top, const AntiplaneStrip& bottom,
                                                    double wavenumber, double max_frequency) {
  std::vector<double> out;
  for (const auto& p : dispersion_poles(top, bottom, std::abs(wavenumber), max_frequency))
    if (p.omega <= max_frequency) out.push_back(p.omega);
  return out;
}

std::vector<StripMode> antiplane_pair_modes(const AntiplaneStrip& top, const AntiplaneStrip& bottom,
                                            double wavenumber, double max_frequency) {
  for (const auto* body : {&top, &bottom})
    if (!(body->height > 0.0) || is_half_space(body->height))
      throw std::invalid_argument("antiplane_pair_modes: both bodies need a finite height > 0");
  const double k = std::abs(wavenumber);
  const auto poles = dispersion_poles(top, bottom, k, max_frequency);
  // A root where K_t = K_b = 0 (proportional bodies: D = 2K or (mu_t + mu_b) f)
  // has K_t K_b at round-off: no pole of K_c.  Weights below this fraction of
  // the comb scale mu/H are such roots.
  const double scale = std::max(top.material.shear_modulus / top.height, bottom.material.shear_modulus / bottom.height);
  std::vector<StripMode> modes;
  int index = 0;
  double left = 0.0;  // D(0) > 0: both bodies' static stiffnesses
  for (const auto& pole : poles) {
    if (left > max_frequency) break;
    ++index;
    const double root = bracketed_root(top, bottom, k, left, pole.omega);
    if (root <= max_frequency) {
      const AxisValue t = body_on_axis(top, k, root), b = body_on_axis(bottom, k, root);
      const double amplitude = t.stiffness * b.stiffness / (t.stiffness_slope + b.stiffness_slope);
      const double weight = amplitude / (root * root);
      if (std::abs(weight) > 1e-13 * scale) modes.push_back({root, weight, ModeFamily::shear, index});
    }
    if (pole.residue_top != 0.0 && pole.residue_bottom != 0.0 && pole.omega <= max_frequency) {
      ++index;
      const double amplitude = pole.residue_top * pole.residue_bottom / (pole.residue_top + pole.residue_bottom);
      modes.push_back({pole.omega, amplitude / (pole.omega * pole.omega), ModeFamily::shear, index});
    }
    left = pole.omega;
  }
  return modes;
}

StripPairConstants antiplane_pair_constants(const AntiplaneStrip& top, const AntiplaneStrip& bottom,
                                            double time_step) {
  const auto echo_steps = [&](const AntiplaneStrip& body) {
    const double echo = 2.0 * body.height / body.material.shear_wave_speed();
    const auto steps = static_cast<std::size_t>(std::llround(echo / time_step));
    if (steps < 1 || std::abs(static_cast<double>(steps) * time_step - echo) > 1e-9 * echo)
      throw std::invalid_argument("time_step = " + std::to_string(time_step) +
                                  " s must divide both shear echo times 2H/c_s into whole numbers of steps "
                                  "(use two_body_time_step); got " +
                                  std::to_string(echo) + " s");
    return steps;
  };
  const std::size_t mt = echo_steps(top), mb = echo_steps(bottom);
  const auto& a = top.material;
  const auto& b = bottom.material;
  // Identical bodies: the identical pair's constants, the same bits.
  if (a.shear_modulus == b.shear_modulus && a.density == b.density && top.height == bottom.height)
    return identical_strip_pair(a, mt);
  const double eta_t = a.shear_modulus / a.shear_wave_speed(), eta_b = b.shear_modulus / b.shear_wave_speed();
  const double eta = eta_t * eta_b / (eta_t + eta_b);
  return {eta, 2.0 * eta, mt, mb, eta_t, eta_b};
}

std::vector<DiscreteMode> antiplane_pair_discrete_modes(const AntiplaneStrip& top, const AntiplaneStrip& bottom,
                                                        double wavenumber, double time_step) {
  std::vector<DiscreteMode> out;
  if (wavenumber == 0.0) return out;  // the uniform mode is UniformModeEchoes alone
  const StripPairConstants constants = antiplane_pair_constants(top, bottom, time_step);
  const double nyquist = std::numbers::pi / time_step;
  // The comb of K_c(0, s)/s and the comb modes that cancel its poles add up
  // to the constant kernel 2 eta (docs/bodies.md), whose static stiffness is
  // 2 eta / dt; the kept modes' is the sum of their weights.
  double kept = constants.running_sum_weight / time_step;
  for (const auto& m : antiplane_pair_modes(top, bottom, wavenumber, nyquist)) {
    out.push_back({std::min(m.frequency * time_step, std::numbers::pi), m.weight, m.family});
    kept += m.weight;
  }
  place_truncated_stiffness(out, antiplane_pair_static_stiffness(top, bottom, wavenumber) - kept);
  return out;
}

StripKernels compute_antiplane_pair_kernels(const AntiplaneStrip& top, const AntiplaneStrip& bottom,
                                            double length, int nodes, double time_step,
                                            const CancelCheck& cancelled) {
  const StripPairConstants constants = antiplane_pair_constants(top, bottom, time_step);
  StripKernels kernels;
  kernels.time_step = time_step;
  kernels.echo_steps = constants.top_echo_steps == constants.bottom_echo_steps
                           ? constants.top_echo_steps
                           : constants.top_echo_steps + constants.bottom_echo_steps;
  kernels.first_oscillator.assign(1, 0);
  for (int q = 0; q <= nodes / 2; ++q) {
    throw_if_cancelled(cancelled, "the antiplane pair's kernels");
    const double k = 2.0 * std::numbers::pi * q / length;
    for (const auto& m : antiplane_pair_discrete_modes(top, bottom, k, time_step)) {
      kernels.phase.push_back(m.phase);
      kernels.weight.push_back(m.weight);
    }
    kernels.first_oscillator.push_back(kernels.weight.size());
  }
  return kernels;
}

}  // namespace slipstrip
