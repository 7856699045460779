// Self-intersection check of the triangle mesh (design.md, "The guarantee is about what the user sees").
// Broad phase: a median-split BVH over triangle boxes, refitted where vertices moved. Narrow phase: exact
// predicates (triangle_pair.cpp, on CGAL).
#include "core/self_intersection.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <numeric>

#include "core/triangle_pair.h"

namespace sculpt::core {

namespace {

constexpr int kLeafSize = 4;

Eigen::AlignedBox3d triangleBox(const Positions& positions, const Triangles& triangles, int t) {
    Eigen::AlignedBox3d box(positions.row(triangles(t, 0)).transpose());
    box.extend(positions.row(triangles(t, 1)).transpose());
    box.extend(positions.row(triangles(t, 2)).transpose());
    return box;
}

// Closed boxes: touching counts (the exact test decides).
bool overlaps(const Eigen::AlignedBox3d& a, const Eigen::AlignedBox3d& b) {
    return (a.min().array() <= b.max().array()).all() && (b.min().array() <= a.max().array()).all();
}

template <typename PointOf>
TriangleCorners corners(const Triangles& triangles, int t, PointOf pointOf) {
    TriangleCorners c;
    for (int k = 0; k < 3; ++k) {
        c.vertex[k] = triangles(t, k);
        c.point[k] = pointOf(c.vertex[k]);
    }
    return c;
}

}  // namespace

void SelfIntersectionIndex::clear() {
    nodes_.clear();
    leafTriangles_.clear();
    leafOfTriangle_.clear();
    vertexTriangleStart_.clear();
    vertexTriangles_.clear();
    dirtyTriangles_.clear();
    dirtyFlag_.clear();
    movedVertexFlag_.clear();
    movedTriangleFlag_.clear();
    allDirty_ = false;
}

void SelfIntersectionIndex::build(const Positions& positions, const Triangles& triangles) {
    clear();
    const int nv = static_cast<int>(positions.rows());
    const int nt = static_cast<int>(triangles.rows());
    vertexTriangleStart_.assign(static_cast<size_t>(nv) + 1, 0);
    for (int t = 0; t < nt; ++t)
        for (int k = 0; k < 3; ++k) ++vertexTriangleStart_[static_cast<size_t>(triangles(t, k)) + 1];
    std::partial_sum(vertexTriangleStart_.begin(), vertexTriangleStart_.end(), vertexTriangleStart_.begin());
    vertexTriangles_.resize(static_cast<size_t>(vertexTriangleStart_.back()));
    std::vector<int> cursor(vertexTriangleStart_.begin(), vertexTriangleStart_.end() - 1);
    for (int t = 0; t < nt; ++t)
        for (int k = 0; k < 3; ++k) vertexTriangles_[static_cast<size_t>(cursor[triangles(t, k)]++)] = t;
    movedVertexFlag_.assign(static_cast<size_t>(nv), 0);
    movedTriangleFlag_.assign(static_cast<size_t>(nt), 0);
    dirtyFlag_.assign(static_cast<size_t>(nt), 0);
    leafOfTriangle_.assign(static_cast<size_t>(nt), -1);
    if (nt == 0) return;

    std::vector<Eigen::Vector3d> centroid(static_cast<size_t>(nt));
    for (int t = 0; t < nt; ++t)
        centroid[t] = (positions.row(triangles(t, 0)) + positions.row(triangles(t, 1)) + positions.row(triangles(t, 2))).transpose() / 3.0;
    leafTriangles_.resize(static_cast<size_t>(nt));
    std::iota(leafTriangles_.begin(), leafTriangles_.end(), 0);
    nodes_.reserve(static_cast<size_t>(2 * (nt / 2 + 1)));
    Node root;
    root.first = 0;
    root.count = nt;
    nodes_.push_back(root);
    std::vector<int> pending{0};
    while (!pending.empty()) {
        const int index = pending.back();
        pending.pop_back();
        const int first = nodes_[index].first, count = nodes_[index].count;
        if (count <= kLeafSize) continue;
        Eigen::AlignedBox3d bounds;
        for (int e = first; e < first + count; ++e) bounds.extend(centroid[leafTriangles_[e]]);
        int axis = 0;
        bounds.sizes().maxCoeff(&axis);
        const int half = count / 2;
        std::nth_element(leafTriangles_.begin() + first, leafTriangles_.begin() + first + half, leafTriangles_.begin() + first + count,
                         [&](int a, int b) { return centroid[a][axis] < centroid[b][axis]; });
        const int left = static_cast<int>(nodes_.size());
        Node child;
        child.parent = index;
        child.first = first;
        child.count = half;
        nodes_.push_back(child);
        child.first = first + half;
        child.count = count - half;
        nodes_.push_back(child);
        nodes_[index].first = left;
        nodes_[index].count = 0;
        pending.push_back(left);
        pending.push_back(left + 1);
    }
    for (int index = 0; index < static_cast<int>(nodes_.size()); ++index)
        if (nodes_[index].count > 0)
            for (int e = nodes_[index].first; e < nodes_[index].first + nodes_[index].count; ++e) leafOfTriangle_[leafTriangles_[e]] = index;
    allDirty_ = true;
    refit(positions, triangles);
}

Eigen::AlignedBox3d SelfIntersectionIndex::leafBox(const Node& node, const Positions& positions, const Triangles& triangles) const {
    Eigen::AlignedBox3d box;
    for (int e = node.first; e < node.first + node.count; ++e) box.extend(triangleBox(positions, triangles, leafTriangles_[e]));
    return box;
}

void SelfIntersectionIndex::verticesMoved(const std::vector<int>& vertices) {
    if (allDirty_ || nodes_.empty()) return;
    for (int v : vertices)
        forEachTriangleOf(v, [&](int t) {
            if (!dirtyFlag_[t]) {
                dirtyFlag_[t] = 1;
                dirtyTriangles_.push_back(t);
            }
        });
    if (dirtyTriangles_.size() * 8 > leafTriangles_.size()) allDirty_ = true;  // a full refit is cheaper
}

void SelfIntersectionIndex::refit(const Positions& positions, const Triangles& triangles) {
    if (nodes_.empty()) return;
    if (allDirty_) {
        // Children always come after their parent: one backward sweep refits everything.
        for (int index = static_cast<int>(nodes_.size()) - 1; index >= 0; --index) {
            Node& node = nodes_[index];
            if (node.count > 0) node.box = leafBox(node, positions, triangles);
            else node.box = nodes_[node.first].box.merged(nodes_[node.first + 1].box);
        }
    } else {
        for (int t : dirtyTriangles_) {
            int index = leafOfTriangle_[t];
            nodes_[index].box = leafBox(nodes_[index], positions, triangles);
            for (index = nodes_[index].parent; index >= 0; index = nodes_[index].parent)
                nodes_[index].box = nodes_[nodes_[index].first].box.merged(nodes_[nodes_[index].first + 1].box);
        }
    }
    for (int t : dirtyTriangles_) dirtyFlag_[t] = 0;
    dirtyTriangles_.clear();
    allDirty_ = false;
}

SelfIntersectionIndex::Result SelfIntersectionIndex::findNewIntersection(const Positions& positions, const Triangles& triangles,
                                                                          const std::vector<int>& moved, const Positions& before) {
    const auto start = std::chrono::steady_clock::now();
    Result result;
    if (nodes_.empty() || moved.empty()) return result;
    std::vector<int> movedTriangles;
    for (int v : moved) {
        movedVertexFlag_[v] = 1;
        forEachTriangleOf(v, [&](int t) {
            if (!movedTriangleFlag_[t]) {
                movedTriangleFlag_[t] = 1;
                movedTriangles.push_back(t);
            }
        });
    }
    verticesMoved(moved);
    refit(positions, triangles);
    // Queries in leaf order: neighbouring queries walk the same nodes, which stay in cache.
    std::sort(movedTriangles.begin(), movedTriangles.end(), [&](int x, int y) { return leafOfTriangle_[x] < leafOfTriangle_[y]; });

    const auto now = [&](int v) -> Eigen::Vector3d { return positions.row(v).transpose(); };
    const auto then = [&](int v) -> Eigen::Vector3d { return (movedVertexFlag_[v] ? before.row(v) : positions.row(v)).transpose(); };
    // The moved triangles of one leaf share one walk of the hierarchy with the union of their boxes.
    std::vector<int> groupStart;
    for (size_t m = 0; m < movedTriangles.size(); ++m)
        if (m == 0 || leafOfTriangle_[movedTriangles[m]] != leafOfTriangle_[movedTriangles[m - 1]]) groupStart.push_back(static_cast<int>(m));
    groupStart.push_back(static_cast<int>(movedTriangles.size()));
    std::atomic<bool> found{false};
    std::atomic<long long> tested{0};
    TrianglePairHit hit;
    const int groups = static_cast<int>(groupStart.size()) - 1;
#pragma omp parallel for schedule(dynamic, 32) if (groups > 128)
    for (int g = 0; g < groups; ++g) {
        if (found.load(std::memory_order_relaxed)) continue;
        const int first = groupStart[g], last = groupStart[g + 1];
        Eigen::AlignedBox3d boxes[kLeafSize];
        TriangleCorners cornersNow[kLeafSize];
        Eigen::AlignedBox3d all;
        for (int m = first; m < last; ++m) {
            boxes[m - first] = triangleBox(positions, triangles, movedTriangles[m]);
            cornersNow[m - first] = corners(triangles, movedTriangles[m], now);
            all.extend(boxes[m - first]);
        }
        long long local = 0;
        forEachCandidate(all, [&](int b) {
            if (found.load(std::memory_order_relaxed)) return false;
            const Eigen::AlignedBox3d boxB = triangleBox(positions, triangles, b);
            if (!overlaps(boxB, all)) return true;
            TriangleCorners cornersB;
            bool haveB = false;
            for (int m = first; m < last; ++m) {
                const int a = movedTriangles[m];
                // A pair of two moved triangles is tested once, from its lower id.
                if (b == a || (movedTriangleFlag_[b] && b < a) || !overlaps(boxB, boxes[m - first])) continue;
                if (!haveB) cornersB = corners(triangles, b, now), haveB = true;
                ++local;
                if (!trianglesIntersect(cornersNow[m - first], cornersB)) continue;
                // It intersects now; it is new only if it did not before the move.
                if (trianglesIntersect(corners(triangles, a, then), corners(triangles, b, then))) continue;
#pragma omp critical(sculpt_self_intersection_hit)
                if (!found.load()) {
                    hit.first = std::min(a, b);
                    hit.second = std::max(a, b);
                    const TriangleCorners& c = cornersNow[m - first];
                    hit.where = (c.point[0] + c.point[1] + c.point[2]) / 3.0;
                    found.store(true);
                }
                return false;
            }
            return true;
        });
        tested += local;
    }
    const int count = static_cast<int>(movedTriangles.size());
    for (int v : moved) movedVertexFlag_[v] = 0;
    for (int t : movedTriangles) movedTriangleFlag_[t] = 0;
    result.found = found.load();
    result.pair = hit;
    result.trianglesMoved = count;
    result.pairsTested = tested.load();
    result.milliseconds = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return result;
}

std::vector<TrianglePairHit> SelfIntersectionIndex::allIntersections(const Positions& positions, const Triangles& triangles,
                                                                      size_t limit) {
    std::vector<TrianglePairHit> hits;
    const int nt = static_cast<int>(triangles.rows());
    if (nt < 2 || limit == 0 || nodes_.empty()) return hits;
    refit(positions, triangles);
    // Every triangle against the hierarchy; a pair is kept from its lower id.
    const auto now = [&](int v) -> Eigen::Vector3d { return positions.row(v).transpose(); };
    std::atomic<size_t> total{0};
#pragma omp parallel
    {
        std::vector<TrianglePairHit> local;
#pragma omp for schedule(dynamic, 256)
        for (int e = 0; e < nt; ++e) {
            const int a = leafTriangles_[e];  // in leaf order, so neighbouring queries share cached nodes
            if (total.load(std::memory_order_relaxed) >= limit) continue;
            const Eigen::AlignedBox3d box = triangleBox(positions, triangles, a);
            const TriangleCorners cornersA = corners(triangles, a, now);
            forEachCandidate(box, [&](int b) {
                if (b <= a || !overlaps(triangleBox(positions, triangles, b), box)) return true;
                if (!trianglesIntersect(cornersA, corners(triangles, b, now))) return true;
                local.push_back({a, b, (cornersA.point[0] + cornersA.point[1] + cornersA.point[2]) / 3.0});
                ++total;
                return true;
            });
        }
#pragma omp critical(sculpt_self_intersections_merge)
        hits.insert(hits.end(), local.begin(), local.end());
    }
    std::sort(hits.begin(), hits.end(), [](const TrianglePairHit& x, const TrianglePairHit& y) {
        return x.first != y.first ? x.first < y.first : x.second < y.second;
    });
    if (hits.size() > limit) hits.resize(limit);
    return hits;
}

std::vector<TrianglePairHit> findSelfIntersections(const Positions& positions, const Triangles& triangles, size_t limit) {
    SelfIntersectionIndex index;
    index.build(positions, triangles);
    return index.allIntersections(positions, triangles, limit);
}

}  // namespace sculpt::core
