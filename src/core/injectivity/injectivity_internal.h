// What injectivity.cpp (the tests) and jacobian_determinant.cpp (det J at points and vertices) share.
// Internal to src/core/injectivity.
#pragma once

#include <array>
#include <vector>

#include "core/volume/lattice.h"

namespace sculpt::core::injectivity_detail {

// A volume that is not one tensor product (volume.h): its cells are its chunks, reported as (chunk, 0, 0).
inline bool chunked(const Lattice& lattice) { return lattice.volume && !lattice.tensorNet(); }

// A cell's index triple (i, j, k) from its linear index; a chunk's is (chunk, 0, 0).
inline std::array<int, 3> cellIjk(const Lattice& lattice, int cell) {
    if (chunked(lattice)) return {cell, 0, 0};
    const int s0 = lattice.axes[0].spans, s1 = lattice.axes[1].spans;
    return {cell % s0, (cell / s0) % s1, cell / (s0 * s1)};
}

// The requested cells (all for an empty list; the chunks of a net lattice) that have a non-zero displacement
// somewhere in their support, in increasing order; cells outside this list have det J == 1 exactly.
// requestedCount gets the size of the request.
std::vector<int> deformedCells(const Lattice& lattice, const std::vector<int>& requested, int& requestedCount);

}  // namespace sculpt::core::injectivity_detail
