// The normal-mode expansion of a finite body's 2x2 face response
// (kernels/face_modes.hpp):  K(k, s) = K(k, 0) - sum_m W_m s^2 / (s^2 + omega_m^2).
#include <doctest/doctest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <numbers>
#include <vector>

#include "face_reference.hpp"
#include "kernels/face_modes.hpp"
#include "kernels/face_response.hpp"

namespace {

using cd = std::complex<double>;
using slipstrip::ElasticMaterial;
using slipstrip::FaceMatrix;
using slipstrip::FaceMode;
using slipstrip::OuterFace;
using slipstrip::PlaneCondition;

ElasticMaterial material(double mu, double nu, double rho, PlaneCondition plane) { return {mu, nu, rho, plane}; }

FaceMatrix truncated_expansion(const FaceMatrix& static_k, const std::vector<FaceMode>& modes, cd s,
                               double max_frequency) {
  FaceMatrix sum = static_k;
  for (const FaceMode& m : modes)
    if (m.frequency <= max_frequency) sum = sum - (s * s / (s * s + m.frequency * m.frequency)) * m.weight;
  return sum;
}

const std::vector<ElasticMaterial> kMaterials{material(9e9, 0.33, 1200.0, PlaneCondition::strain),
                                              material(1.9e9, 0.34, 1230.0, PlaneCondition::stress),
                                              material(30e9, 0.45, 2700.0, PlaneCondition::strain)};

}  // namespace

TEST_CASE("face modes: the truncated expansion converges to the closed form like 1/omega_max") {
  // The weights W_m tend to a constant, so once omega_max >> |s| the tail is
  // ~ -s^2 sum_{omega_m > omega_max} W_m / omega_m^2 = C / omega_max + O(omega_max^-2).
  // Checked from omega_max = max(8 |s|, 100 c_s/H) on (~60 modes or more, so that the
  // count at the cut fluctuates little): each doubling divides the error by
  // 1.8..2.2 and the Richardson combination D(W) - 2 D(2W) is below 10 % of D(W) (the
  // O(omega_max^-2) term and the mode-count fluctuation at the cut).  A mode missed
  // below ~|s| would leave a non-decaying term of the size of K itself.
  const double H = 0.1;
  int checked = 0;
  double worst_ratio_low = 2.0, worst_ratio_high = 2.0, worst_richardson = 0.0;
  for (const ElasticMaterial& m : kMaterials) {
    const double cs = m.shear_wave_speed();
    for (OuterFace face : {OuterFace::driven, OuterFace::clamped})
      for (double kH : {0.05, 1.0, 10.0, -3.0, 0.0}) {
        const double k = kH / H;
        const FaceMatrix k0 = slipstrip::face_stiffness(m, H, face, k, 0.0);
        for (cd su : {cd(0.5, 0.3), cd(0.05, 2.0), cd(1.0, -1.0)}) {
          const cd s = su * cs * std::max(std::abs(k), 1.0 / H);
          const double base = std::max(8.0 * std::abs(s), 100.0 * cs / H);
          const auto modes = slipstrip::face_modes(m, H, face, k, 8.0 * base);
          const FaceMatrix exact = slipstrip::face_stiffness(m, H, face, k, s);
          std::vector<FaceMatrix> d;
          for (double w : {1.0, 2.0, 4.0, 8.0}) d.push_back(truncated_expansion(k0, modes, s, w * base) - exact);
          CAPTURE(kH);
          CAPTURE(int(face));
          CAPTURE(su);
          for (int j = 0; j + 1 < 4; ++j) {
            const double ratio = d[j].max_abs() / d[j + 1].max_abs();
            const double richardson = (d[j] - cd(2.0) * d[j + 1]).max_abs() / d[j].max_abs();
            CHECK(ratio >= 1.8);
            CHECK(ratio <= 2.2);
            CHECK(richardson <= 0.1);
            worst_ratio_low = std::min(worst_ratio_low, ratio);
            worst_ratio_high = std::max(worst_ratio_high, ratio);
            worst_richardson = std::max(worst_richardson, richardson);
          }
          ++checked;
        }
      }
  }
  std::printf("[face modes] expansion: error ratio per doubling %.3f..%.3f, Richardson residue <= %.3f\n",
              worst_ratio_low, worst_ratio_high, worst_richardson);
  CHECK(checked == 90);
}

TEST_CASE("face modes: a 16 times finer bracketing grid finds the same modes") {
  // The modes are bracketed on a grid of 1/16 of a half wavelength in each vertical
  // wavenumber; two zeros closer than a grid cell would be missed.  A grid 16 times
  // finer must find exactly the same list (frequencies to the bisection's 1e-15).
  const double H = 0.1;
  for (const ElasticMaterial& m : kMaterials)
    for (OuterFace face : {OuterFace::driven, OuterFace::clamped})
      for (double kH : {0.05, 1.0, 10.0, 100.0}) {
        const double wmax = 300.0 * m.shear_wave_speed() / H;
        const auto a = slipstrip::face_modes(m, H, face, kH / H, wmax);
        const auto b = slipstrip::face_modes(m, H, face, kH / H, wmax, 256);
        CAPTURE(kH);
        CAPTURE(int(face));
        REQUIRE(a.size() == b.size());
        for (std::size_t i = 0; i < a.size(); ++i)
          CHECK(std::abs(a[i].frequency - b[i].frequency) <= 1e-13 * a[i].frequency);
      }
}

TEST_CASE("face modes: each residue is rank one, Hermitian and negative semidefinite") {
  // det W / |W|^2 <= 1e-13: a rank-one matrix's determinant cancels two products of
  // size |W|^2 (measured <= 3e-16).  W <= 0 is the passivity of the lossless body.
  const double H = 0.1;
  std::size_t count = 0;
  for (const ElasticMaterial& m : kMaterials)
    for (OuterFace face : {OuterFace::driven, OuterFace::clamped})
      for (double kH : {0.01, 0.3, 2.0, 30.0}) {
        const auto modes = slipstrip::face_modes(m, H, face, kH / H, 200.0 * m.shear_wave_speed() / H);
        for (const FaceMode& md : modes) {
          const FaceMatrix& w = md.weight;
          CHECK(std::abs(w.determinant()) <= 1e-13 * w.max_abs() * w.max_abs());
          CHECK(w.xx.real() <= 0.0);
          CHECK(w.yy.real() <= 0.0);
          CHECK(std::abs(w.xx.imag()) + std::abs(w.yy.imag()) == 0.0);
          CHECK(std::abs(w.xy - std::conj(w.yx)) <= 1e-15 * w.max_abs());
        }
        count += modes.size();
      }
  std::printf("[face modes] %zu residues checked\n", count);
  CHECK(count > 2000);
}

TEST_CASE("face modes: frequencies and residues agree with the propagator reference at the poles") {
  // (s^2 + omega_m^2) K_ref(s) at s = i omega_m (1 + eps) tends to the residue
  // R_m = W_m omega_m^2 with relative error O(eps omega_m / gap) (gap = distance to the
  // next mode) plus the reference's rounding amplified by 1/eps: eps = 1e-8, gaps >=
  // 1e-3 omega_m, so <= 1e-5 |W_neighbour| / |W_m|; tolerance 1e-4 relative to |R_m|
  // (a wrong frequency would not converge at all).
  const double H = 0.1;
  int checked = 0;
  for (const ElasticMaterial& m : kMaterials)
    for (OuterFace face : {OuterFace::driven, OuterFace::clamped})
      for (double kH : {0.2, 2.0, -6.0}) {
        const double k = kH / H;
        const auto modes = slipstrip::face_modes(m, H, face, k, 40.0 * m.shear_wave_speed() / H);
        for (std::size_t i = 0; i < modes.size() && i < 12; ++i) {
          const double w = modes[i].frequency;
          const double gap = std::min(i > 0 ? w - modes[i - 1].frequency : w,
                                      i + 1 < modes.size() ? modes[i + 1].frequency - w : w);
          if (gap < 1e-3 * w) continue;  // a near-double pole needs a smaller eps
          const cd s(0.0, w * (1.0 + 1e-8));
          const FaceMatrix ref = cd(s * s + w * w) * slipstrip::testing::reference_strip(m, H, face, k, s);
          const FaceMatrix expected = cd(w * w) * modes[i].weight;
          CAPTURE(kH);
          CAPTURE(int(face));
          CAPTURE(i);
          CAPTURE(w);
          CHECK((ref - expected).max_abs() <= 1e-4 * expected.max_abs());
          ++checked;
        }
      }
  CHECK(checked >= 150);
}

TEST_CASE("face modes: residues where both vertical wavenumbers are multiples of pi/H at once") {
  // Plane strain, nu = 0.33: (c_d/c_s)^2 = 67/17, and a mode of a driven layer of
  // height h with q_s h = 2 j pi, q_d h = j pi (q^2 = omega^2/c^2 - k^2) exists at
  // k h = j pi / (5 sqrt 2) (17 (2j)^2 - 67 j^2 = j^2).  There a sinh of each vertical
  // wavenumber vanishes and f = a coth(a h) of both waves is infinite; the clamped
  // body's driven half-layer (h = H/2) meets it at even j.  The kH grids of the
  // tests above miss these points.  Reference: the residue of the propagator
  // reference, the symmetric average of (s^2 + omega_m^2) K_ref(s) at
  // s = i omega_m (1 +- eps), which cancels the O(eps) term: its error is
  // O(eps^2 (omega_m / gap)^2) plus the reference's rounding amplified by 1/eps
  // (measured worst over all modes 2.4e-5, 2.4e-7, 2.6e-9, 2.7e-8 of |R_m| at eps =
  // 1e-5, 1e-6, 1e-7, 1e-8).  eps = 1e-7, tolerance 1e-7; a weight evaluated as
  // inf/inf at the degenerate modes was off by 0.24 to 0.995.  Every mode below
  // 40 c_s / H is checked, not only the degenerate ones.
  const double H = 0.1, eps = 1e-7;
  const ElasticMaterial m = kMaterials[0];  // Table S1, plane strain, nu = 0.33
  int checked = 0, degenerate = 0;
  double worst = 0.0, worst_degenerate = 0.0;
  for (OuterFace face : {OuterFace::driven, OuterFace::clamped})
    for (int j = 1; j <= 8; ++j) {
      if (face == OuterFace::clamped && j % 2 != 0) continue;
      const double kH = j * std::numbers::pi / (5.0 * std::sqrt(2.0));
      for (double sign : {1.0, -1.0}) {
        const double k = sign * kH / H;
        const auto all = slipstrip::face_modes(m, H, face, k, 40.0 * m.shear_wave_speed() / H);
        // The clamped body's roller and driven half-layers share the degenerate
        // frequency (both sines vanish in either layer's pole function): a double
        // pole of K whose residue is the sum of the two listed weights.
        std::vector<FaceMode> modes;
        for (const FaceMode& md : all)
          if (!modes.empty() && md.frequency - modes.back().frequency <= 1e-12 * md.frequency)
            modes.back().weight = modes.back().weight + md.weight;
          else
            modes.push_back(md);
        const double h = face == OuterFace::driven ? H : 0.5 * H;
        const double c_s = m.shear_wave_speed(), c_d = m.dilatational_wave_speed();
        for (std::size_t i = 0; i < modes.size(); ++i) {
          const double w = modes[i].frequency;
          const double gap = std::min(i > 0 ? w - modes[i - 1].frequency : w,
                                      i + 1 < modes.size() ? modes[i + 1].frequency - w : w);
          if (gap < 1e-3 * w) continue;
          FaceMatrix ref;
          for (double e : {eps, -eps}) {
            const cd s(0.0, w * (1.0 + e));
            ref = ref + cd(0.5 * (s * s + w * w)) * slipstrip::testing::reference_strip(m, H, face, k, s);
          }
          const FaceMatrix expected = cd(w * w) * modes[i].weight;
          // Is this one of the degenerate modes (both sin(q h) = 0)?
          const double qs = std::sqrt(std::max(0.0, w * w / (c_s * c_s) - k * k)) * h / std::numbers::pi;
          const double qd = std::sqrt(std::max(0.0, w * w / (c_d * c_d) - k * k)) * h / std::numbers::pi;
          const bool both = std::abs(qs - std::round(qs)) < 1e-9 && std::abs(qd - std::round(qd)) < 1e-9 &&
                            std::round(qd) > 0.0;
          const double err = (ref - expected).max_abs() / ref.max_abs();
          CAPTURE(kH);
          CAPTURE(sign);
          CAPTURE(int(face));
          CAPTURE(i);
          CAPTURE(w * H / c_s);
          CAPTURE(both);
          CAPTURE(expected.xx);
          CAPTURE(ref.xx);
          CHECK(err <= 1e-7);
          worst = std::max(worst, err);
          if (both) worst_degenerate = std::max(worst_degenerate, err);
          degenerate += both;
          ++checked;
        }
      }
    }
  std::printf("[face modes] degenerate kH: %d residues, worst relative error %.2e; %d with both sines zero, "
              "worst %.2e\n",
              checked, worst, degenerate, worst_degenerate);
  // The degenerate mode has q_s H = 2 j pi for either face (the clamped body's
  // half-layer: q_s H / 2 = 2 (j / 2) pi), so omega H / c_s is just above 2 pi j and
  // below 40 for j <= 6: driven j = 1..6, clamped j = 2, 4, 6, both signs of k.
  CHECK(degenerate == 18);
}
