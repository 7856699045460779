// edit_lattice's "edits" (Coquillart 1990, 3.1.4; core/volume/lattice_edit.h in scripts): edits apply in order to the
// tool's current net and keep its name, bad edits are refused with the field path or the reason and change
// nothing, and a session with edits, recorded and replayed through its JSON text, gives the same mesh and
// lattice list bit for bit.
#include <catch2/catch.hpp>

#include <cstdio>
#include <memory>
#include <random>

#include "../core/mesh_fixtures.h"
#include "core/volume/lattice.h"
#include "core/volume/lattice_edit.h"
#include "io/script.h"
#include "core/session/session.h"
#include "io/lattice_json.h"
#include "io/script_json.h"
#include "replay_support.h"

using namespace sculpt;
using namespace sculpt::core;
using namespace sculpt::io;

namespace {

struct Sphere {
    Positions positions;
    Triangles triangles;
};

Sphere sphereMesh() {
    Sphere mesh;
    test::icosphere(2, 1.0, Eigen::Vector3d::Zero(), mesh.positions, mesh.triangles);
    return mesh;
}

// Runs `text` on a fresh session on the sphere; `ran` gets runScript's status.
Session runText(const std::string& text, const Sphere& mesh, Status& ran) {
    Script script;
    const Status parsed = io::parseScript(text, "edits.json", script);
    INFO(parsed.message);
    REQUIRE(parsed);
    Session session;
    REQUIRE(session.setMesh(mesh.positions, mesh.triangles, script.lattice));
    session.setInjectivity(script.injectivity);
    ScriptReport report;
    ran = runScript(session, script, report);
    return session;
}

const char* kCylinder = R"({"kind": "cylinder", "base": [0, 0, -1.2], "axis": [0, 0, 1], "radius": 1.3, "height": 2.4, "chunks": [2, 6, 2], "degree": [2, 2]})";

}  // namespace

TEST_CASE("lattice edit script: edits apply to the current net keep the tool's name and replay bitwise", "[netedit][io][script]") {
    const Sphere mesh = sphereMesh();
    // Refined along w the cylinder has 4 x 13 x 6 slots; slot 0 is the axis of the bottom slice (one welded
    // point), 3 + 4 * (1 + 13 * 5) and 3 + 4 * (2 + 13 * 5) are neighbouring points of the top ring.
    const std::string edits =
        R"([{"refine": {"axis": 2}}, {"move": {"points": [0], "offset": [0, 0, 0.05]}}, {"merge": [267, 271]}, {"remove": {"axis": 2, "index": 3}}])";
    const std::string text = std::string(R"({"injectivity": {"mode": "exact"}, "ops": [
        {"op": "add_lattice", "name": "pie", "lattice": )") + kCylinder + R"(},
        {"op": "edit_lattice", "index": 0, "edits": )" + edits + R"(},
        {"op": "freeze", "index": 0, "pin_layers": 0},
        {"op": "move_control_point", "indices": [[0, 0, 2]], "by": [0.02, 0, 0.1]},
        {"op": "unfreeze"},
        {"op": "edit_lattice", "index": 0, "edits": [{"refine": {"axis": 0}}]}]})";
    Status ran;
    Session session = runText(text, mesh, ran);
    INFO(ran.message);
    REQUIRE(ran);
    REQUIRE(session.tools().list().size() == 1);
    REQUIRE(session.tools().list()[0].name == "pie");  // an edit without "name" keeps the tool's name

    // The tool's net is the core edits applied to the cylinder, in order.
    LatticeNet cylinder;
    REQUIRE(io::parseLatticeNetJson(nlohmann::json::parse(kCylinder), "lattice", cylinder));
    std::vector<NetEdit> list(5);
    list[0].kind = NetEdit::Kind::Refine;
    list[0].axis = 2;
    list[1].kind = NetEdit::Kind::Move;
    list[1].slots = {0};
    list[1].offset = Eigen::Vector3d(0, 0, 0.05);
    list[2].kind = NetEdit::Kind::Merge;
    list[2].slots = {267, 271};
    list[3].kind = NetEdit::Kind::Remove;
    list[3].axis = 2;
    list[3].index = 3;
    list[4].kind = NetEdit::Kind::Refine;
    list[4].axis = 0;
    LatticeNet expected;
    REQUIRE(applyNetEdits(cylinder, list, expected));
    REQUIRE(sameLatticeNet(*session.tools().list()[0].volume->tensorNet(), expected));
    REQUIRE(session.mesh().positions != mesh.positions);  // the frozen, edited lattice deformed the mesh

    // Recorded and replayed through the JSON text: the same mesh and tool list, bit for bit.
    const Script recording = recordSession(session);
    Script parsed;
    const Session replayed = test::replayThroughJson(recording, mesh.positions, mesh.triangles, parsed);
    REQUIRE(replayed.mesh().positions == session.mesh().positions);
    REQUIRE(replayed.tools().list().size() == session.tools().list().size());
    for (size_t t = 0; t < replayed.tools().list().size(); ++t) {
        REQUIRE(replayed.tools().list()[t].name == session.tools().list()[t].name);
        REQUIRE(sameLatticeNet(*replayed.tools().list()[t].volume->tensorNet(), *session.tools().list()[t].volume->tensorNet()));
    }
    // The script with its edits also round-trips through scriptToJson as edits.
    Script original, again;
    REQUIRE(io::parseScript(text, "edits.json", original));
    REQUIRE(io::parseScript(io::scriptToJson(original), "again.json", again));
    REQUIRE(again.ops[1].netEdits.size() == 4);
    REQUIRE_FALSE(again.ops[1].tool.volume);
    REQUIRE(again.ops[1].tool.name.empty());
    REQUIRE(again.ops[1].netEdits[2].slots == std::vector<int>{267, 271});
    // Undo takes the edits back one op at a time (each edit_lattice is one history entry).
    Session undone = session;
    OpReport report;
    REQUIRE(undone.undo(report));
    REQUIRE(undone.tools().list()[0].volume->tensorNet()->count[0] == 4);
}

TEST_CASE("lattice edit script: an edit with a lattice and no name keeps the tool's name", "[netedit][io][script]") {
    const Sphere mesh = sphereMesh();
    const std::string text = std::string(R"({"ops": [{"op": "add_lattice", "name": "pie", "lattice": )") + kCylinder +
                             R"(}, {"op": "edit_lattice", "index": 0, "lattice": )" + kCylinder +
                             R"(, "edits": [{"refine": {"axis": 1}}]}, {"op": "edit_lattice", "index": 0, "name": "tart", "edits": [{"refine": {"axis": 0}}]}]})";
    Status ran;
    Session session = runText(text, mesh, ran);
    INFO(ran.message);
    REQUIRE(ran);
    REQUIRE(session.tools().list()[0].name == "tart");
    REQUIRE(session.tools().list()[0].volume->tensorNet()->count == std::array<int, 3>{6, 25, 4});
    OpReport report;
    REQUIRE(session.undo(report));
    REQUIRE(session.tools().list()[0].name == "pie");
    REQUIRE(session.tools().list()[0].volume->tensorNet()->count == std::array<int, 3>{4, 25, 4});
}

TEST_CASE("lattice edit script: bad edits name the field or the reason and change nothing", "[netedit][io][script]") {
    const std::string head = std::string(R"({"ops": [{"op": "add_lattice", "name": "pie", "lattice": )") + kCylinder + "}, ";
    // Parse errors: the field path.
    const std::vector<std::pair<std::string, std::string>> parseCases = {
        {R"({"op": "edit_lattice", "index": 0, "edits": [{"refine": {"axis": 0}}, {"merge": [1, 2, "x"]}]})", "ops[1].edits[1].merge[2]: expected an integer"},
        {R"({"op": "edit_lattice", "index": 0, "edits": [{"merge": [1]}]})", "ops[1].edits[0].merge: expected an array of 2 or more slot ids"},
        {R"({"op": "edit_lattice", "index": 0, "edits": [{"move": {"points": [], "offset": [0, 0, 1]}}]})", "ops[1].edits[0].move.points"},
        {R"({"op": "edit_lattice", "index": 0, "edits": [{"move": {"points": [1], "offset": [0, 1]}}]})", "ops[1].edits[0].move.offset"},
        {R"({"op": "edit_lattice", "index": 0, "edits": [{"move": {"points": [-4], "offset": [0, 0, 1]}}]})", "ops[1].edits[0].move.points[0]: expected a slot id >= 0"},
        {R"({"op": "edit_lattice", "index": 0, "edits": [{"refine": {"axis": 3}}]})", "ops[1].edits[0].refine.axis: expected 0 (u), 1 (v) or 2 (w)"},
        {R"({"op": "edit_lattice", "index": 0, "edits": [{"remove": {"axis": 1}}]})", "ops[1].edits[0].remove.index: missing"},
        {R"({"op": "edit_lattice", "index": 0, "edits": [{"twist": {}}]})", "ops[1].edits[0].twist: unknown edit"},
        {R"({"op": "edit_lattice", "index": 0, "edits": [{"insert": {"axis": 1, "at": 1.5}}]})", "ops[1].edits[0].insert.at: expected a lattice parameter"},
        {R"({"op": "edit_lattice", "index": 0, "edits": [{"insert": {"axis": 1}}]})", "ops[1].edits[0].insert.at: missing"},
        {R"({"op": "edit_lattice", "index": 0, "edits": [{"insert": {"axis": 1, "at": 0.3, "times": 0}}]})", "ops[1].edits[0].insert.times"},
        {R"({"op": "edit_lattice", "index": 0, "edits": [{"refine": {"axis": 0}, "merge": [1, 2]}]})", "ops[1].edits[0]: expected an object with one of"},
        {R"({"op": "edit_lattice", "index": 0, "edits": []})", "ops[1].edits: expected a non-empty array"},
        {R"({"op": "edit_lattice", "index": 0})", "ops[1]: expected \"lattice\", \"file\" or \"edits\""},
        {R"({"op": "edit_lattice", "index": 0, "edits": [{"refine": {"axis": 0}}], "place": {"point": [0,0,0], "normal": [0,0,1], "size": 1}})", "ops[1].place"},
        {R"({"op": "add_lattice", "edits": [{"refine": {"axis": 0}}], "lattice": {"kind": "sphere", "centre": [0,0,0], "radius": 1, "chunks": [1,3,2]}})", "ops[1].edits: unknown field"},
    };
    for (const auto& [op, message] : parseCases) {
        Script script;
        const Status s = io::parseScript(head + op + "]}", "bad.json", script);
        INFO(op << " / " << s.message);
        REQUIRE_FALSE(s);
        REQUIRE(s.message.find(message) != std::string::npos);
    }
    // Run-time errors (the lattice is known only then): the reason, and the session as it was before the op.
    const Sphere mesh = sphereMesh();
    const std::vector<std::pair<std::string, std::string>> runCases = {
        {R"({"op": "edit_lattice", "index": 0, "edits": [{"refine": {"axis": 2}}, {"merge": [3, 999]}]})",
         "op 1 (edit_lattice): edits[1]: slot 999 is out of range (the lattice has 312 points)"},
        {R"({"op": "edit_lattice", "index": 0, "edits": [{"remove": {"axis": 1, "index": 0}}]})", "per knot span"},
        {R"({"op": "edit_lattice", "index": 0, "edits": [{"remove": {"axis": 0, "index": 0}}]})", "collapsed face"},
        {R"({"op": "edit_lattice", "index": 3, "edits": [{"refine": {"axis": 0}}]})", "there is no lattice 3"},
        {R"({"op": "edit_lattice", "index": 0, "edits": [{"insert": {"axis": 0, "at": 0.5, "times": 2}}]})", "multiplicity 1 already"},
        {R"({"op": "freeze", "index": 0}, {"op": "edit_lattice", "index": 0, "edits": [{"refine": {"axis": 0}}]})", "frozen"},
    };
    LatticeNet cylinder;
    REQUIRE(io::parseLatticeNetJson(nlohmann::json::parse(kCylinder), "lattice", cylinder));
    for (const auto& [op, message] : runCases) {
        Status ran;
        Session session = runText(head + op + "]}", mesh, ran);
        INFO(op << " / " << ran.message);
        REQUIRE_FALSE(ran);
        REQUIRE(ran.message.find(message) != std::string::npos);
        REQUIRE(session.tools().list().size() == 1);
        REQUIRE(session.tools().list()[0].name == "pie");
        REQUIRE(sameLatticeNet(*session.tools().list()[0].volume->tensorNet(), cylinder));
    }
}

TEST_CASE("lattice edit script: a knot inserted at a chosen parameter is one edit that replays bitwise", "[netedit][io][script]") {
    const Sphere mesh = sphereMesh();
    // Split the radial axis inside its first chunk, the angle axis twice in one chunk and the axial axis at
    // 0.3; the volume is the cylinder's (the mesh does not move), and a later drag on the frozen net replays.
    const std::string text = std::string(R"({"injectivity": {"mode": "exact"}, "ops": [
        {"op": "add_lattice", "name": "pie", "lattice": )") + kCylinder + R"(},
        {"op": "edit_lattice", "index": 0, "edits": [{"insert": {"axis": 0, "at": 0.2}}, {"insert": {"axis": 1, "at": 0.04, "times": 2}},
                                                    {"insert": {"axis": 2, "at": 0.3}}]},
        {"op": "freeze", "index": 0, "pin_layers": 0},
        {"op": "move_control_point", "indices": [[1, 0, 2]], "by": [0.02, 0, 0.1]}]})";
    Status ran;
    Session session = runText(text, mesh, ran);
    INFO(ran.message);
    REQUIRE(ran);
    const LatticeNet& net = *session.tools().list()[0].volume->tensorNet();
    REQUIRE(net.count == std::array<int, 3>{5, 15, 5});
    REQUIRE_FALSE(net.knots[0].empty());
    REQUIRE(session.mesh().positions != mesh.positions);
    // The recording carries the general knots (in the lattice's JSON) and replays bit for bit.
    const Script recording = recordSession(session);
    Script parsed;
    const Session replayed = test::replayThroughJson(recording, mesh.positions, mesh.triangles, parsed);
    REQUIRE(replayed.mesh().positions == session.mesh().positions);
    REQUIRE(sameLatticeNet(*replayed.tools().list()[0].volume->tensorNet(), net));
    // And the lattice file form round-trips bitwise too.
    LatticeNet back;
    REQUIRE(io::parseLatticeNetJson(io::latticeNetJson(net), "lattice", back));
    REQUIRE(sameLatticeNet(back, net));
    // The inserted knots leave the volume as it was: freezing the mesh in the split net and in the cylinder
    // gives the same points (every vertex inside maps to itself at rest).
    LatticeNet cylinder;
    REQUIRE(io::parseLatticeNetJson(nlohmann::json::parse(kCylinder), "lattice", cylinder));
    std::mt19937 rng(77);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (int sample = 0; sample < 100; ++sample) {
        const Eigen::Vector3d t(unit(rng), unit(rng), unit(rng));
        Eigen::Vector3d before, after;
        evaluateNetVolume(cylinder, cylinder.rest, t, before);
        Eigen::Vector3d tau;
        for (int a = 0; a < 3; ++a) tau[a] = net.axes[a].latticeParameter(cylinder.axes[a].knotParameter(t[a]));
        evaluateNetVolume(net, net.rest, tau, after);
        REQUIRE((after - before).norm() <= 1e-12 * cylinder.diagonal());
    }
}

TEST_CASE("lattice edit script: groups holding tool changes and freezes are one history entry, undone, redone and replayed bitwise",
          "[netedit][io][script][session]") {
    const Sphere mesh = sphereMesh();
    std::mt19937 rng(2711);
    for (int trial = 0; trial < 4; ++trial) {
        // A random run of ops over two tools; begin_group / end_group around random stretches of it.
        std::vector<std::string> ops = {R"({"op": "add_lattice", "name": "pie", "lattice": )" + std::string(kCylinder) + "}"};
        bool frozen = false;
        for (int k = 0; k < 7; ++k) {
            const int pick = std::uniform_int_distribution<int>(0, 3)(rng);
            if (!frozen && pick <= 1) {
                ops.push_back(R"({"op": "freeze", "index": 0})");
                frozen = true;
            } else if (frozen && pick == 0) {
                ops.push_back(R"({"op": "unfreeze"})");
                frozen = false;
            } else if (frozen) {
                const int vertex = std::uniform_int_distribution<int>(0, static_cast<int>(mesh.positions.rows()) - 1)(rng);
                const Eigen::Vector3d target = mesh.positions.row(vertex).transpose() * std::uniform_real_distribution<double>(0.9, 1.1)(rng);
                char text[200];
                std::snprintf(text, sizeof text, R"({"op": "drag_vertex", "vertex": %d, "target": [%.17g, %.17g, %.17g]})", vertex, target[0],
                              target[1], target[2]);
                ops.push_back(text);
            } else {
                ops.push_back(R"({"op": "edit_lattice", "index": 0, "edits": [{"move": {"points": [5], "offset": [0, 0, 0.01]}}]})");
            }
        }
        // Reference: every op on its own; then the same with groups.
        std::string plain = R"({"injectivity": {"mode": "exact"}, "ops": [)";
        std::string grouped = plain;
        const int groupStart = std::uniform_int_distribution<int>(0, 3)(rng);
        const int groupEnd = std::uniform_int_distribution<int>(groupStart + 2, static_cast<int>(ops.size()))(rng);
        for (size_t k = 0; k < ops.size(); ++k) {
            const std::string comma = k ? ", " : "";
            plain += comma + ops[k];
            grouped += comma + (static_cast<int>(k) == groupStart ? R"({"op": "begin_group", "label": "several"}, )" : "") + ops[k];
            if (static_cast<int>(k) + 1 == groupEnd) grouped += R"(, {"op": "end_group"})";
        }
        plain += "]}";
        grouped += "]}";
        INFO("trial " << trial << ": " << grouped);
        Status ran;
        Session reference = runText(plain, mesh, ran);
        REQUIRE(ran);
        Session session = runText(grouped, mesh, ran);
        REQUIRE(ran);
        const int members = groupEnd - groupStart;
        REQUIRE(session.history().size() + static_cast<size_t>(members - 1) == reference.history().size());
        REQUIRE(session.mesh().positions == reference.mesh().positions);
        REQUIRE(session.tools().frozen() == reference.tools().frozen());
        // Undo everything after the group, then the group: the state the reference has before its members.
        OpReport undone;
        const Positions end = session.mesh().positions;
        const int after = static_cast<int>(session.history().size()) - groupStart - 1;
        for (int k = 0; k < after; ++k) REQUIRE(session.undo(undone));
        for (int k = 0; k < after; ++k) REQUIRE(reference.undo(undone));
        REQUIRE(session.mesh().positions == reference.mesh().positions);
        REQUIRE(session.undo(undone));  // the group: one entry
        for (int k = 0; k < members; ++k) REQUIRE(reference.undo(undone));
        REQUIRE(session.history().cursor() == groupStart);
        REQUIRE(session.mesh().positions == reference.mesh().positions);
        REQUIRE(session.tools().frozen() == reference.tools().frozen());
        REQUIRE(session.tools().list().size() == reference.tools().list().size());
        for (size_t t = 0; t < session.tools().list().size(); ++t)
            REQUIRE(io::volumeJson(*session.tools().list()[t].volume).dump() == io::volumeJson(*reference.tools().list()[t].volume).dump());
        // Redo to the end, bitwise; then the recording replays to the same mesh, tools and history.
        // Redo to the end: as the ops one by one redo, bitwise (a frame's redo rebuilds it, so the end is met
        // to rounding, not bitwise).
        while (reference.history().cursor() < static_cast<int>(reference.history().size())) REQUIRE(reference.redo(undone));
        while (session.history().cursor() < static_cast<int>(session.history().size())) REQUIRE(session.redo(undone));
        REQUIRE(session.mesh().positions == reference.mesh().positions);
        REQUIRE((session.mesh().positions - end).cwiseAbs().maxCoeff() <= 1e-13);
        Script parsed;
        const Session replayed = test::replayThroughJson(recordSession(session), mesh.positions, mesh.triangles, parsed);
        REQUIRE(replayed.mesh().positions == session.mesh().positions);
        REQUIRE(replayed.history().size() == session.history().size());
        REQUIRE(replayed.tools().frozen() == session.tools().frozen());
    }
}
