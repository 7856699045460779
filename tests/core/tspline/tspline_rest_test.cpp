// The rest volume of weighted T-splines (tspline_rest.cpp; Song & Yang 2005, seed 002, sec. 4-5): octree volumes
// over random point clouds with sec. 4's weights at 1:1 to 1000:1, balanced, never fold (det dQ0/dt sampled through
// evaluate(), independently of the proof), the weights fall off by their step, folding or mirrored placements are
// refused naming the element, and the paper's two weight levels, which do fold, get a reduced ratio that does not.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <random>

#include "core/tspline/tspline_volume.h"
#include "../mesh_fixtures.h"

using namespace sculpt;
using namespace sculpt::core;

namespace {

double uniform(std::mt19937& rng, double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); }

// `n` points of a random shape: a thick shell, a curved sheet, two blobs or a thin rod (kind 0-3), placed at random.
Positions randomCloud(std::mt19937& rng, int kind, int n) {
    Positions points(n, 3);
    const Eigen::Vector3d shift(uniform(rng, -5, 5), uniform(rng, -5, 5), uniform(rng, -5, 5));
    const Eigen::Vector3d blob(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
    for (int i = 0; i < n; ++i) {
        Eigen::Vector3d x(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
        if (kind == 0) x = x.normalized() * uniform(rng, 0.4, 0.6);
        if (kind == 1) x = Eigen::Vector3d(x[0], x[1], 0.3 * x[0] * x[0]);
        if (kind == 2) x = (i % 3 == 0 ? blob : -blob) * 0.5 + 0.2 * x;
        if (kind == 3) x = Eigen::Vector3d(x[0], 0.05 * x[1], 0.05 * x[2]);
        points.row(i) = (x + shift).transpose();
    }
    return points;
}

// The least det dQ0/dt over `samples` random parameters, by evaluate() (not the proof's Bezier forms), relative to
// the box's volume (1 for the identity map of the box).
double leastSampledDeterminant(const TSplineVolume& volume, std::mt19937& rng, int samples) {
    const Eigen::Vector3d size = volume.restBounds().sizes();
    double least = std::numeric_limits<double>::infinity();
    for (int k = 0; k < samples; ++k) {
        const Eigen::Vector3d t(uniform(rng, 0, 1), uniform(rng, 0, 1), uniform(rng, 0, 1));
        Eigen::Vector3d q;
        Eigen::Matrix3d d;
        volume.evaluate(volume.restControlPoints(), t, q, &d);
        least = std::min(least, d.determinant() / size.prod());
    }
    return least;
}

}  // namespace

TEST_CASE("tspline: octree rest volumes over random point clouds do not fold at weight ratios 1 to 1000", "[tspline]") {
    std::mt19937 rng(1301);
    const double ratios[4] = {1.0, 10.0, 100.0, 1000.0};
    for (int trial = 0; trial < 14; ++trial) {
        TSplineOctreeSettings settings;
        settings.octree.depth = 2 + trial % 4;
        settings.octree.rootCount = {1 + trial % 2, 1, 1 + trial / 2 % 2};
        settings.weightRatio = ratios[trial / 2 % 4];
        const Positions points = randomCloud(rng, trial % 4, settings.octree.depth == 5 ? 300 : 200 + 100 * (trial % 5));
        std::shared_ptr<const TSplineVolume> volume;
        TSplineWeightOutcome outcome;
        const Status made = makeOctreeTSplineVolume(points, settings, volume, nullptr, &outcome);
        INFO("trial " << trial << ", depth " << settings.octree.depth << ", ratio " << settings.weightRatio << ": " << made.message << outcome.message);
        REQUIRE(made);
        // The balanced weights keep the requested ratio (the point of the balance); the proof passed, so the
        // volume exists and no sample may fold.
        REQUIRE_FALSE(outcome.ratioReduced);
        REQUIRE(outcome.weightRatio == settings.weightRatio);
        REQUIRE(*std::max_element(volume->controlWeights().begin(), volume->controlWeights().end()) == std::max(1.0, settings.weightRatio));
        REQUIRE(leastSampledDeterminant(*volume, rng, settings.octree.depth == 5 ? 20000 : 5000) > 0.0);
        REQUIRE(checkTSplineRestVolume(*volume));
    }
}

TEST_CASE("tspline: sec. 4 weights fall off by the weight step from the non-empty cells' control points", "[tspline]") {
    Positions positions;
    Triangles triangles;
    test::icosphere(2, 1.0, Eigen::Vector3d(0.3, -0.2, 0.1), positions, triangles);
    for (const double step : {10.0, 3.0, 1e6}) {
        TSplineOctreeSettings settings;
        settings.octree.depth = 3;
        settings.weightRatio = 100.0;
        settings.weightStep = step;
        std::shared_ptr<const TSplineVolume> volume;
        REQUIRE(makeOctreeTSplineVolume(positions, settings, volume));
        const std::vector<double>& w = volume->controlWeights();
        int heavy = 0, light = 0;
        for (double x : w) {
            REQUIRE(x >= 1.0);
            REQUIRE(x <= 100.0);
            heavy += x == 100.0;
            light += x == 1.0;
        }
        REQUIRE(heavy > 0);
        REQUIRE(light > 0);
        // Neighbours in the control net within the step; with a step past the ratio, the paper's two levels.
        for (const auto& e : volume->controlNetEdgeList()) {
            const double ratio = w[static_cast<size_t>(e[0])] / w[static_cast<size_t>(e[1])];
            REQUIRE(std::max(ratio, 1.0 / ratio) <= std::min(step, 100.0) * (1.0 + 1e-12));
        }
        if (step >= 100.0)
            for (double x : w) REQUIRE((x == 1.0 || x == 100.0));
    }
    // The helper on its own: heavy below light falls the other way.
    std::shared_ptr<const TSplineVolume> volume;
    REQUIRE(makeOctreeTSplineVolume(positions, TSplineOctreeSettings{}, volume));
    std::vector<std::uint8_t> flags(static_cast<size_t>(volume->controlPointCount()), 0);
    flags[0] = 1;
    const std::vector<double> w = balancedTSplineWeights(volume->basis(), flags, 0.01, 1.0, 10.0);
    REQUIRE(w[0] == 0.01);
    for (double x : w) REQUIRE((x >= 0.01 && x <= 1.0));
}

TEST_CASE("tspline: folding or mirrored control points are refused, naming the element", "[tspline]") {
    // 2 x 2 x 2 cells, one of them subdivided: T-junctions on its faces.
    TLattice lattice;
    lattice.rootCount = {2, 2, 2};
    for (int z = 0; z < 2; ++z)
        for (int y = 0; y < 2; ++y)
            for (int x = 0; x < 2; ++x) lattice.cells.push_back(TLatticeCell{0, {x, y, z}});
    REQUIRE(finishTLattice(lattice));
    TLattice finer;
    REQUIRE(subdivideTLatticeCells(lattice, {7}, true, finer));
    std::shared_ptr<const TSplineVolume> placed;
    REQUIRE(makeTSplineVolumeInBox(finer, Eigen::AlignedBox3d(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones()), {}, placed));
    TSplineRestCheckStats stats;
    REQUIRE(checkTSplineRestVolume(*placed, {}, &stats));
    REQUIRE(stats.elementsChecked == placed->chunkCount());
    REQUIRE(stats.elementsByJacobianHull + stats.elementsBySubdivision == placed->chunkCount());
    REQUIRE(checkTSplineRestVolume(*placed, {0, placed->chunkCount() - 1}));
    REQUIRE_FALSE(checkTSplineRestVolume(*placed, {placed->chunkCount()}));
    // The anchor at the centre vertex (0.5, 0.5, 0.5) pushed through its +x neighbour: the volume folds round it.
    const TSplineBasis& basis = placed->basis();
    int centre = -1;
    for (int s = 0; s < basis.anchorCount(); ++s) {
        const auto& p = basis.lattice.vertices[static_cast<size_t>(basis.anchors[static_cast<size_t>(s)].vertex)];
        if (basis.anchors[static_cast<size_t>(s)].boundaryCopy == 0 && 2 * p[0] == basis.lattice.fineCount[0] &&
            2 * p[1] == basis.lattice.fineCount[1] && 2 * p[2] == basis.lattice.fineCount[2])
            centre = s;
    }
    REQUIRE(centre >= 0);
    Positions folded = placed->restControlPoints();
    folded(centre, 0) += 3.0;
    std::shared_ptr<const TSplineVolume> volume;
    Status s = TSplineVolume::make(placed->sharedBasis(), folded, placed->controlWeights(), volume);
    INFO(s.message);
    REQUIRE_FALSE(s);
    REQUIRE(s.message.find("folds or is mirrored: det dQ0/dt = -") != std::string::npos);
    REQUIRE(s.message.find("in element ") != std::string::npos);
    REQUIRE(s.message.find("(T-lattice cell ") != std::string::npos);
    // The reported point does fold: its parameters, read back from the message, give det <= 0 by evaluate().
    const size_t at = s.message.find("at t = (");
    REQUIRE(at != std::string::npos);
    Eigen::Vector3d t;
    REQUIRE(std::sscanf(s.message.c_str() + at, "at t = (%lf, %lf, %lf)", &t[0], &t[1], &t[2]) == 3);
    // note: the message rounds t to 4 digits; the fold region round the moved point is far wider than that.
    Eigen::Vector3d q;
    Eigen::Matrix3d d;
    placed->evaluate(folded, t, q, &d);
    REQUIRE(d.determinant() <= 0.0);
    // Sampled, the moved point folds the volume too (the proof did not invent it).
    double least = 1e300;
    std::mt19937 rng(1302);
    for (int k = 0; k < 20000; ++k) {
        const Eigen::Vector3d u(uniform(rng, 0, 1), uniform(rng, 0, 1), uniform(rng, 0, 1));
        placed->evaluate(folded, u, q, &d);
        least = std::min(least, d.determinant());
    }
    REQUIRE(least < 0.0);
    // Mirrored (every x negated): det < 0 everywhere, the lowest element is named.
    Positions mirrored = placed->restControlPoints();
    mirrored.col(0) *= -1.0;
    s = TSplineVolume::make(placed->sharedBasis(), mirrored, placed->controlWeights(), volume);
    REQUIRE_FALSE(s);
    REQUIRE(s.message.find("in element 0 (T-lattice cell 0") != std::string::npos);
    // Random weights up to 10:1 between neighbours on a valid placement: still proven (or refused, never crashing);
    // whatever is accepted does not fold where sampled.
    for (int trial = 0; trial < 6; ++trial) {
        std::vector<double> weights(static_cast<size_t>(placed->controlPointCount()));
        for (double& w : weights) w = std::exp(uniform(rng, -1, 1) * std::log(3.0));
        if (!TSplineVolume::make(placed->sharedBasis(), placed->restControlPoints(), weights, volume)) continue;
        REQUIRE(leastSampledDeterminant(*volume, rng, 5000) > 0.0);
    }
}

TEST_CASE("tspline: the paper's two weight levels fold at 1000:1, and the ratio is reduced to one that does not", "[tspline]") {
    Positions positions;
    Triangles triangles;
    test::icosphere(3, 1.0, Eigen::Vector3d(0.3, -0.2, 0.1), positions, triangles);
    TSplineOctreeSettings settings;
    settings.octree.depth = 4;
    settings.weightRatio = 1000.0;
    settings.weightStep = 1e9;  // no balance: 1000 next to 1
    std::shared_ptr<const TSplineVolume> volume;
    TSplineWeightOutcome outcome;
    REQUIRE(makeOctreeTSplineVolume(positions, settings, volume, nullptr, &outcome));
    INFO(outcome.message);
    REQUIRE(outcome.ratioReduced);
    REQUIRE(outcome.weightRatio > 1.0);
    REQUIRE(outcome.weightRatio < 1000.0);
    REQUIRE(outcome.message.find("weight ratio 1000:1 reduced to ") == 0);
    REQUIRE(std::abs(*std::max_element(volume->controlWeights().begin(), volume->controlWeights().end()) - outcome.weightRatio) <=
            1e-12 * outcome.weightRatio);
    std::mt19937 rng(1303);
    REQUIRE(leastSampledDeterminant(*volume, rng, 20000) > 0.0);
    // The same lattice with the balance keeps the whole ratio.
    settings.weightStep = 10.0;
    REQUIRE(makeOctreeTSplineVolume(positions, settings, volume, nullptr, &outcome));
    REQUIRE_FALSE(outcome.ratioReduced);
    REQUIRE(outcome.weightRatio == 1000.0);
}

TEST_CASE("tspline: subdividing cells keeps which side is heavy, for weight ratios above and below 1", "[tspline]") {
    std::mt19937 rng(1317);
    for (int trial = 0; trial < 6; ++trial) {
        Positions positions;
        Triangles triangles;
        const double radius = uniform(rng, 0.5, 2.0);
        const Eigen::Vector3d centre(uniform(rng, -2, 2), uniform(rng, -2, 2), uniform(rng, -2, 2));
        test::icosphere(2, radius, centre, positions, triangles);
        TSplineOctreeSettings settings;
        settings.octree.depth = 2 + trial % 2;
        settings.weightRatio = (trial % 3 == 0) ? 0.1 : (trial % 3 == 1 ? 0.5 : 20.0);
        std::shared_ptr<const TSplineVolume> volume;
        REQUIRE(makeOctreeTSplineVolume(positions, settings, volume));
        const std::vector<double>& before = volume->controlWeights();
        const auto [lo, hi] = std::minmax_element(before.begin(), before.end());
        REQUIRE(*hi / *lo == Approx(std::max(settings.weightRatio, 1.0 / settings.weightRatio)));
        // A random handful of cells, then the finer volume's weight at a mesh vertex's nearest anchor must be
        // the non-empty side's (the heavy one when the ratio is above 1, the light one below).
        std::vector<int> cells;
        for (int k = 0; k < 3; ++k)
            cells.push_back(std::uniform_int_distribution<int>(0, static_cast<int>(volume->lattice().cells.size()) - 1)(rng));
        std::sort(cells.begin(), cells.end());
        cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
        std::shared_ptr<const TSplineVolume> finer;
        TSplineWeightOutcome outcome;
        INFO("trial " << trial << ", ratio " << settings.weightRatio);
        REQUIRE(subdivideTSplineVolume(*volume, cells, true, positions, finer, &outcome));
        REQUIRE(finer->lattice().cells.size() > volume->lattice().cells.size());
        const std::vector<double>& after = finer->controlWeights();
        // Light weight 1, so the non-empty cells' points weigh the ratio (or the reduced one): on a sphere they
        // lie near its surface, and the points of the other extreme weight (the far ones) lie away from it.
        const double nonEmptySide = outcome.ratioReduced ? outcome.weightRatio : settings.weightRatio;
        double nearSum = 0.0, farSum = 0.0;
        int nearCount = 0, farCount = 0;
        for (int s = 0; s < finer->controlPointCount(); ++s) {
            const double offSurface = std::abs((finer->restControlPoints().row(s).transpose() - centre).norm() - radius);
            if (after[static_cast<size_t>(s)] == Approx(nonEmptySide)) nearSum += offSurface, ++nearCount;
            if (after[static_cast<size_t>(s)] == Approx(1.0)) farSum += offSurface, ++farCount;
        }
        REQUIRE(nearCount > 0);
        REQUIRE(farCount > 0);
        REQUIRE(nearSum / nearCount < 0.5 * (farSum / farCount));
        const auto [flo, fhi] = std::minmax_element(after.begin(), after.end());
        REQUIRE(*flo == Approx(std::min(1.0, nonEmptySide)));
        REQUIRE(*fhi == Approx(std::max(1.0, nonEmptySide)));
    }
}
