#pragma once
// Overflow-safe hyperbolic helpers for the strip responses (docs/theory.md §3
// and docs/bodies.md): a coth(aH) and a tanh(aH) for Re a >= 0, and their
// divided differences, evaluated without the 1/(a - b) cancellation that the
// static limit a -> b would otherwise cause.
#include <cmath>
#include <complex>

namespace slipstrip::hyperbolic {

using complex = std::complex<double>;

// coth(z) for Re z >= 0 written with e^{-2z} so that it neither overflows for
// large Re z nor loses the oscillation on the imaginary axis.
inline complex coth_right_half(complex z) {
  const complex e = std::exp(-2.0 * z);
  return (1.0 + e) / (1.0 - e);
}

// tanh(z) for Re z >= 0, likewise.
inline complex tanh_right_half(complex z) {
  const complex e = std::exp(-2.0 * z);
  return (1.0 - e) / (1.0 + e);
}

// sinh(z)/z, with its series near 0.
inline complex sinhc(complex z) {
  return std::abs(z) < 1e-3 ? 1.0 + z * z / 6.0 + z * z * z * z / 120.0 : std::sinh(z) / z;
}

// Divided difference (f(a) - f(b)) / (a - b) of f(a) = a coth(aH), stable when a ~ b:
//   f[a,b] = coth(aH) - bH sinhc((a-b)H) / (sinh(aH) sinh(bH))
// (from coth x - coth y = -sinh(x - y) / (sinh x sinh y)).
inline complex divided_difference_a_coth(complex a, complex b, double H) {
  const complex d = a - b;
  if (std::abs(d * H) > 0.5) return (a * coth_right_half(a * H) - b * coth_right_half(b * H)) / d;
  // 1/(sinh(aH) sinh(bH)) written with decaying exponentials (Re a, Re b >= 0).
  const complex csch_product = 4.0 * std::exp(-(a + b) * H) /
                               ((1.0 - std::exp(-2.0 * a * H)) * (1.0 - std::exp(-2.0 * b * H)));
  return coth_right_half(a * H) - b * H * sinhc(d * H) * csch_product;
}

// The same for f(a) = a tanh(aH):
//   f[a,b] = tanh(aH) + bH sinhc((a-b)H) / (cosh(aH) cosh(bH))
// (from tanh x - tanh y = sinh(x - y) / (cosh x cosh y)).
inline complex divided_difference_a_tanh(complex a, complex b, double H) {
  const complex d = a - b;
  if (std::abs(d * H) > 0.5) return (a * tanh_right_half(a * H) - b * tanh_right_half(b * H)) / d;
  const complex sech_product = 4.0 * std::exp(-(a + b) * H) /
                               ((1.0 + std::exp(-2.0 * a * H)) * (1.0 + std::exp(-2.0 * b * H)));
  return tanh_right_half(a * H) + b * H * sinhc(d * H) * sech_product;
}

}  // namespace slipstrip::hyperbolic
