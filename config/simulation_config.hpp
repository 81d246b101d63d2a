#pragma once
// The fully resolved description of one run.  Every field is in SI units and
// maps one-to-one onto a TOML key; the defaults below are the defaults of the
// config.  The keys themselves (unit, range, help) are declared once in
// config/config_schema.cpp, from which parsing, to_toml and docs/config.md follow.
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "config/interface_law_name.hpp"
#include "friction/friction_law.hpp"
#include "friction/parameter_profile.hpp"
#include "kernels/elastic_material.hpp"
#include "kernels/face_response.hpp"

namespace slipstrip {

struct GeometryConfig {
  double length = 4.0;   // [geometry] length L [m], period in x
  double height = 0.1;   // [geometry] height H [m] of each strip; +inf = half-space
  int nodes = 1600;      // [geometry] nodes N (power of two recommended for FFT speed)
  // A 2D interface (docs/3d.md): period along z and nodes across it; nodes_z
  // = 1 is the one-dimensional interface (the 2D problem; width unused).
  double width = 1.0;    // [geometry] width L_z [m], period in z
  int nodes_z = 1;       // [geometry] nodes_z
};

// What loads the interface's uniform (k = 0) mode (docs/transition.md, "Driving
// the mean slip rate"):
//   outer_faces    : the outer faces move at +-v0/2 (a half-space: only
//                    radiation damping acts on the uniform mode)
//   mean_slip_rate : a uniform shear stress tau_0(t), the unknown of every
//                    step, keeps the mean slip rate over the nodes at v0; the
//                    modes k != 0 are unchanged
enum class LoadingDrive { outer_faces, mean_slip_rate };
inline constexpr std::string_view kLoadingDriveNames[] = {"outer_faces", "mean_slip_rate"};  // index = enumerator

struct LoadingConfig {
  double driving_velocity = 2e-3;  // [loading] driving_velocity v0 [m/s]
  double normal_stress = 1e6;      // [loading] normal_stress sigma0 [Pa]
  LoadingDrive drive = LoadingDrive::outer_faces;  // [loading] drive
};

// How the interface closes the elastodynamic problem: the interface law
// (laws/interface_law.hpp) of the registered name InterfaceLawName
// (config/interface_law_name.hpp).  Built in:
//   rate_and_state  : the paper's friction (default)
//   prescribed_slip : slip(x,t) = amplitude cos(2 pi mode x / L) g(t)   (verification)
//   free            : no friction, an imposed shear-stress perturbation   (verification)

// Time profile g(t) used by the verification laws.
//   ramp : g = 0 for t<0, (1 - cos(pi t / T))/2 for 0<=t<T, 1 after   (C1 ramp)
//   bump : g = sin^4(pi t / T) for 0<=t<T, 0 otherwise                  (C3 bump)
enum class TimeProfile { ramp, bump };
inline constexpr std::string_view kTimeProfileNames[] = {"ramp", "bump"};  // index = enumerator

// In-plane dissimilar bodies, where the compressive normal stress would become
// <= 0: the faces separate (zero traction, a gap; docs/bodies.md §4) or the
// run stops with a diagnostic naming the node and the time.
enum class OpeningResponse { open, stop };
inline constexpr std::string_view kOpeningResponseNames[] = {"open", "stop"};  // index = enumerator

struct InterfaceConfig {
  InterfaceLawName law = InterfaceLawName::rate_and_state;  // [interface] law
  // prescribed_slip: [interface] slip_amplitude [m], mode (integer m), profile, rise_time [s]
  double slip_amplitude = 1e-6;
  int mode = 1;
  TimeProfile profile = TimeProfile::ramp;
  double rise_time = 1e-4;
  // free: shear-stress pulse dtau(x,t) = stress_amplitude * exp(-((x-x0)/w)^2 / 2) * g(t)
  //   [interface] stress_amplitude [Pa], pulse_center [m], pulse_width [m] (<=0 or inf: uniform)
  double stress_amplitude = 1e5;
  double pulse_center = 0.0;
  double pulse_width = std::numeric_limits<double>::infinity();
  // rate_and_state: an extra shear-load pulse of this amplitude [Pa] with the
  // same shape (pulse_center, pulse_width, profile, rise_time); 0 = off.  A
  // smooth way to nucleate at a chosen place, and a problem that is smooth in
  // time (an initial state perturbation makes v jump at t = 0+).
  double load_pulse_amplitude = 0.0;
  // In-plane dissimilar bodies: the friction sees an effective normal stress
  // relaxing towards the current one over a slip L_sigma (0 = the friction's
  // characteristic slip) or, when normal_stress_time > 0, over that time
  // (docs/bodies.md, "normal-stress memory").
  double normal_stress_slip = 0.0;
  double normal_stress_time = 0.0;
  OpeningResponse opening = OpeningResponse::open;  // [interface] opening
};

// Initial perturbations on top of steady sliding at v0 (phi = phi_ss(v0)).
struct InitialConfig {
  double noise_amplitude = 0.0;      // [initial] noise_amplitude: relative std of the noise in phi
  std::uint64_t noise_seed = 1;      // [initial] noise_seed
  int noise_modes = 0;               // [initial] noise_modes: 0 = white noise per node; M = first M
                                     // Fourier modes (the same field on every mesh, laws/initial_state.hpp)
  double sine_amplitude = 0.0;       // [initial] sine_amplitude eps: phi_ss eps sin(2 pi m x/L + pi/2)
  int sine_mode = 1;                 // [initial] sine_mode m
  double local_amplitude = 0.0;      // [initial] local_amplitude: relative bump in phi (Gaussian)
  double local_center = 0.0;         // [initial] local_center x [m]
  double local_width = 0.0;          // [initial] local_width [m]
  // A 2D interface: the bump is also a Gaussian in z (a patch) when
  // local_width_z > 0; 0 = the same bump on every row z.
  double local_center_z = 0.0;       // [initial] local_center_z z [m]
  double local_width_z = 0.0;        // [initial] local_width_z [m]
};

// How the strip's history operator is applied (both give the same discrete
// operator, to ~1e-13; docs/performance.md):
//   modal : one rotation per strip normal mode and step, O(H/dx) per Fourier mode
//   block : FFT block convolutions + NUFFT-moved normal-mode states, O(log^2(H/dx))
//   auto  : block when a Fourier mode has >= 128 normal modes, else modal
// The half-space has its own operator and ignores this key.
enum class HistoryAlgorithm { automatic, modal, block };
inline constexpr std::string_view kHistoryAlgorithmNames[] = {"auto", "modal", "block"};  // index = enumerator

// [time] half_space_pair: how an in-plane pair of two different half-spaces is
// simulated (docs/bodies.md §4): one combined operator of the interface's
// jumps (docs/inplane_bodies.md §7), or each body's own operator.
enum class HalfSpacePairOperator { combined, bodies };
inline constexpr std::string_view kHalfSpacePairOperatorNames[] = {"combined", "bodies"};  // index = enumerator

// [time] antiplane_pair: how an antiplane pair of two different bodies is
// simulated on a line: one combined scalar operator of the pair
// (kernels/antiplane_pair_modes.hpp for two finite strips; HalfSpaceHistory's
// pair constructor for two half-spaces), or each body's own operator
// (kernels/two_body_history.hpp).
enum class AntiplanePairOperator { combined, bodies };
inline constexpr std::string_view kAntiplanePairOperatorNames[] = {"combined", "bodies"};  // index = enumerator

struct TimeConfig {
  HistoryAlgorithm history = HistoryAlgorithm::automatic;  // [time] history
  HalfSpacePairOperator half_space_pair = HalfSpacePairOperator::combined;  // [time] half_space_pair
  AntiplanePairOperator antiplane_pair = AntiplanePairOperator::combined;   // [time] antiplane_pair
  double beta = 0.25;       // [time] beta: dt <= beta dx / c_s (see docs: dt is adjusted so 2H/c_s is a whole number of steps)
  double duration = 1e-3;   // [time] duration [s] (or duration_transit in units of L/c_s, resolved here)
};

struct OutputConfig {
  double timeseries_interval = 0.0;  // [output] timeseries_interval [s]; 0 = every step
  double snapshot_interval = 0.0;    // [output] snapshot_interval [s]; 0 = no time snapshots
  double snapshot_slip_increment = 0.0;  // [output] snapshot_slip_increment [m] (mean slip); 0 = off
  double delta_th = 1e-8;            // [output] delta_th [m], slip-sampling threshold; 0 = off
  double flush_interval = 5.0;       // [output] flush_interval [s of wall time]
  // [output] checkpoint_interval [s of wall time] between restart points
  // (RUN.h5.restart, docs/output.md); 0 = only when SIGTERM/SIGINT stops the run.
  double checkpoint_interval = 600.0;
  // [output] kernel_cache: directory where the strip kernels (normal-mode
  // phases and weights per Fourier mode) are cached, one HDF5 file per set of
  // inputs they depend on, so a scan computes them once; "" = no cache.
  std::string kernel_cache;
  // [output] stations: positions x [m] (0 <= x < L) of on-fault stations whose
  // slip, slip_rate, shear_stress, state and normal_stress are recorded
  // (linear interpolation between the two neighbouring nodes; exact on a
  // node) every station_interval [s] (0 = every step) in /stations, with the
  // global max slip rate and moment rate.  Empty = no stations.
  std::vector<double> stations;
  // [output] stations_z: on a 2D interface (geometry.nodes_z > 1), the z
  // positions [m] (0 <= z < W) of the stations, paired with `stations` by
  // index (bilinear interpolation in x and z; exact on a node).  Empty on a
  // one-dimensional interface.
  std::vector<double> stations_z;
  double station_interval = 0.0;
  // [output] front_slip_rate [m/s]: per node, the first time the slip rate
  // exceeds it is stored in /rupture_front (0 = off).
  double front_slip_rate = 0.0;
};

// The two bodies (docs/bodies.md).  [material] and geometry.height are the
// top body; the bottom body is its mirror image (the default: two identical
// bodies, today's problem), another elastic body, or a rigid base.
enum class BodyKind { mirror, elastic, rigid };
inline constexpr std::string_view kBodyKindNames[] = {"mirror", "elastic", "rigid"};  // index = enumerator
// Outer face of a body (OuterFace, kernels/face_response.hpp): driven (tangential
// displacement moving with the face's share of v0, normal stress prescribed) or
// clamped (both displacements prescribed).  Antiplane: both prescribe u_z.

struct TopBodyConfig {
  OuterFace outer_face = OuterFace::driven;  // [top] outer_face
  // [top] velocity_share: the top outer face moves at +share v0, the bottom
  // one at -(1 - share) v0.  Only v0 loads the interface (docs/bodies.md).
  double velocity_share = 0.5;
};

struct BottomBodyConfig {
  BodyKind body = BodyKind::mirror;  // [bottom] body
  // [bottom] shear_modulus, poisson_ratio, density, height: used when body =
  // "elastic"; with "mirror" they must equal the top body's.
  double shear_modulus = 9e9;
  double poisson_ratio = 0.33;
  double density = 1200.0;
  double height = 0.1;
  OuterFace outer_face = OuterFace::driven;  // [bottom] outer_face
};

struct SimulationConfig {
  GeometryConfig geometry;
  ElasticMaterial material;  // [material] shear_modulus, poisson_ratio, density, plane
  TopBodyConfig top;
  BottomBodyConfig bottom;
  LoadingConfig loading;
  FrictionParameters friction;  // [friction] law, f0, a, b, characteristic_slip, v_star, phi_star; [state] law
  // [friction] f0, a, b, characteristic_slip given as profiles along x or z
  // (the matching field of `friction` is then NaN; friction/parameter_profile.hpp).
  FrictionProfiles friction_profiles;
  InterfaceConfig interface;
  InitialConfig initial;
  TimeConfig time;
  OutputConfig output;
};

// The nodes friction profiles are sampled at: geometry.nodes along x and
// geometry.nodes_z along z (1: a one-dimensional interface).
inline FrictionNodeGrid friction_node_grid(const SimulationConfig& c) {
  const auto& g = c.geometry;
  return FrictionNodeGrid{static_cast<std::size_t>(g.nodes), g.length / g.nodes,
                          static_cast<std::size_t>(g.nodes_z), g.width / g.nodes_z};
}

// The bottom body as the kernels see it: the top body's material and height
// for "mirror", its own for "elastic" (rigid: not an elastic body; these give
// its stored values).  The plane condition is always [material]'s.
inline ElasticMaterial bottom_material(const SimulationConfig& c) {
  if (c.bottom.body == BodyKind::mirror) return c.material;
  ElasticMaterial m = c.material;
  m.shear_modulus = c.bottom.shear_modulus;
  m.poisson_ratio = c.bottom.poisson_ratio;
  m.density = c.bottom.density;
  return m;
}
inline double bottom_height(const SimulationConfig& c) {
  return c.bottom.body == BodyKind::mirror ? c.geometry.height : c.bottom.height;
}

}  // namespace slipstrip
