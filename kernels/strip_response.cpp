#include "kernels/strip_response.hpp"

#include "kernels/antiplane_response.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace slipstrip {
namespace {

// coth(z) for Re z >= 0 written with e^{-2z} so that it neither overflows for
// large Re z nor loses the oscillation on the imaginary axis.
complex coth_right_half(complex z) {
  const complex e = std::exp(-2.0 * z);
  return (1.0 + e) / (1.0 - e);
}

// Principal square root; Re >= 0, which is the decaying branch for Re s > 0 and
// the outgoing-wave branch on the imaginary axis (limit from Re s > 0).
complex decaying_root(complex x) { return std::sqrt(x); }

// Divided difference (f(a) - f(b)) / (a - b) of f(a) = a coth(aH), stable when a ~ b:
//   f[a,b] = coth(aH) - bH sinhc((a-b)H) / (sinh(aH) sinh(bH)).
complex divided_difference_a_coth(complex a, complex b, double H) {
  const complex d = a - b;
  if (std::abs(d * H) > 0.5) return (a * coth_right_half(a * H) - b * coth_right_half(b * H)) / d;
  const complex z = d * H;
  const complex sinhc = std::abs(z) < 1e-3 ? 1.0 + z * z / 6.0 + z * z * z * z / 120.0 : std::sinh(z) / z;
  // 1/(sinh(aH) sinh(bH)) written with decaying exponentials (Re a, Re b >= 0).
  const complex csch_product = 4.0 * std::exp(-(a + b) * H) /
                               ((1.0 - std::exp(-2.0 * a * H)) * (1.0 - std::exp(-2.0 * b * H)));
  return coth_right_half(a * H) - b * H * sinhc * csch_product;
}

}  // namespace

complex shear_comb_response(const ElasticMaterial& material, double strip_height, complex s) {
  const double mu = material.shear_modulus;
  const double cs = material.shear_wave_speed();
  if (is_half_space(strip_height)) return mu * s / (2.0 * cs);
  const complex z = s * strip_height / cs;
  if (std::abs(z) < 1e-6) return mu / (2.0 * strip_height) * (1.0 + z * z / 3.0);
  return mu * s / (2.0 * cs) * coth_right_half(z);
}

complex strip_response(const ElasticMaterial& material, double strip_height, double wavenumber,
                       complex s) {
  if (material.antiplane()) return antiplane_strip_response(material, strip_height, wavenumber, s);
  const double k = std::abs(wavenumber);
  const double mu = material.shear_modulus;
  const double cs = material.shear_wave_speed();
  const double cd = material.dilatational_wave_speed();
  if (k == 0.0) return shear_comb_response(material, strip_height, s);

  // Cancellation-free form (docs/theory.md, "closed form"): with
  //   f(a) = a coth(aH),  g(a) = coth(aH)/a,  f[a,b] the divided difference,
  //   S = 2 mu k^2 (1 - cs^2/cd^2) f[alpha_s, alpha_d] / (alpha_s + alpha_d)
  //       + mu s^2 g(alpha_s) / (2 cs^2).
  // The textbook form has two O(1/s^2) terms that cancel; this one has none.
  const complex s2 = s * s;
  const complex alpha_d = decaying_root(k * k + s2 / (cd * cd));
  const complex alpha_s = decaying_root(k * k + s2 / (cs * cs));
  const double r = 1.0 - (cs * cs) / (cd * cd);
  if (is_half_space(strip_height))
    return 2.0 * mu * k * k * r / (alpha_s + alpha_d) + mu * s2 / (2.0 * cs * cs * alpha_s);

  const double H = strip_height;
  const complex g_s = coth_right_half(alpha_s * H) / alpha_s;
  return 2.0 * mu * k * k * r * divided_difference_a_coth(alpha_s, alpha_d, H) /
             (alpha_s + alpha_d) +
         mu * s2 * g_s / (2.0 * cs * cs);
}

complex half_space_response(const ElasticMaterial& material, double wavenumber, complex s) {
  return strip_response(material, std::numeric_limits<double>::infinity(), wavenumber, s);
}

double strip_static_stiffness(const ElasticMaterial& material, double strip_height,
                              double wavenumber) {
  if (material.antiplane()) return antiplane_static_stiffness(material, strip_height, wavenumber);
  const double mu = material.shear_modulus;
  const double k = std::abs(wavenumber);
  const double factor = 1.0 - 1.0 / material.wave_speed_ratio_squared();
  if (is_half_space(strip_height)) return mu * k * factor;
  if (k == 0.0) return mu / (2.0 * strip_height);
  const double x = k * strip_height;
  double bracket;
  if (x < 1e-3) {
    // series of coth x - x/sinh^2 x = 2x/3 - 4x^3/45 + 4x^5/315 - ...
    bracket = x * (2.0 / 3.0 - x * x * (4.0 / 45.0 - x * x * 4.0 / 315.0));
  } else if (x > 40.0) {
    bracket = 1.0;  // exponentially close
  } else {
    const double sh = std::sinh(x);
    bracket = 1.0 / std::tanh(x) - x / (sh * sh);
  }
  return mu * k * factor * bracket;
}

std::vector<StripMode> strip_modes(const ElasticMaterial& material, double strip_height,
                                   double wavenumber, double max_frequency) {
  if (material.antiplane())
    return antiplane_strip_modes(material, strip_height, wavenumber, max_frequency);
  if (is_half_space(strip_height))
    throw std::invalid_argument("strip_modes: a half-space has no discrete normal modes");
  const double mu = material.shear_modulus;
  const double cs = material.shear_wave_speed();
  const double cd = material.dilatational_wave_speed();
  const double H = strip_height;
  const double k = std::abs(wavenumber);
  std::vector<StripMode> modes;
  if (k == 0.0) return modes;  // S(0, s; H) is exactly the shear comb.

  auto add = [&](double omega, double rho, ModeFamily family, int m) {
    if (omega <= max_frequency) modes.push_back({omega, rho / (omega * omega), family, m});
  };
  // m = 0 shear family (alpha_s^2 = 0): the only term that survives k -> 0 statically.
  add(cs * k, -mu / (2.0 * H) * cs * cs * k * k, ModeFamily::shear, 0);
  for (int m = 1;; ++m) {
    const double kappa = m * std::numbers::pi / H;
    const double q2 = k * k + kappa * kappa;
    const double omega_s = cs * std::sqrt(q2);
    const double omega_comb = cs * kappa;
    const double omega_d = cd * std::sqrt(q2);
    if (omega_comb > max_frequency) break;  // omega_comb < omega_s < omega_d
    const double d2 = kappa * kappa - k * k;
    add(omega_s, -mu / H * cs * cs * d2 * d2 / q2, ModeFamily::shear, m);
    // The comb mode only with its shear partner: alone it is an O(mu/H) term
    // that does not decay with m (the pair's sum decays like 1/m^2).
    if (omega_s <= max_frequency)
      add(omega_comb, mu / H * cs * cs * kappa * kappa, ModeFamily::comb, m);  // removes the comb's own mode
    add(omega_d, -4.0 * mu * k * k * cs * cs * kappa * kappa / (H * q2), ModeFamily::dilatational, m);
  }
  return modes;
}

}  // namespace slipstrip
