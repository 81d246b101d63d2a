#include "solver/simulation_3d.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <iomanip>
#include <limits>
#include <optional>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <string>

#include "friction/normal_stress_response.hpp"
#include "kernels/face_half_space.hpp"
#include "kernels/two_body_history.hpp"
#include "laws/initial_state.hpp"
#include "simd/parallel_for.hpp"
#include "solver/half_space_time_step.hpp"
#include "solver/interface_contact.hpp"

namespace slipstrip {

namespace {

// The node loops of a step run on the OpenMP threads (simd::parallel_for, one
// contiguous share each) from this many nodes up: below it a loop costs less
// than waking the other threads.  Every loop is node by node, so the results
// do not depend on the thread count.
constexpr std::size_t parallel_nodes = 8192;

template <class Body>
void for_each_node(std::size_t n, Body&& body) {
  if (n < parallel_nodes) {
    for (std::size_t i = 0; i < n; ++i) body(i);
    return;
  }
  simd::parallel_for(static_cast<long long>(n), [&](long long i) { body(static_cast<std::size_t>(i)); });
}

}  // namespace

InterfaceGrid2d interface_grid(const SimulationConfig& config) {
  const auto& g = config.geometry;
  return InterfaceGrid2d{g.length, g.width, g.nodes, g.nodes_z};
}

namespace {

// What the 3D path supports; the message names the key and what is allowed.
const SimulationConfig& checked_3d(const SimulationConfig& c) {
  auto refuse = [](const std::string& what) {
    throw std::invalid_argument(what + " (a 2D interface, geometry.nodes_z > 1; docs/3d.md)");
  };
  if (c.material.plane != PlaneCondition::strain)
    refuse("material.plane = \"" + std::string(kPlaneConditionNames[static_cast<int>(c.material.plane)]) +
           "\" is not allowed with a 2D interface: expected \"strain\" (the bodies are 3D; slip has x and z parts)");
  if (c.interface.law != InterfaceLawName::rate_and_state)
    refuse("interface.law must be \"rate_and_state\"");
  if (c.interface.load_pulse_amplitude != 0.0) refuse("interface.load_pulse_amplitude must be 0");
  if (c.loading.drive != LoadingDrive::outer_faces)
    refuse("loading.drive = \"" + std::string(kLoadingDriveNames[static_cast<int>(c.loading.drive)]) +
           "\" is not supported with a 2D interface: expected \"outer_faces\"");
  return c;
}

bool dissimilar(const SimulationConfig& c) { return c.bottom.body != BodyKind::mirror; }

// The time step and the bottom height the operators use.  Identical bodies:
// the 2D step at min(dx, dz).  Dissimilar ones: the antiplane operators carry
// each finite body's shear echo with an exact delay line, so it must be a
// whole number of steps (two_body_time_step; a rigid base has none).
TwoBodyTiming timing_3d(const SimulationConfig& c) {
  const auto grid = interface_grid(c);
  const double dx_min = std::min(grid.length_x / grid.nodes_x, grid.length_z / grid.nodes_z);
  if (c.bottom.body == BodyKind::elastic)
    return two_body_time_step(c.material, c.geometry.height, bottom_material(c), c.bottom.height, dx_min,
                              c.time.beta);
  const double dt = strip_time_step(c.material, c.geometry.height, dx_min, c.time.beta);
  const double bottom = c.bottom.body == BodyKind::rigid ? std::numeric_limits<double>::quiet_NaN()
                                                          : c.geometry.height;
  return TwoBodyTiming{dt, c.geometry.height, bottom, 0.0};
}

// A half-space body's 2x2 operator exists only while c_s |k| dt stays below a
// limit set by its Poisson ratio, at the grid's largest |k| (hypot(pi/dx,
// pi/dz) on even grids): the refusal names the failing body and the bound on
// time.beta it implies (solver/half_space_time_step.hpp).  The failing body is
// the first half-space one whose mode at |k|_max, designed alone, has no
// passive correction (the one the bound is computed for).  Otherwise (the
// operator failed at a smaller |k|, or on another process: failed_h = 0) the
// bound follows from the c_s |k| dt that failed (failed_h, else each body's at
// |k|_max), the smallest over the half-space bodies.
std::string half_space_time_step_error(const SimulationConfig& config, double time_step, double failed_h) {
  double k_max = 0.0;
  for (double k : interface_wavevectors(interface_grid(config)).magnitude) k_max = std::max(k_max, k);
  struct Body {
    const char* name;
    ElasticMaterial material;
    double height;
  };
  std::vector<Body> bodies{{"top", config.material, config.geometry.height}};
  if (config.bottom.body == BodyKind::elastic)
    bodies.push_back({"bottom", bottom_material(config), config.bottom.height});
  std::erase_if(bodies, [](const Body& b) { return !is_half_space(b.height); });
  for (Body& b : bodies) b.material.plane = PlaneCondition::strain;  // as build_pair's 2x2 operators
  for (const Body& b : bodies) {
    const double h_max = b.material.shear_wave_speed() * k_max * time_step;
    if (face_half_space_mode_passive(1.0 / b.material.wave_speed_ratio_squared(), HalfSpaceOperatorDesign{}, h_max))
      continue;
    return half_space_time_step_message(config.time.beta, b.name, b.material, k_max,
                                        half_space_time_step_bound(b.material, k_max, time_step, config.time.beta),
                                        true);
  }
  double beta_max = config.time.beta;
  for (const Body& b : bodies) {
    const double h_max = b.material.shear_wave_speed() * k_max * time_step;
    const double failed = failed_h > 0.0 && failed_h <= h_max ? failed_h : h_max;
    beta_max = std::min(beta_max,
                        half_space_time_step_bound(b.material, k_max, time_step, config.time.beta, failed).beta_max);
  }
  std::ostringstream msg;
  msg << "time.beta = " << config.time.beta
      << " is too large for a half-space body's passive 2x2 operator on this 2D interface";
  if (failed_h > 0.0) msg << " (it has none at c_s |k| dt = " << std::setprecision(4) << failed_h << ")";
  msg << ": expected time.beta <= " << std::setprecision(4) << beta_max << " (docs/3d.md)";
  return msg.str();
}

}  // namespace

InterfaceHistory2d interface_pair_history(const SimulationConfig& config, double time_step,
                                          const CancelCheck& cancelled, const InterfaceModeSet& modes,
                                          const InterfaceHistory2d::StripOperatorFactory& strip_operator,
                                          const InterfaceHistory2d::PairPart& part) {
  const InterfaceBody top{config.material, config.geometry.height, config.top.outer_face};
  std::optional<InterfaceBody> bottom;
  if (config.bottom.body == BodyKind::elastic)
    bottom = InterfaceBody{bottom_material(config), timing_3d(config).bottom_height, config.bottom.outer_face};
  try {
    return InterfaceHistory2d::build_pair(top, bottom, interface_grid(config), modes, time_step, cancelled,
                                          strip_operator, part);
  } catch (const FaceHalfSpaceNotPassive& e) {
    throw std::invalid_argument(half_space_time_step_error(config, time_step, e.h));
  }
}

namespace {

// One process: RealFft2d and the operator over every mode.
class SerialSpectralStep final : public InterfaceSpectralStep {
 public:
  SerialSpectralStep(const SimulationConfig& config, double time_step, const CancelCheck& cancelled)
      : history_(build_history(config, time_step, cancelled)),
        fft_(config.geometry.nodes, config.geometry.nodes_z),
        spectrum_x_(fft_.modes()), spectrum_z_(fft_.modes()) {
    if (history_.variable_normal_stress()) {
      spectrum_opening_.assign(fft_.modes(), 0.0);
      spectrum_normal_.assign(fft_.modes(), 0.0);
    }
  }

  InterfaceSlab slab() const override { return {0, fft_.nodes_z()}; }
  void history(std::span<const double> rate_x, std::span<const double> rate_z, std::span<double> history_x,
               std::span<double> history_z) override {
    transform_push_invert(fft_, history_, spectrum_x_, spectrum_z_, rate_x, rate_z, history_x, history_z);
  }
  bool variable_normal_stress() const override { return history_.variable_normal_stress(); }
  void history(std::span<const double> rate_x, std::span<const double> rate_z,
               std::span<const double> opening_stress, std::span<double> history_x, std::span<double> history_z,
               std::span<double> normal_stress) override {
    transform_push_invert(fft_, history_, spectrum_x_, spectrum_z_, spectrum_opening_, spectrum_normal_, rate_x,
                          rate_z, opening_stress, history_x, history_z, normal_stress);
  }
  const InterfaceHistory2d& history_operator() const override { return history_; }
  InterfaceHistory2d& history_operator() override { return history_; }
  double sum(double local) const override { return local; }
  double max(double local) const override { return local; }

 private:
  static InterfaceHistory2d build_history(const SimulationConfig& config, double time_step,
                                          const CancelCheck& cancelled) {
    const auto strip_operator = [&](const ElasticMaterial& body, const StripKernels& kernels) {
      return make_strip_history(body, kernels, config.time.history, cancelled);
    };
    if (!dissimilar(config))
      return InterfaceHistory2d::build(config.material, config.geometry.height, interface_grid(config), time_step,
                                       cancelled, strip_operator);
    return interface_pair_history(config, time_step, cancelled, interface_modes_all(interface_grid(config)),
                                  strip_operator, {});
  }

  InterfaceHistory2d history_;
  RealFft2d fft_;
  std::vector<std::complex<double>> spectrum_x_, spectrum_z_, spectrum_opening_, spectrum_normal_;
};

}  // namespace

void InterfaceSpectralStep::history(std::span<const double>, std::span<const double>, std::span<const double>,
                                    std::span<double>, std::span<double>, std::span<double>) {
  throw std::logic_error("InterfaceSpectralStep: this spectral step carries no normal stress");
}

std::unique_ptr<InterfaceSpectralStep> serial_spectral_step(const SimulationConfig& config, double time_step,
                                                           const CancelCheck& cancelled) {
  return std::make_unique<SerialSpectralStep>(config, time_step, cancelled);
}

Simulation3d::Simulation3d(const SimulationConfig& config, const CancelCheck& cancelled)
    : Simulation3d(config, {}, cancelled) {}

Simulation3d::Simulation3d(const SimulationConfig& config, std::span<const double> initial_state,
                           const CancelCheck& cancelled, const SpectralStepFactory& spectral)
    : config_(checked_3d(config)), nodes_x_(config.geometry.nodes), nodes_z_(config.geometry.nodes_z),
      dx_(config.geometry.length / config.geometry.nodes), dz_(config.geometry.width / config.geometry.nodes_z),
      dt_(timing_3d(config).time_step), eta_(config.material.radiation_damping()),
      v0_(config.loading.driving_velocity),
      bottom_height_used_(timing_3d(config).bottom_height),
      local_(config.friction, config.loading.normal_stress, eta_),
      spectral_(spectral ? spectral(config_, dt_, cancelled) : serial_spectral_step(config_, dt_, cancelled)) {
  if (dissimilar(config_)) {
    if (!spectral_->variable_normal_stress())
      throw std::invalid_argument(
          "bottom.body = \"" + std::string(kBodyKindNames[static_cast<int>(config_.bottom.body)]) +
          "\" is not allowed with this spectral step (it carries no normal stress): expected \"mirror\"");
    // The pair's instantaneous response (kernels/inplane_pair_history.hpp).
    eta_ = spectral_->history_operator().radiation_damping();
    local_ = LocalSolveParameters(config_.friction, config_.loading.normal_stress, eta_);
  }
  const InterfaceSlab slab = spectral_->slab();
  if (slab.first_row < 0 || slab.rows < 1 || slab.first_row + slab.rows > nodes_z_)
    throw std::invalid_argument("Simulation3d: rows " + std::to_string(slab.first_row) + " + " +
                                std::to_string(slab.rows) + " outside the interface's " + std::to_string(nodes_z_));
  const std::size_t n = static_cast<std::size_t>(nodes_x_) * slab.rows;
  for (auto* v : {&slip_x_, &slip_z_, &slip_rate_x_, &slip_rate_z_, &state_, &shear_stress_x_,
                  &shear_stress_z_, &speed_, &previous_speed_, &previous_state_, &previous_rate_x_,
                  &previous_rate_z_, &load_x_, &load_z_, &load_magnitude_, &rate_perturbation_x_,
                  &rate_perturbation_z_, &reference_, &drive_})
    v->assign(n, 0.0);
  if (dissimilar(config_)) {
    // Steady sliding: sigma = sigma_eff = sigma0 (the history is empty).
    normal_stress_.assign(n, config_.loading.normal_stress);
    previous_normal_stress_ = effective_normal_stress_ = previous_effective_ = normal_stress_;
    gap_.assign(n, 0.0);
    opening_stress_ = opening_ = opening_rate_ = normal_perturbation_ = gap_;
  }
  // Steady sliding at v0 on the whole interface (the initial state needs it
  // everywhere), tau_0 and the drive on this process's rows.
  const std::size_t all = static_cast<std::size_t>(nodes_x_) * nodes_z_;
  const std::size_t first = static_cast<std::size_t>(nodes_x_) * slab.first_row;
  const double sigma = config_.loading.normal_stress;
  std::vector<double> phi_ss(all);
  if (config_.friction_profiles.any()) {
    const FrictionNodeValues whole = resolve_friction_nodes(config_.friction, config_.friction_profiles,
                                                            friction_node_grid(config_));
    for (std::size_t i = 0; i < all; ++i) phi_ss[i] = steady_state(friction_at_node(config_.friction, whole, i), v0_);
    const auto rows = [&](const std::vector<double>& v) {
      return std::vector<double>(v.begin() + static_cast<std::ptrdiff_t>(first),
                                 v.begin() + static_cast<std::ptrdiff_t>(first + n));
    };
    friction_nodes_ = {rows(whole.f0), rows(whole.a), rows(whole.b), rows(whole.characteristic_slip)};
    local_ = LocalSolveParameters(config_.friction, sigma, eta_,
                                  {friction_nodes_.f0, friction_nodes_.a, friction_nodes_.b,
                                   friction_nodes_.characteristic_slip});
    for (std::size_t i = 0; i < n; ++i)
      reference_[i] = frictional_strength(friction_at_node(config_.friction, friction_nodes_, i), sigma, v0_,
                                          phi_ss[first + i]);
  } else {
    // One steady state and one tau_0 for every node, computed once.
    std::fill(phi_ss.begin(), phi_ss.end(), steady_state(config_.friction, v0_));
    std::fill(reference_.begin(), reference_.end(), frictional_strength(config_.friction, sigma, v0_, phi_ss[0]));
  }
  for (std::size_t i = 0; i < n; ++i) drive_[i] = reference_[i] + eta_ * v0_;
  initialise(initial_state, phi_ss);
}

void Simulation3d::initialise(std::span<const double> initial_state, std::span<const double> steady_state_all) {
  // The whole interface's initial state, then this process's rows of it.
  const std::size_t n = static_cast<std::size_t>(nodes_x_) * nodes_z_;
  const std::size_t first = static_cast<std::size_t>(nodes_x_) * spectral_->slab().first_row;
  if (!initial_state.empty()) {
    if (initial_state.size() != n)
      throw std::invalid_argument("Simulation3d: the initial state has " + std::to_string(initial_state.size()) +
                                  " values, the interface " + std::to_string(n) + " nodes");
    std::copy_n(initial_state.begin() + first, nodes(), state_.begin());
  } else {
    // [initial] at every node from its (x, z): white noise (noise_modes = 0)
    // is drawn node by node, so it varies along z too; the sine and
    // band-limited noise are functions of x, the same on every row; the
    // Gaussian bump too unless initial.local_width_z > 0 makes it a patch.
    std::vector<double> x(n), z(n);
    for (std::size_t i = 0; i < n; ++i) {
      x[i] = static_cast<double>(i % nodes_x_) * dx_;
      z[i] = static_cast<double>(i / nodes_x_) * dz_;
    }
    const std::vector<double> phi = perturbed_steady_state(config_.initial, x, z, config_.geometry.length,
                                                           config_.geometry.width, steady_state_all);
    std::copy_n(phi.begin() + first, nodes(), state_.begin());
  }
  // t = 0: no history; tau_h = tau_0 + eta v0 along x.
  std::copy(drive_.begin(), drive_.end(), load_x_.begin());
  std::fill(load_z_.begin(), load_z_.end(), 0.0);
  for (std::size_t i = 0; i < nodes(); ++i)
    load_magnitude_[i] = std::sqrt(load_x_[i] * load_x_[i] + load_z_[i] * load_z_[i]);
  solve(/*initial=*/true);
  check_finite("initial fields");
}

// load_magnitude_ = |tau_h| at every node, set by the caller with the load.
void Simulation3d::solve(bool initial) {
  if (variable_normal_stress()) {
    solve_with_normal_stress(initial);
    directions();
    return;
  }
  try {
    if (initial) {
      std::fill(speed_.begin(), speed_.end(), v0_);  // the guess
      solve_slip_rate_parallel(local_, load_magnitude_, state_, speed_, speed_);
    } else {
      predictor_corrector_parallel(local_, dt_, load_magnitude_, previous_speed_, previous_state_, speed_, state_);
    }
  } catch (const BatchFailure& e) {
    std::ostringstream msg;
    msg << "local friction solve failed at node (ix, iz) = (" << e.index % nodes_x_ << ", "
        << e.index / nodes_x_ + spectral_->slab().first_row << "), t = " << time_ << " s, step " << step_index_ << ": " << e.what();
    throw SimulationError(msg.str());
  }
  directions();
}

void Simulation3d::directions() {
  const std::size_t n = nodes();
  for_each_node(n, [&](std::size_t i) {
    // v parallel to the load; a load of zero has no direction and sticks.
    const double m = load_magnitude_[i];
    const double along_x = m > 0.0 ? load_x_[i] / m : 0.0, along_z = m > 0.0 ? load_z_[i] / m : 0.0;
    slip_rate_x_[i] = speed_[i] * along_x;
    slip_rate_z_[i] = speed_[i] * along_z;
    shear_stress_x_[i] = load_x_[i] - eta_ * slip_rate_x_[i];
    shear_stress_z_[i] = load_z_[i] - eta_ * slip_rate_z_[i];
  });
}

// The batch predictor-corrector with a normal stress per node
// (friction/batch_solve.hpp), as the 1D pair's law runs it on the signed slip
// rate (laws/law_rate_and_state.cpp), here on the magnitudes:
// |tau_h| - eta |v| = sigma_eff f(|v|, phi), each node with its own sigma_eff and
// its own friction parameters (local_.per_node with [friction] profiles).
void Simulation3d::solve_with_normal_stress(bool initial) {
  const auto& in = config_.interface;
  // L_sigma: interface.normal_stress_slip, or friction.characteristic_slip
  // (a number: a profiled one with neither memory key is refused,
  // config/config_schema.cpp).
  const NormalStressMemory memory{
      in.normal_stress_time, in.normal_stress_slip > 0.0 ? in.normal_stress_slip : config_.friction.characteristic_slip,
      config_.friction.v_star};
  LocalSolveParameters params = local_;
  try {
    if (initial) {
      std::copy(normal_stress_.begin(), normal_stress_.end(), effective_normal_stress_.begin());
      params.normal_stress_per_node = normal_stress_;
      std::fill(speed_.begin(), speed_.end(), v0_);  // the guess
      solve_slip_rate_parallel(params, load_magnitude_, state_, speed_, speed_);
    } else {
      // sigma_eff at t_n, kept while the step writes the new level in place.
      std::copy(effective_normal_stress_.begin(), effective_normal_stress_.end(), previous_effective_.begin());
      const NormalStressStep normal{previous_normal_stress_, normal_stress_, previous_effective_,
                                    effective_normal_stress_};
      predictor_corrector_normal_stress_parallel(params, memory, dt_, load_magnitude_, previous_speed_,
                                                 previous_state_, normal, speed_, state_);
    }
  } catch (const BatchFailure& e) {
    std::ostringstream msg;
    msg << "local friction solve failed at node (ix, iz) = (" << e.index % nodes_x_ << ", "
        << e.index / nodes_x_ + spectral_->slab().first_row << "), t = " << time_ << " s, step " << step_index_
        << ": " << e.what();
    throw SimulationError(msg.str());
  }
}

// The normal stress at t_{n+1} and the contact step per node, as the 1D pair's
// (Simulation::update_normal_stress): where the contact normal stress would not
// be compressive the faces open, or with interface.opening = "stop" the run
// stops naming the node.
void Simulation3d::update_normal_stress() {
  const std::size_t n = nodes();
  std::copy(normal_stress_.begin(), normal_stress_.end(), previous_normal_stress_.begin());
  const double sigma0 = config_.loading.normal_stress;
  const double eta_y = spectral_->history_operator().normal_radiation_damping();
  const bool stop = config_.interface.opening == OpeningResponse::stop;
  any_opening_stress_ = false;
  for (std::size_t i = 0; i < n; ++i) {
    const double contact = sigma0 + normal_perturbation_[i];
    if ((stop && !(contact > 0.0)) || !std::isfinite(contact)) {
      std::ostringstream msg;
      msg << (std::isfinite(contact) ? "interface opening" : "non-finite normal stress") << " at node (ix, iz) = ("
          << i % nodes_x_ << ", " << i / nodes_x_ + spectral_->slab().first_row << "), t = " << time_ + dt_
          << " s, step " << step_index_ + 1 << ": the compressive normal stress would be " << contact
          << " Pa (loading.normal_stress = " << sigma0 << " Pa)";
      if (std::isfinite(contact))
        msg << "; interface.opening = \"stop\" ends the run here (\"open\" lets the faces separate; docs/bodies.md)";
      throw SimulationError(msg.str());
    }
    const bool opening = contact_step(i, contact, eta_y, dt_, normal_stress_, opening_stress_, gap_);
    any_opening_stress_ = any_opening_stress_ || opening;
  }
  update_opening_outputs();
}

void Simulation3d::update_opening_outputs() {
  const double eta_y = spectral_->history_operator().normal_radiation_damping();
  for (std::size_t i = 0; i < nodes(); ++i) {
    opening_rate_[i] = opening_stress_[i] / eta_y;
    opening_[i] = reported_gap(normal_stress_[i], gap_[i], opening_rate_[i], dt_);
  }
}

void Simulation3d::step() {
  const std::size_t n = nodes();
  // History at t_{n+1} from the slip-rate perturbations up to t_n; the first
  // sample enters at half weight, as in the 2D solver (solver/simulation.cpp).
  const double first_sample_weight = step_index_ == 0 ? 0.5 : 1.0;
  for_each_node(n, [&](std::size_t i) {
    rate_perturbation_x_[i] = first_sample_weight * (slip_rate_x_[i] - v0_);
    rate_perturbation_z_[i] = first_sample_weight * slip_rate_z_[i];
  });
  if (variable_normal_stress()) {
    // Some node open or closing at t_n: its faces move apart (docs/bodies.md §4).
    spectral_->history(rate_perturbation_x_, rate_perturbation_z_,
                       any_opening_stress_ ? std::span<const double>(opening_stress_) : std::span<const double>(),
                       load_x_, load_z_, normal_perturbation_);
    update_normal_stress();
  } else {
    spectral_->history(rate_perturbation_x_, rate_perturbation_z_, load_x_, load_z_);
  }
  // The step's slip rate at t_n, as the friction step sees it: the slip-rate
  // vector at t_n projected on the new load direction, signed.  The scheme
  // averages it with the new speed, so where the slip rate reverses within a
  // step the state and sigma_eff advance with |v_n + v_{n+1}|/2, as the 1D
  // solver's signed slip rate does (an average of the magnitudes would carry a
  // node that stops and turns back at full speed through the step).  For a
  // direction that turns smoothly the projection differs from |v_n| at second
  // order in the turn per step, within the scheme's local error.  A node
  // without load keeps its speed: it has no new direction.  The unit vector is
  // formed as directions() forms it, so that a load along x projects exactly
  // (v * 1, not v * tau / tau) and a field independent of z keeps the 1D
  // arithmetic.  One pass for the load, its direction and the copies of t_n
  // (the loop is bound by memory traffic).
  for_each_node(n, [&](std::size_t i) {
    const double lx = drive_[i] - load_x_[i], lz = -load_z_[i];
    load_x_[i] = lx;
    load_z_[i] = lz;
    const double m = std::sqrt(lx * lx + lz * lz);
    load_magnitude_[i] = m;
    previous_speed_[i] = m > 0.0 ? slip_rate_x_[i] * (lx / m) + slip_rate_z_[i] * (lz / m) : speed_[i];
    previous_state_[i] = state_[i];
    previous_rate_x_[i] = slip_rate_x_[i];
    previous_rate_z_[i] = slip_rate_z_[i];
  });
  solve(/*initial=*/false);
  for_each_node(n, [&](std::size_t i) {
    slip_x_[i] += 0.5 * dt_ * (previous_rate_x_[i] + slip_rate_x_[i]);
    slip_z_[i] += 0.5 * dt_ * (previous_rate_z_[i] + slip_rate_z_[i]);
  });
  time_ += dt_;
  ++step_index_;
  check_finite("interface fields");
}

void Simulation3d::check_finite(const char* what) const {
  const std::size_t n = nodes();
  const bool normal = variable_normal_stress();
  const auto finite_at = [&](std::size_t i) {
    return std::isfinite(speed_[i]) && std::isfinite(state_[i]) && std::isfinite(slip_x_[i]) &&
           std::isfinite(slip_z_[i]) && std::isfinite(shear_stress_x_[i]) && std::isfinite(shear_stress_z_[i]) &&
           (!normal || std::isfinite(effective_normal_stress_[i]));
  };
  // Every step checks every node: in parallel, and the first bad node is
  // looked for (serially, for a message that does not depend on the thread
  // count) only when there is one.
  constexpr std::size_t shares = 16;
  std::array<bool, shares> share_finite;
  share_finite.fill(true);
  const std::size_t share = (n + shares - 1) / shares;
  const auto check_share = [&](std::size_t k) {
    for (std::size_t i = k * share; i < std::min(n, (k + 1) * share); ++i)
      if (!finite_at(i)) {
        share_finite[k] = false;
        return;
      }
  };
  if (n < parallel_nodes) {
    for (std::size_t k = 0; k < shares; ++k) check_share(k);
  } else {
    simd::parallel_for(static_cast<long long>(shares), [&](long long k) { check_share(static_cast<std::size_t>(k)); });
  }
  if (std::all_of(share_finite.begin(), share_finite.end(), [](bool b) { return b; })) return;
  for (std::size_t i = 0; i < n; ++i) {
    if (finite_at(i)) continue;
    std::ostringstream msg;
    msg << "non-finite " << what << " at node (ix, iz) = (" << i % nodes_x_ << ", "
        << i / nodes_x_ + spectral_->slab().first_row << "), t = " << time_ << " s, step " << step_index_ << ": slip_rate = (" << slip_rate_x_[i] << ", "
        << slip_rate_z_[i] << ") m/s, state = " << state_[i] << " s";
    throw SimulationError(msg.str());
  }
}

SimulationState Simulation3d::save_state() const {
  SimulationState saved;
  saved.time = time_;
  saved.step_index = step_index_;
  saved.slip = slip_x_;
  saved.slip_rate = slip_rate_x_;
  saved.state = state_;
  saved.shear_stress = shear_stress_x_;
  saved.slip_z = slip_z_;
  saved.slip_rate_z = slip_rate_z_;
  saved.shear_stress_z = shear_stress_z_;
  saved.speed = speed_;
  saved.normal_stress = normal_stress_;
  saved.effective_normal_stress = effective_normal_stress_;
  saved.gap = gap_;
  saved.opening_stress = opening_stress_;
  saved.history = spectral_->history_operator().save_state();
  return saved;
}

void Simulation3d::restore_state(const SimulationState& saved) {
  // Everything the next step reads: the previous-step copies and the load are
  // recomputed by step() before they are used.
  const SavedField fields[] = {{"slip", &saved.slip, &slip_x_},
                               {"slip_rate", &saved.slip_rate, &slip_rate_x_},
                               {"state", &saved.state, &state_},
                               {"shear_stress", &saved.shear_stress, &shear_stress_x_},
                               {"slip_z", &saved.slip_z, &slip_z_},
                               {"slip_rate_z", &saved.slip_rate_z, &slip_rate_z_},
                               {"shear_stress_z", &saved.shear_stress_z, &shear_stress_z_},
                               {"speed", &saved.speed, &speed_},
                               {"normal_stress", &saved.normal_stress, &normal_stress_},
                               {"effective_normal_stress", &saved.effective_normal_stress, &effective_normal_stress_},
                               {"gap", &saved.gap, &gap_},
                               {"opening_stress", &saved.opening_stress, &opening_stress_}};
  check_saved_state(fields, saved, nodes(), "saved 2D-interface state");
  // The history state of this operator, or the records of its own Fourier
  // modes cut from the whole operator's state (a restart point resumed on
  // another process count, parallel/distributed_run.cpp).
  if (saved.history.kind == InterfaceHistory2d::kModeRecordsKind)
    spectral_->history_operator().restore_mode_records(saved.history);
  else
    spectral_->history_operator().restore_state(saved.history);
  for (const auto& f : fields) std::copy(f.saved->begin(), f.saved->end(), f.target->begin());
  time_ = saved.time;
  step_index_ = saved.step_index;
  if (variable_normal_stress()) {
    any_opening_stress_ = std::any_of(opening_stress_.begin(), opening_stress_.end(),
                                      [](double d) { return d != 0.0; });
    update_opening_outputs();
  }
}

// On one process sum() and max() return their argument, so these are the
// plain sums over all nodes.
double Simulation3d::max_slip_rate() const {
  return spectral_->max(*std::max_element(speed_.begin(), speed_.end()));
}

double Simulation3d::mean_slip_x() const {
  const double nodes_total = static_cast<double>(static_cast<std::size_t>(nodes_x_) * nodes_z_);
  return spectral_->sum(std::accumulate(slip_x_.begin(), slip_x_.end(), 0.0)) / nodes_total;
}

double Simulation3d::mean_shear_stress_x() const {
  const double nodes_total = static_cast<double>(static_cast<std::size_t>(nodes_x_) * nodes_z_);
  return spectral_->sum(std::accumulate(shear_stress_x_.begin(), shear_stress_x_.end(), 0.0)) / nodes_total;
}

}  // namespace slipstrip

