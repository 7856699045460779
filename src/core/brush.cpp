// The sculpting brush's geometry: mirror images of a drag and its region-of-interest lattice (brush.h).
#include "core/brush.h"

#include <algorithm>
#include <cmath>

#include "core/bspline_basis.h"

namespace sculpt::core {

const char* brushFalloffName(BrushFalloff falloff) {
    switch (falloff) {
        case BrushFalloff::Smooth: return "smooth";
        case BrushFalloff::Medium: return "medium";
        case BrushFalloff::Sharp: return "sharp";
    }
    return "smooth";
}

Status parseBrushFalloff(const std::string& name, BrushFalloff& out) {
    for (BrushFalloff f : {BrushFalloff::Smooth, BrushFalloff::Medium, BrushFalloff::Sharp})
        if (name == brushFalloffName(f)) {
            out = f;
            return Status::success();
        }
    return Status::error("unknown falloff '" + name + "' (expected \"smooth\", \"medium\" or \"sharp\")");
}

Status parseSymmetry(const std::string& text, Symmetry& out) {
    Symmetry symmetry;
    for (char c : text) {
        const int axis = c == 'x' || c == 'X' ? 0 : c == 'y' || c == 'Y' ? 1 : c == 'z' || c == 'Z' ? 2 : -1;
        if (axis < 0) return Status::error(std::string("symmetry '") + text + "': '" + c + "' is not an axis (use x, y, z or combinations such as \"xz\")");
        if (symmetry.mirror[axis]) return Status::error(std::string("symmetry '") + text + "' names axis " + c + " twice");
        symmetry.mirror[axis] = true;
    }
    out = symmetry;
    return Status::success();
}

std::string symmetryText(const Symmetry& symmetry) {
    std::string text;
    for (int a = 0; a < 3; ++a)
        if (symmetry.mirror[a]) text += static_cast<char>('x' + a);
    return text;
}

Status validateBrush(const BrushSettings& brush) {
    if (!std::isfinite(brush.radius) || brush.radius < 0.0) return Status::error("brush radius must be a finite number >= 0");
    if (!std::isfinite(brush.strength) || brush.strength <= 0.0 || brush.strength > 1.0)
        return Status::error("brush strength must be in (0, 1]");
    return Status::success();
}

int brushDegree(BrushFalloff falloff) {
    switch (falloff) {
        case BrushFalloff::Smooth: return 3;
        case BrushFalloff::Medium: return 2;
        case BrushFalloff::Sharp: return 1;
    }
    return 3;
}

int brushSpansPerRadius(BrushFalloff falloff) {
    // Knot spans h with sqrt(3) ((p+1)/2 + 1/2) h <= 1.25 radius: wherever the grabbed point lies, the support
    // of the basis function centred nearest to it fits in the ball, so a brush always has a free point there.
    switch (falloff) {
        case BrushFalloff::Smooth: return 4;  // cubic over 4 spans: the bump reaches about one radius
        case BrushFalloff::Medium: return 3;  // quadratic over 3 spans: one radius
        case BrushFalloff::Sharp: return 3;   // linear over 2 spans: a peak reaching 2/3 radius
    }
    return 4;
}

Eigen::Vector3d reflectPoint(const Eigen::Vector3d& p, int mask, const Eigen::Vector3d& centre) {
    Eigen::Vector3d q = p;
    for (int a = 0; a < 3; ++a)
        if (mask & (1 << a)) q[a] = 2.0 * centre[a] - q[a];
    return q;
}

std::vector<MirroredConstraint> mirrorConstraints(const std::vector<Eigen::Vector3d>& sources, const std::vector<bool>& held,
                                                  const Symmetry& symmetry, const Eigen::Vector3d& centre, double mergeDistance) {
    std::vector<MirroredConstraint> out;
    for (size_t f = 0; f < sources.size(); ++f) out.push_back({sources[f], {{static_cast<int>(f), 0}}});
    for (int mask = 1; mask < 8; ++mask) {
        bool usable = true;
        for (int a = 0; a < 3; ++a) usable = usable && (!(mask & (1 << a)) || symmetry.mirror[a]);
        if (!usable) continue;
        for (size_t f = 0; f < sources.size(); ++f) {
            if (f < held.size() && held[f]) continue;
            const Eigen::Vector3d s = reflectPoint(sources[f], mask, centre);
            auto near = std::find_if(out.begin(), out.end(), [&](const MirroredConstraint& c) { return (c.source - s).norm() <= mergeDistance; });
            if (near != out.end()) near->images.emplace_back(static_cast<int>(f), mask);
            else out.push_back({s, {{static_cast<int>(f), mask}}});
        }
    }
    return out;
}

Eigen::Vector3d mirroredTarget(const MirroredConstraint& constraint, const std::vector<Eigen::Vector3d>& userTargets,
                               const Eigen::Vector3d& centre) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (const auto& [user, mask] : constraint.images) sum += reflectPoint(userTargets[static_cast<size_t>(user)], mask, centre);
    return sum / static_cast<double>(constraint.images.size());
}

Status regionLattice(const std::vector<Eigen::Vector3d>& centres, double radius, BrushFalloff falloff, RegionLattice& out) {
    if (centres.empty()) return Status::error("a brush drag needs a grabbed point");
    if (!std::isfinite(radius) || radius <= 0.0) return Status::error("brush radius must be a finite number > 0");
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = Eigen::Vector3d::Constant(-INFINITY);
    for (const Eigen::Vector3d& c : centres) {
        if (!c.allFinite()) return Status::error("a brush centre has non-finite coordinates");
        lo = lo.cwiseMin(c);
        hi = hi.cwiseMax(c);
    }
    const double reach = 1.25 * radius;  // no vertex farther than this from a grabbed point moves
    const int degree = brushDegree(falloff);
    const double span = radius / brushSpansPerRadius(falloff);
    RegionLattice region;
    region.settings.degree = {degree, degree, degree};
    region.settings.padding = 0.0;
    region.settings.pinLayers = 0;
    for (int a = 0; a < 3; ++a) {
        // Whole spans of the falloff's width, centred on the centres' bounds, at most 64 control points.
        const double extent = hi[a] - lo[a] + 2.0 * reach;
        const int spans = std::clamp(static_cast<int>(std::ceil(extent / span - 1e-9)), 1, kMaxControlPointsPerAxis - degree);
        const double width = std::max(extent, spans * span);
        const double middle = 0.5 * (lo[a] + hi[a]);
        region.boxMin[a] = middle - 0.5 * width;
        region.boxMax[a] = middle + 0.5 * width;
        region.settings.resolution[a] = spans + degree;
    }
    // A control point is free when its whole support box lies within `reach` of one centre: outside the
    // balls only pinned points' bases are non-zero, so nothing there moves.
    std::array<SplineAxis, 3> axes;
    for (int a = 0; a < 3; ++a) axes[a] = makeSplineAxis(region.settings.resolution[a], degree);
    const std::array<int, 3> count = region.settings.resolution;
    for (int k = 0; k < count[2]; ++k)
        for (int j = 0; j < count[1]; ++j)
            for (int i = 0; i < count[0]; ++i) {
                const std::array<int, 3> c{i, j, k};
                Eigen::Vector3d supportLo, supportHi;
                for (int a = 0; a < 3; ++a) {
                    const double size = region.boxMax[a] - region.boxMin[a];
                    supportLo[a] = region.boxMin[a] + axes[a].knots[c[a]] * size;
                    supportHi[a] = region.boxMin[a] + axes[a].knots[c[a] + degree + 1] * size;
                }
                bool free = false;
                for (const Eigen::Vector3d& centre : centres) {
                    // The support box's corner farthest from the centre.
                    const Eigen::Vector3d far = (supportLo - centre).cwiseAbs().cwiseMax((supportHi - centre).cwiseAbs());
                    free = free || far.norm() <= reach;
                }
                if (free) region.freePoints.push_back(i + count[0] * (j + count[1] * k));
            }
    out = std::move(region);
    return Status::success();
}

void pinAllBut(Lattice& lattice, const std::vector<int>& freePoints) {
    std::fill(lattice.pinned.begin(), lattice.pinned.end(), std::uint8_t{1});
    for (int idx : freePoints) lattice.pinned[static_cast<size_t>(idx)] = 0;
}

}  // namespace sculpt::core
