#include "kernels/interface_2d_history.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "kernels/half_space_history.hpp"

namespace slipstrip {

InterfaceWavevectors interface_wavevectors(const InterfaceGrid2d& grid) {
  if (!(grid.length_x > 0) || !(grid.length_z > 0) || grid.nodes_x < 1 || grid.nodes_z < 1)
    throw std::invalid_argument("interface grid: lengths must be > 0 and node counts >= 1");
  const int half_x = grid.nodes_x / 2 + 1;
  InterfaceWavevectors k;
  k.kx.resize(grid.modes());
  k.kz.resize(grid.modes());
  k.magnitude.resize(grid.modes());
  for (int qz = 0; qz < grid.nodes_z; ++qz) {
    const int signed_qz = qz <= grid.nodes_z / 2 ? qz : qz - grid.nodes_z;
    const double kz = 2.0 * std::numbers::pi * static_cast<double>(signed_qz) / grid.length_z;
    for (int qx = 0; qx < half_x; ++qx) {
      const std::size_t m = static_cast<std::size_t>(qz) * half_x + qx;
      // The same expression as the one-dimensional interface's wavenumbers.
      k.kx[m] = 2.0 * std::numbers::pi * static_cast<double>(qx) / grid.length_x;
      k.kz[m] = kz;
      k.magnitude[m] = std::hypot(k.kx[m], kz);
    }
  }
  return k;
}

InterfaceWavevectors interface_operator_wavevectors(const InterfaceGrid2d& grid) {
  InterfaceWavevectors k = interface_wavevectors(grid);
  if (grid.nodes_z % 2 == 0 && grid.nodes_z > 1) {
    const std::size_t half_x = grid.nodes_x / 2 + 1, row = static_cast<std::size_t>(grid.nodes_z / 2) * half_x;
    for (std::size_t qx = 0; qx < half_x; ++qx) {
      k.kx.push_back(k.kx[row + qx]);
      k.kz.push_back(-k.kz[row + qx]);
      k.magnitude.push_back(k.magnitude[row + qx]);
    }
  }
  return k;
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
    : grid_(grid), inplane_(std::move(inplane)), antiplane_(std::move(antiplane)) {
  if (!inplane_ || !antiplane_)
    throw std::invalid_argument("InterfaceHistory2d: needs an in-plane and an antiplane operator");
  const InterfaceWavevectors k = interface_operator_wavevectors(grid_);
  const std::size_t n = k.magnitude.size();
  if (static_cast<std::size_t>(inplane_->modes()) != n ||
      static_cast<std::size_t>(antiplane_->modes()) != n ||
      inplane_->time_step() != antiplane_->time_step() ||
      inplane_->radiation_damping() != antiplane_->radiation_damping())
    throw std::invalid_argument(
        "InterfaceHistory2d: the in-plane and antiplane operators must have the grid's " +
        std::to_string(n) + " operator modes, one time step and one radiation damping");
  if (n > grid_.modes()) nyquist_row_ = static_cast<std::size_t>(grid_.nodes_z / 2) * (grid_.nodes_x / 2 + 1);
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
  history_x_.assign(grid_.modes(), 0.0);
  history_z_.assign(grid_.modes(), 0.0);
}

InterfaceHistory2d InterfaceHistory2d::build(const ElasticMaterial& material, double strip_height,
                                             const InterfaceGrid2d& grid, double time_step,
                                             const CancelCheck& cancelled,
                                             const StripOperatorFactory& strip_operator) {
  ElasticMaterial inplane = material, antiplane = material;
  inplane.plane = PlaneCondition::strain;  // a body invariant along the crest of the mode
  antiplane.plane = PlaneCondition::antiplane;
  const std::vector<double> magnitude = interface_operator_wavevectors(grid).magnitude;
  if (is_half_space(strip_height))
    return InterfaceHistory2d(
        grid, std::make_unique<HalfSpaceHistory>(inplane, magnitude, time_step, HalfSpaceOperatorDesign{}, cancelled),
        std::make_unique<HalfSpaceHistory>(antiplane, magnitude, time_step, HalfSpaceOperatorDesign{}, cancelled));
  // One operator at a time: the kernels (one copy of every mode's normal
  // modes) are freed before the next ones are computed.
  auto make = [&](const ElasticMaterial& body) -> std::unique_ptr<HistoryOperator> {
    const StripKernels kernels = compute_strip_kernels(body, strip_height, magnitude, time_step, cancelled);
    if (strip_operator) return strip_operator(body, kernels);
    return std::make_unique<StripHistory>(body, kernels, cancelled);
  };
  auto inplane_operator = make(inplane);
  return InterfaceHistory2d(grid, std::move(inplane_operator), make(antiplane));
}

namespace {
constexpr const char* kInterface2dKind = "interface 2d";
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
  const std::size_t n = history_x_.size(), n_operator = along_.size();
  // Operator mode m < n is grid mode m; the extra z-Nyquist row takes its grid row's input.
  for (std::size_t m = 0; m < n_operator; ++m) {
    const std::size_t g = m < n ? m : nyquist_row_ + (m - n);
    along_[m] = cos_[m] * slip_rate_x[g] + sin_[m] * slip_rate_z[g];
    across_[m] = cos_[m] * slip_rate_z[g] - sin_[m] * slip_rate_x[g];
  }
  inplane_->push(along_);
  antiplane_->push(across_);
  const auto h_along = inplane_->history(), h_across = antiplane_->history();
  for (std::size_t m = 0; m < n; ++m) {
    history_x_[m] = cos_[m] * h_along[m] - sin_[m] * h_across[m];
    history_z_[m] = sin_[m] * h_along[m] + cos_[m] * h_across[m];
  }
  // z-Nyquist row: the average over kz = +-pi/dz (no coupling term).
  for (std::size_t m = n; m < n_operator; ++m) {
    const std::size_t g = nyquist_row_ + (m - n);
    history_x_[g] = 0.5 * (history_x_[g] + (cos_[m] * h_along[m] - sin_[m] * h_across[m]));
    history_z_[g] = 0.5 * (history_z_[g] + (sin_[m] * h_along[m] + cos_[m] * h_across[m]));
  }
  // x-Nyquist column: its Hermitian part, h(qz) <- (h(qz) + conj h(-qz)) / 2,
  // the average over kx = +-pi/dx.
  if (grid_.nodes_x % 2 == 0) {
    const std::size_t half_x = grid_.nodes_x / 2 + 1, qx = grid_.nodes_x / 2;
    const int nz = grid_.nodes_z;
    for (int qz = 0; qz <= nz / 2; ++qz) {
      const std::size_t a = static_cast<std::size_t>(qz) * half_x + qx;
      const std::size_t b = static_cast<std::size_t>((nz - qz) % nz) * half_x + qx;
      for (auto* h : {&history_x_, &history_z_}) {
        const std::complex<double> mean = 0.5 * ((*h)[a] + std::conj((*h)[b]));
        (*h)[a] = mean;
        (*h)[b] = std::conj(mean);
      }
    }
  }
}

}  // namespace slipstrip
