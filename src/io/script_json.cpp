#include "io/script_json.h"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

namespace sculpt::io {

namespace {

using nlohmann::json;

// A parse failure carries the field path; thrown only inside this file and turned into a Status.
struct FieldError {
    std::string path;
    std::string what;
};

[[noreturn]] void fail(const std::string& path, const std::string& what) { throw FieldError{path, what}; }

void allowOnly(const json& object, const std::string& path, std::initializer_list<const char*> keys) {
    if (!object.is_object()) fail(path, "expected an object");
    const std::set<std::string> allowed(keys.begin(), keys.end());
    for (auto it = object.begin(); it != object.end(); ++it)
        if (!allowed.count(it.key())) fail(path + "." + it.key(), "unknown field");
}

double number(const json& value, const std::string& path) {
    if (!value.is_number()) fail(path, "expected a number");
    const double d = value.get<double>();
    if (!std::isfinite(d)) fail(path, "expected a finite number");
    return d;
}

int integer(const json& value, const std::string& path) {
    if (!value.is_number_integer()) fail(path, "expected an integer");
    const auto i = value.get<long long>();
    if (i < -1000000000LL || i > 1000000000LL) fail(path, "integer out of range");
    return static_cast<int>(i);
}

Eigen::Vector3d vector3(const json& value, const std::string& path) {
    if (!value.is_array() || value.size() != 3) fail(path, "expected an array of 3 numbers");
    return {number(value[0], path + "[0]"), number(value[1], path + "[1]"), number(value[2], path + "[2]")};
}

std::array<int, 3> int3(const json& value, const std::string& path) {
    if (!value.is_array() || value.size() != 3) fail(path, "expected an array of 3 integers");
    return {integer(value[0], path + "[0]"), integer(value[1], path + "[1]"), integer(value[2], path + "[2]")};
}

core::LatticeSettings parseLattice(const json& j, const std::string& path) {
    allowOnly(j, path, {"resolution", "degree", "padding", "pin_layers", "region"});
    core::LatticeSettings s;
    if (j.contains("resolution")) s.resolution = int3(j["resolution"], path + ".resolution");
    if (j.contains("degree")) s.degree = int3(j["degree"], path + ".degree");
    if (j.contains("padding")) s.padding = number(j["padding"], path + ".padding");
    if (j.contains("pin_layers")) s.pinLayers = integer(j["pin_layers"], path + ".pin_layers");
    if (j.contains("region") && !j["region"].is_null()) {
        const json& r = j["region"];
        allowOnly(r, path + ".region", {"min", "max"});
        if (!r.contains("min") || !r.contains("max")) fail(path + ".region", "needs both \"min\" and \"max\"");
        s.hasRegion = true;
        s.regionMin = vector3(r["min"], path + ".region.min");
        s.regionMax = vector3(r["max"], path + ".region.max");
    }
    if (Status status = core::validateLatticeSettings(s); !status) fail(path, status.message);
    return s;
}

const json& required(const json& object, const char* key, const std::string& path) {
    if (!object.contains(key)) fail(path + "." + key, "missing");
    return object[key];
}

core::ScriptOp parseOp(const json& j, const std::string& path) {
    if (!j.is_object()) fail(path, "expected an object");
    if (!j.contains("op") || !j["op"].is_string()) fail(path + ".op", "expected a string");
    const std::string name = j["op"].get<std::string>();
    core::ScriptOp op;
    if (name == "drag") {
        allowOnly(j, path, {"op", "constraints"});
        op.kind = core::ScriptOp::Kind::Drag;
        const json& list = required(j, "constraints", path);
        if (!list.is_array() || list.empty()) fail(path + ".constraints", "expected a non-empty array");
        for (size_t c = 0; c < list.size(); ++c) {
            const std::string cp = path + ".constraints[" + std::to_string(c) + "]";
            allowOnly(list[c], cp, {"source", "target"});
            op.constraints.push_back({vector3(required(list[c], "source", cp), cp + ".source"),
                                      vector3(required(list[c], "target", cp), cp + ".target")});
        }
    } else if (name == "drag_vertex") {
        allowOnly(j, path, {"op", "vertex", "target"});
        op.kind = core::ScriptOp::Kind::DragVertex;
        op.vertex = integer(required(j, "vertex", path), path + ".vertex");
        op.target = vector3(required(j, "target", path), path + ".target");
    } else if (name == "move_control_point") {
        allowOnly(j, path, {"op", "index", "indices", "to", "by"});
        op.kind = core::ScriptOp::Kind::MoveControlPoint;
        if (j.contains("to") == j.contains("by")) fail(path, "needs exactly one of \"to\" and \"by\"");
        if (j.contains("index") == j.contains("indices")) fail(path, "needs exactly one of \"index\" and \"indices\"");
        op.relative = j.contains("by");
        const char* valueKey = op.relative ? "by" : "to";
        if (j.contains("index")) {
            op.controlPoints.push_back(int3(j["index"], path + ".index"));
            op.values = vector3(j[valueKey], path + "." + valueKey).transpose();
        } else {
            const json& ids = j["indices"];
            if (!ids.is_array() || ids.empty()) fail(path + ".indices", "expected a non-empty array of [i,j,k]");
            for (size_t c = 0; c < ids.size(); ++c)
                op.controlPoints.push_back(int3(ids[c], path + ".indices[" + std::to_string(c) + "]"));
            const json& values = j[valueKey];
            const std::string vp = path + "." + valueKey;
            op.values.resize(static_cast<Eigen::Index>(ids.size()), 3);
            if (values.is_array() && values.size() == 3 && values[0].is_number()) {
                // One offset/position for every listed point.
                const Eigen::Vector3d v = vector3(values, vp);
                for (Eigen::Index c = 0; c < op.values.rows(); ++c) op.values.row(c) = v.transpose();
            } else {
                if (!values.is_array() || values.size() != ids.size())
                    fail(vp, "expected one [x,y,z] per index, or a single [x,y,z]");
                for (size_t c = 0; c < ids.size(); ++c)
                    op.values.row(static_cast<Eigen::Index>(c)) = vector3(values[c], vp + "[" + std::to_string(c) + "]").transpose();
            }
        }
    } else if (name == "setup_lattice") {
        allowOnly(j, path, {"op", "lattice"});
        op.kind = core::ScriptOp::Kind::SetupLattice;
        if (j.contains("lattice") && !j["lattice"].is_null()) {
            op.hasSettings = true;
            op.settings = parseLattice(j["lattice"], path + ".lattice");
        }
    } else if (name == "set_pins") {
        allowOnly(j, path, {"op", "pin", "unpin"});
        op.kind = core::ScriptOp::Kind::SetPins;
        for (const char* key : {"pin", "unpin"}) {
            if (!j.contains(key)) continue;
            const json& ids = j[key];
            const std::string kp = path + "." + key;
            if (!ids.is_array()) fail(kp, "expected an array of [i,j,k]");
            auto& list = std::string(key) == "pin" ? op.controlPoints : op.unpinned;
            for (size_t c = 0; c < ids.size(); ++c) list.push_back(int3(ids[c], kp + "[" + std::to_string(c) + "]"));
        }
    } else if (name == "begin_group") {
        allowOnly(j, path, {"op", "label"});
        op.kind = core::ScriptOp::Kind::BeginGroup;
        if (j.contains("label")) {
            if (!j["label"].is_string()) fail(path + ".label", "expected a string");
            op.label = j["label"].get<std::string>();
        }
    } else if (name == "end_group") {
        allowOnly(j, path, {"op"});
        op.kind = core::ScriptOp::Kind::EndGroup;
    } else if (name == "undo" || name == "redo") {
        allowOnly(j, path, {"op"});
        op.kind = name == "undo" ? core::ScriptOp::Kind::Undo : core::ScriptOp::Kind::Redo;
    } else if (name == "screenshot") {
        allowOnly(j, path, {"op", "path"});
        op.kind = core::ScriptOp::Kind::Screenshot;
        const json& p = required(j, "path", path);
        if (!p.is_string() || p.get<std::string>().empty()) fail(path + ".path", "expected a file path");
        op.path = p.get<std::string>();
    } else {
        fail(path + ".op", "unknown op \"" + name +
                               "\" (known: drag, drag_vertex, move_control_point, setup_lattice, set_pins, begin_group, end_group, undo, redo, screenshot)");
    }
    return op;
}

json vectorJson(const Eigen::Vector3d& v) { return json::array({v.x(), v.y(), v.z()}); }

int lineOfByte(const std::string& text, size_t byte) {
    int line = 1;
    for (size_t i = 0; i < byte && i < text.size(); ++i) line += text[i] == '\n';
    return line;
}

}  // namespace

Status readTextFile(const std::string& path, std::string& out) {
    std::ifstream file(path, std::ios::binary);
    if (!file) return Status::error(path + ": cannot open (" + std::string(std::strerror(errno)) + ")");
    std::ostringstream buffer;
    buffer << file.rdbuf();
    if (file.bad()) return Status::error(path + ": read error");
    out = buffer.str();
    return Status::success();
}

Status parseScript(const std::string& text, const std::string& displayName, core::Script& out) {
    json root;
    try {
        root = json::parse(text);
    } catch (const json::parse_error& e) {
        return Status::error(displayName + ":" + std::to_string(lineOfByte(text, e.byte)) + ": invalid JSON (" + e.what() + ")");
    } catch (const json::exception& e) {  // e.g. a number too large for a double (1e999)
        return Status::error(displayName + ": invalid JSON (" + e.what() + ")");
    }
    try {
        core::Script script;
        allowOnly(root, "", {"mesh", "lattice", "ops", "injectivity"});
        if (root.contains("mesh")) {
            const json& mesh = root["mesh"];
            if (!mesh.is_string() || mesh.get<std::string>().empty()) fail("mesh", "expected a file path");
            script.mesh = mesh.get<std::string>();
        }
        if (root.contains("lattice")) script.lattice = parseLattice(root["lattice"], "lattice");
        if (root.contains("injectivity")) {
            const json& inj = root["injectivity"];
            allowOnly(inj, "injectivity", {"mode", "max_depth", "triangles"});
            if (inj.contains("mode")) {
                if (!inj["mode"].is_string() || !core::parseInjectivityMode(inj["mode"].get<std::string>(), script.injectivity.mode))
                    fail("injectivity.mode", "expected \"off\", \"conic\" or \"exact\"");
            }
            if (inj.contains("max_depth")) {
                script.injectivity.maxDepth = integer(inj["max_depth"], "injectivity.max_depth");
                if (script.injectivity.maxDepth < 0 || script.injectivity.maxDepth > 12)
                    fail("injectivity.max_depth", "must be in [0, 12]");
            }
            if (inj.contains("triangles")) {
                if (!inj["triangles"].is_boolean()) fail("injectivity.triangles", "expected true or false");
                script.injectivity.checkTriangles = inj["triangles"].get<bool>();
            }
        }
        if (root.contains("ops")) {
            const json& ops = root["ops"];
            if (!ops.is_array()) fail("ops", "expected an array");
            for (size_t i = 0; i < ops.size(); ++i) script.ops.push_back(parseOp(ops[i], "ops[" + std::to_string(i) + "]"));
        }
        out = std::move(script);
        return Status::success();
    } catch (const FieldError& e) {
        const std::string field = e.path.empty() ? "top level" : (e.path[0] == '.' ? e.path.substr(1) : e.path);
        return Status::error(displayName + ": " + field + ": " + e.what);
    } catch (const std::exception& e) {
        return Status::error(displayName + ": " + e.what());
    }
}

namespace {

json injectivityJson(const core::InjectivitySettings& s) {
    return {{"mode", core::injectivityModeName(s.mode)}, {"max_depth", s.maxDepth}, {"triangles", s.checkTriangles}};
}

json latticeJson(const core::LatticeSettings& s) {
    json j = {{"resolution", s.resolution}, {"degree", s.degree}, {"padding", s.padding}, {"pin_layers", s.pinLayers}};
    j["region"] = s.hasRegion ? json{{"min", vectorJson(s.regionMin)}, {"max", vectorJson(s.regionMax)}} : json(nullptr);
    return j;
}

}  // namespace

std::string scriptToJson(const core::Script& script) {
    json root;
    if (!script.mesh.empty()) root["mesh"] = script.mesh;
    root["lattice"] = latticeJson(script.lattice);
    root["injectivity"] = injectivityJson(script.injectivity);
    json ops = json::array();
    for (const core::ScriptOp& op : script.ops) {
        json j;
        j["op"] = core::scriptOpName(op.kind);
        switch (op.kind) {
            case core::ScriptOp::Kind::Drag: {
                json constraints = json::array();
                for (const core::PointConstraint& c : op.constraints)
                    constraints.push_back({{"source", vectorJson(c.source)}, {"target", vectorJson(c.target)}});
                j["constraints"] = constraints;
                break;
            }
            case core::ScriptOp::Kind::DragVertex:
                j["vertex"] = op.vertex;
                j["target"] = vectorJson(op.target);
                break;
            case core::ScriptOp::Kind::MoveControlPoint: {
                json ids = json::array(), values = json::array();
                for (size_t c = 0; c < op.controlPoints.size(); ++c) {
                    ids.push_back(op.controlPoints[c]);
                    values.push_back(vectorJson(op.values.row(static_cast<Eigen::Index>(c)).transpose()));
                }
                j["indices"] = ids;
                j[op.relative ? "by" : "to"] = values;
                break;
            }
            case core::ScriptOp::Kind::SetupLattice:
                if (op.hasSettings) j["lattice"] = latticeJson(op.settings);
                break;
            case core::ScriptOp::Kind::SetPins:
                j["pin"] = op.controlPoints;
                j["unpin"] = op.unpinned;
                break;
            case core::ScriptOp::Kind::BeginGroup:
                if (!op.label.empty()) j["label"] = op.label;
                break;
            case core::ScriptOp::Kind::EndGroup: break;
            case core::ScriptOp::Kind::Screenshot: j["path"] = op.path; break;
            case core::ScriptOp::Kind::Undo:
            case core::ScriptOp::Kind::Redo: break;
        }
        ops.push_back(j);
    }
    root["ops"] = ops;
    return root.dump(2) + "\n";
}

std::string resolveScriptMesh(const core::Script& script, const std::string& scriptPath) {
    namespace fs = std::filesystem;
    if (script.mesh.empty()) return {};
    const fs::path mesh(script.mesh);
    if (mesh.is_absolute()) return mesh.lexically_normal().string();
    return (fs::path(scriptPath).parent_path() / mesh).lexically_normal().string();
}

std::string scriptRelativeMeshPath(const std::string& meshPath, const std::string& scriptPath) {
    namespace fs = std::filesystem;
    std::error_code error;
    const fs::path mesh = fs::absolute(meshPath, error).lexically_normal();
    if (error) return meshPath;
    const fs::path folder = fs::absolute(fs::path(scriptPath), error).parent_path().lexically_normal();
    if (error) return mesh.string();
    const fs::path relative = mesh.lexically_relative(folder);
    return relative.empty() ? mesh.string() : relative.string();
}

Status loadScript(const std::string& path, core::Script& out) {
    std::string text;
    if (Status s = readTextFile(path, text); !s) return s;
    return parseScript(text, path, out);
}

std::string reportToJson(const core::ScriptReport& report, const core::Session& session, const ReportContext& context) {
    json root;
    root["input"] = context.input;
    root["script"] = context.script;
    root["output"] = context.output;
    root["vertices"] = context.vertexCount;
    root["triangles"] = context.triangleCount;
    root["bbox_diagonal"] = context.diagonal;
    const core::Lattice& lattice = session.lattice();
    root["lattice"] = {{"resolution", lattice.count},
                       {"degree", lattice.degree},
                       {"box_min", vectorJson(lattice.boxMin)},
                       {"box_max", vectorJson(lattice.boxMax)}};
    json ops = json::array();
    for (size_t i = 0; i < report.ops.size(); ++i) {
        const core::OpReport& r = report.ops[i];
        json op;
        op["index"] = i;
        op["op"] = r.op;
        op["status"] = core::opStatusName(r.status);
        if (!r.reason.empty()) op["reason"] = r.reason;
        if (!r.residuals.empty()) {
            op["residuals"] = r.residuals;
            double worst = 0.0;
            for (double v : r.residuals) worst = std::max(worst, v);
            op["max_residual"] = worst;
            op["rank_deficient"] = r.rankDeficient;
        }
        if (!r.injectivity.empty()) op["injectivity"] = r.injectivity;
        op["sub_steps"] = r.subSteps;
        op["depth_reached"] = r.depthReached;
        op["injectivity_ms"] = r.injectivityMs;
        if (!r.refusedBy.empty()) op["refused_by"] = r.refusedBy;
        op["triangle_check_ms"] = r.triangleCheckMs;
        if (r.fractionApplied < 1.0) op["fraction_applied"] = r.fractionApplied;
        op["control_points_changed"] = r.controlPointsChanged;
        op["vertices_moved"] = r.verticesMoved;
        op["wall_ms"] = r.wallMs;
        ops.push_back(op);
    }
    root["ops"] = ops;
    root["history"] = {{"entries", session.history().size()}, {"cursor", session.historyCursor()},
                       {"bytes", session.historyBytes()}, {"lattice_frames", session.frameDepth() + 1}};
    root["injectivity"] = injectivityJson(session.injectivity());
    root["self_intersecting_pairs_at_load"] = session.initialIntersectingPairs();
    return root.dump(2) + "\n";
}

}  // namespace sculpt::io
