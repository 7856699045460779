// Session: the brush's stroke (brush_field.h). Every update replaces the stroke's one layer by the pull field
// from where the stroke began to where the grabbed points are asked to be, or by the largest share of that
// pull that passes every check; the stroke is one history entry with one injective step.
#include <algorithm>

#include "core/brush_field.h"
#include "core/session.h"
#include "core/session_internal.h"

namespace sculpt::core {

using detail::Clock;
using detail::millisecondsSince;

double Session::applyBrushPulls(const std::vector<BrushPull>& pulls, const BrushSettings& brush, std::vector<Step>& steps,
                                OpReport& report, StepFailure& failure) {
    std::vector<int> moved;
    Step previous;
    const bool hadStep = !steps.empty();
    // Only vertices in the last step's box or within reach of the new pulls can change: their rows as they are,
    // so the report counts the vertices whose position this update changed (trials taken back do not count).
    Eigen::Vector3d reachLo = Eigen::Vector3d::Constant(INFINITY), reachHi = Eigen::Vector3d::Constant(-INFINITY);
    if (hadStep) {
        reachLo = steps.back().frameMin;
        reachHi = steps.back().frameMax;
    }
    for (const BrushPull& p : pulls) {
        if (!p.moving()) continue;
        const Eigen::Vector3d reach = Eigen::Vector3d::Constant(kBrushReach * brush.radius);
        reachLo = reachLo.cwiseMin(p.source.cwiseMin(p.source + p.pull) - reach);
        reachHi = reachHi.cwiseMax(p.source.cwiseMax(p.source + p.pull) + reach);
    }
    std::vector<int> candidates;
    for (Eigen::Index v = 0; v < positions_.rows(); ++v)
        if ((positions_.row(v).transpose().array() >= reachLo.array()).all() && (positions_.row(v).transpose().array() <= reachHi.array()).all())
            candidates.push_back(static_cast<int>(v));
    Positions rowsBefore(static_cast<Eigen::Index>(candidates.size()), 3);
    for (size_t c = 0; c < candidates.size(); ++c) rowsBefore.row(static_cast<Eigen::Index>(c)) = positions_.row(candidates[c]);
    if (hadStep) {
        previous = steps.back();
        popLayer(&moved);  // the stroke's layer is the newest: back to where the stroke began
        steps.clear();
    }
    double residual = 0.0;
    const auto attempt = [&](double share) {
        std::vector<BrushPull> scaled = pulls;
        for (BrushPull& p : scaled) p.pull *= share;
        RegionLattice region;
        if (Status s = pullRegionLattice(scaled, brush.radius, region); !s) {
            failure.cause = StepFailure::Cause::SourceLeft;
            failure.technical = s.message;
            return false;
        }
        Step step;
        step.freshFrame = true;
        step.region = true;
        step.settings = region.settings;
        step.frameMin = region.boxMin;
        step.frameMax = region.boxMax;
        step.regionFree = std::move(region.freePoints);
        if (Status s = enterLayer(nullptr, nullptr, &step); !s) {
            failure.cause = StepFailure::Cause::SourceLeft;
            failure.technical = s.message;
            return false;
        }
        residual = 0.0;
        Status solved = brushFieldDelta(layers_.back().lattice, scaled, brush.radius, brush.falloff, step.delta, residual);
        if (!solved || !tryDelta(step.delta, &moved, failure, report.injectivityMs, report.triangleCheckMs)) {
            if (!solved) {
                failure.cause = StepFailure::Cause::SourceLeft;
                failure.technical = solved.message;
            }
            popLayer(nullptr);
            return false;
        }
        layerActive_ = false;
        for (const BrushPull& p : scaled) step.constraints.push_back({p.source, p.source + p.pull});
        steps.push_back(std::move(step));
        return true;
    };
    double share = 0.0;
    bool moving = false;
    for (const BrushPull& p : pulls) moving = moving || p.moving();
    if (moving) {
        if (attempt(1.0)) {
            share = 1.0;
        } else if (failure.cause != StepFailure::Cause::SourceLeft) {
            // The last injective point along the pull (to 1/64 of it), as a control-point edit stops.
            const StepFailure stopped = failure;
            double lo = 0.0, hi = 1.0;
            for (int iteration = 0; iteration < 6; ++iteration) {
                const double mid = 0.5 * (lo + hi);
                if (attempt(mid)) {
                    lo = mid;
                    popLayer(&moved);
                    steps.clear();
                } else {
                    hi = mid;
                }
            }
            failure = stopped;
            if (lo > 0.0 && attempt(lo)) share = lo;
        }
    }
    if (share == 0.0 && hadStep && moving) {
        // Nothing of this pull passes: the stroke stays where the last update left it (already certified).
        enterLayer(nullptr, nullptr, &previous);
        applyDelta(previous.delta, 1.0, &moved);
        layerActive_ = false;
        steps.push_back(previous);
    }
    // Held points (pins inside the region) and crossing regions are met by the minimum-norm correction; where
    // the free control points cannot, the report says so.
    if (share > 0.0 && residual > 1e-9 * brush.radius) {
        report.rankDeficient = true;
        report.reason = "the held points and the pull ask more than the brush's region can give (largest miss " + std::to_string(residual) +
                        "): met as closely as possible";
    }
    (void)moved;
    lastMoved_.clear();
    for (size_t c = 0; c < candidates.size(); ++c)
        if (positions_.row(candidates[c]) != rowsBefore.row(static_cast<Eigen::Index>(c))) lastMoved_.push_back(candidates[c]);
    lastMovedAll_ = false;
    return share;
}

}  // namespace sculpt::core
