// Test meshes and an independent self-intersection check for the injectivity tests.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <unordered_map>
#include <vector>

#include <Eigen/Geometry>
#include <gmpxx.h>

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

// Two icospheres of the same level and radius as one mesh of two parts (an assembly): the first around `first`,
// its vertices and triangles before the second's. Returns the first triangle of the second part.
inline int twoIcospheres(int levels, double radius, const Eigen::Vector3d& first, const Eigen::Vector3d& second, Positions& positions,
                         Triangles& triangles) {
    Positions a, b;
    Triangles ta, tb;
    icosphere(levels, radius, first, a, ta);
    icosphere(levels, radius, second, b, tb);
    positions.resize(a.rows() + b.rows(), 3);
    positions << a, b;
    triangles.resize(ta.rows() + tb.rows(), 3);
    triangles << ta, (tb.array() + static_cast<int>(a.rows())).matrix();
    return static_cast<int>(ta.rows());
}

namespace detail {

// Exact predicates: every double is a rational, so the signs below are exact. Each sign is first computed in
// double with a forward error bound (Shewchuk 1997's static filter, made 10x more cautious); only where the
// double result is within the bound of zero is it computed again in rational arithmetic (GMP). Written apart
// from the engine's check (which uses CGAL's filtered predicates and its own case analysis), so the tests
// compare two independent computations.
using Rational = mpq_class;
struct ExactPoint {
    double x, y, z;
    explicit ExactPoint(const Eigen::Vector3d& p) : x(p.x()), y(p.y()), z(p.z()) {}
};

inline int sign(const Rational& r) { return sgn(r); }

// The sign of `value` if its error `bound` cannot reach zero, else 2 (undecided). A bound that underflows or
// overflows, or a NaN, is undecided too: the caller then computes exactly.
inline int filteredSign(double value, double bound) {
    constexpr double kTiny = 1e-280;  // below it the static bound may have lost its meaning to underflow
    if (!(std::isfinite(value) && std::isfinite(bound)) || bound < kTiny) return 2;
    if (value > bound) return 1;
    if (value < -bound) return -1;
    return 2;
}

// Relative error bounds of the double evaluations below, against their permanents: Shewchuk's orient3d bound is
// (7 + 56 eps) eps, his orient2d bound (3 + 16 eps) eps, eps = 2^-53; 10x those.
constexpr double kOrient3dBound = 10.0 * 8.0 * 1.1102230246251565e-16;
constexpr double kOrient2dBound = 10.0 * 4.0 * 1.1102230246251565e-16;

// Sign of det[b-a, c-a, d-a]: > 0 when d is on the side of plane (a, b, c) its normal (b-a) x (c-a) points to.
inline int orient3d(const ExactPoint& a, const ExactPoint& b, const ExactPoint& c, const ExactPoint& d) {
    {
        const double bx = b.x - a.x, by = b.y - a.y, bz = b.z - a.z;
        const double cx = c.x - a.x, cy = c.y - a.y, cz = c.z - a.z;
        const double dx = d.x - a.x, dy = d.y - a.y, dz = d.z - a.z;
        const double value = bx * (cy * dz - cz * dy) - by * (cx * dz - cz * dx) + bz * (cx * dy - cy * dx);
        const double permanent = std::abs(bx) * (std::abs(cy * dz) + std::abs(cz * dy)) +
                                 std::abs(by) * (std::abs(cx * dz) + std::abs(cz * dx)) +
                                 std::abs(bz) * (std::abs(cx * dy) + std::abs(cy * dx));
        const int filtered = filteredSign(value, kOrient3dBound * permanent);
        if (filtered != 2) return filtered;
    }
    const Rational ax(a.x), ay(a.y), az(a.z);
    const Rational bx = Rational(b.x) - ax, by = Rational(b.y) - ay, bz = Rational(b.z) - az;
    const Rational cx = Rational(c.x) - ax, cy = Rational(c.y) - ay, cz = Rational(c.z) - az;
    const Rational dx = Rational(d.x) - ax, dy = Rational(d.y) - ay, dz = Rational(d.z) - az;
    return sign(bx * (cy * dz - cz * dy) - by * (cx * dz - cz * dx) + bz * (cx * dy - cy * dx));
}

// The coordinates kept when axis `drop` is dropped.
inline double planeU(const ExactPoint& p, int drop) { return drop == 0 ? p.y : p.x; }
inline double planeV(const ExactPoint& p, int drop) { return drop == 2 ? p.y : p.z; }

// 2D orientation of (a, b, c) in the coordinate plane that drops axis `drop`.
inline int orient2d(const ExactPoint& a, const ExactPoint& b, const ExactPoint& c, int drop) {
    const double ua = planeU(a, drop), va = planeV(a, drop), ub = planeU(b, drop), vb = planeV(b, drop);
    const double uc = planeU(c, drop), vc = planeV(c, drop);
    {
        const double left = (ub - ua) * (vc - va), right = (vb - va) * (uc - ua);
        const int filtered = filteredSign(left - right, kOrient2dBound * (std::abs(left) + std::abs(right)));
        if (filtered != 2) return filtered;
    }
    const Rational u0(ua), v0(va);
    return sign((Rational(ub) - u0) * (Rational(vc) - v0) - (Rational(vb) - v0) * (Rational(uc) - u0));
}

// Closed 2D segments pq and rs (in the plane dropping `drop`, all four points coplanar) meet.
inline bool segmentsMeet2d(const ExactPoint& p, const ExactPoint& q, const ExactPoint& r, const ExactPoint& s, int drop) {
    const int o1 = orient2d(p, q, r, drop), o2 = orient2d(p, q, s, drop), o3 = orient2d(r, s, p, drop), o4 = orient2d(r, s, q, drop);
    if (o1 * o2 < 0 && o3 * o4 < 0) return true;
    auto within = [drop](const ExactPoint& a, const ExactPoint& b, const ExactPoint& c) {  // c on segment ab, given collinear
        const double ua = planeU(a, drop), ub = planeU(b, drop), uc = planeU(c, drop);  // coordinates compare exactly
        const double va = planeV(a, drop), vb = planeV(b, drop), vc = planeV(c, drop);
        return std::min(ua, ub) <= uc && uc <= std::max(ua, ub) && std::min(va, vb) <= vc && vc <= std::max(va, vb);
    };
    return (o1 == 0 && within(p, q, r)) || (o2 == 0 && within(p, q, s)) || (o3 == 0 && within(r, s, p)) || (o4 == 0 && within(r, s, q));
}

// Closed segment pq meets closed, non-degenerate triangle abc.
inline bool segmentMeetsTriangle(const ExactPoint& p, const ExactPoint& q, const ExactPoint& a, const ExactPoint& b, const ExactPoint& c) {
    const int op = orient3d(a, b, c, p), oq = orient3d(a, b, c, q);
    if (op * oq > 0) return false;
    if (op == 0 && oq == 0) {
        // Coplanar (rare): project along the normal's largest component, computed exactly.
        const Rational ax = Rational(a.x), ay = Rational(a.y), az = Rational(a.z);
        const Rational bx = Rational(b.x) - ax, by = Rational(b.y) - ay, bz = Rational(b.z) - az;
        const Rational cx = Rational(c.x) - ax, cy = Rational(c.y) - ay, cz = Rational(c.z) - az;
        const Rational nx = by * cz - bz * cy, ny = bz * cx - bx * cz, nz = bx * cy - by * cx;
        const Rational mx = abs(nx), my = abs(ny), mz = abs(nz);
        const int drop = mx >= my && mx >= mz ? 0 : (my >= mz ? 1 : 2);
        auto inside = [&](const ExactPoint& x) {
            const int s1 = orient2d(a, b, x, drop), s2 = orient2d(b, c, x, drop), s3 = orient2d(c, a, x, drop);
            return (s1 >= 0 && s2 >= 0 && s3 >= 0) || (s1 <= 0 && s2 <= 0 && s3 <= 0);
        };
        return inside(p) || inside(q) || segmentsMeet2d(p, q, a, b, drop) || segmentsMeet2d(p, q, b, c, drop) ||
               segmentsMeet2d(p, q, c, a, drop);
    }
    // The line pq crosses the plane once, inside [p, q]: is the crossing inside the triangle?
    const int s1 = orient3d(p, q, a, b), s2 = orient3d(p, q, b, c), s3 = orient3d(p, q, c, a);
    return (s1 >= 0 && s2 >= 0 && s3 >= 0) || (s1 <= 0 && s2 <= 0 && s3 <= 0);
}

// Two triangles meet beyond what they share (by vertex id or by exactly equal position). Degenerate triangles are not counted (the test
// meshes have none). Intersecting triangles have an edge of one meeting the other, coplanar or not.
inline bool exactTrianglesIntersect(const std::array<Eigen::Vector3d, 3>& pa, const std::array<int, 3>& ia,
                                    const std::array<Eigen::Vector3d, 3>& pb, const std::array<int, 3>& ib) {
    std::vector<ExactPoint> A, B;
    for (int k = 0; k < 3; ++k) A.emplace_back(pa[k]), B.emplace_back(pb[k]);
    auto degenerate = [](const std::vector<ExactPoint>& t) {
        for (int drop = 0; drop < 3; ++drop)
            if (orient2d(t[0], t[1], t[2], drop) != 0) return false;
        return true;
    };
    if (degenerate(A) || degenerate(B)) return false;
    // Shared: the same vertex id, or exactly the same position (a soup's neighbours touch as neighbours do).
    std::vector<std::pair<int, int>> shared;  // corner of a, corner of b
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i)
            if (ia[i] == ib[j] || pa[i] == pb[j]) {
                shared.emplace_back(i, j);
                break;
            }
    if (shared.size() >= 3) return false;
    if (shared.size() == 2) {
        // Shared edge: they meet beyond it only when coplanar with the other corners on one side of it.
        const int oa = 3 - shared[0].first - shared[1].first, ob = 3 - shared[0].second - shared[1].second;
        const ExactPoint& u = A[shared[0].first];
        const ExactPoint& v = A[shared[1].first];
        if (orient3d(u, v, A[oa], B[ob]) != 0) return false;
        for (int drop = 0; drop < 3; ++drop) {
            const int sa = orient2d(u, v, A[oa], drop), sb = orient2d(u, v, B[ob], drop);
            if (sa != 0) return sa == sb;
        }
        return false;
    }
    if (shared.size() == 1) {
        const int wa = shared[0].first, wb = shared[0].second;
        return segmentMeetsTriangle(B[(wb + 1) % 3], B[(wb + 2) % 3], A[0], A[1], A[2]) ||
               segmentMeetsTriangle(A[(wa + 1) % 3], A[(wa + 2) % 3], B[0], B[1], B[2]);
    }
    for (int e = 0; e < 3; ++e) {
        if (segmentMeetsTriangle(A[e], A[(e + 1) % 3], B[0], B[1], B[2])) return true;
        if (segmentMeetsTriangle(B[e], B[(e + 1) % 3], A[0], A[1], A[2])) return true;
    }
    return false;
}

}  // namespace detail

// The intersecting pairs of triangles (what two triangles share by vertex id or position does not count), exactly, as
// sorted (lower, higher) id pairs. Sweep and prune over the triangles' bounding boxes prunes pairs, so meshes
// of tens of thousands of triangles take well under a second.
inline std::vector<std::pair<int, int>> intersectingPairs(const Positions& positions, const Triangles& triangles) {
    const int n = static_cast<int>(triangles.rows());
    std::vector<Eigen::AlignedBox3d> boxes(n);
    for (int t = 0; t < n; ++t)
        for (int c = 0; c < 3; ++c) boxes[t].extend(positions.row(triangles(t, c)).transpose());
    // Sweep and prune along x (boxes sorted by their low x; each meets those that start before it ends), then y
    // and z: a locally refined mesh (a brush stroke splits thousands of triangles in one spot) stays n log n plus
    // the overlaps, where a uniform grid put them all in one cell.
    std::vector<int> order(static_cast<size_t>(n));
    for (int t = 0; t < n; ++t) order[static_cast<size_t>(t)] = t;
    std::sort(order.begin(), order.end(), [&](int p, int q) { return boxes[p].min().x() < boxes[q].min().x(); });
    std::vector<std::pair<int, int>> pairs;
    for (size_t i = 0; i < order.size(); ++i) {
        const Eigen::AlignedBox3d& bi = boxes[order[i]];
        for (size_t j = i + 1; j < order.size() && boxes[order[j]].min().x() <= bi.max().x(); ++j) {
            const Eigen::AlignedBox3d& bj = boxes[order[j]];
            if (bj.min().y() <= bi.max().y() && bi.min().y() <= bj.max().y() && bj.min().z() <= bi.max().z() && bi.min().z() <= bj.max().z())
                pairs.emplace_back(std::min(order[i], order[j]), std::max(order[i], order[j]));
        }
    }
    std::sort(pairs.begin(), pairs.end());
    std::vector<std::pair<int, int>> hits;
    for (const auto& [a, b] : pairs) {
        if (!(boxes[a].min().array() <= boxes[b].max().array()).all() || !(boxes[b].min().array() <= boxes[a].max().array()).all()) continue;
        std::array<Eigen::Vector3d, 3> pa, pb;
        std::array<int, 3> ia, ib;
        for (int c = 0; c < 3; ++c) {
            ia[c] = triangles(a, c);
            ib[c] = triangles(b, c);
            pa[c] = positions.row(ia[c]).transpose();
            pb[c] = positions.row(ib[c]).transpose();
        }
        if (detail::exactTrianglesIntersect(pa, ia, pb, ib)) hits.emplace_back(a, b);
    }
    return hits;
}

inline int selfIntersectingPairs(const Positions& positions, const Triangles& triangles) {
    return static_cast<int>(intersectingPairs(positions, triangles).size());
}

}  // namespace sculpt::test
