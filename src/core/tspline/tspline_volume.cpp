// Weighted T-spline volumes (Song & Yang 2005, seed 002): eq. 5-7 blending functions on local knot vectors
// inferred from a T-lattice (3.2.2), Bezier extraction of their elements and freezing (sec. 5, eq. 8). Making
// volumes (sec. 4, 6) and the proof that a rest volume does not fold: tspline_rest.cpp.
#include "core/tspline/tspline_volume.h"

#include <Eigen/Geometry>

#include "core/volume/volume_kinds.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <tuple>

#include <Eigen/LU>
#include <Eigen/SVD>

namespace sculpt::core {

// ---- univariate cubic pieces (eq. 7) -------------------------------------------------------------------------

// note: the B-spline on local knots k0..k4 is function 3 of the clamped knot vector
// E = [k0 k0 k0 k0 k1 k2 k3 k4 k4 k4 k4] with coefficient vector e_3, and its span j is E's span m = 3 + j, so de
// Boor's algorithm on E (one blossom argument per level) gives the piece's blossom. Every denominator
// E[i+4-r] - E[i] spans [k_j, k_(j+1)], so it is > 0 on a non-empty span.
double cubicBlossom(const double* k, int span, double x1, double x2, double x3) {
    const double e[11] = {k[0], k[0], k[0], k[0], k[1], k[2], k[3], k[4], k[4], k[4], k[4]};
    const int m = 3 + span;
    double d[4];
    for (int i = 0; i < 4; ++i) d[i] = m - 3 + i == 3 ? 1.0 : 0.0;
    const double x[3] = {x1, x2, x3};
    for (int r = 1; r <= 3; ++r)
        for (int i = m; i >= m - 3 + r; --i) {
            const double alpha = (x[r - 1] - e[i]) / (e[i + 4 - r] - e[i]);
            d[i - (m - 3)] = (1.0 - alpha) * d[i - 1 - (m - 3)] + alpha * d[i - (m - 3)];
        }
    return d[3];
}

void cubicPiece(const double* k, int span, double u, double& value, double& derivative) {
    const double e[11] = {k[0], k[0], k[0], k[0], k[1], k[2], k[3], k[4], k[4], k[4], k[4]};
    const int m = 3 + span;
    double d[4];
    for (int i = 0; i < 4; ++i) d[i] = m - 3 + i == 3 ? 1.0 : 0.0;
    for (int r = 1; r <= 2; ++r)
        for (int i = m; i >= m - 3 + r; --i) {
            const double alpha = (u - e[i]) / (e[i + 4 - r] - e[i]);
            d[i - (m - 3)] = (1.0 - alpha) * d[i - 1 - (m - 3)] + alpha * d[i - (m - 3)];
        }
    // The last level is affine in its argument x: blossom(u, u, x); p'(u) = 3 d/dx blossom(u, u, x).
    const double width = e[m + 1] - e[m];
    const double alpha = (u - e[m]) / width;
    value = (1.0 - alpha) * d[2] + alpha * d[3];
    derivative = 3.0 * (d[3] - d[2]) / width;
}

namespace {

// The span of local knots `knots` (fine) holding the element starting at fine coordinate lo.
inline int spanAt(const std::array<int, 5>& knots, int lo) {
    int j = 0;
    while (j < 3 && knots[static_cast<size_t>(j) + 1] <= lo) ++j;
    return j;
}

// Bezier extraction's sum: points (4 blocks of 64: x, y, z, w) += the tensor products of the pieces' Bernstein
// coefficients times the homogeneous control points (W P, W). note: the AVX2 clone does the 4 contiguous terms
// at once (chosen at run time; no FMA contraction, so both clones give the same bits).
// Four doubles as one value (GCC vector extension; an AVX2 register in the AVX2 clones, two SSE2 ones otherwise),
// loaded and stored unaligned.
typedef double Double4 __attribute__((vector_size(32), aligned(8), may_alias));

__attribute__((target_clones("avx2", "default"))) void accumulateTensorPieces(int count, const double (*__restrict bernstein)[3][4],
                                                                              const double (*__restrict homogeneous)[4], double* __restrict points) {
    Double4* out = reinterpret_cast<Double4*>(points);  // 4 blocks of 16 rows of 4
    for (int i = 0; i < count; ++i) {
        const Double4 bu = *reinterpret_cast<const Double4*>(bernstein[i][0]);
        const double* hp = homogeneous[i];
        for (int o = 0; o < 4; ++o)
            for (int m = 0; m < 4; ++m) {
                const Double4 b = (bernstein[i][1][m] * bernstein[i][2][o]) * bu;
                const int row = m + 4 * o;
                out[row] += b * hp[0];
                out[16 + row] += b * hp[1];
                out[32 + row] += b * hp[2];
                out[48 + row] += b * hp[3];
            }
    }
}

// Cells whose open box meets the open box (lo, hi) (fine coordinates), by descent from the roots.
void cellsOverlapping(const TLattice& lattice, int node, const std::array<int, 3>& lo, const std::array<int, 3>& hi, std::vector<int>& out) {
    const TLatticeNode& n = lattice.nodes[static_cast<size_t>(node)];
    const int shift = lattice.maxLevel - n.level;
    for (int a = 0; a < 3; ++a)
        if (!(lo[a] < ((n.index[a] + 1) << shift) && hi[a] > (n.index[a] << shift))) return;
    if (n.firstChild < 0) {
        out.push_back(n.cell);
        return;
    }
    for (int o = 0; o < 8; ++o) cellsOverlapping(lattice, n.firstChild + o, lo, hi, out);
}

}  // namespace

// ---- the basis ---------------------------------------------------------------------------------------------

Status buildTSplineBasis(const TLattice& input, std::shared_ptr<const TSplineBasis>& out) {
    auto made = std::make_shared<TSplineBasis>();
    TSplineBasis& b = *made;
    b.lattice = rawTLatticeFields(input);
    if (Status s = finishTLattice(b.lattice); !s) return s;
    const TLattice& lattice = b.lattice;
    const int vertexCount = static_cast<int>(lattice.vertices.size());
    // Local knot vectors by the knot rule (3.2.2), per vertex; boundary copies replace one axis's vector.
    b.anchorOfVertex.assign(static_cast<size_t>(vertexCount), std::array<int, 8>{-1, -1, -1, -1, -1, -1, -1, -1});
    for (int v = 0; v < vertexCount; ++v) {
        const std::array<int, 3>& p = lattice.vertices[static_cast<size_t>(v)];
        std::array<std::array<int, 5>, 3> regular{};
        int boundaryBits = 0;
        for (int a = 0; a < 3; ++a) {
            std::array<int, 3> q = p;
            const int r1 = lattice.nextKnotPlane(p, a, -1);
            q[a] = r1;
            const int r2 = lattice.nextKnotPlane(q, a, -1);
            const int f1 = lattice.nextKnotPlane(p, a, +1);
            q[a] = f1;
            const int f2 = lattice.nextKnotPlane(q, a, +1);
            regular[static_cast<size_t>(a)] = {r2, r1, p[a], f1, f2};
            if (p[a] == 0 || p[a] == lattice.fineCount[a]) boundaryBits |= 1 << a;
        }
        for (int mask = 0; mask < 8; ++mask) {
            if (mask & ~boundaryBits) continue;
            TSplineAnchor anchor;
            anchor.vertex = v;
            anchor.boundaryCopy = static_cast<std::uint8_t>(mask);
            anchor.knots = regular;
            for (int a = 0; a < 3; ++a) {
                if (!((mask >> a) & 1)) continue;
                // The clamped end: knot multiplicity 4 at the boundary (see the header).
                const int end = p[a];
                anchor.knots[static_cast<size_t>(a)] = end == 0 ? std::array<int, 5>{0, 0, 0, 0, regular[static_cast<size_t>(a)][3]}
                                                                : std::array<int, 5>{regular[static_cast<size_t>(a)][1], end, end, end, end};
            }
            b.anchorOfVertex[static_cast<size_t>(v)][static_cast<size_t>(mask)] = static_cast<int>(b.anchors.size());
            b.anchors.push_back(anchor);
        }
    }
    const int anchorCount = b.anchorCount();
    b.knotValues.resize(static_cast<size_t>(anchorCount));
    for (int s = 0; s < anchorCount; ++s)
        for (int a = 0; a < 3; ++a)
            for (int i = 0; i < 5; ++i)
                b.knotValues[static_cast<size_t>(s)][static_cast<size_t>(a)][static_cast<size_t>(i)] =
                    lattice.knotValue[static_cast<size_t>(a)][static_cast<size_t>(b.anchors[static_cast<size_t>(s)].knots[static_cast<size_t>(a)][static_cast<size_t>(i)])];
    // The spans' pieces in power form: Bernstein coefficients (blossoms) on [k_j, k_(j+1)], converted to powers
    // of s = x / h, then of x.
    b.piecePowers.assign(static_cast<size_t>(anchorCount), {});
    for (int s = 0; s < anchorCount; ++s)
        for (int a = 0; a < 3; ++a) {
            const double* k = b.knotValues[static_cast<size_t>(s)][static_cast<size_t>(a)].data();
            for (int j = 0; j < 4; ++j) {
                if (!(k[j] < k[j + 1])) continue;
                const double lo = k[j], hi = k[j + 1], h = hi - lo;
                const double b0 = cubicBlossom(k, j, lo, lo, lo), b1 = cubicBlossom(k, j, lo, lo, hi);
                const double b2 = cubicBlossom(k, j, lo, hi, hi), b3 = cubicBlossom(k, j, hi, hi, hi);
                auto& c = b.piecePowers[static_cast<size_t>(s)][static_cast<size_t>(a)][static_cast<size_t>(j)];
                c[0] = b0;
                c[1] = 3.0 * (b1 - b0) / h;
                c[2] = 3.0 * (b2 - 2.0 * b1 + b0) / (h * h);
                c[3] = (b3 - 3.0 * b2 + 3.0 * b1 - b0) / (h * h * h);
            }
        }
    // No T-junction: the vertices are a full tensor grid, the blending functions the tensor B-splines.
    {
        size_t product = 1;
        for (int a = 0; a < 3; ++a) {
            std::vector<int> coordinates;
            for (const auto& p : lattice.vertices) coordinates.push_back(p[a]);
            std::sort(coordinates.begin(), coordinates.end());
            product *= static_cast<size_t>(std::unique(coordinates.begin(), coordinates.end()) - coordinates.begin());
        }
        b.partitionOfUnity = product == lattice.vertices.size();
    }
    // The blending functions over each cell (open supports meeting the open cell), ascending anchor ids.
    const int cellCount = static_cast<int>(lattice.cells.size());
    std::vector<std::vector<int>> cellAnchors(static_cast<size_t>(cellCount));
    {
        std::vector<int> found;
        const int roots = lattice.rootCount[0] * lattice.rootCount[1] * lattice.rootCount[2];
        for (int s = 0; s < anchorCount; ++s) {
            const auto& k = b.anchors[static_cast<size_t>(s)].knots;
            const std::array<int, 3> lo{k[0][0], k[1][0], k[2][0]}, hi{k[0][4], k[1][4], k[2][4]};
            found.clear();
            for (int r = 0; r < roots; ++r) cellsOverlapping(lattice, r, lo, hi, found);
            for (int c : found) cellAnchors[static_cast<size_t>(c)].push_back(s);
        }
    }
    // Bezier elements: each cell split at the local knots inside it, so every B_s is one polynomial per element.
    b.cellElementStart.assign(1, 0);
    b.cellSplitStart.resize(static_cast<size_t>(cellCount));
    b.cellSplitCount.resize(static_cast<size_t>(cellCount));
    b.supportStart.assign(1, 0);
    for (int c = 0; c < cellCount; ++c) {
        const std::array<int, 3> lo = lattice.cellLo(c), hi = lattice.cellHi(c);
        const std::vector<int>& over = cellAnchors[static_cast<size_t>(c)];
        std::array<int, 3> pieces{};
        for (int a = 0; a < 3; ++a) {
            std::vector<int> cuts{lo[a], hi[a]};
            for (int s : over)
                for (int knot : b.anchors[static_cast<size_t>(s)].knots[static_cast<size_t>(a)])
                    if (knot > lo[a] && knot < hi[a]) cuts.push_back(knot);
            std::sort(cuts.begin(), cuts.end());
            cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());
            b.cellSplitStart[static_cast<size_t>(c)][static_cast<size_t>(a)] = static_cast<int>(b.splits.size());
            b.cellSplitCount[static_cast<size_t>(c)][static_cast<size_t>(a)] = static_cast<int>(cuts.size());
            b.splits.insert(b.splits.end(), cuts.begin(), cuts.end());
            pieces[static_cast<size_t>(a)] = static_cast<int>(cuts.size()) - 1;
        }
        const int* split[3] = {&b.splits[static_cast<size_t>(b.cellSplitStart[static_cast<size_t>(c)][0])],
                               &b.splits[static_cast<size_t>(b.cellSplitStart[static_cast<size_t>(c)][1])],
                               &b.splits[static_cast<size_t>(b.cellSplitStart[static_cast<size_t>(c)][2])]};
        for (int k = 0; k < pieces[2]; ++k)
            for (int j = 0; j < pieces[1]; ++j)
                for (int i = 0; i < pieces[0]; ++i) {
                    const std::array<int, 3> elo{split[0][i], split[1][j], split[2][k]}, ehi{split[0][i + 1], split[1][j + 1], split[2][k + 1]};
                    int count = 0;
                    for (int s : over) {
                        const auto& knots = b.anchors[static_cast<size_t>(s)].knots;
                        bool meets = true;
                        for (int a = 0; a < 3 && meets; ++a) meets = knots[static_cast<size_t>(a)][0] < ehi[a] && knots[static_cast<size_t>(a)][4] > elo[a];
                        if (!meets) continue;
                        b.supportIds.push_back(s);
                        ++count;
                    }
                    const std::string where = "cell " + std::to_string(c) + " (level " + std::to_string(lattice.cells[static_cast<size_t>(c)].level) + ")";
                    if (count == 0) return Status::error("no blending function covers part of T-lattice " + where);
                    if (count > 216)
                        return Status::error(std::to_string(count) + " blending functions overlap part of T-lattice " + where +
                                             ", more than the 216 a point may have: balance the T-lattice (2:1 between cells that touch)");
                    b.maxSupport = std::max(b.maxSupport, count);
                    b.supportStart.push_back(static_cast<int>(b.supportIds.size()));
                    b.elementCell.push_back(c);
                    b.elementLo.push_back(elo);
                    b.elementHi.push_back(ehi);
                }
        b.cellElementStart.push_back(b.elementCount());
    }
    // The inverse of the support lists: which elements each anchor reaches (what a changed control point makes the
    // injectivity tests look at again).
    b.anchorElementStart.assign(static_cast<size_t>(b.anchorCount()) + 1, 0);
    for (int id : b.supportIds) ++b.anchorElementStart[static_cast<size_t>(id) + 1];
    for (size_t s = 1; s < b.anchorElementStart.size(); ++s) b.anchorElementStart[s] += b.anchorElementStart[s - 1];
    b.anchorElements.resize(b.supportIds.size());
    {
        std::vector<int> cursor(b.anchorElementStart.begin(), b.anchorElementStart.end() - 1);
        for (int e = 0; e < b.elementCount(); ++e)
            for (int c = b.supportStart[static_cast<size_t>(e)]; c < b.supportStart[static_cast<size_t>(e) + 1]; ++c)
                b.anchorElements[static_cast<size_t>(cursor[static_cast<size_t>(b.supportIds[static_cast<size_t>(c)])]++)] = e;
    }
    // T-lattice edges: each cell edge split at the vertices on it (T-junctions), each edge once.
    {
        for (int a = 0; a < 3; ++a) {
            const int bAxis = (a + 1) % 3, cAxis = (a + 2) % 3;
            std::vector<int> order(static_cast<size_t>(vertexCount));
            std::iota(order.begin(), order.end(), 0);
            auto key = [&](int v) {
                const auto& p = lattice.vertices[static_cast<size_t>(v)];
                return std::make_tuple(p[bAxis], p[cAxis], p[a]);
            };
            std::sort(order.begin(), order.end(), [&](int x, int y) { return key(x) < key(y); });
            std::vector<std::array<int, 2>> edges;
            for (int c = 0; c < cellCount; ++c) {
                const std::array<int, 3> lo = lattice.cellLo(c), hi = lattice.cellHi(c);
                for (int e = 0; e < 4; ++e) {
                    const int pb = (e & 1) ? hi[bAxis] : lo[bAxis], pc = (e & 2) ? hi[cAxis] : lo[cAxis];
                    auto it = std::lower_bound(order.begin(), order.end(), std::make_tuple(pb, pc, lo[a]),
                                               [&](int v, const std::tuple<int, int, int>& k) { return key(v) < k; });
                    for (; it + 1 != order.end() && key(*(it + 1)) <= std::make_tuple(pb, pc, hi[a]); ++it) edges.push_back({*it, *(it + 1)});
                }
            }
            std::sort(edges.begin(), edges.end());
            edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
            b.latticeEdges.insert(b.latticeEdges.end(), edges.begin(), edges.end());
        }
    }
    out = std::move(made);
    return Status::success();
}

int TSplineBasis::elementOf(const Eigen::Vector3d& t, Eigen::Vector3d& local) const {
    std::array<int, 3> fine{}, doubled{};
    for (int a = 0; a < 3; ++a) {
        if (!(t[a] >= 0.0 && t[a] <= 1.0)) return -1;
        fine[a] = lattice.fineVoxel(a, t[a]);
        doubled[a] = 2 * fine[a] + 1;
    }
    const int c = lattice.cellAtDoubled(doubled);
    std::array<int, 3> piece{}, pieces{};
    for (int a = 0; a < 3; ++a) {
        const int* s = splits.data() + cellSplitStart[static_cast<size_t>(c)][static_cast<size_t>(a)];
        const int n = cellSplitCount[static_cast<size_t>(c)][static_cast<size_t>(a)];
        pieces[a] = n - 1;
        piece[a] = std::clamp(static_cast<int>(std::upper_bound(s, s + n, fine[a]) - s) - 1, 0, n - 2);
    }
    const int e = cellElementStart[static_cast<size_t>(c)] + piece[0] + pieces[0] * (piece[1] + pieces[1] * piece[2]);
    const Eigen::Vector3d lo = elementMin(e), hi = elementMax(e);
    local = (t - lo).cwiseQuotient(hi - lo);
    return e;
}

Eigen::Vector3d TSplineBasis::elementMin(int e) const {
    const auto& f = elementLo[static_cast<size_t>(e)];
    return {lattice.knotValue[0][static_cast<size_t>(f[0])], lattice.knotValue[1][static_cast<size_t>(f[1])], lattice.knotValue[2][static_cast<size_t>(f[2])]};
}

Eigen::Vector3d TSplineBasis::elementMax(int e) const {
    const auto& f = elementHi[static_cast<size_t>(e)];
    return {lattice.knotValue[0][static_cast<size_t>(f[0])], lattice.knotValue[1][static_cast<size_t>(f[1])], lattice.knotValue[2][static_cast<size_t>(f[2])]};
}

Eigen::Vector3d TSplineBasis::grevilleParameters(int anchor) const {
    Eigen::Vector3d g;
    for (int a = 0; a < 3; ++a) {
        const auto& k = knotValues[static_cast<size_t>(anchor)][static_cast<size_t>(a)];
        g[a] = (k[1] + k[2] + k[3]) / 3.0;
    }
    return g;
}

void TSplineBasis::blendingValues(int e, const Eigen::Vector3d& t, double* values, Eigen::Vector3d* gradients) const {
    const std::array<int, 3>& lo = elementLo[static_cast<size_t>(e)];
    for (int c = supportStart[static_cast<size_t>(e)], i = 0; c < supportStart[static_cast<size_t>(e) + 1]; ++c, ++i) {
        const int s = supportIds[static_cast<size_t>(c)];
        double value[3], derivative[3];
        for (int a = 0; a < 3; ++a) {
            const int j = spanAt(anchors[static_cast<size_t>(s)].knots[static_cast<size_t>(a)], lo[a]);
            const auto& power = piecePowers[static_cast<size_t>(s)][static_cast<size_t>(a)][static_cast<size_t>(j)];
            const double x = t[a] - knotValues[static_cast<size_t>(s)][static_cast<size_t>(a)][static_cast<size_t>(j)];
            value[a] = ((power[3] * x + power[2]) * x + power[1]) * x + power[0];
            derivative[a] = (3.0 * power[3] * x + 2.0 * power[2]) * x + power[1];
        }
        values[i] = value[0] * value[1] * value[2];  // eq. 6
        if (gradients)
            gradients[i] = Eigen::Vector3d(derivative[0] * value[1] * value[2], value[0] * derivative[1] * value[2], value[0] * value[1] * derivative[2]);
    }
}

std::vector<std::array<int, 2>> TSplineBasis::controlNetEdges() const {
    // T-lattice edges on every boundary-copy layer, and each copy joined to what it copies.
    std::vector<std::array<int, 2>> edges;
    for (const auto& edge : latticeEdges) {
        const auto& p = lattice.vertices[static_cast<size_t>(edge[0])];
        const auto& q = lattice.vertices[static_cast<size_t>(edge[1])];
        const int axis = p[0] != q[0] ? 0 : p[1] != q[1] ? 1 : 2;
        for (int mask = 0; mask < 8; ++mask) {
            if ((mask >> axis) & 1) continue;
            const int s = anchorOfVertex[static_cast<size_t>(edge[0])][static_cast<size_t>(mask)];
            const int r = anchorOfVertex[static_cast<size_t>(edge[1])][static_cast<size_t>(mask)];
            if (s >= 0 && r >= 0) edges.push_back({s, r});
        }
    }
    for (int s = 0; s < anchorCount(); ++s) {
        const TSplineAnchor& anchor = anchors[static_cast<size_t>(s)];
        for (int a = 0; a < 3; ++a) {
            if ((anchor.boundaryCopy >> a) & 1) continue;
            const int copy = anchorOfVertex[static_cast<size_t>(anchor.vertex)][static_cast<size_t>(anchor.boundaryCopy | (1 << a))];
            if (copy >= 0) edges.push_back({s, copy});
        }
    }
    return edges;
}

// ---- the volume --------------------------------------------------------------------------------------------

Status TSplineVolume::make(std::shared_ptr<const TSplineBasis> basis, Positions points, std::vector<double> weights,
                           std::shared_ptr<const TSplineVolume>& out) {
    if (!basis) return Status::error("a T-spline volume needs a basis");
    const int n = basis->anchorCount();
    if (points.rows() != n) return Status::error("a T-spline volume of this T-lattice needs " + std::to_string(n) + " control points, got " + std::to_string(points.rows()));
    if (!points.allFinite()) return Status::error("T-spline control points must be finite");
    if (static_cast<int>(weights.size()) != n) return Status::error("a T-spline volume of this T-lattice needs " + std::to_string(n) + " weights");
    for (int s = 0; s < n; ++s)
        if (!(weights[static_cast<size_t>(s)] > 0.0) || !std::isfinite(weights[static_cast<size_t>(s)]))
            return Status::error("T-spline weight " + std::to_string(s) + " must be finite and > 0");
    auto volume = std::make_shared<TSplineVolume>();
    TSplineVolume& v = *volume;
    v.basis_ = std::move(basis);
    v.rest_ = std::move(points);
    v.weights_ = std::move(weights);
    v.equalWeights_ = std::all_of(v.weights_.begin(), v.weights_.end(), [&](double w) { return w == v.weights_[0]; });
    v.rational_ = !v.equalWeights_ || !v.basis_->partitionOfUnity;
    v.bounds_.setEmpty();
    for (int s = 0; s < n; ++s) v.bounds_.extend(v.rest_.row(s).transpose());
    const TSplineBasis& b = *v.basis_;
    v.netEdges_ = b.controlNetEdges();
    // Layers: breadth-first over the net from the boundary copies (the outer surface).
    std::vector<std::vector<int>> neighbours(static_cast<size_t>(n));
    for (const auto& e : v.netEdges_) {
        neighbours[static_cast<size_t>(e[0])].push_back(e[1]);
        neighbours[static_cast<size_t>(e[1])].push_back(e[0]);
    }
    v.layer_.assign(static_cast<size_t>(n), std::numeric_limits<int>::max());
    std::vector<int> queue;
    for (int s = 0; s < n; ++s)
        if (b.anchors[static_cast<size_t>(s)].boundaryCopy != 0) {
            v.layer_[static_cast<size_t>(s)] = 0;
            queue.push_back(s);
        }
    for (size_t head = 0; head < queue.size(); ++head)
        for (int r : neighbours[static_cast<size_t>(queue[head])])
            if (v.layer_[static_cast<size_t>(r)] == std::numeric_limits<int>::max()) {
                v.layer_[static_cast<size_t>(r)] = v.layer_[static_cast<size_t>(queue[head])] + 1;
                queue.push_back(r);
            }
    // A valid volume is right-handed at rest, proven on every element (tspline_rest.cpp), so freezing has one
    // answer and det J = det dQ/dt / det dQ0/dt has the sign of det dQ/dt; a folded or mirrored placement is refused.
    if (Status s = checkTSplineRestVolume(v); !s) return s;
    v.restIndex_ = v.buildFreezeIndex(v.rest_);
    out = std::move(volume);
    return Status::success();
}

void TSplineVolume::basisAt(const Eigen::Vector3d& t, SupportWeights& out) const {
    out.count = 0;
    if (!t.allFinite()) return;
    const Eigen::Vector3d clamped = t.cwiseMax(0.0).cwiseMin(1.0);
    Eigen::Vector3d local;
    const int e = basis_->elementOf(clamped, local);
    const int start = basis_->supportStart[static_cast<size_t>(e)];
    const int count = basis_->supportStart[static_cast<size_t>(e) + 1] - start;
    double values[216];
    basis_->blendingValues(e, clamped, values, nullptr);
    double sum = 0.0;
    for (int i = 0; i < count; ++i) {
        const int s = basis_->supportIds[static_cast<size_t>(start + i)];
        out.index[static_cast<size_t>(i)] = s;
        out.weight[static_cast<size_t>(i)] = weights_[static_cast<size_t>(s)] * values[i];
        sum += out.weight[static_cast<size_t>(i)];
    }
    // Eq. 5's denominator (a PB-spline always divides: sum B is 1 only without T-junctions).
    for (int i = 0; i < count; ++i) out.weight[static_cast<size_t>(i)] /= sum;
    out.count = count;
}

void TSplineVolume::evaluate(const Positions& points, const Eigen::Vector3d& t, Eigen::Vector3d& value, Eigen::Matrix3d* derivative) const {
    const Eigen::Vector3d clamped = t.allFinite() ? Eigen::Vector3d(t.cwiseMax(0.0).cwiseMin(1.0)) : Eigen::Vector3d::Constant(0.5);
    Eigen::Vector3d local;
    const int e = basis_->elementOf(clamped, local);
    const int start = basis_->supportStart[static_cast<size_t>(e)];
    const int count = basis_->supportStart[static_cast<size_t>(e) + 1] - start;
    double values[216];
    Eigen::Vector3d gradients[216];
    basis_->blendingValues(e, clamped, values, derivative ? gradients : nullptr);
    Eigen::Vector3d numerator = Eigen::Vector3d::Zero();
    double denominator = 0.0;
    Eigen::Matrix3d dNumerator = Eigen::Matrix3d::Zero();
    Eigen::RowVector3d dDenominator = Eigen::RowVector3d::Zero();
    for (int i = 0; i < count; ++i) {
        const int s = basis_->supportIds[static_cast<size_t>(start + i)];
        const double w = weights_[static_cast<size_t>(s)];
        const Eigen::Vector3d p = points.row(s).transpose();
        numerator += (w * values[i]) * p;
        denominator += w * values[i];
        if (derivative) {
            dNumerator += p * (w * gradients[i].transpose());
            dDenominator += w * gradients[i].transpose();
        }
    }
    value = numerator / denominator;  // eq. 5
    if (derivative) *derivative = (dNumerator - value * dDenominator) / denominator;  // quotient rule
}

Eigen::Vector3d TSplineVolume::chunkParameters(int chunk, const Eigen::Vector3d& local) const {
    const Eigen::Vector3d lo = basis_->elementMin(chunk), hi = basis_->elementMax(chunk);
    return lo + local.cwiseProduct(hi - lo);
}

void TSplineVolume::chunksOfControlPoints(const std::vector<int>& ids, std::vector<int>& chunks) const {
    chunks.clear();
    for (int id : ids)
        chunks.insert(chunks.end(), basis_->anchorElements.begin() + basis_->anchorElementStart[static_cast<size_t>(id)],
                      basis_->anchorElements.begin() + basis_->anchorElementStart[static_cast<size_t>(id) + 1]);
    std::sort(chunks.begin(), chunks.end());
    chunks.erase(std::unique(chunks.begin(), chunks.end()), chunks.end());
}

void TSplineVolume::chunkSupport(int chunk, std::vector<int>& ids) const {
    ids.assign(basis_->supportIds.begin() + basis_->supportStart[static_cast<size_t>(chunk)],
               basis_->supportIds.begin() + basis_->supportStart[static_cast<size_t>(chunk) + 1]);
}

void TSplineVolume::bezierChunk(int chunk, const Positions* displacement, BezierChunk& out) const {
    const TSplineBasis& b = *basis_;
    constexpr int n = 64;
    out.degree = {3, 3, 3};
    out.collapse = {};
    if (out.points.size() < 4 * static_cast<size_t>(n)) out.points.resize(4 * static_cast<size_t>(n));
    double* control = out.points.data();
    std::fill(control, control + 4 * n, 0.0);
    const Eigen::Vector3d lo = b.elementMin(chunk), hi = b.elementMax(chunk);
    for (int a = 0; a < 3; ++a) out.parameterScale[static_cast<size_t>(a)] = hi[a] - lo[a];
    const std::array<int, 3>& fineLo = b.elementLo[static_cast<size_t>(chunk)];
    const int start = b.supportStart[static_cast<size_t>(chunk)];
    const int count = b.supportStart[static_cast<size_t>(chunk) + 1] - start;
    double bernstein[216][3][4], homogeneous[216][4];
    for (int i = 0; i < count; ++i) {
        const int s = b.supportIds[static_cast<size_t>(start + i)];
        // The Bernstein coefficients of B_s on the element, per axis: the span's piece (powers of x = t - k_j)
        // re-expanded at the element's start in powers of h s (Taylor), then Bernstein from powers.
        // note: the blossoms at (lo^(3-l), hi^l) give the same values at ~3x the cost (divisions per level).
        for (int a = 0; a < 3; ++a) {
            const int span = spanAt(b.anchors[static_cast<size_t>(s)].knots[static_cast<size_t>(a)], fineLo[a]);
            const auto& power = b.piecePowers[static_cast<size_t>(s)][static_cast<size_t>(a)][static_cast<size_t>(span)];
            const double x = lo[a] - b.knotValues[static_cast<size_t>(s)][static_cast<size_t>(a)][static_cast<size_t>(span)];
            const double h = hi[a] - lo[a];
            constexpr double third = 1.0 / 3.0;
            const double p0 = ((power[3] * x + power[2]) * x + power[1]) * x + power[0];
            const double p1 = ((3.0 * power[3] * x + 2.0 * power[2]) * x + power[1]) * h;
            const double p2 = (3.0 * power[3] * x + power[2]) * h * h;
            const double p3 = power[3] * h * h * h;
            bernstein[i][a][0] = p0;
            bernstein[i][a][1] = p0 + p1 * third;
            bernstein[i][a][2] = p0 + (2.0 * p1 + p2) * third;
            bernstein[i][a][3] = p0 + p1 + p2 + p3;
        }
        const double w = weights_[static_cast<size_t>(s)];
        Eigen::Vector3d p = rest_.row(s).transpose();
        if (displacement) p += displacement->row(s).transpose();
        homogeneous[i][0] = w * p.x(), homogeneous[i][1] = w * p.y(), homogeneous[i][2] = w * p.z(), homogeneous[i][3] = w;
    }
    accumulateTensorPieces(count, bernstein, homogeneous, control);
    // Polynomial when the denominator sum W b is one constant on the element.
    bool polynomial = equalWeights_;
    for (int e = 1; e < n && polynomial; ++e) polynomial = std::abs(control[3 * n + e] - control[3 * n]) <= 1e-13 * control[3 * n];
    out.polynomial = polynomial;
    if (polynomial)
        for (int e = 0; e < n; ++e) {
            for (int comp = 0; comp < 3; ++comp) control[comp * n + e] /= control[3 * n + e];
            control[3 * n + e] = 1.0;
        }
}

void TSplineVolume::chunksAlong(int chunk, int, std::vector<int>& row, bool& closed) const {
    row.assign(1, chunk);
    closed = false;
}

std::vector<std::array<Eigen::Vector3d, 2>> TSplineVolume::chunkEdgeLines() const {
    const TLattice& lattice = basis_->lattice;
    std::vector<std::array<Eigen::Vector3d, 2>> lines;
    lines.reserve(basis_->latticeEdges.size());
    auto parameters = [&](int v) {
        const auto& p = lattice.vertices[static_cast<size_t>(v)];
        return Eigen::Vector3d(lattice.knotValue[0][static_cast<size_t>(p[0])], lattice.knotValue[1][static_cast<size_t>(p[1])],
                               lattice.knotValue[2][static_cast<size_t>(p[2])]);
    };
    for (const auto& edge : basis_->latticeEdges) lines.push_back({parameters(edge[0]), parameters(edge[1])});
    return lines;
}

// ---- freezing (sec. 5) -------------------------------------------------------------------------------------

ChunkIndex TSplineVolume::buildElementIndex(const Positions& points) const {
    const TSplineBasis& b = *basis_;
    ChunkIndex index;
    const int elements = b.elementCount();
    index.chunkBounds.resize(static_cast<size_t>(elements));
    index.bounds.setEmpty();
    for (Eigen::Index i = 0; i < points.rows(); ++i) index.bounds.extend(points.row(i).transpose());
    // note: an element lies in the convex hull of the control points of its blending functions (eq. 5 with
    // W > 0 and B >= 0 is a convex combination of them). Padded for rounding.
    const double pad = 1e-9 * std::max(index.bounds.diagonal().norm(), 1e-300);
    for (int e = 0; e < elements; ++e) {
        Eigen::AlignedBox3d box;
        box.setEmpty();
        for (int c = b.supportStart[static_cast<size_t>(e)]; c < b.supportStart[static_cast<size_t>(e) + 1]; ++c)
            box.extend(points.row(b.supportIds[static_cast<size_t>(c)]).transpose());
        box.min().array() -= pad;
        box.max().array() += pad;
        index.chunkBounds[static_cast<size_t>(e)] = box;
    }
    index.bounds.min().array() -= pad;
    index.bounds.max().array() += pad;
    const int perAxis = std::clamp(static_cast<int>(std::ceil(std::cbrt(static_cast<double>(elements)))), 1, 64);
    index.gridSize = {perAxis, perAxis, perAxis};
    const int cells = perAxis * perAxis * perAxis;
    const Eigen::Vector3d size = index.bounds.sizes();
    std::vector<int> counts(static_cast<size_t>(cells) + 1, 0);
    auto range = [&](int e, int lo[3], int hi[3]) {
        for (int a = 0; a < 3; ++a) {
            const double inverse = size[a] > 0.0 ? perAxis / size[a] : 0.0;
            lo[a] = std::clamp(static_cast<int>((index.chunkBounds[static_cast<size_t>(e)].min()[a] - index.bounds.min()[a]) * inverse), 0, perAxis - 1);
            hi[a] = std::clamp(static_cast<int>((index.chunkBounds[static_cast<size_t>(e)].max()[a] - index.bounds.min()[a]) * inverse), 0, perAxis - 1);
        }
    };
    for (int pass = 0; pass < 2; ++pass) {  // count, then fill (CSR, elements ascending per grid cell)
        if (pass == 1) {
            index.gridStart.assign(static_cast<size_t>(cells) + 1, 0);
            for (int g = 0; g < cells; ++g) index.gridStart[static_cast<size_t>(g) + 1] = index.gridStart[static_cast<size_t>(g)] + counts[static_cast<size_t>(g)];
            index.gridChunks.resize(static_cast<size_t>(index.gridStart.back()));
            std::fill(counts.begin(), counts.end(), 0);
        }
        for (int e = 0; e < elements; ++e) {
            int lo[3], hi[3];
            range(e, lo, hi);
            for (int z = lo[2]; z <= hi[2]; ++z)
                for (int y = lo[1]; y <= hi[1]; ++y)
                    for (int x = lo[0]; x <= hi[0]; ++x) {
                        const int g = x + perAxis * (y + perAxis * z);
                        if (pass == 1) index.gridChunks[static_cast<size_t>(index.gridStart[static_cast<size_t>(g)] + counts[static_cast<size_t>(g)])] = e;
                        ++counts[static_cast<size_t>(g)];
                    }
        }
    }
    return index;
}

namespace {

// Newton's method for Q(t) = x over the whole domain from `start`: LU steps, pseudo-inverse ones where dQ/dt is
// nearly singular, halved (up to 6 times) until |Q - x| decreases. Converged: |Q - x| <= tight, or the best
// residual <= loose once no step helps (rounding level).
bool newtonSolve(const TSplineVolume& volume, const Positions& points, const Eigen::Vector3d& x, const Eigen::Vector3d& start, double tight,
                 double loose, Eigen::Vector3d& t) {
    Eigen::Vector3d u = start, q;
    Eigen::Matrix3d d;
    volume.evaluate(points, u, q, &d);
    Eigen::Vector3d residual = x - q;
    double r = residual.norm();
    int slow = 0;
    for (int iteration = 0; iteration < 40 && r > tight && slow < 4; ++iteration) {
        const Eigen::Vector3d step = freezingNewtonStep(d, residual);
        if (!step.allFinite()) break;
        bool accepted = false;
        for (int halving = 0; halving <= 6 && !accepted; ++halving) {
            const Eigen::Vector3d candidate = (u + std::ldexp(1.0, -halving) * step).cwiseMax(0.0).cwiseMin(1.0);
            Eigen::Vector3d qc;
            Eigen::Matrix3d dc;
            volume.evaluate(points, candidate, qc, &dc);
            const double rc = (x - qc).norm();
            if (rc < r) {
                slow = rc > 0.5 * r ? slow + 1 : 0;
                u = candidate, q = qc, d = dc, residual = x - qc, r = rc;
                accepted = true;
            }
        }
        if (!accepted) break;
    }
    t = u;
    return r <= loose;
}

}  // namespace

TSplineVolume::FreezeIndex TSplineVolume::buildFreezeIndex(const Positions& points) const {
    FreezeIndex index;
    index.elements = buildElementIndex(points);
    // P_s ~ A g_s + b by least squares (normal equations of the 4 x 4 system [g 1]).
    const int n = basis_->anchorCount();
    Eigen::Matrix4d normal = Eigen::Matrix4d::Zero();
    Eigen::Matrix<double, 4, 3> right = Eigen::Matrix<double, 4, 3>::Zero();
    for (int s = 0; s < n; ++s) {
        Eigen::Vector4d g;
        g << basis_->grevilleParameters(s), 1.0;
        normal += g * g.transpose();
        right += g * points.row(s);
    }
    const Eigen::Matrix<double, 4, 3> map = normal.ldlt().solve(right);  // rows: A^T, then b^T
    const Eigen::Matrix3d linear = map.topRows<3>().transpose();
    const Eigen::FullPivLU<Eigen::Matrix3d> lu(linear);
    if (map.allFinite() && lu.isInvertible()) {
        index.inverse = lu.inverse();
        index.offset = map.row(3).transpose();
        index.affine = index.inverse.allFinite();
    }
    return index;
}

bool TSplineVolume::freezeWith(const Positions& points, const FreezeIndex& index, const Eigen::Vector3d& x, Eigen::Vector3d& t) const {
    if (!x.allFinite()) return false;
    const double diagonal = std::max(index.elements.bounds.diagonal().norm(), 1e-300);
    const double tight = 4e-15 * diagonal + 8.0 * std::numeric_limits<double>::epsilon() * x.cwiseAbs().maxCoeff();
    const double loose = 1e-13 * diagonal + 64.0 * std::numeric_limits<double>::epsilon() * x.cwiseAbs().maxCoeff();
    // Pass 0: from the affine preimage (the usual case: the point's own neighbourhood, 2-3 steps).
    if (index.affine) {
        const Eigen::Vector3d start = (index.inverse * (x - index.offset)).cwiseMax(0.0).cwiseMin(1.0);
        Eigen::Vector3d end;
        if (start.allFinite() && newtonSolve(*this, points, x, start, tight, loose, end)) {
            t = end;
            return true;
        }
    }
    thread_local std::vector<int> candidates;
    index.elements.candidates(x, candidates);
    if (candidates.empty()) return false;
    // Pass 1: from each candidate element's centre, lowest id first (deterministic on shared faces).
    bool allStoppedOnBoundary = true;
    for (int e : candidates) {
        const Eigen::Vector3d lo = basis_->elementMin(e), hi = basis_->elementMax(e);
        Eigen::Vector3d end;
        if (newtonSolve(*this, points, x, 0.5 * (lo + hi), tight, loose, end)) {
            t = end;
            return true;
        }
        // note: for a point outside the volume Newton walks onto the domain's boundary (Q's outer surface) and
        // stops there; only a start that stalled inside needs the finer starts below.
        allStoppedOnBoundary = allStoppedOnBoundary && (end.array() == 0.0 || end.array() == 1.0).any();
    }
    if (allStoppedOnBoundary) return false;
    // Pass 2: from the centres of each candidate's 8 octants, then of its 64 sub-boxes.
    for (int level = 2; level <= 4; level *= 2)
        for (int e : candidates) {
            const Eigen::Vector3d lo = basis_->elementMin(e), hi = basis_->elementMax(e);
            for (int s = 0; s < level * level * level; ++s) {
                const Eigen::Vector3d local((s % level + 0.5) / level, ((s / level) % level + 0.5) / level, (s / (level * level) + 0.5) / level);
                if (newtonSolve(*this, points, x, lo + (hi - lo).cwiseProduct(local), tight, loose, t)) return true;
            }
        }
    return false;
}

bool TSplineVolume::freeze(const Eigen::Vector3d& x, Eigen::Vector3d& t) const {
    Eigen::Vector3d found;
    if (!freezeWith(rest_, restIndex_, x, found)) return false;
    t = found;
    return true;
}

namespace {

class TSplineLocator final : public Volume::Locator {
public:
    TSplineLocator(const TSplineVolume& volume, const Positions& points) : volume_(volume), points_(points), index_(volume.buildFreezeIndex(points)) {}
    bool freeze(const Eigen::Vector3d& x, Eigen::Vector3d& t) const override {
        Eigen::Vector3d found;
        if (!volume_.freezeWith(points_, index_, x, found)) return false;
        t = found;
        return true;
    }

private:
    const TSplineVolume& volume_;
    Positions points_;
    TSplineVolume::FreezeIndex index_;
};

}  // namespace

std::unique_ptr<Volume::Locator> TSplineVolume::locatorFor(const Positions& points) const { return std::make_unique<TSplineLocator>(*this, points); }

Status TSplineVolume::placed(const Eigen::Vector3d& point, const Eigen::Vector3d& normal, double size,
                             std::shared_ptr<const Volume>& out) const {
    PlacementSimilarity similarity;
    if (Status s = placementSimilarity(restBounds(), point, normal, size, similarity); !s) return s;
    Positions points = restControlPoints();
    for (Eigen::Index s = 0; s < points.rows(); ++s) points.row(s) = similarity(points.row(s).transpose()).transpose();
    std::shared_ptr<const TSplineVolume> moved;
    if (Status s = TSplineVolume::make(sharedBasis(), std::move(points), controlWeights(), moved); !s) return s;
    out = std::move(moved);
    return Status::success();
}

}  // namespace sculpt::core
