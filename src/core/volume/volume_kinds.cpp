// The positioning command for a lattice of any kind (volume_kinds.h): each kind places itself (Volume::placed).
#include "core/volume/volume_kinds.h"

#include <cmath>

namespace sculpt::core {

Status Volume::placed(const Eigen::Vector3d&, const Eigen::Vector3d&, double, std::shared_ptr<const Volume>&) const {
    return Status::error("placing a " + kindName() + " lattice is not supported");
}

Status placementSimilarity(const Eigen::AlignedBox3d& bounds, const Eigen::Vector3d& point, const Eigen::Vector3d& normal, double size,
                           PlacementSimilarity& out) {
    if (!point.allFinite() || !normal.allFinite() || !(normal.norm() > 0.0))
        return Status::error("placing a lattice needs a finite point and a non-zero normal");
    if (!(size > 0.0) || !std::isfinite(size)) return Status::error("placing a lattice needs a size that is finite and > 0");
    out.rotation = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), normal.normalized()).toRotationMatrix();
    out.from = bounds.center();
    out.to = point;
    out.scale = size / bounds.diagonal().norm();
    return Status::success();
}

Status placeVolume(const Volume& tool, const Eigen::Vector3d& point, const Eigen::Vector3d& normal, double size,
                   std::shared_ptr<const Volume>& out) {
    return tool.placed(point, normal, size, out);
}

}  // namespace sculpt::core
