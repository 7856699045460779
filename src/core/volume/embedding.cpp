#include "core/volume/embedding.h"

#include <algorithm>
#include <limits>
#include <numeric>

#include <Eigen/LU>

#include "core/spline/evaluation_kernel.h"

namespace sculpt::core {

namespace {

bool haveAvx2() {
#if defined(SCULPT_HAVE_AVX2_KERNEL)
    return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#else
    return false;
#endif
}

const bool gAvx2 = haveAvx2();
const char* gKernelName = gAvx2 ? "avx2-fma" : "generic";
#if defined(SCULPT_HAVE_AVX2_KERNEL)
const detail::CellKernel gKernel = gAvx2 ? detail::evaluateCellsAvx2 : detail::evaluateCellsGeneric;
const auto gInCellOrder = gAvx2 ? detail::evaluateInCellOrderAvx2 : detail::evaluateInCellOrderGeneric;
const detail::IncrementKernel gIncrement = gAvx2 ? detail::incrementCellsAvx2 : detail::incrementCellsGeneric;
#else
const detail::CellKernel gKernel = detail::evaluateCellsGeneric;
const auto gInCellOrder = detail::evaluateInCellOrderGeneric;
const detail::IncrementKernel gIncrement = detail::incrementCellsGeneric;
#endif

}  // namespace

const char* evaluationKernelName() { return gKernelName; }

namespace {

// Cell of one axis and the local coordinate in it, for a point known to be inside the box.
// note: u * spans >= 0, so truncation is floor (std::floor is a libm call in the default x86-64 build).
inline int spanOf(double u, int spans, double& local) {
    const double scaled = u * spans;
    int span = static_cast<int>(scaled);
    if (span > spans - 1) span = spans - 1;
    local = scaled - span;
    return span;
}

}  // namespace

namespace {

// A box lattice's parameters of x clamped to [0,1]^3: those of the nearest point of the box.
Eigen::Vector3d clampedParameters(const Lattice& lattice, const Eigen::Vector3d& x) {
    Eigen::Vector3d t;
    for (int a = 0; a < 3; ++a) t[a] = std::clamp((x[a] - lattice.boxMin[a]) / (lattice.boxMax[a] - lattice.boxMin[a]), 0.0, 1.0);
    return t;
}

// The closed-box test of the embedding (every vertex is either embedded or in the collar).
bool insideBox(const Lattice& lattice, const Eigen::Vector3d& x) {
    return (x.array() >= lattice.boxMin.array()).all() && (x.array() <= lattice.boxMax.array()).all();
}

void clearCollar(Embedding& e) {
    e.collarVertex.clear();
    e.collarCell.clear();
    e.collarParams.clear();
    e.collarRest.clear();
}

}  // namespace

Embedding embedVertices(const Lattice& lattice, const Positions& rest) {
    Embedding e;
    embedVertices(lattice, rest, e);
    return e;
}

namespace {

void embedVertexSet(const Lattice& lattice, const Positions& rest, Embedding& e, const std::vector<int>* only) {
    const int n = static_cast<int>(rest.rows());
    // The vertices tested: all, or `only` (entry i is vertex vertexAt(i)).
    const int tested = only ? static_cast<int>(only->size()) : n;
    const auto vertexAt = [&](int i) { return only ? (*only)[static_cast<size_t>(i)] : i; };
    e.vertexCount = n;
    clearCollar(e);  // a cage's collar is embedded apart (embedCollar), after this
    const std::array<int, 3> spans = lattice.spans();
    const int cellCount = lattice.cellCount();
    const double lo[3] = {lattice.boxMin.x(), lattice.boxMin.y(), lattice.boxMin.z()};
    const double hi[3] = {lattice.boxMax.x(), lattice.boxMax.y(), lattice.boxMax.z()};
    const double* positions = rest.data();
    // The parameters are the box's linear map (restParameters), inlined here: this runs on every re-embedding.
    // A lattice of another kind freezes each vertex (Coquillart 1990, 3.3) once, in pass 1, into scratchParams.
    const bool net = lattice.volume != nullptr;
    const bool turned = lattice.boxTurned();  // a turned box (lattice.h): its coordinates are boxAxes * x
    // A volume that is not one tensor product: its cells are its chunks (Volume::chunkOf).
    const Volume* chunked = lattice.volume && !lattice.tensorNet() ? lattice.volume.get() : nullptr;
    auto parameters = [&](int v, double t[3]) {
        if (net) {
            const double* frozen = &e.scratchParams[3 * static_cast<size_t>(v)];
            if (!(frozen[0] >= 0.0)) return false;  // NaN marks a vertex outside every chunk
            for (int a = 0; a < 3; ++a) t[a] = frozen[a];
            return true;
        }
        if (turned) {
            const Eigen::Vector3d b = lattice.boxAxes * Eigen::Vector3d(positions[3 * static_cast<size_t>(v)], positions[3 * static_cast<size_t>(v) + 1],
                                                                        positions[3 * static_cast<size_t>(v) + 2]);
            for (int a = 0; a < 3; ++a) {
                if (!(b[a] >= lo[a] && b[a] <= hi[a])) return false;
                t[a] = std::clamp((b[a] - lo[a]) / (hi[a] - lo[a]), 0.0, 1.0);
            }
            return true;
        }
        for (int a = 0; a < 3; ++a) {
            const double x = positions[3 * static_cast<size_t>(v) + a];
            if (!(x >= lo[a] && x <= hi[a])) return false;
            t[a] = std::clamp((x - lo[a]) / (hi[a] - lo[a]), 0.0, 1.0);
        }
        return true;
    };

    if (net) {
        e.scratchParams.resize(3 * static_cast<size_t>(n));
#pragma omp parallel for schedule(dynamic, 256) if (n > 2000)
        for (int v = 0; v < n; ++v) {
            Eigen::Vector3d t;
            double* frozen = &e.scratchParams[3 * static_cast<size_t>(v)];
            if (restParameters(lattice, rest.row(v).transpose(), t)) {
                for (int a = 0; a < 3; ++a) frozen[a] = t[a];
            } else {
                frozen[0] = frozen[1] = frozen[2] = std::numeric_limits<double>::quiet_NaN();
            }
        }
    }
    // Pass 1: the cell of every vertex (-1 outside the box).
    std::vector<int>& cellOf = e.scratchCell;  // per tested vertex
    cellOf.resize(tested);
#pragma omp parallel for schedule(static) if (tested > 20000)
    for (int i = 0; i < tested; ++i) {
        const int v = vertexAt(i);
        double t[3] = {0.0, 0.0, 0.0}, local = 0.0;
        if (!parameters(v, t)) {
            cellOf[i] = -1;
            continue;
        }
        if (chunked) {
            Eigen::Vector3d localT;
            cellOf[i] = chunked->chunkOf(Eigen::Vector3d(t[0], t[1], t[2]), localT);
            continue;
        }
        cellOf[i] = spanOf(t[0], spans[0], local) + spans[0] * (spanOf(t[1], spans[1], local) + spans[1] * spanOf(t[2], spans[2], local));
    }
    // Counting sort by cell: stable, O(n + cells).
    e.cellStart.assign(static_cast<size_t>(cellCount) + 1, 0);
    for (int i = 0; i < tested; ++i) ++e.cellStart[cellOf[i] + 1];  // outside vertices land in slot 0, dropped below
    e.cellStart[0] = 0;
    std::partial_sum(e.cellStart.begin(), e.cellStart.end(), e.cellStart.begin());
    const int inside = e.cellStart.back();
    e.order.resize(inside);
    {
        std::vector<int>& cursor = e.scratchCursor;
        cursor.assign(e.cellStart.begin(), e.cellStart.end() - 1);
        for (int i = 0; i < tested; ++i)
            if (cellOf[i] >= 0) e.order[cursor[cellOf[i]]++] = vertexAt(i);
    }
    // Pass 2: local coordinates and rest positions in cell order, so the kernel reads them sequentially.
    e.localX.resize(inside);
    e.localY.resize(inside);
    e.localZ.resize(inside);
    e.restX.resize(inside);
    e.restY.resize(inside);
    e.restZ.resize(inside);
#pragma omp parallel for schedule(static) if (inside > 20000)
    for (int s = 0; s < inside; ++s) {
        const int v = e.order[s];
        double t[3] = {0.0, 0.0, 0.0};
        parameters(v, t);  // inside by construction of `order`
        if (chunked) {
            Eigen::Vector3d localT;
            chunked->chunkOf(Eigen::Vector3d(t[0], t[1], t[2]), localT);
            e.localX[s] = localT[0], e.localY[s] = localT[1], e.localZ[s] = localT[2];
        } else {
            spanOf(t[0], spans[0], e.localX[s]);
        spanOf(t[1], spans[1], e.localY[s]);
            spanOf(t[2], spans[2], e.localZ[s]);
        }
        e.restX[s] = positions[3 * static_cast<size_t>(v)];
        e.restY[s] = positions[3 * static_cast<size_t>(v) + 1];
        e.restZ[s] = positions[3 * static_cast<size_t>(v) + 2];
    }
}

}  // namespace

void embedVertices(const Lattice& lattice, const Positions& rest, Embedding& e) { embedVertexSet(lattice, rest, e, nullptr); }

void embedVertices(const Lattice& lattice, const Positions& rest, Embedding& e, const std::vector<int>& candidates) {
    embedVertexSet(lattice, rest, e, lattice.volume ? nullptr : &candidates);
}

void embedCollar(const Lattice& lattice, const Positions& rest, Embedding& e) {
    clearCollar(e);
    if (lattice.volume || lattice.boxTurned()) return;
    const std::array<int, 3> spans = lattice.spans();
    const int n = static_cast<int>(rest.rows());
    for (int v = 0; v < n; ++v) {
        const Eigen::Vector3d x = rest.row(v).transpose();
        if (!x.allFinite() || insideBox(lattice, x)) continue;
        const Eigen::Vector3d t = clampedParameters(lattice, x);
        double local = 0.0;
        e.collarVertex.push_back(v);
        e.collarCell.push_back(spanOf(t[0], spans[0], local) + spans[0] * (spanOf(t[1], spans[1], local) + spans[1] * spanOf(t[2], spans[2], local)));
        e.collarParams.push_back(t);
        e.collarRest.push_back(x);
    }
}

Eigen::Vector3d collarPoint(const Lattice& lattice, const Eigen::Vector3d& params, const Eigen::Vector3d& rest) {
    Eigen::Vector3d displacement;
    Eigen::Matrix3d jacobian;
    deformationJacobian(lattice, params, displacement, jacobian);
    if (lattice.volume) return rest + displacement;
    // note: undeformed, D = 0 and J - I = 0 exactly, so the point is X0 bitwise.
    return rest + displacement + (jacobian - Eigen::Matrix3d::Identity()) * (rest - restPoint(lattice, params));
}

Eigen::Vector3d collarImage(const Lattice& lattice, const Eigen::Vector3d& rest) {
    return collarPoint(lattice, clampedParameters(lattice, rest), rest);
}

bool collarPreimage(const Lattice& lattice, const Eigen::Vector3d& y, Eigen::Vector3d& rest) {
    if (lattice.volume || lattice.boxTurned() || !y.allFinite()) return false;
    const double diagonal = lattice.diagonal();
    const auto image = [&](const Eigen::Vector3d& x) { return collarImage(lattice, x); };
    Eigen::Vector3d x = y - displacementAt(lattice, clampedParameters(lattice, y));
    Eigen::Vector3d residual = image(x) - y;
    double size = residual.norm();
    // The derivative: J(p) first (exact across the face; along it the collar also turns with J, a term of the
    // offset's size times D's second derivative, so Newton converges linearly); where that step no longer
    // descends (a knot of a degree-1 or -2 axis puts a kink in the collar) or converges slowly, central
    // differences over a growing width, which see across the kink.
    int widthStep = 0;
    for (int iteration = 0; iteration < 80 && size > 1e-15 * diagonal; ++iteration) {
        Eigen::Matrix3d jacobian;
        if (widthStep == 0) {
            Eigen::Vector3d displacement;
            deformationJacobian(lattice, clampedParameters(lattice, x), displacement, jacobian);
        } else {
            const double h = (widthStep == 1 ? 1e-7 : widthStep == 2 ? 1e-5 : 1e-3) * diagonal;
            for (int a = 0; a < 3; ++a) {
                Eigen::Vector3d e = Eigen::Vector3d::Zero();
                e[a] = h;
                jacobian.col(a) = (image(x + e) - image(x - e)) / (2.0 * h);
            }
        }
        const Eigen::Vector3d step = jacobian.partialPivLu().solve(residual);
        const double before = size;
        // Damped: halve the step until the residual drops.
        bool improved = false;
        double scale = 1.0;
        for (int halving = 0; step.allFinite() && halving < 30 && !improved; ++halving, scale *= 0.5) {
            const Eigen::Vector3d next = x - scale * step;
            const Eigen::Vector3d nextResidual = image(next) - y;
            if (nextResidual.norm() < size) {
                x = next, residual = nextResidual, size = nextResidual.norm();
                improved = true;
            }
        }
        if (improved) {
            // Slow (a long offset along a strongly curved face): the true derivative, by differences, from here on.
            if (widthStep == 0 && size > 0.25 * before) widthStep = 1;
            continue;
        }
        if (++widthStep > 3) break;  // no derivative descends any more: at rounding level, or stuck
    }
    if (!(size <= 1e-13 * diagonal) || insideBox(lattice, x)) return false;
    rest = x;
    return true;
}

void appendVerticesOfCells(const Embedding& embedding, const std::vector<int>& cells, std::vector<int>& out) {
    for (int cell : cells) out.insert(out.end(), embedding.order.begin() + embedding.cellStart[cell], embedding.order.begin() + embedding.cellStart[cell + 1]);
    for (size_t c = 0; c < embedding.collarVertex.size(); ++c)
        if (std::binary_search(cells.begin(), cells.end(), embedding.collarCell[c])) out.push_back(embedding.collarVertex[c]);
}

Eigen::Vector3d embeddedParameters(const Lattice& lattice, const Embedding& embedding, int cell, int entry) {
    if (lattice.volume && !lattice.tensorNet())
        return lattice.volume->chunkParameters(cell, {embedding.localX[entry], embedding.localY[entry], embedding.localZ[entry]});
    const std::array<int, 3> spans = lattice.spans();
    const int cellIndex[3] = {cell % spans[0], (cell / spans[0]) % spans[1], cell / (spans[0] * spans[1])};
    const double local[3] = {embedding.localX[entry], embedding.localY[entry], embedding.localZ[entry]};
    Eigen::Vector3d t;
    for (int a = 0; a < 3; ++a) t[a] = std::min(1.0, (cellIndex[a] + local[a]) / spans[a]);
    return t;
}

std::vector<int> cellsInfluencedBy(const Lattice& lattice, const std::vector<int>& controlPoints) {
    const std::array<int, 3> spans = lattice.spans();
    std::vector<int> cells;
    if (lattice.volume && !lattice.tensorNet()) {
        lattice.volume->chunksOfControlPoints(controlPoints, cells);
        return cells;
    }
    // Many control points (a brush region's thousands): a mark per cell, read in order, instead of sorting
    // (p+1)^3 entries per point.
    const bool marking = controlPoints.size() > 64;
    std::vector<std::uint8_t> marked(marking ? static_cast<size_t>(lattice.cellCount()) : 0, 0);
    for (int idx : controlPoints) {
        const std::array<int, 3> c = lattice.ijk(idx);
        // Control point i has support on spans [i - p, i] (clamped to the existing spans; SplineAxis::supportSpans
        // with repeated knots).
        int lo[3], hi[3];
        for (int a = 0; a < 3; ++a) lattice.axes[a].supportSpans(c[a], lo[a], hi[a]);
        for (int w = lo[2]; w <= hi[2]; ++w)
            for (int v = lo[1]; v <= hi[1]; ++v)
                for (int u = lo[0]; u <= hi[0]; ++u) {
                    const int cell = u + spans[0] * (v + spans[1] * w);
                    if (marking) marked[static_cast<size_t>(cell)] = 1;
                    else cells.push_back(cell);
                }
    }
    if (marking) {
        for (size_t cell = 0; cell < marked.size(); ++cell)
            if (marked[cell]) cells.push_back(static_cast<int>(cell));
        return cells;
    }
    std::sort(cells.begin(), cells.end());
    cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
    return cells;
}

namespace {

// A volume that is not one tensor product (no vectorised kernel): x = X0 + sum R(t) delta per vertex.
void evaluateChunksGeneric(const Lattice& lattice, const Embedding& embedding, const std::vector<int>& cells, Positions& positions) {
    const int count = static_cast<int>(cells.size());
#pragma omp parallel for schedule(dynamic, 4) if (count > 8)
    for (int c = 0; c < count; ++c) {
        const int cell = cells[static_cast<size_t>(c)];
        for (int s = embedding.cellStart[cell]; s < embedding.cellStart[cell + 1]; ++s) {
            const Eigen::Vector3d d = displacementAt(lattice, embeddedParameters(lattice, embedding, cell, s));
            const int v = embedding.order[static_cast<size_t>(s)];
            positions(v, 0) = embedding.restX[s] + d.x();
            positions(v, 1) = embedding.restY[s] + d.y();
            positions(v, 2) = embedding.restZ[s] + d.z();
        }
    }
}

bool chunkedVolume(const Lattice& lattice) { return lattice.volume && !lattice.tensorNet(); }

// The collar's vertices in `cells` (ascending; null: all) evaluated in full (collarPoint): a few spike tips, so
// the increment's bookkeeping is not worth it, and a full evaluation is exact whatever came before.
void evaluateCollar(const Lattice& lattice, const Embedding& embedding, const std::vector<int>* cells, Positions& positions,
                    std::vector<int>* movedVertices) {
    for (size_t c = 0; c < embedding.collarVertex.size(); ++c) {
        if (cells && !std::binary_search(cells->begin(), cells->end(), embedding.collarCell[c])) continue;
        const int v = embedding.collarVertex[c];
        positions.row(v) = collarPoint(lattice, embedding.collarParams[c], embedding.collarRest[c]).transpose();
        if (movedVertices) movedVertices->push_back(v);
    }
}

}  // namespace

void evaluateIncrement(const Lattice& lattice, const Embedding& embedding, const std::vector<int>& controlPoints,
                       const Positions& deltas, double sign, Positions& positions, IncrementScratch& scratch,
                       std::vector<int>* movedVertices) {
    const std::vector<int> cells = cellsInfluencedBy(lattice, controlPoints);
    if (lattice.rational || chunkedVolume(lattice)) return evaluateCells(lattice, embedding, cells, positions, movedVertices);
    const int n = lattice.controlPointCount();
    if (scratch.increment.rows() != n) scratch.increment = Positions::Zero(n, 3);
    if (static_cast<int>(scratch.changed.size()) != n) scratch.changed.assign(n, 0);
    for (size_t c = 0; c < controlPoints.size(); ++c) {
        scratch.increment.row(controlPoints[c]) = sign * deltas.row(static_cast<Eigen::Index>(c));
        scratch.changed[controlPoints[c]] = 1;
    }
    gIncrement(lattice, embedding, cells.data(), static_cast<int>(cells.size()), scratch.increment, scratch.changed.data(),
               positions.data());
    for (int idx : controlPoints) {  // back to all zero for the next call
        scratch.increment.row(idx).setZero();
        scratch.changed[idx] = 0;
    }
    if (movedVertices)
        for (int cell : cells)
            movedVertices->insert(movedVertices->end(), embedding.order.begin() + embedding.cellStart[cell],
                                  embedding.order.begin() + embedding.cellStart[cell + 1]);
    evaluateCollar(lattice, embedding, &cells, positions, movedVertices);
}

void controlPointInfluence(const Lattice& lattice, const Embedding& embedding, const std::vector<int>& controlPoints,
                           std::vector<float>& weights) {
    weights.assign(static_cast<size_t>(embedding.vertexCount), 0.0f);
    std::vector<std::uint8_t> chosen(lattice.controlPointCount(), 0);
    for (int idx : controlPoints)
        if (idx >= 0 && idx < lattice.controlPointCount()) chosen[idx] = 1;
    for (int cell : cellsInfluencedBy(lattice, controlPoints)) {
        for (int s = embedding.cellStart[cell]; s < embedding.cellStart[cell + 1]; ++s) {
            SupportWeights support;
            supportWeights(lattice, embeddedParameters(lattice, embedding, cell, s), support);
            double sum = 0.0;
            for (int c = 0; c < support.count; ++c)
                if (chosen[support.index[c]]) sum += support.weight[c];
            weights[embedding.order[s]] = static_cast<float>(std::clamp(sum, 0.0, 1.0));
        }
    }
}

void evaluateAll(const Lattice& lattice, const Embedding& embedding, Positions& positions) {
    std::vector<int> cells(lattice.cellCount());
    std::iota(cells.begin(), cells.end(), 0);
    if (chunkedVolume(lattice)) return evaluateChunksGeneric(lattice, embedding, cells, positions);
    gKernel(lattice, embedding, cells.data(), static_cast<int>(cells.size()), positions.data());
    evaluateCollar(lattice, embedding, nullptr, positions, nullptr);
}

void evaluateAllInCellOrder(const Lattice& lattice, const Embedding& embedding, double* out) {
    if (!chunkedVolume(lattice)) gInCellOrder(lattice, embedding, out);
}

void evaluateCells(const Lattice& lattice, const Embedding& embedding, const std::vector<int>& cells,
                   Positions& positions, std::vector<int>* movedVertices) {
    if (chunkedVolume(lattice))
        evaluateChunksGeneric(lattice, embedding, cells, positions);
    else
        gKernel(lattice, embedding, cells.data(), static_cast<int>(cells.size()), positions.data());
    if (movedVertices)
        for (int cell : cells)
            movedVertices->insert(movedVertices->end(), embedding.order.begin() + embedding.cellStart[cell],
                                  embedding.order.begin() + embedding.cellStart[cell + 1]);
    evaluateCollar(lattice, embedding, &cells, positions, movedVertices);
}

}  // namespace sculpt::core
