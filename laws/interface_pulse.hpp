#pragma once
// The imposed time profiles and shear-stress pulse of [interface], shared by
// the verification laws (prescribed_slip, free) and the rate-and-state law's
// load pulse (docs/config.md, [interface]).
#include "config/simulation_config.hpp"

namespace slipstrip {

// g(t) of `profile` with rise time T (0 for t <= 0):
//   ramp: (1 - cos(pi t/T))/2 on [0, T), 1 after;  bump: sin^4(pi t/T) on [0, T), 0 after.
double pulse_profile(const InterfaceConfig& in, double t);
double pulse_profile_rate(const InterfaceConfig& in, double t);  // dg/dt [1/s]

// amplitude * exp(-d^2 / (2 w^2)) * g(t), d the periodic distance from
// pulse_center (uniform in x when pulse_width is inf or <= 0) [Pa].
double imposed_stress(const InterfaceConfig& in, double amplitude, double length, double x,
                      double t);

}  // namespace slipstrip
