#define SCULPT_KERNEL_NAME evaluateCellsGeneric
#include "core/evaluation_kernel.inl"
