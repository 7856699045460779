// The table of script ops (script_ops.h): per op its name, its JSON fields, how it runs on a session and which
// history entries it records.
#include "core/session/script_ops.h"

#include <algorithm>
#include <chrono>

namespace sculpt::core {

namespace {

using K = ScriptOp::Kind;

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

}  // namespace

const std::vector<ScriptOpInfo>& scriptOps() {
    using S = Session;
    static const std::vector<ScriptOpInfo> table = {
        {K::Drag, "drag", {"constraints", "radius", "strength", "falloff", "symmetry", "applied", "cancelled"},
         [](S& s, const ScriptOp& op, OpReport& r, const ScreenshotHook&) { return s.drag(op.constraints, r, op.brush); },
         [](const Operation& o, ScriptOp& op) {
             if (o.kind != OperationKind::Drag) return false;
             op.constraints = o.constraints;
             op.brush = o.brush;
             return true;
         }},
        {K::DragVertex, "drag_vertex", {"vertex", "target", "radius", "strength", "falloff", "symmetry"},
         [](S& s, const ScriptOp& op, OpReport& r, const ScreenshotHook&) { return s.dragVertex(op.vertex, op.target, r, op.brush); }, nullptr},
        {K::MoveControlPoint, "move_control_point", {"index", "indices", "to", "by", "applied", "cancelled"},
         [](S& s, const ScriptOp& op, OpReport& r, const ScreenshotHook&) {
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
         [](S& s, const ScriptOp& op, OpReport& r, const ScreenshotHook&) {
             return s.setupLattice(op.hasSettings ? op.settings : s.cage().settings(), r);
         },
         [](const Operation& o, ScriptOp& op) { return o.frozenAfter < 0 && o.frozenBefore < 0 && recordSetup(o, op); }},
        {K::SetPins, "set_pins", {"pin", "unpin"}, runSetPins, nullptr},  // recorded from the journal's pin changes
        {K::BeginGroup, "begin_group", {"label"}, nullptr, nullptr},     // runScript keeps the groups
        {K::EndGroup, "end_group", {}, nullptr, nullptr},
        {K::Group, "group", {"first", "label"},
         [](S& s, const ScriptOp& op, OpReport& r, const ScreenshotHook&) { return setting(r, [&] { return s.groupOperations(op.groupFirst, op.label); }); },
         nullptr},  // recorded from the journal's groups
        {K::Refine, "refine", {"tolerance", "applied"},
         [](S& s, const ScriptOp& op, OpReport& r, const ScreenshotHook&) {
             return s.refinement().refine(op.tolerance > 0.0 ? op.tolerance : s.refinement().settings().options.tolerance, r);
         },
         [](const Operation& o, ScriptOp& op) {
             if (o.kind != OperationKind::Refine) return false;
             op.tolerance = o.refinement.tolerance;
             return true;
         }},
        {K::SetRefinement, "set_refinement", {"automatic", "tolerance", "max_rounds", "max_vertices"},
         [](S& s, const ScriptOp& op, OpReport& r, const ScreenshotHook&) { return setting(r, [&] { return s.refinement().set(op.refinement); }); },
         nullptr},  // recorded from the journal's setting changes
        {K::Undo, "undo", {}, [](S& s, const ScriptOp&, OpReport& r, const ScreenshotHook&) { return s.undo(r); }, nullptr},
        {K::Redo, "redo", {}, [](S& s, const ScriptOp&, OpReport& r, const ScreenshotHook&) { return s.redo(r); }, nullptr},
        {K::Screenshot, "screenshot", {"path"}, runScreenshot, nullptr},
        // "index" is read only to say that add_lattice takes none.
        {K::AddLattice, "add_lattice", {"name", "lattice", "file", "place", "index"},
         [](S& s, const ScriptOp& op, OpReport& r, const ScreenshotHook&) { return s.tools().add(op.tool, r); },
         [](const Operation& o, ScriptOp& op) {
             if (o.kind != OperationKind::LatticeTools || o.toolBefore.volume) return false;
             op.tool = o.toolAfter;
             op.toolIndex = o.toolIndex;
             return true;
         }},
        {K::EditLattice, "edit_lattice", {"index", "name", "lattice", "file", "place", "edits"}, runEditLattice,
         [](const Operation& o, ScriptOp& op) {
             if (o.kind != OperationKind::LatticeTools || !o.toolBefore.volume || !o.toolAfter.volume) return false;
             op.tool = o.toolAfter;
             op.toolIndex = o.toolIndex;
             return true;
         }},
        {K::RemoveLattice, "remove_lattice", {"index"},
         [](S& s, const ScriptOp& op, OpReport& r, const ScreenshotHook&) { return s.tools().remove(op.toolIndex, r); },
         [](const Operation& o, ScriptOp& op) {
             if (o.kind != OperationKind::LatticeTools || !o.toolBefore.volume || o.toolAfter.volume) return false;
             op.tool = o.toolAfter;
             op.toolIndex = o.toolIndex;
             return true;
         }},
        {K::Freeze, "freeze", {"index", "pin_layers", "applied"},
         [](S& s, const ScriptOp& op, OpReport& r, const ScreenshotHook&) { return s.tools().freeze(op.toolIndex, op.pinLayers, r); },
         [](const Operation& o, ScriptOp& op) {
             if (o.frozenAfter < 0 || !recordSetup(o, op)) return false;  // on another mesh the tool is frozen again
             op.toolIndex = o.frozenAfter;
             op.pinLayers = o.settings.pinLayers;
             return true;
         }},
        {K::Unfreeze, "unfreeze", {"applied"},
         [](S& s, const ScriptOp&, OpReport& r, const ScreenshotHook&) { return s.tools().unfreeze(r); },
         [](const Operation& o, ScriptOp& op) { return o.frozenAfter < 0 && o.frozenBefore >= 0 && recordSetup(o, op); }},
        {K::SetupTSpline, "setup_tspline", {"depth", "weight_ratio", "region", "root", "name", "freeze"},
         [](S& s, const ScriptOp& op, OpReport& r, const ScreenshotHook&) { return s.tspline().setup(op.tspline, r); }, nullptr},
        {K::SubdivideCells, "subdivide_cells", {"index", "cells", "at", "balance"},
         [](S& s, const ScriptOp& op, OpReport& r, const ScreenshotHook&) {
             return s.tspline().subdivideCells(op.toolIndex, op.cells, op.cellPoints, op.balance, r);
         },
         nullptr},
        {K::SetWeights, "set_weights", {"ids", "weights", "applied"}, runWeightTool,
         [](const Operation& o, ScriptOp& op) { return recordWeightTool(o, op, WeightToolSettings::Tool::SetWeights); }},
        {K::Hammer, "hammer", {"vertex", "control_point", "radius", "height", "scale", "applied"}, runWeightTool,
         [](const Operation& o, ScriptOp& op) { return recordWeightTool(o, op, WeightToolSettings::Tool::Hammer); }},
        {K::Crimp, "crimp", {"vertex", "control_point", "radius", "width_factor", "applied"}, runWeightTool,
         [](const Operation& o, ScriptOp& op) { return recordWeightTool(o, op, WeightToolSettings::Tool::Crimp); }},
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

}  // namespace sculpt::core
