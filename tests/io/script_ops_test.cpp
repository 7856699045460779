// The table of script ops (io/script_ops.h) against what uses it: the reader takes exactly the fields an entry
// lists, the writer writes no other, each entry's read and write are inverses, and the docs' op reference
// (docs/scripting.md "Every op" and the page each row points to) names every op and every field.
#include <catch2/catch.hpp>

#include <fstream>
#include <random>
#include <set>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "io/script.h"
#include "io/script_ops.h"
#include "core/volume/lattice_net.h"
#include "io/script_json.h"

using namespace sculpt;
using json = nlohmann::json;

namespace {

std::string readDoc(const std::string& name) {
    std::ifstream in(std::string(SCULPT_SOURCE_DIR) + "/docs/" + name);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
}

Status parseOne(const json& op, io::Script& script) {
    const json root = {{"ops", json::array({op})}};
    return io::parseScript(root.dump(), "ops.json", script);
}

constexpr int kKinds = static_cast<int>(io::ScriptOp::Kind::Crimp) + 1;

}  // namespace

TEST_CASE("script ops: one table entry per kind, and the reader takes exactly the fields it lists", "[io][script]") {
    const std::vector<io::ScriptOpInfo>& table = io::scriptOps();
    REQUIRE(table.size() == static_cast<size_t>(kKinds));
    std::set<std::string> names;
    for (int k = 0; k < kKinds; ++k) {
        const io::ScriptOpInfo& info = io::scriptOpInfo(static_cast<io::ScriptOp::Kind>(k));
        INFO("kind " << k << " " << info.name);
        CHECK(static_cast<int>(info.kind) == k);
        CHECK(std::string(io::scriptOpName(info.kind)) == info.name);
        CHECK(io::findScriptOp(info.name) == &info);
        CHECK(names.insert(info.name).second);
        // A field the entry does not list is refused, named.
        io::Script script;
        Status s = parseOne({{"op", info.name}, {"no_such_field", 1}}, script);
        CHECK(!s.ok);
        CHECK(s.message.find("ops[0].no_such_field: unknown field") != std::string::npos);
        // Each listed field is one the reader knows: given a value of no type any field takes, the error is
        // about that value (or a field missing), never that the field is unknown.
        for (const char* field : info.fields) {
            INFO("field " << field);
            io::Script other;
            s = parseOne({{"op", info.name}, {field, json::object({{"no", "such"}})}}, other);
            CHECK(s.message.find("ops[0]." + std::string(field) + ": unknown field") == std::string::npos);
        }
    }
    // A name no op has: refused, naming every op from the table.
    io::Script script;
    const Status s = parseOne({{"op", "sculpt_everything"}}, script);
    CHECK(!s.ok);
    CHECK(s.message.find("unknown op \"sculpt_everything\" (known: " + io::scriptOpNames() + ")") != std::string::npos);
}

TEST_CASE("script ops: the writer writes only fields the table lists, and reads back what it wrote", "[io][script]") {
    io::Script script;
    for (int k = 0; k < kKinds; ++k) {
        io::ScriptOp op;
        op.kind = static_cast<io::ScriptOp::Kind>(k);
        // Values the reader accepts for every kind's required fields.
        op.constraints = {core::PointConstraint{Eigen::Vector3d(0.1, 0.2, 0.3), Eigen::Vector3d(0.1, 0.4, 0.3)}};
        op.controlPoints = {{1, 1, 1}};
        op.values = Eigen::RowVector3d(0.0, 0.1, 0.0);
        op.relative = true;
        op.path = "shot.png";
        op.tspline.octree.octree.depth = 2;
        op.toolIndex = 0;
        op.cells = {0};
        op.weightTool.ids = {0};
        op.weightTool.weights = {2.0};
        op.weightTool.scale = 1.5;
        op.weightTool.widthFactor = 0.5;
        op.refinement.options.tolerance = 0.01;
        op.vertex = 3;
        if (op.kind == io::ScriptOp::Kind::AddLattice || op.kind == io::ScriptOp::Kind::EditLattice) {
            core::LatticeNet net;
            REQUIRE(core::makeParallelepipedNet(Eigen::Vector3d::Zero(), Eigen::Matrix3d::Identity(), {1, 1, 1}, {1, 1, 1}, net).ok);
            op.tool.volume = std::make_shared<const core::LatticeNet>(std::move(net));
            op.tool.name = "box";
        }
        script.ops.push_back(op);
    }
    const std::string text = io::scriptToJson(script);
    const json written = json::parse(text);
    REQUIRE(written["ops"].size() == static_cast<size_t>(kKinds));
    for (int k = 0; k < kKinds; ++k) {
        const io::ScriptOpInfo& info = io::scriptOpInfo(static_cast<io::ScriptOp::Kind>(k));
        const json& op = written["ops"][static_cast<size_t>(k)];
        INFO(info.name << ": " << op.dump());
        CHECK(op["op"] == info.name);
        const std::set<std::string> allowed(info.fields.begin(), info.fields.end());
        for (auto it = op.begin(); it != op.end(); ++it)
            if (it.key() != "op") CHECK(allowed.count(it.key()) == 1);
    }
    io::Script back;
    const Status s = io::parseScript(text, "written.json", back);
    INFO(s.message);
    REQUIRE(s.ok);
    REQUIRE(back.ops.size() == script.ops.size());
    for (size_t i = 0; i < back.ops.size(); ++i) CHECK(back.ops[i].kind == script.ops[i].kind);
}

TEST_CASE("script ops: each entry's read gives back what its write wrote, for random ops of every kind", "[io][script]") {
    // write -> read -> write is the same text for ops whose every field holds a random value the reader accepts
    // (fixed seeds): an entry's read and write are inverses, bit for bit (doubles included), whatever fields
    // the op uses.
    std::mt19937 random(2912);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    std::uniform_int_distribution<int> small(0, 5);
    const auto vec = [&] { return Eigen::Vector3d(unit(random), unit(random), unit(random)); };
    for (int round = 0; round < 12; ++round) {
        io::Script script;
        for (int k = 0; k < kKinds; ++k) {
            io::ScriptOp op;
            op.kind = static_cast<io::ScriptOp::Kind>(k);
            const int count = 1 + small(random);
            for (int c = 0; c < count; ++c) {
                op.constraints.push_back({vec(), vec()});
                op.controlPoints.push_back({small(random), small(random), small(random)});
                op.unpinned.push_back({small(random), small(random), small(random)});
                op.cells.push_back(small(random) * 7);
                op.cellPoints.push_back(vec());
                op.weightTool.ids.push_back(small(random) * 3);
                op.weightTool.weights.push_back(0.25 + std::abs(unit(random)) * 4.0);
            }
            op.values.resize(count, 3);
            for (int c = 0; c < count; ++c) op.values.row(c) = vec().transpose();
            op.relative = round % 2 == 0;
            op.vertex = small(random) * 11;
            op.target = vec();
            op.brush.radius = round % 3 == 0 ? 0.0 : std::abs(unit(random)) * 0.3;
            op.brush.strength = 0.1 + 0.9 * std::abs(unit(random));
            op.brush.falloff = static_cast<core::BrushFalloff>(round % 3);
            op.brush.symmetry.mirror = {round % 2 == 1, false, round % 4 == 3};
            op.path = "shot" + std::to_string(round) + ".png";
            op.label = round % 2 == 0 ? "" : "stroke " + std::to_string(round);
            op.groupFirst = small(random);
            op.hasSettings = round % 2 == 1;
            op.settings.resolution = {4 + small(random), 4, 5};
            op.settings.padding = std::abs(unit(random)) * 0.2;
            op.toolIndex = small(random);
            op.pinLayers = round % 4;
            op.tolerance = round % 2 == 0 ? 0.0 : 0.001 + std::abs(unit(random)) * 0.01;
            op.refinement.automatic = round % 2 == 0;
            op.refinement.options.tolerance = 0.001 + std::abs(unit(random)) * 0.01;
            op.refinement.options.maxRounds = 1 + small(random);
            op.refinement.options.maxVertices = 1000 * (1 + small(random));
            op.tspline.octree.octree.depth = 1 + round % 3;
            op.tspline.octree.weightRatio = 1.0 + std::abs(unit(random)) * 4.0;
            op.tspline.octree.octree.rootCount = {1 + small(random), 1, 2};
            op.tspline.hasRegion = round % 2 == 0;
            op.tspline.regionMin = Eigen::Vector3d(-1.0, -1.0, -1.0) + 0.1 * vec();
            op.tspline.regionMax = Eigen::Vector3d(1.0, 1.0, 1.0) + 0.1 * vec();
            op.tspline.name = round % 2 == 0 ? "" : "hug " + std::to_string(round);
            op.tspline.freeze = round % 2 == 1;
            op.balance = round % 2 == 0;
            op.weightTool.vertex = small(random);
            op.weightTool.controlPoint = round % 2 == 0 ? -1 : small(random);
            op.weightTool.radius = round % 3 == 0 ? 0.0 : std::abs(unit(random));
            op.weightTool.hasHeight = round % 2 == 0;
            op.weightTool.height = unit(random);
            op.weightTool.scale = 0.5 + std::abs(unit(random));
            op.weightTool.widthFactor = 0.2 + std::abs(unit(random));
            if (op.kind == io::ScriptOp::Kind::AddLattice || op.kind == io::ScriptOp::Kind::EditLattice) {
                core::LatticeNet net;
                REQUIRE(core::makeParallelepipedNet(vec(), Eigen::Matrix3d::Identity(), {1, 1 + round % 2, 1}, {1, 1, 1}, net).ok);
                op.tool.volume = std::make_shared<const core::LatticeNet>(std::move(net));
                op.tool.name = "tool " + std::to_string(round);
                if (op.kind == io::ScriptOp::Kind::EditLattice && round % 2 == 0) {
                    core::NetEdit edit;
                    edit.kind = core::NetEdit::Kind::Move;
                    edit.slots = {0, 1};
                    edit.offset = vec();
                    op.netEdits.push_back(edit);
                }
            }
            script.ops.push_back(op);
        }
        const std::string text = io::scriptToJson(script);
        io::Script back;
        const Status s = io::parseScript(text, "written.json", back);
        INFO("round " << round << ": " << s.message);
        REQUIRE(s.ok);
        REQUIRE(back.ops.size() == script.ops.size());
        const json first = json::parse(text), second = json::parse(io::scriptToJson(back));
        for (size_t i = 0; i < back.ops.size(); ++i) {
            INFO(first["ops"][i].dump());
            CHECK(back.ops[i].kind == script.ops[i].kind);
            CHECK(second["ops"][i] == first["ops"][i]);
        }
    }
}

TEST_CASE("script ops: the docs' op reference names every op of the table and every field of each", "[io][script]") {
    const std::string reference = readDoc("scripting.md");
    const size_t from = reference.find("## Every op"), to = reference.find("## Script format");
    REQUIRE(from != std::string::npos);
    REQUIRE(to != std::string::npos);
    const std::string table = reference.substr(from, to - from);
    // The recording fields are described once, for every op that has them, in scripting.md's recording bullet.
    const size_t applied = reference.find("`\"applied\"` on"), cancelled = reference.find("`\"cancelled\": true` on");
    REQUIRE(applied != std::string::npos);
    REQUIRE(cancelled != std::string::npos);
    const std::string appliedOps = reference.substr(applied, reference.find(" (the", applied) - applied);
    const std::string cancelledOps = reference.substr(cancelled, reference.find("taken back", cancelled) - cancelled);
    std::set<std::string> listed;
    std::istringstream lines(table);
    int rows = 0;
    // A row: "| `op`, `op` | what it does | [page](file.md#anchor) |" (a link with no file: this page). Read with
    // plain string searches (std::regex trips GCC 12's -Wmaybe-uninitialized in the sanitizer build).
    for (std::string line; std::getline(lines, line);) {
        if (line.rfind("| `", 0) != 0) continue;
        std::vector<std::string> cells;
        for (size_t at = 1, bar; (bar = line.find('|', at)) != std::string::npos; at = bar + 1) cells.push_back(line.substr(at, bar - at));
        REQUIRE(cells.size() == 3);
        ++rows;
        const size_t link = cells[2].find("](");
        REQUIRE(link != std::string::npos);
        const std::string target = cells[2].substr(link + 2, cells[2].find(')', link) - link - 2);
        const std::string file = target.substr(0, target.find('#'));
        const std::string page = file.empty() ? std::string("scripting.md") : file;
        const std::string text = readDoc(page);
        REQUIRE(!text.empty());
        for (size_t open = cells[0].find('`'), close; open != std::string::npos; open = cells[0].find('`', close + 1)) {
            close = cells[0].find('`', open + 1);
            REQUIRE(close != std::string::npos);
            const std::string op = cells[0].substr(open + 1, close - open - 1);
            INFO("op " << op << " (described in " << page << ")");
            CHECK(listed.insert(op).second);  // one row each
            const io::ScriptOpInfo* info = io::findScriptOp(op);
            REQUIRE(info != nullptr);  // the docs name no op the program lacks
            for (const char* field : info->fields) {
                INFO("field " << field);
                if (std::string(field) == "applied") CHECK(appliedOps.find("`" + op + "`") != std::string::npos);
                else if (std::string(field) == "cancelled") CHECK(cancelledOps.find("`" + op + "`") != std::string::npos);
                else CHECK((text.find("`" + std::string(field) + "`") != std::string::npos || text.find("\"" + std::string(field) + "\"") != std::string::npos));
            }
        }
    }
    CHECK(rows >= 8);
    // Every op of the table has its row.
    for (const io::ScriptOpInfo& info : io::scriptOps()) CHECK(listed.count(info.name) == 1);
}

TEST_CASE("script ops: every kind of history entry is recorded by exactly one op of the table", "[io][script]") {
    core::LatticeNet net;
    REQUIRE(core::makeParallelepipedNet(Eigen::Vector3d::Zero(), Eigen::Matrix3d::Identity(), {1, 1, 1}, {1, 1, 1}, net).ok);
    const auto volume = std::make_shared<const core::LatticeNet>(std::move(net));
    std::vector<std::pair<core::Operation, io::ScriptOp::Kind>> cases;
    const auto add = [&](core::OperationKind kind, io::ScriptOp::Kind expected, auto&& shape) {
        core::Operation operation;
        operation.kind = kind;
        operation.steps.emplace_back();
        shape(operation);
        cases.emplace_back(operation, expected);
    };
    using OK = core::OperationKind;
    using SK = io::ScriptOp::Kind;
    add(OK::Drag, SK::Drag, [](core::Operation&) {});
    add(OK::ControlPointEdit, SK::MoveControlPoint, [](core::Operation& o) { o.controlPoints = {0}, o.offsets = Eigen::RowVector3d(0, 1, 0); });
    add(OK::LatticeSetup, SK::SetupLattice, [](core::Operation&) {});
    add(OK::LatticeSetup, SK::Freeze, [](core::Operation& o) { o.frozenAfter = 0; });
    add(OK::LatticeSetup, SK::Unfreeze, [](core::Operation& o) { o.frozenBefore = 0; });
    add(OK::Refine, SK::Refine, [](core::Operation&) {});
    add(OK::WeightEdit, SK::SetWeights, [](core::Operation& o) { o.weightTool.tool = core::WeightToolSettings::Tool::SetWeights; });
    add(OK::WeightEdit, SK::Hammer, [](core::Operation& o) { o.weightTool.tool = core::WeightToolSettings::Tool::Hammer; });
    add(OK::WeightEdit, SK::Crimp, [](core::Operation& o) { o.weightTool.tool = core::WeightToolSettings::Tool::Crimp; });
    add(OK::LatticeTools, SK::AddLattice, [&](core::Operation& o) { o.toolAfter.volume = volume; });
    add(OK::LatticeTools, SK::EditLattice, [&](core::Operation& o) { o.toolBefore.volume = volume, o.toolAfter.volume = volume; });
    add(OK::LatticeTools, SK::RemoveLattice, [&](core::Operation& o) { o.toolBefore.volume = volume; });
    for (const auto& [operation, expected] : cases) {
        INFO(io::scriptOpName(expected));
        int claims = 0;
        for (const io::ScriptOpInfo& info : io::scriptOps()) {
            io::ScriptOp op;
            if (info.record && info.record(operation, op)) {
                ++claims;
                CHECK(info.kind == expected);
            }
        }
        CHECK(claims == 1);
    }
    // Every op but begin_group and end_group runs through its entry.
    for (const io::ScriptOpInfo& info : io::scriptOps())
        CHECK((info.run == nullptr) == (info.kind == SK::BeginGroup || info.kind == SK::EndGroup));
}

// The window runs its commands through runScriptOp; each report names the op that ran (scriptOpName), as
// runScript's do, also where the command behind it names itself otherwise (a group, pins, undo of a drag).
TEST_CASE("script ops: runScriptOp's report names the op that ran, as runScript's does", "[io][script]") {
    core::Session session;
    Positions positions(8, 3);
    Triangles triangles(12, 3);
    positions << -1, -1, -1, 1, -1, -1, 1, 1, -1, -1, 1, -1, -1, -1, 1, 1, -1, 1, 1, 1, 1, -1, 1, 1;
    triangles << 0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4, 1, 2, 6, 1, 6, 5, 2, 3, 7, 2, 7, 6, 3, 0, 4, 3, 4, 7;
    REQUIRE(session.setMesh(positions, triangles).ok);
    const std::vector<json> ops = {
        {{"op", "drag_vertex"}, {"vertex", 6}, {"target", {1.1, 1.1, 1.1}}},
        {{"op", "drag"}, {"constraints", {{{"source", {-1, -1, -1}}, {"target", {-1.1, -1.0, -1.0}}}}}},
        {{"op", "group"}, {"first", 0}, {"label", "two drags"}},
        {{"op", "move_control_point"}, {"index", {1, 1, 1}}, {"by", {0.01, 0.0, 0.0}}},
        {{"op", "set_pins"}, {"pin", {{0, 0, 0}}}},
        {{"op", "undo"}},
        {{"op", "redo"}},
        {{"op", "refine"}, {"tolerance", 0.01}},
    };
    for (const json& op : ops) {
        io::Script script;
        const Status parsed = parseOne(op, script);
        INFO(op.dump() << ": " << parsed.message);
        REQUIRE(parsed.ok);
        core::OpReport report;
        const Status ran = io::runScriptOp(session, script.ops[0], report);
        INFO(ran.message << " / " << report.reason);
        CHECK(ran.ok);
        CHECK(report.op == io::scriptOpName(script.ops[0].kind));
        CHECK(report.op == op["op"].get<std::string>());
    }
}
