#pragma once
// History part of the traction on a two-dimensional interface, periodic in x
// and z, between two identical bodies of height H (or half-spaces), for slip
// in any direction of the interface plane (docs/3d.md).
//
// An isotropic body's response to one Fourier mode exp(i (kx x + kz z)) of the
// slip splits along k-hat = (kx, kz)/|k|: slip along k-hat excites the
// in-plane (P-SV, plane strain) problem of the plane (k-hat, y), slip across
// it (along y x k-hat) the antiplane (SH) problem, and the two do not couple.
// Both are the 2D operators at the wavenumber |k|:
//   tau_along^  = -S_inplane(|k|, s) delta_along^,
//   tau_across^ = -S_antiplane(|k|, s) delta_across^,
// so per mode the traction history is the in-plane history of the slip rate's
// component along k-hat plus the antiplane history of its component across,
// rotated back into x and z.  Both operators have the same radiation damping
// mu / (2 c_s), so the instantaneous part stays scalar and the local friction
// solve stays collinear.  The uniform mode (k = 0) is the 1-D shear-wave
// problem in both directions; it is taken with k-hat = x, so a field
// independent of z sees exactly the in-plane operator along x.
//
// Mode layout: RealFft2d's [qz][qx] (kernels/fft.hpp) on one process; a
// process of a run split over several (FFTW's MPI transform with transposed
// output) holds whole columns qx of modes stored as [qx][qz]
// (InterfaceModeSet).
//
// Nyquist modes.  On an even grid the Nyquist wavenumber pi/dz stands for both
// +pi/dz and -pi/dz (likewise pi/dx), and the coupling term c s (S_P - S_SH)
// changes sign between them.  A real field's mode there is its own z-mirror
// image, so the only operator that keeps both the Hermitian symmetry (a real
// traction) and the z -> -z mirror symmetry is the average over the two signs,
// which has no coupling term.  The z-Nyquist row is therefore carried twice
// (kz = +pi/dz and -pi/dz, sharing one design) and averaged, and the x-Nyquist
// column is projected onto its Hermitian part (the average over kx = +-pi/dx).
// Resolved modes are untouched.
//
// Dissimilar bodies (build_pair): the in-plane operator is the 1D in-plane
// pair's (InplanePairHistory: each body's 2x2 face operator at |k|, finite or
// a half-space, continuous tractions, the slip component along k-hat, the
// normal stress) and the antiplane one the 1D antiplane pair's (TwoBodyHistory).  The normal stress
// of each mode is the in-plane pair's, fed with the slip along k-hat (and the
// opening stress of the contact step); the SH problem carries no normal
// stress.  It gets the same Nyquist treatment as the shear history.
#include <complex>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "kernels/elastic_material.hpp"
#include "kernels/face_response.hpp"
#include "kernels/half_space_design.hpp"
#include "kernels/history_convolution.hpp"

namespace slipstrip {

struct InterfaceGrid2d {
  double length_x = 0.0, length_z = 0.0;  // periods [m]
  int nodes_x = 0, nodes_z = 0;
  std::size_t modes() const { return static_cast<std::size_t>(nodes_x / 2 + 1) * nodes_z; }
};

// The grid modes a process holds, in the order of its spectra: slot s is the
// mode (qx[s], qz[s]), qx = 0..nodes_x/2, qz = 0..nodes_z-1 (RealFft2d's
// indices).
struct InterfaceModeSet {
  std::vector<int> qx, qz;
  std::size_t size() const { return qx.size(); }
};
// All modes in RealFft2d's [qz][qx] order.
InterfaceModeSet interface_modes_all(const InterfaceGrid2d& grid);
// The columns qx = qx_begin .. qx_begin + qx_count - 1, every qz, stored
// [qx][qz]: the modes FFTW's MPI r2c transform with FFTW_MPI_TRANSPOSED_OUT
// leaves on one process.
InterfaceModeSet interface_mode_columns(const InterfaceGrid2d& grid, int qx_begin, int qx_count);

// Wavevector of each mode of the grid (RealFft2d's layout): kx, kz [1/m] and
// |k| = hypot(kx, kz).  kx = 2 pi qx / L_x is computed exactly as for a
// one-dimensional interface, so the modes with kz = 0 get the 2D designs bit
// for bit; modes qz and nodes_z - qz have the same |k| bit for bit.
struct InterfaceWavevectors {
  std::vector<double> kx, kz, magnitude;
};
InterfaceWavevectors interface_wavevectors(const InterfaceGrid2d& grid);
// The same for the modes of a set, slot by slot (bit for bit the values of
// those modes in the whole grid's list).
InterfaceWavevectors interface_wavevectors(const InterfaceGrid2d& grid, const InterfaceModeSet& modes);

// The operators' mode list: the grid's modes, then (nodes_z even and > 1)
// the z-Nyquist row again with kz = -pi/dz.
InterfaceWavevectors interface_operator_wavevectors(const InterfaceGrid2d& grid);
// The same for a set: its modes, then its modes with qz = nodes_z/2 again
// (kz = -pi/dz), in slot order.  The 2D operators carry the uniform mode
// first (the shear echo's delay line), so a set without it (a process of a
// split run other than the first) gets an idle uniform mode in front: zero
// input, its output unused.
InterfaceWavevectors interface_operator_wavevectors(const InterfaceGrid2d& grid, const InterfaceModeSet& modes);

// Largest time.beta for which every mode's discrete operator is passive:
// the one-dimensional limit `beta_1d` (reached at the Nyquist wavenumber pi/dx
// of a grid of spacing dx) scaled by pi / (dx_min |k|_max), since the limit is a
// bound on c_s |k| dt.  dx_min = min(L_x / nodes_x, L_z / nodes_z), the spacing
// that sets the time step.
double interface_2d_beta_limit(const InterfaceGrid2d& grid, double beta_1d);

class InplanePairHistory;

// One body of a dissimilar pair (docs/bodies.md): material (its plane
// condition is replaced per operator), height (finite; +inf a half-space) and
// outer face.
struct InterfaceBody {
  ElasticMaterial material;
  double height = 0.0;
  OuterFace outer_face = OuterFace::driven;
};

class InterfaceHistory2d {
 public:
  // in-plane (plane strain) and antiplane operators built over the |k| list
  // interface_operator_wavevectors(grid).magnitude, e.g. StripHistory from
  // compute_strip_kernels(material, H, magnitudes, dt) or HalfSpaceHistory;
  // both with the same time step and radiation damping.
  InterfaceHistory2d(const InterfaceGrid2d& grid, std::unique_ptr<HistoryOperator> inplane,
                     std::unique_ptr<HistoryOperator> antiplane);
  // The same over the modes of a set only (the operators built over
  // interface_operator_wavevectors(grid, modes).magnitude): the part of a run
  // split over processes that one process holds.  A set holding part of the
  // x-Nyquist column (qx = nodes_x/2, nodes_x even) is refused: its
  // projection pairs qz with nodes_z - qz.
  InterfaceHistory2d(const InterfaceGrid2d& grid, const InterfaceModeSet& modes,
                     std::unique_ptr<HistoryOperator> inplane, std::unique_ptr<HistoryOperator> antiplane);

  // Makes a strip operator from its material (plane strain or antiplane) and
  // kernels: the modal StripHistory or the block BlockStripHistory (the same
  // discrete operator; the solver's choice, solver/simulation.hpp).
  using StripOperatorFactory =
      std::function<std::unique_ptr<HistoryOperator>(const ElasticMaterial&, const StripKernels&)>;

  // The in-plane and antiplane operators of `material` (its plane condition
  // is replaced by strain and antiplane) for strips of height H (finite:
  // strip_operator of each one's kernels, by default the modal StripHistory;
  // +inf: HalfSpaceHistory).  Throws what the operators throw (e.g. a time
  // step too large for passivity).
  static InterfaceHistory2d build(const ElasticMaterial& material, double strip_height,
                                  const InterfaceGrid2d& grid, double time_step,
                                  const CancelCheck& cancelled = {},
                                  const StripOperatorFactory& strip_operator = {});
  // The same over the modes of a set (designs shared among its own modes of
  // equal |k|), half-spaces with `half_space` (set_near_field_range of the
  // whole grid's modes gives a part the whole operator's near-field fit).
  static InterfaceHistory2d build(const ElasticMaterial& material, double strip_height,
                                  const InterfaceGrid2d& grid, const InterfaceModeSet& modes,
                                  double time_step, const CancelCheck& cancelled = {},
                                  const StripOperatorFactory& strip_operator = {},
                                  const HalfSpaceOperatorDesign& half_space = {});

  // Two different bodies (docs/3d.md, "Dissimilar bodies"): the in-plane
  // operator is InplanePairHistory over each body's 2x2 face operator at the
  // operator modes' |k| (FaceModalHistory for a finite body,
  // FaceHalfSpaceHistory for a half-space), the antiplane one TwoBodyHistory
  // over each body's pair-normalised operator (strip_operator, by default the
  // modal StripHistory; HalfSpaceHistory for a half-space).  bottom = nullopt
  // is a rigid base.  A half-space body's 2x2 operator throws
  // FaceHalfSpaceNotPassive when the step is too long for its Poisson ratio.  The time step must make every finite body's
  // shear echo a whole number of steps (two_body_time_step); a bottom height
  // is used as given.
  static InterfaceHistory2d build_pair(const InterfaceBody& top, const std::optional<InterfaceBody>& bottom,
                                       const InterfaceGrid2d& grid, double time_step,
                                       const CancelCheck& cancelled = {},
                                       const StripOperatorFactory& strip_operator = {});
  // What a part of a pair operator split over processes needs to be the
  // whole one's part: each body's half-space design (set_near_field_range over
  // the whole grid's h = c_s |k| dt of that body), and `any_process`, which
  // returns whether the flag it is given is true on any process building a
  // part (collective; called once, after the in-plane face operators, so that
  // a half-space face without a passive correction on one process's modes
  // stops every process there, before the antiplane operators' collectives).
  // Defaults: the operator's own modes' ranges; this process only.
  struct PairPart {
    HalfSpaceOperatorDesign top_half_space, bottom_half_space;
    std::function<bool(bool)> any_process;
  };
  // The same over the modes of a set (designs shared among its own modes of
  // equal |k|).  When some process's half-space face has no passive
  // correction, every process throws FaceHalfSpaceNotPassive (h = the largest
  // failed c_s |k| dt among this process's modes, 0 on a process without one).
  static InterfaceHistory2d build_pair(const InterfaceBody& top, const std::optional<InterfaceBody>& bottom,
                                       const InterfaceGrid2d& grid, const InterfaceModeSet& modes,
                                       double time_step, const CancelCheck& cancelled,
                                       const StripOperatorFactory& strip_operator, const PairPart& part);

  const InterfaceGrid2d& grid() const { return grid_; }
  double time_step() const { return inplane_->time_step(); }
  double radiation_damping() const { return inplane_->radiation_damping(); }
  std::size_t modes() const { return history_x_.size(); }
  ModeOperatorStats stats() const;
  const HistoryOperator& inplane() const { return *inplane_; }
  const HistoryOperator& antiplane() const { return *antiplane_; }

  // Feed the slip-rate perturbation spectra (x and z components) at t_n;
  // afterwards history_x(), history_z() hold the history part at t_{n+1}.
  // No allocation.
  void push(std::span<const std::complex<double>> slip_rate_x,
            std::span<const std::complex<double>> slip_rate_z);
  // Dissimilar in-plane bodies: the same with the spectrum of the opening
  // stress d at t_n [Pa] (kernels/inplane_pair_history.hpp; empty: none);
  // afterwards normal_stress() holds the compressive normal stress
  // perturbation at t_{n+1}.
  void push(std::span<const std::complex<double>> slip_rate_x, std::span<const std::complex<double>> slip_rate_z,
            std::span<const std::complex<double>> opening_stress);
  // True for dissimilar bodies (the in-plane operator is an InplanePairHistory).
  bool variable_normal_stress() const { return pair_ != nullptr; }
  std::span<const std::complex<double>> normal_stress() const { return normal_; }
  // eta_y of the in-plane pair [Pa s/m] (the gap rate is the opening stress
  // over it); 0 without variable normal stress.
  double normal_radiation_damping() const;
  std::span<const std::complex<double>> history_x() const { return history_x_; }
  std::span<const std::complex<double>> history_z() const { return history_z_; }

  // The state after the last push (the in-plane and antiplane operators'
  // states, kind "interface 2d"; allocates: restart points only) and its
  // restoration into an operator built from the same config: afterwards push()
  // continues exactly as the saved operator would.
  HistoryOperatorState save_state() const;
  void restore_state(const HistoryOperatorState& state);
  // The kind of that state.
  static constexpr const char* kStateKind = "interface 2d";

  // Regrouping the state by Fourier mode: a restart point of a run split
  // over P processes holds the whole operator's state (the one-process
  // operator's save_state(), kind "interface 2d"), resumed on any number of
  // processes (docs/3d.md section 6).  A mode's global index is its index in
  // the whole interface's operator (interface_operator_wavevectors(grid)):
  // qz (nodes_x/2 + 1) + qx for the grid mode (qx, qz), grid.modes() + qx for
  // the extra z-Nyquist mode of (qx, nodes_z/2).  Each array of every
  // operator kind is contiguous per mode in mode order (state_layout), so the
  // whole state's arrays are each mode's values concatenated in global order.
  //
  // This operator's modes' states ("mode records", kind kModeRecordsKind):
  // the counters and the counter "@operator_modes" (the whole operator's
  // mode count), the array "@modes" (this operator's global indices,
  // ascending), and for each array X of save_state() its modes' values in
  // that order (X) with their offsets (X + "@first", one more than the
  // modes).  An idle uniform mode is left out (not a mode of the interface;
  // its state stays zero).  with_values = false: the arrays X are empty (the
  // layout alone).  Allocates: restart points only.
  HistoryOperatorState save_mode_records(bool with_values = true) const;
  // The whole operator's state from the mode records of parts that hold
  // every mode once (the processes of a split run).  Throws
  // std::invalid_argument naming a missing or repeated mode, or a counter
  // that differs between parts.
  static HistoryOperatorState merge_mode_records(std::span<const HistoryOperatorState> parts);
  // The whole operator's state (kind "interface 2d") cut into the mode
  // records of parts whose layouts (save_mode_records(false)) hold every
  // mode once.  Throws std::invalid_argument naming an array whose size does
  // not fit the parts' operators (a state of another config or grid).
  static std::vector<HistoryOperatorState> split_state(const HistoryOperatorState& whole,
                                                       std::span<const HistoryOperatorState> layouts);
  // Restores this operator from the records of exactly its own modes.
  void restore_mode_records(const HistoryOperatorState& records);
  static constexpr const char* kModeRecordsKind = "interface 2d mode records";

 private:
  InterfaceGrid2d grid_;
  std::unique_ptr<HistoryOperator> inplane_, antiplane_;
  // Operator mode first_ + s is slot s; first_ = 1 when operator mode 0 is an
  // idle uniform mode (a set without the uniform mode).  Operator mode
  // first_ + modes() + j is the slot extra_slot_[j] (qz = nodes_z/2) with -kz.
  std::size_t first_ = 0;
  std::vector<std::size_t> extra_slot_;
  // Global index of each operator mode (-1: the idle uniform mode), and the
  // whole interface's operator mode count.
  std::vector<long long> global_mode_;
  long long operator_modes_ = 0;
  HistoryStateLayout state_layout() const;
  // The x-Nyquist column's pairs of slots (qz, nodes_z - qz), qz = 0..nodes_z/2.
  std::vector<std::pair<std::size_t, std::size_t>> x_nyquist_pairs_;
  std::vector<double> cos_, sin_;  // k-hat per operator mode
  InplanePairHistory* pair_ = nullptr;  // inplane_ when it is one, else null
  std::vector<std::complex<double>> opening_, normal_;  // per operator mode, per slot (pairs only)
  std::vector<std::complex<double>> along_, across_, history_x_, history_z_;
};

}  // namespace slipstrip
