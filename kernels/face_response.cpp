#include "kernels/face_response.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "kernels/hyperbolic.hpp"

namespace slipstrip {
namespace {

using complex = std::complex<double>;

// Which function f(a) of the potentials' decay rate the layer contributes
// (docs/bodies.md, "face response"):
//   half-space           : f(a) = a
//   driven layer of h    : f(a) = a coth(a h)   (u_x = 0, sigma_yy = 0 at y = h)
//   roller layer of h    : f(a) = a tanh(a h)   (u_y = 0, sigma_xy = 0 at y = h)
enum class Layer { half_space, driven, roller };

complex f_of(Layer layer, complex a, double h) {
  switch (layer) {
    case Layer::half_space: return a;
    case Layer::driven: return a * hyperbolic::coth_right_half(a * h);
    case Layer::roller: return a * hyperbolic::tanh_right_half(a * h);
  }
  return a;
}

// (f(a) - f(b)) / (a - b), cancellation-free.
complex f_divided_difference(Layer layer, complex a, complex b, double h) {
  switch (layer) {
    case Layer::half_space: return 1.0;
    case Layer::driven: return hyperbolic::divided_difference_a_coth(a, b, h);
    case Layer::roller: return hyperbolic::divided_difference_a_tanh(a, b, h);
  }
  return 1.0;
}

// z coth z and z tanh z... as x coth(x) with its series at 0 (the k = 0 mode at s -> 0).
complex z_coth_z(complex z) { return std::abs(z) < 1e-6 ? 1.0 + z * z / 3.0 : z * hyperbolic::coth_right_half(z); }

// K of one layer type.  With alpha_{s,d} = sqrt(k^2 + s^2/c_{s,d}^2), f_{s,d} = f(alpha_{s,d}),
// F = f[alpha_s, alpha_d] / (alpha_s + alpha_d) and rbar = 1 - c_s^2/c_d^2:
//   Q = f_s - rbar alpha_s^2 F,   P = f_s - 2 rbar alpha_s^2 F,
//   K_xx = mu f_s f_d / Q,  K_yy = mu alpha_s^2 / Q,  K_xy = -K_yx = -i k mu P / Q.
// The textbook form -T U^{-1} (potential amplitudes -> face displacement U and
// stress T) divides O(s^2) by O(s^2) near s = 0 (the Lame potentials
// degenerate as alpha_d -> alpha_s); this one has no such cancellation.
FaceMatrix layer_stiffness(const ElasticMaterial& m, Layer layer, double h, double k, complex s) {
  const double mu = m.shear_modulus;
  const double cs = m.shear_wave_speed();
  const double cd = m.dilatational_wave_speed();
  const complex i(0.0, 1.0);
  if (k == 0.0) {
    // Uniform mode: a 1D shear wave (x) and a 1D P wave (y), alpha = s / c.
    const complex zs = s * (layer == Layer::half_space ? 1.0 : h) / cs;
    const complex zd = s * (layer == Layer::half_space ? 1.0 : h) / cd;
    FaceMatrix out;
    switch (layer) {
      case Layer::half_space:
        out.xx = mu * s / cs;
        out.yy = mu * cd * s / (cs * cs);  // rho c_d s
        break;
      case Layer::driven:
        // mu alpha_s coth(alpha_s h);  (mu c_d s / c_s^2) tanh(s h / c_d)
        out.xx = mu / h * z_coth_z(zs);
        out.yy = mu * cd * cd / (cs * cs * h) * zd * zd / z_coth_z(zd);
        break;
      case Layer::roller:
        // mu alpha_s tanh(alpha_s h);  (mu c_d s / c_s^2) coth(s h / c_d)
        out.xx = mu / h * zs * zs / z_coth_z(zs);
        out.yy = mu * cd * cd / (cs * cs * h) * z_coth_z(zd);
        break;
    }
    return out;
  }
  const complex s2 = s * s;
  const complex alpha_s = std::sqrt(k * k + s2 / (cs * cs));
  const complex alpha_d = std::sqrt(k * k + s2 / (cd * cd));
  const double rbar = 1.0 - (cs * cs) / (cd * cd);
  const complex fs = f_of(layer, alpha_s, h);
  const complex fd = f_of(layer, alpha_d, h);
  const complex F = f_divided_difference(layer, alpha_s, alpha_d, h) / (alpha_s + alpha_d);
  const complex a2 = alpha_s * alpha_s;
  const complex Q = fs - rbar * a2 * F;
  const complex P = fs - 2.0 * rbar * a2 * F;
  FaceMatrix out;
  out.xx = mu * fs * fd / Q;
  out.yy = mu * a2 / Q;
  out.xy = -i * k * mu * P / Q;
  out.yx = -out.xy;
  return out;
}

}  // namespace

FaceMatrix FaceMatrix::inverse() const {
  const complex det = determinant();
  return {yy / det, -xy / det, -yx / det, xx / det};
}

double FaceMatrix::max_abs() const {
  return std::max({std::abs(xx), std::abs(xy), std::abs(yx), std::abs(yy)});
}

FaceMatrix operator+(const FaceMatrix& a, const FaceMatrix& b) {
  return {a.xx + b.xx, a.xy + b.xy, a.yx + b.yx, a.yy + b.yy};
}
FaceMatrix operator-(const FaceMatrix& a, const FaceMatrix& b) {
  return {a.xx - b.xx, a.xy - b.xy, a.yx - b.yx, a.yy - b.yy};
}
FaceMatrix operator*(const FaceMatrix& a, const FaceMatrix& b) {
  return {a.xx * b.xx + a.xy * b.yx, a.xx * b.xy + a.xy * b.yy, a.yx * b.xx + a.yy * b.yx,
          a.yx * b.xy + a.yy * b.yy};
}
FaceMatrix operator*(complex c, const FaceMatrix& a) { return {c * a.xx, c * a.xy, c * a.yx, c * a.yy}; }

FaceMatrix mirrored(const FaceMatrix& k) { return {k.xx, -k.xy, -k.yx, k.yy}; }

FaceMatrix face_stiffness(const ElasticMaterial& material, double height, OuterFace outer_face,
                          double wavenumber, complex s) {
  if (!(height > 0.0))
    throw std::invalid_argument("face_stiffness: height = " + std::to_string(height) + " must be > 0 (or inf)");
  if (material.antiplane())
    throw std::invalid_argument("face_stiffness: the in-plane 2x2 response needs material.plane = \"strain\" or "
                                "\"stress\" (antiplane bodies: kernels/antiplane_response.hpp)");
  if (is_half_space(height)) return layer_stiffness(material, Layer::half_space, height, wavenumber, s);
  if (outer_face == OuterFace::driven)
    return layer_stiffness(material, Layer::driven, height, wavenumber, s);
  // Clamped face: split the field into the parts symmetric and antisymmetric
  // about the mid-plane y = H/2 (mirror (u_x, u_y) -> (u_x, -u_y)).  The
  // symmetric part sees a roller mid-plane (u_y = 0, sigma_xy = 0), the
  // antisymmetric part a driven one (u_x = 0, sigma_yy = 0); face data U at
  // y = 0 and 0 at y = H is U/2 + U/2 in the two parts, so
  //   K_clamped(H) = (K_roller(H/2) + K_driven(H/2)) / 2.
  const double half = 0.5 * height;
  return 0.5 * (layer_stiffness(material, Layer::roller, half, wavenumber, s) +
                layer_stiffness(material, Layer::driven, half, wavenumber, s));
}

FaceMatrix series_stiffness(const ElasticBody& top, const ElasticBody& bottom, double wavenumber,
                            complex s) {
  if (top.rigid && bottom.rigid)
    throw std::invalid_argument("interface: both bodies are rigid; at least one must deform");
  const auto stiffness = [&](const ElasticBody& b) {
    return face_stiffness(b.material, b.height, b.outer_face, wavenumber, s);
  };
  // A rigid body has zero compliance: K_ser is the other body's K.
  if (bottom.rigid) return stiffness(top);
  if (top.rigid) return mirrored(stiffness(bottom));
  const FaceMatrix kt = stiffness(top);
  const FaceMatrix kb = mirrored(stiffness(bottom));
  return kb * ((kt + kb).inverse() * kt);
}

SlipResponse interface_slip_response(const ElasticBody& top, const ElasticBody& bottom,
                                     double wavenumber, complex s) {
  const FaceMatrix k = series_stiffness(top, bottom, wavenumber, s);
  return {k.xx, k.yx};
}

}  // namespace slipstrip
