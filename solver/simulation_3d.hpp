#pragma once
// One simulation of a two-dimensional interface (periodic in x and z) between
// two identical bodies of height H (or half-spaces): vector slip, rate-and-state
// friction with the shear traction collinear with the slip rate,
//   |tau| = sigma0 f(|v|, phi),   tau / |tau| = v / |v|,
// one state variable per node, loading along x (docs/3d.md).
//
// Fields are stored row-major [iz][ix] (x fastest), node (ix, iz) at
// (ix dx, iz dz).  Per step: the x and z slip-rate perturbations go through a
// 2D FFT each, the history operator of kernels/interface_2d_history.hpp, and
// back; at each node the history load tau_h = (tau_0 + eta v0 - h_x, -h_z) is
// solved for the slip rate.  Because the instantaneous response is the same
// scalar eta = mu / (2 c_s) in every direction, tau_h - eta v = |tau| v / |v|
// makes v parallel to tau_h, and |v| solves the scalar local problem
// |tau_h| - eta |v| = sigma0 f(|v|, phi): the 2D batch predictor-corrector
// (friction/batch_solve.hpp) on the magnitudes, then v = |v| tau_h / |tau_h|.
#include <complex>
#include <functional>
#include <memory>
#include <span>
#include <vector>

#include "config/simulation_config.hpp"
#include "friction/batch_solve.hpp"
#include "kernels/fft.hpp"
#include "kernels/interface_2d_history.hpp"
#include "solver/simulation.hpp"

namespace slipstrip {

// The rows z of the interface a process holds: all of them on one process;
// a slab of consecutive rows on each process of a run split over several
// (parallel/, built with SLIPSTRIP_MPI; docs/3d.md).
struct InterfaceSlab {
  int first_row = 0, rows = 0;
};

// The spectral part of a step and the sums over the whole interface.  The
// default (serial_spectral_step) is RealFft2d and the history operator over
// every Fourier mode, in this process; a run split over processes supplies one
// whose FFT is distributed and whose operator holds only this process's modes.
class InterfaceSpectralStep {
 public:
  virtual ~InterfaceSpectralStep() = default;
  virtual InterfaceSlab slab() const = 0;
  // The history part of the traction at t_{n+1} at this process's nodes
  // ([row][ix]) from their slip-rate perturbations (x and z) at t_n.  No
  // allocation.
  virtual void history(std::span<const double> rate_x, std::span<const double> rate_z,
                       std::span<double> history_x, std::span<double> history_z) = 0;
  // The operator over this process's Fourier modes.
  virtual const InterfaceHistory2d& history_operator() const = 0;
  virtual InterfaceHistory2d& history_operator() = 0;
  // Over all processes: the sum and the largest of each one's value.
  virtual double sum(double local) const = 0;
  virtual double max(double local) const = 0;
};

// The spectral step through `fft` (RealFft2d or a distributed transform with
// the same forward / inverse) and `history` (over the transform's modes):
// rates -> spectra -> history -> history part of the traction.  No allocation.
template <class Fft>
void transform_push_invert(Fft& fft, InterfaceHistory2d& history, std::span<std::complex<double>> spectrum_x,
                           std::span<std::complex<double>> spectrum_z, std::span<const double> rate_x,
                           std::span<const double> rate_z, std::span<double> history_x, std::span<double> history_z) {
  fft.forward(rate_x, spectrum_x);
  fft.forward(rate_z, spectrum_z);
  history.push(spectrum_x, spectrum_z);
  fft.inverse(history.history_x(), history_x);
  fft.inverse(history.history_z(), history_z);
}

// Makes the spectral step of `config` at time step `time_step`.
using SpectralStepFactory = std::function<std::unique_ptr<InterfaceSpectralStep>(
    const SimulationConfig& config, double time_step, const CancelCheck& cancelled)>;

// One process: all rows, all modes; the strip operators chosen by
// time.history (make_strip_history).
std::unique_ptr<InterfaceSpectralStep> serial_spectral_step(const SimulationConfig& config, double time_step,
                                                           const CancelCheck& cancelled);

class Simulation3d {
 public:
  // The initial state is steady sliding plus config.initial's perturbations
  // (white noise node by node; the sine, the bump and band-limited noise as
  // functions of x, the same on every row z).  Throws
  // std::invalid_argument naming the key for a config the 3D path does not
  // support (docs/3d.md, "Limits").
  explicit Simulation3d(const SimulationConfig& config, const CancelCheck& cancelled = {});
  // The same with a given initial state phi [s] per node of the whole
  // interface ([iz][ix]) instead (empty: from config.initial), and the
  // spectral step made by `spectral` (empty: serial_spectral_step).  Fields
  // then hold the rows of spectral's slab; max_slip_rate and the means are
  // over the whole interface.
  Simulation3d(const SimulationConfig& config, std::span<const double> initial_state,
               const CancelCheck& cancelled = {}, const SpectralStepFactory& spectral = {});

  void step();  // advance one time step; no allocation

  const SimulationConfig& config() const { return config_; }
  int nodes_x() const { return nodes_x_; }
  int nodes_z() const { return nodes_z_; }
  std::size_t nodes() const { return slip_x_.size(); }  // this process's
  InterfaceSlab slab() const { return spectral_->slab(); }
  double dx() const { return dx_; }
  double dz() const { return dz_; }
  double time() const { return time_; }
  long long step_index() const { return step_index_; }
  double time_step() const { return dt_; }
  double radiation_damping() const { return eta_; }
  double reference_shear_stress() const { return tau0_; }  // steady sliding, along x
  const InterfaceHistory2d& history_operator() const { return spectral_->history_operator(); }
  // For `slipstrip bench` only (timing the operator alone after a run): any
  // push through it changes the simulation's history.
  InterfaceHistory2d& history_operator_for_timing() { return spectral_->history_operator(); }

  std::span<const double> slip_x() const { return slip_x_; }                  // [m]
  std::span<const double> slip_z() const { return slip_z_; }
  std::span<const double> slip_rate_x() const { return slip_rate_x_; }        // [m/s]
  std::span<const double> slip_rate_z() const { return slip_rate_z_; }
  std::span<const double> state() const { return state_; }                    // phi [s]
  std::span<const double> shear_stress_x() const { return shear_stress_x_; }  // [Pa]
  std::span<const double> shear_stress_z() const { return shear_stress_z_; }

  std::span<const double> speed() const { return speed_; }                    // |v| [m/s]

  // Over the whole interface (every process takes part on a split run).
  double max_slip_rate() const;  // max |v| over the nodes
  double mean_slip_x() const;
  double mean_shear_stress_x() const;

  // The state after the current step, this process's part (SimulationState's x fields, its
  // 2D-interface fields and the history operator; allocates: restart points
  // only) and its restoration into a Simulation3d of the same config:
  // afterwards step() continues bit for bit as the saved one would.
  // restore_state throws std::invalid_argument naming a field of the wrong
  // size or an invalid time level.
  SimulationState save_state() const;
  void restore_state(const SimulationState& saved);

 private:
  void initialise(std::span<const double> initial_state);
  void solve(bool initial);
  void check_finite(const char* what) const;

  SimulationConfig config_;
  int nodes_x_, nodes_z_;
  double dx_, dz_, dt_, eta_, v0_, tau0_;
  double time_ = 0.0;
  long long step_index_ = 0;
  LocalSolveParameters local_;
  std::unique_ptr<InterfaceSpectralStep> spectral_;

  std::vector<double> slip_x_, slip_z_, slip_rate_x_, slip_rate_z_, state_;
  std::vector<double> shear_stress_x_, shear_stress_z_;
  // Per step: previous magnitudes and state, the history load and its magnitude.
  std::vector<double> speed_, previous_speed_, previous_state_;
  std::vector<double> previous_rate_x_, previous_rate_z_;
  std::vector<double> load_x_, load_z_, load_magnitude_;
  std::vector<double> rate_perturbation_x_, rate_perturbation_z_;
};

// The 2D interface's grid of a config (geometry.length, .width, .nodes, .nodes_z).
InterfaceGrid2d interface_grid(const SimulationConfig& config);

}  // namespace slipstrip
