#include "core/config.hpp"

#include "core/friction_profile_toml.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <numbers>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <span>
#include <sstream>
#include <string_view>

namespace slipstrip {
namespace {

// ---------------------------------------------------------------------------
// Schema: the only sections and keys a config may contain.  Everything else is
// rejected, because a silently ignored typo ("lenght") would run the default
// instead of what the user asked for.
struct SectionSchema {
  std::string_view name;
  std::span<const std::string_view> keys;
};

constexpr std::string_view kGeometryKeys[] = {"length", "height", "nodes", "dx"};
constexpr std::string_view kMaterialKeys[] = {"shear_modulus", "youngs_modulus", "poisson_ratio",
                                              "density", "plane"};
constexpr std::string_view kLoadingKeys[] = {"driving_velocity", "normal_stress"};
constexpr std::string_view kFrictionKeys[] = {"law", "f0", "a", "b", "characteristic_slip",
                                              "v_star", "phi_star"};
constexpr std::string_view kStateKeys[] = {"law"};
constexpr std::string_view kInterfaceKeys[] = {"law",       "slip_amplitude",   "mode",
                                               "profile",   "rise_time",        "stress_amplitude",
                                               "pulse_center", "pulse_width", "load_pulse_amplitude"};
constexpr std::string_view kInitialKeys[] = {"noise_amplitude", "noise_seed",      "sine_amplitude",
                                             "sine_mode",       "local_amplitude", "local_center",
                                             "local_width"};
constexpr std::string_view kTimeKeys[] = {"beta", "duration", "duration_transits", "history"};
constexpr std::string_view kOutputKeys[] = {"timeseries_interval", "snapshot_interval",
                                            "snapshot_slip_increment", "delta_th",
                                            "flush_interval", "kernel_cache", "stations",
                                            "station_interval", "front_slip_rate",
                                            "checkpoint_interval"};

constexpr SectionSchema kSchema[] = {
    {"geometry", kGeometryKeys}, {"material", kMaterialKeys},   {"loading", kLoadingKeys},
    {"friction", kFrictionKeys}, {"state", kStateKeys},         {"interface", kInterfaceKeys},
    {"initial", kInitialKeys},   {"time", kTimeKeys},           {"output", kOutputKeys},
};

// Pairs of keys that describe the same quantity: exactly one may be given.
struct Alternatives {
  std::string_view section, first, second;
};
constexpr Alternatives kAlternatives[] = {
    {"geometry", "nodes", "dx"},
    {"material", "shear_modulus", "youngs_modulus"},
    {"time", "duration", "duration_transits"},
};

// The largest node count accepted: keeps N and N/2+1 spectral modes far from
// int overflow and any run within memory of one machine.
constexpr std::int64_t kMaxNodes = std::int64_t{1} << 24;

// A config is a few kB of TOML; anything above this is not one.
constexpr std::uintmax_t kMaxConfigBytes = 1u << 20;

const SectionSchema* find_section(std::string_view name) {
  for (const auto& s : kSchema)
    if (s.name == name) return &s;
  return nullptr;
}

bool has_key(const SectionSchema& s, std::string_view key) {
  return std::find(s.keys.begin(), s.keys.end(), key) != s.keys.end();
}

// ---------------------------------------------------------------------------
// Suggestions for misspelt names (Levenshtein distance).
std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      const std::size_t substitution = diagonal + (a[i - 1] == b[j - 1] ? 0 : 1);
      row[j] = std::min({above + 1, row[j - 1] + 1, substitution});
      diagonal = above;
    }
  }
  return row[b.size()];
}

// A suggestion is only useful when it is plausibly what was meant; beyond a
// third of the word the nearest name is noise, so we list the options instead.
bool close_enough(std::string_view given, std::size_t distance) {
  return distance <= std::max<std::size_t>(2, given.size() / 3);
}

std::string join(std::span<const std::string_view> names) {
  std::string out;
  for (const auto& n : names) {
    if (!out.empty()) out += ", ";
    out += n;
  }
  return out;
}

std::string section_names() {
  std::string out;
  for (const auto& s : kSchema) {
    if (!out.empty()) out += ", ";
    out += s.name;
  }
  return out;
}

std::string unknown_section_message(std::string_view name) {
  std::string_view best;
  std::size_t best_distance = std::numeric_limits<std::size_t>::max();
  for (const auto& s : kSchema) {
    const std::size_t d = edit_distance(name, s.name);
    if (d < best_distance) best_distance = d, best = s.name;
  }
  std::string message = "unknown section '" + std::string(name) + "'";
  if (close_enough(name, best_distance))
    return message + "; did you mean '" + std::string(best) + "'?";
  return message + "; allowed sections: " + section_names();
}

std::string unknown_key_message(const SectionSchema& section, std::string_view key) {
  std::string_view best;
  std::size_t best_distance = std::numeric_limits<std::size_t>::max();
  for (const auto& k : section.keys) {
    const std::size_t d = edit_distance(key, k);
    if (d < best_distance) best_distance = d, best = k;
  }
  const std::string prefix = std::string(section.name) + ".";
  std::string message = "unknown key '" + prefix + std::string(key) + "'";
  if (close_enough(key, best_distance))
    return message + "; did you mean '" + prefix + std::string(best) + "'?";
  return message + "; allowed keys in [" + std::string(section.name) + "]: " + join(section.keys);
}

// A key written outside any section: point at the section it belongs to.
std::string top_level_key_message(std::string_view key) {
  std::string best;
  std::size_t best_distance = std::numeric_limits<std::size_t>::max();
  for (const auto& s : kSchema)
    for (const auto& k : s.keys) {
      const std::size_t d = edit_distance(key, k);
      if (d < best_distance) best_distance = d, best = std::string(s.name) + "." + std::string(k);
    }
  std::string message = "unknown key '" + std::string(key) +
                        "' at top level (every key belongs to a section such as [geometry])";
  if (close_enough(key, best_distance)) return message + "; did you mean '" + best + "'?";
  return message + "; allowed sections: " + section_names();
}

// ---------------------------------------------------------------------------
// Formatting.

// Shortest decimal text that parses back to the same double, always a TOML
// float (so "4" becomes "4.0").
std::string format_number(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  std::string text(buffer, result.ptr);
  if (text.find_first_of(".eE") == std::string::npos) text += ".0";
  return text;
}

std::string quote(std::string_view text) {
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

// The value as the user wrote it, for error messages.
std::string describe(const toml::node& node) {
  if (const auto* s = node.as_string()) return quote(s->get());
  if (const auto* i = node.as_integer()) return std::to_string(i->get());
  if (const auto* f = node.as_floating_point()) return format_number(f->get());
  if (const auto* b = node.as_boolean()) return b->get() ? "true" : "false";
  std::ostringstream out;
  if (const auto* t = node.as_table()) {
    out << "{" << *t << "}";
  } else {
    node.visit([&out](const auto& n) { out << n; });
  }
  return out.str();
}

// "file:line: " when the node came from a file, "line N: " for text input.
std::string location(const toml::node* node) {
  if (node == nullptr) return {};
  const auto& source = node->source();
  if (source.begin.line == 0) return {};
  const std::string line = std::to_string(source.begin.line);
  // A value given with --set carries its override as its source (apply_override).
  if (source.path && source.path->rfind("override '", 0) == 0) return *source.path + ": ";
  if (source.path && !source.path->empty()) return *source.path + ":" + line + ": ";
  return "line " + line + ": ";
}

[[noreturn]] void fail(const toml::node* node, const std::string& message) {
  throw ConfigError(location(node) + message);
}

// ---------------------------------------------------------------------------
// Typed access to one section.  Every accessor names the key ("section.key")
// and the offending value in its error.
class Section {
 public:
  Section(const toml::table& root, std::string_view name) : name_(name) {
    table_ = root[name].as_table();
  }

  std::string full(std::string_view key) const { return name_ + "." + std::string(key); }
  const toml::node* node(std::string_view key) const {
    return table_ ? table_->get(key) : nullptr;
  }
  bool has(std::string_view key) const { return node(key) != nullptr; }

  [[noreturn]] void wrong_type(std::string_view key, std::string_view expected) const {
    const toml::node* n = node(key);
    fail(n, full(key) + " = " + describe(*n) + " has the wrong type: expected " +
                std::string(expected));
  }

  // Out-of-range value: "<key> = <value> is out of range: expected <allowed>".
  [[noreturn]] void out_of_range(std::string_view key, const std::string& value,
                                 std::string_view allowed) const {
    fail(node(key), full(key) + " = " + value + " is out of range: expected " +
                        std::string(allowed));
  }

  // A finite number (TOML integer or float).
  std::optional<double> number(std::string_view key) const {
    const toml::node* n = node(key);
    if (n == nullptr) return std::nullopt;
    double value;
    if (const auto* f = n->as_floating_point()) {
      value = f->get();
    } else if (const auto* i = n->as_integer()) {
      value = static_cast<double>(i->get());
    } else {
      wrong_type(key, "a number");
    }
    if (!std::isfinite(value)) out_of_range(key, describe(*n), "a finite number");
    return value;
  }

  // A positive number or +infinity, written as the string "inf" or the TOML
  // float inf (used for lengths where infinity means "no limit").
  std::optional<double> number_or_inf(std::string_view key) const {
    const toml::node* n = node(key);
    if (n == nullptr) return std::nullopt;
    if (const auto* s = n->as_string()) {
      if (s->get() == "inf") return std::numeric_limits<double>::infinity();
      fail(n, full(key) + " = " + describe(*n) +
                  " is not allowed: expected a number or the string \"inf\"");
    }
    double value;
    if (const auto* f = n->as_floating_point()) {
      value = f->get();
    } else if (const auto* i = n->as_integer()) {
      value = static_cast<double>(i->get());
    } else {
      wrong_type(key, "a number or the string \"inf\"");
    }
    if (std::isnan(value)) out_of_range(key, describe(*n), "a number or \"inf\"");
    return value;
  }

  std::optional<std::int64_t> integer(std::string_view key) const {
    const toml::node* n = node(key);
    if (n == nullptr) return std::nullopt;
    if (const auto* i = n->as_integer()) return i->get();
    wrong_type(key, "an integer");
  }

  // An array of finite numbers.
  std::optional<std::vector<double>> numbers(std::string_view key) const {
    const toml::node* n = node(key);
    if (n == nullptr) return std::nullopt;
    const auto* array = n->as_array();
    if (array == nullptr) wrong_type(key, "an array of numbers, e.g. [0.5, 1.0]");
    std::vector<double> out;
    for (const auto& element : *array) {
      double value;
      if (const auto* f = element.as_floating_point()) {
        value = f->get();
      } else if (const auto* i = element.as_integer()) {
        value = static_cast<double>(i->get());
      } else {
        wrong_type(key, "an array of numbers, e.g. [0.5, 1.0]");
      }
      if (!std::isfinite(value)) out_of_range(key, describe(*n), "an array of finite numbers");
      out.push_back(value);
    }
    return out;
  }

  // Free text (a path).
  std::optional<std::string> text(std::string_view key) const {
    const toml::node* n = node(key);
    if (n == nullptr) return std::nullopt;
    if (const auto* t = n->as_string()) return t->get();
    wrong_type(key, "a string");
  }

  // One of a fixed list of names.
  std::optional<std::string> choice(std::string_view key,
                                    std::span<const std::string_view> allowed) const {
    const toml::node* n = node(key);
    if (n == nullptr) return std::nullopt;
    const auto* s = n->as_string();
    if (s == nullptr) wrong_type(key, "a string, one of " + quoted_list(allowed));
    const std::string& value = s->get();
    if (std::find(allowed.begin(), allowed.end(), value) != allowed.end()) return value;
    std::string message = full(key) + " = " + quote(value) + " is not allowed: expected one of " +
                          quoted_list(allowed);
    std::string_view best;
    std::size_t best_distance = std::numeric_limits<std::size_t>::max();
    for (const auto& a : allowed) {
      const std::size_t d = edit_distance(value, a);
      if (d < best_distance) best_distance = d, best = a;
    }
    if (close_enough(value, best_distance)) message += "; did you mean " + quote(best) + "?";
    fail(n, message);
  }

  static std::string quoted_list(std::span<const std::string_view> names) {
    std::string out;
    for (const auto& n : names) {
      if (!out.empty()) out += ", ";
      out += quote(n);
    }
    return out;
  }

 private:
  std::string name_;
  const toml::table* table_ = nullptr;
};

// ---------------------------------------------------------------------------
// Physically generous ranges (docs/config.md, "Ranges"): values far outside
// them are typos or fuzz, and would make the kernel set-up or the local
// friction solve run forever or fail at t = 0 without naming the key.
struct Range {
  double low, high;
  std::string_view unit;
};
constexpr Range kLengthRange{1e-6, 1e6, "m"};
constexpr Range kModulusRange{1.0, 1e13, "Pa"};
constexpr Range kDensityRange{1e-3, 1e6, "kg/m^3"};
constexpr Range kVelocityRange{1e-15, 1e3, "m/s"};
constexpr Range kStressRange{1.0, 1e11, "Pa"};
constexpr Range kSlipDistanceRange{1e-12, 1.0, "m"};
constexpr Range kVStarRange{1e-20, 1e3, "m/s"};
constexpr Range kPhiStarRange{1e-15, 1e15, "s"};
constexpr double kMaxFrictionCoefficient = 10.0;
constexpr double kMinBeta = 1e-3;
constexpr double kMinDeltaTh = 1e-12;

std::string range_text(const Range& r) {
  return "between " + format_number(r.low) + " and " + format_number(r.high) + " [" +
         std::string(r.unit) + "] (the physically generous range of docs/config.md)";
}

void check_range(const Section& s, std::string_view key, double value, const Range& r,
                 std::string_view what) {
  if (!(value >= r.low && value <= r.high))
    s.out_of_range(key, format_number(value), std::string(what) + " " + range_text(r));
}

// ---------------------------------------------------------------------------
// Enumerations: the TOML spelling of each value.
constexpr std::string_view kPlaneNames[] = {"strain", "stress"};
constexpr std::string_view kStrengthLawNames[] = {"paper", "dieterich_ruina", "regularized"};
constexpr std::string_view kStateLawNames[] = {"aging", "slip"};
constexpr std::string_view kProfileNames[] = {"ramp", "bump"};
constexpr std::string_view kHistoryAlgorithmNames[] = {"auto", "modal", "block"};

template <typename Enum, std::size_t N>
Enum enum_from_name(const std::string& name, const std::string_view (&names)[N]) {
  for (std::size_t i = 0; i < N; ++i)
    if (names[i] == name) return static_cast<Enum>(i);
  throw std::logic_error("enum name not in table: " + name);  // Section::choice checked it
}

template <typename Enum, std::size_t N>
std::string_view enum_name(Enum value, const std::string_view (&names)[N]) {
  const auto i = static_cast<std::size_t>(value);
  if (i >= N) throw std::logic_error("enum value out of its name table");
  return names[i];
}

// ---------------------------------------------------------------------------
// Structural check: unknown sections and keys, values where a section belongs.
void check_names(const toml::table& root) {
  for (const auto& [key, node] : root) {
    const std::string_view name = key.str();
    const SectionSchema* section = find_section(name);
    if (section == nullptr) {
      if (node.is_table()) fail(&node, unknown_section_message(name));
      fail(&node, top_level_key_message(name));
    }
    const auto* table = node.as_table();
    if (table == nullptr)
      fail(&node, "'" + std::string(name) + "' = " + describe(node) +
                      " must be a section [" + std::string(name) + "], not a value");
    for (const auto& [sub_key, sub_node] : *table)
      if (!has_key(*section, sub_key.str()))
        fail(&sub_node, unknown_key_message(*section, sub_key.str()));
  }
  for (const auto& alt : kAlternatives) {
    const Section s(root, alt.section);
    if (s.has(alt.first) && s.has(alt.second))
      fail(s.node(alt.second), s.full(alt.first) + " = " + describe(*s.node(alt.first)) +
                                   " and " + s.full(alt.second) + " = " +
                                   describe(*s.node(alt.second)) +
                                   " are alternatives: give exactly one of them");
  }
}

// ---------------------------------------------------------------------------
// Section readers.  Each reads into the default-initialised struct (so an
// absent key keeps the Table S1 default) and checks ranges as it goes.

void read_geometry(const toml::table& root, GeometryConfig& g) {
  const Section s(root, "geometry");
  if (auto v = s.number("length")) {
    if (!(*v > 0.0)) s.out_of_range("length", format_number(*v), "a length > 0 [m]");
    check_range(s, "length", *v, kLengthRange, "a length");
    g.length = *v;
  }
  if (auto v = s.number_or_inf("height")) {
    if (!(*v > 0.0))
      s.out_of_range("height", format_number(*v), "a height > 0 [m] or \"inf\" (half-space)");
    if (!is_half_space(*v))
      check_range(s, "height", *v, kLengthRange, "a height (or \"inf\" for a half-space)");
    g.height = *v;
  }
  const std::string node_range = "an integer between 8 and " + std::to_string(kMaxNodes);
  if (auto v = s.integer("nodes")) {
    if (*v < 8 || *v > kMaxNodes) s.out_of_range("nodes", std::to_string(*v), node_range);
    g.nodes = static_cast<int>(*v);
  }
  if (auto dx = s.number("dx")) {
    if (!(*dx > 0.0)) s.out_of_range("dx", format_number(*dx), "a node spacing > 0 [m]");
    const double ratio = g.length / *dx;
    const double whole = std::round(ratio);
    // dx must tile the period: a rounded N would silently change dx.  The
    // tolerance only absorbs the decimal representation of dx (e.g. 4/0.0025).
    if (std::abs(ratio - whole) > 1e-9 * ratio)
      fail(s.node("dx"), "geometry.dx = " + format_number(*dx) +
                             " does not divide geometry.length = " + format_number(g.length) +
                             " into a whole number of nodes (length/dx = " +
                             format_number(ratio) + "): expected dx = length/N with N an integer");
    if (whole < 8 || whole > static_cast<double>(kMaxNodes))
      s.out_of_range("dx", format_number(*dx),
                     "a spacing giving length/dx between 8 and " + std::to_string(kMaxNodes) +
                         " nodes (got " + format_number(whole) + ")");
    g.nodes = static_cast<int>(whole);
  }
}

void read_material(const toml::table& root, ElasticMaterial& m) {
  const Section s(root, "material");
  if (auto v = s.number("poisson_ratio")) {
    // nu >= 0.5 makes the plane-strain c_d infinite; nu <= 0 is excluded as
    // unphysical for the rocks and polymers this models.
    if (!(*v > 0.0 && *v < 0.5))
      s.out_of_range("poisson_ratio", format_number(*v), "0 < poisson_ratio < 0.5");
    m.poisson_ratio = *v;
  }
  if (auto v = s.number("shear_modulus")) {
    if (!(*v > 0.0)) s.out_of_range("shear_modulus", format_number(*v), "a modulus > 0 [Pa]");
    check_range(s, "shear_modulus", *v, kModulusRange, "a modulus");
    m.shear_modulus = *v;
  }
  if (auto v = s.number("youngs_modulus")) {
    if (!(*v > 0.0)) s.out_of_range("youngs_modulus", format_number(*v), "a modulus > 0 [Pa]");
    check_range(s, "youngs_modulus", *v, kModulusRange, "a modulus");
    m.shear_modulus = *v / (2.0 * (1.0 + m.poisson_ratio));
  }
  if (auto v = s.number("density")) {
    if (!(*v > 0.0)) s.out_of_range("density", format_number(*v), "a density > 0 [kg/m^3]");
    check_range(s, "density", *v, kDensityRange, "a density");
    m.density = *v;
  }
  if (auto v = s.choice("plane", kPlaneNames))
    m.plane = enum_from_name<PlaneCondition>(*v, kPlaneNames);
}

void read_loading(const toml::table& root, LoadingConfig& l) {
  const Section s(root, "loading");
  if (auto v = s.number("driving_velocity")) {
    // v0 > 0: the initial state is steady sliding, phi = phi_ss(v0).
    if (!(*v > 0.0))
      s.out_of_range("driving_velocity", format_number(*v), "a velocity > 0 [m/s]");
    check_range(s, "driving_velocity", *v, kVelocityRange, "a velocity");
    l.driving_velocity = *v;
  }
  if (auto v = s.number("normal_stress")) {
    if (!(*v > 0.0))
      s.out_of_range("normal_stress", format_number(*v), "a compressive stress > 0 [Pa]");
    check_range(s, "normal_stress", *v, kStressRange, "a compressive stress");
    l.normal_stress = *v;
  }
}

// f0, a, b and characteristic_slip may be tables: profiles along x
// (core/friction_profile_toml.hpp).  Such a key is parsed here and skipped by
// the scalar checks below; its scalar field is set to NaN, so nothing can use
// one value for the whole interface by accident (friction/parameter_profile.hpp);
// its values are checked node by node in config_from_table.
void read_friction_profiles(const Section& s, FrictionParameters& f, FrictionProfiles& profiles) {
  const auto read = [&](std::string_view key, double& field, std::optional<ParameterProfile>& out) {
    const toml::node* n = s.node(key);
    if (n == nullptr || !n->is_table()) return;
    try {
      out = parse_parameter_profile(*n, s.full(key));
    } catch (const std::invalid_argument& e) {
      fail(n, e.what());
    }
    field = std::numeric_limits<double>::quiet_NaN();
  };
  read("f0", f.f0, profiles.f0);
  read("a", f.a, profiles.a);
  read("b", f.b, profiles.b);
  read("characteristic_slip", f.characteristic_slip, profiles.characteristic_slip);
}

void read_friction(const toml::table& root, FrictionParameters& f, FrictionProfiles& profiles) {
  const Section s(root, "friction");
  if (auto v = s.choice("law", kStrengthLawNames))
    f.strength_law = enum_from_name<StrengthLaw>(*v, kStrengthLawNames);
  read_friction_profiles(s, f, profiles);
  const auto scalar = [&s](std::string_view key) {
    const toml::node* n = s.node(key);
    return n != nullptr && !n->is_table();
  };
  const auto positive = [&s, &scalar](std::string_view key, double& field, std::string_view allowed) {
    if (!scalar(key)) return;
    if (auto v = s.number(key)) {
      if (!(*v > 0.0)) s.out_of_range(key, format_number(*v), allowed);
      field = *v;
    }
  };
  positive("f0", f.f0, "f0 > 0");
  const auto non_negative = [&s, &scalar](std::string_view key, double& field) {
    if (!scalar(key)) return;
    if (auto v = s.number(key)) {
      if (!(*v >= 0.0)) s.out_of_range(key, format_number(*v), std::string(key) + " >= 0");
      field = *v;
    }
  };
  non_negative("a", f.a);
  non_negative("b", f.b);
  // Friction coefficients are O(0.01-1); beyond 10 the strength (and the
  // local solve at t = 0) is meaningless.
  for (std::string_view key : {"f0", "a", "b"})
    if (auto v = scalar(key) ? s.number(key) : std::nullopt; v && *v > kMaxFrictionCoefficient)
      s.out_of_range(key, format_number(*v),
                     std::string(key) + " <= " + format_number(kMaxFrictionCoefficient) +
                         " (dimensionless; the physically generous range of docs/config.md)");
  positive("characteristic_slip", f.characteristic_slip, "a slip distance D > 0 [m]");
  positive("v_star", f.v_star, "a velocity v* > 0 [m/s]");
  positive("phi_star", f.phi_star, "a time phi* > 0 [s]");
  if (scalar("characteristic_slip"))
    check_range(s, "characteristic_slip", f.characteristic_slip, kSlipDistanceRange, "a slip distance D");
  if (s.has("v_star")) check_range(s, "v_star", f.v_star, kVStarRange, "a velocity v*");
  if (s.has("phi_star")) check_range(s, "phi_star", f.phi_star, kPhiStarRange, "a time phi*");

  // The regularized law divides by a (exp(psi/a)); the others stay defined at
  // a = 0 because radiation damping alone fixes the slip rate.
  if (f.strength_law == StrengthLaw::regularized && !profiles.a && !(f.a > 0.0))
    fail(s.has("a") ? s.node("a") : s.node("law"),
         "friction.a = " + format_number(f.a) +
             " is out of range for friction.law = \"regularized\": expected a > 0");

  const Section state(root, "state");
  if (auto v = state.choice("law", kStateLawNames))
    f.state_law = enum_from_name<StateLaw>(*v, kStateLawNames);
}

void read_interface(const toml::table& root, int nodes, InterfaceConfig& in) {
  const Section s(root, "interface");
  // The registered laws (core/interface_laws.inc); the name kept is the
  // registry's (static storage), not the parsed string.
  const InterfaceLawRegistry laws = builtin_interface_laws();
  const std::vector<std::string_view> law_names = laws.names();
  if (auto v = s.choice("law", law_names)) in.law = InterfaceLaw{laws.find(*v)->name};
  if (auto v = s.number("slip_amplitude")) in.slip_amplitude = *v;
  if (auto v = s.integer("mode")) {
    // Below Nyquist: mode N/2 has no sine partner on the grid.
    if (*v < 0 || *v >= nodes / 2)
      s.out_of_range("mode", std::to_string(*v),
                     "an integer 0 <= mode < nodes/2 = " + std::to_string(nodes / 2));
    in.mode = static_cast<int>(*v);
  }
  if (auto v = s.choice("profile", kProfileNames))
    in.profile = enum_from_name<TimeProfile>(*v, kProfileNames);
  if (auto v = s.number("rise_time")) {
    if (!(*v > 0.0)) s.out_of_range("rise_time", format_number(*v), "a time > 0 [s]");
    in.rise_time = *v;
  }
  if (auto v = s.number("stress_amplitude")) in.stress_amplitude = *v;
  if (auto v = s.number("load_pulse_amplitude")) in.load_pulse_amplitude = *v;
  if (auto v = s.number("pulse_center")) in.pulse_center = *v;
  if (auto v = s.number_or_inf("pulse_width")) {
    if (!(*v > 0.0))
      s.out_of_range("pulse_width", format_number(*v),
                     "a width > 0 [m] or \"inf\" (uniform stress)");
    in.pulse_width = *v;
  }
}

void read_initial(const toml::table& root, const GeometryConfig& g, InitialConfig& init) {
  const Section s(root, "initial");
  if (auto v = s.number("noise_amplitude")) {
    if (!(*v >= 0.0))
      s.out_of_range("noise_amplitude", format_number(*v), "a relative amplitude >= 0");
    init.noise_amplitude = *v;
  }
  if (auto v = s.integer("noise_seed")) {
    if (*v < 0) s.out_of_range("noise_seed", std::to_string(*v), "an integer >= 0");
    init.noise_seed = static_cast<std::uint64_t>(*v);
  }
  if (auto v = s.number("sine_amplitude")) {
    // |eps| < 1 keeps phi_ss (1 + eps sin) positive everywhere.
    if (!(std::abs(*v) < 1.0))
      s.out_of_range("sine_amplitude", format_number(*v), "-1 < sine_amplitude < 1");
    init.sine_amplitude = *v;
  }
  if (auto v = s.integer("sine_mode")) {
    if (*v < 0 || *v >= g.nodes / 2)
      s.out_of_range("sine_mode", std::to_string(*v),
                     "an integer 0 <= sine_mode < nodes/2 = " + std::to_string(g.nodes / 2));
    init.sine_mode = static_cast<int>(*v);
  }
  if (auto v = s.number("local_amplitude")) {
    // > -1 keeps phi positive at the centre of a weakening (negative) bump.
    if (!(*v > -1.0))
      s.out_of_range("local_amplitude", format_number(*v), "a relative amplitude > -1");
    init.local_amplitude = *v;
  }
  if (auto v = s.number("local_center")) {
    if (!(*v >= 0.0 && *v <= g.length))
      s.out_of_range("local_center", format_number(*v),
                     "a position 0 <= x <= geometry.length = " + format_number(g.length) + " [m]");
    init.local_center = *v;
  }
  if (auto v = s.number("local_width")) {
    if (!(*v >= 0.0))
      s.out_of_range("local_width", format_number(*v), "a width >= 0 [m]");
    init.local_width = *v;
  }
  if (init.local_amplitude != 0.0 && !(init.local_width > 0.0))
    fail(s.node("local_amplitude"),
         "initial.local_amplitude = " + format_number(init.local_amplitude) +
             " needs initial.local_width > 0 [m] (got " + format_number(init.local_width) +
             "): the perturbation is a Gaussian of that standard deviation");
}

void read_time(const toml::table& root, const SimulationConfig& c, TimeConfig& t) {
  const Section s(root, "time");
  if (auto v = s.number("beta")) {
    // 0.4: above it the static stiffness of the modes beyond Nyquist cannot be
    // placed passively for the shortest wavelengths (docs/config.md, docs/theory.md).
    if (!(*v > 0.0 && *v <= 0.4))
      s.out_of_range("beta", format_number(*v), "0 < beta <= 0.4 (dt = beta dx / c_s)");
    // Below ~1e-3 the number of steps per shear echo (and the strip operator's
    // memory) explodes for no gain in accuracy (docs/config.md).
    if (*v < kMinBeta)
      s.out_of_range("beta", format_number(*v),
                     format_number(kMinBeta) + " <= beta <= 0.4 (dt = beta dx / c_s; smaller steps "
                     "only multiply the cost and the operator memory)");
    // Exact limit of a positive-real discrete operator (docs/theory.md 6.4):
    // dt S(k,0)/2 <= eta at the grid's Nyquist wavenumber, i.e.
    // beta <= 1 / (pi (1 - c_s^2/c_d^2)); it falls below 0.4 for nu > ~0.36
    // in plane strain.
    const double beta_max =
        1.0 / (std::numbers::pi * (1.0 - 1.0 / c.material.wave_speed_ratio_squared()));
    if (*v > beta_max)
      s.out_of_range("beta", format_number(*v),
                     "0 < beta <= " + format_number(std::floor(beta_max * 1e4) / 1e4) +
                         " for this material (1/(pi (1 - c_s^2/c_d^2)), the limit of a passive "
                         "discrete strip operator; docs/theory.md)");
    // Half-space: the passivity correction of the sampled kernel exists up to
    // c_s k dt ~ 1.11 at the Nyquist mode (plane strain, nu = 0.33), i.e.
    // beta ~ 0.355 (kernels/passivity.hpp, docs/theory.md section 9).
    if (is_half_space(c.geometry.height) && *v > 0.35)
      s.out_of_range("beta", format_number(*v),
                     "0 < beta <= 0.35 for a half-space (geometry.height = \"inf\"): above it "
                     "the sampled half-space kernel cannot be made passive at the shortest "
                     "wavelength; docs/theory.md");
    t.beta = *v;
  }
  if (auto v = s.choice("history", kHistoryAlgorithmNames))
    t.history = enum_from_name<HistoryAlgorithm>(*v, kHistoryAlgorithmNames);
  if (auto v = s.number("duration")) {
    if (!(*v > 0.0)) s.out_of_range("duration", format_number(*v), "a time > 0 [s]");
    t.duration = *v;
  }
  if (auto v = s.number("duration_transits")) {
    if (!(*v > 0.0))
      s.out_of_range("duration_transits", format_number(*v), "a number > 0 of L/c_s");
    t.duration = *v * c.geometry.length / c.material.shear_wave_speed();
  }
}

void read_output(const toml::table& root, double length, OutputConfig& o) {
  const Section s(root, "output");
  const auto non_negative = [&s](std::string_view key, double& field, std::string_view allowed) {
    if (auto v = s.number(key)) {
      if (!(*v >= 0.0)) s.out_of_range(key, format_number(*v), allowed);
      field = *v;
    }
  };
  non_negative("timeseries_interval", o.timeseries_interval, "a time >= 0 [s] (0 = every step)");
  non_negative("snapshot_interval", o.snapshot_interval, "a time >= 0 [s] (0 = off)");
  non_negative("snapshot_slip_increment", o.snapshot_slip_increment, "a slip >= 0 [m] (0 = off)");
  non_negative("delta_th", o.delta_th, "a slip threshold >= 0 [m] (0 = off)");
  if (o.delta_th > 0.0 && o.delta_th < kMinDeltaTh)
    s.out_of_range("delta_th", format_number(o.delta_th),
                   "0 (off) or a slip threshold >= " + format_number(kMinDeltaTh) +
                       " [m] (every node writes one crossing time per delta_th of slip)");
  if (auto v = s.number("flush_interval")) {
    if (!(*v > 0.0))
      s.out_of_range("flush_interval", format_number(*v), "a wall-clock time > 0 [s]");
    o.flush_interval = *v;
  }
  if (auto v = s.number("checkpoint_interval")) {
    if (!(*v >= 0.0) || !std::isfinite(*v))
      s.out_of_range("checkpoint_interval", format_number(*v),
                     "0 (restart points only on SIGTERM/SIGINT) or a finite wall-clock time > 0 [s]");
    o.checkpoint_interval = *v;
  }
  if (auto v = s.text("kernel_cache")) o.kernel_cache = *v;
  if (auto v = s.numbers("stations")) {
    for (double x : *v)
      if (!(x >= 0.0 && x < length))
        s.out_of_range("stations", format_number(x),
                       "positions 0 <= x < geometry.length = " + format_number(length) + " [m]");
    o.stations = *v;
  }
  non_negative("station_interval", o.station_interval, "a time >= 0 [s] (0 = every step)");
  non_negative("front_slip_rate", o.front_slip_rate, "a slip rate >= 0 [m/s] (0 = off)");
}

std::string trim(std::string_view text) {
  const auto first = text.find_first_not_of(" \t");
  if (first == std::string_view::npos) return {};
  const auto last = text.find_last_not_of(" \t");
  return std::string(text.substr(first, last - first + 1));
}

toml::table parse_text(const std::string& text, const std::string& source_path) {
  try {
    return toml::parse(text, source_path);
  } catch (const toml::parse_error& e) {
    const auto& where = e.source().begin;
    std::string place = source_path.empty() ? std::string("line ") : source_path + ":";
    throw ConfigError(place + std::to_string(where.line) + ":" + std::to_string(where.column) +
                      ": invalid TOML: " + std::string(e.description()));
  }
}

SimulationConfig load(toml::table root, const std::vector<std::string>& overrides) {
  for (const auto& o : overrides) apply_override(root, o);
  return config_from_table(root);
}

}  // namespace

// ---------------------------------------------------------------------------

SimulationConfig config_from_table(const toml::table& root) {
  check_names(root);
  SimulationConfig c;
  // Order matters only where a check uses another section: geometry first
  // (nodes bound the mode numbers, length bounds local_center), material
  // before time (duration_transits needs c_s).
  read_geometry(root, c.geometry);
  read_material(root, c.material);
  read_loading(root, c.loading);
  read_friction(root, c.friction, c.friction_along_x);
  if (c.friction_along_x.any()) {
    // Every node's values against the scalar rules (a profile may not carry a
    // value its key would refuse as a number).
    try {
      (void)resolve_friction_nodes(c.friction, c.friction_along_x,
                                   static_cast<std::size_t>(c.geometry.nodes),
                                   c.geometry.length / c.geometry.nodes);
    } catch (const std::invalid_argument& e) {
      throw ConfigError(e.what());
    }
  }
  read_interface(root, c.geometry.nodes, c.interface);
  read_initial(root, c.geometry, c.initial);
  read_time(root, c, c.time);
  read_output(root, c.geometry.length, c.output);
  return c;
}

// An override as it appears in messages: control characters (a newline would
// split the one-line message) are shown escaped.
std::string printable_override(const std::string& assignment) {
  std::string out;
  for (const unsigned char c : assignment) {
    if (c == '\n') out += "\\n";
    else if (c == '\r') out += "\\r";
    else if (c == '\t') out += "\\t";
    else if (c < 0x20 || c == 0x7f) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", c);
      out += buf;
    } else out += static_cast<char>(c);
  }
  return out;
}

void apply_override(toml::table& root, const std::string& assignment) {
  const std::string shown = printable_override(assignment);
  const std::string context = "override '" + shown + "': ";
  const auto equals = assignment.find('=');
  if (equals == std::string::npos)
    throw ConfigError(context + "expected the form section.key=value");
  const std::string path = trim(std::string_view(assignment).substr(0, equals));
  const std::string text = trim(std::string_view(assignment).substr(equals + 1));
  if (printable_override(path) != path)
    throw ConfigError(context + "the key '" + printable_override(path) +
                      "' contains control characters: expected the form section.key=value");
  const auto dot = path.find('.');
  if (dot == std::string::npos || dot == 0 || dot + 1 == path.size() ||
      path.find('.', dot + 1) != std::string::npos)
    throw ConfigError(context + "expected the form section.key=value (got key '" + path + "')");
  const std::string section_name = path.substr(0, dot);
  const std::string key = path.substr(dot + 1);
  const SectionSchema* section = find_section(section_name);
  if (section == nullptr) throw ConfigError(context + unknown_section_message(section_name));
  if (!has_key(*section, key)) throw ConfigError(context + unknown_key_message(*section, key));

  // The value as TOML; anything that is not a single TOML value is a string.
  toml::table parsed;
  bool as_toml = text.find_first_of("\n\r") == std::string::npos;
  if (as_toml) {
    try {
      parsed = toml::parse("value = " + text, "override '" + shown + "'");
      as_toml = parsed.size() == 1;
    } catch (const toml::parse_error&) {
      as_toml = false;
    }
  }
  if (!as_toml) {
    try {
      parsed = toml::parse("value = " + quote(text), "override '" + shown + "'");
    } catch (const toml::parse_error& e) {
      throw ConfigError(context + path + " = '" + printable_override(text) +
                        "' is not a valid value: " + std::string(e.description()));
    }
  }

  toml::node* existing = root.get(section_name);
  if (existing == nullptr) {
    root.insert(section_name, toml::table{});
    existing = root.get(section_name);
  }
  toml::table* table = existing->as_table();
  if (table == nullptr)
    throw ConfigError(context + "'" + section_name + "' is a value in the file, not a section");
  table->insert_or_assign(key, std::move(*parsed.get("value")));
  for (const auto& alt : kAlternatives) {
    if (alt.section != section_name) continue;
    if (alt.first == key) table->erase(alt.second);
    if (alt.second == key) table->erase(alt.first);
  }
}

SimulationConfig load_config_string(const std::string& toml_text,
                                    const std::vector<std::string>& overrides) {
  return load(parse_text(toml_text, ""), overrides);
}

SimulationConfig load_config_file(const std::string& path,
                                  const std::vector<std::string>& overrides) {
  // Only a regular file of sane size: a directory used to run the defaults,
  // and /dev/zero was read forever.
  namespace fs = std::filesystem;
  std::error_code ec;
  const auto status = fs::status(path, ec);
  if (ec || !fs::exists(status))
    throw ConfigError("cannot open config file '" + path + "': " +
                      (ec ? ec.message() : std::string("no such file")));
  if (!fs::is_regular_file(status))
    throw ConfigError("config file '" + path + "' is not a regular file (" +
                      (fs::is_directory(status) ? std::string("a directory")
                                                : std::string("a device, FIFO or socket")) +
                      "): expected a TOML file");
  const auto size = fs::file_size(path, ec);
  if (!ec && size > kMaxConfigBytes)
    throw ConfigError("config file '" + path + "' is " + std::to_string(size) +
                      " bytes: allowed at most " + std::to_string(kMaxConfigBytes) +
                      " (1 MiB; a config is a few kB of TOML)");
  std::ifstream file(path, std::ios::binary);
  if (!file) throw ConfigError("cannot open config file '" + path + "'");
  std::ostringstream text;
  text << file.rdbuf();
  if (file.bad()) throw ConfigError("cannot read config file '" + path + "'");
  return load(parse_text(text.str(), path), overrides);
}

std::string to_toml(const SimulationConfig& c) {
  std::ostringstream out;
  const auto number = [&out](std::string_view key, double value, std::string_view comment) {
    out << key << " = " << format_number(value) << "  # " << comment << "\n";
  };
  const auto length_or_inf = [&out](std::string_view key, double value,
                                    std::string_view comment) {
    out << key << " = " << (std::isinf(value) && value > 0 ? "\"inf\"" : format_number(value))
        << "  # " << comment << "\n";
  };
  const auto integer = [&out](std::string_view key, auto value, std::string_view comment) {
    out << key << " = " << value << "  # " << comment << "\n";
  };
  const auto name = [&out](std::string_view key, std::string_view value,
                           std::string_view comment) {
    out << key << " = " << quote(value) << "  # " << comment << "\n";
  };

  out << "# slipstrip resolved configuration: every key, SI units (docs/config.md)\n";
  out << "\n[geometry]\n";
  number("length", c.geometry.length, "L [m], period along the interface");
  length_or_inf("height", c.geometry.height, "H [m] of each strip; \"inf\" = half-space");
  integer("nodes", c.geometry.nodes, "N, dx = L/N");

  out << "\n[material]\n";
  number("shear_modulus", c.material.shear_modulus, "mu [Pa]");
  number("poisson_ratio", c.material.poisson_ratio, "nu [-]");
  number("density", c.material.density, "rho [kg/m^3]");
  name("plane", enum_name(c.material.plane, kPlaneNames), "\"strain\" | \"stress\"");

  out << "\n[loading]\n";
  number("driving_velocity", c.loading.driving_velocity, "v0 [m/s]");
  number("normal_stress", c.loading.normal_stress, "sigma0 [Pa]");

  out << "\n[friction]\n";
  name("law", enum_name(c.friction.strength_law, kStrengthLawNames),
       "\"paper\" | \"dieterich_ruina\" | \"regularized\"");
  // A parameter that varies along x is written as its profile (inline table).
  const auto parameter = [&out, &number](std::string_view key, double value,
                                         const std::optional<ParameterProfile>& profile,
                                         std::string_view comment) {
    if (profile)
      out << key << " = " << parameter_profile_toml(*profile) << "  # " << comment << " along x\n";
    else
      number(key, value, comment);
  };
  parameter("f0", c.friction.f0, c.friction_along_x.f0, "[-]");
  parameter("a", c.friction.a, c.friction_along_x.a, "[-]");
  parameter("b", c.friction.b, c.friction_along_x.b, "[-]");
  parameter("characteristic_slip", c.friction.characteristic_slip,
            c.friction_along_x.characteristic_slip, "D [m]");
  number("v_star", c.friction.v_star, "v* [m/s]");
  number("phi_star", c.friction.phi_star, "phi* [s]");

  out << "\n[state]\n";
  name("law", enum_name(c.friction.state_law, kStateLawNames), "\"aging\" | \"slip\"");

  out << "\n[interface]\n";
  {
    std::string laws;
    for (const auto law : builtin_interface_laws().names())
      laws += (laws.empty() ? "\"" : " | \"") + std::string(law) + "\"";
    name("law", c.interface.law.name, laws);
  }
  number("slip_amplitude", c.interface.slip_amplitude, "[m] (prescribed_slip)");
  integer("mode", c.interface.mode, "m (prescribed_slip)");
  name("profile", enum_name(c.interface.profile, kProfileNames), "\"ramp\" | \"bump\"");
  number("rise_time", c.interface.rise_time, "T [s]");
  number("stress_amplitude", c.interface.stress_amplitude, "[Pa] (free)");
  number("load_pulse_amplitude", c.interface.load_pulse_amplitude,
         "[Pa] extra shear-load pulse on the rate_and_state interface (same shape); 0 = off");
  number("pulse_center", c.interface.pulse_center, "x0 [m] (free)");
  length_or_inf("pulse_width", c.interface.pulse_width, "w [m] (free); \"inf\" = uniform");

  out << "\n[initial]\n";
  number("noise_amplitude", c.initial.noise_amplitude, "relative std of white noise in phi");
  integer("noise_seed", c.initial.noise_seed, "seed of the noise");
  number("sine_amplitude", c.initial.sine_amplitude, "eps in phi_ss eps sin(2 pi m x/L + pi/2)");
  integer("sine_mode", c.initial.sine_mode, "m");
  number("local_amplitude", c.initial.local_amplitude, "relative Gaussian bump in phi");
  number("local_center", c.initial.local_center, "[m]");
  number("local_width", c.initial.local_width, "standard deviation [m]");

  out << "\n[time]\n";
  number("beta", c.time.beta, "dt = beta dx / c_s");
  number("duration", c.time.duration, "[s]");
  name("history", enum_name(c.time.history, kHistoryAlgorithmNames),
       "\"auto\" | \"modal\" | \"block\" (strip history algorithm; same operator)");

  out << "\n[output]\n";
  number("timeseries_interval", c.output.timeseries_interval, "[s]; 0 = every step");
  number("snapshot_interval", c.output.snapshot_interval, "[s]; 0 = off");
  number("snapshot_slip_increment", c.output.snapshot_slip_increment, "[m]; 0 = off");
  number("delta_th", c.output.delta_th, "[m] slip-sampling threshold; 0 = off");
  number("flush_interval", c.output.flush_interval, "[s of wall time]");
  number("checkpoint_interval", c.output.checkpoint_interval,
         "[s of wall time] between restart points (RUN.h5.restart); 0 = only on SIGTERM/SIGINT");
  {
    out << "stations = [";
    for (std::size_t i = 0; i < c.output.stations.size(); ++i)
      out << (i ? ", " : "") << format_number(c.output.stations[i]);
    out << "]  # station positions x [m]; [] = none\n";
  }
  number("station_interval", c.output.station_interval, "[s]; 0 = every step");
  number("front_slip_rate", c.output.front_slip_rate, "[m/s] rupture-front threshold; 0 = off");
  name("kernel_cache", c.output.kernel_cache, "directory caching the strip kernels (HDF5, one file per key); \"\" = off");
  return out.str();
}

}  // namespace slipstrip
