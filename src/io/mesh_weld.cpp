#include "io/mesh_weld.h"

#include <cstdint>
#include <cstring>
#include <unordered_map>
#include <vector>

namespace sculpt::io {

namespace {

// Vertex v -> its welded number (the order of first use); firstOf: the first vertex of each welded one.
void weldMap(const Positions& positions, std::vector<int>& remap, std::vector<Eigen::Index>& firstOf) {
    struct Key {
        double x, y, z;
        bool operator==(const Key& o) const { return std::memcmp(this, &o, sizeof(Key)) == 0; }
    };
    struct KeyHash {
        size_t operator()(const Key& k) const {
            uint64_t h = 1469598103934665603ull;
            const unsigned char* p = reinterpret_cast<const unsigned char*>(&k);
            for (size_t i = 0; i < sizeof(Key); ++i) h = (h ^ p[i]) * 1099511628211ull;
            return static_cast<size_t>(h);
        }
    };
    const Eigen::Index n = positions.rows();
    std::unordered_map<Key, int, KeyHash> index;
    index.reserve(static_cast<size_t>(n));
    remap.assign(static_cast<size_t>(n), 0);
    firstOf.clear();
    firstOf.reserve(static_cast<size_t>(n));
    for (Eigen::Index v = 0; v < n; ++v) {
        // + 0.0 turns -0.0 into +0.0: a writer may print a shared corner as "-0" in one facet and "0" in another.
        const Key key{positions(v, 0) + 0.0, positions(v, 1) + 0.0, positions(v, 2) + 0.0};
        const auto [it, inserted] = index.emplace(key, static_cast<int>(firstOf.size()));
        if (inserted) firstOf.push_back(v);
        remap[static_cast<size_t>(v)] = it->second;
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
