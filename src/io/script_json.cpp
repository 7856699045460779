// Reading scripts and recorded sessions (script_json.h): the top level, each op through its entry in the op
// table (script_ops.h), a recording's "applied" steps, and the fields several ops share (script_json_fields.h).
// Writing: script_json_write.cpp.
#include "io/script_json.h"

#include "core/volume/volume_kinds.h"

#include <sys/stat.h>

#include <cerrno>
#include <cstdio>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <set>

#include <nlohmann/json.hpp>

#include "io/huge_pages.h"
#include "io/json_fields.h"
#include "io/json_text.h"
#include "io/lattice_json.h"
#include "io/script_json_fields.h"
#include "io/script_ops.h"

namespace sculpt::io {

namespace {

// The folder file paths in a script are relative to (the script's own), set by parseScript.
thread_local std::string gScriptFolder;

}  // namespace

namespace script_fields {

using namespace json_fields;

core::BrushSettings parseBrush(const json& j, const std::string& path) {
    core::BrushSettings brush;
    if (j.contains("radius")) {
        brush.radius = number(j["radius"], path + ".radius");
        if (brush.radius < 0.0) fail(path + ".radius", "expected a number >= 0 (world units; 0 = no brush)");
    }
    if (j.contains("strength")) {
        brush.strength = number(j["strength"], path + ".strength");
        if (brush.strength <= 0.0 || brush.strength > 1.0) fail(path + ".strength", "expected a number in (0, 1]");
    }
    if (j.contains("falloff")) {
        if (!j["falloff"].is_string()) fail(path + ".falloff", "expected \"smooth\", \"medium\" or \"sharp\"");
        if (Status s = core::parseBrushFalloff(j["falloff"].get<std::string>(), brush.falloff); !s) fail(path + ".falloff", s.message);
    }
    if (j.contains("symmetry")) {
        if (!j["symmetry"].is_string()) fail(path + ".symmetry", "expected a string such as \"x\" or \"xz\"");
        if (Status s = core::parseSymmetry(j["symmetry"].get<std::string>(), brush.symmetry); !s) fail(path + ".symmetry", s.message);
    }
    return brush;
}

core::LatticeSettings parseLattice(const json& j, const std::string& path) {
    core::LatticeSettings s;
    if (j.is_object() && j.contains("kind")) {
        // A lattice of any shape (lattice_json.h), with the pin layers counted from its boundary faces.
        json shape = j;
        shape.erase("pin_layers");
        if (Status status = parseVolumeJson(shape, path, s.volume); !status) {
            const size_t colon = status.message.find(": ");  // "field.path: what"
            fail(status.message.substr(0, colon), colon == std::string::npos ? status.message : status.message.substr(colon + 2));
        }
        if (j.contains("pin_layers")) s.pinLayers = integer(j["pin_layers"], path + ".pin_layers");
        if (Status status = core::validateLatticeSettings(s); !status) fail(path, status.message);
        return s;
    }
    allowOnly(j, path, {"resolution", "degree", "padding", "pin_layers", "region"});
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

std::vector<core::PointConstraint> parseConstraints(const json& list, const std::string& path, bool allowEmpty) {
    if (!list.is_array() || (!allowEmpty && list.empty())) fail(path, allowEmpty ? "expected an array" : "expected a non-empty array");
    std::vector<core::PointConstraint> out;
    for (size_t c = 0; c < list.size(); ++c) {
        const std::string cp = path + "[" + std::to_string(c) + "]";
        allowOnly(list[c], cp, {"source", "target"});
        out.push_back({vector3(required(list[c], "source", cp), cp + ".source"), vector3(required(list[c], "target", cp), cp + ".target")});
    }
    return out;
}

std::vector<int> intList(const json& list, const std::string& path) {
    if (!list.is_array()) fail(path, "expected an array of integers");
    std::vector<int> out;
    for (size_t i = 0; i < list.size(); ++i) out.push_back(integer(list[i], path + "[" + std::to_string(i) + "]"));
    return out;
}

std::vector<double> numberList(const json& list, const std::string& path) {
    if (!list.is_array()) fail(path, "expected an array of numbers");
    std::vector<double> out;
    for (size_t i = 0; i < list.size(); ++i) out.push_back(number(list[i], path + "[" + std::to_string(i) + "]"));
    return out;
}

Eigen::MatrixX3d vectorRows(const json& list, const std::string& path) {
    if (!list.is_array()) fail(path, "expected an array of [x,y,z]");
    Eigen::MatrixX3d out(static_cast<Eigen::Index>(list.size()), 3);
    for (size_t i = 0; i < list.size(); ++i) out.row(static_cast<Eigen::Index>(i)) = vector3(list[i], path + "[" + std::to_string(i) + "]").transpose();
    return out;
}

double tolerance(const json& value, const std::string& path) {
    const double t = number(value, path);
    if (t <= 0.0) fail(path, "expected a number > 0 (a fraction of the bounding-box diagonal)");
    return t;
}

core::RefinementSettings parseRefinementSettings(const json& j, const std::string& path) {
    core::RefinementSettings settings;
    if (j.contains("automatic")) settings.automatic = boolean(j["automatic"], path + ".automatic");
    if (j.contains("tolerance")) settings.options.tolerance = tolerance(j["tolerance"], path + ".tolerance");
    if (j.contains("max_rounds")) settings.options.maxRounds = integer(j["max_rounds"], path + ".max_rounds");
    if (j.contains("max_vertices")) settings.options.maxVertices = integer(j["max_vertices"], path + ".max_vertices");
    if (j.contains("under_brush")) settings.underBrush = boolean(j["under_brush"], path + ".under_brush");
    if (Status s = core::validateRefinementOptions(settings.options); !s) fail(path, s.message);
    return settings;
}


core::LatticeTool parseTool(const json& j, const std::string& path, bool edit) {
    core::LatticeTool tool;
    std::shared_ptr<const core::Volume> volume;
    if (edit && !j.contains("lattice") && !j.contains("file")) {
        if (!j.contains("edits")) fail(path, "expected \"lattice\", \"file\" or \"edits\"");
        if (j.contains("place")) fail(path + ".place", "places a \"lattice\" or \"file\"; an edit of the current net has neither");
        if (j.contains("name")) tool.name = text(j["name"], path + ".name");
        return tool;
    }
    if (j.contains("lattice") == j.contains("file")) fail(path, "expected one of \"lattice\" and \"file\"");
    if (j.contains("file")) {
        std::filesystem::path file(text(j["file"], path + ".file"));
        if (file.is_relative() && !gScriptFolder.empty()) file = std::filesystem::path(gScriptFolder) / file;
        LatticeFile library;
        if (Status s = readLatticeFile(file.string(), library); !s) fail(path + ".file", s.message);
        volume = std::move(library.volume);
        tool.name = library.name;
    } else if (Status s = parseVolumeJson(j["lattice"], path + ".lattice", volume); !s) {
        const size_t colon = s.message.find(": ");
        fail(s.message.substr(0, colon), colon == std::string::npos ? s.message : s.message.substr(colon + 2));
    }
    if (j.contains("place")) {
        const json& place = j["place"];
        allowOnly(place, path + ".place", {"point", "normal", "size"});
        std::shared_ptr<const core::Volume> placed;
        if (Status s = core::placeVolume(*volume, vector3(required(place, "point", path + ".place"), path + ".place.point"),
                                             vector3(required(place, "normal", path + ".place"), path + ".place.normal"),
                                             number(required(place, "size", path + ".place"), path + ".place.size"), placed);
            !s)
            fail(path + ".place", s.message);
        volume = std::move(placed);
    }
    if (edit) tool.name.clear();  // note: an edit keeps the tool's name, whatever a library file calls its lattice
    if (j.contains("name")) tool.name = text(j["name"], path + ".name");
    if (tool.name.empty() && !edit) tool.name = volume->kindName();
    tool.volume = std::move(volume);
    return tool;
}


namespace {

// Slot ids of an edit: integers >= 0 (whether they are in the lattice is known when the edit runs).
std::vector<int> parseSlots(const json& j, const std::string& path, size_t least) {
    if (!j.is_array() || j.size() < least)
        fail(path, "expected an array of " + std::to_string(least) + " or more slot ids (i + count_u (j + count_v k))");
    std::vector<int> slots;
    for (size_t s = 0; s < j.size(); ++s) {
        const std::string sp = path + "[" + std::to_string(s) + "]";
        const int id = integer(j[s], sp);
        if (id < 0) fail(sp, "expected a slot id >= 0");
        slots.push_back(id);
    }
    return slots;
}

int parseEditAxis(const json& j, const std::string& path) {
    const int axis = integer(required(j, "axis", path), path + ".axis");
    if (axis < 0 || axis > 2) fail(path + ".axis", "expected 0 (u), 1 (v) or 2 (w)");
    return axis;
}

}  // namespace

std::vector<core::NetEdit> parseEdits(const json& j, const std::string& path) {
    if (!j.is_array() || j.empty()) fail(path, "expected a non-empty array of edits");
    std::vector<core::NetEdit> edits;
    for (size_t e = 0; e < j.size(); ++e) {
        const std::string ep = path + "[" + std::to_string(e) + "]";
        const json& item = j[e];
        if (!item.is_object() || item.size() != 1)
            fail(ep, "expected an object with one of \"move\", \"merge\", \"refine\", \"insert\", \"remove\"");
        const std::string key = item.begin().key();
        const json& value = item.begin().value();
        const std::string vp = ep + "." + key;
        core::NetEdit edit;
        if (key == "move") {
            edit.kind = core::NetEdit::Kind::Move;
            allowOnly(value, vp, {"points", "offset"});
            edit.slots = parseSlots(required(value, "points", vp), vp + ".points", 1);
            edit.offset = vector3(required(value, "offset", vp), vp + ".offset");
        } else if (key == "merge") {
            edit.kind = core::NetEdit::Kind::Merge;
            edit.slots = parseSlots(value, vp, 2);
        } else if (key == "refine") {
            edit.kind = core::NetEdit::Kind::Refine;
            allowOnly(value, vp, {"axis"});
            edit.axis = parseEditAxis(value, vp);
        } else if (key == "insert") {
            edit.kind = core::NetEdit::Kind::Insert;
            allowOnly(value, vp, {"axis", "at", "times"});
            edit.axis = parseEditAxis(value, vp);
            edit.at = number(required(value, "at", vp), vp + ".at");
            if (!(edit.at > 0.0 && edit.at < 1.0)) fail(vp + ".at", "expected a lattice parameter strictly inside (0, 1)");
            edit.times = value.contains("times") ? integer(value["times"], vp + ".times") : 1;
            if (edit.times < 1 || edit.times > core::kMaxDegree) fail(vp + ".times", "expected 1 to the axis' degree");
        } else if (key == "remove") {
            edit.kind = core::NetEdit::Kind::Remove;
            allowOnly(value, vp, {"axis", "index"});
            edit.axis = parseEditAxis(value, vp);
            edit.index = integer(required(value, "index", vp), vp + ".index");
            if (edit.index < 0) fail(vp + ".index", "expected a slice index >= 0");
        } else {
            fail(vp, "unknown edit (known: move, merge, refine, insert, remove)");
        }
        edits.push_back(std::move(edit));
    }
    return edits;
}

}  // namespace script_fields

namespace {

using namespace json_fields;
using namespace script_fields;

// "refinement" of a recorded operation: {"tolerance": t, "splits": [[a, b], ...]} (refinement.h, EdgeSplit).
core::RefinementRecord parseRefinementRecord(const json& j, const std::string& path) {
    allowOnly(j, path, {"tolerance", "splits"});
    core::RefinementRecord record;
    if (j.contains("tolerance")) record.tolerance = tolerance(j["tolerance"], path + ".tolerance");
    const json& splits = required(j, "splits", path);
    if (!splits.is_array()) fail(path + ".splits", "expected an array of [a, b] vertex pairs");
    record.splits.reserve(splits.size());
    for (size_t k = 0; k < splits.size(); ++k) {
        const std::string sp = path + ".splits[" + std::to_string(k) + "]";
        if (!splits[k].is_array() || splits[k].size() != 2) fail(sp, "expected [a, b]: the two vertices of the edge split");
        record.splits.push_back({integer(splits[k][0], sp + "[0]"), integer(splits[k][1], sp + "[1]")});
    }
    return record;
}


// A recorded operation as it was applied (ScriptOp::applied): its steps in their lattices.
core::Operation parseApplied(const json& j, const std::string& path) {
    allowOnly(j, path, {"kind", "label", "interactive", "depth", "constraints", "control_points", "offsets", "lattice", "steps", "brush", "frozen", "refinement", "refinement_before"});
    core::Operation operation;
    const json& kind = required(j, "kind", path);
    const std::string name = kind.is_string() ? kind.get<std::string>() : "";
    if (name == "drag") operation.kind = core::OperationKind::Drag;
    else if (name == "control_point_edit") operation.kind = core::OperationKind::ControlPointEdit;
    else if (name == "lattice_setup") operation.kind = core::OperationKind::LatticeSetup;
    else if (name == "refine") operation.kind = core::OperationKind::Refine;
    else if (name == "weight_edit") operation.kind = core::OperationKind::WeightEdit;
    else fail(path + ".kind", "expected \"drag\", \"control_point_edit\", \"lattice_setup\", \"refine\" or \"weight_edit\"");
    if (j.contains("label")) operation.label = text(j["label"], path + ".label");
    if (j.contains("interactive")) operation.interactive = boolean(j["interactive"], path + ".interactive");
    if (j.contains("depth")) operation.depthReached = integer(j["depth"], path + ".depth");
    if (j.contains("constraints")) operation.constraints = parseConstraints(j["constraints"], path + ".constraints", true);
    if (j.contains("control_points")) operation.controlPoints = intList(j["control_points"], path + ".control_points");
    if (j.contains("offsets")) operation.offsets = vectorRows(j["offsets"], path + ".offsets");
    if (operation.offsets.rows() != static_cast<Eigen::Index>(operation.controlPoints.size()))
        fail(path + ".offsets", "expected one [x,y,z] per control point");
    if (j.contains("lattice")) operation.settings = parseLattice(j["lattice"], path + ".lattice");
    if (j.contains("frozen")) {  // a freeze or unfreeze: the frozen lattice tool before and after (-1: the box)
        const std::array<int, 2> frozen = intArray<2>(j["frozen"], path + ".frozen");
        operation.frozenBefore = frozen[0];
        operation.frozenAfter = frozen[1];
    }
    if (j.contains("brush")) {
        allowOnly(j["brush"], path + ".brush", {"radius", "strength", "falloff", "symmetry"});
        operation.brush = parseBrush(j["brush"], path + ".brush");
    }
    if (j.contains("refinement")) operation.refinement = parseRefinementRecord(j["refinement"], path + ".refinement");
    if (j.contains("refinement_before")) operation.refinementBefore = parseRefinementRecord(j["refinement_before"], path + ".refinement_before");
    if (operation.kind == core::OperationKind::Refine && operation.refinement.empty()) fail(path + ".refinement", "a refine splits at least one edge");
    const json& steps = required(j, "steps", path);
    // A refine has no lattice steps, only its splits.
    if (!steps.is_array() || (steps.empty() && operation.kind != core::OperationKind::Refine)) fail(path + ".steps", "expected a non-empty array");
    for (size_t k = 0; k < steps.size(); ++k) {
        const std::string sp = path + ".steps[" + std::to_string(k) + "]";
        allowOnly(steps[k], sp, {"new_layer", "new_cage", "fresh_frame", "frame", "region_free", "lattice", "indices", "deltas", "constraints", "weights",
                                 "baked"});
        core::Step step;
        const auto flag = [&](const char* key) { return steps[k].contains(key) && boolean(steps[k][key], sp + "." + key); };
        step.freshFrame = flag("new_layer");
        step.newCage = flag("new_cage");
        step.baked = flag("baked");
        // note: recordings before layers said "fresh_frame" for both; a set-up's was a new cage.
        if (flag("fresh_frame")) (operation.kind == core::OperationKind::LatticeSetup ? step.newCage : step.freshFrame) = true;
        if (step.freshFrame && step.newCage) fail(sp, "a step cannot make both a new layer and a new cage");
        if (steps[k].contains("region_free")) {
            if (!step.freshFrame) fail(sp + ".region_free", "only a step with \"new_layer\" has a region");
            step.region = true;
            step.regionFree = intList(steps[k]["region_free"], sp + ".region_free");
        }
        if (step.freshFrame || step.newCage) {
            const json& frame = required(steps[k], "frame", sp);
            const std::string fp = sp + ".frame";
            allowOnly(frame, fp, {"min", "max", "pins_kept", "axes"});
            if (frame.contains("axes")) {
                // A brush region turned to its pull (Lattice::boxAxes): three rows, the world directions of u, v, w.
                const Eigen::MatrixX3d rows = vectorRows(frame["axes"], fp + ".axes");
                if (rows.rows() != 3) fail(fp + ".axes", "expected three [x,y,z] rows");
                if (!step.freshFrame) fail(fp + ".axes", "only a step with \"new_layer\" has turned axes");
                step.frameAxes = rows;
            }
            step.frameMin = vector3(required(frame, "min", fp), fp + ".min");
            step.frameMax = vector3(required(frame, "max", fp), fp + ".max");
            if (!(step.frameMin.array() < step.frameMax.array()).all()) fail(fp, "\"min\" must be below \"max\" on every axis");
            step.framePinsKept = boolean(required(frame, "pins_kept", fp), fp + ".pins_kept");
        }
        step.settings = parseLattice(required(steps[k], "lattice", sp), sp + ".lattice");
        step.delta.indices = intList(required(steps[k], "indices", sp), sp + ".indices");
        step.delta.deltas = vectorRows(required(steps[k], "deltas", sp), sp + ".deltas");
        if (step.delta.deltas.rows() != static_cast<Eigen::Index>(step.delta.indices.size()))
            fail(sp + ".deltas", "expected one [x,y,z] per index");
        if (steps[k].contains("constraints")) step.constraints = parseConstraints(steps[k]["constraints"], sp + ".constraints", true);
        if (steps[k].contains("weights")) {  // a weight change of the frozen T-spline (core::WeightChange)
            const json& w = steps[k]["weights"];
            const std::string wp = sp + ".weights";
            allowOnly(w, wp, {"ids", "before", "after"});
            step.weights.ids = intList(required(w, "ids", wp), wp + ".ids");
            step.weights.before = numberList(required(w, "before", wp), wp + ".before");
            step.weights.after = numberList(required(w, "after", wp), wp + ".after");
            if (step.weights.before.size() != step.weights.ids.size() || step.weights.after.size() != step.weights.ids.size())
                fail(wp, "expected one weight before and after per id");
            if (step.freshFrame || step.newCage) fail(wp, "a weight change is in the frozen lattice, not in a new layer or cage");
        }
        operation.steps.push_back(std::move(step));
    }
    return operation;
}

// "applied" and "cancelled", the fields a recording adds to an op.
void parseRecorded(const json& j, const std::string& path, io::ScriptOp& op) {
    if (j.contains("applied")) {
        op.hasApplied = true;
        op.applied = parseApplied(j["applied"], path + ".applied");
    }
    if (j.contains("cancelled")) {
        op.cancelled = boolean(j["cancelled"], path + ".cancelled");
        if (op.cancelled && !op.hasApplied) fail(path + ".cancelled", "needs \"applied\"");
    }
}


io::ScriptOp parseOp(const json& j, const std::string& path) {
    if (!j.is_object()) fail(path, "expected an object");
    if (!j.contains("op") || !j["op"].is_string()) fail(path + ".op", "expected a string");
    const std::string name = j["op"].get<std::string>();
    // The op's entry in the table (script_ops.h) names its kind and every field it may have, and reads them.
    const io::ScriptOpInfo* info = io::findScriptOp(name);
    if (!info) fail(path + ".op", "unknown op \"" + name + "\" (known: " + io::scriptOpNames() + ")");
    const std::set<std::string> allowed(info->fields.begin(), info->fields.end());
    for (auto it = j.begin(); it != j.end(); ++it)
        if (it.key() != "op" && !allowed.count(it.key())) fail(path + "." + it.key(), "unknown field");
    io::ScriptOp op;
    op.kind = info->kind;
    if (allowed.count("applied")) parseRecorded(j, path, op);
    if (info->read) info->read(j, path, op);
    return op;
}


}  // namespace

Status readTextFile(const std::string& path, std::string& out) {
    std::FILE* file = std::fopen(path.c_str(), "rb");
    if (!file) return Status::error(path + ": cannot open (" + std::string(std::strerror(errno)) + ")");
    // One buffer of the file's size (advised for huge pages: a 40 MB scan is 10,000 page faults otherwise), then
    // whatever more there is (a file still growing, a pipe, a /proc file that says 0).
    struct stat info {};
    const size_t expected = ::fstat(::fileno(file), &info) == 0 && S_ISREG(info.st_mode) ? static_cast<size_t>(info.st_size) : 0;
    std::string text;
    reserveWithHugePages(text, expected + 1);
    text.resize(expected);
    text.resize(std::fread(text.data(), 1, expected, file));
    if (text.size() == expected) {
        char chunk[65536];
        for (size_t n; (n = std::fread(chunk, 1, sizeof chunk, file)) > 0;) text.append(chunk, n);
    }
    const bool failed = std::ferror(file) != 0;
    const int error = errno;
    std::fclose(file);
    if (failed) return Status::error(path + ": read error (" + std::string(std::strerror(error)) + ")");
    out = std::move(text);
    return Status::success();
}

Status parseScript(const std::string& text, const std::string& displayName, io::Script& out) {
    json root;
    if (Status s = parseJsonText(text, displayName, root); !s) return s;
    try {
        io::Script script;
        allowOnly(root, "", {"mesh", "mesh_fingerprint", "weld", "lattice", "ops", "injectivity"});
        if (root.contains("weld")) script.weldMesh = boolean(root["weld"], "weld");
        if (root.contains("mesh_fingerprint")) script.meshFingerprint = json_fields::text(root["mesh_fingerprint"], "mesh_fingerprint");
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
            if (inj.contains("triangles")) script.injectivity.checkTriangles = boolean(inj["triangles"], "injectivity.triangles");
        }
        if (root.contains("ops")) {
            const json& ops = root["ops"];
            if (!ops.is_array()) fail("ops", "expected an array");
            gScriptFolder = std::filesystem::path(displayName).parent_path().string();
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

std::string resolveScriptMesh(const io::Script& script, const std::string& scriptPath) {
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

Status loadScript(const std::string& path, io::Script& out) {
    std::string text;
    if (Status s = readTextFile(path, text); !s) return s;
    return parseScript(text, path, out);
}

}  // namespace sculpt::io