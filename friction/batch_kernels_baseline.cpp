// The batch kernels compiled with the build's own flags: xsimd's widest
// architecture for them (SSE2 in a portable x86-64 build, the building CPU's
// best with SLIPSTRIP_NATIVE=ON, NEON on 64-bit ARM).  Every CPU the binary
// runs on can run this copy.
#define SLIPSTRIP_BATCH_ARCH xsimd::default_arch
#define SLIPSTRIP_BATCH_SET baseline
#define SLIPSTRIP_BATCH_KERNELS kBaselineBatchKernels
#include "friction/batch_kernels.inc"
