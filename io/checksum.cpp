#include "io/checksum.hpp"

#include <array>
#include <cstdio>

namespace slipstrip::io {
namespace {

// The byte table of the reflected ECMA-182 polynomial.
constexpr std::array<std::uint64_t, 256> make_table() {
  constexpr std::uint64_t polynomial = 0xC96C5795D7870F42ull;
  std::array<std::uint64_t, 256> table{};
  for (std::uint64_t byte = 0; byte < 256; ++byte) {
    std::uint64_t crc = byte;
    for (int bit = 0; bit < 8; ++bit) crc = (crc & 1) ? (crc >> 1) ^ polynomial : crc >> 1;
    table[byte] = crc;
  }
  return table;
}
constexpr auto kTable = make_table();

}  // namespace

void Checksum::add_bytes(const void* data, std::size_t size) {
  const auto* bytes = static_cast<const unsigned char*>(data);
  std::uint64_t crc = state_;
  for (std::size_t k = 0; k < size; ++k) crc = kTable[(crc ^ bytes[k]) & 0xFF] ^ (crc >> 8);
  state_ = crc;
}

void Checksum::add_tag(std::string_view name, std::uint64_t count) {
  add_bytes(name.data(), name.size());
  const unsigned char separator = 0;
  add_bytes(&separator, 1);
  unsigned char le[8];
  for (int k = 0; k < 8; ++k) le[k] = static_cast<unsigned char>(count >> (8 * k));
  add_bytes(le, sizeof le);
}

void Checksum::add(std::string_view name, std::string_view text) {
  add_tag(name, text.size());
  add_bytes(text.data(), text.size());
}

std::string Checksum::text() const {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "crc64-xz:%016llx", static_cast<unsigned long long>(value()));
  return buffer;
}

}  // namespace slipstrip::io
