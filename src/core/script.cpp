#include "core/script.h"

#include <chrono>

namespace sculpt::core {

const char* scriptOpName(ScriptOp::Kind kind) {
    switch (kind) {
        case ScriptOp::Kind::Drag: return "drag";
        case ScriptOp::Kind::DragVertex: return "drag_vertex";
        case ScriptOp::Kind::MoveControlPoint: return "move_control_point";
        case ScriptOp::Kind::Undo: return "undo";
        case ScriptOp::Kind::Redo: return "redo";
        case ScriptOp::Kind::Screenshot: return "screenshot";
        case ScriptOp::Kind::SetupLattice: return "setup_lattice";
    }
    return "?";
}

namespace {

Status runOp(Session& session, const ScriptOp& op, OpReport& report, const ScreenshotHook& screenshot) {
    switch (op.kind) {
        case ScriptOp::Kind::Drag: return session.drag(op.constraints, report);
        case ScriptOp::Kind::DragVertex: return session.dragVertex(op.vertex, op.target, report);
        case ScriptOp::Kind::MoveControlPoint: {
            const Lattice& lattice = session.lattice();
            std::vector<int> ids;
            for (const auto& c : op.controlPoints) {
                for (int a = 0; a < 3; ++a)
                    if (c[a] < 0 || c[a] >= lattice.count[a])
                        return Status::error("control point index [" + std::to_string(c[0]) + "," + std::to_string(c[1]) +
                                             "," + std::to_string(c[2]) + "] is outside the " + std::to_string(lattice.count[0]) +
                                             "x" + std::to_string(lattice.count[1]) + "x" + std::to_string(lattice.count[2]) +
                                             " lattice");
                ids.push_back(lattice.index(c[0], c[1], c[2]));
            }
            return session.moveControlPoints(ids, op.values, op.relative, report);
        }
        case ScriptOp::Kind::SetupLattice:
            return session.setupLattice(op.hasSettings ? op.settings : session.latticeSettings(), report);
        case ScriptOp::Kind::Undo: return session.undo(report);
        case ScriptOp::Kind::Redo: return session.redo(report);
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

}  // namespace

Status runScript(Session& session, const Script& script, ScriptReport& report, const ScreenshotHook& screenshot) {
    report.ops.clear();
    for (size_t i = 0; i < script.ops.size(); ++i) {
        OpReport opReport;
        if (Status s = runOp(session, script.ops[i], opReport, screenshot); !s)
            return Status::error("op " + std::to_string(i) + " (" + scriptOpName(script.ops[i].kind) + "): " + s.message);
        opReport.op = scriptOpName(script.ops[i].kind);
        report.ops.push_back(std::move(opReport));
    }
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
    for (int i = 0; i < session.historyCursor(); ++i) {
        const Operation& operation = session.history()[i];
        switch (operation.kind) {
            case OperationKind::Drag:
                if (!operation.interactive) {
                    ScriptOp op;
                    op.kind = ScriptOp::Kind::Drag;
                    op.constraints = operation.constraints;
                    script.ops.push_back(op);
                    break;
                }
                // An interactive drag was tested increment by increment; replaying its steps (each one in
                // its own fresh lattice where the original entered one) reproduces it exactly.
                for (const Step& step : operation.steps) {
                    if (step.freshFrame) {
                        ScriptOp fresh;
                        fresh.kind = ScriptOp::Kind::SetupLattice;
                        script.ops.push_back(fresh);
                    }
                    ScriptOp op;
                    op.kind = ScriptOp::Kind::Drag;
                    op.constraints = step.constraints;
                    script.ops.push_back(op);
                }
                break;
            case OperationKind::ControlPointEdit: {
                // An interactive control-point drag is replayed step by step, like an interactive drag.
                auto moveOp = [](const std::vector<int>& ids, const Eigen::MatrixX3d& offsets, const std::array<int, 3>& resolution) {
                    ScriptOp op;
                    op.kind = ScriptOp::Kind::MoveControlPoint;
                    op.relative = true;
                    op.values = offsets;
                    for (int idx : ids)
                        op.controlPoints.push_back({idx % resolution[0], (idx / resolution[0]) % resolution[1],
                                                    idx / (resolution[0] * resolution[1])});
                    return op;
                };
                if (!operation.interactive) {
                    script.ops.push_back(moveOp(operation.controlPoints, operation.offsets, operation.steps.front().settings.resolution));
                    break;
                }
                for (const Step& step : operation.steps) {
                    if (step.freshFrame) {
                        ScriptOp fresh;
                        fresh.kind = ScriptOp::Kind::SetupLattice;
                        script.ops.push_back(fresh);
                    }
                    if (!step.delta.indices.empty())
                        script.ops.push_back(moveOp(step.delta.indices, step.delta.deltas, step.settings.resolution));
                }
                break;
            }
            case OperationKind::LatticeSetup: {
                ScriptOp op;
                op.kind = ScriptOp::Kind::SetupLattice;
                op.hasSettings = true;
                op.settings = operation.settings;
                script.ops.push_back(op);
                break;
            }
        }
    }
    return script;
}

}  // namespace sculpt::core
