// Small helpers shared by the io/ tests: a per-process temporary file name and
// the message of an expected exception.
#pragma once

#include <unistd.h>

#include <exception>
#include <filesystem>
#include <string>

namespace slipstrip::io_test {

// One name per process, so two test programs running side by side never share a file.
inline std::string temp_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("slipstrip_io_" + std::to_string(getpid()) + "_" + name + ".h5"))
      .string();
}

// An error message, or "<no error>".
template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "<no error>";
}

inline bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

}  // namespace slipstrip::io_test
