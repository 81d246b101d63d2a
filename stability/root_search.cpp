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
constexpr int kSamplesPerEdge = 256;  // dense enough that two nearby zeros do not alias

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
  // Where F is a sum of terms much larger than F near the root (rate-and-state
  // terms that cancel), rounding stalls Newton at steps above 1e-14 |z|
  // (pmma_homalite_pair.toml at L = 300 m: steps of 1.3e-12 |z| from the
  // 1e-5 Pa/m noise of F).  Such an iterate is accepted when the last
  // `stalled` steps all stayed below 1e-6 of the rectangle: the zero is then
  // located far below the subdivision's resolution.
  constexpr int stalled = 10;
  int small_steps = 0;
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
    small_steps = std::abs(step) <= 1e-6 * size ? small_steps + 1 : 0;
  }
  if (small_steps >= stalled) return z;
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
  int n_first = count_zeros(g, first);
  int n_second = count_zeros(g, second);
  // Counts that do not add up mean that some contour stepped over a pair of
  // features (a zero with a small Re next to a pole on Re = 0 turns the argument
  // by 2 pi between two samples).  Recount the three contours at 16 and 256
  // times the sampling before giving up.
  for (int finer = 16; n_first + n_second != count && finer <= 256; finer *= 16) {
    count = count_zeros(g, b, finer * kSamplesPerEdge);
    n_first = count_zeros(g, first, finer * kSamplesPerEdge);
    n_second = count_zeros(g, second, finer * kSamplesPerEdge);
  }
  if (n_first + n_second != count)
    throw std::runtime_error("linear stability: subdivision counts do not add up");
  locate(g, first, n_first, min_size, roots);
  locate(g, second, n_second, min_size, roots);
}

}  // namespace

int count_zeros(const AnalyticFunction& g, const Rectangle& box) { return count_zeros(g, box, kSamplesPerEdge); }

int count_zeros(const AnalyticFunction& g, const Rectangle& box, int samples_per_edge) {
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

std::vector<Rectangle> graded_tiling(const Rectangle& box, double inner) {
  if (!(inner > 0.0)) throw std::invalid_argument("graded_tiling: inner half-side must be > 0");
  std::vector<Rectangle> pieces;
  const auto keep = [&](Rectangle r) {
    r.re0 = std::max(r.re0, box.re0);
    r.re1 = std::min(r.re1, box.re1);
    r.im0 = std::max(r.im0, box.im0);
    r.im1 = std::min(r.im1, box.im1);
    if (r.re1 > r.re0 && r.im1 > r.im0) pieces.push_back(r);
  };
  const double extent = std::max({box.re1, -box.im0, box.im1});
  if (inner >= extent) return {box};
  keep({box.re0, inner, -inner, inner});
  for (double s = inner; s < extent; s *= 4.0) {
    const double t = 4.0 * s;
    keep({box.re0, t, s, t});    // top
    keep({box.re0, t, -t, -s});  // bottom
    keep({s, t, -s, s});         // right
  }
  return pieces;
}

namespace {

// The count of one piece once it no longer changes when the sampling is made 4
// times denser: 256, 1024, ... up to 65536 samples per edge.  A zero with a
// small Re next to a pole on Re = 0 (lossless strips) turns the argument by
// 2 pi within one coarse step and is missed by it (pmma_homalite_pair.toml at
// L = 3 m: 5, 7, 8, 8, 8 zeros at 256 ... 65536 samples per edge).
int converged_count(const AnalyticFunction& g, const Rectangle& piece) {
  int samples = kSamplesPerEdge;
  int count = count_zeros(g, piece, samples);
  for (; samples < 65536; samples *= 4) {
    const int denser = count_zeros(g, piece, 4 * samples);
    if (denser == count) return count;
    count = denser;
  }
  throw std::runtime_error("linear stability: the zero count of a rectangle did not converge under refinement "
                           "of its contour (65536 samples per edge)");
}

}  // namespace

int count_zeros_graded(const AnalyticFunction& g, const Rectangle& box, double inner) {
  int count = 0;
  for (const Rectangle& piece : graded_tiling(box, inner)) count += converged_count(g, piece);
  return count;
}

std::vector<complex> sorted_zeros_graded(const AnalyticFunction& g, const Rectangle& box, double inner) {
  const double resolution = location_resolution(box);
  std::vector<complex> roots;
  for (const Rectangle& piece : graded_tiling(box, inner))
    locate(g, piece, converged_count(g, piece), resolution, roots);
  sort_fastest_first(roots, resolution);
  return roots;
}

}  // namespace slipstrip
