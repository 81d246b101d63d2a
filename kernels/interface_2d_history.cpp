#include "kernels/interface_2d_history.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <string_view>

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
  {
    const long long half_x = grid_.nodes_x / 2 + 1, grid_modes = static_cast<long long>(grid_.modes());
    operator_modes_ = grid_modes + (grid_.nodes_z % 2 == 0 && grid_.nodes_z > 1 ? half_x : 0);
    global_mode_.assign(n, -1);
    for (std::size_t s = 0; s < modes.size(); ++s) global_mode_[first_ + s] = modes.qz[s] * half_x + modes.qx[s];
    for (std::size_t j = 0; j < extra_slot_.size(); ++j)
      global_mode_[first_ + modes.size() + j] = grid_modes + modes.qx[extra_slot_[j]];
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

HistoryStateLayout InterfaceHistory2d::state_layout() const {
  HistoryStateLayout layout;
  layout.add_part("inplane.", inplane_->state_layout());
  layout.add_part("antiplane.", antiplane_->state_layout());
  return layout;
}

namespace {

constexpr const char* kModesArray = "@modes";
constexpr const char* kOperatorModesCounter = "@operator_modes";
constexpr const char* kFirstSuffix = "@first";
// Marks a counter of HistoryStateLayout::any_counters in mode records: "@any." + name.
constexpr const char* kAnyPrefix = "@any.";

bool is_mode_array(const std::string& name) {
  return name != kModesArray &&
         !(name.size() > std::string_view(kFirstSuffix).size() && name.ends_with(kFirstSuffix));
}

const std::vector<double>& record_array(const HistoryOperatorState& records, const std::string& name) {
  for (const auto& [key, values] : records.arrays)
    if (key == name) return values;
  throw std::invalid_argument("history operator mode records: array '" + name + "' is missing");
}

// A mode index or offset stored as a double: a whole number in range.
std::size_t stored_index(double value, double limit, const std::string& what) {
  if (!(value >= 0.0 && value <= limit && value == std::floor(value)))
    throw std::invalid_argument("history operator mode records: " + what + " = " + std::to_string(value) +
                                " is not an index in 0.." + std::to_string(static_cast<long long>(limit)));
  return static_cast<std::size_t>(value);
}

// Which part holds each global mode, and where: (part, record), checked to
// cover 0..operator_modes-1 once.
std::vector<std::pair<std::size_t, std::size_t>> mode_owners(std::span<const HistoryOperatorState> parts,
                                                             long long operator_modes) {
  if (operator_modes < 1) throw std::invalid_argument("history operator mode records: no modes");
  constexpr std::size_t none = static_cast<std::size_t>(-1);
  std::vector<std::pair<std::size_t, std::size_t>> owner(static_cast<std::size_t>(operator_modes), {none, none});
  const double limit = static_cast<double>(operator_modes - 1);
  for (std::size_t p = 0; p < parts.size(); ++p) {
    if (parts[p].counter(kOperatorModesCounter) != operator_modes)
      throw std::invalid_argument("history operator mode records: the parts' operators have " +
                                  std::to_string(parts[p].counter(kOperatorModesCounter)) + " and " +
                                  std::to_string(operator_modes) + " modes");
    const auto& modes = record_array(parts[p], kModesArray);
    for (std::size_t i = 0; i < modes.size(); ++i) {
      const std::size_t g = stored_index(modes[i], limit, "mode");
      if (owner[g].first != none)
        throw std::invalid_argument("history operator mode records: mode " + std::to_string(g) +
                                    " is held by two parts");
      owner[g] = {p, i};
    }
  }
  for (std::size_t g = 0; g < owner.size(); ++g)
    if (owner[g].first == none)
      throw std::invalid_argument("history operator mode records: mode " + std::to_string(g) + " is held by no part");
  return owner;
}

// The offsets of record array `name` of a part: checked to rise from 0, one
// more than the part's modes.
std::vector<std::size_t> record_offsets(const HistoryOperatorState& part, const std::string& name) {
  const auto& stored = record_array(part, name + kFirstSuffix);
  const std::size_t modes = record_array(part, kModesArray).size();
  if (stored.size() != modes + 1 || stored[0] != 0.0)
    throw std::invalid_argument("history operator mode records: '" + name + kFirstSuffix + "' has " +
                                std::to_string(stored.size()) + " offsets for " + std::to_string(modes) + " modes");
  std::vector<std::size_t> first(stored.size());
  for (std::size_t i = 0; i < stored.size(); ++i) {
    first[i] = stored_index(stored[i], 0x1p53, name + kFirstSuffix);
    if (i > 0 && first[i] < first[i - 1])
      throw std::invalid_argument("history operator mode records: '" + name + kFirstSuffix + "' decreases");
  }
  return first;
}

}  // namespace

HistoryOperatorState InterfaceHistory2d::save_mode_records(bool with_values) const {
  const HistoryOperatorState state = save_state();
  const HistoryStateLayout layout = state_layout();
  if (layout.arrays.size() != state.arrays.size())
    throw std::logic_error("InterfaceHistory2d: the state has " + std::to_string(state.arrays.size()) +
                           " arrays, its per-mode layout " + std::to_string(layout.arrays.size()));
  // This operator's modes in global order (an idle uniform mode left out).
  std::vector<std::pair<long long, std::size_t>> order;
  for (std::size_t m = 0; m < global_mode_.size(); ++m)
    if (global_mode_[m] >= 0) order.emplace_back(global_mode_[m], m);
  std::sort(order.begin(), order.end());
  HistoryOperatorState records;
  records.kind = kModeRecordsKind;
  records.counters = state.counters;
  records.counters.emplace_back(kOperatorModesCounter, operator_modes_);
  for (const auto& name : layout.any_counters) records.counters.emplace_back(kAnyPrefix + name, 1);
  std::vector<double> modes;
  for (const auto& [g, m] : order) modes.push_back(static_cast<double>(g));
  records.arrays.emplace_back(kModesArray, std::move(modes));
  for (const auto& [name, values] : state.arrays) {
    const auto& first = layout.of(name);
    if (first.size() != global_mode_.size() + 1 || first.front() != 0 || first.back() != values.size())
      throw std::logic_error("InterfaceHistory2d: the per-mode layout of '" + name + "' does not fit its " +
                             std::to_string(values.size()) + " values");
    std::vector<double> record, offsets{0.0};
    std::size_t size = 0;
    for (const auto& [g, m] : order) {
      if (with_values) record.insert(record.end(), values.begin() + first[m], values.begin() + first[m + 1]);
      size += first[m + 1] - first[m];
      offsets.push_back(static_cast<double>(size));
    }
    records.arrays.emplace_back(name, std::move(record));
    records.arrays.emplace_back(name + kFirstSuffix, std::move(offsets));
  }
  return records;
}

HistoryOperatorState InterfaceHistory2d::merge_mode_records(std::span<const HistoryOperatorState> parts) {
  if (parts.empty()) throw std::invalid_argument("history operator mode records: no parts");
  const long long operator_modes = parts[0].counter(kOperatorModesCounter);
  const auto owner = mode_owners(parts, operator_modes);
  HistoryOperatorState whole;
  whole.kind = kStateKind;
  for (const auto& [name, value] : parts[0].counters) {
    if (name.starts_with("@")) continue;
    const bool any = std::any_of(parts[0].counters.begin(), parts[0].counters.end(),
                                 [&](const auto& c) { return c.first == kAnyPrefix + name; });
    long long merged = value;
    for (const auto& part : parts) {
      const long long other = part.counter(name);
      if (any)
        merged = std::max(merged, other);
      else if (other != value)
        throw std::invalid_argument("history operator mode records: counter '" + name + "' is " +
                                    std::to_string(value) + " in one part and " + std::to_string(other) +
                                    " in another");
    }
    whole.counters.emplace_back(name, merged);
  }
  for (const auto& [name, unused] : parts[0].arrays) {
    if (!is_mode_array(name)) continue;
    std::vector<std::vector<std::size_t>> first(parts.size());
    std::vector<const std::vector<double>*> values(parts.size());
    std::size_t total = 0;
    for (std::size_t p = 0; p < parts.size(); ++p) {
      first[p] = record_offsets(parts[p], name);
      values[p] = &record_array(parts[p], name);
      if (values[p]->size() != first[p].back())
        throw std::invalid_argument("history operator mode records: '" + name + "' has " +
                                    std::to_string(values[p]->size()) + " values, its offsets " +
                                    std::to_string(first[p].back()));
      total += values[p]->size();
    }
    std::vector<double> merged;
    merged.reserve(total);
    for (const auto& [p, i] : owner)
      merged.insert(merged.end(), values[p]->begin() + first[p][i], values[p]->begin() + first[p][i + 1]);
    whole.arrays.emplace_back(name, std::move(merged));
  }
  return whole;
}

std::vector<HistoryOperatorState> InterfaceHistory2d::split_state(const HistoryOperatorState& whole,
                                                                  std::span<const HistoryOperatorState> layouts) {
  whole.require_kind(kStateKind);
  if (layouts.empty()) throw std::invalid_argument("history operator mode records: no parts");
  const long long operator_modes = layouts[0].counter(kOperatorModesCounter);
  const auto owner = mode_owners(layouts, operator_modes);
  std::vector<HistoryOperatorState> parts(layouts.size());
  for (std::size_t p = 0; p < layouts.size(); ++p) {
    parts[p].kind = kModeRecordsKind;
    parts[p].counters = whole.counters;
    parts[p].counters.emplace_back(kOperatorModesCounter, operator_modes);
    parts[p].arrays.emplace_back(kModesArray, record_array(layouts[p], kModesArray));
  }
  std::size_t arrays = 0;
  for (const auto& [name, unused] : layouts[0].arrays) {
    if (!is_mode_array(name)) continue;
    ++arrays;
    std::vector<std::vector<std::size_t>> first(layouts.size());
    for (std::size_t p = 0; p < layouts.size(); ++p) first[p] = record_offsets(layouts[p], name);
    // The whole array's offsets: each mode's size, in global order.
    std::vector<std::size_t> offset(owner.size() + 1, 0);
    for (std::size_t g = 0; g < owner.size(); ++g) {
      const auto [p, i] = owner[g];
      offset[g + 1] = offset[g] + first[p][i + 1] - first[p][i];
    }
    bool found = false;
    for (const auto& [key, values] : whole.arrays) {
      if (key != name) continue;
      found = true;
      if (values.size() != offset.back())
        throw std::invalid_argument("history operator state: array '" + name + "' has " +
                                    std::to_string(values.size()) + " values, this run's operator needs " +
                                    std::to_string(offset.back()) + " (a restart point of another config or grid?)");
      for (std::size_t p = 0; p < layouts.size(); ++p) {
        const auto& modes = record_array(layouts[p], kModesArray);
        std::vector<double> record;
        record.reserve(first[p].back());
        for (const double stored : modes) {
          const auto g = static_cast<std::size_t>(stored);
          record.insert(record.end(), values.begin() + offset[g], values.begin() + offset[g + 1]);
        }
        parts[p].arrays.emplace_back(name, std::move(record));
        parts[p].arrays.emplace_back(name + kFirstSuffix, record_array(layouts[p], name + kFirstSuffix));
      }
    }
    if (!found) throw std::invalid_argument("history operator state: array '" + name + "' is missing");
  }
  if (whole.arrays.size() != arrays)
    throw std::invalid_argument("history operator state: " + std::to_string(whole.arrays.size()) +
                                " arrays, this run's operator has " + std::to_string(arrays) +
                                " (a restart point of another config?)");
  return parts;
}

void InterfaceHistory2d::restore_mode_records(const HistoryOperatorState& records) {
  records.require_kind(kModeRecordsKind);
  HistoryOperatorState target = save_state();
  const HistoryOperatorState own = save_mode_records(false);
  if (records.counter(kOperatorModesCounter) != operator_modes_ ||
      record_array(records, kModesArray) != record_array(own, kModesArray))
    throw std::invalid_argument("history operator mode records: not this operator's modes");
  const HistoryStateLayout layout = state_layout();
  std::vector<std::pair<long long, std::size_t>> order;
  for (std::size_t m = 0; m < global_mode_.size(); ++m)
    if (global_mode_[m] >= 0) order.emplace_back(global_mode_[m], m);
  std::sort(order.begin(), order.end());
  for (auto& [name, values] : target.arrays) {
    const auto& first = layout.of(name);
    const auto& record = record_array(records, name);
    if (record_array(records, name + kFirstSuffix) != record_array(own, name + kFirstSuffix) ||
        record.size() != record_offsets(own, name).back())
      throw std::invalid_argument("history operator mode records: array '" + name +
                                  "' has other sizes per mode than this operator's (another config?)");
    auto from = record.begin();
    for (const auto& [g, m] : order) {
      const auto count = static_cast<std::ptrdiff_t>(first[m + 1] - first[m]);
      std::copy(from, from + count, values.begin() + static_cast<std::ptrdiff_t>(first[m]));
      from += count;
    }
  }
  for (auto& [name, value] : target.counters) value = records.counter(name);
  restore_state(target);
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
