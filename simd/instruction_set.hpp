#pragma once
// Which vector instruction set the hot loops run with.  The vectorised
// friction solve (friction/batch_kernels.hpp) and the half-space history
// operator's mode loop (kernels/half_space_history.cpp) are compiled several
// times -- with the build's own flags ("baseline": SSE2 in a portable x86-64
// build) and, on x86-64, for AVX2 + FMA and for AVX-512 -- and the first call
// picks the widest set this CPU can run.  So one portable binary uses
// AVX-512 where the CPU has it.  See docs/performance.md, "Portable builds".
#include <string_view>
#include <vector>

namespace slipstrip::simd {

enum class InstructionSet {
  baseline,  // the build's own compiler flags; every CPU the binary runs on
  avx2,      // AVX2 and FMA (x86-64-v3 vector units; 4 doubles per register)
  avx512,    // AVX-512 F, CD, DQ, BW and VL (x86-64-v4; 8 doubles per register)
};

// Spellings for SLIPSTRIP_SIMD and reports (index = enumerator value).
inline constexpr std::string_view kInstructionSetNames[] = {"baseline", "avx2", "avx512"};
std::string_view to_string(InstructionSet set);

// Whether this build holds code for `set` (baseline always; avx2 and avx512 in
// x86-64 builds with GCC or Clang).
bool compiled(InstructionSet set);

// Whether this CPU, and its operating system, can run `set`'s instructions.
// (GCC's __builtin_cpu_supports reports a feature only when the operating
// system also saves its registers.)  This code is itself compiled with the
// baseline flags, so it is safe to call on any CPU.
bool cpu_supports(InstructionSet set);

// The sets compiled into this build that this CPU can run, widest first.
std::vector<InstructionSet> usable_instruction_sets();

// `requested` empty: the widest usable set.  Otherwise the set of that name,
// which must be compiled and usable; throws std::invalid_argument naming
// SLIPSTRIP_SIMD, the value and the allowed values otherwise.
InstructionSet choose_instruction_set(std::string_view requested);

// The set the hot loops use: choose_instruction_set(the environment variable
// SLIPSTRIP_SIMD, empty when unset), decided once per process.
InstructionSet instruction_set();

}  // namespace slipstrip::simd

// Function attributes that compile one function for a wider set (GCC and
// Clang on x86-64; the same feature lists as the -m flags CMakeLists.txt gives
// friction/batch_kernels_<set>.cpp, and as cpu_supports() checks).  Code that
// uses them calls the function only when instruction_set() says so.
#if SLIPSTRIP_X86_DISPATCH
#define SLIPSTRIP_TARGET_AVX2 __attribute__((target("avx2,fma")))
#define SLIPSTRIP_TARGET_AVX512 \
  __attribute__((target("avx512f,avx512cd,avx512dq,avx512bw,avx512vl,avx2,fma")))
#endif
