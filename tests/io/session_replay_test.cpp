// A saved session reopens with the same history: interactive drags and control-point drags come back as one
// undo step each, with the same injective steps (a recording holds each operation with the steps it was applied as).
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

// A random interactive drag of one or two sources in `moves` increments; large ones get subdivided.
void interactiveDrag(Session& session, std::mt19937& rng, const Positions& mesh, double size) {
    const int sources = test::randomInt(rng, 1, 2), moves = test::randomInt(rng, 3, 10);
    std::vector<Eigen::Vector3d> params, starts;
    for (int s = 0; s < sources; ++s) {
        Eigen::Vector3d t;
        const int v = test::randomInt(rng, 0, static_cast<int>(mesh.rows()) - 1);
        if (!session.cage().parametersOfCurrentPoint(session.mesh().positions.row(v).transpose(), t)) continue;
        params.push_back(t);
    }
    if (params.empty()) return;
    REQUIRE(session.stroke().begin(params).ok);
    starts = session.stroke().sources();
    std::vector<Eigen::Vector3d> offsets;
    for (size_t s = 0; s < params.size(); ++s) offsets.push_back(size * test::randomVector(rng, -1, 1));
    for (int m = 1; m <= moves; ++m) {
        std::vector<Eigen::Vector3d> targets;
        for (size_t s = 0; s < params.size(); ++s) targets.push_back(starts[s] + offsets[s] * (double(m) / moves));
        OpReport report;
        REQUIRE(session.stroke().update(targets, report).ok);
    }
    session.stroke().end();
}

}  // namespace

TEST_CASE("recording: a replayed session has the same history entries, undo and redo", "[io]") {
    std::mt19937 rng(702);
    Positions positions;
    Triangles triangles;
    test::icosphere(2, 1.0, Eigen::Vector3d::Zero(), positions, triangles);
    int grouped = 0, subdividedGroups = 0;
    for (int trial = 0; trial < 5; ++trial) {
        LatticeSettings settings;
        settings.resolution = {6, 6, 6};
        settings.pinLayers = trial % 2;
        Session original;
        REQUIRE(original.setMesh(positions, triangles, settings).ok);
        original.setInjectivity({InjectivityMode::Conic, 5});
        for (int op = 0; op < 7; ++op) {
            const int n = original.lattice().controlPointCount();  // a set-up may have changed it
            OpReport report;
            switch (test::randomInt(rng, 0, 3)) {
                case 0: interactiveDrag(original, rng, positions, op % 2 ? 0.8 : 0.1); break;
                case 1: {  // an interactive control-point drag
                    std::vector<int> ids;
                    for (int k = 0; k < 3; ++k) {
                        const int id = test::randomInt(rng, 0, n - 1);
                        if (!original.lattice().pinned[id]) ids.push_back(id);
                    }
                    if (ids.empty()) break;
                    const Status begun = original.stroke().beginControl(ids);
                    INFO(begun.message);
                    REQUIRE(begun.ok);
                    const Eigen::Vector3d offset = (op % 2 ? 0.6 : 0.1) * test::randomVector(rng, -1, 1);
                    for (int m = 1; m <= 5; ++m) REQUIRE(original.stroke().updateControl(offset * (m / 5.0), report).ok);
                    original.stroke().end();
                    break;
                }
                case 2: {
                    const int v = test::randomInt(rng, 0, static_cast<int>(positions.rows()) - 1);
                    REQUIRE(original.dragVertex(v, original.mesh().positions.row(v).transpose() + 0.2 * test::randomVector(rng, -1, 1), report).ok);
                    break;
                }
                default: {
                    LatticeSettings other = settings;
                    other.resolution = {test::randomInt(rng, 5, 8), 6, test::randomInt(rng, 5, 8)};
                    REQUIRE(original.setupLattice(other, report).ok);
                }
            }
        }
        const Script recording = recordSession(original);
        Script parsed;
        Session replayed = test::replayThroughJson(recording, positions, triangles, parsed);

        const double diagonal = original.lattice().diagonal();
        REQUIRE(replayed.history().size() == original.history().size());
        for (size_t i = 0; i < original.history().size(); ++i) {
            const Operation& a = original.history()[i];
            const Operation& b = replayed.history()[i];
            CHECK(a.kind == b.kind);
            CHECK(a.label == b.label);
            CHECK(a.interactive == b.interactive);
            if (!a.interactive) continue;
            ++grouped;
            subdividedGroups += a.steps.size() > 1;
            // The same steps, less the ones that moved nothing (all their control points pinned).
            size_t effective = 0;
            for (const Step& step : a.steps) effective += !step.delta.indices.empty() || step.freshFrame;
            CHECK(b.steps.size() == effective);
        }
        CHECK((replayed.mesh().positions - original.mesh().positions).cwiseAbs().maxCoeff() <= 1e-12 * diagonal);  // the recorded steps, repeated
        const Positions final = replayed.mesh().positions;
        OpReport step;
        for (size_t i = 0; i < replayed.history().size(); ++i) REQUIRE(replayed.undo(step).ok);
        CHECK((replayed.mesh().positions - positions).cwiseAbs().maxCoeff() <= 1e-9 * diagonal);
        for (size_t i = 0; i < replayed.history().size(); ++i) REQUIRE(replayed.redo(step).ok);
        CHECK((replayed.mesh().positions - final).cwiseAbs().maxCoeff() <= 1e-9 * diagonal);
    }
    CHECK(grouped >= 5);
    CHECK(subdividedGroups >= 2);
}

TEST_CASE("recording: groups must be closed, in order, and not mix drags with control-point edits", "[io]") {
    Positions positions;
    Triangles triangles;
    test::icosphere(1, 1.0, Eigen::Vector3d::Zero(), positions, triangles);
    for (const char* text : {R"({"ops":[{"op":"end_group"}]})",
                             R"({"ops":[{"op":"begin_group","label":"x"},{"op":"drag_vertex","vertex":0,"target":[1.1,0,0]}]})",
                             R"({"ops":[{"op":"begin_group"},{"op":"drag_vertex","vertex":0,"target":[1.1,0,0]},
                                        {"op":"move_control_point","index":[3,3,3],"by":[0.1,0,0]},{"op":"end_group"}]})"}) {
        Session session;
        REQUIRE(session.setMesh(positions, triangles).ok);
        Script script;
        REQUIRE(io::parseScript(text, "groups.json", script).ok);
        ScriptReport report;
        const Status ran = runScript(session, script, report);
        CHECK_FALSE(ran.ok);
        CHECK(ran.message.find("group") != std::string::npos);
    }
    Script script;
    CHECK_FALSE(io::parseScript(R"({"ops":[{"op":"begin_group","label":3}]})", "groups.json", script).ok);
}

// A drag (the window's stroke, or a script's) scales its pull by the brush's strength; its recording, replayed
// where the recorded steps do not apply (another mesh: here the same one with the fingerprint cleared, so the
// result must be the same), solves the drag again from the recorded targets and brush. The strength must be
// applied once: the recorded targets are the pulls as asked, not as scaled.
TEST_CASE("recording: a drag with strength below 1 replays on another mesh with its strength applied once", "[io]") {
    Positions positions;
    Triangles triangles;
    test::icosphere(2, 1.0, Eigen::Vector3d::Zero(), positions, triangles);
    std::mt19937 rng(11);
    int compared = 0;
    for (int trial = 0; trial < 16; ++trial) {
        const bool scripted = trial >= 8;  // a script's drag, one update of the same stroke
        BrushSettings brush;
        brush.strength = 0.3 + 0.1 * (trial % 8) / 2.0;              // 0.3 .. 0.65
        if (trial % 2 == 0) brush.radius = 0.5;                     // a brush stroke; otherwise a solved drag
        if (trial % 4 == 1) brush.symmetry.mirror[0] = true;        // with a mirror image
        Session original;
        REQUIRE(original.setMesh(positions, triangles).ok);
        const int v = test::randomInt(rng, 0, static_cast<int>(positions.rows()) - 1);
        const Eigen::Vector3d start = positions.row(v).transpose();
        if (brush.symmetry.mirror[0] && std::abs(start.x()) < 0.2) continue;  // images that merge
        const Eigen::Vector3d pull = 0.4 * (start.normalized() + 0.5 * test::randomVector(rng, -1, 1));
        OpReport report;
        if (scripted) {
            REQUIRE(original.drag({{start, start + pull}}, report, brush).ok);
        } else {
            REQUIRE(original.stroke().beginAt({start}, {}, brush).ok);
            for (int m = 1; m <= 4; ++m) REQUIRE(original.stroke().update({start + pull * (m / 4.0)}, report).ok);
            original.stroke().end();
        }
        INFO("trial " << trial << ": " << report.reason);
        if (original.history().size() != 1) continue;  // refused: nothing to replay
        Script recording = recordSession(original);
        recording.meshFingerprint.clear();  // solve again, as on another mesh
        Script parsed;
        const Session replayed = test::replayThroughJson(recording, positions, triangles, parsed);
        const double diagonal = original.lattice().diagonal();
        // The grabbed vertex lands where the window's stroke put it (strength once), not short of it.
        CHECK((replayed.mesh().positions.row(v) - original.mesh().positions.row(v)).norm() <= 1e-6 * diagonal);
        ++compared;
    }
    CHECK(compared >= 10);
}
