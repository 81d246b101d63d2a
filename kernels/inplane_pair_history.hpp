#pragma once
// The history operator of an in-plane interface between two different bodies
// (docs/bodies.md, "In-plane dissimilar bodies"): each body carried by its own
// 2x2 operator (FaceModalHistory, docs/inplane_bodies.md §5), combined with
// continuous tractions, no interpenetration and slip = jump of u_x.
//
// Per Fourier mode, body b's traction in its own frame (the body above its
// face) is t_b = E_b v_b + h_b, E_b = diag(Ex_b, Ey_b) = diag(mu/c_s, rho c_d).
// The top body's t is -(sigma_xy, sigma_yy); the bottom body is the mirror
// image (y -> -y), so its own-frame velocity is D v and its traction D
// (sigma_xy, sigma_yy), D = diag(1, -1).  With the slip rate V = v_x,top -
// v_x,bottom and v_y continuous, eliminating the face velocities gives
//   sigma_xy = -eta V - h,        eta = Ex_t Ex_b / (Ex_t + Ex_b),
//                                 h   = (Ex_b hx_t - Ex_t hx_b) / (Ex_t + Ex_b),
//   sigma    = -sigma_yy = (Ey_b hy_t + Ey_t hy_b) / (Ey_t + Ey_b)   (compressive),
// so the normal stress at t_{n+1} follows from the history alone (it has no
// instantaneous term in V): the friction solve stays local and scalar.  Then
//   v_y       = -(hy_t - hy_b) / (Ey_t + Ey_b),
//   v_x,bottom = -(Ex_t V + hx_t + hx_b) / (Ex_t + Ex_b),   v_x,top = v_x,bottom + V,
// which feed the body operators (the bottom one with -v_y).  A rigid bottom
// (no operator) has Ex_b = Ey_b = inf: v_top = (V, 0), h = hx_t, sigma = hy_t.
// Identical bodies give h = (hx_t - hx_b)/2 and sigma = 0 by symmetry.
//
// Opening (docs/bodies.md §4): where the faces do not move together the normal
// traction differs from the contact one sigma by an opening stress d (the
// solver's contact step decides it per node, in x).  Both faces then carry
// sigma + d, so each body's own-frame normal velocity gains d / Ey_b (each face
// is pushed into its own body) and the gap opens at d / Ey_t + d / Ey_b =
// d / eta_y, eta_y = Ey_t Ey_b / (Ey_t + Ey_b) (Ey_t for a rigid bottom).  The
// shear elimination is unchanged: both faces carry the same shear traction in
// contact and open alike.
#include <complex>
#include <memory>
#include <span>
#include <vector>

#include "kernels/face_history.hpp"
#include "kernels/history_convolution.hpp"

namespace slipstrip {

class InplanePairHistory final : public HistoryOperator {
 public:
  // Both operators share the time step and the number of Fourier modes;
  // bottom == nullptr is a rigid bottom body.
  // Either body's operator may be a finite body's (FaceModalHistory) or a
  // half-space's (FaceHalfSpaceHistory).
  InplanePairHistory(std::unique_ptr<FaceHistory> top, std::unique_ptr<FaceHistory> bottom);
  // One operator of the whole pair: the combined operator of two half-spaces
  // (FaceHalfSpaceHistory's pair constructor, docs/inplane_bodies.md §7), fed
  // the slip rate V and the opening rate Omega = d / eta_y directly; its
  // histories are h and the contact normal stress (-(sigma_xy, sigma_yy) =
  // diag(eta, eta_y) [V, Omega] + (h_x, h_y)).  No face velocity is
  // eliminated.
  struct Combined {};
  InplanePairHistory(Combined, std::unique_ptr<FaceHistory> pair);
  bool combined() const { return combined_; }

  double time_step() const override { return top_->time_step(); }
  double radiation_damping() const override { return eta_; }
  int modes() const override { return top_->modes(); }
  ModeOperatorStats stats() const override;
  void push(std::span<const std::complex<double>> slip_rate_spectrum) override;
  // The same with the spectrum of the opening stress d at t_n [Pa] (above).
  void push(std::span<const std::complex<double>> slip_rate_spectrum,
            std::span<const std::complex<double>> opening_stress_spectrum);
  // eta_y [Pa s/m]: the gap rate is the opening stress over it.
  double normal_radiation_damping() const { return eta_y_; }
  // Shear history part h at t_{n+1} (sigma_xy = -eta V - h).
  std::span<const std::complex<double>> history() const override { return history_; }
  // Compressive normal stress perturbation at t_{n+1} [Pa] (spectrum).
  std::span<const std::complex<double>> normal_stress() const { return normal_; }
  HistoryOperatorState save_state() const override;
  void restore_state(const HistoryOperatorState& state) override;
  HistoryStateLayout state_layout() const override;
  // Steps after which both bodies' per-step work repeats (FaceHistory::period).
  int period() const;

 private:
  std::unique_ptr<FaceHistory> top_, bottom_;  // combined: top_ is the pair's operator
  bool combined_ = false;
  double ex_top_, ey_top_, ex_bottom_, ey_bottom_, eta_, eta_y_;
  std::vector<std::complex<double>> top_x_, top_y_, bottom_x_, bottom_y_, history_, normal_;
};

}  // namespace slipstrip
