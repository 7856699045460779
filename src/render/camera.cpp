#include "render/camera.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

namespace sculpt::render {

void Bounds::add(const glm::dvec3& point) {
    sphereRadius = -1.0;
    if (empty) {
        min = max = point;
        empty = false;
        return;
    }
    min = glm::min(min, point);
    max = glm::max(max, point);
}

void Bounds::add(const Bounds& other) {
    if (other.empty) return;
    if (empty) {
        *this = other;
        return;
    }
    const Bounds before = *this;
    min = glm::min(min, other.min);
    max = glm::max(max, other.max);
    sphereRadius = -1.0;
    if (before.sphereRadius >= 0.0 && other.sphereRadius >= 0.0) {
        // Both spheres, seen from the new centre, fit in this one.
        sphereRadius = std::max(glm::length(before.center() - center()) + before.sphereRadius,
                                glm::length(other.center() - center()) + other.sphereRadius);
        sphereRadius = std::min(sphereRadius, 0.5 * glm::length(max - min));
    }
}

double Bounds::radius() const {
    if (empty) return 0.0;
    return sphereRadius >= 0.0 ? sphereRadius : 0.5 * glm::length(max - min);
}

Bounds boundsOf(const Positions& points) {
    Bounds bounds;
    const auto row = [&](Eigen::Index i) { return glm::dvec3(points(i, 0), points(i, 1), points(i, 2)); };
    for (Eigen::Index i = 0; i < points.rows(); ++i)
        if (points.row(i).allFinite()) bounds.add(row(i));
    if (bounds.empty) return bounds;
    const glm::dvec3 center = bounds.center();
    double radius = 0.0;
    for (Eigen::Index i = 0; i < points.rows(); ++i)
        if (points.row(i).allFinite()) radius = std::max(radius, glm::length(row(i) - center));
    bounds.sphereRadius = radius;
    return bounds;
}

double framingRadius(const Bounds& bounds) {
    if (bounds.empty) return 1.0;
    const double radius = bounds.radius();
    if (radius > 0.0 && std::isfinite(radius)) return radius;
    // note: a single point has no size of its own; any positive radius frames it, and one relative to where it
    // lies keeps its neighbourhood representable (no absolute floor: that would swallow a 1e-9 mesh).
    const double away = glm::length(bounds.center());
    return away > 0.0 && std::isfinite(away) ? 1e-3 * away : 1.0;
}

LocalFrame localFrameOf(const Bounds& bounds) {
    if (bounds.empty) return {};
    return {bounds.center(), framingRadius(bounds)};
}

void Camera::frame(const Bounds& bounds, float aspect, float fill) {
    if (bounds.empty) return;
    target = bounds.center();
    sceneRadius = framingRadius(bounds);
    const double halfFovY = glm::radians(double(fovYDeg)) * 0.5;
    // note: the aspect floor is a ratio of pixels, not a length.
    const double halfFovX = std::atan(std::tan(halfFovY) * std::max(double(aspect), 1e-3));
    const double halfFov = std::min(halfFovX, halfFovY);
    // The sphere's silhouette spans radius / distance = sin(angle): it fills `fill` of the half angle.
    distance = sceneRadius / std::sin(halfFov * std::clamp(double(fill), 0.05, 1.0));
}

glm::dvec3 Camera::towardEye() const {
    const double yaw = glm::radians(double(yawDeg));
    const double pitch = glm::radians(std::clamp(double(pitchDeg), -90.0, 90.0));
    return {std::cos(pitch) * std::sin(yaw), std::sin(pitch), std::cos(pitch) * std::cos(yaw)};
}

glm::dvec3 Camera::eye() const { return target + distance * towardEye(); }

glm::dvec3 Camera::right() const {
    // glm::lookAt's side vector: forward x up, forward = -towardEye(). Looking straight down or up (pitch
    // +-90, the top and bottom views) that is parallel to +Y; the same vector then comes from the yaw alone.
    if (std::abs(pitchDeg) >= 90.0f) {
        const double yaw = glm::radians(double(yawDeg));
        return {std::cos(yaw), 0.0, -std::sin(yaw)};
    }
    return glm::normalize(glm::cross(-towardEye(), glm::dvec3(0.0, 1.0, 0.0)));
}

glm::dvec3 Camera::up() const { return glm::cross(right(), -towardEye()); }

double Camera::worldPerPixel(int height) const {
    return 2.0 * distance * std::tan(glm::radians(double(fovYDeg)) * 0.5) / double(std::max(height, 1));
}

glm::dmat4 Camera::view(const LocalFrame& frame) const {
    // note: the eye is placed relative to the target in the frame (not eye() minus the origin), so a camera
    // 1e7 away from the world origin still sees a 1e-3 mesh with all of double's digits.
    const glm::dvec3 localTarget = frame.toLocal(target);
    const glm::dvec3 localEye = localTarget + (distance / frame.scale) * towardEye();
    // note: +Y as lookAt's up hint except straight down or up, where it is parallel to the view direction.
    const bool vertical = std::abs(pitchDeg) >= 90.0f;
    return glm::lookAt(localEye, localTarget, vertical ? up() : glm::dvec3(0.0, 1.0, 0.0));
}

glm::dmat4 Camera::projection(double aspect, const LocalFrame& frame) const {
    // Near and far hug the content (four times its radius around the target, for padded lattices and
    // handles that stick out) so the 24-bit depth buffer keeps its precision on the surface. Both are
    // relative: the content's radius, and near at least 1e-3 of far (the ratio decides depth precision).
    const double reach = 4.0 * sceneRadius;
    const double farPlane = distance + reach;
    if (orthographic) {
        // A parallel view may reach behind the eye (zoomed in, the eye can sit inside the content).
        const double halfHeight = distance * std::tan(glm::radians(double(fovYDeg)) * 0.5) / frame.scale;
        const double halfWidth = halfHeight * std::max(aspect, 1e-3);
        return glm::ortho(-halfWidth, halfWidth, -halfHeight, halfHeight, (distance - reach) / frame.scale,
                          farPlane / frame.scale);
    }
    const double nearPlane = std::max(distance - reach, farPlane * 1e-3);
    return glm::perspective(glm::radians(double(fovYDeg)), std::max(aspect, 1e-3), nearPlane / frame.scale,
                            farPlane / frame.scale);
}

}  // namespace sculpt::render
