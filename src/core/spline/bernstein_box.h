// Free-form deformation by one Bernstein box, as Sederberg & Parry (1986) define it and PyGeM's pygem.FFD
// computes it: the classic FFD of a point set, without the direct-manipulation solve and without the
// injectivity test (a plain FFD: whatever the displacements say). Used by the Python module's FFD class,
// which takes PyGeM's parameters and gives PyGeM's results.
#pragma once

#include <array>
#include <vector>

#include "core/mesh_types.h"
#include "core/status.h"

namespace sculpt::core {

// The box and its control displacements.
//   - controlPoints: (l+1, m+1, n+1) per axis, each in [1, kMaxBernsteinDegree + 1] (Bernstein degree l, m, n).
//   - origin: the box corner of control point (0,0,0), world units; lengths: the box's edge lengths (> 0).
//   - rotationDegrees: (a_x, a_y, a_z), the box's edges are the columns of R diag(lengths), R = R_x(a_x)
//     R_y(a_y) R_z(a_z) (PyGeM's angles2matrix, counter-clockwise about each axis, right-hand rule).
//   - mu[axis]: the displacement of each control point along that box axis, in box lengths (PyGeM's
//     array_mu_x/y/z), (l+1)(m+1)(n+1) values, control point (i,j,k) at i + (l+1) (j + (m+1) k).
struct BernsteinBox {
    std::array<int, 3> controlPoints{2, 2, 2};
    Eigen::Vector3d origin = Eigen::Vector3d::Zero();
    Eigen::Vector3d lengths = Eigen::Vector3d::Ones();
    Eigen::Vector3d rotationDegrees = Eigen::Vector3d::Zero();
    std::array<std::vector<double>, 3> mu;
};

// R_x(a_x) R_y(a_y) R_z(a_z) for angles in degrees.
Eigen::Matrix3d bernsteinBoxRotation(const Eigen::Vector3d& degrees);

// The deformed points (#N x 3, world units): a point with box parameters u = (R diag(lengths))^-1 (x - origin)
// in the closed unit cube moves to x + R diag(lengths) sum_ijk b_i^l(u_0) b_j^m(u_1) b_k^n(u_2) mu_ijk
// (Sederberg & Parry 1986, eq. 1 and 3, with the box's local frame), every other point stays where it is.
// Parallel over points. Fails (out untouched) on counts out of range, mu of the wrong size, lengths not > 0,
// or anything not finite in the box or the points.
Status deformByBernsteinBox(const BernsteinBox& box, const Positions& points, Positions& out);

}  // namespace sculpt::core
