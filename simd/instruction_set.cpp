#include "simd/instruction_set.hpp"

#include <cstdlib>
#include <stdexcept>
#include <string>

namespace slipstrip::simd {

std::string_view to_string(InstructionSet set) {
  const auto i = static_cast<std::size_t>(set);
  if (i >= std::size(kInstructionSetNames))
    throw std::invalid_argument("instruction set: unknown enumerator " + std::to_string(i));
  return kInstructionSetNames[i];
}

bool compiled(InstructionSet set) {
#if SLIPSTRIP_X86_DISPATCH
  (void)set;
  return true;
#else
  return set == InstructionSet::baseline;
#endif
}

bool cpu_supports(InstructionSet set) {
  switch (set) {
    case InstructionSet::baseline:
      return true;
    case InstructionSet::avx2:
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
      __builtin_cpu_init();
      return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#else
      return false;
#endif
    case InstructionSet::avx512:
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
      __builtin_cpu_init();
      return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512cd") &&
             __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512bw") &&
             __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx2") &&
             __builtin_cpu_supports("fma");
#else
      return false;
#endif
  }
  return false;
}

std::vector<InstructionSet> usable_instruction_sets() {
  std::vector<InstructionSet> usable;
  for (auto set : {InstructionSet::avx512, InstructionSet::avx2, InstructionSet::baseline})
    if (compiled(set) && cpu_supports(set)) usable.push_back(set);
  return usable;
}

InstructionSet choose_instruction_set(std::string_view requested) {
  const auto usable = usable_instruction_sets();
  if (requested.empty()) return usable.front();
  std::string allowed;
  for (auto set : usable) {
    if (to_string(set) == requested) return set;
    allowed += (allowed.empty() ? "" : ", ") + std::string(to_string(set));
  }
  std::string reason = "no such instruction set";
  for (std::size_t i = 0; i < std::size(kInstructionSetNames); ++i)
    if (kInstructionSetNames[i] == requested)
      reason = compiled(static_cast<InstructionSet>(i)) ? "this CPU cannot run it"
                                                        : "this build has no code for it";
  throw std::invalid_argument("SLIPSTRIP_SIMD = '" + std::string(requested) + "' is invalid: " +
                              reason + "; allowed on this machine: " + allowed +
                              " (unset: the widest)");
}

InstructionSet instruction_set() {
  // Decided once.  A bad SLIPSTRIP_SIMD throws on every call: the static is
  // initialised only by a call that returns.
  static const InstructionSet chosen = [] {
    const char* requested = std::getenv("SLIPSTRIP_SIMD");
    return choose_instruction_set(requested ? requested : "");
  }();
  return chosen;
}

}  // namespace slipstrip::simd
