#include "kernels/face_half_space.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <type_traits>

#include "kernels/mode_parallel.hpp"
#include "kernels/passivity.hpp"
#include "kernels/slow_block.hpp"

namespace slipstrip {
namespace {

using complex = std::complex<double>;
constexpr double pi = std::numbers::pi;

// A, B, D through the roots (so that the cut integration can continue them).
complex entry_of_roots(double r2, FaceEntry entry, complex a, complex d) {
  const complex R = r2 * a + d;
  switch (entry) {
    case FaceEntry::shear: return d * (a + d) / R;
    case FaceEntry::coupling: return ((2.0 * r2 - 1.0) * a + d) / R;
    case FaceEntry::normal: return a * (a + d) / R;
  }
  return 0.0;
}

// G_e = entry / p - E'_e, E' = diag(1, 1/r).
double instantaneous_of(double r2, FaceEntry entry) {
  switch (entry) {
    case FaceEntry::shear: return 1.0;
    case FaceEntry::coupling: return 0.0;
    case FaceEntry::normal: return 1.0 / std::sqrt(r2);
  }
  return 0.0;
}

complex history_of_roots(double r2, FaceEntry entry, complex p, complex a, complex d) {
  return entry_of_roots(r2, entry, a, d) / p - instantaneous_of(r2, entry);
}

std::size_t index_of(FaceEntry e) { return static_cast<std::size_t>(e); }

// Design constants (as kernels/half_space_design.cpp): Gauss-Legendre nodes per
// panel of the near-field sums (evaluated at every stored lag) and of the far
// field's exponentials (whose count sets the cost per step); a far exponential
// whose weight at the first far lag is below kNegligibleAmplitude (units of the
// kernel, which is O(1) there) is dropped.
constexpr int kNearNodesPerPanel = 10;
constexpr int kFarNodesPerPanel = 8;
constexpr double kNegligibleAmplitude = 1e-17;
constexpr double kWindowSlack = 1e-12;
// Passivity grid (passivity_phases): 2048 phases over (0, pi], 2048 across the band
// up to 2.5 times the P-wave frequency (lossless below c_s k, where aliasing
// makes the sampled kernel dip), 64 on each side of each branch point.
constexpr int kCircleThetas = 2048, kBandThetas = 2048, kClusterThetas = 64;
// Cutting-plane rounds of the passivity correction, and the margin each new
// constraint asks for above `margin` (so that the next round's eigenvectors,
// which move with the corrections, still clear it).
constexpr int kCorrectionRounds = 40;
constexpr double kMarginSlack = 0.5;
// The smallest eigenvalue asked for on the grid, in units of mu/c_s.  Between
// the SV and P frequencies the exact Hermitian part is rank one and the
// corrected one dips between grid phases by up to ~2e-7 (measured on a 10 times
// finer grid), so the grid margin is 1e-6 (the scalar operator's 1e-9 does not
// cover it): an added damping of 1e-6 of the radiation impedance at most.
constexpr double kMatrixPassivityMargin = 1e-6;

// Re of the three entries' symbols (units mu/c_s) at theta, from the mode's
// coefficients: E' + static (Re sum_{j>=1} e^{-ij theta} = -1/2) + stored lags +
// the exponentials' geometric series.
struct ModeDesign {
  double h = 0.0;
  int window = 0;
  std::array<double, 3> static_value{};          // units mu/c_s (h g(inf))
  std::array<std::vector<double>, 3> lag;         // units mu/c_s, j = 1..W
  std::vector<complex> pole;
  std::vector<complex> rate;                      // pole = e^{rate h} (rate in units c_s |k|)
  std::array<std::vector<complex>, 3> weight;     // units mu/c_s
};

// The phases where passivity is imposed: a uniform grid over (0, pi], a finer
// one across the band up to 2.5 times the P-wave frequency, and geometric
// clusters on both sides of the branch points theta = h and h / r (shear and P
// frequencies), where Re Z_d has square-root kinks and its minima sit.
// For the combined pair (FaceKernelShape::pair) the same with every branch
// point's frequency b h and the band up to 2.5 times the highest.
std::vector<double> passivity_phases(double h, const FaceKernelShape& shape) {
  std::vector<double> thetas;
  for (int i = 1; i <= kCircleThetas; ++i) thetas.push_back(pi * i / kCircleThetas);
  std::vector<double> branch_frequencies;
  if (!shape.pair) {
    branch_frequencies = {h, h / std::sqrt(shape.r2)};
  } else {
    for (double b : shape.heights) branch_frequencies.push_back(b * h);
  }
  // (One body: written as it always was, so its grid is the same to the bit.)
  const double band = std::min(pi, shape.pair ? 2.5 * branch_frequencies.back() : 2.5 * h / std::sqrt(shape.r2));
  for (int i = 1; i <= kBandThetas; ++i) thetas.push_back(band * (i - 0.5) / kBandThetas);
  for (double b : branch_frequencies)
    for (int i = 0; i < kClusterThetas; ++i) {
      const double offset = b * std::pow(10.0, -8.0 + 7.7 * i / (kClusterThetas - 1));  // 1e-8 b .. 0.5 b
      for (double theta : {b - offset, b + offset})
        if (theta > 0.0 && theta <= pi) thetas.push_back(theta);
    }
  return thetas;
}

// The three entries' symbols Z_d(theta) (units mu/c_s) at every phase of
// `thetas`, from the mode's coefficients: E' + static (sum_{j>=1} e^{-ij theta}
// = rotation / (1 - rotation)) + stored lags + the exponentials' geometric
// series.  The set-up evaluates this for every exponential at thousands of
// phases per mode, so the loops run over the phases innermost (they vectorise)
// and a / (1 - a) is written out, (Re a - |a|^2 + i Im a) / |1 - a|^2, instead
// of the library's complex division with its overflow handling.
std::vector<std::array<complex, 3>> symbols_of(const ModeDesign& m, const FaceKernelShape& shape,
                                               std::span<const double> thetas) {
  const std::size_t n = thetas.size();
  std::vector<double> c(n), s(n);  // rotation e^{-i theta} = c - i s
  for (std::size_t t = 0; t < n; ++t) {
    c[t] = std::cos(thetas[t]);
    s[t] = std::sin(thetas[t]);
  }
  // Stored lags: power = e^{-i j theta} by recursion, j = 1..W.
  std::vector<double> power_re(n, 1.0), power_im(n, 0.0);
  std::array<std::vector<double>, 3> near_re, near_im, far_re, far_im;
  for (std::size_t i = 0; i < 3; ++i) {
    near_re[i].assign(n, 0.0);
    near_im[i].assign(n, 0.0);
    far_re[i].assign(n, 0.0);
    far_im[i].assign(n, 0.0);
  }
  for (int j = 1; j <= m.window; ++j) {
    for (std::size_t t = 0; t < n; ++t) {
      const double re = power_re[t] * c[t] + power_im[t] * s[t];
      power_im[t] = power_im[t] * c[t] - power_re[t] * s[t];
      power_re[t] = re;
    }
    for (std::size_t i = 0; i < 3; ++i) {
      const double lag = m.lag[i][j - 1];
      double* nr = near_re[i].data();
      double* ni = near_im[i].data();
#pragma omp simd
      for (std::size_t t = 0; t < n; ++t) {
        nr[t] += lag * power_re[t];
        ni[t] += lag * power_im[t];
      }
    }
  }
  // Exponentials: w a / (1 - a) + conj(w) b / (1 - b), a = z e^{-i theta}, b = conj(z) e^{-i theta}.
  for (std::size_t k = 0; k < m.pole.size(); ++k) {
    const double zr = m.pole[k].real(), zi = m.pole[k].imag();
    double wr[3], wi[3];
    for (std::size_t i = 0; i < 3; ++i) {
      wr[i] = m.weight[i][k].real();
      wi[i] = m.weight[i][k].imag();
    }
    double *fr0 = far_re[0].data(), *fr1 = far_re[1].data(), *fr2 = far_re[2].data();
    double *fi0 = far_im[0].data(), *fi1 = far_im[1].data(), *fi2 = far_im[2].data();
    const double *ct = c.data(), *st = s.data();
#pragma omp simd
    for (std::size_t t = 0; t < n; ++t) {
      const double ar = zr * ct[t] + zi * st[t], ai = zi * ct[t] - zr * st[t];
      const double br = zr * ct[t] - zi * st[t], bi = -zi * ct[t] - zr * st[t];
      const double sa = 1.0 / ((1.0 - ar) * (1.0 - ar) + ai * ai), sb = 1.0 / ((1.0 - br) * (1.0 - br) + bi * bi);
      const double gar = (ar - (ar * ar + ai * ai)) * sa, gai = ai * sa;
      const double gbr = (br - (br * br + bi * bi)) * sb, gbi = bi * sb;
      // w ga + conj(w) gb.
      const double sum_re = gar + gbr, dif_re = gar - gbr, sum_im = gai + gbi, dif_im = gai - gbi;
      fr0[t] += wr[0] * sum_re - wi[0] * dif_im;
      fi0[t] += wr[0] * sum_im + wi[0] * dif_re;
      fr1[t] += wr[1] * sum_re - wi[1] * dif_im;
      fi1[t] += wr[1] * sum_im + wi[1] * dif_re;
      fr2[t] += wr[2] * sum_re - wi[2] * dif_im;
      fi2[t] += wr[2] * sum_im + wi[2] * dif_re;
    }
  }
  std::vector<std::array<complex, 3>> z(n);
  for (std::size_t t = 0; t < n; ++t) {
    const complex rotation(c[t], -s[t]), power(power_re[t], power_im[t]);
    const complex static_sum = rotation / (1.0 - rotation);
    for (FaceEntry e : kFaceEntries) {
      const std::size_t i = index_of(e);
      // One body: the sum written as it always was (its constants E' let the
      // compiler fuse it differently, and the corrections' bits follow).
      if (!shape.pair)
        z[t][i] = instantaneous_of(shape.r2, e) + m.static_value[i] * static_sum +
                  complex(near_re[i][t], near_im[i][t]) + power * complex(far_re[i][t], far_im[i][t]);
      else
        z[t][i] = shape.instantaneous[i] + m.static_value[i] * static_sum + complex(near_re[i][t], near_im[i][t]) +
                  power * complex(far_re[i][t], far_im[i][t]);
    }
  }
  return z;
}

// The smallest corrections of the first `lags` weights of each entry (units
// mu/c_s) that make the real matrix M = [[Re Z_A, Re Z_B], [Re Z_B, Re Z_D]]
// have both eigenvalues >= margin at every grid phase: the Hermitian part of
// Z_d = [[Z_A, -i Z_B], [i Z_B, Z_D]] is diag(1, i) M diag(1, -i), so the two
// are positive semidefinite together.  w^T M w >= margin is linear in the
// corrections for a fixed direction w; between the shear and P frequencies the
// exact M is rank one (only the SV wave radiates), so the binding direction is
// sharp and a fixed set of directions would not do.  Cutting planes: each round
// adds, at every phase where the corrected M has an eigenvalue below the
// margin, the constraint along that eigenvector, and solves the minimum-norm
// problem on all constraints so far.
//
// The combined pair's M also touches singularity at isolated frequencies
// (between the branch frequencies of the two bodies), in parabolic minima
// narrow enough to dip below zero between the uniform phases (measured:
// -2.7e-5 mu_ref/c_ref, strong contrast, h = 0.2): for the pair each local
// minimum of M's smallest eigenvalue on the uniform grids gets 16 more phases
// across its two neighbouring intervals.
std::vector<double> passivity_correction(const ModeDesign& m, const FaceKernelShape& shape, int lags, double margin) {
  std::vector<double> thetas = passivity_phases(m.h, shape);
  std::vector<std::array<double, 3>> base;  // Re Z_A, Re Z_B, Re Z_D uncorrected
  for (const auto& z : symbols_of(m, shape, thetas)) base.push_back({z[0].real(), z[1].real(), z[2].real()});
  if (shape.pair) {
    const auto lowest_of = [](const std::array<double, 3>& re) {
      return 0.5 * (re[0] + re[2]) - std::hypot(0.5 * (re[0] - re[2]), re[1]);
    };
    std::vector<double> extra;
    // The circle's phases [0, kCircleThetas), then the band's.
    for (const auto& [first, count] : {std::pair<std::size_t, std::size_t>{0, kCircleThetas},
                                      std::pair<std::size_t, std::size_t>{kCircleThetas, kBandThetas}})
      for (std::size_t i = first + 1; i + 1 < first + count; ++i) {
        const double here = lowest_of(base[i]);
        if (here > lowest_of(base[i - 1]) || here > lowest_of(base[i + 1])) continue;
        const double spacing = thetas[i + 1] - thetas[i];
        for (int j = -8; j <= 8; ++j)
          if (j != 0) {
            const double theta = thetas[i] + spacing * j / 8.0;
            if (theta > 0.0 && theta <= pi) extra.push_back(theta);
          }
      }
    if (!extra.empty()) {
      for (const auto& z : symbols_of(m, shape, extra)) base.push_back({z[0].real(), z[1].real(), z[2].real()});
      thetas.insert(thetas.end(), extra.begin(), extra.end());
    }
  }
  const int n = 3 * lags;
  // cos(j theta) of every grid phase, computed once for all rounds and entries.
  std::vector<double> cosine(thetas.size() * lags);
  for (std::size_t t = 0; t < thetas.size(); ++t)
    for (int j = 1; j <= lags; ++j) cosine[t * lags + j - 1] = std::cos(j * thetas[t]);
  std::vector<double> rows, rhs, x(n, 0.0);
  for (int round = 0; round < kCorrectionRounds; ++round) {
    bool added = false;
    for (std::size_t t = 0; t < thetas.size(); ++t) {
      std::array<double, 3> re = base[t];
      const double* cos_t = cosine.data() + t * lags;
      for (int e = 0; e < 3; ++e)
        for (int j = 1; j <= lags; ++j) re[e] += x[e * lags + j - 1] * cos_t[j - 1];
      // Smallest eigenvalue of [[a, b], [b, d]] and its eigenvector (cos phi, sin phi).
      const double a = re[0], b = re[1], d = re[2];
      const double lowest = 0.5 * (a + d) - std::hypot(0.5 * (a - d), b);
      if (lowest >= margin) continue;
      const double phi = 0.5 * std::atan2(2.0 * b, a - d) + 0.5 * pi;
      const double c = std::cos(phi), sn = std::sin(phi);
      const double weights[3] = {c * c, 2.0 * c * sn, sn * sn};
      for (int e = 0; e < 3; ++e)
        for (int j = 1; j <= lags; ++j) rows.push_back(weights[e] * cos_t[j - 1]);
      rhs.push_back(margin * (1.0 + kMarginSlack) -
                    (weights[0] * base[t][0] + weights[1] * base[t][1] + weights[2] * base[t][2]));
      added = true;
    }
    if (!added) return x;
    x = minimum_norm_point(rows, rhs, n);
  }
  throw std::runtime_error("the passivity correction did not settle in " + std::to_string(kCorrectionRounds) +
                           " rounds");
}

// The entries' exponential sums: near field over [h_min, 2 tau_near_max + 1]
// (evaluated at every stored lag), far field over [near_field_tau, horizon_tau].
struct EntrySums {
  std::array<ExponentialSum, 3> near, far;
};

EntrySums entry_sums(const FaceKernelShape& shape, double h_min, double tau_near_max,
                     const HalfSpaceOperatorDesign& design) {
  EntrySums sums;
  if (shape.pair) {
    sums.near = half_space_pair_exponential_sums(shape.pair_shape, h_min, 2.0 * tau_near_max + 1.0, kNearNodesPerPanel);
    sums.far =
        half_space_pair_exponential_sums(shape.pair_shape, design.near_field_tau, design.horizon_tau, kFarNodesPerPanel);
    return sums;
  }
  const double r2 = shape.r2;
  for (FaceEntry e : kFaceEntries) {
    sums.near[index_of(e)] = half_space_face_exponential_sum(r2, e, h_min, 2.0 * tau_near_max + 1.0, kNearNodesPerPanel);
    sums.far[index_of(e)] =
        half_space_face_exponential_sum(r2, e, design.near_field_tau, design.horizon_tau, kFarNodesPerPanel);
  }
  return sums;
}

// One mode's design at h = c_s |k| dt with `window` stored lags, before its
// passivity correction.
ModeDesign design_mode(const FaceKernelShape& shape, double h, int window, const EntrySums& sums) {
  ModeDesign m;
  m.h = h;
  m.window = window;
  for (FaceEntry e : kFaceEntries) {
    const std::size_t i = index_of(e);
    m.static_value[i] = h * sums.far[i].static_value;
    m.lag[i].resize(m.window);
    for (int j = 1; j <= m.window; ++j) m.lag[i][j - 1] = h * (evaluate(sums.near[i], j * h) - sums.near[i].static_value);
  }
  // The coupling's step: its trapezoidal half weight at j = 0 moves to j = 1.
  m.lag[1][0] += 0.5 * h * shape.coupling_initial;
  const double shift = m.window * h;
  for (std::size_t k = 0; k < sums.far[0].rate.size(); ++k) {
    std::array<complex, 3> w;
    double largest = 0.0;
    for (std::size_t i = 0; i < 3; ++i) {
      w[i] = h * sums.far[i].amplitude[k] * std::exp(sums.far[i].rate[k] * shift);
      largest = std::max(largest, std::abs(w[i]));
    }
    if (largest < kNegligibleAmplitude) continue;
    m.pole.push_back(std::exp(sums.far[0].rate[k] * h));
    m.rate.push_back(sums.far[0].rate[k]);
    for (std::size_t i = 0; i < 3; ++i) m.weight[i].push_back(w[i]);
  }
  return m;
}

FaceKernelShape one_body_shape(double r2) {
  FaceKernelShape shape;
  shape.r2 = r2;
  for (FaceEntry e : kFaceEntries) shape.instantaneous[index_of(e)] = instantaneous_of(r2, e);
  shape.coupling_initial = half_space_face_initial_value(r2, FaceEntry::coupling);
  // As the cuts of in_plane_exponential_sum (the rates' imaginary parts).
  shape.heights = {1.0, 1.0 / std::sqrt(r2)};
  return shape;
}

int window_of(double h, const HalfSpaceOperatorDesign& design) {
  return std::max(design.corrected_lags, static_cast<int>(std::ceil(design.near_field_tau / h - kWindowSlack)));
}

}  // namespace

complex half_space_face_entry(double r2, FaceEntry entry, complex p) {
  const complex a = std::sqrt(1.0 + p * p), d = std::sqrt(1.0 + r2 * (p * p));
  return entry_of_roots(r2, entry, a, d);
}

FaceMatrix half_space_face_stiffness(const ElasticMaterial& material, double k, complex s) {
  const double mu = material.shear_modulus, cs = material.shear_wave_speed();
  const double r2 = 1.0 / material.wave_speed_ratio_squared();
  FaceMatrix out;
  if (k == 0.0) {
    out.xx = mu * s / cs;
    out.yy = mu * s / (cs * std::sqrt(r2));
    return out;
  }
  const double ak = std::abs(k);
  const complex p = s / (cs * ak);
  const complex i(0.0, 1.0);
  out.xx = mu * ak * half_space_face_entry(r2, FaceEntry::shear, p);
  out.yy = mu * ak * half_space_face_entry(r2, FaceEntry::normal, p);
  out.xy = -i * k * mu * half_space_face_entry(r2, FaceEntry::coupling, p);
  out.yx = -out.xy;
  return out;
}

complex half_space_face_history_transform(double r2, FaceEntry entry, complex p) {
  const complex a = std::sqrt(1.0 + p * p), d = std::sqrt(1.0 + r2 * (p * p));
  return history_of_roots(r2, entry, p, a, d);
}

double half_space_face_static_value(double r2, FaceEntry entry) {
  return entry_of_roots(r2, entry, 1.0, 1.0).real();
}

double half_space_face_initial_value(double r2, FaceEntry entry) {
  return entry == FaceEntry::coupling ? (2.0 * std::sqrt(r2) - 1.0) / std::sqrt(r2) : 0.0;
}

ExponentialSum half_space_face_exponential_sum(double r2, FaceEntry entry, double tau_min, double tau_max,
                                               int nodes_per_panel) {
  return in_plane_exponential_sum(
      r2, half_space_face_static_value(r2, entry),
      [r2, entry](complex p, complex a, complex d) { return history_of_roots(r2, entry, p, a, d); }, tau_min,
      tau_max, nodes_per_panel);
}

namespace {
// A value for an error message, at the default stream precision (6 digits).
std::string number_text(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}
}  // namespace

bool face_half_space_mode_passive(double r2, const HalfSpaceOperatorDesign& design, double h) {
  if (!(h > 0.0)) throw std::invalid_argument("face_half_space_mode_passive: need h > 0, got " + number_text(h));
  const double margin = std::max(design.passivity_margin, kMatrixPassivityMargin);
  const int window = window_of(h, design);
  const FaceKernelShape shape = one_body_shape(r2);
  const ModeDesign m = design_mode(shape, h, window, entry_sums(shape, h, window * h, design));
  try {
    (void)passivity_correction(m, shape, design.corrected_lags, margin);
    return true;
  } catch (const std::exception&) {
    return false;
  }
}

double face_half_space_passive_limit(double r2, const HalfSpaceOperatorDesign& design, double failed) {
  if (!(failed > 0.0))
    throw std::invalid_argument("face_half_space_passive_limit: need failed > 0, got " + number_text(failed));
  const auto passive = [&](double h) { return face_half_space_mode_passive(r2, design, h); };
  double hi = failed, lo = 0.5 * failed;
  while (!passive(lo)) {
    hi = lo;
    lo *= 0.5;
    if (lo < 1e-3 * failed) return 0.0;
  }
  while (hi - lo > 1e-3 * hi) {
    const double mid = 0.5 * (lo + hi);
    (passive(mid) ? lo : hi) = mid;
  }
  return lo;
}

namespace {
std::vector<double> line_wavenumbers(double length, int nodes, double time_step) {
  if (!(time_step > 0.0) || nodes < 2 || !(length > 0.0))
    throw std::invalid_argument("FaceHalfSpaceHistory: need time_step > 0, nodes >= 2, length > 0; got time_step = " +
                                number_text(time_step) + " s, nodes = " + std::to_string(nodes) +
                                ", length = " + number_text(length) + " m");
  std::vector<double> k(static_cast<std::size_t>(nodes / 2 + 1));
  for (int q = 0; q < static_cast<int>(k.size()); ++q) k[q] = 2.0 * pi * q / length;
  return k;
}
}  // namespace

FaceHalfSpaceHistory::FaceHalfSpaceHistory(const ElasticMaterial& material, double length, int nodes,
                                           double time_step, const HalfSpaceOperatorDesign& design,
                                           const CancelCheck& cancelled)
    : FaceHalfSpaceHistory(material, line_wavenumbers(length, nodes, time_step), time_step, design, cancelled) {}

namespace {
FaceKernelShape body_kernel_shape(const ElasticMaterial& material) {
  if (material.antiplane())
    throw std::invalid_argument("FaceHalfSpaceHistory: the in-plane 2x2 operator needs an in-plane material");
  return one_body_shape(1.0 / material.wave_speed_ratio_squared());
}

FaceKernelShape pair_kernel_shape(const ElasticMaterial& top, const ElasticMaterial& bottom) {
  if (top.antiplane() || bottom.antiplane())
    throw std::invalid_argument("FaceHalfSpaceHistory: the combined pair operator needs two in-plane materials");
  FaceKernelShape shape;
  shape.pair = true;
  shape.pair_shape = half_space_pair_shape(top, bottom);
  const auto e = half_space_pair_impedances(shape.pair_shape);
  shape.instantaneous = {e[0], 0.0, e[1]};
  shape.coupling_initial = half_space_pair_initial_values(shape.pair_shape)[1];
  shape.heights = shape.pair_shape.branch_heights;
  // The kernels are universal functions of tau for the pair: the check that
  // no pole was missed runs once, before any mode is designed.
  verify_half_space_pair_sums(shape.pair_shape);
  return shape;
}

double reference_unit(const ElasticMaterial& top, const ElasticMaterial& bottom) {
  const ElasticMaterial& ref = bottom.shear_wave_speed() < top.shear_wave_speed() ? bottom : top;
  return ref.shear_modulus / ref.shear_wave_speed();
}
}  // namespace

FaceHalfSpaceHistory::FaceHalfSpaceHistory(const ElasticMaterial& material, std::span<const double> wavenumbers,
                                           double time_step, const HalfSpaceOperatorDesign& design,
                                           const CancelCheck& cancelled)
    : FaceHalfSpaceHistory(body_kernel_shape(material), material.shear_modulus / material.shear_wave_speed(),
                           material.shear_wave_speed(), wavenumbers, time_step, design, cancelled) {}

FaceHalfSpaceHistory::FaceHalfSpaceHistory(const ElasticMaterial& top, const ElasticMaterial& bottom, double length,
                                           int nodes, double time_step, const HalfSpaceOperatorDesign& design,
                                           const CancelCheck& cancelled)
    : FaceHalfSpaceHistory(pair_kernel_shape(top, bottom), reference_unit(top, bottom),
                           std::min(top.shear_wave_speed(), bottom.shear_wave_speed()),
                           line_wavenumbers(length, nodes, time_step), time_step, design, cancelled) {}

FaceHalfSpaceHistory::FaceHalfSpaceHistory(FaceKernelShape shape, double unit, double cs,
                                           std::span<const double> wavenumbers, double time_step,
                                           const HalfSpaceOperatorDesign& design, const CancelCheck& cancelled)
    : shape_(std::move(shape)), dt_(time_step), lags_(design.corrected_lags) {
  if (!(time_step > 0.0))
    throw std::invalid_argument("FaceHalfSpaceHistory: need time_step > 0, got " + number_text(time_step) + " s");
  if (wavenumbers.size() < 2 || wavenumbers[0] != 0.0)
    throw std::invalid_argument("FaceHalfSpaceHistory: need at least two modes, the uniform mode 0 (|k| = 0) "
                                "first; got " + std::to_string(wavenumbers.size()) + " modes" +
                                (wavenumbers.empty() ? std::string()
                                                     : ", |k| = " + number_text(wavenumbers[0]) + " 1/m at mode 0"));
  for (std::size_t q = 1; q < wavenumbers.size(); ++q)
    if (!(wavenumbers[q] > 0.0))
      throw std::invalid_argument("FaceHalfSpaceHistory: need |k| > 0 at every mode but the first; got |k| = " +
                                  number_text(wavenumbers[q]) + " 1/m at mode " + std::to_string(q));
  check_half_space_design(design);
  // One body: E' = diag(1, 1/r) in units mu/c_s; the pair: the series
  // impedances in units mu_ref/c_ref.
  unit_ = unit;
  impedance_x_ = shape_.pair ? unit * shape_.instantaneous[0] : unit;
  impedance_y_ = shape_.pair ? unit * shape_.instantaneous[2] : unit / std::sqrt(shape_.r2);
  const int n_modes = static_cast<int>(wavenumbers.size());
  wavenumber_.assign(wavenumbers.begin(), wavenumbers.end());
  h_.resize(n_modes);
  for (int q = 0; q < n_modes; ++q) h_[q] = cs * wavenumber_[q] * dt_;
  // The near-field sums span every mode's stored lags: from the smallest h
  // (mode 1 on a line, whose wavenumbers increase with q) up to the longest
  // window, widened to design.near_field_h_min and near_field_tau_max when set.
  std::vector<int> window(n_modes, 0);
  double tau_near_max = design.near_field_tau_max;
  double h_min = design.near_field_h_min > 0.0 ? design.near_field_h_min : std::numeric_limits<double>::infinity();
  for (int q = 1; q < n_modes; ++q) {
    window[q] = window_of(h_[q], design);
    tau_near_max = std::max(tau_near_max, window[q] * h_[q]);
    h_min = std::min(h_min, h_[q]);
  }
  const EntrySums sums = entry_sums(shape_, h_min, tau_near_max, design);
  // Modes of equal h (the modes +-kz of a 2D interface) share one design:
  // design_of[q] is the first mode with q's h; only those are designed.
  std::vector<int> design_of(n_modes, 0), distinct;
  {
    std::map<double, int> first_of;
    for (int q = 1; q < n_modes; ++q) {
      const auto [at, added] = first_of.emplace(h_[q], q);
      design_of[q] = at->second;
      if (added) distinct.push_back(q);
    }
  }

  // Each distinct mode's design (sampled near field, exponentials, passivity
  // correction) is independent: computed in parallel, then laid out flat for
  // the time loop.
  std::vector<ModeDesign> designs(n_modes);
  std::vector<std::vector<double>> corrections(n_modes);
  const std::string failure = for_each_mode_in_parallel(
      0, static_cast<int>(distinct.size()), cancelled, "the half-space body's operator", [&](int d) {
    const int q = distinct[d];
    ModeDesign& m = designs[q];
    m = design_mode(shape_, h_[q], window[q], sums);
    try {
      corrections[q] =
          passivity_correction(m, shape_, lags_, std::max(design.passivity_margin, kMatrixPassivityMargin));
    } catch (const std::exception& ex) {
      std::ostringstream msg;
      msg << (shape_.pair ? "combined half-space pair operator (dt = " : "half-space body operator (dt = ") << dt_ << " s, c_s k dt = " << m.h << " at mode " << q
          << "): no passive correction (" << ex.what() << "); refine the time step (time.beta)";
      throw std::invalid_argument(msg.str());
    }
  });
  if (!failure.empty()) {
    // The largest c_s k dt that failed (a failed mode has no correction).
    double failed_h = 0.0;
    for (int q : distinct)
      if (corrections[q].empty()) failed_h = std::max(failed_h, h_[q]);
    throw FaceHalfSpaceNotPassive(failure, failed_h);
  }
  for (int q = 1; q < n_modes; ++q)
    if (design_of[q] != q) {
      designs[q] = designs[design_of[q]];
      corrections[q] = corrections[design_of[q]];
    }

  static_weight_.assign(n_modes, {});
  first_lag_.assign(n_modes + 1, 0);
  first_pole_.assign(n_modes + 1, 0);
  correction_.assign(static_cast<std::size_t>(n_modes) * lags_, {});
  std::vector<complex> rates;  // of pole_, in its order
  for (int q = 1; q < n_modes; ++q) {
    ModeDesign& m = designs[q];
    const std::vector<double>& e = corrections[q];
    for (std::size_t i = 0; i < 3; ++i) {
      static_weight_[q][i] = unit * m.static_value[i];
      for (int j = 1; j <= lags_; ++j) {
        m.lag[i][j - 1] += e[i * lags_ + (j - 1)];
        correction_[(q - 1) * static_cast<std::size_t>(lags_) + (j - 1)][i] = e[i * lags_ + (j - 1)];
      }
    }
    for (int j = 1; j <= m.window; ++j) lag_weight_.push_back({unit * m.lag[0][j - 1], unit * m.lag[1][j - 1],
                                                               unit * m.lag[2][j - 1]});
    for (std::size_t k = 0; k < m.pole.size(); ++k) {
      rates.push_back(m.rate[k]);
      pole_.push_back(m.pole[k]);
      pole_weight_.push_back({unit * m.weight[0][k], unit * m.weight[1][k], unit * m.weight[2][k]});
    }
    first_lag_[q + 1] = lag_weight_.size();
    first_pole_[q + 1] = pole_.size();
  }
  first_lag_[1] = first_lag_[0] = 0;
  ring_x_.assign(lag_weight_.size(), 0.0);
  ring_y_ = ring_x_;
  running_x_.assign(n_modes, 0.0);
  running_y_ = history_x_ = history_y_ = running_x_;
  build_exponentials(rates, design);
  // The far field's batch: at most design.far_batch steps, at most the
  // shortest window (its inputs, delayed by W, must be in the ring when it
  // starts), and a divisor of the slow block (no batch straddles a block end).
  if (design.far_batch < 1) throw std::invalid_argument("FaceHalfSpaceHistory: need design.far_batch >= 1");
  std::size_t shortest = static_cast<std::size_t>(design.far_batch);
  for (int q = 1; q < n_modes; ++q) shortest = std::min(shortest, first_lag_[q + 1] - first_lag_[q]);
  batch_ = static_cast<int>(std::max<std::size_t>(shortest, 1));
  while (block_ > 0 && block_ % batch_ != 0) --batch_;
  far_batch_x_.assign(static_cast<std::size_t>(n_modes) * batch_, 0.0);
  far_batch_y_ = far_batch_x_;
  slow_batch_out_.assign(4 * static_cast<std::size_t>(batch_), 0.0);
  fast_batch_out_ = slow_batch_out_;
}

void FaceHalfSpaceHistory::build_exponentials(std::span<const complex> rates, const HalfSpaceOperatorDesign& design) {
  // Fast exponentials rotate every step; slow ones (decay over a block below
  // the Taylor radius) are advanced once per block (docs/theory.md §8.7, as
  // HalfSpaceHistory).  pole_ and pole_weight_ keep every exponential in the
  // design's order (mode_kernel, symbol).
  const std::size_t n_modes = h_.size();
  block_ = design.slow_block;
  terms_ = block_ > 0 ? design.taylor_terms : 0;
  block_centre_ = 0.5 * (block_ + 1);
  const double slow_limit = slow_decay_limit(block_, design.slow_taylor_radius);
  first_fast_.assign(n_modes + 1, 0);
  first_slow_.assign(n_modes + 1, 0);
  branches_ = shape_.heights.size();
  groups_ = (branches_ + 1) / 2;
  slow_branch_start_.assign(n_modes * (branches_ + 1), 0);
  std::vector<std::size_t> branch_count(branches_);
  slow_lag_weight_.assign(n_modes * 3 * static_cast<std::size_t>(block_), 0.0);
  for (std::size_t q = 1; q < n_modes; ++q) {
    const double h = h_[q];
    std::fill(branch_count.begin(), branch_count.end(), 0);
    std::size_t last_branch = 0;
    for (std::size_t k = first_pole_[q]; k < first_pole_[q + 1]; ++k) {
      const std::array<complex, 3>& w = pole_weight_[k];
      const complex rate = rates[k];
      // The cut an exponential lies on: its rate's imaginary part is exactly
      // that branch height.  A pole's exponential (the pair's leaky waves) is
      // on none and rotates every step: the block rotations are per branch.
      const std::size_t branch = static_cast<std::size_t>(
          std::find(shape_.heights.begin(), shape_.heights.end(), rate.imag()) - shape_.heights.begin());
      if (-rate.real() * h > slow_limit || branch == branches_) {
        pole_re_.push_back(pole_[k].real());
        pole_im_.push_back(pole_[k].imag());
        for (std::size_t e = 0; e < 3; ++e) {
          weight_cos_[e].push_back(2.0 * w[e].real());
          weight_sin_[e].push_back(-2.0 * w[e].imag());
        }
        continue;
      }
      slow_decay_.push_back(-rate.real() * h);
      slow_centre_factor_.push_back(std::exp(rate.real() * h * block_centre_));
      slow_block_pole_.push_back(std::exp(rate * (h * block_)));
      slow_weight_.push_back(w);
      // In-block lags of each entry: 2 Re w z^{i+1}, i = 0..B-1 (the exact
      // powers), stored reversed: lag i at [e][B - 1 - i].
      double* lag = slow_lag_weight_.data() + q * 3 * block_;
      for (int i = 0; i < block_; ++i) {
        const complex power = std::exp(rate * (h * (i + 1)));
        for (std::size_t e = 0; e < 3; ++e) lag[e * block_ + (block_ - 1 - i)] += 2.0 * (w[e] * power).real();
      }
      // The sums list the cuts in the order of their heights.
      if (branch < last_branch) throw std::logic_error("FaceHalfSpaceHistory: exponentials out of branch order");
      last_branch = branch;
      ++branch_count[branch];
    }
    first_fast_[q + 1] = pole_re_.size();
    first_slow_[q + 1] = slow_decay_.size();
    std::size_t* start = slow_branch_start_.data() + q * (branches_ + 1);
    start[0] = first_slow_[q];
    for (std::size_t b = 0; b < branches_; ++b) start[b + 1] = start[b] + branch_count[b];
  }
  first_fast_[1] = first_fast_[0] = 0;
  first_slow_[1] = first_slow_[0] = 0;
  for (auto& state : far_) state.assign(pole_re_.size(), 0.0);
  // One rotation table per group of two branches, e^{i b h t'}: one body's
  // (shear, P) as the table's (1, c_d/c_s); the pair's from each group's
  // first height (a lone last branch with an unused second one).
  rotation_.clear();
  if (!shape_.pair) {
    rotation_.push_back(slow_block_rotations(h_, std::sqrt(1.0 / shape_.r2), block_));
  } else {
    for (std::size_t g = 0; g < groups_; ++g) {
      const double first = shape_.heights[2 * g];
      const double second = 2 * g + 1 < branches_ ? shape_.heights[2 * g + 1] : 2.0 * first;
      std::vector<double> scaled(h_.size());
      for (std::size_t q = 0; q < h_.size(); ++q) scaled[q] = first * h_[q];
      rotation_.push_back(slow_block_rotations(scaled, second / first, block_));
    }
  }
  for (auto& state : slow_state_) state.assign(slow_decay_.size(), 0.0);
  for (auto& input : block_input_) input.assign(n_modes * static_cast<std::size_t>(block_), 0.0);
  std::size_t most_slow = 0;
  for (std::size_t q = 1; q < n_modes; ++q) most_slow = std::max(most_slow, first_slow_[q + 1] - first_slow_[q]);
  for (auto& scratch : slow_scratch_) scratch.assign(most_slow, 0.0);
  block_moment_.assign(n_modes * groups_ * kSlowPolynomials * static_cast<std::size_t>(terms_), 0.0);
}

void FaceHalfSpaceHistory::push(std::span<const complex> velocity_x, std::span<const complex> velocity_y) {
  const complex i(0.0, 1.0);
  const std::size_t n_modes = history_x_.size();
  const int position = static_cast<int>(step_ % batch_);
  const bool batch_start = position == 0;
  // The far field of this batch reads inputs at least W >= batch steps old,
  // pushed before this step: an input v_y that turns nonzero here reaches it
  // from the next batch on, whichever way this batch was worked.
  if (!normal_active_)
    for (std::size_t q = 1; q < n_modes; ++q)
      if (velocity_y[q] != 0.0) {
        normal_active_ = true;
        break;
      }
  // q = 0: a half-space's uniform mode is pure radiation damping (no history).
  for (std::size_t q = 1; q < n_modes; ++q) {
    // Before this step's input replaces v_{n-W} in the ring.
    if (batch_start) advance_far(q, step_, 0, batch_);
    const complex vx = velocity_x[q], vy = velocity_y[q];
    const std::size_t lag0 = first_lag_[q], window = first_lag_[q + 1] - lag0;
    // The slot of v_{n-W} (the oldest stored input), which v_n replaces.
    const std::size_t slot = static_cast<std::size_t>(step_ % static_cast<long long>(window));
    ring_x_[lag0 + slot] = vx;
    ring_y_[lag0 + slot] = vy;
    running_x_[q] += vx;
    running_y_[q] += vy;
    const auto& s = static_weight_[q];
    std::array<complex, 3> from_x{s[0] * running_x_[q], s[1] * running_x_[q], 0.0};
    std::array<complex, 3> from_y{0.0, s[1] * running_y_[q], s[2] * running_y_[q]};
    // Stored lags j = 1..W: v_{n+1-j} sits at slot - (j - 1) (mod W); the
    // y ring holds zeros until the normal channel is active.
    if (normal_active_) {
      for (std::size_t j = 1; j <= window; ++j) {
        const std::size_t at = lag0 + (slot + window - (j - 1)) % window;
        const auto& w = lag_weight_[lag0 + j - 1];
        from_x[0] += w[0] * ring_x_[at];
        from_x[1] += w[1] * ring_x_[at];
        from_y[1] += w[1] * ring_y_[at];
        from_y[2] += w[2] * ring_y_[at];
      }
    } else {
      for (std::size_t j = 1; j <= window; ++j) {
        const std::size_t at = lag0 + (slot + window - (j - 1)) % window;
        const auto& w = lag_weight_[lag0 + j - 1];
        from_x[0] += w[0] * ring_x_[at];
        from_x[1] += w[1] * ring_x_[at];
      }
    }
    // [[K^0, -i K^1], [i K^1, K^2]] (k > 0), plus the lags beyond W from the batch.
    const std::size_t at = q * batch_ + position;
    history_x_[q] = from_x[0] - i * from_y[1] + far_batch_x_[at];
    history_y_[q] = i * from_x[1] + from_y[2] + far_batch_y_[at];
  }
  ++step_;
}

void FaceHalfSpaceHistory::advance_far(std::size_t q, long long batch_step, int first, int last) {
  const complex i(0.0, 1.0);
  const std::size_t ring0 = first_lag_[q], window = first_lag_[q + 1] - ring0;
  const std::size_t k0 = first_fast_[q], count = first_fast_[q + 1] - k0;
  const double *zr = pole_re_.data() + k0, *zi = pole_im_.data() + k0;
  const double *wc0 = weight_cos_[0].data() + k0, *ws0 = weight_sin_[0].data() + k0;
  const double *wc1 = weight_cos_[1].data() + k0, *ws1 = weight_sin_[1].data() + k0;
  const double *wc2 = weight_cos_[2].data() + k0, *ws2 = weight_sin_[2].data() + k0;
  double *cxr = far_[0].data() + k0, *cxi = far_[1].data() + k0, *sxr = far_[2].data() + k0,
         *sxi = far_[3].data() + k0;
  double *cyr = far_[4].data() + k0, *cyi = far_[5].data() + k0, *syr = far_[6].data() + k0,
         *syi = far_[7].data() + k0;
  if (block_ > 0) slow_batch_outputs(q, batch_step, first, last);
  if (!normal_active_) fast_batch_outputs(q, batch_step, first, last);
  for (int d = first; d < last; ++d) {
    const long long n = batch_step + d;
    // v_{n-W}, still in the ring (the batch is at most W steps long).
    const std::size_t slot = ring0 + static_cast<std::size_t>(n % static_cast<long long>(window));
    const complex old_x = ring_x_[slot], old_y = ring_y_[slot];
    // Lags W + i of the fast exponentials: kernel 2 Re(w z^i) = wc Re z^i + ws Im z^i, states
    // C = sum_i Re(z^i) v_{n+1-W-i}, S = sum_i Im(z^i) v_{n+1-W-i}:
    // [C; S] <- [[Re z, -Im z], [Im z, Re z]] [C + v_{n-W}; S], per input component.
    // After the batch's first step the mode's rows are in the cache.
    const double uxr = old_x.real(), uxi = old_x.imag(), uyr = old_y.real(), uyi = old_y.imag();
    double x0r = 0.0, x0i = 0.0, x1r = 0.0, x1i = 0.0, y1r = 0.0, y1i = 0.0, y2r = 0.0, y2i = 0.0;
    if (!normal_active_) {
      // The y states are zero and stay so: the x input's rotation and its
      // two outputs, worked for the batch by fast_batch_outputs.
      const double* fast = fast_batch_out_.data() + d;
      x0r = fast[0];
      x0i = fast[batch_];
      x1r = fast[2 * batch_];
      x1i = fast[3 * batch_];
    } else {
#pragma omp simd reduction(+ : x0r, x0i, x1r, x1i, y1r, y1i, y2r, y2i)
    for (std::size_t k = 0; k < count; ++k) {
      const double a = zr[k], b = zi[k];
      const double pxr = cxr[k] + uxr, pxi = cxi[k] + uxi, pyr = cyr[k] + uyr, pyi = cyi[k] + uyi;
      const double ncxr = a * pxr - b * sxr[k], ncxi = a * pxi - b * sxi[k];
      const double nsxr = b * pxr + a * sxr[k], nsxi = b * pxi + a * sxi[k];
      const double ncyr = a * pyr - b * syr[k], ncyi = a * pyi - b * syi[k];
      const double nsyr = b * pyr + a * syr[k], nsyi = b * pyi + a * syi[k];
      cxr[k] = ncxr;
      cxi[k] = ncxi;
      sxr[k] = nsxr;
      sxi[k] = nsxi;
      cyr[k] = ncyr;
      cyi[k] = ncyi;
      syr[k] = nsyr;
      syi[k] = nsyi;
      x0r += wc0[k] * ncxr + ws0[k] * nsxr;
      x0i += wc0[k] * ncxi + ws0[k] * nsxi;
      x1r += wc1[k] * ncxr + ws1[k] * nsxr;
      x1i += wc1[k] * ncxi + ws1[k] * nsxi;
      y1r += wc1[k] * ncyr + ws1[k] * nsyr;
      y1i += wc1[k] * ncyi + ws1[k] * nsyi;
      y2r += wc2[k] * ncyr + ws2[k] * nsyr;
      y2i += wc2[k] * ncyi + ws2[k] * nsyi;
    }
    }
    // [[K^0, -i K^1], [i K^1, K^2]] (k > 0).
    complex far_x = complex(x0r, x0i) - i * complex(y1r, y1i);
    complex far_y = i * complex(x1r, x1i) + complex(y2r, y2i);
    if (block_ > 0) {
      // The slow exponentials: the block-start states' polynomials on the four
      // real output channels (Re, Im of history x, then of y), plus the slow
      // kernel's lags applied to this block's own inputs, each entry to its
      // input as in the matrix above.
      const int t = static_cast<int>(n % block_);
      const std::size_t row = q * block_;
      double *in_xr = block_input_[0].data() + row, *in_xi = block_input_[1].data() + row;
      double *in_yr = block_input_[2].data() + row, *in_yi = block_input_[3].data() + row;
      in_xr[t] = uxr;
      in_xi[t] = uxi;
      in_yr[t] = uyr;
      in_yi[t] = uyi;
      const double* slow = slow_batch_out_.data() + d;
      const double out[4] = {slow[0], slow[batch_], slow[2 * batch_], slow[3 * batch_]};
      // Lag t - j of entry e sits at [e][B - 1 - t + j] (stored reversed, so
      // that this loop reads forward); the eight sums vectorise together.
      const double* lag = slow_lag_weight_.data() + q * 3 * block_ + (block_ - 1 - t);
      const double *lag0 = lag, *lag1 = lag + block_, *lag2 = lag + 2 * block_;
      double x0r = 0.0, x0i = 0.0, x1r = 0.0, x1i = 0.0, y1r = 0.0, y1i = 0.0, y2r = 0.0, y2i = 0.0;
      if (!normal_active_) {
#pragma omp simd reduction(+ : x0r, x0i, x1r, x1i)
        for (int j = 0; j <= t; ++j) {
          const double xr = in_xr[j], xi = in_xi[j];
          x0r += lag0[j] * xr;
          x0i += lag0[j] * xi;
          x1r += lag1[j] * xr;
          x1i += lag1[j] * xi;
        }
      } else {
#pragma omp simd reduction(+ : x0r, x0i, x1r, x1i, y1r, y1i, y2r, y2i)
      for (int j = 0; j <= t; ++j) {
        const double xr = in_xr[j], xi = in_xi[j], yr = in_yr[j], yi = in_yi[j];
        x0r += lag0[j] * xr;
        x0i += lag0[j] * xi;
        x1r += lag1[j] * xr;
        x1i += lag1[j] * xi;
        y1r += lag1[j] * yr;
        y1i += lag1[j] * yi;
        y2r += lag2[j] * yr;
        y2i += lag2[j] * yi;
      }
      }
      // [[K^0, -i K^1], [i K^1, K^2]] as above.
      far_x += complex(out[0] + x0r + y1i, out[1] + x0i - y1r);
      far_y += complex(out[2] - x1i + y2r, out[3] + x1r + y2i);
      if (t == block_ - 1) push_slow_block_end(q);
    }
    far_batch_x_[q * batch_ + d] = far_x;
    far_batch_y_[q * batch_ + d] = far_y;
  }
}

void FaceHalfSpaceHistory::fast_batch_outputs(std::size_t q, long long batch_step, int first, int last) {
  // While the normal channel is inactive: the x input's rotation and its two
  // outputs (entries A and B), as push()'s loop with both channels, two steps
  // per pass over the exponentials (each state is read and written once per
  // two steps, its rotation's intermediate kept in registers), a last odd
  // step alone.  Each step's arithmetic is that of the loop with both
  // channels, in the same order, whatever the pairing.
  const std::size_t ring0 = first_lag_[q], window = first_lag_[q + 1] - ring0;
  const std::size_t k0 = first_fast_[q], count = first_fast_[q + 1] - k0;
  const double *zr = pole_re_.data() + k0, *zi = pole_im_.data() + k0;
  const double *wc0 = weight_cos_[0].data() + k0, *ws0 = weight_sin_[0].data() + k0;
  const double *wc1 = weight_cos_[1].data() + k0, *ws1 = weight_sin_[1].data() + k0;
  double *cxr = far_[0].data() + k0, *cxi = far_[1].data() + k0, *sxr = far_[2].data() + k0,
         *sxi = far_[3].data() + k0;
  double* out = fast_batch_out_.data();
  // v_{n-W} of step d, still in the ring (the batch is at most W steps long).
  const auto input = [&](int d) {
    return ring_x_[ring0 + static_cast<std::size_t>((batch_step + d) % static_cast<long long>(window))];
  };
  int d = first;
  for (; d + 1 < last; d += 2) {
    const complex u = input(d), v = input(d + 1);
    const double uxr = u.real(), uxi = u.imag(), vxr = v.real(), vxi = v.imag();
    double x0r = 0.0, x0i = 0.0, x1r = 0.0, x1i = 0.0, z0r = 0.0, z0i = 0.0, z1r = 0.0, z1i = 0.0;
#pragma omp simd reduction(+ : x0r, x0i, x1r, x1i, z0r, z0i, z1r, z1i)
    for (std::size_t k = 0; k < count; ++k) {
      const double a = zr[k], b = zi[k];
      const double pxr = cxr[k] + uxr, pxi = cxi[k] + uxi;
      const double ncxr = a * pxr - b * sxr[k], ncxi = a * pxi - b * sxi[k];
      const double nsxr = b * pxr + a * sxr[k], nsxi = b * pxi + a * sxi[k];
      x0r += wc0[k] * ncxr + ws0[k] * nsxr;
      x0i += wc0[k] * ncxi + ws0[k] * nsxi;
      x1r += wc1[k] * ncxr + ws1[k] * nsxr;
      x1i += wc1[k] * ncxi + ws1[k] * nsxi;
      const double qxr = ncxr + vxr, qxi = ncxi + vxi;
      const double mcxr = a * qxr - b * nsxr, mcxi = a * qxi - b * nsxi;
      const double msxr = b * qxr + a * nsxr, msxi = b * qxi + a * nsxi;
      cxr[k] = mcxr;
      cxi[k] = mcxi;
      sxr[k] = msxr;
      sxi[k] = msxi;
      z0r += wc0[k] * mcxr + ws0[k] * msxr;
      z0i += wc0[k] * mcxi + ws0[k] * msxi;
      z1r += wc1[k] * mcxr + ws1[k] * msxr;
      z1i += wc1[k] * mcxi + ws1[k] * msxi;
    }
    out[d] = x0r;
    out[batch_ + d] = x0i;
    out[2 * batch_ + d] = x1r;
    out[3 * batch_ + d] = x1i;
    out[d + 1] = z0r;
    out[batch_ + d + 1] = z0i;
    out[2 * batch_ + d + 1] = z1r;
    out[3 * batch_ + d + 1] = z1i;
  }
  if (d < last) {
    const complex u = input(d);
    const double uxr = u.real(), uxi = u.imag();
    double x0r = 0.0, x0i = 0.0, x1r = 0.0, x1i = 0.0;
#pragma omp simd reduction(+ : x0r, x0i, x1r, x1i)
    for (std::size_t k = 0; k < count; ++k) {
      const double a = zr[k], b = zi[k];
      const double pxr = cxr[k] + uxr, pxi = cxi[k] + uxi;
      const double ncxr = a * pxr - b * sxr[k], ncxi = a * pxi - b * sxi[k];
      const double nsxr = b * pxr + a * sxr[k], nsxi = b * pxi + a * sxi[k];
      cxr[k] = ncxr;
      cxi[k] = ncxi;
      sxr[k] = nsxr;
      sxi[k] = nsxi;
      x0r += wc0[k] * ncxr + ws0[k] * nsxr;
      x0i += wc0[k] * ncxi + ws0[k] * nsxi;
      x1r += wc1[k] * ncxr + ws1[k] * nsxr;
      x1i += wc1[k] * ncxi + ws1[k] * nsxi;
    }
    out[d] = x0r;
    out[batch_ + d] = x0i;
    out[2 * batch_ + d] = x1r;
    out[3 * batch_ + d] = x1i;
  }
}

void FaceHalfSpaceHistory::slow_batch_outputs(std::size_t q, long long batch_step, int first, int last) {
  // The polynomials are those of the block's start until its last step (a
  // batch never straddles a block end), so Horner's rule runs on kLanes steps
  // side by side: one vector per polynomial instead of one scalar chain per
  // polynomial and step (the pair's two groups make 16 complex polynomials per
  // mode).  Every lane does the same arithmetic whatever the batch (unused
  // lanes are evaluated at x = 0 and dropped), so the outputs do not depend on
  // how the steps were batched.
  constexpr int kLanes = 8;
  const std::size_t n_modes = history_x_.size();
  const int terms = terms_;
  const complex* moments = block_moment_.data() + q * groups_ * kSlowPolynomials * terms_;
  for (int d0 = first; d0 < last; d0 += kLanes) {
    const int lanes = std::min(kLanes, last - d0);
    // Block positions t0 + s (the batch lies in one block).
    const int t0 = static_cast<int>((batch_step + d0) % block_);
    double x[kLanes] = {};
    for (int s = 0; s < lanes; ++s) x[s] = (t0 + s + 1) - block_centre_;
    double out[4][kLanes] = {};
    for (std::size_t g = 0; g < groups_; ++g) {
      // Polynomial (b, o) of this group at moment[(b * 4 + o) * terms], b = the
      // group's first and second branch, o = the output channel; the 16 real
      // chains advance together (independent, so they overlap instead of
      // waiting on each other's latency).
      const complex* m = moments + g * kSlowPolynomials * terms;
      double re[kSlowPolynomials][kLanes], im[kSlowPolynomials][kLanes];
      for (std::size_t beta = 0; beta < kSlowPolynomials; ++beta)
        for (int s = 0; s < kLanes; ++s) {
          re[beta][s] = m[beta * terms + terms - 1].real();
          im[beta][s] = m[beta * terms + terms - 1].imag();
        }
      for (int p = terms - 2; p >= 0; --p)
        for (std::size_t beta = 0; beta < kSlowPolynomials; ++beta) {
          const double mr = m[beta * terms + p].real(), mi = m[beta * terms + p].imag();
#pragma omp simd
          for (int s = 0; s < kLanes; ++s) {
            re[beta][s] = re[beta][s] * x[s] + mr;
            im[beta][s] = im[beta][s] * x[s] + mi;
          }
        }
      // Channel o: 2 Re(rho_1^{t'} P_{1,o} + rho_2^{t'} P_{2,o}), the group's
      // rotations at this step (real arithmetic: std::complex's products stay
      // scalar).
      for (int s = 0; s < lanes; ++s) {
        const std::size_t at = (static_cast<std::size_t>(t0 + s) * n_modes + q) * 2;
        const double r1 = rotation_[g][at].real(), i1 = rotation_[g][at].imag();
        const double r2 = rotation_[g][at + 1].real(), i2 = rotation_[g][at + 1].imag();
        for (int o = 0; o < 4; ++o)
          out[o][s] += 2.0 * ((r1 * re[o][s] - i1 * im[o][s]) + (r2 * re[4 + o][s] - i2 * im[4 + o][s]));
      }
    }
    for (int o = 0; o < 4; ++o)
      for (int s = 0; s < lanes; ++s) slow_batch_out_[o * batch_ + d0 + s] = out[o][s];
  }
}

void FaceHalfSpaceHistory::push_slow_block_end(std::size_t q) {
  // The block's input moments of x and y, each slow state advanced over the
  // block, and the next block's polynomials: channel o of branch b at
  // block_moment_[((q * 2 + b) * 4 + o) * terms].  The same
  // arithmetic as slow_taylor_factors, advance_slow_state and add_slow_moment
  // (kernels/slow_block.hpp), arranged as loops over the exponentials (they
  // vectorise; per exponential, the loops over the terms do not).
  // Per group of two branches (its own rotations, its own polynomials);
  // while the normal channel is inactive its moments are zero (its inputs
  // were), and the states it feeds stay zero.
  const std::size_t n_modes = history_x_.size();
  const std::size_t row = q * block_;
  const int terms = terms_;
  const std::size_t* start = slow_branch_start_.data() + q * (branches_ + 1);
  for (std::size_t g = 0; g < groups_; ++g) {
  std::array<complex, 4 * kMaxTaylorTerms> mu_x{}, mu_y{};
  slow_input_moments(block_input_[0].data() + row, block_input_[1].data() + row, 1, rotation_[g].data(), n_modes, q,
                     block_, block_centre_, terms_, mu_x.data());
  if (normal_active_)
    slow_input_moments(block_input_[2].data() + row, block_input_[3].data() + row, 1, rotation_[g].data(), n_modes,
                       q, block_, block_centre_, terms_, mu_y.data());
  complex* moment = block_moment_.data() + (q * groups_ + g) * kSlowPolynomials * terms_;
  std::fill(moment, moment + kSlowPolynomials * terms_, complex(0.0));
  for (int branch = 0; branch < 2; ++branch) {
    const std::size_t b = 2 * g + static_cast<std::size_t>(branch);
    if (b >= branches_) continue;
    const std::size_t m0 = start[b];
    const std::size_t count = start[b + 1] - m0;
    if (count == 0) continue;
    // This branch's moments of Re x, Im x, Re y, Im y (each complex), term p.
    const complex* mu[4] = {mu_x.data() + 2 * branch * terms, mu_x.data() + (2 * branch + 1) * terms,
                            mu_y.data() + 2 * branch * terms, mu_y.data() + (2 * branch + 1) * terms};
    // Work arrays: the Taylor factor of term p, and per exponential eight
    // doubles, first the feeds (Re, Im of the four channels' sums), then the
    // weighted states.
    double* factor = slow_scratch_[0].data();
    double* part[8];
    for (int c = 0; c < 8; ++c) part[c] = slow_scratch_[1 + c].data();
    const double* decay = slow_decay_.data() + m0;
    const double* centre_factor = slow_centre_factor_.data() + m0;
    const double* block_pole = reinterpret_cast<const double*>(slow_block_pole_.data() + m0);
    const double* w = reinterpret_cast<const double*>(slow_weight_.data() + m0);  // 6 per exponential
    double* state[4];
    for (int c = 0; c < 4; ++c) state[c] = reinterpret_cast<double*>(slow_state_[c].data() + m0);
    // Feeds sum_p factor[p] mu_c[p], factor[p] = e^{-lambda t_c} (-lambda)^p / p!.
    // While the normal channel is inactive its feeds and states are zero and
    // are neither computed nor stored; its terms of the outputs are left out
    // (the same values: they add zeros).
    // The number of feeds is a compile-time constant in each copy of the loop:
    // with a run-time count the loop over the exponentials stayed scalar.
    const auto feed = [&](auto feeds_constant) {
      constexpr int feeds = decltype(feeds_constant)::value;
      for (int p = 0; p < terms; ++p) {
        double mu_p[8];
        for (int c = 0; c < 4; ++c) {
          mu_p[2 * c] = mu[c][p].real();
          mu_p[2 * c + 1] = mu[c][p].imag();
        }
        if (p == 0) {
#pragma omp simd
          for (std::size_t k = 0; k < count; ++k) {
            factor[k] = centre_factor[k];
            for (int c = 0; c < feeds; ++c) part[c][k] = 0.0 + factor[k] * mu_p[c];
          }
          continue;
        }
#pragma omp simd
        for (std::size_t k = 0; k < count; ++k) {
          factor[k] *= -decay[k] / p;
          for (int c = 0; c < feeds; ++c) part[c][k] += factor[k] * mu_p[c];
        }
      }
    };
    if (normal_active_)
      feed(std::integral_constant<int, 8>{});
    else
      feed(std::integral_constant<int, 4>{});
    // Y_c <- z^B Y_c + feed_c, and the four output channels' weighted states,
    // as the matrix in push().
    if (!normal_active_) {
#pragma omp simd
      for (std::size_t k = 0; k < count; ++k) {
        const double zr = block_pole[2 * k], zi = block_pole[2 * k + 1];
        double y[4];
        for (int c = 0; c < 2; ++c) {
          const double sr = state[c][2 * k], si = state[c][2 * k + 1];
          y[2 * c] = (zr * sr - zi * si) + part[2 * c][k];
          y[2 * c + 1] = (zr * si + zi * sr) + part[2 * c + 1][k];
          state[c][2 * k] = y[2 * c];
          state[c][2 * k + 1] = y[2 * c + 1];
        }
        // As below with Y_{Re y} = Y_{Im y} = 0.
        const double w0r = w[6 * k], w0i = w[6 * k + 1], w1r = w[6 * k + 2], w1i = w[6 * k + 3];
        part[0][k] = w0r * y[0] - w0i * y[1];
        part[1][k] = w0r * y[1] + w0i * y[0];
        part[2][k] = w0r * y[2] - w0i * y[3];
        part[3][k] = w0r * y[3] + w0i * y[2];
        part[4][k] = -(w1r * y[2] - w1i * y[3]);
        part[5][k] = -(w1r * y[3] + w1i * y[2]);
        part[6][k] = w1r * y[0] - w1i * y[1];
        part[7][k] = w1r * y[1] + w1i * y[0];
        factor[k] = centre_factor[k];
      }
    } else {
#pragma omp simd
    for (std::size_t k = 0; k < count; ++k) {
      const double zr = block_pole[2 * k], zi = block_pole[2 * k + 1];
      double y[8];
      for (int c = 0; c < 4; ++c) {
        const double sr = state[c][2 * k], si = state[c][2 * k + 1];
        y[2 * c] = (zr * sr - zi * si) + part[2 * c][k];
        y[2 * c + 1] = (zr * si + zi * sr) + part[2 * c + 1][k];
        state[c][2 * k] = y[2 * c];
        state[c][2 * k + 1] = y[2 * c + 1];
      }
      // The products written out in real arithmetic (std::complex's stay scalar):
      // w0 Y_{Re x} + w1 Y_{Im y}, w0 Y_{Im x} - w1 Y_{Re y}, w2 Y_{Re y} - w1 Y_{Im x},
      // w1 Y_{Re x} + w2 Y_{Im y}.
      const double w0r = w[6 * k], w0i = w[6 * k + 1], w1r = w[6 * k + 2], w1i = w[6 * k + 3];
      const double w2r = w[6 * k + 4], w2i = w[6 * k + 5];
      part[0][k] = (w0r * y[0] - w0i * y[1]) + (w1r * y[6] - w1i * y[7]);
      part[1][k] = (w0r * y[1] + w0i * y[0]) + (w1r * y[7] + w1i * y[6]);
      part[2][k] = (w0r * y[2] - w0i * y[3]) - (w1r * y[4] - w1i * y[5]);
      part[3][k] = (w0r * y[3] + w0i * y[2]) - (w1r * y[5] + w1i * y[4]);
      part[4][k] = (w2r * y[4] - w2i * y[5]) - (w1r * y[2] - w1i * y[3]);
      part[5][k] = (w2r * y[5] + w2i * y[4]) - (w1r * y[3] + w1i * y[2]);
      part[6][k] = (w1r * y[0] - w1i * y[1]) + (w2r * y[6] - w2i * y[7]);
      part[7][k] = (w1r * y[1] + w1i * y[0]) + (w2r * y[7] + w2i * y[6]);
      factor[k] = centre_factor[k];
    }
    }
    // Term p of polynomial (b, o): the branch's exponentials' factor[p] times their weighted states.
    for (int p = 0; p < terms; ++p) {
      if (p > 0)
#pragma omp simd
        for (std::size_t k = 0; k < count; ++k) factor[k] *= -decay[k] / p;
      double sum[8] = {};
#pragma omp simd reduction(+ : sum[:8])
      for (std::size_t k = 0; k < count; ++k)
        for (int c = 0; c < 8; ++c) sum[c] += factor[k] * part[c][k];
      for (int o = 0; o < 4; ++o) moment[(branch * 4 + o) * terms + p] += complex(sum[2 * o], sum[2 * o + 1]);
    }
  }
  }
}

FaceHalfSpaceModeKernel FaceHalfSpaceHistory::mode_kernel(int q) const {
  if (q < 1 || q >= modes()) throw std::out_of_range("FaceHalfSpaceHistory::mode_kernel: q out of range");
  FaceHalfSpaceModeKernel out;
  out.wavenumber = wavenumber_[q];
  out.h = h_[q];
  out.static_weight = static_weight_[q];
  for (std::size_t i = 0; i < 3; ++i) {
    for (std::size_t j = first_lag_[q]; j < first_lag_[q + 1]; ++j) out.lag_weight[i].push_back(lag_weight_[j][i]);
    for (int j = 0; j < lags_; ++j) out.correction[i].push_back(correction_[(q - 1) * static_cast<std::size_t>(lags_) + j][i]);
    for (std::size_t k = first_pole_[q]; k < first_pole_[q + 1]; ++k) out.pole_weight[i].push_back(pole_weight_[k][i]);
  }
  out.pole.assign(pole_.begin() + first_pole_[q], pole_.begin() + first_pole_[q + 1]);
  return out;
}

FaceMatrix FaceHalfSpaceHistory::symbol(int q, double theta) const {
  const FaceHalfSpaceModeKernel k = mode_kernel(q);
  ModeDesign m;
  m.h = k.h;
  m.window = static_cast<int>(k.lag_weight[0].size());
  m.pole = k.pole;
  // One body: r^2 from the impedances (E'_D = 1/r), as the operator was designed.
  FaceKernelShape shape = shape_;
  if (!shape.pair) {
    shape.r2 = (impedance_x_ / impedance_y_) * (impedance_x_ / impedance_y_);
    shape.instantaneous[2] = 1.0 / std::sqrt(shape.r2);
  }
  // The coefficients' unit: mu/c_s (one body, = impedance_x_), mu_ref/c_ref (the pair).
  for (std::size_t i = 0; i < 3; ++i) {
    m.static_value[i] = k.static_weight[i] / unit_;
    for (double w : k.lag_weight[i]) m.lag[i].push_back(w / unit_);
    for (complex w : k.pole_weight[i]) m.weight[i].push_back(w / unit_);
  }
  const auto z = symbols_of(m, shape, std::span<const double>(&theta, 1)).front();
  const complex i(0.0, 1.0);
  FaceMatrix out;
  out.xx = unit_ * z[0];
  out.xy = -i * unit_ * z[1];
  out.yx = i * unit_ * z[1];
  out.yy = unit_ * z[2];
  return out;
}

namespace {
// The far-field states (far_, the fast exponentials) and the slow states
// (slow_state_), in their order.
constexpr const char* kFarStateNames[8] = {"far_c_x_re", "far_c_x_im", "far_s_x_re", "far_s_x_im",
                                           "far_c_y_re", "far_c_y_im", "far_s_y_re", "far_s_y_im"};
constexpr const char* kSlowStateNames[4] = {"slow_x_re", "slow_x_im", "slow_y_re", "slow_y_im"};
// Format 2: fast and slow exponentials in their own arrays (docs/theory.md
// §8.7); the every-step operator's restart points have no format counter.
constexpr long long kFaceStateFormatPerStep = 2;
// Format 3: the far field advanced a batch of steps at a time (far_batch).
constexpr long long kFaceStateFormat = 3;

// A design length the restart point must share with this operator (its
// states are laid out by it): refused by name otherwise.
void require_same(const HistoryOperatorState& state, const std::string& key, long long expected, const char* what) {
  if (state.counter(key) != expected)
    throw std::invalid_argument("history operator state: the half-space body's restart point has " + std::string(what) +
                                " " + std::to_string(state.counter(key)) + ", this operator " +
                                std::to_string(expected) + "; it cannot be resumed with another " + what);
}
}  // namespace

void FaceHalfSpaceHistory::save_into(HistoryOperatorState& state, const std::string& prefix) const {
  state.counters.emplace_back(prefix + "format", kFaceStateFormat);
  state.counters.emplace_back(prefix + "slow_block", block_);
  // The far field is advanced to the end of the current batch (its states,
  // the block's inputs and polynomials), its outputs for the batch's steps
  // kept in far_batch.
  state.counters.emplace_back(prefix + "far_batch", batch_);
  state.add(prefix + "far_batch_x", far_batch_x_);
  state.add(prefix + "far_batch_y", far_batch_y_);
  state.add(prefix + "ring_x", ring_x_);
  state.add(prefix + "ring_y", ring_y_);
  state.add(prefix + "running_x", running_x_);
  state.add(prefix + "running_y", running_y_);
  for (std::size_t i = 0; i < far_.size(); ++i) state.add(prefix + kFarStateNames[i], far_[i]);
  for (std::size_t i = 0; i < slow_state_.size(); ++i) state.add(prefix + kSlowStateNames[i], slow_state_[i]);
  // The block's inputs as complex arrays (format 2's layout).
  for (int c = 0; c < 2; ++c) {
    std::vector<complex> input(block_input_[0].size());
    for (std::size_t s = 0; s < input.size(); ++s) input[s] = {block_input_[2 * c][s], block_input_[2 * c + 1][s]};
    state.add(prefix + (c == 0 ? "block_input_x" : "block_input_y"), input);
  }
  state.add(prefix + "block_moment", block_moment_);
  state.add(prefix + "history_x", history_x_);
  state.add(prefix + "history_y", history_y_);
  state.counters.emplace_back(prefix + "step", step_);
  state.counters.emplace_back(prefix + "normal_active", normal_active_ ? 1 : 0);
}

void FaceHalfSpaceHistory::state_layout_into(HistoryStateLayout& layout, const std::string& prefix) const {
  const std::size_t n = history_x_.size(), block = static_cast<std::size_t>(block_);
  layout.add_uniform(prefix + "far_batch_x", n, 2 * static_cast<std::size_t>(batch_));
  layout.add_uniform(prefix + "far_batch_y", n, 2 * static_cast<std::size_t>(batch_));
  layout.add(prefix + "ring_x", first_lag_, 2);
  layout.add(prefix + "ring_y", first_lag_, 2);
  layout.add_uniform(prefix + "running_x", n, 2);
  layout.add_uniform(prefix + "running_y", n, 2);
  for (const char* name : kFarStateNames) layout.add(prefix + name, first_fast_, 1);
  for (const char* name : kSlowStateNames) layout.add(prefix + name, first_slow_, 2);
  layout.add_uniform(prefix + "block_input_x", n, 2 * block);
  layout.add_uniform(prefix + "block_input_y", n, 2 * block);
  layout.add_uniform(prefix + "block_moment", n, 2 * groups_ * kSlowPolynomials * static_cast<std::size_t>(terms_));
  layout.add_uniform(prefix + "history_x", n, 2);
  layout.add_uniform(prefix + "history_y", n, 2);
  // Whether the second channel's inputs were ever nonzero: the parts of an
  // operator split by mode may differ (one part's modes had nonzero inputs,
  // another's not yet), and a channel worked while its states are zero gives
  // the same histories, so the whole operator's is whether any part's is.
  layout.any_counters.push_back(prefix + "normal_active");
}

void FaceHalfSpaceHistory::restore_from(const HistoryOperatorState& state, const std::string& prefix) {
  const bool has_format = std::any_of(state.counters.begin(), state.counters.end(),
                                      [&](const auto& c) { return c.first == prefix + "format"; });
  const long long format = has_format ? state.counter(prefix + "format") : 0;
  if (format != kFaceStateFormat && format != kFaceStateFormatPerStep)
    throw std::invalid_argument(
        "history operator state: this half-space body's restart point was written by a slipstrip older than the "
        "blocked half-space body operator (docs/theory.md §8.7; its state has neither format " +
        std::to_string(kFaceStateFormatPerStep) + " nor " + std::to_string(kFaceStateFormat) +
        ") and cannot be resumed by this version; rerun the case from the start, or resume it with the version "
        "that wrote it");
  require_same(state, prefix + "slow_block", block_, "slow block");
  state.copy_to(prefix + "ring_x", std::span<complex>(ring_x_));
  state.copy_to(prefix + "ring_y", std::span<complex>(ring_y_));
  state.copy_to(prefix + "running_x", std::span<complex>(running_x_));
  state.copy_to(prefix + "running_y", std::span<complex>(running_y_));
  for (std::size_t i = 0; i < far_.size(); ++i) state.copy_to(prefix + kFarStateNames[i], std::span<double>(far_[i]));
  for (std::size_t i = 0; i < slow_state_.size(); ++i)
    state.copy_to(prefix + kSlowStateNames[i], std::span<complex>(slow_state_[i]));
  for (int c = 0; c < 2; ++c) {
    std::vector<complex> input(block_input_[0].size());
    state.copy_to(prefix + (c == 0 ? "block_input_x" : "block_input_y"), std::span<complex>(input));
    for (std::size_t s = 0; s < input.size(); ++s) {
      block_input_[2 * c][s] = input[s].real();
      block_input_[2 * c + 1][s] = input[s].imag();
    }
  }
  state.copy_to(prefix + "block_moment", std::span<complex>(block_moment_));
  state.copy_to(prefix + "history_x", std::span<complex>(history_x_));
  state.copy_to(prefix + "history_y", std::span<complex>(history_y_));
  step_ = state.counter(prefix + "step");
  // A restart point without the flag (an older slipstrip) resumes with the
  // normal channel worked in full, which is always exact.
  const bool has_flag = std::any_of(state.counters.begin(), state.counters.end(),
                                    [&](const auto& c) { return c.first == prefix + "normal_active"; });
  normal_active_ = !has_flag || state.counter(prefix + "normal_active") != 0;
  if (format == kFaceStateFormat) {
    require_same(state, prefix + "far_batch", batch_, "far-field batch");
    state.copy_to(prefix + "far_batch_x", std::span<complex>(far_batch_x_));
    state.copy_to(prefix + "far_batch_y", std::span<complex>(far_batch_y_));
    return;
  }
  // Format 2 holds the far field at this step: advanced here over the rest of
  // the current batch, as push() would have at the batch's start.
  const int position = static_cast<int>(step_ % batch_);
  if (position != 0)
    for (std::size_t q = 1; q < history_x_.size(); ++q) advance_far(q, step_ - position, position, batch_);
}

std::size_t FaceHalfSpaceHistory::memory_bytes() const {
  return sizeof(complex) * (ring_x_.size() + ring_y_.size() + running_x_.size() + running_y_.size() +
                            history_x_.size() + history_y_.size() + pole_.size()) +
         sizeof(double) * (far_.size() + 8) * pole_re_.size() +
         sizeof(pole_weight_[0]) * pole_weight_.size() + sizeof(lag_weight_[0]) * lag_weight_.size() +
         sizeof(static_weight_[0]) * static_weight_.size() + sizeof(correction_[0]) * correction_.size() +
         sizeof(double) * (wavenumber_.size() + h_.size()) +
         sizeof(std::size_t) * (first_lag_.size() + first_pole_.size() + first_fast_.size() + first_slow_.size() +
                                slow_branch_start_.size()) +
         sizeof(double) * (slow_decay_.size() + slow_centre_factor_.size() + slow_lag_weight_.size()) +
         sizeof(complex) * (slow_block_pole_.size() + groups_ * (rotation_.empty() ? 0 : rotation_[0].size()) +
                            4 * slow_state_[0].size() +
                            block_moment_.size()) +
         sizeof(double) * 4 * block_input_[0].size() +
         sizeof(complex) * (far_batch_x_.size() + far_batch_y_.size()) + sizeof(double) * (slow_batch_out_.size() + fast_batch_out_.size()) +
         sizeof(slow_weight_[0]) * slow_weight_.size();
}

}  // namespace slipstrip
