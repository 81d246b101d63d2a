#pragma once
// Internal to io/: the one string encoding (variable-length UTF-8) shared by
// string attributes and string datasets, the reader that also accepts
// fixed-length and ASCII strings, and the collector of member and attribute names.
#include <span>
#include <string>
#include <vector>

#include "io/hdf5.hpp"

namespace slipstrip::io {

// Iteration callback of H5Literate (Info = H5L_info_t) and H5Aiterate2
// (Info = H5A_info_t) that appends each name to the std::vector<std::string>
// passed as `names`.
template <class Info>
herr_t append_name(hid_t, const char* name, const Info*, void* names) {
  static_cast<std::vector<std::string>*>(names)->emplace_back(name);
  return 0;
}

// A variable-length, NUL-terminated UTF-8 string type.
Handle utf8_string_type();

// Pointers to the texts' characters, for writing variable-length strings.
std::vector<const char*> c_strings(std::span<const std::string> texts);

// Reads `count` strings stored with `stored_type` (fixed or variable length,
// ASCII or UTF-8).  `read(memory_type, buffer)` is H5Aread or H5Dread of the
// whole object; returns {} if it failed (HDF5's error stack tells why).
template <class Read>
std::vector<std::string> read_string_values(hid_t stored_type, std::size_t count, Read&& read);

}  // namespace slipstrip::io

// --- implementation -----------------------------------------------------------

namespace slipstrip::io {

template <class Read>
std::vector<std::string> read_string_values(hid_t stored_type, std::size_t count, Read&& read) {
  std::vector<std::string> texts;
  if (count == 0) return texts;
  texts.reserve(count);
  if (H5Tis_variable_str(stored_type) > 0) {
    Handle memory(H5Tcopy(H5T_C_S1), "H5Tcopy");
    check(H5Tset_size(memory, H5T_VARIABLE), "H5Tset_size");
    // HDF5 does not convert between ASCII and UTF-8: read in the stored set.
    check(H5Tset_cset(memory, H5Tget_cset(stored_type)), "H5Tset_cset");
    std::vector<char*> pointers(count, nullptr);
    const herr_t status = read(memory.get(), static_cast<void*>(pointers.data()));
    for (char* p : pointers) {
      if (status >= 0) texts.emplace_back(p ? p : "");
      if (p) H5free_memory(p);
    }
    if (status < 0) texts.clear();
    return texts;
  }
  const std::size_t size = H5Tget_size(stored_type);
  Handle memory(H5Tcopy(stored_type), "H5Tcopy");
  std::string buffer(count * size, '\0');
  if (read(memory.get(), static_cast<void*>(buffer.data())) < 0) return texts;
  for (std::size_t k = 0; k < count; ++k) {
    std::string text = buffer.substr(k * size, size);
    // Fixed-length strings are padded with NULs (or spaces, H5T_STR_SPACEPAD).
    const bool space_padded = H5Tget_strpad(stored_type) == H5T_STR_SPACEPAD;
    const auto end = text.find('\0');
    if (end != std::string::npos) text.resize(end);
    while (space_padded && !text.empty() && text.back() == ' ') text.pop_back();
    texts.push_back(std::move(text));
  }
  return texts;
}

}  // namespace slipstrip::io
