// InjectSubdiv (Gain & Dodgson 2001, section 8 and Appendix): each step of a manipulation is certified (the
// injectivity test of the lattice's cells, then no new crossing of the mesh's triangles) or split in two and
// tried again, down to the maximum depth; what the user is told when a step is refused or stopped short.
#include "core/session/session.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

#include "core/deform/brush_field.h"
#include "core/injectivity/injectivity.h"
#include "core/injectivity/triangle_pair.h"
#include "core/session/session_internal.h"
#include "core/volume/lattice_boundary.h"

namespace sculpt::core {

using detail::Clock;
using detail::mergeDelta;
using detail::millisecondsSince;
using detail::percentText;
using detail::vectorText;

namespace {

// Three significant digits: where on the mesh, for a person to find, not to compute with.
std::string shortVectorText(const Eigen::Vector3d& v) {
    char buffer[128];
    std::snprintf(buffer, sizeof buffer, "(%.3g, %.3g, %.3g)", v.x(), v.y(), v.z());
    return buffer;
}

}  // namespace

// ---- InjectSubdiv ---------------------------------------------------------------------------------------

void Session::reportSingleStep(std::vector<int> moved, OpReport& report) {
    std::sort(moved.begin(), moved.end());
    moved.erase(std::unique(moved.begin(), moved.end()), moved.end());
    lastMoved_.vertices = std::move(moved);
    lastMoved_.all = false;
    report.status = OpStatus::Applied;
    report.injectivity = injectivity_.mode == InjectivityMode::Off ? "not checked" : "injective";
    report.subSteps = 1;
    report.verticesMoved = movedCount();
}

bool Session::certifyCells(const Lattice& lattice, const std::vector<int>& cells, StepFailure& failure, double& injectivityMs) const {
    if (injectivity_.mode == InjectivityMode::Off || cells.empty()) return true;  // note: an empty list would mean "all cells"
    // Cells displaced along one line (a brush's pull) are proven by the directional bound; the rest by the test.
    const auto start = Clock::now();
    const std::vector<int> left = cellsLeftByDirectionalBound(lattice, cells);
    injectivityMs += millisecondsSince(start);
    if (left.empty()) return true;
    InjectivityResult verdict = checkInjectivity(lattice, injectivity_.mode, left);
    injectivityMs += verdict.milliseconds;
    if (verdict.certified) return true;
    if (injectivity_.mode == InjectivityMode::Conic) {
        // The cone test is sufficient only: where it cannot decide, the exact test does (Gain & Dodgson 2001,
        // section 6) before anything is called a fold.
        verdict = checkInjectivity(lattice, InjectivityMode::Exact, left);
        injectivityMs += verdict.milliseconds;
        if (verdict.certified) return true;
    }
    if (verdict.verdict == InjectivityVerdict::Undecided) {
        // Undecided is not a fold: search deeper (boxes of 2^-13 of a cell, 10x the work) before giving up. A
        // smaller step is the next escalation (the caller's subdivision of the manipulation).
        ExactOptions deeper;
        deeper.maxSubdivisionDepth = 13;
        deeper.maxBoxesPerCell = 200000;
        verdict = checkInjectivityExact(lattice, deeper, left);
        injectivityMs += verdict.milliseconds;
        if (verdict.certified) return true;
    }
    const auto& ijk = verdict.failingCellIjk;
    // Only a point where det J <= 0 was evaluated is a fold; what the tests could not decide is "not certified".
    const bool fold = verdict.verdict == InjectivityVerdict::Fold;
    failure.cause = fold ? StepFailure::Cause::Lattice : StepFailure::Cause::Uncertified;
    failure.technical = std::string(injectivityModeName(injectivity_.mode)) + " test " + (fold ? "finds a fold" : "cannot decide") + " in " +
                        (lattice.volume && !lattice.tensorNet() ? "chunk " + std::to_string(ijk[0])
                                                                : "cell [" + std::to_string(ijk[0]) + "," + std::to_string(ijk[1]) + "," +
                                                                      std::to_string(ijk[2]) + "]");
    if (!verdict.message.empty()) failure.technical += " (" + verdict.message + ")";
    if (verdict.failingParams.allFinite()) failure.where = stack_.currentImage(verdict.failingParams);
    return false;
}

bool Session::noNewCrossing(const std::vector<int>& changed, StepFailure& failure, double& injectivityMs, double& triangleMs) {
    const SelfIntersectionIndex::Result crossing = meshIndex_.findNewIntersection(mesh_.positions, mesh_.triangles, changed, before_);
    injectivityMs += crossing.milliseconds;  // all checks, the triangle check included
    triangleMs += crossing.milliseconds;
    if (!crossing.found) return true;
    failure.cause = StepFailure::Cause::Triangles;
    failure.technical = "triangles " + std::to_string(crossing.pair.first) + " and " + std::to_string(crossing.pair.second) + " would cross";
    // On a mesh of several parts (an assembly), which two block it.
    const int partA = meshIndex_.partOfTriangle(crossing.pair.first), partB = meshIndex_.partOfTriangle(crossing.pair.second);
    if (meshIndex_.partCount() > 1) {
        const auto named = [this](int part) {
            return "part " + std::to_string(part + 1) + " (" + std::to_string(meshIndex_.partTriangleCount(part)) + " triangles)";
        };
        failure.parts = partA == partB ? named(partA) + " would pass through itself"
                                       : named(std::min(partA, partB)) + " and " + named(std::max(partA, partB)) + " would cross";
        failure.parts += " (of the mesh's " + std::to_string(meshIndex_.partCount()) + " parts)";
    }
    // Where the first triangle is now (before the move): before_ holds the moved vertices' rows only, the others are
    // where they were (a triangle none of whose corners moved read as the origin).
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) {
        const int corner = mesh_.triangles(crossing.pair.first, k);
        const bool moved = std::find(changed.begin(), changed.end(), corner) != changed.end();
        centroid += (moved ? before_.row(corner) : mesh_.positions.row(corner)).transpose();
    }
    failure.where = centroid / 3.0;
    return false;
}

bool Session::tryDelta(const ControlDelta& delta, std::vector<int>* moved, StepFailure& failure, double& injectivityMs,
                       double& triangleMs, bool keep) {
    const bool checking = injectivity_.mode != InjectivityMode::Off;
    Lattice& lattice = stack_.activeLattice();
    const Embedding& embedding = stack_.activeEmbedding();
    Positions& output = activeOutput();  // the cage's output under layers (then carried through them)
    const bool layered = stack_.cageUnderLayers();
    // Tentatively change the lattice; keep the rows so a refusal puts them back bitwise.
    Positions savedRows(static_cast<Eigen::Index>(delta.indices.size()), 3);
    for (size_t c = 0; c < delta.indices.size(); ++c) savedRows.row(static_cast<Eigen::Index>(c)) = lattice.displacement.row(delta.indices[c]);
    const auto restoreLattice = [&] {
        for (size_t c = 0; c < delta.indices.size(); ++c) lattice.displacement.row(delta.indices[c]) = savedRows.row(static_cast<Eigen::Index>(c));
    };
    applyControlDelta(lattice, delta, 1.0);
    const std::vector<int> cells = cellsInfluencedBy(lattice, delta.indices);
    if (checking && !cells.empty()) {
        // note: an empty change (every control point that could move is pinned) reaches no cell; an empty cell
        // list would mean "all cells" to the checker.
        // Gain & Dodgson 2001: det J > 0 in the cells the change reaches (the rest were tested before).
        if (!certifyCells(lattice, cells, failure, injectivityMs)) {
            restoreLattice();
            return false;
        }
        // A free boundary: det J > 0 is local only. The deformed box boundary must not overlap itself
        // (lattice_boundary.h); only pairs that did not overlap before the change count.
        bool boundaryMoved = false;
        for (int idx : delta.indices) boundaryMoved = boundaryMoved || inOuterLayers(lattice, idx, 1);
        if (boundaryMoved && !boundaryUnmoved(lattice) && lattice.volume && !lattice.tensorNet()) {
            // The boundary overlap test tessellates tensor lattices' faces only; a composite's outer surface stays.
            restoreLattice();
            failure.cause = StepFailure::Cause::Boundary;
            failure.technical = "the outer surface of a " + lattice.volume->kindName() + " lattice stays where it is (pin it again)";
            return false;
        }
        if (boundaryMoved && !boundaryUnmoved(lattice)) {
            const auto start = Clock::now();
            std::vector<TrianglePairHit> after = boundarySelfIntersections(lattice);
            if (!after.empty()) {
                restoreLattice();
                const std::vector<TrianglePairHit> before = boundarySelfIntersections(lattice);
                for (const TrianglePairHit& hit : after) {
                    const bool existed = std::any_of(before.begin(), before.end(), [&](const TrianglePairHit& b) {
                        return b.first == hit.first && b.second == hit.second;
                    });
                    if (existed) continue;
                    failure.cause = StepFailure::Cause::Boundary;
                    failure.technical = "the deformed lattice boundary overlaps itself (boundary triangles " + std::to_string(hit.first) +
                                        " and " + std::to_string(hit.second) + ")";
                    failure.where = hit.where;
                    injectivityMs += millisecondsSince(start);
                    return false;
                }
                applyControlDelta(lattice, delta, 1.0);
            }
            injectivityMs += millisecondsSince(start);
        }
    }

    // The mesh: evaluate the vertices of the cells reached, keeping their rows as they were where the triangle
    // check or a probe needs them.
    const bool checkTriangles = checking && injectivity_.checkTriangles && mesh_.triangles.rows() > 0;
    std::vector<int> changed;
    if (!checkTriangles && keep) {
        const size_t first = moved ? moved->size() : 0;
        evaluateIncrement(lattice, embedding, delta.indices, delta.deltas, 1.0, output, increment_, moved ? moved : &changed);
        if (moved) changed.assign(moved->begin() + static_cast<std::ptrdiff_t>(first), moved->end());
        if (layered) refreshLayerOutput(changed);
        if (meshIndex_.built()) positionsChanged(&changed);  // a point cloud has no triangle index to tell
        return true;
    }
    appendVerticesOfCells(embedding, cells, changed);  // the collar's too: the triangle check is what certifies it
    // Deferred (beginDeferredTriangles): each vertex's row as the first deferred layer found it; the check at the
    // end, and nothing here to refuse or put back.
    const bool deferred = checkTriangles && deferTriangles_ && keep;
    if (deferred) {
        if (deferredSaved_.size() < static_cast<size_t>(mesh_.positions.rows())) deferredSaved_.resize(static_cast<size_t>(mesh_.positions.rows()), 0);
        for (int v : changed)
            if (!deferredSaved_[static_cast<size_t>(v)]) {
                deferredSaved_[static_cast<size_t>(v)] = 1;
                deferredChanged_.push_back(v);
                before_.row(v) = mesh_.positions.row(v);
            }
    } else {
        for (int v : changed) before_.row(v) = mesh_.positions.row(v);
        if (layered) {
            if (stack_.beforeCage_.rows() != mesh_.positions.rows()) stack_.beforeCage_.resize(mesh_.positions.rows(), 3);
            for (int v : changed) stack_.beforeCage_.row(v) = stack_.cageOut_.row(v);
        }
    }
    evaluateIncrement(lattice, embedding, delta.indices, delta.deltas, 1.0, output, increment_, nullptr);
    if (layered) refreshLayerOutput(changed);
    bool refused = false;
    if (checkTriangles && !deferred) {
        // The triangles the step moved must not cross any triangle they did not cross before.
        refused = !noNewCrossing(changed, failure, injectivityMs, triangleMs);
    } else {
        positionsChanged(&changed);
    }
    if (refused || !keep) {
        restoreLattice();
        for (int v : changed) mesh_.positions.row(v) = before_.row(v);
        if (layered)
            for (int v : changed) stack_.cageOut_.row(v) = stack_.beforeCage_.row(v);
        positionsChanged(&changed);
        return !refused;
    }
    if (moved) moved->insert(moved->end(), changed.begin(), changed.end());
    return true;
}

void Session::beginDeferredTriangles() {
    abandonDeferredTriangles();
    deferTriangles_ = true;
}

void Session::abandonDeferredTriangles() {
    for (int v : deferredChanged_) deferredSaved_[static_cast<size_t>(v)] = 0;
    deferredChanged_.clear();
    deferTriangles_ = false;
}

bool Session::finishDeferredTriangles(StepFailure& failure, double& injectivityMs, double& triangleMs) {
    deferTriangles_ = false;
    const bool passed = deferredChanged_.empty() || noNewCrossing(deferredChanged_, failure, injectivityMs, triangleMs);
    abandonDeferredTriangles();
    return passed;
}

double Session::applyLargestInjectiveFraction(const ControlDelta& delta, std::vector<int>* moved, StepFailure& failure,
                                              double& injectivityMs, double& triangleMs) {
    if (tryDelta(delta, moved, failure, injectivityMs, triangleMs)) return 1.0;
    // Bisection on the fraction of the move: lo passes (0 always does: nothing changes), hi fails.
    const StepFailure firstFailure = failure;
    double lo = 0.0, hi = 1.0;
    ControlDelta part = delta;
    for (int iteration = 0; iteration < 10; ++iteration) {
        const double mid = 0.5 * (lo + hi);
        part.deltas = mid * delta.deltas;
        StepFailure probeFailure;
        if (tryDelta(part, nullptr, probeFailure, injectivityMs, triangleMs, false)) lo = mid;
        else hi = mid;
    }
    failure = firstFailure;
    if (lo == 0.0) return 0.0;
    part.deltas = lo * delta.deltas;
    StepFailure finalFailure;
    if (!tryDelta(part, moved, finalFailure, injectivityMs, triangleMs)) return 0.0;  // passed as a probe: cannot happen
    return lo;
}

const char* stepFailureCauseName(StepFailure::Cause cause) {
    switch (cause) {
        case StepFailure::Cause::Triangles: return "triangles";
        case StepFailure::Cause::Boundary: return "boundary";
        case StepFailure::Cause::Lattice: return "lattice";
        case StepFailure::Cause::Uncertified: return "uncertified";
        case StepFailure::Cause::MirrorPlane: return "symmetry";
        case StepFailure::Cause::SourceLeft: return "source";
        case StepFailure::Cause::None: break;
    }
    return "";
}

std::string stepFailureWords(const StepFailure& failure, bool drag) {
    const std::string near = failure.where.allFinite() ? " near " + shortVectorText(failure.where) : "";
    switch (failure.cause) {
        case StepFailure::Cause::Triangles:
            return (failure.parts.empty() ? std::string("the surface would pass through itself") : failure.parts) + near;
        case StepFailure::Cause::Boundary: return "the lattice's outer surface would fold onto itself" + near;
        case StepFailure::Cause::Lattice: return std::string("the ") + (drag ? "mesh" : "lattice") + " would fold over itself" + near;
        case StepFailure::Cause::Uncertified:
            return "the deformation could not be certified free of folds" + near + " (no fold was found there; the tests stayed undecided)";
        case StepFailure::Cause::MirrorPlane:
            return "the grabbed point would meet its mirror image at the " + failure.plane +
                   " symmetry plane (a symmetric deformation keeps each side of the plane on its side)";
        case StepFailure::Cause::SourceLeft:
        case StepFailure::Cause::None: break;
    }
    return failure.technical;
}

std::string stepStopWords(StepFailure::Cause cause) {
    switch (cause) {
        case StepFailure::Cause::Triangles: return "where the surface would pass through itself";
        case StepFailure::Cause::Boundary: return "where the lattice's outer surface would fold onto itself";
        case StepFailure::Cause::Lattice: return "where the lattice would fold";
        case StepFailure::Cause::Uncertified: return "where the deformation could no longer be certified";
        case StepFailure::Cause::MirrorPlane: return "where the grabbed point meets its mirror image";
        case StepFailure::Cause::SourceLeft:
        case StepFailure::Cause::None: break;
    }
    return "short";
}

std::string stepFailureAdvice(StepFailure::Cause cause) {
    switch (cause) {
        case StepFailure::Cause::Triangles: return "try a smaller move, a finer lattice, or a finer mesh there";
        case StepFailure::Cause::Boundary: return "pin the outer layer (pin layers 1), make a smaller move, or enlarge the lattice";
        case StepFailure::Cause::Lattice: return "try a smaller move or a finer lattice";
        case StepFailure::Cause::Uncertified:
            return "the move may well be injective: try it in smaller moves, a finer lattice there, or the exact test";
        case StepFailure::Cause::MirrorPlane: return "pull along the plane or away from it, or turn symmetry off for this stroke";
        case StepFailure::Cause::SourceLeft:
        case StepFailure::Cause::None: break;
    }
    return "";
}

bool Session::tryStep(Manipulation& m, int depth, Progress& progress) {
    // Each step after the first is a separate deformation in a fresh lattice (a layer) around the mesh the
    // earlier steps produced (design.md): with one lattice the halves would just add up to the failing move.
    const bool needLayer = progress.appliedInCurrentFrame;
    if (depth > 0 || needLayer) saveSnapshot(progress.snapshot);  // what a rejection must restore
    if (needLayer) {
        const Status entered = enterLayer(&progress, &progress.pendingFrame, nullptr);
        if (!entered) {
            progress.failure.cause = StepFailure::Cause::SourceLeft;
            progress.failure.technical = entered.message;
            return false;
        }
    }
    std::vector<Eigen::Vector3d> params(m.sources.size());
    Eigen::MatrixX3d displacements(static_cast<Eigen::Index>(m.sources.size()), 3);
    for (size_t f = 0; f < m.sources.size(); ++f) {
        Eigen::Vector3d target;
        Status s = stack_.parametersOfCurrentPoint(m.sources[f], params[f]);
        if (s && !stack_.toActiveSpace(m.targets[f], target))
            s = Status::error("its target " + vectorText(m.targets[f]) + " is not the image of any point inside the lattice");
        if (!s) {
            progress.failure.cause = StepFailure::Cause::SourceLeft;
            progress.failure.technical = "constraint " + std::to_string(f) + " source left the lattice: " + s.message;
            return false;
        }
        // In the active lattice's own output space (under layers: traced back through them), where the
        // explicit solution is linear in the control points.
        displacements.row(static_cast<Eigen::Index>(f)) = (target - stack_.activeImage(params[f])).transpose();
    }
    DirectManipulationResult solved = directManipulation(stack_.activeLattice(), params, displacements);  // Hu et al. 2001, eq. 7 / 12
    ControlDelta delta = std::move(solved.delta);

    if (!tryDelta(delta, &progress.moved, progress.failure, progress.injectivityMs, progress.triangleMs)) {
        if (progress.firstFailure.cause == StepFailure::Cause::None) progress.firstFailure = progress.failure;
        return false;
    }

    Step step;
    if (progress.pendingFreshFrame) step = progress.pendingFrame;  // the layer's placement
    step.freshFrame = progress.pendingFreshFrame;
    progress.pendingFreshFrame = false;
    if (!step.freshFrame) step.settings = stack_.settings_;
    step.delta = std::move(delta);
    for (size_t f = 0; f < m.sources.size(); ++f) step.constraints.push_back({m.sources[f], stack_.currentImage(params[f])});
    progress.operation->steps.push_back(std::move(step));
    progress.operation->depthReached = std::max(progress.operation->depthReached, depth);
    progress.appliedInCurrentFrame = true;
    for (size_t f = 0; f < m.sources.size(); ++f) m.sources[f] = stack_.currentImage(params[f]);
    return true;
}

bool Session::injectSubdiv(Manipulation& m, int depth, Progress& progress) {
    // Gain & Dodgson 2001, Appendix, InjectSubdiv(F, dF, L, d).
    if (tryStep(m, depth, progress)) return true;
    if (depth >= injectivity_.maxDepth || progress.failure.cause == StepFailure::Cause::SourceLeft) return false;
    // (F, dF/2) then (F + dF/2, dF/2): the second half starts where the first left the sources.
    Manipulation first = m;
    for (size_t f = 0; f < m.sources.size(); ++f) first.targets[f] = m.sources[f] + 0.5 * (m.targets[f] - m.sources[f]);
    if (!injectSubdiv(first, depth + 1, progress)) return false;
    Manipulation second = m;
    second.sources = first.sources;
    if (!injectSubdiv(second, depth + 1, progress)) return false;
    m.sources = second.sources;
    return true;
}

}  // namespace sculpt::core
