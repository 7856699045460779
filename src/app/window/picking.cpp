#include "app/window/picking.h"

#include <cmath>
#include <limits>

#include <Eigen/Geometry>
#include <glm/gtc/matrix_transform.hpp>

namespace sculpt::app {

bool rayThroughPixel(const render::Camera& camera, int width, int height, double x, double y, Ray& ray) {
    if (width <= 0 || height <= 0) return false;
    const float aspect = static_cast<float>(width) / static_cast<float>(height);
    const glm::mat4 inverse = glm::inverse(camera.projection(aspect) * camera.view());
    const float ndcX = static_cast<float>(2.0 * x / width - 1.0);
    const float ndcY = static_cast<float>(1.0 - 2.0 * y / height);
    glm::vec4 nearPoint = inverse * glm::vec4(ndcX, ndcY, -1.0f, 1.0f);
    glm::vec4 farPoint = inverse * glm::vec4(ndcX, ndcY, 1.0f, 1.0f);
    if (nearPoint.w == 0.0f || farPoint.w == 0.0f) return false;
    nearPoint /= nearPoint.w;
    farPoint /= farPoint.w;
    const glm::vec3 eye = camera.eye();
    ray.origin = Eigen::Vector3d(eye.x, eye.y, eye.z);
    Eigen::Vector3d direction(farPoint.x - nearPoint.x, farPoint.y - nearPoint.y, farPoint.z - nearPoint.z);
    const double length = direction.norm();
    if (!(length > 0.0) || !std::isfinite(length)) return false;
    ray.direction = direction / length;
    return true;
}

SurfaceHit intersectMesh(const Ray& ray, const Positions& positions, const Triangles& triangles) {
    SurfaceHit best;
    double bestT = std::numeric_limits<double>::infinity();
    const Eigen::Vector3d& o = ray.origin;
    const Eigen::Vector3d& d = ray.direction;
    for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
        const Eigen::Vector3d p0 = positions.row(triangles(f, 0)).transpose();
        const Eigen::Vector3d e1 = positions.row(triangles(f, 1)).transpose() - p0;
        const Eigen::Vector3d e2 = positions.row(triangles(f, 2)).transpose() - p0;
        const Eigen::Vector3d p = d.cross(e2);
        const double det = e1.dot(p);
        // note: relative threshold so tiny and huge meshes pick alike; skips only degenerate/edge-on triangles.
        if (std::abs(det) <= 1e-14 * e1.squaredNorm() * e2.norm()) continue;
        const double invDet = 1.0 / det;
        const Eigen::Vector3d s = o - p0;
        const double u = s.dot(p) * invDet;
        if (u < 0.0 || u > 1.0) continue;
        const Eigen::Vector3d q = s.cross(e1);
        const double v = d.dot(q) * invDet;
        if (v < 0.0 || u + v > 1.0) continue;
        const double t = e2.dot(q) * invDet;
        if (t <= 0.0 || t >= bestT) continue;
        bestT = t;
        best.triangle = static_cast<int>(f);
        best.barycentric = Eigen::Vector3d(1.0 - u - v, u, v);
        best.distance = t;
    }
    if (best.triangle >= 0) {
        best.point = o + best.distance * d;
        Eigen::Index corner = 0;
        best.barycentric.maxCoeff(&corner);
        best.nearestCorner = triangles(best.triangle, static_cast<int>(corner));
    }
    return best;
}

bool intersectPlane(const Ray& ray, const Eigen::Vector3d& point, const Eigen::Vector3d& normal,
                    Eigen::Vector3d& hit) {
    const double denom = ray.direction.dot(normal);
    if (std::abs(denom) < 1e-9) return false;
    const double t = (point - ray.origin).dot(normal) / denom;
    if (!(t > 0.0) || !std::isfinite(t)) return false;
    hit = ray.origin + t * ray.direction;
    return true;
}

}  // namespace sculpt::app
