#include "core/volume_kinds.h"

#include <cmath>

#include <Eigen/Geometry>

#include "core/composite_volume.h"
#include "core/lattice_net.h"
#include "core/tspline_volume.h"

namespace sculpt::core {

Status placeVolume(const Volume& tool, const Eigen::Vector3d& point, const Eigen::Vector3d& normal, double size,
                   std::shared_ptr<const Volume>& out) {
    if (const LatticeNet* net = tool.tensorNet()) {
        LatticeNet placed;
        if (Status s = placeLatticeNet(*net, point, normal, size, placed); !s) return s;
        out = std::make_shared<const LatticeNet>(std::move(placed));
        return Status::success();
    }
    if (const auto* composite = dynamic_cast<const CompositeVolume*>(&tool)) {
        // Each part by the composite's similarity: the part's own placement (its centre to the image of its
        // centre, its diagonal scaled alike) is exactly that similarity restricted to it.
        if (!point.allFinite() || !normal.allFinite() || !(normal.norm() > 0.0))
            return Status::error("placing a lattice needs a finite point and a non-zero normal");
        if (!(size > 0.0) || !std::isfinite(size)) return Status::error("placing a lattice needs a size that is finite and > 0");
        const Eigen::Matrix3d rotation = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), normal.normalized()).toRotationMatrix();
        const Eigen::Vector3d centre = composite->restBounds().center();
        const double scale = size / composite->restBounds().diagonal().norm();
        std::vector<std::shared_ptr<const LatticeNet>> parts;
        for (const auto& block : composite->blocks()) {
            LatticeNet part;
            const Eigen::Vector3d at = point + scale * (rotation * (block->bounds.center() - centre));
            if (Status s = placeLatticeNet(*block, at, normal, scale * block->diagonal(), part); !s) return s;
            parts.push_back(std::make_shared<const LatticeNet>(std::move(part)));
        }
        std::shared_ptr<const CompositeVolume> placed;
        if (Status s = CompositeVolume::make(std::move(parts), placed); !s) return s;
        out = std::move(placed);
        return Status::success();
    }
    if (const auto* tspline = dynamic_cast<const TSplineVolume*>(&tool)) {
        // The similarity applied to every control point; the T-lattice (parameter space) and weights are kept.
        if (!point.allFinite() || !normal.allFinite() || !(normal.norm() > 0.0))
            return Status::error("placing a lattice needs a finite point and a non-zero normal");
        if (!(size > 0.0) || !std::isfinite(size)) return Status::error("placing a lattice needs a size that is finite and > 0");
        const Eigen::Matrix3d rotation = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), normal.normalized()).toRotationMatrix();
        const Eigen::Vector3d centre = tspline->restBounds().center();
        const double scale = size / tspline->restBounds().diagonal().norm();
        Positions points = tspline->restControlPoints();
        for (Eigen::Index s = 0; s < points.rows(); ++s) points.row(s) = (point + scale * (rotation * (points.row(s).transpose() - centre))).transpose();
        std::shared_ptr<const TSplineVolume> placed;
        if (Status s = TSplineVolume::make(tspline->sharedBasis(), std::move(points), tspline->controlWeights(), placed); !s) return s;
        out = std::move(placed);
        return Status::success();
    }
    return Status::error("placing a " + tool.kindName() + " lattice is not supported");
}

}  // namespace sculpt::core
