// Stroke: a brush stroke (brush_field.h). Every update replaces the stroke's one layer by the pull field
// from where the stroke began to where the grabbed points are asked to be, or by the largest share of that
// pull that passes every check; the stroke is one history entry with one injective step.
#include <algorithm>
#include <map>
#include <optional>
#include <utility>

#include "core/deform/brush_field.h"
#include "core/injectivity/triangle_pair.h"
#include "core/session/session.h"
#include "core/session/session_internal.h"

namespace sculpt::core {

using detail::Clock;
using detail::millisecondsSince;

double Stroke::applyBrushPulls(const std::vector<BrushPull>& pulls, const BrushSettings& brush, std::vector<Step>& steps,
                                OpReport& report, StepFailure& failure, bool wholeOnly) {
    std::vector<int> moved;
    const bool hadStep = !steps.empty();
    // Only vertices in the last step's box or within reach of the new pulls can change: their rows as they are,
    // so the report counts the vertices whose position this update changed (trials taken back do not count).
    Eigen::Vector3d reachLo = Eigen::Vector3d::Constant(INFINITY), reachHi = Eigen::Vector3d::Constant(-INFINITY);
    for (const Step& step : steps) {
        Eigen::Vector3d lo, hi;
        turnedBoxBounds(step.frameAxes, step.frameMin, step.frameMax, lo, hi);
        reachLo = reachLo.cwiseMin(lo);
        reachHi = reachHi.cwiseMax(hi);
    }
    for (const BrushPull& p : pulls) {
        if (!p.moving()) continue;
        // (a hair wider than the reach: the free supports reach it up to the ties pullRegionLattice counts in)
        const Eigen::Vector3d reach = Eigen::Vector3d::Constant(kBrushReach * brush.radius * (1.0 + 1e-6));
        reachLo = reachLo.cwiseMin(p.source.cwiseMin(p.source + p.pull) - reach);
        reachHi = reachHi.cwiseMax(p.source.cwiseMax(p.source + p.pull) + reach);
    }
    std::vector<int> candidates;
    Positions rowsBefore;
    const auto findCandidates = [&] {
        // (a scan of every vertex, in chunks in parallel, each chunk's in order: on a million vertices the scan is
        // a sixth of a brush move)
        const Positions& x = s_.mesh_.positions;
        const int n = static_cast<int>(x.rows());
        constexpr int kChunk = 65536;
        const int chunks = (n + kChunk - 1) / kChunk;
        std::vector<std::vector<int>> found(static_cast<size_t>(chunks));
#pragma omp parallel for schedule(dynamic, 1) if (chunks > 1)
        for (int chunk = 0; chunk < chunks; ++chunk)
            for (int v = chunk * kChunk; v < std::min(n, (chunk + 1) * kChunk); ++v)
                if (x(v, 0) >= reachLo[0] && x(v, 0) <= reachHi[0] && x(v, 1) >= reachLo[1] && x(v, 1) <= reachHi[1] && x(v, 2) >= reachLo[2] &&
                    x(v, 2) <= reachHi[2])
                    found[static_cast<size_t>(chunk)].push_back(v);
        candidates.clear();
        for (const std::vector<int>& part : found) candidates.insert(candidates.end(), part.begin(), part.end());
        rowsBefore.resize(static_cast<Eigen::Index>(candidates.size()), 3);
        for (size_t c = 0; c < candidates.size(); ++c) rowsBefore.row(static_cast<Eigen::Index>(c)) = s_.mesh_.positions.row(candidates[c]);
    };
    findCandidates();
    s_.layerCandidates_ = &candidates;
    std::vector<Step> previous;
    if (hadStep) {
        previous = steps;
        s_.popLayers(steps.size(), &moved);  // the stroke's layers are the newest: back to where the stroke began
        steps.clear();
    }
    // Each grabbed image's triangle on the mesh as the stroke began (the mesh is there now): the nearest among
    // `among` (all triangles when null), where it lies within the refinement's tolerance of the surface.
    std::vector<int>& grabbedTriangle = s_.drag_.grabbedTriangle;
    std::vector<Eigen::Vector3d>& grabbedWeights = s_.drag_.grabbedWeights;
    const auto locateGrabbed = [&](const std::vector<int>* among) {
        grabbedTriangle.assign(pulls.size(), -1);
        grabbedWeights.assign(pulls.size(), Eigen::Vector3d::Zero());
        const Triangles& triangles = s_.mesh_.triangles;
        const Positions& x = s_.mesh_.positions;
        const double onSurface = kBrushRefineTolerance * brush.radius;
        for (size_t k = 0; k < pulls.size(); ++k) {
            double best = onSurface;
            const Eigen::Vector3d& p = pulls[k].source;
            const auto consider = [&](int t) {
                const Eigen::Vector3d a = x.row(triangles(t, 0)).transpose(), b = x.row(triangles(t, 1)).transpose(), c = x.row(triangles(t, 2)).transpose();
                if (((p.array() < a.cwiseMin(b).cwiseMin(c).array() - best) || (p.array() > a.cwiseMax(b).cwiseMax(c).array() + best)).any()) return;
                const Eigen::Vector3d w = nearestOnTriangle(p, a, b, c);
                if (!w.allFinite()) return;
                const double distance = (w[0] * a + w[1] * b + w[2] * c - p).norm();
                if (distance <= best) {
                    best = distance;
                    grabbedTriangle[k] = t;
                    grabbedWeights[k] = w;
                }
            };
            if (among) {
                for (int t : *among) consider(t);
            } else {
                for (Eigen::Index t = 0; t < triangles.rows(); ++t) consider(static_cast<int>(t));
            }
        }
    };
    if (grabbedTriangle.size() != pulls.size()) locateGrabbed(nullptr);
    // How far the flat triangles put a grabbed image from its target, with the pull's layers in place (world
    // units; 0 for images off the surface or held): the field lands the point exactly, the flat mesh between
    // its moved corners only as well as its triangles follow the bend (a coarse mesh's long triangle not at all).
    const auto grabbedMiss = [&] {
        double miss = 0.0;
        for (size_t k = 0; k < pulls.size(); ++k) {
            const int t = grabbedTriangle[k];
            if (!pulls[k].moving() || t < 0) continue;
            Eigen::Vector3d flat = Eigen::Vector3d::Zero();
            for (int c = 0; c < 3; ++c) flat += grabbedWeights[k][c] * s_.mesh_.positions.row(s_.mesh_.triangles(t, c)).transpose();
            miss = std::max(miss, (flat - (pulls[k].source + pulls[k].pull)).norm());
        }
        return miss;
    };
    double residual = 0.0;
    std::vector<Eigen::Vector3d> where;  // each grabbed image, where the layers entered so far put it
    // One layer per moving image, each a field along its own pull (brush_field.h), so every layer is proven by
    // the directional bound and undone along its line; the images already placed are held where they are.
    // Images whose pulls share a direction (mirror images of a pull along the plane) are pulled by one field in
    // one layer instead: held inside each other's region, near the plane, they would bend each other's field
    // into a fold at once.
    // (Apart, out of each other's reach, they keep a layer each: each moves exactly along its own pull.)
    int movingCount = 0;
    bool withinReach = false;
    for (size_t a = 0; a < pulls.size(); ++a) {
        if (!pulls[a].moving()) continue;
        ++movingCount;
        for (size_t b = a + 1; b < pulls.size() && !withinReach; ++b) {
            if (!pulls[b].moving()) continue;
            // The two capsules (segments grown by the reach) overlap: segment distance < 2 reaches, sampled.
            for (int t = 0; t <= 16 && !withinReach; ++t) {
                const Eigen::Vector3d x = pulls[a].source + (t / 16.0) * pulls[a].pull;
                withinReach = segmentDistance(x, pulls[b].source, pulls[b].source + pulls[b].pull) < 2.0 * kBrushReach * brush.radius;
            }
        }
    }
    // Images within each other's reach whose pulls part (a normal pull beside the mirror plane) have no shared
    // direction: their one layer sums the scaled fields (brushFieldDelta), which no bound proves injective, so
    // it is tried only after the layers each failed, and the injectivity test decides it as every layer.
    const bool jointPossible = movingCount > 1 && withinReach;
    // Two mirror images within reach whose pulls part (a normal pull beside the plane): their pulls differ only
    // in the component across the mirror plane (axis `splitAxis`), so the stroke can be carried in two layers,
    // each a field along one line: first the part along the plane, which both share exactly (one field along it,
    // the larger share at each point: brushFieldDelta's shared direction, proven by the slope bound), then the
    // part across it, opposite for the two (brushFieldDelta's opposed pair: each side's share ramped through
    // zero between the images, so moving apart stretches the space between them). Each layer is mirror
    // symmetric, so the result is; the directional bound certifies each (injectivity_directional.cpp).
    int splitAxis = -1;
    if (jointPossible && movingCount == 2) {
        std::vector<size_t> movers;
        for (size_t k = 0; k < pulls.size(); ++k)
            if (pulls[k].moving()) movers.push_back(k);
        const BrushPull& a = pulls[movers[0]];
        const BrushPull& b = pulls[movers[1]];
        const double tolerance = 1e-9 * std::max(a.pull.norm(), brush.radius);
        // In the mirror planes' frame (the identity while the cage has not moved or turned the mesh).
        const Eigen::Matrix3d& axes = s_.drag_.symmetry.axes;
        const Eigen::Vector3d pa = axes.transpose() * a.pull, pb = axes.transpose() * b.pull;
        for (int axis = 0; axis < 3 && splitAxis < 0; ++axis) {
            bool mirrored = std::abs(pa[axis] + pb[axis]) <= tolerance && std::abs(pa[axis]) > tolerance;
            for (int other = 0; other < 3; ++other)
                if (other != axis) mirrored = mirrored && std::abs(pa[other] - pb[other]) <= tolerance;
            if (mirrored) splitAxis = axis;
        }
    }
    // The ways `attempt` can carry the pulls: the split above, a layer per image (each holding the images
    // placed before it; its space ahead widened first, by all or half the widening, or not), one layer for all
    // images (the scaled fields summed).
    // Widened: Layers, each pull's space ahead widened first; HalfWidened: by half as much (where the widened
    // field's triangles cross even split, a gentler widening keeps most of its profile).
    // Stepped (images within each other's reach): the split (or a layer per image) in kSteps steps, each from
    // where the last left the images to the next quarter of the pull. Each step's pull is a quarter as long, so
    // its field's slope bound (brushFieldSlope) is gentler and its region follows the images along the pull: two
    // mirror images pulled three radii beside the plane fold the space between them in one field (a held image
    // inside the other's region), not a step at a time (CGAL's camel, elephant and armadillo: strokes_real).
    enum class Mode { Split, Widened, HalfWidened, Layers, Joint, Stepped };
    Mode mode = Mode::Layers;  // the one `attempt` uses
    constexpr int kSteps = 4;  // Stepped's
    bool planning = false;     // `attempt` only puts the layers in place, unchecked, the mesh left as it is
    bool widened = false;      // some attempt widened the space ahead of a pull (else Widened was Layers)
    const auto attemptLayers = [&](double shareAsked) {
        double share = shareAsked;  // (Stepped: each step's)
        where.clear();
        for (const BrushPull& p : pulls) where.push_back(p.source);
        residual = 0.0;
        size_t entered = 0;
        const auto fail = [&](const Status& s) {
            if (!s) {
                failure.cause = StepFailure::Cause::SourceLeft;
                failure.technical = s.message;
            }
            s_.popLayers(entered, &moved);
            steps.resize(steps.size() - entered);
            return false;
        };
        // Enters one layer for `local` (one field: brushFieldDelta) and passes it through every check; moves
        // `where` on by it. False, with every layer of this attempt taken back, if any step fails.
        // `widening`: the layer holds no pull (each image's constraint is where the layer put it).
        const auto enterWith = [&](const std::vector<BrushPull>& local, bool widening, const auto& makeDelta) {
            RegionLattice region;
            if (Status s = pullRegionLattice(local, brush.radius, region, brushFieldSpansPerRadius(brush.falloff)); !s) return fail(s);
            Step step;
            step.freshFrame = true;
            step.region = true;
            step.settings = region.settings;
            step.frameMin = region.boxMin;
            step.frameMax = region.boxMax;
            step.frameAxes = region.axes;
            step.regionFree = std::move(region.freePoints);
            if (Status s = s_.enterLayer(nullptr, nullptr, &step); !s) return fail(s);
            double miss = 0.0;
            Status solved = makeDelta(s_.stack_.layers_.back().lattice, step.delta, miss);
            if (!solved) {
                s_.popLayer(nullptr);
                return fail(solved);
            }
            if (planning) {
                core::applyControlDelta(s_.stack_.layers_.back().lattice, step.delta, 1.0);
            } else if (!s_.tryDelta(step.delta, &moved, failure, report.injectivityMs, report.triangleCheckMs)) {
                s_.popLayer(nullptr);
                return fail(Status::success());
            }
            s_.stack_.layerActive_ = false;
            residual = std::max(residual, miss);
            const Lattice& layer = s_.stack_.layers_.back().lattice;
            for (Eigen::Vector3d& w : where) w = layerImage(layer, w);
            for (size_t j = 0; j < local.size(); ++j)
                step.constraints.push_back({local[j].source, widening ? where[j] : Eigen::Vector3d(local[j].source + local[j].pull)});
            steps.push_back(std::move(step));
            ++entered;
            return true;
        };
        const auto enter = [&](const std::vector<BrushPull>& local) {
            return enterWith(local, false, [&](const Lattice& layer, ControlDelta& delta, double& miss) {
                return brushFieldDelta(layer, local, brush.radius, brush.falloff, delta, miss);
            });
        };
        // The space ahead of image k's pull widened about its line (brush_field.h: BrushWidening), in two layers
        // each parallel to one lateral axis of the pull's region, before its field: where no other image lies
        // within the pull's reach (the widening would move it, and no correction holds it). False, with every
        // layer of this attempt taken back, if a layer fails a check.
        const auto widen = [&](size_t k) {
            const BrushPull pull{where[k], pulls[k].source + share * pulls[k].pull - where[k]};
            if (!pull.moving()) return true;
            for (size_t j = 0; j < pulls.size(); ++j)
                if (j != k && segmentDistance(where[j], pull.source, pull.source + pull.pull) <= kBrushReach * brush.radius * (1.0 + 1e-9)) return true;
            // Only for a pull out of the surface, within 45 degrees of its normal there (as it is now): along it or
            // into it, the surface ahead is the grabbed point's own sheet, which widening would tear open along the
            // line instead of letting the pull pass it. And only where the surface lies ahead
            // within the radius, where the pull's own field would carry it more than 0.05 of the pull above its
            // falloff (the walls of a hollow, an overhang): elsewhere the two layers move nothing of the mesh that
            // matters, and their checks cost a stroke 2-3 times its time.
            const Eigen::Vector3d e = pull.pull.normalized();
            const int t = k < grabbedTriangle.size() ? grabbedTriangle[k] : -1;
            if (t < 0) return true;
            // (The surface's normal there: its corners' vertex normals (area-weighted over the triangles around
            // each) weighted by where the point lies on the triangle, so a grabbed vertex reads its own. One
            // triangle's normal misleads at a vertex grabbed on a crease, where the triangle the point is found on
            // may face away from the others: a femur's vertex pulled along its normal read as a pull 109 degrees
            // from it. The triangles around all three corners alike misled on a coarse model: CGAL's anchor.off,
            // vertex 261 pulled one radius along its normal read as 21 to 71 degrees off it (by the triangle it
            // was found on), no widening for four of its five, and its surface ahead was left 0.117 RMS off
            // its falloff.)
            const auto normalOf = [&](int triangle) {
                const auto corner = [&](int c) { return Eigen::Vector3d(s_.mesh_.positions.row(s_.mesh_.triangles(triangle, c)).transpose()); };
                return Eigen::Vector3d((corner(1) - corner(0)).cross(corner(2) - corner(0)));
            };
            Eigen::Vector3d normal = Eigen::Vector3d::Zero();
            for (int c = 0; c < 3; ++c) {
                Eigen::Vector3d vertexNormal = normalOf(t);  // (the triangle alone where the mesh has no triangle index)
                if (s_.meshIndex_.built()) {
                    vertexNormal.setZero();
                    s_.meshIndex_.forEachTriangleOf(s_.mesh_.triangles(t, c), [&](int n) { vertexNormal += normalOf(n); });
                }
                if (vertexNormal.squaredNorm() > 0.0) normal += grabbedWeights[k][c] * vertexNormal.normalized();
            }
            if (!(normal.dot(e) > std::sqrt(0.5) * normal.norm())) return true;
            bool ahead = false;
            for (size_t c = 0; c < candidates.size() && !ahead; ++c) {
                const Eigen::Vector3d x = s_.mesh_.positions.row(candidates[c]).transpose(), offset = x - pull.source;
                const double z = offset.dot(e);
                if (z <= 0.0 || z >= kBrushReach * brush.radius || offset.squaredNorm() - z * z >= brush.radius * brush.radius) continue;
                ahead = brushFieldWeight(pull, brush.radius, brush.falloff, x) - brushFieldProfile(brush.falloff, offset.norm() / brush.radius) > 0.05;
            }
            if (!ahead) return true;
            // (The table last: the two tests above turn most pulls away for less.)
            BrushWidening widening = brushWidening(pull, brush.radius, brush.falloff);
            if (widening.empty()) return true;
            if (mode == Mode::HalfWidened)
                for (double& push : widening.push) push *= 0.5;  // keeps every bound: l + E / 2 rises at least 0.7 per unit
            widened = true;
            std::vector<BrushPull> local;
            for (size_t j = 0; j < pulls.size(); ++j) local.push_back(j == k ? pull : BrushPull{where[j], Eigen::Vector3d::Zero()});
            for (int axis = 0; axis < 2; ++axis)
                if (!enterWith(local, true, [&](const Lattice& layer, ControlDelta& delta, double& miss) {
                        miss = 0.0;
                        return brushWideningDelta(layer, widening, axis, delta);
                    }))
                    return false;
            return true;
        };
        const auto pass = [&] {
            if (mode == Mode::Split) {
                // Along the plane (both images' share of it is the same vector), then across it to the targets.
                Eigen::Vector3d along = Eigen::Vector3d::Zero();
                for (size_t j = 0; j < pulls.size(); ++j)
                    if (pulls[j].moving()) {
                        along = pulls[j].source + share * pulls[j].pull - where[j];
                        break;
                    }
                const Eigen::Vector3d normal = s_.drag_.symmetry.axes.col(splitAxis);
                along -= along.dot(normal) * normal;
                if (along.norm() > 1e-12 * brush.radius) {
                    std::vector<BrushPull> local;
                    for (size_t j = 0; j < pulls.size(); ++j) local.push_back(BrushPull{where[j], pulls[j].moving() ? along : Eigen::Vector3d::Zero()});
                    if (!enter(local)) return false;
                }
                std::vector<BrushPull> local;
                for (size_t j = 0; j < pulls.size(); ++j)
                    local.push_back(BrushPull{where[j], pulls[j].moving() ? Eigen::Vector3d(pulls[j].source + share * pulls[j].pull - where[j]) : Eigen::Vector3d::Zero()});
                return enter(local);
            }
            for (size_t k = 0; k < pulls.size(); ++k) {
                if (!pulls[k].moving()) continue;
                if ((mode == Mode::Widened || mode == Mode::HalfWidened) && !widen(k)) return false;
                std::vector<BrushPull> local;
                for (size_t j = 0; j < pulls.size(); ++j)
                    local.push_back(j == k || (mode == Mode::Joint && pulls[j].moving()) ? BrushPull{where[j], pulls[j].source + share * pulls[j].pull - where[j]}
                                                                           : BrushPull{where[j], Eigen::Vector3d::Zero()});
                if (!local[k].moving()) continue;
                if (!enter(local)) return false;
                if (mode == Mode::Joint) break;  // every image is in this one layer
            }
            return true;
        };
        if (mode != Mode::Stepped) return pass();
        mode = splitAxis >= 0 ? Mode::Split : Mode::Layers;
        bool passed = true;
        for (int step = 1; step <= kSteps && passed; ++step) {
            share = shareAsked * step / kSteps;
            passed = pass();
        }
        mode = Mode::Stepped;
        return passed;
    };
    // attemptLayers with the triangle check of its layers on their result only (Session::beginDeferredTriangles):
    // the user sees the result, and each layer's map is proven injective on its own.
    const auto attempt = [&](double share) {
        if (planning) return attemptLayers(share);
        const size_t stepsBefore = steps.size();
        s_.beginDeferredTriangles();
        if (!attemptLayers(share)) {
            s_.abandonDeferredTriangles();
            return false;
        }
        if (s_.finishDeferredTriangles(failure, report.injectivityMs, report.triangleCheckMs)) return true;
        s_.popLayers(steps.size() - stepsBefore, &moved);
        steps.resize(stepsBefore);
        return false;
    };
    double share = 0.0;
    bool moving = false;
    for (const BrushPull& p : pulls) moving = moving || p.moving();
    // Where the last update of this stroke left the first pulled image, as a share of this pull: a stroke
    // that keeps stopping short stops near there again, so the search starts there (a mouse move costs
    // five trials instead of eight; the first update of a stroke, a scripted drag's only one, searches all).
    double hint = 0.0;
    if (hadStep && s_.drag_.strokeReached.size() == pulls.size())
        for (size_t k = 0; k < pulls.size(); ++k)
            if (pulls[k].moving()) {
                hint = (s_.drag_.strokeReached[k] - pulls[k].source).dot(pulls[k].pull) / pulls[k].pull.squaredNorm();
                break;
            }
    const auto clearStroke = [&] {
        s_.popLayers(steps.size(), &moved);
        steps.clear();
    };
    // Puts back layers that passed every check before, in this update or the last (certified: applied as they
    // were, not tried again).
    const auto reenter = [&](const std::vector<Step>& certified) {
        for (const Step& step : certified) {
            s_.enterLayer(nullptr, nullptr, &step);
            s_.applyDelta(step.delta, 1.0, &moved);
            s_.stack_.layerActive_ = false;
        }
        steps = certified;
    };
    // The last passing share on [lo, hi], to (hi - lo) / 2^iterations, by bisection: lo passes with the layers
    // `atLo` (none at 0), hi fails. probeFirst: the least share past lo that the bisection could find is tried
    // first, and where it fails the search ends there (a stroke dragged on past where it stops fails there: one
    // trial, not `iterations`). Leaves the share found with its layers in place, put back as they passed (not
    // tried again).
    struct Passed {
        std::vector<Step> steps;
        double residual = 0.0;
    };
    const auto lastPassing = [&](double lo, double hi, int iterations, Passed atLo, bool probeFirst) {
        const auto passes = [&](double tried) {
            if (!attempt(tried)) return false;
            lo = tried;
            atLo = {steps, residual};
            clearStroke();
            return true;
        };
        bool searching = !probeFirst || passes(lo + (hi - lo) / static_cast<double>(1 << iterations));
        for (int iteration = 0; searching && iteration < iterations; ++iteration) {
            const double mid = 0.5 * (lo + hi);
            if (!passes(mid)) hi = mid;
        }
        reenter(atLo.steps);
        residual = atLo.residual;
        return lo;
    };
    // The mesh refined under the pull (Refiner::refineUnderPull), as the stroke began: the triangles the first
    // mode's whole pull would bend further from flat than `tolerance` (world units) are split, so that the mesh
    // follows the field (injective in space: a surface fine enough cannot cross itself under it) instead of
    // cutting through itself with long flat triangles. The splits go into the operation's refinementBefore.
    // False when nothing was split (or the split surface would cross itself as it is now).
    std::vector<Mode> modes;
    Mode carriedBy = Mode::Layers;  // the mode whose layers are in place
    // The modes whose triangles crossed (tryWhole), whose fields the refinement plans on, a round each in turn:
    // the first such, and Stepped where it crossed too (its steps bend the mesh otherwise than one field does).
    std::vector<Mode> crossedIn;
    const auto refineUnderPull = [&](double tolerance, Mode planOn) {
        mode = planOn;
        planning = true;
        const bool planned = attempt(1.0);
        planning = false;
        if (!planned) return false;
        std::vector<Lattice> field;  // the pull's layers, in order
        Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = Eigen::Vector3d::Constant(-INFINITY);
        for (size_t k = 0; k < steps.size(); ++k) {
            field.push_back(s_.stack_.layers_[s_.stack_.layers_.size() - steps.size() + k].lattice);
            Eigen::Vector3d regionLo, regionHi;
            deformationBounds(field.back(), regionLo, regionHi);
            lo = lo.cwiseMin(regionLo);
            hi = hi.cwiseMax(regionHi);
        }
        clearStroke();
        // Every triangle that may meet the reach of a moving pull (brush_field.h: nothing farther than 1.25 radius
        // from a pull's segment moves, whatever the layers' coefficients), whose box meets the region the field
        // moves (a triangle larger than the brush moves there with none of its corners). A triangle is out of reach
        // when its centroid is farther from every segment than the reach and the farthest corner from the
        // centroid together: the rest of the field's box (a pull's region lattice is long and turned to the pull:
        // on CGAL's armadillo its world box held three times the triangles that move) is left out of the splits.
        const double reach = kBrushReach * brush.radius * (1.0 + 1e-6);
        const Triangles& faces = s_.mesh_.triangles;
        const Positions& at = s_.mesh_.positions;
        std::vector<char> meets(static_cast<size_t>(faces.rows()), 0);
#pragma omp parallel for schedule(static) if (faces.rows() > 65536)
        for (Eigen::Index t = 0; t < faces.rows(); ++t) {
            const Eigen::Vector3d a = at.row(faces(t, 0)).transpose(), b = at.row(faces(t, 1)).transpose(), c = at.row(faces(t, 2)).transpose();
            const Eigen::Vector3d tLo = a.cwiseMin(b).cwiseMin(c), tHi = a.cwiseMax(b).cwiseMax(c);
            if (!((tLo.array() <= hi.array()).all() && (tHi.array() >= lo.array()).all())) continue;
            const Eigen::Vector3d centroid = (a + b + c) / 3.0;
            const double spread = std::sqrt(std::max({(a - centroid).squaredNorm(), (b - centroid).squaredNorm(), (c - centroid).squaredNorm()}));
            for (const BrushPull& p : pulls)
                if (p.moving() && segmentDistance(centroid, p.source, p.source + p.pull) <= reach + spread) {
                    meets[static_cast<size_t>(t)] = 1;
                    break;
                }
        }
        std::vector<int> near;
        for (Eigen::Index t = 0; t < faces.rows(); ++t)
            if (meets[static_cast<size_t>(t)]) near.push_back(static_cast<int>(t));
        const LatticeStack& stack = s_.stack_;
        const RestImage target = [&stack, &field](const Eigen::Vector3d& rest) {
            Eigen::Vector3d x = stack.imageOfRestPoint(rest);
            for (const Lattice& layer : field) x = layerImage(layer, x);
            return x;
        };
        if (!s_.refinement().refineUnderPull(near, target, tolerance, kBrushRefineShortestEdge * brush.radius, s_.drag_.operation.refinementBefore,
                                             report))
            return false;
        findCandidates();
        return true;
    };
    if (moving) {
        // The modes, in the order they are tried: the split where it applies (mirror symmetric, each layer
        // proven), a layer per image with the space ahead widened, with half the widening, without it, one field
        // for the images.
        if (splitAxis >= 0) modes.push_back(Mode::Split);
        modes.push_back(Mode::Widened);
        modes.push_back(Mode::HalfWidened);
        modes.push_back(Mode::Layers);
        if (jointPossible) modes.push_back(Mode::Joint);
        if (jointPossible) modes.push_back(Mode::Stepped);
        bool whole = false;
        std::optional<StepFailure> first;  // why the first mode did not carry the whole pull
        // Each mode in turn on the whole pull: whole when one carries it (its layers in place), else `first`.
        // Modes whose whole pull failed a check of its lattices alone (a fold, an undecided test, the boundary):
        // their fields do not depend on the mesh (all but the widened ones, which look at the surface ahead), so
        // after the mesh is split under the pull they fail again as they did, and are not tried again (CGAL's
        // camel, strokes_real's stroke 75: three of four modes folded in each of three rounds).
        std::map<Mode, StepFailure> latticeFailed;
        const auto tryWhole = [&] {
            first.reset();
            crossedIn.clear();
            for (Mode tried : modes) {
                if ((tried == Mode::Layers || tried == Mode::HalfWidened) && !widened && first) continue;  // Widened was this, and failed
                mode = tried;
                failure = StepFailure{};
                if (const auto known = latticeFailed.find(tried); known != latticeFailed.end()) {
                    failure = known->second;
                } else if (attempt(1.0)) {
                    whole = true;
                    return;
                } else if (tried != Mode::Widened && tried != Mode::HalfWidened &&
                           (failure.cause == StepFailure::Cause::Lattice || failure.cause == StepFailure::Cause::Uncertified ||
                            failure.cause == StepFailure::Cause::Boundary)) {
                    latticeFailed.emplace(tried, failure);
                }
                if (!first) first = failure;
                if ((crossedIn.empty() || tried == Mode::Stepped) && failure.cause == StepFailure::Cause::Triangles) crossedIn.push_back(tried);
                if (first->cause == StepFailure::Cause::SourceLeft) return;  // no mode has a region for it
            }
        };
        // Where the triangles stopped the whole pull, the mesh is refined under it and the modes tried again, each
        // time to half the tolerance (kBrushRefinements times at most).
        double tolerance = kBrushRefineTolerance * brush.radius;
        // What this update splits is kept only where the whole pull then passes: elsewhere (a pull that really
        // cannot be carried, or a field too steep for the smallest edge) it is taken back and the stroke stops
        // short on the mesh as it was.
        RefinementRecord& splitBefore = s_.drag_.operation.refinementBefore;
        const size_t splitsBefore = splitBefore.splits.size(), halvingsBefore = splitBefore.halvings.size();
        const int addedBefore = report.verticesAdded, trianglesBefore = report.trianglesAdded;
        double pullLength = 0.0;  // the first moving image's
        for (const BrushPull& p : pulls)
            if (p.moving()) {
                pullLength = p.pull.norm();
                break;
            }
        bool triedSplitting = false;
        const std::vector<int> grabbedTriangleBefore = grabbedTriangle;
        const std::vector<Eigen::Vector3d> grabbedWeightsBefore = grabbedWeights;
        for (int refined = 0;; ++refined) {
            tryWhole();
            // Split where the triangles stop the whole pull, or where it passes but the flat triangles leave a
            // grabbed point further than the tolerance from its target (a point grabbed inside a coarse mesh's
            // long triangle: a trial saw a horn's tip 25% short of the cursor).
            // (Also where the widened field crossed triangles and only the plain one passed: split, the widened
            // field keeps the surface ahead on its falloff.)
            const bool stoppedByTriangles = !crossedIn.empty() && (!whole || (modes[0] == Mode::Widened && mode != modes[0] && crossedIn[0] == modes[0]));
            const bool missed = whole && grabbedMiss() > kBrushRefineTolerance * brush.radius;
            if (!(stoppedByTriangles || missed) || refined == kBrushRefinements || !s_.refinement_.settings.underBrush || wholeOnly ||
                pullLength >= s_.drag_.splitFailedAt)
                break;
            const bool passed = whole;  // (a later mode carried it, or it passed with the grabbed point missed)
            if (whole) {
                clearStroke();
                whole = false;
            }
            triedSplitting = true;
            const int trianglesThen = static_cast<int>(s_.mesh_.triangles.rows());
            // (Each round on one field, in turn: on both at once the splits cost 2.5 times as long.)
            const Mode planOn = crossedIn.empty() ? modes[0] : crossedIn[static_cast<size_t>(refined) % crossedIn.size()];
            if (!refineUnderPull(tolerance, planOn)) {
                if (passed) tryWhole();  // nothing to split: the whole pull as it passed (a later mode's, or missed)
                break;
            }
            // The grabbed triangles are split too: each grabbed image is on its old triangle's half or on a new one.
            std::vector<int> among;
            for (int t : grabbedTriangle)
                if (t >= 0) among.push_back(t);
            for (int t = trianglesThen; t < static_cast<int>(s_.mesh_.triangles.rows()); ++t) among.push_back(t);
            locateGrabbed(&among);
            tolerance *= 0.5;
        }
        if (!whole && triedSplitting) s_.drag_.splitFailedAt = std::min(s_.drag_.splitFailedAt, pullLength);
        if (!whole && splitBefore.splits.size() > splitsBefore) {
            RefinementRecord added;
            added.splits.assign(splitBefore.splits.begin() + static_cast<std::ptrdiff_t>(splitsBefore), splitBefore.splits.end());
            added.halvings.assign(splitBefore.halvings.begin() + static_cast<std::ptrdiff_t>(halvingsBefore), splitBefore.halvings.end());
            s_.refinement().remove(added);
            splitBefore.splits.resize(splitsBefore);
            splitBefore.halvings.resize(halvingsBefore);
            report.verticesAdded = addedBefore;
            report.trianglesAdded = trianglesBefore;
            grabbedTriangle = grabbedTriangleBefore;
            grabbedWeights = grabbedWeightsBefore;
            findCandidates();
            tryWhole();  // what stopped the whole pull on the mesh as it was (it failed there before)
        }
        if (whole) {
            share = 1.0;
            carriedBy = mode;
        } else if (first->cause != StepFailure::Cause::SourceLeft && !wholeOnly) {
            // The last injective point along the pull (to 1/64 of it; from a hint, to 1/8 of what is left past
            // it), as a control-point edit stops: in the first mode, or from a hint in the mode that carried the
            // last update, where its share passes again as it did (the same field), so a stroke dragged on past
            // where it stops keeps the ground it gained. (Also where the last update reached nearly all of this
            // pull, a slow hand's small mouse moves: searched from the start, a share short of it passed first.)
            const bool hinted = hint > 1.0 / 64.0 && hint < 1.0;
            const Mode searchedFirst =
                hinted && std::find(modes.begin(), modes.end(), static_cast<Mode>(s_.drag_.strokeMode)) != modes.end()
                    ? static_cast<Mode>(s_.drag_.strokeMode)
                    : modes[0];
            mode = searchedFirst;
            double lo = 0.0, hi = 1.0;
            int iterations = 6;
            Passed atHint;
            if (hinted) {
                if (attempt(hint)) {
                    lo = hint;
                    atHint = {steps, residual};
                    iterations = 3;
                    clearStroke();
                } else {
                    hi = hint;
                }
            }
            share = lastPassing(lo, hi, iterations, atHint, lo > 0.0);
            carriedBy = searchedFirst;
            // The other modes may carry the images further (never less: what the first found stays unless
            // another passes beyond it). Each is tried first at the least share past it that its search would
            // find: a mode that fails there costs one trial, not four (a stroke dragged on past where it stops
            // tries every mode on every mouse move: 1.8 s a move on CGAL's camel, strokes_real's stroke 75).
            for (size_t other = 0; other < modes.size() && share < 1.0; ++other) {
                if (modes[other] == searchedFirst) continue;
                if ((modes[other] == Mode::Layers || modes[other] == Mode::HalfWidened) && !widened) continue;  // Widened was this
                Passed best{steps, residual};
                clearStroke();
                mode = modes[other];
                const double found = lastPassing(share, 1.0, 4, std::move(best), true);
                if (found > share) {
                    share = found;
                    carriedBy = mode;
                    break;
                }
            }
        }
        if (!whole) failure = *first;  // what stopped the pull is what stopped the first mode
    }
    if (share == 0.0 && hadStep && moving) reenter(previous);  // nothing of this pull passes: the stroke stays where the last update left it
    if (share > 0.0) s_.drag_.strokeMode = static_cast<int>(carriedBy);
    // Where the grabbed images are now: the last layer's constraints hold every image's place.
    s_.drag_.strokeReached.clear();
    if (!steps.empty())
        for (const PointConstraint& c : steps.back().constraints) s_.drag_.strokeReached.push_back(c.target);
    else
        for (const BrushPull& p : pulls) s_.drag_.strokeReached.push_back(p.source);
    // Held points (pins inside the region) and crossing regions are met by the minimum-norm correction; where
    // the free control points cannot, the report says so.
    if (share > 0.0 && residual > 1e-9 * brush.radius) {
        report.rankDeficient = true;
        report.reason = "the held points and the pull ask more than the brush's region can give (largest miss " + std::to_string(residual) +
                        "): met as closely as possible";
    }
    (void)moved;
    s_.layerCandidates_ = nullptr;
    if (s_.cageOutKept_) {  // the stroke ends this update with no layer: no cage output without layers
        s_.cageOutKept_ = false;
        if (s_.stack_.layers_.empty()) s_.stack_.cageOut_.resize(0, 3);
    }
    s_.lastMoved_.vertices.clear();
    for (size_t c = 0; c < candidates.size(); ++c)
        if (s_.mesh_.positions.row(candidates[c]) != rowsBefore.row(static_cast<Eigen::Index>(c))) s_.lastMoved_.vertices.push_back(candidates[c]);
    s_.lastMoved_.all = false;
    return share;
}

}  // namespace sculpt::core
