// Session history: the operation list, undo and redo as inverse manipulations (Hu et al. 2001, section 4;
// design.md "What undo means"), grouping, pins as journal entries, and replaying an operation from the
// journal (recordings).
#include "core/session/session.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "core/injectivity/injectivity.h"
#include "core/session/session_internal.h"

namespace sculpt::core {

using detail::Clock;
using detail::mergeDelta;
using detail::millisecondsSince;
using detail::vectorText;

void Session::pushOperation(Operation operation) {
    // note: pins only change between operations, and fresh frames of the same settings inherit them, so the
    // pins at the end of the operation are the ones every one of its steps was solved with.
    if (operation.kind != OperationKind::LatticeSetup) operation.pinToggles = pins().toggles();
    history_.push(std::move(operation));
}

size_t Session::historyBytes() const {
    auto deltaBytes = [](const ControlDelta& d) {
        return d.indices.capacity() * sizeof(int) + static_cast<size_t>(d.deltas.size()) * sizeof(double);
    };
    auto operationBytes = [&](const Operation& op) {
        size_t bytes = op.label.capacity() + op.constraints.capacity() * sizeof(PointConstraint) + op.controlPoints.capacity() * sizeof(int) +
                       static_cast<size_t>(op.offsets.size()) * sizeof(double) + op.steps.capacity() * sizeof(Step);
        for (const Step& step : op.steps) bytes += deltaBytes(step.delta);
        bytes += op.refinement.splits.capacity() * sizeof(EdgeSplit) + op.refinement.halvings.capacity() * sizeof(TriangleHalving);
        return bytes;
    };
    size_t bytes = history_.entries().capacity() * sizeof(Operation) + stack_.frames_.capacity() * sizeof(FrozenFrame) +
                   history_.journal().capacity() * sizeof(JournalEntry);
    for (const Operation& op : history_.entries()) bytes += operationBytes(op);
    for (const JournalEntry& entry : history_.journal()) bytes += operationBytes(entry.operation) + entry.pinToggles.capacity() * sizeof(int);
    for (const FrozenFrame& frame : stack_.frames_) bytes += deltaBytes(frame.displacement) + frame.pinToggles.capacity() * sizeof(int);
    return bytes;
}

void Session::undoSteps(const std::vector<Step>& steps) {
    // A step in a layer of its own (a fresh frame): the layer and everything it did go, and the layers below give
    // the positions. A run of them (an adaptive subdivision's sub-steps) goes at once.
    const auto isLayer = [](const Step& step) { return step.weights.empty() && step.freshFrame; };
    for (size_t i = steps.size(); i-- > 0;) {
        const Step& step = steps[i];
        if (step.baked) unbakeLayers(steps, i);  // the layers it put into the rest shape come back first
        if (isLayer(step)) {
            size_t run = 1;  // steps[i - run + 1 .. i] are layers, popped together (not across another bake)
            while (run <= i && isLayer(steps[i - run]) && !steps[i - run].baked) ++run;
            popLayers(run, &lastMoved_.vertices);
            i -= run - 1;
            continue;
        }
        stack_.layerActive_ = false;
        if (!step.weights.empty()) {  // a weight change (and the displacement with it) in the cage
            tspline().revertStep(step, &lastMoved_.vertices);
            continue;
        }
        applyDelta(step.delta, -1.0, &lastMoved_.vertices);  // the inverse manipulation in the cage (omega(S, -rho))
        if (step.newCage) leaveCage();              // inverse of the frozen cage's injective FFD
    }
}

void Session::revertSteps(const std::vector<Step>& steps) {
    lastMoved_.vertices.clear();
    lastMoved_.all = false;
    undoSteps(steps);
}

void Session::countChangedVertices(const Positions& before, OpReport& report) {
    // The vertices whose positions differ, among the rows both have: undo and redo of one operation report the
    // same count, never more than the mesh has, and an undo that leaves a frame (a lattice set-up taken back)
    // counts the vertices it moved, not every vertex. Rows a refinement added or removed are counted apart
    // (report.verticesAdded, report.verticesRemoved), the same both ways too.
    const Eigen::Index common = std::min(before.rows(), mesh_.positions.rows());
    std::vector<int> changed;
    for (Eigen::Index v = 0; v < common; ++v)
        if (mesh_.positions.row(v) != before.row(v)) changed.push_back(static_cast<int>(v));
    const int moved = static_cast<int>(changed.size());
    for (Eigen::Index v = common; v < mesh_.positions.rows(); ++v) changed.push_back(static_cast<int>(v));  // to redraw
    report.verticesMoved = moved;
    report.verticesAdded = static_cast<int>(mesh_.positions.rows() - common);
    report.verticesRemoved = static_cast<int>(before.rows() - common);
    if (!lastMoved_.all) lastMoved_.vertices = std::move(changed);
}

int Session::movedCount() const {
    return lastMoved_.all ? static_cast<int>(mesh_.positions.rows()) : static_cast<int>(lastMoved_.vertices.size());
}

void Session::redoStep(const Step& step) {
    if (!step.weights.empty()) {
        stack_.layerActive_ = false;
        tspline().applyStep(step, &lastMoved_.vertices);
        return;
    }
    if (step.newCage) enterNewCage(step.settings, nullptr, &step);
    else if (step.freshFrame) enterLayer(nullptr, nullptr, &step);
    else stack_.layerActive_ = false;  // a step without a lattice of its own is in the cage
    applyDelta(step.delta, 1.0, &lastMoved_.vertices);
}

void Session::bakeAfter(const Step& step) {
    if (!step.baked) return;
    stack_.layerActive_ = false;
    bakeAllLayers(&step.bakedOutside);
}

void Session::bakeLastStep(const Operation& operation) {
    if (!operation.steps.empty()) bakeAfter(operation.steps.back());
}

void Session::undoOperationBody(const Operation& operation) {
    if (!operation.parts.empty()) {
        for (auto part = operation.parts.rbegin(); part != operation.parts.rend(); ++part) undoOperationBody(*part);
        return;
    }
    stack_.layerActive_ = false;
    undoSteps(operation.steps);
    if (operation.kind == OperationKind::LatticeTools) tools().applyChange(operation, false);
    if (operation.kind == OperationKind::LatticeTools || operation.kind == OperationKind::LatticeSetup) tools_.frozen = operation.frozenBefore;
}

void Session::redoOperationBody(const Operation& operation) {
    for (const Operation& part : operation.parts) {
        redoOperationBody(part);
        bakeLastStep(part);
    }
    // A step baked within the operation (a group's) is baked again where it was; the last one after the
    // refinement (redo, replay), as the operation did it.
    for (size_t k = 0; k < operation.steps.size(); ++k) {
        redoStep(operation.steps[k]);
        if (k + 1 < operation.steps.size()) bakeAfter(operation.steps[k]);
    }
    if (operation.parts.empty() && operation.kind == OperationKind::LatticeTools) tools().applyChange(operation, true);
    if (operation.parts.empty() && (operation.kind == OperationKind::LatticeTools || operation.kind == OperationKind::LatticeSetup))
        tools_.frozen = operation.frozenAfter;
    stack_.layerActive_ = false;
}

Status Session::groupOperations(int first, const std::string& label) {
    if (drag_.active) return Status::error("an interactive drag is in progress");
    if (!history_.atEnd()) return Status::error("a group must end at the last operation");
    const int cursor = history_.cursor();
    if (first < 0 || first > cursor) return Status::error("the group's first operation is outside the history");
    if (cursor == first) return Status::success();  // an empty group
    if (Status s = refinement().checkGroup(first); !s) return s;
    bool keepWhole = false;  // tools added, removed or edited, or the frozen one changed: see Operation::parts
    for (int i = first; i < cursor; ++i) {
        const Operation& op = history_.entry(i);
        keepWhole = keepWhole || op.kind == OperationKind::LatticeTools || !op.parts.empty() ||
                    (op.kind == OperationKind::LatticeSetup && op.frozenBefore != op.frozenAfter);
    }
    Operation merged;
    if (keepWhole) {
        merged.kind = OperationKind::LatticeTools;
        merged.frozenBefore = history_.entry(first).frozenBefore;
        merged.frozenAfter = tools_.frozen;
        merged.label = label.empty() ? history_.entry(first).label : label;
    } else {
        merged.kind = OperationKind::LatticeSetup;
        const Operation* firstEdit = nullptr;
        const Operation* lastEdit = nullptr;
        for (int i = first; i < cursor; ++i) {
            const Operation& op = history_.entry(i);
            if (op.kind == OperationKind::LatticeSetup || op.kind == OperationKind::Refine) continue;
            if (firstEdit && op.kind != firstEdit->kind) return Status::error("a group mixes drags and control-point edits");
            if (!firstEdit) firstEdit = &op;
            lastEdit = &op;
        }
        if (firstEdit) {
            merged.kind = firstEdit->kind;
            merged.pinToggles = firstEdit->pinToggles;
            merged.controlPoints = firstEdit->controlPoints;
            merged.offsets = firstEdit->offsets;
            merged.constraints = firstEdit->constraints;
            merged.weightTool = firstEdit->weightTool;
            // From where the first edit took its sources to where the last one put them.
            if (lastEdit->constraints.size() == merged.constraints.size())
                for (size_t c = 0; c < merged.constraints.size(); ++c) merged.constraints[c].target = lastEdit->constraints[c].target;
        } else {
            merged.settings = history_.entry(cursor - 1).settings;
            if (history_.entry(cursor - 1).kind == OperationKind::Refine) merged.kind = OperationKind::Refine;
        }
        merged.interactive = true;
        merged.label = label.empty() ? (firstEdit ? firstEdit->label : history_.entry(first).label) : label;
    }
    // A stroke refined under its pull splits its triangles before its steps: only the group's first operation can
    // (redo splits them before the whole group, undo removes them after it).
    merged.refinementBefore = std::move(history_.entry(first).refinementBefore);
    history_.entry(first).refinementBefore = RefinementRecord{};
    for (int i = first; i < cursor; ++i) {
        Operation& op = history_.entry(i);
        merged.depthReached = std::max(merged.depthReached, op.depthReached);
        // The refinements, in order, are one sequence of splits (undone before the steps, redone after them).
        for (const EdgeSplit& split : op.refinement.splits) merged.refinement.splits.push_back(split);
        for (const TriangleHalving& halving : op.refinement.halvings) merged.refinement.halvings.push_back(halving);
        if (!op.refinement.empty()) merged.refinement.tolerance = op.refinement.tolerance;
        if (keepWhole) {
            op.refinement = RefinementRecord{};
            merged.parts.push_back(std::move(op));
            continue;
        }
        for (Step& step : op.steps) {
            // A fresh frame that moved nothing followed by a step in it is one step, as the interactive
            // operation that was recorded had it (same undo: the delta, then leaving the frame).
            if (!merged.steps.empty() && merged.steps.back().newCage && merged.steps.back().delta.indices.empty() &&
                !step.freshFrame && !step.newCage && step.weights.empty()) {
                Step& combined = merged.steps.back();
                combined.delta = std::move(step.delta);
                combined.constraints = std::move(step.constraints);
                continue;
            }
            merged.steps.push_back(std::move(step));
        }
    }
    history_.replaceTail(first, std::move(merged));
    return Status::success();
}

Status Session::undo(OpReport& report) {
    const auto start = Clock::now();
    report = OpReport{};
    report.op = "undo";
    if (drag_.active) return Status::error("an interactive drag is in progress");
    if (history_.cursor() == 0) {
        report.status = OpStatus::NoOp;
        report.reason = "nothing to undo";
        return Status::success();
    }
    const Operation& operation = history_.stepBack();
    lastMoved_.vertices.clear();
    lastMoved_.all = false;
    const Positions before = mesh_.positions;  // to count what changed (not kept: the history holds no mesh)
    undoOperationBody(operation);
    refinement().remove(operation.refinement);
    refinement().remove(operation.refinementBefore);  // split when the stroke began: removed last
    countChangedVertices(before, report);
    report.status = OpStatus::Applied;
    report.reason = "undid " + operation.label;
    report.subSteps = operation.injectiveSteps();
    report.controlPointsChanged = 0;
    for (const Step& step : operation.steps) report.controlPointsChanged += static_cast<int>(step.delta.indices.size());
    report.wallMs = millisecondsSince(start);
    return Status::success();
}

Status Session::redo(OpReport& report) {
    const auto start = Clock::now();
    report = OpReport{};
    report.op = "redo";
    if (drag_.active) return Status::error("an interactive drag is in progress");
    if (history_.atEnd()) {
        report.status = OpStatus::NoOp;
        report.reason = "nothing to redo";
        return Status::success();
    }
    const Operation& operation = history_.stepForward();
    lastMoved_.vertices.clear();
    lastMoved_.all = false;
    const Positions before = mesh_.positions;
    Operation& entry = history_.entry(history_.cursor() - 1);  // `operation`, to fill its records' halvings again
    if (!entry.refinementBefore.empty()) refinement().apply(entry.refinementBefore);  // as the stroke began
    redoOperationBody(operation);
    refinement().reapply(entry);
    bakeLastStep(operation);
    countChangedVertices(before, report);
    report.status = OpStatus::Applied;
    report.reason = "redid " + operation.label;
    report.subSteps = operation.injectiveSteps();
    for (const Step& step : operation.steps) report.controlPointsChanged += static_cast<int>(step.delta.indices.size());
    report.wallMs = millisecondsSince(start);
    return Status::success();
}

Status Session::replayOperation(const Operation& operation, bool cancelled, OpReport& report) {
    const auto start = Clock::now();
    report = OpReport{};
    report.op = "replay";
    if (mesh_.empty()) return Status::error("no mesh is loaded");
    if (drag_.active) return Status::error("an interactive drag is in progress");
    if (operation.steps.empty() && operation.kind != OperationKind::Refine) return Status::error("the recorded operation has no steps");
    if (Status s = refinement().checkRecorded(operation, cancelled); !s) return s;
    // Every step must fit the lattice it will be applied in: its own where it makes one (a layer or a new
    // cage), else the cage.
    LatticeSettings cageSettings = stack_.settings_;
    for (size_t k = 0; k < operation.steps.size(); ++k) {
        const Step& step = operation.steps[k];
        LatticeSettings settings = cageSettings;
        if (step.freshFrame || step.newCage) {
            if (Status s = validateLatticeSettings(step.settings); !s) return Status::error("step " + std::to_string(k) + ": " + s.message);
            if (!step.frameMin.allFinite() || !step.frameMax.allFinite() || !(step.frameMin.array() < step.frameMax.array()).all())
                return Status::error("step " + std::to_string(k) + ": the lattice box must be finite with min < max on every axis");
            if (Lattice probe; !turnBoxLattice(probe, step.frameAxes))
                return Status::error("step " + std::to_string(k) + ": a layer's box axes must be orthonormal and right-handed");
            settings = step.settings;
            if (step.newCage) cageSettings = step.settings;
        }
        const std::array<int, 3> counts = latticeCounts(settings);
        const int count = counts[0] * counts[1] * counts[2];
        for (int idx : step.regionFree)
            if (idx < 0 || idx >= count) return Status::error("step " + std::to_string(k) + ": free control point id " + std::to_string(idx) + " is outside the lattice");
        if (static_cast<Eigen::Index>(step.delta.indices.size()) != step.delta.deltas.rows())
            return Status::error("step " + std::to_string(k) + ": control point ids and displacements differ in count");
        for (int idx : step.delta.indices)
            if (idx < 0 || idx >= count) return Status::error("step " + std::to_string(k) + ": control point id " + std::to_string(idx) + " is outside the lattice");
        if (!step.delta.deltas.allFinite()) return Status::error("step " + std::to_string(k) + ": non-finite displacement");
        if (!step.weights.empty())
            if (Status s = tspline().checkRecordedWeights(step.weights); !s) return Status::error("step " + std::to_string(k) + ": " + s.message);
    }
    lastMoved_.vertices.clear();
    lastMoved_.all = false;
    RefinementRecord refinedBefore = operation.refinementBefore;  // split as the stroke began (fills its halvings)
    if (!refinedBefore.empty()) refinement().apply(refinedBefore);
    for (size_t k = 0; k < operation.steps.size(); ++k) {
        redoStep(operation.steps[k]);
        if (k + 1 < operation.steps.size() && !cancelled) bakeAfter(operation.steps[k]);
    }
    if (operation.kind == OperationKind::LatticeSetup && !cancelled) tools_.frozen = operation.frozenAfter;
    stack_.layerActive_ = false;
    report.status = OpStatus::Applied;
    report.subSteps = operation.injectiveSteps();
    report.depthReached = operation.depthReached;
    report.injectivity = "as recorded";
    for (const Step& step : operation.steps) report.controlPointsChanged += static_cast<int>(step.delta.indices.size());
    if (cancelled) {
        revertSteps(operation.steps);
        refinement().remove(refinedBefore);
        history_.note(JournalEntry{JournalEntry::Kind::CancelledDrag, operation, 0, {}, {}, {}}, false);
        report.reason = "replayed the steps of a drag that was taken back, and took them back";
    } else {
        pushOperation(operation);
        history_.last().refinementBefore = std::move(refinedBefore);
        refinement().reapply(history_.last());
        bakeLastStep(history_.last());
        report.reason = "replayed " + operation.label + " as recorded (" + std::to_string(report.subSteps) + " steps)";
    }
    report.verticesMoved = movedCount();
    report.wallMs = millisecondsSince(start);
    return Status::success();
}

}  // namespace sculpt::core
