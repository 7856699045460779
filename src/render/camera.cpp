#include "render/camera.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

namespace sculpt::render {

void Bounds::add(const glm::vec3& point) {
    sphereRadius = -1.0f;
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
    sphereRadius = -1.0f;
    if (before.sphereRadius >= 0.0f && other.sphereRadius >= 0.0f) {
        // Both spheres, seen from the new centre, fit in this one.
        sphereRadius = std::max(glm::length(before.center() - center()) + before.sphereRadius,
                                glm::length(other.center() - center()) + other.sphereRadius);
        sphereRadius = std::min(sphereRadius, 0.5f * glm::length(max - min));
    }
}

float Bounds::radius() const {
    if (empty) return 0.0f;
    return sphereRadius >= 0.0f ? sphereRadius : 0.5f * glm::length(max - min);
}

Bounds boundsOf(const Positions& points) {
    Bounds bounds;
    for (Eigen::Index i = 0; i < points.rows(); ++i) {
        if (!points.row(i).allFinite()) continue;
        bounds.add(glm::vec3(float(points(i, 0)), float(points(i, 1)), float(points(i, 2))));
    }
    if (bounds.empty) return bounds;
    const glm::vec3 center = bounds.center();
    float radius = 0.0f;
    for (Eigen::Index i = 0; i < points.rows(); ++i) {
        if (!points.row(i).allFinite()) continue;
        radius = std::max(radius, glm::length(glm::vec3(float(points(i, 0)), float(points(i, 1)),
                                                        float(points(i, 2))) - center));
    }
    bounds.sphereRadius = radius;
    return bounds;
}

void Camera::frame(const Bounds& bounds, float aspect, float fill) {
    if (bounds.empty) return;
    target = bounds.center();
    // note: a flat or single-point box still needs a positive radius to place the camera.
    sceneRadius = std::max(bounds.radius(), 1e-6f);
    const float halfFovY = glm::radians(fovYDeg) * 0.5f;
    const float halfFovX = std::atan(std::tan(halfFovY) * std::max(aspect, 1e-3f));
    const float halfFov = std::min(halfFovX, halfFovY);
    // The sphere's silhouette spans radius / distance = sin(angle): it fills `fill` of the half angle.
    distance = sceneRadius / std::sin(halfFov * std::clamp(fill, 0.05f, 1.0f));
}

glm::vec3 Camera::eye() const {
    const float yaw = glm::radians(yawDeg);
    const float pitch = glm::radians(std::clamp(pitchDeg, -89.0f, 89.0f));
    const glm::vec3 direction(std::cos(pitch) * std::sin(yaw), std::sin(pitch), std::cos(pitch) * std::cos(yaw));
    return target + distance * direction;
}

glm::mat4 Camera::view() const { return glm::lookAt(eye(), target, glm::vec3(0.0f, 1.0f, 0.0f)); }

glm::mat4 Camera::projection(float aspect) const {
    // Near and far hug the content (four times its radius around the target, for padded lattices and
    // handles that stick out) so the 24-bit depth buffer keeps its precision on the surface.
    const float reach = 4.0f * sceneRadius;
    const float farPlane = distance + reach;
    const float nearPlane = std::max(distance - reach, farPlane * 1e-3f);
    return glm::perspective(glm::radians(fovYDeg), std::max(aspect, 1e-3f), nearPlane, farPlane);
}

}  // namespace sculpt::render
