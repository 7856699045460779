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
        // (Odd trials: along a box axis, as the brush's layers are, where the bound reads the divided differences.)
        const Eigen::Vector3d random = Eigen::Vector3d(unit(rng), unit(rng), unit(rng)).normalized();
        const Eigen::Vector3d e = trial % 2 ? Eigen::Vector3d((trial % 4 == 1 ? 1.0 : -1.0) * Eigen::Vector3d::Unit(trial / 2 % 3)) : random;
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
        // Smooth, then medium (steep at the rim, across the pull: 12 knot spans a radius) and sharp (a rounded peak).
        const BrushFalloff falloff = static_cast<BrushFalloff>(trial / 24);
        REQUIRE(pullRegionLattice({pull}, radius, region, brushFieldSpansPerRadius(falloff)));
        Lattice lattice;
        REQUIRE(makeLatticeInBox(region.settings, region.boxMin, region.boxMax, lattice));
        // The region is turned to the pull (its w axis is the pull's direction), and no larger than the capsule.
        REQUIRE(turnBoxLattice(lattice, region.axes));
        CHECK((region.axes.row(2).transpose() - pull.pull.normalized()).norm() <= 1e-12);
        CHECK(region.boxMax[2] - region.boxMin[2] <= length + 2.0 * kBrushReach * radius + 4.0 * radius / brushFieldSpansPerRadius(falloff));
        pinAllBut(lattice, region.freePoints);
        ControlDelta delta;
        double residual = 1.0;
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

TEST_CASE("directional bound: the widening ahead of a long pull is a radial map out from the pull's line, carried in two layers each proven injective", "[injectivity][brush]") {
    std::mt19937 rng(17);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    int widened = 0;
    for (int trial = 0; trial < 24; ++trial) {
        const double radius = 0.2 + 0.1 * (trial % 3);
        const double length = radius * (0.6 + 0.1 * trial);  // 0.6 to 2.9 radii
        const BrushFalloff falloff = static_cast<BrushFalloff>(trial % 3);
        const BrushPull pull{Eigen::Vector3d(unit(rng), unit(rng), unit(rng)), Eigen::Vector3d(unit(rng), unit(rng), unit(rng)).normalized() * length};
        const BrushWidening widening = brushWidening(pull, radius, falloff);
        INFO("trial " << trial << " pull " << length / radius << " radii, falloff " << brushFalloffName(falloff));
        if (widening.empty()) continue;
        ++widened;
        // The radial map: l + E(l, z) rises with l by at least 0.4 per unit, keeps the line (E <= 2 l), and is the
        // identity behind the source, beyond 0.85 radius from the line and beyond 1.25 radius ahead.
        for (int z = -4; z <= 30; ++z) {
            const double axial = z * radius / 20.0;
            double previous = 0.0;
            for (int l = 1; l <= 60; ++l) {
                const double lateral = l * radius / 40.0, out = widening.widenedLateral(lateral, axial);
                CHECK(out >= lateral);
                CHECK(out <= 3.0 * lateral * (1.0 + 1e-12));
                CHECK(out - previous >= 0.4 * radius / 40.0 * (1.0 - 1e-9));
                if (axial <= 0.0 || axial >= 1.25 * radius || lateral >= 0.85 * radius) CHECK(out - lateral <= 1e-12 * radius);
                previous = out;
            }
        }
        // Its two layers in the pull's region: each proven by the directional bound, det J sampled > 0, and the
        // two together near the radial map (within 0.04-0.09 radius: the quasi-interpolant's error).
        RegionLattice region;
        REQUIRE(pullRegionLattice({pull}, radius, region, brushFieldSpansPerRadius(falloff)));
        std::array<Lattice, 2> layers;
        for (int axis = 0; axis < 2; ++axis) {
            Lattice& lattice = layers[static_cast<size_t>(axis)];
            REQUIRE(makeLatticeInBox(region.settings, region.boxMin, region.boxMax, lattice));
            REQUIRE(turnBoxLattice(lattice, region.axes));
            pinAllBut(lattice, region.freePoints);
            ControlDelta delta;
            REQUIRE(brushWideningDelta(lattice, widening, axis, delta));
            CHECK(!delta.empty());
            applyControlDelta(lattice, delta, 1.0);
            std::vector<int> cells(static_cast<size_t>(lattice.cellCount()));
            for (int c = 0; c < lattice.cellCount(); ++c) cells[static_cast<size_t>(c)] = c;
            CHECK(cellsLeftByDirectionalBound(lattice, cells).empty());
            double least = INFINITY;
            for (int i = 0; i < 10; ++i)
                for (int j = 0; j < 10; ++j)
                    for (int k = 0; k < 10; ++k) least = std::min(least, jacobianDeterminant(lattice, Eigen::Vector3d(i + 0.5, j + 0.5, k + 0.5) / 10.0));
            CHECK(least > 0.0);
        }
        const Eigen::Vector3d e = pull.pull.normalized(), u = e.unitOrthogonal(), v = e.cross(u);
        double worst = 0.0;
        for (int sample = 0; sample < 200; ++sample) {
            // Around the line ahead of the source, where the widening moves points.
            const Eigen::Vector3d x = pull.source + radius * (unit(rng) * u + unit(rng) * v + 0.6 * (unit(rng) + 1.0) * e);
            Eigen::Vector3d y = x;
            for (const Lattice& layer : layers) y = layerImage(layer, y);
            const Eigen::Vector3d offset = x - pull.source;
            const double z = offset.dot(e);
            const Eigen::Vector3d across = offset - z * e;
            const double l = across.norm();
            const Eigen::Vector3d radial = pull.source + z * e + (l > 0.0 ? widening.widenedLateral(l, z) / l : 1.0) * across;
            worst = std::max(worst, (y - radial).norm());
            CHECK(std::abs((y - x).dot(e)) <= 1e-12 * radius);  // nothing moves along the pull
        }
        CHECK(worst <= 0.12 * radius);  // the quasi-interpolant's error: the map has kinks where its bounds take over
    }
    CHECK(widened >= 12);
}
