// Independent check of the per-body in-plane face response K(k, s)
// (kernels/face_response.hpp).
//
// The reference does NOT use Lame potentials, the closed form, the
// divided differences or the mid-plane decomposition of the clamped strip.  It
// integrates the elastodynamic equations written as a first-order system in y
// for the state X = (u_x, u_y, sigma_xy/mu, sigma_yy/mu),
//   u_x'      = sigma_xy/mu - i k u_y
//   u_y'      = (sigma_yy/mu - (lambda/mu) i k u_x) / ((lambda + 2 mu)/mu)
//   sigma_xy' = rho s^2 u_x - i k sigma_xx,  sigma_xx = (lambda + 2 mu) i k u_x + lambda u_y'
//   sigma_yy' = rho s^2 u_y - i k sigma_xy
// (Hooke's law and momentum balance, lambda from nu; plane stress uses
// lambda* = 2 lambda mu / (lambda + 2 mu)).  The two-dimensional space of
// states allowed by the outer face (driven: u_x = sigma_yy = 0; clamped:
// u_x = u_y = 0) is carried from y = H down to the face y = 0 through thin
// sublayers with exp(-A h) (Taylor series, |A h| <= 1/4) and re-orthonormalised
// after each (so the exponentially growing and decaying parts never mix); at
// y = 0 the basis [U; S] gives sigma = mu S U^{-1} u and K = -mu S U^{-1}.
// The half-space is the invariant subspace of A that decays as y -> +inf
// (eigenvalues -alpha_s, -alpha_d; outgoing waves on the imaginary axis).
#include <doctest/doctest.h>

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <limits>
#include <vector>

#include "kernels/elastic_material.hpp"
#include "kernels/face_response.hpp"
#include "kernels/strip_response.hpp"
#include "face_reference.hpp"

namespace {

using cd = std::complex<double>;
using slipstrip::ElasticBody;
using slipstrip::ElasticMaterial;
using slipstrip::FaceMatrix;
using slipstrip::OuterFace;
using slipstrip::PlaneCondition;
using slipstrip::testing::reference_half_space;
using slipstrip::testing::reference_strip;
constexpr double inf = std::numeric_limits<double>::infinity();

double relative_difference(const FaceMatrix& a, const FaceMatrix& b) {
  return (a - b).max_abs() / b.max_abs();
}

ElasticMaterial material(double mu, double nu, double rho, PlaneCondition plane) { return {mu, nu, rho, plane}; }

std::vector<ElasticMaterial> test_materials() {
  std::vector<ElasticMaterial> out;
  for (PlaneCondition plane : {PlaneCondition::strain, PlaneCondition::stress}) {
    out.push_back(material(9e9, 0.33, 1200.0, plane));    // Table S1
    out.push_back(material(1.96e9, 0.35, 1230.0, plane));  // Homalite-100-like
    out.push_back(material(30e9, 0.45, 2700.0, plane));    // nearly incompressible rock
  }
  return out;
}

// s in units of c_s max(|k|, 1/H): Re s > 0 large and small, both signs of Im s,
// on the imaginary axis, and s = 0.
const std::vector<cd> kSUnits{{1.0, 0.0}, {0.3, 2.0},  {0.3, -2.0}, {1e-3, 1.7}, {1e-3, -0.45},
                              {2.0, 5.0}, {0.0, 0.77}, {0.0, -2.3}, {0.0, 0.0}, {1e-4, 0.0}};

}  // namespace

TEST_CASE("face_stiffness agrees with a direct propagator solve of the strip (driven and clamped)") {
  // Tolerance 1e-11 relative to the largest entry: both sides are double
  // evaluations of the same analytic 2x2 function; the closed form is
  // cancellation-free, the reference multiplies up to a few hundred 4x4
  // sublayer propagators (each exact to rounding), re-orthonormalised, and
  // solves one 2x2 system.  Points on the imaginary axis near a resonance
  // (where K is huge and both sides lose digits in proportion) are skipped by
  // the conditioning guard below.
  const double H = 0.1;
  const std::vector<double> kHs{0.01, 0.1, 0.5, 1.0, 3.0, 10.0};
  int checked = 0;
  double worst = 0.0;
  for (const ElasticMaterial& m : test_materials()) {
    const double cs = m.shear_wave_speed();
    for (OuterFace face : {OuterFace::driven, OuterFace::clamped}) {
      for (double kH : kHs) {
        for (double sign : {1.0, -1.0}) {
          const double k = sign * kH / H;
          const double scale = cs * std::max(std::abs(k), 1.0 / H);
          for (cd su : kSUnits) {
            const cd s = su * scale;
            const FaceMatrix ref = reference_strip(m, H, face, k, s);
            const FaceMatrix got = slipstrip::face_stiffness(m, H, face, k, s);
            // Static stiffness scale mu max(|k|, 1/H): a response 1e4 times larger
            // is within ~1e-4 of a resonance; skip it (relative digits lost).
            if (ref.max_abs() > 1e4 * m.shear_modulus * std::max(std::abs(k), 1.0 / H)) continue;
            const double err = relative_difference(got, ref);
            CAPTURE(kH);
            CAPTURE(k);
            CAPTURE(s);
            CAPTURE(int(face));
            CAPTURE(ref.xx);
            CAPTURE(got.xx);
            CAPTURE(ref.xy);
            CAPTURE(got.xy);
            CAPTURE(ref.yy);
            CAPTURE(got.yy);
            CHECK(err <= 1e-11);
            worst = std::max(worst, err);
            ++checked;
          }
        }
      }
      // k = 0: uniform shear and normal motion.
      for (cd su : kSUnits) {
        const cd s = su * (cs / H);
        const FaceMatrix ref = reference_strip(m, H, face, 0.0, s);
        const FaceMatrix got = slipstrip::face_stiffness(m, H, face, 0.0, s);
        if (ref.max_abs() > 1e4 * m.shear_modulus / H) continue;
        const double scale = std::max(ref.max_abs(), m.shear_modulus / H);  // K_yy(k=0, s=0) = 0 when driven
        const double err = (got - ref).max_abs() / scale;
        CAPTURE(s);
        CAPTURE(int(face));
        CHECK(err <= 1e-11);
        worst = std::max(worst, err);
        ++checked;
      }
    }
  }
  std::printf("[face] strips: %d points, max relative error %.2e\n", checked, worst);
  CHECK(checked >= 1000);
}

TEST_CASE("face_stiffness of a half-space agrees with the decaying invariant subspace") {
  // Same tolerance and reasoning; the eigenvectors of A are well conditioned
  // for |s| >= 0.1 c_s |k| (at s = 0 the eigenvalues +-|k| are double and A is
  // defective, so s -> 0 is checked against a thick clamped strip instead).
  int checked = 0;
  double worst = 0.0;
  for (const ElasticMaterial& m : test_materials()) {
    const double cs = m.shear_wave_speed();
    for (double k : {3.0, -3.0, 40.0, -0.5}) {
      for (cd su : kSUnits) {
        if (std::abs(su) < 0.1) continue;
        const cd s = su * cs * std::abs(k);
        const FaceMatrix ref = reference_half_space(m, k, s);
        const FaceMatrix got = slipstrip::face_stiffness(m, inf, OuterFace::driven, k, s);
        const double err = relative_difference(got, ref);
        CAPTURE(k);
        CAPTURE(s);
        CHECK(err <= 1e-11);
        worst = std::max(worst, err);
        ++checked;
      }
      // Near-static: a clamped strip of |k| H = 40 differs from the half-space
      // by ~e^{-40} (both outer conditions reflect an evanescent field).
      for (cd su : {cd(0.0, 0.0), cd(1e-4, 0.0), cd(0.05, 0.02)}) {
        const cd s = su * cs * std::abs(k);
        const FaceMatrix ref = reference_strip(m, 40.0 / std::abs(k), OuterFace::clamped, k, s);
        const FaceMatrix got = slipstrip::face_stiffness(m, inf, OuterFace::clamped, k, s);
        const double err = relative_difference(got, ref);
        CAPTURE(k);
        CAPTURE(s);
        CHECK(err <= 1e-11);
        worst = std::max(worst, err);
        ++checked;
      }
    }
  }
  std::printf("[face] half-space: %d points, max relative error %.2e\n", checked, worst);
}

TEST_CASE("face response: reciprocity, real-field symmetry and Hermitian statics") {
  // Reciprocity K(k, s)^T = K(-k, s) and the real-field symmetry
  // K(-k, conj s) = conj K(k, s) are checked on the REFERENCE (the propagator
  // knows nothing about them) and on the closed form.  Tolerance as above.
  const ElasticMaterial m = material(1.96e9, 0.35, 1230.0, PlaneCondition::stress);
  const double H = 0.05, cs = m.shear_wave_speed();
  for (OuterFace face : {OuterFace::driven, OuterFace::clamped}) {
    for (double kH : {0.2, 2.0}) {
      const double k = kH / H;
      for (cd su : {cd(0.4, 1.3), cd(2.0, -0.7), cd(0.5, 0.0)}) {
        const cd s = su * cs * k;
        for (bool closed : {false, true}) {
          const auto K = [&](double kk, cd ss) {
            return closed ? slipstrip::face_stiffness(m, H, face, kk, ss) : reference_strip(m, H, face, kk, ss);
          };
          const FaceMatrix a = K(k, s), b = K(-k, s), c = K(-k, std::conj(s));
          const FaceMatrix at{a.xx, a.yx, a.xy, a.yy};
          const FaceMatrix ac{std::conj(a.xx), std::conj(a.xy), std::conj(a.yx), std::conj(a.yy)};
          CAPTURE(closed);
          CAPTURE(s);
          CHECK(relative_difference(at, b) <= 1e-11);
          CHECK(relative_difference(ac, c) <= 1e-11);
          if (s.imag() == 0.0) {  // real s: Hermitian
            const FaceMatrix ah{std::conj(a.xx), std::conj(a.yx), std::conj(a.xy), std::conj(a.yy)};
            CHECK(relative_difference(ah, a) <= 1e-11);
          }
        }
      }
    }
  }
}

namespace {
// Smallest eigenvalue of the Hermitian part of Z = K / s, relative to |Z|.
double min_hermitian_eigenvalue(const FaceMatrix& K, cd s) {
  const FaceMatrix Z = (1.0 / s) * K;
  Eigen::Matrix2cd h;
  h << Z.xx + std::conj(Z.xx), Z.xy + std::conj(Z.yx), Z.yx + std::conj(Z.xy), Z.yy + std::conj(Z.yy);
  h *= 0.5;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2cd> eig(h);
  return eig.eigenvalues()(0) / Z.max_abs();
}
}  // namespace

TEST_CASE("face response is positive real as a matrix (passive bodies and pairs)") {
  // At s = i w + eps the Hermitian part of Z = K/s must be positive
  // semidefinite.  Tolerance -1e-12 relative to |Z|: rounding of the closed form
  // (entries cancel in Z + Z^H for a lossless strip, whose Hermitian part is
  // O(eps) only).  Swept over w in (0, 40 c_s |k|] for strips of both outer
  // faces, the half-space, and dissimilar pairs (including a rigid base).
  const double H = 0.1;
  const ElasticMaterial soft = material(1.96e9, 0.35, 1230.0, PlaneCondition::strain);
  const ElasticMaterial stiff = material(9e9, 0.33, 1200.0, PlaneCondition::strain);
  double worst = 1.0;
  int checked = 0;
  for (double kH : {0.05, 1.0, 8.0}) {
    const double k = kH / H;
    const double w0 = soft.shear_wave_speed() * std::max(k, 1.0 / H);
    for (double eps_rel : {1e-3, 1e-6}) {
      for (int j = 1; j <= 400; ++j) {
        const double w = 0.1 * j * w0;
        const cd s(eps_rel * w0, w);
        std::vector<FaceMatrix> Ks;
        for (OuterFace face : {OuterFace::driven, OuterFace::clamped}) {
          Ks.push_back(slipstrip::face_stiffness(soft, H, face, k, s));
          Ks.push_back(slipstrip::face_stiffness(stiff, 3 * H, face, -k, s));
        }
        Ks.push_back(slipstrip::face_stiffness(soft, inf, OuterFace::driven, k, s));
        const ElasticBody top{soft, H, OuterFace::driven, false};
        const ElasticBody bottom{stiff, 4 * H, OuterFace::clamped, false};
        const ElasticBody rigid{stiff, H, OuterFace::driven, true};
        const ElasticBody half{stiff, inf, OuterFace::driven, false};
        Ks.push_back(slipstrip::series_stiffness(top, bottom, k, s));
        Ks.push_back(slipstrip::series_stiffness(top, rigid, k, s));
        Ks.push_back(slipstrip::series_stiffness(half, top, -k, s));
        for (const FaceMatrix& K : Ks) {
          const double e = min_hermitian_eigenvalue(K, s);
          worst = std::min(worst, e);
          CHECK(e >= -1e-12);
          ++checked;
        }
      }
    }
  }
  std::printf("[face] passivity: %d matrices, min eigenvalue of Herm(Z)/|Z| = %.2e\n", checked, worst);
}

TEST_CASE("face response limits: identical pair, radiation damping, k = 0 statics, rigid base") {
  const double H = 0.1;
  for (PlaneCondition plane : {PlaneCondition::strain, PlaneCondition::stress}) {
    const ElasticMaterial m = material(9e9, 0.33, 1200.0, plane);
    const double cs = m.shear_wave_speed(), cdil = m.dilatational_wave_speed();
    // Two identical driven strips: the pair's response is the identical-strip
    // S(k, s; H) and the slip does not load the normal stress.  Tolerance
    // 1e-12: two cancellation-free closed forms, no subtraction of large terms
    // (K_top + mirrored(K_bottom) is diagonal).
    for (double height : {H, inf}) {
      const ElasticBody body{m, height, OuterFace::driven, false};
      for (double kH : {0.0, 0.05, 1.0, 20.0}) {
        const double k = kH / H;
        for (cd su : {cd(1.0, 0.0), cd(0.2, 3.0), cd(0.0, 0.37), cd(1e-3, 0.0)}) {
          const cd s = su * cs / H;
          const auto r = slipstrip::interface_slip_response(body, body, k, s);
          const cd S = slipstrip::strip_response(m, height, k, s);
          CAPTURE(kH);
          CAPTURE(s);
          CHECK(std::abs(r.shear - S) <= 1e-12 * std::abs(S));
          CHECK(std::abs(r.normal) <= 1e-12 * std::abs(S));
        }
      }
    }
    // A strip of growing height tends to the half-space for Re s > 0: the outer
    // face's reflection is weighted by ~e^{-2 Re(alpha) H}; with H = 30 / min
    // Re(alpha_s, alpha_d) that is <= e^{-60}; tolerance 1e-12 (rounding).
    for (OuterFace face : {OuterFace::driven, OuterFace::clamped})
      for (cd su : {cd(0.5, 0.0), cd(0.1, 2.0), cd(1e-3, 0.3)}) {
        const double k = 40.0;
        const cd s = su * cs * k;
        const double decay = std::min(std::sqrt(k * k + s * s / (cs * cs)).real(),
                                      std::sqrt(k * k + s * s / (cdil * cdil)).real());
        const FaceMatrix half = slipstrip::face_stiffness(m, inf, face, k, s);
        CAPTURE(s);
        CHECK(relative_difference(slipstrip::face_stiffness(m, 30.0 / decay, face, k, s), half) <= 1e-12);
        CHECK(relative_difference(slipstrip::face_stiffness(m, 0.5 / decay, face, k, s), half) > 1e-3);
      }
    // s -> infinity: K / s -> diag(mu/c_s, rho c_d) (a face radiates plane waves).
    // At |s| = 1e6 c_s/H the corrections are O(c k / s) and O(e^{-2 Re alpha H})
    // = 0; tolerance 1e-5.
    for (OuterFace face : {OuterFace::driven, OuterFace::clamped}) {
      const cd s(1e6 * cs / H, 2e5 * cs / H);
      const FaceMatrix K = (1.0 / s) * slipstrip::face_stiffness(m, H, face, 30.0, s);
      CHECK(std::abs(K.xx - m.shear_modulus / cs) <= 1e-5 * m.shear_modulus / cs);
      CHECK(std::abs(K.yy - m.density * cdil) <= 1e-5 * m.density * cdil);
      CHECK(std::abs(K.xy) <= 1e-5 * m.shear_modulus / cs);
    }
    // k = 0, s -> 0: clamped strip = shear and normal springs mu/H, (lambda+2mu)/H;
    // driven strip: shear mu/H, normal 0 (the outer face is free to move normally).
    const double M = m.density * cdil * cdil;  // lambda + 2 mu
    const FaceMatrix c0 = slipstrip::face_stiffness(m, H, OuterFace::clamped, 0.0, 0.0);
    const FaceMatrix d0 = slipstrip::face_stiffness(m, H, OuterFace::driven, 0.0, 0.0);
    CHECK(std::abs(c0.xx - m.shear_modulus / H) <= 1e-14 * m.shear_modulus / H);
    CHECK(std::abs(c0.yy - M / H) <= 1e-14 * M / H);
    CHECK(std::abs(d0.xx - m.shear_modulus / H) <= 1e-14 * m.shear_modulus / H);
    CHECK(std::abs(d0.yy) == 0.0);
    // A rigid base: the pair's series stiffness is the deformable body's own K
    // (mirrored when the rigid body is on top); a very stiff base tends to it.
    const ElasticBody strip{m, H, OuterFace::driven, false};
    ElasticMaterial hard = m;
    hard.shear_modulus *= 1e8;
    hard.density *= 1e8;  // same wave speeds, 1e8 times the impedance
    const ElasticBody rigid{m, H, OuterFace::driven, true};
    const ElasticBody very_stiff{hard, H, OuterFace::driven, false};
    const cd s(0.3 * cs / H, 1.1 * cs / H);
    const FaceMatrix on_rigid = slipstrip::series_stiffness(strip, rigid, 20.0, s);
    CHECK(relative_difference(on_rigid, slipstrip::face_stiffness(m, H, OuterFace::driven, 20.0, s)) == 0.0);
    // Compliance ratio 1e-8: K_ser = K_top (1 + C_bottom K_top)^{-1}, off by ~1e-8.
    CHECK(relative_difference(slipstrip::series_stiffness(strip, very_stiff, 20.0, s), on_rigid) <= 1e-7);
    CHECK(relative_difference(slipstrip::series_stiffness(rigid, strip, 20.0, s),
                              slipstrip::mirrored(slipstrip::face_stiffness(m, H, OuterFace::driven, 20.0, s))) ==
          0.0);
    CHECK_THROWS_AS(slipstrip::series_stiffness(rigid, rigid, 20.0, s), std::invalid_argument);
  }
}
