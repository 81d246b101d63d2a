#pragma once
// Attributes on a file, group or dataset (io/hdf5.hpp for errors).
//
// The one string encoding: every string slipstrip writes (attribute or
// dataset, scalar or array) is variable-length UTF-8.  h5py then returns a
// plain `str` (no bytes to decode), and a long text such as the resolved
// config has no fixed-size limit.  Readers accept fixed-length and ASCII
// strings too, so files written before the encoding was unified still read.
//
// Numbers are stored in a fixed little-endian file type chosen from the C++
// type: double -> float64, float -> float32, signed/unsigned 8/16/32/64-bit
// integers -> the integer of that width and sign.
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "io/hdf5.hpp"

namespace slipstrip::io {

// A C++ number type with an HDF5 counterpart (bool and char are not numbers here).
template <class T>
concept Number = std::is_arithmetic_v<T> && !std::is_same_v<T, bool> && !std::is_same_v<T, char>;

// The in-memory (native) and stored (little-endian) HDF5 types of T.
struct NumberTypes {
  hid_t memory;
  hid_t file;
};
NumberTypes number_types(bool floating, bool is_signed, std::size_t size);
template <Number T>
NumberTypes number_types() {
  return number_types(std::is_floating_point_v<T>, std::is_signed_v<T>, sizeof(T));
}

bool has_attribute(hid_t object, const std::string& name);
void remove_attribute_if_present(hid_t object, const std::string& name);
std::vector<std::string> attribute_names(hid_t object);

// Scalar attributes; an existing attribute of the same name is replaced.
void write_attribute(hid_t object, const std::string& name, std::string_view text);
inline void write_attribute(hid_t object, const std::string& name, const char* text) {
  write_attribute(object, name, std::string_view(text));
}
inline void write_attribute(hid_t object, const std::string& name, const std::string& text) {
  write_attribute(object, name, std::string_view(text));
}
void write_number_attribute(hid_t object, const std::string& name, NumberTypes types, const void* value);
template <Number T>
void write_attribute(hid_t object, const std::string& name, T value) {
  write_number_attribute(object, name, number_types<T>(), &value);
}
// A 1-D array of strings.
void write_attribute(hid_t object, const std::string& name, std::span<const std::string> texts);

// Reading.  A missing attribute, or one whose shape or type does not fit,
// throws std::invalid_argument naming the file, object and attribute.
std::string read_string_attribute(hid_t object, const std::string& name);
std::vector<std::string> read_string_array_attribute(hid_t object, const std::string& name);
void read_number_attribute(hid_t object, const std::string& name, hid_t memory_type, void* value);
// A scalar number (integer or float in the file; converted to T by HDF5).
template <Number T>
T read_attribute(hid_t object, const std::string& name) {
  T value{};
  read_number_attribute(object, name, number_types<T>().memory, &value);
  return value;
}

}  // namespace slipstrip::io
