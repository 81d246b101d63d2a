#pragma once
// Unilateral contact of the two faces at one node (docs/bodies.md §4,
// "Opening"): no interpenetration, no tension.  Per node and time level, from
// the compressive normal stress the faces would carry if they moved together
// (`contact`, the elimination of kernels/inplane_pair_history.hpp) and the gap
// at the level before.  The normal traction is contact + d, with d the opening
// stress, and the gap opens at the rate d / eta_y (eta_y: the pair's normal
// radiation damping, InplanePairHistory::normal_radiation_damping()).
//
// The gap g_{n+1} = g_n + dt d_{n+1} / eta_y (the rate at the new level, so a
// node in contact has rate 0 and gap 0 exactly), and:
//   * closed (g_n = 0) and contact > 0: stays in contact, d = 0;
//   * else try open (normal traction 0, d = -contact): if the new gap is >= 0
//     the node is open;
//   * else the faces meet within the step: the gap is clamped at 0 and the
//     contact stress that brings them together exactly is applied,
//     d = -eta_y g_n / dt (normal traction contact + d > 0).
// Both faces' normal velocities are then those of a body loaded by its own
// traction alone (t_b = E_b v_b + h_b with t_b = 0 while open).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <span>

namespace slipstrip {

struct NormalContact {
  double normal_stress;   // compressive normal traction at the new level [Pa] (0: open)
  double opening_stress;  // d = normal_stress - contact [Pa]
  double gap;             // g_{n+1} >= 0 [m]
};

inline NormalContact normal_contact(double contact, double gap, double eta_y, double dt) {
  if (gap == 0.0 && contact > 0.0) return {contact, 0.0, 0.0};
  const double opened = gap - dt * contact / eta_y;
  if (opened >= 0.0) return {0.0, -contact, opened};
  const double opening_stress = -eta_y * gap / dt;
  const double closed = contact + opening_stress;
  // closed > 0 follows from opened < 0; only rounding can break it, and then the
  // faces are exactly touching with no traction.
  if (closed > 0.0) return {closed, opening_stress, 0.0};
  return {0.0, -contact, 0.0};
}

// The contact step of node i (the fields of a simulation, one value per node):
// its normal stress, opening stress and gap at the new level.  Returns whether
// the node has an opening stress (open or closing: the operators must see it).
inline bool contact_step(std::size_t i, double contact, double eta_y, double dt, std::span<double> normal_stress,
                         std::span<double> opening_stress, std::span<double> gap) {
  const NormalContact c = normal_contact(contact, gap[i], eta_y, dt);
  normal_stress[i] = c.normal_stress;
  opening_stress[i] = c.opening_stress;
  gap[i] = c.gap;
  return c.opening_stress != 0.0;
}

// The gap reported (Simulation::opening()): 0 where the faces are in contact
// (normal_stress > 0), else the trapezoidal integral of the gap rate -- the rule
// the history operators and the slip use -- which is g_{n+1} minus half a step
// of the current rate.  max() only guards rounding: that value is >= 0 for
// every sequence normal_contact produces.
inline double reported_gap(double normal_stress, double gap, double opening_rate, double dt) {
  return normal_stress > 0.0 ? 0.0 : std::max(0.0, gap - 0.5 * dt * opening_rate);
}

}  // namespace slipstrip
