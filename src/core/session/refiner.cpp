// Refiner: refinement where the surface stretches (Coquillart 1990, section 3.4, after Griessmair and
// Purgathofer 1989). The geometry is refinement.h's; here it becomes an operation: the rest positions of the
// new vertices are rest-space edge midpoints, their positions the deformation's image of those points, and
// every per-vertex array of the session grows or shrinks with them.
#include <algorithm>
#include <cassert>
#include <cstdio>
#include <optional>

#include "core/injectivity/self_intersection.h"
#include "core/injectivity/triangle_pair.h"
#include "core/session/session.h"
#include "core/session/session_internal.h"

namespace sculpt::core {

using detail::Clock;
using detail::millisecondsSince;
using detail::vectorText;

namespace {

std::string deviationText(double deviation, double diagonal) {
    char buffer[96];
    std::snprintf(buffer, sizeof buffer, "%.3g (%.3g of the diagonal)", deviation, diagonal > 0.0 ? deviation / diagonal : 0.0);
    return buffer;
}

double boundingDiagonal(const Positions& positions) {
    if (positions.rows() == 0) return 0.0;
    return (positions.colwise().maxCoeff() - positions.colwise().minCoeff()).norm();
}

// The listed triangles of `triangles` as a mesh of their own: `global` holds their vertices' ids in order of first
// use, `part` the triangles in that numbering; with seamCopies (seamCopiesOf), welded at the seams (each corner
// its first copy).
struct Submesh {
    std::vector<int> global;
    Triangles part;
};

Submesh submeshOf(const Triangles& triangles, const std::vector<int>& listed, Eigen::Index vertexCount,
                  const std::vector<int>& seamCopies = {}) {
    Submesh out;
    std::vector<int> local(static_cast<size_t>(vertexCount), -1);
    out.part.resize(static_cast<Eigen::Index>(listed.size()), 3);
    for (size_t t = 0; t < listed.size(); ++t)
        for (int k = 0; k < 3; ++k) {
            int v = triangles(listed[t], k);
            if (!seamCopies.empty()) v = seamCopies[static_cast<size_t>(v)];
            if (local[static_cast<size_t>(v)] < 0) {
                local[static_cast<size_t>(v)] = static_cast<int>(out.global.size());
                out.global.push_back(v);
            }
            out.part(static_cast<Eigen::Index>(t), k) = local[static_cast<size_t>(v)];
        }
    return out;
}

// A submesh's splits (refineMesh on it) in the whole mesh's numbering: a vertex the splits added is numbered
// after the whole mesh's `first` vertices.
std::vector<EdgeSplit> splitsInWhole(const std::vector<EdgeSplit>& splits, const std::vector<int>& global, int first) {
    const int count = static_cast<int>(global.size());
    const auto toWhole = [&](int v) { return v < count ? global[static_cast<size_t>(v)] : first + (v - count); };
    std::vector<EdgeSplit> out;
    for (const EdgeSplit& e : splits) out.push_back({toWhole(e.a), toWhole(e.b)});
    return out;
}

// Refines `plan` (refineMesh's result: rest, current = target(rest), triangles) further where two of its
// triangles cross at the target while the target map is injective: a brush's field pushes what lies ahead of
// the pull on to (1 - k) of its distance (brush_field.h), and flat triangles long against the squeezed gap cut
// through each other however closely they follow the field. Each round bisects every triangle of such a pair
// once (refineMesh, one round, longest edge first, no rest edge shorter than shortestEdge), each new vertex at
// its image, until no pair crosses, `rounds` rounds, or plan holds maxVertices vertices. A pair whose
// triangles cross as the mesh is now (`now`: rest point -> world, the shape before the pull; the first
// `nowKnown.rows()` vertices' positions given) was there before the pull (a mesh loaded with parts in
// contact) and does not count. Since the image is injective, the crossings close as the triangles shrink.
// note: a CAD model's slivers (CGAL's boeing.off: 0.005 high over 0.35, a 1/500 of the radius across) flip
// wherever the field bends more than their height over their length; longest-edge bisection keeps that height,
// so each needs its long edge halved three or four times, and the crossings first double with each round
// before they close (251, 596, 936, 1,161, 1,550 triangles, then fewer). Hence 12 rounds, edges down to a
// 1/16 of refineUnderPull's shortest, and a stop only where the crossings grow past 16 times the first round's
// (8 rounds, 1/4 and 4 times stopped boeing's one-radius pulls; the vertex limit still bounds the work).
constexpr int kCrossingRounds = 12;
constexpr double kCrossingShortestEdge = 0.0625;  // of refineUnderPull's shortest edge
constexpr int kCrossingGrowth = 16;               // the most crossing triangles, in multiples of the first round's

void refineWhereCrossing(RefinementResult& plan, const RestImage& target, const RestImage& now, const Positions& nowKnown,
                         double shortestEdge, int maxVertices, int rounds) {
    std::vector<std::optional<Eigen::Vector3d>> nowAt;
    const auto nowPosition = [&](int v) -> Eigen::Vector3d {
        if (v < nowKnown.rows()) return nowKnown.row(v).transpose();
        if (nowAt.size() <= static_cast<size_t>(v)) nowAt.resize(static_cast<size_t>(v) + 1);
        if (!nowAt[static_cast<size_t>(v)]) nowAt[static_cast<size_t>(v)] = now(plan.rest.row(v).transpose());
        return *nowAt[static_cast<size_t>(v)];
    };
    const auto corners = [&](int t, bool before) {
        TriangleCorners c;
        for (int k = 0; k < 3; ++k) {
            c.vertex[static_cast<size_t>(k)] = plan.triangles(t, k);
            c.point[static_cast<size_t>(k)] = before ? nowPosition(plan.triangles(t, k)) : Eigen::Vector3d(plan.current.row(plan.triangles(t, k)).transpose());
        }
        return c;
    };
    int firstCount = 0;
    // The crossings: every pair at round 0 (through an index of the plan as it was then); in each later round the
    // pairs that hold a triangle split since (the rows halved in place and the new ones, flagged against the
    // plan's rows at round 0), and the pairs of round 0 whose rows are both unchanged (each pair of two unchanged
    // rows is as it was then): the same pairs as a full search, the same splits. (A full search each round cost
    // 40 ms on 27k triangles, ten rounds for a long inward pull on CGAL's armadillo.)
    SelfIntersectionIndex index;
    Triangles atFirstRound;
    std::vector<TrianglePairHit> firstHits;
    for (int round = 0; round < rounds && plan.rest.rows() < maxVertices; ++round) {
        std::vector<std::uint8_t> selected(static_cast<size_t>(plan.triangles.rows()), 0);
        std::vector<int> listed;
        std::vector<TrianglePairHit> hits;
        if (round == 0) {
            index.build(plan.current, plan.triangles);
            hits = index.allIntersections(plan.current, plan.triangles);
            atFirstRound = plan.triangles;
            firstHits = hits;
        } else {
            std::vector<std::uint8_t> changed(static_cast<size_t>(plan.triangles.rows()), 1);
            for (Eigen::Index t = 0; t < atFirstRound.rows(); ++t) changed[static_cast<size_t>(t)] = plan.triangles.row(t) != atFirstRound.row(t);
            hits = index.intersectionsOfChanged(plan.current, plan.triangles, changed);
            for (const TrianglePairHit& hit : firstHits)
                if (!changed[static_cast<size_t>(hit.first)] && !changed[static_cast<size_t>(hit.second)]) hits.push_back(hit);
        }
        for (const TrianglePairHit& hit : hits) {
            if (trianglesIntersect(corners(hit.first, true), corners(hit.second, true))) continue;
            for (int t : {hit.first, hit.second})
                if (!selected[static_cast<size_t>(t)]) selected[static_cast<size_t>(t)] = 1, listed.push_back(t);
        }
        const int selectedCount = static_cast<int>(listed.size());
        // Crossings that multiply as the triangles shrink are not the flat triangles' (the planned image folds
        // there): the pull's own check will say so. (Where the sheets touch, as at a load contact, they stay: the
        // rounds and the shortest edge bound the splits.)
        if (selectedCount == 0 || (round > 0 && selectedCount > kCrossingGrowth * firstCount)) return;
        if (round == 0) firstCount = selectedCount;
        // The selected triangles' own mesh (in ascending order, as the bisection's order depends on it).
        std::sort(listed.begin(), listed.end());
        const Submesh sub = submeshOf(plan.triangles, listed, plan.rest.rows());
        const std::vector<int>& global = sub.global;
        const int count = static_cast<int>(global.size());
        Positions rest(count, 3), current(count, 3);
        for (int c = 0; c < count; ++c) {
            rest.row(c) = plan.rest.row(global[static_cast<size_t>(c)]);
            current.row(c) = plan.current.row(global[static_cast<size_t>(c)]);
        }
        RefinementOptions options;
        options.tolerance = 1e-12;  // every selected triangle is over it: each is bisected once
        options.maxRounds = 1;
        options.shortestEdge = shortestEdge;
        options.maxVertices = count + (maxVertices - static_cast<int>(plan.rest.rows()));
        RefinementResult split;
        if (Status s = refineMesh(rest, current, sub.part, target, options, split); !s || split.splits.empty()) return;
        // The bisections in plan's numbering (applyEdgeSplits halves the neighbours outside the selection too,
        // so plan stays conforming); the new vertices keep the images refineMesh found.
        const int first = static_cast<int>(plan.rest.rows());
        const std::vector<EdgeSplit> splits = splitsInWhole(split.splits, global, first);
        if (Status s = applyEdgeSplits(plan.triangles, first, splits); !s) return;
        appendSplitMidpoints(plan.rest, splits);
        plan.current.conservativeResize(plan.rest.rows(), 3);
        for (size_t k = 0; k < splits.size(); ++k) plan.current.row(first + static_cast<Eigen::Index>(k)) = split.current.row(count + static_cast<Eigen::Index>(k));
        plan.splits.insert(plan.splits.end(), splits.begin(), splits.end());
    }
}

}  // namespace

const RefinementSettings& Refiner::settings() const { return s_.refinement_.settings; }

int Refiner::topologyVersion() const { return s_.refinement_.topologyVersion; }

Status Refiner::set(const RefinementSettings& settings) {
    if (Status s = validateRefinementOptions(settings.options); !s) return s;
    s_.refinement_.settings = settings;
    JournalEntry entry;
    entry.kind = JournalEntry::Kind::Refinement;
    entry.refinement = settings;
    s_.history_.note(std::move(entry), true);  // consecutive changes: only where they ended counts
    return Status::success();
}

std::vector<EdgeSplit> Refiner::appliedSplits() const {
    std::vector<EdgeSplit> splits;
    const auto add = [&](const RefinementRecord& record) { splits.insert(splits.end(), record.splits.begin(), record.splits.end()); };
    for (int i = 0; i < s_.history_.cursor(); ++i) {
        const Operation& operation = s_.history_.entries()[static_cast<size_t>(i)];
        add(operation.refinementBefore);
        add(operation.refinement);
    }
    if (s_.drag_.active) add(s_.drag_.operation.refinementBefore);  // a stroke in progress refined under its pull
    return splits;
}

Status Refiner::refine(double tolerance, OpReport& report) {
    const auto start = Clock::now();
    report = OpReport{};
    report.op = "refine";
    if (s_.mesh().empty()) return Status::error("no mesh is loaded");
    if (s_.drag_.active) return Status::error("an interactive drag is in progress");
    RefinementOptions options = s_.refinement_.settings.options;
    options.tolerance = tolerance;
    if (Status s = validateRefinementOptions(options); !s) return s;
    Operation operation;
    operation.kind = OperationKind::Refine;
    s_.stack_.layerActive_ = false;
    if (!refineNow(options, operation.refinement, report)) {
        report.wallMs = millisecondsSince(start);
        return Status::success();
    }
    operation.label = "refine (+" + std::to_string(report.verticesAdded) + " vertices)";
    s_.pushOperation(std::move(operation));
    report.wallMs = millisecondsSince(start);
    return Status::success();
}

void Refiner::afterEdit(Operation& operation, OpReport* report) {
    if (!s_.refinement_.settings.automatic || s_.mesh_.triangles.rows() == 0) return;
    OpReport refined;
    if (!refineNow(s_.refinement_.settings.options, operation.refinement, refined)) {
        // The edit stands; only a refused refinement is worth a word (nothing over the tolerance is normal).
        if (report && refined.status == OpStatus::Rejected)
            report->reason += (report->reason.empty() ? "" : "; ") + std::string("not refined: ") + refined.reason;
        if (report) report->deviation = refined.deviation;
        return;
    }
    if (!report) return;
    report->verticesAdded = refined.verticesAdded;
    report->trianglesAdded = refined.trianglesAdded;
    report->deviation = refined.deviation;
    if (!refined.reason.empty()) report->reason += (report->reason.empty() ? "" : "; ") + refined.reason;
}

bool Refiner::refineNow(const RefinementOptions& options, RefinementRecord& record, OpReport& report) {
    const double diagonal = boundingDiagonal(s_.mesh_.positions);
    RefinementResult plan;
    const RestImage image = [this](const Eigen::Vector3d& rest) { return s_.stack_.imageOfRestPoint(rest); };
    // (planned on the mesh welded at its seams, then made on every copy of each split edge)
    const std::vector<int> seamCopies = seamCopiesOf(s_.mesh_.rest);
    if (Status s = refineMesh(s_.mesh_.rest, s_.mesh_.positions, weldedAtSeams(s_.mesh_.triangles, seamCopies), image, options, plan); !s) {
        report.status = OpStatus::Rejected;  // not expected: the arrays are the session's own
        report.reason = s.message;
        return false;
    }
    report.deviation = plan.worstAfter;
    if (plan.splits.empty()) {
        report.status = OpStatus::NoOp;
        report.reason = "every triangle is within the tolerance (largest deviation " + deviationText(plan.worstBefore, diagonal) + ")";
        return false;
    }
    record.tolerance = options.tolerance;
    record.splits = splitsOnSeamCopies(s_.mesh_.triangles, static_cast<int>(s_.mesh_.rest.rows()), seamCopies, plan.splits);
    if (!applyChecked(record, report)) return false;
    if (!plan.converged)
        report.reason = "stopped at " + plan.stopped + " with " + std::to_string(plan.trianglesOver) +
                        " triangles still over the tolerance (largest deviation " + deviationText(plan.worstAfter, diagonal) + ")";
    return true;
}

bool Refiner::applyChecked(RefinementRecord& record, OpReport& report) {
    const Eigen::Index vertexCount = s_.mesh_.positions.rows(), triangleCount = s_.mesh_.triangles.rows();
    apply(record);

    // The triangle check (what injectivity means for the user): the refined triangles must not cross any
    // triangle they did not cross when their new vertices still lay on the flat triangles they split.
    if (s_.injectivity_.mode != InjectivityMode::Off && s_.injectivity_.checkTriangles) {
        const auto checkStart = Clock::now();
        std::vector<int> added;
        // A new vertex "before": on the flat triangles it split (the midpoint of its edge as the mesh showed it).
        const auto flat = [&](int v) { return v < vertexCount ? s_.mesh_.positions.row(v) : s_.before_.row(v); };
        for (Eigen::Index v = vertexCount; v < s_.mesh_.positions.rows(); ++v) {
            const EdgeSplit& split = record.splits[static_cast<size_t>(v - vertexCount)];
            s_.before_.row(v) = 0.5 * (flat(split.a) + flat(split.b));
            // (a vertex exactly on the flat triangles changes no triangle's shape: an undeformed region's)
            if (s_.mesh_.positions.row(v) != s_.before_.row(v)) added.push_back(static_cast<int>(v));
        }
        const SelfIntersectionIndex::Result crossing = s_.meshIndex_.findNewIntersection(s_.mesh_.positions, s_.mesh_.triangles, added, s_.before_);
        report.triangleCheckMs += millisecondsSince(checkStart);
        report.injectivityMs += millisecondsSince(checkStart);
        if (crossing.found) {
            Eigen::Vector3d where = Eigen::Vector3d::Zero();
            for (int k = 0; k < 3; ++k) where += s_.mesh_.positions.row(s_.mesh_.triangles(crossing.pair.first, k)).transpose() / 3.0;
            remove(record);
            record = RefinementRecord{};
            report.status = OpStatus::Rejected;
            report.refusedBy = "triangles";
            report.injectivity = "rejected: triangles " + std::to_string(crossing.pair.first) + " and " + std::to_string(crossing.pair.second) +
                                 " would cross";
            report.reason = "refused: the refined surface would pass through itself near " + vectorText(where) +
                            "; nothing was changed (try a larger tolerance)";
            return false;
        }
    }
    report.status = OpStatus::Applied;
    report.verticesAdded = static_cast<int>(s_.mesh_.positions.rows() - vertexCount);
    report.trianglesAdded = static_cast<int>(s_.mesh_.triangles.rows() - triangleCount);
    report.verticesMoved = 0;
    return true;
}

bool Refiner::refineUnderPull(const std::vector<int>& triangles, const RestImage& target, double tolerance, double shortestEdge,
                              RefinementRecord& record, OpReport& report) {
    // The triangles' own mesh, welded at its seams: their vertices, numbered in order of first use, rest points
    // and images at the target.
    std::vector<int> corners;
    corners.reserve(3 * triangles.size());
    for (int t : triangles)
        for (int k = 0; k < 3; ++k) corners.push_back(s_.mesh_.triangles(t, k));
    const std::vector<int> seamCopies = seamCopiesOf(s_.mesh_.rest, corners);
    const Submesh sub = submeshOf(s_.mesh_.triangles, triangles, s_.mesh_.rest.rows(), seamCopies);
    const std::vector<int>& global = sub.global;
    if (global.empty()) return false;
    const int count = static_cast<int>(global.size());
    Positions rest(count, 3), atTarget(count, 3);
    for (int c = 0; c < count; ++c) rest.row(c) = s_.mesh_.rest.row(global[static_cast<size_t>(c)]);
#pragma omp parallel for schedule(static) if (count > 2048)
    for (int c = 0; c < count; ++c) atTarget.row(c) = target(rest.row(c).transpose()).transpose();
    RefinementOptions options = s_.refinement_.settings.options;
    const double diagonal = boundingDiagonal(atTarget);
    if (!(diagonal > 0.0) || !(tolerance > 0.0)) return false;
    options.tolerance = std::min(tolerance / diagonal, 1.0);
    options.shortestEdge = shortestEdge;
    options.maxRounds = std::min(options.maxRounds, 6);
    // Growth stops at a few times the triangles under the pull (a jump in the image, or a pull too long for the
    // tolerance, would otherwise split without end).
    options.maxVertices = std::min(options.maxVertices, 4 * count + 5000);
    RefinementResult plan;
    if (Status s = refineMesh(rest, atTarget, sub.part, target, options, plan); !s) return false;
    // Then where the field squeezes two sheets closer than the flat triangles follow it.
    Positions nowKnown(count, 3);
    for (int c = 0; c < count; ++c) nowKnown.row(c) = s_.mesh_.positions.row(global[static_cast<size_t>(c)]);
    const LatticeStack& stack = s_.stack_;
    const RestImage now = [&stack](const Eigen::Vector3d& point) { return stack.imageOfRestPoint(point); };
    refineWhereCrossing(plan, target, now, nowKnown, kCrossingShortestEdge * shortestEdge, options.maxVertices, kCrossingRounds);
    if (plan.splits.empty()) return false;
    // The splits in the whole mesh's numbering: a vertex the plan added is numbered after the mesh's.
    RefinementRecord piece;
    piece.tolerance = tolerance;
    const int first = static_cast<int>(s_.mesh_.rest.rows());
    piece.splits = splitsOnSeamCopies(s_.mesh_.triangles, first, seamCopies, splitsInWhole(plan.splits, global, first));
    OpReport refined;
    if (!applyChecked(piece, refined)) return false;
    report.verticesAdded += refined.verticesAdded;
    report.trianglesAdded += refined.trianglesAdded;
    report.triangleCheckMs += refined.triangleCheckMs;
    report.injectivityMs += refined.injectivityMs;
    record.tolerance = tolerance;
    record.splits.insert(record.splits.end(), piece.splits.begin(), piece.splits.end());
    record.halvings.insert(record.halvings.end(), piece.halvings.begin(), piece.halvings.end());
    return true;
}

void Refiner::apply(RefinementRecord& record) {
    const Eigen::Index first = s_.mesh_.rest.rows();
    const Eigen::Index count = first + static_cast<Eigen::Index>(record.splits.size());
    [[maybe_unused]] const Status split = applyEdgeSplits(s_.mesh_.triangles, static_cast<int>(first), record.splits, &record.halvings);
    assert(split.ok);  // planned here, or checked by checkRecordedRefinement
    appendSplitMidpoints(s_.mesh_.rest, record.splits);
    s_.mesh_.positions.conservativeResize(count, 3);
    const bool layered = !s_.stack_.layers_.empty();
    if (layered) s_.stack_.cageOut_.conservativeResize(count, 3);
    const int added = static_cast<int>(count - first);
#pragma omp parallel for schedule(dynamic, 64) if (added > 256)
    for (int k = 0; k < added; ++k) {
        const Eigen::Index v = first + k;
        const Eigen::Vector3d rest = s_.mesh_.rest.row(v).transpose();
        const Eigen::Vector3d cage = s_.stack_.cageImage(rest);
        if (layered) s_.stack_.cageOut_.row(v) = cage.transpose();
        s_.mesh_.positions.row(v) = (layered ? s_.stack_.pushThroughLayers(cage) : cage).transpose();
    }
    if (s_.trackJacobian_) {
        // note: the frozen frames' det J at a new vertex would need its preimage through each frame; det J is
        // smooth, so the mean of the edge's ends stands in for it.
        s_.frozenJacobian_.resize(static_cast<size_t>(count));
        for (size_t k = 0; k < record.splits.size(); ++k)
            s_.frozenJacobian_[static_cast<size_t>(first) + k] =
                0.5 * (s_.frozenJacobian_[static_cast<size_t>(record.splits[k].a)] + s_.frozenJacobian_[static_cast<size_t>(record.splits[k].b)]);
    }
    if (!s_.loadContacts_.empty()) {
        // A split's midpoint is in the load contact's neighbourhood when both ends of its edge are.
        s_.loadContacts_.zoneVertex.resize(static_cast<size_t>(count), 0);
        for (size_t k = 0; k < record.splits.size(); ++k)
            s_.loadContacts_.zoneVertex[static_cast<size_t>(first) + k] =
                s_.loadContacts_.zoneVertex[static_cast<size_t>(record.splits[k].a)] && s_.loadContacts_.zoneVertex[static_cast<size_t>(record.splits[k].b)];
    }
    finishTopologyChange(count);
}

void Refiner::remove(const RefinementRecord& record) {
    if (record.empty()) return;
    const Eigen::Index count = s_.mesh_.rest.rows() - static_cast<Eigen::Index>(record.splits.size());
    assert(count >= 0);
    revertEdgeSplits(s_.mesh_.triangles, record.halvings);
    s_.mesh_.rest.conservativeResize(count, 3);
    s_.mesh_.positions.conservativeResize(count, 3);
    if (s_.stack_.cageOut_.rows() > 0) s_.stack_.cageOut_.conservativeResize(count, 3);
    if (s_.trackJacobian_) s_.frozenJacobian_.resize(static_cast<size_t>(count));
    if (!s_.loadContacts_.empty()) s_.loadContacts_.zoneVertex.resize(static_cast<size_t>(count));
    finishTopologyChange(count);
}

void Refiner::finishTopologyChange(Eigen::Index count) {
    s_.before_.conservativeResize(count, 3);
    if (s_.stack_.beforeCage_.rows() > 0) s_.stack_.beforeCage_.conservativeResize(count, 3);
    s_.stack_.embedCage(s_.mesh_.rest);
    ++s_.mesh_.restVersion;
    s_.meshIndex_.build(s_.mesh_.positions, s_.mesh_.triangles);
    if (!s_.loadContacts_.empty()) s_.meshIndex_.setLoadContacts(s_.loadContacts_, s_.mesh_.triangles);
    s_.lastMoved_.vertices.clear();
    s_.lastMoved_.all = true;
    ++s_.refinement_.topologyVersion;
}

Status Refiner::checkGroup(int first) const {
    bool refined = false;
    for (int i = first; i < s_.history_.cursor(); ++i) {
        const Operation& op = s_.history_.entries()[static_cast<size_t>(i)];
        if (i > first && !op.refinementBefore.empty())
            return Status::error("a group cannot hold a stroke refined under its pull after its first operation");
        for (const Step& step : op.steps)
            if (refined && step.newCage) return Status::error("a group cannot hold a lattice set-up after a refinement");
        refined = refined || !op.refinement.empty();
    }
    return Status::success();
}

Status Refiner::checkRecorded(const Operation& operation, bool cancelled) const {
    if (operation.refinement.empty() && operation.refinementBefore.empty()) {
        if (operation.kind == OperationKind::Refine) return Status::error("the recorded refinement splits no edge");
        return Status::success();
    }
    if (cancelled && !operation.refinement.empty()) return Status::error("a drag that was taken back has no refinement after it");
    Triangles triangles = s_.mesh_.triangles;
    int vertexCount = static_cast<int>(s_.mesh_.rest.rows());
    if (Status s = applyEdgeSplits(triangles, vertexCount, operation.refinementBefore.splits); !s)
        return Status::error("the recorded refinement under the stroke does not fit this mesh: " + s.message);
    vertexCount += static_cast<int>(operation.refinementBefore.splits.size());
    if (Status s = applyEdgeSplits(triangles, vertexCount, operation.refinement.splits); !s)
        return Status::error("the recorded refinement does not fit this mesh: " + s.message);
    return Status::success();
}

}  // namespace sculpt::core
