#pragma once
// TOML spelling of a friction parameter profile (friction/parameter_profile.hpp),
// self-contained so any config parser can call it for a [friction] key whose
// value is a table instead of a number (docs/config.md, "Parameters along x"):
//
//   a = { profile = "piecewise_linear",   x = [0.0, 1.0, 1.2, 4.0], values = [0.005, 0.005, 0.02, 0.02] }
//   a = { profile = "piecewise_constant", x = [0.0, 1.0, 1.2],      values = [0.005, 0.02, 0.005] }
//   a = { profile = "piecewise_linear",   z = [0.0, 0.1, 0.4, 0.5], values = [0.03, 0.005, 0.005, 0.03] }  # 2D interface
//   a = { profile = "node_file", path = "a_nodes.txt" }   # one number per line, one line per node
#include <filesystem>
#include <string>
#include <string_view>

// Debian's libtomlplusplus-dev ships only toml.h; upstream names it toml.hpp.
#if __has_include(<toml++/toml.hpp>)
#include <toml++/toml.hpp>
#else
#include <toml++/toml.h>
#endif

#include "friction/parameter_profile.hpp"

namespace slipstrip {

// Parses the table `node` given for `key` ("friction.a").  A relative node_file
// path is taken relative to the directory of the config file the node came
// from (the working directory for TOML text), and stored absolute, so the
// resolved config names the file wherever it is read back.  Throws
// std::invalid_argument naming the key and what is wrong (no file location:
// the caller adds it).
ParameterProfile parse_parameter_profile(const toml::node& node, std::string_view key);

// The same profile as a TOML inline table; parse_parameter_profile of it gives
// back the same profile (numbers in shortest round-trip form).
std::string parameter_profile_toml(const ParameterProfile& profile);

// Reads a node file: one finite number per line; blank lines and lines
// starting with '#' are skipped.  Throws std::invalid_argument naming `key`,
// the file and the line.
std::vector<double> read_node_file(const std::filesystem::path& path, std::string_view key);

}  // namespace slipstrip
