#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "core/volume/embedding.h"
#include "../test_support.h"

using namespace sculpt;
using namespace sculpt::core;

namespace {

// Independent scalar evaluation through the public single-point path.
Positions referencePositions(const Lattice& lattice, const Positions& rest) {
    Positions out = rest;
    for (Eigen::Index v = 0; v < rest.rows(); ++v) {
        Eigen::Vector3d t;
        if (restParameters(lattice, rest.row(v).transpose(), t)) out.row(v) += displacementAt(lattice, t).transpose();
    }
    return out;
}

// A random lattice with a random displacement (up to 5% of its box), rational with weights in [0.5, 2] if asked.
Lattice displacedLattice(std::mt19937& rng, bool mixedDegrees, bool rational) {
    Positions points;
    Lattice lattice = test::randomLattice(rng, mixedDegrees, &points);
    test::randomDisplacement(rng, lattice, 0.05);
    if (rational) {
        for (double& w : lattice.weights) w = std::uniform_real_distribution<double>(0.5, 2.0)(rng);
        lattice.rational = true;
    }
    return lattice;
}

}  // namespace

TEST_CASE("embedding: kernel evaluation equals the scalar NURBS evaluation", "[core]") {
    std::mt19937 rng(31);
    for (int trial = 0; trial < 40; ++trial) {
        const Lattice lattice = displacedLattice(rng, /*mixedDegrees=*/trial % 3 == 0, /*rational=*/trial % 4 == 1);
        // Points inside, on faces and outside the box.
        const int n = test::randomInt(rng, 1, 3000);
        const Eigen::Vector3d margin = 0.1 * (lattice.boxMax - lattice.boxMin);
        Positions rest = test::randomPoints(rng, n, lattice.boxMin - margin, lattice.boxMax + margin);
        rest.row(0) = lattice.boxMax.transpose();
        const Embedding embedding = embedVertices(lattice, rest);
        Positions positions = rest;
        evaluateAll(lattice, embedding, positions);
        const Positions reference = referencePositions(lattice, rest);
        // The kernel's power form about each cell's centre rounds as the basis form does (about 4e-16 of the
        // diagonal here at every degree); powers of the local coordinate itself lost 2.5e-13 at degree 5.
        REQUIRE((positions - reference).cwiseAbs().maxCoeff() <= 1e-14 * lattice.diagonal());
        for (Eigen::Index v = 0; v < n; ++v) {
            Eigen::Vector3d t;
            if (!restParameters(lattice, rest.row(v).transpose(), t)) REQUIRE(positions.row(v) == rest.row(v));
        }
    }
}

TEST_CASE("embedding: sparse update equals full evaluation, untouched vertices stay bitwise", "[core]") {
    std::mt19937 rng(32);
    for (int trial = 0; trial < 30; ++trial) {
        Lattice lattice = test::randomLattice(rng, trial % 2 == 0);
        const Positions rest = test::randomPoints(rng, 5000, lattice.boxMin, lattice.boxMax);
        const Embedding embedding = embedVertices(lattice, rest);
        Positions positions = rest;
        // Change a few random control points, update sparsely.
        std::vector<int> changed;
        for (int c = 0; c < test::randomInt(rng, 1, 4); ++c) {
            const int idx = test::randomInt(rng, 0, lattice.controlPointCount() - 1);
            lattice.displacement.row(idx) += 0.05 * lattice.diagonal() * test::randomVector(rng, -1, 1).transpose();
            changed.push_back(idx);
        }
        std::vector<int> moved;
        evaluateCells(lattice, embedding, cellsInfluencedBy(lattice, changed), positions, &moved);
        Positions full = rest;
        evaluateAll(lattice, embedding, full);
        REQUIRE(positions == full);  // same kernel, same arithmetic: identical
        std::vector<char> isMoved(rest.rows(), 0);
        for (int v : moved) isMoved[v] = 1;
        for (Eigen::Index v = 0; v < rest.rows(); ++v)
            if (!isMoved[v]) REQUIRE(positions.row(v) == rest.row(v));
    }
}

TEST_CASE("embedding: every embedded vertex appears once, grouped by cell", "[core]") {
    std::mt19937 rng(33);
    for (int trial = 0; trial < 10; ++trial) {
        const Lattice lattice = test::randomLattice(rng);
        const Positions rest = test::randomPoints(rng, 2000, lattice.boxMin, lattice.boxMax);
        const Embedding embedding = embedVertices(lattice, rest);
        REQUIRE(embedding.insideCount() == 2000);
        std::vector<int> sorted = embedding.order;
        std::sort(sorted.begin(), sorted.end());
        for (int v = 0; v < 2000; ++v) REQUIRE(sorted[v] == v);
        REQUIRE(embedding.cellStart.back() == 2000);
    }
}

TEST_CASE("embedding: the incremental update equals a full re-evaluation after the change", "[core]") {
    std::mt19937 rng(34);
    IncrementScratch scratch;
    for (int trial = 0; trial < 40; ++trial) {
        Lattice lattice = test::randomLattice(rng, trial % 3 == 0);
        const Positions rest = test::randomPoints(rng, 4000, lattice.boxMin, lattice.boxMax);
        const Embedding embedding = embedVertices(lattice, rest);
        test::randomDisplacement(rng, lattice, 0.02);
        Positions positions = rest;
        evaluateAll(lattice, embedding, positions);
        for (int round = 0; round < 3; ++round) {
            std::vector<int> ids;
            for (int c = 0; c < test::randomInt(rng, 1, 70); ++c) ids.push_back(test::randomInt(rng, 0, lattice.controlPointCount() - 1));
            std::sort(ids.begin(), ids.end());
            ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
            Positions deltas(static_cast<Eigen::Index>(ids.size()), 3);
            for (Eigen::Index c = 0; c < deltas.rows(); ++c) deltas.row(c) = 0.03 * lattice.diagonal() * test::randomVector(rng, -1, 1).transpose();
            const double sign = round == 2 ? -1.0 : 1.0;
            for (size_t c = 0; c < ids.size(); ++c) lattice.displacement.row(ids[c]) += sign * deltas.row(static_cast<Eigen::Index>(c));
            std::vector<int> moved;
            const Positions before = positions;
            evaluateIncrement(lattice, embedding, ids, deltas, sign, positions, scratch, &moved);
            Positions full = rest;
            evaluateAll(lattice, embedding, full);
            REQUIRE((positions - full).cwiseAbs().maxCoeff() <= 1e-13 * lattice.diagonal());
            std::vector<char> isMoved(rest.rows(), 0);
            for (int v : moved) isMoved[v] = 1;
            for (Eigen::Index v = 0; v < rest.rows(); ++v)
                if (!isMoved[v]) REQUIRE(positions.row(v) == before.row(v));  // untouched: bitwise unchanged
        }
    }
}

// The benchmark's cell-order evaluation (eval_full_8_in_cell_order) must compute what evaluateAll does, only
// stored in cell order: row e equals the mesh-order row of embedding.order[e], bit for bit.
TEST_CASE("embedding: the cell-order evaluation equals evaluateAll, row for row in cell order", "[core]") {
    std::mt19937 rng(57);
    for (int trial = 0; trial < 30; ++trial) {
        const Lattice lattice = displacedLattice(rng, /*mixedDegrees=*/trial % 5 == 0, /*rational=*/trial % 4 == 1);
        const int n = test::randomInt(rng, 1, 3000);
        const Positions rest = test::randomPoints(rng, n, lattice.boxMin, lattice.boxMax);
        const Embedding embedding = embedVertices(lattice, rest);
        Positions positions = rest;
        evaluateAll(lattice, embedding, positions);
        std::vector<double> inCellOrder(3 * static_cast<size_t>(embedding.insideCount()), NAN);
        evaluateAllInCellOrder(lattice, embedding, inCellOrder.data());
        const bool mixed = lattice.degree[0] != lattice.degree[1] || lattice.degree[0] != lattice.degree[2];
        for (int e = 0; e < embedding.insideCount() && mixed; ++e) REQUIRE(std::isnan(inCellOrder[3 * static_cast<size_t>(e)]));
        if (mixed) continue;  // documented: nothing written
        for (int e = 0; e < embedding.insideCount(); ++e)
            for (int c = 0; c < 3; ++c)
                REQUIRE(inCellOrder[3 * static_cast<size_t>(e) + static_cast<size_t>(c)] == positions(embedding.order[static_cast<size_t>(e)], c));
    }
}

namespace {

// A random point outside the lattice's box, at most `reach` x its diagonal beyond it.
Eigen::Vector3d pointOutside(std::mt19937& rng, const Lattice& lattice, double reach) {
    for (;;) {
        const Eigen::Vector3d margin = Eigen::Vector3d::Constant(reach * lattice.diagonal());
        const Eigen::Vector3d x = test::randomPoints(rng, 1, lattice.boxMin - margin, lattice.boxMax + margin).row(0).transpose();
        if ((x.array() < lattice.boxMin.array()).any() || (x.array() > lattice.boxMax.array()).any()) return x;
    }
}

Eigen::Vector3d clampedParameters(const Lattice& lattice, const Eigen::Vector3d& x) {
    return ((x - lattice.boxMin).cwiseQuotient(lattice.boxMax - lattice.boxMin)).cwiseMax(0.0).cwiseMin(1.0);
}

}  // namespace

TEST_CASE("embedding: the collar continues the lattice beyond its box, exact for affine motions, continuous at its faces, and inverted by collarPreimage", "[core]") {
    std::mt19937 rng(77);
    for (int trial = 0; trial < 30; ++trial) {
        INFO("trial " << trial);
        Lattice lattice = test::randomLattice(rng, trial % 2 == 0);
        // At rest the collar is the identity, bit for bit.
        for (int k = 0; k < 20; ++k) {
            const Eigen::Vector3d x = pointOutside(rng, lattice, 0.3);
            CHECK(collarPoint(lattice, clampedParameters(lattice, x), x) == x);
        }
        // An affine motion of every control point (a turn, a scale, a shear, a shift): the B-spline volume
        // reproduces it in the box (its control points rest on the Greville points), and the collar outside.
        Eigen::Matrix3d a;
        for (int r = 0; r < 3; ++r) a.row(r) = 0.3 * test::randomVector(rng, -1.0, 1.0).transpose();
        a += Eigen::Matrix3d::Identity();
        const Eigen::Vector3d b = 0.2 * lattice.diagonal() * test::randomVector(rng, -1.0, 1.0);
        const Positions rest = controlPointPositions(lattice);
        for (int idx = 0; idx < lattice.controlPointCount(); ++idx)
            lattice.displacement.row(idx) = (a * rest.row(idx).transpose() + b - rest.row(idx).transpose()).transpose();
        for (int k = 0; k < 40; ++k) {
            const Eigen::Vector3d x = pointOutside(rng, lattice, 0.3);
            CHECK((collarPoint(lattice, clampedParameters(lattice, x), x) - (a * x + b)).norm() <= 1e-12 * lattice.diagonal());
        }
        // Any deformation: on the box's faces the collar is the volume's FFD, and just off them it is close.
        test::randomDisplacement(rng, lattice, 0.05);
        for (int k = 0; k < 40; ++k) {
            Eigen::Vector3d t = test::randomVector(rng, 0.0, 1.0);
            const int axis = test::randomInt(rng, 0, 2);
            t[axis] = test::randomInt(rng, 0, 1);
            const Eigen::Vector3d onFace = restPoint(lattice, t);
            const Eigen::Vector3d ffd = onFace + displacementAt(lattice, t);
            CHECK((collarPoint(lattice, t, onFace) - ffd).norm() <= 1e-13 * lattice.diagonal());
            Eigen::Vector3d off = onFace;
            off[axis] += (t[axis] == 0.0 ? -1.0 : 1.0) * 1e-7 * lattice.diagonal();
            CHECK((collarPoint(lattice, clampedParameters(lattice, off), off) - ffd).norm() <= 1e-5 * lattice.diagonal());
        }
        // The inverse: every collar point within 15% of the diagonal beyond the box comes back (a deformation
        // small enough to be injective on any of these lattices, whose spans can be 1/18 of a thin box).
        test::randomDisplacement(rng, lattice, 0.002);
        for (int k = 0; k < 40; ++k) {
            const Eigen::Vector3d x = pointOutside(rng, lattice, 0.15);
            const Eigen::Vector3d y = collarPoint(lattice, clampedParameters(lattice, x), x);
            Eigen::Vector3d back;
            INFO("x " << x.transpose() << ", degrees " << lattice.degree[0] << lattice.degree[1] << lattice.degree[2]);
            REQUIRE(collarPreimage(lattice, y, back));
            CHECK((back - x).norm() <= 1e-12 * lattice.diagonal());
        }
        // Not a collar point: a point the volume carries from inside its box has no preimage outside it here.
        const Eigen::Vector3d inside = restPoint(lattice, Eigen::Vector3d::Constant(0.5));
        Eigen::Vector3d back;
        CHECK(!collarPreimage(lattice, inside + displacementAt(lattice, Eigen::Vector3d::Constant(0.5)), back));
    }
}

TEST_CASE("embedding: a collar's vertices are evaluated with the box's, fully and incrementally, and listed by cell", "[core]") {
    std::mt19937 rng(78);
    IncrementScratch scratch;
    for (int trial = 0; trial < 20; ++trial) {
        INFO("trial " << trial);
        Lattice lattice = test::randomLattice(rng, trial % 3 == 0);
        const Eigen::Vector3d margin = Eigen::Vector3d::Constant(0.1 * lattice.diagonal());
        const Positions rest = test::randomPoints(rng, 3000, lattice.boxMin - margin, lattice.boxMax + margin);
        Embedding embedding = embedVertices(lattice, rest);
        embedCollar(lattice, rest, embedding);
        REQUIRE(embedding.insideCount() + embedding.collarCount() == rest.rows());
        REQUIRE(embedding.collarCount() > 0);
        test::randomDisplacement(rng, lattice, 0.02);
        Positions positions = rest;
        evaluateAll(lattice, embedding, positions);
        // Independently: the FFD inside, the collar point outside.
        for (Eigen::Index v = 0; v < rest.rows(); ++v) {
            const Eigen::Vector3d x = rest.row(v).transpose();
            Eigen::Vector3d t;
            const Eigen::Vector3d expected = restParameters(lattice, x, t) ? Eigen::Vector3d(x + displacementAt(lattice, t))
                                                                           : collarPoint(lattice, clampedParameters(lattice, x), x);
            REQUIRE((positions.row(v).transpose() - expected).norm() <= 1e-13 * lattice.diagonal());
        }
        // A change of a few control points: the incremental update is the full one, the vertices it reports are
        // the vertices of the cells it reaches (collar included), and the others are bitwise unchanged.
        std::vector<int> ids;
        for (int c = 0; c < test::randomInt(rng, 1, 30); ++c) ids.push_back(test::randomInt(rng, 0, lattice.controlPointCount() - 1));
        std::sort(ids.begin(), ids.end());
        ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
        Positions deltas(static_cast<Eigen::Index>(ids.size()), 3);
        for (Eigen::Index c = 0; c < deltas.rows(); ++c) deltas.row(c) = 0.03 * lattice.diagonal() * test::randomVector(rng, -1, 1).transpose();
        for (size_t c = 0; c < ids.size(); ++c) lattice.displacement.row(ids[c]) += deltas.row(static_cast<Eigen::Index>(c));
        const Positions before = positions;
        std::vector<int> moved;
        evaluateIncrement(lattice, embedding, ids, deltas, 1.0, positions, scratch, &moved);
        Positions full = rest;
        evaluateAll(lattice, embedding, full);
        CHECK((positions - full).cwiseAbs().maxCoeff() <= 1e-13 * lattice.diagonal());
        std::vector<int> listed;
        appendVerticesOfCells(embedding, cellsInfluencedBy(lattice, ids), listed);
        std::sort(moved.begin(), moved.end());
        std::sort(listed.begin(), listed.end());
        CHECK(moved == listed);
        std::vector<char> isMoved(rest.rows(), 0);
        for (int v : moved) isMoved[v] = 1;
        for (Eigen::Index v = 0; v < rest.rows(); ++v)
            if (!isMoved[v]) REQUIRE(positions.row(v) == before.row(v));
    }
}
