// sculpt_bench eval_full_8_vs_limit (issue 12, point 4): a reference for how fast a full evaluation of a cubic
// lattice can go on this machine, to hold the engine's evaluateAll against in the same run.
#pragma once

#include "core/volume/embedding.h"
#include "core/volume/lattice.h"

namespace sculpt::bench {

// True when the reference can run here: built for x86-64 with AVX2+FMA available, a polynomial lattice (unit
// weights) of degree 3 on every axis, one tensor product (not a chunked volume).
bool limitKernelApplies(const core::Lattice& lattice);

// The reference: written for speed alone, with AVX2/FMA intrinsics, in parallel over cells. Per cell the
// map in power form (Hu et al. 2001 eq. 1 on the cell's 64 control points, converted once); per four vertices
// three nested Horner schemes, 189 multiply-adds, the fewest this evaluation needs that we know of; read and
// written with unit stride: out{X,Y,Z}[e] = rest + displacement of
// entry e of embedding.order (cell order, structure of arrays, insideCount() values each). Nothing is
// scattered to the mesh's order, nothing is checked. Does nothing unless limitKernelApplies(lattice).
void evaluateCubicLimit(const core::Lattice& lattice, const core::Embedding& embedding, double* outX, double* outY,
                        double* outZ);

}  // namespace sculpt::bench
