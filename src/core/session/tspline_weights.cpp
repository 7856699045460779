// Sculpting by weights on the frozen weighted T-spline (Song & Yang 2005, "Free-form deformation with weighted
// T-spline", sec. 1 and 6 step 4, after Noble & Gordon 1999): set_weights, the hammer and the crimp, each one
// history operation (tspline_tools.h, TSplineTools::sculptWeights, states the definitions; weight_sculpt.h the closed form).
//
// What a weight change does to the frame. The mesh is x_v = Q(P; W)(t_v) at its frozen parameters (eq. 5),
// stored as the rest row X0_v = Q(P0; W)(t_v) plus the displacement sum R_s(t_v; W) delta_s. New weights W'
// move the mesh to Q(P; W')(t_v), so the rest row becomes X0_v + Q(P0; W')(t_v) - Q(P0; W)(t_v) (Q(P0; W')(t_v)
// up to rounding): the frame stays one volume, rest and deformed, with one set of weights, and the mesh's map
// from where it was frozen is Q(P; W') o Q(P0; W)^-1, injective when det dQ(P; W')/dt > 0 (Gain & Dodgson 2001)
// -- what the cells' test checks -- and the rest volume Q(P0; W') stays injective so points can still be frozen.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/volume/embedding.h"
#include "core/injectivity/injectivity.h"
#include "core/session/session.h"
#include "core/session/session_internal.h"
#include "core/tspline/tspline_view.h"
#include "core/deform/vertex_normals.h"
#include "core/tspline/weight_sculpt.h"

namespace sculpt::core {

using detail::Clock;
using detail::millisecondsSince;
using detail::percentText;

// What the hammer and crimp act on (TSplineTools::weightBump).
struct WeightBump {
    const TSplineVolume* volume = nullptr;
    std::vector<int> controlPoints;       // S, ascending
    Eigen::Vector3d direction = Eigen::Vector3d::Zero();
    bool hasBump = false;                 // b(t_p) != 0
    BumpSums sums;
    size_t picked = 0;                    // the picked vertex's entry in sums
    std::vector<int> triangleIds;         // triangles with a vertex in the support
    std::vector<double> heights;          // #V: the current height of every vertex of those triangles (else 0)
};

namespace {

const TSplineVolume* asTSpline(const Lattice& lattice) { return lattice.volume ? lattice.volume->tsplineVolume() : nullptr; }

std::string numberText(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.6g", value);
    return text;
}

// The control points shown and picked (Song & Yang 2005 sec. 4, Fig. 10; tspline_view.h): those of the cells
// holding the mesh, classified as the weights were set, less the boundary copies (which carry the outer faces).
// What to try instead when the hammer or the crimp would fold the lattice or cross triangles. A hammer moves a
// few control points along the normal: the fold comes from moving them far against their neighbours.
std::string weightToolAdvice(StepFailure::Cause cause, bool hammer) {
    if (hammer && cause == StepFailure::Cause::Lattice)
        return "a larger radius spreads the raise over more control points, or subdivide the cells there";
    return stepFailureAdvice(cause);
}

std::vector<std::uint8_t> shownControlPoints(const TSplineVolume& volume, const Positions& rest) {
    std::vector<std::uint8_t> shown = controlPointsOfCells(volume.basis(), nonEmptyTSplineCells(volume, rest));
    for (size_t s = 0; s < shown.size(); ++s)
        if (volume.onOuterSurface(static_cast<int>(s))) shown[s] = 0;
    return shown;
}

}  // namespace

std::vector<int> TSplineTools::visiblePoints() const {
    std::vector<int> ids;
    const TSplineVolume* volume = s_.tools_.frozen >= 0 ? asTSpline(s_.stack_.lattice_) : nullptr;
    if (!volume) return ids;
    const std::vector<std::uint8_t> visible = shownControlPoints(*volume, s_.mesh_.rest);
    for (size_t s = 0; s < visible.size(); ++s)
        if (visible[s]) ids.push_back(static_cast<int>(s));
    return ids;
}

// ---- the bump --------------------------------------------------------------------------------------------

Status TSplineTools::weightBump(const WeightToolSettings& settings, WeightBump& out) const {
    out = WeightBump{};
    const TSplineVolume* volume = s_.tools_.frozen >= 0 ? asTSpline(s_.stack_.lattice_) : nullptr;
    if (!volume)
        return Status::error("no weighted T-spline lattice is frozen: set one up first (setup_tspline, or T-spline in the Lattices panel)");
    out.volume = volume;
    const TSplineBasis& basis = volume->basis();
    const int vertexCount = static_cast<int>(s_.mesh_.positions.rows());
    if (settings.vertex < 0 || settings.vertex >= vertexCount)
        return Status::error("vertex: " + std::to_string(settings.vertex) + " is not a vertex of the mesh (0 to " + std::to_string(vertexCount - 1) + ")");
    if (!std::isfinite(settings.radius) || settings.radius < 0.0) return Status::error("radius: expected a finite number >= 0");
    // The picked vertex's element and parameters, as frozen.
    int pickedElement = -1, pickedEntry = -1;
    for (int e = 0; e < basis.elementCount() && pickedElement < 0; ++e)
        for (int s = s_.stack_.embedding_.cellStart[static_cast<size_t>(e)]; s < s_.stack_.embedding_.cellStart[static_cast<size_t>(e) + 1]; ++s)
            if (s_.stack_.embedding_.order[static_cast<size_t>(s)] == settings.vertex) {
                pickedElement = e;
                pickedEntry = s;
                break;
            }
    if (pickedElement < 0)
        return Status::error("vertex: " + std::to_string(settings.vertex) + " is outside the T-spline lattice (it does not move with it)");
    const Eigen::Vector3d tp = embeddedParameters(s_.stack_.lattice_, s_.stack_.embedding_, pickedElement, pickedEntry);
    const std::vector<double>& weights = volume->controlWeights();
    std::vector<double> blending(static_cast<size_t>(basis.maxSupport));
    basis.blendingValues(pickedElement, tp, blending.data(), nullptr);
    const int* support = basis.supportIds.data() + basis.supportStart[static_cast<size_t>(pickedElement)];
    const int supportCount = basis.supportStart[static_cast<size_t>(pickedElement) + 1] - basis.supportStart[static_cast<size_t>(pickedElement)];

    // S: the control points of the bump.
    const std::vector<std::uint8_t> visible = shownControlPoints(*volume, s_.mesh_.rest);
    const Eigen::Vector3d pickedRest = s_.mesh_.rest.row(settings.vertex).transpose();
    if (settings.controlPoint >= 0) {
        if (settings.controlPoint >= volume->controlPointCount())
            return Status::error("control_point: " + std::to_string(settings.controlPoint) + " is not a control point of the T-spline (0 to " +
                                 std::to_string(volume->controlPointCount() - 1) + ")");
        if (!visible[static_cast<size_t>(settings.controlPoint)])
            return Status::error("control_point: " + std::to_string(settings.controlPoint) +
                                 " is a hidden control point (of no non-empty cell, or on the outer faces): it serves the parametrization only");
        bool reaches = false;
        for (int c = 0; c < supportCount; ++c) reaches = reaches || (support[c] == settings.controlPoint && blending[static_cast<size_t>(c)] > 0.0);
        if (!reaches)
            return Status::error("control_point: " + std::to_string(settings.controlPoint) + " has no influence at vertex " + std::to_string(settings.vertex));
        out.controlPoints = {settings.controlPoint};
    } else {
        // The strongest: the control point whose displacement moves the vertex most (the one that made the
        // bump there), or with no bump yet the one whose R_s is largest there.
        int strongest = -1, strongestPull = -1;
        double strongestValue = 0.0, strongestPullValue = 0.0;
        for (int c = 0; c < supportCount; ++c) {
            const int s = support[c];
            const double r = weights[static_cast<size_t>(s)] * blending[static_cast<size_t>(c)];
            // note: the boundary copies carry the lattice's outer faces; a local tool leaves them where they are.
            if (!visible[static_cast<size_t>(s)] || !(r > 0.0) || volume->onOuterSurface(s) || s_.stack_.lattice_.pinned[static_cast<size_t>(s)]) continue;
            if (r > strongestValue) {
                strongestValue = r;
                strongest = s;
            }
            const double pull = r * s_.stack_.lattice_.displacement.row(s).norm();
            if (pull > strongestPullValue) {
                strongestPullValue = pull;
                strongestPull = s;
            }
            // At rest (the control point's rest position, the vertex's rest position): the same points are
            // chosen however far the bump has grown.
            if (settings.radius > 0.0 && (s_.stack_.lattice_.restControlPoint(s) - pickedRest).norm() <= settings.radius)
                out.controlPoints.push_back(s);
        }
        if (strongest < 0) return Status::error("vertex: no visible control point influences vertex " + std::to_string(settings.vertex));
        if (strongestPull >= 0) strongest = strongestPull;
        if (std::find(out.controlPoints.begin(), out.controlPoints.end(), strongest) == out.controlPoints.end()) out.controlPoints.push_back(strongest);
        std::sort(out.controlPoints.begin(), out.controlPoints.end());
    }
    for (int s : out.controlPoints)
        if (s_.stack_.lattice_.pinned[static_cast<size_t>(s)]) return Status::error("control point " + std::to_string(s) + " is pinned");

    // The sums of weight_sculpt.h over the vertices of the elements S reaches.
    std::vector<std::uint8_t> inS(static_cast<size_t>(volume->controlPointCount()), 0);
    for (int s : out.controlPoints) inS[static_cast<size_t>(s)] = 1;
    const std::vector<int> cells = cellsInfluencedBy(s_.stack_.lattice_, out.controlPoints);
    BumpSums& sums = out.sums;
    for (int e : cells) {
        const int* ids = basis.supportIds.data() + basis.supportStart[static_cast<size_t>(e)];
        const int count = basis.supportStart[static_cast<size_t>(e) + 1] - basis.supportStart[static_cast<size_t>(e)];
        for (int s = s_.stack_.embedding_.cellStart[static_cast<size_t>(e)]; s < s_.stack_.embedding_.cellStart[static_cast<size_t>(e) + 1]; ++s) {
            const Eigen::Vector3d t = embeddedParameters(s_.stack_.lattice_, s_.stack_.embedding_, e, s);
            basis.blendingValues(e, t, blending.data(), nullptr);
            double others = 0.0, own = 0.0;
            Eigen::Vector3d othersDisplacement = Eigen::Vector3d::Zero(), ownDisplacement = Eigen::Vector3d::Zero();
            for (int c = 0; c < count; ++c) {
                const double wb = weights[static_cast<size_t>(ids[c])] * blending[static_cast<size_t>(c)];
                const Eigen::Vector3d d = s_.stack_.lattice_.displacement.row(ids[c]).transpose();
                if (inS[static_cast<size_t>(ids[c])]) {
                    own += wb;
                    ownDisplacement += wb * d;
                } else {
                    others += wb;
                    othersDisplacement += wb * d;
                }
            }
            if (s_.stack_.embedding_.order[static_cast<size_t>(s)] == settings.vertex) out.picked = sums.vertices.size();
            sums.vertices.push_back(s_.stack_.embedding_.order[static_cast<size_t>(s)]);
            sums.others.push_back(others);
            sums.own.push_back(own);
            sums.othersDisplacement.push_back(othersDisplacement);
            sums.ownDisplacement.push_back(ownDisplacement);
        }
    }
    // The direction: the bump's own at the picked vertex, else the surface normal there.
    const size_t p = out.picked;
    const Eigen::Vector3d bump = sums.ownDisplacement[p] / (sums.others[p] + sums.own[p]);
    out.hasBump = bump.norm() > 1e-12 * s_.stack_.lattice_.diagonal();
    if (out.hasBump) {
        out.direction = bump.normalized();
    } else {
        Positions normals;
        computeVertexNormals(s_.mesh_.positions, s_.mesh_.triangles, normals);
        out.direction = normals.row(settings.vertex).transpose();
    }
    // Heights of every vertex of the triangles that touch the support: the closed form inside it, the
    // output's displacement along n outside (they do not change).
    std::vector<std::uint8_t> inSupport(static_cast<size_t>(vertexCount), 0);
    for (int v : sums.vertices) inSupport[static_cast<size_t>(v)] = 1;
    out.heights.assign(static_cast<size_t>(vertexCount), 0.0);
    const Positions& output = s_.stack_.cageUnderLayers() ? s_.stack_.cageOut_ : s_.mesh_.positions;
    for (Eigen::Index f = 0; f < s_.mesh_.triangles.rows(); ++f) {
        bool touches = false;
        for (int k = 0; k < 3; ++k) touches = touches || inSupport[static_cast<size_t>(s_.mesh_.triangles(f, k))];
        if (!touches) continue;
        out.triangleIds.push_back(static_cast<int>(f));
        for (int k = 0; k < 3; ++k) {
            const int v = s_.mesh_.triangles(f, k);
            out.heights[static_cast<size_t>(v)] = out.direction.dot((output.row(v) - s_.mesh_.rest.row(v)).transpose());
        }
    }
    for (size_t c = 0; c < sums.vertices.size(); ++c)
        out.heights[static_cast<size_t>(sums.vertices[c])] = bumpHeight(sums, c, out.direction, 1.0, 1.0, 0.0);
    return Status::success();
}

Status TSplineTools::bumpAt(const WeightToolSettings& settings, Bump& out) const {
    WeightBump bump;
    if (Status s = weightBump(settings, bump); !s) return s;
    out = Bump{};
    out.controlPoints = bump.controlPoints;
    out.direction = bump.direction;
    out.vertices = bump.sums.vertices;
    for (int v : out.vertices) out.heights.push_back(bump.heights[static_cast<size_t>(v)]);
    const double peak = bump.heights[static_cast<size_t>(settings.vertex)];
    if (bump.hasBump && peak > 0.0) out.width = equivalentDiameter(s_.mesh_.rest, s_.mesh_.triangles, bump.triangleIds, bump.heights, 0.5 * peak);
    return Status::success();
}

// ---- the operation ---------------------------------------------------------------------------------------

Status TSplineTools::sculptWeights(const WeightToolSettings& settings, OpReport& report) {
    const auto start = Clock::now();
    report = OpReport{};
    using Tool = WeightToolSettings::Tool;
    report.op = settings.tool == Tool::SetWeights ? "set_weights" : settings.tool == Tool::Hammer ? "hammer" : "crimp";
    if (s_.mesh().empty()) return Status::error("no mesh is loaded");
    if (s_.drag_.active) return Status::error("an interactive drag is in progress");
    const TSplineVolume* volume = s_.tools_.frozen >= 0 ? asTSpline(s_.stack_.lattice_) : nullptr;
    if (!volume)
        return Status::error("no weighted T-spline lattice is frozen: set one up first (setup_tspline, or T-spline in the Lattices panel)");
    const std::vector<double>& weights = volume->controlWeights();
    Step step;
    step.settings = s_.stack_.settings_;
    std::string label;

    if (settings.tool == Tool::SetWeights) {
        if (settings.ids.empty()) return Status::error("ids: no control point given");
        if (settings.ids.size() != settings.weights.size()) return Status::error("weights: expected one weight per id");
        std::vector<std::pair<int, double>> changes;
        for (size_t c = 0; c < settings.ids.size(); ++c) {
            const int id = settings.ids[c];
            if (id < 0 || id >= volume->controlPointCount())
                return Status::error("ids[" + std::to_string(c) + "]: " + std::to_string(id) + " is not a control point of the T-spline (0 to " +
                                     std::to_string(volume->controlPointCount() - 1) + ")");
            if (!std::isfinite(settings.weights[c]) || !(settings.weights[c] > 0.0))
                return Status::error("weights[" + std::to_string(c) + "]: expected a finite number > 0");
            changes.emplace_back(id, settings.weights[c]);
        }
        std::stable_sort(changes.begin(), changes.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
        for (size_t c = 1; c < changes.size(); ++c)
            if (changes[c].first == changes[c - 1].first) return Status::error("ids: control point " + std::to_string(changes[c].first) + " is listed twice");
        for (const auto& [id, w] : changes) {
            if (w == weights[static_cast<size_t>(id)]) continue;
            step.weights.ids.push_back(id);
            step.weights.before.push_back(weights[static_cast<size_t>(id)]);
            step.weights.after.push_back(w);
        }
        label = "set " + std::to_string(changes.size()) + (changes.size() == 1 ? " weight" : " weights");
    } else {
        WeightBump bump;
        if (Status s = weightBump(settings, bump); !s) return s;
        const BumpSums& sums = bump.sums;
        const size_t p = bump.picked;
        const Eigen::Vector3d& n = bump.direction;
        const double height = bump.heights[static_cast<size_t>(settings.vertex)];
        // n.b(t_p): the part of the height the bump's control points carry.
        const double own = n.dot(sums.ownDisplacement[p]) / (sums.others[p] + sums.own[p]);
        const double share = sums.own[p] / (sums.others[p] + sums.own[p]);  // sum_{s in S} R_s(t_p)
        double lambda = 1.0, mu = 0.0;
        if (settings.tool == Tool::Hammer) {
            if (settings.hasHeight ? !std::isfinite(settings.height) : !std::isfinite(settings.scale))
                return Status::error(settings.hasHeight ? "height: expected a finite number" : "scale: expected a finite number");
            if (!settings.hasHeight && !bump.hasBump)
                return Status::error("scale: there is no bump at vertex " + std::to_string(settings.vertex) + " to scale: give a height to raise one");
            const double target = settings.hasHeight ? settings.height : height + (settings.scale - 1.0) * own;
            if (bump.hasBump) lambda = 1.0 + (target - height) / own;
            else mu = (target - height) / share;
            label = "hammer";
        } else {
            if (!std::isfinite(settings.widthFactor) || !(settings.widthFactor > 0.0))
                return Status::error("width_factor: expected a finite number > 0");
            if (!bump.hasBump || !(height > 0.0))
                return Status::error("vertex: there is no raised bump at vertex " + std::to_string(settings.vertex) +
                                     " to crimp (raise one with the hammer first)");
            // lambda(beta) keeps H_p: (n.a + beta lambda n.c) / (A + beta C) = H_p at the picked vertex.
            const double na = n.dot(sums.othersDisplacement[p]), nc = n.dot(sums.ownDisplacement[p]);
            const auto lambdaFor = [&](double beta) { return (height * (sums.others[p] + beta * sums.own[p]) - na) / (beta * nc); };
            // The width of the part of the surface (as it is before the crimp) that ends at or above half height:
            // which surface points the bump lifts. (The rest surface itself moves with the weights, eq. 5's pull
            // towards the control points; measured on it the reach of one weight would be much smaller.)
            std::vector<double> heights = bump.heights, inSupport;
            const auto widthFor = [&](double beta) {
                bumpHeights(sums, n, beta, lambdaFor(beta), 0.0, inSupport);
                for (size_t c = 0; c < sums.vertices.size(); ++c) heights[static_cast<size_t>(sums.vertices[c])] = inSupport[c];
                return equivalentDiameter(s_.mesh_.rest, s_.mesh_.triangles, bump.triangleIds, heights, 0.5 * height);
            };
            const double before = widthFor(1.0);
            if (!(before > 0.0)) return Status::error("vertex: the bump at vertex " + std::to_string(settings.vertex) + " has no width at half height");
            double beta = 1.0;
            if (Status s = solveCrimpFactor(widthFor, settings.widthFactor * before, 1.0 / 64.0, 64.0, beta); !s)
                return Status::error("width_factor: " + s.message + " (x" + numberText(settings.widthFactor) + " of " + numberText(before) + ")");
            lambda = lambdaFor(beta);
            for (int s : bump.controlPoints) {
                step.weights.ids.push_back(s);
                step.weights.before.push_back(weights[static_cast<size_t>(s)]);
                step.weights.after.push_back(beta * weights[static_cast<size_t>(s)]);
            }
            label = "crimp";
        }
        for (int s : bump.controlPoints) {
            const Eigen::Vector3d d = (lambda - 1.0) * s_.stack_.lattice_.displacement.row(s).transpose() + mu * n;
            if (d.isZero(0.0)) continue;
            step.delta.indices.push_back(s);
            step.delta.deltas.conservativeResize(step.delta.deltas.rows() + 1, 3);
            step.delta.deltas.row(step.delta.deltas.rows() - 1) = d.transpose();
        }
        if (!step.delta.deltas.allFinite()) return Status::error("the bump at vertex " + std::to_string(settings.vertex) + " cannot be scaled there");
        label += bump.controlPoints.size() == 1 ? " (control point " + std::to_string(bump.controlPoints.front()) + ")"
                                                : " (" + std::to_string(bump.controlPoints.size()) + " control points)";
    }
    if (step.weights.empty() && step.delta.indices.empty()) {
        report.status = OpStatus::NoOp;
        report.reason = "nothing changes";
        report.wallMs = millisecondsSince(start);
        return Status::success();
    }
    if (Status s = applyTool(settings, std::move(step), label, report); !s) return s;
    report.wallMs = millisecondsSince(start);
    return Status::success();
}

Status TSplineTools::applyTool(const WeightToolSettings& settings, Step step, const std::string& label, OpReport& report) {
    s_.stack_.layerActive_ = false;
    s_.lastMoved_.vertices.clear();
    s_.lastMoved_.all = false;
    std::vector<int> moved;
    StepFailure failure;
    bool applied = false;
    double fraction = 1.0;
    if (step.weights.empty()) {
        // The hammer: a control displacement of the bump's points, all scaled by one factor, so any part of it is
        // the same bump at a smaller height. Where the whole raise would fold the lattice, the bump stops at the
        // largest injective part (as a control-point edit does) and the report says how far it got.
        fraction = s_.applyLargestInjectiveFraction(step.delta, &moved, failure, report.injectivityMs, report.triangleCheckMs);
        applied = fraction > 0.0;
        step.delta.deltas *= fraction;
    } else {
        if (Status s = applyStep(step, &moved); !s) {
            report.status = OpStatus::Rejected;
            report.refusedBy = "lattice";
            report.reason = "refused: " + s.message + "; nothing was changed";
            report.injectivity = "rejected: " + s.message;
            return Status::success();
        }
        applied = true;
        const WeightUndo& undo = *step.weightUndo;  // its rows are the positions before (moved lists its vertices)
        // The same checks as a control displacement's (tryDelta): the cells the weights and displacements reach,
        // then no new triangle crossing among the vertices moved.
        std::vector<int> ids = step.weights.ids;
        ids.insert(ids.end(), step.delta.indices.begin(), step.delta.indices.end());
        applied = s_.certifyCells(s_.stack_.lattice_, cellsInfluencedBy(s_.stack_.lattice_, ids), failure, report.injectivityMs);
        if (applied && s_.injectivity_.mode != InjectivityMode::Off && s_.injectivity_.checkTriangles && s_.mesh_.triangles.rows() > 0) {
            if (s_.before_.rows() != s_.mesh_.positions.rows()) s_.before_.resize(s_.mesh_.positions.rows(), 3);
            for (size_t c = 0; c < undo.vertices.size(); ++c) s_.before_.row(undo.vertices[c]) = undo.positions.row(static_cast<Eigen::Index>(c));
            applied = s_.noNewCrossing(moved, failure, report.injectivityMs, report.triangleCheckMs);
        }
        if (!applied) revertStep(step, nullptr);
    }
    if (!applied) {
        report.status = OpStatus::Rejected;
        detail::noteFailure(report, failure, false);
        report.reason = "refused: " + std::string(step.weights.empty() ? "even a small part of " : "") + "this " + label + ", " +
                        report.failureWords + "; nothing was changed (" + weightToolAdvice(failure.cause, step.weights.empty()) + ")";
        report.injectivity = "rejected: " + failure.technical;
        return Status::success();
    }
    Operation operation;
    operation.kind = OperationKind::WeightEdit;
    operation.label = label;
    operation.weightTool = settings;
    report.controlPointsChanged = static_cast<int>(std::max(step.weights.ids.size(), step.delta.indices.size()));
    operation.steps.push_back(std::move(step));
    s_.pushOperation(std::move(operation));
    s_.reportSingleStep(std::move(moved), report);
    report.reason = label + ": " + std::to_string(report.verticesMoved) + " vertices moved";
    report.fractionApplied = fraction;
    if (fraction < 1.0) {
        detail::noteFailure(report, failure, false);
        report.reason += "; stopped at " + percentText(fraction) + " of the change asked (beyond it " + report.failureWords + "; " +
                         weightToolAdvice(failure.cause, true) + ")";
    }
    return Status::success();
}

// ---- applying and undoing a weight change ----------------------------------------------------------------

Status TSplineTools::checkRecordedWeights(const WeightChange& change) const {
    const TSplineVolume* volume = s_.tools_.frozen >= 0 ? asTSpline(s_.stack_.lattice_) : nullptr;
    if (!volume) return Status::error("a weight change needs a frozen weighted T-spline lattice");
    if (change.before.size() != change.ids.size() || change.after.size() != change.ids.size())
        return Status::error("weights: expected one weight before and after per id");
    for (size_t c = 0; c < change.ids.size(); ++c) {
        const int id = change.ids[c];
        if (id < 0 || id >= volume->controlPointCount() || (c > 0 && id <= change.ids[c - 1]))
            return Status::error("weights: control point ids must be ascending, each once, in the T-spline");
        if (!std::isfinite(change.after[c]) || !(change.after[c] > 0.0)) return Status::error("weights: expected finite weights > 0");
        if (change.before[c] != volume->controlWeights()[static_cast<size_t>(id)])
            return Status::error("weights: control point " + std::to_string(id) + " has weight " + numberText(volume->controlWeights()[static_cast<size_t>(id)]) +
                                 ", the recording expected " + numberText(change.before[c]));
    }
    return Status::success();
}

Status TSplineTools::applyStep(const Step& step, std::vector<int>* moved) {
    const TSplineVolume* old = asTSpline(s_.stack_.lattice_);
    if (!old) return Status::error("a weight change needs a frozen weighted T-spline lattice");
    std::vector<double> weights = old->controlWeights();
    for (size_t c = 0; c < step.weights.ids.size(); ++c) weights[static_cast<size_t>(step.weights.ids[c])] = step.weights.after[c];
    std::shared_ptr<const TSplineVolume> fresh;
    if (Status s = TSplineVolume::make(old->sharedBasis(), old->restControlPoints(), std::move(weights), fresh); !s)
        return Status::error("these weights: " + s.message);

    auto undo = std::make_shared<WeightUndo>();
    undo->volume = s_.stack_.lattice_.volume;
    std::vector<int> ids = step.weights.ids;
    ids.insert(ids.end(), step.delta.indices.begin(), step.delta.indices.end());
    for (int e : cellsInfluencedBy(s_.stack_.lattice_, ids))
        for (int s = s_.stack_.embedding_.cellStart[static_cast<size_t>(e)]; s < s_.stack_.embedding_.cellStart[static_cast<size_t>(e) + 1]; ++s) {
            undo->vertices.push_back(s_.stack_.embedding_.order[static_cast<size_t>(s)]);
            undo->entries.push_back(s);
        }
    const bool layered = s_.stack_.cageUnderLayers();
    Positions& output = s_.activeOutput();
    const Eigen::Index count = static_cast<Eigen::Index>(undo->vertices.size());
    undo->rest.resize(count, 3);
    undo->positions.resize(count, 3);
    if (layered) undo->output.resize(count, 3);
    for (Eigen::Index c = 0; c < count; ++c) {
        const int v = undo->vertices[static_cast<size_t>(c)];
        undo->rest.row(c) = s_.mesh_.rest.row(v);
        undo->positions.row(c) = s_.mesh_.positions.row(v);
        if (layered) undo->output.row(c) = s_.stack_.cageOut_.row(v);
        if (s_.trackJacobian_) undo->jacobian.push_back(s_.frozenJacobian_[static_cast<size_t>(v)]);
    }
    undo->displacement.indices = step.delta.indices;
    undo->displacement.deltas.resize(static_cast<Eigen::Index>(step.delta.indices.size()), 3);
    for (size_t c = 0; c < step.delta.indices.size(); ++c)
        undo->displacement.deltas.row(static_cast<Eigen::Index>(c)) = s_.stack_.lattice_.displacement.row(step.delta.indices[c]);

    // The new volume in the frame, the tool list and the settings (a later set-up freezes it as it is now).
    s_.stack_.lattice_.volume = fresh;
    s_.stack_.lattice_.weights = fresh->controlWeights();
    s_.stack_.lattice_.rational = fresh->isRational();
    s_.stack_.settings_.volume = fresh;
    s_.tools_.list[static_cast<size_t>(s_.tools_.frozen)].volume = fresh;
    applyControlDelta(s_.stack_.lattice_, step.delta, 1.0);
    // Rest rows rebased, outputs evaluated again (file comment), per element.
    const std::vector<int> cells = cellsInfluencedBy(s_.stack_.lattice_, ids);
    const int cellCount = static_cast<int>(cells.size());
#pragma omp parallel for schedule(dynamic, 8) if (cellCount > 64)
    for (int k = 0; k < cellCount; ++k) {
        const int e = cells[static_cast<size_t>(k)];
        for (int s = s_.stack_.embedding_.cellStart[static_cast<size_t>(e)]; s < s_.stack_.embedding_.cellStart[static_cast<size_t>(e) + 1]; ++s) {
            const int v = s_.stack_.embedding_.order[static_cast<size_t>(s)];
            const Eigen::Vector3d t = embeddedParameters(s_.stack_.lattice_, s_.stack_.embedding_, e, s);
            Eigen::Vector3d restBefore, restAfter;
            Eigen::Matrix3d derivativeBefore, derivativeAfter;
            old->evaluate(old->restControlPoints(), t, restBefore, s_.trackJacobian_ ? &derivativeBefore : nullptr);
            fresh->evaluate(fresh->restControlPoints(), t, restAfter, s_.trackJacobian_ ? &derivativeAfter : nullptr);
            s_.mesh_.rest.row(v) += (restAfter - restBefore).transpose();
            s_.stack_.embedding_.restX[static_cast<size_t>(s)] = s_.mesh_.rest(v, 0);  // the evaluation kernels read the rest rows here
            s_.stack_.embedding_.restY[static_cast<size_t>(s)] = s_.mesh_.rest(v, 1);
            s_.stack_.embedding_.restZ[static_cast<size_t>(s)] = s_.mesh_.rest(v, 2);
            output.row(v) = s_.mesh_.rest.row(v) + displacementAt(s_.stack_.lattice_, t).transpose();
            if (s_.trackJacobian_) s_.frozenJacobian_[static_cast<size_t>(v)] *= derivativeAfter.determinant() / derivativeBefore.determinant();
        }
    }
    if (layered) s_.refreshLayerOutput(undo->vertices);
    ++s_.mesh_.restVersion;  // the rest surface moved with the weights
    s_.positionsChanged(&undo->vertices);
    if (moved) moved->insert(moved->end(), undo->vertices.begin(), undo->vertices.end());
    step.weightUndo = std::move(undo);
    return Status::success();
}

void TSplineTools::revertStep(const Step& step, std::vector<int>* moved) {
    const std::shared_ptr<WeightUndo> undo = step.weightUndo;
    if (!undo) return;
    for (size_t c = 0; c < undo->displacement.indices.size(); ++c)
        s_.stack_.lattice_.displacement.row(undo->displacement.indices[c]) = undo->displacement.deltas.row(static_cast<Eigen::Index>(c));
    s_.stack_.lattice_.volume = undo->volume;
    ++s_.mesh_.restVersion;
    s_.stack_.lattice_.weights = undo->volume->controlWeights();
    s_.stack_.lattice_.rational = undo->volume->isRational();
    s_.stack_.settings_.volume = undo->volume;
    s_.tools_.list[static_cast<size_t>(s_.tools_.frozen)].volume = undo->volume;
    const bool layered = undo->output.rows() > 0;
    for (size_t c = 0; c < undo->vertices.size(); ++c) {
        const int v = undo->vertices[c];
        const Eigen::Index row = static_cast<Eigen::Index>(c);
        s_.mesh_.rest.row(v) = undo->rest.row(row);
        const size_t entry = static_cast<size_t>(undo->entries[c]);
        s_.stack_.embedding_.restX[entry] = s_.mesh_.rest(v, 0);
        s_.stack_.embedding_.restY[entry] = s_.mesh_.rest(v, 1);
        s_.stack_.embedding_.restZ[entry] = s_.mesh_.rest(v, 2);
        s_.mesh_.positions.row(v) = undo->positions.row(row);
        if (layered) s_.stack_.cageOut_.row(v) = undo->output.row(row);
        if (!undo->jacobian.empty()) s_.frozenJacobian_[static_cast<size_t>(v)] = undo->jacobian[c];
    }
    s_.positionsChanged(&undo->vertices);
    if (moved) moved->insert(moved->end(), undo->vertices.begin(), undo->vertices.end());
    step.weightUndo.reset();
}

}  // namespace sculpt::core
