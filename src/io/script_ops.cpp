// The table of script ops (script_ops.h): per op its name, its JSON fields and how they are read and written, how
// it runs on a session and which history entries it records.
#include "io/script_ops.h"

#include <algorithm>
#include <chrono>

#include "io/json_fields.h"
#include "io/lattice_json.h"
#include "io/script_json_fields.h"

namespace sculpt::io {

using namespace sculpt::core;

namespace {

using K = ScriptOp::Kind;
using nlohmann::json;
using namespace json_fields;
using namespace script_fields;

// Lattice ids of (i,j,k) triples; an error names the first one outside the lattice.
Status controlPointIds(const Lattice& lattice, const std::vector<std::array<int, 3>>& points, std::vector<int>& ids) {
    for (const auto& c : points) {
        for (int a = 0; a < 3; ++a)
            if (c[a] < 0 || c[a] >= lattice.count[a])
                return Status::error("control point index [" + std::to_string(c[0]) + "," + std::to_string(c[1]) + "," +
                                     std::to_string(c[2]) + "] is outside the " + std::to_string(lattice.count[0]) + "x" +
                                     std::to_string(lattice.count[1]) + "x" + std::to_string(lattice.count[2]) + " lattice");
        ids.push_back(lattice.index(c[0], c[1], c[2]));
    }
    return Status::success();
}

// A command that is no history entry (a setting), reported as applied when it succeeds.
template <typename Command>
Status setting(OpReport& report, Command command) {
    report = OpReport{};
    if (Status s = command(); !s) return s;
    report.status = OpStatus::Applied;
    return Status::success();
}

Status runSetPins(Session& session, const ScriptOp& op, OpReport& report, const ScreenshotHook&) {
    report = OpReport{};
    report.op = "set_pins";
    const Lattice& lattice = session.lattice();
    std::vector<int> pin, unpin;
    if (Status s = controlPointIds(lattice, op.controlPoints, pin); !s) return s;
    if (Status s = controlPointIds(lattice, op.unpinned, unpin); !s) return s;
    const int layers = session.cage().settings().pinLayers;
    for (int idx : pin)
        if (inOuterLayers(lattice, idx, layers)) return Status::error("\"pin\" lists a control point the pin layers already pin");
    for (int idx : unpin)
        if (!inOuterLayers(lattice, idx, layers)) return Status::error("\"unpin\" lists a control point outside the pin layers");
    pin.insert(pin.end(), unpin.begin(), unpin.end());
    std::sort(pin.begin(), pin.end());
    pin.erase(std::unique(pin.begin(), pin.end()), pin.end());
    if (Status s = session.pins().setToggles(pin); !s) return s;
    report.status = OpStatus::Applied;
    return Status::success();
}

Status runEditLattice(Session& session, const ScriptOp& op, OpReport& report, const ScreenshotHook&) {
    const std::vector<LatticeTool>& tools = session.tools().list();
    if (op.toolIndex < 0 || op.toolIndex >= static_cast<int>(tools.size()) || op.toolIndex == session.tools().frozen())
        return session.tools().edit(op.toolIndex, op.tool, report);  // refused there, with the reason
    const LatticeTool& current = tools[static_cast<size_t>(op.toolIndex)];
    LatticeTool tool = op.tool;
    if (tool.name.empty()) tool.name = current.name;  // an edit keeps the tool's name unless it gives one
    if (!tool.volume) tool.volume = current.volume;
    if (!op.netEdits.empty()) {
        const LatticeNet* net = tool.volume->tensorNet();
        if (!net)
            return Status::error("edits move, merge, refine and remove the points of one net; lattice " + tool.name + " is a " +
                                 tool.volume->kindName() + " (edit its parts before welding them)");
        LatticeNet edited;
        if (Status s = applyNetEdits(*net, op.netEdits, edited); !s) return s;
        tool.volume = std::make_shared<const LatticeNet>(std::move(edited));
    }
    return session.tools().edit(op.toolIndex, tool, report);
}

Status runWeightTool(Session& session, const ScriptOp& op, OpReport& report, const ScreenshotHook&) {
    WeightToolSettings settings = op.weightTool;
    settings.tool = op.kind == K::SetWeights ? WeightToolSettings::Tool::SetWeights
                    : op.kind == K::Hammer   ? WeightToolSettings::Tool::Hammer
                                             : WeightToolSettings::Tool::Crimp;
    return session.tspline().sculptWeights(settings, report);
}

Status runScreenshot(Session& session, const ScriptOp& op, OpReport& report, const ScreenshotHook& screenshot) {
    const auto start = std::chrono::steady_clock::now();
    report = OpReport{};
    report.op = "screenshot";
    if (!screenshot) return Status::error("screenshots are not available in this build");
    if (Status s = screenshot(session, op); !s) return s;
    report.status = OpStatus::Applied;
    report.reason = "wrote " + op.path;
    report.wallMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return Status::success();
}

bool recordWeightTool(const Operation& operation, ScriptOp& op, WeightToolSettings::Tool tool) {
    if (operation.kind != OperationKind::WeightEdit || operation.weightTool.tool != tool) return false;
    op.weightTool = operation.weightTool;
    return true;
}

// A lattice set-up as recorded: its settings (a freeze or unfreeze is a set-up that changes the frozen tool).
bool recordSetup(const Operation& operation, ScriptOp& op) {
    if (operation.kind != OperationKind::LatticeSetup) return false;
    op.hasSettings = true;
    op.settings = operation.settings;
    return true;
}

// add_lattice / edit_lattice: the tool's name, net and edits as read by parseTool (script_json_fields.h).
void writeTool(const ScriptOp& op, json& j) {
    if (!op.tool.name.empty()) j["name"] = op.tool.name;
    if (op.tool.volume) j["lattice"] = volumeJson(*op.tool.volume);
    if (!op.netEdits.empty()) j["edits"] = editsJson(op.netEdits);
}

// A change of the lattice list as recorded: the tool after it and its index.
bool recordTool(const Operation& operation, ScriptOp& op) {
    op.tool = operation.toolAfter;
    op.toolIndex = operation.toolIndex;
    return true;
}

// The fields hammer and crimp share: the vertex whose bump is shaped, the control point (or the nearest), and
// the radius of the region.
void readWeightBrush(const json& j, const std::string& path, ScriptOp& op, WeightToolSettings::Tool kind) {
    WeightToolSettings& tool = op.weightTool;
    tool.tool = kind;
    tool.vertex = integer(required(j, "vertex", path), path + ".vertex");
    if (j.contains("control_point")) tool.controlPoint = integer(j["control_point"], path + ".control_point");
    if (j.contains("radius")) {
        tool.radius = number(j["radius"], path + ".radius");
        if (tool.radius < 0.0) fail(path + ".radius", "expected a distance >= 0");
    }
}

void writeWeightBrush(const ScriptOp& op, json& j) {
    j["vertex"] = op.weightTool.vertex;
    if (op.weightTool.controlPoint >= 0) j["control_point"] = op.weightTool.controlPoint;
    if (op.weightTool.radius > 0.0) j["radius"] = op.weightTool.radius;
}

}  // namespace

// Each entry: kind, name, fields; read (the fields into the op), write (the op's fields), run, record.
const std::vector<ScriptOpInfo>& scriptOps() {
    using S = Session;
    using R = OpReport;
    using H = ScreenshotHook;
    static const std::vector<ScriptOpInfo> table = {
        {K::Drag, "drag", {"constraints", "radius", "strength", "falloff", "symmetry", "applied", "cancelled"},
         [](const json& j, const std::string& path, ScriptOp& op) {
             op.constraints = parseConstraints(required(j, "constraints", path), path + ".constraints", false);
             op.brush = parseBrush(j, path);
         },
         [](const ScriptOp& op, json& j) {
             j["constraints"] = constraintsJson(op.constraints);
             addBrushJson(j, op.brush);
         },
         [](S& s, const ScriptOp& op, R& r, const H&) { return s.drag(op.constraints, r, op.brush); },
         [](const Operation& o, ScriptOp& op) {
             if (o.kind != OperationKind::Drag) return false;
             op.constraints = o.constraints;
             op.brush = o.brush;
             return true;
         }},
        {K::DragVertex, "drag_vertex", {"vertex", "target", "radius", "strength", "falloff", "symmetry"},
         [](const json& j, const std::string& path, ScriptOp& op) {
             op.vertex = integer(required(j, "vertex", path), path + ".vertex");
             op.target = vector3(required(j, "target", path), path + ".target");
             op.brush = parseBrush(j, path);
         },
         [](const ScriptOp& op, json& j) {
             j["vertex"] = op.vertex;
             j["target"] = vectorJson(op.target);
             addBrushJson(j, op.brush);
         },
         [](S& s, const ScriptOp& op, R& r, const H&) { return s.dragVertex(op.vertex, op.target, r, op.brush); },
         nullptr},  // recorded as the drag it was
        {K::MoveControlPoint, "move_control_point", {"index", "indices", "to", "by", "applied", "cancelled"},
         [](const json& j, const std::string& path, ScriptOp& op) {
             if (j.contains("to") == j.contains("by")) fail(path, "needs exactly one of \"to\" and \"by\"");
             if (j.contains("index") == j.contains("indices")) fail(path, "needs exactly one of \"index\" and \"indices\"");
             op.relative = j.contains("by");
             const char* valueKey = op.relative ? "by" : "to";
             if (j.contains("index")) {
                 op.controlPoints.push_back(int3(j["index"], path + ".index"));
                 op.values = vector3(j[valueKey], path + "." + valueKey).transpose();
                 return;
             }
             const json& ids = j["indices"];
             if (!ids.is_array() || ids.empty()) fail(path + ".indices", "expected a non-empty array of [i,j,k]");
             for (size_t c = 0; c < ids.size(); ++c) op.controlPoints.push_back(int3(ids[c], path + ".indices[" + std::to_string(c) + "]"));
             const json& values = j[valueKey];
             const std::string vp = path + "." + valueKey;
             op.values.resize(static_cast<Eigen::Index>(ids.size()), 3);
             if (values.is_array() && values.size() == 3 && values[0].is_number()) {
                 // One offset/position for every listed point.
                 const Eigen::Vector3d v = vector3(values, vp);
                 for (Eigen::Index c = 0; c < op.values.rows(); ++c) op.values.row(c) = v.transpose();
                 return;
             }
             if (!values.is_array() || values.size() != ids.size()) fail(vp, "expected one [x,y,z] per index, or a single [x,y,z]");
             for (size_t c = 0; c < ids.size(); ++c)
                 op.values.row(static_cast<Eigen::Index>(c)) = vector3(values[c], vp + "[" + std::to_string(c) + "]").transpose();
         },
         [](const ScriptOp& op, json& j) {
             j["indices"] = op.controlPoints;
             j[op.relative ? "by" : "to"] = rowsJson(op.values);
         },
         [](S& s, const ScriptOp& op, R& r, const H&) {
             std::vector<int> ids;
             if (Status st = controlPointIds(s.lattice(), op.controlPoints, ids); !st) return st;
             return s.moveControlPoints(ids, op.values, op.relative, r);
         },
         [](const Operation& o, ScriptOp& op) {
             if (o.kind != OperationKind::ControlPointEdit) return false;
             op.relative = true;
             op.values = o.offsets;
             const std::array<int, 3> resolution = latticeCounts(o.steps.front().settings);
             for (int idx : o.controlPoints) op.controlPoints.push_back(gridIjk(resolution, idx));
             return true;
         }},
        {K::SetupLattice, "setup_lattice", {"lattice", "applied"},
         [](const json& j, const std::string& path, ScriptOp& op) {
             if (!j.contains("lattice") || j["lattice"].is_null()) return;  // a fresh lattice with the current settings
             op.hasSettings = true;
             op.settings = parseLattice(j["lattice"], path + ".lattice");
         },
         [](const ScriptOp& op, json& j) {
             if (op.hasSettings) j["lattice"] = latticeJson(op.settings);
         },
         [](S& s, const ScriptOp& op, R& r, const H&) { return s.setupLattice(op.hasSettings ? op.settings : s.cage().settings(), r); },
         [](const Operation& o, ScriptOp& op) { return o.frozenAfter < 0 && o.frozenBefore < 0 && recordSetup(o, op); }},
        {K::SetPins, "set_pins", {"pin", "unpin"},
         [](const json& j, const std::string& path, ScriptOp& op) {
             for (const char* key : {"pin", "unpin"}) {
                 if (!j.contains(key)) continue;
                 const json& ids = j[key];
                 const std::string kp = path + "." + key;
                 if (!ids.is_array()) fail(kp, "expected an array of [i,j,k]");
                 auto& list = std::string(key) == "pin" ? op.controlPoints : op.unpinned;
                 for (size_t c = 0; c < ids.size(); ++c) list.push_back(int3(ids[c], kp + "[" + std::to_string(c) + "]"));
             }
         },
         [](const ScriptOp& op, json& j) {
             j["pin"] = op.controlPoints;
             j["unpin"] = op.unpinned;
         },
         runSetPins, nullptr},  // recorded from the journal's pin changes
        {K::BeginGroup, "begin_group", {"label"},
         [](const json& j, const std::string& path, ScriptOp& op) {
             if (j.contains("label")) op.label = text(j["label"], path + ".label");
         },
         [](const ScriptOp& op, json& j) {
             if (!op.label.empty()) j["label"] = op.label;
         },
         nullptr, nullptr},  // runScript keeps the groups
        {K::EndGroup, "end_group", {}, nullptr, nullptr, nullptr, nullptr},
        {K::Group, "group", {"first", "label"},
         [](const json& j, const std::string& path, ScriptOp& op) {
             op.groupFirst = integer(required(j, "first", path), path + ".first");
             if (j.contains("label")) op.label = text(j["label"], path + ".label");
         },
         [](const ScriptOp& op, json& j) {
             j["first"] = op.groupFirst;
             if (!op.label.empty()) j["label"] = op.label;
         },
         [](S& s, const ScriptOp& op, R& r, const H&) { return setting(r, [&] { return s.groupOperations(op.groupFirst, op.label); }); },
         nullptr},  // recorded from the journal's groups
        {K::Refine, "refine", {"tolerance", "applied"},
         [](const json& j, const std::string& path, ScriptOp& op) {
             if (j.contains("tolerance")) op.tolerance = tolerance(j["tolerance"], path + ".tolerance");
         },
         [](const ScriptOp& op, json& j) {
             if (op.tolerance > 0.0) j["tolerance"] = op.tolerance;
         },
         [](S& s, const ScriptOp& op, R& r, const H&) {
             return s.refinement().refine(op.tolerance > 0.0 ? op.tolerance : s.refinement().settings().options.tolerance, r);
         },
         [](const Operation& o, ScriptOp& op) {
             if (o.kind != OperationKind::Refine) return false;
             op.tolerance = o.refinement.tolerance;
             return true;
         }},
        {K::SetRefinement, "set_refinement", {"automatic", "tolerance", "max_rounds", "max_vertices", "under_brush"},
         [](const json& j, const std::string& path, ScriptOp& op) { op.refinement = parseRefinementSettings(j, path); },
         [](const ScriptOp& op, json& j) {
             j["automatic"] = op.refinement.automatic;
             j["tolerance"] = op.refinement.options.tolerance;
             j["max_rounds"] = op.refinement.options.maxRounds;
             j["max_vertices"] = op.refinement.options.maxVertices;
             j["under_brush"] = op.refinement.underBrush;
         },
         [](S& s, const ScriptOp& op, R& r, const H&) { return setting(r, [&] { return s.refinement().set(op.refinement); }); },
         nullptr},  // recorded from the journal's setting changes
        {K::Undo, "undo", {}, nullptr, nullptr, [](S& s, const ScriptOp&, R& r, const H&) { return s.undo(r); }, nullptr},
        {K::Redo, "redo", {}, nullptr, nullptr, [](S& s, const ScriptOp&, R& r, const H&) { return s.redo(r); }, nullptr},
        {K::Screenshot, "screenshot", {"path"},
         [](const json& j, const std::string& path, ScriptOp& op) {
             const json& p = required(j, "path", path);
             if (!p.is_string() || p.get<std::string>().empty()) fail(path + ".path", "expected a file path");
             op.path = p.get<std::string>();
         },
         [](const ScriptOp& op, json& j) { j["path"] = op.path; }, runScreenshot, nullptr},
        // "index" is read only to say that add_lattice takes none.
        {K::AddLattice, "add_lattice", {"name", "lattice", "file", "place", "index"},
         [](const json& j, const std::string& path, ScriptOp& op) {
             if (j.contains("index")) fail(path + ".index", "add_lattice appends to the list; it takes no index");
             op.tool = parseTool(j, path, false);
         },
         [](const ScriptOp& op, json& j) { writeTool(op, j); },
         [](S& s, const ScriptOp& op, R& r, const H&) { return s.tools().add(op.tool, r); },
         [](const Operation& o, ScriptOp& op) { return o.kind == OperationKind::LatticeTools && !o.toolBefore.volume && recordTool(o, op); }},
        {K::EditLattice, "edit_lattice", {"index", "name", "lattice", "file", "place", "edits"},
         [](const json& j, const std::string& path, ScriptOp& op) {
             op.toolIndex = integer(required(j, "index", path), path + ".index");
             if (j.contains("edits")) op.netEdits = parseEdits(j["edits"], path + ".edits");
             op.tool = parseTool(j, path, true);
         },
         [](const ScriptOp& op, json& j) {
             j["index"] = op.toolIndex;
             writeTool(op, j);
         },
         runEditLattice,
         [](const Operation& o, ScriptOp& op) {
             return o.kind == OperationKind::LatticeTools && o.toolBefore.volume && o.toolAfter.volume && recordTool(o, op);
         }},
        {K::RemoveLattice, "remove_lattice", {"index"},
         [](const json& j, const std::string& path, ScriptOp& op) { op.toolIndex = integer(required(j, "index", path), path + ".index"); },
         [](const ScriptOp& op, json& j) { j["index"] = op.toolIndex; },
         [](S& s, const ScriptOp& op, R& r, const H&) { return s.tools().remove(op.toolIndex, r); },
         [](const Operation& o, ScriptOp& op) {
             return o.kind == OperationKind::LatticeTools && o.toolBefore.volume && !o.toolAfter.volume && recordTool(o, op);
         }},
        {K::Freeze, "freeze", {"index", "pin_layers", "applied"},
         [](const json& j, const std::string& path, ScriptOp& op) {
             op.toolIndex = integer(required(j, "index", path), path + ".index");
             if (j.contains("pin_layers")) op.pinLayers = integer(j["pin_layers"], path + ".pin_layers");
             if (op.pinLayers < 0 || op.pinLayers > 3) fail(path + ".pin_layers", "expected 0 to 3");
         },
         [](const ScriptOp& op, json& j) {
             j["index"] = op.toolIndex;
             j["pin_layers"] = op.pinLayers;
         },
         [](S& s, const ScriptOp& op, R& r, const H&) { return s.tools().freeze(op.toolIndex, op.pinLayers, r); },
         [](const Operation& o, ScriptOp& op) {
             if (o.frozenAfter < 0 || !recordSetup(o, op)) return false;  // on another mesh the tool is frozen again
             op.toolIndex = o.frozenAfter;
             op.pinLayers = o.settings.pinLayers;
             return true;
         }},
        {K::Unfreeze, "unfreeze", {"applied"}, nullptr, nullptr,
         [](S& s, const ScriptOp&, R& r, const H&) { return s.tools().unfreeze(r); },
         [](const Operation& o, ScriptOp& op) { return o.frozenAfter < 0 && o.frozenBefore >= 0 && recordSetup(o, op); }},
        // Song & Yang 2005, sec. 4 / sec. 6 steps 1-3 (core::TSplineTools::setup).
        {K::SetupTSpline, "setup_tspline", {"depth", "weight_ratio", "region", "root", "name", "freeze"},
         [](const json& j, const std::string& path, ScriptOp& op) {
             TSplineSetup& setup = op.tspline;
             setup.octree.octree.depth = integer(required(j, "depth", path), path + ".depth");
             if (setup.octree.octree.depth < 1 || setup.octree.octree.depth > kMaxTSplineSetupDepth)
                 fail(path + ".depth", "expected 1 to " + std::to_string(kMaxTSplineSetupDepth) + " levels of octree subdivision");
             if (j.contains("weight_ratio")) {
                 setup.octree.weightRatio = number(j["weight_ratio"], path + ".weight_ratio");
                 if (!(setup.octree.weightRatio > 0.0)) fail(path + ".weight_ratio", "expected a number > 0 (heavy : light weights)");
             }
             if (j.contains("root")) {
                 setup.octree.octree.rootCount = int3(j["root"], path + ".root");
                 for (int a = 0; a < 3; ++a)
                     if (setup.octree.octree.rootCount[a] < 1 || setup.octree.octree.rootCount[a] > kMaxTSplineSetupRootCells)
                         fail(path + ".root[" + std::to_string(a) + "]",
                              "expected 1 to " + std::to_string(kMaxTSplineSetupRootCells) + " root cells");
             }
             if (j.contains("region") && !j["region"].is_null()) {
                 const json& r = j["region"];
                 const std::string rp = path + ".region";
                 allowOnly(r, rp, {"min", "max"});
                 setup.hasRegion = true;
                 setup.regionMin = vector3(required(r, "min", rp), rp + ".min");
                 setup.regionMax = vector3(required(r, "max", rp), rp + ".max");
                 if (!(setup.regionMin.array() < setup.regionMax.array()).all()) fail(rp, "\"min\" must be below \"max\" on every axis");
             }
             if (j.contains("name")) setup.name = text(j["name"], path + ".name");
             if (j.contains("freeze")) setup.freeze = boolean(j["freeze"], path + ".freeze");
         },
         [](const ScriptOp& op, json& j) {
             const TSplineSetup& setup = op.tspline;
             j["depth"] = setup.octree.octree.depth;
             j["weight_ratio"] = setup.octree.weightRatio;
             j["root"] = setup.octree.octree.rootCount;
             if (setup.hasRegion) j["region"] = {{"min", vectorJson(setup.regionMin)}, {"max", vectorJson(setup.regionMax)}};
             if (!setup.name.empty()) j["name"] = setup.name;
             j["freeze"] = setup.freeze;
         },
         [](S& s, const ScriptOp& op, R& r, const H&) { return s.tspline().setup(op.tspline, r); }, nullptr},
        // Song & Yang 2005, sec. 6 step 2 / Fig. 11 (core::TSplineTools::subdivideCells).
        {K::SubdivideCells, "subdivide_cells", {"index", "cells", "at", "balance"},
         [](const json& j, const std::string& path, ScriptOp& op) {
             op.toolIndex = integer(required(j, "index", path), path + ".index");
             if (!j.contains("cells") && !j.contains("at")) fail(path, "needs \"cells\" (cell ids) or \"at\" (points whose cells are subdivided)");
             if (j.contains("cells")) {
                 op.cells = intList(j["cells"], path + ".cells");
                 for (size_t c = 0; c < op.cells.size(); ++c)
                     if (op.cells[c] < 0) fail(path + ".cells[" + std::to_string(c) + "]", "expected a cell id >= 0");
             }
             if (j.contains("at")) {
                 const Eigen::MatrixX3d points = vectorRows(j["at"], path + ".at");
                 for (Eigen::Index p = 0; p < points.rows(); ++p) op.cellPoints.push_back(points.row(p).transpose());
             }
             if (op.cells.empty() && op.cellPoints.empty()) fail(path, "\"cells\" and \"at\" name no cell");
             if (j.contains("balance")) op.balance = boolean(j["balance"], path + ".balance");
         },
         [](const ScriptOp& op, json& j) {
             j["index"] = op.toolIndex;
             if (!op.cells.empty()) j["cells"] = op.cells;
             if (!op.cellPoints.empty()) {
                 json points = json::array();
                 for (const Eigen::Vector3d& p : op.cellPoints) points.push_back(vectorJson(p));
                 j["at"] = points;
             }
             j["balance"] = op.balance;
         },
         [](S& s, const ScriptOp& op, R& r, const H&) { return s.tspline().subdivideCells(op.toolIndex, op.cells, op.cellPoints, op.balance, r); },
         nullptr},
        // Sculpting by weights (Song & Yang 2005 sec. 1 and 6; core::TSplineTools::sculptWeights).
        {K::SetWeights, "set_weights", {"ids", "weights", "applied"},
         [](const json& j, const std::string& path, ScriptOp& op) {
             WeightToolSettings& tool = op.weightTool;
             tool.tool = WeightToolSettings::Tool::SetWeights;
             tool.ids = intList(required(j, "ids", path), path + ".ids");
             tool.weights = numberList(required(j, "weights", path), path + ".weights");
             if (tool.ids.size() != tool.weights.size()) fail(path + ".weights", "expected one weight per id");
             for (size_t c = 0; c < tool.weights.size(); ++c)
                 if (!(tool.weights[c] > 0.0)) fail(path + ".weights[" + std::to_string(c) + "]", "expected a weight > 0");
         },
         [](const ScriptOp& op, json& j) {
             j["ids"] = op.weightTool.ids;
             j["weights"] = op.weightTool.weights;
         },
         runWeightTool, [](const Operation& o, ScriptOp& op) { return recordWeightTool(o, op, WeightToolSettings::Tool::SetWeights); }},
        {K::Hammer, "hammer", {"vertex", "control_point", "radius", "height", "scale", "applied"},
         [](const json& j, const std::string& path, ScriptOp& op) {
             readWeightBrush(j, path, op, WeightToolSettings::Tool::Hammer);
             WeightToolSettings& tool = op.weightTool;
             if (j.contains("height") == j.contains("scale")) fail(path, "needs one of \"height\" (the vertex's height after) or \"scale\" (of the bump)");
             tool.hasHeight = j.contains("height");
             if (tool.hasHeight) tool.height = number(j["height"], path + ".height");
             else tool.scale = number(j["scale"], path + ".scale");
         },
         [](const ScriptOp& op, json& j) {
             writeWeightBrush(op, j);
             if (op.weightTool.hasHeight) j["height"] = op.weightTool.height;
             else j["scale"] = op.weightTool.scale;
         },
         runWeightTool, [](const Operation& o, ScriptOp& op) { return recordWeightTool(o, op, WeightToolSettings::Tool::Hammer); }},
        {K::Crimp, "crimp", {"vertex", "control_point", "radius", "width_factor", "applied"},
         [](const json& j, const std::string& path, ScriptOp& op) {
             readWeightBrush(j, path, op, WeightToolSettings::Tool::Crimp);
             op.weightTool.widthFactor = number(required(j, "width_factor", path), path + ".width_factor");
             if (!(op.weightTool.widthFactor > 0.0)) fail(path + ".width_factor", "expected a factor > 0");
         },
         [](const ScriptOp& op, json& j) {
             writeWeightBrush(op, j);
             j["width_factor"] = op.weightTool.widthFactor;
         },
         runWeightTool, [](const Operation& o, ScriptOp& op) { return recordWeightTool(o, op, WeightToolSettings::Tool::Crimp); }},
    };
    return table;
}

const ScriptOpInfo& scriptOpInfo(ScriptOp::Kind kind) {
    for (const ScriptOpInfo& info : scriptOps())
        if (info.kind == kind) return info;
    static const ScriptOpInfo none{};  // not reached: the table has every kind (tested)
    return none;
}

const ScriptOpInfo* findScriptOp(const std::string& name) {
    for (const ScriptOpInfo& info : scriptOps())
        if (name == info.name) return &info;
    return nullptr;
}

std::string scriptOpNames() {
    std::string names;
    for (const ScriptOpInfo& info : scriptOps()) names += (names.empty() ? "" : ", ") + std::string(info.name);
    return names;
}

}  // namespace sculpt::io
