// Exact intersection test of two triangles of a mesh, counting only what they do not share; and the nearest
// point of a triangle, on the same library.
//
// Two triangles of one mesh that share an edge or a vertex always touch there; that is not a
// self-intersection. What counts is any other common point: a shared-edge pair that folds flat onto itself,
// a shared-vertex pair where one triangle's opposite edge pierces the other, or any common point of two
// triangles that share nothing. The predicates are CGAL's exact ones (Exact_predicates_inexact_constructions
// kernel: double inputs, exact signs), the same case analysis as CGAL's Polygon_mesh_processing
// self_intersections (do_faces_intersect), so a touching or coplanar configuration is decided exactly, not
// within a tolerance.
#pragma once

#include <array>

#include <Eigen/Core>

namespace sculpt::core {

// One triangle: its corner positions and the mesh's vertex ids of those corners (ids, and equal positions, decide
// what is shared; -1: no id).
struct TriangleCorners {
    std::array<Eigen::Vector3d, 3> point;
    std::array<int, 3> vertex{-1, -1, -1};
};

// True if a and b have a common point other than their shared vertices/edge: shared by vertex id, or by exactly
// the same position (a triangle soup's neighbours, a seam's split vertices: they touch as neighbours do). A degenerate
// triangle (collinear corners) is tested as its longest segment, a triangle collapsed to a point as that
// point; a degenerate triangle that shares a vertex with the other is not counted (it touches the other
// there, and has no interior to cross it with). The same three ids twice (a duplicated face) is not counted.
// Never throws; coordinates must be finite (the engine never produces others).
bool trianglesIntersect(const TriangleCorners& a, const TriangleCorners& b);

// True if a and b, not intersecting, still come within `tolerance` (world units, >= 0) of each other apart from what
// they share (a vertex shared by id or by position, as trianglesIntersect): a corner of one within `tolerance` of
// the other's face (a sliver folded over its neighbour, a vertex hovering on a face), or two edges without a common
// corner within `tolerance` of each other. Such a pair touches to within a file's precision: any move may cross it.
// The distances are CGAL's (point-triangle, segment-segment) in doubles; a triangle with no area (its corners' cross product
// zero in doubles) is never within (it is counted apart: triangleDegenerate). Coordinates must be finite.
bool trianglesWithin(const TriangleCorners& a, const TriangleCorners& b, double tolerance);

// True if the triangle has no area: its corners are collinear or coincide (CGAL's exact collinear predicate on
// the double coordinates, no tolerance). A mesh file's zero-area facets are such triangles: the load counts them
// apart from crossings (Session::meshAsSet().degenerateTriangles).
bool triangleDegenerate(const TriangleCorners& t);

// The point of the triangle (a, b, c) nearest p, as its barycentric weights (w_a, w_b, w_c), each in [0, 1],
// summing to 1: CGAL's projection of a point on a triangle (Kernel::Construct_projected_point_3, the corners', edges'
// and face's Voronoi regions), in doubles; the weights are the nearest point's barycentric coordinates in the
// triangle's plane, clamped to the triangle. Not finite (NaN) for a triangle with no area in doubles (collinear or
// coinciding corners), which has no such weights. Coordinates must be finite.
Eigen::Vector3d nearestOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c);

}  // namespace sculpt::core
