// What the window shows and picks of a weighted T-spline lattice (Song & Yang 2005, "Free-form deformation
// with weighted T-spline", seed 002): read-only queries on a TSplineVolume and the session, no drawing.
//   Fig. 9 / sec. 3.2.2: the T-lattice's edges, with its T-junctions marked (where a line of the lattice ends);
//   Fig. 10 / sec. 4:    only the control points of non-empty cells are shown and picked (the heavy ones; the
//                        light ones only serve the parametrization: "we hide the rest of the control points");
//   Fig. 11 / sec. 6:    the cell under a picked point, and a cell's edges, for choosing cells to subdivide.
// Plain data and Eigen only (no GL, no UI): the app copies these into the renderer's LatticeView.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "core/mesh_types.h"
#include "core/session/session.h"
#include "core/tspline/tspline_lattice.h"
#include "core/tspline/tspline_volume.h"
#include "core/volume/volume.h"

namespace sculpt::core {

// The volume as a weighted T-spline, or null when it is of another kind (or null).
const TSplineVolume* asTSpline(const Volume* volume);

// Sec. 4: per cell of the volume's T-lattice, 1 when it holds one of `points` (#P x 3, world), classified as
// makeOctreeTSplineVolume and subdivideTSplineVolume classify them when they set the weights: a point's
// parameters are its image under the inverse of the affine map that takes the anchors' Greville parameters onto
// the rest control points (least squares over all of them, exact for a generated or placed volume), its cell
// the one holding that parameter's fine voxel; points outside [0,1]^3 count for no cell.
// note: the sec. 4 classification is a box one, not the frozen parameters: with weights 100:1 the rest map is
// not affine, and a vertex's frozen parameters can lie in a neighbouring cell. This is the one the weights follow.
std::vector<std::uint8_t> nonEmptyTSplineCells(const TSplineVolume& volume, const Positions& points);

// Fig. 10: per control point (anchor), 1 when its T-lattice vertex is a corner of a non-empty cell or lies on
// one's boundary (a T-junction on its face or edge); boundary copies as the vertex they copy. These are the
// control points sec. 4 gives the heavy weight. cells: one flag per cell of basis.lattice.
std::vector<std::uint8_t> controlPointsOfCells(const TSplineBasis& basis, const std::vector<std::uint8_t>& cells);

// Sec. 3.2.2: the T-junctions, vertices (ids into lattice.vertices, ascending) where a line of the T-lattice
// ends: along some axis direction that stays inside the domain no lattice edge leaves the vertex (a corner of
// finer cells on the face or edge of a coarser one). Found from the cells around each vertex.
std::vector<int> tJunctionVertices(const TLattice& lattice);

// The parameters of vertex v (its fine coordinates through knotValue).
Eigen::Vector3d vertexParameters(const TLattice& lattice, int vertex);

// The leaf cell holding parameter t (half-open voxels; t_a = 1 in the last), -1 outside [0,1]^3 or not finite.
int cellAtParameters(const TLattice& lattice, const Eigen::Vector3d& t);

// The cell of `volume` holding rest point x (its frozen parameters, as subdivide_cells's "at" finds it), or -1
// when x is outside the volume.
int cellAtRestPoint(const TSplineVolume& volume, const Eigen::Vector3d& x);

// The vertex at fine coordinates p (an id into lattice.vertices), or -1 when no cell has a corner there.
int vertexAt(const TLattice& lattice, const std::array<int, 3>& p);

// The control point a T-lattice vertex anchors (not a boundary copy): where the window draws the vertex.
inline int vertexAnchor(const TSplineBasis& basis, int vertex) { return basis.anchorOfVertex[static_cast<size_t>(vertex)][0]; }

// Whether the vertex anchor `anchor` (or boundary copy) hangs on a vertex of the domain's boundary: the
// T-lattice's outer faces (what "outer only" keeps).
bool anchorOnDomainBoundary(const TSplineBasis& basis, int anchor);

// Fig. 9: the T-lattice's edges (cell edges split at T-junctions) between the control points of their vertices
// (vertexAnchor), as the control net the window draws: straight lines that follow the points as they move.
std::vector<std::array<int, 2>> tlatticeNetEdges(const TSplineBasis& basis);

// Fig. 11: cell c's 12 edges as segments (2 x 3 each) between the control points (#anchors x 3) of its corners.
// Empty for a cell id out of range.
std::vector<Positions> cellEdgeSegments(const TSplineBasis& basis, int cell, const Positions& controlPoints);

// The session's frozen T-spline as the window draws it (Fig. 10). All empty when the cage is not a T-spline.
struct TSplineCageView {
    const TSplineVolume* volume = nullptr;   // the cage's volume (owned by the session)
    std::vector<std::uint8_t> cells;         // nonEmptyTSplineCells of the mesh when the cage was frozen
    // Drawn and picked: controlPointsOfCells less the boundary copies. The copies are our construction (the
    // clamped boundary, tspline_volume.h), not the paper's: the session keeps them pinned (a chunked volume
    // keeps its outer surface), and drawn they doubled every boundary point just outside the T-lattice.
    std::vector<std::uint8_t> controlPoints;
};
// restPositions(): the mesh the cage was frozen around, the mesh sec. 4's weights were set from by
// setup_tspline and subdivide_cells (which freeze right after). Costs #V affine maps and #anchors x 8 look-ups.
TSplineCageView tsplineCageView(const Session& session);

}  // namespace sculpt::core
