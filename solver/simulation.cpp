#include "solver/simulation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <sstream>
#include <string>

#include "kernels/antiplane_pair_modes.hpp"
#include "kernels/block_strip_history.hpp"
#include "kernels/half_space_history.hpp"
#include "kernels/kernel_cache.hpp"
#include "kernels/face_block_history.hpp"
#include "kernels/face_history.hpp"
#include "kernels/face_half_space.hpp"
#include "kernels/inplane_pair_history.hpp"
#include "kernels/two_body_history.hpp"
#include "solver/half_space_time_step.hpp"
#include "solver/interface_contact.hpp"

namespace slipstrip {
// Both algorithms apply the same discrete operator (to ~1e-13,
// tests/cpp/test_kernels_block_history.cpp); the block one wins once a
// Fourier mode carries more than ~100 normal modes (bench_kernels_history:
// 1.8x faster at 150 modes per Fourier mode, 55x at 6000) but needs ~2-3x the
// memory, so below that the modal one is kept.
std::size_t most_normal_modes(const StripKernels& kernels) {
  std::size_t most = 0;
  for (std::size_t q = 0; q + 1 < kernels.first_oscillator.size(); ++q)
    most = std::max(most, kernels.first_oscillator[q + 1] - kernels.first_oscillator[q]);
  return most;
}

std::unique_ptr<HistoryOperator> make_strip_history(const ElasticMaterial& material,
                                                    const StripKernels& kernels,
                                                    HistoryAlgorithm algorithm,
                                                    const CancelCheck& cancelled,
                                                    std::size_t most_normal_modes_override, int block) {
  return make_strip_history(identical_strip_pair(material, kernels.echo_steps), kernels, algorithm, cancelled,
                            most_normal_modes_override, block);
}

std::unique_ptr<HistoryOperator> make_strip_history(const StripPairConstants& constants,
                                                    const StripKernels& kernels,
                                                    HistoryAlgorithm algorithm,
                                                    const CancelCheck& cancelled,
                                                    std::size_t most_normal_modes_override, int block) {
  const std::size_t most =
      most_normal_modes_override > 0 ? most_normal_modes_override : most_normal_modes(kernels);
  if (algorithm == HistoryAlgorithm::automatic)
    algorithm = most >= kBlockHistoryThreshold ? HistoryAlgorithm::block : HistoryAlgorithm::modal;
  if (algorithm == HistoryAlgorithm::block) {
    BlockHistoryDesign design;
    if (most_normal_modes_override > 0) design.block = automatic_block_length(most, design.direct_block);
    if (block > 0) design.block = block;
    return std::make_unique<BlockStripHistory>(constants, kernels, design, cancelled);
  }
  return std::make_unique<StripHistory>(constants, kernels, cancelled);
}

namespace {
// One finite body's 2x2 operator in an in-plane pair of different bodies:
// modal or block (the same operator, tests/cpp/test_kernels_face_block_history.cpp),
// chosen by time.history as for the identical pair; `auto` counts the normal
// modes of the uniform mode, which has the most.
std::unique_ptr<FaceHistory> make_finite_body_history(const SimulationConfig& config, const ElasticMaterial& m,
                                                      double height, OuterFace face, double time_step,
                                                      const CancelCheck& cancelled) {
  const auto& g = config.geometry;
  HistoryAlgorithm algorithm = config.time.history;
  const std::size_t most = face_discrete_modes(m, height, face, 0.0, time_step).phase.size();
  if (algorithm == HistoryAlgorithm::automatic)
    algorithm = most >= kBlockHistoryThreshold ? HistoryAlgorithm::block : HistoryAlgorithm::modal;
  if (algorithm == HistoryAlgorithm::block) {
    FaceBlockDesign design;
    design.block = face_block_length(most, design.direct_block, static_cast<std::size_t>(g.nodes / 2 + 1));
    return std::make_unique<FaceBlockHistory>(m, height, face, g.length, g.nodes, time_step, design, cancelled);
  }
  return std::make_unique<FaceModalHistory>(m, height, face, g.length, g.nodes, time_step);
}

// The operator of two identical copies of one body (material, height): the
// whole history operator of a mirror pair, and each body's "pair-normalised"
// operator otherwise (kernels/two_body_history.hpp; `body_of_two`).  A body of
// two different ones takes body_block_length's B: at least 1024 (N = 2048,
// H = 0.1 m, SH: 1024 instead of the identical pair's 256; docs/performance.md).
std::unique_ptr<HistoryOperator> make_pair_history(const SimulationConfig& config,
                                                   const ElasticMaterial& material, double height,
                                                   double time_step, const CancelCheck& cancelled,
                                                   bool body_of_two = false) {
  const auto& g = config.geometry;
  const int nodes = g.nodes;
  if (is_half_space(height)) {
    // Sampled exact half-space kernel, made passive, with bounded memory
    // (kernels/half_space_history.hpp, docs/theory.md "bounded-memory half-space").
    return std::make_unique<HalfSpaceHistory>(material, g.length, nodes, time_step,
                                              HalfSpaceOperatorDesign{}, cancelled);
  }
  const auto kernels =
      config.output.kernel_cache.empty()
          ? compute_strip_kernels(material, height, g.length, nodes, time_step, cancelled)
          : load_or_compute_strip_kernels(config.output.kernel_cache, material, height, g.length,
                                          nodes, time_step, nullptr, cancelled);
  const int block = body_of_two ? body_block_length(most_normal_modes(kernels), BlockHistoryDesign{}.direct_block,
                                                    kernels.first_oscillator.size() - 1)
                                : 0;
  return make_strip_history(material, kernels, config.time.history, cancelled, 0, block);
}

// Two different finite antiplane strips: one scalar operator of the bonded
// pair (kernels/antiplane_pair_modes.hpp), modal or block by time.history as
// the identical pair.  Its B is body_block_length's: the far field's cost per
// step goes like the frequencies over B, and the pair has the normal modes of
// both bodies (docs/performance.md).
std::unique_ptr<HistoryOperator> make_antiplane_pair_history(const SimulationConfig& config,
                                                             const AntiplaneStrip& top, const AntiplaneStrip& bottom,
                                                             double time_step, const CancelCheck& cancelled) {
  const auto& g = config.geometry;
  const auto kernels = compute_antiplane_pair_kernels(top, bottom, g.length, g.nodes, time_step, cancelled);
  const int block = body_block_length(most_normal_modes(kernels), BlockHistoryDesign{}.direct_block,
                                      kernels.first_oscillator.size() - 1);
  return make_strip_history(antiplane_pair_constants(top, bottom, time_step), kernels, config.time.history,
                            cancelled, 0, block);
}
// A half-space body's 2x2 operator exists only below a c_s k dt set by its
// Poisson ratio: the refusal names the bound on time.beta it implies at the
// line's shortest wavelength, k_max = pi / dx (Nyquist).
std::string half_space_time_step_error(const SimulationConfig& config, const ElasticMaterial& m, const char* body,
                                       double dx, double dt) {
  const double k_max = std::numbers::pi / dx;
  return half_space_time_step_message(config.time.beta, body, m, k_max,
                                      half_space_time_step_bound(m, k_max, dt, config.time.beta), false);
}

}  // namespace

Simulation::Simulation(const SimulationConfig& config, const CancelCheck& cancelled,
                       const InterfaceLawRegistry& laws)
    : config_(config), nodes_(config.geometry.nodes) {
  const auto& g = config_.geometry;
  if (config_.loading.drive == LoadingDrive::mean_slip_rate) {
    // The config schema refuses these too; a config built in code reaches here.
    if (config_.bottom.body != BodyKind::mirror)
      throw std::invalid_argument("loading.drive = \"mean_slip_rate\" is not supported with bottom.body = \"" +
                                  std::string(kBodyKindNames[static_cast<int>(config_.bottom.body)]) +
                                  "\": expected bottom.body = \"mirror\" (or loading.drive = \"outer_faces\")");
    if (config_.interface.law != InterfaceLawName::rate_and_state)
      throw std::invalid_argument("loading.drive = \"mean_slip_rate\" is not supported with interface.law = \"" +
                                  std::string(config_.interface.law.name) +
                                  "\": expected interface.law = \"rate_and_state\" (or loading.drive = \"outer_faces\")");
  }
  dx_ = g.length / nodes_;
  fft_ = std::make_unique<RealFft>(nodes_);
  bottom_height_used_ = bottom_height(config_);
  const bool inplane = !config_.material.antiplane();
  if (config_.bottom.body == BodyKind::mirror) {
    // Two identical bodies: one operator of the pair (docs/theory.md).
    dt_ = strip_time_step(config_.material, g.height, dx_, config_.time.beta);
    history_ = make_pair_history(config_, config_.material, g.height, dt_, cancelled);
  } else if (inplane) {
    // In-plane dissimilar bodies: each body's 2x2 operator, combined with the
    // normal-stress coupling (kernels/inplane_pair_history.hpp).  No shear echo
    // needs a whole number of steps (the modes carry the echoes), so the step
    // follows the faster body: exactly the mirror pair's step when the top body
    // is the faster one (identical bodies step alike on both paths).
    const ElasticMaterial bottom_body = bottom_material(config_);
    const bool rigid = config_.bottom.body == BodyKind::rigid;
    const double c_top = config_.material.shear_wave_speed();
    const double c_bottom = rigid ? 0.0 : bottom_body.shear_wave_speed();
    dt_ = c_top >= c_bottom ? strip_time_step(config_.material, g.height, dx_, config_.time.beta)
                            : config_.time.beta * dx_ / c_bottom;
    if (rigid) bottom_height_used_ = std::numeric_limits<double>::quiet_NaN();
    // Two different half-spaces: one operator of the interface's jumps
    // (docs/inplane_bodies.md §7) unless time.half_space_pair = "bodies".  A
    // pair it cannot carry (a Stoneley wave, a failed set-up check, no passive
    // correction at this step) takes the bodies' operators, which carry any
    // pair or name the time step that fails.
    if (!rigid && is_half_space(g.height) && is_half_space(config_.bottom.height) &&
        config_.time.half_space_pair == HalfSpacePairOperator::combined) {
      try {
        auto pair = std::make_unique<InplanePairHistory>(
            InplanePairHistory::Combined{},
            std::make_unique<FaceHalfSpaceHistory>(config_.material, bottom_body, g.length, nodes_, dt_,
                                                   HalfSpaceOperatorDesign{}, cancelled));
        pair_ = pair.get();
        history_ = std::move(pair);
      } catch (const HalfSpacePairHasInterfaceWave&) {
      } catch (const HalfSpacePairCheckFailed&) {
      } catch (const FaceHalfSpaceNotPassive&) {
      }
      throw_if_cancelled(cancelled, "the combined half-space pair's operator");
    }
  }
  if (history_) {
    // The mirror pair's operator, or the combined operator of two half-spaces.
  } else if (inplane) {
    // Each body: its modal 2x2 operator (finite height) or the half-space's
    // (kernels/face_half_space.hpp).
    const ElasticMaterial bottom_body = bottom_material(config_);
    const bool rigid = config_.bottom.body == BodyKind::rigid;
    const auto body_operator = [&](const ElasticMaterial& m, double height, OuterFace face,
                                   const char* body) -> std::unique_ptr<FaceHistory> {
      if (is_half_space(height)) {
        try {
          return std::make_unique<FaceHalfSpaceHistory>(m, g.length, nodes_, dt_, HalfSpaceOperatorDesign{},
                                                        cancelled);
        } catch (const FaceHalfSpaceNotPassive&) {
          throw std::invalid_argument(half_space_time_step_error(config_, m, body, dx_, dt_));
        }
      }
      return make_finite_body_history(config_, m, height, face, dt_, cancelled);
    };
    auto top = body_operator(config_.material, g.height, config_.top.outer_face, "top");
    throw_if_cancelled(cancelled, "the top body's operator");
    std::unique_ptr<FaceHistory> bottom;
    if (!rigid) bottom = body_operator(bottom_body, config_.bottom.height, config_.bottom.outer_face, "bottom");
    auto pair = std::make_unique<InplanePairHistory>(std::move(top), std::move(bottom));
    pair_ = pair.get();
    history_ = std::move(pair);
  } else {
    // Antiplane: the scalar per-body combination (kernels/two_body_history.hpp).
    std::unique_ptr<HistoryOperator> bottom;
    if (config_.bottom.body == BodyKind::rigid) {
      dt_ = strip_time_step(config_.material, g.height, dx_, config_.time.beta);
      bottom_height_used_ = std::numeric_limits<double>::quiet_NaN();
    } else {
      const ElasticMaterial bottom_body = bottom_material(config_);
      const TwoBodyTiming timing = two_body_time_step(config_.material, g.height, bottom_body,
                                                      config_.bottom.height, dx_, config_.time.beta);
      dt_ = timing.time_step;
      bottom_height_used_ = timing.bottom_height;
      // Two finite strips: one operator of the pair unless time.antiplane_pair
      // = "bodies" (docs/bodies.md §3).  Two half-spaces: likewise one
      // operator of the slip rate, the combined kernel K_t K_b / (K_t + K_b)
      // (kernels/half_space_history.hpp, docs/bodies.md §3); a pair it refuses
      // (a failed set-up check, no passive correction at this step) takes the
      // bodies' operators, which carry any pair or name the time step that
      // fails.  A half-space on a finite body keeps one operator per body.
      const bool combined = config_.time.antiplane_pair == AntiplanePairOperator::combined;
      if (combined && !is_half_space(g.height) && !is_half_space(timing.bottom_height)) {
        history_ = make_antiplane_pair_history(config_, {config_.material, g.height},
                                               {bottom_body, timing.bottom_height}, dt_, cancelled);
      } else if (combined && is_half_space(g.height) && is_half_space(config_.bottom.height)) {
        try {
          history_ = std::make_unique<HalfSpaceHistory>(config_.material, bottom_body, g.length, nodes_, dt_,
                                                        HalfSpaceOperatorDesign{}, cancelled);
        } catch (const HalfSpacePairCheckFailed&) {
        } catch (const HalfSpaceNotPassive&) {
        }
        throw_if_cancelled(cancelled, "the combined antiplane half-space pair's operator");
      }
      if (!history_) bottom = make_pair_history(config_, bottom_body, timing.bottom_height, dt_, cancelled, true);
    }
    if (!history_)
      history_ = std::make_unique<TwoBodyHistory>(
          make_pair_history(config_, config_.material, g.height, dt_, cancelled, true), std::move(bottom));
  }
  // mu / (2 c_s) for identical bodies (the same expression the operators use).
  eta_ = history_->radiation_damping();

  const auto n = static_cast<std::size_t>(nodes_);
  x_.resize(n);
  for (std::size_t i = 0; i < n; ++i) x_[i] = i * dx_;
  slip_.assign(n, 0.0);
  slip_rate_.assign(n, 0.0);
  state_.assign(n, 0.0);
  shear_stress_.assign(n, 0.0);
  previous_slip_rate_.assign(n, 0.0);
  previous_state_.assign(n, 0.0);
  history_stress_.assign(n, 0.0);
  work_real_.assign(n, 0.0);
  spectrum_.assign(n / 2 + 1, 0.0);
  if (pair_) {
    // Steady sliding: sigma = sigma_eff = sigma0 (the history is empty).
    normal_stress_.assign(n, config_.loading.normal_stress);
    previous_normal_stress_ = effective_normal_stress_ = normal_stress_;
    gap_.assign(n, 0.0);
    opening_stress_ = opening_ = opening_rate_ = gap_;
    opening_spectrum_.assign(n / 2 + 1, 0.0);
  }

  law_ = laws.make(InterfaceSetup{config_, x_, eta_});
  driving_velocity_ = law_->driving_velocity();
  InterfaceFields f = fields();
  run_law([&] { law_->initialise(f); });
  check_finite("initial fields");
}

InterfaceFields Simulation::fields() {
  return InterfaceFields{x_,    history_stress_, previous_slip_rate_, previous_state_,
                         slip_, slip_rate_,      state_,              shear_stress_,
                         normal_stress_, previous_normal_stress_, effective_normal_stress_};
}

// The normal stress at t_{n+1}: the contact one from the pair operator (it has
// no instantaneous term in the slip rate), then the unilateral contact per node
// (solver/interface_contact.hpp): where it would not be compressive the faces
// open (or, with interface.opening = "stop", the run stops naming the node).
void Simulation::update_normal_stress() {
  std::copy(normal_stress_.begin(), normal_stress_.end(), previous_normal_stress_.begin());
  fft_->inverse(pair_->normal_stress(), work_real_);
  const double sigma0 = config_.loading.normal_stress;
  const double eta_y = pair_->normal_radiation_damping();
  const bool stop = config_.interface.opening == OpeningResponse::stop;
  any_opening_stress_ = false;
  for (int i = 0; i < nodes_; ++i) {
    const double contact = sigma0 + work_real_[i];
    if (stop && !(contact > 0.0)) {
      std::ostringstream msg;
      msg << "interface opening at node " << i << " (x = " << x_[i] << " m), t = " << time_ + dt_
          << " s, step " << step_index_ + 1 << ": the compressive normal stress would be " << contact
          << " Pa (loading.normal_stress = " << sigma0
          << " Pa); interface.opening = \"stop\" ends the run here (\"open\" lets the faces separate; "
             "docs/bodies.md)";
      throw SimulationError(msg.str());
    }
    if (!std::isfinite(contact)) {
      std::ostringstream msg;
      msg << "non-finite normal stress at node " << i << " (x = " << x_[i] << " m), t = " << time_ + dt_
          << " s, step " << step_index_ + 1 << ": " << contact << " Pa";
      throw SimulationError(msg.str());
    }
    const bool opening =
        contact_step(static_cast<std::size_t>(i), contact, eta_y, dt_, normal_stress_, opening_stress_, gap_);
    any_opening_stress_ = any_opening_stress_ || opening;
  }
  update_opening_outputs();
}

void Simulation::update_opening_outputs() {
  const double eta_y = pair_->normal_radiation_damping();
  for (int i = 0; i < nodes_; ++i) {
    opening_rate_[i] = opening_stress_[i] / eta_y;
    opening_[i] = reported_gap(normal_stress_[i], gap_[i], opening_rate_[i], dt_);
  }
}

int Simulation::open_nodes() const {
  return static_cast<int>(std::count(normal_stress_.begin(), normal_stress_.end(), 0.0));
}

template <class Call>
void Simulation::run_law(Call&& call) {
  try {
    call();
  } catch (const InterfaceFailure& e) {
    const std::size_t i = e.node;
    std::ostringstream msg;
    msg << e.failed;
    if (i != InterfaceFailure::kWholeInterface) msg << " at node " << i << " (x = " << x_[i] << " m)";
    msg << ", t = " << time_ << " s, step " << step_index_ << ": " << e.what();
    throw SimulationError(msg.str());
  }
}

double Simulation::reference_shear_stress() const {
  const auto tau0 = law_->reference_shear_stress();
  if (tau0.empty()) return 0.0;
  if (std::all_of(tau0.begin(), tau0.end(), [&](double t) { return t == tau0[0]; })) return tau0[0];
  return std::accumulate(tau0.begin(), tau0.end(), 0.0) / static_cast<double>(tau0.size());
}

void Simulation::step() {
  // 1. history stress at t_{n+1} from slip rates up to t_n.
  // The perturbation v - v0 is zero before t = 0 and may jump at t = 0+ (an
  // initial state perturbation changes v at once).  The trapezoidal rule over
  // the history puts weight 1/2 on that end point (equivalently: a delta of the
  // echo comb that lands on the jump samples its mean), so the first sample
  // enters the history at half weight.  Full weight costs an O(dt) error for
  // the whole run (tests/cpp/test_solver_convergence.cpp).
  const double first_sample_weight = step_index_ == 0 ? 0.5 : 1.0;
  for (int i = 0; i < nodes_; ++i)
    work_real_[i] = first_sample_weight * (slip_rate_[i] - driving_velocity_);
  fft_->forward(work_real_, spectrum_);
  // loading.drive = "mean_slip_rate": the uniform mode is not the operator's;
  // its stress is tau_0(t), solved for by the law, and its slip-rate
  // perturbation is zero to the root-find tolerance: the residual is dropped,
  // so the history has no uniform part.
  if (config_.loading.drive == LoadingDrive::mean_slip_rate) spectrum_[0] = 0.0;
  if (any_opening_stress_) {
    // Some node is open or closing at t_n: its faces move apart (docs/bodies.md §4).
    fft_->forward(opening_stress_, opening_spectrum_);
    pair_->push(spectrum_, opening_spectrum_);
  } else {
    history_->push(spectrum_);
  }
  fft_->inverse(history_->history(), history_stress_);
  if (pair_) update_normal_stress();

  std::copy(slip_rate_.begin(), slip_rate_.end(), previous_slip_rate_.begin());
  std::copy(state_.begin(), state_.end(), previous_state_.begin());
  const double t_new = time_ + dt_;

  // 2. interface law at t_{n+1}.
  InterfaceFields f = fields();
  run_law([&] { law_->advance(InterfaceStep{time_, dt_, step_index_}, f); });
  time_ = t_new;
  ++step_index_;
  check_finite("interface fields");
}

void Simulation::check_finite(const char* what) const {
  for (int i = 0; i < nodes_; ++i) {
    if (!std::isfinite(slip_rate_[i]) || !std::isfinite(slip_[i]) ||
        !std::isfinite(shear_stress_[i]) || !std::isfinite(state_[i])) {
      std::ostringstream msg;
      msg << "non-finite " << what << " at node " << i << " (x = " << x_[i] << " m), t = "
          << time_ << " s, step " << step_index_ << ": slip = " << slip_[i]
          << " m, slip_rate = " << slip_rate_[i] << " m/s, state = " << state_[i]
          << " s, shear_stress = " << shear_stress_[i] << " Pa";
      throw SimulationError(msg.str());
    }
  }
}

SimulationState Simulation::save_state() const {
  SimulationState saved;
  saved.time = time_;
  saved.step_index = step_index_;
  saved.slip = slip_;
  saved.slip_rate = slip_rate_;
  saved.state = state_;
  saved.shear_stress = shear_stress_;
  saved.history_stress = history_stress_;
  saved.normal_stress = normal_stress_;
  saved.effective_normal_stress = effective_normal_stress_;
  saved.gap = gap_;
  saved.opening_stress = opening_stress_;
  saved.history = history_->save_state();
  return saved;
}

void check_saved_state(std::span<const SavedField> fields, const SimulationState& saved, std::size_t nodes,
                       const std::string& what) {
  for (const auto& f : fields)
    if (f.saved->size() != f.target->size())
      throw std::invalid_argument(what + ": " + f.name + " has " + std::to_string(f.saved->size()) +
                                  " values, this config has " + std::to_string(nodes) + " nodes");
  if (!(saved.step_index >= 0) || !std::isfinite(saved.time))
    throw std::invalid_argument(what + ": step " + std::to_string(saved.step_index) + ", t = " +
                                std::to_string(saved.time) + " s is not a valid time level");
}

void Simulation::restore_state(const SimulationState& saved) {
  const SavedField fields[] = {{"slip", &saved.slip, &slip_},
                               {"slip_rate", &saved.slip_rate, &slip_rate_},
                               {"state", &saved.state, &state_},
                               {"shear_stress", &saved.shear_stress, &shear_stress_},
                               {"history_stress", &saved.history_stress, &history_stress_},
                               {"normal_stress", &saved.normal_stress, &normal_stress_},
                               {"effective_normal_stress", &saved.effective_normal_stress, &effective_normal_stress_},
                               {"gap", &saved.gap, &gap_},
                               {"opening_stress", &saved.opening_stress, &opening_stress_}};
  check_saved_state(fields, saved, nodes_, "saved simulation state");
  history_->restore_state(saved.history);
  for (const auto& f : fields) std::copy(f.saved->begin(), f.saved->end(), f.target->begin());
  time_ = saved.time;
  step_index_ = saved.step_index;
  if (pair_) {
    any_opening_stress_ = std::any_of(opening_stress_.begin(), opening_stress_.end(),
                                      [](double d) { return d != 0.0; });
    update_opening_outputs();
  }
}

double Simulation::max_slip_rate() const {
  return *std::max_element(slip_rate_.begin(), slip_rate_.end());
}
double Simulation::mean_slip() const {
  return std::accumulate(slip_.begin(), slip_.end(), 0.0) / nodes_;
}
double Simulation::mean_shear_stress() const {
  return std::accumulate(shear_stress_.begin(), shear_stress_.end(), 0.0) / nodes_;
}

}  // namespace slipstrip
