#include "core/session/script.h"
#include "core/session/script_ops.h"

#include <algorithm>
#include <chrono>

namespace sculpt::core {

const std::vector<ScriptOpInfo>& scriptOps() {
    using K = ScriptOp::Kind;
    static const std::vector<ScriptOpInfo> table = {
        {K::Drag, "drag", {"constraints", "radius", "strength", "falloff", "symmetry", "applied", "cancelled"}},
        {K::DragVertex, "drag_vertex", {"vertex", "target", "radius", "strength", "falloff", "symmetry"}},
        {K::MoveControlPoint, "move_control_point", {"index", "indices", "to", "by", "applied", "cancelled"}},
        {K::SetupLattice, "setup_lattice", {"lattice", "applied"}},
        {K::SetPins, "set_pins", {"pin", "unpin"}},
        {K::BeginGroup, "begin_group", {"label"}},
        {K::EndGroup, "end_group", {}},
        {K::Group, "group", {"first", "label"}},
        {K::Refine, "refine", {"tolerance", "applied"}},
        {K::SetRefinement, "set_refinement", {"automatic", "tolerance", "max_rounds", "max_vertices"}},
        {K::Undo, "undo", {}},
        {K::Redo, "redo", {}},
        {K::Screenshot, "screenshot", {"path"}},
        // "index" is read only to say that add_lattice takes none.
        {K::AddLattice, "add_lattice", {"name", "lattice", "file", "place", "index"}},
        {K::EditLattice, "edit_lattice", {"index", "name", "lattice", "file", "place", "edits"}},
        {K::RemoveLattice, "remove_lattice", {"index"}},
        {K::Freeze, "freeze", {"index", "pin_layers", "applied"}},
        {K::Unfreeze, "unfreeze", {"applied"}},
        {K::SetupTSpline, "setup_tspline", {"depth", "weight_ratio", "region", "root", "name", "freeze"}},
        {K::SubdivideCells, "subdivide_cells", {"index", "cells", "at", "balance"}},
        {K::SetWeights, "set_weights", {"ids", "weights", "applied"}},
        {K::Hammer, "hammer", {"vertex", "control_point", "radius", "height", "scale", "applied"}},
        {K::Crimp, "crimp", {"vertex", "control_point", "radius", "width_factor", "applied"}},
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

const char* scriptOpName(ScriptOp::Kind kind) {
    const char* name = scriptOpInfo(kind).name;
    return *name ? name : "?";
}

namespace {

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

Status runOp(Session& session, const ScriptOp& op, OpReport& report, const ScreenshotHook& screenshot, bool exact) {
    // A recording on the mesh it was made on: repeat what was applied, decide nothing again.
    if (op.hasApplied && exact) return session.replayOperation(op.applied, op.cancelled, report);
    if (op.cancelled) {
        report = OpReport{};
        report.status = OpStatus::NoOp;
        report.reason = "a drag that was taken back";
        return Status::success();
    }
    switch (op.kind) {
        case ScriptOp::Kind::Drag: return session.drag(op.constraints, report, op.brush);
        case ScriptOp::Kind::DragVertex: return session.dragVertex(op.vertex, op.target, report, op.brush);
        case ScriptOp::Kind::MoveControlPoint: {
            std::vector<int> ids;
            if (Status s = controlPointIds(session.lattice(), op.controlPoints, ids); !s) return s;
            return session.moveControlPoints(ids, op.values, op.relative, report);
        }
        case ScriptOp::Kind::SetPins: {
            report = OpReport{};
            report.op = "set_pins";
            const Lattice& lattice = session.lattice();
            std::vector<int> pin, unpin;
            if (Status s = controlPointIds(lattice, op.controlPoints, pin); !s) return s;
            if (Status s = controlPointIds(lattice, op.unpinned, unpin); !s) return s;
            const int layers = session.latticeSettings().pinLayers;
            for (int idx : pin)
                if (inOuterLayers(lattice, idx, layers)) return Status::error("\"pin\" lists a control point the pin layers already pin");
            for (int idx : unpin)
                if (!inOuterLayers(lattice, idx, layers)) return Status::error("\"unpin\" lists a control point outside the pin layers");
            pin.insert(pin.end(), unpin.begin(), unpin.end());
            std::sort(pin.begin(), pin.end());
            pin.erase(std::unique(pin.begin(), pin.end()), pin.end());
            if (Status s = session.setPinToggles(pin); !s) return s;
            report.status = OpStatus::Applied;
            return Status::success();
        }
        case ScriptOp::Kind::SetupLattice:
            return session.setupLattice(op.hasSettings ? op.settings : session.latticeSettings(), report);
        case ScriptOp::Kind::BeginGroup:
        case ScriptOp::Kind::EndGroup: break;  // runScript keeps the groups
        case ScriptOp::Kind::Group:
            report = OpReport{};
            if (Status s = session.groupOperations(op.groupFirst, op.label); !s) return s;
            report.status = OpStatus::Applied;
            return Status::success();
        case ScriptOp::Kind::Refine:
            return session.refine(op.tolerance > 0.0 ? op.tolerance : session.refinement().options.tolerance, report);
        case ScriptOp::Kind::SetRefinement:
            report = OpReport{};
            if (Status s = session.setRefinement(op.refinement); !s) return s;
            report.status = OpStatus::Applied;
            return Status::success();
        case ScriptOp::Kind::Undo: return session.undo(report);
        case ScriptOp::Kind::Redo: return session.redo(report);
        case ScriptOp::Kind::AddLattice: return session.addLatticeTool(op.tool, report);
        case ScriptOp::Kind::EditLattice: {
            const std::vector<LatticeTool>& tools = session.latticeTools();
            if (op.toolIndex < 0 || op.toolIndex >= static_cast<int>(tools.size()) || op.toolIndex == session.frozenTool())
                return session.editLatticeTool(op.toolIndex, op.tool, report);  // refused there, with the reason
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
            return session.editLatticeTool(op.toolIndex, tool, report);
        }
        case ScriptOp::Kind::RemoveLattice: return session.removeLatticeTool(op.toolIndex, report);
        case ScriptOp::Kind::Freeze: return session.freezeLattice(op.toolIndex, op.pinLayers, report);
        case ScriptOp::Kind::Unfreeze: return session.unfreezeLattice(report);
        case ScriptOp::Kind::SetupTSpline: return session.setupTSpline(op.tspline, report);
        case ScriptOp::Kind::SubdivideCells: return session.subdivideTSplineCells(op.toolIndex, op.cells, op.cellPoints, op.balance, report);
        case ScriptOp::Kind::SetWeights:
        case ScriptOp::Kind::Hammer:
        case ScriptOp::Kind::Crimp: {
            WeightToolSettings settings = op.weightTool;
            settings.tool = op.kind == ScriptOp::Kind::SetWeights ? WeightToolSettings::Tool::SetWeights
                            : op.kind == ScriptOp::Kind::Hammer   ? WeightToolSettings::Tool::Hammer
                                                                  : WeightToolSettings::Tool::Crimp;
            return session.sculptWeights(settings, report);
        }
        case ScriptOp::Kind::Screenshot: {
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
    }
    return Status::error("unknown op");
}

// The op a user would write for an operation (what a replay on another mesh decides again), with the steps it
// was applied as.
ScriptOp recordedOp(const Operation& operation) {
    ScriptOp op;
    switch (operation.kind) {
        case OperationKind::Drag:
            op.kind = ScriptOp::Kind::Drag;
            op.constraints = operation.constraints;
            op.brush = operation.brush;
            break;
        case OperationKind::ControlPointEdit: {
            op.kind = ScriptOp::Kind::MoveControlPoint;
            op.relative = true;
            op.values = operation.offsets;
            const std::array<int, 3> resolution = latticeCounts(operation.steps.front().settings);
            for (int idx : operation.controlPoints) op.controlPoints.push_back(gridIjk(resolution, idx));
            break;
        }
        case OperationKind::LatticeSetup:
            op.kind = ScriptOp::Kind::SetupLattice;
            op.hasSettings = true;
            op.settings = operation.settings;
            if (operation.frozenAfter >= 0) {  // a freeze: on another mesh the tool is frozen again
                op.kind = ScriptOp::Kind::Freeze;
                op.toolIndex = operation.frozenAfter;
                op.pinLayers = operation.settings.pinLayers;
            } else if (operation.frozenBefore >= 0) {
                op.kind = ScriptOp::Kind::Unfreeze;
            }
            break;
        case OperationKind::Refine:
            op.kind = ScriptOp::Kind::Refine;
            op.tolerance = operation.refinement.tolerance;
            break;
        case OperationKind::WeightEdit:
            op.weightTool = operation.weightTool;
            op.kind = operation.weightTool.tool == WeightToolSettings::Tool::SetWeights ? ScriptOp::Kind::SetWeights
                      : operation.weightTool.tool == WeightToolSettings::Tool::Hammer   ? ScriptOp::Kind::Hammer
                                                                                        : ScriptOp::Kind::Crimp;
            break;
        case OperationKind::LatticeTools:
            // The list changes repeat as they were (they do not depend on the mesh).
            op.tool = operation.toolAfter;
            op.toolIndex = operation.toolIndex;
            op.kind = !operation.toolBefore.volume ? ScriptOp::Kind::AddLattice
                                                : (!operation.toolAfter.volume ? ScriptOp::Kind::RemoveLattice : ScriptOp::Kind::EditLattice);
            return op;
    }
    op.hasApplied = true;
    op.applied = operation;
    return op;
}

}  // namespace

Status runScriptOp(Session& session, const ScriptOp& op, OpReport& report) { return runOp(session, op, report, {}, false); }

Status runScript(Session& session, const Script& script, ScriptReport& report, const ScreenshotHook& screenshot,
                 const ScriptProgress& progress) {
    report.ops.clear();
    const bool exact = !script.meshFingerprint.empty() && script.meshFingerprint == session.meshFingerprint();
    std::vector<std::pair<int, std::string>> groups;  // open begin_group ops: history cursor and label
    for (size_t i = 0; i < script.ops.size(); ++i) {
        if (progress && !progress(i, script.ops.size())) return Status::error("stopped before op " + std::to_string(i));
        const ScriptOp& op = script.ops[i];
        OpReport opReport;
        Status s = Status::success();
        if (op.kind == ScriptOp::Kind::BeginGroup) {
            groups.emplace_back(session.historyCursor(), op.label);
            opReport.status = OpStatus::Applied;
        } else if (op.kind == ScriptOp::Kind::EndGroup) {
            if (groups.empty()) {
                s = Status::error("end_group without a begin_group");
            } else {
                s = session.groupOperations(groups.back().first, groups.back().second);
                opReport.status = OpStatus::Applied;
                opReport.reason = "the ops since begin_group are one history entry";
                groups.pop_back();
            }
        } else {
            s = runOp(session, op, opReport, screenshot, exact);
        }
        if (!s) return Status::error("op " + std::to_string(i) + " (" + scriptOpName(op.kind) + "): " + s.message);
        opReport.op = scriptOpName(op.kind);
        report.ops.push_back(std::move(opReport));
    }
    if (!groups.empty()) return Status::error("begin_group without an end_group");
    if (progress) progress(script.ops.size(), script.ops.size());
    return Status::success();
}

Script recordSession(const Session& session) {
    Script script;
    script.lattice = session.initialSettings();
    script.lattice.hasRegion = true;
    script.lattice.regionMin = session.initialBoxMin();
    script.lattice.regionMax = session.initialBoxMax();
    script.lattice.padding = 0.0;
    script.injectivity = session.injectivity();
    script.meshFingerprint = session.meshFingerprint();
    for (const JournalEntry& entry : session.journal()) {
        ScriptOp op;
        switch (entry.kind) {
            case JournalEntry::Kind::Operation: op = recordedOp(entry.operation); break;
            case JournalEntry::Kind::CancelledDrag:
                op = recordedOp(entry.operation);
                op.cancelled = true;
                break;
            case JournalEntry::Kind::Undo: op.kind = ScriptOp::Kind::Undo; break;
            case JournalEntry::Kind::Redo: op.kind = ScriptOp::Kind::Redo; break;
            case JournalEntry::Kind::Group:
                op.kind = ScriptOp::Kind::Group;
                op.groupFirst = entry.groupFirst;
                op.label = entry.label;
                break;
            case JournalEntry::Kind::Pins:
                // The user's pins shape the solution (pinned points are removed from R, Hu et al. eq. 12).
                op.kind = ScriptOp::Kind::SetPins;
                for (int idx : entry.pinToggles) {
                    const std::array<int, 3> ijk = gridIjk(latticeCounts(entry.settings), idx);
                    (inPinLayers(entry.settings, idx) ? op.unpinned : op.controlPoints).push_back(ijk);
                }
                break;
            case JournalEntry::Kind::Refinement:
                op.kind = ScriptOp::Kind::SetRefinement;
                op.refinement = entry.refinement;
                break;
        }
        script.ops.push_back(std::move(op));
    }
    return script;
}

}  // namespace sculpt::core
