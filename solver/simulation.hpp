#pragma once
// One simulation: interface fields, the spectral history operator and the
// explicit time step.  A process may hold several Simulation objects; nothing
// here is global.
#include <complex>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "laws/interface_law.hpp"
#include "config/simulation_config.hpp"
#include "kernels/fft.hpp"
#include "kernels/history_convolution.hpp"
#include "kernels/inplane_pair_history.hpp"

namespace slipstrip {

// A run that cannot continue (non-finite value, failed local solve): the
// message names the node, the time and the values involved.
struct SimulationError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Everything a Simulation carries from one step to the next: the interface
// fields, the time, and the history operator's state.  What a restart point
// holds (solver/checkpoint.hpp); the other members are per-step scratch or are
// rebuilt from the config.
struct SimulationState {
  double time = 0.0;
  long long step_index = 0;
  std::vector<double> slip, slip_rate, state, shear_stress, history_stress;
  // In-plane dissimilar bodies only (empty otherwise); gap and opening_stress
  // as in solver/interface_contact.hpp (all zero while the faces are in contact).
  std::vector<double> normal_stress, effective_normal_stress, gap, opening_stress;
  // A 2D interface only (Simulation3d, empty otherwise): slip, slip_rate and
  // shear_stress above hold the x components, these the z components, and
  // speed |v| as the local solve left it (the next step's previous speed,
  // which hypot(v_x, v_z) need not reproduce bit for bit).
  std::vector<double> slip_z, slip_rate_z, shear_stress_z, speed;
  HistoryOperatorState history;
};

// restore_state of Simulation and Simulation3d: each saved field must have
// the size of the simulation's field (else std::invalid_argument naming it,
// `what` and `nodes`), and the time level must be valid; checked before
// anything is copied.
struct SavedField {
  const char* name;
  const std::vector<double>* saved;
  std::vector<double>* target;
};
void check_saved_state(std::span<const SavedField> fields, const SimulationState& saved, std::size_t nodes,
                       const std::string& what);

// The strip history operator of `kernels` by `algorithm`: the modal
// StripHistory or the BlockStripHistory (the same discrete operator,
// docs/theory.md 11.1); "auto" takes the block one when some Fourier mode
// carries kBlockHistoryThreshold normal modes or more.  Used by the 1D
// interface and by each of the 2D interface's in-plane and antiplane operators.
// `most_normal_modes` > 0 replaces the kernels' own largest count of normal
// modes per Fourier mode, for the automatic choice and the block length B:
// kernels holding part of an operator's modes (one process of a split run)
// then choose as the whole operator does.  `block` > 0: the block operator's B
// (a body of a pair of different bodies, body_block_length); 0: the identical
// pair's automatic_block_length.
inline constexpr std::size_t kBlockHistoryThreshold = 128;
std::unique_ptr<HistoryOperator> make_strip_history(const ElasticMaterial& material,
                                                    const StripKernels& kernels,
                                                    HistoryAlgorithm algorithm,
                                                    const CancelCheck& cancelled = {},
                                                    std::size_t most_normal_modes = 0, int block = 0);
// The same from the bodies' constants (two different antiplane strips,
// kernels/antiplane_pair_modes.hpp: one operator of the pair).
std::unique_ptr<HistoryOperator> make_strip_history(const StripPairConstants& constants,
                                                    const StripKernels& kernels,
                                                    HistoryAlgorithm algorithm,
                                                    const CancelCheck& cancelled = {},
                                                    std::size_t most_normal_modes = 0, int block = 0);
// The largest number of normal modes of any Fourier mode of `kernels`.
std::size_t most_normal_modes(const StripKernels& kernels);

class Simulation {
 public:
  // `cancelled` is polled during the kernel and operator set-up (which takes
  // seconds for thick strips); when it returns true the constructor throws
  // SetupCancelled (kernels/history_convolution.hpp).
  // The interface law is config.interface.law, looked up in `laws`.
  explicit Simulation(const SimulationConfig& config, const CancelCheck& cancelled = {},
                      const InterfaceLawRegistry& laws = builtin_interface_laws());

  // Advance one time step dt.
  void step();

  const SimulationConfig& config() const { return config_; }
  double time() const { return time_; }
  long long step_index() const { return step_index_; }
  double time_step() const { return dt_; }
  double dx() const { return dx_; }
  // mu / (2 c_s) for identical bodies; eta_t eta_b / (eta_t + eta_b) for two
  // different ones (docs/bodies.md) [Pa s/m]
  double radiation_damping() const { return eta_; }
  // The bottom body's height as its operator uses it: its shear echo rounded
  // to whole time steps (docs/bodies.md); NaN for a rigid base.
  double bottom_height_used() const { return bottom_height_used_; }
  const HistoryOperator& history_operator() const { return *history_; }

  std::span<const double> x() const { return x_; }
  std::span<const double> slip() const { return slip_; }                // [m]
  std::span<const double> slip_rate() const { return slip_rate_; }      // [m/s]
  std::span<const double> state() const { return state_; }              // phi [s]
  std::span<const double> shear_stress() const { return shear_stress_; }  // [Pa]
  // True for in-plane dissimilar bodies, where the normal stress changes with
  // time and position (docs/bodies.md); otherwise it is loading.normal_stress.
  bool variable_normal_stress() const { return pair_ != nullptr; }
  // Compressive normal stress sigma and the effective one the friction sees
  // [Pa]; empty unless variable_normal_stress().
  std::span<const double> normal_stress() const { return normal_stress_; }
  std::span<const double> effective_normal_stress() const { return effective_normal_stress_; }
  // Opening of the interface (docs/bodies.md §4): the gap, the jump of the
  // normal displacement [m] (>= 0, 0 where the faces are in contact), and its
  // rate [m/s]; empty unless variable_normal_stress().
  std::span<const double> opening() const { return opening_; }
  std::span<const double> opening_rate() const { return opening_rate_; }
  // Nodes open at the current level (normal traction 0).
  int open_nodes() const;

  // Save (allocates: outside the time loop) and restore into a Simulation
  // built from the same config; the restored one then steps bit for bit as
  // the saved one would.  restore_state throws std::invalid_argument naming
  // the field if a size does not match this config.
  SimulationState save_state() const;
  void restore_state(const SimulationState& saved);

  double max_slip_rate() const;
  double mean_slip() const;
  double mean_shear_stress() const;
  // loading.drive = "mean_slip_rate": the uniform shear stress tau_0(t) [Pa]
  // that holds the mean slip rate at v0, at the level last solved by this
  // object (after restore_state: from the next step on); NaN otherwise.
  double loading_shear_stress() const { return law_->loading_shear_stress(); }

  // Steady sliding reference: tau_0 = strength(v0, phi_ss(v0)) (rate_and_state),
  // 0 for the verification laws: the value of every node when it is the same
  // everywhere, else the mean over the nodes (per node: reference_shear_stresses()).
  double reference_shear_stress() const;
  std::span<const double> reference_shear_stresses() const {
    return law_->reference_shear_stress();
  }

 private:
  InterfaceFields fields();
  // Runs the law; a failed node becomes a SimulationError naming x, t and the step.
  template <class Call>
  void run_law(Call&& call);
  void check_finite(const char* what) const;
  void update_normal_stress();
  void update_opening_outputs();

  SimulationConfig config_;
  int nodes_;
  double dx_, dt_, eta_, bottom_height_used_;
  double driving_velocity_;  // v0 used for the perturbation split (0 for verification laws)
  double time_ = 0.0;
  long long step_index_ = 0;

  std::vector<double> x_, slip_, slip_rate_, state_, shear_stress_;
  std::vector<double> previous_slip_rate_, previous_state_;
  std::vector<double> history_stress_;  // history part in x [Pa]
  // In-plane dissimilar bodies (empty otherwise).
  std::vector<double> normal_stress_, previous_normal_stress_, effective_normal_stress_;
  // Opening: the gap by the contact rule and the opening stress (the state,
  // solver/interface_contact.hpp), the gap as the operators see it and its rate
  // (outputs, derived from the state).
  std::vector<double> gap_, opening_stress_, opening_, opening_rate_;
  std::vector<std::complex<double>> opening_spectrum_;
  bool any_opening_stress_ = false;  // some node has opening_stress != 0 (push it)
  std::vector<double> work_real_;
  std::vector<std::complex<double>> spectrum_;

  std::unique_ptr<RealFft> fft_;
  std::unique_ptr<HistoryOperator> history_;
  InplanePairHistory* pair_ = nullptr;  // history_ when it is one (normal stress), else null
  std::unique_ptr<InterfaceLaw> law_;
};

}  // namespace slipstrip
