#include "kernels/passivity.hpp"

// GCC 12 reports false -Wmaybe-uninitialized inside Eigen's AVX-512 kernels
// (uninitialised lanes of partial packets); the whole translation unit is
// compiled without that one warning rather than drowning real ones.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "kernels/half_space_kernel.hpp"

namespace slipstrip {

double strip_passivity_beta_limit(double speed_ratio_squared) {
  return 1.0 / (std::numbers::pi * (1.0 - 1.0 / speed_ratio_squared));
}

std::vector<double> minimum_norm_point(std::span<const double> C_flat, std::span<const double> b,
                                       int n) {
  const int rows = static_cast<int>(b.size());
  if (n < 1 || C_flat.size() != static_cast<std::size_t>(rows) * n)
    throw std::invalid_argument("minimum_norm_point: C must be rows x n");
  using Matrix = Eigen::MatrixXd;
  using Vector = Eigen::VectorXd;
  const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> C(
      C_flat.data(), rows, n);
  const Eigen::Map<const Vector> rhs(b.data(), rows);

  // Scale for the feasibility tolerance: the size of what has to be corrected
  // (constraints with b < 0 hold at x = 0 whatever their size).
  const double scale = std::max(1.0, rhs.maxCoeff());
  const double tolerance = 1e-13 * scale;

  Vector x = Vector::Zero(n);
  std::vector<int> active;       // indices of active constraints
  std::vector<double> multiplier;  // their Lagrange multipliers (>= 0)

  for (int outer = 0; outer < 10 * rows + 100; ++outer) {
    // Most violated constraint.
    const Vector slack = C * x - rhs;
    int p = -1;
    double worst = -tolerance;
    for (int i = 0; i < rows; ++i)
      if (slack[i] < worst) {
        worst = slack[i];
        p = i;
      }
    if (p < 0) return std::vector<double>(x.data(), x.data() + n);

    const Vector normal = C.row(p).transpose();
    double multiplier_p = 0.0;
    for (int inner = 0; inner < 4 * n + 10; ++inner) {
      // Primal direction z = projection of the normal off the active normals;
      // dual direction r = (N^T N)^{-1} N^T normal.
      Vector z = normal;
      Vector r;
      const int m = static_cast<int>(active.size());
      if (m > 0) {
        Matrix N(n, m);
        for (int k = 0; k < m; ++k) N.col(k) = C.row(active[k]).transpose();
        r = (N.transpose() * N).ldlt().solve(N.transpose() * normal);
        z -= N * r;
      }
      // Largest dual step that keeps the active multipliers >= 0.
      double t_dual = std::numeric_limits<double>::infinity();
      int blocking = -1;
      for (int k = 0; k < m; ++k)
        if (r[k] > 0.0 && multiplier[k] / r[k] < t_dual) {
          t_dual = multiplier[k] / r[k];
          blocking = k;
        }
      const double zz = z.dot(normal);
      const double violation = normal.dot(x) - rhs[p];
      double t_primal = std::numeric_limits<double>::infinity();
      if (zz > 1e-14 * normal.squaredNorm()) t_primal = -violation / zz;
      const double t = std::min(t_dual, t_primal);
      if (!std::isfinite(t))
        throw std::runtime_error("minimum_norm_point: the constraints are inconsistent");
      if (std::isfinite(t_primal)) x += t * z;
      for (int k = 0; k < m; ++k) multiplier[k] -= t * r[k];
      multiplier_p += t;
      if (t == t_primal) {
        active.push_back(p);
        multiplier.push_back(multiplier_p);
        break;
      }
      // A constraint leaves the active set; keep stepping on p.
      active.erase(active.begin() + blocking);
      multiplier.erase(multiplier.begin() + blocking);
    }
  }
  throw std::runtime_error("minimum_norm_point: no convergence");
}

namespace {

// sum_{m != 0} (theta + 2 pi m)^-2 and ^-4 for |theta| <= pi, in closed form
// (from sum_m (theta + 2 pi m)^-2 = 1 / (4 sin^2(theta/2))), with the Taylor
// series sum_k c_k theta^k, c_k = binom(k+q-1, q-1) 2 zeta(k+q) / (2 pi)^(k+q),
// near theta = 0 where the closed form cancels.
struct AliasSums {
  double inverse_square, inverse_fourth;
};
AliasSums alias_sums(double theta) {
  constexpr double pi = std::numbers::pi, two_pi = 2.0 * pi;
  const double a = std::abs(theta);
  if (a < 0.3) {
    // zeta(2..14)
    const double zeta[] = {0, 0, pi * pi / 6, 1.2020569031595942, std::pow(pi, 4) / 90,
                           1.0369277551433699, std::pow(pi, 6) / 945, 1.0083492773819228,
                           std::pow(pi, 8) / 9450, 1.0020083928260822, std::pow(pi, 10) / 93555,
                           1.0004941886041195, 691 * std::pow(pi, 12) / 638512875.0,
                           1.0001227133475785, 2 * std::pow(pi, 14) / 18243225.0};
    double s2 = 0, s4 = 0;
    for (int k = 0; k <= 10; k += 2) {
      const double tk = std::pow(theta, k);
      s2 += (k + 1) * tk * 2 * zeta[k + 2] / std::pow(two_pi, k + 2);
      if (k + 4 <= 14)
        s4 += (k + 1) * (k + 2) * (k + 3) / 6.0 * tk * 2 * zeta[k + 4] / std::pow(two_pi, k + 4);
    }
    return {s2, s4};
  }
  const double sn = std::sin(0.5 * theta), ct = std::cos(0.5 * theta) / sn;
  const double csc2 = 1.0 / (sn * sn);
  const double t2 = theta * theta;
  return {0.25 * csc2 - 1.0 / t2,
          (0.25 * csc2 * ct * ct + 0.125 * csc2 * csc2) / 6.0 - 1.0 / (t2 * t2)};
}

// (argument, value) of the minimum of f on [lo, hi], f unimodal there.
template <class F>
std::pair<double, double> golden_section_minimum(F&& f, double lo, double hi) {
  const double golden = 0.5 * (std::sqrt(5.0) - 1.0);
  double x1 = hi - golden * (hi - lo), x2 = lo + golden * (hi - lo);
  double f1 = f(x1), f2 = f(x2);
  for (int it = 0; it < 50; ++it) {  // 0.618^50 ~ 4e-11 of the bracket
    if (f1 < f2) {
      hi = x2;
      x2 = x1;
      f2 = f1;
      x1 = hi - golden * (hi - lo);
      f1 = f(x1);
    } else {
      lo = x1;
      x1 = x2;
      f1 = f2;
      x2 = lo + golden * (hi - lo);
      f2 = f(x2);
    }
  }
  return f1 < f2 ? std::pair{x1, f1} : std::pair{x2, f2};
}

}  // namespace

double sampled_half_space_real_part(double r2, double h, double theta) {
  return sampled_half_space_real_part(HalfSpaceShape{r2, false}, h, theta);
}

double sampled_half_space_real_part(const HalfSpaceShape& shape, double h, double theta) {
  constexpr double two_pi = 2.0 * std::numbers::pi;
  // Re G(i w) = -c2 / w^2 + c4 / w^4 + O(w^-6) for w > c_d / c_s: the two
  // leading terms are summed over all aliases in closed form, the O(w^-6)
  // remainder over |m| <= 8 (the rest is < 1e-10 (c_s k dt)^6).
  // (Antiplane: w > 1 and the coefficients of kernels/half_space_kernel.hpp.)
  constexpr int M = 8;
  const double c2 = half_space_initial_slope(shape), c4 = half_space_fourth_coefficient(shape);
  auto remainder = [&](double omega) {
    const double w2 = omega * omega;
    return half_space_relaxation_transform(shape, std::complex<double>(0.0, omega)).real() + c2 / w2 -
           c4 / (w2 * w2);
  };
  double value = half_space_instantaneous_value(shape) +
                 half_space_relaxation_transform(shape, std::complex<double>(0.0, theta / h)).real();
  for (int m = 1; m <= M; ++m)
    value += remainder((theta + two_pi * m) / h) + remainder((theta - two_pi * m) / h);
  const auto sums = alias_sums(theta);
  value += -c2 * h * h * sums.inverse_square + c4 * h * h * h * h * sums.inverse_fourth;
  return value;
}

std::vector<double> half_space_passivity_correction(double r2, double h, int lags, double margin) {
  return half_space_passivity_correction(HalfSpaceShape{r2, false}, h, lags, margin);
}

std::vector<double> half_space_passivity_correction(const HalfSpaceShape& shape, double h, int lags,
                                                    double margin) {
  constexpr double pi = std::numbers::pi;
  // The exact Re Z vanishes on (0, h) and touches zero at sqrt(2) h; both lie
  // in (0, 2.5 h), which gets a dense grid of its own.
  const int n_band = 256, n_circle = 384;
  const double band = std::min(pi, 2.5 * h);
  std::vector<double> theta;
  theta.reserve(n_band + n_circle + 80);
  for (int i = 0; i < n_band; ++i) theta.push_back((i + 0.5) * band / n_band);
  for (int i = 0; i < n_circle; ++i) theta.push_back((i + 0.5) * pi / n_circle);
  // Re Z has square-root cusps at the branch points w = c_s k and c_d k and
  // touches zero at w = sqrt(2) c_s k: a minimum of Re Z_d can sit exactly
  // there, so those points and geometric clusters around them are constraints.
  // (Antiplane: the one cusp at w = c_s k; Re Z > 0 above it.  An antiplane
  // pair of different speeds: the cusps at w = c_slow k and c_ref k, Re Z = 0
  // below the first.)
  std::vector<double> singular_points{h};
  if (shape.antiplane_pair()) singular_points.push_back(h * shape.slow_speed);
  if (!shape.antiplane)
    singular_points.insert(singular_points.end(),
                           {std::sqrt(2.0) * h, h / std::sqrt(shape.speed_ratio_squared)});
  for (double singular : singular_points) {
    if (singular >= pi) continue;
    if (singular != h) theta.push_back(singular);
    for (int k = 1; k <= 12; ++k)
      for (double side : {-1.0, 1.0}) {
        const double t = singular * (1.0 + side * std::pow(10.0, -k));
        if (t > 0.0 && t < pi) theta.push_back(t);
      }
  }
  // Constraint points (theta, Re Z_d of the sampled kernel there), kept sorted.
  struct Point {
    double theta, base;
  };
  std::vector<Point> points;
  points.reserve(theta.size());
  for (double t : theta) points.push_back({t, sampled_half_space_real_part(shape, h, t)});
  auto by_theta = [](const Point& x, const Point& y) { return x.theta < y.theta; };
  std::sort(points.begin(), points.end(), by_theta);

  auto corrected = [&](const std::vector<double>& e, double t, double base_value) {
    double v = base_value;
    for (int j = 0; j < lags; ++j) v += e[j] * std::cos((j + 1) * t);
    return v;
  };
  auto fail = [&]() {
    std::ostringstream msg;
    msg << "the half-space operator cannot be made passive at c_s |k| dt = " << h << " with "
        << lags << " corrected lags (reduce time.beta)";
    return std::runtime_error(msg.str());
  };

  // Cutting planes: solve on the grid, then look between grid points near every
  // low local minimum (golden section) and add any point that still violates
  // the bound.  A few rounds suffice: the corrected Re Z_d is smooth there.
  for (int round = 0; round < 20; ++round) {
    const int rows = static_cast<int>(points.size());
    std::vector<double> C(static_cast<std::size_t>(rows) * lags), b(rows);
    for (int i = 0; i < rows; ++i) {
      b[i] = margin - points[i].base;
      for (int j = 0; j < lags; ++j) C[i * lags + j] = std::cos((j + 1) * points[i].theta);
    }
    std::vector<double> e;
    try {
      e = minimum_norm_point(C, b, lags);
    } catch (const std::runtime_error&) {
      throw fail();
    }
    std::vector<double> value(rows);
    for (int i = 0; i < rows; ++i) value[i] = corrected(e, points[i].theta, points[i].base);
    std::vector<double> added;
    for (int i = 0; i < rows; ++i) {
      const bool low = value[i] < margin + 1e-3;  // eta = 0.5: only near-zero minima matter
      const bool local_min = (i == 0 || value[i] <= value[i - 1]) && (i + 1 == rows || value[i] <= value[i + 1]);
      if (!low || !local_min) continue;
      const double lo = i == 0 ? 0.5 * points[0].theta : points[i - 1].theta;
      const double hi = i + 1 == rows ? 0.5 * (points[i].theta + pi) : points[i + 1].theta;
      const auto [t_min, f_min] = golden_section_minimum(
          [&](double t) { return corrected(e, t, sampled_half_space_real_part(shape, h, t)); }, lo, hi);
      // (the QP meets its constraints to ~1e-13, so only a clear miss counts)
      if (f_min < 0.5 * margin) added.push_back(t_min);
    }
    if (added.empty()) return e;
    for (double t : added) points.push_back({t, sampled_half_space_real_part(shape, h, t)});
    std::sort(points.begin(), points.end(), by_theta);
  }
  throw fail();
}

}  // namespace slipstrip
