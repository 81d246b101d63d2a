#pragma once
// A checksum of file content, so that damage after writing (a flipped bit, a
// torn copy, an edit) is found before the content is used: CRC-64/XZ (the
// polynomial of ECMA-182, reflected, as `xz` uses), which finds every
// error burst up to 64 bits and any odd number of flipped bits.  Not a
// protection against deliberate forgery.
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>

namespace slipstrip::io {

class Checksum {
 public:
  // Adds raw bytes.
  void add_bytes(const void* data, std::size_t size);

  // Adds a named item: the name, the number of values and the values'
  // little-endian bytes, so that the same values under another name, or split
  // differently between items, give another checksum.
  template <class T>
    requires std::is_arithmetic_v<T>
  void add(std::string_view name, std::span<const T> values) {
    add_tag(name, values.size());
    if constexpr (std::endian::native == std::endian::little) {
      add_bytes(values.data(), values.size_bytes());
    } else {
      for (const T& v : values) {
        unsigned char bytes[sizeof(T)];
        std::memcpy(bytes, &v, sizeof(T));
        for (std::size_t k = 0; k < sizeof(T); ++k) add_bytes(&bytes[sizeof(T) - 1 - k], 1);
      }
    }
  }
  template <class T>
    requires std::is_arithmetic_v<T>
  void add(std::string_view name, const T& value) {
    add(name, std::span<const T>(&value, 1));
  }
  void add(std::string_view name, std::string_view text);

  std::uint64_t value() const { return ~state_; }
  // "crc64-xz:" and 16 hex digits: how the value is stored (an HDF5 string
  // attribute; a 64-bit integer attribute would be read as signed by some tools).
  std::string text() const;

 private:
  void add_tag(std::string_view name, std::uint64_t count);
  std::uint64_t state_ = ~std::uint64_t{0};
};

}  // namespace slipstrip::io
