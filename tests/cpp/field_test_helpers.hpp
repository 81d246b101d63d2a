#pragma once
// Small helpers for tests that compare fields node by node.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <span>

inline double max_abs(std::span<const double> x) {
  double m = 0;
  for (double v : x) m = std::max(m, std::abs(v));
  return m;
}

inline double max_abs_difference(std::span<const double> a, std::span<const double> b) {
  double d = 0;
  for (std::size_t i = 0; i < a.size(); ++i) d = std::max(d, std::abs(a[i] - b[i]));
  return d;
}
