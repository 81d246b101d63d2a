#pragma once
// In-plane response of ONE elastic body seen from its sliding face, per
// Fourier mode k and Laplace variable s: a 2x2 complex matrix (docs/bodies.md,
// "face response").  This is the building block of dissimilar pairs: each body
// is described on its own (material, height, outer face), and the interface
// combines two of them.
//
// Convention (the body above its face, 0 < y < H, face y = 0):
//     t(k, s) = K(k, s) u(k, s),
// u = (u_x, u_y) the face displacement, t = -(sigma_xy, sigma_yy)(y = 0+) the
// traction exerted ON the body through its face.  A body below the interface
// is the mirror image (y -> -y) of a body above it: mirrored(K) = D K D,
// D = diag(1, -1).
//
// Structure (checked in tests/cpp/test_kernels_face_response.cpp):
//   - K_xx, K_yy are even in k; K_xy = -K_yx is i k times an even function,
//     so K(k, s)^T = K(-k, s) (reciprocity) and K is Hermitian for real s;
//   - Z = K / s is positive real as a matrix (the body is passive): its
//     Hermitian part is positive semidefinite for Re s > 0; a finite strip is
//     lossless (Z + Z^H = 0 on the imaginary axis away from its poles);
//   - s -> infinity: K ~ s diag(mu / c_s, rho c_d) (radiation damping).
#include <complex>
#include <limits>
#include <string_view>

#include "kernels/elastic_material.hpp"

namespace slipstrip {

// Condition on the outer face (y = H) of a finite body, for the perturbation:
//   driven : u_x and sigma_yy prescribed (the solver's loading: tangential
//            velocity imposed, normal stress imposed);
//   clamped: u_x and u_y prescribed.
// Irrelevant for a half-space.
enum class OuterFace { driven, clamped };
inline constexpr std::string_view kOuterFaceNames[] = {"driven", "clamped"};

// 2x2 complex matrix on the (x, y) components.
struct FaceMatrix {
  std::complex<double> xx{}, xy{}, yx{}, yy{};

  std::complex<double> determinant() const { return xx * yy - xy * yx; }
  FaceMatrix inverse() const;
  // Largest absolute entry (a norm for relative comparisons).
  double max_abs() const;
};
FaceMatrix operator+(const FaceMatrix& a, const FaceMatrix& b);
FaceMatrix operator-(const FaceMatrix& a, const FaceMatrix& b);
FaceMatrix operator*(const FaceMatrix& a, const FaceMatrix& b);
FaceMatrix operator*(std::complex<double> c, const FaceMatrix& a);

// One body: material, height (finite strip or +inf half-space), outer face,
// or rigid (its face does not deform; material and height are then unused).
struct ElasticBody {
  ElasticMaterial material;
  double height = std::numeric_limits<double>::infinity();
  OuterFace outer_face = OuterFace::driven;
  bool rigid = false;
};

// K(k, s) of a deformable body above its face (convention above), wavenumber
// k [1/m] of either sign, Re s >= 0 (on the imaginary axis: the limit from
// Re s > 0, i.e. outgoing waves for a half-space).  height = +inf is the
// half-space.  Units Pa/m.
FaceMatrix face_stiffness(const ElasticMaterial& material, double height, OuterFace outer_face,
                          double wavenumber, std::complex<double> s);

// The same body placed below the interface: D K D.
FaceMatrix mirrored(const FaceMatrix& k);

// Two bodies in contact at the interface y = 0 (top above, bottom below), the
// tractions continuous, no interpenetration (u_y continuous) and a prescribed
// slip delta = u_x(0+) - u_x(0-).  The interface stresses are
//     sigma_xy = -shear * delta,    sigma_yy = -normal * delta,
// i.e. (shear, normal) is the first column of the series stiffness
//     K_ser = K_bottom' (K_top + K_bottom')^{-1} K_top = (K_top^{-1} + K_bottom'^{-1})^{-1},
// K_bottom' = mirrored(K of the bottom body).  For two identical bodies
// normal = 0 and shear = S(k, s; H) of kernels/strip_response.hpp.  A rigid
// body has zero compliance; two rigid bodies are refused.
struct SlipResponse {
  std::complex<double> shear;   // [Pa/m]
  std::complex<double> normal;  // [Pa/m]
};
SlipResponse interface_slip_response(const ElasticBody& top, const ElasticBody& bottom,
                                     double wavenumber, std::complex<double> s);

// K_ser itself (the full 2x2 series stiffness; first column = SlipResponse).
FaceMatrix series_stiffness(const ElasticBody& top, const ElasticBody& bottom, double wavenumber,
                            std::complex<double> s);

}  // namespace slipstrip
