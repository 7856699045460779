// Refinement where the surface stretches (Coquillart 1990, section 3.4, after Griessmair and Purgathofer
// 1989): a deformation maps each flat triangle of the rest mesh onto a curved patch, but the mesh shows the
// flat triangle through the three mapped corners. Where the two differ by more than a tolerance, triangles
// are split at the midpoints of their edges *in rest space*, and each new vertex is put where the
// deformation takes that rest point, so a coarse mesh follows a sharp bump.
//
// The pure geometry lives here, testable without a Session: which triangles stray from their image
// (triangleDeviation), how to split them so the mesh stays conforming (longest-edge bisection, Rivara 1984:
// every triangle that shares the split edge is halved too, so there is never a T-junction), and the
// combinatorial replay of a list of splits (applyEdgeSplits), which the Session's undo/redo, recordings and
// the OBJ writer share. The map from rest space to the current shape is given as a callable.
#pragma once

#include <cassert>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/mesh_types.h"
#include "core/status.h"

namespace sculpt::core {

// One edge split at its midpoint: the edge between vertices a and b (an edge of the mesh when the split is
// made) gets a new vertex, numbered next (the vertex count at that moment). Every triangle that has the edge
// is halved (TriangleHalving).
struct EdgeSplit {
    int a = -1, b = -1;
};

// How one triangle was halved by a split. The split edge runs from local corner `corner` to corner
// (corner + 1) % 3 of triangle `triangle`; the triangle keeps its half at `corner` (its corner (corner + 1) % 3
// becomes the new vertex) and the other half is appended as triangle `appended`, a copy whose corner `corner`
// is the new vertex. Both halves keep the triangle's orientation.
struct TriangleHalving {
    int triangle = -1;
    int corner = 0;
    int appended = -1;
};

// What a refinement did, as history keeps it: the splits in order (enough to redo it and to record it) and,
// once applied, how each triangle was halved (enough to undo it: restore the halved corners, drop the
// appended triangles and the new vertices).
struct RefinementRecord {
    double tolerance = 0.0;                 // as asked (fraction of the bounding-box diagonal); 0: not recorded
    std::vector<EdgeSplit> splits;
    std::vector<TriangleHalving> halvings;  // filled when applied (applyEdgeSplits); not part of a recording
    bool empty() const { return splits.empty(); }
};

struct RefinementOptions {
    double tolerance = 0.002;    // the largest deviation a triangle may keep, as a fraction of the diagonal of
                                 // the current shape's bounding box; finite and > 0
    int maxRounds = 24;          // rounds of bisection (each halves every triangle still over the tolerance
                                 // once); in [1, 64]
    int maxVertices = 2000000;   // stop splitting when the mesh has this many vertices; >= 1
    double shortestEdge = 0.0;   // no edge shorter than this in rest space (world units) is split; 0: tolerance
                                 // times the rest bounding-box diagonal; finite and >= 0
};

// The session's refinement setting: the options, and whether every applied drag or control-point edit is
// followed by a refinement with them, in the same history entry (one Ctrl+Z takes back both).
struct RefinementSettings {
    bool automatic = false;
    RefinementOptions options;
    // A brush stroke whose whole pull the mesh's triangles would stop (long flat triangles cutting through each
    // other where the field bends them) splits them under the pull and goes on (Stroke::applyBrushPulls; the
    // splits are part of its history entry). Off: such a stroke stops short and the mesh keeps its triangles.
    bool underBrush = true;
};

// Checks ranges and finiteness; the message names the offending field.
Status validateRefinementOptions(const RefinementOptions& options);

// Maps a rest-space point to where the current deformation puts it. Called from several threads at once.
using RestImage = std::function<Eigen::Vector3d(const Eigen::Vector3d&)>;

// How far the image of the rest triangle (restA, restB, restC) strays from the flat triangle through its mapped
// corners (currentA, currentB, currentC), in world units: an estimate of the largest distance between the image
// of a rest point and the point with the same barycentric coordinates on the flat triangle.
// note: for a quadratic patch the error is e(b) = sum_{i<j} b_i b_j c_ij, whose largest value over the triangle
// is at most 1/3 max|c_ij|, while the edge midpoints show |c_ij| / 4: 4/3 of the midpoints' worst bounds it.
// The estimate applies that bound to the four halves of the triangle's 1-to-4 split, each against the flat
// triangle through its own corner images, plus the error at those corners (16 images: every edge at 1/4, 1/2
// and 3/4, the inner triangle's edge midpoints, the four centroids): at half the size the quadratic model is four
// times closer, so the cubic B-spline pieces a large triangle spans are not missed.
double triangleDeviation(const Eigen::Vector3d& restA, const Eigen::Vector3d& restB, const Eigen::Vector3d& restC,
                         const Eigen::Vector3d& currentA, const Eigen::Vector3d& currentB, const Eigen::Vector3d& currentC,
                         const RestImage& image);

// Applies `splits` in order to `triangles` (#T x 3 ids into vertexCount vertices); split k's new vertex is
// vertexCount + k. Every triangle having the edge {a, b} at that moment is halved, in ascending triangle id
// (so the result depends only on the triangles and the splits); triangles whose corners repeat a vertex id are
// never halved. halvings (may be null) receives each halving in order. Fails, leaving triangles untouched, on a
// split whose vertices are out of range or that names no edge of the mesh at that point.
Status applyEdgeSplits(Triangles& triangles, int vertexCount, const std::vector<EdgeSplit>& splits,
                       std::vector<TriangleHalving>* halvings = nullptr);

// Undoes applyEdgeSplits: restores the halved corners (last halving first) and drops the appended triangles.
// triangles must be what applyEdgeSplits produced with these halvings (asserted).
void revertEdgeSplits(Triangles& triangles, const std::vector<TriangleHalving>& halvings);

// Appends a row per split to `rows` (rest positions, or any per-vertex attribute: a row-major Eigen matrix with
// one row per vertex): the midpoint of its edge's two rows (rows added by earlier splits count). Ids out of range
// are a programmer mistake (asserted).
template <typename Rows>
void appendSplitMidpoints(Rows& rows, const std::vector<EdgeSplit>& splits) {
    using Scalar = typename Rows::Scalar;
    const Eigen::Index first = rows.rows();
    rows.conservativeResize(first + static_cast<Eigen::Index>(splits.size()), Eigen::NoChange);
    for (size_t k = 0; k < splits.size(); ++k) {
        const Eigen::Index row = first + static_cast<Eigen::Index>(k);
        assert(splits[k].a >= 0 && splits[k].a < row && splits[k].b >= 0 && splits[k].b < row);
        rows.row(row) = Scalar(0.5) * (rows.row(splits[k].a) + rows.row(splits[k].b));
    }
}

struct RefinementResult {
    std::vector<EdgeSplit> splits;  // in order (applyEdgeSplits reproduces `triangles` from them)
    Positions rest, current;        // the refined mesh: #V' x 3, the input's rows first
    Triangles triangles;            // #T' x 3, the input's rows first (halved ones changed in place)
    bool converged = false;         // every triangle is within the tolerance
    std::string stopped;            // otherwise why it stopped: "max rounds", "max vertices", or "smallest size"
                                    // (the triangles still over it are no longer than tolerance times the rest
                                    // diagonal: the deformation jumps there)
    int rounds = 0;                 // rounds of bisection done
    double toleranceWorld = 0.0;    // the tolerance in world units
    double worstBefore = 0.0;       // the largest triangleDeviation before and after, world units
    double worstAfter = 0.0;
    int trianglesOver = 0;          // triangles still over the tolerance afterwards
};

// Seams: vertices at exactly the same rest point (a triangle soup, as CAD exports and STL give, or a mesh split
// at seams for its normals or texture). For each vertex of `rest` (#V x 3) the smallest id of a vertex at the
// same point (itself where none is); empty when no two vertices share a point. -0 and +0 are one point.
// `among` (empty: every vertex) limits the points looked at to those of the vertices listed: a vertex elsewhere
// is its own (one lookup per vertex, not a table of every point: 1M vertices cost 0.85 s that way).
// Refinement plans on the mesh welded by this map (each triangle's corners replaced by their first copies), so
// that the two sides of a seam are one surface to it, and splitsOnSeamCopies then splits every copy of each
// edge: split on one side only, the other side's straight edge parts from the bent one, and the two cut through
// each other's neighbours (CGAL's boeing.off stopped a one-radius brush pull at 4.7% that way).
// Welding on load (io/mesh_weld.h) makes the same copies one vertex.
std::vector<int> seamCopiesOf(const Positions& rest, const std::vector<int>& among = {});

// The mesh `triangles` (#T x 3 ids into vertexCount vertices) with each corner replaced by canonical[corner]
// (seamCopiesOf; empty: unchanged).
Triangles weldedAtSeams(const Triangles& triangles, const std::vector<int>& canonical);

// The splits of `triangles` that make the splits `welded` of weldedAtSeams(triangles, canonical) on every copy
// of each welded edge: for welded split k of {A, B} (new vertex vertexCount + k there), every edge of the
// mesh, as earlier output splits left it, whose corners are copies of A and B is split, each split's new vertex
// a copy of vertexCount + k (at the same rest midpoint, so the copies move as one). Without seams (canonical
// empty) the result is `welded`. Ids out of range are a programmer mistake (asserted).
std::vector<EdgeSplit> splitsOnSeamCopies(const Triangles& triangles, int vertexCount, const std::vector<int>& canonical,
                                          const std::vector<EdgeSplit>& welded);

// Refines the mesh (rest positions, current positions = image(rest) at the vertices, triangles) until every
// triangle's triangleDeviation is within options.tolerance times the diagonal of the current bounding box, or
// a limit of `options` is reached (result.stopped says which). Each round bisects every triangle over the
// tolerance once by its longest edge in rest space, along its longest-edge propagation path (Rivara's
// LEPP bisection: the neighbour across the edge is bisected first where the edge is not its own longest), so
// the mesh stays conforming, keeps its orientation, and its triangles do not degenerate into slivers. New
// vertices get rest position = the midpoint of the rest edge and current position = image(that midpoint).
// A triangle whose rest-space edges are all shorter than options.shortestEdge (0: options.tolerance times the rest
// bounding-box diagonal) is not split (only a jump in the image keeps one that small over the tolerance: "smallest size").
// Triangles with a repeated vertex id are left as they are. Bad options or arrays of different sizes are
// errors (result untouched). Cost: about 11.5 image evaluations per triangle evaluated (edge samples are shared),
// in parallel.
Status refineMesh(const Positions& rest, const Positions& current, const Triangles& triangles, const RestImage& image,
                  const RefinementOptions& options, RefinementResult& result);

}  // namespace sculpt::core
