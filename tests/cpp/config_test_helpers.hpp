#pragma once
// Shared by the config tests: the message of a rejected config, a temporary
// file (profiles' node files) and a bit-for-bit comparison of fields.
#include <cstring>
#include <filesystem>
#include <fstream>
#include <span>
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

inline bool same_bits(std::span<const double> a, std::span<const double> b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

// A temporary file removed at the end of the scope.
struct TempFile {
  std::filesystem::path path;
  TempFile(const std::string& name, const std::string& text)
      : path(std::filesystem::temp_directory_path() / name) {
    std::ofstream(path) << text;
  }
  ~TempFile() { std::filesystem::remove(path); }
};

}  // namespace slipstrip::testing
