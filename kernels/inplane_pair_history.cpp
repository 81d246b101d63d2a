#include "kernels/inplane_pair_history.hpp"

#include <algorithm>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>

namespace slipstrip {

namespace {

// Which face operator wrote a body's part of a restart point, from an array
// only that algorithm writes ("" when none is there).  The half-space body
// stored its exponentials as complex pairs (far_x, far_conj_x, ...) before it
// advanced them as real rotations (far_c_x_re, ...): such a part cannot be
// continued by this version.
std::string saved_face_algorithm(const HistoryOperatorState& state, const std::string& prefix) {
  const auto has = [&](const char* name) { return state.has(prefix + name); };
  if (has("cx")) return "modal";
  if (has("state_x")) return "block";
  if (has("far_c_x_re")) return "half-space";
  if (has("far_x")) return "half-space (the complex layout of an older slipstrip)";
  return "";
}

void require_same_algorithm(const HistoryOperatorState& state, const std::string& prefix,
                            const FaceHistory& body, const char* which) {
  const std::string saved = saved_face_algorithm(state, prefix);
  if (saved.empty() || saved == body.algorithm()) return;  // a missing array is named by copy_to
  throw std::invalid_argument(std::string("history operator state 'in-plane pair': the ") + which +
                              " body's part was written by the " + saved + " operator, this run builds the " +
                              body.algorithm() +
                              " one (a restart point of another slipstrip version); resume it with the "
                              "version that wrote it, or rerun from the start");
}

}  // namespace

InplanePairHistory::InplanePairHistory(std::unique_ptr<FaceHistory> top, std::unique_ptr<FaceHistory> bottom)
    : top_(std::move(top)), bottom_(std::move(bottom)) {
  if (!top_) throw std::invalid_argument("InplanePairHistory: the top body needs an operator");
  if (bottom_ && (bottom_->modes() != top_->modes() || bottom_->time_step() != top_->time_step()))
    throw std::invalid_argument("InplanePairHistory: the two body operators differ in modes or time step");
  constexpr double rigid = std::numeric_limits<double>::infinity();
  ex_top_ = top_->shear_impedance();
  ey_top_ = top_->normal_impedance();
  ex_bottom_ = bottom_ ? bottom_->shear_impedance() : rigid;
  ey_bottom_ = bottom_ ? bottom_->normal_impedance() : rigid;
  eta_ = bottom_ ? ex_top_ * ex_bottom_ / (ex_top_ + ex_bottom_) : ex_top_;
  eta_y_ = bottom_ ? ey_top_ * ey_bottom_ / (ey_top_ + ey_bottom_) : ey_top_;
  const auto n = static_cast<std::size_t>(top_->modes());
  top_x_.assign(n, 0.0);
  top_y_ = history_ = normal_ = top_x_;
  bottom_x_.assign(bottom_ ? n : 0, 0.0);
  bottom_y_ = bottom_x_;
}

InplanePairHistory::InplanePairHistory(Combined, std::unique_ptr<FaceHistory> pair)
    : top_(std::move(pair)), combined_(true) {
  if (!top_) throw std::invalid_argument("InplanePairHistory: the combined pair needs an operator");
  ex_top_ = ey_top_ = ex_bottom_ = ey_bottom_ = 0.0;
  eta_ = top_->shear_impedance();
  eta_y_ = top_->normal_impedance();
  const auto n = static_cast<std::size_t>(top_->modes());
  top_x_.assign(n, 0.0);
  top_y_ = history_ = normal_ = top_x_;
}

ModeOperatorStats InplanePairHistory::stats() const {
  ModeOperatorStats s;
  s.modes = history_.size();
  s.oscillators = top_->discrete_modes() + (bottom_ ? bottom_->discrete_modes() : 0);
  s.memory_bytes = top_->memory_bytes() + (bottom_ ? bottom_->memory_bytes() : 0) +
                   sizeof(std::complex<double>) *
                       (top_x_.size() + top_y_.size() + bottom_x_.size() + bottom_y_.size() +
                        history_.size() + normal_.size());
  return s;
}

int InplanePairHistory::period() const {
  const int top = top_->period(), bottom = bottom_ ? bottom_->period() : 1;
  return std::lcm(top, bottom);
}

void InplanePairHistory::push(std::span<const std::complex<double>> slip_rate_spectrum) {
  push(slip_rate_spectrum, {});
}

void InplanePairHistory::push(std::span<const std::complex<double>> slip_rate_spectrum,
                              std::span<const std::complex<double>> opening_stress_spectrum) {
  const std::size_t n = history_.size();
  const bool opening = !opening_stress_spectrum.empty();
  if (combined_ || !bottom_) {
    // One operator fed the jumps themselves: the slip rate V and the gap rate
    // d / eta_y (0 in contact).  The combined pair's operator acts on the
    // jumps; over a rigid bottom the top face carries the whole slip and
    // opens alone (eta_y = Ey_t).
    for (std::size_t q = 0; q < n; ++q) {
      top_x_[q] = slip_rate_spectrum[q];
      top_y_[q] = opening ? opening_stress_spectrum[q] / eta_y_ : 0.0;
    }
    top_->push(top_x_, top_y_);
    const auto x = top_->history_x(), y = top_->history_y();
    for (std::size_t q = 0; q < n; ++q) {
      history_[q] = x[q];
      normal_[q] = y[q];
    }
    return;
  }
  const auto hx_t = top_->history_x(), hy_t = top_->history_y();
  {
    // Face velocities at t_n from the slip rate and the body histories at t_n.
    const auto hx_b = bottom_->history_x(), hy_b = bottom_->history_y();
    const double sum_x = ex_top_ + ex_bottom_, sum_y = ey_top_ + ey_bottom_;
    for (std::size_t q = 0; q < n; ++q) {
      const std::complex<double> v = slip_rate_spectrum[q];
      const std::complex<double> vy = -(hy_t[q] - hy_b[q]) / sum_y;
      const std::complex<double> vx_bottom = -(ex_top_ * v + hx_t[q] + hx_b[q]) / sum_x;
      top_x_[q] = vx_bottom + v;
      top_y_[q] = vy;
      bottom_x_[q] = vx_bottom;
      bottom_y_[q] = -vy;  // the bottom body's own frame
    }
    if (opening)
      for (std::size_t q = 0; q < n; ++q) {
        top_y_[q] += opening_stress_spectrum[q] / ey_top_;
        bottom_y_[q] += opening_stress_spectrum[q] / ey_bottom_;
      }
  }
  top_->push(top_x_, top_y_);
  bottom_->push(bottom_x_, bottom_y_);
  const auto x_t = top_->history_x(), y_t = top_->history_y();
  const auto x_b = bottom_->history_x(), y_b = bottom_->history_y();
  const double sum_x = ex_top_ + ex_bottom_, sum_y = ey_top_ + ey_bottom_;
  for (std::size_t q = 0; q < n; ++q) {
    history_[q] = (ex_bottom_ * x_t[q] - ex_top_ * x_b[q]) / sum_x;
    normal_[q] = (ey_bottom_ * y_t[q] + ey_top_ * y_b[q]) / sum_y;
  }
}

namespace {
constexpr const char* kKind = "in-plane pair";
}

HistoryOperatorState InplanePairHistory::save_state() const {
  HistoryOperatorState s;
  s.kind = kKind;
  if (combined_) {
    top_->save_into(s, "combined.");
    s.add("history", history_);
    s.add("normal_stress", normal_);
    return s;
  }
  top_->save_into(s, "top.");
  if (bottom_) bottom_->save_into(s, "bottom.");
  s.add("history", history_);
  s.add("normal_stress", normal_);
  return s;
}

HistoryStateLayout InplanePairHistory::state_layout() const {
  HistoryStateLayout layout;
  if (combined_) {
    top_->state_layout_into(layout, "combined.");
  } else {
    top_->state_layout_into(layout, "top.");
    if (bottom_) bottom_->state_layout_into(layout, "bottom.");
  }
  layout.add_uniform("history", history_.size(), 2);
  layout.add_uniform("normal_stress", normal_.size(), 2);
  return layout;
}

void InplanePairHistory::restore_state(const HistoryOperatorState& state) {
  state.require_kind(kKind);
  // A restart point of the two bodies' operators cannot be resumed by the
  // combined one, nor the other way round: different states.
  const bool saved_combined = !saved_face_algorithm(state, "combined.").empty();
  const bool saved_bodies = !saved_face_algorithm(state, "top.").empty();
  if (combined_ ? saved_bodies : saved_combined)
    throw std::invalid_argument(std::string("history operator state 'in-plane pair': the restart point holds ") +
                                (saved_combined ? "the combined half-space pair operator" : "the two bodies' operators") +
                                ", this run builds " +
                                (combined_ ? "the combined half-space pair operator" : "the two bodies' operators") +
                                " (time.half_space_pair); resume it with the setting that wrote it");
  if (combined_) {
    top_->restore_from(state, "combined.");
    state.copy_to("history", std::span<std::complex<double>>(history_));
    state.copy_to("normal_stress", std::span<std::complex<double>>(normal_));
    return;
  }
  require_same_algorithm(state, "top.", *top_, "top");
  if (bottom_) require_same_algorithm(state, "bottom.", *bottom_, "bottom");
  top_->restore_from(state, "top.");
  if (bottom_) bottom_->restore_from(state, "bottom.");
  state.copy_to("history", std::span<std::complex<double>>(history_));
  state.copy_to("normal_stress", std::span<std::complex<double>>(normal_));
}

}  // namespace slipstrip
