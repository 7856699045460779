// Session: the mesh, the commands (drag, drag_vertex, control point moves, lattice set-up) and the inverse
// of a deformation (Hu et al. 2001, section 4; design.md "Two kinds of composition"). InjectSubdiv and the
// certification of each step: session_certify.cpp.
#include "core/session/session.h"

#include <algorithm>
#include <cstdio>
#include <chrono>
#include <cmath>
#include <string>

#include <Eigen/LU>

#include "core/deform/brush_field.h"
#include "core/injectivity/injectivity.h"
#include "core/volume/lattice_boundary.h"
#include "core/session/session_internal.h"
#include "core/injectivity/triangle_pair.h"

namespace sculpt::core {

using detail::Clock;
using detail::mergeDelta;
using detail::millisecondsSince;
using detail::percentText;
using detail::vectorText;

namespace detail {

double millisecondsSince(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

std::string percentText(double fraction) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.1f%%", 100.0 * fraction);
    return buffer;
}

std::string vectorText(const Eigen::Vector3d& v) {
    char buffer[128];
    std::snprintf(buffer, sizeof buffer, "(%g, %g, %g)", v.x(), v.y(), v.z());
    return buffer;
}

// Adds b into a (sorted unions of control point ids).
void mergeDelta(ControlDelta& a, const ControlDelta& b) {
    ControlDelta merged;
    merged.deltas.resize(static_cast<Eigen::Index>(a.indices.size() + b.indices.size()), 3);
    size_t i = 0, j = 0;
    Eigen::Index row = 0;
    while (i < a.indices.size() || j < b.indices.size()) {
        if (j == b.indices.size() || (i < a.indices.size() && a.indices[i] < b.indices[j])) {
            merged.indices.push_back(a.indices[i]);
            merged.deltas.row(row++) = a.deltas.row(static_cast<Eigen::Index>(i++));
        } else if (i == a.indices.size() || b.indices[j] < a.indices[i]) {
            merged.indices.push_back(b.indices[j]);
            merged.deltas.row(row++) = b.deltas.row(static_cast<Eigen::Index>(j++));
        } else {
            merged.indices.push_back(a.indices[i]);
            merged.deltas.row(row++) = a.deltas.row(static_cast<Eigen::Index>(i++)) + b.deltas.row(static_cast<Eigen::Index>(j++));
        }
    }
    merged.deltas.conservativeResize(row, 3);
    a = std::move(merged);
}

}  // namespace detail

namespace {

// FNV-1a (64 bit) over the positions' bits and the triangle ids, with the counts: names a mesh exactly.
std::string fingerprint(const Positions& positions, const Triangles& triangles) {
    std::uint64_t hash = 1469598103934665603ull;
    const auto add = [&hash](const void* data, size_t bytes) {
        const auto* p = static_cast<const unsigned char*>(data);
        for (size_t i = 0; i < bytes; ++i) hash = (hash ^ p[i]) * 1099511628211ull;
    };
    const std::int64_t counts[2] = {static_cast<std::int64_t>(positions.rows()), static_cast<std::int64_t>(triangles.rows())};
    add(counts, sizeof counts);
    add(positions.data(), static_cast<size_t>(positions.size()) * sizeof(double));
    add(triangles.data(), static_cast<size_t>(triangles.size()) * sizeof(int));
    char text[32];
    std::snprintf(text, sizeof text, "%zu:%016llx", static_cast<size_t>(positions.rows()), static_cast<unsigned long long>(hash));
    return text;
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

void invertDeformation(const Lattice& lattice, const Positions& deformed, Positions& rest, bool collar) {
    rest = deformed;  // same size as before: no new pages
    const int n = static_cast<int>(deformed.rows());
    if (lattice.volume) {
        // A lattice of another kind: the parameters t of y in the deformed volume (freezing it, Coquillart 1990,
        // 3.3), whose rest point Q0(t) is the preimage. Points the deformed volume does not hold did not move.
        const Volume& volume = *lattice.volume;
        const std::unique_ptr<Volume::Locator> locator = volume.locatorFor(volume.restControlPoints() + lattice.displacement);
        const bool boundaryFixed = boundaryUnmoved(lattice);
#pragma omp parallel for schedule(dynamic, 256) if (n > 2000)
        for (int v = 0; v < n; ++v) {
            const Eigen::Vector3d y = deformed.row(v).transpose();
            Eigen::Vector3d t;
            const bool inside = restParameters(lattice, y, t);
            if (inside && displacementAt(lattice, t).isZero(0.0)) continue;  // bitwise its own preimage
            // With the boundary fixed the volume maps onto itself, so a point outside it never moved.
            if (!inside && boundaryFixed) continue;
            if (!locator->freeze(y, t)) continue;
            rest.row(v) = restPoint(lattice, t).transpose();
        }
        return;
    }
    // note: the residual x + d(x) - y sums up to (p+1)^3 terms of size ~|x|, so it cannot go much below a few
    // ulps of the box; Newton stops at 1e-14 of the diagonal or when even a halved step no longer improves
    // (below 1e-13 only the full step is tried: rounding level), so no iterations are burnt on noise. Undo chains many inversions: each must be this tight.
    const double tolerance = 1e-14 * lattice.diagonal();
    const double roundingLevel = 1e-13 * lattice.diagonal();  // below this a failed step is rounding, not overshoot
    // With the boundary where it started, a point outside the box is its own preimage (not so for a collar:
    // it follows the volume's derivative at the box too).
    const bool boundaryFixed = boundaryUnmoved(lattice) && !collar;
#pragma omp parallel for schedule(dynamic, 256) if (n > 2000)
    for (int v = 0; v < n; ++v) {
        const Eigen::Vector3d y = deformed.row(v).transpose();
        const Eigen::Vector3d yBox = toBoxCoordinates(lattice, y);  // Newton runs in box coordinates (lattice.h)
        Eigen::Vector3d t;
        // A point whose own displacement is exactly zero is its own preimage (the map is injective), so
        // vertices the frame never moved come back bitwise.
        const bool inside = restParameters(lattice, y, t);
        Eigen::Vector3d displacementAtY = Eigen::Vector3d::Zero();
        if (inside) {
            displacementAtY = displacementAt(lattice, t);
            if (displacementAtY.isZero(0.0)) continue;
        } else if (boundaryFixed) {
            continue;
        }
        // Start from the fixed-point guess x = y - d(y): off by |d| |grad d|, so Newton needs two or three steps.
        Eigen::Vector3d x = (yBox - toBoxCoordinates(lattice, displacementAtY)).cwiseMax(lattice.boxMin).cwiseMin(lattice.boxMax), params;
        const double r = newtonPreimageInBox(lattice, yBox, x, params, tolerance, roundingLevel, 40);
        // Outside the box nothing moved (or the collar carried it): keep y unless Newton found a genuine
        // preimage inside.
        Eigen::Vector3d beyond = y;
        if (r > 1e-9 * lattice.diagonal() && collar) collarPreimage(lattice, y, beyond);
        rest.row(v) = (r <= 1e-9 * lattice.diagonal() ? fromBoxCoordinates(lattice, x) : beyond).transpose();
    }
}

void Session::setInjectivity(const InjectivitySettings& settings) {
    const bool testing = injectivity_.mode != InjectivityMode::Off;
    injectivity_ = settings;
    if (!testing && settings.mode != InjectivityMode::Off && !drag_.active && stack_.lattice_.controlPointCount() > 0)
        pins().pinBoundaryIfPartial(stack_.lattice_, stack_.embedding_);
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
    drag_.active = false;
    mesh_.original = positions;
    mesh_.rest = positions;
    mesh_.positions = positions;
    mesh_.triangles = triangles;
    stack_.settings_ = settings;
    stack_.initialSettings_ = settings;
    stack_.initialBoxMin_ = lattice.boxMin;
    stack_.initialBoxMax_ = lattice.boxMax;
    stack_.lattice_ = std::move(lattice);
    embedVertices(stack_.lattice_, mesh_.rest, stack_.embedding_);
    stack_.setCollarFromSetUp(mesh_.rest);  // every vertex is inside: no collar to embed yet
    ++mesh_.restVersion;
    stack_.frames_.clear();
    stack_.layers_.clear();
    stack_.cageOut_.resize(0, 3);
    stack_.layerActive_ = false;
    {
        const Eigen::Vector3d lo = positions.colwise().minCoeff().transpose(), hi = positions.colwise().maxCoeff().transpose();
        asSet_.symmetryCentre = 0.5 * (lo + hi);
        symmetryRest_ = SymmetryFrame{asSet_.symmetryCentre, Eigen::Matrix3d::Identity()};
    }
    if (trackJacobian_) frozenJacobian_.assign(static_cast<size_t>(mesh_.rest.rows()), 1.0);
    // The triangle check's index, and the pairs that already cross (they never count against an edit).
    meshIndex_.build(mesh_.positions, mesh_.triangles);
    {
        // Zero-area facets (common in STL files) touch their neighbours in ways that read as crossings: they are
        // counted apart, and pairs that hold one are not counted as crossings.
        std::vector<char> degenerate(static_cast<size_t>(mesh_.triangles.rows()), 0);
        int degenerateCount = 0;
#pragma omp parallel for schedule(static) reduction(+ : degenerateCount)
        for (Eigen::Index t = 0; t < mesh_.triangles.rows(); ++t) {
            TriangleCorners corners;
            for (int k = 0; k < 3; ++k) corners.point[static_cast<size_t>(k)] = mesh_.positions.row(mesh_.triangles(t, k)).transpose();
            degenerate[static_cast<size_t>(t)] = triangleDegenerate(corners);
            degenerateCount += degenerate[static_cast<size_t>(t)];
        }
        asSet_.degenerateTriangles = degenerateCount;
        asSet_.intersectingPairs = 0;
        // Parts touching at load (an assembly's), or within a file's precision of touching (kNearContactTolerance):
        // their contact may shift as they move (self_intersection.h).
        const double diagonal = (mesh_.positions.colwise().maxCoeff() - mesh_.positions.colwise().minCoeff()).norm();
        std::vector<TrianglePairHit> near;
        const std::vector<TrianglePairHit> initial = meshIndex_.allIntersections(
            mesh_.positions, mesh_.triangles, static_cast<size_t>(-1), SelfIntersectionIndex::kNearContactTolerance * diagonal, &near);
        for (const TrianglePairHit& hit : initial)
            asSet_.intersectingPairs += !degenerate[static_cast<size_t>(hit.first)] && !degenerate[static_cast<size_t>(hit.second)];
        std::vector<TrianglePairHit> contacts = initial;
        contacts.insert(contacts.end(), near.begin(), near.end());
        asSet_.nearContactPairs = static_cast<int>(near.size());
        loadContacts_ = meshIndex_.findLoadContacts(contacts, mesh_.triangles);
        meshIndex_.setLoadContacts(loadContacts_, mesh_.triangles);
    }
    before_.resize(mesh_.positions.rows(), 3);
    history_.clear();
    asSet_.fingerprint = fingerprint(mesh_.original, mesh_.triangles);
    lastMoved_.vertices.clear();
    lastMoved_.all = true;
    return Status::success();
}

Status Session::parametersOfVertex(int vertex, Eigen::Vector3d& params) const {
    if (vertex < 0 || vertex >= mesh_.rest.rows())
        return Status::error("vertex index " + std::to_string(vertex) + " is out of range (mesh has " +
                             std::to_string(mesh_.rest.rows()) + " vertices)");
    if (!restParameters(stack_.lattice_, mesh_.rest.row(vertex).transpose(), params))
        return Status::error("vertex " + std::to_string(vertex) + " lies outside the lattice region");
    return Status::success();
}

void Session::applyDelta(const ControlDelta& delta, double sign, std::vector<int>* moved) {
    Lattice& lattice = stack_.activeLattice();
    applyControlDelta(lattice, delta, sign);
    std::vector<int> changed;
    evaluateIncrement(lattice, stack_.activeEmbedding(), delta.indices, delta.deltas, sign, activeOutput(), increment_, &changed);
    if (stack_.cageUnderLayers()) refreshLayerOutput(changed);
    positionsChanged(&changed);
    if (moved) moved->insert(moved->end(), changed.begin(), changed.end());
}

void Session::positionsChanged(const std::vector<int>* vertices) {
    if (vertices) meshIndex_.verticesMoved(*vertices);
    else meshIndex_.allVerticesMoved();
}

// ---- commands -------------------------------------------------------------------------------------------

void Session::trimResiduals(OpReport& report, size_t userConstraints) const {
    // Mirror images and profile samples are the engine's own constraints: the report speaks of the user's.
    if (report.residuals.size() <= userConstraints) return;
    report.residuals.resize(userConstraints);
    double worst = 0.0;
    for (double r : report.residuals) worst = std::max(worst, r);
    if (report.rankDeficient && worst <= 1e-9 * stack_.lattice_.diagonal()) {
        report.rankDeficient = false;
        if (report.reason.rfind("the constraints contradict", 0) == 0) report.reason.clear();
    }
}

double Session::mirrorMergeDistance(const BrushSettings& brush) const {
    // Closer than a quarter of a knot span, two sources would pull on the same few control points in
    // different directions: one point on the mirror plane.
    if (brush.active()) return 0.25 * brush.radius / kBrushFieldSpansPerRadius;
    double span = INFINITY;
    for (int a = 0; a < 3; ++a) span = std::min(span, (stack_.lattice_.boxMax[a] - stack_.lattice_.boxMin[a]) / stack_.lattice_.axes[a].spans);
    return 0.25 * span;
}

Status Session::checkBrush(const BrushSettings& brush) const {
    if (Status s = validateBrush(brush); !s) return s;
    // A radius beyond all scale of the mesh makes the region lattice's numbers overflow: name it, with the size
    // that covers everything (the whole mesh is within a radius of its diagonal).
    const double diagonal = (mesh_.positions.colwise().maxCoeff() - mesh_.positions.colwise().minCoeff()).norm();
    if (brush.active() && brush.radius > 1000.0 * std::max(diagonal, 1e-300)) {
        char text[160];
        std::snprintf(text, sizeof text, "brush radius %g is far larger than the mesh (diagonal %g): use at most %g, which already reaches every vertex",
                      brush.radius, diagonal, 1000.0 * diagonal);
        return Status::error(text);
    }
    return Status::success();
}

Status Session::drag(const std::vector<PointConstraint>& constraints, OpReport& report, const BrushSettings& brush) {
    const auto start = Clock::now();
    report = OpReport{};
    report.op = "drag";
    if (mesh_.empty()) return Status::error("no mesh is loaded");
    if (drag_.active) return Status::error("an interactive drag is in progress");
    if (constraints.empty()) return Status::error("drag has no constraints");
    if (Status s = checkBrush(brush); !s) return s;
    stack_.layerActive_ = false;
    if (brush.active()) {
        // A scripted brush drag is the window's stroke with one mouse move (stroke_brush.cpp).
        std::vector<Eigen::Vector3d> sources, targets;
        for (size_t f = 0; f < constraints.size(); ++f) {
            const std::string which = "constraint " + std::to_string(f);
            if (!constraints[f].target.allFinite()) return Status::error(which + " target has non-finite coordinates");
            sources.push_back(constraints[f].source);
            targets.push_back(constraints[f].target);
        }
        if (Status s = stroke().beginAt(sources, {}, brush); !s) return s;
        const Status updated = stroke().update(targets, report);
        stroke().end();
        report.op = "drag";
        report.wallMs = millisecondsSince(start);
        return updated;
    }
    // The constraints as asked, their targets scaled by the brush's strength.
    std::vector<Eigen::Vector3d> sources, targets;
    for (size_t f = 0; f < constraints.size(); ++f) {
        const std::string which = "constraint " + std::to_string(f);
        if (!constraints[f].source.allFinite()) return Status::error(which + " source has non-finite coordinates");
        if (!constraints[f].target.allFinite()) return Status::error(which + " target has non-finite coordinates");
        sources.push_back(constraints[f].source);
        targets.push_back(brush.scaledTarget(constraints[f].source, constraints[f].target));
    }
    // With symmetry, the mirror images join as further constraints (Hu et al. 2001, eq. 12). (A drag with a
    // radius is a brush stroke: it went the stroke's way above.)
    Manipulation m;
    const SymmetryFrame frame = symmetryFrame();
    std::vector<MirroredConstraint> solved = mirrorConstraints(sources, {}, brush.symmetry, frame, mirrorMergeDistance(brush));
    for (const MirroredConstraint& c : solved) {
        m.sources.push_back(c.source);
        m.targets.push_back(mirroredTarget(c, targets, sources, frame));
    }
    bool moves = false;
    for (size_t f = 0; f < m.sources.size(); ++f) {
        // Solved in the cage: the source must lie in it (as the engine sees it: equal up to rounding).
        const std::string which = f < constraints.size() ? "constraint " + std::to_string(f) : "the mirror image of a constraint";
        Eigen::Vector3d params;
        if (Status s = stack_.parametersOfCurrentPoint(m.sources[f], params); !s) {
            if (stack_.layers_.empty()) return Status::error(which + " source: " + s.message);
            // Through the layers after the cage Newton's method found no cage point: refused, not an input error.
            report.status = OpStatus::Rejected;
            report.refusedBy = "setup";
            report.reason = which + " source could not be traced back into the lattice through the layers after it (" + s.message +
                            "); nothing was changed";
            report.wallMs = millisecondsSince(start);
            return Status::success();
        }
        m.sources[f] = stack_.currentImage(params);
        moves = moves || m.sources[f] != m.targets[f];
    }
    if (!moves) {
        report.status = OpStatus::NoOp;
        report.reason = "every source is already on its target";
        report.residuals.assign(m.sources.size(), 0.0);
        report.wallMs = millisecondsSince(start);
        return Status::success();
    }
    // Simple causes no subdivision can help, said plainly before any work.
    if (std::string cause = unreachableDragCause(m); !cause.empty()) {
        report.status = OpStatus::Rejected;
        report.reason = "refused: " + cause + "; nothing was changed";
        report.injectivity = "rejected: " + cause;
        report.refusedBy = "setup";
        report.wallMs = millisecondsSince(start);
        return Status::success();
    }
    // The window's drag with one update (stroke.cpp): one increment solved in the cage through its
    // layers (Hu et al. 2001, eq. 12), applied when injective, otherwise subdivided (Gain & Dodgson 2001,
    // Appendix) or refused whole, as every move of a drag in the window.
    std::vector<Eigen::Vector3d> userTargets;
    for (const PointConstraint& c : constraints) userTargets.push_back(c.target);
    if (Status s = stroke().beginAt(sources, {}, brush); !s) return s;
    drag_.operation.interactive = false;
    drag_.operation.constraints = constraints;  // as asked: a replay on another mesh decides them again
    const Status updated = stroke().update(userTargets, report);
    if (!updated || report.status != OpStatus::Applied) {
        stroke().finish(nullptr);  // nothing applied: nothing is pushed
        report.op = "drag";
        report.subSteps = 0;
        report.wallMs = millisecondsSince(start);
        return updated;
    }
    if (report.subSteps > 1)  // why it had to be split: what the move in one step would have done
        report.reason = "subdivided into " + std::to_string(report.subSteps) + " injective steps: in one step " + report.failureWords;
    std::vector<int> changed;
    for (const Step& step : drag_.operation.steps) changed.insert(changed.end(), step.delta.indices.begin(), step.delta.indices.end());
    std::sort(changed.begin(), changed.end());
    report.controlPointsChanged = static_cast<int>(std::unique(changed.begin(), changed.end()) - changed.begin());
    // Each constraint's miss (its mirror images' too), as the targets were asked: from where the last step put
    // each source (evaluated at the parameters that step solved for, not found again by Newton's method).
    report.residuals.clear();
    report.rankDeficient = false;
    double worst = 0.0;
    const std::vector<PointConstraint>& reached = drag_.operation.steps.back().constraints;
    for (size_t f = 0; f < m.targets.size(); ++f) {
        report.residuals.push_back((m.targets[f] - (f < reached.size() ? reached[f].target : drag_.sourceWorld[f])).norm());
        worst = std::max(worst, report.residuals.back());
    }
    if (worst > 1e-9 * stack_.lattice_.diagonal()) {
        report.rankDeficient = true;
        report.reason = "the constraints contradict each other or ask more than the free control points can give (largest miss " +
                        std::to_string(worst) + "): met as closely as possible; use fewer constraints, unpin points, or a finer lattice";
    }
    stroke().finish(&report);
    report.op = "drag";
    trimResiduals(report, constraints.size());
    report.wallMs = millisecondsSince(start);
    return Status::success();
}

std::string Session::unreachableDragCause(const Manipulation& m) const {
    // Only pinned control points (or none) have a basis function that is non-zero at the source: nothing can
    // move it (Hu et al. 2001 eq. 12 with those columns of R removed).
    for (size_t f = 0; f < m.sources.size(); ++f) {
        if (m.sources[f] == m.targets[f]) continue;
        Eigen::Vector3d params;
        if (!stack_.parametersOfCurrentPoint(m.sources[f], params)) continue;
        SupportWeights support;
        supportWeights(stack_.lattice_, params, support);
        bool movable = false;
        for (int c = 0; c < support.count && !movable; ++c) movable = support.weight[c] > 0.0 && !stack_.lattice_.pinned[support.index[c]];
        if (!movable)
            return "every control point that moves " + std::string(m.sources.size() > 1 ? "constraint " + std::to_string(f) + "'s source" : "the grabbed point") +
                   " is pinned: unpin some of them (fewer pin layers, or P in the lattice tool) or use a finer lattice";
    }
    // With the whole outer layer pinned the lattice maps its box onto itself, so an injective deformation
    // cannot carry a point inside the box to a target outside it.
    if (injectivity_.mode == InjectivityMode::Off) return "";
    for (int idx = 0; idx < stack_.lattice_.controlPointCount(); ++idx)
        if (inOuterLayers(stack_.lattice_, idx, 1) && !stack_.lattice_.pinned[idx]) return "";
    for (size_t f = 0; f < m.targets.size(); ++f) {
        const Eigen::Vector3d& t = m.targets[f];
        if ((t.array() < stack_.lattice_.boxMin.array()).any() || (t.array() > stack_.lattice_.boxMax.array()).any()) {
            if (stack_.lattice_.volume && tools_.frozen >= 0)
                return "the target " + vectorText(t) + " lies outside lattice " + tools_.list[static_cast<size_t>(tools_.frozen)].name +
                       ", whose boundary stays fixed (" +
                       (stack_.lattice_.tensorNet() ? "it does not hold the whole mesh" : std::string("a ") + stack_.lattice_.volume->kindName() + " keeps its outer surface") +
                       "), so nothing inside it can reach there: make the lattice larger (Move on mesh, or edit_lattice with \"place\"), or drag less far";
            return "the target " + vectorText(t) + " lies outside the lattice, whose outer layer is pinned, so nothing inside it can reach there: " +
                   "unpin the outer layer (pin layers 0), enlarge the region, or drag less far";
        }
    }
    return "";
}

Status Session::dragVertex(int vertex, const Eigen::Vector3d& target, OpReport& report, const BrushSettings& brush) {
    report = OpReport{};
    report.op = "drag_vertex";
    if (mesh_.empty()) return Status::error("no mesh is loaded");
    if (!target.allFinite()) return Status::error("drag_vertex target has non-finite coordinates");
    if (vertex < 0 || vertex >= mesh_.positions.rows())
        return Status::error("vertex index " + std::to_string(vertex) + " is out of range (mesh has " + std::to_string(mesh_.positions.rows()) +
                             " vertices)");
    Eigen::Vector3d params;
    if (!brush.active() && !parametersOfVertex(vertex, params)) {
        // Sculpted out of the cage's box (a brush stroke goes where it is pulled): the cage cannot move it.
        report.status = OpStatus::Rejected;
        report.refusedBy = "setup";
        report.reason = stack_.carriesCollar()
                            ? "vertex " + std::to_string(vertex) + " rests outside the lattice's box, where a stroke pulled it: the lattice carries it along "
                              "but solves drags only inside its box; drag it with the brush (a radius), or set up a lattice around the mesh as it is now"
                            : "vertex " + std::to_string(vertex) + " lies outside the lattice, which moves only what it holds: drag it with the brush, or set up a larger lattice";
        return Status::success();
    }
    Eigen::Vector3d current;
    if (!brush.active() && !stack_.parametersOfCurrentPoint(mesh_.positions.row(vertex).transpose(), current)) {
        // The layers after the cage carry it where Newton's method finds no cage point for it (a mesh vertex, so
        // not the user's mistake): refused, nothing changed.
        report.status = OpStatus::Rejected;
        report.refusedBy = "setup";
        report.reason = "vertex " + std::to_string(vertex) + " could not be traced back into the lattice through the layers after it; "
                        "nothing was changed (set up a fresh lattice around the mesh, or use the brush)";
        return Status::success();
    }
    const Status status = drag({PointConstraint{mesh_.positions.row(vertex).transpose(), target}}, report, brush);
    report.op = "drag_vertex";
    return status;
}

Status Session::checkMovable(int idx) const {
    const int n = stack_.lattice_.controlPointCount();
    if (idx < 0 || idx >= n)
        return Status::error("control point id " + std::to_string(idx) + " is outside the lattice (" + std::to_string(n) +
                             " control points)");
    if (stack_.lattice_.pinned[idx]) {
        if (pins().pinnedAsPartialBoundary(idx) && !inOuterLayers(stack_.lattice_, idx, stack_.settings_.pinLayers))
            return Status::error("control point " + stack_.lattice_.controlPointName(idx) +
                                 " is pinned: the lattice holds only part of the mesh, so its outer surface stays where it "
                                 "is while the injectivity test is on (the vertices outside never move, and a moving "
                                 "boundary would tear the mesh there); set the injectivity test off for a plain FFD, "
                                 "as PyGeM computes it (every control point moves, the vertices outside stay), or set up "
                                 "a lattice that holds the whole mesh");
        return Status::error("control point " + stack_.lattice_.controlPointName(idx) + " is pinned");
    }
    return Status::success();
}

Status Session::moveControlPoints(const std::vector<int>& indices, const Eigen::MatrixX3d& values, bool relative,
                                  OpReport& report) {
    const auto start = Clock::now();
    report = OpReport{};
    report.op = "move_control_point";
    if (mesh_.empty()) return Status::error("no mesh is loaded");
    if (drag_.active) return Status::error("an interactive drag is in progress");
    if (indices.empty()) return Status::error("no control point given");
    if (static_cast<Eigen::Index>(indices.size()) != values.rows())
        return Status::error("control point ids and values differ in count");
    stack_.layerActive_ = false;
    std::vector<std::pair<int, Eigen::Vector3d>> moves;
    for (size_t c = 0; c < indices.size(); ++c) {
        const int idx = indices[c];
        if (Status s = checkMovable(idx); !s) return s;
        const Eigen::Vector3d value = values.row(static_cast<Eigen::Index>(c)).transpose();
        if (!value.allFinite()) return Status::error("control point move has non-finite coordinates");
        if (stack_.layers_.empty()) {
            moves.emplace_back(idx, relative ? value : Eigen::Vector3d(value - stack_.lattice_.controlPoint(idx)));
            continue;
        }
        // Under layers the user moves the cage as shown (carried through the layers): the cage point goes
        // where the layers take it onto the asked position.
        const Eigen::Vector3d shown = stack_.pushThroughLayers(stack_.lattice_.controlPoint(idx));
        Eigen::Vector3d cageTarget;
        if (!stack_.pullThroughLayers(relative ? Eigen::Vector3d(shown + value) : value, cageTarget, stack_.layers_.size())) {
            // A valid request the sculpted shape cannot give: refused, not an error.
            report.status = OpStatus::Rejected;
            report.reason = "refused: control point " + stack_.lattice_.controlPointName(idx) + " cannot go there: the later sculpting steps' lattices map no point onto it; nothing was changed";
            report.wallMs = millisecondsSince(start);
            return Status::success();
        }
        moves.emplace_back(idx, Eigen::Vector3d(cageTarget - stack_.lattice_.controlPoint(idx)));
    }
    // The same id listed twice: offsets add up for "by", the last position wins for "to".
    std::stable_sort(moves.begin(), moves.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    {
        std::vector<std::pair<int, Eigen::Vector3d>> merged;
        for (const auto& [idx, offset] : moves) {
            if (!merged.empty() && merged.back().first == idx)
                merged.back().second = relative ? Eigen::Vector3d(merged.back().second + offset) : offset;
            else
                merged.emplace_back(idx, offset);
        }
        moves = std::move(merged);
    }
    // Copies of one welded point (Coquillart 1990, 3.1.2: one control point; e.g. both sides of a seam when a
    // whole ring is listed) move once, and must be asked the same move.
    {
        const double tolerance = 1e-12 * std::max(stack_.lattice_.diagonal(), 1e-300);
        std::stable_sort(moves.begin(), moves.end(),
                         [&](const auto& a, const auto& b) { return stack_.lattice_.representative(a.first) < stack_.lattice_.representative(b.first); });
        std::vector<std::pair<int, Eigen::Vector3d>> merged;
        int asked = -1;  // the id that gave the last merged move
        for (const auto& [idx, offset] : moves) {
            const int representative = stack_.lattice_.representative(idx);
            if (merged.empty() || merged.back().first != representative) {
                merged.emplace_back(representative, offset);
                asked = idx;
            } else if ((merged.back().second - offset).norm() > tolerance) {
                const auto name = [&](int id) {
                    const std::array<int, 3> c = stack_.lattice_.ijk(id);
                    return "[" + std::to_string(c[0]) + "," + std::to_string(c[1]) + "," + std::to_string(c[2]) + "]";
                };
                return Status::error("control points " + name(asked) + " and " + name(idx) +
                                     " are one welded point but are given different moves: give them one move, or list one of them");
            }
        }
        moves = std::move(merged);
    }
    ControlDelta delta;
    std::vector<Eigen::Vector3d> offsets;
    for (const auto& [idx, offset] : moves) {
        if (!delta.indices.empty() && delta.indices.back() == idx) {
            offsets.back() = relative ? Eigen::Vector3d(offsets.back() + offset) : offset;
            continue;
        }
        delta.indices.push_back(idx);
        offsets.push_back(offset);
    }
    delta.deltas.resize(static_cast<Eigen::Index>(offsets.size()), 3);
    for (size_t c = 0; c < offsets.size(); ++c) delta.deltas.row(static_cast<Eigen::Index>(c)) = offsets[c].transpose();
    expandWelds(stack_.lattice_, delta);  // a welded point moves as one (Coquillart 1990, 3.1.2)
    if ((delta.deltas.array() == 0.0).all()) {
        report.status = OpStatus::NoOp;
        report.reason = "the control points are already there";
        report.wallMs = millisecondsSince(start);
        return Status::success();
    }
    Operation operation;
    operation.kind = OperationKind::ControlPointEdit;
    operation.label = delta.indices.size() == 1 ? "move control point" : "move " + std::to_string(delta.indices.size()) + " control points";
    operation.controlPoints = delta.indices;
    operation.offsets = delta.deltas;

    // A control-point edit moves those points in this lattice, never a fresh one (design.md "The cage is the
    // user's object"): where the whole move would fold, the points stop at the last injective position.
    std::vector<int> moved;
    StepFailure failure;
    const double fraction = applyLargestInjectiveFraction(delta, &moved, failure, report.injectivityMs, report.triangleCheckMs);
    lastMoved_.vertices.clear();
    lastMoved_.all = false;
    report.fractionApplied = fraction;
    if (fraction == 0.0) {
        report.status = OpStatus::Rejected;
        detail::noteFailure(report, failure, false);
        report.reason = "refused: even a small part of this move, " + report.failureWords + "; nothing was changed (" +
                        stepFailureAdvice(failure.cause) + ")";
        report.injectivity = "rejected: " + failure.technical;
        report.wallMs = millisecondsSince(start);
        return Status::success();
    }
    Step step;
    step.settings = stack_.settings_;
    step.delta = delta;
    step.delta.deltas *= fraction;
    operation.steps.push_back(std::move(step));
    reportSingleStep(std::move(moved), report);
    report.controlPointsChanged = static_cast<int>(delta.indices.size());
    if (fraction < 1.0) {
        detail::noteFailure(report, failure, false);
        report.reason = "stopped " + stepStopWords(failure.cause) + ": moved " + percentText(fraction) + " of the way (beyond it " + report.failureWords +
                        "); control point " + stack_.lattice_.controlPointName(delta.indices.front()) + " ended at " +
                        vectorText(stack_.lattice_.controlPoint(delta.indices.front()));
    }
    refinement().afterEdit(operation, &report);
    pushOperation(std::move(operation));
    report.wallMs = millisecondsSince(start);
    return Status::success();
}

Status Session::setupLattice(const LatticeSettings& settings, OpReport& report) {
    const auto start = Clock::now();
    report = OpReport{};
    report.op = "setup_lattice";
    if (mesh_.empty()) return Status::error("no mesh is loaded");
    if (drag_.active) return Status::error("an interactive drag is in progress");
    Eigen::Vector3d lo, hi;
    if (Status s = latticeBox(settings, mesh_.positions, lo, hi); !s) return s;
    Operation operation;
    operation.kind = OperationKind::LatticeSetup;
    const std::array<int, 3> counts = latticeCounts(settings);
    operation.label = "set up " + (settings.volume ? settings.volume->kindName() + " " : std::string()) + "lattice " + std::to_string(counts[0]) + "x" +
                      std::to_string(counts[1]) + "x" + std::to_string(counts[2]);
    operation.settings = settings;
    // A fresh, undeformed lattice is injective: no test needed.
    stack_.layerActive_ = false;
    Step step;
    enterNewCage(settings, &step);
    operation.steps.push_back(std::move(step));
    pushOperation(std::move(operation));
    lastMoved_.vertices.clear();
    report.status = OpStatus::Applied;
    report.subSteps = 1;
    report.injectivity = "injective";
    report.wallMs = millisecondsSince(start);
    return Status::success();
}

}  // namespace sculpt::core
