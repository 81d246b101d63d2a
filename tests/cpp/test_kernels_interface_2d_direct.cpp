// The traction history on a tiny 2D interface (6 x 4 nodes) evaluated
// directly, without an FFT and without the solver's modal or block machinery,
// against the spectral path the solver takes (solver/simulation_3d.cpp: the
// nodal slip rates through RealFft2d, InterfaceHistory2d, and back).
//
// The prescribed slip at node n along j is a sum of delayed smooth bumps,
//   delta_j(x_n, t) = sum_a A_{a,j,n} g(t - t_a),  g = sin^4 on [0, T],
// with random amplitudes and onsets t_a on the time grid, so the slip rate
// given to the solver is sampled from a known smooth history.  Then
//   tau_i(x_n, t) = sum_{n', j, a} A_{a,j,n'} G_ij(x_n - x_n', t - t_a),
// a space-time convolution with the real-space response G_ij to one bump at
// one node.  G_ij is the explicit sum over the grid's discrete Fourier modes,
//   G_ij(dx, dz, t) = 1/(N N_z) sum_k cos(k . d) [R^P_ij(k^) T_P(|k|, t) + R^SH_ij(k^) T_SH(|k|, t)],
// R^P = k^ k^ (the in-plane response acts along k^), R^SH = 1 - k^ k^, and
// T(|k|, t) the inverse Laplace transform (Durbin, tests/cpp/inverse_laplace.hpp)
// of -S(|k|, s) g^(s) with the closed forms S_P (strip_response, plane strain)
// and S_SH (antiplane_strip_response) at |k|.  The Nyquist wavenumbers of the
// even grid stand for +pi/dx and -pi/dx (and +-pi/dz): the sum takes both
// signs at half weight, which makes G real and even in d (this is the
// operator's Nyquist convention, docs/3d.md, derived here from the real-space
// sum and not from the operator).  k = 0 is the 1-D shear problem, where
// S_P = S_SH and R^P + R^SH = 1.
//
// Two different bodies (InterfaceHistory2d::build_pair): per mode, slip along
// k-hat gives the shear traction -K_xx delta and the compressive normal
// stress K_yx delta ((K_xx, K_yx) the first column of the closed-form series
// stiffness K_ser = (K_t^-1 + mirrored(K_b)^-1)^-1, kernels/face_response.hpp),
// slip across it the antiplane pair's -(K_t^-1 + K_b^-1)^-1 delta.  K_yx is
// i sgn(k) times a real function (odd in k), so the normal stress's real-space
// response is the sine sum
//   G_nj(d, t) = 1/(N N_z) sum_k (-sin(k . d)) k-hat_j T_N(|k|, t),
// T_N the inverse transform of -i K_yx(|k|, s) g^(s).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <functional>
#include <limits>
#include <map>
#include <numbers>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "inverse_laplace.hpp"
#include "kernels/antiplane_response.hpp"
#include "kernels/block_strip_history.hpp"
#include "kernels/face_response.hpp"
#include "kernels/fft.hpp"
#include "kernels/interface_2d_history.hpp"
#include "kernels/strip_response.hpp"
#include "kernels/two_body_history.hpp"
#include "single_mode_drive.hpp"

using namespace slipstrip;
using testing::with_plane;
using cplx = std::complex<double>;
constexpr double pi = std::numbers::pi;
constexpr double kInf = std::numeric_limits<double>::infinity();

namespace {

struct Source {
  int node, direction, onset;  // onset t_a = onset dt
  double amplitude;            // [m]
};

// The real-space response G_ij(node offset, t_m), m = 0..steps, to one bump
// of unit slip along j (x, z) at one node, for the outputs i = shear x,
// shear z and the compressive normal stress: [iz][ix][i][j][m].
constexpr int kOutputs = 3;
struct RealSpaceKernel {
  int nodes_x, nodes_z, samples;
  std::vector<double> values;
  double& at(int ix, int iz, int i, int j, int m) {
    return values[((((static_cast<std::size_t>(iz) * nodes_x + ix) * kOutputs + i) * 2 + j) * samples) + m];
  }
  double at(int ix, int iz, int i, int j, int m) const {
    return values[((((static_cast<std::size_t>(iz) * nodes_x + ix) * kOutputs + i) * 2 + j) * samples) + m];
  }
};

// The inverse transforms at one |k|: of -S_along g^, -S_across g^ and (pairs
// only; empty otherwise) -i K_yx g^ (the normal stress's real part).
struct ModeResponses {
  std::vector<double> along, across, normal;
};
using ResponsesAt = std::function<ModeResponses(double)>;

// Signed wavenumber indices of a grid of n nodes, each with its weight: the
// Nyquist index n/2 of an even grid as +-n/2 at half weight.
std::vector<std::pair<int, double>> signed_indices(int n) {
  std::vector<std::pair<int, double>> out;
  for (int q = -((n - 1) / 2); q <= (n - 1) / 2; ++q) out.push_back({q, 1.0});
  if (n % 2 == 0) {
    out.push_back({n / 2, 0.5});
    out.push_back({-n / 2, 0.5});
  }
  return out;
}

// The identical bodies' responses: the closed forms S_P (plane strain) and S_SH.
ResponsesAt identical_responses(const ElasticMaterial& material, double H, double dt, double rise, int steps,
                                int durbin_terms) {
  const ElasticMaterial strain = with_plane(material, PlaneCondition::strain),
                        sh = with_plane(material, PlaneCondition::antiplane);
  return [=](double km) {
    auto inverted = [&](bool inplane) {
      return testing::inverse_laplace(
          [&](cplx p) {
            const cplx S = inplane ? strip_response(strain, H, km, p) : antiplane_strip_response(sh, H, km, p);
            return -S * testing::bump_laplace(p, rise);
          },
          dt, durbin_terms, steps + 1);
    };
    return ModeResponses{inverted(true), inverted(false), {}};
  };
}

RealSpaceKernel direct_kernel(const ResponsesAt& responses_at, const InterfaceGrid2d& grid, int steps) {
  // Responses per distinct |k| (both signs of a wavevector give the same hypot bit for bit).
  std::map<double, ModeResponses> responses;
  auto response = [&](double km) -> const ModeResponses& {
    auto it = responses.find(km);
    if (it != responses.end()) return it->second;
    return responses.emplace(km, responses_at(km)).first->second;
  };
  RealSpaceKernel G{grid.nodes_x, grid.nodes_z, steps + 1,
                    std::vector<double>(static_cast<std::size_t>(grid.nodes_x) * grid.nodes_z * kOutputs * 2 *
                                            (steps + 1),
                                        0.0)};
  const double dx = grid.length_x / grid.nodes_x, dz = grid.length_z / grid.nodes_z;
  const double norm = 1.0 / (grid.nodes_x * grid.nodes_z);
  for (const auto& [qx, wx] : signed_indices(grid.nodes_x))
    for (const auto& [qz, wz] : signed_indices(grid.nodes_z)) {
      const double kx = 2 * pi * qx / grid.length_x, kz = 2 * pi * qz / grid.length_z;
      const double km = std::hypot(kx, kz);
      const double c = km > 0 ? kx / km : 1.0, s = km > 0 ? kz / km : 0.0;
      const double along[2][2] = {{c * c, c * s}, {c * s, s * s}};
      const double across[2][2] = {{s * s, -c * s}, {-c * s, c * c}};
      const double direction[2] = {c, s};
      const ModeResponses& T = response(km);
      for (int iz = 0; iz < grid.nodes_z; ++iz)
        for (int ix = 0; ix < grid.nodes_x; ++ix) {
          const double phase = kx * ix * dx + kz * iz * dz;
          const double even = norm * wx * wz * std::cos(phase), odd = -norm * wx * wz * std::sin(phase);
          for (int i = 0; i < 2; ++i)
            for (int j = 0; j < 2; ++j)
              for (int m = 0; m <= steps; ++m)
                G.at(ix, iz, i, j, m) += even * (along[i][j] * T.along[m] + across[i][j] * T.across[m]);
          if (T.normal.empty()) continue;
          for (int j = 0; j < 2; ++j)
            for (int m = 0; m <= steps; ++m) G.at(ix, iz, 2, j, m) += odd * direction[j] * T.normal[m];
        }
    }
  return G;
}

// tau_x, tau_z and the normal stress at (node, t_m) [3][N][steps + 1] by the
// direct space-time convolution.
std::vector<double> direct_traction(const RealSpaceKernel& G, const std::vector<Source>& sources, int steps) {
  const int nx = G.nodes_x, nz = G.nodes_z, nodes = nx * nz;
  std::vector<double> tau(static_cast<std::size_t>(kOutputs) * nodes * (steps + 1), 0.0);
  for (int n = 0; n < nodes; ++n)
    for (const Source& src : sources) {
      const int ix = ((n % nx) - (src.node % nx) + nx) % nx, iz = ((n / nx) - (src.node / nx) + nz) % nz;
      for (int i = 0; i < kOutputs; ++i)
        for (int m = src.onset; m <= steps; ++m)
          tau[(static_cast<std::size_t>(i) * nodes + n) * (steps + 1) + m] +=
              src.amplitude * G.at(ix, iz, i, src.direction, m - src.onset);
    }
  return tau;
}

// The same by the solver's spectral path: per step the nodal slip rates
// through RealFft2d, the operator, and back; tau = -eta v - h (h at t_n from
// the rates up to t_{n-1}, as in Simulation3d::step); for different bodies
// the normal stress at t_n from the same pushes (no opening; it has no
// instantaneous term), zero for identical ones.
std::vector<double> spectral_traction(InterfaceHistory2d& op, const std::vector<Source>& sources, double rise,
                                      int steps) {
  const InterfaceGrid2d& grid = op.grid();
  const int nodes = grid.nodes_x * grid.nodes_z;
  const double dt = op.time_step(), eta = op.radiation_damping();
  RealFft2d fft(grid.nodes_x, grid.nodes_z);
  std::vector<double> v[2] = {std::vector<double>(nodes), std::vector<double>(nodes)};
  std::vector<double> h[3] = {std::vector<double>(nodes, 0.0), std::vector<double>(nodes, 0.0),
                              std::vector<double>(nodes, 0.0)};
  std::vector<cplx> spectrum[2] = {std::vector<cplx>(grid.modes()), std::vector<cplx>(grid.modes())};
  std::vector<double> tau(static_cast<std::size_t>(kOutputs) * nodes * (steps + 1));
  for (int m = 0; m <= steps; ++m) {
    for (int j = 0; j < 2; ++j) std::fill(v[j].begin(), v[j].end(), 0.0);
    for (const Source& src : sources)
      v[src.direction][src.node] += src.amplitude * testing::bump_rate((m - src.onset) * dt, rise);
    for (int i = 0; i < 2; ++i)
      for (int n = 0; n < nodes; ++n) tau[(static_cast<std::size_t>(i) * nodes + n) * (steps + 1) + m] =
          -eta * v[i][n] - h[i][n];
    for (int n = 0; n < nodes; ++n) tau[(static_cast<std::size_t>(2) * nodes + n) * (steps + 1) + m] = h[2][n];
    for (int j = 0; j < 2; ++j) fft.forward(v[j], spectrum[j]);
    if (op.variable_normal_stress()) {
      op.push(spectrum[0], spectrum[1], {});
      fft.inverse(op.normal_stress(), h[2]);
    } else {
      op.push(spectrum[0], spectrum[1]);
    }
    fft.inverse(op.history_x(), h[0]);
    fft.inverse(op.history_z(), h[1]);
  }
  return tau;
}

// Two bumps per node and direction, onsets within the first 4 echoes on a grid
// of 128 steps per echo, scaled to `steps_per_echo` (the same history at every dt).
std::vector<Source> random_sources(int nodes, int steps_per_echo) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> amplitude(-1e-6, 1e-6);
  std::uniform_int_distribution<int> onset(0, 4 * 128);
  std::vector<Source> sources;
  for (int n = 0; n < nodes; ++n)
    for (int j = 0; j < 2; ++j)
      for (int a = 0; a < 2; ++a) {
        const int start = onset(rng) * (steps_per_echo / 128);
        sources.push_back({n, j, start, amplitude(rng)});
      }
  return sources;
}

// The relative L2 difference over all nodes and times of each of the first
// `components` outputs (x, z, normal), printed; each must be below `bound`;
// returns the largest.
double compare_components(const std::vector<double>& spectral, const std::vector<double>& direct, int nodes, int steps,
                          int components, const std::string& label, double bound) {
  const char* names[kOutputs] = {"tau_x", "tau_z", "normal stress"};
  double worst = 0.0;
  for (int i = 0; i < components; ++i) {
    const auto first = static_cast<std::size_t>(i) * nodes * (steps + 1), count = first + nodes * (steps + 1);
    const std::vector<double> a(spectral.begin() + first, spectral.begin() + count),
        b(direct.begin() + first, direct.begin() + count);
    double peak = 0.0;
    for (double value : b) peak = std::max(peak, std::abs(value));
    const double error = testing::relative_l2_difference(a, b);
    MESSAGE(label << ", " << steps << " steps, " << std::string(names[i]) << ": relative L2 |spectral - direct| = " << error
                  << " (max " << peak << " Pa)");
    CHECK(error < bound);
    worst = std::max(worst, error);
  }
  return worst;
}

int durbin_terms_for(int steps) {
  // Durbin: period 2 T_p = K dt with T_p = 4 t_max, so the aliasing
  // e^{-24} ~ 4e-11 of the static traction; truncation at 2 pi/dt, where the
  // bump's transform (~ s^-5) has fallen by ~(1/128)^5.
  int terms = 1;
  while (terms < 8 * (steps + 1)) terms *= 2;
  return terms;
}

}  // namespace

TEST_CASE("6 x 4 interface: traction history by direct space-time convolution = the spectral operators") {
  const ElasticMaterial material;
  const double cs = material.shear_wave_speed();
  // 6 x 4 nodes, dx = dz = 0.1 m: both Nyquist wavenumbers, the corner mode and
  // oblique modes at every angle the grid has; |k| up to pi sqrt(2)/0.1 m.
  const InterfaceGrid2d grid{0.6, 0.4, 6, 4};
  const int nodes = grid.nodes_x * grid.nodes_z;
  // 128 steps per echo 2 (0.1 m)/c_s, as the oblique single-mode test; the
  // half-space takes the same dt (c_s |k|_max dt = 0.07).
  const double echo = 2 * 0.1 / cs;
  const double dmin = 0.1;
  struct Case {
    double H;
    std::string history;
    int steps_per_echo;
  };
  // The strips at 128 and 256 steps per echo: the difference is the time
  // discretisation's, second order in dt.
  std::map<std::pair<std::string, int>, double> errors;
  for (const Case& test : {Case{0.1, "modal", 128}, Case{0.1, "modal", 256}, Case{0.1, "block", 128},
                           Case{kInf, "half-space", 128}}) {
    const double dt = strip_time_step(material, test.H, dmin, echo / test.steps_per_echo * cs / dmin);
    const double rise = echo;
    const int steps = static_cast<int>(std::lround(8 * echo / dt));
    const std::vector<Source> sources = random_sources(nodes, test.steps_per_echo);
    const int durbin_terms = durbin_terms_for(steps);
    const RealSpaceKernel G =
        direct_kernel(identical_responses(material, test.H, dt, rise, steps, durbin_terms), grid, steps);
    const std::vector<double> direct = direct_traction(G, sources, steps);

    InterfaceHistory2d::StripOperatorFactory factory;
    if (test.history == "block")
      factory = [](const ElasticMaterial& body, const StripKernels& kernels) {
        // Blocks of 64 steps: ~16 far-field updates in the run.
        return std::unique_ptr<HistoryOperator>(
            std::make_unique<BlockStripHistory>(body, kernels, BlockHistoryDesign{8, 64, 14}));
      };
    InterfaceHistory2d op = InterfaceHistory2d::build(material, test.H, grid, dt, {}, factory);
    const std::vector<double> spectral = spectral_traction(op, sources, rise, steps);

    // The 2D operators' discretisation error at 128 steps per echo: 1e-6
    // for strips (test_kernels_time_domain, second order in dt), ~4e-5 for
    // the half-space at c_s |k| dt ~ 1/13 (docs/theory.md 8.4); the Durbin
    // references are good to ~1e-10 and the direct sums add round-off.  The
    // oblique single-mode test's bound, 1e-4, covers every case.
    const double worst =
        compare_components(spectral, direct, nodes, steps, 2, test.history + ", H = " + std::to_string(test.H), 1e-4);
    errors[{test.history, test.steps_per_echo}] = worst;
  }
  // The difference is the time discretisation's: halving dt must divide it
  // by at least ~4 (second order; > 3 allows for the Durbin references' and
  // the round-off's share at 256 steps).
  const double ratio = errors[{"modal", 128}] / errors[{"modal", 256}];
  MESSAGE("strips, modal: error at 128 / at 256 steps per echo = " << ratio);
  CHECK(ratio > 3.0);
  // The block operator is the modal one's discrete operator (test_kernels_interface_2d: 1e-10).
  CHECK(std::abs(errors[{"block", 128}] - errors[{"modal", 128}]) <= 1e-3 * errors[{"modal", 128}]);
}

namespace {

// Two different bodies: the in-plane series stiffness's first column (shear
// along k-hat, compressive normal stress) and the antiplane pair, each body
// in closed form (kernels/face_response.hpp, kernels/antiplane_response.hpp).
ResponsesAt pair_responses(const ElasticMaterial& top, double top_height, const ElasticMaterial& bottom,
                           double bottom_height, bool rigid_bottom, double dt, double rise, int steps,
                           int durbin_terms) {
  const ElasticMaterial strain_top = with_plane(top, PlaneCondition::strain),
                        strain_bottom = with_plane(bottom, PlaneCondition::strain),
                        sh_top = with_plane(top, PlaneCondition::antiplane),
                        sh_bottom = with_plane(bottom, PlaneCondition::antiplane);
  const ElasticBody top_body{strain_top, top_height, OuterFace::driven, false};
  const ElasticBody bottom_body{strain_bottom, bottom_height, OuterFace::clamped, rigid_bottom};
  return [=](double km) {
    auto inverted = [&](int part) {
      return testing::inverse_laplace(
          [&](cplx p) {
            const cplx g = testing::bump_laplace(p, rise);
            if (part == 2) {
              // One body's SH stiffness is twice the identical pair's response.
              const cplx kt = 2.0 * antiplane_strip_response(sh_top, top_height, km, p);
              if (rigid_bottom) return -kt * g;
              const cplx kb = 2.0 * antiplane_strip_response(sh_bottom, bottom_height, km, p);
              return -(kt * kb / (kt + kb)) * g;
            }
            const SlipResponse r = interface_slip_response(top_body, bottom_body, km, p);
            return part == 0 ? -r.shear * g : cplx(0.0, -1.0) * r.normal * g;
          },
          dt, durbin_terms, steps + 1);
    };
    return ModeResponses{inverted(0), inverted(2), inverted(1)};
  };
}

}  // namespace

TEST_CASE("6 x 4 interface, different bodies: traction and normal stress by direct space-time convolution = the "
          "spectral operators") {
  // The top body: Table S1, H_t = 0.1 m, driven.  The bottom body: slower and
  // denser (c_s 1369 against 1679 m/s) with another Poisson ratio, H_b = 0.05
  // m, clamped; the same material as a half-space; or a rigid base.  Same grid as the identical bodies' case
  // (both Nyquist wavenumbers, the corner mode, every oblique angle), so the
  // normal stress's sine sum also checks the Nyquist modes' treatment, where
  // the coupling averages out between the two signs.
  ElasticMaterial top_material;
  ElasticMaterial bottom_material = top_material;
  bottom_material.shear_modulus = 4.5e9;
  bottom_material.density = 2400.0;
  bottom_material.poisson_ratio = 0.25;
  const InterfaceGrid2d grid{0.6, 0.4, 6, 4};
  const int nodes = grid.nodes_x * grid.nodes_z;
  const double top_height = 0.1, dmin = 0.1;
  const double cs_top = top_material.shear_wave_speed();
  const double echo = 2 * top_height / cs_top;
  const double c_max = std::max(cs_top, bottom_material.shear_wave_speed());
  // 256 steps per top echo: the dissimilar pair's discretisation error there
  // is 1.0e-5 to 5.0e-5 (relative L2, the oblique single-mode test against the
  // same closed forms), 4.0e-5 to 1.9e-4 at 128.
  const TwoBodyTiming timing = two_body_time_step(with_plane(top_material, PlaneCondition::strain), top_height,
                                                  with_plane(bottom_material, PlaneCondition::strain), 0.05, dmin,
                                                  echo / 256 * c_max / dmin);
  const double dt = timing.time_step;
  const double rise = echo;
  const int steps = static_cast<int>(std::lround(8 * echo / dt));
  const std::vector<Source> sources = random_sources(nodes, 256);
  const int durbin_terms = durbin_terms_for(steps);
  struct Bottom {
    const char* name;
    double height;
    bool rigid;
  };
  for (const Bottom& b : {Bottom{"strip on a different strip", timing.bottom_height, false},
                          Bottom{"strip on a different half-space", kInf, false}, Bottom{"rigid base", 0.0, true}}) {
    const RealSpaceKernel G = direct_kernel(
        pair_responses(top_material, top_height, bottom_material, b.height, b.rigid, dt, rise, steps, durbin_terms),
        grid, steps);
    const std::vector<double> direct = direct_traction(G, sources, steps);
    std::optional<InterfaceBody> bottom;
    if (!b.rigid) bottom = InterfaceBody{bottom_material, b.height, OuterFace::clamped};
    InterfaceHistory2d op =
        InterfaceHistory2d::build_pair(InterfaceBody{top_material, top_height, OuterFace::driven}, bottom, grid, dt);
    REQUIRE(op.variable_normal_stress());
    const std::vector<double> spectral = spectral_traction(op, sources, rise, steps);
    // The bound of the oblique single-mode test (the same operators, the same
    // closed forms): 1e-4 at 256 steps per echo, where their time
    // discretisation gives up to 5e-5; the Durbin references ~1e-10.
    compare_components(spectral, direct, nodes, steps, 3, b.name, 1e-4);
  }
}
