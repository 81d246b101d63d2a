#pragma once
// Slip-sampled records built by hand for the event-detection tests
// (test_events_detection.cpp, test_events_interface_2d.cpp).
#include <doctest/doctest.h>

#include <algorithm>
#include <cstddef>
#include <limits>
#include <vector>

namespace events_test {

// Per-node lists of crossing times, turned into the [n_levels, N] matrix with
// NaN tails.
struct History {
  std::vector<std::vector<double>> columns;
  explicit History(std::size_t n) : columns(n) {}
  void slip(std::size_t node, double t) {
    auto& c = columns[node % columns.size()];
    REQUIRE((c.empty() || t >= c.back()));  // the builder itself must be monotone
    c.push_back(t);
  }
  std::size_t n_levels() const {
    std::size_t m = 0;
    for (const auto& c : columns) m = std::max(m, c.size());
    return m;
  }
  std::vector<double> matrix() const {
    const std::size_t nl = n_levels(), n = columns.size();
    std::vector<double> m(nl * n, std::numeric_limits<double>::quiet_NaN());
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = 0; j < columns[i].size(); ++j) m[j * n + i] = columns[i][j];
    return m;
  }
};

}  // namespace events_test
