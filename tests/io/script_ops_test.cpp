// The table of script ops (core/session/script_ops.h) against what uses it: the reader takes exactly the
// fields an entry lists, the writer writes no other, and the docs' op reference (docs/scripting.md "Every op"
// and the page each row points to) names every op and every field.
#include <catch2/catch.hpp>

#include <fstream>
#include <set>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "core/session/script.h"
#include "core/session/script_ops.h"
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

Status parseOne(const json& op, core::Script& script) {
    const json root = {{"ops", json::array({op})}};
    return io::parseScript(root.dump(), "ops.json", script);
}

constexpr int kKinds = static_cast<int>(core::ScriptOp::Kind::Crimp) + 1;

}  // namespace

TEST_CASE("script ops: one table entry per kind, and the reader takes exactly the fields it lists", "[io][script]") {
    const std::vector<core::ScriptOpInfo>& table = core::scriptOps();
    REQUIRE(table.size() == static_cast<size_t>(kKinds));
    std::set<std::string> names;
    for (int k = 0; k < kKinds; ++k) {
        const core::ScriptOpInfo& info = core::scriptOpInfo(static_cast<core::ScriptOp::Kind>(k));
        INFO("kind " << k << " " << info.name);
        CHECK(static_cast<int>(info.kind) == k);
        CHECK(std::string(core::scriptOpName(info.kind)) == info.name);
        CHECK(core::findScriptOp(info.name) == &info);
        CHECK(names.insert(info.name).second);
        // A field the entry does not list is refused, named.
        core::Script script;
        Status s = parseOne({{"op", info.name}, {"no_such_field", 1}}, script);
        CHECK(!s.ok);
        CHECK(s.message.find("ops[0].no_such_field: unknown field") != std::string::npos);
        // Each listed field is one the reader knows: given a value of no type any field takes, the error is
        // about that value (or a field missing), never that the field is unknown.
        for (const char* field : info.fields) {
            INFO("field " << field);
            core::Script other;
            s = parseOne({{"op", info.name}, {field, json::object({{"no", "such"}})}}, other);
            CHECK(s.message.find("ops[0]." + std::string(field) + ": unknown field") == std::string::npos);
        }
    }
    // A name no op has: refused, naming every op from the table.
    core::Script script;
    const Status s = parseOne({{"op", "sculpt_everything"}}, script);
    CHECK(!s.ok);
    CHECK(s.message.find("unknown op \"sculpt_everything\" (known: " + core::scriptOpNames() + ")") != std::string::npos);
}

TEST_CASE("script ops: the writer writes only fields the table lists, and reads back what it wrote", "[io][script]") {
    core::Script script;
    for (int k = 0; k < kKinds; ++k) {
        core::ScriptOp op;
        op.kind = static_cast<core::ScriptOp::Kind>(k);
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
        if (op.kind == core::ScriptOp::Kind::AddLattice || op.kind == core::ScriptOp::Kind::EditLattice) {
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
        const core::ScriptOpInfo& info = core::scriptOpInfo(static_cast<core::ScriptOp::Kind>(k));
        const json& op = written["ops"][static_cast<size_t>(k)];
        INFO(info.name << ": " << op.dump());
        CHECK(op["op"] == info.name);
        const std::set<std::string> allowed(info.fields.begin(), info.fields.end());
        for (auto it = op.begin(); it != op.end(); ++it)
            if (it.key() != "op") CHECK(allowed.count(it.key()) == 1);
    }
    core::Script back;
    const Status s = io::parseScript(text, "written.json", back);
    INFO(s.message);
    REQUIRE(s.ok);
    REQUIRE(back.ops.size() == script.ops.size());
    for (size_t i = 0; i < back.ops.size(); ++i) CHECK(back.ops[i].kind == script.ops[i].kind);
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
            const core::ScriptOpInfo* info = core::findScriptOp(op);
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
    for (const core::ScriptOpInfo& info : core::scriptOps()) CHECK(listed.count(info.name) == 1);
}

TEST_CASE("script ops: every kind of history entry is recorded by exactly one op of the table", "[io][script]") {
    core::LatticeNet net;
    REQUIRE(core::makeParallelepipedNet(Eigen::Vector3d::Zero(), Eigen::Matrix3d::Identity(), {1, 1, 1}, {1, 1, 1}, net).ok);
    const auto volume = std::make_shared<const core::LatticeNet>(std::move(net));
    std::vector<std::pair<core::Operation, core::ScriptOp::Kind>> cases;
    const auto add = [&](core::OperationKind kind, core::ScriptOp::Kind expected, auto&& shape) {
        core::Operation operation;
        operation.kind = kind;
        operation.steps.emplace_back();
        shape(operation);
        cases.emplace_back(operation, expected);
    };
    using OK = core::OperationKind;
    using SK = core::ScriptOp::Kind;
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
        INFO(core::scriptOpName(expected));
        int claims = 0;
        for (const core::ScriptOpInfo& info : core::scriptOps()) {
            core::ScriptOp op;
            if (info.record && info.record(operation, op)) {
                ++claims;
                CHECK(info.kind == expected);
            }
        }
        CHECK(claims == 1);
    }
    // Every op but begin_group and end_group runs through its entry.
    for (const core::ScriptOpInfo& info : core::scriptOps())
        CHECK((info.run == nullptr) == (info.kind == SK::BeginGroup || info.kind == SK::EndGroup));
}
