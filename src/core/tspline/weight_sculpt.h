// Sculpting by weights (Song & Yang 2005, "Free-form deformation with weighted T-spline", sec. 1 and 6, after
// Noble & Gordon 1999): the closed form of a bump made by a set S of control points of a rational volume, and
// its width at half height, for the hammer and crimp tools (Session::tspline().sculptWeights).
//
// With weights W and control displacements delta, the deformation at a vertex with parameters t is
//   D(t) = sum_r W_r B_r(t) delta_r / sum_r W_r B_r(t)                       (eq. 5 minus its rest volume)
// Split into the control points of S and the others, per vertex v:
//   A_v = sum_{r not in S} W_r B_r(t_v),  a_v = sum_{r not in S} W_r B_r(t_v) delta_r,
//   C_v = sum_{s in S}     W_s B_s(t_v),  c_v = sum_{s in S}     W_s B_s(t_v) delta_s.
// Multiplying the weights of S by beta and replacing their displacements by lambda delta_s + mu n gives the
// height along the unit direction n
//   H_v(beta, lambda, mu) = (n.a_v + beta (lambda n.c_v + mu C_v)) / (A_v + beta C_v)
// exactly (up to rounding), without building the volume again: the tools solve for beta, lambda and mu on it.
#pragma once

#include <functional>
#include <vector>

#include <Eigen/Core>

#include "core/mesh_types.h"
#include "core/status.h"

namespace sculpt::core {

struct BumpSums {
    std::vector<int> vertices;                 // the vertices where some B_s (s in S) is non-zero
    std::vector<double> others, own;           // A_v, C_v
    std::vector<Eigen::Vector3d> othersDisplacement, ownDisplacement;  // a_v, c_v
};

// H_v(beta, lambda, mu) for every vertex of `sums` (out: sums.vertices.size() values). beta > 0.
void bumpHeights(const BumpSums& sums, const Eigen::Vector3d& direction, double beta, double lambda, double mu,
                 std::vector<double>& out);
// The same at one entry c of sums.
double bumpHeight(const BumpSums& sums, size_t c, const Eigen::Vector3d& direction, double beta, double lambda, double mu);

// The area of the part of triangle (x0, x1, x2) where the linear interpolant of the vertex values (h0, h1, h2)
// is >= level (the triangle clipped by the level line; exact for linear interpolation).
double areaAtOrAbove(const Eigen::Vector3d& x0, const Eigen::Vector3d& x1, const Eigen::Vector3d& x2, double h0, double h1, double h2,
                     double level);

// The bump's width at half height: the equivalent diameter 2 sqrt(A / pi) of the surface (rest positions
// `rest`, #V x 3) where the per-vertex height (heights, #V values, linear within each triangle) is >= level,
// over the triangles listed (ids into `triangles`).
double equivalentDiameter(const Positions& rest, const Triangles& triangles, const std::vector<int>& triangleIds,
                          const std::vector<double>& heights, double level);

// Crimp: a beta in [betaMin, betaMax] with width(beta) = target: the widths on a log grid of 49 factors, then
// bisection on log beta (to a relative width tolerance of 1e-6, or 100 halvings) in the bracket nearest beta = 1.
// Fails, naming the widths seen, when no grid interval brackets the target.
Status solveCrimpFactor(const std::function<double(double)>& width, double target, double betaMin, double betaMax, double& beta);

}  // namespace sculpt::core
