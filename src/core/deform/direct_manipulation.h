// Explicit direct manipulation of the lattice (Hu, Zhang, Tai, Sun 2001).
//
// Given h source points with lattice parameters t_f and wanted displacements D_f, find the control point
// displacements delta of least norm with sum_ijk delta_ijk R_ijk(t_f) = D_f for every f:
//   one point:     delta_ijk = R_ijk(t) / sum R^2 * D                                  (eq. 7)
//   several:       delta = R (R^T R)^-1 D                                             (eq. 12)
// R is the #free-control-points x h matrix of basis values; pinned control points are left out of it, so
// they never move and the solution is least-norm over the free ones. When R^T R is singular or
// ill-conditioned (coincident sources, more constraints than the support can satisfy), the result is the
// minimum-norm least-squares solution (Hsu et al. 1992's pseudo-inverse) and each constraint's residual is
// reported.
//
// Precompute -> data -> solve: the sources of a drag stay fixed while the targets follow the mouse, so the
// factorisation is done once per drag and each mouse move costs one small solve.
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include <Eigen/Core>
#include <Eigen/QR>
#include <Eigen/Cholesky>

#include "core/volume/lattice.h"
#include "core/status.h"

namespace sculpt::core {

// A sparse change of the lattice: control point ids (sorted, unique) and their displacements.
struct ControlDelta {
    std::vector<int> indices;
    Positions deltas;  // #indices x 3
    bool empty() const { return indices.empty(); }
};

struct DirectManipulationOptions {
    // Relative eigenvalue floor of R^T R below which the fast normal-equation path is not trusted and the
    // complete orthogonal decomposition of R^T decides the (numerical) rank instead.
    double normalEquationFloor = 1e-10;
    // Singular values of R^T below this fraction of the largest count as zero: the minimum-norm
    // least-squares solution then ignores those directions instead of producing huge control moves.
    double rankThreshold = 1e-8;
};

struct DirectManipulationData {
    int constraintCount = 0;
    std::vector<int> columns;          // free control point ids in the union of the supports (sorted)
    Eigen::MatrixXd rt;                // h x m: R^T restricted to `columns`
    bool useNormalEquations = false;   // fast path: Cholesky of R^T R plus iterative refinement
    // note: optional, because a default-constructed Eigen::LLT leaves its status uninitialised and copying
    // it (a Session is copyable) reads that (UBSan); only a computed factorisation is ever held.
    std::optional<Eigen::LLT<Eigen::MatrixXd>> gram;  // of R^T R, when useNormalEquations
    std::optional<Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd>> cod;  // of R^T, otherwise
    int rank = 0;
    double rankThreshold = 1e-8;       // copied from the options
    std::shared_ptr<const Volume> volume;  // a lattice of another kind: solutions are expanded to every welded id
};

// sourceParams: h parameter points in [0,1]^3. Fails only for h == 0.
Status precomputeDirectManipulation(const Lattice& lattice, const std::vector<Eigen::Vector3d>& sourceParams,
                                    DirectManipulationData& data, const DirectManipulationOptions& options = {});

struct DirectManipulationResult {
    ControlDelta delta;
    std::vector<double> residuals;  // per constraint: |D_f - sum delta R(t_f)|
    bool rankDeficient = false;
};

// displacements: h x 3 (row f = D_f = T_f - current image of S_f). Never produces NaN for finite input.
DirectManipulationResult solveDirectManipulation(const DirectManipulationData& data, const Eigen::MatrixX3d& displacements);

// One-call wrapper.
DirectManipulationResult directManipulation(const Lattice& lattice, const std::vector<Eigen::Vector3d>& sourceParams,
                                            const Eigen::MatrixX3d& displacements,
                                            const DirectManipulationOptions& options = {});

// Gives every slot of a weld group the displacement of its member in `delta` (Coquillart 1990, 3.1.2: welded
// points act as one control point). Sorted, unique ids; a no-op for lattices without welds. Every delta
// applied to a net lattice goes through this (the solver's results already have).
void expandWelds(const Volume& volume, ControlDelta& delta);
void expandWelds(const Lattice& lattice, ControlDelta& delta);

// Applies a control delta (sign +1) or its inverse (sign -1) to the lattice.
void applyControlDelta(Lattice& lattice, const ControlDelta& delta, double sign = 1.0);

}  // namespace sculpt::core
