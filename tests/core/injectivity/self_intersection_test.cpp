// The triangle-mesh check (issue: "the promise holds on the mesh itself"): the engine's exact pair test and
// its BVH against an independent rational-arithmetic brute force. Sessions of strong drags checked the same
// way: tests/core/session/session_crossing_test.cpp.
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <numeric>
#include <random>
#include <set>

#include "core/deform/refinement.h"
#include "core/volume/lattice_boundary.h"
#include "core/injectivity/self_intersection.h"
#include "core/session/session.h"
#include "core/injectivity/triangle_pair.h"
#include "../cgal_meshes.h"
#include "../mesh_fixtures.h"
#include "../test_support.h"
#include "../../test_scale.h"

using namespace sculpt;
using namespace sculpt::core;

namespace {

// A soup of n small triangles (each within 0.08 x scale of a random corner of the box [0, scale]^3), every
// `weldEvery`-th sharing a corner with the one before, so shared vertices occur.
void randomSoup(std::mt19937& rng, int n, double scale, int weldEvery, Positions& positions, Triangles& triangles) {
    positions.resize(3 * n, 3);
    triangles.resize(n, 3);
    for (int t = 0; t < n; ++t) {
        const Eigen::Vector3d corner = test::randomVector(rng, 0.0, 1.0);
        for (int k = 0; k < 3; ++k) {
            positions.row(3 * t + k) = (scale * (corner + test::randomVector(rng, -0.08, 0.08))).transpose();
            triangles(t, k) = 3 * t + k;
        }
    }
    for (int t = 1; t < n; t += weldEvery) triangles(t, 0) = triangles(t - 1, 1);
}

// Random triangle pairs on a small integer grid: coplanar, touching and collinear configurations are common,
// so the exact case analysis is exercised, not just generic positions. Some share a vertex or an edge.
TEST_CASE("self_intersection: the engine's pair test agrees with an independent exact test", "[core]") {
    std::mt19937 rng(20261129);
    int intersecting = 0, sharedCases = 0;
    for (int trial = 0; trial < 20000; ++trial) {
        const int span = trial % 3 == 0 ? 2 : 4;
        std::array<Eigen::Vector3d, 6> p;
        for (auto& x : p) {
            x = Eigen::Vector3d(test::randomInt(rng, -span, span), test::randomInt(rng, -span, span), test::randomInt(rng, -span, span));
            if (trial % 5 == 1) x.z() = 0.0;  // coplanar pairs
            if (trial % 7 == 2) x *= 1e-9;    // any scale
        }
        std::array<int, 3> ia{0, 1, 2}, ib{3, 4, 5};
        const int share = trial % 4;  // 0: none, 1: a vertex, 2: an edge
        if (share == 1 || share == 2) {
            ib[0] = 0;
            p[3] = p[0];
            ++sharedCases;
        }
        if (share == 2) {
            ib[1] = 1;
            p[4] = p[1];
        }
        TriangleCorners a, b;
        for (int k = 0; k < 3; ++k) {
            a.point[k] = p[k];
            a.vertex[k] = ia[k];
            b.point[k] = p[3 + k];
            b.vertex[k] = ib[k];
        }
        const bool degenerate = ((p[1] - p[0]).cross(p[2] - p[0])).squaredNorm() == 0.0 || ((p[4] - p[3]).cross(p[5] - p[3])).squaredNorm() == 0.0;
        if (degenerate) continue;  // the reference does not define those
        const bool expected = test::detail::exactTrianglesIntersect({p[0], p[1], p[2]}, ia, {p[3], p[4], p[5]}, ib);
        INFO("trial " << trial);
        REQUIRE(trianglesIntersect(a, b) == expected);
        REQUIRE(trianglesIntersect(b, a) == expected);
        intersecting += expected;
    }
    CHECK(intersecting > 1000);  // both answers were well represented
    CHECK(sharedCases > 5000);
}

// Issue: triangle soups are not crossings. Corners at the very same position are one vertex whatever their ids:
// random pairs sharing a vertex or an edge by id give the same answer when the shared corners get ids of their
// own, and a real mesh written as a soup (three vertices per triangle) has exactly the crossings of the mesh.
TEST_CASE("self_intersection: triangles that share a position, not an id, touch as neighbours do", "[core][weld]") {
    std::mt19937 rng(20261203);
    int compared = 0, intersecting = 0;
    for (int trial = 0; trial < 20000; ++trial) {
        const int span = trial % 3 == 0 ? 2 : 4;
        std::array<Eigen::Vector3d, 6> p;
        for (auto& x : p) {
            x = Eigen::Vector3d(test::randomInt(rng, -span, span), test::randomInt(rng, -span, span), test::randomInt(rng, -span, span));
            if (trial % 5 == 1) x.z() = 0.0;
        }
        TriangleCorners a, b;
        for (int k = 0; k < 3; ++k) {
            a.point[k] = p[k];
            a.vertex[k] = k;
            b.point[k] = p[3 + k];
            b.vertex[k] = 3 + k;
        }
        const int share = 1 + trial % 2;  // a vertex or an edge, by id
        for (int k = 0; k < share; ++k) {
            b.point[k] = a.point[k];
            b.vertex[k] = a.vertex[k];
        }
        const bool byId = trianglesIntersect(a, b);
        TriangleCorners apart = b;  // the same corners, ids of their own (a soup)
        for (int k = 0; k < 3; ++k) apart.vertex[k] = 10 + k;
        INFO("trial " << trial);
        REQUIRE(trianglesIntersect(a, apart) == byId);
        REQUIRE(trianglesIntersect(apart, a) == byId);
        ++compared;
        intersecting += byId;
    }
    CHECK(compared == 20000);
    CHECK(intersecting > 500);
    for (const char* name : {"elephant.off", "cow.off"}) {
        Positions positions;
        Triangles triangles;
        std::string error;
        REQUIRE(test::loadCgalMesh(name, positions, triangles, error));
        Positions soup(3 * triangles.rows(), 3);
        Triangles soupTriangles(triangles.rows(), 3);
        for (Eigen::Index t = 0; t < triangles.rows(); ++t)
            for (int k = 0; k < 3; ++k) {
                soup.row(3 * t + k) = positions.row(triangles(t, k));
                soupTriangles(t, k) = static_cast<int>(3 * t + k);
            }
        const std::vector<TrianglePairHit> mesh = findSelfIntersections(positions, triangles);
        const std::vector<TrianglePairHit> asSoup = findSelfIntersections(soup, soupTriangles);
        INFO(name);
        REQUIRE(asSoup.size() == mesh.size());
        for (size_t h = 0; h < mesh.size(); ++h) {
            CHECK(asSoup[h].first == mesh[h].first);
            CHECK(asSoup[h].second == mesh[h].second);
        }
        Session session;
        REQUIRE(session.setMesh(soup, soupTriangles, LatticeSettings{}));
        CHECK(session.meshAsSet().intersectingPairs == static_cast<int>(mesh.size()));
    }
}

// Random soups of small triangles in a box: every intersecting pair, from the index, equals the brute force.
TEST_CASE("self_intersection: the index finds exactly the intersecting pairs", "[core]") {
    std::mt19937 rng(7);
    for (int trial = 0; trial < 12; ++trial) {
        const int n = test::randomInt(rng, 20, 600);
        const double scale = std::pow(10.0, test::randomInt(rng, -6, 6));
        Positions positions;
        Triangles triangles;
        randomSoup(rng, n, scale, 5, positions, triangles);
        const std::vector<std::pair<int, int>> expected = test::intersectingPairs(positions, triangles);
        const std::vector<TrianglePairHit> hits = findSelfIntersections(positions, triangles);
        std::vector<std::pair<int, int>> found;
        for (const TrianglePairHit& h : hits) found.emplace_back(h.first, h.second);
        INFO("trial " << trial << ", " << n << " triangles");
        REQUIRE(found == expected);
        CHECK(findSelfIntersections(positions, triangles, 1).size() == std::min<size_t>(1, expected.size()));
    }
}

// A mesh split after its index was built (refinement's rounds, refiner.cpp: edges halved, new vertices put
// anywhere): the pairs holding a halved or new triangle, through the old index, are exactly the brute force's
// pairs holding one, on random soups with welded corners and on an icosphere, over many sizes and scales.
TEST_CASE("self_intersection: the pairs of triangles split since the index was built match the brute force", "[core]") {
    std::mt19937 rng(20261207);
    int withPairs = 0;
    const int trials = test::scaledCount(24, 8);
    for (int trial = 0; trial < trials; ++trial) {
        Positions positions;
        Triangles triangles;
        const double scale = std::pow(10.0, test::randomInt(rng, -4, 4));
        if (trial % 3 == 0) {
            test::icosphere(test::randomInt(rng, 1, 3), scale, Eigen::Vector3d::Zero(), positions, triangles);
        } else {
            randomSoup(rng, test::randomInt(rng, 20, 400), scale, 4, positions, triangles);
        }
        SelfIntersectionIndex index;
        index.build(positions, triangles);
        const std::vector<TrianglePairHit> all = index.allIntersections(positions, triangles);
        const Triangles built = triangles;
        // Random edges halved, over one to three rounds; each new vertex off its edge's midpoint.
        const int rounds = test::randomInt(rng, 1, 3);
        for (int round = 0; round < rounds; ++round) {
            std::vector<EdgeSplit> splits;
            std::set<std::pair<int, int>> edges;  // each edge once a round (a split edge is gone)
            const int count = test::randomInt(rng, 1, std::max(1, static_cast<int>(triangles.rows()) / 8));
            for (int s = 0; s < count; ++s) {
                const int t = test::randomInt(rng, 0, static_cast<int>(triangles.rows()) - 1), k = test::randomInt(rng, 0, 2);
                const int a = triangles(t, k), b = triangles(t, (k + 1) % 3);
                if (edges.insert({std::min(a, b), std::max(a, b)}).second) splits.push_back({a, b});
            }
            const int first = static_cast<int>(positions.rows());
            REQUIRE(applyEdgeSplits(triangles, first, splits));
            positions.conservativeResize(first + static_cast<Eigen::Index>(splits.size()), 3);
            for (size_t s = 0; s < splits.size(); ++s)
                positions.row(first + static_cast<Eigen::Index>(s)) =
                    0.5 * (positions.row(splits[s].a) + positions.row(splits[s].b)) + scale * test::randomVector(rng, -0.1, 0.1).transpose();
        }
        std::vector<std::uint8_t> changed(static_cast<size_t>(triangles.rows()), 1);
        for (Eigen::Index t = 0; t < built.rows(); ++t) changed[static_cast<size_t>(t)] = triangles.row(t) != built.row(t);
        std::vector<std::pair<int, int>> expected;
        for (const auto& pair : test::intersectingPairs(positions, triangles))
            if (changed[static_cast<size_t>(pair.first)] || changed[static_cast<size_t>(pair.second)]) expected.push_back(pair);
        std::vector<std::pair<int, int>> found;
        for (const TrianglePairHit& hit : index.intersectionsOfChanged(positions, triangles, changed)) {
            found.emplace_back(hit.first, hit.second);
            // reported as allIntersections reports a pair: at the lower id's centroid
            Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
            for (int k = 0; k < 3; ++k) centroid += positions.row(triangles(hit.first, k)).transpose() / 3.0;
            REQUIRE((hit.where - centroid).norm() <= 1e-12 * scale);
        }
        INFO("trial " << trial << ", " << triangles.rows() << " triangles, " << built.rows() << " when built");
        REQUIRE(found == expected);
        // the unchanged pairs are the built mesh's: with them the whole brute force
        std::set<std::pair<int, int>> whole(found.begin(), found.end());
        for (const TrianglePairHit& hit : all)
            if (!changed[static_cast<size_t>(hit.first)] && !changed[static_cast<size_t>(hit.second)]) whole.insert({hit.first, hit.second});
        const std::vector<std::pair<int, int>> brute = test::intersectingPairs(positions, triangles);
        REQUIRE(std::vector<std::pair<int, int>>(whole.begin(), whole.end()) == brute);
        withPairs += !expected.empty();
    }
    CHECK(withPairs * 2 > trials);  // the splits moved enough to make new pairs in most trials
}

// Moving random vertices of a sphere: findNewIntersection reports a pair exactly when the brute force finds a
// pair after the move that was not there before; the index stays right over many successive moves.
// 150 moves in three runs of 50 (each from the undeformed sphere, with its own seed), so ctest runs them side by side.
static void runMovesAgainstBruteForce(unsigned seed, int moveCount) {
    std::mt19937 rng(seed);
    Positions positions;
    Triangles triangles;
    test::icosphere(2, 1.0, Eigen::Vector3d(0.3, 0.1, -0.2), positions, triangles);
    SelfIntersectionIndex index;
    index.build(positions, triangles);
    std::set<std::pair<int, int>> current;
    int newCount = 0;
    const int moves = test::scaledCount(moveCount, 20);
    for (int move = 0; move < moves; ++move) {
        const Positions before = positions;
        std::vector<int> moved;
        const int count = test::randomInt(rng, 1, 6);
        for (int m = 0; m < count; ++m) {
            const int v = test::randomInt(rng, 0, static_cast<int>(positions.rows()) - 1);
            if (std::find(moved.begin(), moved.end(), v) != moved.end()) continue;
            moved.push_back(v);
            positions.row(v) += test::randomVector(rng, -0.5, 0.5).transpose();
        }
        const SelfIntersectionIndex::Result result = index.findNewIntersection(positions, triangles, moved, before);
        const std::vector<std::pair<int, int>> after = test::intersectingPairs(positions, triangles);
        bool expectNew = false;
        for (const auto& pair : after) expectNew = expectNew || !current.count(pair);
        INFO("move " << move);
        REQUIRE(result.found == expectNew);
        if (result.found) {
            REQUIRE(std::find(after.begin(), after.end(), std::make_pair(result.pair.first, result.pair.second)) != after.end());
            REQUIRE_FALSE(current.count({result.pair.first, result.pair.second}));
            ++newCount;
        }
        current = std::set<std::pair<int, int>>(after.begin(), after.end());
    }
    INFO(newCount << " of " << moves << " moves made a new pair");
    CHECK(newCount * 15 > moves);  // the moves are strong enough to make new pairs often
}

TEST_CASE("self_intersection: new pairs after a move match the brute force, over many moves, part 1 of 3", "[core]") {
    runMovesAgainstBruteForce(11, 50);
}
TEST_CASE("self_intersection: new pairs after a move match the brute force, over many moves, part 2 of 3", "[core]") {
    runMovesAgainstBruteForce(12, 50);
}
TEST_CASE("self_intersection: new pairs after a move match the brute force, over many moves, part 3 of 3", "[core]") {
    runMovesAgainstBruteForce(13, 50);
}

// Random global and local steps on CGAL's real meshes (issue "Certification that decides", point 5): the check with
// its pruning (the dual traversal, and pairs at a vertex whose star is still embedded not tested) reports a new
// pair exactly when the brute force (a grid and an exact test of every near pair) finds one. Global steps move every
// vertex along smooth waves of random frequency; local ones shake the vertices near one vertex by up to a few edge
// lengths, which often crosses triangles.
TEST_CASE("self_intersection: the pruned check finds every new crossing the brute force finds, on real meshes", "[core]") {
    int newCount = 0, quietCount = 0;
    long long proven = 0, patches = 0;
    for (const char* name : {"elephant.off", "cow.off", "blobby.off"}) {
        Positions positions;
        Triangles triangles;
        std::string error;
        REQUIRE(test::loadCgalMesh(name, positions, triangles, error));
        const double diagonal = (positions.colwise().maxCoeff() - positions.colwise().minCoeff()).norm();
        double edge = 0.0;
        for (int t = 0; t < triangles.rows(); ++t) edge += (positions.row(triangles(t, 0)) - positions.row(triangles(t, 1))).norm();
        edge /= static_cast<double>(triangles.rows());
        std::mt19937 rng(2819);
        SelfIntersectionIndex index;
        index.build(positions, triangles);
        const std::vector<std::pair<int, int>> initial = test::intersectingPairs(positions, triangles);
        std::set<std::pair<int, int>> current(initial.begin(), initial.end());
        const int steps = test::scaledCount(30, 12);
        for (int step = 0; step < steps; ++step) {
            const Positions before = positions;
            std::vector<int> moved;
            const bool global = step % 2 == 0;
            if (global) {
                const double amplitude = std::exp(std::uniform_real_distribution<double>(std::log(1e-3), std::log(3e-2))(rng)) * diagonal;
                const Eigen::Vector3d frequency = test::randomVector(rng, 1.0, 12.0) / diagonal, phase = test::randomVector(rng, 0.0, 6.3);
                for (int v = 0; v < positions.rows(); ++v) {
                    const Eigen::Vector3d x = positions.row(v).transpose();
                    positions.row(v) += amplitude * Eigen::RowVector3d(std::sin(frequency.y() * x.y() + phase.x()), std::sin(frequency.z() * x.z() + phase.y()),
                                                                        std::sin(frequency.x() * x.x() + phase.z()));
                    moved.push_back(v);
                }
            } else {
                const int centre = test::randomInt(rng, 0, static_cast<int>(positions.rows()) - 1);
                const double radius = std::uniform_real_distribution<double>(1.0, 4.0)(rng) * edge;
                const double shake = std::uniform_real_distribution<double>(0.1, 2.0)(rng) * edge;
                for (int v = 0; v < positions.rows(); ++v)
                    if ((before.row(v) - before.row(centre)).norm() <= radius) {
                        positions.row(v) += shake * test::randomVector(rng, -1.0, 1.0).transpose();
                        moved.push_back(v);
                    }
            }
            const SelfIntersectionIndex::Result result = index.findNewIntersection(positions, triangles, moved, before);
            proven += result.pairsProvenByStar;
            patches += result.patchesProven;
            const std::vector<std::pair<int, int>> after = test::intersectingPairs(positions, triangles);
            bool expectNew = false;
            for (const auto& pair : after) expectNew = expectNew || !current.count(pair);
            INFO(name << ", step " << step << (global ? " (global)" : " (local)") << ", " << moved.size() << " vertices moved");
            REQUIRE(result.found == expectNew);
            if (result.found) {
                REQUIRE(std::find(after.begin(), after.end(), std::make_pair(result.pair.first, result.pair.second)) != after.end());
                REQUIRE_FALSE(current.count({result.pair.first, result.pair.second}));
                ++newCount;
            } else {
                ++quietCount;
            }
            current = std::set<std::pair<int, int>>(after.begin(), after.end());
        }
    }
    INFO(newCount << " steps made a new pair, " << quietCount << " did not; " << proven << " pairs proven by their stars, "
                   << patches << " patches proven whole");
    CHECK(newCount >= 5);
    CHECK(quietCount >= 5);
    CHECK(proven > 0);
    CHECK(patches > 0);
}

// The patch certificate (a hierarchy node proven a height field as a whole) on open sheets, where the root itself has
// a boundary and can be proven: random grid sheets of several sizes, jittered in the plane so their triangles and
// boundaries are irregular, then moved by smooth waves (height fields stay), by folds that lay a band of the sheet
// back over itself, by coils whose ends overlap (every triangle positive, the boundary winding twice), and by shakes of
// a few vertices; and rippled coils of a strip, whose overlapping ends only the boundary's winding reveals. After every move the check reports a new pair exactly when the
// brute force finds one, and whole patches are proven on the smooth moves.
TEST_CASE("self_intersection: sheets proven whole as height fields, and folded ones not, against the brute force", "[core]") {
    std::mt19937 rng(20261202);
    int newCount = 0, quietCount = 0;
    long long patchTriangles = 0;
    for (const int size : {9, 16, 23, 40}) {
        Positions positions((size + 1) * (size + 1), 3);
        for (int i = 0; i <= size; ++i)
            for (int j = 0; j <= size; ++j) {
                const double jitter = 0.3 / size;
                const double x = double(i) / size + jitter * std::uniform_real_distribution<double>(-1, 1)(rng);
                const double y = double(j) / size + jitter * std::uniform_real_distribution<double>(-1, 1)(rng);
                positions.row(i * (size + 1) + j) << x, y, 0.1 * x * y + 0.05 * x * x;  // curved: few coplanar pairs
            }
        Triangles triangles(2 * size * size, 3);
        for (int i = 0, t = 0; i < size; ++i)
            for (int j = 0; j < size; ++j) {
                const int a = i * (size + 1) + j, b = a + 1, c = a + size + 1, d = c + 1;
                const bool flip = (i + j) % 3 == 0;  // both diagonals occur
                if (flip) triangles.row(t++) << a, c, b, triangles.row(t++) << b, c, d;
                else triangles.row(t++) << a, d, b, triangles.row(t++) << a, c, d;
            }
        SelfIntersectionIndex index;
        index.build(positions, triangles);
        const Positions rest = positions;
        std::set<std::pair<int, int>> current;
        for (int step = 0; step < 24; ++step) {
            // Each step's shape is made from the flat sheet; what moved is what differs from the step before.
            const Positions before = positions;
            positions = rest;
            const int kind = step % 4;
            if (kind == 0) {  // smooth waves: still a height field over the plane
                const double amplitude = std::uniform_real_distribution<double>(0.01, 0.2)(rng);
                const Eigen::Vector3d frequency = test::randomVector(rng, 1.0, 9.0), phase = test::randomVector(rng, 0.0, 6.3);
                for (int v = 0; v < positions.rows(); ++v)
                    positions(v, 2) = amplitude * std::sin(frequency.x() * rest(v, 0) + phase.x()) * std::cos(frequency.y() * rest(v, 1) + phase.y());
            } else if (kind == 1) {  // a fold: the band beyond a line is turned over about it, laid just above the rest
                const double at = std::uniform_real_distribution<double>(0.3, 0.7)(rng);
                const double lift = std::uniform_real_distribution<double>(-0.02, 0.02)(rng);
                for (int v = 0; v < positions.rows(); ++v)
                    if (rest(v, 0) > at) positions.row(v) << 2.0 * at - rest(v, 0), rest(v, 1), lift * (rest(v, 0) - at);
            } else if (kind == 3) {  // a coil: the sheet wound 1.1 to 1.4 turns round an axis, every triangle still
                                     // positive along it, the ends overlapping and crossing, or a little apart
                const double turns = std::uniform_real_distribution<double>(1.1, 1.4)(rng);
                const bool apart = step % 8 != 3;
                for (int v = 0; v < positions.rows(); ++v) {
                    const double angle = 2.0 * M_PI * turns * rest(v, 0), radius = 0.4 + 0.5 * rest(v, 1);
                    // Crossing: a ripple of 7.5 waves a turn, so the overlapping ends meet transversally (not coplanar).
                    positions.row(v) << radius * std::cos(angle), radius * std::sin(angle), apart ? 0.02 * angle : 0.01 * std::sin(7.5 * angle);
                }
            } else {  // shakes of a few vertices by up to two edge lengths
                for (int m = 0; m < 4; ++m)
                    positions.row(test::randomInt(rng, 0, static_cast<int>(positions.rows()) - 1)) +=
                        (2.0 / size) * test::randomVector(rng, -1.0, 1.0).transpose();
            }
            std::vector<int> moved;
            for (int v = 0; v < positions.rows(); ++v)
                if (positions.row(v) != before.row(v)) moved.push_back(v);
            const SelfIntersectionIndex::Result result = index.findNewIntersection(positions, triangles, moved, before);
            if (kind == 0) patchTriangles += result.trianglesInProvenPatches;
            const std::vector<std::pair<int, int>> after = test::intersectingPairs(positions, triangles);
            bool expectNew = false;
            for (const auto& pair : after) expectNew = expectNew || !current.count(pair);
            INFO(size << "^2 sheet, step " << step << " (kind " << kind << "), " << moved.size() << " vertices moved, "
                      << result.patchesProven << " patches proven");
            REQUIRE(result.found == expectNew);
            if (result.found) {
                REQUIRE(std::find(after.begin(), after.end(), std::make_pair(result.pair.first, result.pair.second)) != after.end());
                ++newCount;
            } else {
                ++quietCount;
            }
            current = std::set<std::pair<int, int>>(after.begin(), after.end());
        }
    }
    // A strip wound 1.1 to 1.5 turns into a rippled coil: every triangle keeps its orientation along the axis, so only
    // the boundary's winding (twice round the overlap) tells that the ends cross.
    for (int trial = 0; trial < 6; ++trial) {
        const int columns = 240 + 40 * trial, rows = 3;
        Positions positions((columns + 1) * (rows + 1), 3);
        for (int i = 0; i <= columns; ++i)
            for (int j = 0; j <= rows; ++j) positions.row(i * (rows + 1) + j) << double(i) / columns, 0.2 * j / rows, 0.0;
        Triangles triangles(2 * columns * rows, 3);
        for (int i = 0, t = 0; i < columns; ++i)
            for (int j = 0; j < rows; ++j) {
                const int a = i * (rows + 1) + j, b = a + 1, c = a + rows + 1, d = c + 1;
                triangles.row(t++) << a, c, d, triangles.row(t++) << a, d, b;
            }
        SelfIntersectionIndex index;
        index.build(positions, triangles);
        const Positions before = positions;
        const double turns = std::uniform_real_distribution<double>(1.1, 1.5)(rng);
        std::vector<int> moved;
        for (int v = 0; v < positions.rows(); ++v) {
            const double angle = 2.0 * M_PI * turns * before(v, 0), radius = 0.5 + before(v, 1);
            positions.row(v) << radius * std::cos(angle), radius * std::sin(angle), 0.01 * std::sin(7.5 * angle);
            moved.push_back(v);
        }
        const SelfIntersectionIndex::Result result = index.findNewIntersection(positions, triangles, moved, before);
        INFO("coil of " << turns << " turns, " << columns << " columns: " << result.patchesProven << " patches proven");
        REQUIRE_FALSE(test::intersectingPairs(positions, triangles).empty());
        REQUIRE(result.found);
        ++newCount;
    }
    INFO(newCount << " moves made a new pair, " << quietCount << " did not; " << patchTriangles << " triangles in proven patches");
    CHECK(newCount >= 8);
    CHECK(quietCount >= 8);
    CHECK(patchTriangles > 0);
}

}  // namespace

// trianglesWithin (the load's near contacts: a sliver folded over its neighbour a file's precision above its face)
// on pairs built at a known distance d apart from what they share, at random shapes, orientations and scales: a
// corner hovering d above the other's face (the pairs share nothing, or a corner), and an edge passing d over the
// other's face and across its edges (closest there edge to edge). Within a tolerance iff d is at most it (d at
// half and twice the tolerance); and a pair that intersects is not asked about (trianglesIntersect decides it).
TEST_CASE("self_intersection: trianglesWithin finds a pair within a tolerance of each other exactly when the distance apart from what they share is within it", "[core]") {
    std::mt19937 rng(1205);
    int within = 0, apart = 0;
    for (int trial = 0; trial < 600; ++trial) {
        const double scale = std::pow(10.0, test::randomVector(rng, -3.0, 3.0).x());
        TriangleCorners a, b;
        for (int k = 0; k < 3; ++k) {
            a.point[static_cast<size_t>(k)] = scale * test::randomVector(rng, -1.0, 1.0);
            a.vertex[static_cast<size_t>(k)] = k;
        }
        const Eigen::Vector3d normal = (a.point[1] - a.point[0]).cross(a.point[2] - a.point[0]);
        // (a triangle with a fair shape: its smallest height at least 10% of its longest edge)
        double longest = 0.0;
        for (int k = 0; k < 3; ++k) longest = std::max(longest, (a.point[static_cast<size_t>((k + 1) % 3)] - a.point[static_cast<size_t>(k)]).norm());
        if (normal.norm() / longest < 0.1 * longest) continue;
        const Eigen::Vector3d n = normal.normalized();
        const double tolerance = scale * std::pow(10.0, test::randomVector(rng, -7.0, -3.0).x());
        const bool near = trial % 2 == 0;
        const double d = near ? 0.5 * tolerance : 2.0 * tolerance;
        // A point inside a (barycentric weights at least 0.15).
        Eigen::Vector3d w = test::randomVector(rng, 0.15, 1.0);
        w /= w.sum();
        if (w.minCoeff() < 0.1) continue;
        const Eigen::Vector3d inside = w[0] * a.point[0] + w[1] * a.point[1] + w[2] * a.point[2];
        const Eigen::Vector3d up = scale * (n + 0.3 * test::randomVector(rng, -1.0, 1.0).cross(n));  // away from a
        const int kind = trial / 2 % 3;
        for (int k = 0; k < 3; ++k) b.vertex[static_cast<size_t>(k)] = 10 + k;
        if (kind == 0) {  // a corner of b hovers over a's face; b shares nothing
            b.point = {inside + d * n, inside + d * n + up + 0.5 * scale * n.unitOrthogonal(), inside + d * n + up - 0.5 * scale * n.unitOrthogonal()};
        } else if (kind == 1) {  // b shares a's corner 0 and folds over a: its corner 1 hovers over a's face
            b.point = {a.point[0], inside + d * n, inside + d * n + up};
            b.vertex[0] = 0;
        } else {  // an edge of b parallel to a, d above it, running across a from outside to outside
            const Eigen::Vector3d across = n.cross(a.point[2] - a.point[1]).normalized();
            const Eigen::Vector3d start = inside + d * n - 3.0 * longest * across, end = inside + d * n + 3.0 * longest * across;
            b.point = {start, end, 0.5 * (start + end) + up};
        }
        INFO("trial " << trial << " kind " << kind << " scale " << scale << " tolerance " << tolerance << " d " << d);
        REQUIRE_FALSE(trianglesIntersect(a, b));
        CHECK(trianglesWithin(a, b, tolerance) == near);
        CHECK(trianglesWithin(b, a, tolerance) == near);
        (near ? within : apart) += 1;
    }
    CHECK(within > 150);
    CHECK(apart > 150);
}

// nearestOnTriangle (the grabbed point's triangle and weights under a brush): random triangles at scales 1e-3 to
// 1e3, fair ones and slivers, random points over the face, beyond its edges and corners, above and below. The
// weights are checked against the characterisation of the nearest point of a convex set, independent of how it
// is found: q (the weights' point) is nearest p iff (p - q) . (x - q) <= 0 for every point x of the triangle,
// which, linear in x, is for its three corners. And no point of a 40 x 40 barycentric grid on the triangle is nearer.
// A triangle with no area has no weights (not finite).
TEST_CASE("self_intersection: nearestOnTriangle's weights give the triangle's point nearest any point", "[core]") {
    std::mt19937 rng(20261207);
    int onFace = 0, onEdge = 0, onCorner = 0;
    for (int trial = 0; trial < 3000; ++trial) {
        const double scale = std::pow(10.0, test::randomVector(rng, -3.0, 3.0).x());
        std::array<Eigen::Vector3d, 3> t;
        for (Eigen::Vector3d& x : t) x = scale * test::randomVector(rng, -1.0, 1.0);
        if (trial % 4 == 1) t[2] = 0.5 * (t[0] + t[1]) + 1e-3 * scale * test::randomVector(rng, -1.0, 1.0);  // a sliver
        const Eigen::Vector3d centre = (t[0] + t[1] + t[2]) / 3.0;
        const Eigen::Vector3d p = centre + 2.0 * scale * test::randomVector(rng, -1.0, 1.0);
        const Eigen::Vector3d w = nearestOnTriangle(p, t[0], t[1], t[2]);
        INFO("trial " << trial << " scale " << scale << " weights " << w.transpose());
        REQUIRE(w.allFinite());
        CHECK(w.minCoeff() >= 0.0);
        CHECK(std::abs(w.sum() - 1.0) <= 1e-12);
        const Eigen::Vector3d q = w[0] * t[0] + w[1] * t[1] + w[2] * t[2];
        const double span = std::max({(t[1] - t[0]).norm(), (t[2] - t[0]).norm(), (t[2] - t[1]).norm()});
        for (const Eigen::Vector3d& x : t) CHECK((p - q).dot(x - q) <= 1e-9 * span * (span + (p - q).norm()));
        double grid = INFINITY;
        for (int i = 0; i <= 40; ++i)
            for (int j = 0; i + j <= 40; ++j) grid = std::min(grid, (p - (t[0] + i / 40.0 * (t[1] - t[0]) + j / 40.0 * (t[2] - t[0]))).norm());
        CHECK((p - q).norm() <= grid + 1e-12 * scale);
        const int zeros = (w.array() == 0.0).count();
        (zeros == 0 ? onFace : zeros == 1 ? onEdge : onCorner) += 1;
    }
    CHECK(onFace > 100);
    CHECK(onEdge > 300);
    CHECK(onCorner > 300);
    // No area: collinear corners, coinciding ones.
    const Eigen::Vector3d a(0.0, 0.0, 0.0), b(1.0, 2.0, 3.0);
    CHECK_FALSE(nearestOnTriangle(Eigen::Vector3d(1.0, 0.0, 0.0), a, b, 2.0 * b).allFinite());
    CHECK_FALSE(nearestOnTriangle(Eigen::Vector3d(1.0, 0.0, 0.0), a, a, b).allFinite());
    CHECK_FALSE(nearestOnTriangle(Eigen::Vector3d(1.0, 0.0, 0.0), b, b, b).allFinite());
}
