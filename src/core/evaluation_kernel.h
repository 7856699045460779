// Internal: the per-cell evaluation kernel, compiled twice (generic and AVX2+FMA) and chosen at run time.
#pragma once

#include "core/embedding.h"

namespace sculpt::core::detail {

// Writes positions (row-major #V x 3) for the vertices of cells[first..last).
using CellKernel = void (*)(const Lattice& lattice, const Embedding& embedding, const int* cells, int cellCount,
                            double* positions);

void evaluateCellsGeneric(const Lattice&, const Embedding&, const int*, int, double*);
void evaluateCellsAvx2(const Lattice&, const Embedding&, const int*, int, double*);

}  // namespace sculpt::core::detail
