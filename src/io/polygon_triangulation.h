// Triangulation of one polygon (an OBJ face) for the engine, the renderer and picking: triangles that cover
// exactly the polygon, all facing the same way as the polygon, using only its corners (no new vertices).
//
// A polygon in 3D need not be planar. It is triangulated in the plane of its Newell normal (Newell's method,
// see Sutherland, Sproull & Schumacker 1974, "A characterization of ten hidden-surface algorithms", and
// Tampieri, "Newell's method for computing the plane equation of a polygon", Graphics Gems III, 1992): the
// corners are projected onto that plane, and the triangles of the projected polygon are used with the 3D
// corners. Every triangle's normal then points along the Newell normal, and the projected triangle areas
// add up to the projected polygon's area.
//
// Convex polygons (in that projection) get the fan (c0, ci, ci+1), so a convex face is split exactly as
// before; any other polygon goes to a constrained Delaunay triangulation (CGAL, polygon_triangulation_cdt.cpp),
// triangulating polygons being outside this project's own field.
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

#include "core/mesh_types.h"
#include "core/status.h"

namespace sculpt::io {

// One triangle as three indices into the polygon's corner list (0 .. N-1), counter-clockwise seen from the
// side the Newell normal points to.
using CornerTriangle = std::array<int, 3>;

// The Newell normal of corners (N x 3, N >= 3, in order), not normalised: its length is twice the area of
// the polygon projected onto the plane it is normal to. Computed on a rescaled, recentred copy, so huge and
// tiny coordinates neither overflow nor underflow; the result is scaled to unit-size coordinates (only its
// direction and whether it is zero are meaningful). Zero for a polygon of zero area (all corners on one
// line or point, or parts whose areas cancel) and for non-finite input.
Eigen::Vector3d polygonNormal(const Eigen::Ref<const Positions>& corners);

// Triangulates the polygon with corners (N x 3, N >= 3, in order, any winding). On success, triangles holds
// the triangles (N - 2 of them for a simple polygon; fewer where corners coincide), each counter-clockwise
// about polygonNormal(corners), together covering the polygon's projection exactly once. A triangle (N = 3)
// is returned as it is, even when degenerate.
//
// Fails (triangles empty, an error saying why, e.g. "the polygon crosses itself") when there is no such
// triangulation with the polygon's own corners: non-finite coordinates, zero area (collinear or coincident
// corners), edges that cross, or parts that overlap or wind the other way. Callers then fall back to a fan
// and warn. Never throws except std::bad_alloc; O(N) for convex polygons, O(N log N) expected otherwise.
Status triangulatePolygon(const Eigen::Ref<const Positions>& corners, std::vector<CornerTriangle>& triangles);

// The general path of triangulatePolygon, for any polygon (also convex ones; exposed for tests): the corners
// projected to 2D along normal (as returned by polygonNormal, non-zero) and triangulated by a constrained
// Delaunay triangulation (CGAL) of the polygon's edges; the triangles where the polygon's winding number is 1
// are returned. Same contract and failures as triangulatePolygon.
Status triangulatePolygonCdt(const Eigen::Ref<const Positions>& corners, const Eigen::Vector3d& normal,
                             std::vector<CornerTriangle>& triangles);

}  // namespace sculpt::io
