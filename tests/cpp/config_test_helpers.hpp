#pragma once
// Shared by the config tests: the message of a rejected config.
#include <string>
#include <vector>

#include "config/config.hpp"

namespace slipstrip::testing {

// The message of the ConfigError thrown by load_config_string(text, overrides).
inline std::string error_of(const std::string& text, const std::vector<std::string>& overrides = {}) {
  try {
    load_config_string(text, overrides);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "<no error>";
}

inline bool contains(const std::string& haystack, const std::string& needle) {
  return haystack.find(needle) != std::string::npos;
}

}  // namespace slipstrip::testing
