// Deterministic meshes for the GL tests and the render benchmarks (no files needed).
#pragma once

#include <cmath>
#include <vector>

#include "../core/mesh_fixtures.h"
#include "core/mesh_types.h"
#include "render/scene.h"

namespace sculpt::test {

struct TestMesh {
    Positions positions;
    Triangles triangles;
};

// Icosahedron subdivided `subdivisions` times, projected to the sphere: 20 * 4^s triangles (the engine tests'
// generator, mesh_fixtures.h).
inline TestMesh makeIcosphere(int subdivisions, double radius = 1.0) {
    TestMesh mesh;
    icosphere(subdivisions, radius, Eigen::Vector3d::Zero(), mesh.positions, mesh.triangles);
    return mesh;
}

// An icosphere with smooth deterministic bumps: reads as an organic 3D shape, so shading is judged fairly.
inline TestMesh makeBlob(int subdivisions) {
    TestMesh mesh = makeIcosphere(subdivisions);
    for (Eigen::Index v = 0; v < mesh.positions.rows(); ++v) {
        const Eigen::Vector3d p = mesh.positions.row(v).transpose();
        const double bump = 0.16 * std::sin(3.0 * p.x() + 0.5) * std::cos(2.0 * p.y()) +
                            0.10 * std::sin(4.0 * p.z() + 2.0 * p.y()) + 0.08 * p.y() * p.y() +
                            0.035 * std::sin(7.0 * p.x() + 1.0) * std::sin(6.0 * p.z() + 0.3) * std::cos(5.0 * p.y());
        mesh.positions.row(v) = ((1.0 + bump) * p).transpose();
        mesh.positions(v, 1) *= 0.85;  // a little squat, so the silhouette is not a circle
    }
    return mesh;
}

// Latitude-longitude sphere: `segments` around, `rings` latitude bands (>= 2).
// 2 * segments * (rings - 1) triangles, segments * (rings - 1) + 2 vertices.
inline TestMesh makeUvSphere(int segments, int rings, double radius = 1.0) {
    const double pi = 3.14159265358979323846;
    TestMesh mesh;
    const int vertexCount = segments * (rings - 1) + 2;
    mesh.positions.resize(vertexCount, 3);
    mesh.positions.row(0) << 0.0, radius, 0.0;
    for (int r = 1; r < rings; ++r) {
        const double polar = pi * r / rings;
        for (int s = 0; s < segments; ++s) {
            const double azimuth = 2.0 * pi * s / segments;
            mesh.positions.row(1 + (r - 1) * segments + s) << radius * std::sin(polar) * std::cos(azimuth),
                radius * std::cos(polar), radius * std::sin(polar) * std::sin(azimuth);
        }
    }
    mesh.positions.row(vertexCount - 1) << 0.0, -radius, 0.0;
    mesh.triangles.resize(2 * segments * (rings - 1), 3);
    int t = 0;
    const auto ring = [&](int r, int s) { return 1 + (r - 1) * segments + (s % segments); };
    for (int s = 0; s < segments; ++s) mesh.triangles.row(t++) << 0, ring(1, s + 1), ring(1, s);
    for (int r = 1; r + 1 < rings; ++r)
        for (int s = 0; s < segments; ++s) {
            mesh.triangles.row(t++) << ring(r, s), ring(r, s + 1), ring(r + 1, s);
            mesh.triangles.row(t++) << ring(r, s + 1), ring(r + 1, s + 1), ring(r + 1, s);
        }
    for (int s = 0; s < segments; ++s) mesh.triangles.row(t++) << vertexCount - 1, ring(rings - 1, s), ring(rings - 1, s + 1);
    return mesh;
}

// A regular nu x nv x nw lattice spanning the box [lo, hi] (control point i + nu*(j + nv*k)).
inline render::LatticeView makeBoxLattice(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, int nu, int nv,
                                          int nw) {
    render::LatticeView lattice;
    lattice.nu = nu;
    lattice.nv = nv;
    lattice.nw = nw;
    lattice.controlPoints.resize(Eigen::Index(nu) * nv * nw, 3);
    for (int k = 0; k < nw; ++k)
        for (int j = 0; j < nv; ++j)
            for (int i = 0; i < nu; ++i) {
                const Eigen::Vector3d t(nu > 1 ? double(i) / (nu - 1) : 0.5, nv > 1 ? double(j) / (nv - 1) : 0.5,
                                        nw > 1 ? double(k) / (nw - 1) : 0.5);
                lattice.controlPoints.row(i + nu * (j + nv * k)) = (lo + t.cwiseProduct(hi - lo)).transpose();
            }
    return lattice;
}

}  // namespace sculpt::test
