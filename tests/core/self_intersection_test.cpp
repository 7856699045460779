// The triangle-mesh check (issue: "the promise holds on the mesh itself"): the engine's exact pair test and
// its BVH against an independent rational-arithmetic brute force, and sessions of strong drags whose every
// result is checked for new crossing pairs.
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <numeric>
#include <random>
#include <set>

#include "core/lattice_boundary.h"
#include "core/self_intersection.h"
#include "core/session.h"
#include "core/triangle_pair.h"
#include "cgal_meshes.h"
#include "mesh_fixtures.h"
#include "test_support.h"
#include "../test_scale.h"

using namespace sculpt;
using namespace sculpt::core;

namespace {

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
        CHECK(session.initialIntersectingPairs() == static_cast<int>(mesh.size()));
    }
}

// Random soups of small triangles in a box: every intersecting pair, from the index, equals the brute force.
TEST_CASE("self_intersection: the index finds exactly the intersecting pairs", "[core]") {
    std::mt19937 rng(7);
    for (int trial = 0; trial < 12; ++trial) {
        const int n = test::randomInt(rng, 20, 600);
        const double scale = std::pow(10.0, test::randomInt(rng, -6, 6));
        Positions positions(3 * n, 3);
        Triangles triangles(n, 3);
        for (int t = 0; t < n; ++t) {
            const Eigen::Vector3d corner = test::randomVector(rng, 0.0, 1.0);
            for (int k = 0; k < 3; ++k) {
                positions.row(3 * t + k) = (scale * (corner + test::randomVector(rng, -0.08, 0.08))).transpose();
                triangles(t, k) = 3 * t + k;
            }
        }
        // Weld a few corners so shared vertices occur.
        for (int t = 1; t < n; t += 5) triangles(t, 0) = triangles(t - 1, 1);
        const std::vector<std::pair<int, int>> expected = test::intersectingPairs(positions, triangles);
        const std::vector<TrianglePairHit> hits = findSelfIntersections(positions, triangles);
        std::vector<std::pair<int, int>> found;
        for (const TrianglePairHit& h : hits) found.emplace_back(h.first, h.second);
        INFO("trial " << trial << ", " << n << " triangles");
        REQUIRE(found == expected);
        CHECK(findSelfIntersections(positions, triangles, 1).size() == std::min<size_t>(1, expected.size()));
    }
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

// issue 9 item 1's sequence: a unit icosphere, cubic 8^3 lattice with one pinned layer, the exact (or conic)
// test, drags each pulling a random vertex 30-90% of the way toward the vertex opposite it.
struct PinchRun {
    int applied = 0, rejected = 0, subdivided = 0;
};

PinchRun runPinch(int levels, unsigned seed, int drags, InjectivityMode mode, int pinLayers, bool checkEveryOp) {
    Positions positions;
    Triangles triangles;
    test::icosphere(levels, 1.0, Eigen::Vector3d::Zero(), positions, triangles);
    LatticeSettings settings;
    settings.padding = 0.05;
    settings.pinLayers = pinLayers;
    Session session;
    REQUIRE(session.setMesh(positions, triangles, settings).ok);
    session.setInjectivity({mode, 6});
    REQUIRE(session.initialIntersectingPairs() == 0);
    std::mt19937 rng(seed);
    const int pool = std::min<int>(162, static_cast<int>(positions.rows()));
    PinchRun run;
    for (int d = 0; d < drags; ++d) {
        const int k = test::randomInt(rng, 0, pool - 1);
        int opposite = 0;
        double best = INFINITY;
        for (int i = 0; i < pool; ++i) {
            const double s = (positions.row(i) + positions.row(k)).squaredNorm();
            if (s < best) best = s, opposite = i;
        }
        const double s = std::uniform_real_distribution<double>(0.3, 0.9)(rng);
        const Eigen::Vector3d target = (positions.row(k) + (positions.row(opposite) - positions.row(k)) * s).transpose();
        OpReport report;
        REQUIRE(session.dragVertex(k, target, report).ok);
        if (report.status == OpStatus::Applied) {
            ++run.applied;
            run.subdivided += report.subSteps > 1;
            if (report.subSteps > 1) REQUIRE_FALSE(report.refusedBy.empty());  // the report says why
        } else {
            REQUIRE(report.status == OpStatus::Rejected);
            REQUIRE_FALSE(report.refusedBy.empty());
            REQUIRE(report.reason.find("nothing was changed") != std::string::npos);
            ++run.rejected;
        }
        if (checkEveryOp || d + 1 == drags) {
            INFO("levels " << levels << " seed " << seed << " drag " << d << ": " << report.reason);
            REQUIRE(test::selfIntersectingPairs(session.positions(), triangles) == 0);
        }
    }
    return run;
}

TEST_CASE("session: pinch drags never leave a crossing triangle pair, at several densities and seeds", "[core]") {
    int applied = 0, rejected = 0;
    for (int levels : {2, 3})
        for (unsigned seed : {1u, 2u, 3u}) {
            const PinchRun run = runPinch(levels, seed, 20, InjectivityMode::Exact, 1, levels == 2);
            applied += run.applied;
            rejected += run.rejected;
        }
    const PinchRun conic = runPinch(3, 4, 20, InjectivityMode::Conic, 0, false);  // conic test, free boundary
    applied += conic.applied;
    CHECK(applied > 30);  // the check refuses only what it must
    CHECK(rejected > 0);  // and these drags are strong enough to need it
}

TEST_CASE("session: pinch drags on 2562 vertices leave no crossing pair", "[core]") {
    runPinch(4, 1, 20, InjectivityMode::Exact, 1, false);
}

// A mesh that already self-intersects (two spheres through each other): reported once at load, counted as the
// brute force counts, and never held against an edit; only new crossing pairs are refused.
// The neighbourhood of a mesh's load crossings, by its own search: for each triangle, its ring distance (sharing
// a corner) from a triangle of a crossing pair, up to SelfIntersectionIndex::kContactRings; -1 beyond.
static std::vector<int> loadContactRings(const Positions& positions, const Triangles& triangles,
                                         const std::vector<std::pair<int, int>>& atLoad) {
    const int nt = static_cast<int>(triangles.rows());
    std::vector<std::vector<int>> ofVertex(static_cast<size_t>(positions.rows()));
    for (int t = 0; t < nt; ++t)
        for (int k = 0; k < 3; ++k) ofVertex[static_cast<size_t>(triangles(t, k))].push_back(t);
    std::vector<int> ring(static_cast<size_t>(nt), -1);
    std::vector<int> frontier;
    for (const auto& [x, y] : atLoad)
        for (int t : {x, y})
            if (ring[static_cast<size_t>(t)] < 0) ring[static_cast<size_t>(t)] = 0, frontier.push_back(t);
    for (int r = 1; r <= SelfIntersectionIndex::kContactRings; ++r) {
        std::vector<int> next;
        for (int t : frontier)
            for (int k = 0; k < 3; ++k)
                for (int n : ofVertex[static_cast<size_t>(triangles(t, k))])
                    if (ring[static_cast<size_t>(n)] < 0) ring[static_cast<size_t>(n)] = r, next.push_back(n);
        frontier = std::move(next);
    }
    return ring;
}

// Crossings at load never count against an edit; they may shift to neighbouring triangles (within two rings of
// the load's crossing triangles, as a contact of an assembly's parts does), never appear elsewhere.
TEST_CASE("session: crossings a mesh was loaded with are reported and never count against an edit", "[core]") {
    Positions a, b;
    Triangles ta, tb;
    test::icosphere(2, 1.0, Eigen::Vector3d::Zero(), a, ta);
    test::icosphere(2, 0.8, Eigen::Vector3d(1.2, 0.1, 0.0), b, tb);
    Positions positions(a.rows() + b.rows(), 3);
    positions << a, b;
    Triangles triangles(ta.rows() + tb.rows(), 3);
    triangles << ta, (tb.array() + static_cast<int>(a.rows())).matrix();
    const std::vector<std::pair<int, int>> initial = test::intersectingPairs(positions, triangles);
    REQUIRE(initial.size() > 20);
    Session session;
    REQUIRE(session.setMesh(positions, triangles, {}).ok);
    session.setInjectivity({InjectivityMode::Conic, 3});
    CHECK(session.initialIntersectingPairs() == static_cast<int>(initial.size()));
    std::mt19937 rng(5);
    const std::vector<int> ring = loadContactRings(positions, triangles, initial);
    std::set<std::pair<int, int>> current(initial.begin(), initial.end());
    int applied = 0;
    for (int d = 0; d < 40; ++d) {
        const int v = test::randomInt(rng, 0, static_cast<int>(positions.rows()) - 1);
        OpReport report;
        REQUIRE(session.dragVertex(v, session.positions().row(v).transpose() + 0.15 * test::randomVector(rng, -1, 1), report).ok);
        applied += report.status == OpStatus::Applied;
        const std::vector<std::pair<int, int>> now = test::intersectingPairs(session.positions(), triangles);
        INFO("drag " << d << ": " << report.reason);
        for (const auto& pair : now) {
            if (current.count(pair)) continue;
            // New: only the load contact shifted, both triangles in its neighbourhood.
            REQUIRE(ring[static_cast<size_t>(pair.first)] >= 0);
            REQUIRE(ring[static_cast<size_t>(pair.second)] >= 0);
        }
        current = std::set<std::pair<int, int>>(now.begin(), now.end());
    }
    CHECK(applied > 20);  // the crossings it came with did not block the edits
}

// A coarse sphere squeezed by hundreds of random drags: after every one, no crossing pair.
TEST_CASE("session: a coarse icosphere squeezed by hundreds of random drags never self-intersects", "[core]") {
    Positions positions;
    Triangles triangles;
    test::icosphere(1, 1.0, Eigen::Vector3d(0.1, 0.0, -0.1), positions, triangles);  // 42 vertices, 80 triangles
    Session session;
    LatticeSettings settings;
    settings.resolution = {5, 5, 5};
    REQUIRE(session.setMesh(positions, triangles, settings).ok);
    session.setInjectivity({InjectivityMode::Conic, 4});
    std::mt19937 rng(99);
    int applied = 0;
    for (int d = 0; d < 300; ++d) {
        const int v = test::randomInt(rng, 0, static_cast<int>(positions.rows()) - 1);
        const Eigen::Vector3d from = session.positions().row(v).transpose();
        // Squeeze: toward the centre and across, by up to the radius.
        const Eigen::Vector3d target = from - std::uniform_real_distribution<double>(0.2, 1.6)(rng) * (from - Eigen::Vector3d(0.1, 0.0, -0.1)) +
                                       test::randomVector(rng, -0.2, 0.2);
        OpReport report;
        REQUIRE(session.dragVertex(v, target, report).ok);
        applied += report.status == OpStatus::Applied;
        INFO("drag " << d << ": " << report.reason);
        REQUIRE(test::selfIntersectingPairs(session.positions(), triangles) == 0);
    }
    CHECK(applied > 50);
}

// A flat slab in a free lattice (no pinned layer), bent by its control points in growing arcs of the same
// length until its ends pass each other: det J > 0 holds everywhere, but past a full turn the lattice would
// overlap itself. The bend stops where the ends meet; the lattice boundary and the mesh never overlap.
TEST_CASE("session: a slab lattice bent until its ends meet stops before they overlap", "[core]") {
    // A 4 x 0.4 x 0.1 slab of 40 x 4 quads, both faces.
    Positions positions(2 * 41 * 5, 3);
    std::vector<std::array<int, 3>> tris;
    for (int side = 0; side < 2; ++side)
        for (int j = 0; j <= 4; ++j)
            for (int i = 0; i <= 40; ++i) positions.row(side * 205 + j * 41 + i) << -2.0 + 0.1 * i, -0.2 + 0.1 * j, side ? 0.05 : -0.05;
    for (int side = 0; side < 2; ++side)
        for (int j = 0; j < 4; ++j)
            for (int i = 0; i < 40; ++i) {
                const int a = side * 205 + j * 41 + i, b = a + 1, c = a + 42, d = a + 41;
                if (side) tris.push_back({a, b, c}), tris.push_back({a, c, d});
                else tris.push_back({a, c, b}), tris.push_back({a, d, c});
            }
    Triangles triangles(static_cast<Eigen::Index>(tris.size()), 3);
    for (size_t t = 0; t < tris.size(); ++t) triangles.row(static_cast<Eigen::Index>(t)) << tris[t][0], tris[t][1], tris[t][2];

    for (InjectivityMode mode : {InjectivityMode::Conic, InjectivityMode::Exact}) {
        Session session;
        LatticeSettings settings;
        settings.resolution = {16, 2, 2};
        settings.degree = {2, 1, 1};
        settings.padding = 0.01;
        REQUIRE(session.setMesh(positions, triangles, settings).ok);
        session.setInjectivity({mode, 6});
        const Lattice rest = session.lattice();
        const double length = rest.boxMax.x() - rest.boxMin.x();
        std::vector<int> ids(static_cast<size_t>(rest.controlPointCount()));
        std::iota(ids.begin(), ids.end(), 0);
        bool stopped = false;
        double turned = 0.0;
        for (int step = 1; step <= 60 && !stopped; ++step) {
            // The slab's mid-plane rolled onto a circle of radius length / angle, keeping its length.
            const double angle = step * 2.4 * M_PI / 60;
            const double radius = length / angle;
            Eigen::MatrixX3d to(rest.controlPointCount(), 3);
            for (int idx = 0; idx < rest.controlPointCount(); ++idx) {
                const Eigen::Vector3d p = rest.restControlPoint(idx);
                const double phi = (p.x() - rest.boxMin.x()) / radius;
                to.row(idx) << rest.boxMin.x() + (radius - p.z()) * std::sin(phi), p.y(), radius - (radius - p.z()) * std::cos(phi);
            }
            OpReport report;
            REQUIRE(session.moveControlPoints(ids, to, false, report).ok);
            INFO(injectivityModeName(mode) << " step " << step << " (" << angle / M_PI << " pi): " << report.reason);
            REQUIRE(boundarySelfIntersections(session.lattice()).empty());
            REQUIRE(test::selfIntersectingPairs(session.positions(), triangles) == 0);
            if (report.fractionApplied < 1.0) {
                stopped = true;
                CHECK(report.reason.find("stopped") != std::string::npos);
                // The exact test certifies the bend itself; what stops it is the ends meeting. (The conic test
                // is sufficient only and may stop a strong bend earlier.)
                if (mode == InjectivityMode::Exact) CHECK(report.refusedBy == "boundary");
            } else {
                turned = angle;
            }
        }
        REQUIRE(stopped);
        if (mode == InjectivityMode::Exact) CHECK(turned > 1.7 * M_PI);  // it bent freely until the ends came close
    }
}

// Is the pinch a certification bug (the continuous map folds) or only straight triangles crossing under
// compression? A dense grid of points fills the sphere's box and travels with the map (vertices without
// triangles). det J of the whole composed map, the product over the lattice frames of each frame's det J at
// the point's image in it (evaluated directly from the basis, not by the Bernstein test that certified the
// steps), stays positive at every grid point and vertex; with the pinned layer holding the box's boundary,
// a map with det J > 0 is globally injective. Meanwhile, with the triangle check off, the straight triangles
// between the mapped vertices do cross: the fault is the discretisation, and the triangle check closes it.
TEST_CASE("session: under pinch drags the composed map does not fold, only straight triangles cross", "[core]") {
    Positions sphere;
    Triangles triangles;
    test::icosphere(3, 1.0, Eigen::Vector3d::Zero(), sphere, triangles);
    const int g = 25;  // grid nodes per axis over [-1, 1]^3
    Positions positions(sphere.rows() + g * g * g, 3);
    positions.topRows(sphere.rows()) = sphere;
    for (int k = 0; k < g; ++k)
        for (int j = 0; j < g; ++j)
            for (int i = 0; i < g; ++i)
                positions.row(sphere.rows() + i + g * (j + g * k)) = (Eigen::Vector3d(i, j, k) / (g - 1) * 2.0 - Eigen::Vector3d::Ones()).transpose();
    LatticeSettings settings;
    settings.pinLayers = 1;
    Session session;
    REQUIRE(session.setMesh(positions, triangles, settings).ok);
    session.setTrackJacobian(true);
    InjectivitySettings injectivity{InjectivityMode::Exact, 6};
    injectivity.checkTriangles = false;  // the certified continuous map alone, as before the triangle check
    session.setInjectivity(injectivity);
    std::mt19937 rng(1);
    int steps = 0;
    for (int d = 0; d < 20; ++d) {
        const int k = test::randomInt(rng, 0, 161);
        int opposite = 0;
        double best = INFINITY;
        for (int i = 0; i < 162; ++i)
            if ((sphere.row(i) + sphere.row(k)).squaredNorm() < best) best = (sphere.row(i) + sphere.row(k)).squaredNorm(), opposite = i;
        const double s = std::uniform_real_distribution<double>(0.3, 0.9)(rng);
        OpReport report;
        REQUIRE(session.dragVertex(k, (sphere.row(k) + (sphere.row(opposite) - sphere.row(k)) * s).transpose(), report).ok);
        steps += report.subSteps;
        const std::vector<double> det = session.totalJacobianDeterminants();
        const double smallest = *std::min_element(det.begin(), det.end());
        INFO("drag " << d << ": smallest det J of the composed map " << smallest);
        REQUIRE(smallest > 0.0);
    }
    CHECK(session.frameDepth() > 10);  // many fresh frames were composed
    CHECK(test::selfIntersectingPairs(session.positions(), triangles) > 0);
}

}  // namespace

namespace sculpt::core {

// Zero-area facets (an STL's slivers collapsed to a segment or a point) are counted as what they are, apart
// from crossings: a closed sphere with degenerate facets piercing it, lying in it and touching it reports the
// degenerate facets and no crossing pair, while a real crossing added beside them is still counted.
TEST_CASE("session: degenerate facets at load are counted apart from crossing pairs", "[core]") {
    std::mt19937 rng(77);
    for (int trial = 0; trial < 6; ++trial) {
        Positions sphere;
        Triangles sphereTriangles;
        test::icosphere(1 + trial % 3, 1.0, Eigen::Vector3d::Zero(), sphere, sphereTriangles);
        std::vector<Eigen::Vector3d> points;
        for (Eigen::Index v = 0; v < sphere.rows(); ++v) points.push_back(sphere.row(v).transpose());
        std::vector<std::array<int, 3>> triangles;
        for (Eigen::Index t = 0; t < sphereTriangles.rows(); ++t)
            triangles.push_back({sphereTriangles(t, 0), sphereTriangles(t, 1), sphereTriangles(t, 2)});
        const int degenerate = 1 + trial;
        std::uniform_int_distribution<Eigen::Index> pick(0, sphereTriangles.rows() - 1);
        for (int d = 0; d < degenerate; ++d) {
            // Through a random facet's centroid along its normal: two corners at one end, one at the other
            // (collinear exactly), or all three on one point on the surface.
            const Eigen::Index t = pick(rng);
            const Eigen::Vector3d a = sphere.row(sphereTriangles(t, 0)), b = sphere.row(sphereTriangles(t, 1)), c = sphere.row(sphereTriangles(t, 2));
            const Eigen::Vector3d centre = (a + b + c) / 3.0, normal = (b - a).cross(c - a).normalized();
            const int first = static_cast<int>(points.size());
            if (d % 3 == 2) {
                for (int k = 0; k < 3; ++k) points.push_back(centre);
            } else {
                points.push_back(centre + 0.05 * normal);
                points.push_back(centre + 0.05 * normal);
                points.push_back(centre - 0.05 * normal);
            }
            triangles.push_back({first, first + 1, first + 2});
        }
        const bool crossing = trial % 2 == 1;
        if (crossing) {
            // A proper triangle through the sphere: one real crossing (two pairs or more with the facets it pierces).
            const int first = static_cast<int>(points.size());
            points.emplace_back(0.0, 0.013, -1.5);
            points.emplace_back(0.011, 0.0, -0.5);
            points.emplace_back(-0.012, 0.0, -0.5);
            triangles.push_back({first, first + 1, first + 2});
        }
        Positions positions(static_cast<Eigen::Index>(points.size()), 3);
        for (size_t i = 0; i < points.size(); ++i) positions.row(static_cast<Eigen::Index>(i)) = points[i].transpose();
        Triangles all(static_cast<Eigen::Index>(triangles.size()), 3);
        for (size_t i = 0; i < triangles.size(); ++i) all.row(static_cast<Eigen::Index>(i)) << triangles[i][0], triangles[i][1], triangles[i][2];
        // The brute force (which skips degenerate triangles) counts the real crossings; the engine's pair test,
        // which tests a degenerate facet as its segment or point, finds the pairs the load used to call crossings.
        const int real = static_cast<int>(test::intersectingPairs(positions, all).size());
        int withDegenerate = 0;
        for (int d = 0; d < degenerate; ++d)
            for (Eigen::Index t = 0; t < all.rows(); ++t) {
                TriangleCorners sliver, other;
                for (int k = 0; k < 3; ++k) {
                    sliver.vertex[static_cast<size_t>(k)] = all(sphereTriangles.rows() + d, k);
                    sliver.point[static_cast<size_t>(k)] = positions.row(sliver.vertex[static_cast<size_t>(k)]).transpose();
                    other.vertex[static_cast<size_t>(k)] = all(t, k);
                    other.point[static_cast<size_t>(k)] = positions.row(other.vertex[static_cast<size_t>(k)]).transpose();
                }
                if (t != sphereTriangles.rows() + d) withDegenerate += trianglesIntersect(sliver, other);
            }
        INFO("trial " << trial << ": " << real << " real pairs, " << withDegenerate << " with a degenerate facet");
        CHECK(withDegenerate > 0);  // the old count called these crossings
        Session session;
        REQUIRE(session.setMesh(positions, all, {}).ok);
        CHECK(session.initialDegenerateTriangles() == degenerate);
        CHECK(session.initialIntersectingPairs() == real);
        CHECK((real > 0) == crossing);
    }
}

}  // namespace sculpt::core

// Issue: a CAD assembly whose parts touch at load had every move refused for new crossings. Two spheres modelled
// overlapping (parts of an assembly in contact): random drags shift their contact to neighbouring triangles and
// apply; afterwards every crossing pair (by the independent exact test) is a load pair or a pair of the two parts
// within kContactRings rings of the load contact (computed here by its own search), never a pair elsewhere; a
// drag that pushes one part through the other is refused, and the reason names the two parts.
TEST_CASE("session: parts touching at load keep their contact as it shifts, and crossing triangles of two parts are refused by name", "[core][parts]") {
    Positions a, b;
    Triangles ta, tb;
    test::icosphere(3, 1.0, Eigen::Vector3d(-0.97, 0, 0), a, ta);
    test::icosphere(3, 1.0, Eigen::Vector3d(0.97, 0, 0), b, tb);
    Positions positions(a.rows() + b.rows(), 3);
    positions << a, b;
    Triangles triangles(ta.rows() + tb.rows(), 3);
    triangles << ta, (tb.array() + static_cast<int>(a.rows())).matrix();
    const std::vector<std::pair<int, int>> atLoad = test::intersectingPairs(positions, triangles);
    REQUIRE_FALSE(atLoad.empty());
    // The contact's neighbourhood, by its own search: triangles within kContactRings rings (sharing a corner).
    const std::vector<int> ring = loadContactRings(positions, triangles, atLoad);
    const int firstOfB = static_cast<int>(ta.rows());
    LatticeSettings settings;
    settings.resolution = {10, 6, 6};
    Session session;
    REQUIRE(session.setMesh(positions, triangles, settings).ok);
    CHECK(session.initialIntersectingPairs() == static_cast<int>(atLoad.size()));
    std::mt19937 rng(2026);
    int applied = 0;
    for (int d = 0; d < 24; ++d) {
        const int v = test::randomInt(rng, 0, static_cast<int>(positions.rows()) - 1);
        const Eigen::Vector3d target = session.positions().row(v).transpose() + test::randomVector(rng, -0.12, 0.12);
        OpReport report;
        REQUIRE(session.dragVertex(v, target, report).ok);
        applied += report.status == OpStatus::Applied;
    }
    WARN(applied << " of 24 drags applied");
    CHECK(applied >= 12);
    std::set<std::pair<int, int>> load(atLoad.begin(), atLoad.end());
    for (const auto& [x, y] : test::intersectingPairs(session.positions(), triangles)) {
        if (load.count({x, y})) continue;
        INFO("new pair " << x << ", " << y);
        CHECK((x < firstOfB) != (y < firstOfB));  // between the two parts
        CHECK(ring[static_cast<size_t>(x)] >= 0);
        CHECK(ring[static_cast<size_t>(y)] >= 0);
    }
    // An injective map keeps apart what is apart; what can still cross are the straight triangles between moved
    // vertices. Two coarse spheres a hair apart, squeezed together by random drags: every refusal for crossing
    // triangles names the two parts.
    Positions c, e;
    Triangles tc, te;
    test::icosphere(1, 1.0, Eigen::Vector3d(-1.01, 0, 0), c, tc);
    test::icosphere(1, 1.0, Eigen::Vector3d(1.01, 0, 0), e, te);
    Positions near(c.rows() + e.rows(), 3);
    near << c, e;
    Triangles nearTriangles(tc.rows() + te.rows(), 3);
    nearTriangles << tc, (te.array() + static_cast<int>(c.rows())).matrix();
    Session squeezed;
    REQUIRE(squeezed.setMesh(near, nearTriangles, LatticeSettings{}).ok);
    REQUIRE(squeezed.initialIntersectingPairs() == 0);
    int named = 0;
    for (int d = 0; d < 60; ++d) {
        const int v = test::randomInt(rng, 0, static_cast<int>(near.rows()) - 1);
        const Eigen::Vector3d from = squeezed.positions().row(v).transpose();
        const Eigen::Vector3d target = from + Eigen::Vector3d(from.x() < 0 ? 0.5 : -0.5, 0, 0) + test::randomVector(rng, -0.1, 0.1);
        OpReport report;
        REQUIRE(squeezed.dragVertex(v, target, report).ok);
        if (report.refusedBy != "triangles") continue;
        INFO(report.reason);
        CHECK(report.reason.find("part 1 (") != std::string::npos);
        CHECK(report.reason.find("part 2 (") != std::string::npos);
        ++named;
    }
    WARN(named << " of 60 squeezing drags stopped by crossing triangles, each naming the parts");
    CHECK(named > 0);
}
