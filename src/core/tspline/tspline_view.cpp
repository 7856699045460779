// Read-only views of weighted T-spline lattices for drawing and picking (Song & Yang 2005, seed 002: sec.
// 3.2.2 and Fig. 9 for the T-lattice and its T-junctions, sec. 4 and Fig. 10 for the control points of
// non-empty cells, sec. 6 and Fig. 11 for choosing cells to subdivide).
#include "core/tspline/tspline_view.h"

#include <algorithm>
#include <tuple>

#include <Eigen/Dense>

namespace sculpt::core {

namespace {

// The 8 voxels round fine point p that lie in the domain, as doubled coordinates (odd).
template <typename Visit>
void forVoxelsAround(const TLattice& lattice, const std::array<int, 3>& p, Visit visit) {
    for (int corner = 0; corner < 8; ++corner) {
        std::array<int, 3> doubled{};
        bool inside = true;
        for (int a = 0; a < 3; ++a) {
            doubled[a] = 2 * p[a] + (((corner >> a) & 1) ? 1 : -1);
            inside = inside && doubled[a] > 0 && doubled[a] < 2 * lattice.fineCount[a];
        }
        if (inside && visit(doubled)) return;
    }
}

}  // namespace

const TSplineVolume* asTSpline(const Volume* volume) { return volume ? volume->tsplineVolume() : nullptr; }

std::vector<std::uint8_t> nonEmptyTSplineCells(const TSplineVolume& volume, const Positions& points) {
    const TSplineBasis& basis = volume.basis();
    const TLattice& lattice = basis.lattice;
    std::vector<std::uint8_t> cells(lattice.cells.size(), 0);
    // The affine map P_s = A g_s + b the rest control points are an image of the Greville parameters by.
    const int n = basis.anchorCount();
    Eigen::MatrixXd greville(n, 4);
    for (int s = 0; s < n; ++s) greville.row(s) << basis.grevilleParameters(s).transpose(), 1.0;
    const Eigen::MatrixXd map = greville.colPivHouseholderQr().solve(Eigen::MatrixXd(volume.restControlPoints()));
    const Eigen::Matrix3d linear = map.topRows<3>().transpose();
    const Eigen::Vector3d offset = map.row(3).transpose();
    const Eigen::FullPivLU<Eigen::Matrix3d> lu(linear);
    if (!lu.isInvertible()) return cells;
    const Eigen::Matrix3d inverse = lu.inverse();
    for (Eigen::Index p = 0; p < points.rows(); ++p) {
        const Eigen::Vector3d t = inverse * (points.row(p).transpose() - offset);
        const int cell = cellAtParameters(lattice, t);
        if (cell >= 0) cells[static_cast<size_t>(cell)] = 1;
    }
    return cells;
}

std::vector<std::uint8_t> controlPointsOfCells(const TSplineBasis& basis, const std::vector<std::uint8_t>& cells) {
    const TLattice& lattice = basis.lattice;
    std::vector<std::uint8_t> vertexShown(lattice.vertices.size(), 0);
    if (cells.size() != lattice.cells.size()) return std::vector<std::uint8_t>(basis.anchors.size(), 0);
    for (size_t v = 0; v < lattice.vertices.size(); ++v)
        forVoxelsAround(lattice, lattice.vertices[v], [&](const std::array<int, 3>& doubled) {
            return (vertexShown[v] = cells[static_cast<size_t>(lattice.cellAtDoubled(doubled))]) != 0;
        });
    std::vector<std::uint8_t> shown(basis.anchors.size(), 0);
    for (size_t s = 0; s < basis.anchors.size(); ++s) shown[s] = vertexShown[static_cast<size_t>(basis.anchors[s].vertex)];
    return shown;
}

std::vector<int> tJunctionVertices(const TLattice& lattice) {
    std::vector<int> junctions;
    for (size_t v = 0; v < lattice.vertices.size(); ++v) {
        const std::array<int, 3>& p = lattice.vertices[v];
        bool lineEnds = false;
        for (int a = 0; a < 3 && !lineEnds; ++a) {
            const int b = (a + 1) % 3, c = (a + 2) % 3;
            for (int direction : {-1, 1}) {
                if (direction < 0 ? p[a] <= 0 : p[a] >= lattice.fineCount[a]) continue;  // the domain ends here
                // An edge leaves p along direction a when one of the (up to 4) cells touching the ray just beyond
                // p has p's other two coordinates on its bounds: the ray then runs along that cell's edge.
                bool edge = false;
                for (int quadrant = 0; quadrant < 4 && !edge; ++quadrant) {
                    std::array<int, 3> doubled{};
                    doubled[a] = 2 * p[a] + direction;
                    doubled[b] = 2 * p[b] + ((quadrant & 1) ? 1 : -1);
                    doubled[c] = 2 * p[c] + ((quadrant & 2) ? 1 : -1);
                    if (doubled[b] <= 0 || doubled[b] >= 2 * lattice.fineCount[b] || doubled[c] <= 0 || doubled[c] >= 2 * lattice.fineCount[c])
                        continue;
                    const int cell = lattice.cellAtDoubled(doubled);
                    const std::array<int, 3> lo = lattice.cellLo(cell), hi = lattice.cellHi(cell);
                    edge = (p[b] == lo[b] || p[b] == hi[b]) && (p[c] == lo[c] || p[c] == hi[c]);
                }
                if (!edge) lineEnds = true;
            }
        }
        if (lineEnds) junctions.push_back(static_cast<int>(v));
    }
    return junctions;
}

Eigen::Vector3d vertexParameters(const TLattice& lattice, int vertex) {
    const std::array<int, 3>& p = lattice.vertices[static_cast<size_t>(vertex)];
    return {lattice.knotValue[0][static_cast<size_t>(p[0])], lattice.knotValue[1][static_cast<size_t>(p[1])],
            lattice.knotValue[2][static_cast<size_t>(p[2])]};
}

int cellAtParameters(const TLattice& lattice, const Eigen::Vector3d& t) {
    if (!t.allFinite() || (t.array() < 0.0).any() || (t.array() > 1.0).any()) return -1;
    std::array<int, 3> doubled{};
    for (int a = 0; a < 3; ++a) doubled[a] = 2 * lattice.fineVoxel(a, t[a]) + 1;
    return lattice.cellAtDoubled(doubled);
}

int cellAtRestPoint(const TSplineVolume& volume, const Eigen::Vector3d& x) {
    Eigen::Vector3d t;
    if (!x.allFinite() || !volume.freeze(x, t)) return -1;
    return cellAtParameters(volume.lattice(), t);
}

int vertexAt(const TLattice& lattice, const std::array<int, 3>& p) {
    const auto byWvu = [](const std::array<int, 3>& a, const std::array<int, 3>& b) {
        return std::tie(a[2], a[1], a[0]) < std::tie(b[2], b[1], b[0]);
    };
    const auto found = std::lower_bound(lattice.vertices.begin(), lattice.vertices.end(), p, byWvu);
    return found != lattice.vertices.end() && *found == p ? static_cast<int>(found - lattice.vertices.begin()) : -1;
}

bool anchorOnDomainBoundary(const TSplineBasis& basis, int anchor) {
    const TLattice& lattice = basis.lattice;
    const std::array<int, 3>& p = lattice.vertices[static_cast<size_t>(basis.anchors[static_cast<size_t>(anchor)].vertex)];
    for (int a = 0; a < 3; ++a)
        if (p[a] == 0 || p[a] == lattice.fineCount[a]) return true;
    return false;
}

std::vector<std::array<int, 2>> tlatticeNetEdges(const TSplineBasis& basis) {
    std::vector<std::array<int, 2>> edges;
    edges.reserve(basis.latticeEdges.size());
    for (const std::array<int, 2>& edge : basis.latticeEdges) edges.push_back({vertexAnchor(basis, edge[0]), vertexAnchor(basis, edge[1])});
    return edges;
}

std::vector<Positions> cellEdgeSegments(const TSplineBasis& basis, int cell, const Positions& controlPoints) {
    const TLattice& lattice = basis.lattice;
    std::vector<Positions> segments;
    if (cell < 0 || cell >= static_cast<int>(lattice.cells.size())) return segments;
    const std::array<int, 3> lo = lattice.cellLo(cell), hi = lattice.cellHi(cell);
    std::array<int, 8> corner{};  // corner o = x + 2y + 4z
    for (int o = 0; o < 8; ++o) {
        const int v = vertexAt(lattice, {(o & 1) ? hi[0] : lo[0], (o & 2) ? hi[1] : lo[1], (o & 4) ? hi[2] : lo[2]});
        if (v < 0) return {};  // not a finished lattice: every cell corner is a vertex
        corner[static_cast<size_t>(o)] = vertexAnchor(basis, v);
    }
    for (int o = 0; o < 8; ++o)
        for (int a = 0; a < 3; ++a) {
            if (o & (1 << a)) continue;
            Positions segment(2, 3);
            segment.row(0) = controlPoints.row(corner[static_cast<size_t>(o)]);
            segment.row(1) = controlPoints.row(corner[static_cast<size_t>(o | (1 << a))]);
            segments.push_back(std::move(segment));
        }
    return segments;
}

TSplineCageView tsplineCageView(const Session& session) {
    TSplineCageView view;
    view.volume = asTSpline(session.lattice().volume.get());
    if (!view.volume) return view;
    view.cells = nonEmptyTSplineCells(*view.volume, session.mesh().rest);
    const TSplineBasis& basis = view.volume->basis();
    view.controlPoints = controlPointsOfCells(basis, view.cells);
    for (size_t s = 0; s < basis.anchors.size(); ++s)
        if (basis.anchors[s].boundaryCopy != 0) view.controlPoints[s] = 0;
    return view;
}

}  // namespace sculpt::core
