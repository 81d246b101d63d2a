#include "stability/root_search.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>

namespace slipstrip {
namespace {

using complex = std::complex<double>;
constexpr double pi = std::numbers::pi;

// Sum of arg changes of g along the segment, refined until each step turns by less
// than max_turn (a zero passing at distance d from the contour is resolved once the
// step is ~d).  Throws rather than return an unresolved count.
double segment_turn(const AnalyticFunction& g, complex z1, complex g1, complex z2, complex g2,
                    int depth) {
  constexpr double max_turn = 0.25 * pi;
  const double turn = std::arg(g2 / g1);
  if (std::abs(turn) < max_turn) return turn;
  if (depth > 64)
    throw std::runtime_error("linear stability: argument principle did not resolve near Lambda = " +
                             std::to_string(z1.real()) + " + " + std::to_string(z1.imag()) +
                             " i (zero on the contour?)");
  const complex zm = 0.5 * (z1 + z2);
  const complex gm = g(zm);
  if (!std::isfinite(gm.real()) || !std::isfinite(gm.imag()) || gm == 0.0)
    throw std::runtime_error("linear stability: F not finite or zero on the contour at Lambda = " +
                             std::to_string(zm.real()) + " + " + std::to_string(zm.imag()) + " i");
  return segment_turn(g, z1, g1, zm, gm, depth + 1) + segment_turn(g, zm, gm, z2, g2, depth + 1);
}

// Newton on g with a central-difference derivative; returns nullopt if it leaves
// the (slightly enlarged) rectangle or does not converge.
std::optional<complex> newton_in_box(const AnalyticFunction& g, const Rectangle& b) {
  const double size = std::max(b.re1 - b.re0, b.im1 - b.im0);
  complex z(0.5 * (b.re0 + b.re1), 0.5 * (b.im0 + b.im1));
  const double slack = 1e-6 * size;
  for (int it = 0; it < 100; ++it) {
    const double h = 1e-7 * (size + 1e-3 * std::abs(z));
    const complex gz = g(z);
    const complex dg = (g(z + h) - g(z - h)) / (2.0 * h);
    if (dg == 0.0) return std::nullopt;
    const complex step = gz / dg;
    z -= step;
    if (z.real() < b.re0 - slack || z.real() > b.re1 + slack || z.imag() < b.im0 - slack ||
        z.imag() > b.im1 + slack)
      return std::nullopt;
    if (std::abs(step) <= 1e-14 * (std::abs(z) + size)) return z;
  }
  return std::nullopt;
}

void locate(const AnalyticFunction& g, const Rectangle& b, int count, double min_size,
            std::vector<complex>& roots) {
  if (count <= 0) return;
  const double size = std::max(b.re1 - b.re0, b.im1 - b.im0);
  if (count == 1 || size < min_size) {
    if (const auto z = newton_in_box(g, b)) {
      for (int j = 0; j < count; ++j) roots.push_back(*z);  // count > 1 only for a multiple root
      return;
    }
    if (size < min_size)
      throw std::runtime_error("linear stability: Newton failed in a tiny rectangle near Lambda = " +
                               std::to_string(0.5 * (b.re0 + b.re1)) + " + " +
                               std::to_string(0.5 * (b.im0 + b.im1)) + " i");
  }
  // Split off-centre so that symmetric features (real roots, conjugate pairs) never
  // sit on a cut.
  constexpr double cut = 0.4861;
  Rectangle first = b, second = b;
  if (b.re1 - b.re0 >= b.im1 - b.im0) {
    first.re1 = second.re0 = b.re0 + cut * (b.re1 - b.re0);
  } else {
    first.im1 = second.im0 = b.im0 + cut * (b.im1 - b.im0);
  }
  const int n_first = count_zeros(g, first);
  const int n_second = count_zeros(g, second);
  if (n_first + n_second != count)
    throw std::runtime_error("linear stability: subdivision counts do not add up");
  locate(g, first, n_first, min_size, roots);
  locate(g, second, n_second, min_size, roots);
}

}  // namespace

int count_zeros(const AnalyticFunction& g, const Rectangle& box) {
  constexpr int samples_per_edge = 256;  // dense enough that two nearby zeros do not alias
  const complex corners[5] = {{box.re0, box.im0}, {box.re1, box.im0}, {box.re1, box.im1},
                              {box.re0, box.im1}, {box.re0, box.im0}};
  double total = 0.0;
  complex z_prev = corners[0];
  complex g_prev = g(z_prev);
  for (int e = 0; e < 4; ++e) {
    for (int j = 1; j <= samples_per_edge; ++j) {
      const complex z = corners[e] + (corners[e + 1] - corners[e]) * (double(j) / samples_per_edge);
      const complex gz = g(z);
      if (!std::isfinite(gz.real()) || !std::isfinite(gz.imag()) || gz == 0.0)
        throw std::runtime_error("linear stability: F not finite or zero on the contour");
      total += segment_turn(g, z_prev, g_prev, z, gz, 0);
      z_prev = z;
      g_prev = gz;
    }
  }
  const double w = total / (2.0 * pi);
  const double n = std::round(w);
  if (std::abs(w - n) > 0.05)
    throw std::runtime_error("linear stability: winding number " + std::to_string(w) +
                             " is not an integer");
  return static_cast<int>(n);
}

std::vector<complex> locate_zeros(const AnalyticFunction& g, const Rectangle& box, int count,
                                  double min_size) {
  std::vector<complex> roots;
  locate(g, box, count, min_size, roots);
  return roots;
}

double location_resolution(const Rectangle& box) {
  return 1e-9 * std::max(box.re1 - box.re0, box.im1 - box.im0);
}

void sort_fastest_first(std::vector<complex>& roots, double tie) {
  std::sort(roots.begin(), roots.end(), [](complex x, complex y) {
    return x.real() != y.real() ? x.real() > y.real() : x.imag() > y.imag();
  });
  // The exact order of real parts that agree to rounding depends on the build
  // (FMA contraction, inlining); within such a run only the imaginary part counts.
  for (auto first = roots.begin(); first != roots.end();) {
    auto last = std::next(first);
    while (last != roots.end() && std::prev(last)->real() - last->real() <= tie) ++last;
    std::sort(first, last, [](complex x, complex y) { return x.imag() > y.imag(); });
    first = last;
  }
}

std::vector<complex> sorted_zeros_in(const AnalyticFunction& g, const Rectangle& box) {
  const double resolution = location_resolution(box);
  auto roots = locate_zeros(g, box, count_zeros(g, box), resolution);
  sort_fastest_first(roots, resolution);
  return roots;
}

}  // namespace slipstrip
