#pragma once
// Reference face response K(k, s) of one body for the kernel tests, independent of
// kernels/face_response.cpp: the elastodynamic equations as a first-order system
// in y, carried through sublayers (see tests/cpp/test_kernels_face_response.cpp).
#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>

#include "kernels/elastic_material.hpp"
#include "kernels/face_response.hpp"

namespace slipstrip::testing {

using cd = std::complex<double>;
using Mat4 = Eigen::Matrix4cd;
using Mat42 = Eigen::Matrix<cd, 4, 2>;

struct Lame {
  double mu, lambda, rho;
};
inline Lame lame_of(const slipstrip::ElasticMaterial& m) {
  const double mu = m.shear_modulus, nu = m.poisson_ratio;
  const double lambda3d = 2 * mu * nu / (1 - 2 * nu);
  const double lambda =
      m.plane == slipstrip::PlaneCondition::strain ? lambda3d : 2 * lambda3d * mu / (lambda3d + 2 * mu);
  return {mu, lambda, m.density};
}

// dX/dy = A X for the scaled state (u_x/l, u_y/l, sigma_xy/mu, sigma_yy/mu),
// l a length that makes every entry O(1/l).
inline Mat4 system_matrix(const Lame& L, double k, cd s, double l) {
  const cd ik(0.0, k);
  const double a = (L.lambda + 2 * L.mu) / L.mu, b = L.lambda / L.mu;
  const cd w = L.rho * s * s / L.mu;  // rho s^2 / mu
  // Unscaled rows: u' = [ux', uy'], t' = [txy', tyy'].
  Mat4 A = Mat4::Zero();
  // ux' = txy - ik uy
  A(0, 2) = 1.0;
  A(0, 1) = -ik;
  // uy' = (tyy - b ik ux) / a
  A(1, 3) = 1.0 / a;
  A(1, 0) = -b * ik / a;
  // txy' = w ux - ik (a ik ux + b uy'),  uy' as above
  A(2, 0) = w - ik * (a * ik + b * A(1, 0));
  A(2, 3) = -ik * b * A(1, 3);
  // tyy' = w uy - ik txy
  A(3, 1) = w;
  A(3, 2) = -ik;
  // Scale: X = D Y with D = diag(l, l, 1, 1)  ->  Y' = D^{-1} A D Y.
  Mat4 D = Mat4::Identity();
  D(0, 0) = D(1, 1) = l;
  return D.inverse() * A * D;
}

inline Mat4 expm_small(const Mat4& M) {  // |M| <= 1/4: 24 Taylor terms, error < 1e-30
  Mat4 term = Mat4::Identity(), sum = Mat4::Identity();
  for (int j = 1; j <= 24; ++j) {
    term = term * M / double(j);
    sum += term;
  }
  return sum;
}

inline slipstrip::FaceMatrix from_basis(const Mat42& W, double mu, double l) {
  const Eigen::Matrix2cd U = W.topRows<2>();
  const Eigen::Matrix2cd S = W.bottomRows<2>();
  const Eigen::Matrix2cd K = -(mu / l) * S * U.inverse();
  return {K(0, 0), K(0, 1), K(1, 0), K(1, 1)};
}

inline double length_scale(double k, cd s, const Lame& L, double H) {
  const double cs = std::sqrt(L.mu / L.rho);
  double inv = std::max(std::abs(k), std::abs(s) / cs);
  if (std::isfinite(H)) inv = std::max(inv, 1.0 / H);
  return 1.0 / inv;
}

inline slipstrip::FaceMatrix reference_strip(const slipstrip::ElasticMaterial& m, double H, slipstrip::OuterFace face, double k, cd s) {
  const Lame L = lame_of(m);
  const double l = length_scale(k, s, L, H);
  const Mat4 A = system_matrix(L, k, s, l);
  const int n = std::max(4, int(std::ceil(A.norm() * H / 0.25)));
  const Mat4 step = expm_small(-A * (H / n));
  Mat42 W = Mat42::Zero();
  if (face == slipstrip::OuterFace::driven) {
    W(1, 0) = 1.0;  // u_y free
    W(2, 1) = 1.0;  // sigma_xy free
  } else {
    W(2, 0) = 1.0;  // sigma_xy free
    W(3, 1) = 1.0;  // sigma_yy free
  }
  for (int j = 0; j < n; ++j) {
    W = step * W;
    Eigen::HouseholderQR<Mat42> qr(W);
    W = qr.householderQ() * Mat42::Identity();
  }
  return from_basis(W, L.mu, l);
}

// Decay rate that is the limit from Re s > 0 (for s on the imaginary axis).
inline cd outgoing_root(double k, cd s, double c) {
  const cd probe = s + cd(1e-9 * (std::abs(s) + c * std::abs(k)), 0.0);
  cd a = std::sqrt(k * k + s * s / (c * c));
  const cd ap = std::sqrt(k * k + probe * probe / (c * c));
  if (std::abs(a - ap) > std::abs(-a - ap)) a = -a;
  return a;
}

inline slipstrip::FaceMatrix reference_half_space(const slipstrip::ElasticMaterial& m, double k, cd s) {
  const Lame L = lame_of(m);
  const double l = length_scale(k, s, L, std::numeric_limits<double>::infinity());
  const Mat4 A = system_matrix(L, k, s, l);
  Eigen::ComplexEigenSolver<Mat4> eig(A);
  const double cs = std::sqrt(L.mu / L.rho), cdil = std::sqrt((L.lambda + 2 * L.mu) / L.rho);
  Mat42 W;
  int col = 0;
  for (double c : {cs, cdil}) {
    const cd target = -outgoing_root(k, s, c);  // the scaling of the state is a similarity
    int best = 0;
    for (int j = 1; j < 4; ++j)
      if (std::abs(eig.eigenvalues()(j) - target) < std::abs(eig.eigenvalues()(best) - target)) best = j;
    W.col(col++) = eig.eigenvectors().col(best);
  }
  return from_basis(W, L.mu, l);
}

}  // namespace slipstrip::testing
