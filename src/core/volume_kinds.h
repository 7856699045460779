// Operations on a lattice of any kind (volume.h): placing a lattice tool, through each kind's Volume::placed
// (a new kind places itself in its own files; nothing here names the kinds).
#pragma once

#include <memory>

#include <Eigen/Core>

#include "core/status.h"
#include "core/volume.h"

namespace sculpt::core {

// The positioning command (Coquillart 1990, 3.2) for a lattice of any kind: the same similarity for all of its
// control points, which moves the centre of its bounds to `point`, turns its own z axis onto `normal` (the
// shortest rotation) and scales its bounds' diagonal to `size` (placeLatticeNet per part of a composite).
// Weights and welds are kept. Fails on a zero normal, a size that is not finite and > 0, or a kind it does not
// know; `out` is then untouched.
Status placeVolume(const Volume& tool, const Eigen::Vector3d& point, const Eigen::Vector3d& normal, double size,
                   std::shared_ptr<const Volume>& out);

// The checks every similarity placement makes: a finite point, a finite non-zero normal, a size finite and > 0;
// the message names what is wrong.
Status checkPlacement(const Eigen::Vector3d& point, const Eigen::Vector3d& normal, double size);

}  // namespace sculpt::core
