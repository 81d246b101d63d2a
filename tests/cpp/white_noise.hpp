#pragma once
// Slip-rate (or velocity) spectra of white noise for driving history
// operators: `steps` spectra of `modes` Fourier modes, real and imaginary
// parts standard normal, the uniform mode real.  White input excites every
// normal mode, the hardest case for the block operators' far-field states.
#include <complex>
#include <random>
#include <vector>

namespace slipstrip_test {

inline std::vector<std::vector<std::complex<double>>> white_noise_spectra(int modes, int steps, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<std::vector<std::complex<double>>> spectra(steps, std::vector<std::complex<double>>(modes));
  for (auto& v : spectra) {
    for (auto& x : v) x = std::complex<double>(normal(rng), normal(rng));
    v[0] = v[0].real();
  }
  return spectra;
}

}  // namespace slipstrip_test
