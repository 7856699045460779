// One Newton step of freezing (Coquillart 1990, 3.3; Song & Yang 2005, sec. 5), declared in volume.h.
// note: here rather than inline in volume.h, so the LU and SVD headers are parsed only by this file and not by
// every file that includes volume.h.
#include "core/volume/volume.h"

#include <Eigen/LU>
#include <Eigen/SVD>

namespace sculpt::core {

Eigen::Vector3d freezingNewtonStep(const Eigen::Matrix3d& d, const Eigen::Vector3d& residual) {
    const double scale = d.colwise().norm().prod();
    if (scale > 0.0 && std::abs(d.determinant()) > 1e-9 * scale) return d.partialPivLu().solve(residual);
    Eigen::JacobiSVD<Eigen::Matrix3d> svd(d, Eigen::ComputeFullU | Eigen::ComputeFullV);
    svd.setThreshold(1e-9);
    return svd.solve(residual);
}

}  // namespace sculpt::core
