// T-lattices (Song & Yang 2005, "Free-form deformation with weighted T-spline", seed 002, sec. 3.2.2 and 4):
// the control structure of a weighted T-spline volume. A T-lattice here is a set of axis-aligned box cells that
// tile the parameter domain [0,1]^3: a regular root grid of cells (Fig. 9a: the initial lattice), each of them
// the root of an octree whose leaves are the cells (Fig. 9b-c, Fig. 11). Its vertices are the cells' corners;
// a corner of a finer cell that lies inside a coarser cell's face or edge is a T-junction. The T-spline's
// blending functions are anchored at the vertices (tspline_volume.h).
//
// Integer coordinates: every knot line of the lattice lies on the "fine grid" of the deepest level, fine index
// f in [0, rootCount[a] 2^maxLevel] per axis, parameter knotValue[a][f]. Topology (rays, elements, supports)
// is computed on these integers, so no comparison of parameters ever depends on rounding.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/mesh_types.h"
#include "core/status.h"

namespace sculpt::core {

// Limits: levels below a root cell, root cells per axis (fine indices stay below 2^16, doubled below 2^17).
constexpr int kMaxTLatticeLevel = 10;
constexpr int kMaxTLatticeRootCells = 64;

// One cell (an octree leaf): `level` subdivisions below the root grid, `index` its position among the
// rootCount[a] 2^level cells of that level along each axis.
struct TLatticeCell {
    int level = 0;
    std::array<int, 3> index{};
    bool operator==(const TLatticeCell& o) const { return level == o.level && index == o.index; }
};

// An octree node (derived): a cell (leaf) or 8 children at firstChild .. firstChild+7 (child o = x + 2y + 4z).
struct TLatticeNode {
    int level = 0;
    std::array<int, 3> index{};
    int firstChild = -1;  // -1: a leaf
    int cell = -1;        // the leaf's cell id
};

struct TLattice {
    // ---- raw fields ----
    std::array<int, 3> rootCount{1, 1, 1};     // root cells per axis, in [1, kMaxTLatticeRootCells]
    // Root knot lines per axis: rootCount[a] + 1 values from 0 to 1, strictly increasing (rule 3: no zero
    // edges). Empty: uniform, i / rootCount[a].
    std::array<std::vector<double>, 3> rootKnots;
    std::vector<TLatticeCell> cells;           // the leaves, any order (cell id = position)

    // ---- derived (finishTLattice) ----
    int maxLevel = 0;
    std::array<int, 3> fineCount{};                 // rootCount[a] << maxLevel
    std::array<std::vector<double>, 3> knotValue;   // fineCount[a] + 1 parameters per axis, 0 .. 1
    std::vector<TLatticeNode> nodes;                // the root grid's nodes first (i + R0 (j + R1 k)), then children
    std::vector<std::array<int, 3>> vertices;       // fine coordinates of the cell corners, sorted by (w, v, u)

    // Fine coordinates of cell c's box: [lo, hi) per axis.
    std::array<int, 3> cellLo(int c) const;
    std::array<int, 3> cellHi(int c) const;
    // The cell holding the fine voxel whose doubled coordinates are `doubled` (odd, in [1, 2 fineCount - 1]).
    int cellAtDoubled(const std::array<int, 3>& doubled) const;
    // The fine voxel holding parameter t_a along axis a: the last f with knotValue[f] <= t_a, clamped to
    // [0, fineCount - 1] (so t_a = 1 lies in the last voxel).
    int fineVoxel(int axis, double t) const;
    // Song & Yang 2005, sec. 3.2.2, the knot rule: from the vertex line through fine point p along `axis`, the
    // fine coordinate of the first knot plane (a cell face of constant t_axis, touching the line) strictly
    // beyond p[axis] in `direction` (+1 or -1); the domain boundary itself where the ray leaves the domain
    // (the boundary repeats). p's other two coordinates must be fine knot lines inside the domain.
    int nextKnotPlane(const std::array<int, 3>& p, int axis, int direction) const;
};

// Validates the raw fields and fills the derived ones. Errors name the rule of sec. 3.2.2 and the cell:
//   rule 1 (in each minimal cell the knot intervals of opposite sides sum equal): a region covered by no cell
//     (the minimal cell there would not be a box);
//   rule 2 (any edge must be a cell edge): two cells that overlap (the edges of one run inside the other);
//   rule 3 (no zero edges): root knot lines that coincide or decrease;
// plus levels and indices out of range and non-finite knots. `lattice` is unspecified on failure.
Status finishTLattice(TLattice& lattice);

// The raw fields only (a copy to edit).
TLattice rawTLatticeFields(const TLattice& lattice);

// ---- generation (sec. 4) ------------------------------------------------------------------------------------

struct TLatticeOctreeSettings {
    std::array<int, 3> rootCount{1, 1, 1};  // the initial lattice (Fig. 9a), cells per axis
    int depth = 3;                          // levels of octree subdivision of the non-empty cells, in [0, kMaxTLatticeLevel]
    // 2:1 balance: cells that share a point (face, edge or corner) differ by at most one level; subdividing
    // a cell also subdivides coarser neighbours until this holds. Keeps the Bezier elements few and the blending
    // functions overlapping a point well within SupportWeights' 216 (measured, not proven: at most 116 round a
    // sphere at depth 5; buildTSplineBasis refuses a lattice where more overlap). The rules of 3.2.2 themselves
    // hold for any octree, balanced or not.
    bool balance = true;
};

// Fig. 9 / sec. 4 steps 1-3: the octree T-lattice of `points` (#P x 3, world) in `box` (mapped affinely onto
// [0,1]^3): cells holding a point (closed boxes) are subdivided until `depth`, then balanced. nonEmpty (if not
// null) gets, per cell, whether it holds a point. Fails on an empty or non-finite box, or settings out of range.
Status makeOctreeTLattice(const Positions& points, const Eigen::AlignedBox3d& box, const TLatticeOctreeSettings& settings,
                          TLattice& out, std::vector<std::uint8_t>* nonEmpty = nullptr);

// Fig. 11 / sec. 6 step 2: local octree subdivision of the chosen cells (ids of `lattice`, finished), then the
// 2:1 balance if `balance`. Fails on an id out of range or a cell already at kMaxTLatticeLevel.
Status subdivideTLatticeCells(const TLattice& lattice, const std::vector<int>& cells, bool balance, TLattice& out);

// Whether every two cells sharing a point differ by at most one level.
bool tlatticeBalanced(const TLattice& lattice);

}  // namespace sculpt::core
