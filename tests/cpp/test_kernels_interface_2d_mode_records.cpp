// A 2D interface's history operator state regrouped by Fourier mode
// (InterfaceHistory2d::save_mode_records, merge_mode_records, split_state,
// restore_mode_records; docs/3d.md section 6): what lets a restart point
// written by a run split over P processes resume on Q processes.  No MPI
// here: the parts of a split run are operators over column sets of the grid
// (interface_mode_columns, as FFTW's MPI transform distributes the modes),
// built with the whole operator's choices (block length, half-space
// near-field range), all in one process.  For each operator kind (modal,
// block and half-space strips; a strip on a clamped strip of another
// material and on a half-space: face modal and face half-space operators,
// antiplane pairs, the normal stress), on a 16 x 8 grid (Nyquist modes in x
// and z) cut into 2 and 3 parts and a 15 x 9 grid cut into 2 (the
// half-spaces: an 8 x 8 grid cut into 2), 300 steps of random spectra:
//   * layouts: every array of every leaf operator's state has a per-mode
//     offset table that ends at its size;
//   * fed the same inputs, the parts' records merged give the whole
//     operator's state bit for bit (but the block strips, whose far field
//     rounds differently for a design a part holds alone: compared to
//     1e-13 of each array's largest value, round-off; measured at most
//     1.2e-15), and that state cut for the parts and merged again is itself
//     bit for bit;
//   * the whole operator's state cut into fresh parts, which then continue
//     with the whole operator on the same inputs for 200 steps: every mode's
//     history (and normal stress) bit for bit (block strips: 1e-13 of the
//     largest value; measured at most 7.4e-16);
//   * refusals: a state of another grid, a mode held twice or by no part,
//     records of another part's modes, counters that differ between parts;
//     a half-space face's flag of a worked normal channel, which parts may
//     hold differently, merged as whether any part's is set.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "kernels/block_strip_history.hpp"
#include "kernels/face_block_history.hpp"
#include "kernels/face_half_space.hpp"
#include "kernels/face_history.hpp"
#include "kernels/half_space_history.hpp"
#include "kernels/interface_2d_history.hpp"
#include "kernels/two_body_history.hpp"

using namespace slipstrip;
using cplx = std::complex<double>;
constexpr double kInf = std::numeric_limits<double>::infinity();

namespace {

enum class Kind { modal, block, half_space, pair_strip, pair_half_space };

const char* name(Kind kind) {
  switch (kind) {
    case Kind::modal: return "modal strips";
    case Kind::block: return "block strips";
    case Kind::half_space: return "half-spaces";
    case Kind::pair_strip: return "strip on a clamped strip of another material";
    case Kind::pair_half_space: return "strip on a half-space of another material";
  }
  return "";
}

ElasticMaterial other_material() {
  ElasticMaterial m;  // Table S1's, then stiffer, denser, another Poisson ratio
  m.shear_modulus *= 1.7;
  m.density *= 1.3;
  m.poisson_ratio = 0.25;
  return m;
}

// The columns of `parts` processes as FFTW's block distribution gives them
// (ceil(columns / parts) each, the last fewer).
std::vector<InterfaceModeSet> column_parts(const InterfaceGrid2d& grid, int parts) {
  const int columns = grid.nodes_x / 2 + 1, each = (columns + parts - 1) / parts;
  std::vector<InterfaceModeSet> sets;
  for (int p = 0; p < parts; ++p) {
    const int begin = std::min(columns, p * each), count = std::min(each, columns - begin);
    REQUIRE(count > 0);
    sets.push_back(interface_mode_columns(grid, begin, count));
  }
  return sets;
}

// Builds the whole operator (modes = nullopt) or a part with the whole one's
// choices: the block strips' block lengths (recorded in build order from the
// whole operator's), each half-space body's near-field range over the whole
// grid's h = c_s |k| dt.
class Builder {
 public:
  Builder(Kind kind, const InterfaceGrid2d& grid) : kind_(kind), grid_(grid) {
    const double dx = std::min(grid.length_x / grid.nodes_x, grid.length_z / grid.nodes_z);
    if (kind == Kind::pair_strip || kind == Kind::pair_half_space) {
      const TwoBodyTiming timing =
          two_body_time_step(top_, height_, other_material(), kind == Kind::pair_strip ? 2.0 * height_ : kInf, dx, 0.2);
      dt_ = timing.time_step;
      bottom_height_ = timing.bottom_height;
    } else {
      dt_ = strip_time_step(top_, kind == Kind::half_space ? kInf : height_, dx, 0.2);
    }
  }

  InterfaceHistory2d build(const std::optional<InterfaceModeSet>& modes) {
    const InterfaceModeSet set = modes ? *modes : interface_modes_all(grid_);
    std::size_t next_block = 0;
    InterfaceHistory2d::StripOperatorFactory strip;
    if (kind_ == Kind::block) {
      strip = [&, whole = !modes](const ElasticMaterial& m, const StripKernels& k) -> std::unique_ptr<HistoryOperator> {
        BlockHistoryDesign design;
        if (!whole) design.block = blocks_.at(next_block++);
        auto op = std::make_unique<BlockStripHistory>(m, k, design);
        if (whole) blocks_.push_back(op->block());
        return op;
      };
    }
    switch (kind_) {
      case Kind::modal:
      case Kind::block:
        return InterfaceHistory2d::build(top_, height_, grid_, set, dt_, {}, strip);
      case Kind::half_space:
        return InterfaceHistory2d::build(top_, kInf, grid_, set, dt_, {}, {}, near_field(top_));
      case Kind::pair_strip:
      case Kind::pair_half_space: {
        const InterfaceBody top{top_, height_, OuterFace::driven};
        const InterfaceBody bottom{other_material(), bottom_height_, OuterFace::clamped};
        InterfaceHistory2d::PairPart part;
        part.top_half_space = near_field(top_);
        part.bottom_half_space = near_field(other_material());
        return InterfaceHistory2d::build_pair(top, bottom, grid_, set, dt_, {}, {}, part);
      }
    }
    throw std::logic_error("unknown kind");
  }

 private:
  HalfSpaceOperatorDesign near_field(const ElasticMaterial& m) const {
    std::vector<double> h = interface_operator_wavevectors(grid_).magnitude;
    for (double& value : h) value = m.shear_wave_speed() * value * dt_;
    HalfSpaceOperatorDesign design;
    set_near_field_range(design, h);
    return design;
  }

  Kind kind_;
  InterfaceGrid2d grid_;
  ElasticMaterial top_;
  double height_ = 0.1, bottom_height_ = 0.0, dt_ = 0.0;
  std::vector<int> blocks_;
};

// Random spectra of the whole grid (interface_modes_all's order), and a
// part's slots taken from them.
struct Inputs {
  std::vector<cplx> x, z, opening;
};

Inputs random_inputs(std::size_t modes, std::mt19937_64& rng) {
  std::normal_distribution<double> normal;
  Inputs in;
  for (auto* v : {&in.x, &in.z, &in.opening}) {
    v->resize(modes);
    for (cplx& c : *v) c = {normal(rng), normal(rng)};
  }
  for (cplx& c : in.opening) c *= 1e3;  // Pa, against slip rates of order 1 m/s
  return in;
}

std::size_t whole_index(const InterfaceGrid2d& grid, const InterfaceModeSet& set, std::size_t slot) {
  return static_cast<std::size_t>(set.qz[slot]) * (grid.nodes_x / 2 + 1) + static_cast<std::size_t>(set.qx[slot]);
}

void push(InterfaceHistory2d& op, const InterfaceGrid2d& grid, const InterfaceModeSet& set, const Inputs& in) {
  std::vector<cplx> x(set.size()), z(set.size()), opening(set.size());
  for (std::size_t s = 0; s < set.size(); ++s) {
    const std::size_t w = whole_index(grid, set, s);
    x[s] = in.x[w];
    z[s] = in.z[w];
    opening[s] = in.opening[w];
  }
  if (op.variable_normal_stress())
    op.push(x, z, opening);
  else
    op.push(x, z);
}

double largest(const std::vector<double>& values) {
  double m = 0.0;
  for (double v : values) m = std::max(m, std::abs(v));
  return m;
}

// Two states of the one-process layout: the same counters and arrays; the
// arrays bit for bit (tolerance 0) or within tolerance times each array's
// largest value.
void check_states_equal(const HistoryOperatorState& a, const HistoryOperatorState& b, double tolerance) {
  CHECK(a.kind == b.kind);
  auto ca = a.counters, cb = b.counters;
  std::sort(ca.begin(), ca.end());
  std::sort(cb.begin(), cb.end());
  CHECK(ca == cb);
  REQUIRE(a.arrays.size() == b.arrays.size());
  for (std::size_t i = 0; i < a.arrays.size(); ++i) {
    INFO(a.arrays[i].first);
    REQUIRE(a.arrays[i].first == b.arrays[i].first);
    const auto &x = a.arrays[i].second, &y = b.arrays[i].second;
    REQUIRE(x.size() == y.size());
    if (tolerance == 0.0) {
      CHECK(x == y);
    } else {
      const double scale = largest(x);
      double worst = 0.0;
      for (std::size_t j = 0; j < x.size(); ++j) worst = std::max(worst, std::abs(x[j] - y[j]));
      CHECK(worst <= tolerance * scale);
    }
  }
}

void check_layouts_fit(const HistoryOperator& op) {
  const HistoryOperatorState state = op.save_state();
  const HistoryStateLayout layout = op.state_layout();
  CHECK(layout.arrays.size() == state.arrays.size());
  for (const auto& [array, values] : state.arrays) {
    INFO(state.kind << " " << array);
    const auto& first = layout.of(array);
    REQUIRE(first.size() == static_cast<std::size_t>(op.modes()) + 1);
    CHECK(first.front() == 0);
    CHECK(first.back() == values.size());
    CHECK(std::is_sorted(first.begin(), first.end()));
  }
}

void run_case(Kind kind, const InterfaceGrid2d& grid, int parts_count) {
  INFO(std::string(name(kind)) << ", " << grid.nodes_x << " x " << grid.nodes_z << " in " << parts_count << " parts");
  Builder builder(kind, grid);
  InterfaceHistory2d whole = builder.build(std::nullopt);
  const std::vector<InterfaceModeSet> sets = column_parts(grid, parts_count);
  std::vector<InterfaceHistory2d> parts;
  for (const auto& set : sets) parts.push_back(builder.build(set));
  check_layouts_fit(whole.inplane());
  check_layouts_fit(whole.antiplane());
  const InterfaceModeSet all = interface_modes_all(grid);
  std::mt19937_64 rng(17);
  // Longer than a block of the block strips (B <= 256 here) and than the
  // half-spaces' windows and slow blocks.
  const int steps = 300;
  for (int n = 0; n < steps; ++n) {
    const Inputs in = random_inputs(grid.modes(), rng);
    push(whole, grid, all, in);
    for (std::size_t p = 0; p < parts.size(); ++p) push(parts[p], grid, sets[p], in);
  }
  std::vector<HistoryOperatorState> records, layouts;
  for (const auto& part : parts) {
    records.push_back(part.save_mode_records());
    layouts.push_back(part.save_mode_records(false));
  }
  const HistoryOperatorState whole_state = whole.save_state();
  const HistoryOperatorState merged = InterfaceHistory2d::merge_mode_records(records);
  check_states_equal(whole_state, merged, kind == Kind::block ? 1e-13 : 0.0);
  // Cut and merged again: the same state, bit for bit (data moved, never computed).
  check_states_equal(whole_state,
                     InterfaceHistory2d::merge_mode_records(InterfaceHistory2d::split_state(whole_state, layouts)), 0.0);

  // The whole state cut into fresh parts, which continue with the whole operator.
  std::vector<InterfaceHistory2d> resumed;
  const auto cut = InterfaceHistory2d::split_state(whole_state, layouts);
  for (std::size_t p = 0; p < sets.size(); ++p) {
    resumed.push_back(builder.build(sets[p]));
    resumed.back().restore_mode_records(cut[p]);
  }
  double worst = 0.0, scale = 0.0;
  for (int n = 0; n < 200; ++n) {
    const Inputs in = random_inputs(grid.modes(), rng);
    push(whole, grid, all, in);
    for (std::size_t p = 0; p < resumed.size(); ++p) {
      push(resumed[p], grid, sets[p], in);
      for (std::size_t s = 0; s < sets[p].size(); ++s) {
        const std::size_t w = whole_index(grid, sets[p], s);
        std::vector<std::pair<cplx, cplx>> pairs{{whole.history_x()[w], resumed[p].history_x()[s]},
                                                 {whole.history_z()[w], resumed[p].history_z()[s]}};
        if (whole.variable_normal_stress()) pairs.emplace_back(whole.normal_stress()[w], resumed[p].normal_stress()[s]);
        for (const auto& [a, b] : pairs) {
          worst = std::max(worst, std::abs(a - b));
          scale = std::max(scale, std::abs(a));
        }
      }
    }
  }
  CHECK(scale > 0.0);
  if (kind == Kind::block)
    CHECK(worst <= 1e-13 * scale);
  else
    CHECK(worst == 0.0);

  // Refusals.
  // Records of another part's modes.
  if (parts.size() > 1)
    CHECK_THROWS_WITH_AS(parts[0].restore_mode_records(records[1]), doctest::Contains("not this operator's modes"),
                         std::invalid_argument);
  // A mode held by no part, and one held by two.
  const std::vector<HistoryOperatorState> missing(records.begin() + 1, records.end());
  CHECK_THROWS_WITH_AS(InterfaceHistory2d::merge_mode_records(missing), doctest::Contains("is held by no part"),
                       std::invalid_argument);
  std::vector<HistoryOperatorState> twice = records;
  twice.push_back(records[0]);
  CHECK_THROWS_WITH_AS(InterfaceHistory2d::merge_mode_records(twice), doctest::Contains("is held by two parts"),
                       std::invalid_argument);
  // A counter that differs between parts.
  std::vector<HistoryOperatorState> other_counter = records;
  other_counter.back().counters.front().second += 1;
  CHECK_THROWS_WITH_AS(InterfaceHistory2d::merge_mode_records(other_counter), doctest::Contains("counter '"),
                       std::invalid_argument);
  // The half-space faces' flag: set in the whole operator when set in any part.
  std::size_t flags = 0;
  for (const auto& [counter, value] : whole_state.counters) {
    if (!counter.ends_with("normal_active")) continue;
    ++flags;
    CHECK(value == 1);  // the random inputs drive every channel
    std::vector<HistoryOperatorState> unset = records;
    const auto set_flag = [&](HistoryOperatorState& part, long long flag) {
      for (auto& [key, v] : part.counters)
        if (key == counter) v = flag;
    };
    for (std::size_t p = 1; p < unset.size(); ++p) set_flag(unset[p], 0);
    CHECK(InterfaceHistory2d::merge_mode_records(unset).counter(counter) == 1);
    set_flag(unset[0], 0);
    CHECK(InterfaceHistory2d::merge_mode_records(unset).counter(counter) == 0);
  }
  CHECK(flags == (kind == Kind::pair_half_space ? 1u : 0u));
}

}  // namespace

TEST_CASE("leaf history operators state where each Fourier mode's values lie in every state array") {
  // The face block operator is used by 1D pairs only; its layout is checked here.
  const ElasticMaterial m;
  const double dx = 0.8 / 16, dt = strip_time_step(m, 0.1, dx, 0.2);
  FaceBlockHistory block(m, 0.1, OuterFace::clamped, 0.8, 16, dt, FaceBlockDesign{});
  std::mt19937_64 rng(3);
  std::normal_distribution<double> normal;
  std::vector<cplx> vx(block.modes()), vy(block.modes());
  for (int n = 0; n < 100; ++n) {
    for (auto* v : {&vx, &vy})
      for (cplx& c : *v) c = {normal(rng), normal(rng)};
    block.push(vx, vy);
  }
  HistoryOperatorState state;
  HistoryStateLayout layout;
  block.save_into(state, "face.");
  block.state_layout_into(layout, "face.");
  CHECK(layout.arrays.size() == state.arrays.size());
  for (const auto& [array, values] : state.arrays) {
    INFO(array);
    const auto& first = layout.of(array);
    REQUIRE(first.size() == static_cast<std::size_t>(block.modes()) + 1);
    CHECK(first.front() == 0);
    CHECK(first.back() == values.size());
    CHECK(std::is_sorted(first.begin(), first.end()));
  }
  CHECK_THROWS_WITH_AS(layout.of("face.nothing"), doctest::Contains("no per-mode layout"), std::invalid_argument);
}

TEST_CASE("2D interface history regrouped by Fourier mode: parts merged = the whole operator, cut parts continue it") {
  const InterfaceGrid2d even{0.8, 0.4, 16, 8}, odd{0.75, 0.45, 15, 9}, small{0.8, 0.4, 8, 8};
  for (const Kind kind : {Kind::modal, Kind::block, Kind::pair_strip}) {
    run_case(kind, even, 2);
    run_case(kind, even, 3);
    run_case(kind, odd, 2);
  }
  // The half-space operators' set-up takes seconds at 16 x 8: an 8 x 8 grid
  // (Nyquist modes in x and z too) in two parts.
  for (const Kind kind : {Kind::half_space, Kind::pair_half_space}) run_case(kind, small, 2);
}

TEST_CASE("2D interface history regrouped by Fourier mode: a state of another grid is refused") {
  const InterfaceGrid2d grid{0.8, 0.4, 16, 8}, other{0.8, 0.3, 16, 6};
  Builder builder(Kind::modal, grid), other_builder(Kind::modal, other);
  const HistoryOperatorState state = other_builder.build(std::nullopt).save_state();
  std::vector<HistoryOperatorState> layouts;
  for (const auto& set : column_parts(grid, 2)) layouts.push_back(builder.build(set).save_mode_records(false));
  CHECK_THROWS_WITH_AS(InterfaceHistory2d::split_state(state, layouts),
                       doctest::Contains("this run's operator needs"), std::invalid_argument);
  HistoryOperatorState foreign = state;
  foreign.kind = "modal strip";
  CHECK_THROWS_AS(InterfaceHistory2d::split_state(foreign, layouts), std::invalid_argument);
}
