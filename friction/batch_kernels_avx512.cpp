// The batch kernels for AVX-512 (8 doubles per register; xsimd's avx512bw).
// CMake compiles this file alone with AVX-512 F, CD, DQ, BW and VL, AVX2 and
// FMA switched on (x86-64 only); batch_kernels() runs it only when
// simd::instruction_set() is avx512.
#define SLIPSTRIP_BATCH_X86_ONLY
#define SLIPSTRIP_BATCH_ARCH xsimd::avx512bw
#define SLIPSTRIP_BATCH_SET avx512
#define SLIPSTRIP_BATCH_KERNELS kAvx512BatchKernels
#include "friction/batch_kernels.inc"
