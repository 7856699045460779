// The sculpting brush's geometry: mirror images of a drag and its region-of-interest lattice (brush.h).
#include "core/deform/brush.h"

#include <algorithm>
#include <cmath>

#include "core/spline/bspline_basis.h"

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

std::string symmetryText(const Symmetry& symmetry, bool planes) {
    std::string text;
    for (int a = 0; a < 3; ++a)
        if (symmetry.mirror[a]) text += static_cast<char>((planes ? 'X' : 'x') + a);
    return text;
}

Status validateBrush(const BrushSettings& brush) {
    if (!std::isfinite(brush.radius) || brush.radius < 0.0) return Status::error("brush radius must be a finite number >= 0");
    if (!std::isfinite(brush.strength) || brush.strength <= 0.0 || brush.strength > 1.0)
        return Status::error("brush strength must be in (0, 1]");
    return Status::success();
}

Eigen::Vector3d reflectPoint(const Eigen::Vector3d& p, int mask, const SymmetryFrame& frame) {
    Eigen::Vector3d q = p;
    const bool aligned = frame.axes == Eigen::Matrix3d::Identity();
    for (int a = 0; a < 3; ++a) {
        if (!(mask & (1 << a))) continue;
        if (aligned) {
            q[a] = 2.0 * frame.centre[a] - q[a];
        } else {
            const Eigen::Vector3d n = frame.axes.col(a);
            q -= 2.0 * (q - frame.centre).dot(n) * n;  // the normals are orthogonal: the reflections commute
        }
    }
    return q;
}

Eigen::Vector3d reflectVector(const Eigen::Vector3d& d, int mask, const SymmetryFrame& frame) {
    return reflectPoint(d, mask, SymmetryFrame{Eigen::Vector3d::Zero(), frame.axes});  // the planes through the origin
}

std::vector<MirroredConstraint> mirrorConstraints(const std::vector<Eigen::Vector3d>& sources, const std::vector<bool>& held,
                                                  const Symmetry& symmetry, const SymmetryFrame& frame, double mergeDistance) {
    std::vector<MirroredConstraint> out;
    for (size_t f = 0; f < sources.size(); ++f) out.push_back({sources[f], {{static_cast<int>(f), 0}}});
    for (int mask = 1; mask < 8; ++mask) {
        bool usable = true;
        for (int a = 0; a < 3; ++a) usable = usable && (!(mask & (1 << a)) || symmetry.mirror[a]);
        if (!usable) continue;
        for (size_t f = 0; f < sources.size(); ++f) {
            if (f < held.size() && held[f]) continue;
            const Eigen::Vector3d s = reflectPoint(sources[f], mask, frame);
            auto near = std::find_if(out.begin(), out.end(), [&](const MirroredConstraint& c) { return (c.source - s).norm() <= mergeDistance; });
            if (near != out.end()) near->images.emplace_back(static_cast<int>(f), mask);
            else out.push_back({s, {{static_cast<int>(f), mask}}});
        }
    }
    return out;
}

Eigen::Vector3d mirroredTarget(const MirroredConstraint& constraint, const std::vector<Eigen::Vector3d>& userTargets,
                               const std::vector<Eigen::Vector3d>& userSources, const SymmetryFrame& frame) {
    Eigen::Vector3d move = Eigen::Vector3d::Zero();
    for (const auto& [user, mask] : constraint.images) {
        // A reflection is affine: the image of a move is the move reflected by its linear part.
        move += reflectVector(userTargets[static_cast<size_t>(user)] - userSources[static_cast<size_t>(user)], mask, frame);
    }
    return constraint.source + move / static_cast<double>(constraint.images.size());
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

void pinAllBut(Lattice& lattice, const std::vector<int>& freePoints) {
    std::fill(lattice.pinned.begin(), lattice.pinned.end(), std::uint8_t{1});
    for (int idx : freePoints) lattice.pinned[static_cast<size_t>(idx)] = 0;
}

}  // namespace sculpt::core
