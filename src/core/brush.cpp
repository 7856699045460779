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
                               const std::vector<Eigen::Vector3d>& userSources) {
    Eigen::Vector3d move = Eigen::Vector3d::Zero();
    for (const auto& [user, mask] : constraint.images) {
        // A reflection is affine: the image of a move is the move with the mirrored axes negated.
        Eigen::Vector3d d = userTargets[static_cast<size_t>(user)] - userSources[static_cast<size_t>(user)];
        for (int a = 0; a < 3; ++a)
            if (mask & (1 << a)) d[a] = -d[a];
        move += d;
    }
    return constraint.source + constraint.weight * move / static_cast<double>(constraint.images.size());
}

double brushProfile(BrushFalloff falloff, double x) {
    x = std::clamp(x, 0.0, 1.0);
    switch (falloff) {
        case BrushFalloff::Smooth: return 1.0 - x * x * (3.0 - 2.0 * x);
        case BrushFalloff::Medium: return std::sqrt(1.0 - x * x);
        case BrushFalloff::Sharp: return (1.0 - x) * (1.0 - x);
    }
    return 0.0;
}

void addBrushProfile(std::vector<MirroredConstraint>& constraints, const std::vector<bool>& held, double radius, BrushFalloff falloff) {
    const size_t count = constraints.size();
    const double distance = 0.3 * radius, minGap = 0.2 * radius;
    std::vector<Eigen::Vector3d> directions;
    for (int a = 0; a < 3; ++a)
        for (double sign : {-1.0, 1.0}) directions.push_back(sign * Eigen::Vector3d::Unit(a));
    for (int corner = 0; corner < 8; ++corner)
        directions.push_back(Eigen::Vector3d(corner & 1 ? 1 : -1, corner & 2 ? 1 : -1, corner & 4 ? 1 : -1).normalized());
    for (size_t e = 0; e < count; ++e) {
        const MirroredConstraint grabbed = constraints[e];
        const int user = grabbed.images.front().first;
        if (grabbed.weight != 1.0 || (static_cast<size_t>(user) < held.size() && held[static_cast<size_t>(user)])) continue;
        for (const Eigen::Vector3d& direction : directions) {
            const Eigen::Vector3d q = grabbed.source + distance * direction;
            bool crowded = false;
            for (size_t other = 0; other < constraints.size() && !crowded; ++other)
                crowded = other != e && (constraints[other].source - q).norm() < minGap;
            if (crowded) continue;
            constraints.push_back({q, grabbed.images, brushProfile(falloff, distance / radius)});
        }
    }
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

double freeCoverage(const Lattice& lattice, const Eigen::Vector3d& params) {
    SupportWeights support;
    supportWeights(lattice, params, support);
    double free = 0.0, total = 0.0;
    for (int c = 0; c < support.count; ++c) {
        total += support.weight[c];
        if (!lattice.pinned[static_cast<size_t>(support.index[c])]) free += support.weight[c];
    }
    return total > 0.0 ? free / total : 0.0;
}

void pinAllBut(Lattice& lattice, const std::vector<int>& freePoints) {
    std::fill(lattice.pinned.begin(), lattice.pinned.end(), std::uint8_t{1});
    for (int idx : freePoints) lattice.pinned[static_cast<size_t>(idx)] = 0;
}

}  // namespace sculpt::core
