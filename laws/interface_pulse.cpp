#include "laws/interface_pulse.hpp"

#include <cmath>
#include <numbers>

namespace slipstrip {

namespace {
constexpr double pi = std::numbers::pi;
}

double pulse_profile(const InterfaceConfig& in, double t) {
  const double T = in.rise_time;
  if (t <= 0.0) return 0.0;
  if (in.profile == TimeProfile::ramp) return t >= T ? 1.0 : 0.5 * (1.0 - std::cos(pi * t / T));
  if (t >= T) return 0.0;
  const double s = std::sin(pi * t / T);
  return s * s * s * s;
}

double pulse_profile_rate(const InterfaceConfig& in, double t) {
  const double T = in.rise_time;
  if (t <= 0.0 || t >= T) return 0.0;
  if (in.profile == TimeProfile::ramp) return 0.5 * pi / T * std::sin(pi * t / T);
  const double s = std::sin(pi * t / T), c = std::cos(pi * t / T);
  return 4.0 * s * s * s * c * pi / T;
}

double imposed_stress(const InterfaceConfig& in, double amplitude, double length, double x,
                      double t) {
  if (amplitude == 0.0) return 0.0;
  double shape = 1.0;
  if (std::isfinite(in.pulse_width) && in.pulse_width > 0.0) {
    const double d = std::remainder(x - in.pulse_center, length);
    shape = std::exp(-0.5 * (d / in.pulse_width) * (d / in.pulse_width));
  }
  return amplitude * shape * pulse_profile(in, t);
}

}  // namespace slipstrip
