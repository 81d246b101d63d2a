#pragma once
// Discrete 2x2 history operator of ONE finite body (docs/inplane_bodies.md §5):
// per Fourier mode, the face traction on the body for face velocities v_n is
//     t_n = E v_n + h_n,   E = diag(mu / c_s, rho c_d)  (radiation impedances),
//     h_n = 2 E R_n + dt sum_m W'_m sum_{j>=1} (1 - cos(phi_m j)) v_{n-j},
// R_n = sum_{j>=1} v_{n-j}, phi_m = omega_m dt: the body's normal modes below
// Nyquist (kernels/face_modes.hpp) with weights W'_m <= 0 chosen so that
//     2 E / dt + sum_m W'_m = K(k, 0)         (exact static stiffness),
// i.e. the static stiffness of the modes above Nyquist is placed passively (a
// negative part on a Nyquist element, a positive part absorbed into the highest
// modes along their own rank-one directions).  In Foster form
//     Z_d(z) = (dt/2) K(k,0) C_1(z) - sum_m (dt/4) W'_m (C_{e^{i phi}} + C_{e^{-i phi}}),
// every coefficient is positive semidefinite and the constant is zero: the
// operator is lossless and passive as a matrix (the matrix form of
// docs/theory.md §6.3-6.4).  For two identical strips this is, per component,
// the identical-strip operator's structure; here the shear echoes are carried by
// the modes (band-limited), not by an exact delay line.
#include <complex>
#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "kernels/face_modes.hpp"
#include "kernels/face_response.hpp"
#include "kernels/history_convolution.hpp"

namespace slipstrip {

// The discrete weights of one Fourier mode: phases in (0, pi] and 2x2 weights.
struct FaceDiscreteModes {
  std::vector<double> phase;
  std::vector<FaceMatrix> weight;
};

// Throws std::runtime_error ("refine the time step") when K(k,0) - 2E/dt is not
// negative semidefinite (no passive operator of this form exists) or the
// positive part cannot be absorbed.
FaceDiscreteModes face_discrete_modes(const ElasticMaterial& material, double height,
                                      OuterFace outer_face, double wavenumber, double time_step);

// One body's discrete 2x2 history operator as the interface sees it (per
// Fourier mode: t_n = E v_n + h_n, E = diag(shear_impedance, normal_impedance)):
// the finite body's modal operator below, or a half-space's
// (kernels/face_half_space.hpp).
class FaceHistory {
 public:
  virtual ~FaceHistory() = default;
  virtual double time_step() const = 0;
  // E = diag(mu/c_s, rho c_d).
  virtual double shear_impedance() const = 0;
  virtual double normal_impedance() const = 0;
  virtual int modes() const = 0;
  // Feed the face-velocity spectra (x and y, q = 0..N/2) at t_n; afterwards
  // history_x/y hold h_{n+1}.  No allocation.
  virtual void push(std::span<const std::complex<double>> velocity_x,
                    std::span<const std::complex<double>> velocity_y) = 0;
  virtual std::span<const std::complex<double>> history_x() const = 0;
  virtual std::span<const std::complex<double>> history_y() const = 0;
  // Everything push() changes, as arrays named prefix + "...", and its
  // restoration into an operator built with the same arguments (then push()
  // continues bit for bit).  Allocates: not in the time loop.
  virtual void save_into(HistoryOperatorState& state, const std::string& prefix) const = 0;
  virtual void restore_from(const HistoryOperatorState& state, const std::string& prefix) = 0;
  // Where each mode's values lie in save_into's arrays (HistoryStateLayout),
  // named as save_into names them.  Allocates: not in the time loop.
  virtual void state_layout_into(HistoryStateLayout& layout, const std::string& prefix) const = 0;
  virtual std::size_t memory_bytes() const = 0;
  // Recursions per step (modes, exponentials): the stats' "oscillators".
  virtual std::size_t discrete_modes() const = 0;
  // Steps after which the pattern of per-step work repeats (a block
  // algorithm's block; 1 when every step costs the same): benchmarks time a
  // whole number of periods.
  virtual int period() const { return 1; }
  // The operator's algorithm as a restart point names it ("modal", "block",
  // "half-space"); save_into writes one array no other algorithm writes
  // (saved_face_algorithm in inplane_pair_history.cpp tells them apart).
  virtual const char* algorithm() const = 0;
};

class FaceModalHistory final : public FaceHistory {
 public:
  // Fourier modes q = 0..nodes/2 of a periodic interface of length `length`.
  FaceModalHistory(const ElasticMaterial& material, double height, OuterFace outer_face,
                   double length, int nodes, double time_step);
  // One Fourier mode per wavenumber |k| of the list (the first 0: the uniform
  // mode), e.g. the |k| of a 2D interface's modes (docs/3d.md); the discrete
  // weights of each distinct |k| are designed once and shared bit for bit.
  FaceModalHistory(const ElasticMaterial& material, double height, OuterFace outer_face,
                   std::span<const double> wavenumbers, double time_step);

  double time_step() const override { return dt_; }
  double shear_impedance() const override { return impedance_x_; }
  double normal_impedance() const override { return impedance_y_; }
  int modes() const override { return static_cast<int>(first_.size()) - 1; }
  void push(std::span<const std::complex<double>> velocity_x,
            std::span<const std::complex<double>> velocity_y) override;
  std::span<const std::complex<double>> history_x() const override { return history_x_; }
  std::span<const std::complex<double>> history_y() const override { return history_y_; }
  // The discrete weights of Fourier mode q (for tests).
  FaceDiscreteModes mode(int q) const;
  void save_into(HistoryOperatorState& state, const std::string& prefix) const override;
  void restore_from(const HistoryOperatorState& state, const std::string& prefix) override;
  void state_layout_into(HistoryStateLayout& layout, const std::string& prefix) const override;
  std::size_t memory_bytes() const override;
  std::size_t discrete_modes() const override { return weight_.size(); }
  const char* algorithm() const override { return "modal"; }

 private:
  double dt_, impedance_x_, impedance_y_;
  std::vector<std::size_t> first_;  // per Fourier mode: its discrete modes
  std::vector<double> cos_, sin_;
  std::vector<FaceMatrix> weight_;
  std::vector<FaceMatrix> weight_sum_;  // per Fourier mode
  // State: per discrete mode, C and S sums of each input component.
  std::vector<std::complex<double>> cx_, sx_, cy_, sy_;
  std::vector<std::complex<double>> running_x_, running_y_;
  std::vector<std::complex<double>> history_x_, history_y_;
};

}  // namespace slipstrip
