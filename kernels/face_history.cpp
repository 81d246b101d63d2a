#include "kernels/face_history.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <stdexcept>
#include <string>

namespace slipstrip {
namespace {

using complex = std::complex<double>;
constexpr double pi = std::numbers::pi;

// Every matrix here is Hermitian with real diagonal and imaginary off-diagonal
// (K, W and E for real k and s): (xx, Im xy, yy) is a real 3-vector.
struct Real3 {
  double a, c, d;
};
Real3 to_real3(const FaceMatrix& m) { return {m.xx.real(), m.xy.imag(), m.yy.real()}; }

// Eigenvalues (ascending) of [[a, -i c... ]]: the Hermitian matrix [[a, i c], [-i c, d]].
std::pair<double, double> eigenvalues(const Real3& m) {
  const double mean = 0.5 * (m.a + m.d), half = 0.5 * (m.a - m.d);
  const double r = std::sqrt(half * half + m.c * m.c);
  return {mean - r, mean + r};
}

// The matrix sum_{lambda > 0} lambda e e^H (positive part) or the negative part.
FaceMatrix spectral_part(const FaceMatrix& m, bool positive) {
  const Real3 v = to_real3(m);
  const auto [l1, l2] = eigenvalues(v);
  FaceMatrix out;
  for (double l : {l1, l2}) {
    if (positive ? !(l > 0.0) : !(l < 0.0)) continue;
    // Eigenvector of [[a, i c], [-i c, d]] for l: (i c, l - a) or (l - d, -i c).
    complex ex, ey;
    if (std::abs(l - v.a) + std::abs(v.c) >= std::abs(l - v.d) + std::abs(v.c)) {
      ex = complex(0.0, v.c);
      ey = l - v.a;
    } else {
      ex = l - v.d;
      ey = complex(0.0, -v.c);
    }
    const double norm2 = std::norm(ex) + std::norm(ey);
    if (norm2 == 0.0) {  // diagonal matrix, l = a = d or c = 0
      if (l == v.a) ex = 1.0;
      else ey = 1.0;
    }
    const double n2 = std::norm(ex) + std::norm(ey);
    out.xx += l * ex * std::conj(ex) / n2;
    out.xy += l * ex * std::conj(ey) / n2;
    out.yx += l * ey * std::conj(ex) / n2;
    out.yy += l * ey * std::conj(ey) / n2;
  }
  return out;
}

}  // namespace

FaceDiscreteModes face_discrete_modes(const ElasticMaterial& m, double height, OuterFace face,
                                      double k, double dt) {
  const double nyquist = pi / dt;
  const auto modes = face_modes(m, height, face, k, nyquist);
  FaceDiscreteModes out;
  FaceMatrix sum;
  for (const FaceMode& md : modes) {
    out.phase.push_back(std::min(md.frequency * dt, pi));
    out.weight.push_back(md.weight);
    sum = sum + md.weight;
  }
  FaceMatrix two_e_over_dt;
  two_e_over_dt.xx = 2.0 * m.shear_modulus / (m.shear_wave_speed() * dt);
  two_e_over_dt.yy = 2.0 * m.density * m.dilatational_wave_speed() / dt;
  const FaceMatrix k0 = face_stiffness(m, height, face, k, 0.0);
  const FaceMatrix target = k0 - two_e_over_dt;  // the final weights must sum to this
  const double scale = two_e_over_dt.max_abs();
  if (eigenvalues(to_real3(target)).second > 1e-12 * scale)
    throw std::runtime_error(
        "face history: the static stiffness K(k, 0) exceeds 2 E / dt at k = " + std::to_string(k) +
        " 1/m; no passive operator of this form exists: refine the time step (time.beta)");
  // truncated = target - sum W_m: the static stiffness of the modes above Nyquist.
  // Final weights W'_m = (1 - t_m) W_m, t_m in [0, 1] (a rank-one W_m <= 0 can only
  // be reduced along itself), plus one Nyquist element W_N = truncated - sum t_m (-W_m),
  // which is passive iff it is <= 0.  So: raise t_m until truncated <= sum t_m (-W_m).
  // A solution exists once target <= 0 (checked above): t_m = 1 for every mode
  // leaves W_N = target.  Every mode below Nyquist is a candidate: their count
  // grows like H/dx and each weight falls like 1/H, so a fixed number of top modes
  // cannot hold the positive part in a tall body (at H/dx = 128, beta = 0.25, the
  // 64 highest modes together carry 6.3e11 Pa/m of xx stiffness against 8.7e11 of
  // positive part at the Nyquist wavenumber; the default material).  Each round
  // takes the top eigenpair (lambda, e) of the remainder and lowers e^H R e to zero
  // with the highest-phase mode (those nearest Nyquist stand for the truncated ones
  // best) whose direction is within 90 % of the best alignment with e, as far as
  // its room allows.  (The rounds are a heuristic: they stop when no mode with
  // room is aligned with e, or at the round limit.  Over plane strain and stress,
  // nu = 0.2-0.45, both outer faces, H/dx = 2-300 and beta = 0.1-0.4 they never
  // stopped short of R <= 0; the error below would say so.)
  const FaceMatrix truncated = target - sum;
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < modes.size(); ++i) order.push_back(i);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return out.phase[a] > out.phase[b]; });
  std::vector<double> t(order.size(), 0.0);
  FaceMatrix remainder = truncated;
  // Each round either uses up a mode's room or zeroes e^H R e: a few rounds per
  // mode used in practice (at most ~230 at H/dx = 512); the limit only bounds the
  // work (4096 as with the 64-mode cap, more when there are over 1000 modes).
  const std::size_t max_rounds = std::max<std::size_t>(4096, 4 * order.size() + 64);
  for (std::size_t round = 0; round < max_rounds; ++round) {
    const FaceMatrix pos = spectral_part(remainder, true);
    const Real3 p = to_real3(pos);
    const double lambda = p.a + p.d;  // trace = the positive eigenvalue (rank <= 2; see below)
    if (!(lambda > 1e-13 * scale)) break;
    // Unit top eigenvector of the remainder from its positive part (largest eigenvalue).
    const Real3 r = to_real3(remainder);
    const double top = eigenvalues(r).second;
    complex ex(0.0, r.c), ey(top - r.a, 0.0);
    if (std::norm(ex) + std::norm(ey) < 1e-30 * top * top) {
      ex = top - r.d;
      ey = complex(0.0, -r.c);
    }
    const double n = std::sqrt(std::norm(ex) + std::norm(ey));
    ex /= n;
    ey /= n;
    const auto along = [&](const FaceMatrix& g) {  // e^H g e
      return (std::conj(ex) * (g.xx * ex + g.xy * ey) + std::conj(ey) * (g.yx * ex + g.yy * ey)).real();
    };
    double best = 0.0;
    for (std::size_t i = 0; i < order.size(); ++i) {
      const FaceMatrix& w = out.weight[order[i]];
      const double tr = -(w.xx + w.yy).real();
      if (t[i] < 1.0 && tr > 0.0) best = std::max(best, -along(w) / tr);
    }
    if (best <= 0.0) break;
    bool moved = false;
    for (std::size_t i = 0; i < order.size() && !moved; ++i) {
      const FaceMatrix& w = out.weight[order[i]];
      const double tr = -(w.xx + w.yy).real();
      if (!(t[i] < 1.0 && tr > 0.0) || -along(w) / tr < 0.9 * best) continue;
      const double step = std::min(1.0 - t[i], top / -along(w));
      t[i] += step;
      remainder = remainder + complex(step) * w;  // R = truncated - sum t (-W)
      moved = true;
    }
    if (!moved) break;
  }
  if (eigenvalues(to_real3(remainder)).second > 1e-12 * scale)
    throw std::runtime_error("face history: cannot place the truncated static stiffness passively at k = " +
                             std::to_string(k) + " 1/m; refine the time step (time.beta)");
  for (std::size_t i = 0; i < order.size(); ++i)
    out.weight[order[i]] = complex(1.0 - t[i]) * out.weight[order[i]];
  // The Nyquist element (kernel 1 - (-1)^j): the remainder's negative part (its
  // positive part is below 1e-12 of 2E/dt: rounding, dropped).
  const FaceMatrix nyquist_element = spectral_part(remainder, false);
  if (nyquist_element.max_abs() > 0.0) {
    out.phase.push_back(pi);
    out.weight.push_back(nyquist_element);
  }
  return out;
}

namespace {
std::vector<double> interface_wavenumbers(double length, int nodes) {
  std::vector<double> k(static_cast<std::size_t>(nodes / 2 + 1));
  for (std::size_t q = 0; q < k.size(); ++q) k[q] = 2.0 * pi * static_cast<int>(q) / length;
  return k;
}
}  // namespace

FaceModalHistory::FaceModalHistory(const ElasticMaterial& m, double height, OuterFace face, double length,
                                   int nodes, double time_step)
    : FaceModalHistory(m, height, face, interface_wavenumbers(length, nodes), time_step) {}

FaceModalHistory::FaceModalHistory(const ElasticMaterial& m, double height, OuterFace face,
                                   std::span<const double> wavenumbers, double time_step)
    : dt_(time_step),
      impedance_x_(m.shear_modulus / m.shear_wave_speed()),
      impedance_y_(m.density * m.dilatational_wave_speed()) {
  const int n_modes = static_cast<int>(wavenumbers.size());
  if (n_modes < 1) throw std::invalid_argument("FaceModalHistory: needs at least one wavenumber");
  first_.assign(1, 0);
  // The design of each distinct |k| (the modes +-kz of a 2D interface share it).
  std::map<double, int> designed;
  for (int q = 0; q < n_modes; ++q) {
    const auto known = designed.find(wavenumbers[q]);
    if (known != designed.end()) {
      // The stored values of the earlier mode (copies: push_back may reallocate).
      const std::size_t from = first_[known->second], count = first_[known->second + 1] - from;
      for (std::size_t i = 0; i < count; ++i) {
        const double c = cos_[from + i], s = sin_[from + i];
        const FaceMatrix w = weight_[from + i];
        cos_.push_back(c);
        sin_.push_back(s);
        weight_.push_back(w);
      }
      const FaceMatrix sum = weight_sum_[known->second];
      weight_sum_.push_back(sum);
      first_.push_back(weight_.size());
      continue;
    }
    designed.emplace(wavenumbers[q], q);
    const FaceDiscreteModes d = face_discrete_modes(m, height, face, wavenumbers[q], dt_);
    FaceMatrix sum;
    for (std::size_t i = 0; i < d.phase.size(); ++i) {
      cos_.push_back(std::cos(d.phase[i]));
      sin_.push_back(std::sin(d.phase[i]));
      weight_.push_back(d.weight[i]);
      sum = sum + d.weight[i];
    }
    weight_sum_.push_back(sum);
    first_.push_back(weight_.size());
  }
  cx_.assign(weight_.size(), 0.0);
  sx_ = cy_ = sy_ = cx_;
  running_x_.assign(n_modes, 0.0);
  running_y_ = history_x_ = history_y_ = running_x_;
}

FaceDiscreteModes FaceModalHistory::mode(int q) const {
  FaceDiscreteModes d;
  for (std::size_t i = first_[q]; i < first_[q + 1]; ++i) {
    d.phase.push_back(std::atan2(sin_[i], cos_[i]));
    d.weight.push_back(weight_[i]);
  }
  return d;
}

void FaceModalHistory::push(std::span<const complex> vx, std::span<const complex> vy) {
  const int n_modes = modes();
  for (int q = 0; q < n_modes; ++q) {
    const complex ux = vx[q], uy = vy[q];
    complex acc_x = 0.0, acc_y = 0.0;
    for (std::size_t i = first_[q]; i < first_[q + 1]; ++i) {
      // [C; S] <- rotation(phi) [C + v; S], per input component.
      const double c = cos_[i], s = sin_[i];
      const complex x = cx_[i] + ux, y = cy_[i] + uy;
      cx_[i] = c * x - s * sx_[i];
      sx_[i] = s * x + c * sx_[i];
      cy_[i] = c * y - s * sy_[i];
      sy_[i] = s * y + c * sy_[i];
      const FaceMatrix& w = weight_[i];
      acc_x += w.xx * cx_[i] + w.xy * cy_[i];
      acc_y += w.yx * cx_[i] + w.yy * cy_[i];
    }
    running_x_[q] += ux;
    running_y_[q] += uy;
    const FaceMatrix& ws = weight_sum_[q];
    history_x_[q] = 2.0 * impedance_x_ * running_x_[q] +
                    dt_ * (ws.xx * running_x_[q] + ws.xy * running_y_[q] - acc_x);
    history_y_[q] = 2.0 * impedance_y_ * running_y_[q] +
                    dt_ * (ws.yx * running_x_[q] + ws.yy * running_y_[q] - acc_y);
  }
}

void FaceModalHistory::save_into(HistoryOperatorState& state, const std::string& prefix) const {
  state.add(prefix + "cx", cx_);
  state.add(prefix + "sx", sx_);
  state.add(prefix + "cy", cy_);
  state.add(prefix + "sy", sy_);
  state.add(prefix + "running_x", running_x_);
  state.add(prefix + "running_y", running_y_);
  state.add(prefix + "history_x", history_x_);
  state.add(prefix + "history_y", history_y_);
}

void FaceModalHistory::restore_from(const HistoryOperatorState& state, const std::string& prefix) {
  state.copy_to(prefix + "cx", std::span<complex>(cx_));
  state.copy_to(prefix + "sx", std::span<complex>(sx_));
  state.copy_to(prefix + "cy", std::span<complex>(cy_));
  state.copy_to(prefix + "sy", std::span<complex>(sy_));
  state.copy_to(prefix + "running_x", std::span<complex>(running_x_));
  state.copy_to(prefix + "running_y", std::span<complex>(running_y_));
  state.copy_to(prefix + "history_x", std::span<complex>(history_x_));
  state.copy_to(prefix + "history_y", std::span<complex>(history_y_));
}

void FaceModalHistory::state_layout_into(HistoryStateLayout& layout, const std::string& prefix) const {
  const std::size_t n = history_x_.size();
  for (const char* name : {"cx", "sx", "cy", "sy"}) layout.add(prefix + name, first_, 2);
  for (const char* name : {"running_x", "running_y", "history_x", "history_y"}) layout.add_uniform(prefix + name, n, 2);
}

std::size_t FaceModalHistory::memory_bytes() const {
  return sizeof(complex) * (4 * cx_.size() + 4 * running_x_.size()) +
         sizeof(double) * (cos_.size() + sin_.size()) + sizeof(FaceMatrix) * (weight_.size() + weight_sum_.size()) +
         sizeof(std::size_t) * first_.size();
}

}  // namespace slipstrip
