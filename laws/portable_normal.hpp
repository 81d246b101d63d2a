#pragma once
// Standard-normal numbers whose sequence is fixed by this code, not by the
// standard library.  The C++ standard fixes std::mt19937_64's output but not
// std::normal_distribution's algorithm, so a seed gave different initial noise
// with different standard libraries.  This is Marsaglia's polar method on
// 53-bit uniforms double(g) / 2^64, with the same arithmetic, in the same
// order, as libstdc++'s std::normal_distribution<double> driven by
// std::mt19937_64 (GCC 12, Debian 12, built with FMA): runs made with that
// library are reproduced bit for bit, and every other library and build now
// gives the same numbers (up to the platform's std::log, which is glibc's on
// Debian; std::sqrt and std::fma are exactly rounded by IEEE 754).
#include <cmath>
#include <cstdint>
#include <random>

namespace slipstrip {

class PortableNormal {
 public:
  explicit PortableNormal(std::uint64_t seed) : engine_(seed) {}

  double operator()() {
    if (has_saved_) {
      has_saved_ = false;
      return saved_;
    }
    double x, y, r2;
    do {
      x = 2.0 * uniform() - 1.0;
      y = 2.0 * uniform() - 1.0;
      // Written as the fused multiply-add that GCC emits for libstdc++'s
      // x * x + y * y when FMA instructions are enabled (-march=native, how
      // every earlier run was built): std::fma is exactly rounded everywhere,
      // so a build without FMA instructions now gives the same numbers too.
      r2 = std::fma(x, x, y * y);
    } while (r2 > 1.0 || r2 == 0.0);
    const double multiplier = std::sqrt(-2.0 * std::log(r2) / r2);
    saved_ = x * multiplier;
    has_saved_ = true;
    return y * multiplier;
  }

 private:
  // [0, 1): one 64-bit draw rounded to double and scaled by 2^-64 (exact);
  // rounding can reach 1, which is mapped to the largest double below 1.
  double uniform() {
    const double value = static_cast<double>(engine_()) * 0x1p-64;
    return value >= 1.0 ? std::nextafter(1.0, 0.0) : value;
  }

  std::mt19937_64 engine_;
  double saved_ = 0.0;
  bool has_saved_ = false;
};

}  // namespace slipstrip
