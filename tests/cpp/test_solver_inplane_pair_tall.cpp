// A dissimilar in-plane pair of tall strips (H/dx = 128 at beta = 0.25): each
// body's 2x2 operator (kernels/face_history.hpp) must place the static
// stiffness of its modes above Nyquist passively at every wavenumber of the
// grid, and the pair must set up and run.  With the placement limited to the 64
// highest modes it could not (at the Nyquist wavenumber those modes carry less
// xx stiffness than the positive part to be placed), and the set-up threw
// "cannot place the truncated static stiffness passively"; the sizes are those
// of `slipstrip bench --pairs` at N = 512, H = 1 m, with L = 1 m instead of 4 m
// (the same dx, dt and Nyquist wavenumber, a quarter of the Fourier modes).
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>

#include "kernels/face_history.hpp"
#include "kernels/history_convolution.hpp"
#include "solver/simulation.hpp"

using namespace slipstrip;

namespace {

constexpr double kLength = 1.0, kHeight = 1.0, kBeta = 0.25;
constexpr int kNodes = 128;

// Largest eigenvalue of a Hermitian 2x2 matrix.
double max_eigenvalue(const FaceMatrix& m) {
  const double a = m.xx.real(), d = m.yy.real();
  return 0.5 * (a + d) + std::sqrt(0.25 * (a - d) * (a - d) + std::norm(m.xy));
}

}  // namespace

TEST_CASE("face history of a tall body (H/dx = 128): passive placement at every wavenumber") {
  // The matrix passivity check of test_kernels_face_history ("exact statics and
  // positive semidefinite Foster coefficients"), with its tolerances, on every
  // Fourier mode q = 0..N/2 of the bench's pair: both outer faces, plane strain
  // and plane stress, the top material and the bottom one (2 mu, 2 rho).
  int checked = 0;
  for (PlaneCondition plane : {PlaneCondition::strain, PlaneCondition::stress})
    for (double factor : {1.0, 2.0})
      for (OuterFace face : {OuterFace::driven, OuterFace::clamped}) {
        ElasticMaterial m;
        m.plane = plane;
        m.shear_modulus *= factor;
        m.density *= factor;
        const double cs = m.shear_wave_speed();
        const double dt = strip_time_step(m, kHeight, kLength / kNodes, kBeta);
        for (int q = 0; q <= kNodes / 2; ++q) {
          const double k = 2 * std::numbers::pi * q / kLength;
          CAPTURE(q);
          CAPTURE(factor);
          FaceDiscreteModes d;
          REQUIRE_NOTHROW(d = face_discrete_modes(m, kHeight, face, k, dt));
          FaceMatrix sum;
          sum.xx = 2 * m.shear_modulus / (cs * dt);
          sum.yy = 2 * m.density * m.dilatational_wave_speed() / dt;
          const double scale = sum.max_abs();
          bool negative_semidefinite = true, phases_in_range = true;
          for (const FaceMatrix& w : d.weight) {
            negative_semidefinite = negative_semidefinite && max_eigenvalue(w) <= 1e-13 * w.max_abs();
            sum = sum + w;
          }
          for (double p : d.phase) phases_in_range = phases_in_range && p > 0.0 && p <= std::numbers::pi;
          CHECK(negative_semidefinite);
          CHECK(phases_in_range);
          CHECK((sum - face_stiffness(m, kHeight, face, k, 0.0)).max_abs() <= 1e-12 * scale);
          ++checked;
        }
      }
  CHECK(checked == 2 * 2 * 2 * (kNodes / 2 + 1));
}

TEST_CASE("a dissimilar in-plane pair of tall strips sets up and a short run stays finite") {
  // The bench's pair (bottom body: same height and wave speeds, 2 mu and 2 rho)
  // with both body algorithms, from a noisy initial state.  256 steps are a
  // quarter of the shear echo 2H/c_s (1024 steps) but 128 periods of the
  // Nyquist-phase elements, where a misplaced stiffness would act; the run must
  // stay finite and the slip rate bounded (it stays within 1 % of its initial
  // maximum; the bound 10x only catches a blow-up).
  for (HistoryAlgorithm algorithm : {HistoryAlgorithm::modal, HistoryAlgorithm::block}) {
    SimulationConfig c;
    c.geometry = {kLength, kHeight, kNodes};
    c.time.beta = kBeta;
    c.time.history = algorithm;
    c.initial.noise_amplitude = 1e-3;
    c.bottom.body = BodyKind::elastic;
    c.bottom.shear_modulus = 2.0 * c.material.shear_modulus;
    c.bottom.density = 2.0 * c.material.density;
    c.bottom.poisson_ratio = c.material.poisson_ratio;
    c.bottom.height = kHeight;
    Simulation sim(c);
    REQUIRE(sim.variable_normal_stress());
    const double v0 = sim.max_slip_rate();
    for (int n = 0; n < 256; ++n) sim.step();
    bool finite = true;
    for (double v : sim.slip_rate()) finite = finite && std::isfinite(v);
    for (double s : sim.normal_stress()) finite = finite && std::isfinite(s);
    for (double s : sim.shear_stress()) finite = finite && std::isfinite(s);
    CHECK(finite);
    CHECK(sim.max_slip_rate() < 10.0 * v0);
    MESSAGE("max slip rate: " << v0 << " m/s at set-up, " << sim.max_slip_rate() << " m/s after 256 steps");
  }
}
