// Picking: the ray under a cursor and its first hit on the mesh (current positions).
#pragma once

#include <Eigen/Core>

#include "core/mesh_types.h"
#include "render/camera.h"

namespace sculpt::app {

struct Ray {
    Eigen::Vector3d origin = Eigen::Vector3d::Zero();
    Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();  // unit length
};

// The ray through pixel (x, y) (framebuffer pixels, origin top-left) of a width x height view of `camera`.
// Returns false for an empty view (width or height <= 0) or a degenerate camera.
bool rayThroughPixel(const render::Camera& camera, int width, int height, double x, double y, Ray& ray);

struct SurfaceHit {
    int triangle = -1;                                  // -1: no hit
    Eigen::Vector3d barycentric = Eigen::Vector3d::Zero();  // weights of the triangle's three corners
    Eigen::Vector3d point = Eigen::Vector3d::Zero();
    double distance = 0.0;                              // along the ray
    int nearestCorner = -1;                             // vertex id of the corner with the largest weight
};

// Nearest intersection of the ray with the triangles (Moller & Trumbore 1997, both faces), brute force over
// all #F triangles: ~0.1 ms per 10k triangles, paid once per click. positions #V x 3, triangles #F x 3.
SurfaceHit intersectMesh(const Ray& ray, const Positions& positions, const Triangles& triangles);

// Where the ray meets the plane through `point` with normal `normal` (any nonzero length); false if the ray is
// within 1e-9 (a cosine) of parallel to the plane, or the plane is behind the ray's origin.
bool intersectPlane(const Ray& ray, const Eigen::Vector3d& point, const Eigen::Vector3d& normal,
                    Eigen::Vector3d& hit);

}  // namespace sculpt::app
