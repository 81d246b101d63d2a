#include "kernels/face_modes.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "kernels/hyperbolic.hpp"

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

complex f_of(Layer layer, complex a, double h) {
  return layer == Layer::driven ? a * hyperbolic::coth_right_half(a * h)
                                : a * hyperbolic::tanh_right_half(a * h);
}

// f'(a) / (2a), finite at a = 0.
complex f_slope(Layer layer, complex a, double h) {
  const complex z = a * h;
  if (std::abs(z) < 1e-3) {
    const complex z2 = z * z;
    return layer == Layer::driven ? h / 3.0 * (1.0 - 2.0 * z2 / 15.0) : h * (1.0 - 2.0 * z2 / 3.0);
  }
  const complex e = std::exp(-2.0 * z);
  if (layer == Layer::driven) {
    // coth z - z / sinh^2 z,  1/sinh^2 z = 4 e^{-2z} / (1 - e^{-2z})^2
    return (hyperbolic::coth_right_half(z) - 4.0 * z * e / ((1.0 - e) * (1.0 - e))) / (2.0 * a);
  }
  // tanh z + z / cosh^2 z,  1/cosh^2 z = 4 e^{-2z} / (1 + e^{-2z})^2
  return (hyperbolic::tanh_right_half(z) + 4.0 * z * e / ((1.0 + e) * (1.0 + e))) / (2.0 * a);
}

// Decay rate alpha with alpha^2 = x, on the branch Re alpha >= 0 (alpha = i beta for x < 0).
complex rate_of(double x) { return x >= 0.0 ? complex(std::sqrt(x), 0.0) : complex(0.0, std::sqrt(-x)); }

// W_m of one layer at its mode omega: K = mu N s^2 / (c_s^2 E) near the zero of E in
// s^2, N = [[f_s f_d, -i k P],[i k P, alpha_s^2]] with P = -f_s there, so
//   W = R / omega^2 = -mu N / (c_s^2 E'),   E' = dE/d(s^2),
//   E' = f_d / c_s^2 + alpha_s^2 f'(alpha_d) / (2 alpha_d c_d^2) - k^2 f'(alpha_s) / (2 alpha_s c_s^2),
// and N = v v^H / alpha_s^2 with v = (i k f_s, alpha_s^2) (rank one).
FaceMatrix mode_weight(const ElasticMaterial& m, Layer layer, double h, double k, double omega) {
  const double mu = m.shear_modulus, cs = m.shear_wave_speed(), cd = m.dilatational_wave_speed();
  const double xs = k * k - omega * omega / (cs * cs), xd = k * k - omega * omega / (cd * cd);
  const complex as = rate_of(xs), ad = rate_of(xd);
  const complex fs = f_of(layer, as, h), fd = f_of(layer, ad, h);
  const double e_prime = (fd / (cs * cs) + xs * f_slope(layer, ad, h) / (cd * cd) -
                          k * k * f_slope(layer, as, h) / (cs * cs)).real();
  // v = (i k f_s, x_s) or, equally at the mode (x_s f_d = k^2 f_s), x_s (i f_d / k, 1):
  // take the form with the smaller first entry (f_s or f_d may sit near a pole of f).
  const double fs_r = fs.real(), fd_r = fd.real();
  double vx, vy;  // v = (i vx, vy), both real
  if (std::abs(k * fs_r) <= std::abs(xs * fd_r / k)) {
    vx = k * fs_r;
    vy = xs;
  } else {
    vx = xs * fd_r / k;
    vy = xs;
  }
  const double scale = -mu / (cs * cs * e_prime * xs);
  FaceMatrix w;
  w.xx = scale * vx * vx;
  w.xy = scale * complex(0.0, vx * vy);   // (i vx) * conj(vy)
  w.yx = scale * complex(0.0, -vx * vy);  // vy * conj(i vx)
  w.yy = scale * vy * vy;
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
