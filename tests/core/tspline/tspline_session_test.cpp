// Strong drags on a frozen weighted T-spline (Song & Yang 2005, sec. 6 step 4; seed 003's injectivity on its
// Bezier elements): in the conic and the exact mode, drags that pull vertices most of the way through a sphere are
// split into substeps with fresh frames (Gain & Dodgson 2001, sec. 8) or refused, as on the box lattice. After
// every drag the mesh has no crossing triangle pair (an independent exact brute force), every frame the history
// holds passes the exact test again, and undoing everything gives back the sphere.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>

#include "core/injectivity/injectivity.h"
#include "core/session/session.h"
#include "core/tspline/tspline_view.h"
#include "../mesh_fixtures.h"
#include "../test_support.h"

using namespace sculpt;
using namespace sculpt::core;

namespace {

struct PinchCount {
    int applied = 0, rejected = 0, subdivided = 0, freshFrames = 0;
};

// `drags` pinch drags (a random vertex 30-90% of the way toward the one opposite it) on a level-2 icosphere in an
// octree T-spline of `depth`, in `mode`.
PinchCount pinchTSpline(InjectivityMode mode, int depth, unsigned seed, int drags) {
    Positions positions;
    Triangles triangles;
    test::icosphere(2, 1.0, Eigen::Vector3d(0.2, -0.1, 0.3), positions, triangles);
    const double diagonal = 2.0 * std::sqrt(3.0);
    Session session;
    REQUIRE(session.setMesh(positions, triangles, LatticeSettings{}));
    session.setInjectivity({mode, 6});
    TSplineSetup setup;
    setup.octree.octree.depth = depth;
    OpReport report;
    REQUIRE(session.tspline().setup(setup, report));
    REQUIRE(report.status == OpStatus::Applied);
    REQUIRE(asTSpline(session.lattice().volume.get()));
    const int setupEntries = session.history().cursor();
    std::mt19937 rng(seed);
    PinchCount count;
    for (int d = 0; d < drags; ++d) {
        const int k = test::randomInt(rng, 0, static_cast<int>(positions.rows()) - 1);
        int opposite = 0;
        for (int i = 1; i < positions.rows(); ++i)
            if ((positions.row(i) + positions.row(k) - 2.0 * Eigen::RowVector3d(0.2, -0.1, 0.3)).squaredNorm() <
                (positions.row(opposite) + positions.row(k) - 2.0 * Eigen::RowVector3d(0.2, -0.1, 0.3)).squaredNorm())
                opposite = i;
        const double s = std::uniform_real_distribution<double>(0.3, 0.9)(rng);
        const Eigen::Vector3d from = session.mesh().positions.row(k).transpose();
        const Eigen::Vector3d target = from + s * (session.mesh().positions.row(opposite).transpose() - from);
        REQUIRE(session.dragVertex(k, target, report));
        INFO("mode " << injectivityModeName(mode) << ", depth " << depth << ", drag " << d << ": " << report.reason);
        if (report.status == OpStatus::Applied) {
            ++count.applied;
            if (report.subSteps > 1) {
                ++count.subdivided;
                REQUIRE_FALSE(report.refusedBy.empty());  // the report says why it was split
            }
            const Operation& op = session.history().back();
            for (const Step& step : op.steps) count.freshFrames += step.freshFrame || step.newCage;
            // Applied means the whole drag: the vertex is on its target (seed 000's exact solution per substep).
            REQUIRE((session.mesh().positions.row(k).transpose() - target).norm() <= 1e-9 * diagonal);
        } else {
            REQUIRE(report.status == OpStatus::Rejected);
            REQUIRE(report.reason.find("nothing was changed") != std::string::npos);
            ++count.rejected;
        }
        REQUIRE(session.mesh().positions.allFinite());
        REQUIRE(test::selfIntersectingPairs(session.mesh().positions, triangles) == 0);
        // The frame now in use (the T-spline, or a fresh box frame on top of it) is injective by the exact test.
        REQUIRE(checkInjectivityExact(session.lattice()).certified);
    }
    OpReport undone;
    while (session.history().cursor() > setupEntries) REQUIRE(session.undo(undone));
    REQUIRE((session.mesh().positions - positions).cwiseAbs().maxCoeff() <= 1e-9 * diagonal);
    return count;
}

}  // namespace

TEST_CASE("tspline session: pinch drags are split with fresh frames or refused, never leaving a fold or a crossing", "[tspline][session]") {
    PinchCount total;
    for (const InjectivityMode mode : {InjectivityMode::Exact, InjectivityMode::Conic})
        for (unsigned seed : {5u, 6u}) {
            const PinchCount c = pinchTSpline(mode, seed == 5u ? 2 : 3, seed, 10);
            total.applied += c.applied;
            total.rejected += c.rejected;
            total.subdivided += c.subdivided;
            total.freshFrames += c.freshFrames;
        }
    INFO("applied " << total.applied << ", rejected " << total.rejected << ", subdivided " << total.subdivided << ", fresh frames "
                    << total.freshFrames);
    CHECK(total.applied > 10);     // the checks refuse only what they must
    CHECK(total.subdivided > 0);   // and these drags are strong enough to need the subdivision
    CHECK(total.freshFrames > 0);
}
