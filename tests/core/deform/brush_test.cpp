// The sculpting brush (core/deform/brush.h): radius, falloff, strength and symmetry built from a region-of-interest
// lattice and multi-point drags; and the cage that stays the user's under the layers (session.h).
#include <catch2/catch.hpp>

#include <random>

#include <Eigen/Geometry>

#include "core/deform/brush.h"
#include "core/deform/brush_field.h"
#include "core/deform/vertex_normals.h"
#include "io/script.h"
#include "core/session/session.h"
#include "io/script_json.h"
#include "../mesh_fixtures.h"
#include "../test_support.h"

using namespace sculpt;
using namespace sculpt::core;
using namespace sculpt::io;

namespace {

struct Mesh {
    Positions positions;
    Triangles triangles;
    double diagonal = 0.0;
};

Mesh sphereMesh(int levels, double radius, const Eigen::Vector3d& centre) {
    Mesh m;
    test::icosphere(levels, radius, centre, m.positions, m.triangles);
    m.diagonal = (m.positions.colwise().maxCoeff() - m.positions.colwise().minCoeff()).norm();
    return m;
}

// The vertex nearest to p (its distance in `distance`).
int nearestVertex(const Positions& positions, const Eigen::Vector3d& p, double* distance = nullptr) {
    Eigen::Index best;
    const double d2 = (positions.rowwise() - p.transpose()).rowwise().squaredNorm().minCoeff(&best);
    if (distance) *distance = std::sqrt(d2);
    return static_cast<int>(best);
}

BrushFalloff randomFalloff(std::mt19937& rng) {
    return std::array<BrushFalloff, 3>{BrushFalloff::Smooth, BrushFalloff::Medium, BrushFalloff::Sharp}[test::randomInt(rng, 0, 2)];
}

}  // namespace

TEST_CASE("brush: the region lattice frees only control points whose support lies within 1.25 radius of a pull's segment", "[core]") {
    std::mt19937 rng(5);
    for (int trial = 0; trial < 60; ++trial) {
        const double radius = std::exp(std::uniform_real_distribution<double>(std::log(1e-3), std::log(5.0))(rng));
        std::vector<BrushPull> pulls;
        for (int c = test::randomInt(rng, 1, 3); c > 0; --c)
            pulls.push_back({test::randomVector(rng, -3.0, 3.0), radius * std::uniform_real_distribution<double>(0.0, 3.0)(rng) * test::randomVector(rng, -1.0, 1.0).normalized()});
        if (trial % 5 == 0) pulls.push_back({test::randomVector(rng, -3.0, 3.0), Eigen::Vector3d::Zero()});  // a held point
        RegionLattice region;
        REQUIRE(pullRegionLattice(pulls, radius, region).ok);
        Lattice lattice;
        REQUIRE(makeLatticeInBox(region.settings, region.boxMin, region.boxMax, lattice).ok);
        REQUIRE(turnBoxLattice(lattice, region.axes).ok);
        // One moving pull: the box is turned to it (its w axis along the pull).
        size_t moving = 0;
        for (const BrushPull& p : pulls) moving += p.moving();
        if (moving == 1)
            for (const BrushPull& p : pulls)
                if (p.moving()) CHECK((region.axes.row(2).transpose() - p.pull.normalized()).norm() <= 1e-12);
        pinAllBut(lattice, region.freePoints);
        CHECK(boundaryUnmoved(lattice));
        // An independent check of the support: random points where a free basis function is non-zero lie within
        // the reach of some moving pull's segment.
        for (int sample = 0; sample < 400; ++sample) {
            const Eigen::Vector3d t = test::randomParams(rng);
            SupportWeights support;
            supportWeights(lattice, t, support);
            bool freeHere = false;
            for (int c = 0; c < support.count; ++c)
                freeHere = freeHere || (support.weight[c] > 0.0 && !lattice.pinned[support.index[c]]);
            if (!freeHere) continue;
            const Eigen::Vector3d x = restPoint(lattice, t);
            double nearest = INFINITY;
            for (const BrushPull& p : pulls)
                if (p.moving()) nearest = std::min(nearest, segmentDistance(x, p.source, p.source + p.pull));
            CHECK(nearest <= kBrushReach * radius * (1.0 + 1e-8));
        }
        // A lone pull has free points around it (a brush that can move something).
        if (moving == 1) CHECK(!region.freePoints.empty());
    }
}

TEST_CASE("brush: a drag with radius r pulls the grabbed point as far as asked and moves nothing farther than 1.25 r from its path", "[core]") {
    std::mt19937 rng(11);
    int full = 0, counted = 0;
    for (int level : {2, 3, 4}) {
        const Mesh mesh = sphereMesh(level, 1.0 + level, test::randomVector(rng, -2.0, 2.0));
        const Eigen::Vector3d centre = 0.5 * (mesh.positions.colwise().maxCoeff() + mesh.positions.colwise().minCoeff()).transpose();
        for (int trial = 0; trial < 8; ++trial) {
            Session session;
            REQUIRE(session.setMesh(mesh.positions, mesh.triangles).ok);
            InjectivitySettings injectivity;
            injectivity.mode = trial % 2 ? InjectivityMode::Exact : InjectivityMode::Conic;
            session.setInjectivity(injectivity);
            BrushSettings brush;
            brush.radius = std::uniform_real_distribution<double>(0.08, 0.2)(rng) * mesh.diagonal;
            brush.falloff = randomFalloff(rng);
            const int vertex = test::randomInt(rng, 0, static_cast<int>(mesh.positions.rows()) - 1);
            const Eigen::Vector3d grabbed = mesh.positions.row(vertex).transpose();
            // Outward, sideways or anywhere, 0.3 to 3 radii: the region follows the pull.
            const Eigen::Vector3d normal = (grabbed - centre).normalized();
            Eigen::Vector3d direction = trial % 3 == 0 ? normal : trial % 3 == 1 ? normal.unitOrthogonal() : test::randomVector(rng, -1.0, 1.0).normalized();
            if (trial % 3 == 2 && direction.dot(normal) < 0.0) direction = -direction;  // inward pulls through a sphere: see the stopping test
            const double length = std::uniform_real_distribution<double>(0.3, 3.0)(rng) * brush.radius;
            const Eigen::Vector3d target = grabbed + length * direction;
            OpReport report;
            REQUIRE(session.dragVertex(vertex, target, report, brush).ok);
            INFO("level " << level << " trial " << trial << " radius " << brush.radius << " pull " << length / brush.radius << " radii, falloff "
                          << brushFalloffName(brush.falloff) << ": " << report.reason);
            REQUIRE(report.status == OpStatus::Applied);
            // Medium's steep rim makes long pulls stop short sooner (docs/window.md, "The brush"); smooth and sharp go all the way.
            if (brush.falloff != BrushFalloff::Medium) {
                ++counted;
                full += report.fractionApplied == 1.0;
            }
            // Where it stopped, the grabbed point is on the segment towards its target.
            const Eigen::Vector3d reached = grabbed + report.fractionApplied * (target - grabbed);
            CHECK((session.mesh().positions.row(vertex).transpose() - reached).norm() <= 1e-9 * mesh.diagonal);
            int moved = 0;
            for (Eigen::Index v = 0; v < mesh.positions.rows(); ++v) {
                if (session.mesh().positions.row(v) == mesh.positions.row(v)) continue;
                ++moved;
                CHECK(segmentDistance(mesh.positions.row(v).transpose(), grabbed, reached) <= 1.25 * brush.radius * (1.0 + 1e-12));
            }
            CHECK(moved > 0);
            CHECK(isUndeformed(session.lattice()));  // the cage is not what the brush moves
        }
    }
    CHECK(counted >= 10);
    CHECK(full >= counted * 9 / 10);
}

TEST_CASE("brush: with symmetry the mirror images land on the mirrored targets, with and without a radius", "[core]") {
    std::mt19937 rng(23);
    // An icosphere is symmetric in every coordinate plane through its centre, so each vertex has a mirror vertex.
    const Eigen::Vector3d centre(0.7, -0.4, 1.1);
    const Mesh mesh = sphereMesh(3, 1.5, centre);
    const std::vector<std::string> symmetries = {"x", "y", "z", "xz", "xyz"};
    int checked = 0;
    for (int trial = 0; trial < 20; ++trial) {
        Session session;
        REQUIRE(session.setMesh(mesh.positions, mesh.triangles).ok);
        CHECK((session.meshAsSet().symmetryCentre - centre).norm() <= 1e-12);
        BrushSettings brush;
        REQUIRE(parseSymmetry(symmetries[static_cast<size_t>(trial) % symmetries.size()], brush.symmetry).ok);
        if (trial % 2 == 0) brush.radius = 0.25 * mesh.diagonal;
        brush.strength = trial % 3 == 0 ? 0.5 : 1.0;
        // A vertex well away from every mirror plane, so its images are separate points.
        int vertex = -1;
        for (int attempt = 0; attempt < 1000 && vertex < 0; ++attempt) {
            const int v = test::randomInt(rng, 0, static_cast<int>(mesh.positions.rows()) - 1);
            if (((mesh.positions.row(v).transpose() - centre).cwiseAbs().array() > 0.4).all()) vertex = v;
        }
        REQUIRE(vertex >= 0);
        const Eigen::Vector3d source = mesh.positions.row(vertex).transpose();
        const Eigen::Vector3d asked = source + 0.1 * mesh.diagonal * test::randomVector(rng, -1.0, 1.0);
        OpReport report;
        REQUIRE(session.dragVertex(vertex, asked, report, brush).ok);
        if (report.status != OpStatus::Applied || report.fractionApplied < 1.0) continue;
        const Eigen::Vector3d target = source + brush.strength * (asked - source);
        CHECK((session.mesh().positions.row(vertex).transpose() - target).norm() <= 1e-9 * mesh.diagonal);
        for (int mask = 1; mask < 8; ++mask) {
            bool usable = true;
            for (int a = 0; a < 3; ++a) usable = usable && (!(mask & (1 << a)) || brush.symmetry.mirror[a]);
            if (!usable) continue;
            double distance = 0.0;
            const int mirror = nearestVertex(mesh.positions, reflectPoint(source, mask, SymmetryFrame{centre}), &distance);
            REQUIRE(distance <= 1e-12 * mesh.diagonal);
            INFO("trial " << trial << " mask " << mask);
            CHECK((session.mesh().positions.row(mirror).transpose() - reflectPoint(target, mask, SymmetryFrame{centre})).norm() <= 1e-9 * mesh.diagonal);
            ++checked;
        }
    }
    CHECK(checked >= 20);
}

TEST_CASE("brush: a symmetric pull onto or across its mirror plane stops as the symmetry's, named in words, and other stops keep their cause", "[core]") {
    // An injective deformation that is the identity far away and commutes with the mirror keeps each side of the
    // plane on its side, so a grabbed point pulled onto the plane meets its own image: the stop is the symmetry's.
    std::mt19937 rng(41);
    const Eigen::Vector3d centre(0.3, 0.2, -0.5);
    const Mesh mesh = sphereMesh(3, 1.0, centre);
    int acrossStopped = 0, otherStopped = 0, strokes = 0;
    for (int trial = 0; trial < 24; ++trial) {
        Session session;
        REQUIRE(session.setMesh(mesh.positions, mesh.triangles).ok);
        BrushSettings brush;
        brush.symmetry.mirror[0] = true;
        brush.radius = std::uniform_real_distribution<double>(0.08, 0.2)(rng) * mesh.diagonal;
        brush.falloff = randomFalloff(rng);
        // A vertex off the plane x = centre.x (farther than the merge distance), near it or far from it.
        int vertex = -1;
        for (int attempt = 0; attempt < 1000 && vertex < 0; ++attempt) {
            const int v = test::randomInt(rng, 0, static_cast<int>(mesh.positions.rows()) - 1);
            const double offPlane = std::abs(mesh.positions(v, 0) - centre.x());
            if (offPlane > 0.05 && offPlane < (trial % 2 ? 0.3 : 0.9)) vertex = v;
        }
        REQUIRE(vertex >= 0);
        const Eigen::Vector3d source = mesh.positions.row(vertex).transpose();
        const double side = source.x() > centre.x() ? 1.0 : -1.0;
        // Across the plane (toward it, past it) on even trials; along it, or away from it, on odd ones.
        Eigen::Vector3d pull = test::randomVector(rng, -1.0, 1.0);
        const double offPlane = std::abs(source.x() - centre.x());
        pull.x() = trial % 2 == 0 ? -side * offPlane * std::uniform_real_distribution<double>(1.0, 2.5)(rng) : side * std::abs(pull.x()) * 0.3;
        if (trial % 2 == 0) pull.y() *= 0.3 * offPlane, pull.z() *= 0.3 * offPlane;
        else pull *= brush.radius / pull.norm();
        const bool across = (source.x() + pull.x() - centre.x()) * side <= 0.0;
        OpReport report;
        REQUIRE(session.dragVertex(vertex, source + pull, report, brush).ok);
        ++strokes;
        const bool stopped = report.status != OpStatus::Applied || report.fractionApplied < 1.0;
        INFO("trial " << trial << " across " << across << " refused_by " << report.refusedBy << ": " << report.reason);
        if (report.refusedBy == "symmetry") {
            CHECK(across);
            CHECK(stopped);
            CHECK(report.reason.find("meet its mirror image at the X symmetry plane") != std::string::npos);
        }
        if (stopped && across) {
            CHECK(report.refusedBy == "symmetry");
            ++acrossStopped;
        }
        if (stopped && !across) {
            CHECK(report.refusedBy != "symmetry");
            ++otherStopped;
        }
        // Whatever stopped it, the grabbed point stays on its side of the plane.
        CHECK((session.mesh().positions(vertex, 0) - centre.x()) * side > 0.0);
    }
    CHECK(strokes == 24);
    CHECK(acrossStopped + otherStopped <= strokes);
    CHECK(acrossStopped >= 8);  // every pull across the plane stops short of it (12 asked)
}

TEST_CASE("brush: mirror images near the plane pulled along it move as one field, as far as the stroke without symmetry", "[core]") {
    // Images within each other's reach, a hair off the plane: one layer each, each holding the other inside its
    // region, folded at once (a new user: 3 px off the camel's spine, 8% of a 100 px pull). With the pulls
    // sharing a direction, one field carries both (brush_field.h, sharedPullDirection).
    std::mt19937 rng(57);
    const Eigen::Vector3d centre(0.3, 0.2, -0.5);
    const Mesh mesh = sphereMesh(4, 1.0, centre);
    int full = 0, trials = 0;
    for (int trial = 0; trial < 12; ++trial) {
        BrushSettings brush;
        brush.symmetry.mirror[0] = true;
        brush.radius = std::uniform_real_distribution<double>(0.08, 0.15)(rng) * mesh.diagonal;
        brush.falloff = randomFalloff(rng);
        // Off the plane x = centre.x by more than the merge distance and less than a tenth of the radius.
        const double merge = 0.25 * brush.radius / kBrushFieldSpansPerRadius;
        int vertex = -1;
        for (int attempt = 0; attempt < 5000 && vertex < 0; ++attempt) {
            const int v = test::randomInt(rng, 0, static_cast<int>(mesh.positions.rows()) - 1);
            const double offPlane = std::abs(mesh.positions(v, 0) - centre.x());
            if (offPlane > 2.0 * merge && offPlane < 0.1 * brush.radius) vertex = v;
        }
        if (vertex < 0) continue;
        const Eigen::Vector3d source = mesh.positions.row(vertex).transpose();
        // Along the plane: outward (the sphere's normal, its x part dropped) or sideways in the plane.
        Eigen::Vector3d normal = (source - centre).normalized();
        normal.x() = 0.0;
        const Eigen::Vector3d inPlane = trial % 2 ? normal.normalized() : Eigen::Vector3d::UnitX().cross(normal).normalized();
        const Eigen::Vector3d target = source + std::uniform_real_distribution<double>(0.5, 1.5)(rng) * brush.radius * inPlane;
        Session alone, mirrored;
        REQUIRE(alone.setMesh(mesh.positions, mesh.triangles).ok);
        REQUIRE(mirrored.setMesh(mesh.positions, mesh.triangles).ok);
        OpReport withoutSymmetry, withSymmetry;
        BrushSettings single = brush;
        single.symmetry = Symmetry{};
        REQUIRE(alone.dragVertex(vertex, target, withoutSymmetry, single).ok);
        REQUIRE(mirrored.dragVertex(vertex, target, withSymmetry, brush).ok);
        if (withoutSymmetry.status != OpStatus::Applied || withoutSymmetry.fractionApplied < 1.0) continue;
        ++trials;
        INFO("trial " << trial << ": " << withSymmetry.reason);
        CHECK(withSymmetry.status == OpStatus::Applied);
        CHECK(withSymmetry.fractionApplied == 1.0);
        if (withSymmetry.status != OpStatus::Applied || withSymmetry.fractionApplied < 1.0) continue;
        ++full;
        // The grabbed point and its mirror image land exactly.
        CHECK((mirrored.mesh().positions.row(vertex).transpose() - target).norm() <= 1e-9 * mesh.diagonal);
        double distance = 0.0;
        const int image = nearestVertex(mesh.positions, reflectPoint(source, 1, SymmetryFrame{centre}), &distance);
        REQUIRE(distance <= 1e-12 * mesh.diagonal);
        CHECK((mirrored.mesh().positions.row(image).transpose() - reflectPoint(target, 1, SymmetryFrame{centre})).norm() <= 1e-9 * mesh.diagonal);
        // Undo is exact.
        REQUIRE(mirrored.undo(withSymmetry).ok);
        CHECK((mirrored.mesh().positions - mesh.positions).cwiseAbs().maxCoeff() <= 1e-12 * mesh.diagonal);
    }
    CHECK(trials >= 6);
    CHECK(full == trials);
}

TEST_CASE("brush: a point on the mirror plane is one constraint moving in the plane", "[core]") {
    std::vector<MirroredConstraint> mirrored = mirrorConstraints({Eigen::Vector3d(0.0, 1.0, 2.0), Eigen::Vector3d(0.5, 0.0, 0.0)}, {}, Symmetry{{true, false, false}},
                                                                 SymmetryFrame{}, 1e-6);
    REQUIRE(mirrored.size() == 3);
    CHECK(mirrored[0].images.size() == 2);  // on the plane x = 0: its image is itself
    const Eigen::Vector3d target = mirroredTarget(mirrored[0], {Eigen::Vector3d(0.3, 1.0, 2.0), Eigen::Vector3d(0.5, 0.0, 0.0)},
                                                  {Eigen::Vector3d(0.0, 1.0, 2.0), Eigen::Vector3d(0.5, 0.0, 0.0)}, SymmetryFrame{});
    CHECK(target.isApprox(Eigen::Vector3d(0.0, 1.0, 2.0)));
    CHECK(mirrored[2].source.isApprox(Eigen::Vector3d(-0.5, 0.0, 0.0)));
    // Held constraints (pins) are not mirrored.
    CHECK(mirrorConstraints({Eigen::Vector3d(1, 1, 1)}, {true}, Symmetry{{true, true, true}}, SymmetryFrame{}, 1e-6).size() == 1);
    Symmetry s;
    CHECK(!parseSymmetry("xq", s).ok);
    CHECK(parseSymmetry("xq", s).message.find("'q'") != std::string::npos);
    CHECK(!parseSymmetry("xx", s).ok);
}

TEST_CASE("brush: brush drags undo to the original and redo to the result, and a recording replays them to 1e-15 x diagonal", "[core]") {
    std::mt19937 rng(31);
    for (int level : {2, 3}) {
        const Mesh mesh = sphereMesh(level, 1.0, test::randomVector(rng, -1.0, 1.0));
        Session session;
        REQUIRE(session.setMesh(mesh.positions, mesh.triangles).ok);
        int applied = 0;
        for (int op = 0; op < 25; ++op) {
            BrushSettings brush;
            brush.radius = std::uniform_real_distribution<double>(0.1, 0.4)(rng) * mesh.diagonal;
            brush.falloff = randomFalloff(rng);
            brush.symmetry.mirror[0] = op % 4 == 0;
            const int vertex = test::randomInt(rng, 0, static_cast<int>(mesh.positions.rows()) - 1);
            OpReport report;
            if (op % 5 == 4) {  // a plain drag in the cage between brush strokes
                REQUIRE(session.dragVertex(vertex, session.mesh().positions.row(vertex).transpose() + 0.05 * mesh.diagonal * test::randomVector(rng, -1, 1), report).ok);
            } else {
                REQUIRE(session.dragVertex(vertex, session.mesh().positions.row(vertex).transpose() + 0.3 * brush.radius * test::randomVector(rng, -1, 1), report, brush).ok);
            }
            applied += report.status == OpStatus::Applied;
        }
        REQUIRE(applied > 10);
        const Positions after = session.mesh().positions;
        const Script recording = recordSession(session);
        OpReport report;
        while (session.history().cursor() > 0) REQUIRE(session.undo(report).ok);
        CHECK(session.cage().layers().empty());
        CHECK((session.mesh().positions - mesh.positions).cwiseAbs().maxCoeff() <= 1e-12 * mesh.diagonal);
        while (session.history().cursor() < static_cast<int>(session.history().size())) REQUIRE(session.redo(report).ok);
        CHECK((session.mesh().positions - after).cwiseAbs().maxCoeff() <= 1e-12 * mesh.diagonal);

        // Through the JSON text, as a saved session is replayed: the same vertices, bit for bit.
        Script parsed;
        REQUIRE(io::parseScript(io::scriptToJson(recording), "recording", parsed).ok);
        Session replayed;
        REQUIRE(replayed.setMesh(mesh.positions, mesh.triangles, parsed.lattice).ok);
        replayed.setInjectivity(parsed.injectivity);
        ScriptReport scriptReport;
        REQUIRE(runScript(replayed, parsed, scriptReport).ok);
        // note: bitwise but for a symmetric stroke that stopped short, whose replay is one ulp off (6e-17 x the
        // diagonal on the level-3 sphere; an open defect). This test never ran under ctest before: its name
        // held a ';', which split it into two names that matched nothing.
        INFO("replay off by " << (replayed.mesh().positions - after).cwiseAbs().maxCoeff() / mesh.diagonal << " x diagonal");
        CHECK((replayed.mesh().positions - after).cwiseAbs().maxCoeff() <= 1e-15 * mesh.diagonal);
        // And decided again on the same ops (no recorded steps): brush ops keep their radius and symmetry.
        for (ScriptOp& op : parsed.ops) op.hasApplied = false;
        parsed.meshFingerprint.clear();
        Session decided;
        REQUIRE(decided.setMesh(mesh.positions, mesh.triangles, parsed.lattice).ok);
        decided.setInjectivity(parsed.injectivity);
        REQUIRE(runScript(decided, parsed, scriptReport).ok);
        CHECK((decided.mesh().positions - after).cwiseAbs().maxCoeff() <= 1e-9 * mesh.diagonal);
    }
}

TEST_CASE("layers: after subdivided drags the cage is carried through the layers and edits move it as shown", "[core]") {
    std::mt19937 rng(41);
    const Mesh mesh = sphereMesh(3, 1.0, Eigen::Vector3d(0.1, 0.2, -0.3));
    for (int trial = 0; trial < 6; ++trial) {
        Session session;
        LatticeSettings settings;
        settings.resolution = {6, 6, 6};
        settings.pinLayers = trial % 2;
        REQUIRE(session.setMesh(mesh.positions, mesh.triangles, settings).ok);
        // A strong pull that needs several injective steps.
        Eigen::Index top;
        mesh.positions.col(2).maxCoeff(&top);
        OpReport report;
        REQUIRE(session.dragVertex(static_cast<int>(top), mesh.positions.row(top).transpose() + Eigen::Vector3d(0.5, 0.2, 0.9), report).ok);
        if (report.status != OpStatus::Applied || report.subSteps < 2) continue;
        INFO("trial " << trial);
        CHECK(session.cage().frameDepth() == static_cast<int>(session.cage().layers().size()));  // layers, not new cages
        CHECK(session.cage().settings().resolution == settings.resolution);
        // The shown cage is the cage carried through the layers.
        const Positions shown = session.cage().cagePoints();
        const Positions cage = controlPointPositions(session.lattice());
        // A control point moved "by" an offset moves that much as shown, and the layers stay as they were.
        int idx = -1;
        for (int attempt = 0; attempt < 100 && idx < 0; ++attempt) {
            const int candidate = test::randomInt(rng, 0, session.lattice().controlPointCount() - 1);
            if (!session.lattice().pinned[candidate]) idx = candidate;
        }
        REQUIRE(idx >= 0);
        const size_t layerCount = session.cage().layers().size();
        const Eigen::Vector3d offset = 0.02 * mesh.diagonal * test::randomVector(rng, -1.0, 1.0);
        Eigen::MatrixX3d values(1, 3);
        values.row(0) = offset.transpose();
        REQUIRE(session.moveControlPoints({idx}, values, true, report).ok);
        if (report.status == OpStatus::Applied && report.fractionApplied == 1.0) {
            CHECK((session.cage().cagePoints().row(idx) - shown.row(idx) - offset.transpose()).norm() <= 1e-9 * mesh.diagonal);
            CHECK(session.cage().layers().size() == layerCount);
        }
        REQUIRE(session.undo(report).ok);
        CHECK((controlPointPositions(session.lattice()) - cage).cwiseAbs().maxCoeff() <= 1e-12 * mesh.diagonal);
        CHECK((session.cage().cagePoints() - shown).cwiseAbs().maxCoeff() <= 1e-12 * mesh.diagonal);
    }
}

TEST_CASE("brush: a point grabbed beside a mirror plane and its image make one bump, not two peaks", "[core][brush]") {
    // A flat sheet (a 41 x 41 grid on y = 0, centred on the X plane), a grid vertex a fifth of a radius or so off
    // the plane pulled one radius up with X symmetry: the two images are closer than half a radius, and the grid
    // vertex on the plane midway between them rises as high as they do (one ridge). The max of two bumps dipped
    // there to about f(d / 2r) of the pull (smooth: 0.90 at a fifth of a radius; sharp: lower).
    const int n = 41;
    const double spacing = 0.05;
    Positions positions(n * n, 3);
    Triangles triangles(2 * (n - 1) * (n - 1), 3);
    for (int i = 0; i < n; ++i)
        for (int k = 0; k < n; ++k) positions.row(i + n * k) << (i - n / 2) * spacing, 0.0, (k - n / 2) * spacing;
    int t = 0;
    for (int i = 0; i + 1 < n; ++i)
        for (int k = 0; k + 1 < n; ++k) {
            triangles.row(t++) << i + n * k, i + n * (k + 1), i + 1 + n * k;
            triangles.row(t++) << i + 1 + n * k, i + n * (k + 1), i + 1 + n * (k + 1);
        }
    std::mt19937 rng(61);
    for (int trial = 0; trial < 9; ++trial) {
        BrushSettings brush;
        const int offset = 1 + trial % 2;  // grid columns off the plane
        brush.radius = offset * spacing / std::uniform_real_distribution<double>(0.12, 0.22)(rng);
        brush.falloff = static_cast<BrushFalloff>(trial % 3);
        brush.symmetry.mirror[0] = true;
        const int row = n / 2 + test::randomInt(rng, -3, 3);
        const int v = n / 2 + offset + n * row, middle = n / 2 + n * row;
        INFO("trial " << trial << ", " << offset * spacing / brush.radius << " radius off the plane, falloff " << trial % 3);
        Session session;
        REQUIRE(session.setMesh(positions, triangles).ok);
        OpReport report;
        REQUIRE(session.dragVertex(v, positions.row(v).transpose() + Eigen::Vector3d(0.0, brush.radius, 0.0), report, brush).ok);
        REQUIRE(report.status == OpStatus::Applied);
        REQUIRE(report.fractionApplied == 1.0);
        const double grabbed = session.mesh().positions(v, 1), between = session.mesh().positions(middle, 1);
        INFO("grabbed point rose " << grabbed << ", the point on the plane between the images " << between);
        CHECK(std::abs(grabbed - brush.radius) <= 1e-9);
        CHECK(between >= 0.97 * grabbed);
        CHECK(between <= 1.03 * grabbed);
        // Still mirror symmetric.
        const int image = n / 2 - offset + n * row;
        CHECK((session.mesh().positions.row(image) - Eigen::RowVector3d(-session.mesh().positions(v, 0), session.mesh().positions(v, 1), session.mesh().positions(v, 2))).norm() <= 1e-9);
    }
}

TEST_CASE("brush: the mirror planes move and turn with the cage, as the mesh's own planes", "[core][brush]") {
    // A symmetric icosphere (centre c), the whole cage moved by a random rigid motion T(x) = R (x - c) + c + b,
    // then a symmetric stroke: the grabbed vertex's image is the vertex that was its mirror image at load,
    // carried by T, and it lands on the target mirrored in the carried planes. With the planes left where the
    // mesh was loaded (a window trial), the image landed on the face after a move of the cage.
    std::mt19937 rng(67);
    const Eigen::Vector3d c(0.3, -0.2, 0.1);
    const Mesh mesh = sphereMesh(3, 1.0, c);
    Positions normals;
    computeVertexNormals(mesh.positions, mesh.triangles, normals);
    int checked = 0;
    for (int trial = 0; trial < 8; ++trial) {
        INFO("trial " << trial);
        Session session;
        REQUIRE(session.setMesh(mesh.positions, mesh.triangles).ok);
        const Eigen::Matrix3d turn = trial == 0 ? Eigen::Matrix3d::Identity()
                                                : Eigen::AngleAxisd(0.6 * test::randomVector(rng, -1.0, 1.0).x(), test::randomVector(rng, -1.0, 1.0).normalized()).toRotationMatrix();
        const Eigen::Vector3d by = 0.5 * test::randomVector(rng, -1.0, 1.0);
        const auto carried = [&](const Eigen::Vector3d& x) { return Eigen::Vector3d(turn * (x - c) + c + by); };
        std::vector<int> ids;
        for (int idx = 0; idx < session.lattice().controlPointCount(); ++idx) ids.push_back(idx);
        const Positions points = controlPointPositions(session.lattice());
        Positions displacement(static_cast<Eigen::Index>(ids.size()), 3);
        for (size_t k = 0; k < ids.size(); ++k) displacement.row(static_cast<Eigen::Index>(k)) = (carried(points.row(ids[k]).transpose()) - points.row(ids[k]).transpose()).transpose();
        OpReport report;
        REQUIRE(session.moveControlPoints(ids, displacement, true, report).ok);
        REQUIRE(report.status == OpStatus::Applied);
        // The planes are carried: the frame's centre and axes are T's.
        const SymmetryFrame frame = session.symmetryFrame();
        CHECK((frame.centre - carried(c)).norm() <= 1e-9);
        CHECK((frame.axes - turn).cwiseAbs().maxCoeff() <= 1e-9);
        // A vertex off the planes, pulled along its (carried) normal with X symmetry.
        int v = -1;
        while (v < 0) {
            const int u = test::randomInt(rng, 0, static_cast<int>(mesh.positions.rows()) - 1);
            if (std::abs(mesh.positions(u, 0) - c.x()) > 0.4) v = u;
        }
        const Eigen::Vector3d mirrorRest(2.0 * c.x() - mesh.positions(v, 0), mesh.positions(v, 1), mesh.positions(v, 2));
        double distance = 0.0;
        const int image = nearestVertex(mesh.positions, mirrorRest, &distance);
        REQUIRE(distance <= 1e-12);
        BrushSettings brush;
        brush.radius = 0.3;
        brush.symmetry.mirror[0] = true;
        const Eigen::Vector3d pull = 0.4 * brush.radius * (turn * normals.row(v).transpose());
        const Eigen::Vector3d source = session.mesh().positions.row(v).transpose();
        REQUIRE(session.dragVertex(v, source + pull, report, brush).ok);
        REQUIRE(report.status == OpStatus::Applied);
        REQUIRE(report.fractionApplied == 1.0);
        ++checked;
        // The image's pull: the grabbed one mirrored in the carried X plane.
        const Eigen::Vector3d n = turn.col(0);
        const Eigen::Vector3d mirroredPull = pull - 2.0 * pull.dot(n) * n;
        CHECK((session.mesh().positions.row(v).transpose() - (source + pull)).norm() <= 1e-9);
        CHECK((session.mesh().positions.row(image).transpose() - (carried(mirrorRest) + mirroredPull)).norm() <= 1e-9);
    }
    CHECK(checked == 8);
}
