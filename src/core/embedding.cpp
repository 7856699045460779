#include "core/embedding.h"

#include <algorithm>
#include <numeric>

#include "core/evaluation_kernel.h"

namespace sculpt::core {

namespace {

detail::CellKernel chooseKernel(const char** name) {
#if defined(SCULPT_HAVE_AVX2_KERNEL)
    if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) {
        *name = "avx2-fma";
        return detail::evaluateCellsAvx2;
    }
#endif
    *name = "generic";
    return detail::evaluateCellsGeneric;
}

const char* gKernelName = nullptr;
const detail::CellKernel gKernel = chooseKernel(&gKernelName);

}  // namespace

const char* evaluationKernelName() { return gKernelName; }

Embedding embedVertices(const Lattice& lattice, const Positions& rest) {
    Embedding e;
    const int n = static_cast<int>(rest.rows());
    e.vertexCount = n;
    const std::array<int, 3> spans = lattice.spans();
    const int cellCount = lattice.cellCount();
    // Counting sort by cell: stable, O(n + cells).
    std::vector<int> cellOf(n, -1);
    std::vector<double> local(3 * static_cast<size_t>(n));
#pragma omp parallel for schedule(static)
    for (int v = 0; v < n; ++v) {
        Eigen::Vector3d t;
        if (!restParameters(lattice, rest.row(v).transpose(), t)) continue;
        int s[3];
        for (int a = 0; a < 3; ++a) s[a] = lattice.axes[a].locate(t[a], local[3 * static_cast<size_t>(v) + a]);
        cellOf[v] = s[0] + spans[0] * (s[1] + spans[1] * s[2]);
    }
    e.cellStart.assign(static_cast<size_t>(cellCount) + 1, 0);
    for (int v = 0; v < n; ++v)
        if (cellOf[v] >= 0) ++e.cellStart[cellOf[v] + 1];
    std::partial_sum(e.cellStart.begin(), e.cellStart.end(), e.cellStart.begin());
    const int inside = e.cellStart.back();
    e.order.resize(inside);
    std::vector<int> cursor(e.cellStart.begin(), e.cellStart.end() - 1);
    for (int v = 0; v < n; ++v)
        if (cellOf[v] >= 0) e.order[cursor[cellOf[v]]++] = v;
    e.localX.resize(inside);
    e.localY.resize(inside);
    e.localZ.resize(inside);
    e.restX.resize(inside);
    e.restY.resize(inside);
    e.restZ.resize(inside);
#pragma omp parallel for schedule(static)
    for (int s = 0; s < inside; ++s) {
        const int v = e.order[s];
        e.localX[s] = local[3 * static_cast<size_t>(v) + 0];
        e.localY[s] = local[3 * static_cast<size_t>(v) + 1];
        e.localZ[s] = local[3 * static_cast<size_t>(v) + 2];
        e.restX[s] = rest(v, 0);
        e.restY[s] = rest(v, 1);
        e.restZ[s] = rest(v, 2);
    }
    return e;
}

std::vector<int> cellsInfluencedBy(const Lattice& lattice, const std::vector<int>& controlPoints) {
    const std::array<int, 3> spans = lattice.spans();
    std::vector<int> cells;
    for (int idx : controlPoints) {
        const std::array<int, 3> c = lattice.ijk(idx);
        // Control point i has support on spans [i - p, i] (clamped to the existing spans).
        int lo[3], hi[3];
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::max(0, c[a] - lattice.degree[a]);
            hi[a] = std::min(spans[a] - 1, c[a]);
        }
        for (int w = lo[2]; w <= hi[2]; ++w)
            for (int v = lo[1]; v <= hi[1]; ++v)
                for (int u = lo[0]; u <= hi[0]; ++u) cells.push_back(u + spans[0] * (v + spans[1] * w));
    }
    std::sort(cells.begin(), cells.end());
    cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
    return cells;
}

void evaluateAll(const Lattice& lattice, const Embedding& embedding, Positions& positions) {
    std::vector<int> cells(lattice.cellCount());
    std::iota(cells.begin(), cells.end(), 0);
    gKernel(lattice, embedding, cells.data(), static_cast<int>(cells.size()), positions.data());
}

void evaluateCells(const Lattice& lattice, const Embedding& embedding, const std::vector<int>& cells,
                   Positions& positions, std::vector<int>* movedVertices) {
    gKernel(lattice, embedding, cells.data(), static_cast<int>(cells.size()), positions.data());
    if (movedVertices)
        for (int cell : cells)
            movedVertices->insert(movedVertices->end(), embedding.order.begin() + embedding.cellStart[cell],
                                  embedding.order.begin() + embedding.cellStart[cell + 1]);
}

}  // namespace sculpt::core
