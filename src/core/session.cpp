#include "core/session.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

namespace sculpt::core {

namespace {

using Clock = std::chrono::steady_clock;

double millisecondsSince(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

std::string vectorText(const Eigen::Vector3d& v) {
    char buffer[128];
    std::snprintf(buffer, sizeof buffer, "(%g, %g, %g)", v.x(), v.y(), v.z());
    return buffer;
}

}  // namespace

const char* opStatusName(OpStatus status) {
    switch (status) {
        case OpStatus::Applied: return "applied";
        case OpStatus::Rejected: return "rejected";
        case OpStatus::NoOp: return "no-op";
    }
    return "?";
}

Status Session::setMesh(const Positions& positions, const Triangles& triangles, const LatticeSettings& settings) {
    if (positions.rows() == 0) return Status::error("the mesh has no vertices");
    if (!positions.allFinite()) return Status::error("the mesh has non-finite vertex coordinates");
    for (Eigen::Index t = 0; t < triangles.rows(); ++t)
        for (int c = 0; c < 3; ++c)
            if (triangles(t, c) < 0 || triangles(t, c) >= positions.rows())
                return Status::error("triangle " + std::to_string(t) + " has vertex index " +
                                     std::to_string(triangles(t, c)) + " out of range (mesh has " +
                                     std::to_string(positions.rows()) + " vertices)");
    Lattice lattice;
    if (Status s = makeLattice(settings, positions, lattice); !s) return s;
    endDrag();
    rest_ = positions;
    positions_ = positions;
    triangles_ = triangles;
    settings_ = settings;
    lattice_ = std::move(lattice);
    embedding_ = embedVertices(lattice_, rest_);
    history_.clear();
    cursor_ = 0;
    lastMoved_.clear();
    return Status::success();
}

Status Session::setupLattice(const LatticeSettings& settings) {
    if (!hasMesh()) return Status::error("no mesh is loaded");
    const Positions current = positions_;
    const Triangles triangles = triangles_;
    return setMesh(current, triangles, settings);
}

Status Session::validateSource(const Eigen::Vector3d& params, int constraint) const {
    if (!params.allFinite())
        return Status::error("constraint " + std::to_string(constraint) + " has non-finite source parameters");
    return Status::success();
}

Eigen::Vector3d Session::currentImage(const Eigen::Vector3d& params) const {
    const Eigen::Vector3d rest = lattice_.boxMin + params.cwiseProduct(lattice_.boxMax - lattice_.boxMin);
    return rest + displacementAt(lattice_, params);
}

Status Session::parametersOfCurrentPoint(const Eigen::Vector3d& point, Eigen::Vector3d& params) const {
    if (!point.allFinite()) return Status::error("point has non-finite coordinates");
    if (isUndeformed(lattice_)) {
        if (!restParameters(lattice_, point, params))
            return Status::error("point " + vectorText(point) + " lies outside the lattice box");
        return Status::success();
    }
    // note: the deformed image of the box is what the user sees; find the rest point that maps onto the
    // picked one (the deformation is injective where it matters, so Newton converges from the box guess).
    return locateDeformedPoint(lattice_, point, params);
}

Status Session::parametersOfVertex(int vertex, Eigen::Vector3d& params) const {
    if (vertex < 0 || vertex >= rest_.rows())
        return Status::error("vertex index " + std::to_string(vertex) + " is out of range (mesh has " +
                             std::to_string(rest_.rows()) + " vertices)");
    if (!restParameters(lattice_, rest_.row(vertex).transpose(), params))
        return Status::error("vertex " + std::to_string(vertex) + " lies outside the lattice region");
    return Status::success();
}

void Session::applyDelta(const ControlDelta& delta, double sign) {
    applyControlDelta(lattice_, delta, sign);
    lastMoved_.clear();
    evaluateCells(lattice_, embedding_, cellsInfluencedBy(lattice_, delta.indices), positions_, &lastMoved_);
}

void Session::pushOperation(Operation operation) {
    history_.resize(cursor_);  // a new operation after undo drops the redo branch
    history_.push_back(std::move(operation));
    cursor_ = static_cast<int>(history_.size());
}

Status Session::drag(const std::vector<PointConstraint>& constraints, OpReport& report) {
    const auto start = Clock::now();
    report = OpReport{};
    report.op = "drag";
    if (!hasMesh()) return Status::error("no mesh is loaded");
    if (constraints.empty()) return Status::error("drag has no constraints");
    std::vector<Eigen::Vector3d> params(constraints.size());
    Eigen::MatrixX3d displacements(static_cast<Eigen::Index>(constraints.size()), 3);
    for (size_t f = 0; f < constraints.size(); ++f) {
        const std::string which = "constraint " + std::to_string(f);
        if (!constraints[f].source.allFinite()) return Status::error(which + " source has non-finite coordinates");
        if (!constraints[f].target.allFinite()) return Status::error(which + " target has non-finite coordinates");
        if (Status s = parametersOfCurrentPoint(constraints[f].source, params[f]); !s)
            return Status::error(which + " source: " + s.message);
        displacements.row(static_cast<Eigen::Index>(f)) = (constraints[f].target - currentImage(params[f])).transpose();
    }
    if (dragActive_) return Status::error("an interactive drag is in progress");

    if ((displacements.array() == 0.0).all()) {
        report.status = OpStatus::NoOp;
        report.reason = "every source is already on its target";
        report.residuals.assign(constraints.size(), 0.0);
        report.wallMs = millisecondsSince(start);
        return Status::success();
    }
    const DirectManipulationResult solved = directManipulation(lattice_, params, displacements);
    Operation operation;
    operation.kind = OperationKind::Drag;
    operation.label = constraints.size() == 1 ? "drag" : "drag (" + std::to_string(constraints.size()) + " points)";
    operation.sourceParams = params;
    operation.displacements = displacements;
    operation.delta = solved.delta;
    applyDelta(operation.delta, 1.0);
    report.residuals = solved.residuals;
    report.rankDeficient = solved.rankDeficient;
    report.controlPointsChanged = static_cast<int>(operation.delta.indices.size());
    report.verticesMoved = static_cast<int>(lastMoved_.size());
    report.status = OpStatus::Applied;
    pushOperation(std::move(operation));
    report.wallMs = millisecondsSince(start);
    return Status::success();
}

Status Session::dragVertex(int vertex, const Eigen::Vector3d& target, OpReport& report) {
    if (!hasMesh()) return Status::error("no mesh is loaded");
    if (!target.allFinite()) return Status::error("drag_vertex target has non-finite coordinates");
    Eigen::Vector3d params;
    if (Status s = parametersOfVertex(vertex, params); !s) return s;
    // The vertex's current position is exactly the current image of its parameters; dragging that point
    // goes through the same path as any source point.
    const Status status = drag({PointConstraint{positions_.row(vertex).transpose(), target}}, report);
    report.op = "drag_vertex";
    return status;
}

Status Session::moveControlPoints(const std::vector<int>& indices, const Eigen::MatrixX3d& values, bool relative,
                                  OpReport& report) {
    const auto start = Clock::now();
    report = OpReport{};
    report.op = "move_control_point";
    if (!hasMesh()) return Status::error("no mesh is loaded");
    if (indices.empty()) return Status::error("no control point given");
    if (static_cast<Eigen::Index>(indices.size()) != values.rows())
        return Status::error("control point ids and values differ in count");
    if (dragActive_) return Status::error("an interactive drag is in progress");
    const int n = lattice_.controlPointCount();
    std::vector<std::pair<int, Eigen::Vector3d>> moves;
    for (size_t c = 0; c < indices.size(); ++c) {
        const int idx = indices[c];
        if (idx < 0 || idx >= n)
            return Status::error("control point id " + std::to_string(idx) + " is outside the lattice (" +
                                 std::to_string(n) + " control points)");
        if (lattice_.pinned[idx]) {
            const std::array<int, 3> ijk = lattice_.ijk(idx);
            return Status::error("control point [" + std::to_string(ijk[0]) + "," + std::to_string(ijk[1]) + "," +
                                 std::to_string(ijk[2]) + "] is pinned");
        }
        const Eigen::Vector3d value = values.row(static_cast<Eigen::Index>(c)).transpose();
        if (!value.allFinite()) return Status::error("control point move has non-finite coordinates");
        const Eigen::Vector3d offset = relative ? value : Eigen::Vector3d(value - lattice_.controlPoint(idx));
        moves.emplace_back(idx, offset);
    }
    // The same point listed twice: offsets add up for "by", the last position wins for "to".
    std::sort(moves.begin(), moves.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    Operation operation;
    operation.kind = OperationKind::ControlPointEdit;
    for (size_t c = 0; c < moves.size(); ++c) {
        if (!operation.delta.indices.empty() && operation.delta.indices.back() == moves[c].first) {
            if (relative) operation.delta.deltas.row(operation.delta.deltas.rows() - 1) += moves[c].second.transpose();
            else operation.delta.deltas.row(operation.delta.deltas.rows() - 1) = moves[c].second.transpose();
            continue;
        }
        operation.delta.indices.push_back(moves[c].first);
        operation.delta.deltas.conservativeResize(operation.delta.deltas.rows() + 1, 3);
        operation.delta.deltas.row(operation.delta.deltas.rows() - 1) = moves[c].second.transpose();
    }
    if ((operation.delta.deltas.array() == 0.0).all()) {
        report.status = OpStatus::NoOp;
        report.reason = "the control points are already there";
        report.wallMs = millisecondsSince(start);
        return Status::success();
    }
    operation.label = operation.delta.indices.size() == 1
                          ? "move control point"
                          : "move " + std::to_string(operation.delta.indices.size()) + " control points";
    applyDelta(operation.delta, 1.0);
    report.controlPointsChanged = static_cast<int>(operation.delta.indices.size());
    report.verticesMoved = static_cast<int>(lastMoved_.size());
    report.status = OpStatus::Applied;
    pushOperation(std::move(operation));
    report.wallMs = millisecondsSince(start);
    return Status::success();
}

Status Session::undo(OpReport& report) {
    const auto start = Clock::now();
    report = OpReport{};
    report.op = "undo";
    if (dragActive_) return Status::error("an interactive drag is in progress");
    if (cursor_ == 0) {
        report.status = OpStatus::NoOp;
        report.reason = "nothing to undo";
        return Status::success();
    }
    const Operation& operation = history_[--cursor_];
    applyDelta(operation.delta, -1.0);  // the inverse manipulation
    report.status = OpStatus::Applied;
    report.reason = "undid " + operation.label;
    report.controlPointsChanged = static_cast<int>(operation.delta.indices.size());
    report.verticesMoved = static_cast<int>(lastMoved_.size());
    report.wallMs = millisecondsSince(start);
    return Status::success();
}

Status Session::redo(OpReport& report) {
    const auto start = Clock::now();
    report = OpReport{};
    report.op = "redo";
    if (dragActive_) return Status::error("an interactive drag is in progress");
    if (cursor_ == static_cast<int>(history_.size())) {
        report.status = OpStatus::NoOp;
        report.reason = "nothing to redo";
        return Status::success();
    }
    const Operation& operation = history_[cursor_++];
    applyDelta(operation.delta, 1.0);
    report.status = OpStatus::Applied;
    report.reason = "redid " + operation.label;
    report.controlPointsChanged = static_cast<int>(operation.delta.indices.size());
    report.verticesMoved = static_cast<int>(lastMoved_.size());
    report.wallMs = millisecondsSince(start);
    return Status::success();
}

Status Session::beginDrag(const std::vector<Eigen::Vector3d>& sourceParams) {
    if (!hasMesh()) return Status::error("no mesh is loaded");
    if (dragActive_) return Status::error("an interactive drag is already in progress");
    for (size_t f = 0; f < sourceParams.size(); ++f) {
        if (!sourceParams[f].allFinite() || (sourceParams[f].array() < 0.0).any() || (sourceParams[f].array() > 1.0).any())
            return Status::error("constraint " + std::to_string(f) + " source is outside the lattice");
    }
    DirectManipulationData data;
    if (Status s = precomputeDirectManipulation(lattice_, sourceParams, data); !s) return s;
    dragData_ = std::move(data);
    dragOperation_ = Operation{};
    dragOperation_.kind = OperationKind::Drag;
    dragOperation_.label = sourceParams.size() == 1 ? "drag" : "drag (" + std::to_string(sourceParams.size()) + " points)";
    dragOperation_.sourceParams = sourceParams;
    dragOperation_.displacements = Eigen::MatrixX3d::Zero(static_cast<Eigen::Index>(sourceParams.size()), 3);
    dragOperation_.delta.indices = dragData_.columns;
    dragOperation_.delta.deltas = Positions::Zero(static_cast<Eigen::Index>(dragData_.columns.size()), 3);
    dragActive_ = true;
    return Status::success();
}

Status Session::updateDrag(const std::vector<Eigen::Vector3d>& targets, OpReport& report) {
    const auto start = Clock::now();
    report = OpReport{};
    report.op = "drag";
    if (!dragActive_) return Status::error("no interactive drag is in progress");
    if (targets.size() != dragOperation_.sourceParams.size()) return Status::error("drag target count changed");
    Eigen::MatrixX3d increment(static_cast<Eigen::Index>(targets.size()), 3);
    for (size_t f = 0; f < targets.size(); ++f) {
        if (!targets[f].allFinite()) return Status::error("drag target has non-finite coordinates");
        increment.row(static_cast<Eigen::Index>(f)) = (targets[f] - currentImage(dragOperation_.sourceParams[f])).transpose();
    }
    // Each mouse move is omega(S, increment); by the group property the whole drag is omega(S, sum).
    const DirectManipulationResult solved = solveDirectManipulation(dragData_, increment);
    applyDelta(solved.delta, 1.0);
    dragOperation_.displacements += increment;
    dragOperation_.delta.deltas += solved.delta.deltas;
    report.status = OpStatus::Applied;
    report.residuals = solved.residuals;
    report.rankDeficient = solved.rankDeficient;
    report.controlPointsChanged = static_cast<int>(solved.delta.indices.size());
    report.verticesMoved = static_cast<int>(lastMoved_.size());
    report.wallMs = millisecondsSince(start);
    return Status::success();
}

void Session::endDrag() {
    if (!dragActive_) return;
    dragActive_ = false;
    if (!(dragOperation_.delta.deltas.array() == 0.0).all()) pushOperation(std::move(dragOperation_));
    dragOperation_ = Operation{};
}

Status Session::setPinned(const std::vector<int>& indices, bool pinned) {
    const int n = lattice_.controlPointCount();
    for (int idx : indices)
        if (idx < 0 || idx >= n) return Status::error("control point id " + std::to_string(idx) + " is outside the lattice");
    for (int idx : indices) lattice_.pinned[idx] = pinned ? 1 : 0;
    return Status::success();
}

}  // namespace sculpt::core
