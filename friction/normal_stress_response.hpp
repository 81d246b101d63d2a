#pragma once
// The friction's response to a normal stress that changes with time
// (docs/bodies.md §4): the effective normal stress sigma_eff the friction sees
// relaxes towards the current one sigma (Prakash & Clifton 1993; Cochard &
// Rice 2000), and the optional Linker-Dieterich response of the state.  One
// node's predictor-corrector step of the local problem
//     tau - eta v = sigma_eff f(v, phi)
// with sigma_eff advanced like the state.  Used by the rate-and-state law of a
// one-dimensional interface between in-plane dissimilar bodies (on the signed
// slip rate) and by a 2D interface's (solver/simulation_3d.cpp, on |v|).
#include "friction/friction_law.hpp"

namespace slipstrip {

struct NormalStressMemory {
  // interface.normal_stress_time [s]: > 0 relaxes over this time; else over
  // the slip `slip` [m] (L_sigma), at the rate (|v| + v*) / L_sigma.
  double time = 0.0;
  double slip = 0.0;
  double v_star = 0.0;  // friction.v_star [m/s]

  // sigma_eff at the new level from the old one: d sigma_eff/dt = -r (sigma_eff -
  // sigma(t)), sigma linear in t between the two levels, exactly for the rate r
  // held fixed (r from `slip_rate`).
  double relaxed(double effective_old, double sigma_old, double sigma_new, double slip_rate, double dt) const;
};

// The state over a step with the Linker-Dieterich response:
// d ln(phi)/dt = g(v, phi)/phi - (alpha/B) d ln(sigma_eff)/dt.  The second part
// alone is exact (phi scales by (e_new/e_old)^(-alpha/B) over the step); Strang
// splitting keeps the predictor-corrector second order.  alpha = 0 is
// evolve_state itself.
double evolve_state_with_normal_stress(const FrictionParameters& p, double phi_old, double slip_rate, double dt,
                                       double effective_old, double effective_new);

struct NormalStressNodeStep {
  double slip_rate, state, effective_normal_stress;
};

// One node over one step, from the load tau (the traction with the slip rate
// held at zero, tau - eta v being the shear traction), the slip rate and state
// at the old level, the contact normal stress at both levels and sigma_eff at
// the old one:
//   sigma_p, phi_p from v_old;  v_p = solve(sigma_p, phi_p);
//   sigma_eff, phi from (v_old + v_p)/2;  v = solve(sigma_eff, phi).
// Where the faces are open (sigma_new = 0 exactly) there is no traction: v =
// tau / eta, the state evolves with it and sigma_eff relaxes towards 0 (no
// Linker-Dieterich part: no contact whose state could respond).  Throws what
// solve_slip_rate and evolve_state throw.
NormalStressNodeStep normal_stress_node_step(const FrictionParameters& p, const NormalStressMemory& memory,
                                             double eta, double tau, double v_old, double phi_old,
                                             double sigma_old, double sigma_new, double effective_old, double dt);

}  // namespace slipstrip
