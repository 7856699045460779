// Seed 000's algebra (Hu et al. 2001) as properties over random lattices, degrees, resolutions and
// constraints with fixed seeds.
#include <catch2/catch.hpp>

#include <random>

#include <Eigen/QR>

#include "core/deform/direct_manipulation.h"
#include "../test_support.h"

using namespace sculpt;
using namespace sculpt::core;

namespace {

// The deformed image of parameter point t relative to its rest position: sum R delta.
Eigen::Vector3d imageDisplacement(const Lattice& lattice, const Eigen::Vector3d& t) { return displacementAt(lattice, t); }

// Independent oracle: the minimum-norm least-squares solution of the FULL system (every free control point
// a column, dense), by Eigen's complete orthogonal decomposition. Returns #P x 3.
Eigen::MatrixX3d fullMinimumNorm(const Lattice& lattice, const std::vector<Eigen::Vector3d>& params,
                                 const Eigen::MatrixX3d& d) {
    const int n = lattice.controlPointCount();
    Eigen::MatrixXd rt = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(params.size()), n);
    for (size_t f = 0; f < params.size(); ++f) {
        SupportWeights s;
        supportWeights(lattice, params[f], s);
        for (int c = 0; c < s.count; ++c)
            if (!lattice.pinned[s.index[c]]) rt(static_cast<Eigen::Index>(f), s.index[c]) = s.weight[c];
    }
    Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(rt);
    cod.setThreshold(1e-8);
    return cod.solve(d);
}

Eigen::MatrixX3d dense(const Lattice& lattice, const ControlDelta& delta) {
    Eigen::MatrixX3d out = Eigen::MatrixX3d::Zero(lattice.controlPointCount(), 3);
    for (size_t c = 0; c < delta.indices.size(); ++c) out.row(delta.indices[c]) = delta.deltas.row(static_cast<Eigen::Index>(c));
    return out;
}

Eigen::MatrixX3d randomDisplacements(std::mt19937& rng, int h, double scale) {
    Eigen::MatrixX3d d(h, 3);
    for (int f = 0; f < h; ++f) d.row(f) = scale * test::randomVector(rng, -1, 1).transpose();
    return d;
}

}  // namespace

TEST_CASE("direct_manipulation: one point lands on its target and only its support moves (eq. 7)", "[core]") {
    std::mt19937 rng(41);
    for (int trial = 0; trial < 200; ++trial) {
        Lattice lattice = test::randomLattice(rng);
        if (trial % 3 == 0) test::randomDisplacement(rng, lattice, 0.02);  // start from a deformed lattice
        const Eigen::Vector3d t = test::randomParams(rng);
        const Eigen::MatrixX3d d = randomDisplacements(rng, 1, 0.3 * lattice.diagonal());
        const Eigen::Vector3d before = imageDisplacement(lattice, t);
        const DirectManipulationResult r = directManipulation(lattice, {t}, d);
        const Positions old = lattice.displacement;
        applyControlDelta(lattice, r.delta);
        REQUIRE((imageDisplacement(lattice, t) - before - d.row(0).transpose()).norm() <= 1e-9 * lattice.diagonal());
        const int support = (lattice.degree[0] + 1) * (lattice.degree[1] + 1) * (lattice.degree[2] + 1);
        int moved = 0;
        for (int c = 0; c < lattice.controlPointCount(); ++c) moved += lattice.displacement.row(c) != old.row(c);
        REQUIRE(moved <= support);
        REQUIRE(r.residuals[0] <= 1e-9 * lattice.diagonal());
        // Equals the independently computed minimum-norm solution of the full system.
        const Eigen::MatrixX3d oracle = fullMinimumNorm(lattice, {t}, d);
        REQUIRE((dense(lattice, r.delta) - oracle).cwiseAbs().maxCoeff() <= 1e-9 * (1.0 + oracle.cwiseAbs().maxCoeff()));
    }
}

TEST_CASE("direct_manipulation: several points all land when well conditioned (eq. 12)", "[core]") {
    std::mt19937 rng(42);
    for (int trial = 0; trial < 100; ++trial) {
        Lattice lattice = test::randomLattice(rng, trial % 2 == 0);
        const int h = test::randomInt(rng, 2, 12);
        std::vector<Eigen::Vector3d> params;
        for (int f = 0; f < h; ++f) params.push_back(test::randomParams(rng));
        const Eigen::MatrixX3d d = randomDisplacements(rng, h, 0.2 * lattice.diagonal());
        DirectManipulationData data;
        REQUIRE(precomputeDirectManipulation(lattice, params, data).ok);
        const DirectManipulationResult r = solveDirectManipulation(data, d);
        const Eigen::MatrixX3d oracle = fullMinimumNorm(lattice, params, d);
        REQUIRE((dense(lattice, r.delta) - oracle).cwiseAbs().maxCoeff() <= 1e-7 * (1.0 + oracle.cwiseAbs().maxCoeff()));
        if (data.rank == h && !r.rankDeficient) {
            applyControlDelta(lattice, r.delta);
            for (int f = 0; f < h; ++f)
                REQUIRE((imageDisplacement(lattice, params[f]) - d.row(f).transpose()).norm() <= 1e-9 * lattice.diagonal());
        }
        REQUIRE(r.delta.deltas.allFinite());
    }
}

TEST_CASE("direct_manipulation: coincident and over-constrained sources give the minimum-norm least-squares result", "[core]") {
    std::mt19937 rng(43);
    for (int trial = 0; trial < 100; ++trial) {
        // Degree 1 or 2 so that more constraints than one cell's support (8 or 27 control points) are cheap.
        core::LatticeSettings settings = test::randomSettings(rng, false);
        const int p = 1 + trial % 2;
        settings.degree = {p, p, p};
        for (int a = 0; a < 3; ++a) settings.resolution[a] = std::max(settings.resolution[a], p + 2);
        Lattice lattice;
        REQUIRE(makeLattice(settings, test::randomPoints(rng, 20, Eigen::Vector3d::Zero(), Eigen::Vector3d(2, 1, 3)), lattice).ok);
        // All sources inside one cell: the support has (p+1)^3 control points, so at most that many
        // constraints can be met; two of them are exactly coincident with different targets.
        Eigen::Vector3d cell;
        for (int a = 0; a < 3; ++a) cell[a] = test::randomInt(rng, 0, lattice.axes[a].spans - 1);
        auto inCell = [&] {
            Eigen::Vector3d t;
            for (int a = 0; a < 3; ++a) t[a] = (cell[a] + std::uniform_real_distribution<double>(0.1, 0.9)(rng)) / lattice.axes[a].spans;
            return t;
        };
        const int support = (p + 1) * (p + 1) * (p + 1);
        const int h = trial % 3 == 0 ? 2 : support + test::randomInt(rng, 1, 4);
        std::vector<Eigen::Vector3d> params{inCell()};
        params.push_back(params[0]);
        while (static_cast<int>(params.size()) < h) params.push_back(inCell());
        const Eigen::MatrixX3d d = randomDisplacements(rng, h, 0.1 * lattice.diagonal());
        DirectManipulationData data;
        REQUIRE(precomputeDirectManipulation(lattice, params, data).ok);
        const DirectManipulationResult r = solveDirectManipulation(data, d);
        INFO("trial " << trial << " h " << h << " rank " << data.rank);
        REQUIRE(r.rankDeficient);
        REQUIRE(r.delta.deltas.allFinite());
        const Eigen::MatrixX3d oracle = fullMinimumNorm(lattice, params, d);
        REQUIRE((dense(lattice, r.delta) - oracle).cwiseAbs().maxCoeff() <= 1e-8 * (1.0 + oracle.cwiseAbs().maxCoeff()));
        // Residuals are what is left of each constraint after the change.
        Lattice after = lattice;
        applyControlDelta(after, r.delta);
        for (int f = 0; f < h; ++f)
            REQUIRE(r.residuals[f] == Approx((imageDisplacement(after, params[f]) - imageDisplacement(lattice, params[f]) -
                                              d.row(f).transpose()).norm()).margin(1e-12 * lattice.diagonal()));
        if (h == 2) {  // two coincident sources: the point goes to the mean of the targets
            const Eigen::Vector3d mean = 0.5 * (d.row(0) + d.row(1)).transpose();
            REQUIRE((imageDisplacement(after, params[0]) - imageDisplacement(lattice, params[0]) - mean).norm() <= 1e-9 * lattice.diagonal());
        }
    }
}

TEST_CASE("direct_manipulation: nearly coincident sources never give NaN or infinite control moves", "[core]") {
    std::mt19937 rng(48);
    for (int trial = 0; trial < 100; ++trial) {
        const Lattice lattice = test::randomLattice(rng);
        const Eigen::Vector3d shared = test::randomVector(rng, 0.0, 0.99);
        std::vector<Eigen::Vector3d> params{shared};
        const double gap = std::pow(10.0, -test::randomInt(rng, 3, 15));
        for (int f = 0; f < 1 + trial % 6; ++f) params.push_back(shared + gap * test::randomVector(rng, 0.0, 1.0));
        const int h = static_cast<int>(params.size());
        const Eigen::MatrixX3d d = randomDisplacements(rng, h, 0.1 * lattice.diagonal());
        const DirectManipulationResult r = directManipulation(lattice, params, d);
        REQUIRE(r.delta.deltas.allFinite());
        for (double residual : r.residuals) REQUIRE(std::isfinite(residual));
    }
}

TEST_CASE("direct_manipulation: result does not depend on constraint order", "[core]") {
    std::mt19937 rng(44);
    for (int trial = 0; trial < 60; ++trial) {
        const Lattice lattice = test::randomLattice(rng);
        const int h = test::randomInt(rng, 2, 10);
        std::vector<Eigen::Vector3d> params;
        for (int f = 0; f < h; ++f) params.push_back(test::randomParams(rng));
        if (trial % 3 == 0) params[1] = params[0];  // rank-deficient cases too
        const Eigen::MatrixX3d d = randomDisplacements(rng, h, 0.1 * lattice.diagonal());
        std::vector<int> permutation(h);
        std::iota(permutation.begin(), permutation.end(), 0);
        std::shuffle(permutation.begin(), permutation.end(), rng);
        std::vector<Eigen::Vector3d> shuffledParams(h);
        Eigen::MatrixX3d shuffled(h, 3);
        for (int f = 0; f < h; ++f) {
            shuffledParams[f] = params[permutation[f]];
            shuffled.row(f) = d.row(permutation[f]);
        }
        const DirectManipulationResult a = directManipulation(lattice, params, d);
        const DirectManipulationResult b = directManipulation(lattice, shuffledParams, shuffled);
        REQUIRE(a.delta.indices == b.delta.indices);
        REQUIRE((a.delta.deltas - b.delta.deltas).cwiseAbs().maxCoeff() <= 1e-9 * (1.0 + a.delta.deltas.cwiseAbs().maxCoeff()));
        for (int f = 0; f < h; ++f) REQUIRE(b.residuals[f] == Approx(a.residuals[permutation[f]]).margin(1e-10 * lattice.diagonal()));
    }
}

TEST_CASE("direct_manipulation: composition adds, order does not matter, the inverse restores (section 4)", "[core]") {
    std::mt19937 rng(45);
    for (int trial = 0; trial < 100; ++trial) {
        Lattice lattice = test::randomLattice(rng);
        const Lattice original = lattice;
        const Eigen::Vector3d t = test::randomParams(rng);
        const Eigen::MatrixX3d a = randomDisplacements(rng, 1, 0.1 * lattice.diagonal());
        const Eigen::MatrixX3d b = randomDisplacements(rng, 1, 0.1 * lattice.diagonal());
        const double tolerance = 1e-12 * lattice.diagonal();

        Lattice ab = original, ba = original, sum = original;
        applyControlDelta(ab, directManipulation(ab, {t}, a).delta);
        applyControlDelta(ab, directManipulation(ab, {t}, b).delta);
        applyControlDelta(ba, directManipulation(ba, {t}, b).delta);
        applyControlDelta(ba, directManipulation(ba, {t}, a).delta);
        applyControlDelta(sum, directManipulation(sum, {t}, a + b).delta);
        REQUIRE((ab.displacement - sum.displacement).cwiseAbs().maxCoeff() <= tolerance);  // omega(a) o omega(b) = omega(a+b)
        REQUIRE((ab.displacement - ba.displacement).cwiseAbs().maxCoeff() <= tolerance);   // commutative

        Lattice back = ab;
        applyControlDelta(back, directManipulation(back, {t}, -(a + b)).delta);  // omega(S, -rho)
        REQUIRE((back.displacement - original.displacement).cwiseAbs().maxCoeff() <= tolerance);

        // Multi-point manipulations compose the same way.
        std::vector<Eigen::Vector3d> params{t, test::randomParams(rng), test::randomParams(rng)};
        const Eigen::MatrixX3d c = randomDisplacements(rng, 3, 0.1 * lattice.diagonal());
        const Eigen::MatrixX3d e = randomDisplacements(rng, 3, 0.1 * lattice.diagonal());
        Lattice ce = original, together = original;
        applyControlDelta(ce, directManipulation(ce, params, c).delta);
        applyControlDelta(ce, directManipulation(ce, params, e).delta);
        applyControlDelta(together, directManipulation(together, params, c + e).delta);
        REQUIRE((ce.displacement - together.displacement).cwiseAbs().maxCoeff() <= 1e-9 * lattice.diagonal());
    }
}

TEST_CASE("direct_manipulation: h single-point steps (eq. 13-19) give the joint solution (eq. 12)", "[core]") {
    std::mt19937 rng(46);
    for (int trial = 0; trial < 60; ++trial) {
        const Lattice lattice = test::randomLattice(rng);
        const int h = test::randomInt(rng, 2, 8);
        std::vector<Eigen::Vector3d> params;
        for (int f = 0; f < h; ++f) params.push_back(test::randomParams(rng));
        const Eigen::MatrixX3d d = randomDisplacements(rng, h, 0.1 * lattice.diagonal());
        DirectManipulationData data;
        REQUIRE(precomputeDirectManipulation(lattice, params, data).ok);
        if (!data.useNormalEquations) continue;  // eq. 16 needs (R^T R)^-1
        const DirectManipulationResult joint = solveDirectManipulation(data, d);

        // Eq. 16: M = (R^T R)^-1 D; eq. 19: step q moves source q by D_q^(q) = M_q * sum R^2(t_q).
        const Eigen::MatrixXd gram = data.rt * data.rt.transpose();
        const Eigen::MatrixX3d m = gram.llt().solve(d);
        Lattice stepwise = lattice;
        for (int q = 0; q < h; ++q) {
            const Eigen::MatrixX3d step = m.row(q) * data.rt.row(q).squaredNorm();
            applyControlDelta(stepwise, directManipulation(stepwise, {params[q]}, step).delta);  // eq. 13
        }
        Lattice together = lattice;
        applyControlDelta(together, joint.delta);
        REQUIRE((stepwise.displacement - together.displacement).cwiseAbs().maxCoeff() <= 1e-9 * lattice.diagonal());
        for (int f = 0; f < h; ++f)  // eq. 15: the step displacements add up to D
            REQUIRE((displacementAt(stepwise, params[f]) - d.row(f).transpose()).norm() <= 1e-9 * lattice.diagonal());
    }
}

TEST_CASE("direct_manipulation: pinned control points never move, least norm over the free ones", "[core]") {
    std::mt19937 rng(47);
    for (int trial = 0; trial < 80; ++trial) {
        Lattice lattice = test::randomLattice(rng);
        for (auto& p : lattice.pinned) p = std::uniform_real_distribution<double>(0, 1)(rng) < 0.3;
        const int h = test::randomInt(rng, 1, 5);
        std::vector<Eigen::Vector3d> params;
        for (int f = 0; f < h; ++f) params.push_back(test::randomParams(rng));
        const Eigen::MatrixX3d d = randomDisplacements(rng, h, 0.1 * lattice.diagonal());
        const DirectManipulationResult r = directManipulation(lattice, params, d);
        for (int idx : r.delta.indices) REQUIRE_FALSE(lattice.pinned[idx]);
        const Eigen::MatrixX3d oracle = fullMinimumNorm(lattice, params, d);
        REQUIRE((dense(lattice, r.delta) - oracle).cwiseAbs().maxCoeff() <= 1e-7 * (1.0 + oracle.cwiseAbs().maxCoeff()));
        REQUIRE(r.delta.deltas.allFinite());
    }
}
