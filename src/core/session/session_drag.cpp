// Session: interactive drags, on the surface (with a brush and symmetry) and of control points. The sources
// are fixed at the start, every update moves them towards new targets by an incremental manipulation (Hu et
// al. 2001, section 4: increments of one drag add up to one control displacement per lattice), tested and
// subdivided like any operation (Gain & Dodgson 2001, Appendix), and the whole drag is one history entry.
#include <algorithm>
#include <cmath>

#include "core/session/session.h"
#include "core/session/session_internal.h"

namespace sculpt::core {

using detail::Clock;
using detail::mergeDelta;
using detail::millisecondsSince;
using detail::vectorText;

namespace {

std::string dragLabel(size_t constraints) {
    return constraints == 1 ? "drag" : "drag (" + std::to_string(constraints) + " points)";
}

}  // namespace

Status Session::beginDrag(const std::vector<Eigen::Vector3d>& sourceParams) {
    if (!hasMesh()) return Status::error("no mesh is loaded");
    if (drag_.active) return Status::error("an interactive drag is already in progress");
    if (sourceParams.empty()) return Status::error("a drag needs at least one source");
    for (size_t f = 0; f < sourceParams.size(); ++f)
        if (!sourceParams[f].allFinite() || (sourceParams[f].array() < 0.0).any() || (sourceParams[f].array() > 1.0).any())
            return Status::error("constraint " + std::to_string(f) + " source is outside the lattice");
    layerActive_ = false;  // cage parameters
    DirectManipulationData data;
    if (Status s = precomputeDirectManipulation(lattice_, sourceParams, data); !s) return s;
    drag_.data = std::move(data);
    drag_.operation = Operation{};
    drag_.operation.kind = OperationKind::Drag;
    drag_.operation.interactive = true;
    drag_.operation.label = dragLabel(sourceParams.size());
    drag_.sourceWorld.clear();
    for (const Eigen::Vector3d& t : sourceParams) {
        drag_.sourceWorld.push_back(currentImage(t));
        drag_.operation.constraints.push_back({drag_.sourceWorld.back(), drag_.sourceWorld.back()});
    }
    drag_.params = sourceParams;
    drag_.appliedInFrame = false;
    drag_.mirrored = false;
    drag_.brush = BrushSettings{};
    drag_.active = true;
    return Status::success();
}

void Session::startMirroredDrag(const std::string& label, const std::vector<Eigen::Vector3d>& sources, std::vector<MirroredConstraint> mirror,
                                const BrushSettings& brush) {
    drag_.operation = Operation{};
    drag_.operation.kind = OperationKind::Drag;
    drag_.operation.interactive = true;
    drag_.operation.label = label;
    if (brush.symmetry.any()) drag_.operation.label += ", symmetric in " + symmetryText(brush.symmetry);
    drag_.operation.brush = brush;
    for (const Eigen::Vector3d& source : sources) drag_.operation.constraints.push_back({source, source});
    drag_.appliedInFrame = false;
    drag_.mirrored = true;
    drag_.userStarts = sources;
    drag_.mirror = std::move(mirror);
    drag_.brush = brush;
    drag_.active = true;
}

Status Session::beginDragAt(const std::vector<Eigen::Vector3d>& sources, const std::vector<bool>& held, const BrushSettings& brush) {
    if (!hasMesh()) return Status::error("no mesh is loaded");
    if (drag_.active) return Status::error("an interactive drag is already in progress");
    if (sources.empty()) return Status::error("a drag needs at least one source");
    if (Status s = checkBrush(brush); !s) return s;
    for (size_t f = 0; f < sources.size(); ++f)
        if (!sources[f].allFinite()) return Status::error("constraint " + std::to_string(f) + " source has non-finite coordinates");
    layerActive_ = false;
    const auto isHeld = [&](size_t f) { return f < held.size() && held[f]; };
    std::vector<MirroredConstraint> mirror = mirrorConstraints(sources, held, brush.symmetry, symmetryCentre_, mirrorMergeDistance(brush));
    if (brush.active()) {
        // A stroke (session_brush.cpp): no lattice is solved at the start; every update places the pull field.
        std::vector<bool> moving;
        for (const MirroredConstraint& c : mirror) moving.push_back(!isHeld(static_cast<size_t>(c.images.front().first)));
        if (std::find(moving.begin(), moving.end(), true) == moving.end()) return Status::error("every source of the drag is held");
        drag_.sourceWorld.clear();
        for (const MirroredConstraint& c : mirror) drag_.sourceWorld.push_back(c.source);
        drag_.params.clear();
        drag_.pulled = std::move(moving);
        startMirroredDrag("brush " + dragLabel(sources.size()), sources, std::move(mirror), brush);
        return Status::success();
    }
    std::vector<Eigen::Vector3d> params(mirror.size());
    Status located = Status::success();
    for (size_t e = 0; e < mirror.size() && located; ++e) {
        located = parametersOfCurrentPoint(mirror[e].source, params[e]);
        if (!located) located = Status::error((mirror[e].images.front().second == 0 ? "constraint " + std::to_string(mirror[e].images.front().first)
                                                                                    : std::string("the mirror image of a constraint")) +
                                              " source: " + located.message);
    }
    DirectManipulationData data;
    if (located) located = precomputeDirectManipulation(activeLattice(), params, data);
    if (!located) return located;
    drag_.data = std::move(data);
    drag_.sourceWorld.clear();
    for (const Eigen::Vector3d& t : params) drag_.sourceWorld.push_back(currentImage(t));
    drag_.params = std::move(params);
    startMirroredDrag(dragLabel(sources.size()), sources, std::move(mirror), brush);
    return Status::success();
}

Status Session::beginControlDrag(const std::vector<int>& indices) {
    if (!hasMesh()) return Status::error("no mesh is loaded");
    if (drag_.active) return Status::error("an interactive drag is already in progress");
    if (indices.empty()) return Status::error("no control point given");
    std::vector<int> sorted = indices;
    std::sort(sorted.begin(), sorted.end());
    sorted.erase(std::unique(sorted.begin(), sorted.end()), sorted.end());
    for (int idx : sorted)
        if (Status s = checkMovable(idx); !s) return s;
    layerActive_ = false;
    drag_.operation = Operation{};
    drag_.operation.kind = OperationKind::ControlPointEdit;
    drag_.operation.interactive = true;
    drag_.operation.label = sorted.size() == 1 ? "move control point" : "move " + std::to_string(sorted.size()) + " control points";
    drag_.operation.controlPoints = sorted;
    drag_.operation.offsets = Eigen::MatrixX3d::Zero(static_cast<Eigen::Index>(sorted.size()), 3);
    drag_.controlStart.resize(static_cast<Eigen::Index>(sorted.size()), 3);
    for (size_t c = 0; c < sorted.size(); ++c)
        drag_.controlStart.row(static_cast<Eigen::Index>(c)) = pushThroughLayers(lattice_.controlPoint(sorted[c])).transpose();
    drag_.sourceWorld.clear();
    drag_.params.clear();
    drag_.appliedInFrame = false;
    drag_.mirrored = false;
    drag_.active = true;
    return Status::success();
}

std::vector<Eigen::Vector3d> Session::dragSources() const { return drag_.sourceWorld; }

std::vector<Eigen::Vector3d> Session::dragUserSources() const {
    if (!drag_.mirrored) return drag_.sourceWorld;
    std::vector<Eigen::Vector3d> sources = drag_.userStarts;
    for (size_t e = 0; e < drag_.mirror.size(); ++e)
        if (drag_.mirror[e].images.front().second == 0) sources[static_cast<size_t>(drag_.mirror[e].images.front().first)] = drag_.sourceWorld[e];
    return sources;
}

void Session::mergeInteractiveStep(const ControlDelta& delta) {
    if (!drag_.operation.steps.empty() && drag_.appliedInFrame) {
        mergeDelta(drag_.operation.steps.back().delta, delta);
    } else {
        Step step;
        step.settings = settings_;
        step.delta = delta;
        for (const Eigen::Vector3d& source : drag_.sourceWorld) step.constraints.push_back({source, source});
        drag_.operation.steps.push_back(std::move(step));
    }
    drag_.appliedInFrame = true;
}

bool Session::applyInteractiveIncrement(const ControlDelta& delta, Manipulation& m, OpReport& report) {
    // Fast path: the whole increment as one change of the active lattice (the group property of Hu et al.
    // 2001, section 4, makes a drag's increments add up to one control displacement per lattice).
    StepFailure failure;
    lastMoved_.clear();
    lastMovedAll_ = false;
    if (tryDelta(delta, &lastMoved_, failure, report.injectivityMs, report.triangleCheckMs)) {
        mergeInteractiveStep(delta);
        for (size_t f = 0; f < drag_.params.size(); ++f) drag_.operation.steps.back().constraints[f].target = currentImage(drag_.params[f]);
        report.subSteps = 1;
        return true;
    }
    // Not injective as one step: subdivide this increment like any operation (Gain & Dodgson 2001, Appendix,
    // InjectSubdiv); it may enter new layers.
    Operation increments;
    Progress progress(scratch_);
    progress.operation = &increments;
    progress.appliedInCurrentFrame = drag_.appliedInFrame;
    progress.firstFailure = failure;
    const bool ok = injectSubdiv(m, 0, progress);
    report.injectivityMs += progress.injectivityMs;
    report.triangleCheckMs += progress.triangleMs;
    if (!ok) {
        restoreSnapshot(progress.snapshot);
        std::sort(progress.moved.begin(), progress.moved.end());
        progress.moved.erase(std::unique(progress.moved.begin(), progress.moved.end()), progress.moved.end());
        lastMoved_ = std::move(progress.moved);
        report.status = OpStatus::Rejected;
        report.depthReached = increments.depthReached;
        detail::noteFailure(report, progress.failure, true);
        if (drag_.operation.interactive)
            report.reason = "Refused: " + report.failureWords + ". The drag stays at the last valid position; " +
                            stepFailureAdvice(progress.failure.cause) + ".";
        else if (progress.failure.cause == StepFailure::Cause::SourceLeft)  // a scripted drag (its one move)
            report.reason = progress.failure.technical + "; nothing was changed";
        else
            report.reason = "refused: " + report.failureWords + ", even split into up to " + std::to_string(1 << injectivity_.maxDepth) +
                            " steps; nothing was changed (" + stepFailureAdvice(progress.failure.cause) + ")";
        report.injectivity = "rejected: " + progress.failure.technical;
        return false;
    }
    for (Step& step : increments.steps) {
        // A window drag's increments in one frame add up to one step (Hu et al. 2001, section 4); a scripted
        // drag keeps each injective step as InjectSubdiv made it (its recording lists them).
        if (drag_.operation.interactive && !step.freshFrame && !drag_.operation.steps.empty() && drag_.appliedInFrame) {
            mergeDelta(drag_.operation.steps.back().delta, step.delta);
            for (size_t f = 0; f < step.constraints.size(); ++f)
                drag_.operation.steps.back().constraints[f].target = step.constraints[f].target;
        } else {
            drag_.operation.steps.push_back(std::move(step));
        }
        drag_.appliedInFrame = true;
    }
    drag_.operation.depthReached = std::max(drag_.operation.depthReached, increments.depthReached);
    std::sort(progress.moved.begin(), progress.moved.end());
    progress.moved.erase(std::unique(progress.moved.begin(), progress.moved.end()), progress.moved.end());
    lastMoved_ = std::move(progress.moved);
    lastMovedAll_ = progress.movedAll;
    report.subSteps = static_cast<int>(increments.steps.size());
    report.depthReached = increments.depthReached;
    detail::noteFailure(report, failure, true);
    return true;
}

Status Session::updateDrag(const std::vector<Eigen::Vector3d>& userTargets, OpReport& report) {
    const auto start = Clock::now();
    report = OpReport{};
    report.op = "drag";
    if (!drag_.active || drag_.operation.kind != OperationKind::Drag) return Status::error("no interactive drag is in progress");
    const size_t expected = drag_.mirrored ? drag_.userStarts.size() : drag_.sourceWorld.size();
    if (userTargets.size() != expected) return Status::error("drag target count changed");
    for (const Eigen::Vector3d& t : userTargets)
        if (!t.allFinite()) return Status::error("drag target has non-finite coordinates");
    // With a brush or symmetry: the strength scales each move from where it began, and the mirror images
    // follow the mirrored targets.
    std::vector<Eigen::Vector3d> targets = userTargets;
    if (drag_.mirrored) {
        std::vector<Eigen::Vector3d> scaled(userTargets.size());
        for (size_t u = 0; u < userTargets.size(); ++u)
            scaled[u] = drag_.userStarts[u] + drag_.brush.strength * (userTargets[u] - drag_.userStarts[u]);
        targets.clear();
        for (const MirroredConstraint& c : drag_.mirror) targets.push_back(mirroredTarget(c, scaled, drag_.userStarts));
    }

    if (drag_.mirrored && drag_.brush.active()) {
        updateStroke(targets, report);
        report.wallMs = millisecondsSince(start);
        return Status::success();
    }
    Eigen::MatrixX3d increment(static_cast<Eigen::Index>(targets.size()), 3);
    for (size_t f = 0; f < targets.size(); ++f) {
        Eigen::Vector3d target;
        if (!toActiveSpace(targets[f], target)) {
            report.status = OpStatus::Rejected;
            report.reason = "Refused: the target " + vectorText(targets[f]) + " is not the image of any point inside the lattice.";
            return Status::success();
        }
        increment.row(static_cast<Eigen::Index>(f)) = (target - activeImage(drag_.params[f])).transpose();
    }
    if ((increment.array() == 0.0).all()) {
        report.status = OpStatus::NoOp;
        report.reason = "the sources are already there";
        return Status::success();
    }
    // One incremental manipulation omega(S, increment) with the factorisation made at begin (eq. 7 / 12).
    const DirectManipulationResult solved = solveDirectManipulation(drag_.data, increment);
    Manipulation m;
    for (size_t f = 0; f < targets.size(); ++f) m.sources.push_back(currentImage(drag_.params[f]));
    m.targets = targets;

    const int framesBefore = frameDepth();
    if (!applyInteractiveIncrement(solved.delta, m, report)) {
        report.wallMs = millisecondsSince(start);
        return Status::success();
    }
    if (report.subSteps == 1 && frameDepth() == framesBefore) {
        report.residuals = solved.residuals;
        report.rankDeficient = solved.rankDeficient;
        if (drag_.mirrored) trimResiduals(report, drag_.userStarts.size());
    } else {
        // The active lattice may have changed: the sources' parameters are re-found where the steps left them.
        for (size_t f = 0; f < m.sources.size(); ++f) parametersOfCurrentPoint(m.sources[f], drag_.params[f]);
        DirectManipulationData data;
        precomputeDirectManipulation(activeLattice(), drag_.params, data);
        drag_.data = std::move(data);
    }
    for (size_t f = 0; f < targets.size(); ++f) drag_.sourceWorld[f] = currentImage(drag_.params[f]);
    if (drag_.mirrored) {
        for (size_t e = 0; e < drag_.mirror.size(); ++e)
            if (drag_.mirror[e].images.front().second == 0)
                drag_.operation.constraints[static_cast<size_t>(drag_.mirror[e].images.front().first)].target = drag_.sourceWorld[e];
    } else {
        for (size_t f = 0; f < targets.size(); ++f) drag_.operation.constraints[f].target = drag_.sourceWorld[f];
    }
    report.status = OpStatus::Applied;
    report.injectivity = injectivity_.mode == InjectivityMode::Off ? "not checked" : "injective";
    report.controlPointsChanged = static_cast<int>(solved.delta.indices.size());
    report.verticesMoved = movedCount();
    report.wallMs = millisecondsSince(start);
    return Status::success();
}

void Session::updateStroke(const std::vector<Eigen::Vector3d>& targets, OpReport& report) {
    // Every pull from where the stroke began (brush_field.h): the region follows it, however long.
    std::vector<BrushPull> pulls;
    for (size_t e = 0; e < drag_.mirror.size(); ++e)
        pulls.push_back({drag_.mirror[e].source, drag_.pulled[e] ? Eigen::Vector3d(targets[e] - drag_.mirror[e].source) : Eigen::Vector3d::Zero()});
    StepFailure failure;
    const double share = applyBrushPulls(pulls, drag_.brush, drag_.operation.steps, report, failure);
    if (share < 1.0 && drag_.brush.symmetry.any() &&
        (failure.cause == StepFailure::Cause::Lattice || failure.cause == StepFailure::Cause::Triangles ||
         failure.cause == StepFailure::Cause::Uncertified)) {
        // A pull that carries its grabbed point onto or across a mirror plane meets the point's own mirror image
        // there: no injective symmetric deformation does that, so the stop is the symmetry's, not the mesh's.
        const double merge = mirrorMergeDistance(drag_.brush);
        for (size_t e = 0; e < pulls.size() && failure.cause != StepFailure::Cause::MirrorPlane; ++e) {
            if (!pulls[e].moving()) continue;
            for (int a = 0; a < 3; ++a) {
                if (!drag_.brush.symmetry.mirror[static_cast<size_t>(a)]) continue;
                const double from = pulls[e].source[a] - symmetryCentre_[a], to = from + pulls[e].pull[a];
                if (std::abs(from) > merge && (to == 0.0 || (to > 0.0) != (from > 0.0))) {
                    failure.cause = StepFailure::Cause::MirrorPlane;
                    failure.plane = std::string(1, static_cast<char>('X' + a));
                    break;
                }
            }
        }
    }
    for (size_t e = 0; e < drag_.mirror.size(); ++e)
        drag_.sourceWorld[e] = drag_.strokeReached[e];
    for (size_t e = 0; e < drag_.mirror.size(); ++e)
        if (drag_.mirror[e].images.front().second == 0)
            drag_.operation.constraints[static_cast<size_t>(drag_.mirror[e].images.front().first)].target = drag_.sourceWorld[e];
    report.fractionApplied = share;
    report.subSteps = static_cast<int>(drag_.operation.steps.size());
    report.controlPointsChanged = 0;
    for (const Step& step : drag_.operation.steps) report.controlPointsChanged += static_cast<int>(step.delta.indices.size());
    report.verticesMoved = movedCount();
    report.injectivity = injectivity_.mode == InjectivityMode::Off ? "not checked" : "injective";
    for (size_t e = 0; e < drag_.mirror.size(); ++e)
        if (drag_.mirror[e].images.front().second == 0) report.residuals.push_back((drag_.sourceWorld[e] - targets[e]).norm());
    if (share == 1.0) {
        report.status = OpStatus::Applied;
        return;
    }
    detail::noteFailure(report, failure, true);
    if (share > 0.0) {
        report.status = OpStatus::Applied;
        report.reason = "Stopped at " + detail::percentText(share) + " of the pull, the last injective point: beyond it " +
                        report.failureWords + " (" + stepFailureAdvice(failure.cause) + ").";
        return;
    }
    report.status = OpStatus::Rejected;
    report.reason = failure.cause == StepFailure::Cause::SourceLeft
                        ? "Refused: " + failure.technical + "."
                        : "Refused: " + report.failureWords + ". The stroke stays where it was; " + stepFailureAdvice(failure.cause) + ".";
    report.injectivity = "rejected: " + failure.technical;
}

Status Session::updateControlDrag(const Eigen::Vector3d& offset, OpReport& report) {
    // Every point moves by the same offset since the drag began.
    const Eigen::Index count = static_cast<Eigen::Index>(drag_.operation.controlPoints.size());
    return updateControlDragPerPoint(offset.transpose().replicate(std::max<Eigen::Index>(count, 1), 1), report);
}

Status Session::updateControlDragPerPoint(const Eigen::MatrixX3d& offsets, OpReport& report) {
    const auto start = Clock::now();
    report = OpReport{};
    report.op = "move_control_point";
    if (!drag_.active || drag_.operation.kind != OperationKind::ControlPointEdit)
        return Status::error("no interactive control-point drag is in progress");
    if (!offsets.allFinite()) return Status::error("control point move has non-finite coordinates");
    const std::vector<int>& ids = drag_.operation.controlPoints;
    const Eigen::Index count = static_cast<Eigen::Index>(ids.size());
    if (offsets.rows() != count)
        return Status::error("control point move has " + std::to_string(offsets.rows()) + " offsets for " + std::to_string(count) + " points");
    // Offsets as shown since the drag began; this update adds what is still missing.
    const Eigen::MatrixX3d shownIncrement = offsets - drag_.operation.offsets;
    if ((shownIncrement.array() == 0.0).all()) {
        report.status = OpStatus::NoOp;
        report.reason = "the control points are already there";
        return Status::success();
    }
    ControlDelta delta;
    delta.indices = ids;
    if (layers_.empty()) {
        delta.deltas = shownIncrement;
    } else {
        // Under layers the points follow the cursor as shown: each cage point goes where the layers take it
        // onto its shown start plus its offset.
        delta.deltas.resize(count, 3);
        for (Eigen::Index c = 0; c < count; ++c) {
            const Eigen::Vector3d shownTarget = drag_.controlStart.row(c).transpose() + offsets.row(c).transpose();
            Eigen::Vector3d cageTarget;
            if (!pullThroughLayers(shownTarget, cageTarget, layers_.size())) {
                report.status = OpStatus::Rejected;
                report.reason = "Refused: no point of the lattice's layers maps onto " + vectorText(shownTarget) + ".";
                return Status::success();
            }
            delta.deltas.row(c) = (cageTarget - lattice_.controlPoint(ids[static_cast<size_t>(c)])).transpose();
        }
    }
    applyControlDragDelta(std::move(delta), shownIncrement, report);
    report.wallMs = millisecondsSince(start);
    return Status::success();
}

void Session::applyControlDragDelta(ControlDelta delta, const Eigen::MatrixX3d& shownOffsets, OpReport& report) {
    // The points follow up to the last injective position and stop there (design.md "The cage is the user's
    // object"): never a fresh lattice. A later update that moves back lets them follow again.
    lastMoved_.clear();
    lastMovedAll_ = false;
    expandWelds(lattice_, delta);  // a welded point moves as one (Coquillart 1990, 3.1.2)
    StepFailure failure;
    const double fraction = applyLargestInjectiveFraction(delta, &lastMoved_, failure, report.injectivityMs, report.triangleCheckMs);
    report.fractionApplied = fraction;
    if (fraction > 0.0) {
        delta.deltas *= fraction;
        mergeInteractiveStep(delta);
        drag_.operation.offsets += fraction * shownOffsets;
    }
    std::sort(lastMoved_.begin(), lastMoved_.end());
    lastMoved_.erase(std::unique(lastMoved_.begin(), lastMoved_.end()), lastMoved_.end());
    report.injectivity = injectivity_.mode == InjectivityMode::Off ? "not checked" : "injective";
    report.controlPointsChanged = fraction > 0.0 ? static_cast<int>(delta.indices.size()) : 0;
    report.verticesMoved = movedCount();
    report.subSteps = fraction > 0.0 ? 1 : 0;
    report.status = fraction > 0.0 ? OpStatus::Applied : OpStatus::Rejected;
    if (fraction < 1.0) {
        detail::noteFailure(report, failure, false);
        report.reason = "Stopped " + stepStopWords(failure.cause) + ": moving further, " + report.failureWords + ".";
    }
}

Status Session::setDragLabel(const std::string& label) {
    if (!drag_.active) return Status::error("no interactive drag is in progress");
    if (label.empty()) return Status::error("a history entry needs a name");
    drag_.operation.label = label;
    return Status::success();
}

void Session::endDrag() { finishDrag(nullptr); }

void Session::finishDrag(OpReport* report) {
    if (!drag_.active) return;
    drag_.active = false;
    layerActive_ = false;  // the next operation starts in the cage
    strokeOutsideCage_ = 0;
    if (!drag_.operation.steps.empty()) {
        refineAfterEdit(drag_.operation, report);
        if (bakeLayers(drag_.operation.steps)) drag_.operation.steps.back().baked = true;  // the detail travels with the surface
        pushOperation(std::move(drag_.operation));
    }
    drag_.operation = Operation{};
}

Status Session::cancelDrag(OpReport& report) {
    const auto start = Clock::now();
    report = OpReport{};
    report.op = "cancel_drag";
    if (!drag_.active) {
        report.status = OpStatus::NoOp;
        report.reason = "no drag in progress";
        return Status::success();
    }
    drag_.active = false;
    revertSteps(drag_.operation.steps);
    layerActive_ = false;
    // Taking it back is an inverse manipulation, exact only up to rounding: the replay repeats it.
    if (!drag_.operation.steps.empty()) history_.note(JournalEntry{JournalEntry::Kind::CancelledDrag, drag_.operation, 0, {}, {}, {}}, false);
    report.status = drag_.operation.steps.empty() ? OpStatus::NoOp : OpStatus::Applied;
    report.reason = drag_.operation.steps.empty() ? "the drag had not moved anything" : "the drag was taken back";
    report.subSteps = static_cast<int>(drag_.operation.steps.size());
    report.verticesMoved = movedCount();
    drag_.operation = Operation{};
    report.wallMs = millisecondsSince(start);
    return Status::success();
}

}  // namespace sculpt::core
