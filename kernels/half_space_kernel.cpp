#include "kernels/half_space_kernel.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

namespace slipstrip {
namespace {

using complex = std::complex<double>;
constexpr double pi = std::numbers::pi;

struct GaussRule {
  std::vector<double> node, weight;  // on [-1, 1]
};

// P_n(x) and P_n'(x) by the three-term recurrence (|x| < 1).
std::pair<double, double> legendre(int n, double x) {
  double p0 = 1.0, p1 = x;
  for (int k = 2; k <= n; ++k) {
    const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
    p0 = p1;
    p1 = p2;
  }
  return {p1, n * (x * p1 - p0) / (x * x - 1.0)};
}

// Gauss-Legendre rule by Newton iteration on P_n (n is small: <= 32).
GaussRule gauss_legendre(int n) {
  GaussRule rule;
  for (int i = 0; i < n; ++i) {
    double x = std::cos(pi * (i + 0.75) / (n + 0.5));
    for (int iteration = 0; iteration < 100; ++iteration) {
      const auto [p, dp] = legendre(n, x);
      const double step = p / dp;
      x -= step;
      if (std::abs(step) < 1e-16) break;
    }
    const double dp = legendre(n, x).second;
    rule.node.push_back(x);
    rule.weight.push_back(2.0 / ((1.0 - x * x) * dp * dp));
  }
  return rule;
}

// The square roots a_s = sqrt(1 + p^2), a_d = sqrt(1 + r^2 p^2) on one side of
// a branch cut.  zeta = i b - x lies on the cut that leaves the branch point
// i b horizontally to the left; the factor sqrt(zeta - i b) of the root that
// branches there is +i sqrt(x) on the upper side (side = +1) and -i sqrt(x) on
// the lower side.  Every other square-root factor is the principal one, whose
// own cut (pointing left from its branch point) is not crossed here; this is
// the continuation from Re p > 0 with all four cuts turned horizontal.
struct RootsOnCut {
  complex zeta, alpha_s, alpha_d;
};
RootsOnCut roots_on_cut(double r2, bool shear_branch, double x, int side) {
  const double r = std::sqrt(r2);
  const double b = shear_branch ? 1.0 : 1.0 / r;
  const complex zeta(-x, b);
  const complex on_cut(0.0, side * std::sqrt(x));
  const complex i(0.0, 1.0);
  const complex alpha_s =
      shear_branch ? on_cut * std::sqrt(zeta + i) : std::sqrt(zeta - i) * std::sqrt(zeta + i);
  const complex alpha_d = shear_branch ? r * std::sqrt(zeta - i / r) * std::sqrt(zeta + i / r)
                                       : r * on_cut * std::sqrt(zeta + i / r);
  return {zeta, alpha_s, alpha_d};
}

// G on one side of a branch cut (roots_on_cut).
complex relaxation_on_cut(const HalfSpaceShape& shape, bool shear_branch, double x, int side) {
  const double r2 = shape.speed_ratio_squared;
  if (shape.antiplane) {
    // G = (a_s / p - 1) / 2: only the shear branch point i (and -i).
    const complex zeta(-x, 1.0);
    const complex alpha_s = complex(0.0, side * std::sqrt(x)) * std::sqrt(zeta + complex(0.0, 1.0));
    return 0.5 * (alpha_s / zeta - 1.0);
  }
  const auto [zeta, alpha_s, alpha_d] = roots_on_cut(r2, shear_branch, x, side);
  return 2.0 * (1.0 - r2) / (zeta * (alpha_s + alpha_d)) + zeta / (2.0 * alpha_s) - 0.5;
}

// The exponential sum of any G with the in-plane (or, antiplane, the shear)
// branch points: g(tau) = static + sum over the four cuts of
//   -1/(2 pi i) int_0^inf [G_+(ib - x) - G_-(ib - x)] e^{(ib - x) tau} dx
// (the lower cuts give the complex conjugates, G being real on the real axis).
// With x = u^2 the integrand is smooth at u = 0 and carries the factor
// e^{-u^2 tau}: for tau >= tau_min it is below e^{-36} beyond u_max =
// sqrt(36 / tau_min); below u_min = tau_max^{-1/2} it is nearly constant for
// tau <= tau_max.  Panels [0, u_min], then doubling up to u_max, resolve
// e^{-u^2 tau} uniformly.
template <class OnCut>
ExponentialSum cut_exponential_sum(double static_value, double r2, int branches, double tau_min,
                                   double tau_max, int nodes_per_panel, const OnCut& on_cut) {
  if (!(tau_min > 0.0 && tau_max > tau_min))
    throw std::invalid_argument("half_space_exponential_sum: need 0 < tau_min < tau_max");
  if (nodes_per_panel < 2 || nodes_per_panel > 32)
    throw std::invalid_argument("half_space_exponential_sum: nodes_per_panel must be in [2, 32]");
  const double u_min = 1.0 / std::sqrt(tau_max);
  const double u_max = std::sqrt(36.0 / tau_min);
  std::vector<double> edges{0.0, u_min};
  while (edges.back() < u_max) edges.push_back(2.0 * edges.back());
  const auto rule = gauss_legendre(nodes_per_panel);

  ExponentialSum sum;
  sum.static_value = static_value;
  const double b_values[2] = {1.0, branches == 1 ? 0.0 : 1.0 / std::sqrt(r2)};
  for (int branch = 0; branch < branches; ++branch) {
    const bool shear = branch == 0;
    for (std::size_t p = 0; p + 1 < edges.size(); ++p) {
      const double a = edges[p], c = edges[p + 1];
      for (int j = 0; j < nodes_per_panel; ++j) {
        const double u = 0.5 * (c - a) * rule.node[j] + 0.5 * (c + a);
        const double w = 0.5 * (c - a) * rule.weight[j];
        const double x = u * u;
        const complex jump = on_cut(shear, x, +1) - on_cut(shear, x, -1);
        const complex density = -jump / complex(0.0, 2.0 * pi);
        sum.rate.emplace_back(-x, b_values[branch]);
        sum.amplitude.push_back(w * 2.0 * u * density);
      }
    }
  }
  return sum;
}

// A panel's rule of the antiplane pair's sums is kept when 4 more nodes change
// it by at most this (units mu_u |k|; branch_cut_exponential_sums).
constexpr double kAntiplanePairPanelTolerance = 1e-12;

void require_speed_ratio(double r2) {
  if (!(r2 > 0.0 && r2 < 1.0))
    throw std::invalid_argument("half_space_exponential_sum: c_s^2/c_d^2 = " + std::to_string(r2) +
                                " must lie in (0, 1)");
}

}  // namespace

complex half_space_relaxation_transform(double r2, complex p) {
  // Principal roots: for Re p > 0, 1 + c p^2 never lies on the negative real
  // axis, and on the imaginary axis the signed zero of Im(p^2) picks the
  // limit from Re p > 0 (as in strip_response).
  const complex alpha_s = std::sqrt(1.0 + p * p);
  const complex alpha_d = std::sqrt(1.0 + r2 * (p * p));
  return 2.0 * (1.0 - r2) / (p * (alpha_s + alpha_d)) + p / (2.0 * alpha_s) - 0.5;
}

double half_space_initial_slope(double r2) { return 1.75 - 2.0 * std::sqrt(r2); }

HalfSpaceShape half_space_shape(const ElasticMaterial& material) {
  return {1.0 / material.wave_speed_ratio_squared(), material.antiplane()};
}

AntiplaneHalfSpacePair antiplane_half_space_pair(const ElasticMaterial& top, const ElasticMaterial& bottom) {
  for (const ElasticMaterial* m : {&top, &bottom})
    if (!m->antiplane() || !(m->shear_modulus > 0.0 && m->density > 0.0 && std::isfinite(m->shear_modulus) &&
                             std::isfinite(m->density)))
      throw std::invalid_argument(
          "antiplane_half_space_pair: both bodies must be antiplane with finite shear_modulus > 0 and density > 0");
  const double c_top = top.shear_wave_speed(), c_bottom = bottom.shear_wave_speed();
  const ElasticMaterial& fast = c_bottom > c_top ? bottom : top;
  const ElasticMaterial& slow = c_bottom > c_top ? top : bottom;
  AntiplaneHalfSpacePair pair;
  // mu_u = 2 mu_f w_s, w_s = mu_s / (mu_t + mu_b): exactly mu for identical
  // bodies (w_s = 1/2), so that they get the identical pair's operator bit for bit.
  const double sum = top.shear_modulus + bottom.shear_modulus;
  pair.modulus = 2.0 * fast.shear_modulus * (slow.shear_modulus / sum);
  pair.reference_speed = fast.shear_wave_speed();
  pair.shape.speed_ratio_squared = 1.0 / fast.wave_speed_ratio_squared();  // as half_space_shape (unused)
  pair.shape.antiplane = true;
  if (c_top == c_bottom) {
    // One shear speed: the identical pair's function in units of mu_u, and its
    // radiation damping mu_u / (2 c) as ElasticMaterial writes it.
    pair.radiation_damping = pair.modulus / (2.0 * pair.reference_speed);
    return pair;
  }
  pair.shape.slow_speed = slow.shear_wave_speed() / fast.shear_wave_speed();
  pair.shape.fast_weight = fast.shear_modulus / sum;
  // eta_c = eta_t eta_b / (eta_t + eta_b), eta_i = mu_i / c_i, as TwoBodyHistory forms it.
  const double eta_top = 2.0 * top.radiation_damping(), eta_bottom = 2.0 * bottom.radiation_damping();
  pair.radiation_damping = eta_top * eta_bottom / (eta_top + eta_bottom);
  return pair;
}

double half_space_instantaneous_value(const HalfSpaceShape& shape) {
  if (!shape.antiplane_pair()) return 0.5;
  const double w = shape.fast_weight;
  return 0.5 / (w * shape.slow_speed + (1.0 - w));
}

double half_space_second_branch(const HalfSpaceShape& shape) {
  return shape.antiplane_pair() ? shape.slow_speed : std::sqrt(1.0 / shape.speed_ratio_squared);
}

namespace {
// The antiplane pair's G from its roots a_f, a_s (any sheet), written without
// the cancellation of two O(1) terms at large p: with g_f = 1, g_s = 1/b,
// d_i = a_i - g_i p = 1 / (a_i + g_i p) (a_i^2 = 1 + g_i^2 p^2 on every sheet;
// the form without cancellation is taken) and S = w + (1 - w) / b,
//   G = (1/2) [w a_f d_s + (1 - w) g_s a_s d_f] / (p (w a_f + (1 - w) a_s) S).
complex antiplane_pair_relaxation(const HalfSpaceShape& shape, complex p, complex a_f, complex a_s) {
  const double w = shape.fast_weight, g_s = 1.0 / shape.slow_speed;
  const auto excess = [](complex a, complex gp) {
    return std::abs(a + gp) >= std::abs(a - gp) ? 1.0 / (a + gp) : a - gp;
  };
  const complex d_f = excess(a_f, p), d_s = excess(a_s, g_s * p);
  const double S = w + (1.0 - w) * g_s;
  return 0.5 * (w * a_f * d_s + (1.0 - w) * g_s * a_s * d_f) / (p * (w * a_f + (1.0 - w) * a_s) * S);
}
}  // namespace

complex half_space_relaxation_transform(const HalfSpaceShape& shape, complex p) {
  if (shape.antiplane_pair()) {
    const double b = shape.slow_speed;
    return antiplane_pair_relaxation(shape, p, std::sqrt(1.0 + p * p), std::sqrt(1.0 + (p * p) / (b * b)));
  }
  if (!shape.antiplane) return half_space_relaxation_transform(shape.speed_ratio_squared, p);
  // (sqrt(1 + p^2)/p - 1)/2 written without the cancellation of two O(1)
  // terms at large p: sqrt(1+p^2)/p - 1 = 1 / (p (sqrt(1+p^2) + p)).
  const complex a = std::sqrt(1.0 + p * p);
  return 0.5 / (p * (a + p));
}

double half_space_static_value(const HalfSpaceShape& shape) {
  return shape.antiplane ? 0.5 : 1.0 - shape.speed_ratio_squared;
}

namespace {
// The antiplane pair's G = c2 / p^2 + c4 / p^4 + ...: with x = 1/p,
// a_i / p = g_i + x^2 / (2 g_i) - x^4 / (8 g_i^3) + ..., the quotient
// (a_f a_s / p^2) / ((w a_f + (1 - w) a_s) / p) expanded in x^2.
std::pair<double, double> antiplane_pair_coefficients(const HalfSpaceShape& shape) {
  const double w = shape.fast_weight, g1 = 1.0, g2 = 1.0 / shape.slow_speed;
  const double u1 = 0.5 / g1, u2 = 0.5 / g2, v1 = -0.125 / (g1 * g1 * g1), v2 = -0.125 / (g2 * g2 * g2);
  const double S = w * g1 + (1.0 - w) * g2, U = w * u1 + (1.0 - w) * u2, V = w * v1 + (1.0 - w) * v2;
  const double n0 = g1 * g2, n2 = g1 * u2 + g2 * u1, n4 = g1 * v2 + g2 * v1 + u1 * u2;
  const double c2 = (n2 - n0 * U / S) / (2.0 * S);
  const double c4 = (n4 - n2 * U / S + n0 * (U * U / (S * S) - V / S)) / (2.0 * S);
  return {c2, c4};
}
}  // namespace

double half_space_initial_slope(const HalfSpaceShape& shape) {
  if (shape.antiplane_pair()) return antiplane_pair_coefficients(shape).first;
  return shape.antiplane ? 0.25 : half_space_initial_slope(shape.speed_ratio_squared);
}

double half_space_fourth_coefficient(const HalfSpaceShape& shape) {
  if (shape.antiplane_pair()) return antiplane_pair_coefficients(shape).second;
  // In-plane: 19/16 - 1/r (docs/theory.md 8.1).  Antiplane:
  // (sqrt(1 + 1/p^2) - 1)/2 = 1/(4 p^2) - 1/(16 p^4) + ...
  return shape.antiplane ? -0.0625 : 1.1875 - 1.0 / std::sqrt(shape.speed_ratio_squared);
}

ExponentialSum half_space_exponential_sum(double r2, double tau_min, double tau_max,
                                          int nodes_per_panel) {
  return half_space_exponential_sum(HalfSpaceShape{r2, false}, tau_min, tau_max, nodes_per_panel);
}

ExponentialSum half_space_exponential_sum(const HalfSpaceShape& shape, double tau_min,
                                          double tau_max, int nodes_per_panel) {
  if (shape.antiplane_pair()) {
    // Cuts from p = i (a_f) and from p = i b (a_s): a_i = g_i sqrt(zeta - i b_i)
    // sqrt(zeta + i b_i), the first factor continued by the cut integration.
    const double b = shape.slow_speed;
    if (!(b > 0.0 && b < 1.0) || !(shape.fast_weight > 0.0 && shape.fast_weight < 1.0))
      throw std::invalid_argument("half_space_exponential_sum: an antiplane pair needs 0 < b < 1 and 0 < w < 1");
    const double heights[2] = {1.0, b};
    const double statics[1] = {half_space_static_value(shape)};
    const complex i(0.0, 1.0);
    const CutTransform on_cut = [&](complex zeta, std::span<const complex> factor, std::span<complex> out) {
      const complex a_f = factor[0] * std::sqrt(zeta + i);
      const complex a_s = (1.0 / b) * factor[1] * std::sqrt(zeta + i * b);
      out[0] = antiplane_pair_relaxation(shape, zeta, a_f, a_s);
    };
    return std::move(branch_cut_exponential_sums(heights, statics, on_cut, tau_min, tau_max, nodes_per_panel,
                                                 kAntiplanePairPanelTolerance)[0]);
  }
  if (!shape.antiplane) require_speed_ratio(shape.speed_ratio_squared);
  return cut_exponential_sum(half_space_static_value(shape), shape.speed_ratio_squared, shape.antiplane ? 1 : 2,
                             tau_min, tau_max, nodes_per_panel, [&](bool shear, double x, int side) {
                               return relaxation_on_cut(shape, shear, x, side);
                             });
}

ExponentialSum in_plane_exponential_sum(double r2, double static_value, const InPlaneTransform& transform,
                                        double tau_min, double tau_max, int nodes_per_panel) {
  require_speed_ratio(r2);
  return cut_exponential_sum(static_value, r2, 2, tau_min, tau_max, nodes_per_panel,
                             [&](bool shear, double x, int side) {
                               const RootsOnCut c = roots_on_cut(r2, shear, x, side);
                               return transform(c.zeta, c.alpha_s, c.alpha_d);
                             });
}

std::vector<ExponentialSum> branch_cut_exponential_sums(std::span<const double> heights,
                                                        std::span<const double> static_values,
                                                        const CutTransform& on_cut, double tau_min, double tau_max,
                                                        int nodes_per_panel, double tolerance) {
  if (!(tau_min > 0.0 && tau_max > tau_min))
    throw std::invalid_argument("branch_cut_exponential_sums: need 0 < tau_min < tau_max");
  if (nodes_per_panel < 2 || nodes_per_panel > 32)
    throw std::invalid_argument("branch_cut_exponential_sums: nodes_per_panel must be in [2, 32]");
  if (!(tolerance > 0.0)) throw std::invalid_argument("branch_cut_exponential_sums: need tolerance > 0");
  if (heights.empty() || static_values.empty())
    throw std::invalid_argument("branch_cut_exponential_sums: need at least one branch point and one transform");
  for (std::size_t k = 0; k < heights.size(); ++k) {
    if (!(heights[k] > 0.0 && std::isfinite(heights[k])))
      throw std::invalid_argument("branch_cut_exponential_sums: branch heights must be positive and finite");
    for (std::size_t l = 0; l < k; ++l)
      if (heights[l] == heights[k])
        throw std::invalid_argument("branch_cut_exponential_sums: branch heights must be distinct");
  }
  const std::size_t entries = static_values.size(), branches = heights.size();
  const double u_min = 1.0 / std::sqrt(tau_max);
  const double u_max = std::sqrt(36.0 / tau_min);
  std::vector<double> edges{0.0, u_min};
  while (edges.back() < u_max) edges.push_back(2.0 * edges.back());
  std::vector<double> taus;
  for (double tau = tau_min; tau < tau_max; tau *= 2.0) taus.push_back(tau);
  taus.push_back(tau_max);

  // One panel's rule of `nodes` nodes on cut j: per node x = u^2 and the
  // entries' amplitudes w 2u (-jump / (2 pi i)).
  struct PanelRule {
    std::vector<double> x;
    std::vector<complex> amplitude;  // node-major, `entries` per node
  };
  std::vector<complex> factor(branches), upper(entries), lower(entries);
  const auto panel_rule = [&](std::size_t j, double a, double c, int nodes) {
    const GaussRule rule = gauss_legendre(nodes);
    PanelRule out;
    for (int n = 0; n < nodes; ++n) {
      const double u = 0.5 * (c - a) * rule.node[n] + 0.5 * (c + a);
      const double w = 0.5 * (c - a) * rule.weight[n];
      const double x = u * u;
      const complex zeta(-x, heights[j]);
      for (int side : {+1, -1}) {
        for (std::size_t k = 0; k < branches; ++k)
          factor[k] = k == j ? complex(0.0, side * std::sqrt(x)) : std::sqrt(zeta - complex(0.0, heights[k]));
        on_cut(zeta, factor, side > 0 ? std::span<complex>(upper) : std::span<complex>(lower));
      }
      out.x.push_back(x);
      for (std::size_t e = 0; e < entries; ++e)
        out.amplitude.push_back(w * 2.0 * u * (-(upper[e] - lower[e]) / complex(0.0, 2.0 * pi)));
    }
    return out;
  };
  // The panel's contribution to entry e at tau (the cut's common factor
  // e^{i b tau} left out).
  const auto moment = [&](const PanelRule& r, std::size_t e, double tau) {
    complex acc = 0.0;
    for (std::size_t n = 0; n < r.x.size(); ++n) acc += r.amplitude[n * entries + e] * std::exp(-r.x[n] * tau);
    return acc;
  };
  const auto agree = [&](const PanelRule& a, const PanelRule& b) {
    for (std::size_t e = 0; e < entries; ++e)
      for (double tau : taus)
        if (std::abs(moment(a, e, tau) - moment(b, e, tau)) > tolerance) return false;
    return true;
  };
  std::vector<ExponentialSum> sums(entries);
  for (std::size_t e = 0; e < entries; ++e) sums[e].static_value = static_values[e];
  const auto append = [&](std::size_t j, const PanelRule& r) {
    for (std::size_t n = 0; n < r.x.size(); ++n)
      for (std::size_t e = 0; e < entries; ++e) {
        sums[e].rate.emplace_back(-r.x[n], heights[j]);
        sums[e].amplitude.push_back(r.amplitude[n * entries + e]);
      }
  };
  // A panel's rule is accepted when the rule of 4 more nodes agrees with it;
  // else the panel takes 4 more nodes (their integrand is analytic across the
  // panel, so more nodes converge faster than halves), up to 32, beyond which
  // it is split in halves (up to 12 times).
  constexpr int kMaxSplits = 12, kNodeStep = 4, kMaxNodes = 32;
  const auto refine = [&](auto&& self, std::size_t j, double a, double c, int depth) -> void {
    PanelRule rule = panel_rule(j, a, c, nodes_per_panel);
    for (int nodes = nodes_per_panel; nodes + kNodeStep <= kMaxNodes; nodes += kNodeStep) {
      PanelRule finer = panel_rule(j, a, c, nodes + kNodeStep);
      if (agree(rule, finer)) {
        append(j, rule);
        return;
      }
      rule = std::move(finer);
    }
    if (depth >= kMaxSplits) {
      append(j, rule);
      return;
    }
    const double m = 0.5 * (a + c);
    self(self, j, a, m, depth + 1);
    self(self, j, m, c, depth + 1);
  };
  for (std::size_t j = 0; j < branches; ++j)
    for (std::size_t p = 0; p + 1 < edges.size(); ++p) refine(refine, j, edges[p], edges[p + 1], 0);
  return sums;
}

double evaluate(const ExponentialSum& sum, double tau) {
  complex acc = 0.0;
  for (std::size_t j = 0; j < sum.rate.size(); ++j) acc += sum.amplitude[j] * std::exp(sum.rate[j] * tau);
  return sum.static_value + 2.0 * acc.real();
}

}  // namespace slipstrip
