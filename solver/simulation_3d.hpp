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
//
// Dissimilar bodies (bottom.body = "elastic" or "rigid", outer faces driven or
// clamped; docs/3d.md): the history operator is the rotated 1D pairs'
// (InterfaceHistory2d::build_pair), the radiation damping the pair's, and the
// normal stress varies: per node the contact step of the 1D pair
// (solver/interface_contact.hpp: the faces open where it would be tensile),
// and the friction sees the regularised normal stress sigma_eff
// (friction/normal_stress_response.hpp), |tau| = sigma_eff f(|v|, phi), solved
// node by node with the scalar routines on the magnitudes.
#include <algorithm>
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
  // Dissimilar in-plane bodies: whether this step carries the normal stress,
  // and the same step with the opening stress d at t_n (empty: none) in and the
  // compressive normal stress perturbation at t_{n+1} out.  The default
  // carries none and throws std::logic_error if called.
  virtual bool variable_normal_stress() const { return false; }
  virtual void history(std::span<const double> rate_x, std::span<const double> rate_z,
                       std::span<const double> opening_stress, std::span<double> history_x,
                       std::span<double> history_z, std::span<double> normal_stress);
  // The operator over this process's Fourier modes.
  virtual const InterfaceHistory2d& history_operator() const = 0;
  virtual InterfaceHistory2d& history_operator() = 0;
  // Over all processes: the sum and the largest of each one's value.
  virtual double sum(double local) const = 0;
  virtual double max(double local) const = 0;
};

// The x and z components' transforms: as a pair on threads of their own
// where the transform offers it (RealFft2d), else one after the other (the
// distributed transform, whose messages are not made from two threads).
template <class Fft>
void forward_components(Fft& fft, std::span<const double> rate_x, std::span<std::complex<double>> spectrum_x,
                        std::span<const double> rate_z, std::span<std::complex<double>> spectrum_z) {
  if constexpr (requires { fft.forward_pair(rate_x, spectrum_x, rate_z, spectrum_z); }) {
    fft.forward_pair(rate_x, spectrum_x, rate_z, spectrum_z);
  } else {
    fft.forward(rate_x, spectrum_x);
    fft.forward(rate_z, spectrum_z);
  }
}

template <class Fft>
void inverse_components(Fft& fft, std::span<const std::complex<double>> spectrum_x, std::span<double> history_x,
                        std::span<const std::complex<double>> spectrum_z, std::span<double> history_z) {
  if constexpr (requires { fft.inverse_pair(spectrum_x, history_x, spectrum_z, history_z); }) {
    fft.inverse_pair(spectrum_x, history_x, spectrum_z, history_z);
  } else {
    fft.inverse(spectrum_x, history_x);
    fft.inverse(spectrum_z, history_z);
  }
}

// The spectral step through `fft` (RealFft2d or a distributed transform with
// the same forward / inverse) and `history` (over the transform's modes):
// rates -> spectra -> history -> history part of the traction.  No allocation.
template <class Fft>
void transform_push_invert(Fft& fft, InterfaceHistory2d& history, std::span<std::complex<double>> spectrum_x,
                           std::span<std::complex<double>> spectrum_z, std::span<const double> rate_x,
                           std::span<const double> rate_z, std::span<double> history_x, std::span<double> history_z) {
  forward_components(fft, rate_x, spectrum_x, rate_z, spectrum_z);
  history.push(spectrum_x, spectrum_z);
  inverse_components(fft, history.history_x(), history_x, history.history_z(), history_z);
}

// The same for dissimilar bodies: rates and the opening stress (empty: none)
// -> spectra -> history and normal stress -> their parts at the nodes (a third
// pair of transforms).  spectrum_opening and spectrum_normal are scratch of
// the transform's mode count.  No allocation.
template <class Fft>
void transform_push_invert(Fft& fft, InterfaceHistory2d& history, std::span<std::complex<double>> spectrum_x,
                           std::span<std::complex<double>> spectrum_z,
                           std::span<std::complex<double>> spectrum_opening,
                           std::span<std::complex<double>> spectrum_normal, std::span<const double> rate_x,
                           std::span<const double> rate_z, std::span<const double> opening_stress,
                           std::span<double> history_x, std::span<double> history_z,
                           std::span<double> normal_stress) {
  forward_components(fft, rate_x, spectrum_x, rate_z, spectrum_z);
  if (opening_stress.empty()) {
    history.push(spectrum_x, spectrum_z, {});
  } else {
    fft.forward(opening_stress, spectrum_opening);
    history.push(spectrum_x, spectrum_z, spectrum_opening);
  }
  inverse_components(fft, history.history_x(), history_x, history.history_z(), history_z);
  // The inverse transform may overwrite its input: a copy of the operator's output.
  std::copy(history.normal_stress().begin(), history.normal_stress().end(), spectrum_normal.begin());
  fft.inverse(spectrum_normal, normal_stress);
}

// Makes the spectral step of `config` at time step `time_step`.
using SpectralStepFactory = std::function<std::unique_ptr<InterfaceSpectralStep>(
    const SimulationConfig& config, double time_step, const CancelCheck& cancelled)>;

// The dissimilar bodies' operator of `config` (bottom.body "elastic" or
// "rigid") over a set of Fourier modes (InterfaceHistory2d::build_pair; the
// serial step's over all of them).  A half-space body without a passive 2x2
// operator is a std::invalid_argument naming time.beta, the body's Poisson
// ratio and the bound on time.beta.
InterfaceHistory2d interface_pair_history(const SimulationConfig& config, double time_step,
                                          const CancelCheck& cancelled, const InterfaceModeSet& modes,
                                          const InterfaceHistory2d::StripOperatorFactory& strip_operator,
                                          const InterfaceHistory2d::PairPart& part);

// One process: all rows, all modes; the strip operators chosen by
// time.history (make_strip_history).
std::unique_ptr<InterfaceSpectralStep> serial_spectral_step(const SimulationConfig& config, double time_step,
                                                           const CancelCheck& cancelled);

class Simulation3d {
 public:
  // The initial state is steady sliding at v0 with each node's friction
  // parameters ([friction] profiles along x or z) plus config.initial's
  // perturbations (white noise node by node; the sine, the bump and
  // band-limited noise as functions of x, the same on every row z; the bump a
  // patch with initial.local_width_z > 0).  Throws
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
  // tau_0 [Pa] at this process's nodes: the steady-sliding strength at v0 with
  // each node's friction parameters (the same at every node without profiles).
  std::span<const double> reference_shear_stress() const { return reference_; }
  // The bottom body's height as its operators use it (its shear echo rounded
  // to whole time steps, two_body_time_step); NaN for a rigid base.
  double bottom_height_used() const { return bottom_height_used_; }
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

  // Dissimilar in-plane bodies (docs/3d.md): the normal stress changes; these
  // are empty otherwise.  Compressive normal stress sigma and the effective
  // one sigma_eff the friction sees [Pa]; the opening gap [m] (0 in contact)
  // and its rate [m/s], as the 1D pair's (solver/simulation.hpp).
  bool variable_normal_stress() const { return !normal_stress_.empty(); }
  std::span<const double> normal_stress() const { return normal_stress_; }
  std::span<const double> effective_normal_stress() const { return effective_normal_stress_; }
  std::span<const double> opening() const { return opening_; }
  std::span<const double> opening_rate() const { return opening_rate_; }

  // Over the whole interface (every process takes part on a split run).
  double max_slip_rate() const;  // max |v| over the nodes
  double mean_slip_x() const;
  double mean_shear_stress_x() const;

  // The state after the current step, this process's part (SimulationState's x fields, its
  // 2D-interface fields and the history operator; allocates: restart points
  // only) and its restoration into a Simulation3d of the same config:
  // afterwards step() continues bit for bit as the saved one would.
  // restore_state throws std::invalid_argument naming a field of the wrong
  // size or an invalid time level.  Its history state may also be the mode
  // records of this process's Fourier modes
  // (InterfaceHistory2d::kModeRecordsKind, split_state).
  SimulationState save_state() const;
  void restore_state(const SimulationState& saved);

 private:
  void initialise(std::span<const double> initial_state, std::span<const double> steady_state_all);
  void solve(bool initial);
  void solve_with_normal_stress(bool initial);
  void directions();  // v, tau from |v| and the load
  void update_normal_stress();
  void update_opening_outputs();
  void check_finite(const char* what) const;

  SimulationConfig config_;
  int nodes_x_, nodes_z_;
  double dx_, dz_, dt_, eta_, v0_, bottom_height_used_;
  double time_ = 0.0;
  long long step_index_ = 0;
  // Per-node friction parameters of this process's nodes ([friction] profiles;
  // empty without them: the batch solve's uniform path) and, per node, tau_0 and
  // the drive tau_0 + eta v0 of the history load.
  FrictionNodeValues friction_nodes_;
  LocalSolveParameters local_;
  std::vector<double> reference_, drive_;
  std::unique_ptr<InterfaceSpectralStep> spectral_;

  std::vector<double> slip_x_, slip_z_, slip_rate_x_, slip_rate_z_, state_;
  std::vector<double> shear_stress_x_, shear_stress_z_;
  // Per step: previous magnitudes and state, the history load and its magnitude.
  std::vector<double> speed_, previous_speed_, previous_state_;
  std::vector<double> previous_rate_x_, previous_rate_z_;
  std::vector<double> load_x_, load_z_, load_magnitude_;
  std::vector<double> rate_perturbation_x_, rate_perturbation_z_;
  // Dissimilar bodies only (empty otherwise): as Simulation's.
  std::vector<double> normal_stress_, previous_normal_stress_, effective_normal_stress_, previous_effective_;
  std::vector<double> gap_, opening_stress_, opening_, opening_rate_, normal_perturbation_;
  bool any_opening_stress_ = false;
};

// The 2D interface's grid of a config (geometry.length, .width, .nodes, .nodes_z).
InterfaceGrid2d interface_grid(const SimulationConfig& config);

}  // namespace slipstrip
