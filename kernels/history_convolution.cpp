#include "kernels/history_convolution.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <stdexcept>
#include <string>

#include "kernels/huge_pages.hpp"
#include "kernels/strip_response.hpp"
#include "simd/parallel_for.hpp"

namespace slipstrip {

std::vector<DiscreteMode> discrete_modes(const ElasticMaterial& material, double strip_height,
                                         double wavenumber, double time_step,
                                         std::size_t echo_steps) {
  const double mu = material.shear_modulus;
  const double nyquist = std::numbers::pi / time_step;
  std::vector<DiscreteMode> out;
  if (wavenumber == 0.0) return out;  // the uniform mode is the delay line alone
  // In discrete time the shear-echo delay line plus the comb modes at phases
  // 2 pi m / M (m = 1..floor(M/2), half weight at phase pi) add up to the
  // constant kernel mu/c_s, so they are carried as one running sum
  // (the "comb identity", docs/theory.md).  Their static weight is
  // (mu/H)(M-1)/2 in closed form.
  double kept = mu / strip_height * 0.5 * (static_cast<double>(echo_steps) - 1.0);
  for (const auto& m : strip_modes(material, strip_height, wavenumber, nyquist)) {
    if (m.family == ModeFamily::comb) continue;
    out.push_back({std::min(m.frequency * time_step, std::numbers::pi), m.weight, m.family});
    kept += m.weight;
  }
  // Static stiffness of everything above Nyquist (truncated pairs and P modes).
  const double truncated = strip_static_stiffness(material, strip_height, wavenumber) -
                           mu / (2.0 * strip_height) - kept;
  place_truncated_stiffness(out, truncated);
  return out;
}

void place_truncated_stiffness(std::vector<DiscreteMode>& out, double truncated) {
  if (truncated == 0.0) return;
  if (truncated < 0.0) {
    // Passive element (negative weight) at Nyquist, kernel 1 - (-1)^j: exact
    // static limit, lossless, strictly causal.
    out.push_back({std::numbers::pi, truncated, ModeFamily::shear});
    return;
  }
  // A positive truncated stiffness (the usual case: the shear/comb pairs
  // dominate) would be an active element on its own.  Absorb it into the
  // highest-frequency passive modes, keeping each weight <= 0, so that every
  // Foster coefficient of the discrete operator stays >= 0 (docs/theory.md).
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < out.size(); ++i)
    if (out[i].weight < 0.0) order.push_back(i);
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return out[a].phase > out[b].phase; });
  double remaining = truncated;
  for (std::size_t i : order) {
    const double take = std::min(remaining, -out[i].weight);
    out[i].weight += take;
    remaining -= take;
    if (remaining <= 0.0) break;
  }
  if (remaining > 1e-12 * truncated)
    throw std::runtime_error(
        "discrete_modes: cannot place the truncated static stiffness passively; "
        "refine the time step (more steps per 2H/c_s)");
}

StripPairConstants identical_strip_pair(const ElasticMaterial& material, std::size_t echo_steps) {
  const double impedance = material.shear_modulus / material.shear_wave_speed();
  return {material.radiation_damping(), impedance, echo_steps, echo_steps, impedance, impedance};
}

UniformModeEchoes::UniformModeEchoes(const StripPairConstants& c)
    : recursion_(c.top_echo_steps != c.bottom_echo_steps),
      line_(recursion_ ? 0 : c.top_echo_steps, c.running_sum_weight) {
  if (c.top_echo_steps < 1 || c.bottom_echo_steps < 1)
    throw std::invalid_argument("UniformModeEchoes: the echoes need at least one step each");
  if (!recursion_) return;
  if (!(c.top_impedance > 0.0 && c.bottom_impedance > 0.0))
    throw std::invalid_argument("UniformModeEchoes: the body impedances must be > 0");
  top_ = c.top_echo_steps;
  bottom_ = c.bottom_echo_steps;
  eta_product_ = c.top_impedance * c.bottom_impedance;
  eta_sum_ = c.top_impedance + c.bottom_impedance;
  eta_difference_ = c.bottom_impedance - c.top_impedance;
  input_.assign(top_ + bottom_, 0.0);
  output_.assign(top_ + bottom_, 0.0);
}

void UniformModeEchoes::save_counters(HistoryOperatorState& state) const {
  state.counters.emplace_back("echo_cursor", static_cast<long long>(recursion_ ? cursor_ : line_.cursor()));
}

void UniformModeEchoes::save_arrays(HistoryOperatorState& state) const {
  if (!recursion_) {
    state.add("echo_line", line_.slots());
    return;
  }
  state.add("echo_input", input_);
  state.add("echo_output", output_);
}

void UniformModeEchoes::check_cursor(const HistoryOperatorState& state) const {
  const long long cursor = state.counter("echo_cursor");
  const std::size_t length = recursion_ ? input_.size() : line_.steps();
  if (cursor < 0 || static_cast<std::size_t>(cursor) >= length)
    throw std::invalid_argument("history operator state: echo_cursor = " + std::to_string(cursor) +
                                " outside 0.." + std::to_string(length - 1));
}

void UniformModeEchoes::restore(const HistoryOperatorState& state) {
  check_cursor(state);
  const long long cursor = state.counter("echo_cursor");
  if (!recursion_) {
    state.copy_to("echo_line", line_.slots());
    line_.set_cursor(static_cast<std::size_t>(cursor));
    return;
  }
  state.copy_to("echo_input", std::span<std::complex<double>>(input_));
  state.copy_to("echo_output", std::span<std::complex<double>>(output_));
  cursor_ = static_cast<std::size_t>(cursor);
}

void UniformModeEchoes::add_layout(HistoryStateLayout& layout, std::size_t modes) const {
  if (!recursion_) {
    layout.add_first_mode("echo_line", modes, 2 * line_.steps());
    return;
  }
  layout.add_first_mode("echo_input", modes, 2 * input_.size());
  layout.add_first_mode("echo_output", modes, 2 * output_.size());
}

double strip_time_step(const ElasticMaterial& material, double strip_height, double dx,
                       double beta) {
  const double cs = material.shear_wave_speed();
  const double dt_max = beta * dx / cs;
  if (is_half_space(strip_height)) return dt_max;
  const double echo_time = 2.0 * strip_height / cs;
  const double steps = std::ceil(echo_time / dt_max * (1.0 - 1e-12));
  return echo_time / steps;
}

StripKernels compute_strip_kernels(const ElasticMaterial& material, double strip_height,
                                   double length, int nodes, double time_step,
                                   const CancelCheck& cancelled) {
  std::vector<double> wavenumbers(static_cast<std::size_t>(nodes / 2 + 1));
  for (std::size_t q = 0; q < wavenumbers.size(); ++q)
    wavenumbers[q] = 2.0 * std::numbers::pi * static_cast<double>(q) / length;
  return compute_strip_kernels(material, strip_height, wavenumbers, time_step, cancelled);
}

StripKernels compute_strip_kernels(const ElasticMaterial& material, double strip_height,
                                   std::span<const double> wavenumbers, double time_step,
                                   const CancelCheck& cancelled) {
  if (is_half_space(strip_height))
    throw std::invalid_argument("compute_strip_kernels needs a finite strip_height (got inf)");
  if (!(strip_height > 0)) throw std::invalid_argument("strip_height must be > 0");
  if (wavenumbers.empty() || wavenumbers[0] != 0.0 ||
      std::any_of(wavenumbers.begin() + 1, wavenumbers.end(), [](double k) { return !(k > 0.0); }))
    throw std::invalid_argument(
        "compute_strip_kernels: the wavenumbers must start with the uniform mode 0, all others > 0");
  const double echo_time = 2.0 * strip_height / material.shear_wave_speed();
  StripKernels kernels;
  kernels.time_step = time_step;
  kernels.echo_steps = static_cast<std::size_t>(std::llround(echo_time / time_step));
  if (kernels.echo_steps < 1 ||
      std::abs(kernels.echo_steps * time_step - echo_time) > 1e-9 * echo_time)
    throw std::invalid_argument(
        "time_step = " + std::to_string(time_step) +
        " s must divide the shear echo time 2H/c_s = " + std::to_string(echo_time) +
        " s into a whole number of steps (use strip_time_step)");
  // First mode of each distinct wavenumber: later modes of the same |k| copy its design.
  std::map<double, std::size_t> first_of;
  kernels.first_oscillator.assign(1, 0);
  for (std::size_t q = 0; q < wavenumbers.size(); ++q) {
    const auto [at, fresh] = first_of.emplace(wavenumbers[q], q);
    if (fresh) {
      throw_if_cancelled(cancelled, "the strip kernels");
      for (const auto& m :
           discrete_modes(material, strip_height, wavenumbers[q], time_step, kernels.echo_steps)) {
        kernels.phase.push_back(m.phase);
        kernels.weight.push_back(m.weight);
      }
    } else {
      const std::size_t begin = kernels.first_oscillator[at->second];
      const std::size_t end = kernels.first_oscillator[at->second + 1];
      for (std::size_t m = begin; m < end; ++m) {
        kernels.phase.push_back(kernels.phase[m]);
        kernels.weight.push_back(kernels.weight[m]);
      }
    }
    kernels.first_oscillator.push_back(kernels.weight.size());
  }
  return kernels;
}

StripHistory::StripHistory(const ElasticMaterial& material, double strip_height, double length,
                           int nodes, double time_step)
    : StripHistory(material, compute_strip_kernels(material, strip_height, length, nodes, time_step)) {}

StripHistory::StripHistory(const ElasticMaterial& material, const StripKernels& kernels,
                           const CancelCheck& cancelled)
    : StripHistory(identical_strip_pair(material, kernels.echo_steps), kernels, cancelled) {}

StripHistory::StripHistory(const StripPairConstants& constants, const StripKernels& kernels,
                           const CancelCheck& cancelled)
    : dt_(kernels.time_step), eta_(constants.radiation_damping),
      echo_weight_(constants.running_sum_weight),
      kernels_echo_steps_(kernels.echo_steps), first_oscillator_(kernels.first_oscillator),
      weight_(kernels.weight), echo_(constants) {
  if (first_oscillator_.size() < 2 || first_oscillator_.back() != weight_.size() ||
      kernels.phase.size() != weight_.size() || kernels.echo_steps < 1)
    throw std::invalid_argument("StripHistory: inconsistent kernels");
  const int n_modes = static_cast<int>(first_oscillator_.size()) - 1;
  // The per-step arrays on huge pages (kernels/huge_pages.hpp): every step
  // streams through all of them.
  cos_step_.reserve(weight_.size());
  sin_step_.reserve(weight_.size());
  advise_huge_pages(cos_step_.data(), weight_.size() * sizeof(double));
  advise_huge_pages(sin_step_.data(), weight_.size() * sizeof(double));
  for (std::size_t m = 0; m < kernels.phase.size(); ++m) {
    if ((m & 0xffff) == 0) throw_if_cancelled(cancelled, "the strip history operator");
    const double phase = kernels.phase[m];
    cos_step_.push_back(std::cos(phase));
    sin_step_.push_back(std::sin(phase));
  }
  // For q >= 1 the delay line and the comb modes are never built: in discrete
  // time they add up to exactly the constant kernel mu/c_s (for every lag
  // j >= 1; docs/theory.md, "comb identity"), i.e. a running sum.  Only the
  // uniform mode q = 0 keeps the delay line (it has no other modes).
  integrator_weight_.assign(n_modes, echo_weight_);
  integrator_weight_[0] = 0.0;
  weight_sum_.assign(n_modes, 0.0);
  for (int q = 0; q < n_modes; ++q)
    for (std::size_t m = first_oscillator_[q]; m < first_oscillator_[q + 1]; ++m)
      weight_sum_[q] += weight_[m];
  const std::size_t n_osc = weight_.size();
  for (auto* v : {&c_re_, &c_im_, &s_re_, &s_im_}) assign_on_huge_pages(*v, n_osc, 0.0);
  running_sum_.assign(n_modes, 0.0);
  history_.assign(n_modes, 0.0);
}

ModeOperatorStats StripHistory::stats() const {
  ModeOperatorStats s;
  s.modes = history_.size();
  s.oscillators = weight_.size();
  s.echo_steps = kernels_echo_steps_;
  s.memory_bytes = sizeof(double) * (7 * weight_.size() + weight_sum_.size()) +
                   sizeof(std::complex<double>) *
                       (running_sum_.size() + echo_.slots() + history_.size()) +
                   sizeof(double) * integrator_weight_.size() +
                   sizeof(std::size_t) * first_oscillator_.size();
  return s;
}

void StripHistory::push(std::span<const std::complex<double>> slip_rate_spectrum) {
  const int n_modes = static_cast<int>(history_.size());
  history_[0] = echo_.push(slip_rate_spectrum[0]);
  simd::parallel_for(n_modes - 1, [&](long long item) {
    const int q = static_cast<int>(item) + 1;
    const std::complex<double> v = slip_rate_spectrum[q];
    const double vr = v.real(), vi = v.imag();
    double acc_r = 0.0, acc_i = 0.0;
    const std::size_t begin = first_oscillator_[q], end = first_oscillator_[q + 1];
    for (std::size_t m = begin; m < end; ++m) {
      // [C; S] <- rotation(omega dt) [C + v; S]: C_n = sum_{j>=1} cos(omega j dt) v_{n-j}.
      const double c = cos_step_[m], s = sin_step_[m];
      const double xr = c_re_[m] + vr, xi = c_im_[m] + vi;
      const double sr = s_re_[m], si = s_im_[m];
      const double new_cr = c * xr - s * sr, new_ci = c * xi - s * si;
      s_re_[m] = s * xr + c * sr;
      s_im_[m] = s * xi + c * si;
      c_re_[m] = new_cr;
      c_im_[m] = new_ci;
      acc_r += weight_[m] * new_cr;
      acc_i += weight_[m] * new_ci;
    }
    running_sum_[q] += v;
    history_[q] = integrator_weight_[q] * running_sum_[q] +
                  dt_ * (weight_sum_[q] * running_sum_[q] - std::complex<double>(acc_r, acc_i));
  });
}

void HistoryOperatorState::add(const std::string& name, std::span<const double> values) {
  arrays.emplace_back(name, std::vector<double>(values.begin(), values.end()));
}

void HistoryOperatorState::add(const std::string& name,
                               std::span<const std::complex<double>> values) {
  std::vector<double> flat(2 * values.size());
  for (std::size_t i = 0; i < values.size(); ++i) {
    flat[2 * i] = values[i].real();
    flat[2 * i + 1] = values[i].imag();
  }
  arrays.emplace_back(name, std::move(flat));
}

namespace {
const std::vector<double>& find_array(const HistoryOperatorState& state, const std::string& name,
                                      std::size_t expected_size) {
  for (const auto& [key, values] : state.arrays) {
    if (key != name) continue;
    if (values.size() != expected_size)
      throw std::invalid_argument("history operator state '" + state.kind + "': array '" + name +
                                  "' has " + std::to_string(values.size()) + " values, this operator needs " +
                                  std::to_string(expected_size) + " (a restart point of another config?)");
    return values;
  }
  throw std::invalid_argument("history operator state '" + state.kind + "': array '" + name +
                              "' is missing");
}
}  // namespace

void HistoryOperatorState::copy_to(const std::string& name, std::span<double> target) const {
  const auto& values = find_array(*this, name, target.size());
  std::copy(values.begin(), values.end(), target.begin());
}

void HistoryOperatorState::copy_to(const std::string& name,
                                   std::span<std::complex<double>> target) const {
  const auto& values = find_array(*this, name, 2 * target.size());
  for (std::size_t i = 0; i < target.size(); ++i) target[i] = {values[2 * i], values[2 * i + 1]};
}

long long HistoryOperatorState::counter(const std::string& name) const {
  for (const auto& [key, value] : counters)
    if (key == name) return value;
  throw std::invalid_argument("history operator state '" + kind + "': counter '" + name +
                              "' is missing");
}

bool HistoryOperatorState::has(const std::string& name) const {
  return std::any_of(arrays.begin(), arrays.end(), [&](const auto& a) { return a.first == name; });
}

void HistoryOperatorState::require_kind(const std::string& expected) const {
  if (kind != expected)
    throw std::invalid_argument("history operator state is of kind '" + kind + "', this run's operator is '" +
                                expected + "' (a restart point of another config?)");
}

void HistoryOperatorState::add_part(const std::string& prefix, const HistoryOperatorState& part) {
  for (const auto& [name, values] : part.arrays) arrays.emplace_back(prefix + name, values);
  for (const auto& [name, value] : part.counters) counters.emplace_back(prefix + name, value);
}

HistoryOperatorState HistoryOperatorState::part(const std::string& prefix, const std::string& part_kind) const {
  HistoryOperatorState part;
  part.kind = part_kind;
  for (const auto& [name, values] : arrays)
    if (name.rfind(prefix, 0) == 0) part.arrays.emplace_back(name.substr(prefix.size()), values);
  for (const auto& [name, value] : counters)
    if (name.rfind(prefix, 0) == 0) part.counters.emplace_back(name.substr(prefix.size()), value);
  return part;
}

void HistoryStateLayout::add(const std::string& name, std::span<const std::size_t> first_element,
                             std::size_t doubles_per_element) {
  std::vector<std::size_t> first(first_element.begin(), first_element.end());
  for (auto& f : first) f *= doubles_per_element;
  arrays.emplace_back(name, std::move(first));
}

void HistoryStateLayout::add_uniform(const std::string& name, std::size_t modes, std::size_t values_per_mode) {
  std::vector<std::size_t> first(modes + 1);
  for (std::size_t q = 0; q <= modes; ++q) first[q] = q * values_per_mode;
  arrays.emplace_back(name, std::move(first));
}

void HistoryStateLayout::add_first_mode(const std::string& name, std::size_t modes, std::size_t values) {
  std::vector<std::size_t> first(modes + 1, values);
  first[0] = 0;
  arrays.emplace_back(name, std::move(first));
}

void HistoryStateLayout::add_part(const std::string& prefix, const HistoryStateLayout& part) {
  for (const auto& [name, first] : part.arrays) arrays.emplace_back(prefix + name, first);
  for (const auto& name : part.any_counters) any_counters.push_back(prefix + name);
}

const std::vector<std::size_t>& HistoryStateLayout::of(const std::string& name) const {
  for (const auto& [key, first] : arrays)
    if (key == name) return first;
  throw std::invalid_argument("history operator state: no per-mode layout for array '" + name + "'");
}

HistoryStateLayout StripHistory::state_layout() const {
  const std::size_t n = history_.size();
  HistoryStateLayout layout;
  for (const char* name : {"c_re", "c_im", "s_re", "s_im"}) layout.add(name, first_oscillator_, 1);
  layout.add_uniform("running_sum", n, 2);
  echo_.add_layout(layout, n);
  layout.add_uniform("history", n, 2);
  return layout;
}

HistoryOperatorState StripHistory::save_state() const {
  HistoryOperatorState state;
  state.kind = "modal strip";
  echo_.save_counters(state);
  state.add("c_re", c_re_);
  state.add("c_im", c_im_);
  state.add("s_re", s_re_);
  state.add("s_im", s_im_);
  state.add("running_sum", running_sum_);
  echo_.save_arrays(state);
  state.add("history", history_);
  return state;
}

void StripHistory::restore_state(const HistoryOperatorState& state) {
  state.require_kind("modal strip");
  echo_.check_cursor(state);
  state.copy_to("c_re", std::span<double>(c_re_));
  state.copy_to("c_im", std::span<double>(c_im_));
  state.copy_to("s_re", std::span<double>(s_re_));
  state.copy_to("s_im", std::span<double>(s_im_));
  state.copy_to("running_sum", std::span<std::complex<double>>(running_sum_));
  echo_.restore(state);
  state.copy_to("history", std::span<std::complex<double>>(history_));
}

}  // namespace slipstrip
