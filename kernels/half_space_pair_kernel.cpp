#include "kernels/half_space_pair_kernel.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <span>
#include <sstream>

namespace slipstrip {
namespace {

using complex = std::complex<double>;
using Entries = std::array<complex, 3>;
constexpr double pi = std::numbers::pi;
constexpr complex I(0.0, 1.0);

// Absolute tolerance of a panel's rule (units mu_ref k): 1e-7 leaves the sums
// 3e-7 from a numerical inverse Laplace transform and saves 5 % of the
// exponentials (the panels near the other sheets' singular points need their
// extra nodes at any useful accuracy).
constexpr double kPanelTolerance = 1e-8;
// The set-up check's refusal threshold (units mu_ref k).
constexpr double kCheckTolerance = 1e-6;

std::string number_text(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

// (A, B, D) of one body in units mu_ref k from its roots a = sqrt(1 + p_i^2),
// d = sqrt(1 + r^2 p_i^2) at p_i = p c_ref / c_s,i (kernels/face_half_space.hpp),
// the coupling's sign that of the body's frame (the bottom body is mirrored).
Entries body_entries(const HalfSpacePairShape& s, int body, complex a, complex d) {
  const double r2 = s.speed_ratio_squared[body], m = s.modulus[body];
  const double sign = body == 0 ? 1.0 : -1.0;
  const complex R = r2 * a + d;
  return {m * d * (a + d) / R, sign * m * ((2.0 * r2 - 1.0) * a + d) / R, m * a * (a + d) / R};
}

// The inverse of [[A, -i B], [i B, D]] in the same form: (D, -B, A) / (A D - B^2).
Entries inverse(const Entries& e) {
  const complex det = e[0] * e[2] - e[1] * e[1];
  return {e[2] / det, -e[1] / det, e[0] / det};
}

// Both bodies' roots from the factors sqrt(zeta - i b_k) (factor[k]) and the
// regular sqrt(zeta + i b): a_i = gamma_i sqrt(zeta - i b_s) sqrt(zeta + i b_s)
// (1 + gamma^2 zeta^2 = gamma^2 (zeta - i b_s)(zeta + i b_s), b_s = 1/gamma),
// d_i the same with r_i gamma_i and b_d = b_s / r_i.
std::array<std::array<complex, 2>, 2> roots_of_factors(const HalfSpacePairShape& s, complex zeta,
                                                       std::span<const complex> factor) {
  std::array<std::array<complex, 2>, 2> roots;
  for (int i = 0; i < 2; ++i) {
    const double g = s.slowness[i], r = std::sqrt(s.speed_ratio_squared[i]);
    const double bs = s.branch_heights[s.shear_branch[i]], bd = s.branch_heights[s.pressure_branch[i]];
    roots[i][0] = g * factor[s.shear_branch[i]] * std::sqrt(zeta + I * bs);
    roots[i][1] = g * r * factor[s.pressure_branch[i]] * std::sqrt(zeta + I * bd);
  }
  return roots;
}

Entries entries_of_roots(const HalfSpacePairShape& s, const std::array<std::array<complex, 2>, 2>& roots) {
  const Entries top = inverse(body_entries(s, 0, roots[0][0], roots[0][1]));
  const Entries bottom = inverse(body_entries(s, 1, roots[1][0], roots[1][1]));
  return inverse({top[0] + bottom[0], top[1] + bottom[1], top[2] + bottom[2]});
}

Entries history_of_entries(const HalfSpacePairShape& s, complex p, const Entries& k) {
  const auto e = half_space_pair_impedances(s);
  return {k[0] / p - e[0], k[1] / p, k[2] / p - e[1]};
}

// The principal factors sqrt(p - i b_k): the continuation from Re p > 0 with
// every cut horizontal into Re p < 0.
std::vector<complex> principal_factors(const HalfSpacePairShape& s, complex p) {
  std::vector<complex> f(s.branch_heights.size());
  for (std::size_t k = 0; k < f.size(); ++k) f[k] = std::sqrt(p - I * s.branch_heights[k]);
  return f;
}

complex determinant_of_roots(const HalfSpacePairShape& s, const std::array<std::array<complex, 2>, 2>& roots) {
  const Entries t = body_entries(s, 0, roots[0][0], roots[0][1]);
  const Entries b = body_entries(s, 1, roots[1][0], roots[1][1]);
  const complex A = t[0] + b[0], B = t[1] + b[1], D = t[2] + b[2];
  return A * D - B * B;
}

// --- Zeros of the determinant in the cut plane -------------------------------

struct Rectangle {
  double x0, x1, y0, y1;
};

// Winding number of f along the rectangle's boundary (counter-clockwise):
// each edge in 256 pieces, each split while f turns by more than 0.3 rad.
double winding(const std::function<complex(complex)>& f, const Rectangle& r) {
  const complex corners[5] = {{r.x0, r.y0}, {r.x1, r.y0}, {r.x1, r.y1}, {r.x0, r.y1}, {r.x0, r.y0}};
  double total = 0.0;
  const auto turn = [&](auto&& self, complex za, complex fa, complex zb, complex fb, int depth) -> double {
    const double angle = std::arg(fb / fa);
    if (std::abs(angle) <= 0.3 || depth >= 40) {
      if (depth >= 40) throw std::runtime_error("half_space_pair_poles: the determinant vanishes on a search edge");
      return angle;
    }
    const complex zm = 0.5 * (za + zb);
    const complex fm = f(zm);
    return self(self, za, fa, zm, fm, depth + 1) + self(self, zm, fm, zb, fb, depth + 1);
  };
  for (int e = 0; e < 4; ++e) {
    constexpr int kPieces = 256;
    complex za = corners[e], fa = f(za);
    for (int i = 1; i <= kPieces; ++i) {
      const complex zb = corners[e] + (corners[e + 1] - corners[e]) * (double(i) / kPieces);
      const complex fb = f(zb);
      total += turn(turn, za, fa, zb, fb, 0);
      za = zb;
      fa = fb;
    }
  }
  return total / (2.0 * pi);
}

int zero_count(const std::function<complex(complex)>& f, const Rectangle& r) {
  const double w = winding(f, r);
  const double n = std::round(w);
  if (std::abs(w - n) > 0.05)
    throw std::runtime_error("half_space_pair_poles: the argument principle gave a winding number of " +
                             number_text(w));
  return static_cast<int>(n);
}

// Newton's method with a central-difference derivative (f is analytic).
complex newton(const std::function<complex(complex)>& f, complex z) {
  for (int it = 0; it < 100; ++it) {
    const double h = 1e-6 * (1.0 + std::abs(z));
    const complex derivative = (f(z + h) - f(z - h)) / (2.0 * h);
    const complex step = f(z) / derivative;
    z -= step;
    if (std::abs(step) < 1e-14 * (1.0 + std::abs(z))) break;
  }
  return z;
}

void locate_zeros(const std::function<complex(complex)>& f, const Rectangle& r, int count, int depth,
                  std::vector<complex>& out) {
  if (count == 0) return;
  const double size = std::max(r.x1 - r.x0, r.y1 - r.y0);
  if (count == 1 && size < 1e-2) {
    const complex z = newton(f, {0.5 * (r.x0 + r.x1), 0.5 * (r.y0 + r.y1)});
    const double slack = size;
    if (!(z.real() >= r.x0 - slack && z.real() <= r.x1 + slack && z.imag() >= r.y0 - slack && z.imag() <= r.y1 + slack))
      throw std::runtime_error("half_space_pair_poles: Newton's method left the rectangle of a zero");
    out.push_back(z);
    return;
  }
  if (depth > 60) throw std::runtime_error("half_space_pair_poles: could not separate the zeros of the determinant");
  // Split the longer side, slightly off the middle (so that a symmetric zero
  // does not fall on the new edge).
  Rectangle a = r, b = r;
  if (r.x1 - r.x0 >= r.y1 - r.y0) {
    const double m = r.x0 + 0.5123 * (r.x1 - r.x0);
    a.x1 = b.x0 = m;
  } else {
    const double m = r.y0 + 0.4877 * (r.y1 - r.y0);
    a.y1 = b.y0 = m;
  }
  const int in_a = zero_count(f, a);
  locate_zeros(f, a, in_a, depth + 1, out);
  locate_zeros(f, b, count - in_a, depth + 1, out);
}

// Distance from p to the nearest singular point of G_c other than p itself:
// the cuts {x + i b : x <= 0} (and their mirror images) and the origin.
double distance_to_cuts(const HalfSpacePairShape& s, complex p) {
  double d = std::abs(p);
  for (double b : s.branch_heights)
    for (double y : {b, -b}) d = std::min(d, p.real() <= 0.0 ? std::abs(p.imag() - y) : std::abs(p - complex(0.0, y)));
  return d;
}

void require_in_plane(const ElasticMaterial& m, const char* which) {
  if (m.antiplane())
    throw std::invalid_argument(std::string("half_space_pair_shape: the ") + which + " body must be in-plane");
  if (!(m.shear_modulus > 0.0 && m.density > 0.0) || !poisson_ratio_allowed(m.poisson_ratio))
    throw std::invalid_argument(std::string("half_space_pair_shape: the ") + which +
                                " body needs shear_modulus > 0, density > 0 and 0 < poisson_ratio < 0.5");
}

}  // namespace

HalfSpacePairShape half_space_pair_shape(const ElasticMaterial& top, const ElasticMaterial& bottom) {
  require_in_plane(top, "top");
  require_in_plane(bottom, "bottom");
  const ElasticMaterial* body[2] = {&top, &bottom};
  const ElasticMaterial& ref = bottom.shear_wave_speed() < top.shear_wave_speed() ? bottom : top;
  HalfSpacePairShape s;
  s.reference_modulus = ref.shear_modulus;
  s.reference_speed = ref.shear_wave_speed();
  std::array<double, 2> shear_height{}, pressure_height{};
  for (int i = 0; i < 2; ++i) {
    s.modulus[i] = body[i]->shear_modulus / s.reference_modulus;
    s.slowness[i] = s.reference_speed / body[i]->shear_wave_speed();
    s.speed_ratio_squared[i] = 1.0 / body[i]->wave_speed_ratio_squared();
    shear_height[i] = body[i]->shear_wave_speed() / s.reference_speed;
    pressure_height[i] = body[i]->dilatational_wave_speed() / s.reference_speed;
  }
  // The reference body's shear height is exactly 1.
  (&ref == &top ? shear_height[0] : shear_height[1]) = 1.0;
  for (int i = 0; i < 2; ++i) {
    s.branch_heights.push_back(shear_height[i]);
    s.branch_heights.push_back(pressure_height[i]);
  }
  std::sort(s.branch_heights.begin(), s.branch_heights.end());
  s.branch_heights.erase(std::unique(s.branch_heights.begin(), s.branch_heights.end()), s.branch_heights.end());
  const auto index_of = [&](double b) {
    return static_cast<std::size_t>(std::find(s.branch_heights.begin(), s.branch_heights.end(), b) -
                                    s.branch_heights.begin());
  };
  for (int i = 0; i < 2; ++i) {
    s.shear_branch[i] = index_of(shear_height[i]);
    s.pressure_branch[i] = index_of(pressure_height[i]);
  }
  return s;
}

std::array<double, 2> half_space_pair_impedances(const HalfSpacePairShape& s) {
  std::array<double, 2> ex{}, ey{};
  for (int i = 0; i < 2; ++i) {
    ex[i] = s.modulus[i] * s.slowness[i];
    ey[i] = ex[i] / std::sqrt(s.speed_ratio_squared[i]);
  }
  return {ex[0] * ex[1] / (ex[0] + ex[1]), ey[0] * ey[1] / (ey[0] + ey[1])};
}

std::array<complex, 3> half_space_pair_entries(const HalfSpacePairShape& s, complex p) {
  return entries_of_roots(s, roots_of_factors(s, p, principal_factors(s, p)));
}

std::array<complex, 3> half_space_pair_history_transforms(const HalfSpacePairShape& s, complex p) {
  return history_of_entries(s, p, half_space_pair_entries(s, p));
}

complex half_space_pair_determinant(const HalfSpacePairShape& s, complex p) {
  return determinant_of_roots(s, roots_of_factors(s, p, principal_factors(s, p)));
}

std::array<double, 3> half_space_pair_static_values(const HalfSpacePairShape& s) {
  const std::array<std::array<complex, 2>, 2> ones{{{1.0, 1.0}, {1.0, 1.0}}};
  const Entries k = entries_of_roots(s, ones);
  return {k[0].real(), k[1].real(), k[2].real()};
}

std::array<double, 3> half_space_pair_initial_values(const HalfSpacePairShape& s) {
  const auto e = half_space_pair_impedances(s);
  double sum = 0.0;
  for (int i = 0; i < 2; ++i) {
    const double r = std::sqrt(s.speed_ratio_squared[i]);
    const double ex = s.modulus[i] * s.slowness[i], ey = ex / r;
    const double beta = (2.0 * r - 1.0) / r;
    sum += (i == 0 ? 1.0 : -1.0) * s.modulus[i] * beta / (ex * ey);
  }
  return {0.0, e[0] * e[1] * sum, 0.0};
}

double half_space_pair_stoneley_speed(const HalfSpacePairShape& s) {
  // On p = i y, 0 <= y <= 1, every root is real and >= 0 (b >= 1 for every
  // branch point), so the determinant is real.
  const auto det = [&](double y) { return half_space_pair_determinant(s, complex(0.0, y)).real(); };
  std::vector<double> ys;
  constexpr int kPoints = 4000;
  for (int i = 0; i < kPoints; ++i) ys.push_back(double(i) / kPoints);
  // Up to the branch point, not at it: for identical bodies the determinant
  // vanishes there (D = 0 where a = 0) and nowhere below.
  for (int m = 2; m <= 15; ++m) ys.push_back(1.0 - std::pow(10.0, -m));
  std::sort(ys.begin(), ys.end());
  double y0 = ys[0], f0 = det(y0);
  for (std::size_t i = 1; i < ys.size(); ++i) {
    const double y1 = ys[i], f1 = det(y1);
    if ((f0 > 0.0 && f1 < 0.0) || (f0 < 0.0 && f1 > 0.0)) {
      double lo = y0, hi = y1;
      const bool low_positive = f0 > 0.0;
      while (hi - lo > 1e-14) {
        const double mid = 0.5 * (lo + hi);
        ((det(mid) > 0.0) == low_positive ? lo : hi) = mid;
      }
      return 0.5 * (lo + hi);
    }
    y0 = y1;
    f0 = f1;
  }
  return 0.0;
}

std::vector<complex> cut_plane_zeros(const std::function<complex(complex)>& f, std::span<const double> heights) {
  std::vector<double> b(heights.begin(), heights.end());
  std::sort(b.begin(), b.end());
  const double extent = 16.0 * b.back() + 16.0, x_right = 0.5;
  // Rectangles between the cuts, clear of them by a relative 1e-9.
  std::vector<Rectangle> rectangles;
  const double gap = 1e-9;
  rectangles.push_back({-extent, x_right, -b[0] * (1.0 - gap), b[0] * (1.0 - gap)});
  for (std::size_t k = 0; k + 1 < b.size(); ++k)
    rectangles.push_back({-extent, x_right, b[k] * (1.0 + gap), b[k + 1] * (1.0 - gap)});
  rectangles.push_back({-extent, x_right, b.back() * (1.0 + gap), extent});
  std::vector<complex> zeros;
  for (const Rectangle& r : rectangles) locate_zeros(f, r, zero_count(f, r), 0, zeros);
  return zeros;
}

std::vector<HalfSpacePairPole> half_space_pair_poles(const HalfSpacePairShape& s) {
  const std::function<complex(complex)> det = [&](complex p) { return half_space_pair_determinant(s, p); };
  const std::vector<complex> zeros = cut_plane_zeros(det, s.branch_heights);
  std::vector<HalfSpacePairPole> poles;
  for (complex z : zeros) {
    if (z.imag() < -1e-12 * std::abs(z)) continue;  // the conjugate of one kept
    if (std::abs(z.imag()) <= 1e-12 * std::abs(z)) z = z.real();
    double radius = distance_to_cuts(s, z);
    for (complex w : zeros)
      if (w != z && std::abs(w - z) > 0.0) radius = std::min(radius, std::abs(w - z));
    radius *= 0.25;
    HalfSpacePairPole pole{z, {}};
    constexpr int kCircle = 64;
    for (int m = 0; m < kCircle; ++m) {
      const complex offset = radius * std::polar(1.0, 2.0 * pi * m / kCircle);
      const auto g = half_space_pair_history_transforms(s, z + offset);
      for (std::size_t e = 0; e < 3; ++e) pole.residue[e] += g[e] * offset / double(kCircle);
    }
    poles.push_back(pole);
  }
  return poles;
}

std::array<ExponentialSum, 3> half_space_pair_exponential_sums(const HalfSpacePairShape& s, double tau_min,
                                                               double tau_max, int nodes_per_panel) {
  const double stoneley = half_space_pair_stoneley_speed(s);
  if (stoneley > 0.0)
    throw HalfSpacePairHasInterfaceWave(
        "this pair of half-spaces has a Stoneley wave (an undamped interface wave) at " +
            number_text(stoneley * s.reference_speed) + " m/s, " + number_text(stoneley) +
            " times the slower shear speed: the combined pair operator's sums of decaying exponentials cannot "
            "carry it; the two bodies' operators do",
        stoneley * s.reference_speed);
  const std::vector<HalfSpacePairPole> poles = half_space_pair_poles(s);
  for (const HalfSpacePairPole& pole : poles)
    if (!(pole.p.real() < -1e-9 * std::abs(pole.p)))
      throw HalfSpacePairHasInterfaceWave(
          "this pair of half-spaces has an undamped interface wave at p = " + number_text(pole.p.real()) + " + " +
              number_text(pole.p.imag()) + " i (units c_ref |k|): the combined pair operator's sums of decaying "
              "exponentials cannot carry it; the two bodies' operators do",
          std::abs(pole.p.imag()) * s.reference_speed);
  const auto statics = half_space_pair_static_values(s);
  const CutTransform on_cut = [&](complex zeta, std::span<const complex> factor, std::span<complex> out) {
    const auto g = history_of_entries(s, zeta, entries_of_roots(s, roots_of_factors(s, zeta, factor)));
    for (std::size_t e = 0; e < 3; ++e) out[e] = g[e];
  };
  std::vector<ExponentialSum> cut =
      branch_cut_exponential_sums(s.branch_heights, statics, on_cut, tau_min, tau_max, nodes_per_panel,
                                  kPanelTolerance);
  std::array<ExponentialSum, 3> sums;
  for (std::size_t e = 0; e < 3; ++e) {
    sums[e] = std::move(cut[e]);
    for (const HalfSpacePairPole& pole : poles) {
      sums[e].rate.push_back(pole.p);
      sums[e].amplitude.push_back(pole.p.imag() == 0.0 ? 0.5 * pole.residue[e] : pole.residue[e]);
    }
  }
  return sums;
}

namespace {
// Durbin's formula f(t) = e^{sigma t}/T [-F(sigma)/2 + Re sum_{k<K} F(sigma + i k pi/T) e^{i k pi t/T}]
// with sigma T = 12 (aliasing ~e^{-24}), summed directly at the six check times,
// for N transforms at once (remainder(p) writes them).
constexpr int kCheckTerms = 1 << 15;
constexpr double kCheckPeriod = 24.0, kCheckSigma = 12.0 / kCheckPeriod;
constexpr double kCheckTaus[6] = {0.5, 1.0, 2.0, 4.0, 8.0, 16.0};
template <std::size_t N, class Remainder>
std::array<std::array<double, 6>, N> durbin_at_check_times(const Remainder& remainder) {
  constexpr int K = kCheckTerms;
  constexpr double T = kCheckPeriod, sigma = kCheckSigma;
  std::array<std::array<complex, 6>, N> acc{};
  for (int k = 0; k < K; ++k) {
    const auto g = remainder(complex(sigma, k * pi / T));
    for (int t = 0; t < 6; ++t) {
      const complex phase = std::polar(1.0, k * pi * kCheckTaus[t] / T);
      for (std::size_t e = 0; e < N; ++e) acc[e][t] += g[e] * phase;
    }
  }
  const auto g0 = remainder(complex(sigma, 0.0));
  std::array<std::array<double, 6>, N> out{};
  for (int t = 0; t < 6; ++t)
    for (std::size_t e = 0; e < N; ++e)
      out[e][t] = std::exp(sigma * kCheckTaus[t]) / T * (acc[e][t].real() - 0.5 * g0[e].real());
  return out;
}
}  // namespace

double half_space_pair_sum_check(const HalfSpacePairShape& s, const std::array<ExponentialSum, 3>& sums) {
  const double* taus = kCheckTaus;
  const auto initial = half_space_pair_initial_values(s);
  // The slowly decaying parts inverted in closed form: g_B(0+)/p (a step)
  // and c_e/(p^2 + 1) (c_e sin tau), c_e the p^-2 coefficient left.
  std::array<double, 3> c{};
  {
    const double p = 1e4;
    const auto g = half_space_pair_history_transforms(s, p);
    for (std::size_t e = 0; e < 3; ++e) c[e] = (p * p * g[e] - p * initial[e]).real();
  }
  const auto remainder = [&](complex p) {
    auto g = half_space_pair_history_transforms(s, p);
    for (std::size_t e = 0; e < 3; ++e) g[e] -= initial[e] / p + c[e] / (p * p + 1.0);
    return g;
  };
  const auto inverse = durbin_at_check_times<3>(remainder);
  double worst = 0.0;
  for (int t = 0; t < 6; ++t)
    for (std::size_t e = 0; e < 3; ++e) {
      const double reference = inverse[e][t] + initial[e] + c[e] * std::sin(taus[t]);
      worst = std::max(worst, std::abs(evaluate(sums[e], taus[t]) - reference));
    }
  return worst;
}

void verify_half_space_pair_sums(const HalfSpacePairShape& s) {
  const double worst = half_space_pair_sum_check(s, half_space_pair_exponential_sums(s, 0.5, 16.0));
  if (!(worst <= kCheckTolerance))
    throw HalfSpacePairCheckFailed("the combined half-space pair's kernels differ from a numerical inverse Laplace "
                             "transform by " + number_text(worst) + " (more than " + number_text(kCheckTolerance) +
                             " of mu k): a pole of the pair's response was missed; use the two bodies' operators");
}

}  // namespace slipstrip

namespace slipstrip {

complex antiplane_pair_denominator(const HalfSpaceShape& shape, complex p) {
  const double b = shape.slow_speed, w = shape.fast_weight;
  const complex a_f = std::sqrt(p - I) * std::sqrt(p + I);
  const complex a_s = (1.0 / b) * std::sqrt(p - I * b) * std::sqrt(p + I * b);
  return w * a_f + (1.0 - w) * a_s;
}

double verify_antiplane_half_space_pair(const HalfSpaceShape& shape) {
  if (!shape.antiplane_pair())
    throw std::invalid_argument("verify_antiplane_half_space_pair: needs an antiplane pair of different speeds");
  const double heights[2] = {1.0, shape.slow_speed};
  const std::vector<complex> zeros =
      cut_plane_zeros([&](complex p) { return antiplane_pair_denominator(shape, p); }, heights);
  if (!zeros.empty())
    throw HalfSpacePairCheckFailed("the combined antiplane half-space pair's response has a pole at p = " +
                                   number_text(zeros[0].real()) + " + " + number_text(zeros[0].imag()) +
                                   " i (units c_ref |k|), which its sums over the branch cuts do not carry; "
                                   "use the two bodies' operators");
  const ExponentialSum sum = half_space_exponential_sum(shape, 0.5, 16.0);
  // G = c2 / p^2 + O(p^-4), g(0+) = 0: c2 / (p^2 + 1) (c2 sin tau) inverted in
  // closed form leaves a remainder falling like p^-4.
  const double c2 = half_space_initial_slope(shape);
  const auto inverse = durbin_at_check_times<1>([&](complex p) {
    return std::array<complex, 1>{half_space_relaxation_transform(shape, p) - c2 / (p * p + 1.0)};
  });
  double worst = 0.0;
  for (int t = 0; t < 6; ++t)
    worst = std::max(worst, std::abs(evaluate(sum, kCheckTaus[t]) - (inverse[0][t] + c2 * std::sin(kCheckTaus[t]))));
  if (!(worst <= kCheckTolerance))
    throw HalfSpacePairCheckFailed("the combined antiplane half-space pair's kernel differs from a numerical inverse "
                                   "Laplace transform by " + number_text(worst) + " (more than " +
                                   number_text(kCheckTolerance) + " of mu_u k); use the two bodies' operators");
  return worst;
}

}  // namespace slipstrip
