#include "kernels/two_body_history.hpp"

#include "kernels/block_strip_history.hpp"
#include "kernels/half_space_history.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

namespace slipstrip {

TwoBodyHistory::TwoBodyHistory(std::unique_ptr<HistoryOperator> top,
                               std::unique_ptr<HistoryOperator> bottom)
    : top_(std::move(top)), bottom_(std::move(bottom)) {
  if (!top_) throw std::invalid_argument("TwoBodyHistory: the top body needs an operator");
  if (bottom_ && (bottom_->modes() != top_->modes() || bottom_->time_step() != top_->time_step()))
    throw std::invalid_argument("TwoBodyHistory: the two body operators differ in modes or time step");
  eta_top_ = 2.0 * top_->radiation_damping();
  eta_bottom_ = bottom_ ? 2.0 * bottom_->radiation_damping() : std::numeric_limits<double>::infinity();
  eta_ = bottom_ ? eta_top_ * eta_bottom_ / (eta_top_ + eta_bottom_) : eta_top_;
  const auto n = static_cast<std::size_t>(top_->modes());
  input_top_.assign(n, 0.0);
  input_bottom_.assign(bottom_ ? n : 0, 0.0);
  history_.assign(n, 0.0);
}

namespace {
int operator_period(const HistoryOperator* op) {
  if (const auto* block = dynamic_cast<const BlockStripHistory*>(op)) return block->block();
  if (const auto* half_space = dynamic_cast<const HalfSpaceHistory*>(op)) return half_space->period();
  return 1;
}
}  // namespace

int TwoBodyHistory::period() const { return std::max(operator_period(top_.get()), operator_period(bottom_.get())); }

ModeOperatorStats TwoBodyHistory::stats() const {
  ModeOperatorStats s = top_->stats();
  if (bottom_) {
    const ModeOperatorStats b = bottom_->stats();
    s.oscillators += b.oscillators;
    s.echo_steps = std::max(s.echo_steps, b.echo_steps);
    s.direct_lags += b.direct_lags;
    s.memory_bytes += b.memory_bytes;
  }
  s.memory_bytes += sizeof(std::complex<double>) * (input_top_.size() + input_bottom_.size() + history_.size());
  return s;
}

void TwoBodyHistory::push(std::span<const std::complex<double>> slip_rate_spectrum) {
  const std::size_t n = history_.size();
  if (!bottom_) {
    // Rigid bottom: the top body's face carries the whole slip.
    for (std::size_t q = 0; q < n; ++q) input_top_[q] = 2.0 * slip_rate_spectrum[q];
    top_->push(input_top_);
    const auto h_top = top_->history();
    std::copy(h_top.begin(), h_top.end(), history_.begin());
    return;
  }
  {
    // Face velocities at t_n from the slip rate and the body histories at t_n
    // (what the operators hold since their last push).
    const auto h_top = top_->history(), h_bottom = bottom_->history();
    const double top_share = eta_ / eta_top_, bottom_share = eta_ / eta_bottom_;
    for (std::size_t q = 0; q < n; ++q) {
      const std::complex<double> both = h_top[q] + h_bottom[q];
      const std::complex<double> v = slip_rate_spectrum[q];
      input_top_[q] = 2.0 * top_share * (v - both / eta_bottom_);
      input_bottom_[q] = -2.0 * bottom_share * (v + both / eta_top_);
    }
  }
  top_->push(input_top_);
  bottom_->push(input_bottom_);
  const auto h_top = top_->history(), h_bottom = bottom_->history();
  for (std::size_t q = 0; q < n; ++q) history_[q] = eta_ * (h_top[q] / eta_top_ - h_bottom[q] / eta_bottom_);
}

namespace {
constexpr const char* kKind = "two bodies";

// Which operator wrote a body's part of a restart point, from an array only
// that operator writes ("" when none is there: a missing array is then named
// by the part's own restore).
std::string saved_body_kind(const HistoryOperatorState& state, const std::string& prefix) {
  const auto has = [&](const char* name) { return state.has(prefix + name); };
  if (has("mode_state")) return "block strip";
  if (has("ring")) return "half-space";
  if (has("c_re")) return "modal strip";
  return "";
}

// The part of body `which` restored into `body`, refused naming both
// operators when another one wrote it (a restart point of a version, or a
// time.history, that chose the other algorithm).
void restore_body(const HistoryOperatorState& state, const std::string& prefix, HistoryOperator& body,
                  const char* which) {
  const std::string kind = body.save_state().kind;
  const std::string saved = saved_body_kind(state, prefix);
  if (!saved.empty() && saved != kind)
    throw std::invalid_argument(std::string("history operator state 'two bodies': the ") + which +
                                " body's part was written by the " + saved + " operator, this run builds the " +
                                kind +
                                " one (a restart point of another slipstrip version); resume it with the "
                                "version that wrote it, or rerun from the start");
  body.restore_state(state.part(prefix, kind));
}

}  // namespace

HistoryOperatorState TwoBodyHistory::save_state() const {
  HistoryOperatorState state;
  state.kind = kKind;
  state.counters.emplace_back("rigid_bottom", bottom_ ? 0 : 1);
  state.add_part("top.", top_->save_state());
  if (bottom_) state.add_part("bottom.", bottom_->save_state());
  state.add("history", history_);
  return state;
}

HistoryStateLayout TwoBodyHistory::state_layout() const {
  HistoryStateLayout layout;
  layout.add_part("top.", top_->state_layout());
  if (bottom_) layout.add_part("bottom.", bottom_->state_layout());
  layout.add_uniform("history", history_.size(), 2);
  return layout;
}

void TwoBodyHistory::restore_state(const HistoryOperatorState& state) {
  if (state.kind == "half-space")
    throw std::invalid_argument("history operator state: the restart point holds one half-space operator (an "
                                "antiplane pair's combined one, time.antiplane_pair = \"combined\"), this run "
                                "the two bodies' operators; resume it with the setting that wrote it");
  state.require_kind(kKind);
  if (state.counter("rigid_bottom") != (bottom_ ? 0 : 1))
    throw std::invalid_argument("history operator state: the restart point's bottom body is " +
                                std::string(bottom_ ? "rigid" : "elastic") + ", this run's is not");
  // Each part checks its arrays and counters (a block operator its B).
  restore_body(state, "top.", *top_, "top");
  if (bottom_) restore_body(state, "bottom.", *bottom_, "bottom");
  state.copy_to("history", std::span<std::complex<double>>(history_));
}

TwoBodyTiming two_body_time_step(const ElasticMaterial& top, double top_height,
                                 const ElasticMaterial& bottom, double bottom_height, double dx,
                                 double beta, double max_relative_height_change) {
  const double c_top = top.shear_wave_speed(), c_bottom = bottom.shear_wave_speed();
  const double dt_max = beta * dx / std::max(c_top, c_bottom);
  TwoBodyTiming timing{dt_max, top_height, bottom_height, 0.0};
  const bool top_finite = !is_half_space(top_height), bottom_finite = !is_half_space(bottom_height);
  auto whole_steps = [&](double echo) { return std::ceil(echo / dt_max * (1.0 - 1e-12)); };
  if (!top_finite && !bottom_finite) return timing;
  if (top_finite != bottom_finite) {
    const double echo = top_finite ? 2.0 * top_height / c_top : 2.0 * bottom_height / c_bottom;
    timing.time_step = echo / whole_steps(echo);
    return timing;
  }
  const double echo_top = 2.0 * top_height / c_top, echo_bottom = 2.0 * bottom_height / c_bottom;
  const double first = whole_steps(echo_top);
  const double candidates = std::max(16.0, std::floor(first / 16.0));
  double best_change = std::numeric_limits<double>::infinity();
  for (double m = first; m < first + candidates; m += 1.0) {
    const double dt = echo_top / m;
    const double m_bottom = std::max(1.0, std::round(echo_bottom / dt));
    const double change = std::abs(m_bottom * dt - echo_bottom) / echo_bottom;
    if (change < best_change) {
      best_change = change;
      timing.time_step = dt;
      timing.bottom_height = bottom_height * (m_bottom * dt / echo_bottom);
      timing.bottom_height_change = (m_bottom * dt - echo_bottom) / echo_bottom;
    }
    if (change == 0.0) break;
  }
  if (best_change > max_relative_height_change) {
    std::ostringstream msg;
    msg << "bottom.height = " << bottom_height << " m: its shear echo 2H/c_s = " << echo_bottom
        << " s is not a whole number of time steps (dt <= " << dt_max << " s) to within "
        << max_relative_height_change << " relative (best " << best_change
        << "); lower time.beta or choose heights with commensurate echo times";
    throw std::invalid_argument(msg.str());
  }
  // Exactly commensurate: keep the given height bit for bit.
  if (best_change == 0.0) timing.bottom_height = bottom_height;
  return timing;
}

}  // namespace slipstrip
