#include "app/window/picking.h"

#include <cmath>
#include <limits>

#include <Eigen/Geometry>
#include <glm/glm.hpp>

namespace sculpt::app {
namespace {

// Barycentric weights are dimensionless: a ray through the edge two triangles share hits one of them even
// when rounding puts its weights a few ulps outside [0, 1] in both.
constexpr double kBarycentricSlack = 1e-12;

}  // namespace

bool rayThroughPixel(const render::Camera& camera, int width, int height, double x, double y, Ray& ray) {
    if (width <= 0 || height <= 0) return false;
    // note: built from the camera's own basis in double, not by inverting a float view-projection matrix:
    // that loses everything for a 1e-3 mesh at 1e7 and its near plane depends on the scene's scale.
    const double aspect = double(width) / double(height);
    const double tanHalfY = std::tan(glm::radians(double(camera.fovYDeg)) * 0.5);
    const double ndcX = 2.0 * x / width - 1.0;
    const double ndcY = 1.0 - 2.0 * y / height;
    const glm::dvec3 across = (ndcX * tanHalfY * aspect) * camera.right() + (ndcY * tanHalfY) * camera.up();
    // Orthographic: parallel rays, each from the near plane (4 scene radii in front of the target, as
    // Camera::projection puts it) so that what is drawn between the eye and the target is hit too.
    // note: the perspective sum in this order, as it always was: a 1e-3 mesh at 1e7 picks to the last digit.
    const glm::dvec3 direction = camera.orthographic
                                     ? -camera.towardEye()
                                     : -camera.towardEye() + (ndcX * tanHalfY * aspect) * camera.right() +
                                           (ndcY * tanHalfY) * camera.up();
    const double length = glm::length(direction);
    const glm::dvec3 eye = camera.orthographic
                               ? camera.target + camera.distance * across + 4.0 * camera.sceneRadius * camera.towardEye()
                               : camera.eye();
    if (!(length > 0.0) || !std::isfinite(length) || !std::isfinite(eye.x + eye.y + eye.z)) return false;
    ray.origin = Eigen::Vector3d(eye.x, eye.y, eye.z);
    ray.direction = Eigen::Vector3d(direction.x, direction.y, direction.z) / length;
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
        // note: det = |e1| |e2| times a sine (d is unit), so the threshold is relative in every unit: it skips
        // only degenerate and exactly edge-on triangles, alike for a 1e-9 and a 1e9 mesh.
        if (std::abs(det) <= 1e-14 * e1.norm() * e2.norm()) continue;
        const double invDet = 1.0 / det;
        const Eigen::Vector3d s = o - p0;
        const double u = s.dot(p) * invDet;
        if (u < -kBarycentricSlack || u > 1.0 + kBarycentricSlack) continue;
        const Eigen::Vector3d q = s.cross(e1);
        const double v = d.dot(q) * invDet;
        if (v < -kBarycentricSlack || u + v > 1.0 + kBarycentricSlack) continue;
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
    // note: a cosine between unit vectors (the normal is normalised here), not a length: scale-free.
    const double normalLength = normal.norm();
    if (!(normalLength > 0.0)) return false;
    const double denom = ray.direction.dot(normal) / normalLength;
    if (std::abs(denom) < 1e-9) return false;
    const double t = (point - ray.origin).dot(normal) / normalLength / denom;
    if (!(t > 0.0) || !std::isfinite(t)) return false;
    hit = ray.origin + t * ray.direction;
    return true;
}

}  // namespace sculpt::app
