// Writing a script or a recorded session as JSON (script_json.h): each op with its fields, each applied
// operation with its steps (doubles in the shortest form that reads back to the same bits, so a replay is
// exact); and the report of a run (REPORT.json). Reading scripts: script_json.cpp.
#include "io/script_json.h"

#include <string>

#include <nlohmann/json.hpp>

#include "core/volume/volume_kinds.h"
#include "io/json_fields.h"
#include "io/json_text.h"
#include "io/lattice_json.h"
#include "io/script_json_fields.h"
#include "io/script_ops.h"

namespace sculpt::io {

namespace script_fields {

using namespace json_fields;

bool brushUsed(const core::BrushSettings& brush) { return brush.active() || brush.symmetry.any() || brush.strength != 1.0; }

void addBrushJson(json& j, const core::BrushSettings& brush) {
    if (!brushUsed(brush)) return;
    j["radius"] = brush.radius;
    j["strength"] = brush.strength;
    j["falloff"] = core::brushFalloffName(brush.falloff);
    j["symmetry"] = core::symmetryText(brush.symmetry);
}

json editsJson(const std::vector<core::NetEdit>& edits) {
    json out = json::array();
    for (const core::NetEdit& edit : edits) switch (edit.kind) {
            case core::NetEdit::Kind::Move:
                out.push_back({{"move", {{"points", edit.slots}, {"offset", vectorJson(edit.offset)}}}});
                break;
            case core::NetEdit::Kind::Merge: out.push_back({{"merge", edit.slots}}); break;
            case core::NetEdit::Kind::Refine: out.push_back({{"refine", {{"axis", edit.axis}}}}); break;
            case core::NetEdit::Kind::Insert:
                out.push_back({{"insert", {{"axis", edit.axis}, {"at", edit.at}, {"times", edit.times}}}});
                break;
            case core::NetEdit::Kind::Remove: out.push_back({{"remove", {{"axis", edit.axis}, {"index", edit.index}}}}); break;
        }
    return out;
}

json latticeJson(const core::LatticeSettings& s) {
    if (s.volume) {
        json j = volumeJson(*s.volume);
        j["pin_layers"] = s.pinLayers;
        return j;
    }
    json j = {{"resolution", s.resolution}, {"degree", s.degree}, {"padding", s.padding}, {"pin_layers", s.pinLayers}};
    j["region"] = s.hasRegion ? json{{"min", vectorJson(s.regionMin)}, {"max", vectorJson(s.regionMax)}} : json(nullptr);
    return j;
}

json constraintsJson(const std::vector<core::PointConstraint>& list) {
    json out = json::array();
    for (const core::PointConstraint& c : list) out.push_back({{"source", vectorJson(c.source)}, {"target", vectorJson(c.target)}});
    return out;
}

json rowsJson(const Eigen::MatrixX3d& rows) {
    json out = json::array();
    for (Eigen::Index r = 0; r < rows.rows(); ++r) out.push_back(vectorJson(rows.row(r).transpose()));
    return out;
}

}  // namespace script_fields

namespace {

using nlohmann::json;

using namespace json_fields;
using namespace script_fields;

json injectivityJson(const core::InjectivitySettings& s) {
    return {{"mode", core::injectivityModeName(s.mode)}, {"max_depth", s.maxDepth}, {"triangles", s.checkTriangles}};
}

// Doubles are written in the shortest form that reads back to the same bits, so a replay is exact.
json appliedJson(const core::Operation& operation) {
    json j;
    switch (operation.kind) {
        case core::OperationKind::Drag: j["kind"] = "drag"; break;
        case core::OperationKind::ControlPointEdit: j["kind"] = "control_point_edit"; break;
        case core::OperationKind::LatticeSetup: j["kind"] = "lattice_setup"; break;
        case core::OperationKind::LatticeTools: j["kind"] = "lattice_tools"; break;  // never recorded as applied
        case core::OperationKind::Refine: j["kind"] = "refine"; break;
        case core::OperationKind::WeightEdit: j["kind"] = "weight_edit"; break;
    }
    j["label"] = operation.label;
    j["interactive"] = operation.interactive;
    j["depth"] = operation.depthReached;
    if (brushUsed(operation.brush)) {
        json brush;
        addBrushJson(brush, operation.brush);
        j["brush"] = brush;
    }
    if (!operation.constraints.empty()) j["constraints"] = constraintsJson(operation.constraints);
    if (!operation.controlPoints.empty()) {
        j["control_points"] = operation.controlPoints;
        j["offsets"] = rowsJson(operation.offsets);
    }
    if (operation.kind == core::OperationKind::LatticeSetup) j["lattice"] = latticeJson(operation.settings);
    if (operation.frozenBefore >= 0 || operation.frozenAfter >= 0) j["frozen"] = {operation.frozenBefore, operation.frozenAfter};
    json steps = json::array();
    for (const core::Step& step : operation.steps) {
        json k = {{"lattice", latticeJson(step.settings)}, {"indices", step.delta.indices}, {"deltas", rowsJson(step.delta.deltas)}};
        if (step.freshFrame) k["new_layer"] = true;
        if (step.newCage) k["new_cage"] = true;
        if (step.region) k["region_free"] = step.regionFree;
        if (step.baked) k["baked"] = true;
        if (step.freshFrame || step.newCage)
            k["frame"] = {{"min", vectorJson(step.frameMin)}, {"max", vectorJson(step.frameMax)}, {"pins_kept", step.framePinsKept}};
        if (step.freshFrame && step.frameAxes != Eigen::Matrix3d::Identity()) k["frame"]["axes"] = rowsJson(step.frameAxes);
        if (!step.constraints.empty()) k["constraints"] = constraintsJson(step.constraints);
        if (!step.weights.empty()) k["weights"] = {{"ids", step.weights.ids}, {"before", step.weights.before}, {"after", step.weights.after}};
        steps.push_back(k);
    }
    j["steps"] = steps;
    const auto refinementJson = [](const core::RefinementRecord& record) {
        json splits = json::array();
        for (const core::EdgeSplit& split : record.splits) splits.push_back(json::array({split.a, split.b}));
        return json{{"tolerance", record.tolerance}, {"splits", splits}};
    };
    if (!operation.refinement.empty()) j["refinement"] = refinementJson(operation.refinement);
    if (!operation.refinementBefore.empty()) j["refinement_before"] = refinementJson(operation.refinementBefore);
    return j;
}

}  // namespace

std::string scriptToJson(const io::Script& script) {
    json root;
    if (!script.mesh.empty()) root["mesh"] = script.mesh;
    if (!script.meshFingerprint.empty()) root["mesh_fingerprint"] = script.meshFingerprint;
    if (script.weldMesh) root["weld"] = true;
    root["lattice"] = latticeJson(script.lattice);
    root["injectivity"] = injectivityJson(script.injectivity);
    json ops = json::array();
    for (const io::ScriptOp& op : script.ops) {
        json j;
        j["op"] = io::scriptOpName(op.kind);
        const io::ScriptOpInfo& info = io::scriptOpInfo(op.kind);
        if (info.write) info.write(op, j);
        if (op.hasApplied) j["applied"] = appliedJson(op.applied);
        if (op.cancelled) j["cancelled"] = true;
        ops.push_back(j);
    }
    root["ops"] = ops;
    return root.dump(2) + "\n";
}

std::string reportToJson(const io::ScriptReport& report, const core::Session& session, const ReportContext& context) {
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
        if (r.verticesAdded > 0 || r.deviation > 0.0) {
            op["vertices_added"] = r.verticesAdded;
            op["triangles_added"] = r.trianglesAdded;
            op["max_deviation"] = r.deviation;
        }
        if (r.verticesRemoved > 0) op["vertices_removed"] = r.verticesRemoved;
        op["wall_ms"] = r.wallMs;
        ops.push_back(op);
    }
    root["ops"] = ops;
    root["history"] = {{"entries", session.history().size()}, {"cursor", session.history().cursor()},
                       {"bytes", session.historyBytes()}, {"lattice_frames", session.cage().frameDepth() + 1}};
    root["injectivity"] = injectivityJson(session.injectivity());
    root["self_intersecting_pairs_at_load"] = session.meshAsSet().intersectingPairs;
    root["degenerate_triangles_at_load"] = session.meshAsSet().degenerateTriangles;
    root["near_contact_pairs_at_load"] = session.meshAsSet().nearContactPairs;
    return root.dump(2) + "\n";
}

}  // namespace sculpt::io
