// Hu, Zhang, Tai, Sun (2001), "Direct manipulation of FFD: efficient explicit solutions and decomposable
// multiple point constraints", The Visual Computer 17. Rank-deficient cases follow Hsu, Hughes, Kaufman
// (1992): the pseudo-inverse, i.e. the minimum-norm least-squares solution, with residuals reported.
#include "core/deform/direct_manipulation.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

namespace sculpt::core {

Status precomputeDirectManipulation(const Lattice& lattice, const std::vector<Eigen::Vector3d>& sourceParams,
                                    DirectManipulationData& data, const DirectManipulationOptions& options) {
    const int h = static_cast<int>(sourceParams.size());
    if (h == 0) return Status::error("a manipulation needs at least one constraint");
    std::vector<SupportWeights> supports(h);
    std::vector<int> columns;
    for (int f = 0; f < h; ++f) {
        supportWeights(lattice, sourceParams[f], supports[f]);
        for (int c = 0; c < supports[f].count; ++c)
            if (!lattice.pinned[supports[f].index[c]] && supports[f].weight[c] != 0.0)
                columns.push_back(supports[f].index[c]);
    }
    // note: sorting the union makes the column order independent of the order constraints are listed in.
    std::sort(columns.begin(), columns.end());
    columns.erase(std::unique(columns.begin(), columns.end()), columns.end());
    const int m = static_cast<int>(columns.size());

    DirectManipulationData d;
    d.constraintCount = h;
    d.rankThreshold = options.rankThreshold;
    d.columns = columns;
    d.volume = lattice.volume;
    d.rt = Eigen::MatrixXd::Zero(h, m);
    for (int f = 0; f < h; ++f)
        for (int c = 0; c < supports[f].count; ++c) {
            if (lattice.pinned[supports[f].index[c]]) continue;
            const auto it = std::lower_bound(columns.begin(), columns.end(), supports[f].index[c]);
            if (it != columns.end() && *it == supports[f].index[c]) d.rt(f, it - columns.begin()) = supports[f].weight[c];
        }

    if (m > 0) {
        // R^T R is h x h and small (eq. 12); its eigenvalues are the squared singular values of R.
        const Eigen::MatrixXd gram = d.rt * d.rt.transpose();
        const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(gram, Eigen::EigenvaluesOnly);
        const double largest = eigen.eigenvalues().maxCoeff();
        const double smallest = eigen.eigenvalues().minCoeff();
        if (largest > 0.0 && smallest > options.normalEquationFloor * largest) {
            d.gram.emplace(gram);
            d.useNormalEquations = d.gram->info() == Eigen::Success;
            if (!d.useNormalEquations) d.gram.reset();
            d.rank = h;
        }
        if (!d.useNormalEquations) {
            d.cod.emplace(d.rt.rows(), d.rt.cols());
            d.cod->setThreshold(options.rankThreshold);
            d.cod->compute(d.rt);
            d.rank = static_cast<int>(d.cod->rank());
        }
    }
    data = std::move(d);
    return Status::success();
}

DirectManipulationResult solveDirectManipulation(const DirectManipulationData& data, const Eigen::MatrixX3d& displacements) {
    DirectManipulationResult result;
    const int h = data.constraintCount;
    const int m = static_cast<int>(data.columns.size());
    Eigen::MatrixX3d delta = Eigen::MatrixX3d::Zero(m, 3);
    if (m > 0) {
        if (h == 1) {
            // Hu et al. 2001, eq. 7: delta_ijk = R_ijk(t) / sum R^2 (T - S).
            // note: unit-sum weights give sum R^2 >= 1/216 over a full support; only pins can make it tiny, and
            // then the exact solution would throw control points away, so such a source counts as unreachable.
            const double sumSquares = data.rt.row(0).squaredNorm();
            if (sumSquares > data.rankThreshold * data.rankThreshold)
                delta = data.rt.row(0).transpose() * (displacements.row(0) / sumSquares);
            else
                result.rankDeficient = true;
        } else if (data.useNormalEquations) {
            // Eq. 12: delta = R (R^T R)^-1 D, with two steps of iterative refinement so the constraints are met
            // to rounding even when R^T R's condition number is large (it squares that of R).
            delta = data.rt.transpose() * data.gram->solve(displacements);
            for (int step = 0; step < 2; ++step) {
                const Eigen::MatrixX3d residual = displacements - data.rt * delta;
                delta += data.rt.transpose() * data.gram->solve(residual);
            }
        } else {
            // Minimum-norm least-squares solution of R^T delta = D (complete orthogonal decomposition).
            delta = data.cod->solve(displacements);
            result.rankDeficient = data.rank < h;
        }
    } else {
        result.rankDeficient = true;  // every control point that could move a source is pinned
    }
    if (!delta.allFinite()) delta.setZero();  // unreachable for finite input; keeps NaN out of the lattice

    result.delta.indices = data.columns;
    result.delta.deltas = delta;
    if (data.volume) expandWelds(*data.volume, result.delta);
    const Eigen::MatrixX3d achieved = m > 0 ? Eigen::MatrixX3d(data.rt * delta) : Eigen::MatrixX3d::Zero(h, 3);
    result.residuals.resize(h);
    for (int f = 0; f < h; ++f) result.residuals[f] = (displacements.row(f) - achieved.row(f)).norm();
    return result;
}

DirectManipulationResult directManipulation(const Lattice& lattice, const std::vector<Eigen::Vector3d>& sourceParams,
                                            const Eigen::MatrixX3d& displacements,
                                            const DirectManipulationOptions& options) {
    DirectManipulationData data;
    if (!precomputeDirectManipulation(lattice, sourceParams, data, options)) return {};
    return solveDirectManipulation(data, displacements);
}

void expandWelds(const Volume& volume, ControlDelta& delta) {
    if (volume.weldGroupList().empty()) return;
    std::vector<std::pair<int, int>> rows;  // (id, row of delta)
    for (size_t c = 0; c < delta.indices.size(); ++c) {
        if (const std::vector<int>* group = weldGroupOf(volume, delta.indices[c]))
            for (int s : *group) rows.emplace_back(s, static_cast<int>(c));
        else
            rows.emplace_back(delta.indices[c], static_cast<int>(c));
    }
    std::sort(rows.begin(), rows.end());
    rows.erase(std::unique(rows.begin(), rows.end(), [](const auto& a, const auto& b) { return a.first == b.first; }), rows.end());
    ControlDelta out;
    out.deltas.resize(static_cast<Eigen::Index>(rows.size()), 3);
    for (size_t r = 0; r < rows.size(); ++r) {
        out.indices.push_back(rows[r].first);
        out.deltas.row(static_cast<Eigen::Index>(r)) = delta.deltas.row(rows[r].second);
    }
    delta = std::move(out);
}

void expandWelds(const Lattice& lattice, ControlDelta& delta) {
    if (lattice.volume) expandWelds(*lattice.volume, delta);
}

void applyControlDelta(Lattice& lattice, const ControlDelta& delta, double sign) {
    for (size_t c = 0; c < delta.indices.size(); ++c)
        lattice.displacement.row(delta.indices[c]) += sign * delta.deltas.row(static_cast<Eigen::Index>(c));
}

}  // namespace sculpt::core
