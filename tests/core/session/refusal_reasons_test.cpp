// issue 9 item 6: rejections and shortened moves say why, in the user's terms, with what to do; otherwise
// where on the mesh the fold would be.
#include <catch2/catch.hpp>

#include <cstdio>
#include <random>

#include "core/session/session.h"
#include "../mesh_fixtures.h"
#include "../test_support.h"

using namespace sculpt;
using namespace sculpt::core;

namespace {

bool mentions(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

Session sphereSession(const LatticeSettings& settings, InjectivityMode mode) {
    Positions positions;
    Triangles triangles;
    test::icosphere(2, 1.0, Eigen::Vector3d(0.2, 0.1, -0.3), positions, triangles);
    Session session;
    REQUIRE(session.setMesh(positions, triangles, settings).ok);
    session.setInjectivity({mode, 5});
    return session;
}

TEST_CASE("refusals: a target outside a lattice whose outer layer is pinned says so and what to do", "[core]") {
    std::mt19937 rng(3);
    for (int trial = 0; trial < 10; ++trial) {
        LatticeSettings settings;
        settings.pinLayers = 1 + trial % 2;
        Session session = sphereSession(settings, trial % 2 ? InjectivityMode::Exact : InjectivityMode::Conic);
        const int v = test::randomInt(rng, 0, static_cast<int>(session.mesh().positions.rows()) - 1);
        const Eigen::Vector3d from = session.mesh().positions.row(v).transpose();
        // Outside the box along the vertex's own direction from the centre.
        const Eigen::Vector3d centre = 0.5 * (session.lattice().boxMin + session.lattice().boxMax);
        const Eigen::Vector3d target = centre + (from - centre).normalized() * session.lattice().diagonal();
        const Positions before = session.mesh().positions;
        OpReport report;
        REQUIRE(session.dragVertex(v, target, report).ok);
        REQUIRE(report.status == OpStatus::Rejected);
        INFO(report.reason);
        CHECK(mentions(report.reason, "outside the lattice"));
        CHECK(mentions(report.reason, "pinned"));
        CHECK(mentions(report.reason, "unpin"));
        CHECK(mentions(report.reason, "enlarge the region"));
        CHECK(session.mesh().positions == before);
        CHECK(session.history().empty());
    }
}

TEST_CASE("refusals: a point only pinned control points can move says so", "[core]") {
    LatticeSettings settings;
    settings.resolution = {5, 5, 5};
    Session session = sphereSession(settings, InjectivityMode::Conic);
    std::vector<int> all(static_cast<size_t>(session.lattice().controlPointCount()));
    for (size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
    REQUIRE(session.pins().set(all, true).ok);
    OpReport report;
    REQUIRE(session.dragVertex(4, session.mesh().positions.row(4).transpose() + Eigen::Vector3d(0.0, 0.1, 0.0), report).ok);
    REQUIRE(report.status == OpStatus::Rejected);
    INFO(report.reason);
    CHECK(mentions(report.reason, "is pinned"));
    CHECK(mentions(report.reason, "unpin"));
    CHECK(report.refusedBy == "setup");
}

TEST_CASE("refusals: constraints that contradict each other are met as closely as possible, and it says so", "[core]") {
    Session session = sphereSession({}, InjectivityMode::Off);
    const Eigen::Vector3d p = session.mesh().positions.row(7).transpose();
    OpReport report;
    // One point asked to go two places.
    REQUIRE(session.drag({{p, p + Eigen::Vector3d(0.1, 0, 0)}, {p, p - Eigen::Vector3d(0.1, 0, 0)}}, report).ok);
    REQUIRE(report.status == OpStatus::Applied);
    INFO(report.reason);
    CHECK(report.rankDeficient);
    CHECK(mentions(report.reason, "contradict"));
    CHECK(mentions(report.reason, "largest miss"));
}

TEST_CASE("refusals: a refused fold says where on the mesh it would be", "[core]") {
    Session session = sphereSession({}, InjectivityMode::Exact);
    session.setInjectivity({InjectivityMode::Exact, 0});  // no subdivision: the first failing step decides
    const int v = 11;
    const Eigen::Vector3d from = session.mesh().positions.row(v).transpose();
    OpReport report;
    REQUIRE(session.dragVertex(v, from - 1.8 * (from - Eigen::Vector3d(0.2, 0.1, -0.3)), report).ok);
    REQUIRE(report.status == OpStatus::Rejected);
    INFO(report.reason);
    CHECK(mentions(report.reason, "near ("));
    CHECK(mentions(report.reason, "would"));
    CHECK_FALSE(report.refusedBy.empty());
    CHECK_FALSE(mentions(report.reason, "hodograph"));  // the technical detail stays in report.injectivity
}

// The case: a 3x3x3 quadratic lattice, the bottom-centre control point moved up 10 box heights. It
// stops at the injective limit, in this lattice (no fresh frame), and the report says where it ended.
TEST_CASE("refusals: a control-point edit that had to stop short says where the point ended", "[core]") {
    for (InjectivityMode mode : {InjectivityMode::Conic, InjectivityMode::Exact}) {
        LatticeSettings settings;
        settings.resolution = {3, 3, 3};
        settings.degree = {2, 2, 2};
        Session session = sphereSession(settings, mode);
        const Lattice& lattice = session.lattice();
        const int idx = lattice.index(1, 1, 0);
        const Eigen::Vector3d start = lattice.controlPoint(idx);
        const double height = lattice.boxMax.z() - lattice.boxMin.z();
        Eigen::MatrixX3d offset(1, 3);
        offset << 0.0, 0.0, 10.0 * height;
        OpReport report;
        REQUIRE(session.moveControlPoints({idx}, offset, true, report).ok);
        INFO(injectivityModeName(mode) << ": " << report.reason);
        REQUIRE(report.status == OpStatus::Applied);
        REQUIRE(report.fractionApplied > 0.0);
        REQUIRE(report.fractionApplied < 1.0);
        const Eigen::Vector3d ended = session.lattice().controlPoint(idx);
        CHECK((ended - (start + report.fractionApplied * offset.row(0).transpose())).norm() <= 1e-12 * lattice.diagonal());
        CHECK(mentions(report.reason, "stopped where the lattice would fold"));
        CHECK(mentions(report.reason, "ended at"));
        CHECK(session.cage().frameDepth() == 0);  // the cage stays the user's: no fresh lattice
        CHECK(session.history().size() == 1);
        // A little further is not injective any more (to the bisection's resolution).
        OpReport further;
        Eigen::MatrixX3d more(1, 3);
        more << 0.0, 0.0, 0.01 * 10.0 * height;
        REQUIRE(session.moveControlPoints({idx}, more, true, further).ok);
        CHECK(further.fractionApplied < 1.0);
    }
}

}  // namespace

// A crossing the triangle check refuses is placed at the first triangle of the pair, where it is before the move:
// when that triangle did not move (a part pushed into a still one of lower ids), its corners are where they were
// (they read as the origin once). Two spheres a hair apart, away from the origin, the cage around the right one
// only, all its control points moved into the left one by random vectors: each refusal by the triangles names a
// point on the left sphere's surface or the right one's, never the origin.
TEST_CASE("refusals: a crossing into a part that did not move says where on the mesh it would be", "[core]") {
    Positions positions;
    Triangles triangles;
    const Eigen::Vector3d left(6.0, 2.0, -1.0), right(8.02, 2.0, -1.0);
    test::twoIcospheres(1, 1.0, left, right, positions, triangles);
    LatticeSettings rightOnly;
    rightOnly.hasRegion = true;
    rightOnly.regionMin = right - Eigen::Vector3d(1.005, 1.05, 1.05);
    rightOnly.regionMax = right + Eigen::Vector3d(1.05, 1.05, 1.05);
    rightOnly.padding = 0.0;
    rightOnly.pinLayers = 0;
    Session session;
    REQUIRE(session.setMesh(positions, triangles, rightOnly).ok);
    std::vector<int> all(static_cast<size_t>(session.lattice().controlPointCount()));
    for (size_t k = 0; k < all.size(); ++k) all[k] = static_cast<int>(k);
    std::mt19937 rng(82);
    int placed = 0;
    for (int trial = 0; trial < 6; ++trial) {
        const Eigen::Vector3d by = Eigen::Vector3d(-0.3 - 0.1 * trial, 0, 0) + test::randomVector(rng, -0.1, 0.1);
        OpReport report;
        REQUIRE(session.moveControlPoints(all, by.transpose().replicate(static_cast<Eigen::Index>(all.size()), 1), true, report).ok);
        INFO(report.reason);
        REQUIRE(report.refusedBy == "triangles");
        const size_t at = report.reason.find("near (");
        REQUIRE(at != std::string::npos);
        Eigen::Vector3d where;
        REQUIRE(std::sscanf(report.reason.c_str() + at, "near (%lf, %lf, %lf)", &where.x(), &where.y(), &where.z()) == 3);
        const double fromLeft = (where - left).norm(), fromRight = (where - right).norm();
        CHECK(std::min(std::abs(fromLeft - 1.0), std::abs(fromRight - 1.0)) < 0.2);
        placed += where.norm() > 1.0;
        if (report.status == OpStatus::Applied) REQUIRE(session.undo(report).ok);
    }
    CHECK(placed == 6);
}
