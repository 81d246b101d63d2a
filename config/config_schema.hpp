#pragma once
// The config schema: every TOML key of a run declared once, with its section,
// name, type, SI unit, allowed range, help text, alternative and the member of
// SimulationConfig it binds to (its default is that member's initialiser).
//
// Everything else follows from this one table (config/config_schema.cpp):
//   * parsing and validation (config/config.cpp): unknown keys, types, ranges,
//     the key's extra rule and the messages naming key, value and what is allowed;
//   * to_toml, the resolved config written into every output file;
//   * config_to_table, from which the Python binding builds Config.as_dict();
//   * the key tables of docs/config.md (`slipstrip config-docs`, checked by a test).
//
// Physical limits are not coded here: the rules call the physics that owns them
// (kernels/elastic_material.hpp for the Poisson ratio, kernels/passivity.hpp
// for beta, friction/friction_law.hpp for the friction coefficients).
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

// Debian's libtomlplusplus-dev ships only toml.h; upstream names it toml.hpp.
#if __has_include(<toml++/toml.hpp>)
#include <toml++/toml.hpp>
#else
#include <toml++/toml.h>
#endif

#include "config/simulation_config.hpp"

namespace slipstrip {

enum class KeyType {
  number,              // finite TOML integer or float
  number_or_inf,       // a number, or +infinity written "inf" (a length without limit)
  integer,             // TOML integer
  choice,              // one of a list of names
  text,                // free string (a path)
  numbers,             // array of finite numbers
  friction_parameter,  // a number, or a profile along x (config/friction_profile_toml.hpp)
};

// An interval; infinite ends are open.  Constexpr so the schema is a constant.
struct ValueRange {
  double low = -std::numeric_limits<double>::infinity();
  bool low_inclusive = false;
  double high = std::numeric_limits<double>::infinity();
  bool high_inclusive = false;

  constexpr bool contains(double v) const {
    return (low_inclusive ? v >= low : v > low) && (high_inclusive ? v <= high : v < high);
  }
  constexpr bool has_low() const { return low > -std::numeric_limits<double>::infinity(); }
  constexpr bool has_high() const { return high < std::numeric_limits<double>::infinity(); }
  constexpr bool bounded() const { return has_low() || has_high(); }
};

// Thrown by a key's rule when the value is out of range.  `value` is the value
// as shown (an element of an array, or the key's value); what() is what is
// allowed.  The parser adds the place and the key.
struct KeyOutOfRange : std::runtime_error {
  KeyOutOfRange(std::string shown_value, const std::string& allowed)
      : std::runtime_error(allowed), value(std::move(shown_value)) {}
  std::string value;
};

// Thrown by a key or section rule with a complete message.  The parser points
// at the first of `keys` (names within the section) the file gives; none, or
// an empty list, gives no place.
struct ConfigRuleError : std::runtime_error {
  ConfigRuleError(std::vector<std::string_view> where, const std::string& message)
      : std::runtime_error(message), keys(std::move(where)) {}
  std::vector<std::string_view> keys;
};

// How a key reads and writes its member of SimulationConfig.  Only the pair
// matching the key's type is set (friction_parameter uses real and profile).
struct KeyBinding {
  double (*get_real)(const SimulationConfig&) = nullptr;
  void (*set_real)(SimulationConfig&, double) = nullptr;
  std::int64_t (*get_integer)(const SimulationConfig&) = nullptr;
  void (*set_integer)(SimulationConfig&, std::int64_t) = nullptr;
  std::string (*get_text)(const SimulationConfig&) = nullptr;
  void (*set_text)(SimulationConfig&, const std::string&) = nullptr;
  std::vector<double> (*get_list)(const SimulationConfig&) = nullptr;
  void (*set_list)(SimulationConfig&, const std::vector<double>&) = nullptr;
  const std::optional<ParameterProfile>& (*get_profile)(const SimulationConfig&) = nullptr;
  void (*set_profile)(SimulationConfig&, ParameterProfile) = nullptr;
};

struct ConfigKey {
  std::string_view section = {};
  std::string_view name = {};
  KeyType type = KeyType::number;
  std::string_view unit = {};  // SI unit; "" = dimensionless
  // How messages name the value: "a length" gives "expected a length > 0 [m]";
  // a bare symbol ("beta") gives the chained form "0 < beta <= 0.4".
  std::string_view noun = {};
  ValueRange allowed = {};              // checked on every value
  std::string_view allowed_note = {};   // appended to the allowed text: " (0 = off)"
  std::string_view allowed_message = {};  // replaces the generated allowed text when set
  ValueRange generous = {};             // the physically generous range (docs/config.md, "Ranges")
  std::string_view rule_text = {};      // docs: what `rule` adds to `allowed` (cross-key limits)
  std::string_view help = {};           // docs: meaning
  std::string_view comment = {};        // to_toml: the comment after the value
  // Set on the second key of a pair describing one quantity (dx for nodes):
  // exactly one may be given, it is resolved into the first one's member and
  // to_toml writes only the first.
  std::string_view alternative_to = {};
  std::vector<std::string_view> (*choices)() = nullptr;  // choice keys
  KeyBinding bind = {};
  // Extra checks (other keys, physics): throw KeyOutOfRange or ConfigRuleError.
  // Called after the type and the ranges, before the value is stored; the
  // config holds every key read before (sections in order, then within a
  // section the primary keys before the alternatives).
  void (*real_rule)(const SimulationConfig&, double) = nullptr;
  void (*integer_rule)(const SimulationConfig&, std::int64_t) = nullptr;
  void (*list_rule)(const SimulationConfig&, const std::vector<double>&) = nullptr;
  // A plausibility rule: the config is valid, but the key's value looks like a
  // unit mistake or would degrade the result.  Given the whole resolved
  // config, it returns the warning (naming the key, the value, why and what
  // to change), or "" when the value is plausible.  Never an error: the run
  // goes on.  `plausibility_text` says in docs/config.md when it warns.
  std::string (*plausibility)(const SimulationConfig&) = nullptr;
  std::string_view plausibility_text = {};

  std::string full_name() const { return std::string(section) + "." + std::string(name); }
};

struct ConfigSection {
  std::string_view name = {};
  // Rules between keys of the section, run once all its keys are read.
  void (*rule)(const SimulationConfig&) = nullptr;
};

// The sections in reading order, and every key in writing order.
std::span<const ConfigSection> config_sections();
std::span<const ConfigKey> config_keys();
// nullptr when absent.
const ConfigSection* find_config_section(std::string_view section);
const ConfigKey* find_config_key(std::string_view section, std::string_view name);

// Shortest decimal text that reads back to the same double, always a TOML
// float ("4" becomes "4.0"); "inf", "-inf", "nan" for the others.
std::string format_config_number(double value);
// Shortest decimal text without a forced ".0" ("0", "0.4", "1e-12").
std::string format_bound(double value);
// Three significant digits, for estimates and warnings ("0.0183", "6.5e+03").
std::string format_short(double value);
// A TOML basic string.
std::string quote_toml(std::string_view text);

// A range in words for `subject`: "x > 0", "0 < beta <= 0.4", "length between
// 1e-06 and 1e+06" (bare_symbol: always the chained form).
std::string range_text(const ValueRange& range, std::string_view subject, bool bare_symbol);
// What is allowed for `key` (without the key's extra rule), as messages say it:
// "a length > 0 [m]", "0 < beta <= 0.4 (dt = beta dx / c_s)".
std::string allowed_text(const ConfigKey& key);
// The generous range as messages say it: "a length between 1e-06 and 1e+06 [m]
// (the physically generous range of docs/config.md)".
std::string generous_text(const ConfigKey& key);

// The warnings of every key's plausibility rule for a resolved config, in key
// order (empty when everything is plausible).  The CLI prints them in the run
// header, `scan --dry-run` per run, and Python's run() as warnings.
std::vector<std::string> plausibility_warnings(const SimulationConfig& config);

// The value of `key` in `config` as TOML text (what to_toml writes after "=").
std::string toml_value_text(const ConfigKey& key, const SimulationConfig& config);
// The resolved config as a TOML table of tables, key for key what to_toml writes.
toml::table config_to_table(const SimulationConfig& config);


}  // namespace slipstrip
