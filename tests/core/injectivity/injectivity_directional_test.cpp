// The directional bound (injectivity.h, cellsLeftByDirectionalBound): sound against dense evaluation of det J,
// and it proves the brush's pull fields that the cone test cannot.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>

#include "core/deform/brush_field.h"
#include "core/injectivity/injectivity.h"
#include "core/volume/lattice.h"

using namespace sculpt::core;

namespace {

// The least det J over a grid of points in every cell (an upper bound of the true minimum).
double sampledMinimum(const Lattice& lattice, int cell, int perAxis) {
    const std::array<int, 3> spans = lattice.spans();
    const std::array<int, 3> ijk{cell % spans[0], (cell / spans[0]) % spans[1], cell / (spans[0] * spans[1])};
    double least = INFINITY;
    for (int k = 0; k <= perAxis; ++k)
        for (int j = 0; j <= perAxis; ++j)
            for (int i = 0; i <= perAxis; ++i) {
                const std::array<int, 3> at{i, j, k};
                Eigen::Vector3d t;
                for (int a = 0; a < 3; ++a) {
                    const double lo = lattice.axes[a].breaks[static_cast<size_t>(ijk[a])], hi = lattice.axes[a].breaks[static_cast<size_t>(ijk[a]) + 1];
                    t[a] = lo + (hi - lo) * (0.02 + 0.96 * at[a] / perAxis);
                }
                least = std::min(least, jacobianDeterminant(lattice, t));
            }
    return least;
}

}  // namespace

TEST_CASE("directional bound: a cell it proves has det J > 0 at every sampled point, and a cell it leaves is not parallel or dips", "[injectivity]") {
    std::mt19937 rng(20261202);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    int proven = 0, left = 0;
    for (int trial = 0; trial < 60; ++trial) {
        LatticeSettings settings;
        const int degree = 1 + trial % 3;
        const int count = degree + 2 + trial % 4;
        settings.resolution = {count, count + 1, count};
        settings.degree = {degree, degree, degree};
        Lattice lattice;
        REQUIRE(makeLatticeInBox(settings, Eigen::Vector3d(-1, -2, 0), Eigen::Vector3d(1 + trial % 3, 1, 2), lattice));
        // A parallel displacement of random size along one random direction (every few trials, two directions).
        const Eigen::Vector3d e = Eigen::Vector3d(unit(rng), unit(rng), unit(rng)).normalized();
        const Eigen::Vector3d other = Eigen::Vector3d(unit(rng), unit(rng), unit(rng)).normalized();
        const double size = 0.1 + 0.5 * (trial % 5);
        for (int p = 0; p < lattice.controlPointCount(); ++p) {
            if (inOuterLayers(lattice, p, 1)) continue;
            const Eigen::Vector3d d = (trial % 4 == 3 && p % 3 == 0 ? other : e) * size * unit(rng);
            lattice.displacement.row(p) = d.transpose();
        }
        std::vector<int> cells(static_cast<size_t>(lattice.cellCount()));
        for (int c = 0; c < lattice.cellCount(); ++c) cells[static_cast<size_t>(c)] = c;
        const std::vector<int> remaining = cellsLeftByDirectionalBound(lattice, cells);
        for (int c : cells) {
            if (std::binary_search(remaining.begin(), remaining.end(), c)) {
                ++left;
                continue;
            }
            ++proven;
            INFO("trial " << trial << " cell " << c);
            CHECK(sampledMinimum(lattice, c, 4) > 0.0);
        }
        // Cells with a fold found by sampling are never proven.
        for (int c : cells)
            if (sampledMinimum(lattice, c, 4) <= 0.0) CHECK(std::binary_search(remaining.begin(), remaining.end(), c));
    }
    CHECK(proven > 100);
    CHECK(left > 100);
}

TEST_CASE("directional bound: the brush's pull field is proven injective for every falloff at pulls of 0.1 to 3 radii in any direction", "[injectivity][brush]") {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    for (int trial = 0; trial < 72; ++trial) {
        const double radius = 0.2 + 0.1 * (trial % 4);
        const double length = radius * (0.1 + 0.12 * (trial % 24));
        BrushPull pull{Eigen::Vector3d(unit(rng), unit(rng), unit(rng)), Eigen::Vector3d(unit(rng), unit(rng), unit(rng)).normalized() * length};
        RegionLattice region;
        REQUIRE(pullRegionLattice({pull}, radius, region));
        Lattice lattice;
        REQUIRE(makeLatticeInBox(region.settings, region.boxMin, region.boxMax, lattice));
        // The region is turned to the pull (its w axis is the pull's direction), and no larger than the capsule.
        REQUIRE(turnBoxLattice(lattice, region.axes));
        CHECK((region.axes.row(2).transpose() - pull.pull.normalized()).norm() <= 1e-12);
        CHECK(region.boxMax[2] - region.boxMin[2] <= length + 2.0 * kBrushReach * radius + 4.0 * radius / kBrushFieldSpansPerRadius);
        pinAllBut(lattice, region.freePoints);
        ControlDelta delta;
        double residual = 1.0;
        // Smooth, then medium (steep at the rim, across the pull) and sharp (a rounded peak).
        const BrushFalloff falloff = static_cast<BrushFalloff>(trial / 24);
        REQUIRE(brushFieldDelta(lattice, {pull}, radius, falloff, delta, residual));
        CHECK(residual <= 1e-12 * radius);
        applyControlDelta(lattice, delta, 1.0);
        std::vector<int> cells(static_cast<size_t>(lattice.cellCount()));
        for (int c = 0; c < lattice.cellCount(); ++c) cells[static_cast<size_t>(c)] = c;
        INFO("trial " << trial << " pull " << length / radius << " radii, falloff " << brushFalloffName(falloff));
        const std::vector<int> remaining = cellsLeftByDirectionalBound(lattice, cells);
        CHECK(remaining.empty());
        // Independently: det J sampled on a grid, and the exact test, agree that nothing folds.
        double least = INFINITY;
        for (int i = 0; i < 12; ++i)
            for (int j = 0; j < 12; ++j)
                for (int k = 0; k < 12; ++k) least = std::min(least, jacobianDeterminant(lattice, Eigen::Vector3d(i + 0.5, j + 0.5, k + 0.5) / 12.0));
        CHECK(least > 0.0);
        CHECK(checkInjectivityExact(lattice).verdict == InjectivityVerdict::Certified);
        // The grabbed point lands on its target.
        Eigen::Vector3d t;
        REQUIRE(restParameters(lattice, pull.source, t));
        CHECK((pull.source + displacementAt(lattice, t) - (pull.source + pull.pull)).norm() <= 1e-12 * radius);
    }
}
