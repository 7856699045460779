// Internal to polygon_triangulation*.cpp: the steps both of its files share.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "core/mesh_types.h"
#include "core/status.h"
#include "io/polygon_triangulation.h"

namespace sculpt::io::detail {

// unit = corners scaled by a power of two (largest coordinate below 1) and moved so corner 0 is at the
// origin. False (unit unspecified) when a coordinate is not finite.
bool unitCorners(const Eigen::Ref<const Positions>& corners, Positions& unit);

// Newell normal of unit corners (not normalised).
Eigen::Vector3d newellNormal(const Positions& unit);

// The constrained Delaunay path of triangulatePolygonCdt on unit corners; normal finite and non-zero.
Status triangulateUnitPolygonCdt(const Positions& unit, const Eigen::Vector3d& normal,
                                 std::vector<CornerTriangle>& triangles);

}  // namespace sculpt::io::detail
