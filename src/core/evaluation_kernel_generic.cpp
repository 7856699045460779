#define SCULPT_KERNEL_NAME evaluateCellsGeneric
#define SCULPT_INCREMENT_NAME incrementCellsGeneric
#include "core/evaluation_kernel.inl"
