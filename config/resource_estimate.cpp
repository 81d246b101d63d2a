#include "config/resource_estimate.hpp"

#include <algorithm>

#include "io/messages.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "config/config.hpp"
#include "config/config_schema.hpp"
#include "kernels/block_strip_history.hpp"
#include "kernels/face_block_history.hpp"
#include "kernels/half_space_pair_kernel.hpp"
#include "kernels/strip_response.hpp"

namespace slipstrip {
namespace {

constexpr double kGiB = 1024.0 * 1024.0 * 1024.0;

// The strip algorithms switch at this many normal modes per Fourier mode
// (solver/simulation.hpp, kBlockHistoryThreshold).
constexpr double kBlockThreshold = 128.0;

// Bytes per strip normal mode: modal keeps 7 doubles (kernels/history_convolution.hpp),
// block ~64 P + 48 B with B < 2P (kernels/block_strip_history.hpp); both also
// hold the kernels (phase + weight, 16 bytes) while they are built.
constexpr double kModalBytesPerMode = 56.0 + 16.0;
constexpr double kBlockBytesPerMode = 64.0 + 48.0 * 2.0 + 16.0;
// Half-space: ~300 exponentials per Fourier mode, 8 doubles each, plus a
// direct window of sampled weights (kernels/half_space_history.hpp).
constexpr double kHalfSpaceBytesPerFourierMode = 300.0 * 64.0 + 512.0 * 24.0;
// One body of an in-plane pair of different bodies (kernels/inplane_pair_history.hpp):
// a finite body's 2x2 modal operator keeps per mode four complex states, its
// rotation and a 2x2 complex weight (kernels/face_history.hpp); a half-space
// body ~300 exponentials per Fourier mode with four complex states, the pole
// and three complex weights each, plus its sampled window (two inputs and
// three weights per lag; kernels/face_half_space.hpp).
constexpr double kFaceModalBytesPerMode = 4.0 * 16.0 + 16.0 + 64.0;
// A finite body's 2x2 operator by the block algorithm (kernels/face_block_history.hpp),
// per Fourier mode: two frequencies (+phi, -phi) per normal mode with three half
// weights and the half-block phase (12 doubles per mode) and two complex states
// per mode (64 bytes per mode), three kernel spectra over the FFT levels and the
// block's inputs and outputs of both components (7 complex values per step of
// the block B), the direct lags (3 x 32 doubles) and the current direct block's
// inputs and outputs (2 x 32 complex and 4 x 32 doubles).
constexpr double kFaceBlockBytesPerMode = 12.0 * 8.0 + 4.0 * 16.0;
constexpr double kFaceBlockBytesPerBlockStep = 7.0 * 16.0;
constexpr double kFaceBlockBytesPerFourierMode = 3.0 * 32.0 * 8.0 + 2.0 * 32.0 * 16.0 + 4.0 * 32.0 * 8.0;
constexpr double kFaceHalfSpaceBytesPerFourierMode = 300.0 * 128.0 + 512.0 * 56.0;
// The combined operator of two different half-spaces (kernels/face_half_space.hpp,
// docs/inplane_bodies.md §7), per Fourier mode: ~700 exponentials (four cuts,
// their refined panels, the leaky poles), each with its pole and three complex
// weights (64 bytes) and either a fast one's eight state doubles (128) or a
// slow one's decay, centre factor, block pole, four complex states and weights
// (144; about two thirds are slow), ~200 bytes on average; and the slow
// blocks' tables for two groups of branches (rotations 8 KiB, in-block lags,
// inputs and polynomials 10 KiB).  Its sampled window is short (W h >= 1: ~10
// lags per mode on average at N = 2048).  Built: 142, 156 and 160 KB per mode
// at N = 16, 256 and 2048 (the bench's pair).
constexpr double kHalfSpacePairBytesPerFourierMode = 700.0 * 200.0 + 18432.0;
// The combined operator of two different antiplane half-spaces
// (HalfSpaceHistory's pair constructor): the scalar operator's layout with two
// cuts' exponentials (~230 per mode, their panels refined from 2 nodes,
// against the identical pair's ~170) and the faster body's window.  Built:
// 25.9 KB per mode at N = 2048 (the bench's pair, c_b = 2 c_t; the identical
// pair's 22.1 KB).
constexpr double kAntiplaneHalfSpacePairBytesPerFourierMode = 230.0 * 64.0 + 512.0 * 24.0;

// Wall time per step on one core: a fixed part (bookkeeping, a time-series
// row), the FFT pair and friction solve per node, and the history operator
// per Fourier mode.  Fitted to `slipstrip bench` on a quiet core
// (docs/performance.md, N = 2048: floor 79 us, whole step 196/243/269 us for
// block strips with H = 0.1/1/4 m, 324 us for the half-space) and to small
// modal runs; good to a factor of ~2, enough to show a unit mistake (which is
// a factor of 10 or more).  The progress bar's ETA measures the real rate.
constexpr double kStepFixedSeconds = 1e-5;
constexpr double kStepSecondsPerNode = 4e-8;
constexpr double kModalSecondsPerMode = 1.6e-9;     // per normal mode per Fourier mode
constexpr double kBlockSecondsPerFourierMode = 1.4e-7;
constexpr double kHalfSpaceSecondsPerFourierMode = 2.4e-7;
// A finite body of a dissimilar in-plane pair rotates two states per mode (one
// per input component); a half-space body rotates every exponential's four
// states every step (no slow blocks; docs/bodies.md §4).
constexpr double kFaceModalSecondsPerMode = 2.0 * kModalSecondsPerMode;
constexpr double kFaceHalfSpaceSecondsPerFourierMode = 300.0 * 4.0 * 1e-9;
// The combined half-space pair's operator: fitted to the bench (N = 2048, one
// thread: ~630 us per step against the identical pair's ~330 us).
constexpr double kHalfSpacePairSecondsPerFourierMode = 5.3e-7;
// The combined antiplane half-space pair: fitted to the bench (N = 2048, one
// thread: its history part ~1.45x the identical antiplane pair's).
constexpr double kAntiplaneHalfSpacePairSecondsPerFourierMode = 1.45 * kHalfSpaceSecondsPerFourierMode;

// One body's history operator at the run's time step.
struct BodyOperator {
  double echo_steps = 0.0, modes_per_fourier_mode = 0.0, bytes = 0.0, seconds = 0.0;
  bool block = false;
};

// `pair_operator`: the operator of docs/theory.md (modal/block strip or the
// half-space), as the mirror pair and each antiplane body use it; otherwise an
// in-plane body's 2x2 operator.  `body_of_two`: an antiplane body of two
// different ones on a line, whose block operator takes body_block_length's B
// (Simulation's make_pair_history; a 2D pair's is interface_strip_bytes).
BodyOperator body_operator(const ElasticMaterial& m, double height, double dt, double fourier_modes,
                           HistoryAlgorithm history, bool pair_operator, bool allow_block,
                           bool body_of_two = false) {
  BodyOperator b;
  if (is_half_space(height)) {
    b.bytes = fourier_modes * (pair_operator ? kHalfSpaceBytesPerFourierMode : kFaceHalfSpaceBytesPerFourierMode);
    b.seconds =
        fourier_modes * (pair_operator ? kHalfSpaceSecondsPerFourierMode : kFaceHalfSpaceSecondsPerFourierMode);
    return b;
  }
  const double cs = m.shear_wave_speed(), cd = m.dilatational_wave_speed();
  b.echo_steps = std::ceil(2.0 * height / cs / dt * (1.0 - 1e-12));
  b.modes_per_fourier_mode = 0.5 * b.echo_steps * (1.0 + cs / cd);
  if (!pair_operator) {
    // The block algorithm as Simulation chooses it for a finite body (auto: from
    // kBlockThreshold normal modes), with Simulation's B (face_block_length: the
    // power of two >= max(P, 64), doubled while its block arrays stay within
    // kBlockDoublingBytes).
    b.block = history == HistoryAlgorithm::block ||
              (history == HistoryAlgorithm::automatic && b.modes_per_fourier_mode >= kBlockThreshold);
    if (b.block) {
      const double block = face_block_length(static_cast<std::size_t>(std::ceil(b.modes_per_fourier_mode)),
                                             FaceBlockDesign{}.direct_block, static_cast<std::size_t>(fourier_modes));
      b.bytes = fourier_modes * (b.modes_per_fourier_mode * kFaceBlockBytesPerMode +
                                 block * kFaceBlockBytesPerBlockStep + kFaceBlockBytesPerFourierMode);
      // Two input components through the same steps as a strip's block operator.
      b.seconds = 2.0 * fourier_modes * kBlockSecondsPerFourierMode;
      return b;
    }
    b.bytes = fourier_modes * b.modes_per_fourier_mode * kFaceModalBytesPerMode;
    b.seconds = fourier_modes * b.modes_per_fourier_mode * kFaceModalSecondsPerMode;
    return b;
  }
  b.block = allow_block && (history == HistoryAlgorithm::block ||
                            (history == HistoryAlgorithm::automatic && b.modes_per_fourier_mode >= kBlockThreshold));
  b.bytes = fourier_modes * b.modes_per_fourier_mode * (b.block ? kBlockBytesPerMode : kModalBytesPerMode) +
            8.0 * b.echo_steps;
  if (b.block && body_of_two) {
    // 64 P + 48 B + the kernels (16 P), at body_block_length's B instead of B < 2P.
    const double block = body_block_length(static_cast<std::size_t>(std::ceil(b.modes_per_fourier_mode)),
                                           BlockHistoryDesign{}.direct_block, static_cast<std::size_t>(fourier_modes));
    b.bytes = fourier_modes * (80.0 * b.modes_per_fourier_mode + 48.0 * block) + 8.0 * b.echo_steps;
  }
  b.seconds = b.block ? fourier_modes * kBlockSecondsPerFourierMode
                      : fourier_modes * b.modes_per_fourier_mode * kModalSecondsPerMode;
  return b;
}

// A strip operator of a 2D interface (kernels/interface_2d_history.hpp) as
// make_strip_history builds it over `operator_modes` modes of `modes` normal
// modes each: the algorithm by time.history (auto: block from kBlockThreshold
// normal modes).
bool interface_strip_takes_block(HistoryAlgorithm history, double modes) {
  return history == HistoryAlgorithm::block || (history == HistoryAlgorithm::automatic && modes >= kBlockThreshold);
}

// Its bytes.  Modal: 56 per normal mode (kernels/history_convolution.hpp).
// Block (kernels/block_strip_history.hpp): per mode its states (32 P) and
// block inputs and outputs (32 B), B = automatic_block_length (the power of
// two >= max(P, 64)), and its current direct block (inputs, the rows' part of
// the outputs and the lag kernel: 40 D, kernels/step_major_direct_block.hpp);
// the design part (frequencies and weights 32 P, kernel spectra 16 B) is
// shared by the modes of equal |k|, at most half of them distinct (kz and -kz
// share one).  The kernels are not included.
double interface_strip_bytes(HistoryAlgorithm history, double operator_modes, double modes) {
  if (!interface_strip_takes_block(history, modes)) return operator_modes * modes * 56.0;
  const int direct_block = BlockHistoryDesign{}.direct_block;
  const double block = automatic_block_length(static_cast<std::size_t>(std::ceil(modes)), direct_block);
  return operator_modes * (32.0 * modes + 32.0 * block + 40.0 * direct_block) +
         0.5 * operator_modes * (32.0 * modes + 16.0 * block);
}

std::string bytes_text(double bytes) {
  constexpr const char* kUnits[] = {"B", "KiB", "MiB", "GiB", "TiB"};
  int unit = 0;
  while (bytes >= 1024.0 && unit < 4) {
    bytes /= 1024.0;
    ++unit;
  }
  return format_short(bytes) + " " + kUnits[unit];
}

std::string duration_text(double seconds) {
  if (!(seconds < 1e12)) return format_short(seconds) + " s";
  if (seconds < 120.0) return format_short(seconds) + " s";
  if (seconds < 7200.0) return format_short(seconds / 60.0) + " min";
  if (seconds < 2.0 * 86400.0) return format_short(seconds / 3600.0) + " h";
  return format_short(seconds / 86400.0) + " days";
}

}  // namespace

ResourceEstimate estimate_resources(const SimulationConfig& c) {
  ResourceEstimate e;
  // A 2D interface (nodes_z > 1, docs/3d.md): nodes_z rows of Fourier modes,
  // each with an in-plane and an antiplane operator (modal or half-space),
  // the time step set by the smaller spacing, seven fields per snapshot node
  // (nine for two different bodies).
  const bool interface_2d = c.geometry.nodes_z > 1;
  const double rows_z = interface_2d ? c.geometry.nodes_z : 1.0;
  const double n = c.geometry.nodes * rows_z;
  const double dx = std::min(c.geometry.length / c.geometry.nodes,
                             interface_2d ? c.geometry.width / c.geometry.nodes_z : c.geometry.length);
  const double cs = c.material.shear_wave_speed();
  const double fourier_modes = (std::floor(c.geometry.nodes / 2.0) + 1.0) * rows_z * (interface_2d ? 2.0 : 1.0);
  const double dt_max = c.time.beta * dx / cs;
  if (is_half_space(c.geometry.height)) {
    e.time_step = dt_max;
  } else {
    // As strip_time_step, without its rounding to a whole number of steps
    // (which needs M to fit an integer, the very thing checked here).
    const double echo = std::ceil(2.0 * c.geometry.height / cs / dt_max * (1.0 - 1e-12));
    e.time_step = echo >= 1.0 ? 2.0 * c.geometry.height / cs / echo : dt_max;
  }
  // Two bodies (docs/bodies.md): the step follows the faster one; in-plane
  // each body has its own 2x2 operator, antiplane each a pair operator.
  const bool elastic_bottom = !interface_2d && c.bottom.body == BodyKind::elastic;
  const bool per_body = !interface_2d && c.bottom.body != BodyKind::mirror && !c.material.antiplane();
  const ElasticMaterial bottom = bottom_material(c);
  if (elastic_bottom && bottom.shear_wave_speed() > cs) e.time_step = c.time.beta * dx / bottom.shear_wave_speed();
  const bool antiplane_bodies = !interface_2d && c.bottom.body != BodyKind::mirror && c.material.antiplane();
  const BodyOperator top = body_operator(c.material, c.geometry.height, e.time_step, fourier_modes, c.time.history,
                                         !per_body, !interface_2d, antiplane_bodies);
  e.echo_steps = top.echo_steps;
  e.modes_per_fourier_mode = top.modes_per_fourier_mode;
  e.block_history = top.block;
  e.operator_bytes = top.bytes;
  double history_seconds = top.seconds;
  if (interface_2d && !is_half_space(c.geometry.height)) {
    // Two operators over the operator modes F/2 each (fourier_modes counts
    // both): in-plane P ~ (M/2)(1 + c_s/c_d), antiplane (M/2) normal modes,
    // each algorithm chosen on its own P (interface_strip_bytes).  The
    // kernels (16 bytes per normal mode) live while one operator is built.
    const double operator_modes = fourier_modes / 2.0;
    e.block_history = interface_strip_takes_block(c.time.history, e.modes_per_fourier_mode);
    e.operator_bytes = interface_strip_bytes(c.time.history, operator_modes, e.modes_per_fourier_mode) +
                       interface_strip_bytes(c.time.history, operator_modes, 0.5 * e.echo_steps) +
                       operator_modes * 16.0 * e.modes_per_fourier_mode + 8.0 * e.echo_steps;
    if (e.block_history) history_seconds = fourier_modes * kBlockSecondsPerFourierMode;
  }
  if (interface_2d && c.bottom.body != BodyKind::mirror) {
    // Two different bodies on a 2D interface (kernels/interface_2d_history.hpp,
    // build_pair): per body an in-plane 2x2 operator (a finite body's modal
    // FaceModalHistory, a half-space's FaceHalfSpaceHistory) and an antiplane
    // pair operator (strip or HalfSpaceHistory), each over the F/2 operator
    // modes; a rigid base has none.  The step follows the faster body.
    const double operator_modes = fourier_modes / 2.0;
    const bool elastic = c.bottom.body == BodyKind::elastic;
    if (elastic && bottom.shear_wave_speed() > cs) e.time_step = c.time.beta * dx / bottom.shear_wave_speed();
    e.operator_bytes = 0.0;
    history_seconds = 0.0;
    double kernel_bytes = 0.0;  // the antiplane strip kernels, alive while one operator is built
    const auto add_body = [&](const ElasticMaterial& m, double height, bool is_top) {
      const BodyOperator face = body_operator(m, height, e.time_step, operator_modes, c.time.history, false, false);
      // The 2D pair builds the finite body's modal 2x2 operator (no block one).
      const double face_bytes = is_half_space(height)
                                    ? face.bytes
                                    : operator_modes * face.modes_per_fourier_mode * kFaceModalBytesPerMode;
      const double face_seconds = is_half_space(height)
                                      ? face.seconds
                                      : operator_modes * face.modes_per_fourier_mode * kFaceModalSecondsPerMode;
      // Antiplane: a half-space's HalfSpaceHistory; a finite body's strip
      // operator over its M/2 SH normal modes per mode, as make_strip_history
      // builds it for the 2D pair (the identical bodies' B, not a 1D body's
      // body_block_length; designs shared by equal |k|).
      double sh_bytes = 0.0, sh_seconds = 0.0;
      bool sh_block = false;
      if (is_half_space(height)) {
        const BodyOperator sh = body_operator(m, height, e.time_step, operator_modes, c.time.history, true, true);
        sh_bytes = sh.bytes;
        sh_seconds = sh.seconds;
      } else {
        const double sh_modes = 0.5 * face.echo_steps;
        sh_block = interface_strip_takes_block(c.time.history, sh_modes);
        sh_bytes = interface_strip_bytes(c.time.history, operator_modes, sh_modes) + 8.0 * face.echo_steps;
        sh_seconds = sh_block ? operator_modes * kBlockSecondsPerFourierMode
                              : operator_modes * sh_modes * kModalSecondsPerMode;
        kernel_bytes = std::max(kernel_bytes, operator_modes * 16.0 * sh_modes);
      }
      e.operator_bytes += face_bytes + sh_bytes;
      history_seconds += face_seconds + sh_seconds;
      if (is_top) {
        e.echo_steps = face.echo_steps;
        e.modes_per_fourier_mode = face.modes_per_fourier_mode;
        e.block_history = sh_block;
      } else {
        e.bottom_echo_steps = face.echo_steps;
        e.bottom_modes_per_fourier_mode = face.modes_per_fourier_mode;
      }
    };
    add_body(c.material, c.geometry.height, true);
    if (elastic) add_body(bottom, c.bottom.height, false);
    e.operator_bytes += kernel_bytes;
  }
  // Two different in-plane half-spaces on a line: one combined operator
  // (Simulation, time.half_space_pair = "combined"), unless the pair has a
  // Stoneley wave (then the bodies' operators, counted below).  The rarer
  // fallbacks (a failed set-up check, no passive correction) also take the
  // bodies' operators, which cost ~0.8x the combined one.
  bool combined_pair = per_body && elastic_bottom && is_half_space(c.geometry.height) &&
                       is_half_space(c.bottom.height) && c.time.half_space_pair == HalfSpacePairOperator::combined;
  if (combined_pair) {
    try {
      combined_pair = half_space_pair_stoneley_speed(half_space_pair_shape(c.material, bottom)) == 0.0;
    } catch (const std::invalid_argument&) {
      combined_pair = false;  // bodies the pair's shape refuses: the run refuses them with its own reason
    }
  }
  // Two different finite antiplane strips on a line: one combined operator
  // (Simulation, time.antiplane_pair = "combined"; kernels/antiplane_pair_modes.hpp)
  // over the bilayer's normal modes, (M_t + M_b)/2 per Fourier mode (the poles
  // of both bodies below Nyquist, one mode between each two), with the block
  // algorithm at body_block_length's B as a body of two: 64 P + 48 B + the
  // kernels (16 P); the uniform mode keeps M_t + M_b slots of v and of y.
  const bool combined_antiplane = antiplane_bodies && elastic_bottom && !is_half_space(c.geometry.height) &&
                                  !is_half_space(c.bottom.height) &&
                                  c.time.antiplane_pair == AntiplanePairOperator::combined;
  // Two different antiplane half-spaces on a line: one scalar operator of the
  // combined kernel (Simulation, time.antiplane_pair = "combined"); equal shear
  // speeds make it the identical pair's.  Its rare fallback (a failed set-up
  // check, no passive correction) takes the bodies' operators.
  const bool combined_antiplane_half_spaces = antiplane_bodies && elastic_bottom && is_half_space(c.geometry.height) &&
                                  is_half_space(c.bottom.height) &&
                                  c.time.antiplane_pair == AntiplanePairOperator::combined;
  if (combined_pair) {
    e.operator_bytes = fourier_modes * kHalfSpacePairBytesPerFourierMode;
    history_seconds = fourier_modes * kHalfSpacePairSecondsPerFourierMode;
  } else if (combined_antiplane) {
    const double bottom_echo = std::ceil(2.0 * c.bottom.height / bottom.shear_wave_speed() / e.time_step * (1.0 - 1e-12));
    const double modes = 0.5 * (top.echo_steps + bottom_echo);
    e.bottom_echo_steps = bottom_echo;
    e.bottom_modes_per_fourier_mode = 0.5 * bottom_echo;  // its own echo modes; the operator carries the pair's
    e.modes_per_fourier_mode = modes;
    e.block_history = c.time.history == HistoryAlgorithm::block ||
                      (c.time.history == HistoryAlgorithm::automatic && modes >= kBlockThreshold);
    const double slots = 32.0 * (top.echo_steps + bottom_echo);
    if (e.block_history) {
      const double block = body_block_length(static_cast<std::size_t>(std::ceil(modes)),
                                             BlockHistoryDesign{}.direct_block, static_cast<std::size_t>(fourier_modes));
      e.operator_bytes = fourier_modes * (80.0 * modes + 48.0 * block) + slots;
      history_seconds = fourier_modes * kBlockSecondsPerFourierMode;
    } else {
      e.operator_bytes = fourier_modes * modes * kModalBytesPerMode + slots;
      history_seconds = fourier_modes * modes * kModalSecondsPerMode;
    }
  } else if (combined_antiplane_half_spaces) {
    const bool one_speed = bottom.shear_wave_speed() == cs;
    e.operator_bytes =
        fourier_modes * (one_speed ? kHalfSpaceBytesPerFourierMode : kAntiplaneHalfSpacePairBytesPerFourierMode);
    history_seconds =
        fourier_modes * (one_speed ? kHalfSpaceSecondsPerFourierMode : kAntiplaneHalfSpacePairSecondsPerFourierMode);
  } else if (elastic_bottom) {
    const BodyOperator b =
        body_operator(bottom, c.bottom.height, e.time_step, fourier_modes, c.time.history, !per_body, true,
                      antiplane_bodies);
    e.bottom_echo_steps = b.echo_steps;
    e.bottom_modes_per_fourier_mode = b.modes_per_fourier_mode;
    e.operator_bytes += b.bytes;
    history_seconds += b.seconds;
  }
  e.steps = c.time.duration / e.time_step;
  e.step_seconds = kStepFixedSeconds + kStepSecondsPerNode * n + history_seconds;
  e.wall_seconds = e.steps * e.step_seconds;

  // Output: uncompressed sizes (snapshots are compressed in the file, so this
  // is an upper bound for them; slip sampling is not compressed).
  const auto& o = c.output;
  const double rows = o.timeseries_interval > 0.0
                          ? std::min(e.steps, c.time.duration / o.timeseries_interval)
                          : e.steps;
  double snapshots = 0.0;
  if (o.snapshot_interval > 0.0) snapshots += std::min(e.steps, c.time.duration / o.snapshot_interval);
  // At most one snapshot per step (solver/run.cpp); mean slip ~ v0 t.
  if (o.snapshot_slip_increment > 0.0)
    snapshots += std::min(e.steps, c.loading.driving_velocity * c.time.duration / o.snapshot_slip_increment);
  // Slip sampling: one row of N crossing times per delta_th of slip; the
  // mean slip v0 t gives the number of rows a uniformly sliding run fills.
  const double levels =
      o.delta_th > 0.0 ? c.loading.driving_velocity * c.time.duration / o.delta_th : 0.0;
  // Snapshot fields per node (solver/run.cpp, solver/run_output.cpp): a 2D
  // interface 7, a line 4; with a variable normal stress (two different
  // in-plane bodies) also normal_stress and opening.
  const bool variable_normal_stress = c.bottom.body != BodyKind::mirror && (interface_2d || !c.material.antiplane());
  const double fields = (interface_2d ? 7.0 : 4.0) + (variable_normal_stress ? 2.0 : 0.0);
  // The slip sampling holds one crossing time per node and level on a 2D
  // interface as on a line: at 160 000 nodes and delta_th = 1e-8 m it is the
  // largest dataset by far (0.15 TB over 1.2 mm of mean slip).
  e.output_bytes = interface_2d ? 24.0 * rows + (16.0 + 8.0 * fields * n) * snapshots + 8.0 * n * levels
                                 : 32.0 * rows + (8.0 + 8.0 * fields * n) * snapshots + 8.0 * n * levels;
  return e;
}

void check_resources(const SimulationConfig& c, const ResourceLimits& limits) {
  const ResourceEstimate e = estimate_resources(c);
  // Steps first: an overflowing count makes every other estimate meaningless.
  if (!(e.steps <= limits.max_steps))
    throw ConfigError("time.duration = " + format_short(c.time.duration) + " s needs " + format_short(e.steps) +
                      " time steps of dt = " + format_short(e.time_step) +
                      " s (set by geometry.length/geometry.nodes, geometry.height, time.beta and "
                      "the wave speed sqrt(material.shear_modulus/material.density)): allowed at "
                      "most " + format_short(limits.max_steps) + " steps (--max-steps raises the limit)");
  if (e.steps < 0.5)
    throw ConfigError("time.duration = " + format_short(c.time.duration) +
                      " s is shorter than half a time step (dt = " + format_short(e.time_step) +
                      " s): the run would take 0 steps; expected a duration >= dt");
  // An index of strip normal modes must fit an int (kernels/strip_response.cpp).
  const auto refuse_too_many_modes = [&](const char* key, const char* body, double height, double modes) {
    if (modes > 1e9)
      throw ConfigError(std::string(key) + " = " + format_short(height) + " m is " +
                        format_short(height / (c.geometry.length / c.geometry.nodes)) + " grid spacings: " +
                        body + " would carry " + format_short(modes) +
                        " normal modes per Fourier mode (time.beta = " + format_short(c.time.beta) +
                        "); allowed at most 1e9 (use " + key + " = \"inf\" for a half-space)");
  };
  refuse_too_many_modes("geometry.height", "the strip", c.geometry.height, e.modes_per_fourier_mode);
  refuse_too_many_modes("bottom.height", "the bottom body", c.bottom.height, e.bottom_modes_per_fourier_mode);
  const double gib = e.operator_bytes / kGiB;
  if (!(gib <= limits.max_operator_gib)) {
    std::string drivers = is_half_space(c.geometry.height)
                              ? "geometry.nodes = " + std::to_string(c.geometry.nodes)
                              : "geometry.nodes = " + std::to_string(c.geometry.nodes) +
                                    ", geometry.height = " + format_short(c.geometry.height) +
                                    " m, time.beta = " + format_short(c.time.beta) + " (" +
                                    format_short(e.modes_per_fourier_mode) +
                                    " strip normal modes per Fourier mode, " +
                                    (e.block_history ? "block" : "modal") + " history)";
    if (e.bottom_modes_per_fourier_mode > 0.0)
      drivers += ", bottom.height = " + format_short(c.bottom.height) + " m (" +
                 format_short(e.bottom_modes_per_fourier_mode) + " normal modes per Fourier mode)";
    throw ConfigError("history operator needs ~" + format_short(gib) + " GiB for " + drivers +
                      ": allowed at most " + format_short(limits.max_operator_gib) +
                      " GiB (--max-memory-gib raises the limit)");
  }
  const double out_gib = e.output_bytes / kGiB;
  if (!(out_gib <= limits.max_output_gib))
    throw ConfigError("output file would hold ~" + format_short(out_gib) + " GiB (time.duration = " +
                      format_short(c.time.duration) + " s, output.delta_th = " + format_short(c.output.delta_th) +
                      " m, output.timeseries_interval = " + format_short(c.output.timeseries_interval) +
                      " s, output.snapshot_interval = " + format_short(c.output.snapshot_interval) +
                      " s, output.snapshot_slip_increment = " +
                      format_short(c.output.snapshot_slip_increment) + " m, geometry.nodes = " +
                      std::to_string(c.geometry.nodes) + "): allowed at most " +
                      format_short(limits.max_output_gib) + " GiB (--max-output-gib raises the limit)");
}

std::string run_header(const SimulationConfig& c) {
  const ResourceEstimate e = estimate_resources(c);
  const double transit = c.geometry.length / c.material.shear_wave_speed();
  std::string out = "run: " + format_short(e.steps) + " steps of dt = " + format_short(e.time_step) + " s over " +
                    format_short(c.time.duration) + " s (" + format_short(c.time.duration / transit) +
                    " L/c_s); wall time ~" + duration_text(e.wall_seconds) +
                    " on one core (rough estimate) plus the set-up\n";
  const double dx = c.geometry.length / c.geometry.nodes;
  if (is_half_space(c.geometry.height)) {
    out += std::string("  H = inf (") + (c.bottom.body == BodyKind::mirror ? "two half-spaces" : "half-space") +
           "), L = " + format_short(c.geometry.length) + " m, N = " +
           std::to_string(c.geometry.nodes) + " (dx = " + format_short(dx) + " m); history operator ~" +
           bytes_text(e.operator_bytes) + "\n";
  } else {
    out += "  H = " + format_short(c.geometry.height) + " m, H/L = " + format_short(c.geometry.height / c.geometry.length) +
           ", N = " + std::to_string(c.geometry.nodes) + " (dx = " + format_short(dx) + " m); history operator ~" +
           bytes_text(e.operator_bytes) + " (" + (e.block_history ? "block" : "modal") + ", " +
           format_short(e.modes_per_fourier_mode) + " strip modes per Fourier mode)\n";
  }
  if (c.bottom.body == BodyKind::rigid) {
    out += "  bottom: rigid base\n";
  } else if (c.bottom.body == BodyKind::elastic) {
    out += "  bottom: H_b = " + (is_half_space(c.bottom.height) ? std::string("inf (half-space)")
                                                                  : format_short(c.bottom.height) + " m (" +
                                                                        format_short(e.bottom_modes_per_fourier_mode) +
                                                                        " normal modes per Fourier mode)") +
           ", included in the history operator's memory\n";
  }
  const double slip_per_step = c.loading.driving_velocity * e.time_step;
  out += "  output up to ~" + bytes_text(e.output_bytes) + " (uncompressed estimate); slip per step at v0: " +
         format_short(slip_per_step) + " m" +
         (c.output.delta_th > 0.0 ? " = " + format_short(slip_per_step / c.output.delta_th) + " delta_th\n"
                                  : std::string(" (no slip sampling: output.delta_th = 0)\n"));
  for (const std::string& warning : plausibility_warnings(c)) out += "warning: " + io::one_line(warning) + "\n";
  return out;
}

}  // namespace slipstrip
