#include "kernels/interface_2d_history.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "kernels/face_half_space.hpp"
#include "kernels/face_history.hpp"
#include "kernels/half_space_history.hpp"
#include "kernels/inplane_pair_history.hpp"
#include "kernels/two_body_history.hpp"

namespace slipstrip {

namespace {
void check_grid(const InterfaceGrid2d& grid) {
  if (!(grid.length_x > 0) || !(grid.length_z > 0) || grid.nodes_x < 1 || grid.nodes_z < 1)
    throw std::invalid_argument("interface grid: lengths must be > 0 and node counts >= 1");
}
}  // namespace

InterfaceModeSet interface_modes_all(const InterfaceGrid2d& grid) {
  check_grid(grid);
  const int half_x = grid.nodes_x / 2 + 1;
  InterfaceModeSet modes;
  modes.qx.reserve(grid.modes());
  modes.qz.reserve(grid.modes());
  for (int qz = 0; qz < grid.nodes_z; ++qz)
    for (int qx = 0; qx < half_x; ++qx) {
      modes.qx.push_back(qx);
      modes.qz.push_back(qz);
    }
  return modes;
}

InterfaceModeSet interface_mode_columns(const InterfaceGrid2d& grid, int qx_begin, int qx_count) {
  check_grid(grid);
  if (qx_begin < 0 || qx_count < 0 || qx_begin + qx_count > grid.nodes_x / 2 + 1)
    throw std::invalid_argument("interface_mode_columns: columns " + std::to_string(qx_begin) + " + " +
                                std::to_string(qx_count) + " outside 0.." + std::to_string(grid.nodes_x / 2));
  InterfaceModeSet modes;
  for (int qx = qx_begin; qx < qx_begin + qx_count; ++qx)
    for (int qz = 0; qz < grid.nodes_z; ++qz) {
      modes.qx.push_back(qx);
      modes.qz.push_back(qz);
    }
  return modes;
}

InterfaceWavevectors interface_wavevectors(const InterfaceGrid2d& grid, const InterfaceModeSet& modes) {
  check_grid(grid);
  const std::size_t n = modes.size();
  InterfaceWavevectors k;
  k.kx.resize(n);
  k.kz.resize(n);
  k.magnitude.resize(n);
  for (std::size_t m = 0; m < n; ++m) {
    const int qx = modes.qx[m], qz = modes.qz[m];
    const int signed_qz = qz <= grid.nodes_z / 2 ? qz : qz - grid.nodes_z;
    // The same expression as the one-dimensional interface's wavenumbers.
    k.kx[m] = 2.0 * std::numbers::pi * static_cast<double>(qx) / grid.length_x;
    k.kz[m] = 2.0 * std::numbers::pi * static_cast<double>(signed_qz) / grid.length_z;
    k.magnitude[m] = std::hypot(k.kx[m], k.kz[m]);
  }
  return k;
}

InterfaceWavevectors interface_wavevectors(const InterfaceGrid2d& grid) {
  return interface_wavevectors(grid, interface_modes_all(grid));
}

namespace {
bool holds_uniform_mode(const InterfaceModeSet& modes) {
  for (std::size_t s = 0; s < modes.size(); ++s)
    if (modes.qx[s] == 0 && modes.qz[s] == 0) return true;
  return false;
}
}  // namespace

InterfaceWavevectors interface_operator_wavevectors(const InterfaceGrid2d& grid, const InterfaceModeSet& modes) {
  InterfaceWavevectors k = interface_wavevectors(grid, modes);
  if (!holds_uniform_mode(modes)) {
    // The idle uniform mode in front (the operators need it first).
    k.kx.insert(k.kx.begin(), 0.0);
    k.kz.insert(k.kz.begin(), 0.0);
    k.magnitude.insert(k.magnitude.begin(), 0.0);
  }
  const std::size_t first = k.magnitude.size() - modes.size();  // 1 with the idle uniform mode
  if (grid.nodes_z % 2 == 0 && grid.nodes_z > 1) {
    for (std::size_t m = 0; m < modes.size(); ++m) {
      if (modes.qz[m] != grid.nodes_z / 2) continue;
      k.kx.push_back(k.kx[first + m]);
      k.kz.push_back(-k.kz[first + m]);
      k.magnitude.push_back(k.magnitude[first + m]);
    }
  }
  return k;
}

InterfaceWavevectors interface_operator_wavevectors(const InterfaceGrid2d& grid) {
  return interface_operator_wavevectors(grid, interface_modes_all(grid));
}

double interface_2d_beta_limit(const InterfaceGrid2d& grid, double beta_1d) {
  const double dx = grid.length_x / grid.nodes_x, dz = grid.length_z / grid.nodes_z;
  double k_max = 0.0;
  for (double k : interface_wavevectors(grid).magnitude) k_max = std::max(k_max, k);
  if (k_max == 0.0) return beta_1d;
  return beta_1d * std::numbers::pi / (std::min(dx, dz) * k_max);
}

InterfaceHistory2d::InterfaceHistory2d(const InterfaceGrid2d& grid,
                                       std::unique_ptr<HistoryOperator> inplane,
                                       std::unique_ptr<HistoryOperator> antiplane)
    : InterfaceHistory2d(grid, interface_modes_all(grid), std::move(inplane), std::move(antiplane)) {}

InterfaceHistory2d::InterfaceHistory2d(const InterfaceGrid2d& grid, const InterfaceModeSet& modes,
                                       std::unique_ptr<HistoryOperator> inplane,
                                       std::unique_ptr<HistoryOperator> antiplane)
    : grid_(grid), inplane_(std::move(inplane)), antiplane_(std::move(antiplane)) {
  if (!inplane_ || !antiplane_)
    throw std::invalid_argument("InterfaceHistory2d: needs an in-plane and an antiplane operator");
  const InterfaceWavevectors k = interface_operator_wavevectors(grid_, modes);
  const std::size_t n = k.magnitude.size();
  if (static_cast<std::size_t>(inplane_->modes()) != n ||
      static_cast<std::size_t>(antiplane_->modes()) != n ||
      inplane_->time_step() != antiplane_->time_step() ||
      inplane_->radiation_damping() != antiplane_->radiation_damping())
    throw std::invalid_argument(
        "InterfaceHistory2d: the in-plane and antiplane operators must have the grid's " +
        std::to_string(n) + " operator modes, one time step and one radiation damping");
  first_ = holds_uniform_mode(modes) ? 0 : 1;
  // The extra operator modes, in the order interface_operator_wavevectors appends them.
  for (std::size_t s = 0; s < modes.size() && n > first_ + modes.size(); ++s)
    if (modes.qz[s] == grid_.nodes_z / 2) extra_slot_.push_back(s);
  if (grid_.nodes_x % 2 == 0) {
    // Slot of each qz of the x-Nyquist column, if the set holds it.
    const int nz = grid_.nodes_z;
    std::vector<std::size_t> column(nz, modes.size());
    std::size_t held = 0;
    for (std::size_t s = 0; s < modes.size(); ++s)
      if (modes.qx[s] == grid_.nodes_x / 2) column[modes.qz[s]] = s, ++held;
    if (held != 0 && held != static_cast<std::size_t>(nz))
      throw std::invalid_argument("InterfaceHistory2d: a mode set must hold all or none of the x-Nyquist column");
    if (held != 0)
      for (int qz = 0; qz <= nz / 2; ++qz) x_nyquist_pairs_.emplace_back(column[qz], column[(nz - qz) % nz]);
  }
  cos_.resize(n);
  sin_.resize(n);
  for (std::size_t m = 0; m < n; ++m) {
    if (k.magnitude[m] == 0.0) {
      cos_[m] = 1.0;  // uniform mode: "along" is x (docs/3d.md)
      sin_[m] = 0.0;
    } else {
      cos_[m] = k.kx[m] / k.magnitude[m];
      sin_[m] = k.kz[m] / k.magnitude[m];
    }
  }
  along_.assign(n, 0.0);
  across_.assign(n, 0.0);
  history_x_.assign(modes.size(), 0.0);
  history_z_.assign(modes.size(), 0.0);
  pair_ = dynamic_cast<InplanePairHistory*>(inplane_.get());
  if (pair_) {
    opening_.assign(n, 0.0);
    normal_.assign(modes.size(), 0.0);
  }
}

double InterfaceHistory2d::normal_radiation_damping() const {
  return pair_ ? pair_->normal_radiation_damping() : 0.0;
}

InterfaceHistory2d InterfaceHistory2d::build(const ElasticMaterial& material, double strip_height,
                                             const InterfaceGrid2d& grid, double time_step,
                                             const CancelCheck& cancelled,
                                             const StripOperatorFactory& strip_operator) {
  return build(material, strip_height, grid, interface_modes_all(grid), time_step, cancelled, strip_operator);
}

InterfaceHistory2d InterfaceHistory2d::build(const ElasticMaterial& material, double strip_height,
                                             const InterfaceGrid2d& grid, const InterfaceModeSet& modes,
                                             double time_step, const CancelCheck& cancelled,
                                             const StripOperatorFactory& strip_operator,
                                             const HalfSpaceOperatorDesign& half_space) {
  ElasticMaterial inplane = material, antiplane = material;
  inplane.plane = PlaneCondition::strain;  // a body invariant along the crest of the mode
  antiplane.plane = PlaneCondition::antiplane;
  const std::vector<double> magnitude = interface_operator_wavevectors(grid, modes).magnitude;
  if (is_half_space(strip_height))
    return InterfaceHistory2d(
        grid, modes, std::make_unique<HalfSpaceHistory>(inplane, magnitude, time_step, half_space, cancelled),
        std::make_unique<HalfSpaceHistory>(antiplane, magnitude, time_step, half_space, cancelled));
  // One operator at a time: the kernels (one copy of every mode's normal
  // modes) are freed before the next ones are computed.
  auto make = [&](const ElasticMaterial& body) -> std::unique_ptr<HistoryOperator> {
    const StripKernels kernels = compute_strip_kernels(body, strip_height, magnitude, time_step, cancelled);
    if (strip_operator) return strip_operator(body, kernels);
    return std::make_unique<StripHistory>(body, kernels, cancelled);
  };
  auto inplane_operator = make(inplane);
  return InterfaceHistory2d(grid, modes, std::move(inplane_operator), make(antiplane));
}

InterfaceHistory2d InterfaceHistory2d::build_pair(const InterfaceBody& top, const std::optional<InterfaceBody>& bottom,
                                                  const InterfaceGrid2d& grid, double time_step,
                                                  const CancelCheck& cancelled,
                                                  const StripOperatorFactory& strip_operator) {
  return build_pair(top, bottom, grid, interface_modes_all(grid), time_step, cancelled, strip_operator, PairPart{});
}

InterfaceHistory2d InterfaceHistory2d::build_pair(const InterfaceBody& top, const std::optional<InterfaceBody>& bottom,
                                                  const InterfaceGrid2d& grid, const InterfaceModeSet& modes,
                                                  double time_step, const CancelCheck& cancelled,
                                                  const StripOperatorFactory& strip_operator, const PairPart& part) {
  const std::vector<double> magnitude = interface_operator_wavevectors(grid, modes).magnitude;
  const auto design_of = [&](const InterfaceBody& body) -> const HalfSpaceOperatorDesign& {
    return &body == &top ? part.top_half_space : part.bottom_half_space;
  };
  // In-plane: each body's 2x2 face operator at |k| (kernels/face_history.hpp;
  // a half-space's, kernels/face_half_space.hpp, with its near-field sums
  // over the whole list's |k| and a passivity correction per distinct |k|).
  auto face = [&](const InterfaceBody& body) -> std::unique_ptr<FaceHistory> {
    ElasticMaterial m = body.material;
    m.plane = PlaneCondition::strain;  // a body invariant along the crest of the mode
    if (is_half_space(body.height))
      return std::make_unique<FaceHalfSpaceHistory>(m, magnitude, time_step, design_of(body), cancelled);
    return std::make_unique<FaceModalHistory>(m, body.height, body.outer_face, magnitude, time_step);
  };
  // Antiplane: each body's pair-normalised operator (kernels/two_body_history.hpp);
  // the outer face does not change an SH body's response.
  auto sh = [&](const InterfaceBody& body) -> std::unique_ptr<HistoryOperator> {
    ElasticMaterial m = body.material;
    m.plane = PlaneCondition::antiplane;
    if (is_half_space(body.height))
      return std::make_unique<HalfSpaceHistory>(m, magnitude, time_step, design_of(body), cancelled);
    const StripKernels kernels = compute_strip_kernels(m, body.height, magnitude, time_step, cancelled);
    if (strip_operator) return strip_operator(m, kernels);
    return std::make_unique<StripHistory>(m, kernels, cancelled);
  };
  std::unique_ptr<FaceHistory> face_top, face_bottom;
  std::optional<FaceHalfSpaceNotPassive> not_passive;
  try {
    face_top = face(top);
    if (bottom) face_bottom = face(*bottom);
  } catch (const FaceHalfSpaceNotPassive& e) {
    not_passive.emplace(e);
  }
  if (part.any_process ? part.any_process(not_passive.has_value()) : not_passive.has_value()) {
    if (not_passive) throw *not_passive;
    throw FaceHalfSpaceNotPassive("a half-space body's 2x2 operator has no passive correction on another process's "
                                  "modes",
                                  0.0);
  }
  auto inplane = std::make_unique<InplanePairHistory>(std::move(face_top), std::move(face_bottom));
  throw_if_cancelled(cancelled, "the in-plane pair's operators");
  auto sh_top = sh(top);
  auto antiplane = std::make_unique<TwoBodyHistory>(std::move(sh_top), bottom ? sh(*bottom) : nullptr);
  return InterfaceHistory2d(grid, modes, std::move(inplane), std::move(antiplane));
}

namespace {
constexpr const char* kInterface2dKind = InterfaceHistory2d::kStateKind;
}  // namespace

HistoryOperatorState InterfaceHistory2d::save_state() const {
  HistoryOperatorState state;
  state.kind = kInterface2dKind;
  state.add_part("inplane.", inplane_->save_state());
  state.add_part("antiplane.", antiplane_->save_state());
  return state;
}

void InterfaceHistory2d::restore_state(const HistoryOperatorState& state) {
  state.require_kind(kInterface2dKind);
  // The parts carry the kinds of this run's operators; each part checks its arrays.
  inplane_->restore_state(state.part("inplane.", inplane_->save_state().kind));
  antiplane_->restore_state(state.part("antiplane.", antiplane_->save_state().kind));
}

ModeOperatorStats InterfaceHistory2d::stats() const {
  ModeOperatorStats s = inplane_->stats();
  const ModeOperatorStats a = antiplane_->stats();
  s.oscillators += a.oscillators;
  s.direct_lags += a.direct_lags;
  s.memory_bytes += a.memory_bytes +
                    sizeof(std::complex<double>) * 4 * along_.size() + sizeof(double) * 2 * cos_.size();
  return s;
}

void InterfaceHistory2d::push(std::span<const std::complex<double>> slip_rate_x,
                              std::span<const std::complex<double>> slip_rate_z) {
  push(slip_rate_x, slip_rate_z, {});
}

void InterfaceHistory2d::push(std::span<const std::complex<double>> slip_rate_x,
                              std::span<const std::complex<double>> slip_rate_z,
                              std::span<const std::complex<double>> opening_stress) {
  const std::size_t n = history_x_.size(), n_operator = along_.size();
  // Operator mode first_ + m is slot m; the extra z-Nyquist modes take their
  // slot's input; an idle uniform mode (first_ = 1) stays at zero input.
  const std::size_t f = first_;
  for (std::size_t m = 0; m < n; ++m) {
    along_[f + m] = cos_[f + m] * slip_rate_x[m] + sin_[f + m] * slip_rate_z[m];
    across_[f + m] = cos_[f + m] * slip_rate_z[m] - sin_[f + m] * slip_rate_x[m];
  }
  for (std::size_t m = f + n; m < n_operator; ++m) {
    const std::size_t g = extra_slot_[m - f - n];
    along_[m] = cos_[m] * slip_rate_x[g] + sin_[m] * slip_rate_z[g];
    across_[m] = cos_[m] * slip_rate_z[g] - sin_[m] * slip_rate_x[g];
  }
  if (pair_ && !opening_stress.empty()) {
    // The opening stress is a normal traction: the same in every frame.
    for (std::size_t m = 0; m < n; ++m) opening_[f + m] = opening_stress[m];
    for (std::size_t m = f + n; m < n_operator; ++m) opening_[m] = opening_stress[extra_slot_[m - f - n]];
    pair_->push(along_, opening_);
  } else {
    inplane_->push(along_);
  }
  antiplane_->push(across_);
  const auto h_along = inplane_->history(), h_across = antiplane_->history();
  for (std::size_t m = 0; m < n; ++m) {
    history_x_[m] = cos_[f + m] * h_along[f + m] - sin_[f + m] * h_across[f + m];
    history_z_[m] = sin_[f + m] * h_along[f + m] + cos_[f + m] * h_across[f + m];
  }
  // z-Nyquist row: the average over kz = +-pi/dz (no coupling term).
  for (std::size_t m = f + n; m < n_operator; ++m) {
    const std::size_t g = extra_slot_[m - f - n];
    history_x_[g] = 0.5 * (history_x_[g] + (cos_[m] * h_along[m] - sin_[m] * h_across[m]));
    history_z_[g] = 0.5 * (history_z_[g] + (sin_[m] * h_along[m] + cos_[m] * h_across[m]));
  }
  if (pair_) {
    const auto normal = pair_->normal_stress();
    for (std::size_t m = 0; m < n; ++m) normal_[m] = normal[f + m];
    for (std::size_t m = f + n; m < n_operator; ++m) {
      const std::size_t g = extra_slot_[m - f - n];
      normal_[g] = 0.5 * (normal_[g] + normal[m]);
    }
  }
  // x-Nyquist column: its Hermitian part, h(qz) <- (h(qz) + conj h(-qz)) / 2,
  // the average over kx = +-pi/dx.
  for (const auto& [a, b] : x_nyquist_pairs_) {
    for (auto* h : {&history_x_, &history_z_, &normal_}) {
      if (h->empty()) continue;  // normal_: pairs only
      const std::complex<double> mean = 0.5 * ((*h)[a] + std::conj((*h)[b]));
      (*h)[a] = mean;
      (*h)[b] = std::conj(mean);
    }
  }
}

}  // namespace slipstrip
