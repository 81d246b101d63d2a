// The choice of the instruction set (simd/instruction_set.hpp): the widest one
// this CPU can run unless SLIPSTRIP_SIMD names another, and a one-line error
// naming the variable, the value and what is allowed otherwise.
#include <doctest/doctest.h>

#include <stdexcept>
#include <string>

#include "simd/instruction_set.hpp"

using namespace slipstrip::simd;

TEST_CASE("instruction sets: baseline is always usable, the default is the widest usable") {
  const auto usable = usable_instruction_sets();
  REQUIRE(!usable.empty());
  CHECK(usable.back() == InstructionSet::baseline);
  CHECK(cpu_supports(InstructionSet::baseline));
  CHECK(compiled(InstructionSet::baseline));
  // Widest first: avx512 before avx2 before baseline.
  for (std::size_t i = 1; i < usable.size(); ++i)
    CHECK(static_cast<int>(usable[i - 1]) > static_cast<int>(usable[i]));
  CHECK(choose_instruction_set("") == usable.front());
  // AVX-512 implies AVX2 + FMA here (cpu_supports checks them too).
  if (cpu_supports(InstructionSet::avx512)) CHECK(cpu_supports(InstructionSet::avx2));
  MESSAGE("usable here: " << [&] {
    std::string s;
    for (auto set : usable) s += std::string(to_string(set)) + " ";
    return s;
  }());
}

TEST_CASE("instruction sets: SLIPSTRIP_SIMD names a usable set, or fails naming what is allowed") {
  for (auto set : usable_instruction_sets()) CHECK(choose_instruction_set(to_string(set)) == set);
  for (const char* bad : {"sse9", "AVX2", " avx2"}) {
    try {
      (void)choose_instruction_set(bad);
      FAIL("expected std::invalid_argument for " << bad);
    } catch (const std::invalid_argument& e) {
      const std::string message = e.what();
      CHECK(message.find("SLIPSTRIP_SIMD = '" + std::string(bad) + "'") == 0);
      CHECK(message.find("no such instruction set") != std::string::npos);
      CHECK(message.find("baseline") != std::string::npos);
      CHECK(message.find('\n') == std::string::npos);
    }
  }
  for (auto set : {InstructionSet::avx2, InstructionSet::avx512}) {
    if (compiled(set) && cpu_supports(set)) continue;
    CHECK_THROWS_WITH_AS((void)choose_instruction_set(to_string(set)),
                         doctest::Contains("is invalid"), std::invalid_argument);
  }
}
