#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>

#include <Eigen/Geometry>

#include "io/script.h"
#include "core/session/session.h"
#include "../test_support.h"

using namespace sculpt;
using namespace sculpt::core;
using namespace sculpt::io;

namespace {

Session randomSession(std::mt19937& rng, int n, LatticeSettings settings = {}) {
    Session session;
    const Positions points = test::randomPoints(rng, n, Eigen::Vector3d(-1, -2, 0), Eigen::Vector3d(2, 1, 0.5));
    Triangles triangles(n / 3, 3);
    for (int t = 0; t < n / 3; ++t) triangles.row(t) << 3 * t, 3 * t + 1, 3 * t + 2;
    REQUIRE(session.setMesh(points, triangles, settings).ok);
    // These tests check seed 000's algebra within one lattice; injectivity has its own tests.
    session.setInjectivity({InjectivityMode::Off, 6});
    return session;
}

bool sameState(const Session& a, const Positions& positions, const Positions& displacement, int cursor) {
    return a.mesh().positions == positions && a.lattice().displacement == displacement && a.history().cursor() == cursor;
}

}  // namespace

TEST_CASE("session: a drag puts the source on the target, undo and redo restore", "[core]") {
    std::mt19937 rng(51);
    for (int trial = 0; trial < 20; ++trial) {
        Session session = randomSession(rng, 3000);
        const double diagonal = session.lattice().diagonal();
        const Positions original = session.mesh().positions;
        std::vector<Positions> states{original};
        for (int op = 0; op < 5; ++op) {
            const int v = test::randomInt(rng, 0, 2999);
            const Eigen::Vector3d target = session.mesh().positions.row(v).transpose() + 0.05 * diagonal * test::randomVector(rng, -1, 1);
            OpReport report;
            REQUIRE(session.dragVertex(v, target, report).ok);
            REQUIRE(report.status == OpStatus::Applied);
            REQUIRE((session.mesh().positions.row(v).transpose() - target).norm() <= 1e-9 * diagonal);
            REQUIRE(report.residuals.size() == 1);
            REQUIRE(report.controlPointsChanged <= 64);
            states.push_back(session.mesh().positions);
        }
        OpReport report;
        for (int op = 5; op > 0; --op) {
            REQUIRE(session.undo(report).ok);
            REQUIRE((session.mesh().positions - states[op - 1]).cwiseAbs().maxCoeff() <= 1e-9 * diagonal);
        }
        REQUIRE(session.undo(report).ok);
        REQUIRE(report.status == OpStatus::NoOp);
        for (int op = 1; op <= 5; ++op) {
            REQUIRE(session.redo(report).ok);
            REQUIRE((session.mesh().positions - states[op]).cwiseAbs().maxCoeff() <= 1e-9 * diagonal);
        }
        REQUIRE(session.redo(report).ok);
        REQUIRE(report.status == OpStatus::NoOp);
    }
}

TEST_CASE("session: a world-space source on a deformed lattice is found and moved", "[core]") {
    std::mt19937 rng(52);
    for (int trial = 0; trial < 20; ++trial) {
        Session session = randomSession(rng, 300);
        const double diagonal = session.lattice().diagonal();
        OpReport report;
        REQUIRE(session.dragVertex(5, session.mesh().positions.row(5).transpose() + Eigen::Vector3d(0.05, 0.02, -0.03) * diagonal, report).ok);
        // A second drag given in world coordinates of the deformed shape.
        const Eigen::Vector3d source = session.mesh().positions.row(7).transpose();
        const Eigen::Vector3d target = source + 0.03 * diagonal * test::randomVector(rng, -1, 1);
        REQUIRE(session.drag({PointConstraint{source, target}}, report).ok);
        REQUIRE((session.mesh().positions.row(7).transpose() - target).norm() <= 1e-8 * diagonal);
    }
}

TEST_CASE("session: bad input is refused with a message and changes nothing", "[core]") {
    std::mt19937 rng(53);
    Session session = randomSession(rng, 300);
    OpReport report;
    REQUIRE(session.dragVertex(1, session.mesh().positions.row(1).transpose() + Eigen::Vector3d(0.1, 0, 0), report).ok);
    const Positions positions = session.mesh().positions;
    const Positions displacement = session.lattice().displacement;
    const double inf = std::numeric_limits<double>::infinity();
    const Eigen::Vector3d inside = session.mesh().positions.row(2).transpose();

    auto refused = [&](Status status, const std::string& fragment) {
        REQUIRE_FALSE(status.ok);
        INFO(status.message);
        REQUIRE(status.message.find(fragment) != std::string::npos);
        REQUIRE(sameState(session, positions, displacement, 1));
    };
    refused(session.drag({}, report), "no constraints");
    refused(session.drag({PointConstraint{inside, Eigen::Vector3d(inf, 0, 0)}}, report), "non-finite");
    refused(session.drag({PointConstraint{Eigen::Vector3d(std::nan(""), 0, 0), inside}}, report), "non-finite");
    refused(session.drag({PointConstraint{inside, inside}, PointConstraint{Eigen::Vector3d(100, 100, 100), inside}}, report),
            "constraint 1 source");
    refused(session.dragVertex(300, inside, report), "out of range");
    refused(session.dragVertex(-1, inside, report), "out of range");
    refused(session.moveControlPoints({100000}, Eigen::MatrixX3d::Zero(1, 3), true, report), "outside the lattice");
    refused(session.moveControlPoints({3}, Eigen::MatrixX3d::Constant(1, 3, std::nan("")), true, report), "non-finite");

    Session pinnedSession = randomSession(rng, 300, [] { LatticeSettings s; s.pinLayers = 1; return s; }());
    const Status pinned = pinnedSession.moveControlPoints({0}, Eigen::MatrixX3d::Ones(1, 3), true, report);
    REQUIRE_FALSE(pinned.ok);
    REQUIRE(pinned.message.find("pinned") != std::string::npos);

    Session empty;
    REQUIRE_FALSE(empty.setMesh(Positions(0, 3), Triangles(0, 3)).ok);
    REQUIRE(empty.mesh().empty());
}

TEST_CASE("session: control point edits move exactly those points and undo", "[core]") {
    std::mt19937 rng(54);
    for (int trial = 0; trial < 20; ++trial) {
        Session session = randomSession(rng, 1500);
        const Positions original = session.mesh().positions;
        const int n = session.lattice().controlPointCount();
        std::vector<int> ids{test::randomInt(rng, 0, n - 1), test::randomInt(rng, 0, n - 1)};
        Eigen::MatrixX3d to(2, 3);
        for (int c = 0; c < 2; ++c) to.row(c) = session.lattice().controlPoint(ids[c]).transpose() + 0.1 * test::randomVector(rng, -1, 1).transpose();
        if (ids[0] == ids[1]) to.row(0) = to.row(1);
        OpReport report;
        REQUIRE(session.moveControlPoints(ids, to, false, report).ok);
        for (int c = 0; c < 2; ++c) REQUIRE((session.lattice().controlPoint(ids[c]) - to.row(c).transpose()).norm() <= 1e-12);
        for (int idx = 0; idx < n; ++idx)
            if (idx != ids[0] && idx != ids[1]) REQUIRE(session.lattice().displacement.row(idx).isZero(0.0));
        REQUIRE(session.undo(report).ok);
        REQUIRE((session.mesh().positions - original).cwiseAbs().maxCoeff() <= 1e-12);
    }
}

TEST_CASE("session: an interactive drag of many small moves is one history entry equal to one big drag", "[core]") {
    std::mt19937 rng(55);
    for (int trial = 0; trial < 10; ++trial) {
        Session incremental = randomSession(rng, 900);
        Session direct = incremental;
        const double diagonal = incremental.lattice().diagonal();
        Eigen::Vector3d params;
        REQUIRE(incremental.parametersOfVertex(10, params).ok);
        const Eigen::Vector3d start = incremental.mesh().positions.row(10).transpose();
        const Eigen::Vector3d end = start + 0.1 * diagonal * test::randomVector(rng, -1, 1);
        REQUIRE(incremental.stroke().begin({params}).ok);
        OpReport report;
        for (int step = 1; step <= 20; ++step)
            REQUIRE(incremental.stroke().update({start + (end - start) * (step / 20.0) + 0.01 * diagonal * test::randomVector(rng, -1, 1) * (step < 20)}, report).ok);
        incremental.stroke().end();
        REQUIRE(incremental.history().size() == 1);
        REQUIRE(direct.dragVertex(10, end, report).ok);
        REQUIRE((incremental.mesh().positions - direct.mesh().positions).cwiseAbs().maxCoeff() <= 1e-9 * diagonal);
        REQUIRE(incremental.undo(report).ok);
        REQUIRE((incremental.mesh().positions - incremental.mesh().rest).cwiseAbs().maxCoeff() <= 1e-9 * diagonal);
    }
}

TEST_CASE("session: a lattice re-setup is an operation, undo returns to the old lattice and mesh", "[core]") {
    std::mt19937 rng(56);
    for (int trial = 0; trial < 10; ++trial) {
        Session session = randomSession(rng, 600);
        session.setInjectivity({InjectivityMode::Conic, 6});
        const double diagonal = session.lattice().diagonal();
        OpReport report;
        REQUIRE(session.dragVertex(3, session.mesh().positions.row(3).transpose() + 0.02 * diagonal * test::randomVector(rng, -1, 1), report).ok);
        const Positions beforeSetup = session.mesh().positions;
        const Lattice oldLattice = session.lattice();
        LatticeSettings finer;
        finer.resolution = {10, 11, 12};
        finer.degree = {2, 3, 2};
        REQUIRE(session.setupLattice(finer, report).ok);
        REQUIRE(session.lattice().count == finer.resolution);
        REQUIRE(session.mesh().positions == beforeSetup);  // re-embedding keeps the shape
        REQUIRE(session.dragVertex(9, session.mesh().positions.row(9).transpose() + 0.02 * diagonal * test::randomVector(rng, -1, 1), report).ok);
        REQUIRE(session.undo(report).ok);
        REQUIRE(session.undo(report).ok);  // the set-up
        REQUIRE(session.lattice().count == oldLattice.count);
        REQUIRE((session.lattice().displacement - oldLattice.displacement).cwiseAbs().maxCoeff() <= 1e-15);
        REQUIRE((session.mesh().positions - beforeSetup).cwiseAbs().maxCoeff() <= 1e-9 * diagonal);
        REQUIRE(session.undo(report).ok);
        REQUIRE((session.mesh().positions - session.mesh().original).cwiseAbs().maxCoeff() <= 1e-9 * diagonal);
        // Bad settings are refused and change nothing.
        LatticeSettings bad;
        bad.degree = {0, 3, 3};
        REQUIRE_FALSE(session.setupLattice(bad, report).ok);
        REQUIRE(session.history().cursor() == 0);
    }
}

TEST_CASE("session: a new operation after undo drops the redo branch", "[core]") {
    std::mt19937 rng(57);
    Session session = randomSession(rng, 300);
    OpReport report;
    for (int op = 0; op < 4; ++op)
        REQUIRE(session.dragVertex(op, session.mesh().positions.row(op).transpose() + Eigen::Vector3d(0.01, 0, 0), report).ok);
    REQUIRE(session.undo(report).ok);
    REQUIRE(session.undo(report).ok);
    REQUIRE(session.history().size() == 4);
    REQUIRE(session.dragVertex(7, session.mesh().positions.row(7).transpose() + Eigen::Vector3d(0, 0.01, 0), report).ok);
    REQUIRE(session.history().size() == 3);
    REQUIRE(session.history().cursor() == 3);
    REQUIRE(session.redo(report).ok);
    REQUIRE(report.status == OpStatus::NoOp);
}

TEST_CASE("session: an interactive control-point drag is one history entry equal to one control-point edit", "[core]") {
    std::mt19937 rng(57);
    for (int trial = 0; trial < 12; ++trial) {
        Session incremental = randomSession(rng, 1200);
        Session direct = incremental;
        const int n = incremental.lattice().controlPointCount();
        const double diagonal = incremental.lattice().diagonal();
        std::vector<int> ids;
        for (int k = 0, count = test::randomInt(rng, 1, 4); k < count; ++k) ids.push_back(test::randomInt(rng, 0, n - 1));
        const Eigen::Vector3d total = 0.05 * diagonal * test::randomVector(rng, -1, 1);
        REQUIRE(incremental.stroke().beginControl(ids).ok);
        REQUIRE(incremental.stroke().active());
        OpReport report;
        const int moves = test::randomInt(rng, 2, 25);
        for (int m = 1; m <= moves; ++m) {  // wander, then end exactly at the total offset
            const Eigen::Vector3d offset = m == moves ? total : Eigen::Vector3d(total * (m / double(moves)) + 0.02 * diagonal * test::randomVector(rng, -1, 1));
            REQUIRE(incremental.stroke().updateControl(offset, report).ok);
            REQUIRE(report.status == OpStatus::Applied);
        }
        REQUIRE(incremental.moveControlPoints(ids, Eigen::MatrixX3d::Zero(1, 3), true, report).ok == false);  // busy
        incremental.stroke().end();
        REQUIRE(incremental.history().size() == 1);
        REQUIRE(incremental.history().front().kind == OperationKind::ControlPointEdit);

        std::vector<int> unique = ids;
        std::sort(unique.begin(), unique.end());
        unique.erase(std::unique(unique.begin(), unique.end()), unique.end());
        Eigen::MatrixX3d offsets(static_cast<Eigen::Index>(unique.size()), 3);
        offsets.rowwise() = total.transpose();
        REQUIRE(direct.moveControlPoints(unique, offsets, true, report).ok);
        REQUIRE((incremental.mesh().positions - direct.mesh().positions).cwiseAbs().maxCoeff() <= 1e-12 * diagonal);
        for (int idx : unique) REQUIRE((incremental.lattice().displacement.row(idx).transpose() - total).norm() <= 1e-12 * diagonal);

        // Undo is the inverse manipulation; redo reapplies it.
        const Positions after = incremental.mesh().positions;
        REQUIRE(incremental.undo(report).ok);
        REQUIRE((incremental.mesh().positions - incremental.mesh().rest).cwiseAbs().maxCoeff() <= 1e-12 * diagonal);
        REQUIRE(incremental.lattice().displacement.isZero(1e-12 * diagonal));
        REQUIRE(incremental.redo(report).ok);
        REQUIRE((incremental.mesh().positions - after).cwiseAbs().maxCoeff() <= 1e-12 * diagonal);

        // The recording replays it.
        const Script recording = recordSession(incremental);
        Session replayed;
        const Status set = replayed.setMesh(incremental.mesh().original, incremental.mesh().triangles, recording.lattice);
        INFO(set.message);
        REQUIRE(set.ok);
        replayed.setInjectivity(recording.injectivity);
        ScriptReport scriptReport;
        REQUIRE(runScript(replayed, recording, scriptReport).ok);
        REQUIRE((replayed.mesh().positions - after).cwiseAbs().maxCoeff() <= 1e-9 * diagonal);
    }
}

TEST_CASE("session: a control-point drag with an offset per point equals one edit and stops where it would fold", "[core]") {
    std::mt19937 rng(61);
    int stopped = 0;
    for (int trial = 0; trial < 10; ++trial) {
        Session incremental = randomSession(rng, 900);
        Session direct = incremental;  // injectivity off: applies the same edit in one go
        // A soup of random crossing triangles: the lattice's test is under test, not the triangle check.
        InjectivitySettings injectivity{InjectivityMode::Conic, 5};
        injectivity.checkTriangles = false;
        incremental.setInjectivity(injectivity);
        const int n = incremental.lattice().controlPointCount();
        const double diagonal = incremental.lattice().diagonal();
        std::vector<int> ids;
        for (int k = 0, count = test::randomInt(rng, 2, 5); k < count; ++k) ids.push_back(test::randomInt(rng, 0, n - 1));
        std::sort(ids.begin(), ids.end());
        ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
        // A rotation of the points about their centroid, in steps (as the window's R follows the mouse); large
        // ones (odd trials) fold the lattice somewhere on the way.
        std::vector<Eigen::Vector3d> starts;
        Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
        for (int id : ids) {
            starts.push_back(incremental.lattice().controlPoint(id));
            centroid += starts.back() / double(ids.size());
        }
        const Eigen::Vector3d axis = test::randomVector(rng, -1, 1).normalized();
        const double angle = (trial % 2 == 0 ? 0.15 : 2.5) * std::uniform_real_distribution<double>(0.5, 1.0)(rng);
        const auto offsetsAt = [&](double a) {
            Eigen::MatrixX3d offsets(static_cast<Eigen::Index>(ids.size()), 3);
            const Eigen::Matrix3d rotation = Eigen::AngleAxisd(a, axis).toRotationMatrix();
            for (size_t r = 0; r < ids.size(); ++r)
                offsets.row(static_cast<Eigen::Index>(r)) = (rotation * (starts[r] - centroid) + centroid - starts[r]).transpose();
            return offsets;
        };
        REQUIRE(incremental.stroke().beginControl(ids).ok);
        OpReport report;
        REQUIRE_FALSE(incremental.stroke().updateControlPerPoint(Eigen::MatrixX3d::Zero(static_cast<Eigen::Index>(ids.size()) + 1, 3), report).ok);
        bool anyStop = false;
        for (int m = 1; m <= 8; ++m) {
            REQUIRE(incremental.stroke().updateControlPerPoint(offsetsAt(angle * m / 8.0), report).ok);
            anyStop = anyStop || report.fractionApplied < 1.0;
        }
        stopped += anyStop;
        CHECK(incremental.cage().frameDepth() == 0);  // never a fresh lattice: the points stop instead
        // What the drag applied, as one edit: each point's displacement.
        Eigen::MatrixX3d applied(static_cast<Eigen::Index>(ids.size()), 3);
        for (size_t r = 0; r < ids.size(); ++r)
            applied.row(static_cast<Eigen::Index>(r)) = (incremental.lattice().controlPoint(ids[r]) - starts[r]).transpose();
        incremental.stroke().end();
        if (applied.isZero(0.0)) {
            CHECK(incremental.history().empty());
            continue;
        }
        REQUIRE(incremental.history().size() == 1);
        CHECK((incremental.history().front().offsets - applied).cwiseAbs().maxCoeff() <= 1e-12 * diagonal);
        if (!anyStop) CHECK((applied - offsetsAt(angle)).cwiseAbs().maxCoeff() <= 1e-12 * diagonal);
        REQUIRE(direct.moveControlPoints(ids, applied, true, report).ok);
        CHECK((incremental.mesh().positions - direct.mesh().positions).cwiseAbs().maxCoeff() <= 1e-12 * diagonal);
        REQUIRE(incremental.undo(report).ok);
        CHECK((incremental.mesh().positions - incremental.mesh().rest).cwiseAbs().maxCoeff() <= 1e-12 * diagonal);
    }
    CHECK(stopped >= 1);
}

TEST_CASE("session: a control-point drag refuses pinned or unknown points and a drag of nothing changes nothing", "[core]") {
    std::mt19937 rng(58);
    Session session = randomSession(rng, 600);
    const int n = session.lattice().controlPointCount();
    REQUIRE_FALSE(session.stroke().beginControl({}).ok);
    REQUIRE_FALSE(session.stroke().beginControl({n}).ok);
    REQUIRE_FALSE(session.stroke().beginControl({-1}).ok);
    REQUIRE(session.pins().set({5}, true).ok);
    const Status pinned = session.stroke().beginControl({4, 5});
    REQUIRE_FALSE(pinned.ok);
    REQUIRE(pinned.message.find("pinned") != std::string::npos);
    REQUIRE_FALSE(session.stroke().active());
    OpReport report;
    REQUIRE_FALSE(session.stroke().updateControl(Eigen::Vector3d(0.1, 0, 0), report).ok);  // no drag in progress
    REQUIRE(session.stroke().beginControl({4}).ok);
    REQUIRE_FALSE(session.stroke().update({Eigen::Vector3d::Zero()}, report).ok);  // the other kind of drag
    REQUIRE_FALSE(session.stroke().updateControl(Eigen::Vector3d(NAN, 0, 0), report).ok);
    REQUIRE(session.stroke().updateControl(Eigen::Vector3d::Zero(), report).ok);
    REQUIRE(report.status == OpStatus::NoOp);
    session.stroke().end();
    REQUIRE(session.history().empty());
    REQUIRE(session.mesh().positions == session.mesh().rest);
}

TEST_CASE("session: cancelling a drag takes back what it applied, subdivided steps included", "[core]") {
    std::mt19937 rng(59);
    int subdivided = 0;
    for (int trial = 0; trial < 12; ++trial) {
        Session session = randomSession(rng, 900);
        // A soup of random crossing triangles: the lattice's subdivision is under test, not the triangle check.
        InjectivitySettings injectivity{InjectivityMode::Conic, 5};
        injectivity.checkTriangles = false;
        session.setInjectivity(injectivity);
        OpReport report;
        REQUIRE(session.dragVertex(3, session.mesh().positions.row(3).transpose() + 0.05 * session.lattice().diagonal() * test::randomVector(rng, -1, 1), report).ok);
        const Positions before = session.mesh().positions;
        const double diagonal = session.lattice().diagonal();
        const int frames = session.cage().frameDepth();
        if (trial % 2 == 0) {
            Eigen::Vector3d params;
            REQUIRE(session.parametersOfVertex(10, params).ok);
            REQUIRE(session.stroke().begin({params}).ok);
            const Eigen::Vector3d start = session.stroke().sources().front();
            const Eigen::Vector3d offset = (trial % 4 == 0 ? 0.6 : 0.05) * diagonal * test::randomVector(rng, -1, 1);
            for (int m = 1; m <= 6; ++m) REQUIRE(session.stroke().update({start + offset * (m / 6.0)}, report).ok);
        } else {
            REQUIRE(session.stroke().beginControl({test::randomInt(rng, 0, session.lattice().controlPointCount() - 1)}).ok);
            const Eigen::Vector3d offset = (trial % 4 == 1 ? 0.6 : 0.05) * diagonal * test::randomVector(rng, -1, 1);
            for (int m = 1; m <= 6; ++m) REQUIRE(session.stroke().updateControl(offset * (m / 6.0), report).ok);
        }
        subdivided += session.cage().frameDepth() > frames;
        INFO("trial " << trial << ", frames " << frames << " -> " << session.cage().frameDepth());
        REQUIRE(session.stroke().cancel(report).ok);
        CHECK_FALSE(session.stroke().active());
        CHECK(session.history().size() == 1);
        CHECK(session.cage().frameDepth() == frames);
        CHECK((session.mesh().positions - before).cwiseAbs().maxCoeff() <= 1e-9 * diagonal);
        REQUIRE(session.stroke().cancel(report).ok);
        CHECK(report.status == OpStatus::NoOp);
        REQUIRE(session.undo(report).ok);  // the history before the drag is intact
        CHECK((session.mesh().positions - session.mesh().original).cwiseAbs().maxCoeff() <= 1e-9 * diagonal);
    }
    CHECK(subdivided >= 2);
}

TEST_CASE("session: restVersion changes whenever the rest mesh or its embedding does", "[core]") {
    // The renderer's GPU path keeps a copy of restPositions() and the cage cells of every vertex, and uploads it
    // again only when mesh().restVersion changes: an unchanged version must mean unchanged rest data.
    std::mt19937 rng(31);
    for (int trial = 0; trial < 4; ++trial) {
        Session session = randomSession(rng, 600);
        session.setInjectivity({trial % 2 ? InjectivityMode::Conic : InjectivityMode::Off, 4});
        std::uint64_t version = session.mesh().restVersion;
        Positions rest = session.mesh().rest;
        Embedding embedding = session.cage().embedding();
        int changes = 0;
        for (int op = 0; op < 40; ++op) {
            OpReport report;
            const int kind = test::randomInt(rng, 0, 9);
            const int vertex = test::randomInt(rng, 0, int(session.mesh().positions.rows()) - 1);
            const Eigen::Vector3d target = session.mesh().positions.row(vertex).transpose() + test::randomVector(rng, -0.4, 0.4);
            if (kind <= 3) {
                (void)session.dragVertex(vertex, target, report);
            } else if (kind == 4) {
                BrushSettings brush;
                brush.radius = 0.6;
                (void)session.dragVertex(vertex, target, report, brush);
            } else if (kind == 5) {
                LatticeSettings settings;
                settings.resolution = {test::randomInt(rng, 4, 7), test::randomInt(rng, 4, 7), test::randomInt(rng, 4, 7)};
                (void)session.setupLattice(settings, report);
            } else if (kind <= 7) {
                (void)session.undo(report);
            } else {
                (void)session.redo(report);
            }
            if (session.mesh().restVersion == version) {
                INFO("trial " << trial << ", op " << op << " (kind " << kind << ")");
                REQUIRE(session.mesh().rest.rows() == rest.rows());
                CHECK(session.mesh().rest == rest);
                CHECK(session.cage().embedding().order == embedding.order);
                CHECK(session.cage().embedding().cellStart == embedding.cellStart);
                CHECK(session.cage().embedding().localX == embedding.localX);
                CHECK(session.cage().embedding().localZ == embedding.localZ);
            } else {
                ++changes;
                version = session.mesh().restVersion;
                rest = session.mesh().rest;
                embedding = session.cage().embedding();
            }
        }
        CHECK(changes > 0);  // set-ups (and their undos) did change it
    }
}
