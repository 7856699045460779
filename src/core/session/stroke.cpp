// Stroke: interactive drags, on the surface (with a brush and symmetry) and of control points. The sources
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

// "drag", "drag (2 points)", "drag (1 point, 6 held)": the points pulled, and the held ones (pins) apart.
std::string dragLabel(size_t moving, size_t held) {
    if (held == 0) return moving == 1 ? "drag" : "drag (" + std::to_string(moving) + " points)";
    return "drag (" + std::to_string(moving) + (moving == 1 ? " point, " : " points, ") + std::to_string(held) + " held)";
}

// The operation's constraint targets (what a recording writes) after an update of a drag begun with beginAt:
// where each user's grabbed point got, as the pull that was asked before the brush's strength scaled it. A
// recording replayed where its steps do not apply solves the drag again from these targets and scales them by
// the strength once (update); the scaled points themselves would have it applied twice.
void recordAskedTargets(DragState& drag) {
    for (size_t e = 0; e < drag.mirror.size(); ++e) {
        if (drag.mirror[e].images.front().second != 0) continue;  // a mirror image: not a constraint of the user's
        const size_t u = static_cast<size_t>(drag.mirror[e].images.front().first);
        drag.operation.constraints[u].target = drag.brush.askedTarget(drag.userStarts[u], drag.sourceWorld[e]);
    }
}

}  // namespace

Status Stroke::begin(const std::vector<Eigen::Vector3d>& sourceParams) {
    if (s_.mesh().empty()) return Status::error("no mesh is loaded");
    if (s_.drag_.active) return Status::error("an interactive drag is already in progress");
    if (sourceParams.empty()) return Status::error("a drag needs at least one source");
    for (size_t f = 0; f < sourceParams.size(); ++f)
        if (!sourceParams[f].allFinite() || (sourceParams[f].array() < 0.0).any() || (sourceParams[f].array() > 1.0).any())
            return Status::error("constraint " + std::to_string(f) + " source is outside the lattice");
    s_.stack_.layerActive_ = false;  // cage parameters
    DirectManipulationData data;
    if (Status s = precomputeDirectManipulation(s_.stack_.lattice_, sourceParams, data); !s) return s;
    s_.drag_.data = std::move(data);
    s_.drag_.operation = Operation{};
    s_.drag_.operation.kind = OperationKind::Drag;
    s_.drag_.operation.interactive = true;
    s_.drag_.operation.label = dragLabel(sourceParams.size(), 0);
    s_.drag_.sourceWorld.clear();
    for (const Eigen::Vector3d& t : sourceParams) {
        s_.drag_.sourceWorld.push_back(s_.stack_.currentImage(t));
        s_.drag_.operation.constraints.push_back({s_.drag_.sourceWorld.back(), s_.drag_.sourceWorld.back()});
    }
    s_.drag_.params = sourceParams;
    s_.drag_.appliedInFrame = false;
    s_.drag_.mirrored = false;
    s_.drag_.brush = BrushSettings{};
    s_.drag_.active = true;
    return Status::success();
}

void Stroke::startMirrored(const std::string& label, const std::vector<Eigen::Vector3d>& sources, std::vector<MirroredConstraint> mirror,
                                const BrushSettings& brush) {
    s_.drag_.operation = Operation{};
    s_.drag_.operation.kind = OperationKind::Drag;
    s_.drag_.operation.interactive = true;
    s_.drag_.operation.label = label;
    if (brush.symmetry.any()) s_.drag_.operation.label += ", symmetric in " + symmetryText(brush.symmetry, true);
    s_.drag_.operation.brush = brush;
    for (const Eigen::Vector3d& source : sources) s_.drag_.operation.constraints.push_back({source, source});
    s_.drag_.appliedInFrame = false;
    s_.drag_.mirrored = true;
    s_.drag_.userStarts = sources;
    s_.drag_.mirror = std::move(mirror);
    s_.drag_.brush = brush;
    s_.drag_.splitFailedAt = INFINITY;
    s_.drag_.acrossFailedAt = INFINITY;
    s_.drag_.strokeMode = -1;
    s_.drag_.rowsAtBegin = s_.mesh_.positions.rows();
    s_.drag_.grabbedTriangle.clear();
    s_.drag_.grabbedWeights.clear();
    s_.drag_.active = true;
}

Status Stroke::beginAt(const std::vector<Eigen::Vector3d>& sources, const std::vector<bool>& held, const BrushSettings& brush) {
    if (s_.mesh().empty()) return Status::error("no mesh is loaded");
    if (s_.drag_.active) return Status::error("an interactive drag is already in progress");
    if (sources.empty()) return Status::error("a drag needs at least one source");
    if (Status s = s_.checkBrush(brush); !s) return s;
    for (size_t f = 0; f < sources.size(); ++f)
        if (!sources[f].allFinite()) return Status::error("constraint " + std::to_string(f) + " source has non-finite coordinates");
    s_.stack_.layerActive_ = false;
    const auto isHeld = [&](size_t f) { return f < held.size() && held[f]; };
    const SymmetryFrame frame = s_.symmetryFrame();
    std::vector<MirroredConstraint> mirror = mirrorConstraints(sources, held, brush.symmetry, frame, s_.mirrorMergeDistance(brush));
    s_.drag_.symmetry = frame;  // the updates mirror the targets in these planes
    if (brush.active()) {
        // A stroke (stroke_brush.cpp): no lattice is solved at the start; every update places the pull field.
        std::vector<bool> moving;
        for (const MirroredConstraint& c : mirror) moving.push_back(!isHeld(static_cast<size_t>(c.images.front().first)));
        if (std::find(moving.begin(), moving.end(), true) == moving.end()) return Status::error("every source of the drag is held");
        s_.drag_.sourceWorld.clear();
        for (const MirroredConstraint& c : mirror) s_.drag_.sourceWorld.push_back(c.source);
        s_.drag_.params.clear();
        s_.drag_.pulled = std::move(moving);
        // A brush stroke is named by what it pulls: held points (pins) only keep their place where it reaches.
        const size_t heldCount = static_cast<size_t>(std::count_if(held.begin(), held.end(), [](bool h) { return h; }));
        startMirrored("brush " + dragLabel(sources.size() - std::min(heldCount, sources.size()), 0), sources, std::move(mirror), brush);
        return Status::success();
    }
    std::vector<Eigen::Vector3d> params(mirror.size());
    Status located = Status::success();
    for (size_t e = 0; e < mirror.size() && located; ++e) {
        located = s_.stack_.parametersOfCurrentPoint(mirror[e].source, params[e]);
        if (!located) located = Status::error((mirror[e].images.front().second == 0 ? "constraint " + std::to_string(mirror[e].images.front().first)
                                                                                    : std::string("the mirror image of a constraint")) +
                                              " source: " + located.message);
    }
    DirectManipulationData data;
    if (located) located = precomputeDirectManipulation(s_.stack_.activeLattice(), params, data);
    if (!located) return located;
    s_.drag_.data = std::move(data);
    s_.drag_.sourceWorld.clear();
    for (const Eigen::Vector3d& t : params) s_.drag_.sourceWorld.push_back(s_.stack_.currentImage(t));
    s_.drag_.params = std::move(params);
    const size_t heldCount = static_cast<size_t>(std::count_if(held.begin(), held.end(), [](bool h) { return h; }));
    startMirrored(dragLabel(sources.size() - std::min(heldCount, sources.size()), heldCount), sources, std::move(mirror), brush);
    return Status::success();
}

Status Stroke::beginControl(const std::vector<int>& indices) {
    if (s_.mesh().empty()) return Status::error("no mesh is loaded");
    if (s_.drag_.active) return Status::error("an interactive drag is already in progress");
    if (indices.empty()) return Status::error("no control point given");
    std::vector<int> sorted = indices;
    std::sort(sorted.begin(), sorted.end());
    sorted.erase(std::unique(sorted.begin(), sorted.end()), sorted.end());
    for (int idx : sorted)
        if (Status s = s_.checkMovable(idx); !s) return s;
    s_.stack_.layerActive_ = false;
    s_.drag_.operation = Operation{};
    s_.drag_.operation.kind = OperationKind::ControlPointEdit;
    s_.drag_.operation.interactive = true;
    s_.drag_.operation.label = sorted.size() == 1 ? "move control point" : "move " + std::to_string(sorted.size()) + " control points";
    s_.drag_.operation.controlPoints = sorted;
    s_.drag_.operation.offsets = Eigen::MatrixX3d::Zero(static_cast<Eigen::Index>(sorted.size()), 3);
    s_.drag_.controlStart.resize(static_cast<Eigen::Index>(sorted.size()), 3);
    for (size_t c = 0; c < sorted.size(); ++c)
        s_.drag_.controlStart.row(static_cast<Eigen::Index>(c)) = s_.stack_.pushThroughLayers(s_.stack_.lattice_.controlPoint(sorted[c])).transpose();
    s_.drag_.sourceWorld.clear();
    s_.drag_.params.clear();
    s_.drag_.appliedInFrame = false;
    s_.drag_.mirrored = false;
    s_.drag_.active = true;
    return Status::success();
}

bool Stroke::active() const { return s_.drag_.active; }

int Stroke::verticesOutsideCage() const { return s_.drag_.outsideCage; }

std::vector<Eigen::Vector3d> Stroke::sources() const { return s_.drag_.sourceWorld; }

std::vector<Eigen::Vector3d> Stroke::userSources() const {
    if (!s_.drag_.mirrored) return s_.drag_.sourceWorld;
    std::vector<Eigen::Vector3d> sources = s_.drag_.userStarts;
    for (size_t e = 0; e < s_.drag_.mirror.size(); ++e)
        if (s_.drag_.mirror[e].images.front().second == 0) sources[static_cast<size_t>(s_.drag_.mirror[e].images.front().first)] = s_.drag_.sourceWorld[e];
    return sources;
}

void Stroke::mergeStep(const ControlDelta& delta) {
    if (!s_.drag_.operation.steps.empty() && s_.drag_.appliedInFrame) {
        mergeDelta(s_.drag_.operation.steps.back().delta, delta);
    } else {
        Step step;
        step.settings = s_.stack_.settings_;
        step.delta = delta;
        for (const Eigen::Vector3d& source : s_.drag_.sourceWorld) step.constraints.push_back({source, source});
        s_.drag_.operation.steps.push_back(std::move(step));
    }
    s_.drag_.appliedInFrame = true;
}

bool Stroke::applyIncrement(const ControlDelta& delta, Manipulation& m, OpReport& report) {
    // Fast path: the whole increment as one change of the active lattice (the group property of Hu et al.
    // 2001, section 4, makes a drag's increments add up to one control displacement per lattice).
    StepFailure failure;
    s_.lastMoved_.vertices.clear();
    s_.lastMoved_.all = false;
    if (s_.tryDelta(delta, &s_.lastMoved_.vertices, failure, report.injectivityMs, report.triangleCheckMs)) {
        mergeStep(delta);
        for (size_t f = 0; f < s_.drag_.params.size(); ++f) s_.drag_.operation.steps.back().constraints[f].target = s_.stack_.currentImage(s_.drag_.params[f]);
        report.subSteps = 1;
        return true;
    }
    // Not injective as one step: subdivide this increment like any operation (Gain & Dodgson 2001, Appendix,
    // InjectSubdiv); it may enter new layers.
    Operation increments;
    Session::Progress progress(s_.scratch_);
    progress.operation = &increments;
    progress.appliedInCurrentFrame = s_.drag_.appliedInFrame;
    progress.firstFailure = failure;
    const bool ok = s_.injectSubdiv(m, 0, progress);
    report.injectivityMs += progress.injectivityMs;
    report.triangleCheckMs += progress.triangleMs;
    if (!ok) {
        s_.restoreSnapshot(progress.snapshot);
        std::sort(progress.moved.begin(), progress.moved.end());
        progress.moved.erase(std::unique(progress.moved.begin(), progress.moved.end()), progress.moved.end());
        s_.lastMoved_.vertices = std::move(progress.moved);
        report.status = OpStatus::Rejected;
        report.depthReached = increments.depthReached;
        detail::noteFailure(report, progress.failure, true);
        if (s_.drag_.operation.interactive)
            report.reason = "Refused: " + report.failureWords + ". The drag stays at the last valid position; " +
                            stepFailureAdvice(progress.failure.cause) + ".";
        else if (progress.failure.cause == StepFailure::Cause::SourceLeft)  // a scripted drag (its one move)
            report.reason = progress.failure.technical + "; nothing was changed";
        else
            report.reason = "refused: " + report.failureWords + ", even split into up to " + std::to_string(1 << s_.injectivity_.maxDepth) +
                            " steps; nothing was changed (" + stepFailureAdvice(progress.failure.cause) + ")";
        report.injectivity = "rejected: " + progress.failure.technical;
        return false;
    }
    for (Step& step : increments.steps) {
        // A window drag's increments in one frame add up to one step (Hu et al. 2001, section 4); a scripted
        // drag keeps each injective step as InjectSubdiv made it (its recording lists them).
        if (s_.drag_.operation.interactive && !step.freshFrame && !s_.drag_.operation.steps.empty() && s_.drag_.appliedInFrame) {
            mergeDelta(s_.drag_.operation.steps.back().delta, step.delta);
            for (size_t f = 0; f < step.constraints.size(); ++f)
                s_.drag_.operation.steps.back().constraints[f].target = step.constraints[f].target;
        } else {
            s_.drag_.operation.steps.push_back(std::move(step));
        }
        s_.drag_.appliedInFrame = true;
    }
    s_.drag_.operation.depthReached = std::max(s_.drag_.operation.depthReached, increments.depthReached);
    std::sort(progress.moved.begin(), progress.moved.end());
    progress.moved.erase(std::unique(progress.moved.begin(), progress.moved.end()), progress.moved.end());
    s_.lastMoved_.vertices = std::move(progress.moved);
    s_.lastMoved_.all = progress.movedAll;
    report.subSteps = static_cast<int>(increments.steps.size());
    report.depthReached = increments.depthReached;
    detail::noteFailure(report, failure, true);
    return true;
}

Status Stroke::update(const std::vector<Eigen::Vector3d>& userTargets, OpReport& report) {
    const auto start = Clock::now();
    report = OpReport{};
    report.op = "drag";
    if (!s_.drag_.active || s_.drag_.operation.kind != OperationKind::Drag) return Status::error("no interactive drag is in progress");
    const size_t expected = s_.drag_.mirrored ? s_.drag_.userStarts.size() : s_.drag_.sourceWorld.size();
    if (userTargets.size() != expected) return Status::error("drag target count changed");
    for (const Eigen::Vector3d& t : userTargets)
        if (!t.allFinite()) return Status::error("drag target has non-finite coordinates");
    // With a brush or symmetry: the strength scales each move from where it began, and the mirror images
    // follow the mirrored targets.
    std::vector<Eigen::Vector3d> targets = userTargets;
    if (s_.drag_.mirrored) {
        std::vector<Eigen::Vector3d> scaled(userTargets.size());
        for (size_t u = 0; u < userTargets.size(); ++u)
            scaled[u] = s_.drag_.brush.scaledTarget(s_.drag_.userStarts[u], userTargets[u]);
        targets.clear();
        for (const MirroredConstraint& c : s_.drag_.mirror) targets.push_back(mirroredTarget(c, scaled, s_.drag_.userStarts, s_.drag_.symmetry));
    }

    if (s_.drag_.mirrored && s_.drag_.brush.active()) {
        updatePulls(targets, report);
        report.wallMs = millisecondsSince(start);
        return Status::success();
    }
    Eigen::MatrixX3d increment(static_cast<Eigen::Index>(targets.size()), 3);
    for (size_t f = 0; f < targets.size(); ++f) {
        Eigen::Vector3d target;
        if (!s_.stack_.toActiveSpace(targets[f], target)) {
            report.status = OpStatus::Rejected;
            report.reason = "Refused: the target " + vectorText(targets[f]) + " is not the image of any point inside the lattice.";
            return Status::success();
        }
        increment.row(static_cast<Eigen::Index>(f)) = (target - s_.stack_.activeImage(s_.drag_.params[f])).transpose();
    }
    if ((increment.array() == 0.0).all()) {
        report.status = OpStatus::NoOp;
        report.reason = "the sources are already there";
        return Status::success();
    }
    // One incremental manipulation omega(S, increment) with the factorisation made at begin (eq. 7 / 12).
    const DirectManipulationResult solved = solveDirectManipulation(s_.drag_.data, increment);
    Manipulation m;
    for (size_t f = 0; f < targets.size(); ++f) m.sources.push_back(s_.stack_.currentImage(s_.drag_.params[f]));
    m.targets = targets;

    const int framesBefore = s_.stack_.frameDepth();
    if (!applyIncrement(solved.delta, m, report)) {
        report.wallMs = millisecondsSince(start);
        return Status::success();
    }
    if (report.subSteps == 1 && s_.stack_.frameDepth() == framesBefore) {
        report.residuals = solved.residuals;
        report.rankDeficient = solved.rankDeficient;
        if (s_.drag_.mirrored) s_.trimResiduals(report, s_.drag_.userStarts.size());
    } else {
        // The active lattice may have changed: the sources' parameters are re-found where the steps left them.
        for (size_t f = 0; f < m.sources.size(); ++f) s_.stack_.parametersOfCurrentPoint(m.sources[f], s_.drag_.params[f]);
        DirectManipulationData data;
        precomputeDirectManipulation(s_.stack_.activeLattice(), s_.drag_.params, data);
        s_.drag_.data = std::move(data);
    }
    for (size_t f = 0; f < targets.size(); ++f) s_.drag_.sourceWorld[f] = s_.stack_.currentImage(s_.drag_.params[f]);
    if (s_.drag_.mirrored) {
        recordAskedTargets(s_.drag_);
    } else {
        for (size_t f = 0; f < targets.size(); ++f) s_.drag_.operation.constraints[f].target = s_.drag_.sourceWorld[f];
    }
    report.status = OpStatus::Applied;
    report.injectivity = s_.injectivity_.mode == InjectivityMode::Off ? "not checked" : "injective";
    report.controlPointsChanged = static_cast<int>(solved.delta.indices.size());
    report.verticesMoved = s_.movedCount();
    report.wallMs = millisecondsSince(start);
    return Status::success();
}

void Stroke::updatePulls(const std::vector<Eigen::Vector3d>& targets, OpReport& report) {
    // Every pull from where the stroke began (brush_field.h): the region follows it, however long.
    std::vector<BrushPull> pulls;
    for (size_t e = 0; e < s_.drag_.mirror.size(); ++e)
        pulls.push_back({s_.drag_.mirror[e].source, s_.drag_.pulled[e] ? Eigen::Vector3d(targets[e] - s_.drag_.mirror[e].source) : Eigen::Vector3d::Zero()});
    // A pull that carries its grabbed point onto or across a mirror plane meets the point's own mirror image
    // there: no injective symmetric deformation does that (each side of the plane stays on its side), and a layer
    // per image carries it only where the mesh's sides differ enough that the images pass each other. Such a pull
    // is tried whole as it is (no splits, no search); failing that, it is carried only up to 1/64 of it short of
    // the plane (`reach`, the share of the pull asked): its splits and the search for its last injective point are
    // tried on that, not on what cannot pass (strokes_real's slowest stroke, on the armadillo: 9.5 s before, 2.5 s now).
    // A stroke dragged on past the plane tries the whole pull as it is only while its target lies less far past
    // the plane than where that last failed (`deepest`: the farthest any target lies past its plane; each try of
    // every mode cost a third of a second a mouse move on CGAL's armadillo, strokes_real's stroke 67).
    double reach = 1.0, deepest = 0.0;
    const double merge = s_.mirrorMergeDistance(s_.drag_.brush);
    int crossedPlane = -1;
    for (size_t e = 0; e < pulls.size() && s_.drag_.brush.symmetry.any(); ++e) {
        if (!pulls[e].moving()) continue;
        for (int a = 0; a < 3; ++a) {
            if (!s_.drag_.brush.symmetry.mirror[static_cast<size_t>(a)]) continue;
            const Eigen::Vector3d normal = s_.drag_.symmetry.axes.col(a);
            const double from = (pulls[e].source - s_.drag_.symmetry.centre).dot(normal), to = from + pulls[e].pull.dot(normal);
            if (std::abs(from) > merge && (to == 0.0 || (to > 0.0) != (from > 0.0))) {
                const double atPlane = from / (from - to);  // the share of the pull on the plane, in (0, 1]
                deepest = std::max(deepest, std::abs(to));
                if (atPlane * (1.0 - 1.0 / 64.0) < reach) {
                    reach = atPlane * (1.0 - 1.0 / 64.0);
                    crossedPlane = a;
                }
            }
        }
    }
    StepFailure failure;
    // The mesh's vertices as the stroke began: those a move counts as moved (the ones its splits added, in this
    // move or an earlier one, are counted apart, as the stroke's end and its undo count them).
    const Eigen::Index rowsAtStart = std::min<Eigen::Index>(s_.drag_.rowsAtBegin, s_.mesh_.positions.rows());
    double share = 0.0;
    if (reach < 1.0 && deepest < s_.drag_.acrossFailedAt && applyBrushPulls(pulls, s_.drag_.brush, s_.drag_.operation.steps, report, failure, true) == 1.0) {
        share = reach = 1.0;
    } else if (reach < 1.0) {
        s_.drag_.acrossFailedAt = std::min(s_.drag_.acrossFailedAt, deepest);
        for (BrushPull& p : pulls) p.pull *= reach;
        failure = StepFailure{};
        share = reach * applyBrushPulls(pulls, s_.drag_.brush, s_.drag_.operation.steps, report, failure);
    } else {
        share = applyBrushPulls(pulls, s_.drag_.brush, s_.drag_.operation.steps, report, failure);
    }
    if (reach < 1.0 && (share == reach || failure.cause == StepFailure::Cause::Lattice || failure.cause == StepFailure::Cause::Triangles ||
                        failure.cause == StepFailure::Cause::Uncertified)) {
        failure.cause = StepFailure::Cause::MirrorPlane;  // (what stopped it short of the plane is the plane's)
        failure.plane = std::string(1, static_cast<char>('X' + crossedPlane));
    }
    // The vertices this update moved, among those the mesh had when the stroke began: the ones it split in under
    // the pull are report.verticesAdded (a trial read "1259 vertices moved" live, then "20 moved, 1272 added" at
    // the end; another, a later move's "1125 moved" after splits of earlier moves, then "416 moved, 702 added").
    const int movedHere = s_.lastMoved_.all ? static_cast<int>(rowsAtStart)
                                            : static_cast<int>(std::count_if(s_.lastMoved_.vertices.begin(), s_.lastMoved_.vertices.end(),
                                                                             [rowsAtStart](int v) { return v < rowsAtStart; }));
    for (size_t e = 0; e < s_.drag_.mirror.size(); ++e)
        s_.drag_.sourceWorld[e] = s_.drag_.strokeReached[e];
    recordAskedTargets(s_.drag_);
    report.fractionApplied = share;
    report.subSteps = s_.drag_.operation.injectiveSteps();
    report.controlPointsChanged = 0;
    for (const Step& step : s_.drag_.operation.steps) report.controlPointsChanged += static_cast<int>(step.delta.indices.size());
    report.verticesMoved = movedHere;
    report.injectivity = s_.injectivity_.mode == InjectivityMode::Off ? "not checked" : "injective";
    for (size_t e = 0; e < s_.drag_.mirror.size(); ++e)
        if (s_.drag_.mirror[e].images.front().second == 0) report.residuals.push_back((s_.drag_.sourceWorld[e] - targets[e]).norm());
    if (share == 1.0) {
        report.status = OpStatus::Applied;
        return;
    }
    detail::noteFailure(report, failure, true);
    // A stroke's lattice is the brush's own region, placed for each pull: what helps is the brush, not the cage.
    const std::string advice = failure.cause == StepFailure::Cause::Lattice
                                   ? "the pull is too steep for the brush there: try a larger radius, a smoother falloff or a shorter pull"
                                   : failure.cause == StepFailure::Cause::Triangles
                                         ? (s_.refinement_.settings.underBrush ? "try a larger radius or a shorter pull"
                                                                                : "try a larger radius or a shorter pull, or turn \"Split under the brush\" on")
                                         : stepFailureAdvice(failure.cause);
    if (share > 0.0) {
        report.status = OpStatus::Applied;
        report.reason = "Stopped at " + detail::percentText(share) + " of the pull, the last injective point: beyond it " +
                        report.failureWords + " (" + advice + ").";
        return;
    }
    report.status = OpStatus::Rejected;
    report.reason = failure.cause == StepFailure::Cause::SourceLeft
                        ? "Refused: " + failure.technical + "."
                        : "Refused: " + report.failureWords + ". The stroke stays where it was; " + advice + ".";
    report.injectivity = "rejected: " + failure.technical;
}

Status Stroke::updateControl(const Eigen::Vector3d& offset, OpReport& report) {
    // Every point moves by the same offset since the drag began.
    const Eigen::Index count = static_cast<Eigen::Index>(s_.drag_.operation.controlPoints.size());
    return updateControlPerPoint(offset.transpose().replicate(std::max<Eigen::Index>(count, 1), 1), report);
}

Status Stroke::updateControlPerPoint(const Eigen::MatrixX3d& offsets, OpReport& report) {
    const auto start = Clock::now();
    report = OpReport{};
    report.op = "move_control_point";
    if (!s_.drag_.active || s_.drag_.operation.kind != OperationKind::ControlPointEdit)
        return Status::error("no interactive control-point drag is in progress");
    if (!offsets.allFinite()) return Status::error("control point move has non-finite coordinates");
    const std::vector<int>& ids = s_.drag_.operation.controlPoints;
    const Eigen::Index count = static_cast<Eigen::Index>(ids.size());
    if (offsets.rows() != count)
        return Status::error("control point move has " + std::to_string(offsets.rows()) + " offsets for " + std::to_string(count) + " points");
    // Offsets as shown since the drag began; this update adds what is still missing.
    const Eigen::MatrixX3d shownIncrement = offsets - s_.drag_.operation.offsets;
    if ((shownIncrement.array() == 0.0).all()) {
        report.status = OpStatus::NoOp;
        report.reason = "the control points are already there";
        return Status::success();
    }
    ControlDelta delta;
    delta.indices = ids;
    if (s_.stack_.layers_.empty()) {
        delta.deltas = shownIncrement;
    } else {
        // Under layers the points follow the cursor as shown: each cage point goes where the layers take it
        // onto its shown start plus its offset.
        delta.deltas.resize(count, 3);
        for (Eigen::Index c = 0; c < count; ++c) {
            const Eigen::Vector3d shownTarget = s_.drag_.controlStart.row(c).transpose() + offsets.row(c).transpose();
            Eigen::Vector3d cageTarget;
            if (!s_.stack_.pullThroughLayers(shownTarget, cageTarget, s_.stack_.layers_.size())) {
                report.status = OpStatus::Rejected;
                report.reason = "Refused: no point of the lattice's layers maps onto " + vectorText(shownTarget) + ".";
                return Status::success();
            }
            delta.deltas.row(c) = (cageTarget - s_.stack_.lattice_.controlPoint(ids[static_cast<size_t>(c)])).transpose();
        }
    }
    applyControlDelta(std::move(delta), shownIncrement, report);
    report.wallMs = millisecondsSince(start);
    return Status::success();
}

void Stroke::applyControlDelta(ControlDelta delta, const Eigen::MatrixX3d& shownOffsets, OpReport& report) {
    // The points follow up to the last injective position and stop there (design.md "The cage is the user's
    // object"): never a fresh lattice. A later update that moves back lets them follow again.
    s_.lastMoved_.vertices.clear();
    s_.lastMoved_.all = false;
    expandWelds(s_.stack_.lattice_, delta);  // a welded point moves as one (Coquillart 1990, 3.1.2)
    StepFailure failure;
    const double fraction = s_.applyLargestInjectiveFraction(delta, &s_.lastMoved_.vertices, failure, report.injectivityMs, report.triangleCheckMs);
    report.fractionApplied = fraction;
    if (fraction > 0.0) {
        delta.deltas *= fraction;
        mergeStep(delta);
        s_.drag_.operation.offsets += fraction * shownOffsets;
    }
    std::sort(s_.lastMoved_.vertices.begin(), s_.lastMoved_.vertices.end());
    s_.lastMoved_.vertices.erase(std::unique(s_.lastMoved_.vertices.begin(), s_.lastMoved_.vertices.end()), s_.lastMoved_.vertices.end());
    report.injectivity = s_.injectivity_.mode == InjectivityMode::Off ? "not checked" : "injective";
    report.controlPointsChanged = fraction > 0.0 ? static_cast<int>(delta.indices.size()) : 0;
    report.verticesMoved = s_.movedCount();
    report.subSteps = fraction > 0.0 ? 1 : 0;
    report.status = fraction > 0.0 ? OpStatus::Applied : OpStatus::Rejected;
    if (fraction < 1.0) {
        detail::noteFailure(report, failure, false);
        report.reason = "Stopped " + stepStopWords(failure.cause) + ": moving further, " + report.failureWords + ".";
    }
}

Status Stroke::setLabel(const std::string& label) {
    if (!s_.drag_.active) return Status::error("no interactive drag is in progress");
    if (label.empty()) return Status::error("a history entry needs a name");
    s_.drag_.operation.label = label;
    return Status::success();
}

void Stroke::end() { finish(nullptr); }

void Stroke::finish(OpReport* report) {
    if (!s_.drag_.active) return;
    s_.drag_.active = false;
    s_.stack_.layerActive_ = false;  // the next operation starts in the cage
    s_.drag_.outsideCage = 0;
    if (!s_.drag_.operation.steps.empty()) {
        s_.refinement().afterEdit(s_.drag_.operation, report);
        if (s_.bakeLayers(s_.drag_.operation.steps)) s_.drag_.operation.steps.back().baked = true;  // the detail travels with the surface
        s_.pushOperation(std::move(s_.drag_.operation));
    } else {
        s_.refinement().remove(s_.drag_.operation.refinementBefore);  // split for a pull that moved nothing
    }
    s_.drag_.operation = Operation{};
}

Status Stroke::cancel(OpReport& report) {
    const auto start = Clock::now();
    report = OpReport{};
    report.op = "cancel_drag";
    if (!s_.drag_.active) {
        report.status = OpStatus::NoOp;
        report.reason = "no drag in progress";
        return Status::success();
    }
    s_.drag_.active = false;
    s_.revertSteps(s_.drag_.operation.steps);
    s_.refinement().remove(s_.drag_.operation.refinementBefore);  // the triangles split under its pull
    s_.stack_.layerActive_ = false;
    // Taking it back is an inverse manipulation, exact only up to rounding: the replay repeats it.
    if (!s_.drag_.operation.steps.empty()) s_.history_.note(JournalEntry{JournalEntry::Kind::CancelledDrag, s_.drag_.operation, 0, {}, {}, {}}, false);
    report.status = s_.drag_.operation.steps.empty() ? OpStatus::NoOp : OpStatus::Applied;
    report.reason = s_.drag_.operation.steps.empty() ? "the drag had not moved anything" : "the drag was taken back";
    report.subSteps = s_.drag_.operation.injectiveSteps();
    report.verticesMoved = s_.movedCount();
    s_.drag_.operation = Operation{};
    report.wallMs = millisecondsSince(start);
    return Status::success();
}

}  // namespace sculpt::core
