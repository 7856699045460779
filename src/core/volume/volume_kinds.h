// Operations on a lattice of any kind (volume.h): placing a lattice tool, through each kind's Volume::placed
// (a new kind places itself in its own files; nothing here names the kinds).
#pragma once

#include <memory>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/status.h"
#include "core/volume/volume.h"

namespace sculpt::core {

// The positioning command (Coquillart 1990, 3.2) for a lattice of any kind: the same similarity for all of its
// control points, which moves the centre of its bounds to `point`, turns its own z axis onto `normal` (the
// shortest rotation) and scales its bounds' diagonal to `size` (placeLatticeNet per part of a composite).
// Weights and welds are kept. Fails on a zero normal, a size that is not finite and > 0, or a kind it does not
// know; `out` is then untouched.
Status placeVolume(const Volume& tool, const Eigen::Vector3d& point, const Eigen::Vector3d& normal, double size,
                   std::shared_ptr<const Volume>& out);

// The similarity of the positioning command: x -> to + scale * rotation (x - from), which takes the centre of
// `bounds` (a volume's rest bounds) to `point`, its z axis onto `normal` (the shortest rotation) and its
// diagonal to `size`.
struct PlacementSimilarity {
    Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
    Eigen::Vector3d from = Eigen::Vector3d::Zero(), to = Eigen::Vector3d::Zero();
    double scale = 1.0;
    Eigen::Vector3d operator()(const Eigen::Vector3d& x) const { return to + scale * (rotation * (x - from)); }
};
// Fails, naming what is wrong, on a point that is not finite, a normal that is zero or not finite, or a size that
// is not finite and > 0 (`out` untouched).
Status placementSimilarity(const Eigen::AlignedBox3d& bounds, const Eigen::Vector3d& point, const Eigen::Vector3d& normal, double size,
                           PlacementSimilarity& out);

}  // namespace sculpt::core
