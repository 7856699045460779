// What self_intersection.cpp (the index) and self_intersection_query.cpp (its queries) share: the BVH's
// sizes and the triangle box and corner helpers. Internal to src/core/injectivity.
#pragma once

#include <Eigen/Geometry>

#include "core/injectivity/self_intersection.h"
#include "core/injectivity/triangle_pair.h"

namespace sculpt::core::self_intersection_detail {
constexpr int kLeafSize = 8;
// The smallest patch (hierarchy node) tried as a whole by patchEmbedded; below it, the stars and the pair tests.
constexpr int kPatchMinimum = 32;
// The widest normal cone tried (radians, about 86 degrees).
constexpr double kPatchConeLimit = 1.5;

inline Eigen::AlignedBox3d triangleBox(const Positions& positions, const Triangles& triangles, int t) {
    Eigen::AlignedBox3d box(positions.row(triangles(t, 0)).transpose());
    box.extend(positions.row(triangles(t, 1)).transpose());
    box.extend(positions.row(triangles(t, 2)).transpose());
    return box;
}

// Closed boxes: touching counts (the exact test decides).
inline bool overlaps(const Eigen::AlignedBox3d& a, const Eigen::AlignedBox3d& b) {
    return (a.min().array() <= b.max().array()).all() && (b.min().array() <= a.max().array()).all();
}

template <typename PointOf>
TriangleCorners corners(const Triangles& triangles, int t, PointOf pointOf) {
    TriangleCorners c;
    for (int k = 0; k < 3; ++k) {
        c.vertex[k] = triangles(t, k);
        c.point[k] = pointOf(c.vertex[k]);
    }
    return c;
}

}  // namespace sculpt::core::self_intersection_detail
