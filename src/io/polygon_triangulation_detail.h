// Internal to polygon_triangulation*.cpp: the steps both of its files share.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "core/mesh_types.h"
#include "core/status.h"
#include "io/polygon_triangulation.h"

namespace sculpt::io::detail {

// The corners of a polygon scaled by a power of two (so the largest coordinate is below 1) and moved so
// corner 0 is at the origin: cross products of 1e300-sized coordinates would overflow and those of
// 1e-300-sized ones underflow to zero. Computed on the fly (no copy: most polygons are small).
class UnitCorners {
public:
    // False when a coordinate is not finite. corners must outlive this object.
    bool set(const Eigen::Ref<const Positions>& corners);
    Eigen::Index size() const { return corners_->rows(); }
    Eigen::Vector3d operator[](Eigen::Index i) const {
        // note: two power-of-two factors, each representable, so the scaling is exact (unless a result
        // is subnormal) even where 2^-exponent alone would overflow.
        return corners_->row(i).transpose() * low_ * high_ - origin_;
    }

private:
    const Eigen::Ref<const Positions>* corners_ = nullptr;
    double low_ = 1.0, high_ = 1.0;
    Eigen::Vector3d origin_ = Eigen::Vector3d::Zero();
};

// Newell normal of the unit corners (not normalised; zero or non-finite for a degenerate polygon).
Eigen::Vector3d newellNormal(const UnitCorners& unit);

// The constrained Delaunay path of triangulatePolygonCdt on unit corners; normal finite and non-zero.
Status triangulateUnitPolygonCdt(const UnitCorners& unit, const Eigen::Vector3d& normal,
                                 std::vector<CornerTriangle>& triangles);

}  // namespace sculpt::io::detail
