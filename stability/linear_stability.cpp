#include "stability/linear_stability.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include "stability/root_search.hpp"

namespace slipstrip {
namespace {

constexpr double pi = std::numbers::pi;

std::string shortest(double x) {
  char buffer[32];
  const auto end = std::to_chars(buffer, buffer + sizeof buffer, x).ptr;
  return std::string(buffer, end);
}

// Six significant digits, for derived quantities in messages.
std::string brief(double x) {
  char buffer[32];
  const auto end = std::to_chars(buffer, buffer + sizeof buffer, x, std::chars_format::general, 6).ptr;
  return std::string(buffer, end);
}

void require_positive(double value, const char* name) {
  if (!(value > 0.0))
    throw std::invalid_argument(std::string("linear stability: ") + name + " = " +
                                std::to_string(value) + " is not allowed; it must be > 0");
}

void validate(const SteadySliding& sliding) {
  require_positive(sliding.material.shear_modulus, "material.shear_modulus");
  require_positive(sliding.material.density, "material.density");
  const double nu = sliding.material.poisson_ratio;
  if (!poisson_ratio_allowed(nu))
    throw std::invalid_argument("linear stability: material.poisson_ratio = " + std::to_string(nu) +
                                " is not allowed; it must lie in (" + shortest(kMinPoissonRatio) +
                                ", " + shortest(kMaxPoissonRatio) + ")");
  require_positive(sliding.strip_height, "strip_height");
  require_positive(sliding.normal_stress, "normal_stress");
  require_positive(sliding.driving_velocity, "driving_velocity");
  slipstrip::validate(sliding.friction);
}

// Everything about F that depends on the wavelength only; built once per wavelength
// so the contour sweeps do not allocate.
struct Characteristic {
  const SteadySliding& sliding;
  LinearisedFriction lin;
  double wavenumber;
  // Pole frequencies omega_p of S(k, s; H) on the imaginary axis (finite H only).
  std::vector<double> pole_frequencies;

  complex response(complex z) const { return slip_response(sliding, wavenumber, z); }

  // F itself (has the poles of S and the pole at g_phi).
  complex raw(complex z) const {
    return response(z) + z * (lin.strength_dv + lin.strength_dstate * lin.state_rate_dv /
                                                    (z - lin.state_rate_dstate));
  }

  // G = F (z - g_phi) prod_p (z - i w_p)(z + i w_p) / w_p^2 : same zeros as F in the
  // boxes used, but no poles, so the argument principle counts zeros only and the
  // contour sweep stays smooth next to the lossless strip resonances.
  complex regular(complex z) const {
    const double g_phi = lin.state_rate_dstate;
    if (sliding.two_bodies && !sliding.bottom_rigid) {
      // F (K_t + K_b) = K_t K_b + friction (K_t + K_b) / (z - g_phi): analytic
      // where S = K_t K_b / (K_t + K_b) has its poles (zeros of K_t + K_b, not
      // known in closed form); the poles of K_t and K_b are removed as below.
      const complex top = 2.0 * strip_response(sliding.material, sliding.strip_height, wavenumber, z);
      const complex bottom = 2.0 * strip_response(sliding.bottom_material, sliding.bottom_height, wavenumber, z);
      complex value = top * bottom * (z - g_phi) +
                      z * (lin.strength_dv * (z - g_phi) + lin.strength_dstate * lin.state_rate_dv) * (top + bottom);
      for (double w : pole_frequencies) value *= (z - complex(0.0, w)) * (z + complex(0.0, w)) / (w * w);
      return value;
    }
    complex value = response(z);
    for (double w : pole_frequencies) value *= (z - complex(0.0, w)) * (z + complex(0.0, w)) / (w * w);
    complex friction = z * (lin.strength_dv * (z - g_phi) + lin.strength_dstate * lin.state_rate_dv);
    for (double w : pole_frequencies) friction *= (z - complex(0.0, w)) * (z + complex(0.0, w)) / (w * w);
    return value * (z - g_phi) + friction;
  }

  bool near_removed_pole(complex z) const {
    for (double w : pole_frequencies)
      if (std::abs(z - complex(0.0, w)) < 1e-7 * w || std::abs(z + complex(0.0, w)) < 1e-7 * w)
        return true;
    return false;
  }
};

// Poles of S(k, s; H): sinh(alpha H) = 0 with the residues of strip_modes() that do
// not cancel: omega = c_s k (m = 0), c_s sqrt(k^2 + kappa^2), c_d sqrt(k^2 + kappa^2)
// (m >= 1, kappa = m pi / H).  The comb frequencies c_s kappa are NOT poles of S (the
// k-dependent part cancels the pole of coth(s H / c_s)); the tests check both facts.
std::vector<double> strip_pole_frequencies(const ElasticMaterial& material, double H, double k,
                                           double max_frequency) {
  std::vector<double> poles;
  if (is_half_space(H) || k == 0.0) return poles;  // k = 0: shear comb poles, not used here
  if (material.antiplane()) {
    // (mu/2) alpha coth(alpha H): poles where alpha H = i m pi, m >= 1 only
    // (m = 0 is regular: alpha coth(alpha H) -> 1/H), docs/bodies.md.
    // (every shear mode at or below max_frequency is listed: its comb
    // partner lies lower.)
    for (const auto& mode : strip_modes(material, H, k, max_frequency))
      if (mode.family == ModeFamily::shear) poles.push_back(mode.frequency);
    return poles;
  }
  const double cs = material.shear_wave_speed();
  const double cd = material.dilatational_wave_speed();
  if (cs * k <= max_frequency) poles.push_back(cs * k);
  for (int m = 1;; ++m) {
    const double kappa = m * pi / H;
    const double q = std::sqrt(k * k + kappa * kappa);
    if (cs * q > max_frequency) break;
    // Residue of the shear family vanishes when kappa == k (d2 = 0 in strip_modes).
    if (std::abs(kappa * kappa - k * k) > 1e-12 * kappa * kappa) poles.push_back(cs * q);
    if (cd * q <= max_frequency) poles.push_back(cd * q);
  }
  std::sort(poles.begin(), poles.end());
  // Coincident frequencies of different families are one (simple) pole, not two.
  poles.erase(std::unique(poles.begin(), poles.end(),
                          [](double x, double y) { return std::abs(x - y) <= 1e-13 * y; }),
              poles.end());
  return poles;
}

Characteristic make_characteristic(const SteadySliding& sliding, double wavelength,
                                   const SearchBox& box) {
  validate(sliding);
  require_positive(wavelength, "wavelength");
  const double k = 2.0 * pi / wavelength;
  const double reach = 2.0 * std::hypot(std::max(std::abs(box.min_re), std::abs(box.max_re)),
                                        box.max_im);
  std::vector<double> poles = strip_pole_frequencies(sliding.material, sliding.strip_height, k, reach);
  if (sliding.two_bodies && !sliding.bottom_rigid) {
    // Poles of K_b too (regular() multiplies by K_t K_b); a frequency shared
    // by both bodies is a double pole of K_t K_b.
    const auto bottom = strip_pole_frequencies(sliding.bottom_material, sliding.bottom_height, k, reach);
    poles.insert(poles.end(), bottom.begin(), bottom.end());
    std::sort(poles.begin(), poles.end());
  }
  return Characteristic{sliding, linearise_friction(sliding), k, std::move(poles)};
}

// A half-space body anywhere: branch cuts of S on the imaginary axis.
bool has_half_space(const SteadySliding& sliding) {
  return is_half_space(sliding.strip_height) ||
         (sliding.two_bodies && !sliding.bottom_rigid && is_half_space(sliding.bottom_height));
}

// The search box as a rectangle of the complex plane, checked.
Rectangle checked_rectangle(const SteadySliding& sliding, const SearchBox& box) {
  if (!(box.max_re > box.min_re) || !(box.max_im > 0.0))
    throw std::invalid_argument("count_roots: box must have max_re > min_re and max_im > 0");
  if (has_half_space(sliding) && !(box.min_re > 0.0))
    throw std::invalid_argument("count_roots: box.min_re = " + std::to_string(box.min_re) +
                                " with a half-space; it must be > 0 (branch cuts on Re = 0)");
  return Rectangle{box.min_re, box.max_re, -box.max_im, box.max_im};
}

bool has_unstable_root(const SteadySliding& sliding, double wavelength) {
  return count_roots(sliding, wavelength, unstable_search_box(sliding)) > 0;
}

}  // namespace

LinearisedFriction linearise_friction(const SteadySliding& sliding) {
  validate(sliding);
  const auto& f = sliding.friction;
  const double v0 = sliding.driving_velocity;
  const double s0 = sliding.normal_stress;
  const double phi0 = steady_state(f, v0);
  return LinearisedFriction{phi0, frictional_strength_dv(f, s0, v0, phi0),
                            frictional_strength_dstate(f, s0, v0, phi0),
                            state_rate_dv(f, v0, phi0), state_rate_dstate(f, v0, phi0)};
}

complex slip_response(const SteadySliding& sliding, double wavenumber, complex growth) {
  const double k = wavenumber;
  const complex z = growth;
  if (!sliding.two_bodies) return strip_response(sliding.material, sliding.strip_height, k, z);
  const complex top = 2.0 * strip_response(sliding.material, sliding.strip_height, k, z);
  if (sliding.bottom_rigid) return top;
  const complex bottom = 2.0 * strip_response(sliding.bottom_material, sliding.bottom_height, k, z);
  return top * bottom / (top + bottom);
}

complex characteristic_function(const SteadySliding& sliding, double wavenumber, complex growth) {
  validate(sliding);
  const Characteristic c{sliding, linearise_friction(sliding), wavenumber, {}};
  return c.raw(growth);
}

SearchBox unstable_search_box(const SteadySliding& sliding) {
  const LinearisedFriction lin = linearise_friction(sliding);
  if (!(lin.strength_dv > 0.0))
    throw std::invalid_argument("linear stability: d tau / d v = " + std::to_string(lin.strength_dv) +
                                " at the driving velocity; the search bound needs it > 0");
  // Roots with Re > 0 satisfy |Lambda - g_phi| <= radius (see header); the 1.0137
  // margin keeps roots off the contour and makes exact coincidences unlikely.
  const double radius = std::abs(lin.strength_dstate * lin.state_rate_dv) / lin.strength_dv;
  const double min_re = 1e-9 * radius;
  const double max_re = std::max(lin.state_rate_dstate + 1.0137 * radius, 2.0 * min_re);
  return SearchBox{min_re, max_re, 1.0137 * radius};
}

SearchBox damped_search_box(const SteadySliding& sliding) {
  if (has_half_space(sliding))
    throw std::invalid_argument("damped_search_box: strip_height = inf; the half-space response has "
                                "branch cuts on the imaginary axis, only Re Lambda > 0 is searched");
  SearchBox box = unstable_search_box(sliding);
  box.min_re = -0.9913 * box.max_im;
  return box;
}

int count_roots(const SteadySliding& sliding, double wavelength, const SearchBox& box) {
  const Rectangle r = checked_rectangle(sliding, box);
  const Characteristic c = make_characteristic(sliding, wavelength, box);
  return count_zeros([&c](complex z) { return c.regular(z); }, r);
}

std::vector<complex> characteristic_roots(const SteadySliding& sliding, double wavelength,
                                          const SearchBox& box) {
  const Rectangle r = checked_rectangle(sliding, box);
  const Characteristic c = make_characteristic(sliding, wavelength, box);
  const AnalyticFunction g = [&c](complex z) { return c.regular(z); };
  const double resolution = location_resolution(r);
  auto roots = locate_zeros(g, r, count_zeros(g, r), resolution);
  // Zeros of G sitting exactly on a removed pole frequency would be artefacts of the
  // pole removal (only possible if a listed frequency is not a true pole).
  std::erase_if(roots, [&](complex z) { return c.near_removed_pole(z); });
  sort_fastest_first(roots, resolution);
  return roots;
}

std::vector<complex> characteristic_roots(const SteadySliding& sliding, double wavelength) {
  return characteristic_roots(sliding, wavelength, unstable_search_box(sliding));
}

std::optional<complex> most_unstable_root(const SteadySliding& sliding, double wavelength) {
  const auto roots = characteristic_roots(sliding, wavelength);
  if (roots.empty()) return std::nullopt;
  return roots.front();
}

double critical_wavelength(const SteadySliding& sliding, double lower, double upper,
                           double relative_tolerance) {
  require_positive(lower, "lower wavelength");
  if (!(upper > lower))
    throw std::invalid_argument("critical_wavelength: upper = " + std::to_string(upper) +
                                " must exceed lower = " + std::to_string(lower));
  if (has_unstable_root(sliding, lower))
    throw std::invalid_argument("critical_wavelength: lower = " + std::to_string(lower) +
                                " m is already unstable; it must bracket Lc from below");
  if (!has_unstable_root(sliding, upper))
    throw std::invalid_argument("critical_wavelength: upper = " + std::to_string(upper) +
                                " m is stable; it must bracket Lc from above");
  // Bisection on the (provably complete) existence of an unstable root: it cannot
  // jump to a different branch the way root tracking could.
  while (upper - lower > relative_tolerance * upper) {
    const double mid = 0.5 * (lower + upper);
    (has_unstable_root(sliding, mid) ? upper : lower) = mid;
  }
  return 0.5 * (lower + upper);
}

std::vector<double> critical_wavelength_vs_height(const SteadySliding& sliding,
                                                  const std::vector<double>& heights) {
  SteadySliding half_space = sliding;
  half_space.strip_height = std::numeric_limits<double>::infinity();
  const double guess = quasi_static_critical_wavelength(half_space);
  if (!std::isfinite(guess))
    throw std::invalid_argument("critical_wavelength_vs_height: steady sliding is stable at every "
                                "wavelength (tau_v g_phi - tau_phi g_v <= 0)");
  std::vector<double> result;
  result.reserve(heights.size());
  constexpr int max_steps = 60;
  for (double H : heights) {
    SteadySliding s = sliding;
    s.strip_height = H;
    double lo = guess, hi = guess;
    for (int i = 0; i < max_steps && has_unstable_root(s, lo); ++i) lo *= 0.5;
    int doublings = 0;
    for (; doublings < max_steps && !has_unstable_root(s, hi); ++doublings) hi *= 2.0;
    // An antiplane strip does not bend: thin enough, it is too stiff at every k
    // and no wavelength is unstable (docs/stability.md, thin-strip limit).
    if (doublings == max_steps && !has_unstable_root(s, hi))
      throw std::invalid_argument("critical_wavelength_vs_height: H = " + shortest(H) +
                                  " m: no unstable wavelength; steady sliding is stable at every "
                                  "wavelength up to " + brief(hi) + " m");
    if (lo == hi) hi *= 1.0 + 1e-12;  // guess itself is the boundary (degenerate)
    result.push_back(critical_wavelength(s, lo, hi));
  }
  return result;
}

namespace {

// S(k, 0) of the sliding pair: the static limit of slip_response().
double static_slip_stiffness(const SteadySliding& sliding, double k) {
  if (!sliding.two_bodies) return strip_static_stiffness(sliding.material, sliding.strip_height, k);
  const double top = 2.0 * strip_static_stiffness(sliding.material, sliding.strip_height, k);
  if (sliding.bottom_rigid) return top;
  const double bottom = 2.0 * strip_static_stiffness(sliding.bottom_material, sliding.bottom_height, k);
  return top * bottom / (top + bottom);
}

// lim k -> 0+ of one body's S(k, 0) (strip_static_stiffness at k = 0 exactly is
// the uniform mode, a different limit in-plane): an in-plane strip bends, so its
// stiffness vanishes like E' H k^2 / 6; a half-space's like mu* k; an antiplane
// strip only shears across its height, mu/(2H).
double long_wave_static_stiffness(const ElasticMaterial& material, double H) {
  if (is_half_space(H) || !material.antiplane()) return 0.0;
  return 0.5 * material.shear_modulus / H;
}

double long_wave_slip_stiffness(const SteadySliding& sliding) {
  const double top = long_wave_static_stiffness(sliding.material, sliding.strip_height);
  if (!sliding.two_bodies) return top;
  if (sliding.bottom_rigid) return 2.0 * top;
  const double bottom = 2.0 * long_wave_static_stiffness(sliding.bottom_material, sliding.bottom_height);
  return top > 0.0 && bottom > 0.0 ? 2.0 * top * bottom / (2.0 * top + bottom) : 0.0;
}

}  // namespace

double quasi_static_critical_wavelength(const SteadySliding& sliding) {
  const LinearisedFriction lin = linearise_friction(sliding);
  const double stiffness_needed =
      lin.strength_dv * lin.state_rate_dstate - lin.strength_dstate * lin.state_rate_dv;
  if (!(stiffness_needed > 0.0)) return std::numeric_limits<double>::infinity();
  // The scalar series stiffness of two different bodies is the antiplane
  // problem's only (in-plane pairs couple slip to the normal stress).
  if (sliding.two_bodies && !sliding.material.antiplane())
    throw std::invalid_argument("quasi_static_critical_wavelength: in-plane pairs of different bodies are "
                                "analysed by stability/interface_stability");
  const ElasticMaterial& m = sliding.material;
  // Half-space static stiffness mu* |k|: in-plane mu (1 - c_s^2/c_d^2), antiplane mu/2.
  const double mu_star = m.antiplane() ? 0.5 * m.shear_modulus
                                       : m.shear_modulus * (1.0 - 1.0 / m.wave_speed_ratio_squared());
  const double k_half_space = stiffness_needed / mu_star;
  if (!sliding.two_bodies && is_half_space(sliding.strip_height)) return 2.0 * pi / k_half_space;
  // S0(k) = S(k, 0) increases strictly with k for every body (in-plane strip
  // mu* k (coth x - x / sinh^2 x), antiplane strip (mu k / 2) coth x, x = kH,
  // and their series combination), from its long-wave limit S0(0+) to infinity,
  // so a neutral wavenumber exists iff S0(0+) < K_c and is unique.  Where it lies
  // relative to the top half-space's k_half_space depends on the body: an in-plane
  // strip is softer than mu* k (root above), an antiplane strip stiffer than
  // mu k / 2 (root below), a pair either.  So expand from k_half_space both ways,
  // then bisect.
  const double long_wave = long_wave_slip_stiffness(sliding);
  if (!(long_wave < stiffness_needed)) {
    const std::string critical = "the critical stiffness tau_v g_phi - tau_phi g_v = " + brief(stiffness_needed) + " Pa/m";
    if (!sliding.two_bodies)
      throw std::invalid_argument(
          "quasi_static_critical_wavelength: H = " + shortest(sliding.strip_height) +
          " m: no unstable wavelength; the antiplane strip's static stiffness (mu k/2) coth(kH) exceeds mu/(2H) = " +
          brief(long_wave) + " Pa/m at every k (it shears but does not bend), which is not below " + critical +
          " (an unstable wavelength needs H > mu/(2 K_c) = " + brief(0.5 * m.shear_modulus / stiffness_needed) + " m)");
    throw std::invalid_argument(
        "quasi_static_critical_wavelength: H = " + shortest(sliding.strip_height) + " m on " +
        (sliding.bottom_rigid ? std::string("a rigid base")
                              : "a bottom body of height " + shortest(sliding.bottom_height) + " m") +
        ": no unstable wavelength; the pair's antiplane static stiffness S(k, 0) exceeds its long-wave limit " +
        brief(long_wave) + " Pa/m at every k (the strips shear but do not bend), which is not below " + critical);
  }
  double lo = k_half_space, hi = k_half_space;
  // S0(lo) -> S0(0+) < K_c as lo -> 0; the cap only guards against K_c within
  // rounding of S0(0+) (then the root is at k ~ 0: no finite Lc to report).
  for (int i = 0; static_slip_stiffness(sliding, lo) >= stiffness_needed; ++i) {
    if (i == 1000)
      throw std::invalid_argument("quasi_static_critical_wavelength: the neutral wavelength exceeds " +
                                  brief(2.0 * pi / lo) + " m (critical stiffness within rounding of "
                                  "the long-wave limit " + brief(long_wave) + " Pa/m)");
    lo *= 0.5;
  }
  while (static_slip_stiffness(sliding, hi) < stiffness_needed) hi *= 2.0;
  for (int i = 0; i < 200 && hi - lo > 1e-15 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (static_slip_stiffness(sliding, mid) < stiffness_needed ? lo : hi) = mid;
  }
  return 2.0 * pi / (0.5 * (lo + hi));
}

std::vector<GrowthRate> growth_rates(const SteadySliding& sliding,
                                     const std::vector<double>& wavelengths) {
  std::vector<GrowthRate> out;
  out.reserve(wavelengths.size());
  for (double L : wavelengths) {
    if (const auto z = most_unstable_root(sliding, L)) {
      out.push_back({L, z->real(), std::abs(z->imag()), true});
      continue;
    }
    const double nan = std::numeric_limits<double>::quiet_NaN();
    if (is_half_space(sliding.strip_height)) {
      out.push_back({L, nan, nan, false});
      continue;
    }
    const auto roots = characteristic_roots(sliding, L, damped_search_box(sliding));
    if (roots.empty())
      out.push_back({L, nan, nan, false});
    else
      out.push_back({L, roots.front().real(), std::abs(roots.front().imag()), false});
  }
  return out;
}

}  // namespace slipstrip
