// What lattice_net.cpp and lattice_net_volume.cpp share: the per-axis basis of a net at a parameter point.
// Internal to src/core/volume.
#pragma once

#include <Eigen/Core>

#include "core/spline/bspline_basis.h"
#include "core/volume/lattice_net.h"

namespace sculpt::core::lattice_net_detail {

// Per-axis basis values (and derivatives) at t.
struct NetBases {
    int first[3];
    double value[3][kMaxDegree + 1];
    double derivative[3][kMaxDegree + 1];
};

// The basis of each axis at t (clamped to [0, 1]): its first control point index, values, and derivatives when
// asked (Piegl & Tiller's B-spline basis over the net's knot vectors, with multiplicity).
void netBases(const LatticeNet& net, const Eigen::Vector3d& t, bool derivatives, NetBases& b);

}  // namespace sculpt::core::lattice_net_detail
