// The combined interface response of two different in-plane half-spaces
// (kernels/half_space_pair_kernel.hpp) against independent references: the
// series stiffness of the elastodynamic reference solution, the identical
// pair's scalar kernel, Durbin's numerical inverse Laplace transform of its
// history transforms, the static and initial values from the transforms
// themselves, and a Stoneley root search of its own.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <numbers>
#include <vector>

#include "face_reference.hpp"
#include "inverse_laplace.hpp"
#include "half_space_pair_materials.hpp"
#include "kernels/face_half_space.hpp"
#include "kernels/half_space_kernel.hpp"
#include "kernels/half_space_pair_kernel.hpp"

namespace {

using cd = std::complex<double>;
using slipstrip::ElasticMaterial;
using slipstrip::FaceMatrix;
using slipstrip::PlaneCondition;

using slipstrip::testing::kDenseSlow;
using slipstrip::testing::kHomalite;
using slipstrip::testing::kPmma;
using slipstrip::testing::kPmmaDense;
using slipstrip::testing::kStiff;
using Pair = slipstrip::testing::MaterialPair;
std::vector<Pair> dissimilar_pairs() {
  return {{"PMMA/Homalite", kPmma, kHomalite},
          {"Homalite/PMMA", kHomalite, kPmma},
          {"strong contrast", kStiff, kDenseSlow},
          {"strong contrast reversed", kDenseSlow, kStiff}};
}

// (K_t^{-1} + K_b'^{-1})^{-1} from the reference solution of each body
// (tests/cpp/face_reference.hpp: the outgoing eigenvectors of the first-order
// system, neither potentials nor the closed form).
FaceMatrix reference_pair(const ElasticMaterial& top, const ElasticMaterial& bottom, double k, cd s) {
  const FaceMatrix t = slipstrip::testing::reference_half_space(top, k, s);
  const FaceMatrix b = slipstrip::mirrored(slipstrip::testing::reference_half_space(bottom, k, s));
  return (t.inverse() + b.inverse()).inverse();
}

}  // namespace

TEST_CASE("half-space pair: the combined entries against the reference series stiffness") {
  // K_c = mu_ref k [[A_c, -i B_c], [i B_c, D_c]] at s = p c_ref k, k = 3/m, against
  // the reference pair above at 10 values of p (the imaginary axis between and
  // beyond the branch points included).  Tolerance 1e-10 relative: the
  // reference's eigenvectors are well conditioned (1e-11 per body in
  // test_kernels_face_half_space) and the two inversions lose a digit at most.
  const cd kP[] = {{0.3, 0.0}, {1.0, 0.0}, {4.0, 0.0}, {0.2, 0.5}, {0.05, 0.9},
                   {0.0, 0.5}, {0.0, 1.04}, {0.0, 1.5}, {0.0, 3.0}, {2.0, -1.0}};
  double worst = 0.0;
  for (const Pair& pair : dissimilar_pairs()) {
    const auto shape = slipstrip::half_space_pair_shape(pair.top, pair.bottom);
    const double k = 3.0, unit = shape.reference_modulus * k;
    for (cd p : kP) {
      const auto e = slipstrip::half_space_pair_entries(shape, p);
      const FaceMatrix ref = reference_pair(pair.top, pair.bottom, k, p * shape.reference_speed * k);
      FaceMatrix got;
      got.xx = unit * e[0];
      got.xy = cd(0.0, -1.0) * unit * e[1];
      got.yx = cd(0.0, 1.0) * unit * e[1];
      got.yy = unit * e[2];
      const double err = (got - ref).max_abs() / ref.max_abs();
      CAPTURE(pair.name);
      CAPTURE(p);
      CHECK(err <= 1e-10);
      worst = std::max(worst, err);
    }
  }
  std::printf("[half-space pair] entries vs reference series stiffness: %.2e\n", worst);
}

TEST_CASE("half-space pair: identical bodies give the identical pair's scalar kernel and no coupling") {
  // docs/theory.md §8: for identical bodies A_c = (A - B^2/D)/2 is the scalar
  // half-space response S_inf / (mu k), so G_A is half_space_relaxation_transform,
  // and B_c = 0.  Transforms at 6 points (1e-13 relative: rounding of two
  // codings of one function); the exponential sums of G_A against
  // half_space_exponential_sum on tau in [0.5, 100] (both ~1e-9 accurate:
  // 1e-8), and the coupling's sum is identically zero.
  for (const ElasticMaterial& m : {kPmma, kStiff, kDenseSlow}) {
    const auto shape = slipstrip::half_space_pair_shape(m, m);
    CHECK(shape.branch_heights.size() == 2);
    const double r2 = 1.0 / m.wave_speed_ratio_squared();
    for (cd p : {cd(0.3, 0.0), cd(2.0, 0.0), cd(0.1, 0.7), cd(0.0, 0.5), cd(0.0, 1.2), cd(0.01, 2.5)}) {
      const auto g = slipstrip::half_space_pair_history_transforms(shape, p);
      const cd scalar = slipstrip::half_space_relaxation_transform(r2, p);
      CHECK(std::abs(g[0] - scalar) <= 1e-13 * std::max(1.0, std::abs(scalar)));
      CHECK(g[1] == 0.0);
    }
    const auto sums = slipstrip::half_space_pair_exponential_sums(shape, 0.5, 100.0);
    const auto scalar = slipstrip::half_space_exponential_sum(r2, 0.5, 100.0);
    double worst = 0.0, coupling = 0.0;
    for (double tau = 0.5; tau <= 100.0; tau += 0.25) {
      worst = std::max(worst, std::abs(evaluate(sums[0], tau) - evaluate(scalar, tau)));
      coupling = std::max(coupling, std::abs(evaluate(sums[1], tau)));
    }
    CHECK(worst <= 1e-8);
    CHECK(coupling == 0.0);
    std::printf("[half-space pair] identical bodies (nu = %.2f): A_c's sum vs the scalar kernel %.2e, "
                "%zu exponentials (scalar %zu)\n",
                m.poisson_ratio, worst, sums[0].rate.size(), scalar.rate.size());
  }
}

TEST_CASE("half-space pair: static and initial values from the transforms") {
  // g_e(inf) is the residue of G_e at p = 0 and g_e(0+) = lim p G_e(p) for
  // p -> inf: p G_e at p = 1e-7 and 1e7 differ from them by O(p) and O(1/p)
  // (tolerance 1e-6).  E_A, E_D: the series impedances, from the bodies'
  // E_x = mu/c_s, E_y = rho c_d (1e-14 relative).
  for (const Pair& pair : dissimilar_pairs()) {
    const auto shape = slipstrip::half_space_pair_shape(pair.top, pair.bottom);
    const auto g_inf = slipstrip::half_space_pair_static_values(shape);
    const auto g_0 = slipstrip::half_space_pair_initial_values(shape);
    const auto small = slipstrip::half_space_pair_history_transforms(shape, 1e-7);
    const auto large = slipstrip::half_space_pair_history_transforms(shape, 1e7);
    CAPTURE(pair.name);
    for (std::size_t e = 0; e < 3; ++e) {
      CHECK(std::abs(1e-7 * small[e] - g_inf[e]) <= 1e-6);
      CHECK(std::abs(1e7 * large[e] - g_0[e]) <= 1e-6);
    }
    const double unit = shape.reference_modulus / shape.reference_speed;
    const auto series = [](double a, double b) { return a * b / (a + b); };
    const double ex = series(pair.top.shear_modulus / pair.top.shear_wave_speed(),
                             pair.bottom.shear_modulus / pair.bottom.shear_wave_speed());
    const double ey = series(pair.top.density * pair.top.dilatational_wave_speed(),
                             pair.bottom.density * pair.bottom.dilatational_wave_speed());
    const auto e = slipstrip::half_space_pair_impedances(shape);
    CHECK(std::abs(e[0] * unit - ex) <= 1e-14 * ex);
    CHECK(std::abs(e[1] * unit - ey) <= 1e-14 * ey);
    std::printf("[half-space pair] %s: g(inf) = %.6f %.6f %.6f, g_B(0+) = %.6f\n", pair.name, g_inf[0], g_inf[1],
                g_inf[2], g_0[1]);
  }
}

TEST_CASE("half-space pair: exponential sums against Durbin's inverse Laplace transform") {
  // As test_kernels_face_half_space: Durbin's inverse of G_e at tau in [0.5, 40]
  // (2^20 terms, dtau = 0.01), the coupling's step g_B(0+)/p inverted in closed
  // form; what is left falls like p^-2, whose truncation leaves ~1e-8.
  // Tolerance 1e-7 absolute (units mu_ref k; the kernels are O(1)).  The strong
  // contrast has a leaky interface wave (a zero of det(K_t + K_b') in the cut
  // plane, Re p < 0): without its exponential the sums miss by ~0.1.
  for (const Pair& pair : dissimilar_pairs()) {
    const auto shape = slipstrip::half_space_pair_shape(pair.top, pair.bottom);
    CHECK(slipstrip::half_space_pair_stoneley_speed(shape) == 0.0);
    const auto poles = slipstrip::half_space_pair_poles(shape);
    for (const auto& pole : poles) {
      CHECK(pole.p.real() < 0.0);
      CHECK(std::abs(slipstrip::half_space_pair_determinant(shape, pole.p)) <= 1e-10);
      std::printf("[half-space pair] %s: leaky pole at p = %.6f %+.6fi, residues |%.3g| |%.3g| |%.3g|\n", pair.name,
                  pole.p.real(), pole.p.imag(), std::abs(pole.residue[0]), std::abs(pole.residue[1]),
                  std::abs(pole.residue[2]));
    }
    const auto sums = slipstrip::half_space_pair_exponential_sums(shape, 0.5, 100.0);
    const auto g_0 = slipstrip::half_space_pair_initial_values(shape);
    double worst_all = 0.0;
    for (std::size_t e = 0; e < 3; ++e) {
      const double dtau = 0.01;
      const auto ref = slipstrip::testing::inverse_laplace(
          [&](cd p) { return slipstrip::half_space_pair_history_transforms(shape, p)[e] - g_0[e] / p; }, dtau,
          1 << 20, 4001);
      double worst = 0.0;
      for (int j = 50; j <= 4000; j += 10)
        worst = std::max(worst, std::abs(evaluate(sums[e], j * dtau) - (ref[j] + g_0[e])));
      CAPTURE(pair.name);
      CAPTURE(e);
      CHECK(worst <= 1e-7);
      worst_all = std::max(worst_all, worst);
    }
    std::printf("[half-space pair] %s: %zu exponentials (%zu poles), heights", pair.name, sums[0].rate.size(),
                poles.size());
    for (double b : shape.branch_heights) std::printf(" %.4f", b);
    std::printf(", sums vs Durbin %.2e\n", worst_all);
  }
  const auto strong = slipstrip::half_space_pair_shape(kStiff, kDenseSlow);
  CHECK(!slipstrip::half_space_pair_poles(strong).empty());
  CHECK(slipstrip::half_space_pair_poles(slipstrip::half_space_pair_shape(kPmma, kHomalite)).empty());
}

TEST_CASE("half-space pair: the set-up check sees a missed pole") {
  // verify_half_space_pair_sums passes on the pairs above; the same check on the
  // strong contrast's sums with the leaky poles' exponentials dropped exceeds
  // its 1e-6 by orders of magnitude (their residues are O(0.1) and more), and
  // with them is at Durbin's truncation (~1e-8).
  for (const Pair& pair : dissimilar_pairs()) {
    CAPTURE(pair.name);
    CHECK_NOTHROW(slipstrip::verify_half_space_pair_sums(slipstrip::half_space_pair_shape(pair.top, pair.bottom)));
  }
  const auto shape = slipstrip::half_space_pair_shape(kStiff, kDenseSlow);
  auto sums = slipstrip::half_space_pair_exponential_sums(shape, 0.5, 16.0);
  const double with = slipstrip::half_space_pair_sum_check(shape, sums);
  const std::size_t poles = slipstrip::half_space_pair_poles(shape).size();
  CHECK(poles > 0);
  for (auto& sum : sums) {
    sum.rate.resize(sum.rate.size() - poles);  // the poles' exponentials come last
    sum.amplitude.resize(sum.amplitude.size() - poles);
  }
  const double without = slipstrip::half_space_pair_sum_check(shape, sums);
  CHECK(with <= 1e-7);
  CHECK(without >= 1e-3);
  std::printf("[half-space pair] set-up check: %.2e with the leaky pole, %.2e without\n", with, without);
}

TEST_CASE("half-space pair: a Stoneley wave is found and refused") {
  // Independent search: det(K_t + K_b') from the reference solution of each
  // body (tests/cpp/face_reference.hpp) on s = i y c_ref k, 0 < y < 1, where it
  // is real: a sign change bisected to 1e-12.  PMMA over PMMA at twice the
  // density (the same wave speeds) has one (Stoneley waves need shear speeds
  // close and densities different); PMMA/Homalite and the strong contrast have
  // none.  The kernel's own bisection agrees to 1e-10, and the exponential sums
  // refuse the pair, naming the wave's speed.
  const auto reference_det = [](const ElasticMaterial& top, const ElasticMaterial& bottom, double y, double c_ref) {
    const double k = 1.0;
    const cd s(0.0, y * c_ref * k);
    const FaceMatrix sum = slipstrip::testing::reference_half_space(top, k, s) +
                           slipstrip::mirrored(slipstrip::testing::reference_half_space(bottom, k, s));
    return sum.determinant().real();
  };
  const auto reference_root = [&](const ElasticMaterial& top, const ElasticMaterial& bottom) {
    const double c_ref = std::min(top.shear_wave_speed(), bottom.shear_wave_speed());
    const int n = 20000;
    double y0 = 1e-3, f0 = reference_det(top, bottom, y0, c_ref);
    for (int i = 1; i <= n; ++i) {
      const double y1 = 1e-3 + (1.0 - 1e-9 - 1e-3) * i / n, f1 = reference_det(top, bottom, y1, c_ref);
      if ((f0 > 0) != (f1 > 0)) {
        double lo = y0, hi = y1;
        while (hi - lo > 1e-12) {
          const double mid = 0.5 * (lo + hi);
          ((reference_det(top, bottom, mid, c_ref) > 0) == (f0 > 0) ? lo : hi) = mid;
        }
        return 0.5 * (lo + hi);
      }
      y0 = y1;
      f0 = f1;
    }
    return 0.0;
  };
  const double expected = reference_root(kPmma, kPmmaDense);
  CHECK(expected > 0.9);
  const auto shape = slipstrip::half_space_pair_shape(kPmma, kPmmaDense);
  const double found = slipstrip::half_space_pair_stoneley_speed(shape);
  CHECK(std::abs(found - expected) <= 1e-10);
  std::printf("[half-space pair] PMMA over dense PMMA: Stoneley wave at %.12f c_s (reference %.12f)\n", found,
              expected);
  CHECK_THROWS_WITH_AS(slipstrip::half_space_pair_exponential_sums(shape, 1.0, 1e10),
                       doctest::Contains("Stoneley wave"), slipstrip::HalfSpacePairHasInterfaceWave);
  for (const Pair& pair : dissimilar_pairs()) {
    CAPTURE(pair.name);
    CHECK(reference_root(pair.top, pair.bottom) == 0.0);
    CHECK(slipstrip::half_space_pair_stoneley_speed(slipstrip::half_space_pair_shape(pair.top, pair.bottom)) == 0.0);
  }
}

TEST_CASE("half-space pair: exponential sums at short times") {
  // tau in [0.01, 0.5], where a leaky pole far from the axis (the strong
  // contrast's at Re p = -3) has not decayed: Durbin's inverse with dtau = 0.001
  // (2^20 terms), the coupling's step and each entry's c_e/(p^2 + 1) (c_e = p^2
  // G_e at p = 1e4) inverted in closed form, so that what is left falls like
  // p^-3 and the truncation stays ~1e-8.  Tolerance 1e-7 absolute, as above.
  for (const Pair& pair : dissimilar_pairs()) {
    const auto shape = slipstrip::half_space_pair_shape(pair.top, pair.bottom);
    const auto sums = slipstrip::half_space_pair_exponential_sums(shape, 0.01, 1.0);
    const auto g_0 = slipstrip::half_space_pair_initial_values(shape);
    const auto at_large = slipstrip::half_space_pair_history_transforms(shape, 1e4);
    double worst_all = 0.0;
    for (std::size_t e = 0; e < 3; ++e) {
      const double c = (1e8 * at_large[e] - 1e4 * g_0[e]).real();
      const double dtau = 0.001;
      const auto ref = slipstrip::testing::inverse_laplace(
          [&](cd p) {
            return slipstrip::half_space_pair_history_transforms(shape, p)[e] - g_0[e] / p - c / (p * p + 1.0);
          },
          dtau, 1 << 20, 501);
      double worst = 0.0;
      for (int j = 10; j <= 500; ++j)
        worst = std::max(worst, std::abs(evaluate(sums[e], j * dtau) - (ref[j] + g_0[e] + c * std::sin(j * dtau))));
      CAPTURE(pair.name);
      CAPTURE(e);
      CHECK(worst <= 1e-7);
      worst_all = std::max(worst_all, worst);
    }
    std::printf("[half-space pair] %s: sums vs Durbin at tau in [0.01, 0.5] %.2e\n", pair.name, worst_all);
  }
}

TEST_CASE("half-space pair: how many exponentials the operator's far field takes") {
  // The far field of the body operators (kernels/face_half_space.cpp): tau in
  // [1, 1e10], 8 nodes per panel.  One body: 2 cuts x 21 panels x 8 = 336.  The
  // pair: 4 cuts, split panels where the continuation of a cut's side has a
  // singular point nearby, and its leaky poles; at most 2.5 one body's (the
  // combined operator is meant to cost about two bodies' exponentials fed with
  // one input channel).
  for (const Pair& pair : dissimilar_pairs()) {
    const auto shape = slipstrip::half_space_pair_shape(pair.top, pair.bottom);
    const auto sums = slipstrip::half_space_pair_exponential_sums(shape, 1.0, 1e10, 8);
    const double r2 = 1.0 / pair.top.wave_speed_ratio_squared();
    const auto body = slipstrip::half_space_face_exponential_sum(r2, slipstrip::FaceEntry::shear, 1.0, 1e10, 8);
    CHECK(sums[0].rate.size() <= 2.5 * body.rate.size());
    std::printf("[half-space pair] %s: far field %zu exponentials, one body %zu (%.2fx)\n", pair.name,
                sums[0].rate.size(), body.rate.size(), double(sums[0].rate.size()) / body.rate.size());
  }
}
