// Compiled with -mavx2 -mfma where the compiler targets x86-64 (see src/core/CMakeLists.txt); only called
// after a run-time CPU check, so the binary still runs on CPUs without AVX2.
#if defined(SCULPT_HAVE_AVX2_KERNEL)
#define SCULPT_KERNEL_NAME evaluateCellsAvx2
#define SCULPT_INCREMENT_NAME incrementCellsAvx2
#define SCULPT_CELL_ORDER_NAME evaluateInCellOrderAvx2
#include "core/spline/evaluation_kernel.inl"
#endif
