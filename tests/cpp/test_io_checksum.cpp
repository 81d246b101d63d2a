// io/checksum: CRC-64/XZ against its published check value, and the named
// items: a single flipped bit anywhere, a renamed item or values moved
// between items all change the checksum.
#include <doctest/doctest.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "io/checksum.hpp"

using namespace slipstrip;

TEST_CASE("CRC-64/XZ of '123456789' is the catalogue's check value") {
  io::Checksum c;
  c.add_bytes("123456789", 9);
  CHECK(c.value() == 0x995DC9BBDF1939FAull);
  CHECK(c.text() == "crc64-xz:995dc9bbdf1939fa");
  CHECK(io::Checksum().value() == 0);  // the empty message
}

TEST_CASE("every single flipped bit of a field changes the checksum") {
  std::vector<double> field = {0.0, 1.5, -2.25, 1e-300, 3.0e8};
  const auto of = [](const std::vector<double>& f) {
    io::Checksum c;
    c.add<double>("slip", f);
    return c.value();
  };
  const std::uint64_t reference = of(field);
  for (std::size_t i = 0; i < field.size(); ++i)
    for (int bit = 0; bit < 64; ++bit) {
      auto flipped = field;
      std::uint64_t raw;
      std::memcpy(&raw, &flipped[i], 8);
      raw ^= std::uint64_t{1} << bit;
      std::memcpy(&flipped[i], &raw, 8);
      CHECK(of(flipped) != reference);
    }
}

TEST_CASE("names and item boundaries are part of the checksum") {
  const std::vector<double> a = {1.0, 2.0}, b = {3.0};
  io::Checksum one, renamed, moved;
  one.add<double>("slip", a);
  one.add<double>("state", b);
  renamed.add<double>("slip_rate", a);
  renamed.add<double>("state", b);
  moved.add<double>("slip", std::vector<double>{1.0});
  moved.add<double>("state", std::vector<double>{2.0, 3.0});
  CHECK(one.value() != renamed.value());
  CHECK(one.value() != moved.value());
  io::Checksum t1, t2;
  t1.add("config", std::string_view("a = 1"));
  t2.add("config", std::string_view("a = 2"));
  CHECK(t1.value() != t2.value());
  io::Checksum s1, s2;
  s1.add("step_index", std::int64_t{300});
  s2.add("step_index", std::int64_t{299});
  CHECK(s1.value() != s2.value());
}
