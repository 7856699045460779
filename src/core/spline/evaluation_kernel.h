// Internal: the per-cell evaluation kernel, compiled twice (generic and AVX2+FMA) and chosen at run time.
#pragma once

#include <cstdint>

#include "core/volume/embedding.h"

namespace sculpt::core::detail {

// Writes positions (row-major #V x 3) for the vertices of cells[first..last).
using CellKernel = void (*)(const Lattice& lattice, const Embedding& embedding, const int* cells, int cellCount,
                            double* positions);

void evaluateCellsGeneric(const Lattice&, const Embedding&, const int*, int, double*);
void evaluateCellsAvx2(const Lattice&, const Embedding&, const int*, int, double*);

// Adds sum R_c(t) increment_c over the control points c with changed[c] != 0 (polynomial lattices only).
using IncrementKernel = void (*)(const Lattice& lattice, const Embedding& embedding, const int* cells, int cellCount,
                                 const Positions& increment, const std::uint8_t* changed, double* positions);
void incrementCellsGeneric(const Lattice&, const Embedding&, const int*, int, const Positions&, const std::uint8_t*, double*);
void incrementCellsAvx2(const Lattice&, const Embedding&, const int*, int, const Positions&, const std::uint8_t*, double*);

// For the benchmark (eval_full_8_in_cell_order): the same kernel with entry e of embedding.order written to
// row e of out (#inside x 3, row-major), i.e. the vertices stored in cell order and nothing scattered back to
// the mesh's order. Equal degrees on the three axes only (with mixed degrees nothing is written).
void evaluateInCellOrderGeneric(const Lattice&, const Embedding&, double*);
void evaluateInCellOrderAvx2(const Lattice&, const Embedding&, double*);

}  // namespace sculpt::core::detail
