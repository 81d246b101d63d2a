#pragma once
// The history operator of an interface between two different bodies, each
// carried by its own operator (docs/bodies.md, "per-body formulation").
//
// Body b has face velocity v_b (perturbation, one Fourier mode) and an
// instantaneous impedance eta_b (antiplane: mu_b / c_b); its face traction is
//   top:     tau = -eta_t v_t - h_t,    h_t from v_t at earlier steps,
//   bottom:  tau = +eta_b v_b + h_b,    h_b from v_b at earlier steps
// (the bottom body is the top one reflected in y = 0, which flips the sign of
// sigma_yz).  With the slip rate v = v_t - v_b, eliminating v_t and v_b gives
// the local problem the friction solve sees, of the same form as for
// identical bodies:
//   tau = -eta v - h,   eta = eta_t eta_b / (eta_t + eta_b),   h = eta (h_t/eta_t - h_b/eta_b),
// and, once v is known, each body's face velocity
//   v_t =  (eta/eta_t) (v - (h_t + h_b)/eta_b),   v_b = -(eta/eta_b) (v + (h_t + h_b)/eta_t),
// which feeds that body's own history.  All of it is linear and mode by
// mode, so it is done on the spectra inside push(): the time loop is the
// identical-body one.
//
// Each body operator is "pair-normalised": the operator of two identical
// copies of that body (StripHistory, BlockStripHistory or HalfSpaceHistory,
// radiation damping eta_b / 2), whose response is half the body's.  The
// body's own history is therefore that operator fed with 2 v_b.  A rigid
// bottom body (no operator) has eta_b = inf: v_t = v, h = h_t, eta = eta_t.
//
// Antiplane only: in-plane dissimilar bodies also couple slip to the normal
// stress (a 2x2 response per mode), which this scalar combination omits.
#include <complex>
#include <memory>
#include <span>
#include <vector>

#include "kernels/elastic_material.hpp"
#include "kernels/history_convolution.hpp"

namespace slipstrip {

class TwoBodyHistory final : public HistoryOperator {
 public:
  // Both operators share the time step and the number of modes; bottom ==
  // nullptr is a rigid bottom body.
  TwoBodyHistory(std::unique_ptr<HistoryOperator> top, std::unique_ptr<HistoryOperator> bottom);

  double time_step() const override { return top_->time_step(); }
  double radiation_damping() const override { return eta_; }
  int modes() const override { return top_->modes(); }
  ModeOperatorStats stats() const override;
  void push(std::span<const std::complex<double>> slip_rate_spectrum) override;
  std::span<const std::complex<double>> history() const override { return history_; }
  HistoryOperatorState save_state() const override;
  void restore_state(const HistoryOperatorState& state) override;
  HistoryStateLayout state_layout() const override;

  // The body impedances eta_b (twice the pair operators' radiation damping;
  // +inf for a rigid bottom).
  double top_impedance() const { return eta_top_; }
  double bottom_impedance() const { return eta_bottom_; }
  // The steps after which the bodies' per-step work repeats (their block
  // operators' B, the half-space's slow block; 1 for modal operators), the
  // larger of the two (both are powers of two).
  int period() const;

 private:
  std::unique_ptr<HistoryOperator> top_, bottom_;
  double eta_top_, eta_bottom_, eta_;
  std::vector<std::complex<double>> input_top_, input_bottom_, history_;
};

// The common time step of two bodies and the heights their operators use.
// Each finite body's shear echo 2 H_b / c_b must be a whole number of steps
// (the exact delay line and the comb identity, docs/theory.md 6.2).  The step
// is at most beta dx / max(c_t, c_b) and makes the top body's echo exact; the
// bottom body's echo is rounded to the nearest whole number of steps, choosing
// among the steps from the largest down by up to 1/16 (at least 16 candidates)
// the one that changes the bottom height least.  Identical or commensurate
// bodies are exact.  Throws std::invalid_argument naming bottom.height and
// time.beta when the change would exceed max_relative_height_change.
struct TwoBodyTiming {
  double time_step = 0.0;
  double top_height = 0.0;     // as given
  double bottom_height = 0.0;  // as the bottom operator uses it (H_b (1 + change))
  double bottom_height_change = 0.0;  // relative
};
TwoBodyTiming two_body_time_step(const ElasticMaterial& top, double top_height,
                                 const ElasticMaterial& bottom, double bottom_height, double dx,
                                 double beta, double max_relative_height_change = 1e-3);

}  // namespace slipstrip
