// The bundled assets/default.obj (src/tools/make_default_mesh.cpp) must be a surface one can sculpt
// without surprises: closed, manifold, consistently outward, free of self-intersections.
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <unordered_map>
#include <utility>
#include <vector>

#include <Eigen/Geometry>
#include <catch2/catch.hpp>

#include "io/obj_mesh.h"

using sculpt::io::ObjMesh;

namespace {

using Vec3 = Eigen::Vector3d;

Vec3 corner(const ObjMesh& mesh, int t, int c) { return mesh.positions.row(mesh.triangles(t, c)).transpose(); }

// Sign of the volume of tetrahedron (a, b, c, d), i.e. which side of plane abc d lies on.
double orient(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) { return (b - a).cross(c - a).dot(d - a); }

// Does segment pq cross the interior of triangle abc? Strict tests: touching or coplanar
// configurations do not count (they cannot occur between non-adjacent triangles of a smooth blob,
// and an exact predicate is not worth it here).
bool segmentCrossesTriangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c) {
    const double sp = orient(a, b, c, p), sq = orient(a, b, c, q);
    if (!((sp > 0 && sq < 0) || (sp < 0 && sq > 0))) return false;
    const double e0 = orient(p, q, a, b), e1 = orient(p, q, b, c), e2 = orient(p, q, c, a);
    return (e0 > 0 && e1 > 0 && e2 > 0) || (e0 < 0 && e1 < 0 && e2 < 0);
}

// Two triangles intersect (transversally) iff an edge of one crosses the other.
bool trianglesIntersect(const std::array<Vec3, 3>& s, const std::array<Vec3, 3>& t) {
    for (int i = 0; i < 3; ++i) {
        if (segmentCrossesTriangle(s[i], s[(i + 1) % 3], t[0], t[1], t[2])) return true;
        if (segmentCrossesTriangle(t[i], t[(i + 1) % 3], s[0], s[1], s[2])) return true;
    }
    return false;
}

}  // namespace

TEST_CASE("obj: the default mesh is closed, manifold, outward and free of self-intersections") {
    ObjMesh mesh;
    std::vector<std::string> warnings;
    const sculpt::Status status =
        sculpt::io::loadObj(std::string(SCULPT_SOURCE_DIR) + "/assets/default.obj", mesh, &warnings);
    INFO(status.message);
    REQUIRE(status);
    REQUIRE(warnings.empty());
    const int vertexCount = mesh.vertexCount();
    const int triangleCount = static_cast<int>(mesh.triangles.rows());
    REQUIRE(triangleCount >= 20000);
    REQUIRE(triangleCount <= 40000);
    REQUIRE(mesh.texcoords.rows() > 0);
    REQUIRE(std::count(mesh.cornerTexcoord.begin(), mesh.cornerTexcoord.end(), -1) == 0);
    REQUIRE(mesh.groupNames.size() == 2);

    // Every directed edge occurs once and its reverse once: each edge has exactly two triangles that
    // traverse it in opposite directions (closed, edge-manifold, consistently oriented).
    std::map<std::pair<int, int>, int> directedEdges;
    for (int t = 0; t < triangleCount; ++t)
        for (int c = 0; c < 3; ++c) ++directedEdges[{mesh.triangles(t, c), mesh.triangles(t, (c + 1) % 3)}];
    for (const auto& [edge, count] : directedEdges) {
        REQUIRE(count == 1);
        REQUIRE(directedEdges.count({edge.second, edge.first}) == 1);
    }
    // Vertex-manifold: the triangles around each vertex form one closed fan.
    std::vector<std::unordered_map<int, int>> fanNext(static_cast<size_t>(vertexCount));
    for (int t = 0; t < triangleCount; ++t)
        for (int c = 0; c < 3; ++c)
            fanNext[mesh.triangles(t, c)][mesh.triangles(t, (c + 1) % 3)] = mesh.triangles(t, (c + 2) % 3);
    for (int v = 0; v < vertexCount; ++v) {
        const auto& next = fanNext[static_cast<size_t>(v)];
        REQUIRE(next.size() >= 3);
        int steps = 0;
        int at = next.begin()->first;
        do {
            const auto found = next.find(at);
            REQUIRE(found != next.end());
            at = found->second;
            ++steps;
        } while (at != next.begin()->first && steps <= static_cast<int>(next.size()));
        REQUIRE(steps == static_cast<int>(next.size()));
    }
    // Sphere topology: V - E + F = 2.
    REQUIRE(vertexCount - static_cast<int>(directedEdges.size() / 2) + triangleCount == 2);

    // Outward: positive enclosed volume (divergence theorem over the oriented triangles).
    double volume = 0.0;
    for (int t = 0; t < triangleCount; ++t)
        volume += corner(mesh, t, 0).dot(corner(mesh, t, 1).cross(corner(mesh, t, 2))) / 6.0;
    REQUIRE(volume > 1.0);

    // No degenerate triangles and no sharp folds between neighbours (the pair test below skips
    // triangles that share a vertex, so local fold-overs are caught here).
    std::vector<Vec3> normals(static_cast<size_t>(triangleCount));
    for (int t = 0; t < triangleCount; ++t) {
        const Vec3 n = (corner(mesh, t, 1) - corner(mesh, t, 0)).cross(corner(mesh, t, 2) - corner(mesh, t, 0));
        REQUIRE(n.norm() > 1e-8);
        normals[static_cast<size_t>(t)] = n.normalized();
    }
    std::map<std::pair<int, int>, int> edgeTriangle;
    for (int t = 0; t < triangleCount; ++t)
        for (int c = 0; c < 3; ++c) edgeTriangle[{mesh.triangles(t, c), mesh.triangles(t, (c + 1) % 3)}] = t;
    for (const auto& [edge, t] : edgeTriangle)
        REQUIRE(normals[static_cast<size_t>(t)].dot(
                    normals[static_cast<size_t>(edgeTriangle.at({edge.second, edge.first}))]) > 0.5);

    // Self-intersection: bucket triangle bounding boxes in a uniform grid and test each pair that
    // shares a cell once (in the cell holding the min corner of the two boxes' overlap).
    const Vec3 lower = mesh.positions.colwise().minCoeff().transpose();
    const Vec3 upper = mesh.positions.colwise().maxCoeff().transpose();
    const int cellsPerAxis = 48;
    const Vec3 cellSize = (upper - lower) / cellsPerAxis;
    auto cellOf = [&](const Vec3& p) {
        std::array<int, 3> cell;
        for (int k = 0; k < 3; ++k)
            cell[k] = std::clamp(static_cast<int>((p[k] - lower[k]) / cellSize[k]), 0, cellsPerAxis - 1);
        return cell;
    };
    std::vector<Vec3> boxMin(static_cast<size_t>(triangleCount)), boxMax(static_cast<size_t>(triangleCount));
    std::vector<std::vector<int>> cells(static_cast<size_t>(cellsPerAxis * cellsPerAxis * cellsPerAxis));
    auto cellIndex = [&](const std::array<int, 3>& c) { return (c[0] * cellsPerAxis + c[1]) * cellsPerAxis + c[2]; };
    for (int t = 0; t < triangleCount; ++t) {
        boxMin[t] = corner(mesh, t, 0).cwiseMin(corner(mesh, t, 1)).cwiseMin(corner(mesh, t, 2));
        boxMax[t] = corner(mesh, t, 0).cwiseMax(corner(mesh, t, 1)).cwiseMax(corner(mesh, t, 2));
        const auto from = cellOf(boxMin[t]), to = cellOf(boxMax[t]);
        for (int x = from[0]; x <= to[0]; ++x)
            for (int y = from[1]; y <= to[1]; ++y)
                for (int z = from[2]; z <= to[2]; ++z) cells[static_cast<size_t>(cellIndex({x, y, z}))].push_back(t);
    }
    long long pairsTested = 0;
    int intersections = 0;
    for (size_t cell = 0; cell < cells.size(); ++cell) {
        const std::vector<int>& members = cells[cell];
        for (size_t i = 0; i < members.size(); ++i)
            for (size_t j = i + 1; j < members.size(); ++j) {
                const int s = members[i], t = members[j];
                if ((boxMin[s].array() > boxMax[t].array()).any() || (boxMin[t].array() > boxMax[s].array()).any())
                    continue;
                if (static_cast<size_t>(cellIndex(cellOf(boxMin[s].cwiseMax(boxMin[t])))) != cell) continue;
                bool adjacent = false;
                for (int a = 0; a < 3; ++a)
                    for (int b = 0; b < 3; ++b) adjacent = adjacent || mesh.triangles(s, a) == mesh.triangles(t, b);
                if (adjacent) continue;
                ++pairsTested;
                if (trianglesIntersect({corner(mesh, s, 0), corner(mesh, s, 1), corner(mesh, s, 2)},
                                       {corner(mesh, t, 0), corner(mesh, t, 1), corner(mesh, t, 2)}))
                    ++intersections;
            }
    }
    INFO("pairs tested: " << pairsTested);
    REQUIRE(pairsTested > 0);
    REQUIRE(intersections == 0);
}

TEST_CASE("obj: the self-intersection test of the default-mesh check does detect crossing triangles") {
    // Guards the checker above against passing vacuously.
    const std::array<Vec3, 3> flat = {Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(0, 2, 0)};
    const std::array<Vec3, 3> piercing = {Vec3(0.5, 0.5, -1), Vec3(0.5, 0.5, 1), Vec3(3, 3, 0.5)};
    const std::array<Vec3, 3> above = {Vec3(0.5, 0.5, 1), Vec3(1, 0.5, 1), Vec3(0.5, 1, 2)};
    REQUIRE(trianglesIntersect(flat, piercing));
    REQUIRE_FALSE(trianglesIntersect(flat, above));
}
