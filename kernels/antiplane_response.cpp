#include "kernels/antiplane_response.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace slipstrip {

complex antiplane_strip_response(const ElasticMaterial& material, double strip_height,
                                 double wavenumber, complex s) {
  const double mu = material.shear_modulus;
  const double cs = material.shear_wave_speed();
  const double k = std::abs(wavenumber);
  if (k == 0.0) return shear_comb_response(material, strip_height, s);
  // Principal root: Re alpha >= 0, decaying (outgoing on the imaginary axis).
  const complex alpha = std::sqrt(k * k + s * s / (cs * cs));
  if (is_half_space(strip_height)) return 0.5 * mu * alpha;
  // alpha coth(alpha H) with coth written through e^{-2 alpha H} (no overflow,
  // Re alpha >= 0); near alpha H = 0 (k small, s ~ i c_s k) the series
  // alpha coth(alpha H) = (1 + z^2/3 - z^4/45) / H, z = alpha H.
  const complex z = alpha * strip_height;
  if (std::abs(z) < 1e-4) return 0.5 * mu / strip_height * (1.0 + z * z / 3.0 - z * z * z * z / 45.0);
  const complex e = std::exp(-2.0 * z);
  return 0.5 * mu * alpha * (1.0 + e) / (1.0 - e);
}

double antiplane_static_stiffness(const ElasticMaterial& material, double strip_height,
                                  double wavenumber) {
  const double mu = material.shear_modulus;
  const double k = std::abs(wavenumber);
  if (is_half_space(strip_height)) return 0.5 * mu * k;
  if (k == 0.0) return 0.5 * mu / strip_height;
  const double x = k * strip_height;
  // k coth(kH) = (1 + x^2/3 - x^4/45 + ...) / H for small x.
  if (x < 1e-4) return 0.5 * mu / strip_height * (1.0 + x * x / 3.0 - x * x * x * x / 45.0);
  return 0.5 * mu * k / std::tanh(x);
}

std::vector<StripMode> antiplane_strip_modes(const ElasticMaterial& material, double strip_height,
                                             double wavenumber, double max_frequency) {
  if (is_half_space(strip_height))
    throw std::invalid_argument("antiplane_strip_modes: a half-space has no discrete normal modes");
  const double mu = material.shear_modulus;
  const double cs = material.shear_wave_speed();
  const double H = strip_height;
  const double k = std::abs(wavenumber);
  std::vector<StripMode> modes;
  if (k == 0.0) return modes;
  for (int m = 1;; ++m) {
    const double kappa = m * std::numbers::pi / H;
    const double omega_comb = cs * kappa;
    const double omega_s = cs * std::sqrt(k * k + kappa * kappa);
    if (omega_comb > max_frequency) break;  // omega_comb < omega_s
    if (omega_s > max_frequency) continue;
    const double rho = mu / H * cs * cs * kappa * kappa;
    modes.push_back({omega_s, -rho / (omega_s * omega_s), ModeFamily::shear, m});
    // The comb mode only with its shear partner (as strip_modes): alone it is
    // an O(mu/H) term that does not decay with m.
    modes.push_back({omega_comb, rho / (omega_comb * omega_comb), ModeFamily::comb, m});
  }
  return modes;
}

double antiplane_strip_passivity_beta_limit() { return 2.0 / std::numbers::pi; }

}  // namespace slipstrip
