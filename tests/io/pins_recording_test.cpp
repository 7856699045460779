// The user's control-point pins are part of a recording: a drag solved with some control points pinned
// (removed from R, Hu et al. 2001 eq. 12) replays the same only with the same pins. Recorded as set_pins
// ops, through the JSON text, replayed on a fresh session.
#include <catch2/catch.hpp>

#include <algorithm>
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

TEST_CASE("recording: user pins and unpins replay through set_pins ops and the JSON text", "[io]") {
    std::mt19937 rng(701);
    Positions positions;
    Triangles triangles;
    test::icosphere(2, 1.0, Eigen::Vector3d::Zero(), positions, triangles);
    int pinsMattered = 0;
    for (int trial = 0; trial < 6; ++trial) {
        LatticeSettings settings;
        settings.resolution = {6 + trial % 3, 7, 6};
        settings.pinLayers = trial % 2;
        Session original;
        REQUIRE(original.setMesh(positions, triangles, settings).ok);
        original.setInjectivity({InjectivityMode::Conic, 4});
        const int n = original.lattice().controlPointCount();
        int pinOps = 0;
        for (int op = 0; op < 8; ++op) {
            // Change the pins now and then: pin some points, unpin some (layer points included).
            if (op % 3 == 1) {
                std::vector<int> ids;
                for (int k = 0; k < 6; ++k) ids.push_back(test::randomInt(rng, 0, n - 1));
                REQUIRE(original.pins().set(ids, op % 2 == 1).ok);
                ++pinOps;
            }
            OpReport report;
            const int v = test::randomInt(rng, 0, static_cast<int>(positions.rows()) - 1);
            const Status s = original.dragVertex(v, original.mesh().positions.row(v).transpose() + 0.15 * test::randomVector(rng, -1, 1), report);
            REQUIRE(s.ok);
        }
        const Script recording = recordSession(original);
        int setPins = 0;
        for (const ScriptOp& op : recording.ops) setPins += op.kind == ScriptOp::Kind::SetPins;
        CHECK(setPins >= 1);
        CHECK(setPins <= pinOps);

        Script parsed;
        Session replayed = test::replayThroughJson(recording, positions, triangles, parsed);
        ScriptReport report;
        const double diagonal = original.lattice().diagonal();
        CHECK(replayed.mesh().positions == original.mesh().positions);  // the recorded steps, repeated: bit for bit
        CHECK(replayed.pins().toggles() == original.pins().toggles());

        // Decided again (as on another mesh: no fingerprint), the pins shape the solution: without the set_pins
        // ops the result differs. A trial whose pins lay away from every drag is the same either way.
        parsed.meshFingerprint.clear();
        Session decided;
        REQUIRE(decided.setMesh(positions, triangles, parsed.lattice).ok);
        decided.setInjectivity(parsed.injectivity);
        REQUIRE(runScript(decided, parsed, report).ok);
        Script withoutPins = parsed;
        withoutPins.ops.erase(std::remove_if(withoutPins.ops.begin(), withoutPins.ops.end(),
                                             [](const ScriptOp& op) { return op.kind == ScriptOp::Kind::SetPins; }),
                              withoutPins.ops.end());
        Session unpinned;
        REQUIRE(unpinned.setMesh(positions, triangles, parsed.lattice).ok);
        unpinned.setInjectivity(parsed.injectivity);
        REQUIRE(runScript(unpinned, withoutPins, report).ok);
        pinsMattered += (unpinned.mesh().positions - decided.mesh().positions).cwiseAbs().maxCoeff() > 1e-6 * diagonal;
    }
    CHECK(pinsMattered >= 3);
}

TEST_CASE("recording: set_pins with bad points is an error that names them and changes nothing", "[io]") {
    Positions positions;
    Triangles triangles;
    test::icosphere(1, 1.0, Eigen::Vector3d::Zero(), positions, triangles);
    LatticeSettings settings;
    settings.pinLayers = 1;
    Session session;
    REQUIRE(session.setMesh(positions, triangles, settings).ok);
    for (const char* text : {R"({"ops":[{"op":"set_pins","pin":[[9,0,0]]}]})",
                             R"({"ops":[{"op":"set_pins","pin":[[0,0,0]]}]})",      // already pinned by the layer
                             R"({"ops":[{"op":"set_pins","unpin":[[3,3,3]]}]})"}) {  // not in the layer
        Script script;
        REQUIRE(io::parseScript(text, "pins.json", script).ok);
        ScriptReport report;
        const Status ran = runScript(session, script, report);
        CHECK_FALSE(ran.ok);
        CHECK(ran.message.find("set_pins") != std::string::npos);
        CHECK(session.pins().toggles().empty());
    }
    Script script;
    const Status bad = io::parseScript(R"({"ops":[{"op":"set_pins","pin":[[1,2]]}]})", "pins.json", script);
    CHECK_FALSE(bad.ok);
    CHECK(bad.message.find("pin[0]") != std::string::npos);
}
