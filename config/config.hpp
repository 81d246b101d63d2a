#pragma once
// TOML configuration of one run: parse, validate, override, write back.
//
// Every key, its unit, default and allowed range are declared once in the
// config schema (config/config_schema.hpp) and listed in docs/config.md, which is
// generated from it.  All validation happens here, before any computation starts, so a bad file
// fails in milliseconds with a message that names the key, the value given
// and what is allowed -- never hours into a run.
#include <stdexcept>
#include <string>
#include <vector>

// Debian's libtomlplusplus-dev ships only toml.h; upstream names it toml.hpp.
#if __has_include(<toml++/toml.hpp>)
#include <toml++/toml.hpp>
#else
#include <toml++/toml.h>
#endif

#include "config/simulation_config.hpp"
#include "io/messages.hpp"

namespace slipstrip {

// Any problem with a configuration: unreadable file, TOML syntax, unknown
// section or key, wrong type, value out of range, conflicting keys, malformed
// override.  Derives from std::invalid_argument (the project's type for bad
// input), so `catch (const std::invalid_argument&)` catches it too.  The
// message is made one printable line of bounded length (io/messages.hpp)
// here, whatever value or file content it quotes.
struct ConfigError : std::invalid_argument {
  explicit ConfigError(const std::string& message) : std::invalid_argument(io::one_line(message)) {}
};

// Reads a TOML file, applies the overrides in order ("section.key=value"),
// validates everything and returns the resolved config.  Throws ConfigError.
SimulationConfig load_config_file(const std::string& path,
                                  const std::vector<std::string>& overrides = {});

// Same, from TOML text ("" gives the defaults of Table S1 of the paper).
SimulationConfig load_config_string(const std::string& toml_text,
                                    const std::vector<std::string>& overrides = {});

// Validates a parsed TOML document and resolves it (alternatives such as dx or
// duration_transits are turned into nodes and duration).  Throws ConfigError.
SimulationConfig config_from_table(const toml::table& root);

// Applies one override "section.key=value" to a parsed document.  The value is
// parsed as a TOML value (number, string, boolean, inf); text that is not a
// valid TOML value is taken as a string, so `state.law=slip` works unquoted.
// Unknown sections and keys are errors.  Setting one of a pair of alternative
// keys (nodes/dx, shear_modulus/youngs_modulus, duration/duration_transits)
// removes the other one, so an override always wins over the file.
void apply_override(toml::table& root, const std::string& assignment);

// The full resolved config as TOML: every key of every section, numbers in the
// shortest form that reads back to the same double, so
// load_config_string(to_toml(c)) reproduces c exactly (for a valid c).
std::string to_toml(const SimulationConfig& config);

}  // namespace slipstrip
