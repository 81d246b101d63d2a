#pragma once
// On-fault stations: values of the interface fields at given positions,
// interpolated linearly between the two neighbouring nodes of the periodic
// grid (exact when a station sits on a node).  Weights are computed once;
// sample() writes into preallocated vectors (no allocation in the time loop).
#include <cmath>
#include <cstddef>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace slipstrip {

class StationSampler {
 public:
  StationSampler(std::span<const double> x, double dx, std::size_t nodes) : values_(x.size()) {
    for (double position : x) {
      const double cell = position / dx;
      auto left = static_cast<std::size_t>(std::floor(cell));
      double weight = cell - std::floor(cell);
      // A station within round-off of a node is that node (exact sampling).
      if (weight < 1e-12) weight = 0.0;
      if (weight > 1.0 - 1e-12) weight = 0.0, ++left;
      if (left >= nodes) left -= nodes;
      if (!(position >= 0.0) || left >= nodes)
        throw std::invalid_argument("output.stations: x = " + std::to_string(position) +
                                    " m is outside the interface [0, L)");
      left_.push_back(left);
      right_.push_back(left + 1 == nodes ? 0 : left + 1);
      weight_.push_back(weight);
    }
  }

  std::size_t size() const { return left_.size(); }
  bool empty() const { return left_.empty(); }

  // Values of `field` at the stations (a view of an internal buffer, valid
  // until the next call).
  std::span<const double> sample(std::span<const double> field) {
    for (std::size_t s = 0; s < left_.size(); ++s)
      values_[s] = (1.0 - weight_[s]) * field[left_[s]] + weight_[s] * field[right_[s]];
    return values_;
  }

 private:
  std::vector<std::size_t> left_, right_;
  std::vector<double> weight_;
  std::vector<double> values_;
};

}  // namespace slipstrip
