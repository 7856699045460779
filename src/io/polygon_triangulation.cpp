// Polygon triangulation, the cheap part: Newell normal and the convex fan. Everything else goes to the
// constrained Delaunay triangulation in polygon_triangulation_cdt.cpp (CGAL, compiled on its own).
//
// Newell's method: N = sum_i q_i x q_(i+1) over the corners q_i (Tampieri, Graphics Gems III, 1992); exact
// for planar polygons (twice the area times the unit normal) and the least-squares plane normal direction
// for non-planar ones. Convexity: every turn to the same side and the edge direction reversing at most
// twice along each axis of the plane (Schorn & Fisher, "Testing the convexity of a polygon", Graphics
// Gems IV, 1994), so a pentagram, which turns left at every corner too, is not taken for convex.
#include "io/polygon_triangulation.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>

#include "io/polygon_triangulation_detail.h"

namespace sculpt::io {

namespace detail {

bool UnitCorners::set(const Eigen::Ref<const Positions>& corners) {
    corners_ = &corners;
    double largest = 0.0;
    for (Eigen::Index i = 0; i < corners.rows(); ++i)
        for (int k = 0; k < 3; ++k) {
            const double c = corners(i, k);
            if (!std::isfinite(c)) return false;
            largest = std::max(largest, std::abs(c));
        }
    int exponent = 0;
    if (largest > 0.0) std::frexp(largest, &exponent);  // largest = f 2^exponent, f in [0.5, 1)
    low_ = std::ldexp(1.0, -exponent / 2);
    high_ = std::ldexp(1.0, -(exponent - exponent / 2));
    origin_ = Eigen::Vector3d::Zero();
    if (corners.rows() > 0) origin_ = (*this)[0];
    return true;
}

Eigen::Vector3d newellNormal(const UnitCorners& unit) {
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();
    const Eigen::Index n = unit.size();
    Eigen::Vector3d a = unit[0];
    for (Eigen::Index i = 0; i < n; ++i) {
        const Eigen::Vector3d b = unit[(i + 1) % n];
        normal += a.cross(b);
        a = b;
    }
    return normal;
}

}  // namespace detail

namespace {

// True when the polygon, seen along normal, is strictly convex and winds once, and every fan triangle
// (0, i, i+1) has positive area about normal as computed: then the fan covers it exactly.
bool isStrictlyConvex(const detail::UnitCorners& unit, const Eigen::Vector3d& normal) {
    const Eigen::Index n = unit.size();
    const Eigen::Vector3d axis = normal.normalized();
    // Axes (u, v) of the plane, for the direction-reversal count.
    Eigen::Index least = 0;
    axis.cwiseAbs().minCoeff(&least);
    const Eigen::Vector3d u = axis.cross(Eigen::Vector3d::Unit(least));
    const Eigen::Vector3d v = axis.cross(u);
    Eigen::Vector3d previous = unit[0] - unit[n - 1];
    double previousU = previous.dot(u), previousV = previous.dot(v);
    int reversalsU = 0, reversalsV = 0;
    for (Eigen::Index i = 0; i < n; ++i) {
        const Eigen::Vector3d next = unit[(i + 1) % n] - unit[i];
        if (!(previous.cross(next).dot(axis) > 0.0)) return false;  // reflex, collinear or repeated corner
        const double nextU = next.dot(u), nextV = next.dot(v);
        // A sign change of the edge direction along u (or v); zero components count with the last non-zero.
        if (nextU != 0.0) {
            if (previousU != 0.0 && (nextU > 0.0) != (previousU > 0.0)) ++reversalsU;
            previousU = nextU;
        }
        if (nextV != 0.0) {
            if (previousV != 0.0 && (nextV > 0.0) != (previousV > 0.0)) ++reversalsV;
            previousV = nextV;
        }
        previous = next;
    }
    // note: with every turn to the left the turning angles add up to 2 pi k; a quadrilateral's four turns,
    // each below pi, cannot reach 4 pi, so only larger polygons can wind more than once.
    if (n > 4 && (reversalsU > 2 || reversalsV > 2)) return false;
    const Eigen::Vector3d first = unit[0];
    Eigen::Vector3d a = unit[1] - first;
    for (Eigen::Index i = 1; i + 1 < n; ++i) {
        const Eigen::Vector3d b = unit[i + 1] - first;
        if (!(a.cross(b).dot(axis) > 0.0)) return false;
        a = b;
    }
    return true;
}

// The common case of meshes with polygons, on the coordinates as they are (no rescaling: quads of
// ordinary size only, so no product can overflow or lose its sign to underflow): true when the fan
// (0, 1, 2), (0, 2, 3) covers the quad exactly, i.e. it turns left at every corner about its Newell normal,
// which for a quadrilateral is the cross product of its diagonals. Anything else takes the general path.
bool isConvexQuad(const Eigen::Ref<const Positions>& corners) {
    const double largest = corners.cwiseAbs().maxCoeff();  // NaN compares false below
    if (!(largest >= 1e-100 && largest <= 1e100)) return false;
    const Eigen::Vector3d p[4] = {corners.row(0).transpose(), corners.row(1).transpose(), corners.row(2).transpose(),
                                  corners.row(3).transpose()};
    const Eigen::Vector3d normal = (p[2] - p[0]).cross(p[3] - p[1]);
    for (int i = 0; i < 4; ++i) {
        const Eigen::Vector3d in = p[i] - p[(i + 3) % 4], out = p[(i + 1) % 4] - p[i];
        if (!(in.cross(out).dot(normal) > 0.0)) return false;
    }
    return (p[1] - p[0]).cross(p[2] - p[0]).dot(normal) > 0.0 && (p[2] - p[0]).cross(p[3] - p[0]).dot(normal) > 0.0;
}

}  // namespace

Eigen::Vector3d polygonNormal(const Eigen::Ref<const Positions>& corners) {
    detail::UnitCorners unit;
    if (corners.rows() < 3 || !unit.set(corners)) return Eigen::Vector3d::Zero();
    const Eigen::Vector3d normal = detail::newellNormal(unit);
    return normal.allFinite() ? normal : Eigen::Vector3d::Zero();
}

Status triangulatePolygon(const Eigen::Ref<const Positions>& corners, std::vector<CornerTriangle>& triangles) {
    triangles.clear();
    const Eigen::Index n = corners.rows();
    if (n < 3) return Status::error("a polygon needs at least 3 corners");
    if (n == 3) {
        triangles.push_back({0, 1, 2});
        return Status::success();
    }
    if (n == 4 && isConvexQuad(corners)) {
        triangles.insert(triangles.end(), {CornerTriangle{0, 1, 2}, CornerTriangle{0, 2, 3}});
        return Status::success();
    }
    if (n > static_cast<Eigen::Index>(std::numeric_limits<int>::max()))
        return Status::error("the polygon has too many corners");
    detail::UnitCorners unit;
    if (!unit.set(corners)) return Status::error("the polygon has a non-finite corner");
    const Eigen::Vector3d normal = detail::newellNormal(unit);
    if (!normal.allFinite() || normal.squaredNorm() == 0.0)
        return Status::error("the polygon has zero area (its corners are on one line)");
    if (isStrictlyConvex(unit, normal)) {
        triangles.reserve(static_cast<size_t>(n - 2));
        for (int i = 1; i + 1 < n; ++i) triangles.push_back({0, i, i + 1});
        return Status::success();
    }
    return detail::triangulateUnitPolygonCdt(unit, normal, triangles);
}

Status triangulatePolygonCdt(const Eigen::Ref<const Positions>& corners, const Eigen::Vector3d& normal,
                             std::vector<CornerTriangle>& triangles) {
    triangles.clear();
    if (corners.rows() < 3) return Status::error("a polygon needs at least 3 corners");
    detail::UnitCorners unit;
    if (!unit.set(corners)) return Status::error("the polygon has a non-finite corner");
    if (!normal.allFinite() || normal.squaredNorm() == 0.0)
        return Status::error("the polygon has zero area (its corners are on one line)");
    return detail::triangulateUnitPolygonCdt(unit, normal, triangles);
}

}  // namespace sculpt::io
