// The script runner and recorder (script.h): each op runs, and each history entry is recorded, through its entry
// in the op table (script_ops.h).
#include "io/script.h"

#include <algorithm>

#include "io/script_ops.h"

namespace sculpt::io {

using namespace sculpt::core;

const char* scriptOpName(ScriptOp::Kind kind) {
    const char* name = scriptOpInfo(kind).name;
    return *name ? name : "?";
}

namespace {

Status runOp(Session& session, const ScriptOp& op, OpReport& report, const ScreenshotHook& screenshot, bool exact) {
    // A recording on the mesh it was made on: repeat what was applied, decide nothing again.
    if (op.hasApplied && exact) return session.replayOperation(op.applied, op.cancelled, report);
    if (op.cancelled) {
        report = OpReport{};
        report.status = OpStatus::NoOp;
        report.reason = "a drag that was taken back";
        return Status::success();
    }
    const ScriptOpInfo& info = scriptOpInfo(op.kind);
    if (!info.run) return Status::error("unknown op");  // begin_group and end_group: runScript keeps the groups
    return info.run(session, op, report, screenshot);
}

// The op a user would write for an operation (what a replay on another mesh decides again: the table's entry
// that records it), with the steps it was applied as (the lattice list's changes repeat as they were: they do
// not depend on the mesh).
ScriptOp recordedOp(const Operation& operation) {
    ScriptOp op;
    for (const ScriptOpInfo& info : scriptOps())
        if (info.record && info.record(operation, op)) {
            op.kind = info.kind;
            break;
        }
    if (operation.kind == OperationKind::LatticeTools) return op;
    op.hasApplied = true;
    op.applied = operation;
    return op;
}

}  // namespace

Status runScriptOp(Session& session, const ScriptOp& op, OpReport& report) {
    const Status s = runOp(session, op, report, {}, false);
    report.op = scriptOpName(op.kind);  // the op's name, as runScript reports it (the command may name another)
    return s;
}

Status runScript(Session& session, const Script& script, ScriptReport& report, const ScreenshotHook& screenshot,
                 const ScriptProgress& progress) {
    report.ops.clear();
    const bool exact = !script.meshFingerprint.empty() && script.meshFingerprint == session.meshAsSet().fingerprint;
    std::vector<std::pair<int, std::string>> groups;  // open begin_group ops: history cursor and label
    for (size_t i = 0; i < script.ops.size(); ++i) {
        if (progress && !progress(i, script.ops.size())) return Status::error("stopped before op " + std::to_string(i));
        const ScriptOp& op = script.ops[i];
        OpReport opReport;
        Status s = Status::success();
        if (op.kind == ScriptOp::Kind::BeginGroup) {
            groups.emplace_back(session.history().cursor(), op.label);
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
    script.lattice = session.cage().initialSettings();
    script.lattice.hasRegion = true;
    script.lattice.regionMin = session.cage().initialBoxMin();
    script.lattice.regionMax = session.cage().initialBoxMax();
    script.lattice.padding = 0.0;
    script.injectivity = session.injectivity();
    script.meshFingerprint = session.meshAsSet().fingerprint;
    for (const JournalEntry& entry : session.history().journal()) {
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

}  // namespace sculpt::io
