#include "app/window/tools.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/glm.hpp>

namespace sculpt::app {
namespace {

// World -> clip space in double, in a frame about the camera's target scaled by the scene's radius (camera.h),
// so markers of a 1e-3 mesh at 1e7 or of a 1e-9 one project to the pixels they are drawn at.
struct ClipProjection {
    render::LocalFrame frame;
    glm::dmat4 viewProjection{1.0};

    ClipProjection(const render::Camera& camera, int width, int height)
        : frame{camera.target, camera.sceneRadius > 0.0 ? camera.sceneRadius : 1.0},
          viewProjection(camera.projection(double(width) / double(height), frame) * camera.view(frame)) {}

    // w <= 0 behind the eye.
    glm::dvec4 toClip(const Eigen::Vector3d& point) const {
        return viewProjection * glm::dvec4(frame.toLocal(glm::dvec3(point.x(), point.y(), point.z())), 1.0);
    }
};

bool clipToPixel(const glm::dvec4& clip, int width, int height, double& x, double& y) {
    if (!(clip.w > 0.0)) return false;
    x = (clip.x / clip.w * 0.5 + 0.5) * width;
    y = (0.5 - clip.y / clip.w * 0.5) * height;
    return std::isfinite(x) && std::isfinite(y);
}

}  // namespace

size_t pinCount(const ToolState& tools) {
    return static_cast<size_t>(std::count_if(tools.handles.begin(), tools.handles.end(), [](const SurfaceHandle& h) { return h.pin; }));
}

Eigen::Vector3d handlePosition(const SurfaceHandle& handle, const Positions& positions, const Triangles& triangles) {
    Eigen::Vector3d point = Eigen::Vector3d::Zero();
    for (int c = 0; c < 3; ++c) point += handle.barycentric[c] * positions.row(triangles(handle.triangle, c)).transpose();
    return point;
}

bool projectToPixel(const render::Camera& camera, int width, int height, const Eigen::Vector3d& point, double& x,
                    double& y) {
    if (width <= 0 || height <= 0) return false;
    return clipToPixel(ClipProjection(camera, width, height).toClip(point), width, height, x, y);
}

int handleAtPixel(const ToolState& tools, const Positions& positions, const Triangles& triangles,
                  const render::Camera& camera, int width, int height, double x, double y, double radius) {
    int best = -1;
    double bestDistance = radius;
    for (size_t h = 0; h < tools.handles.size(); ++h) {
        double px = 0.0, py = 0.0;
        if (!projectToPixel(camera, width, height, handlePosition(tools.handles[h], positions, triangles), px, py)) continue;
        const double distance = std::hypot(px - x, py - y);
        if (distance <= bestDistance) {
            bestDistance = distance;
            best = static_cast<int>(h);
        }
    }
    return best;
}

int controlPointAtPixel(const Positions& controlPoints, const std::vector<std::uint8_t>& shown,
                        const render::Camera& camera, int width, int height, double x, double y, double radius,
                        const std::vector<std::uint8_t>& pinned, double overlap) {
    if (width <= 0 || height <= 0) return -1;
    const ClipProjection projection(camera, width, height);
    struct Candidate {
        int id;
        double distance, depth;
        bool pinned;
    };
    std::vector<Candidate> near;
    double nearest = std::numeric_limits<double>::infinity();
    for (Eigen::Index p = 0; p < controlPoints.rows(); ++p) {
        if (!shown.empty() && !shown[static_cast<size_t>(p)]) continue;
        const glm::dvec4 clip = projection.toClip(controlPoints.row(p).transpose());
        double px = 0.0, py = 0.0;
        if (!clipToPixel(clip, width, height, px, py)) continue;
        const double distance = std::hypot(px - x, py - y);
        if (distance > radius) continue;
        // note: the depth is NDC z: in an orthographic view clip.w is 1 for every point.
        const bool isPinned = !pinned.empty() && pinned[static_cast<size_t>(p)] != 0;
        near.push_back({static_cast<int>(p), distance, clip.z / clip.w, isPinned});
        nearest = std::min(nearest, distance);
    }
    int best = -1;
    const Candidate* chosen = nullptr;
    for (const Candidate& c : near) {
        if (c.distance > nearest + overlap) continue;  // not under the cursor: another marker is
        const bool better = !chosen || (chosen->pinned && !c.pinned) ||
                            (chosen->pinned == c.pinned && (c.depth < chosen->depth || (c.depth == chosen->depth && c.distance < chosen->distance)));
        if (better) {
            chosen = &c;
            best = c.id;
        }
    }
    return best;
}

std::vector<int> controlPointsInRectangle(const Positions& controlPoints, const std::vector<std::uint8_t>& shown,
                                          const render::Camera& camera, int width, int height, double x0, double y0,
                                          double x1, double y1) {
    std::vector<int> inside;
    if (width <= 0 || height <= 0) return inside;
    const ClipProjection projection(camera, width, height);
    const double left = std::min(x0, x1), right = std::max(x0, x1), top = std::min(y0, y1), bottom = std::max(y0, y1);
    for (Eigen::Index p = 0; p < controlPoints.rows(); ++p) {
        if (!shown.empty() && !shown[static_cast<size_t>(p)]) continue;
        double px = 0.0, py = 0.0;
        if (!clipToPixel(projection.toClip(controlPoints.row(p).transpose()), width, height, px, py)) continue;
        if (px >= left && px <= right && py >= top && py <= bottom) inside.push_back(static_cast<int>(p));
    }
    return inside;
}

void toggleInSelection(std::vector<int>& selection, int id) {
    const auto at = std::lower_bound(selection.begin(), selection.end(), id);
    if (at != selection.end() && *at == id) selection.erase(at);
    else selection.insert(at, id);
}

void addToSelection(std::vector<int>& selection, const std::vector<int>& ids) {
    selection.insert(selection.end(), ids.begin(), ids.end());
    std::sort(selection.begin(), selection.end());
    selection.erase(std::unique(selection.begin(), selection.end()), selection.end());
}

}  // namespace sculpt::app
