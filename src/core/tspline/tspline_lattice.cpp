// T-lattices as octrees over a root grid (Song & Yang 2005, sec. 3.2.2 rules 1-3, sec. 4 octree generation,
// Fig. 9 and Fig. 11), on the integer fine grid of the deepest level.
#include "core/tspline/tspline_lattice.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <tuple>

namespace sculpt::core {

namespace {

std::string cellName(const TLatticeCell& cell) {
    return "level " + std::to_string(cell.level) + " (" + std::to_string(cell.index[0]) + ", " + std::to_string(cell.index[1]) + ", " +
           std::to_string(cell.index[2]) + ")";
}

std::string nodeName(const TLatticeNode& node) { return cellName(TLatticeCell{node.level, node.index}); }

int rootNodeOf(const std::array<int, 3>& rootCount, const std::array<int, 3>& root) {
    return root[0] + rootCount[0] * (root[1] + rootCount[1] * root[2]);
}

void makeRoots(const std::array<int, 3>& rootCount, std::vector<TLatticeNode>& nodes) {
    nodes.clear();
    for (int k = 0; k < rootCount[2]; ++k)
        for (int j = 0; j < rootCount[1]; ++j)
            for (int i = 0; i < rootCount[0]; ++i) {
                TLatticeNode node;
                node.index = {i, j, k};
                nodes.push_back(node);
            }
}

void splitNode(std::vector<TLatticeNode>& nodes, int n) {
    const int first = static_cast<int>(nodes.size());
    nodes[static_cast<size_t>(n)].firstChild = first;
    nodes[static_cast<size_t>(n)].cell = -1;
    const TLatticeNode parent = nodes[static_cast<size_t>(n)];
    for (int o = 0; o < 8; ++o) {
        TLatticeNode child;
        child.level = parent.level + 1;
        for (int a = 0; a < 3; ++a) child.index[a] = 2 * parent.index[a] + ((o >> a) & 1);
        nodes.push_back(child);
    }
}

// The deepest node holding the level-`level` cell position `index`, descending no further than `level`.
int nodeAt(const std::vector<TLatticeNode>& nodes, const std::array<int, 3>& rootCount, int level, const std::array<int, 3>& index) {
    std::array<int, 3> root{};
    for (int a = 0; a < 3; ++a) root[a] = index[a] >> level;
    int n = rootNodeOf(rootCount, root);
    while (nodes[static_cast<size_t>(n)].firstChild >= 0 && nodes[static_cast<size_t>(n)].level < level) {
        const int childLevel = nodes[static_cast<size_t>(n)].level + 1;
        int o = 0;
        for (int a = 0; a < 3; ++a) o |= ((index[a] >> (level - childLevel)) & 1) << a;
        n = nodes[static_cast<size_t>(n)].firstChild + o;
    }
    return n;
}

// Splits leaves until every two leaves sharing a point differ by at most one level (repeated passes: a split
// can unbalance the split cell's own neighbours).
void balanceNodes(std::vector<TLatticeNode>& nodes, const std::array<int, 3>& rootCount) {
    for (bool changed = true; changed;) {
        changed = false;
        const size_t count = nodes.size();
        for (size_t n = 0; n < count; ++n) {
            if (nodes[n].firstChild >= 0 || nodes[n].level < 2) continue;
            const TLatticeNode leaf = nodes[n];
            for (int d = 0; d < 27; ++d) {
                const std::array<int, 3> offset{d % 3 - 1, (d / 3) % 3 - 1, d / 9 - 1};
                if (offset == std::array<int, 3>{0, 0, 0}) continue;
                std::array<int, 3> position{};
                bool inside = true;
                for (int a = 0; a < 3; ++a) {
                    position[a] = leaf.index[a] + offset[a];
                    inside = inside && position[a] >= 0 && position[a] < (rootCount[a] << leaf.level);
                }
                if (!inside) continue;
                const int m = nodeAt(nodes, rootCount, leaf.level, position);
                if (nodes[static_cast<size_t>(m)].firstChild < 0 && nodes[static_cast<size_t>(m)].level < leaf.level - 1) {
                    splitNode(nodes, m);
                    changed = true;
                }
            }
        }
    }
}

void collectLeaves(const std::vector<TLatticeNode>& nodes, int n, std::vector<TLatticeCell>& cells) {
    const TLatticeNode& node = nodes[static_cast<size_t>(n)];
    if (node.firstChild < 0) {
        cells.push_back(TLatticeCell{node.level, node.index});
        return;
    }
    for (int o = 0; o < 8; ++o) collectLeaves(nodes, node.firstChild + o, cells);
}

// A lattice from a node tree: its leaves in depth-first order from the roots, finished.
Status latticeFromNodes(const std::array<int, 3>& rootCount, const std::array<std::vector<double>, 3>& rootKnots,
                        const std::vector<TLatticeNode>& nodes, TLattice& out) {
    TLattice lattice;
    lattice.rootCount = rootCount;
    lattice.rootKnots = rootKnots;
    const int roots = rootCount[0] * rootCount[1] * rootCount[2];
    for (int r = 0; r < roots; ++r) collectLeaves(nodes, r, lattice.cells);
    if (Status s = finishTLattice(lattice); !s) return s;
    out = std::move(lattice);
    return Status::success();
}

bool validRootCount(const std::array<int, 3>& rootCount) {
    return std::all_of(rootCount.begin(), rootCount.end(), [](int r) { return r >= 1 && r <= kMaxTLatticeRootCells; });
}

}  // namespace

std::array<int, 3> TLattice::cellLo(int c) const {
    const TLatticeCell& cell = cells[static_cast<size_t>(c)];
    return {cell.index[0] << (maxLevel - cell.level), cell.index[1] << (maxLevel - cell.level), cell.index[2] << (maxLevel - cell.level)};
}

std::array<int, 3> TLattice::cellHi(int c) const {
    const TLatticeCell& cell = cells[static_cast<size_t>(c)];
    const int shift = maxLevel - cell.level;
    return {(cell.index[0] + 1) << shift, (cell.index[1] + 1) << shift, (cell.index[2] + 1) << shift};
}

int TLattice::cellAtDoubled(const std::array<int, 3>& doubled) const {
    std::array<int, 3> fine{}, root{};
    for (int a = 0; a < 3; ++a) {
        fine[a] = doubled[a] >> 1;
        root[a] = fine[a] >> maxLevel;
    }
    int n = rootNodeOf(rootCount, root);
    while (nodes[static_cast<size_t>(n)].firstChild >= 0) {
        const int childLevel = nodes[static_cast<size_t>(n)].level + 1;
        int o = 0;
        for (int a = 0; a < 3; ++a) o |= ((fine[a] >> (maxLevel - childLevel)) & 1) << a;
        n = nodes[static_cast<size_t>(n)].firstChild + o;
    }
    return nodes[static_cast<size_t>(n)].cell;
}

int TLattice::fineVoxel(int axis, double t) const {
    const std::vector<double>& knots = knotValue[static_cast<size_t>(axis)];
    const int f = static_cast<int>(std::upper_bound(knots.begin(), knots.end(), t) - knots.begin()) - 1;
    return std::clamp(f, 0, fineCount[axis] - 1);
}

int TLattice::nextKnotPlane(const std::array<int, 3>& p, int axis, int direction) const {
    if (direction > 0 ? p[axis] >= fineCount[axis] : p[axis] <= 0) return p[axis];  // left the domain: the boundary repeats
    const int b = (axis + 1) % 3, c = (axis + 2) % 3;
    int best = direction > 0 ? fineCount[axis] : 0;
    // The cells touching the ray just beyond p: one per quadrant round the line (fewer on the boundary). The
    // first of their faces of constant t_axis is the first knot plane the ray crosses: between p and it those
    // cells' closures cover a neighbourhood of the ray, and none has such a face.
    for (int q = 0; q < 4; ++q) {
        std::array<int, 3> doubled{};
        doubled[axis] = 2 * p[axis] + direction;
        doubled[b] = 2 * p[b] + ((q & 1) ? 1 : -1);
        doubled[c] = 2 * p[c] + ((q & 2) ? 1 : -1);
        if (doubled[b] < 0 || doubled[b] > 2 * fineCount[b] || doubled[c] < 0 || doubled[c] > 2 * fineCount[c]) continue;
        const int cell = cellAtDoubled(doubled);
        best = direction > 0 ? std::min(best, cellHi(cell)[axis]) : std::max(best, cellLo(cell)[axis]);
    }
    return best;
}

Status finishTLattice(TLattice& lattice) {
    if (!validRootCount(lattice.rootCount))
        return Status::error("a T-lattice needs 1 to " + std::to_string(kMaxTLatticeRootCells) + " root cells per axis");
    for (int a = 0; a < 3; ++a) {
        const std::vector<double>& r = lattice.rootKnots[static_cast<size_t>(a)];
        if (r.empty()) continue;
        if (r.size() != static_cast<size_t>(lattice.rootCount[a]) + 1)
            return Status::error("root knots of axis " + std::to_string(a) + ": expected " + std::to_string(lattice.rootCount[a] + 1) + " values");
        if (!std::all_of(r.begin(), r.end(), [](double x) { return std::isfinite(x); }) || r.front() != 0.0 || r.back() != 1.0)
            return Status::error("root knots of axis " + std::to_string(a) + " must be finite, from 0 to 1");
        for (size_t i = 0; i + 1 < r.size(); ++i)
            if (!(r[i] < r[i + 1]))
                return Status::error("rule 3 (no zero edges) fails: root knot lines " + std::to_string(i) + " and " + std::to_string(i + 1) + " of axis " +
                                     std::to_string(a) + " do not increase, so root cell " + std::to_string(i) + " has a zero edge");
    }
    if (lattice.cells.empty()) return Status::error("a T-lattice needs at least one cell");
    lattice.maxLevel = 0;
    for (size_t c = 0; c < lattice.cells.size(); ++c) {
        const TLatticeCell& cell = lattice.cells[c];
        if (cell.level < 0 || cell.level > kMaxTLatticeLevel)
            return Status::error("T-lattice cell " + std::to_string(c) + ": level outside [0, " + std::to_string(kMaxTLatticeLevel) + "]");
        for (int a = 0; a < 3; ++a)
            if (cell.index[a] < 0 || cell.index[a] >= (lattice.rootCount[a] << cell.level))
                return Status::error("T-lattice cell " + std::to_string(c) + " (" + cellName(cell) + ") lies outside the domain");
        lattice.maxLevel = std::max(lattice.maxLevel, cell.level);
    }
    for (int a = 0; a < 3; ++a) {
        const int fine = lattice.rootCount[a] << lattice.maxLevel;
        lattice.fineCount[a] = fine;
        std::vector<double>& values = lattice.knotValue[static_cast<size_t>(a)];
        values.resize(static_cast<size_t>(fine) + 1);
        const std::vector<double>& r = lattice.rootKnots[static_cast<size_t>(a)];
        for (int f = 0; f <= fine; ++f) {
            if (r.empty()) {
                values[static_cast<size_t>(f)] = static_cast<double>(f) / fine;
            } else {
                const int root = std::min(f >> lattice.maxLevel, lattice.rootCount[a] - 1);
                const double fraction = static_cast<double>(f - (root << lattice.maxLevel)) / static_cast<double>(1 << lattice.maxLevel);
                values[static_cast<size_t>(f)] = f == fine ? 1.0 : r[static_cast<size_t>(root)] + fraction * (r[static_cast<size_t>(root) + 1] - r[static_cast<size_t>(root)]);
            }
        }
    }
    // The octree: each cell inserted along its path from its root.
    makeRoots(lattice.rootCount, lattice.nodes);
    auto someCellBelow = [&](int n) {
        while (lattice.nodes[static_cast<size_t>(n)].cell < 0 && lattice.nodes[static_cast<size_t>(n)].firstChild >= 0) {
            const int first = lattice.nodes[static_cast<size_t>(n)].firstChild;
            n = first;
            for (int o = 0; o < 8; ++o)
                if (lattice.nodes[static_cast<size_t>(first + o)].cell >= 0 || lattice.nodes[static_cast<size_t>(first + o)].firstChild >= 0) {
                    n = first + o;
                    break;
                }
        }
        return lattice.nodes[static_cast<size_t>(n)].cell;
    };
    for (size_t c = 0; c < lattice.cells.size(); ++c) {
        const TLatticeCell& cell = lattice.cells[c];
        std::array<int, 3> root{};
        for (int a = 0; a < 3; ++a) root[a] = cell.index[a] >> cell.level;
        int n = rootNodeOf(lattice.rootCount, root);
        for (int level = 1; level <= cell.level; ++level) {
            if (lattice.nodes[static_cast<size_t>(n)].cell >= 0) {
                const int other = lattice.nodes[static_cast<size_t>(n)].cell;
                return Status::error("rule 2 (any edge must be a cell edge) fails: T-lattice cell " + std::to_string(c) + " (" + cellName(cell) +
                                     ") lies inside cell " + std::to_string(other) + " (" + cellName(lattice.cells[static_cast<size_t>(other)]) +
                                     "), so its edges run inside that cell");
            }
            if (lattice.nodes[static_cast<size_t>(n)].firstChild < 0) splitNode(lattice.nodes, n);
            int o = 0;
            for (int a = 0; a < 3; ++a) o |= ((cell.index[a] >> (cell.level - level)) & 1) << a;
            n = lattice.nodes[static_cast<size_t>(n)].firstChild + o;
        }
        TLatticeNode& node = lattice.nodes[static_cast<size_t>(n)];
        if (node.cell >= 0 || node.firstChild >= 0) {
            const int other = node.cell >= 0 ? node.cell : someCellBelow(n);
            return Status::error("rule 2 (any edge must be a cell edge) fails: T-lattice cell " + std::to_string(c) + " (" + cellName(cell) +
                                 ") overlaps cell " + std::to_string(other) + " (" + cellName(lattice.cells[static_cast<size_t>(other)]) +
                                 "), so the edges of one run inside the other");
        }
        node.cell = static_cast<int>(c);
    }
    for (const TLatticeNode& node : lattice.nodes)
        if (node.firstChild < 0 && node.cell < 0)
            return Status::error("rule 1 (in each minimal cell the knot intervals of opposite sides sum equal) fails: no cell covers the region " +
                                 nodeName(node) + ", so the minimal cell there is not a box");
    // Vertices: the distinct cell corners.
    lattice.vertices.clear();
    lattice.vertices.reserve(lattice.cells.size() * 8);
    for (int c = 0; c < static_cast<int>(lattice.cells.size()); ++c) {
        const std::array<int, 3> lo = lattice.cellLo(c), hi = lattice.cellHi(c);
        for (int corner = 0; corner < 8; ++corner)
            lattice.vertices.push_back({(corner & 1) ? hi[0] : lo[0], (corner & 2) ? hi[1] : lo[1], (corner & 4) ? hi[2] : lo[2]});
    }
    auto byWvu = [](const std::array<int, 3>& p, const std::array<int, 3>& q) {
        return std::tie(p[2], p[1], p[0]) < std::tie(q[2], q[1], q[0]);
    };
    std::sort(lattice.vertices.begin(), lattice.vertices.end(), byWvu);
    lattice.vertices.erase(std::unique(lattice.vertices.begin(), lattice.vertices.end()), lattice.vertices.end());
    return Status::success();
}

TLattice rawTLatticeFields(const TLattice& lattice) {
    TLattice raw;
    raw.rootCount = lattice.rootCount;
    raw.rootKnots = lattice.rootKnots;
    raw.cells = lattice.cells;
    return raw;
}

Status makeOctreeTLattice(const Positions& points, const Eigen::AlignedBox3d& box, const TLatticeOctreeSettings& settings, TLattice& out,
                          std::vector<std::uint8_t>* nonEmpty) {
    if (!validRootCount(settings.rootCount))
        return Status::error("an octree T-lattice needs 1 to " + std::to_string(kMaxTLatticeRootCells) + " root cells per axis");
    if (settings.depth < 0 || settings.depth > kMaxTLatticeLevel)
        return Status::error("octree depth must be in [0, " + std::to_string(kMaxTLatticeLevel) + "]");
    if (box.isEmpty() || !box.min().allFinite() || !box.max().allFinite() || !(box.sizes().array() > 0.0).all())
        return Status::error("an octree T-lattice needs a finite box with min < max on every axis");
    // Each point's voxel at the deepest level (half-open cells; a point on the box's max face lies in the last).
    const int depth = settings.depth;
    std::vector<std::array<int, 3>> voxels;
    voxels.reserve(static_cast<size_t>(points.rows()));
    for (Eigen::Index p = 0; p < points.rows(); ++p) {
        const Eigen::Vector3d x = points.row(p).transpose();
        if (!x.allFinite() || !box.contains(x)) continue;
        std::array<int, 3> voxel{};
        for (int a = 0; a < 3; ++a) {
            const int fine = settings.rootCount[a] << depth;
            voxel[a] = std::clamp(static_cast<int>(std::floor((x[a] - box.min()[a]) / box.sizes()[a] * fine)), 0, fine - 1);
        }
        voxels.push_back(voxel);
    }
    std::vector<TLatticeNode> nodes;
    makeRoots(settings.rootCount, nodes);
    // Sec. 4 steps 2-3: subdivide every cell holding a vertex of the model, level by level.
    for (int level = 0; level < depth; ++level) {
        std::vector<std::uint8_t> marked(nodes.size(), 0);
        for (const auto& voxel : voxels) {
            std::array<int, 3> at{};
            for (int a = 0; a < 3; ++a) at[a] = voxel[a] >> (depth - level);
            const int n = nodeAt(nodes, settings.rootCount, level, at);
            if (nodes[static_cast<size_t>(n)].level == level && nodes[static_cast<size_t>(n)].firstChild < 0) marked[static_cast<size_t>(n)] = 1;
        }
        for (size_t n = 0; n < marked.size(); ++n)
            if (marked[n]) splitNode(nodes, static_cast<int>(n));
    }
    if (settings.balance) balanceNodes(nodes, settings.rootCount);
    TLattice lattice;
    if (Status s = latticeFromNodes(settings.rootCount, {}, nodes, lattice); !s) return s;
    if (nonEmpty) {
        nonEmpty->assign(lattice.cells.size(), 0);
        const int shift = depth - lattice.maxLevel;  // no point: nothing was subdivided
        for (const auto& voxel : voxels) {
            std::array<int, 3> doubled{};
            for (int a = 0; a < 3; ++a) doubled[a] = 2 * (voxel[a] >> shift) + 1;
            (*nonEmpty)[static_cast<size_t>(lattice.cellAtDoubled(doubled))] = 1;
        }
    }
    out = std::move(lattice);
    return Status::success();
}

Status subdivideTLatticeCells(const TLattice& lattice, const std::vector<int>& cells, bool balance, TLattice& out) {
    std::vector<TLatticeNode> nodes = lattice.nodes;
    std::vector<int> nodeOfCell(lattice.cells.size(), -1);
    for (size_t n = 0; n < nodes.size(); ++n)
        if (nodes[n].cell >= 0) nodeOfCell[static_cast<size_t>(nodes[n].cell)] = static_cast<int>(n);
    for (int c : cells) {
        if (c < 0 || c >= static_cast<int>(lattice.cells.size())) return Status::error("T-lattice cell " + std::to_string(c) + " does not exist");
        if (lattice.cells[static_cast<size_t>(c)].level >= kMaxTLatticeLevel)
            return Status::error("T-lattice cell " + std::to_string(c) + " is at the deepest level " + std::to_string(kMaxTLatticeLevel));
        const int n = nodeOfCell[static_cast<size_t>(c)];
        if (nodes[static_cast<size_t>(n)].firstChild < 0) splitNode(nodes, n);
    }
    if (balance) balanceNodes(nodes, lattice.rootCount);
    return latticeFromNodes(lattice.rootCount, lattice.rootKnots, nodes, out);
}

bool tlatticeBalanced(const TLattice& lattice) {
    for (const TLatticeNode& leaf : lattice.nodes) {
        if (leaf.firstChild >= 0 || leaf.level < 2) continue;
        for (int d = 0; d < 27; ++d) {
            std::array<int, 3> position{};
            bool inside = true;
            for (int a = 0; a < 3; ++a) {
                position[a] = leaf.index[a] + (a == 0 ? d % 3 : a == 1 ? (d / 3) % 3 : d / 9) - 1;
                inside = inside && position[a] >= 0 && position[a] < (lattice.rootCount[a] << leaf.level);
            }
            if (!inside) continue;
            const TLatticeNode& other = lattice.nodes[static_cast<size_t>(nodeAt(lattice.nodes, lattice.rootCount, leaf.level, position))];
            if (other.firstChild < 0 && other.level < leaf.level - 1) return false;
        }
    }
    return true;
}

}  // namespace sculpt::core
