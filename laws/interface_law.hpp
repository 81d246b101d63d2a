#pragma once
// The interface law: how the interface closes the elastodynamic problem.
//
// Simulation owns the fields and the history operator; at every time level it
// hands the law the history part of the shear stress and the law sets the
// slip rate, state, slip and shear stress at every node -- without Simulation
// knowing which law it is.  A law owns its parameters (per node where they
// vary), its checks and its local solve; it is called once per time step for
// all nodes (one virtual call per step, the per-node loop stays inside the
// law: contiguous, allocation-free, vectorised where it matters).
//
// Adding a law: a new file laws/law_<name>.cpp defining make_<name>_law, and
// one line SLIPSTRIP_INTERFACE_LAW(<name>) in config/interface_laws.inc
// (docs/developing.md).
#include <cstddef>
#include <limits>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "config/interface_law_name.hpp"

namespace slipstrip {

struct SimulationConfig;

// What a law is built from.
struct InterfaceSetup {
  const SimulationConfig& config;
  std::span<const double> x;  // node positions x_i = i dx [m]
  double eta;                 // radiation damping mu / (2 c_s) [Pa s/m]
};

// The interface at the time level being solved for (one value per node).
struct InterfaceFields {
  std::span<const double> x;               // [m]
  std::span<const double> history_stress;  // history part of the shear stress [Pa] (0 at t = 0)
  std::span<const double> previous_slip_rate, previous_state;  // at t_n (advance only)
  std::span<double> slip, slip_rate, state, shear_stress;      // set by the law
  // In-plane dissimilar bodies only (empty otherwise: the normal stress is
  // sigma0 everywhere): the compressive normal stress from the elastodynamics
  // at the level solved for and at t_n [Pa], and the effective normal stress the
  // friction sees (at t_n on entry to advance, set by the law at the new level).
  // A normal stress of exactly 0 marks a node where the faces are open
  // (docs/bodies.md §4): the law gives it zero shear traction.
  std::span<const double> normal_stress = {}, previous_normal_stress = {};
  std::span<double> effective_normal_stress = {};
};

// The level being solved for: t = time + dt (initialise: time = t = 0, dt = 0).
struct InterfaceStep {
  double time = 0.0;  // t_n [s]
  double dt = 0.0;    // [s]
  long long step_index = 0;
};

// A node the law cannot solve.  Simulation adds the node's x, the time and
// the step: "<what> at node <node> (x = ...), t = ..., step ...: <detail>";
// node = kWholeInterface for a failure of no single node (the uniform load of
// loading.drive = "mean_slip_rate"): "<what>, t = ..., step ...: <detail>".
struct InterfaceFailure : std::runtime_error {
  static constexpr std::size_t kWholeInterface = static_cast<std::size_t>(-1);
  InterfaceFailure(std::string what_failed, std::size_t node_index, const std::string& detail)
      : std::runtime_error(detail), failed(std::move(what_failed)), node(node_index) {}
  std::string failed;  // e.g. "local friction solve failed"
  std::size_t node;
};

class InterfaceLaw {
 public:
  virtual ~InterfaceLaw() = default;
  // v0: the history operator sees slip_rate - driving_velocity() (0 for the
  // verification laws, which perturb a body at rest).
  virtual double driving_velocity() const = 0;
  // Steady-sliding shear stress tau_0 per node [Pa] (all zero for verification laws).
  virtual std::span<const double> reference_shear_stress() const = 0;
  // loading.drive = "mean_slip_rate": the uniform shear stress tau_0(t) [Pa]
  // that held the mean slip rate at v0 at the level last solved (the uniform
  // part of the load; docs/transition.md).  NaN for a law or a drive without it.
  virtual double loading_shear_stress() const { return std::numeric_limits<double>::quiet_NaN(); }
  // Every field at t = 0 (history empty).  Throws InterfaceFailure.
  virtual void initialise(InterfaceFields& fields) = 0;
  // Every field at step.time + step.dt, given the history stress there.
  // Throws InterfaceFailure.
  virtual void advance(const InterfaceStep& step, InterfaceFields& fields) = 0;
};

// slip += dt (previous_slip_rate + slip_rate) / 2 at every node (the laws that
// solve for the slip rate integrate the slip this way).
void integrate_slip(InterfaceFields& fields, double dt);

using InterfaceLawFactory = std::unique_ptr<InterfaceLaw> (*)(const InterfaceSetup&);

struct InterfaceLawEntry {
  std::string_view name;  // static storage
  InterfaceLawFactory make;
};

// The laws a run may select.  A value, not a global: builtin_interface_laws()
// returns the built-in ones; a test may add a law of its own to a copy.
class InterfaceLawRegistry {
 public:
  void add(InterfaceLawEntry entry);  // throws std::invalid_argument on a duplicate name
  const InterfaceLawEntry* find(std::string_view name) const;  // nullptr if unknown
  std::vector<std::string_view> names() const;
  // Builds the law config.interface.law names; throws std::invalid_argument
  // listing the registered names if there is none of that name.
  std::unique_ptr<InterfaceLaw> make(const InterfaceSetup& setup) const;

 private:
  std::vector<InterfaceLawEntry> entries_;
};

// The built-in laws (config/interface_laws.inc).
InterfaceLawRegistry builtin_interface_laws();

}  // namespace slipstrip
