// issue 9 item 2: a saved session replays to the same mesh. Random sessions of 50-200 commands mixing every op
// kind (drags of one and several points, drag_vertex, control-point edits to and by, set-ups, pins, undo,
// redo, groups, interactive drags and control drags, taken-back drags), conic and exact, small and large
// moves, on three meshes: recorded, written as JSON, read back and replayed on the same mesh, they give the
// same vertices (to 1e-12 of the diagonal), the same history and the same pins.
#include <catch2/catch.hpp>

#include <random>

#include "../core/mesh_fixtures.h"
#include "../core/test_support.h"
#include "io/script.h"
#include "core/session/session.h"
#include "io/script_json.h"
#include "replay_support.h"

using namespace sculpt;
using namespace sculpt::core;
using namespace sculpt::io;

namespace {

struct TestMesh {
    Positions positions;
    Triangles triangles;
};

// Three shapes: a sphere, a flattened off-centre sphere, and a torus-like ring of quads.
TestMesh testMesh(int which) {
    TestMesh mesh;
    if (which < 2) {
        test::icosphere(2, 1.0, Eigen::Vector3d(0.3 * which, -0.2, 0.1), mesh.positions, mesh.triangles);
        if (which == 1) mesh.positions.col(2) *= 0.4;
        return mesh;
    }
    const int ring = 24, tube = 8;
    mesh.positions.resize(ring * tube, 3);
    mesh.triangles.resize(2 * ring * tube, 3);
    for (int i = 0; i < ring; ++i)
        for (int j = 0; j < tube; ++j) {
            const double u = 2 * M_PI * i / ring, v = 2 * M_PI * j / tube;
            mesh.positions.row(i * tube + j) << (1.0 + 0.35 * std::cos(v)) * std::cos(u), (1.0 + 0.35 * std::cos(v)) * std::sin(u), 0.35 * std::sin(v);
            const int a = i * tube + j, b = ((i + 1) % ring) * tube + j, c = ((i + 1) % ring) * tube + (j + 1) % tube, d = i * tube + (j + 1) % tube;
            mesh.triangles.row(2 * a) << a, b, c;
            mesh.triangles.row(2 * a + 1) << a, c, d;
        }
    return mesh;
}

// One random command of any kind; `size` scales the moves (small or large).
void randomCommand(Session& session, std::mt19937& rng, double size, int& openGroup) {
    const double diagonal = session.lattice().diagonal();
    const int vertices = static_cast<int>(session.mesh().positions.rows());
    OpReport report;
    const auto vertexPoint = [&](int v) -> Eigen::Vector3d { return session.mesh().positions.row(v).transpose(); };
    switch (test::randomInt(rng, 0, 13)) {
        case 0:
        case 1: {  // drag_vertex
            const int v = test::randomInt(rng, 0, vertices - 1);
            REQUIRE(session.dragVertex(v, vertexPoint(v) + size * diagonal * test::randomVector(rng, -1, 1), report).ok);
            break;
        }
        case 2: {  // a drag of one to three points
            std::vector<PointConstraint> constraints;
            for (int c = test::randomInt(rng, 1, 3); c > 0; --c) {
                const Eigen::Vector3d p = vertexPoint(test::randomInt(rng, 0, vertices - 1));
                constraints.push_back({p, p + size * diagonal * test::randomVector(rng, -1, 1)});
            }
            const Status s = session.drag(constraints, report);  // a source that left the lattice is an error
            (void)s;
            break;
        }
        case 3:
        case 4: {  // control-point edits, "by" and "to"
            const Lattice& lattice = session.lattice();
            std::vector<int> ids;
            for (int c = test::randomInt(rng, 1, 3); c > 0; --c) {
                const int idx = test::randomInt(rng, 0, lattice.controlPointCount() - 1);
                if (!lattice.pinned[idx]) ids.push_back(idx);
            }
            if (ids.empty()) break;
            Eigen::MatrixX3d values(static_cast<Eigen::Index>(ids.size()), 3);
            const bool relative = test::randomInt(rng, 0, 1) == 0;
            for (size_t c = 0; c < ids.size(); ++c) {
                const Eigen::Vector3d offset = 0.5 * size * diagonal * test::randomVector(rng, -1, 1);
                // "to" is where the point is shown (carried through the layers) plus the offset
                values.row(static_cast<Eigen::Index>(c)) = (relative ? offset : Eigen::Vector3d(session.cage().cagePoints().row(ids[c]).transpose() + offset)).transpose();
            }
            REQUIRE(session.moveControlPoints(ids, values, relative, report).ok);
            break;
        }
        case 5: {  // set-up with new settings (rarely) or the same
            LatticeSettings settings = session.cage().settings();
            if (test::randomInt(rng, 0, 1)) settings.resolution = {test::randomInt(rng, 5, 8), test::randomInt(rng, 5, 8), test::randomInt(rng, 5, 8)};
            settings.pinLayers = test::randomInt(rng, 0, 1);
            REQUIRE(session.setupLattice(settings, report).ok);
            break;
        }
        case 6: {  // pins
            std::vector<int> ids;
            for (int c = 0; c < 4; ++c) ids.push_back(test::randomInt(rng, 0, session.lattice().controlPointCount() - 1));
            REQUIRE(session.pins().set(ids, test::randomInt(rng, 0, 2) != 0).ok);
            break;
        }
        case 7:
        case 8: REQUIRE(session.undo(report).ok); break;
        case 9: REQUIRE(session.redo(report).ok); break;
        case 10:
        case 11: {  // an interactive drag, sometimes taken back
            Eigen::Vector3d t;
            const int v = test::randomInt(rng, 0, vertices - 1);
            if (!session.cage().parametersOfCurrentPoint(vertexPoint(v), t)) break;
            REQUIRE(session.stroke().begin({t}).ok);
            const Eigen::Vector3d start = session.stroke().sources().front();
            const Eigen::Vector3d offset = size * diagonal * test::randomVector(rng, -1, 1);
            const int moves = test::randomInt(rng, 2, 6);
            for (int m = 1; m <= moves; ++m) REQUIRE(session.stroke().update({start + offset * (double(m) / moves)}, report).ok);
            if (test::randomInt(rng, 0, 3) == 0) REQUIRE(session.stroke().cancel(report).ok);
            else session.stroke().end();
            break;
        }
        case 12: {  // an interactive control-point drag
            const int idx = test::randomInt(rng, 0, session.lattice().controlPointCount() - 1);
            if (session.lattice().pinned[idx]) break;
            REQUIRE(session.stroke().beginControl({idx}).ok);
            const Eigen::Vector3d offset = 0.5 * size * diagonal * test::randomVector(rng, -1, 1);
            for (int m = 1; m <= 4; ++m) REQUIRE(session.stroke().updateControl(offset * (m / 4.0), report).ok);
            session.stroke().end();
            break;
        }
        case 13: {  // a group of the last operations (as a replayed interactive drag makes)
            if (openGroup < 0) {
                if (session.history().cursor() == static_cast<int>(session.history().size())) openGroup = session.history().cursor();
            } else {
                if (session.history().cursor() == static_cast<int>(session.history().size()) && openGroup <= session.history().cursor()) {
                    const Status s = session.groupOperations(openGroup, "group");  // mixed kinds are refused
                    (void)s;
                }
                openGroup = -1;
            }
            break;
        }
    }
}

TEST_CASE("recording: random sessions of every op kind replay on their mesh to the same vertices", "[io]") {
    std::mt19937 rng(90210);
    int commands = 0, subdivided = 0;
    for (int trial = 0; trial < 9; ++trial) {
        const TestMesh mesh = testMesh(trial % 3);
        LatticeSettings settings;
        settings.resolution = {test::randomInt(rng, 5, 8), test::randomInt(rng, 5, 8), test::randomInt(rng, 5, 8)};
        settings.degree = {3, 3, test::randomInt(rng, 2, 3)};
        Session original;
        REQUIRE(original.setMesh(mesh.positions, mesh.triangles, settings).ok);
        original.setInjectivity({trial % 2 ? InjectivityMode::Exact : InjectivityMode::Conic, 4});
        const int count = test::randomInt(rng, 50, 200);
        const double size = trial % 4 < 2 ? 0.03 : 0.25;  // small and large moves
        int openGroup = -1;
        for (int c = 0; c < count; ++c) randomCommand(original, rng, size, openGroup);
        commands += count;
        for (const Operation& op : original.history()) subdivided += op.steps.size() > 1;

        const Script recording = recordSession(original);
        Script parsed;
        Session replayed = test::replayThroughJson(recording, mesh.positions, mesh.triangles, parsed);
        const double diagonal = original.lattice().diagonal();
        INFO("trial " << trial << ": " << count << " commands, " << original.history().journal().size() << " journal entries");
        // note: not bit for bit: an interactive drag's increments were added to the mesh one by one, and the
        // replay adds their sum (one step per frame), which rounds differently.
        REQUIRE((replayed.mesh().positions - original.mesh().positions).cwiseAbs().maxCoeff() <= 1e-12 * diagonal);
        REQUIRE(replayed.history().size() == original.history().size());
        REQUIRE(replayed.history().cursor() == original.history().cursor());
        for (size_t i = 0; i < original.history().size(); ++i) {
            CHECK(replayed.history()[i].label == original.history()[i].label);
            CHECK(replayed.history()[i].steps.size() == original.history()[i].steps.size());
        }
        CHECK(replayed.pins().toggles() == original.pins().toggles());
        CHECK(replayed.cage().frameDepth() == original.cage().frameDepth());
        // The replayed session goes on like the original: undo everything, redo everything.
        OpReport report;
        for (int u = 0; u < original.history().cursor(); ++u) {
            REQUIRE(original.undo(report).ok);
            REQUIRE(replayed.undo(report).ok);
        }
        CHECK((replayed.mesh().positions - original.mesh().positions).cwiseAbs().maxCoeff() <= 1e-12 * diagonal);
    }
    CHECK(commands > 900);
    CHECK(subdivided > 0);
}

// Replayed on another mesh (no matching fingerprint), the recording's operations are decided again for that
// mesh: the replay still runs, and on a copy of the mesh that differs only in one far vertex the first drag's
// source still lands on its target.
TEST_CASE("recording: on another mesh the operations are decided again", "[io]") {
    const TestMesh mesh = testMesh(0);
    Session original;
    REQUIRE(original.setMesh(mesh.positions, mesh.triangles, {}).ok);
    OpReport report;
    const Eigen::Vector3d target = mesh.positions.row(5).transpose() + Eigen::Vector3d(0.1, 0.05, 0.0);
    REQUIRE(original.dragVertex(5, target, report).ok);
    REQUIRE(report.status == OpStatus::Applied);
    Script recording = recordSession(original);
    REQUIRE_FALSE(recording.meshFingerprint.empty());
    TestMesh other = mesh;
    other.positions(0, 0) += 1e-6;  // another mesh, if only just
    Script parsed;
    Session replayed = test::replayThroughJson(recording, other.positions, other.triangles, parsed);
    REQUIRE(replayed.meshAsSet().fingerprint != recording.meshFingerprint);
    REQUIRE(replayed.history().size() == 1);
    CHECK((replayed.mesh().positions.row(5).transpose() - target).norm() <= 1e-9 * original.lattice().diagonal());
}

}  // namespace
