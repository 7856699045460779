// Independent checks for the refinement tests: the deviation of a triangle from its image sampled densely
// (more points than the algorithm's four), and conformity of a triangle mesh from its edges alone.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <random>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "core/mesh_types.h"

namespace sculpt::test {

// The largest |image(rest point) - flat point| over a barycentric grid of `n` steps per side ((n+1)(n+2)/2
// points, corners included) of every triangle: world units, per triangle.
inline std::vector<double> sampledDeviations(const Positions& rest, const Positions& current, const Triangles& triangles,
                                             const std::function<Eigen::Vector3d(const Eigen::Vector3d&)>& image, int n = 8) {
    std::vector<double> out(static_cast<size_t>(triangles.rows()), 0.0);
    for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
        const int a = triangles(t, 0), b = triangles(t, 1), c = triangles(t, 2);
        double worst = 0.0;
        for (int i = 0; i <= n; ++i)
            for (int j = 0; i + j <= n; ++j) {
                const double u = double(i) / n, v = double(j) / n, w = std::max(0.0, 1.0 - u - v);
                // note: kept inside the corners' box, where a convex combination lies: a mesh on the lattice's
                // face (padding 0) must not have samples rounded out of the lattice.
                const Eigen::Vector3d lo = rest.row(a).cwiseMin(rest.row(b)).cwiseMin(rest.row(c)).transpose();
                const Eigen::Vector3d hi = rest.row(a).cwiseMax(rest.row(b)).cwiseMax(rest.row(c)).transpose();
                const Eigen::Vector3d restPoint =
                    (u * rest.row(a).transpose() + v * rest.row(b).transpose() + w * rest.row(c).transpose()).cwiseMax(lo).cwiseMin(hi);
                const Eigen::Vector3d flat = u * current.row(a).transpose() + v * current.row(b).transpose() + w * current.row(c).transpose();
                worst = std::max(worst, (image(restPoint) - flat).norm());
            }
        out[static_cast<size_t>(t)] = worst;
    }
    return out;
}

// What the edges of a triangle mesh say about it (by vertex id only).
struct EdgeCensus {
    int vertices = 0;               // vertices used by a triangle
    int edges = 0;                  // undirected edges
    int boundaryEdges = 0;          // used by one triangle
    int nonManifoldEdges = 0;       // used by more than two
    int inconsistentEdges = 0;      // used twice in the same direction (orientation flips across the edge)
    int euler() const { return vertices - edges; }  // plus the triangle count: V - E + F
};

inline EdgeCensus edgeCensus(const Triangles& triangles) {
    std::map<std::pair<int, int>, std::pair<int, int>> directed;  // undirected edge -> (count a<b, count a>b)
    std::vector<int> used;
    for (Eigen::Index t = 0; t < triangles.rows(); ++t)
        for (int k = 0; k < 3; ++k) {
            const int a = triangles(t, k), b = triangles(t, (k + 1) % 3);
            auto& entry = directed[std::minmax(a, b)];
            (a < b ? entry.first : entry.second) += 1;
            used.push_back(a);
        }
    std::sort(used.begin(), used.end());
    EdgeCensus census;
    census.vertices = static_cast<int>(std::unique(used.begin(), used.end()) - used.begin());
    for (const auto& [edge, counts] : directed) {
        ++census.edges;
        const int total = counts.first + counts.second;
        if (total == 1) ++census.boundaryEdges;
        if (total > 2) ++census.nonManifoldEdges;
        if (total == 2 && counts.first != 1) ++census.inconsistentEdges;
    }
    return census;
}

// Edges of the mesh whose rest-space midpoint is a vertex of the mesh (bitwise): an edge split on one side and
// not the other (a T-junction) leaves exactly that.
inline int tJunctions(const Positions& rest, const Triangles& triangles) {
    std::map<std::array<double, 3>, int> at;
    for (Eigen::Index v = 0; v < rest.rows(); ++v) at[{rest(v, 0), rest(v, 1), rest(v, 2)}] = static_cast<int>(v);
    int count = 0;
    for (Eigen::Index t = 0; t < triangles.rows(); ++t)
        for (int k = 0; k < 3; ++k) {
            const Eigen::RowVector3d m = 0.5 * (rest.row(triangles(t, k)) + rest.row(triangles(t, (k + 1) % 3)));
            count += at.count({m(0), m(1), m(2)}) > 0;
        }
    return count;
}

// A height field over [0, width] x [0, height]: (nx+1) x (ny+1) vertices jittered in the plane, each quad split
// by a random diagonal, all facing +z.
inline void jitteredGrid(std::mt19937& rng, int nx, int ny, double width, double height, Positions& positions, Triangles& triangles) {
    std::uniform_real_distribution<double> jitter(-0.2, 0.2), bump(-0.02, 0.02);
    positions.resize((nx + 1) * (ny + 1), 3);
    for (int j = 0; j <= ny; ++j)
        for (int i = 0; i <= nx; ++i) {
            const bool inside = i > 0 && i < nx && j > 0 && j < ny;
            positions.row(j * (nx + 1) + i) << width * (i + (inside ? jitter(rng) : 0.0)) / nx,
                height * (j + (inside ? jitter(rng) : 0.0)) / ny, inside ? bump(rng) * width : 0.0;
        }
    triangles.resize(2 * nx * ny, 3);
    int t = 0;
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            const int a = j * (nx + 1) + i, b = a + 1, c = a + nx + 1, d = c + 1;
            if (rng() % 2) {
                triangles.row(t++) << a, b, d;
                triangles.row(t++) << a, d, c;
            } else {
                triangles.row(t++) << a, b, c;
                triangles.row(t++) << b, d, c;
            }
        }
}

}  // namespace sculpt::test
