// The config schema: the table of every key (config_keys) and what is derived
// from it without parsing a file: value text for to_toml, the TOML table for
// Python, allowed-range texts for messages (docs/config.md's key tables are
// written from it by config/config_docs.cpp).
// Adding a key: docs/developing.md, "Adding a config key".
#include "config/config_schema.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <sstream>

#include "config/friction_profile_toml.hpp"
#include "config/interface_law_name.hpp"
#include "config/resource_estimate.hpp"
#include "friction/friction_law.hpp"
#include "friction/parameter_profile.hpp"
#include "kernels/antiplane_response.hpp"
#include "kernels/elastic_material.hpp"
#include "kernels/interface_2d_history.hpp"
#include "kernels/passivity.hpp"

namespace slipstrip {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// The largest node count accepted: keeps N and N/2+1 spectral modes far from
// int overflow and any run within memory of one machine.
constexpr std::int64_t kMaxNodes = std::int64_t{1} << 24;
// A nonzero slip-sampling threshold below a picometre is a typo: every node
// writes one crossing time per delta_th of slip.
constexpr double kMinDeltaTh = 1e-12;

// ---------------------------------------------------------------------------
// Bindings: one member of one part of SimulationConfig (Part: &SimulationConfig::geometry,
// Member: &GeometryConfig::length).  Capture-less lambdas, so the table is constant.

template <auto Part, auto Member>
constexpr KeyBinding real_member() {
  return {.get_real = [](const SimulationConfig& c) -> double { return (c.*Part).*Member; },
          .set_real = [](SimulationConfig& c, double v) { (c.*Part).*Member = v; }};
}

template <auto Part, auto Member>
constexpr KeyBinding integer_member() {
  return {.get_integer = [](const SimulationConfig& c) -> std::int64_t {
            return static_cast<std::int64_t>((c.*Part).*Member);
          },
          .set_integer = [](SimulationConfig& c, std::int64_t v) {
            using Field = std::remove_reference_t<decltype((c.*Part).*Member)>;
            (c.*Part).*Member = static_cast<Field>(v);
          }};
}

// An enum member spelt by Names (index = enumerator).
template <auto Part, auto Member, const auto& Names>
constexpr KeyBinding enum_member() {
  return {.get_text = [](const SimulationConfig& c) -> std::string {
            const auto i = static_cast<std::size_t>((c.*Part).*Member);
            if (i >= std::size(Names)) throw std::logic_error("enum value outside its name table");
            return std::string(Names[i]);
          },
          .set_text = [](SimulationConfig& c, const std::string& name) {
            using Enum = std::remove_reference_t<decltype((c.*Part).*Member)>;
            const auto* at = std::find(std::begin(Names), std::end(Names), name);
            if (at == std::end(Names)) throw std::logic_error("name not in its enum table: " + name);
            (c.*Part).*Member = static_cast<Enum>(at - std::begin(Names));
          }};
}

template <const auto& Names>
std::vector<std::string_view> names_of() {
  return {std::begin(Names), std::end(Names)};
}

// A friction parameter: a scalar member of FrictionParameters and its optional
// profile in FrictionProfiles.  A profile leaves the scalar NaN, so nothing can
// use one value for the whole interface by accident (friction/parameter_profile.hpp).
template <auto Scalar, auto Profile>
constexpr KeyBinding friction_parameter() {
  return {.get_real = [](const SimulationConfig& c) -> double { return c.friction.*Scalar; },
          .set_real = [](SimulationConfig& c, double v) { c.friction.*Scalar = v; },
          .get_profile = [](const SimulationConfig& c) -> const std::optional<ParameterProfile>& {
            return c.friction_profiles.*Profile;
          },
          .set_profile = [](SimulationConfig& c, ParameterProfile p) {
            c.friction_profiles.*Profile = std::move(p);
            c.friction.*Scalar = std::numeric_limits<double>::quiet_NaN();
          }};
}

constexpr ValueRange positive{.low = 0.0};
constexpr ValueRange non_negative{.low = 0.0, .low_inclusive = true};

// ---------------------------------------------------------------------------
// Plausibility rules: warnings, never errors (docs/config.md, "Warnings").

// Above this H/L the strips slide as two half-spaces at every wavelength up
// to L (static stiffness coth(2 pi H/L) = 1 to ~1e-27, and echoes from the
// far boundary return only after 2H/c_s >= 20 L/c_s), yet a strip costs ~H/dx
// normal modes per Fourier mode.  The paper's complexity range is 0.01-0.1.
constexpr double kMaxPlausibleHeightRatio = 10.0;
// Normal stresses of friction experiments and faults: a kPa (soft
// materials) to a GPa; outside, the value is most likely in the wrong unit.
constexpr double kMinPlausibleNormalStress = 1e3;
constexpr double kMaxPlausibleNormalStress = 1e9;

std::string height_plausibility(const SimulationConfig& c) {
  const double ratio = c.geometry.height / c.geometry.length;
  if (is_half_space(c.geometry.height) || ratio <= kMaxPlausibleHeightRatio) return {};
  return "geometry.height = " + format_short(c.geometry.height) + " m is H/L = " + format_short(ratio) +
         " (geometry.length = " + format_short(c.geometry.length) +
         " m): strips this tall slide as two half-spaces at every wavelength up to L, but cost ~H/dx "
         "strip modes per Fourier mode (see the history operator above); if H is in mm, give it in m "
         "(5 cm = 0.05), or use geometry.height = \"inf\" for half-spaces";
}

std::string normal_stress_plausibility(const SimulationConfig& c) {
  const double sigma = c.loading.normal_stress;
  if (sigma >= kMinPlausibleNormalStress && sigma <= kMaxPlausibleNormalStress) return {};
  return "loading.normal_stress = " + format_short(sigma) + " Pa is outside " +
         format_short(kMinPlausibleNormalStress) + " ... " + format_short(kMaxPlausibleNormalStress) +
         " Pa, the normal stresses of friction experiments and faults: the key is in Pa (1 MPa = 1e6)";
}

std::string delta_th_plausibility(const SimulationConfig& c) {
  if (!(c.output.delta_th > 0.0)) return {};
  const double dt = estimate_resources(c).time_step;
  const double slip_per_step = c.loading.driving_velocity * dt;
  if (!(slip_per_step > c.output.delta_th)) return {};
  return "each time step slips v0 dt = " + format_short(slip_per_step) + " m = " +
         format_short(slip_per_step / c.output.delta_th) + " output.delta_th at the loading rate (loading." +
         "driving_velocity = " + format_short(c.loading.driving_velocity) + " m/s, dt = " + format_short(dt) +
         " s): slip levels crossed within one step get interpolated times (a coarser event catalog, "
         "a file growing with v0 t / delta_th); check that loading.driving_velocity is in m/s "
         "(2 mm/s = 2e-3), or raise output.delta_th";
}

// ---------------------------------------------------------------------------
// Rules that involve other keys or the physics.

void dx_rule(const SimulationConfig& c, double dx) {
  const double ratio = c.geometry.length / dx;
  const double whole = std::round(ratio);
  // dx must tile the period: a rounded N would silently change dx.  The
  // tolerance only absorbs the decimal representation of dx (e.g. 4/0.0025).
  if (std::abs(ratio - whole) > 1e-9 * ratio)
    throw ConfigRuleError({"dx"}, "geometry.dx = " + format_config_number(dx) +
                                      " does not divide geometry.length = " +
                                      format_config_number(c.geometry.length) +
                                      " into a whole number of nodes (length/dx = " +
                                      format_config_number(ratio) +
                                      "): expected dx = length/N with N an integer");
  if (whole < 8 || whole > static_cast<double>(kMaxNodes))
    throw KeyOutOfRange(format_config_number(dx),
                        "a spacing giving length/dx between 8 and " + std::to_string(kMaxNodes) +
                            " nodes (got " + format_config_number(whole) + ")");
}

// Mode numbers stay below Nyquist: mode N/2 has no sine partner on the grid.
void below_nyquist(const SimulationConfig& c, std::int64_t mode, std::string_view key) {
  const int half = c.geometry.nodes / 2;
  if (mode < 0 || mode >= half)
    throw KeyOutOfRange(std::to_string(mode), "an integer 0 <= " + std::string(key) +
                                                  " < nodes/2 = " + std::to_string(half));
}

void nodes_z_rule(const SimulationConfig& c, std::int64_t nodes_z) {
  if (nodes_z * c.geometry.nodes > kMaxNodes)
    throw KeyOutOfRange(std::to_string(nodes_z), "an integer with nodes x nodes_z <= " +
                                                     std::to_string(kMaxNodes) + " (nodes = " +
                                                     std::to_string(c.geometry.nodes) + ")");
}

void beta_rule(const SimulationConfig& c, double beta) {
  // Antiplane: 2/pi (docs/bodies.md), above the key's cap; in-plane:
  // 1/(pi (1 - c_s^2/c_d^2)).  A second body's operator runs at
  // c_b dt/dx <= beta (the step follows the faster body), so one limit serves both.
  // A 2D interface reaches |k| up to pi sqrt(1/dx^2 + 1/dz^2): the limits,
  // bounds on c_s |k| dt, scale down accordingly (docs/3d.md).
  const bool interface_2d = c.geometry.nodes_z > 1;
  const InterfaceGrid2d grid{c.geometry.length, c.geometry.width, c.geometry.nodes, c.geometry.nodes_z};
  auto scaled = [&](double limit) { return interface_2d ? interface_2d_beta_limit(grid, limit) : limit; };
  const char* where = interface_2d ? ", scaled by pi/(min(dx, dz) |k|_max) for the 2D interface" : "";
  const double beta_max = scaled(c.material.antiplane()
                                     ? antiplane_strip_passivity_beta_limit()
                                     : strip_passivity_beta_limit(c.material.wave_speed_ratio_squared()));
  if (beta > beta_max)
    throw KeyOutOfRange(format_config_number(beta),
                        "0 < beta <= " + format_config_number(std::floor(beta_max * 1e4) / 1e4) +
                            " for this material (1/(pi (1 - c_s^2/c_d^2)) in-plane, 2/pi antiplane" + where +
                            ", the limit of a passive discrete strip operator; docs/theory.md)");
  const bool any_half_space = is_half_space(c.geometry.height) ||
                              (c.bottom.body == BodyKind::elastic && is_half_space(c.bottom.height));
  const double half_space_max = scaled(kHalfSpaceBetaLimit);
  if (any_half_space && beta > half_space_max)
    throw KeyOutOfRange(format_config_number(beta),
                        "0 < beta <= " +
                            format_bound(interface_2d ? std::floor(half_space_max * 1e4) / 1e4 : kHalfSpaceBetaLimit) +
                            " for a half-space (geometry.height or bottom.height = \"inf\")" + where +
                            ": above it the sampled half-space kernel cannot be made passive at the "
                            "shortest wavelength; docs/theory.md");
}

void friction_rule(const SimulationConfig& c) {
  // The regularized law divides by a (exp(psi/a)); the others stay defined at
  // a = 0 because radiation damping alone fixes the slip rate.
  if (c.friction.strength_law == StrengthLaw::regularized && !c.friction_profiles.a &&
      !(c.friction.a > 0.0))
    throw ConfigRuleError({"a", "law"},
                          "friction.a = " + format_config_number(c.friction.a) +
                              " is out of range for friction.law = \"regularized\": expected a > 0");
  if (c.friction_profiles.any()) {
    // Every node's values against the scalar rules (a profile may not carry a
    // value its key would refuse as a number).
    try {
      (void)resolve_friction_nodes(c.friction, c.friction_profiles, friction_node_grid(c));
    } catch (const std::invalid_argument& e) {
      throw ConfigRuleError({}, e.what());
    }
  }
  // The Linker-Dieterich response divides by the state effect B (f0 b or b).
  if (c.friction.linker_dieterich > 0.0) {
    const auto no_state_effect = [](double b) { return !(b > 0.0); };
    bool refused = !c.friction_profiles.b && no_state_effect(c.friction.b);
    if (c.friction_profiles.b) {
      const FrictionNodeValues nodes = resolve_friction_nodes(c.friction, c.friction_profiles, friction_node_grid(c));
      refused = std::any_of(nodes.b.begin(), nodes.b.end(), no_state_effect);
    }
    if (refused)
      throw ConfigRuleError({"linker_dieterich", "b"},
                            "friction.linker_dieterich = " + format_config_number(c.friction.linker_dieterich) +
                                " needs friction.b > 0 (at every node): the state response is scaled by "
                                "1/B, B = f0 b (paper law) or b");
  }
}

void initial_rule(const SimulationConfig& c) {
  const InitialConfig& init = c.initial;
  if (init.local_amplitude != 0.0 && !(init.local_width > 0.0))
    throw ConfigRuleError({"local_amplitude", "local_width"},
                          "initial.local_amplitude = " + format_config_number(init.local_amplitude) +
                              " needs initial.local_width > 0 [m] (got " +
                              format_config_number(init.local_width) +
                              "): the perturbation is a Gaussian of that standard deviation");
  if (init.local_width_z > 0.0 && c.geometry.nodes_z == 1)
    throw ConfigRuleError({"local_width_z"},
                          "initial.local_width_z = " + format_config_number(init.local_width_z) +
                              " on a one-dimensional interface (geometry.nodes_z = 1): expected 0 (the bump "
                              "is a Gaussian in x; its width in z needs a 2D interface)");
}

// A position on the periodic interface: 0 <= x <= L for a point such as a bump's
// centre, 0 <= x < L for stations (x = L is the node at x = 0 again).
void require_on_interface(double x, double length, bool closed_at_length, const std::string& noun) {
  const bool inside = x >= 0.0 && (closed_at_length ? x <= length : x < length);
  if (!inside)
    throw KeyOutOfRange(format_config_number(x), noun + " 0 <= x " + (closed_at_length ? "<=" : "<") +
                                                     " geometry.length = " + format_config_number(length) + " [m]");
}

// A station of a 2D interface is a point (x, z): the two lists pair up.
void output_rule(const SimulationConfig& c) {
  const auto& o = c.output;
  const auto count = [](const std::vector<double>& v) { return std::to_string(v.size()); };
  if (c.geometry.nodes_z > 1 && o.stations_z.size() != o.stations.size())
    throw ConfigRuleError({"stations_z", "stations"},
                          "output.stations_z has " + count(o.stations_z) + " positions and output.stations " +
                              count(o.stations) + ": on a 2D interface (geometry.nodes_z > 1) give one z per "
                              "station (station i is at (stations[i], stations_z[i]))");
  if (c.geometry.nodes_z == 1 && !o.stations_z.empty())
    throw ConfigRuleError({"stations_z"}, "output.stations_z has " + count(o.stations_z) +
                                              " positions on a one-dimensional interface (geometry.nodes_z = 1): "
                                              "expected [] (stations are positions x only)");
}

// [top] and [bottom] (docs/bodies.md).  In-plane pairs other than two
// identical driven strips run through the per-body 2x2 operators: the modal one
// of a finite strip (FaceModalHistory) or a half-space's (FaceHalfSpaceHistory).
void bottom_rule(const SimulationConfig& c) {
  const bool inplane = !c.material.antiplane();
  const bool clamped = c.top.outer_face == OuterFace::clamped || c.bottom.outer_face == OuterFace::clamped;
  if (c.bottom.body == BodyKind::mirror && c.bottom.outer_face != c.top.outer_face)
    throw ConfigRuleError({"outer_face", "body"},
                          "bottom.outer_face differs from top.outer_face but bottom.body = \"mirror\" "
                          "(the mirror image of the top body); set bottom.body = \"elastic\"");
  if (inplane && c.bottom.body == BodyKind::mirror && clamped)
    throw ConfigRuleError({"outer_face", "body"},
                          "outer_face = \"clamped\" in-plane needs bottom.body = \"elastic\" or \"rigid\" "
                          "(the per-body operators); the mirror pair's operator has driven faces");
}

// loading.drive = "mean_slip_rate" solves for one uniform shear stress around
// the batch friction solve of two identical bodies (laws/law_rate_and_state.cpp):
// refused where that is not the path of the run.
std::string mean_slip_rate_refusal(const std::string& what, const std::string& allowed) {
  return "loading.drive = \"mean_slip_rate\" is not supported with " + what + ": expected " + allowed +
         " (or loading.drive = \"outer_faces\"; docs/transition.md)";
}
void loading_rule(const SimulationConfig& c) {
  if (c.loading.drive != LoadingDrive::mean_slip_rate) return;
  if (c.bottom.body != BodyKind::mirror)
    throw ConfigRuleError({"drive"}, mean_slip_rate_refusal(
                                         "bottom.body = \"" + std::string(kBodyKindNames[static_cast<int>(c.bottom.body)]) + "\"",
                                         "bottom.body = \"mirror\" (two identical strips or half-spaces)"));
  if (c.geometry.nodes_z > 1)
    throw ConfigRuleError({"drive"}, mean_slip_rate_refusal("geometry.nodes_z = " + std::to_string(c.geometry.nodes_z),
                                                            "geometry.nodes_z = 1 (a one-dimensional interface)"));
}

// Two forms of the normal-stress memory, one at a time (docs/bodies.md).
void interface_rule(const SimulationConfig& c) {
  if (c.loading.drive == LoadingDrive::mean_slip_rate && c.interface.law != InterfaceLawName::rate_and_state)
    throw ConfigRuleError({"law"}, mean_slip_rate_refusal("interface.law = \"" + std::string(c.interface.law.name) + "\"",
                                                          "interface.law = \"rate_and_state\""));
  if (c.interface.normal_stress_slip > 0.0 && c.interface.normal_stress_time > 0.0)
    throw ConfigRuleError({"normal_stress_time", "normal_stress_slip"},
                          "interface.normal_stress_slip = " + format_config_number(c.interface.normal_stress_slip) +
                              " and interface.normal_stress_time = " +
                              format_config_number(c.interface.normal_stress_time) +
                              ": give one of them (slip-scale or time-scale relaxation), not both");
  // In-plane dissimilar bodies relax sigma_eff over one length L_sigma; 0
  // takes friction.characteristic_slip, which has no single value when it is a
  // profile.
  if (c.bottom.body != BodyKind::mirror && !c.material.antiplane() && c.friction_profiles.characteristic_slip &&
      c.interface.normal_stress_slip == 0.0 && c.interface.normal_stress_time == 0.0)
    throw ConfigRuleError({"normal_stress_slip", "characteristic_slip"},
                          "interface.normal_stress_slip = 0 takes friction.characteristic_slip, which is a profile "
                          "here: expected interface.normal_stress_slip > 0 or interface.normal_stress_time > 0 "
                          "(in-plane dissimilar bodies relax the normal stress over one length)");
}

// With bottom.body = "mirror" a [bottom] value must be the top body's (what
// to_toml writes): a config giving another value but forgetting
// body = "elastic" is refused instead of run as a mirror pair.
void require_mirror_value(const SimulationConfig& c, double value, double top_value, std::string_view key,
                          const std::string& top_key) {
  if (c.bottom.body != BodyKind::mirror) return;
  const bool same = value == top_value || std::abs(value - top_value) <= 1e-12 * std::abs(top_value);
  if (!same)
    throw ConfigRuleError({key, "body"}, "bottom." + std::string(key) + " = " + format_config_number(value) +
                                             " differs from " + top_key + " = " + format_config_number(top_value) +
                                             " but bottom.body = \"mirror\" (the mirror image of the top body); "
                                             "set bottom.body = \"elastic\" to describe another bottom body");
}

// A [bottom] number: its member, read through the mirror (the top body's
// value) when body = "mirror".
template <auto Member, auto TopValue>
constexpr KeyBinding bottom_member() {
  return {.get_real = [](const SimulationConfig& c) -> double {
            return c.bottom.body == BodyKind::mirror ? TopValue(c) : c.bottom.*Member;
          },
          .set_real = [](SimulationConfig& c, double v) { c.bottom.*Member = v; }};
}
constexpr double top_shear_modulus(const SimulationConfig& c) { return c.material.shear_modulus; }
constexpr double top_poisson_ratio(const SimulationConfig& c) { return c.material.poisson_ratio; }
constexpr double top_density(const SimulationConfig& c) { return c.material.density; }
constexpr double top_height(const SimulationConfig& c) { return c.geometry.height; }

// ---------------------------------------------------------------------------
// The sections, in reading order: a rule reads only keys of earlier sections
// (geometry bounds the mode numbers, material sets c_s for duration_transits).
constexpr ConfigSection kSections[] = {
    {"geometry"}, {"material"}, {"top"}, {"bottom", bottom_rule}, {"loading", loading_rule}, {"friction", friction_rule}, {"state"},
    {"interface", interface_rule}, {"initial", initial_rule}, {"time"}, {"output", output_rule},
};

using C = SimulationConfig;

// The keys.  Within a section, the order is that of to_toml and of the docs.
constexpr ConfigKey kKeys[] = {
    // [geometry] ------------------------------------------------------------
    {.section = "geometry", .name = "length", .unit = "m", .noun = "a length",
     .allowed = positive, .generous = {1e-6, true, 1e6, true},
     .help = "L, the period along the interface",
     .comment = "L [m], period along the interface",
     .bind = real_member<&C::geometry, &GeometryConfig::length>()},
    {.section = "geometry", .name = "height", .type = KeyType::number_or_inf, .unit = "m",
     .noun = "a height", .allowed = positive, .allowed_note = " or \"inf\" (half-space)",
     .generous = {1e-6, true, 1e6, true},
     .help = "H, height of each of the two strips; `\"inf\"` (or TOML `inf`) = two half-spaces",
     .comment = "H [m] of each strip; \"inf\" = half-space",
     .bind = real_member<&C::geometry, &GeometryConfig::height>(),
     .plausibility = height_plausibility,
     .plausibility_text = "H/L > 10: the strips slide as half-spaces at every wavelength up to L but cost "
                          "~H/dx strip modes per Fourier mode (a height in mm?)"},
    {.section = "geometry", .name = "nodes", .type = KeyType::integer, .noun = "an integer",
     .allowed = {8.0, true, static_cast<double>(kMaxNodes), true},
     .help = "N interface nodes, dx = L/N", .comment = "N, dx = L/N",
     .bind = integer_member<&C::geometry, &GeometryConfig::nodes>()},
    {.section = "geometry", .name = "dx", .unit = "m", .noun = "a node spacing",
     .allowed = positive, .rule_text = "L/dx a whole number (to 1e-9 relative) in the range of `nodes`",
     .help = "node spacing L/N", .alternative_to = "nodes",
     .bind = {.set_real = [](C& c, double dx) {
       c.geometry.nodes = static_cast<int>(std::round(c.geometry.length / dx));
     }},
     .real_rule = dx_rule},
    {.section = "geometry", .name = "width", .unit = "m", .noun = "a length",
     .allowed = positive, .generous = {1e-6, true, 1e6, true},
     .help = "L_z, the period across the interface (along z); used when `nodes_z` > 1 (docs/3d.md)",
     .comment = "L_z [m], period along z (2D interface: nodes_z > 1)",
     .bind = real_member<&C::geometry, &GeometryConfig::width>()},
    {.section = "geometry", .name = "nodes_z", .type = KeyType::integer, .noun = "an integer",
     .allowed = {1.0, true, static_cast<double>(kMaxNodes), true},
     .rule_text = "nodes x nodes_z <= 2^24",
     .help = "nodes along z, dz = width/nodes_z; 1 = a one-dimensional interface (the 2D problem), "
             "> 1 = a 2D interface between 3D bodies (docs/3d.md)",
     .comment = "N_z; 1 = 2D problem",
     .bind = integer_member<&C::geometry, &GeometryConfig::nodes_z>(),
     .integer_rule = nodes_z_rule},

    // [material] ------------------------------------------------------------
    {.section = "material", .name = "shear_modulus", .unit = "Pa", .noun = "a modulus",
     .allowed = positive, .generous = {1.0, true, 1e13, true}, .help = "mu (Table S1)",
     .comment = "mu [Pa]", .bind = real_member<&C::material, &ElasticMaterial::shear_modulus>()},
    {.section = "material", .name = "youngs_modulus", .unit = "Pa", .noun = "a modulus",
     .allowed = positive, .generous = {1.0, true, 1e13, true},
     .help = "Young's modulus E; mu = E / (2 (1 + nu)) (finite-element codes take E and nu)",
     .alternative_to = "shear_modulus",
     .bind = {.set_real = [](C& c, double E) {
       c.material.shear_modulus = E / (2.0 * (1.0 + c.material.poisson_ratio));
     }}},
    {.section = "material", .name = "poisson_ratio", .noun = "poisson_ratio",
     .allowed = {kMinPoissonRatio, false, kMaxPoissonRatio, false},
     .help = "nu (Table S1); nu >= 0.5 makes the plane-strain c_d infinite",
     .comment = "nu [-]", .bind = real_member<&C::material, &ElasticMaterial::poisson_ratio>()},
    {.section = "material", .name = "density", .unit = "kg/m^3", .noun = "a density",
     .allowed = positive, .generous = {1e-3, true, 1e6, true},
     .help = "rho (Table S1); c_s = sqrt(mu/rho)", .comment = "rho [kg/m^3]",
     .bind = real_member<&C::material, &ElasticMaterial::density>()},
    {.section = "material", .name = "plane", .type = KeyType::choice,
     .help = "in-plane plane strain or plane stress (sets c_d/c_s; slip along x), or `antiplane` "
             "(slip along z, SH waves only; docs/bodies.md)",
     .choices = names_of<kPlaneConditionNames>,
     .bind = enum_member<&C::material, &ElasticMaterial::plane, kPlaneConditionNames>()},

    // [top] -----------------------------------------------------------------
    {.section = "top", .name = "outer_face", .type = KeyType::choice,
     .help = "the top body's outer face: `driven` (tangential displacement moving with its share "
             "of v0, normal stress prescribed) or `clamped` (both displacements prescribed; in-plane "
             "with bottom.body = `elastic` or `rigid`; antiplane, where it is the same body response). "
             "The top body's material and "
             "height are [material] and geometry.height (docs/bodies.md)",
     .choices = names_of<kOuterFaceNames>,
     .bind = enum_member<&C::top, &TopBodyConfig::outer_face, kOuterFaceNames>()},
    {.section = "top", .name = "velocity_share", .noun = "velocity_share",
     .allowed = {0.0, true, 1.0, true},
     .help = "the top outer face moves at +share v0, the bottom one at -(1 - share) v0; only v0 "
             "loads the interface, so this sets the frame and changes no interface field",
     .comment = "top face at +share v0, bottom at -(1 - share) v0",
     .bind = real_member<&C::top, &TopBodyConfig::velocity_share>()},

    // [bottom] --------------------------------------------------------------
    {.section = "bottom", .name = "body", .type = KeyType::choice,
     .help = "`mirror`: the mirror image of the top body (two identical bodies); `elastic`: the "
             "body described by the keys below (with `mirror` they must equal the top body's values, "
             "and a --set of a top key carries over to them); `rigid`: a rigid base, "
             "whose face does not deform. docs/bodies.md; on a 2D interface (geometry.nodes_z > 1) docs/3d.md",
     .choices = names_of<kBodyKindNames>,
     .bind = enum_member<&C::bottom, &BottomBodyConfig::body, kBodyKindNames>()},
    {.section = "bottom", .name = "shear_modulus", .unit = "Pa", .noun = "a modulus",
     .allowed = positive, .generous = {1.0, true, 1e13, true},
     .rule_text = "equal to material.shear_modulus when body = \"mirror\"",
     .help = "mu of the bottom body", .comment = "mu [Pa]",
     .bind = bottom_member<&BottomBodyConfig::shear_modulus, top_shear_modulus>(),
     .real_rule = [](const C& c, double v) {
       require_mirror_value(c, v, c.material.shear_modulus, "shear_modulus", "material.shear_modulus");
     }},
    {.section = "bottom", .name = "youngs_modulus", .unit = "Pa", .noun = "a modulus",
     .allowed = positive, .generous = {1.0, true, 1e13, true},
     .help = "Young's modulus E of the bottom body; mu = E / (2 (1 + nu))",
     .alternative_to = "shear_modulus",
     .bind = {.set_real = [](C& c, double E) {
       c.bottom.shear_modulus = E / (2.0 * (1.0 + bottom_material(c).poisson_ratio));
     }},
     .real_rule = [](const C& c, double E) {
       require_mirror_value(c, E / (2.0 * (1.0 + c.material.poisson_ratio)), c.material.shear_modulus,
                            "youngs_modulus", "material.shear_modulus");
     }},
    {.section = "bottom", .name = "poisson_ratio", .noun = "poisson_ratio",
     .allowed = {kMinPoissonRatio, false, kMaxPoissonRatio, false},
     .rule_text = "equal to material.poisson_ratio when body = \"mirror\"",
     .help = "nu of the bottom body", .comment = "nu [-]",
     .bind = bottom_member<&BottomBodyConfig::poisson_ratio, top_poisson_ratio>(),
     .real_rule = [](const C& c, double v) {
       require_mirror_value(c, v, c.material.poisson_ratio, "poisson_ratio", "material.poisson_ratio");
     }},
    {.section = "bottom", .name = "density", .unit = "kg/m^3", .noun = "a density",
     .allowed = positive, .generous = {1e-3, true, 1e6, true},
     .rule_text = "equal to material.density when body = \"mirror\"",
     .help = "rho of the bottom body", .comment = "rho [kg/m^3]",
     .bind = bottom_member<&BottomBodyConfig::density, top_density>(),
     .real_rule = [](const C& c, double v) {
       require_mirror_value(c, v, c.material.density, "density", "material.density");
     }},
    {.section = "bottom", .name = "height", .type = KeyType::number_or_inf, .unit = "m",
     .noun = "a height", .allowed = positive, .allowed_note = " or \"inf\" (half-space)",
     .generous = {1e-6, true, 1e6, true},
     .rule_text = "equal to geometry.height when body = \"mirror\"",
     .help = "H_b of the bottom body; `\"inf\"` = a half-space. Its shear echo 2H_b/c_b is rounded "
             "to whole time steps (relative change reported, refused above 1e-3; docs/bodies.md)",
     .comment = "H_b [m]; \"inf\" = half-space",
     .bind = bottom_member<&BottomBodyConfig::height, top_height>(),
     .real_rule = [](const C& c, double v) {
       require_mirror_value(c, v, c.geometry.height, "height", "geometry.height");
     }},
    {.section = "bottom", .name = "outer_face", .type = KeyType::choice,
     .help = "the bottom body's outer face, as top.outer_face",
     .choices = names_of<kOuterFaceNames>,
     .bind = enum_member<&C::bottom, &BottomBodyConfig::outer_face, kOuterFaceNames>()},

    // [loading] -------------------------------------------------------------
    {.section = "loading", .name = "driving_velocity", .unit = "m/s", .noun = "a velocity",
     .allowed = positive, .generous = {1e-15, true, 1e3, true},
     .help = "v0; outer faces move at +-v0/2, or the mean slip rate is held at v0 (`drive`); the initial "
             "state is steady sliding at v0",
     .comment = "v0 [m/s]", .bind = real_member<&C::loading, &LoadingConfig::driving_velocity>()},
    {.section = "loading", .name = "drive", .type = KeyType::choice,
     .rule_text = "`mean_slip_rate` needs bottom.body = \"mirror\", geometry.nodes_z = 1 and "
                  "interface.law = \"rate_and_state\"",
     .help = "what loads the uniform (k = 0) mode: `outer_faces`, the outer faces move at +-v0/2 (a "
             "half-space's uniform mode then has only radiation damping, so a locked half-space interface is "
             "never reloaded); `mean_slip_rate`, a uniform shear stress tau_0(t), solved for at every step, "
             "keeps the mean slip rate over the nodes at v0 (the modes k != 0 are unchanged; tau_0 is recorded "
             "as /timeseries/loading_shear_stress). Two identical bodies (strips or half-spaces) only "
             "(docs/transition.md)",
     .comment = "outer_faces | mean_slip_rate (tau_0(t) keeps the mean slip rate at v0)",
     .choices = names_of<kLoadingDriveNames>,
     .bind = enum_member<&C::loading, &LoadingConfig::drive, kLoadingDriveNames>()},
    {.section = "loading", .name = "normal_stress", .unit = "Pa", .noun = "a compressive stress",
     .allowed = positive, .generous = {1.0, true, 1e11, true}, .help = "sigma0, compressive",
     .comment = "sigma0 [Pa]", .bind = real_member<&C::loading, &LoadingConfig::normal_stress>(),
     .plausibility = normal_stress_plausibility,
     .plausibility_text = "outside 1 kPa ... 1 GPa, the normal stresses of friction experiments and "
                          "faults (MPa written as Pa?)"},

    // [friction] ------------------------------------------------------------
    {.section = "friction", .name = "law", .type = KeyType::choice,
     .help = "strength law (friction/friction_law.hpp)", .choices = names_of<kStrengthLawNames>,
     .bind = enum_member<&C::friction, &FrictionParameters::strength_law, kStrengthLawNames>()},
    {.section = "friction", .name = "f0", .type = KeyType::friction_parameter, .noun = "f0",
     .allowed = positive, .generous = {.high = kMaxFrictionCoefficient, .high_inclusive = true},
     .help = "reference friction coefficient", .comment = "[-]",
     .bind = friction_parameter<&FrictionParameters::f0, &FrictionProfiles::f0>()},
    {.section = "friction", .name = "a", .type = KeyType::friction_parameter, .noun = "a",
     .allowed = non_negative, .generous = {.high = kMaxFrictionCoefficient, .high_inclusive = true},
     .rule_text = "> 0 for `\"regularized\"`, which divides by a",
     .help = "direct (rate) effect; steady sliding strengthens with velocity (is stable) where a > f0 b "
             "in the paper law (for v >> v*), a > b in the DR forms (docs/friction.md)",
     .comment = "[-]",
     .bind = friction_parameter<&FrictionParameters::a, &FrictionProfiles::a>()},
    {.section = "friction", .name = "b", .type = KeyType::friction_parameter, .noun = "b",
     .allowed = non_negative, .generous = {.high = kMaxFrictionCoefficient, .high_inclusive = true},
     .help = "state effect; in the paper law (Eq. S1) it multiplies f0, so the Dieterich-Ruina b is "
             "f0 b (0.021 for Table S1); in the DR forms it is the DR b itself (docs/friction.md)",
     .comment = "[-]",
     .bind = friction_parameter<&FrictionParameters::b, &FrictionProfiles::b>()},
    {.section = "friction", .name = "characteristic_slip", .type = KeyType::friction_parameter,
     .unit = "m", .noun = "a slip distance D", .allowed = positive,
     .generous = {kMinCharacteristicSlip, true, kMaxCharacteristicSlip, true},
     .help = "D, the characteristic slip of state evolution", .comment = "D [m]",
     .bind = friction_parameter<&FrictionParameters::characteristic_slip,
                                &FrictionProfiles::characteristic_slip>()},
    {.section = "friction", .name = "v_star", .unit = "m/s", .noun = "a velocity v*",
     .allowed = positive, .generous = {1e-20, true, 1e3, true}, .help = "v*, reference slip rate",
     .comment = "v* [m/s]", .bind = real_member<&C::friction, &FrictionParameters::v_star>()},
    {.section = "friction", .name = "phi_star", .unit = "s", .noun = "a time phi*",
     .allowed = positive, .generous = {1e-15, true, 1e15, true}, .help = "phi*, reference state",
     .comment = "phi* [s]", .bind = real_member<&C::friction, &FrictionParameters::phi_star>()},
    // Measured alpha_LD are 0.2-0.6 (Linker & Dieterich 1992; Richardson & Marone
    // 1999); a value above f0 would make the friction drop as the compression
    // rises, so the generous range stops at 1.
    {.section = "friction", .name = "linker_dieterich", .noun = "alpha_LD",
     .allowed = non_negative, .generous = {0.0, true, 1.0, true},
     .rule_text = "> 0 needs friction.b > 0",
     .help = "alpha_LD, the Linker & Dieterich (1992) state response to normal-stress changes: "
             "d ln(phi)/dt gains -(alpha_LD/B) d ln(sigma_eff)/dt (B = f0 b for the paper law, b for "
             "the DR forms), so a step of normal stress changes the friction coefficient by "
             "-alpha_LD ln(sigma ratio) through the state. Acts where sigma varies (in-plane "
             "dissimilar bodies); 0 = off (docs/bodies.md)",
     .comment = "alpha_LD [-]; 0 = off (dissimilar in-plane pairs)",
     .bind = real_member<&C::friction, &FrictionParameters::linker_dieterich>()},

    // [state] ---------------------------------------------------------------
    {.section = "state", .name = "law", .type = KeyType::choice,
     .help = "aging: Eq. S2 with the sqrt(1 + (v*/v)^2) regularisation; slip: Eq. 2",
     .choices = names_of<kStateLawNames>,
     .bind = enum_member<&C::friction, &FrictionParameters::state_law, kStateLawNames>()},

    // [interface] -----------------------------------------------------------
    {.section = "interface", .name = "law", .type = KeyType::choice,
     .help = "how the interface closes the problem: the registered laws "
             "(config/interface_laws.inc); `prescribed_slip` and `free` are verification modes "
             "(docs/developing.md: adding a law)",
     .choices = names_of<kBuiltinInterfaceLawNames>,
     .bind = {.get_text = [](const C& c) { return std::string(c.interface.law.name); },
              .set_text = [](C& c, const std::string& name) {
                // The name kept is the built-in list's (static storage), not the parsed string.
                const auto* entry = std::find(std::begin(kBuiltinInterfaceLawNames),
                                              std::end(kBuiltinInterfaceLawNames), name);
                if (entry == std::end(kBuiltinInterfaceLawNames))
                  throw std::logic_error("unregistered interface law " + name);
                c.interface.law = InterfaceLawName{*entry};
              }}},
    {.section = "interface", .name = "slip_amplitude", .unit = "m",
     .help = "prescribed_slip: slip = amplitude cos(2 pi mode x/L) g(t)",
     .comment = "[m] (prescribed_slip)",
     .bind = real_member<&C::interface, &InterfaceConfig::slip_amplitude>()},
    {.section = "interface", .name = "mode", .type = KeyType::integer,
     .rule_text = "0 <= mode < N/2", .help = "prescribed_slip: mode number m (0 = uniform slip)",
     .comment = "m (prescribed_slip)", .bind = integer_member<&C::interface, &InterfaceConfig::mode>(),
     .integer_rule = [](const C& c, std::int64_t m) { below_nyquist(c, m, "mode"); }},
    {.section = "interface", .name = "profile", .type = KeyType::choice,
     .help = "g(t): ramp (1 - cos(pi t/T))/2 then 1; bump sin^4(pi t/T) on [0, T]",
     .choices = names_of<kTimeProfileNames>,
     .bind = enum_member<&C::interface, &InterfaceConfig::profile, kTimeProfileNames>()},
    {.section = "interface", .name = "rise_time", .unit = "s", .noun = "a time",
     .allowed = positive, .help = "T of the profile", .comment = "T [s]",
     .bind = real_member<&C::interface, &InterfaceConfig::rise_time>()},
    {.section = "interface", .name = "stress_amplitude", .unit = "Pa",
     .help = "free: imposed shear-stress pulse amplitude", .comment = "[Pa] (free)",
     .bind = real_member<&C::interface, &InterfaceConfig::stress_amplitude>()},
    {.section = "interface", .name = "load_pulse_amplitude", .unit = "Pa",
     .help = "rate_and_state: extra shear load P0 g(x) profile(t) added to the interface load "
             "(g: the Gaussian of `pulse_center`/`pulse_width`; profile: `profile`/`rise_time`), "
             "a smooth trigger used by the benchmark docs/benchmarks/strip_pulse_problem.md; "
             "0 = off",
     .comment = "[Pa] extra shear-load pulse on the rate_and_state interface (same shape); 0 = off",
     .bind = real_member<&C::interface, &InterfaceConfig::load_pulse_amplitude>()},
    {.section = "interface", .name = "normal_stress_slip", .unit = "m", .noun = "a length",
     .allowed = non_negative, .allowed_note = " (0 = friction.characteristic_slip)",
     .generous = {0.0, true, 1.0, true},
     .help = "in-plane dissimilar bodies: L_sigma of the normal-stress memory; the friction sees "
             "sigma_eff with d sigma_eff/dt = -((|v| + v*)/L_sigma)(sigma_eff - sigma) (Prakash & Clifton "
             "1993; Cochard & Rice 2000); 0 = friction.characteristic_slip (refused when that is a profile, "
             "unless normal_stress_time > 0). Identical bodies keep "
             "sigma = sigma0 and do not use it (docs/bodies.md)",
     .comment = "L_sigma [m]; 0 = friction.characteristic_slip (dissimilar in-plane pairs)",
     .bind = real_member<&C::interface, &InterfaceConfig::normal_stress_slip>()},
    {.section = "interface", .name = "normal_stress_time", .unit = "s", .noun = "a time",
     .allowed = non_negative, .allowed_note = " (0 = off)",
     .generous = {0.0, true, 1e3, true},
     .help = "in-plane dissimilar bodies: > 0 relaxes sigma_eff over this fixed time instead, "
             "d sigma_eff/dt = -(sigma_eff - sigma)/t_sigma (Prakash 1998); 0 = the slip form above",
     .comment = "t_sigma [s]; 0 = off (use normal_stress_slip)",
     .bind = real_member<&C::interface, &InterfaceConfig::normal_stress_time>()},
    {.section = "interface", .name = "opening", .type = KeyType::choice,
     .help = "in-plane dissimilar bodies, where the compressive normal stress would become <= 0: "
             "`open` separates the faces there (zero shear and normal traction, the gap recorded as "
             "`opening`, contact again when the gap closes); `stop` ends the run with an error naming "
             "the node and the time (docs/bodies.md). Identical bodies never open",
     .comment = "open | stop (dissimilar in-plane pairs)",
     .choices = names_of<kOpeningResponseNames>,
     .bind = enum_member<&C::interface, &InterfaceConfig::opening, kOpeningResponseNames>()},
    {.section = "interface", .name = "pulse_center", .unit = "m", .help = "free: pulse centre x0",
     .comment = "x0 [m] (free)", .bind = real_member<&C::interface, &InterfaceConfig::pulse_center>()},
    {.section = "interface", .name = "pulse_width", .type = KeyType::number_or_inf, .unit = "m",
     .noun = "a width", .allowed = positive, .allowed_note = " or \"inf\" (uniform stress)",
     .help = "free: Gaussian standard deviation; `\"inf\"` = uniform",
     .comment = "w [m] (free); \"inf\" = uniform",
     .bind = real_member<&C::interface, &InterfaceConfig::pulse_width>()},

    // [initial] -------------------------------------------------------------
    {.section = "initial", .name = "noise_amplitude", .noun = "a relative amplitude",
     .allowed = non_negative, .help = "relative std of the noise (paper: \"small amplitude\")",
     .comment = "relative std of the noise in phi",
     .bind = real_member<&C::initial, &InitialConfig::noise_amplitude>()},
    {.section = "initial", .name = "noise_seed", .type = KeyType::integer, .noun = "an integer",
     .allowed = non_negative, .help = "seed of the noise generator", .comment = "seed of the noise",
     .bind = integer_member<&C::initial, &InitialConfig::noise_seed>()},
    // White noise per node is what the paper's "small amplitude" noise most
    // likely was, but it is a different field on every mesh; a band-limited
    // field is the same on every mesh, so a refinement study changes only the
    // discretisation (docs/fig5_resolution.md).
    {.section = "initial", .name = "noise_modes", .type = KeyType::integer,
     .rule_text = "0 <= M < N/2",
     .help = "0: independent noise per node (white); M > 0: the first M Fourier modes with random "
             "normal coefficients, the same field on every mesh with N/2 > M",
     .comment = "0 = white noise per node; M = first M Fourier modes (mesh-independent)",
     .bind = integer_member<&C::initial, &InitialConfig::noise_modes>(),
     .integer_rule = [](const C& c, std::int64_t m) { below_nyquist(c, m, "noise_modes"); }},
    // |eps| < 1 keeps phi_ss (1 + eps sin) positive everywhere.
    {.section = "initial", .name = "sine_amplitude", .noun = "sine_amplitude",
     .allowed = {-1.0, false, 1.0, false},
     .help = "eps of the sinusoidal perturbation (Sect. S2 of the paper: eps = 1e-4)",
     .comment = "eps in phi_ss eps sin(2 pi m x/L + pi/2)",
     .bind = real_member<&C::initial, &InitialConfig::sine_amplitude>()},
    {.section = "initial", .name = "sine_mode", .type = KeyType::integer,
     .rule_text = "0 <= m < N/2", .help = "mode number m", .comment = "m",
     .bind = integer_member<&C::initial, &InitialConfig::sine_mode>(),
     .integer_rule = [](const C& c, std::int64_t m) { below_nyquist(c, m, "sine_mode"); }},
    // > -1 keeps phi positive at the centre of a weakening (negative) bump.
    {.section = "initial", .name = "local_amplitude", .noun = "a relative amplitude",
     .allowed = {.low = -1.0},
     .help = "relative Gaussian bump; negative = weaker (younger) patch that nucleates slip",
     .comment = "relative Gaussian bump in phi",
     .bind = real_member<&C::initial, &InitialConfig::local_amplitude>()},
    {.section = "initial", .name = "local_center", .unit = "m", .rule_text = "0 <= x <= L",
     .help = "centre of the bump", .comment = "[m]",
     .bind = real_member<&C::initial, &InitialConfig::local_center>(),
     .real_rule = [](const C& c, double x) { require_on_interface(x, c.geometry.length, true, "a position"); }},
    {.section = "initial", .name = "local_width", .unit = "m", .noun = "a width",
     .allowed = non_negative, .rule_text = "> 0 if local_amplitude != 0",
     .help = "standard deviation of the bump", .comment = "standard deviation [m]",
     .bind = real_member<&C::initial, &InitialConfig::local_width>()},
    {.section = "initial", .name = "local_center_z", .unit = "m", .rule_text = "0 <= z <= W",
     .help = "on a 2D interface (`geometry.nodes_z` > 1, docs/3d.md): z of the centre of the bump",
     .comment = "[m] (2D interface)",
     .bind = real_member<&C::initial, &InitialConfig::local_center_z>(),
     .real_rule = [](const C& c, double z) {
       if (!(z >= 0.0 && z <= c.geometry.width))
         throw KeyOutOfRange(format_config_number(z), "a position 0 <= z <= geometry.width = " +
                                                          format_config_number(c.geometry.width) + " [m]");
     }},
    {.section = "initial", .name = "local_width_z", .unit = "m", .noun = "a width",
     .allowed = non_negative, .allowed_note = " (0 = the same bump on every row z)",
     .rule_text = "0 on a one-dimensional interface",
     .help = "on a 2D interface: standard deviation of the bump in z, which makes it a patch "
             "centred at (`local_center`, `local_center_z`); 0 = the same bump on every row z",
     .comment = "standard deviation in z [m] (2D interface); 0 = uniform in z",
     .bind = real_member<&C::initial, &InitialConfig::local_width_z>()},

    // [time] ----------------------------------------------------------------
    // Below ~1e-3 the number of steps per shear echo (and the strip operator's
    // memory) explodes for no gain in accuracy.
    {.section = "time", .name = "beta", .noun = "beta",
     .allowed = {.low = 0.0, .high = kStripBetaLimit, .high_inclusive = true},
     .allowed_note = " (dt = beta dx / c_s)",
     .generous = {1e-3, true, kStripBetaLimit, true},
     .rule_text = "<= 1/(pi (1 - c_s^2/c_d^2)) (passivity of the strip operator), <= 0.35 for a "
                  "half-space",
     .help = "time step dt = beta dx / c_s (adjusted down so 2H/c_s is a whole number of steps)",
     .comment = "dt = beta dx / c_s", .bind = real_member<&C::time, &TimeConfig::beta>(),
     .real_rule = beta_rule},
    {.section = "time", .name = "duration", .unit = "s", .noun = "a time", .allowed = positive,
     .help = "simulated time", .comment = "[s]",
     .bind = real_member<&C::time, &TimeConfig::duration>()},
    {.section = "time", .name = "duration_transits", .unit = "L/c_s", .allowed = positive,
     .allowed_message = "a number > 0 of L/c_s",
     .help = "simulated time in shear-wave transit times of the period",
     .alternative_to = "duration",
     .bind = {.set_real = [](C& c, double transits) {
       c.time.duration = transits * c.geometry.length / c.material.shear_wave_speed();
     }}},
    {.section = "time", .name = "history", .type = KeyType::choice,
     .help = "how the strip's history operator is applied: `modal` rotates every strip normal "
             "mode every step (cost ∝ H/dx per Fourier mode), `block` uses FFT block "
             "convolutions and NUFFT-moved mode states (cost ∝ log²(H/dx), more memory); both "
             "are the same discrete operator to ~1e-13 (docs/performance.md). `auto` takes "
             "`block` when a Fourier mode has ≥ 128 normal modes. The same for each finite body of an "
             "in-plane pair of different bodies (its 2x2 operator). Ignored for a half-space",
     .comment = "(strip history algorithm; same operator)",
     .choices = names_of<kHistoryAlgorithmNames>,
     .bind = enum_member<&C::time, &TimeConfig::history, kHistoryAlgorithmNames>()},
    {.section = "time", .name = "half_space_pair", .type = KeyType::choice,
     .help = "an in-plane pair of two different half-spaces (`geometry.height` and `bottom.height` "
             "\"inf\"): `combined` carries the interface by one operator of the slip and opening rates, "
             "whose exponentials are fed one input while the interface is closed (docs/inplane_bodies.md §7; "
             "~0.7x the step of `bodies`, docs/performance.md); `bodies` by each body's own 2x2 operator. "
             "A pair with a Stoneley wave (an undamped interface wave) takes `bodies` whatever this says. "
             "Ignored for other pairs and on a 2D interface (`geometry.nodes_z` > 1)",
     .comment = "(two different half-spaces: one operator or one per body)",
     .choices = names_of<kHalfSpacePairOperatorNames>,
     .bind = enum_member<&C::time, &TimeConfig::half_space_pair, kHalfSpacePairOperatorNames>()},
    {.section = "time", .name = "antiplane_pair", .type = KeyType::choice,
     .help = "an antiplane pair of two different bodies (`bottom.body` \"elastic\"), both finite or both "
             "half-spaces: `combined` carries the interface by one scalar operator of the bonded pair, whose "
             "normal modes are the bilayer's SH modes for two strips, and whose kernel is K_t K_b / (K_t + K_b) "
             "for two half-spaces (docs/bodies.md §3); `bodies` by each body's own operator, combined through "
             "the instantaneous impedances. Both are exact in the shear echoes. A pair of half-spaces the "
             "combined operator refuses (its set-up check, no passive correction at this step) takes `bodies` "
             "whatever this says. Ignored for a rigid bottom, a half-space on a finite body and on a 2D "
             "interface (`geometry.nodes_z` > 1)",
     .comment = "(two different antiplane strips or half-spaces: one operator or one per body)",
     .choices = names_of<kAntiplanePairOperatorNames>,
     .bind = enum_member<&C::time, &TimeConfig::antiplane_pair, kAntiplanePairOperatorNames>()},

    // [output] --------------------------------------------------------------
    {.section = "output", .name = "timeseries_interval", .unit = "s", .noun = "a time",
     .allowed = non_negative, .allowed_note = " (0 = every step)",
     .help = "between rows of the global time series; 0 = every step",
     .comment = "[s]; 0 = every step",
     .bind = real_member<&C::output, &OutputConfig::timeseries_interval>()},
    {.section = "output", .name = "snapshot_interval", .unit = "s", .noun = "a time",
     .allowed = non_negative, .allowed_note = " (0 = off)",
     .help = "between full interface snapshots; 0 = off", .comment = "[s]; 0 = off",
     .bind = real_member<&C::output, &OutputConfig::snapshot_interval>()},
    {.section = "output", .name = "snapshot_slip_increment", .unit = "m", .noun = "a slip",
     .allowed = non_negative, .allowed_note = " (0 = off)",
     .help = "mean slip between extra snapshots; 0 = off", .comment = "[m]; 0 = off",
     .bind = real_member<&C::output, &OutputConfig::snapshot_slip_increment>()},
    {.section = "output", .name = "delta_th", .unit = "m", .noun = "a slip threshold",
     .allowed = non_negative, .allowed_note = " (0 = off)",
     .rule_text = "nonzero values >= 1e-12",
     .help = "slip-sampling threshold of the event identification (paper: 1e-8 m = 0.02 D); 0 = off",
     .comment = "[m] slip-sampling threshold; 0 = off",
     .bind = real_member<&C::output, &OutputConfig::delta_th>(),
     .real_rule = [](const C&, double v) {
       if (v > 0.0 && v < kMinDeltaTh)
         throw KeyOutOfRange(format_config_number(v),
                             "0 (off) or a slip threshold >= " + format_config_number(kMinDeltaTh) +
                                 " [m] (every node writes one crossing time per delta_th of slip)");
     },
     .plausibility = delta_th_plausibility,
     .plausibility_text = "the slip of one time step at the loading rate, v0 dt, exceeds delta_th: the "
                          "event catalog is coarser than its slip sampling (v0 in mm/s?)"},
    {.section = "output", .name = "flush_interval", .unit = "s (wall clock)",
     .noun = "a wall-clock time", .allowed = positive,
     .allowed_message = "a wall-clock time > 0 [s]", .help = "between writes of the output file",
     .comment = "[s of wall time]", .bind = real_member<&C::output, &OutputConfig::flush_interval>()},
    {.section = "output", .name = "checkpoint_interval", .unit = "s (wall clock)",
     .allowed = non_negative,
     .allowed_message = "0 (restart points only on SIGTERM/SIGINT) or a finite wall-clock time > 0 [s]",
     .help = "between restart points `RUN.h5.restart` (docs/output.md); 0 = a restart point only "
             "when SIGTERM/SIGINT stops the run (always written then). Each one flushes and "
             "`fsync`s the run file and writes the whole solver state, whose size is that of the "
             "history operator's state: measured at N = 2048 (quickstart material, beta = 0.25) "
             "10 MB for the half-space, 54 MB for H = 0.025 m and 214 MB for H = 0.1 m (modal), "
             "933 MB for H = 0.5 m (block); at most one restart point (plus its `.tmp` while one "
             "is written) exists per run",
     .comment = "[s of wall time] between restart points (RUN.h5.restart); 0 = only on SIGTERM/SIGINT",
     .bind = real_member<&C::output, &OutputConfig::checkpoint_interval>()},
    {.section = "output", .name = "stations", .type = KeyType::numbers, .unit = "m",
     .rule_text = "positions 0 <= x < L",
     .help = "on-fault stations recorded in `/stations` (docs/output.md); linear interpolation "
             "between the two neighbouring nodes, exact on a node",
     .comment = "station positions x [m]; [] = none",
     .bind = {.get_list = [](const C& c) { return c.output.stations; },
              .set_list = [](C& c, const std::vector<double>& v) { c.output.stations = v; }},
     .list_rule = [](const C& c, const std::vector<double>& stations) {
       for (double x : stations) require_on_interface(x, c.geometry.length, false, "positions");
     }},
    {.section = "output", .name = "stations_z", .type = KeyType::numbers, .unit = "m",
     .rule_text = "positions 0 <= z < W, one per station; [] on a one-dimensional interface",
     .help = "on a 2D interface (`geometry.nodes_z` > 1, docs/3d.md): the z position of each station, "
             "paired with `stations` by index (station i at (stations[i], stations_z[i])); bilinear "
             "interpolation between the four neighbouring nodes, exact on a node",
     .comment = "station positions z [m] on a 2D interface, paired with stations; [] = none",
     .bind = {.get_list = [](const C& c) { return c.output.stations_z; },
              .set_list = [](C& c, const std::vector<double>& v) { c.output.stations_z = v; }},
     .list_rule = [](const C& c, const std::vector<double>& stations_z) {
       for (double z : stations_z) {
         const bool inside = z >= 0.0 && z < c.geometry.width;
         if (!inside)
           throw KeyOutOfRange(format_config_number(z), "positions 0 <= z < geometry.width = " +
                                                            format_config_number(c.geometry.width) + " [m]");
       }
     }},
    {.section = "output", .name = "station_interval", .unit = "s", .noun = "a time",
     .allowed = non_negative, .allowed_note = " (0 = every step)",
     .help = "between station records; 0 = every step", .comment = "[s]; 0 = every step",
     .bind = real_member<&C::output, &OutputConfig::station_interval>()},
    {.section = "output", .name = "front_slip_rate", .unit = "m/s", .noun = "a slip rate",
     .allowed = non_negative, .allowed_note = " (0 = off)",
     .help = "rupture-front threshold: per node, the first time the slip rate exceeds it goes to "
             "`/rupture_front`; 0 = off (above v0, e.g. 10 v0)",
     .comment = "[m/s] rupture-front threshold; 0 = off",
     .bind = real_member<&C::output, &OutputConfig::front_slip_rate>()},
    {.section = "output", .name = "kernel_cache", .type = KeyType::text,
     .help = "directory caching the strip kernels (normal-mode phases and weights per Fourier "
             "mode), one HDF5 file per set of inputs they depend on, so a scan computes them "
             "once; `\"\"` = no cache",
     .comment = "directory caching the strip kernels (HDF5, one file per key); \"\" = off",
     .bind = {.get_text = [](const C& c) { return c.output.kernel_cache; },
              .set_text = [](C& c, const std::string& v) { c.output.kernel_cache = v; }}},
};

bool dimensionless(const ConfigKey& k) { return k.unit.empty(); }

std::string unit_suffix(const ConfigKey& k) {
  return dimensionless(k) ? std::string() : " [" + std::string(k.unit) + "]";
}

// "> 0", "<= 0.4"
std::string low_relation(const ValueRange& r) { return r.low_inclusive ? ">=" : ">"; }
std::string high_relation(const ValueRange& r) { return r.high_inclusive ? "<=" : "<"; }
std::string flip(const std::string& relation) { return relation == ">" ? "<" : "<="; }

// A range in words for `subject`, numbers through `format`.
template <typename Format>
std::string relation_text(const ValueRange& r, std::string_view subject, bool bare_symbol,
                          Format format) {
  const std::string s(subject);
  if (r.has_low() && r.has_high()) {
    if (!bare_symbol && r.low_inclusive && r.high_inclusive)
      return s + " between " + format(r.low) + " and " + format(r.high);
    return format(r.low) + " " + flip(low_relation(r)) + " " + s + " " + high_relation(r) + " " +
           format(r.high);
  }
  if (r.has_low()) return s + " " + low_relation(r) + " " + format(r.low);
  if (r.has_high()) return s + " " + high_relation(r) + " " + format(r.high);
  return s;
}

bool is_bare_symbol(std::string_view noun) { return noun.find(' ') == std::string_view::npos; }

}  // namespace

// ---------------------------------------------------------------------------

std::span<const ConfigSection> config_sections() { return kSections; }
std::span<const ConfigKey> config_keys() { return kKeys; }

const ConfigSection* find_config_section(std::string_view section) {
  for (const auto& s : kSections)
    if (s.name == section) return &s;
  return nullptr;
}

const ConfigKey* find_config_key(std::string_view section, std::string_view name) {
  for (const auto& k : kKeys)
    if (k.section == section && k.name == name) return &k;
  return nullptr;
}

std::string format_config_number(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  std::string text(buffer, result.ptr);
  if (text.find_first_of(".eE") == std::string::npos) text += ".0";
  return text;
}

std::string format_bound(double value) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

std::string format_short(double value) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value, std::chars_format::general, 3);
  return std::string(buffer, result.ptr);
}

std::vector<std::string> plausibility_warnings(const SimulationConfig& config) {
  std::vector<std::string> warnings;
  for (const auto& k : kKeys)
    if (k.plausibility != nullptr)
      if (std::string warning = k.plausibility(config); !warning.empty()) warnings.push_back(std::move(warning));
  return warnings;
}

std::string quote_toml(std::string_view text) {
  std::string out = "\"";
  for (char c : text) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\t': out += "\\t"; break;
      case '\r': out += "\\r"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char hex[8];
          std::snprintf(hex, sizeof hex, "\\u%04x", static_cast<unsigned>(c));
          out += hex;
        } else {
          out += c;
        }
    }
  }
  return out + "\"";
}

std::string range_text(const ValueRange& range, std::string_view subject, bool bare_symbol) {
  return relation_text(range, subject, bare_symbol, format_bound);
}

std::string allowed_text(const ConfigKey& k) {
  if (!k.allowed_message.empty()) return std::string(k.allowed_message);
  return relation_text(k.allowed, k.noun, is_bare_symbol(k.noun), format_bound) + unit_suffix(k) +
         std::string(k.allowed_note);
}

std::string generous_text(const ConfigKey& k) {
  const ValueRange& g = k.generous;
  const bool bare = is_bare_symbol(k.noun);
  std::string text;
  if (bare && g.has_low() && g.has_high())
    text = format_config_number(g.low) + " " + flip(low_relation(g)) + " " + std::string(k.noun) +
           " " + high_relation(g) + " " + format_config_number(g.high);
  else
    text = relation_text(g, k.noun, bare, format_config_number);
  return text + unit_suffix(k) + (dimensionless(k) ? " (dimensionless; " : " (") +
         "the physically generous range of docs/config.md)";
}

std::string toml_value_text(const ConfigKey& k, const SimulationConfig& c) {
  switch (k.type) {
    case KeyType::friction_parameter:
      if (const auto& profile = k.bind.get_profile(c)) return parameter_profile_toml(*profile);
      return format_config_number(k.bind.get_real(c));
    case KeyType::number: return format_config_number(k.bind.get_real(c));
    case KeyType::number_or_inf: {
      const double v = k.bind.get_real(c);
      return std::isinf(v) && v > 0 ? "\"inf\"" : format_config_number(v);
    }
    case KeyType::integer: return std::to_string(k.bind.get_integer(c));
    case KeyType::choice:
    case KeyType::text: return quote_toml(k.bind.get_text(c));
    case KeyType::numbers: {
      std::string out = "[";
      const auto values = k.bind.get_list(c);
      for (std::size_t i = 0; i < values.size(); ++i)
        out += (i ? ", " : "") + format_config_number(values[i]);
      return out + "]";
    }
  }
  throw std::logic_error("config key of unknown type: " + k.full_name());
}

toml::table config_to_table(const SimulationConfig& c) {
  // Through the TOML text of each value, so the table is exactly what a
  // reader of to_toml gets (profiles as tables, "inf" as a string).
  std::ostringstream text;
  for (const auto& section : kSections) {
    text << "[" << section.name << "]\n";
    for (const auto& k : kKeys)
      if (k.section == section.name && k.alternative_to.empty())
        text << k.name << " = " << toml_value_text(k, c) << "\n";
  }
  return toml::parse(text.str());
}

}  // namespace slipstrip
