// The batch kernels for AVX2 with FMA (4 doubles per register).  CMake
// compiles this file alone with -mavx2 -mfma (x86-64 only); batch_kernels()
// runs it only when simd::instruction_set() is avx2.
#define SLIPSTRIP_BATCH_X86_ONLY
#define SLIPSTRIP_BATCH_ARCH xsimd::fma3<xsimd::avx2>
#define SLIPSTRIP_BATCH_SET avx2
#define SLIPSTRIP_BATCH_KERNELS kAvx2BatchKernels
#include "friction/batch_kernels.inc"
