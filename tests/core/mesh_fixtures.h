// Test meshes and an independent self-intersection check for the injectivity tests.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <unordered_map>
#include <vector>

#include <Eigen/Geometry>

#include "core/mesh_types.h"

namespace sculpt::test {

// A closed icosphere (radius r, centre c) subdivided `levels` times: 20 * 4^levels triangles, outward facing.
inline void icosphere(int levels, double radius, const Eigen::Vector3d& centre, Positions& positions, Triangles& triangles) {
    const double t = (1.0 + std::sqrt(5.0)) / 2.0;
    std::vector<Eigen::Vector3d> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                                      {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    for (auto& p : v) p.normalize();
    std::vector<std::array<int, 3>> f = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                                         {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
                                         {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
    for (int level = 0; level < levels; ++level) {
        std::map<std::pair<int, int>, int> midpoint;
        auto mid = [&](int a, int b) {
            const auto key = std::minmax(a, b);
            auto it = midpoint.find(key);
            if (it != midpoint.end()) return it->second;
            v.push_back((v[a] + v[b]).normalized());
            midpoint[key] = static_cast<int>(v.size()) - 1;
            return static_cast<int>(v.size()) - 1;
        };
        std::vector<std::array<int, 3>> next;
        for (const auto& tri : f) {
            const int ab = mid(tri[0], tri[1]), bc = mid(tri[1], tri[2]), ca = mid(tri[2], tri[0]);
            next.push_back({tri[0], ab, ca});
            next.push_back({tri[1], bc, ab});
            next.push_back({tri[2], ca, bc});
            next.push_back({ab, bc, ca});
        }
        f = next;
    }
    positions.resize(static_cast<Eigen::Index>(v.size()), 3);
    for (size_t i = 0; i < v.size(); ++i) positions.row(static_cast<Eigen::Index>(i)) = (centre + radius * v[i]).transpose();
    triangles.resize(static_cast<Eigen::Index>(f.size()), 3);
    for (size_t i = 0; i < f.size(); ++i) triangles.row(static_cast<Eigen::Index>(i)) << f[i][0], f[i][1], f[i][2];
}

namespace detail {

// Moller's interval overlap test for two non-degenerate triangles that share no vertex. Independent of
// the engine: plain vector algebra on the triangle corners.
inline bool triangleTriangleIntersect(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& p2,
                                      const Eigen::Vector3d& q0, const Eigen::Vector3d& q1, const Eigen::Vector3d& q2) {
    auto separated = [](const Eigen::Vector3d& a0, const Eigen::Vector3d& a1, const Eigen::Vector3d& a2,
                        const Eigen::Vector3d& b0, const Eigen::Vector3d& b1, const Eigen::Vector3d& b2, double d[3]) {
        const Eigen::Vector3d n = (a1 - a0).cross(a2 - a0);
        const double scale = n.norm() * std::max({(b0 - a0).norm(), (b1 - a0).norm(), (b2 - a0).norm(), 1e-300});
        d[0] = n.dot(b0 - a0);
        d[1] = n.dot(b1 - a0);
        d[2] = n.dot(b2 - a0);
        for (int i = 0; i < 3; ++i)
            if (std::abs(d[i]) < 1e-12 * scale) d[i] = 0.0;
        return (d[0] > 0 && d[1] > 0 && d[2] > 0) || (d[0] < 0 && d[1] < 0 && d[2] < 0);
    };
    double dq[3], dp[3];
    if (separated(p0, p1, p2, q0, q1, q2, dq) || separated(q0, q1, q2, p0, p1, p2, dp)) return false;
    const Eigen::Vector3d direction = (p1 - p0).cross(p2 - p0).cross((q1 - q0).cross(q2 - q0));
    if (direction.squaredNorm() < 1e-30) return false;  // coplanar: not produced by these deformations
    auto interval = [&](const Eigen::Vector3d& a0, const Eigen::Vector3d& a1, const Eigen::Vector3d& a2, const double d[3]) {
        const std::array<Eigen::Vector3d, 3> a{a0, a1, a2};
        std::array<double, 3> proj;
        for (int i = 0; i < 3; ++i) proj[i] = direction.dot(a[i]);
        // The vertex alone on its side of the other plane.
        int lone = 0;
        if ((d[0] > 0) == (d[1] > 0) && d[2] != 0) lone = 2;
        else if ((d[0] > 0) == (d[2] > 0) && d[1] != 0) lone = 1;
        else lone = 0;
        if (d[lone] == 0) {  // a vertex on the plane: take the span of the zero vertices and edge crossings
            double lo = INFINITY, hi = -INFINITY;
            for (int i = 0; i < 3; ++i) {
                const int j = (i + 1) % 3;
                if (d[i] == 0) { lo = std::min(lo, proj[i]); hi = std::max(hi, proj[i]); }
                if ((d[i] > 0 && d[j] < 0) || (d[i] < 0 && d[j] > 0)) {
                    const double x = proj[i] + (proj[j] - proj[i]) * d[i] / (d[i] - d[j]);
                    lo = std::min(lo, x);
                    hi = std::max(hi, x);
                }
            }
            return std::make_pair(lo, hi);
        }
        const int i1 = (lone + 1) % 3, i2 = (lone + 2) % 3;
        const double x1 = proj[lone] + (proj[i1] - proj[lone]) * d[lone] / (d[lone] - d[i1]);
        const double x2 = proj[lone] + (proj[i2] - proj[lone]) * d[lone] / (d[lone] - d[i2]);
        return std::make_pair(std::min(x1, x2), std::max(x1, x2));
    };
    const auto a = interval(p0, p1, p2, dp);
    const auto b = interval(q0, q1, q2, dq);
    return a.first <= b.second && b.first <= a.second;
}

}  // namespace detail

// Number of pairs of triangles that share no vertex and intersect. A uniform grid over the triangles'
// bounding boxes prunes pairs, so meshes of a few thousand triangles take milliseconds.
inline int selfIntersectingPairs(const Positions& positions, const Triangles& triangles) {
    const int n = static_cast<int>(triangles.rows());
    std::vector<Eigen::AlignedBox3d> boxes(n);
    Eigen::AlignedBox3d all;
    for (int t = 0; t < n; ++t) {
        for (int c = 0; c < 3; ++c) boxes[t].extend(positions.row(triangles(t, c)).transpose());
        all.extend(boxes[t]);
    }
    const int g = std::max(1, static_cast<int>(std::cbrt(n)));
    const Eigen::Vector3d cell = (all.sizes() / g).cwiseMax(1e-12);
    std::unordered_map<long long, std::vector<int>> grid;
    auto key = [&](int x, int y, int z) { return (static_cast<long long>(x) * (g + 1) + y) * (g + 1) + z; };
    for (int t = 0; t < n; ++t) {
        const Eigen::Vector3i lo = ((boxes[t].min() - all.min()).cwiseQuotient(cell)).cast<int>().cwiseMin(g - 1);
        const Eigen::Vector3i hi = ((boxes[t].max() - all.min()).cwiseQuotient(cell)).cast<int>().cwiseMin(g - 1);
        for (int x = lo.x(); x <= hi.x(); ++x)
            for (int y = lo.y(); y <= hi.y(); ++y)
                for (int z = lo.z(); z <= hi.z(); ++z) grid[key(x, y, z)].push_back(t);
    }
    std::vector<std::pair<int, int>> pairs;
    for (const auto& [k, list] : grid)
        for (size_t i = 0; i < list.size(); ++i)
            for (size_t j = i + 1; j < list.size(); ++j) pairs.emplace_back(std::min(list[i], list[j]), std::max(list[i], list[j]));
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    int count = 0;
    for (const auto& [a, b] : pairs) {
        bool shared = false;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) shared = shared || triangles(a, i) == triangles(b, j);
        if (shared || !boxes[a].intersects(boxes[b])) continue;
        auto p = [&](int t, int c) { return Eigen::Vector3d(positions.row(triangles(t, c)).transpose()); };
        if (detail::triangleTriangleIntersect(p(a, 0), p(a, 1), p(a, 2), p(b, 0), p(b, 1), p(b, 2))) ++count;
    }
    return count;
}

}  // namespace sculpt::test
