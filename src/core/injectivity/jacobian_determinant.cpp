// det J of the lattice deformation at parameter points and at the mesh's vertices (the det J overlay, Gain &
// Dodgson 2001, Theorem 1: positive everywhere for an injective deformation). Only the cells a displacement
// reaches are evaluated; the others have det J == 1 exactly.
#include "core/injectivity/injectivity.h"

#include <array>
#include <cstdint>
#include <vector>

#include "core/injectivity/injectivity_cell.h"
#include "core/injectivity/injectivity_internal.h"
#include "core/injectivity/injectivity_net.h"
#include "core/volume/embedding.h"

namespace sculpt::core {

using injectivity_detail::chunked;
using injectivity_detail::deformedCells;

double jacobianDeterminant(const Lattice& lattice, const Eigen::Vector3d& params) {
    if (chunked(lattice)) {
        Eigen::Vector3d local;
        const int chunk = lattice.volume->chunkOf(params, local);
        return chunk < 0 ? 1.0 : chunkJacobianDeterminant(lattice, chunk, local);
    }
    std::array<int, 3> cell;
    Eigen::Vector3d local;
    for (int a = 0; a < 3; ++a) cell[a] = lattice.axes[a].locate(params[a], local[a]);
    return jacobianDeterminantInCell(lattice, cell, local);
}

namespace {

// A net lattice: each vertex is frozen (Newton) only if one of the chunks whose bounds hold it is deformed;
// the others keep det J == 1 without the cost of freezing.
void netVertexJacobianDeterminants(const Lattice& lattice, const Positions& rest, const std::vector<std::uint8_t>& isDeformed,
                                   std::vector<double>& out) {
    const LatticeNet& net = *lattice.tensorNet();
    const int n = static_cast<int>(rest.rows());
    const int s0 = lattice.axes[0].spans, s1 = lattice.axes[1].spans;
#pragma omp parallel for schedule(dynamic, 64) if (n > 500)
    for (int v = 0; v < n; ++v) {
        thread_local std::vector<int> candidates;
        const Eigen::Vector3d point = rest.row(v).transpose();
        net.restIndex.candidates(point, candidates);
        bool any = false;
        for (int chunk : candidates) any = any || isDeformed[chunk];
        if (!any) continue;
        Eigen::Vector3d t;
        if (!restParameters(lattice, point, t)) continue;
        std::array<int, 3> cell;
        Eigen::Vector3d local;
        for (int a = 0; a < 3; ++a) cell[a] = lattice.axes[a].locate(t[a], local[a]);
        if (isDeformed[cell[0] + s0 * (cell[1] + s1 * cell[2])])
            out[static_cast<size_t>(v)] = netJacobianDeterminantInChunk(lattice, cell, local);
    }
}

}  // namespace

void vertexJacobianDeterminants(const Lattice& lattice, const Positions& rest, std::vector<double>& out) {
    const int n = static_cast<int>(rest.rows());
    out.assign(static_cast<size_t>(n), 1.0);
    // Cells without a moved control point in their support have det J == 1 exactly (J = I): after a local
    // drag that is most of the mesh, so only the deformed cells' vertices are evaluated.
    int cellCount = 0;
    const std::vector<int> deformed = deformedCells(lattice, {}, cellCount);
    if (deformed.empty()) return;
    std::vector<std::uint8_t> isDeformed(static_cast<size_t>(cellCount), 0);
    for (int cell : deformed) isDeformed[cell] = 1;
    if (lattice.tensorNet()) return netVertexJacobianDeterminants(lattice, rest, isDeformed, out);
    if (chunked(lattice)) {
#pragma omp parallel for schedule(dynamic, 64) if (n > 500)
        for (int v = 0; v < n; ++v) {
            Eigen::Vector3d t, local;
            if (!restParameters(lattice, rest.row(v).transpose(), t)) continue;
            const int chunk = lattice.volume->chunkOf(t, local);
            if (chunk >= 0 && isDeformed[static_cast<size_t>(chunk)])
                out[static_cast<size_t>(v)] = chunkJacobianDeterminant(lattice, chunk, local);
        }
        return;
    }
    const int s0 = lattice.axes[0].spans, s1 = lattice.axes[1].spans;
#pragma omp parallel for schedule(static) if (n > 2000)
    for (int v = 0; v < n; ++v) {
        Eigen::Vector3d t;
        if (!restParameters(lattice, rest.row(v).transpose(), t)) continue;
        std::array<int, 3> cell;
        Eigen::Vector3d local;
        for (int a = 0; a < 3; ++a) cell[a] = lattice.axes[a].locate(t[a], local[a]);
        if (isDeformed[cell[0] + s0 * (cell[1] + s1 * cell[2])])
            out[static_cast<size_t>(v)] = jacobianDeterminantInCell(lattice, cell, local);
    }
}

}  // namespace sculpt::core
