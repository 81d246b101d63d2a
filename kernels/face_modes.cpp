#include "kernels/face_modes.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace slipstrip {
namespace {

using complex = std::complex<double>;
constexpr double pi = std::numbers::pi;

// The two layer types of kernels/face_response.cpp with a finite height h:
// driven (f(a) = a coth(a h)) and roller (f(a) = a tanh(a h)).
enum class Layer { driven, roller };

// Scaled real values of a sinh(a h), sinh(a h)/a and cosh(a h) for a^2 = x real
// (a real: evanescent; a = i beta: propagating).  For x > 0 all three are divided
// by e^{a h} (> 0), so signs are kept and nothing overflows.
struct Hyperbolic {
  double a_sinh, sinh_over_a, cosh;
};
Hyperbolic hyperbolic_of(double x, double h) {
  if (x > 0.0) {
    const double a = std::sqrt(x);
    const double one_minus = -std::expm1(-2.0 * a * h);  // 1 - e^{-2ah}
    return {0.5 * a * one_minus, a * h < 1e-300 ? h : 0.5 * one_minus / a,
            0.5 * (2.0 - one_minus)};
  }
  const double b = std::sqrt(-x);
  const double bh = b * h;
  return {-b * std::sin(bh), bh < 1e-8 ? h * (1.0 - bh * bh / 6.0) : std::sin(bh) / b, std::cos(bh)};
}

// An entire function of s^2, real for s = i omega, whose zeros (omega > 0) are the
// poles of K: E = alpha_s^2 f(alpha_d) - k^2 f(alpha_s) (docs/inplane_bodies.md §4)
// times sinh_s sinh_d / (alpha_s alpha_d) (driven) or cosh_s cosh_d / alpha_s^2
// (roller; the roller's E vanishes at alpha_s = 0 together with its numerator, a
// removable zero that the division takes out).
double pole_function(Layer layer, double k, double xs, double xd, double h) {
  const Hyperbolic s = hyperbolic_of(xs, h), d = hyperbolic_of(xd, h);
  if (layer == Layer::driven) return s.a_sinh * d.cosh - k * k * s.cosh * d.sinh_over_a;
  return d.a_sinh * s.cosh - k * k * s.sinh_over_a * d.cosh;
}

// d/dx of the three unscaled quantities (x = a^2), times the same factor e^{-a h}
// as hyperbolic_of (for x > 0):
//   d(a sinh)/dx = (sinh/a + h cosh) / 2,   d(cosh)/dx = h (sinh/a) / 2,
//   d(sinh/a)/dx = (h cosh - sinh/a) / (2x),
// the last from its Taylor series h^3 sum_{n>=1} n z^{n-1} / (2n+1)!, z = x h^2, for
// |z| <= 1, where the difference would cancel (ten terms: the next is below 1e-20 of the sum).
Hyperbolic hyperbolic_slope_of(double x, double h) {
  const Hyperbolic q = hyperbolic_of(x, h);
  double sinh_over_a_slope;
  const double z = x * h * h;
  if (std::abs(z) <= 1.0) {
    double sum = 0.0, power = 1.0, factorial = 6.0;  // z^{n-1}, (2n+1)!
    for (int n = 1; n <= 10; ++n) {
      sum += n * power / factorial;
      power *= z;
      factorial *= (2.0 * n + 2.0) * (2.0 * n + 3.0);
    }
    sinh_over_a_slope = h * h * h * sum * (x > 0.0 ? std::exp(-std::sqrt(x) * h) : 1.0);
  } else {
    sinh_over_a_slope = (h * q.cosh - q.sinh_over_a) / (2.0 * x);
  }
  return {0.5 * (q.sinh_over_a + h * q.cosh), sinh_over_a_slope, 0.5 * h * q.sinh_over_a};
}

// W_m of one layer at its mode omega (docs/inplane_bodies.md §4).  K = mu N s^2 /
// (c_s^2 E) has f(alpha) = alpha coth (driven) or alpha tanh (roller) in N and E,
// and f is infinite where sinh (driven) or cosh (roller) vanishes.  Where that
// happens to both waves at a mode (driven: q_s h and q_d h both multiples of pi),
// E is not zero but infinite and -mu N / (c_s^2 dE/ds^2) is inf/inf.  So take
// numerator and denominator times the factor g of pole_function, which clears
// every such pole:  K = mu (g N) s^2 / (c_s^2 D),  D = g E,  and g N is a matrix
// of products of the bounded quantities of hyperbolic_of:
//   driven, g = sinh_s sinh_d / (alpha_s alpha_d):
//     g N = [[cosh_s cosh_d, i k cosh_s sinh_d/alpha_d], [-i k ..., alpha_s sinh_s sinh_d/alpha_d]],
//   roller, g = cosh_s cosh_d / alpha_s^2:
//     g N = [[(sinh_s/alpha_s) alpha_d sinh_d, i k (sinh_s/alpha_s) cosh_d], [-i k ..., cosh_s cosh_d]],
// where the off-diagonal entry -i k P g uses P g = 2 c_s^2 D / s^2 - f_s g = -f_s g at
// D = 0.  D and g N are entire in s^2, so at a simple zero of D the residue in s^2 is
// mu s^2 (g N) / (c_s^2 D') and W = residue / omega^2 = -mu (g N) / (c_s^2 D'),
// D' = dD/dx_s / c_s^2 + dD/dx_d / c_d^2 (x = alpha^2 = k^2 + s^2/c^2).  The e^{-a h}
// scaling of hyperbolic_of multiplies D, D' (D = 0 kills the derivative of the
// scale) and g N alike and cancels.  det(g N) = (cosh_s sinh_d/alpha_d) D (driven)
// or (sinh_s/alpha_s) cosh_d D (roller) vanishes at the mode: g N is rank one and
// is rebuilt from its larger diagonal entry so that W is rank one to rounding.
FaceMatrix mode_weight(const ElasticMaterial& m, Layer layer, double h, double k, double omega) {
  const double mu = m.shear_modulus, cs = m.shear_wave_speed(), cd = m.dilatational_wave_speed();
  const double xs = k * k - omega * omega / (cs * cs), xd = k * k - omega * omega / (cd * cd);
  const Hyperbolic s = hyperbolic_of(xs, h), d = hyperbolic_of(xd, h);
  const Hyperbolic ds = hyperbolic_slope_of(xs, h), dd = hyperbolic_slope_of(xd, h);
  const double k2 = k * k;
  double nxx, nyy, b, d_xs, d_xd;  // g N = [[nxx, i b], [-i b, nyy]]; dD/dx_s, dD/dx_d
  if (layer == Layer::driven) {
    // D = alpha_s sinh_s cosh_d - k^2 cosh_s sinh_d / alpha_d
    nxx = s.cosh * d.cosh;
    nyy = s.a_sinh * d.sinh_over_a;
    b = k * s.cosh * d.sinh_over_a;
    d_xs = ds.a_sinh * d.cosh - k2 * ds.cosh * d.sinh_over_a;
    d_xd = s.a_sinh * dd.cosh - k2 * s.cosh * dd.sinh_over_a;
  } else {
    // D = alpha_d sinh_d cosh_s - k^2 (sinh_s / alpha_s) cosh_d
    nxx = s.sinh_over_a * d.a_sinh;
    nyy = s.cosh * d.cosh;
    b = k * s.sinh_over_a * d.cosh;
    d_xs = d.a_sinh * ds.cosh - k2 * ds.sinh_over_a * d.cosh;
    d_xd = dd.a_sinh * s.cosh - k2 * s.sinh_over_a * dd.cosh;
  }
  const double d_prime = d_xs / (cs * cs) + d_xd / (cd * cd);
  const double scale = -mu / (cs * cs * d_prime);
  FaceMatrix w;
  const bool xx_pivot = std::abs(nxx) >= std::abs(nyy);
  if ((xx_pivot ? nxx : nyy) == 0.0) return w;  // g N = 0: D vanishes here without a pole of K
  w.xx = scale * (xx_pivot ? nxx : b * b / nyy);
  w.yy = scale * (xx_pivot ? b * b / nxx : nyy);
  w.xy = scale * complex(0.0, b);
  w.yx = scale * complex(0.0, -b);
  return w;
}

void layer_modes(const ElasticMaterial& m, Layer layer, double h, double k, double max_frequency,
                 double factor, int divisions, std::vector<FaceMode>& out) {
  const double cs = m.shear_wave_speed(), cd = m.dilatational_wave_speed();
  const double ka = std::abs(k);
  // Grid: 1/divisions of a half wavelength in both vertical wavenumbers, and 4 divisions points
  // below the shear cut-off c_s |k| (evanescent waves).
  std::vector<double> grid;
  for (int j = 1; j <= 4 * divisions; ++j) grid.push_back(cs * ka * j / (4.0 * divisions));
  for (double c : {cs, cd})
    for (int j = 0;; ++j) {
      const double beta = j * pi / (divisions * h);
      const double w = c * std::sqrt(ka * ka + beta * beta);
      if (w > max_frequency) break;
      grid.push_back(w);
    }
  grid.push_back(max_frequency);
  std::sort(grid.begin(), grid.end());
  grid.erase(std::unique(grid.begin(), grid.end()), grid.end());
  const auto D = [&](double w) {
    return pole_function(layer, ka, ka * ka - w * w / (cs * cs), ka * ka - w * w / (cd * cd), h);
  };
  const auto add = [&](double omega) {
    FaceMatrix weight = mode_weight(m, layer, h, ka, omega);
    if (k < 0.0) {  // K_xy, K_yx are odd in k
      weight.xy = -weight.xy;
      weight.yx = -weight.yx;
    }
    out.push_back({omega, complex(factor) * weight});
  };
  double w_prev = grid.front(), d_prev = D(w_prev);
  for (std::size_t i = 1; i < grid.size() && grid[i] <= max_frequency; ++i) {
    const double w = grid[i], d = D(w);
    if ((d < 0.0) != (d_prev < 0.0) && d != 0.0 && d_prev != 0.0) {
      double lo = w_prev, hi = w, dlo = d_prev;
      for (int it = 0; it < 200 && hi - lo > 4e-16 * hi; ++it) {
        const double mid = 0.5 * (lo + hi), dm = D(mid);
        if ((dm < 0.0) == (dlo < 0.0)) {
          lo = mid;
          dlo = dm;
        } else {
          hi = mid;
        }
      }
      add(0.5 * (lo + hi));
    } else if (d == 0.0 && w < max_frequency) {
      add(w);
    }
    w_prev = w;
    d_prev = d;
  }
}

}  // namespace

std::vector<FaceMode> face_modes(const ElasticMaterial& material, double height, OuterFace outer_face,
                                 double wavenumber, double max_frequency, int grid_divisions) {
  if (grid_divisions < 4) throw std::invalid_argument("face_modes: grid_divisions must be >= 4");
  if (is_half_space(height))
    throw std::invalid_argument("face_modes: a half-space has no discrete normal modes");
  if (!(height > 0.0)) throw std::invalid_argument("face_modes: height must be > 0");
  std::vector<FaceMode> modes;
  if (wavenumber == 0.0) {
    // Uniform mode: a 1D shear wave (u_x = 0 at the outer face for both faces:
    // mu alpha coth(alpha H) = mu/H + sum 2 mu s^2 / (H (s^2 + (m pi c_s/H)^2))) and a
    // 1D P wave (driven: rho c_d s tanh(s H / c_d), poles (m + 1/2) pi c_d / H;
    // clamped: rho c_d s coth(s H / c_d), poles m pi c_d / H), weights -2 mu / H and
    // -2 rho c_d^2 / H (the partial fractions of z coth z and z tanh z).
    const double H = height, mu = material.shear_modulus;
    const double cs = material.shear_wave_speed(), cd = material.dilatational_wave_speed();
    const double p_weight = -2.0 * material.density * cd * cd / H;
    for (int m = 1; m * pi * cs / H <= max_frequency; ++m) {
      FaceMatrix w;
      w.xx = -2.0 * mu / H;
      modes.push_back({m * pi * cs / H, w});
    }
    const double offset = outer_face == OuterFace::driven ? 0.5 : 1.0;
    for (int m = 0; (m + offset) * pi * cd / H <= max_frequency; ++m) {
      FaceMatrix w;
      w.yy = p_weight;
      modes.push_back({(m + offset) * pi * cd / H, w});
    }
    std::sort(modes.begin(), modes.end(),
              [](const FaceMode& a, const FaceMode& b) { return a.frequency < b.frequency; });
    return modes;
  }
  if (outer_face == OuterFace::driven) {
    layer_modes(material, Layer::driven, height, wavenumber, max_frequency, 1.0, grid_divisions, modes);
  } else {
    // K_clamped(H) = (K_roller(H/2) + K_driven(H/2)) / 2 (face_response.cpp): the
    // union of both layers' modes with half weights.
    layer_modes(material, Layer::roller, 0.5 * height, wavenumber, max_frequency, 0.5, grid_divisions, modes);
    layer_modes(material, Layer::driven, 0.5 * height, wavenumber, max_frequency, 0.5, grid_divisions, modes);
  }
  std::sort(modes.begin(), modes.end(),
            [](const FaceMode& a, const FaceMode& b) { return a.frequency < b.frequency; });
  return modes;
}

}  // namespace slipstrip
