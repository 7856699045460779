// Plain FFD by a rotated Bernstein box (bernstein_box.h).
#include "core/spline/bernstein_box.h"

#include <cmath>
#include <string>

#include <Eigen/LU>

#include "core/spline/bernstein.h"

namespace sculpt::core {

Eigen::Matrix3d bernsteinBoxRotation(const Eigen::Vector3d& degrees) {
    const Eigen::Vector3d a = degrees * (M_PI / 180.0);
    Eigen::Matrix3d rx, ry, rz;
    rx << 1, 0, 0, 0, std::cos(a.x()), -std::sin(a.x()), 0, std::sin(a.x()), std::cos(a.x());
    ry << std::cos(a.y()), 0, std::sin(a.y()), 0, 1, 0, -std::sin(a.y()), 0, std::cos(a.y());
    rz << std::cos(a.z()), -std::sin(a.z()), 0, std::sin(a.z()), std::cos(a.z()), 0, 0, 0, 1;
    return rx * ry * rz;
}

Status deformByBernsteinBox(const BernsteinBox& box, const Positions& points, Positions& out) {
    BernsteinDegree degree{};
    size_t count = 1;
    for (int a = 0; a < 3; ++a) {
        const int n = box.controlPoints[static_cast<size_t>(a)];
        if (n < 1 || n > kMaxBernsteinDegree + 1)
            return Status::error("n_control_points[" + std::to_string(a) + "] is " + std::to_string(n) + ": it must be 1 to " +
                                 std::to_string(kMaxBernsteinDegree + 1));
        degree[static_cast<size_t>(a)] = n - 1;
        count *= static_cast<size_t>(n);
    }
    static const char* const names[3] = {"x", "y", "z"};
    for (int a = 0; a < 3; ++a) {
        const std::vector<double>& mu = box.mu[static_cast<size_t>(a)];
        if (mu.size() != count)
            return Status::error(std::string("array_mu_") + names[a] + " holds " + std::to_string(mu.size()) + " values, not " +
                                 std::to_string(count));
        for (double d : mu)
            if (!std::isfinite(d)) return Status::error(std::string("array_mu_") + names[a] + " holds a non-finite value");
    }
    if (!(box.lengths.array() > 0.0).all() || !box.lengths.allFinite()) return Status::error("box_length must be finite and > 0");
    if (!box.origin.allFinite() || !box.rotationDegrees.allFinite()) return Status::error("box_origin and rot_angle must be finite");
    if (!points.allFinite()) return Status::error("the points must be finite");
    // The box frame: columns are the box's edges (PyGeM's position_vertices), its inverse maps to parameters.
    const Eigen::Matrix3d edges = bernsteinBoxRotation(box.rotationDegrees) * box.lengths.asDiagonal();
    const Eigen::Matrix3d toParameters = edges.inverse();
    Positions result = points;
    const Eigen::Index n = points.rows();
#pragma omp parallel for schedule(static)
    for (Eigen::Index p = 0; p < n; ++p) {
        const Eigen::Vector3d x = points.row(p).transpose();
        const Eigen::Vector3d u = toParameters * (x - box.origin);
        if (!((u.array() >= 0.0).all() && (u.array() <= 1.0).all())) continue;  // outside: not moved
        // The Bernstein basis of each axis by the triangular recurrence b_k^j = (1 - t) b_k^(j-1) + t b_(k-1)^(j-1)
        // (stable, no powers), then one pass over the control points for all three components.
        double basis[3][kMaxBernsteinDegree + 1];
        for (int a = 0; a < 3; ++a) {
            const double t = u[a];
            double* b = basis[a];
            b[0] = 1.0;
            for (int j = 1; j <= degree[static_cast<size_t>(a)]; ++j) {
                double saved = 0.0;
                for (int k = 0; k < j; ++k) {
                    const double previous = b[k];
                    b[k] = saved + (1.0 - t) * previous;
                    saved = t * previous;
                }
                b[j] = saved;
            }
        }
        Eigen::Vector3d shift = Eigen::Vector3d::Zero();
        size_t index = 0;
        for (int k = 0; k <= degree[2]; ++k)
            for (int j = 0; j <= degree[1]; ++j) {
                const double bjk = basis[1][j] * basis[2][k];
                for (int i = 0; i <= degree[0]; ++i, ++index) {
                    const double w = basis[0][i] * bjk;
                    shift += w * Eigen::Vector3d(box.mu[0][index], box.mu[1][index], box.mu[2][index]);
                }
            }
        result.row(p) = (x + edges * shift).transpose();
    }
    if (!result.allFinite()) return Status::error("the deformed points are not finite (the displacements overflow)");
    out = std::move(result);
    return Status::success();
}

}  // namespace sculpt::core
