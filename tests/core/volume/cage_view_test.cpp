// The cage as drawn (core/volume/cage_view.h): a frozen cylinder's welded points are one representative each, its
// control net joins representatives only, and its chunk edges lie on the cylinder (curved, not chords).
#include <catch2/catch.hpp>

#include <cmath>
#include <memory>
#include <set>

#include "core/volume/cage_view.h"
#include "core/volume/lattice_net.h"
#include "core/session/session.h"
#include "../mesh_fixtures.h"

using namespace sculpt;
using namespace sculpt::core;

namespace {

constexpr double kRadius = 0.6;

// A unit sphere mesh, a cylinder of radius 0.6 around the y axis through it (3 chunks around: each arc 120
// degrees, so chords and arcs differ a lot), frozen.
Session frozenCylinderSession() {
    Positions positions;
    Triangles triangles;
    test::icosphere(2, 1.0, Eigen::Vector3d::Zero(), positions, triangles);
    Session session;
    REQUIRE(session.setMesh(positions, triangles));
    LatticeNet net;
    REQUIRE(makeCylinderNet(Eigen::Vector3d(0, -1.2, 0), Eigen::Vector3d::UnitY(), kRadius, 2.4, {2, 3, 2}, {2, 2}, net));
    OpReport report;
    REQUIRE(session.tools().add({"pie", std::make_shared<const LatticeNet>(net)}, report));
    REQUIRE(session.tools().freeze(0, 0, report));
    REQUIRE(session.tools().frozen() == 0);
    return session;
}

}  // namespace

TEST_CASE("cage view: a frozen cylinder draws each weld group once, its net on representatives", "[core][effd]") {
    const Session session = frozenCylinderSession();
    const Lattice& lattice = session.lattice();
    const CageView view = cageView(session, 8);
    REQUIRE(view.points.rows() == lattice.controlPointCount());
    REQUIRE(view.representative.size() == size_t(lattice.controlPointCount()));
    std::set<int> groups;
    for (int id = 0; id < lattice.controlPointCount(); ++id) groups.insert(lattice.representative(id));
    size_t drawn = 0;
    for (int id = 0; id < lattice.controlPointCount(); ++id) {
        drawn += view.representative[size_t(id)];
        CHECK(bool(view.representative[size_t(id)]) == (lattice.representative(id) == id));
    }
    CHECK(drawn == groups.size());
    CHECK(drawn < size_t(lattice.controlPointCount()));  // the axis and the seam are welded
    REQUIRE(!view.edges.empty());
    for (const std::array<int, 2>& edge : view.edges) {
        CHECK(view.representative[size_t(edge[0])]);
        CHECK(view.representative[size_t(edge[1])]);
        CHECK(edge[0] != edge[1]);
    }
}

TEST_CASE("cage view: a cylinder's chunk edges lie on its circles and lines, never on the chords", "[core][effd]") {
    const Session session = frozenCylinderSession();
    const CageView view = cageView(session, 8);
    REQUIRE(!view.curves.empty());
    int circles = 0;
    for (const Positions& curve : view.curves) {
        // A curve at one height whose samples all keep one nonzero distance from the y axis is a circle (the
        // others are radial lines at knot angles and lines along the axis).
        Eigen::VectorXd radius(curve.rows());
        for (Eigen::Index s = 0; s < curve.rows(); ++s) radius[s] = std::hypot(curve(s, 0), curve(s, 2));
        const bool level = curve.col(1).maxCoeff() - curve.col(1).minCoeff() < 1e-9;  // not a line along the axis
        if (level && radius.minCoeff() > 0.1 && radius.maxCoeff() - radius.minCoeff() < 1e-9) {
            ++circles;
            CHECK((std::abs(radius.mean() - kRadius) < 1e-9 || std::abs(radius.mean() - 0.5 * kRadius) < 1e-9));
        }
    }
    CHECK(circles == 2 * 3);  // two nonzero radial knots at each of three axial knots
    // The control net's outer edges are chords far outside the circle (a 120-degree arc's middle control point
    // is 2 R away), so the curves are not the net.
    double farthest = 0.0;
    for (Eigen::Index p = 0; p < view.points.rows(); ++p) farthest = std::max(farthest, std::hypot(view.points(p, 0), view.points(p, 2)));
    CHECK(farthest > 1.9 * kRadius);
}

TEST_CASE("cage view: an unfrozen tool's rest chunk edges, and none for the box lattice", "[core][effd]") {
    Positions positions;
    Triangles triangles;
    test::icosphere(1, 1.0, Eigen::Vector3d::Zero(), positions, triangles);
    Session session;
    REQUIRE(session.setMesh(positions, triangles));
    const CageView box = cageView(session, 4);
    CHECK(box.edges.empty());
    CHECK(box.curves.empty());
    for (std::uint8_t flag : box.representative) CHECK(flag == 1);
    LatticeNet net;
    REQUIRE(makeCylinderNet(Eigen::Vector3d(0, -1.2, 0), Eigen::Vector3d::UnitY(), kRadius, 2.4, {2, 3, 2}, {2, 2}, net));
    const std::vector<Positions> rest = restChunkEdges(std::make_shared<const LatticeNet>(net), 4);
    CHECK(!rest.empty());
    for (const Positions& curve : rest)
        for (Eigen::Index s = 0; s < curve.rows(); ++s) CHECK(std::hypot(curve(s, 0), curve(s, 2)) <= kRadius + 1e-9);
    CHECK(restChunkEdges(nullptr, 4).empty());
}

TEST_CASE("cage view: with layers after the cage, points and curves are carried as the session shows them", "[core][effd]") {
    Session session = frozenCylinderSession();
    // A brush drag puts a region lattice after the cage (a layer).
    BrushSettings brush;
    brush.radius = 0.5;
    OpReport report;
    REQUIRE(session.drag({{Eigen::Vector3d(0.3, 0.9, 0.3), Eigen::Vector3d(0.3, 1.0, 0.4)}}, report, brush));
    REQUIRE(report.status == OpStatus::Applied);
    REQUIRE(!session.cage().layers().empty());
    const CageView view = cageView(session, 4);
    // The same map as the session's: the cage's points carried through the layers are cagePoints().
    const Positions carried = carryThroughLayers(session.cage().layers(), controlPointPositions(session.lattice()));
    CHECK((carried - session.cage().cagePoints()).cwiseAbs().maxCoeff() == 0.0);
    CHECK((view.points - session.cage().cagePoints()).cwiseAbs().maxCoeff() == 0.0);
    REQUIRE(view.curves.size() == chunkEdgeCurves(session.lattice(), 4).size());
}
