#pragma once
// On-fault stations: values of the interface fields at given positions,
// interpolated linearly between the neighbouring nodes of the periodic grid
// (along x on a line; bilinearly in x and z on a 2D interface, docs/3d.md),
// exact when a station sits on a node.  Weights are computed once; sample()
// writes into a preallocated vector (no allocation in the time loop).
#include <cmath>
#include <cstddef>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace slipstrip {

// A position between two neighbouring nodes of a periodic axis: the value
// there is (1 - weight) f[left] + weight f[right].
struct StationCell {
  std::size_t left = 0, right = 0;
  double weight = 0.0;
};

// `key`, `symbol` and `axis` name the config key, the coordinate and the
// interval in the error message.
inline StationCell station_cell(double position, double spacing, std::size_t nodes, const char* key,
                                const char* symbol, const char* axis) {
  const double cell = position / spacing;
  auto left = static_cast<std::size_t>(std::floor(cell));
  double weight = cell - std::floor(cell);
  // A station within round-off of a node is that node (exact sampling).
  if (weight < 1e-12) weight = 0.0;
  if (weight > 1.0 - 1e-12) weight = 0.0, ++left;
  if (left >= nodes) left -= nodes;
  if (!(position >= 0.0) || left >= nodes)
    throw std::invalid_argument(std::string(key) + ": " + symbol + " = " + std::to_string(position) + " m is outside the interface " +
                                axis);
  return {left, left + 1 == nodes ? 0 : left + 1, weight};
}

class StationSampler {
 public:
  StationSampler(std::span<const double> x, double dx, std::size_t nodes) : values_(x.size()) {
    for (double position : x) cells_.push_back(station_cell(position, dx, nodes, "output.stations", "x", "[0, L)"));
  }

  std::size_t size() const { return cells_.size(); }
  bool empty() const { return cells_.empty(); }

  // Values of `field` at the stations (a view of an internal buffer, valid
  // until the next call).
  std::span<const double> sample(std::span<const double> field) {
    for (std::size_t s = 0; s < cells_.size(); ++s) {
      const StationCell& c = cells_[s];
      values_[s] = (1.0 - c.weight) * field[c.left] + c.weight * field[c.right];
    }
    return values_;
  }

 private:
  std::vector<StationCell> cells_;
  std::vector<double> values_;
};

// Stations at points (x[s], z[s]) of a 2D interface of nodes_x x nodes_z
// nodes, fields flattened with x fastest (node (ix, iz) at ix + nodes_x iz).
// A station's value is taken in two stages: the value along x in each of its
// two rows (a row term, from that row's nodes only), then the two row terms
// combined along z.  A run split over processes by rows
// (parallel/distributed_run.cpp) takes each row term on the process that
// holds the row and combines them on rank 0 with the same two functions, so
// it records the numbers of one process, bit for bit.
class StationSampler2d {
 public:
  StationSampler2d(std::span<const double> x, std::span<const double> z, double dx, double dz, std::size_t nodes_x,
                   std::size_t nodes_z)
      : nodes_x_(nodes_x), values_(x.size()) {
    if (x.size() != z.size())
      throw std::invalid_argument("output.stations_z: " + std::to_string(z.size()) + " positions for " +
                                  std::to_string(x.size()) + " stations; expected one z per station");
    for (std::size_t s = 0; s < x.size(); ++s) {
      cells_x_.push_back(station_cell(x[s], dx, nodes_x, "output.stations", "x", "[0, L)"));
      cells_z_.push_back(station_cell(z[s], dz, nodes_z, "output.stations_z", "z", "[0, W)"));
    }
  }

  std::size_t size() const { return cells_x_.size(); }
  bool empty() const { return cells_x_.empty(); }

  // Row terms: 2 per station, term 2s in station s's row below (or on) it,
  // term 2s + 1 in the row above (the next row, periodically: row 0 after
  // the last).  The above row's term is taken even for a station on a row
  // (weight 0 along z), as one product of the sum.
  std::size_t terms() const { return 2 * cells_z_.size(); }
  std::size_t term_row(std::size_t term) const {
    const StationCell& cz = cells_z_[term / 2];
    return term % 2 == 0 ? cz.left : cz.right;
  }
  // Row term `term` of a field given for the rows first_row, first_row + 1,
  // ... (x fastest); its row must be among them.
  double row_term(std::span<const double> rows, std::size_t first_row, std::size_t term) const {
    const StationCell& cx = cells_x_[term / 2];
    const std::size_t base = (term_row(term) - first_row) * nodes_x_;
    return (1.0 - cx.weight) * rows[base + cx.left] + cx.weight * rows[base + cx.right];
  }
  // Station s's value from its row terms below (2s) and above (2s + 1).
  double combine(std::size_t s, double below, double above) const {
    const StationCell& cz = cells_z_[s];
    return (1.0 - cz.weight) * below + cz.weight * above;
  }

  // Values of a field of the whole interface at the stations (a view of an
  // internal buffer, valid until the next call).
  std::span<const double> sample(std::span<const double> field) {
    for (std::size_t s = 0; s < cells_x_.size(); ++s)
      values_[s] = combine(s, row_term(field, 0, 2 * s), row_term(field, 0, 2 * s + 1));
    return values_;
  }

 private:
  std::size_t nodes_x_;
  std::vector<StationCell> cells_x_, cells_z_;
  std::vector<double> values_;
};

}  // namespace slipstrip
