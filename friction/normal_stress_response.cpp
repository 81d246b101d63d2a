#include "friction/normal_stress_response.hpp"

#include <cmath>

namespace slipstrip {

double NormalStressMemory::relaxed(double effective_old, double sigma_old, double sigma_new, double slip_rate,
                                   double dt) const {
  const double rate = time > 0.0 ? 1.0 / time : (std::abs(slip_rate) + v_star) / slip;
  const double x = rate * dt;
  const double decay = std::exp(-x);
  const double ramp = x > 0.0 ? -std::expm1(-x) / x : 1.0;  // (1 - e^-x) / x
  return sigma_new + (effective_old - sigma_old) * decay - (sigma_new - sigma_old) * ramp;
}

double evolve_state_with_normal_stress(const FrictionParameters& p, double phi_old, double slip_rate, double dt,
                                       double effective_old, double effective_new) {
  // effective_old = 0 only after a long opening (sigma_eff decayed to 0): no
  // finite ratio, the contact starts afresh.
  if (p.linker_dieterich == 0.0 || !(effective_old > 0.0)) return evolve_state(p, phi_old, slip_rate, dt);
  const double half = std::pow(effective_new / effective_old, -0.5 * p.linker_dieterich / state_log_coefficient(p));
  return half * evolve_state(p, half * phi_old, slip_rate, dt);
}

NormalStressNodeStep normal_stress_node_step(const FrictionParameters& p, const NormalStressMemory& memory,
                                             double eta, double tau, double v_old, double phi_old,
                                             double sigma_old, double sigma_new, double effective_old, double dt) {
  if (sigma_new == 0.0) {
    const double v = tau / eta;
    const double v_mid = 0.5 * (v_old + v);
    return {v, evolve_state(p, phi_old, v_mid, dt), memory.relaxed(effective_old, sigma_old, sigma_new, v_mid, dt)};
  }
  const double e_p = memory.relaxed(effective_old, sigma_old, sigma_new, v_old, dt);
  const double phi_p = evolve_state_with_normal_stress(p, phi_old, v_old, dt, effective_old, e_p);
  const double v_p = solve_slip_rate(p, e_p, eta, tau, phi_p, v_old);
  const double v_mid = 0.5 * (v_old + v_p);
  const double e = memory.relaxed(effective_old, sigma_old, sigma_new, v_mid, dt);
  const double phi = evolve_state_with_normal_stress(p, phi_old, v_mid, dt, effective_old, e);
  return {solve_slip_rate(p, e, eta, tau, phi, v_p), phi, e};
}

}  // namespace slipstrip
