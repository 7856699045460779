#include "core/deform/vertex_normals.h"

#include <cmath>

#include <Eigen/Geometry>

namespace sculpt::core {

namespace {

// Unnormalised normal of triangle t (twice its area, so larger faces weigh more).
inline Eigen::Vector3d faceNormal(const Positions& positions, const Triangles& triangles, Eigen::Index t) {
    const Eigen::Vector3d a = positions.row(triangles(t, 0)).transpose();
    const Eigen::Vector3d b = positions.row(triangles(t, 1)).transpose();
    const Eigen::Vector3d c = positions.row(triangles(t, 2)).transpose();
    return (b - a).cross(c - a);
}

// Sum of unnormalised face normals around v.
Eigen::Vector3d accumulatedNormal(const Positions& positions, const Triangles& triangles,
                                  const VertexTriangles& adjacency, int v) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int k = adjacency.offsets[v]; k < adjacency.offsets[v + 1]; ++k)
        sum += faceNormal(positions, triangles, adjacency.triangles[k]);
    return sum;
}

void storeNormal(const Eigen::Vector3d& sum, Positions& normals, int v) {
    const double length = sum.norm();
    // note: a vertex with only degenerate (or no) triangles has no defined normal; a fixed up vector
    // keeps NaN out of files and the screen.
    if (length > 0.0 && std::isfinite(length))
        normals.row(v) = (sum / length).transpose();
    else
        normals.row(v) << 0.0, 0.0, 1.0;
}

}  // namespace

VertexTriangles buildVertexTriangles(int vertexCount, const Triangles& triangles) {
    VertexTriangles adjacency;
    adjacency.offsets.assign(static_cast<size_t>(vertexCount) + 1, 0);
    for (Eigen::Index t = 0; t < triangles.rows(); ++t)
        for (int c = 0; c < 3; ++c) ++adjacency.offsets[triangles(t, c) + 1];
    for (int v = 0; v < vertexCount; ++v) adjacency.offsets[v + 1] += adjacency.offsets[v];
    adjacency.triangles.resize(adjacency.offsets.back());
    std::vector<int> cursor(adjacency.offsets.begin(), adjacency.offsets.end() - 1);
    for (Eigen::Index t = 0; t < triangles.rows(); ++t)
        for (int c = 0; c < 3; ++c) adjacency.triangles[cursor[triangles(t, c)]++] = static_cast<int>(t);
    return adjacency;
}

void computeVertexNormals(const Positions& positions, const Triangles& triangles, Positions& normals) {
    // A one-off: each vertex sums its ring's face normals itself (no scratch of 3 doubles per triangle to
    // fault in for one use).
    const int n = static_cast<int>(positions.rows());
    const VertexTriangles adjacency = buildVertexTriangles(n, triangles);
    normals.resize(n, 3);
#pragma omp parallel for schedule(static) if (n > 20000)
    for (int v = 0; v < n; ++v) storeNormal(accumulatedNormal(positions, triangles, adjacency, v), normals, v);
}

void computeVertexNormals(const Positions& positions, const Triangles& triangles, const VertexTriangles& adjacency,
                          Positions& normals) {
    const int n = static_cast<int>(positions.rows());
    const int faces = static_cast<int>(triangles.rows());
    normals.resize(n, 3);
    // Each face's normal once (a vertex's ring would compute it three times), then the sums in the order
    // accumulatedNormal adds them, so the sparse update gives these same values.
    std::vector<double>& faceNormals = adjacency.faceNormals;
    faceNormals.resize(3 * static_cast<size_t>(faces));
#pragma omp parallel if (n > 20000)
    {
#pragma omp for schedule(static)
        for (int t = 0; t < faces; ++t) {
            const Eigen::Vector3d normal = faceNormal(positions, triangles, t);
            for (int c = 0; c < 3; ++c) faceNormals[3 * static_cast<size_t>(t) + c] = normal[c];
        }
#pragma omp for schedule(static)
        for (int v = 0; v < n; ++v) {
            Eigen::Vector3d sum = Eigen::Vector3d::Zero();
            for (int k = adjacency.offsets[v]; k < adjacency.offsets[v + 1]; ++k)
                sum += Eigen::Map<const Eigen::Vector3d>(faceNormals.data() + 3 * static_cast<size_t>(adjacency.triangles[k]));
            storeNormal(sum, normals, v);
        }
    }
}

void updateVertexNormals(const Positions& positions, const Triangles& triangles, const VertexTriangles& adjacency,
                         const std::vector<int>& changedVertices, Positions& normals) {
    // The normal of v depends on every triangle around v, so the ring of each changed vertex is stale.
    // A byte per vertex marks each stale vertex once (no sort: a 2% update of 1M vertices lists ~400k ids).
    std::vector<std::uint8_t>& mark = adjacency.stale;
    if (mark.size() != adjacency.offsets.size() - 1) mark.assign(adjacency.offsets.size() - 1, 0);
    std::vector<int> stale;
    stale.reserve(changedVertices.size() * 2);
    for (int v : changedVertices)
        for (int k = adjacency.offsets[v]; k < adjacency.offsets[v + 1]; ++k)
            for (int c = 0; c < 3; ++c) {
                const int w = triangles(adjacency.triangles[k], c);
                if (!mark[w]) {
                    mark[w] = 1;
                    stale.push_back(w);
                }
            }
    for (int w : stale) mark[w] = 0;
    const int count = static_cast<int>(stale.size());
#pragma omp parallel for schedule(static) if (count > 20000)
    for (int i = 0; i < count; ++i)
        storeNormal(accumulatedNormal(positions, triangles, adjacency, stale[i]), normals, stale[i]);
}

}  // namespace sculpt::core
