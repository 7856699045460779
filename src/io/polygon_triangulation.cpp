// Polygon triangulation, the cheap part: Newell normal and the convex fan. Everything else goes to the
// constrained Delaunay triangulation in polygon_triangulation_cdt.cpp (CGAL, compiled on its own).
//
// Newell's method: N = sum_i q_i x q_(i+1) over the corners q_i (Tampieri, Graphics Gems III, 1992); exact
// for planar polygons (twice the area times the unit normal) and the least-squares plane normal direction
// for non-planar ones.
#include "io/polygon_triangulation.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>

#include "io/polygon_triangulation_detail.h"

namespace sculpt::io {

namespace detail {

bool unitCorners(const Eigen::Ref<const Positions>& corners, Positions& unit) {
    // note: scaled by a power of two (exact, unless a coordinate becomes subnormal) so the largest coordinate
    // is below 1, then moved so corner 0 is the origin: cross products of 1e300-sized coordinates would
    // overflow and those of 1e-300-sized ones underflow to zero.
    double largest = 0.0;
    for (Eigen::Index i = 0; i < corners.rows(); ++i)
        for (int k = 0; k < 3; ++k) {
            const double c = corners(i, k);
            if (!std::isfinite(c)) return false;
            largest = std::max(largest, std::abs(c));
        }
    int exponent = 0;
    if (largest > 0.0) std::frexp(largest, &exponent);
    unit.resize(corners.rows(), 3);
    for (Eigen::Index i = 0; i < corners.rows(); ++i)
        for (int k = 0; k < 3; ++k) unit(i, k) = std::ldexp(corners(i, k), -exponent);
    const Eigen::RowVector3d origin = unit.row(0);
    unit.rowwise() -= origin;
    return true;
}

Eigen::Vector3d newellNormal(const Positions& unit) {
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();
    const Eigen::Index n = unit.rows();
    for (Eigen::Index i = 0; i < n; ++i) {
        const Eigen::Vector3d a = unit.row(i).transpose();
        const Eigen::Vector3d b = unit.row((i + 1) % n).transpose();
        normal += a.cross(b);
    }
    return normal;
}

}  // namespace detail

namespace {

// True when the polygon, seen along normal, is strictly convex and winds once, and every fan triangle
// (0, i, i+1) has positive area about normal as computed: then the fan covers it exactly.
bool isStrictlyConvex(const Positions& unit, const Eigen::Vector3d& normal) {
    const Eigen::Index n = unit.rows();
    const Eigen::Vector3d axis = normal.normalized();
    double turning = 0.0;
    for (Eigen::Index i = 0; i < n; ++i) {
        const Eigen::Vector3d previous = unit.row(i).transpose() - unit.row((i + n - 1) % n).transpose();
        const Eigen::Vector3d next = unit.row((i + 1) % n).transpose() - unit.row(i).transpose();
        const double turn = previous.cross(next).dot(axis);
        if (!(turn > 0.0)) return false;  // reflex, collinear or repeated corner
        const double along = previous.dot(next) - previous.dot(axis) * next.dot(axis);
        turning += std::atan2(turn, along);  // in (0, pi)
    }
    // The turning angles of a closed polygon add up to 2 pi k; k = 1 is a convex polygon, k > 1 a star
    // (a pentagram turns left at every corner too).
    constexpr double kPi = 3.14159265358979323846;
    if (turning > 3.0 * kPi) return false;
    const Eigen::Vector3d first = unit.row(0).transpose();
    for (Eigen::Index i = 1; i + 1 < n; ++i) {
        const Eigen::Vector3d a = unit.row(i).transpose() - first;
        const Eigen::Vector3d b = unit.row(i + 1).transpose() - first;
        if (!(a.cross(b).dot(axis) > 0.0)) return false;
    }
    return true;
}

}  // namespace

Eigen::Vector3d polygonNormal(const Eigen::Ref<const Positions>& corners) {
    Positions unit;
    if (corners.rows() < 3 || !detail::unitCorners(corners, unit)) return Eigen::Vector3d::Zero();
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
    Positions unit;
    if (!detail::unitCorners(corners, unit)) return Status::error("the polygon has a non-finite corner");
    const Eigen::Vector3d normal = detail::newellNormal(unit);
    if (!normal.allFinite() || normal.squaredNorm() == 0.0)
        return Status::error("the polygon has zero area (its corners are on one line)");
    if (n > static_cast<Eigen::Index>(std::numeric_limits<int>::max()))
        return Status::error("the polygon has too many corners");
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
    Positions unit;
    if (!detail::unitCorners(corners, unit)) return Status::error("the polygon has a non-finite corner");
    if (!normal.allFinite() || normal.squaredNorm() == 0.0)
        return Status::error("the polygon has zero area (its corners are on one line)");
    return detail::triangulateUnitPolygonCdt(unit, normal, triangles);
}

}  // namespace sculpt::io
