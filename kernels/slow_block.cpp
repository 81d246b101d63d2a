#include "kernels/slow_block.hpp"

namespace slipstrip {

std::vector<std::complex<double>> slow_block_rotations(std::span<const double> h, double b_pressure, int block) {
  const std::size_t n_modes = h.size();
  std::vector<std::complex<double>> rotation(static_cast<std::size_t>(block) * n_modes * 2, 0.0);
  for (int t = 1; t <= block; ++t)
    for (std::size_t q = 0; q < n_modes; ++q) {
      const std::size_t at = (static_cast<std::size_t>(t - 1) * n_modes + q) * 2;
      rotation[at] = std::polar(1.0, h[q] * t);
      rotation[at + 1] = std::polar(1.0, b_pressure * h[q] * t);
    }
  return rotation;
}

}  // namespace slipstrip
