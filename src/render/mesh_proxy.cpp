// Proxy by quadric-error-metric edge collapse (Garland & Heckbert 1997, "Surface simplification using quadric
// error metrics"), as implemented by meshoptimizer's meshopt_simplify; for very large meshes its sloppy
// variant (vertex clustering on a grid, no topology kept), which is about ten times faster.
#include "render/mesh_proxy.h"

#include <vector>

#include <meshoptimizer.h>

namespace sculpt::render {

Triangles buildMeshProxy(const Positions& positions, const Triangles& triangles, const MeshProxyOptions& options) {
    const Eigen::Index triangleCount = triangles.rows();
    if (triangleCount < options.minTriangles || positions.rows() == 0) return Triangles(0, 3);
    // note: float positions about the centre, so a small mesh far from the origin keeps its shape's digits; the
    // simplifier's error is relative to the extent, so the scale does not matter.
    const Eigen::RowVector3d center = 0.5 * (positions.colwise().minCoeff() + positions.colwise().maxCoeff());
    const Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::RowMajor> local = (positions.rowwise() - center).cast<float>();
    static_assert(sizeof(int) == sizeof(unsigned int), "Triangles' indices are read as unsigned int");
    const auto* indices = reinterpret_cast<const unsigned int*>(triangles.data());
    const size_t indexCount = size_t(triangleCount) * 3, vertexCount = size_t(local.rows());
    const size_t targetIndexCount = size_t(options.targetTriangles) * 3;
    std::vector<unsigned int> simplified(indexCount);  // the simplifiers' worst case is the input size
    const size_t kept =
        triangleCount < options.sloppyFromTriangles
            ? meshopt_simplify(simplified.data(), indices, indexCount, local.data(), vertexCount, 3 * sizeof(float),
                               targetIndexCount, options.maxRelativeError, 0, nullptr)
            : meshopt_simplifySloppy(simplified.data(), indices, indexCount, local.data(), vertexCount,
                                     3 * sizeof(float), targetIndexCount, options.maxRelativeError, nullptr);
    if (kept == 0 || kept * 4 > indexCount * 3) return Triangles(0, 3);
    // note: vertex-cache order, so the rasterizer shades each kept vertex about once.
    meshopt_optimizeVertexCache(simplified.data(), simplified.data(), kept, vertexCount);
    Triangles proxy(Eigen::Index(kept / 3), 3);
    for (size_t i = 0; i < kept; ++i) proxy.data()[i] = int(simplified[i]);
    return proxy;
}

}  // namespace sculpt::render
