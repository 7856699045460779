#include "io/mesh_weld.h"

#include <vector>

#include "core/deform/refinement.h"

namespace sculpt::io {

namespace {

// Vertex v -> its welded number (the order of first use); firstOf: the first vertex of each welded one. The
// vertices at one position are the engine's seam copies (core::seamCopiesOf: exactly equal, -0 as 0).
void weldMap(const Positions& positions, std::vector<int>& remap, std::vector<Eigen::Index>& firstOf) {
    const std::vector<int> first = core::seamCopiesOf(positions);
    const Eigen::Index n = positions.rows();
    remap.assign(static_cast<size_t>(n), 0);
    firstOf.clear();
    firstOf.reserve(static_cast<size_t>(n));
    for (Eigen::Index v = 0; v < n; ++v) {
        const int at = first.empty() ? static_cast<int>(v) : first[static_cast<size_t>(v)];
        if (at == v) {
            remap[static_cast<size_t>(v)] = static_cast<int>(firstOf.size());
            firstOf.push_back(v);
        } else {
            remap[static_cast<size_t>(v)] = remap[static_cast<size_t>(at)];  // (at < v: numbered already)
        }
    }
}

}  // namespace

WeldReport countCoincidentVertices(const Positions& positions) {
    std::vector<int> remap;
    std::vector<Eigen::Index> firstOf;
    weldMap(positions, remap, firstOf);
    WeldReport report;
    report.verticesBefore = static_cast<int>(positions.rows());
    report.verticesAfter = static_cast<int>(firstOf.size());
    return report;
}

WeldReport weldCoincidentVertices(ObjMesh& mesh) {
    WeldReport report;
    const Eigen::Index n = mesh.positions.rows();
    report.verticesBefore = report.verticesAfter = static_cast<int>(n);
    std::vector<int> remap;
    std::vector<Eigen::Index> firstOf;  // the vertex each welded one was first
    weldMap(mesh.positions, remap, firstOf);
    const Eigen::Index count = static_cast<Eigen::Index>(firstOf.size());
    if (count == n) return report;
    report.verticesAfter = static_cast<int>(count);
    Positions welded(count, 3);
    for (Eigen::Index w = 0; w < count; ++w) welded.row(w) = mesh.positions.row(firstOf[static_cast<size_t>(w)]);
    mesh.positions = std::move(welded);
    if (mesh.vertexColors.rows() == n) {
        VertexColors colours(count, 4);
        for (Eigen::Index w = 0; w < count; ++w) colours.row(w) = mesh.vertexColors.row(firstOf[static_cast<size_t>(w)]);
        mesh.vertexColors = std::move(colours);
    }
    mesh.vertexNormals.resize(0, 3);
    // A per-vertex format's texture coordinates stay with the corners that used them (cornerTexcoord keeps its
    // rows): a save says where the corners of a welded vertex disagree.
    for (int& c : mesh.cornerVertex) c = remap[static_cast<size_t>(c)];
    for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
        for (int k = 0; k < 3; ++k) mesh.triangles(t, k) = remap[static_cast<size_t>(mesh.triangles(t, k))];
        const auto& tri = mesh.triangles;
        if (tri(t, 0) == tri(t, 1) || tri(t, 1) == tri(t, 2) || tri(t, 0) == tri(t, 2)) ++report.trianglesCollapsed;
    }
    mesh.source.reset();
    return report;
}

}  // namespace sculpt::io
