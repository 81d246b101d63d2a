// Free interface (no friction): the strips ring forever after a stress pulse.
// These tests run the full Simulation time step (FFT, history operator,
// interface law) and check the physics that only exact, lossless reflections
// give: k = 0 periodicity over hundreds of periods, no decay or growth of any
// mode over 1000 round trips, and resonance frequencies at the roots of
// S(k, i omega; H) = 0.
#include <doctest/doctest.h>
#include <fftw3.h>

#include <cmath>
#include <complex>
#include <numbers>
#include <vector>

#include "solver/simulation.hpp"
#include "kernels/fft.hpp"
#include "kernels/history_convolution.hpp"
#include "kernels/strip_response.hpp"

using namespace slipstrip;
constexpr double pi = std::numbers::pi;

namespace {

SimulationConfig free_config(double length, double height, int nodes) {
  SimulationConfig c;
  c.geometry = {length, height, nodes};
  c.interface.law = InterfaceLawName::free;
  c.interface.profile = TimeProfile::bump;
  c.interface.stress_amplitude = 1e5;
  c.time.beta = 0.25;
  return c;
}

double relative_l2(const std::vector<double>& a, const std::vector<double>& b) {
  double num = 0, den = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    num += (a[i] - b[i]) * (a[i] - b[i]);
    den += b[i] * b[i];
  }
  return std::sqrt(num / den);
}

}  // namespace

TEST_CASE("k = 0: free ringing is periodic with period 4H/c_s, unchanged after 500 periods") {
  auto c = free_config(0.4, 0.1, 16);
  c.interface.pulse_width = std::numeric_limits<double>::infinity();  // uniform pulse
  Simulation probe(c);
  const double cs = c.material.shear_wave_speed();
  const double period = 4.0 * c.geometry.height / cs;
  const long steps_per_period = std::lround(period / probe.time_step());
  REQUIRE(std::abs(steps_per_period * probe.time_step() - period) < 1e-12 * period);
  // Pulse smooth over >= 20 steps (the requirement): 24 steps here.
  c.interface.rise_time = 24 * probe.time_step();
  Simulation sim(c);

  auto record_period = [&](std::vector<double>& out) {
    out.clear();
    for (long n = 0; n < steps_per_period; ++n) {
      sim.step();
      out.push_back(sim.slip_rate()[0]);
    }
  };
  // Skip the pulse itself (one period is longer than the rise time).
  std::vector<double> first, last;
  record_period(first);
  record_period(first);
  for (int p = 0; p < 498; ++p) record_period(last);
  record_period(last);
  const double err = relative_l2(last, first);
  MESSAGE("k=0: " << steps_per_period << " steps per period, relative L2 difference after 500 periods = " << err);
  // Tolerance 1e-3 (issue requirement); the delay line is exact, so we expect round-off.
  CHECK(err < 1e-3);
  // And the waveform really is the 4H/c_s-periodic square-ish wave, not zero.
  double peak = 0;
  for (double v : first) peak = std::max(peak, std::abs(v));
  CHECK(peak > 1e-3 * c.interface.stress_amplitude / sim.radiation_damping());
}

TEST_CASE("long free run: no mode decays or grows over 1000 round trips; peaks at resonances") {
  // N = 256; kH = 0.05, 0.5, 5 for modes q = 1, 10, 100 (so L = 2 pi H / 0.05).
  const double height = 0.01;
  const double length = 2 * pi * height / 0.05;
  const int nodes = 256;
  auto c = free_config(length, height, nodes);
  const double dx = length / nodes;
  c.interface.pulse_center = 0.5 * length;
  c.interface.pulse_width = 1.0 * dx;  // localised: excites modes up to q ~ N/2
  Simulation probe(c);
  const double dt = probe.time_step();
  c.interface.rise_time = 8 * dt;  // short, smooth pulse
  Simulation sim(c);
  const double cs = c.material.shear_wave_speed();
  const long steps_per_trip = std::lround(2 * height / cs / dt);
  const long window = 100 * steps_per_trip;
  const long total = 1000 * steps_per_trip + steps_per_trip;
  const int modes[] = {1, 10, 100};

  RealFft fft(nodes);
  std::vector<std::complex<double>> spectrum(nodes / 2 + 1);
  std::vector<std::vector<std::complex<double>>> series(3);
  for (long n = 0; n < total; ++n) {
    sim.step();
    if (n < steps_per_trip) continue;  // pulse over
    fft.forward(sim.slip_rate(), spectrum);
    for (int m = 0; m < 3; ++m) series[m].push_back(spectrum[modes[m]]);
  }
  for (int m = 0; m < 3; ++m) {
    auto mean_square = [&](long begin) {
      double s = 0;
      for (long j = begin; j < begin + window; ++j) s += std::norm(series[m][j]);
      return s / window;
    };
    const double first = mean_square(0);
    const double last = mean_square(static_cast<long>(series[m].size()) - window);
    const double change = std::abs(last / first - 1.0);
    const double kH = 2 * pi * modes[m] / length * height;
    MESSAGE("mode q = " << modes[m] << " (kH = " << kH << "): mean-square change first->last window = " << change);
    CHECK(first > 0);
    CHECK(change < 0.01);  // issue requirement: within 1%

    // Spectral peak vs the strip's free-interface resonance: the largest
    // |v^_q(omega)| must sit at a root of S(k, i omega; H) = 0.
    const long len = static_cast<long>(series[m].size());
    std::vector<fftw_complex> buf(len);
    for (long j = 0; j < len; ++j) {
      // Hann window to keep leakage from hiding the peak.
      const double w = 0.5 - 0.5 * std::cos(2 * pi * j / (len - 1));
      buf[j][0] = w * series[m][j].real();
      buf[j][1] = w * series[m][j].imag();
    }
    fftw_plan plan = fftw_plan_dft_1d(len, buf.data(), buf.data(), FFTW_FORWARD, FFTW_ESTIMATE);
    fftw_execute(plan);
    fftw_destroy_plan(plan);
    long best = 1;
    for (long j = 1; j < len / 2; ++j)
      if (std::hypot(buf[j][0], buf[j][1]) > std::hypot(buf[best][0], buf[best][1])) best = j;
    const double omega_peak = 2 * pi * best / (len * dt);
    // (1) The peak must sit on a root of the DISCRETE characteristic function
    //     Z_d(theta) = eta + (mu/c_s)/(z-1) + dt sum_m w_m [1/(z-1) - (z c_m - 1)/(z^2 - 2 z c_m + 1)],
    //     z = e^{i theta}, built from the operator's own modes (Z_d is purely
    //     imaginary on |z| = 1 because the operator is lossless): within one FFT bin.
    // (2) That discrete root must lie within the derived dispersion bound of a
    //     root of the continuous S(k, i omega; H) = 0: the trapezoidal rule on
    //     the modal kernels shifts frequencies by at most ~ (omega dt)^2 / 12
    //     relative (docs/theory.md, "dispersion").
    const double k = 2 * pi * modes[m] / length;
    const double bin = 2 * pi / (len * dt);
    const auto dmodes = discrete_modes(c.material, height, k, dt, sim.history_operator().stats().echo_steps);
    const double eta = sim.radiation_damping();
    auto Zd = [&](double omega) {
      const std::complex<double> z = std::polar(1.0, omega * dt);
      // delay line + comb modes == running sum with weight mu/c_s = 2 eta
      std::complex<double> total = eta + 2.0 * eta / (z - 1.0);
      for (const auto& d : dmodes) {
        const double cm = std::cos(d.phase);
        total += dt * d.weight * (1.0 / (z - 1.0) - (z * cm - 1.0) / (z * z - 2.0 * z * cm + 1.0));
      }
      return total.imag();
    };
    auto S = [&](double w) { return strip_response(c.material, height, k, {0.0, w}).real(); };
    // Roots (not poles) of f in [lo, hi]: sign changes whose bisected point has
    // |f| far below the typical |f| on the interval.
    auto roots_in = [](auto&& f, double lo, double hi) {
      std::vector<double> roots;
      const int samples = 4000;
      double typical = 0;
      for (int s = 0; s <= samples; ++s) typical += std::abs(f(lo + (hi - lo) * s / samples));
      typical /= samples + 1;
      double a = lo, fa = f(a);
      for (int s = 1; s <= samples; ++s) {
        const double b = lo + (hi - lo) * s / samples, fb = f(b);
        if (fa * fb < 0) {
          double x0 = a, x1 = b, f0 = fa;
          for (int it = 0; it < 100; ++it) {
            const double mid = 0.5 * (x0 + x1), fm = f(mid);
            if (fm * f0 < 0) x1 = mid; else { x0 = mid; f0 = fm; }
          }
          const double r = 0.5 * (x0 + x1);
          if (std::abs(f(r)) < 1e-6 * typical) roots.push_back(r);
        }
        a = b;
        fa = fb;
      }
      return roots;
    };
    auto nearest = [](const std::vector<double>& rs, double x) {
      double best = NAN;
      for (double r : rs) if (std::isnan(best) || std::abs(r - x) < std::abs(best - x)) best = r;
      return best;
    };
    const double discrete_root = nearest(roots_in(Zd, omega_peak - 5 * bin, omega_peak + 5 * bin), omega_peak);
    const double bound = std::pow(omega_peak * dt, 2) / 12.0 * omega_peak;
    const double continuous_root = nearest(roots_in(S, omega_peak - 2 * bound - 5 * bin, omega_peak + 2 * bound + 5 * bin), discrete_root);
    MESSAGE("  peak " << omega_peak << " rad/s (omega dt = " << omega_peak * dt << "), discrete root "
                      << discrete_root << ", continuous root " << continuous_root << "; |peak - discrete| = "
                      << std::abs(omega_peak - discrete_root) << " (bin " << bin << "), |discrete - continuous| = "
                      << std::abs(discrete_root - continuous_root) << " (bound " << bound << ")");
    REQUIRE(std::isfinite(discrete_root));
    REQUIRE(std::isfinite(continuous_root));
    CHECK(std::abs(omega_peak - discrete_root) <= bin);
    CHECK(std::abs(discrete_root - continuous_root) <= bound);
  }
}
