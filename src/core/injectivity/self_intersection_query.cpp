// The self-intersection index's queries (self_intersection.h): the first new crossing after a move, with the
// stars and patches proven embedded skipped, and every crossing pair (exact predicates, triangle_pair.cpp).
#include "core/injectivity/self_intersection.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cassert>
#include <chrono>
#include <functional>
#include <limits>
#include <numeric>

#include "core/injectivity/self_intersection_internal.h"
#include "core/injectivity/triangle_pair.h"

namespace sculpt::core {

using namespace self_intersection_detail;

namespace {

// Pairs in the order the queries return them: by the lower id, then the higher.
bool byIds(const TrianglePairHit& x, const TrianglePairHit& y) { return x.first != y.first ? x.first < y.first : x.second < y.second; }

}  // namespace

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
    // The nodes holding a moved triangle: its leaf and the leaf's ancestors (the walk up stops at a marked one).
    if (nodeMoved_.size() != nodes_.size()) nodeMoved_.assign(nodes_.size(), 0);
    std::vector<int> markedNodes;
    const bool allMoved = movedTriangles.size() == static_cast<size_t>(triangles.rows());
    if (allMoved) {
        std::fill(nodeMoved_.begin(), nodeMoved_.end(), 1);  // every node (cleared below)
    } else {
        for (int t : movedTriangles)
            for (int index = leafOfTriangle_[t]; index >= 0 && !nodeMoved_[index]; index = nodes_[index].parent) {
                nodeMoved_[index] = 1;
                markedNodes.push_back(index);
            }
    }

    // The stars of the moved triangles' corners are looked at when a pair sharing one is met (starProven): a pair
    // sharing a vertex whose star is still embedded after the step cannot cross, and is not tested.
    if (starStamp_.size() != movedVertexFlag_.size()) starStamp_.assign(movedVertexFlag_.size(), 0);
    if (++starGeneration_ >= (1u << 31)) {
        std::fill(starStamp_.begin(), starStamp_.end(), 0u);
        starGeneration_ = 1;
    }
    std::atomic<int> patches{0};
    std::atomic<long long> patchTriangles{0};

    const auto now = [&](int v) -> Eigen::Vector3d { return positions.row(v).transpose(); };
    const auto then = [&](int v) -> Eigen::Vector3d { return (movedVertexFlag_[v] ? before.row(v) : positions.row(v)).transpose(); };
    std::atomic<bool> found{false};
    std::atomic<long long> tested{0}, proven{0};
    TrianglePairHit hit;
    // Broad phase: the hierarchy collided with itself (a dual traversal: each pair of overlapping nodes once, each
    // unordered triangle pair at most once), only where one side holds a moved triangle. It costs what moved and
    // what lies near it; a walk from the root per moved leaf (the earlier broad phase) repeated the upper levels
    // for every leaf: 970 ms of a whole-mesh check on 2M triangles.
    // Items: a node against itself (second == -1) or a pair of nodes.
    struct Item {
        int first, second;
    };
    const auto leafPairs = [&](const Node& na, const Node* nb, long long& local, long long& localProven) {
        // The triangles of one leaf (nb null: pairs inside it) or of two.
        const int countA = na.count, countB = nb ? nb->count : na.count;
        const Eigen::AlignedBox3d* boxA = slotBoxes_.data() + na.first;
        const Eigen::AlignedBox3d* boxB = slotBoxes_.data() + (nb ? nb->first : na.first);
        // Between two leaves, only the triangles whose boxes reach the other leaf's box can pair: 2 x 8 box tests
        // that save most of the 64 (on slivers, about half of each leaf reaches the other).
        int slotsA[kLeafSize], slotsB[kLeafSize], reachA = 0, reachB = 0;
        if (nb) {
            for (int i = 0; i < countA; ++i)
                if (overlaps(boxA[i], nb->box)) slotsA[reachA++] = i;
            for (int j = 0; j < countB; ++j)
                if (overlaps(boxB[j], na.box)) slotsB[reachB++] = j;
        } else {
            for (int i = 0; i < countA; ++i) slotsA[i] = slotsB[i] = i;
            reachA = reachB = countA;
        }
        for (int ia = 0; ia < reachA; ++ia) {
            const int i = slotsA[ia];
            const int a = leafTriangles_[na.first + i];
            const bool movedA = movedTriangleFlag_[a] != 0;
            const int corner[3] = {triangles(a, 0), triangles(a, 1), triangles(a, 2)};
            // a's plane now, once for all its partners: b wholly on one side of it cannot meet a. The side of q is
            // the sign of n . (q - p0), n = (p1 - p0) x (p2 - p0); computed, it is within 8 eps |p1 - p0| |p2 - p0|
            // |q - p0| of the exact value (each rounding relative to its own result), so a margin of 1e-13 of
            // that product decides it for certain (the same sign as the exact orientation predicate).
            const Eigen::Vector3d p0 = now(corner[0]);
            const Eigen::Vector3d edge1 = now(corner[1]) - p0, edge2 = now(corner[2]) - p0;
            const Eigen::Vector3d normal = edge1.cross(edge2);
            const double lengths = 1e-13 * edge1.lpNorm<1>() * edge2.lpNorm<1>();
            for (int jb = nb ? 0 : ia + 1; jb < reachB; ++jb) {
                const int j = slotsB[jb];
                const int b = leafTriangles_[(nb ? nb->first : na.first) + j];
                if (!movedA && !movedTriangleFlag_[b]) continue;
                if (!overlaps(boxA[i], boxB[j])) continue;
                const int b0 = triangles(b, 0), b1 = triangles(b, 1), b2 = triangles(b, 2);
                bool shares = false, byStar = false;
                for (int k = 0; k < 3; ++k) {
                    const bool shared = corner[k] == b0 || corner[k] == b1 || corner[k] == b2;
                    shares = shares || shared;
                    byStar = byStar || (shared && starProven(positions, triangles, corner[k]));
                }
                if (byStar) {
                    ++localProven;
                    continue;
                }
                ++local;
                if (!shares) {
                    int above = 0, below = 0;
                    for (const int q : {b0, b1, b2}) {
                        const Eigen::Vector3d offset = now(q) - p0;
                        const double side = normal.dot(offset), margin = lengths * offset.lpNorm<1>();
                        above += side > margin;
                        below += side < -margin;
                    }
                    if (above == 3 || below == 3) continue;
                }
                if (!trianglesIntersect(corners(triangles, a, now), corners(triangles, b, now))) continue;
                // It intersects now; it is new only if it did not before the move, and it is not a contact the
                // mesh was loaded with, shifted to neighbouring triangles of the same two parts.
                if (trianglesIntersect(corners(triangles, a, then), corners(triangles, b, then))) continue;
                if (shiftedLoadContact(a, b)) continue;
#pragma omp critical(sculpt_self_intersection_hit)
                if (!found.load()) {
                    hit.first = std::min(a, b);
                    hit.second = std::max(a, b);
                    const TriangleCorners c = corners(triangles, movedTriangleFlag_[a] ? a : b, now);
                    hit.where = (c.point[0] + c.point[1] + c.point[2]) / 3.0;
                    found.store(true);
                }
                return;
            }
        }
    };
    // Expands an item one level: into `out` (the children to look at), or tests it when both sides are leaves.
    const auto expand = [&](const Item& item, std::vector<Item>& out, long long& local, long long& localProven) {
        const Node& a = nodes_[item.first];
        if (item.second < 0) {
            if (!nodeMoved_[item.first]) return;
            // A patch proven a height field as a whole: none of its pairs can cross.
            if (a.rangeCount >= kPatchMinimum && patchEmbedded(positions, item.first)) {
                ++patches;
                patchTriangles += a.rangeCount;
                return;
            }
            if (a.count > 0) return leafPairs(a, nullptr, local, localProven);
            out.push_back({a.first, -1});
            out.push_back({a.first + 1, -1});
            out.push_back({a.first, a.first + 1});
            return;
        }
        const Node& b = nodes_[item.second];
        if (!nodeMoved_[item.first] && !nodeMoved_[item.second]) return;
        if ((a.box.min().array() > b.box.max().array()).any() || (b.box.min().array() > a.box.max().array()).any()) return;
        if (a.count > 0 && b.count > 0) return leafPairs(a, &b, local, localProven);
        // Split the inner node with the larger box (a leaf is never split).
        const bool splitA = b.count > 0 || (a.count == 0 && a.box.sizes().maxCoeff() >= b.box.sizes().maxCoeff());
        const Node& split = splitA ? a : b;
        const int other = splitA ? item.second : item.first;
        out.push_back({split.first, other});
        out.push_back({split.first + 1, other});
    };
    // A serial breadth-first start until there is work for every thread, then each item depth-first on its own.
    std::vector<Item> items{{0, -1}}, next;
    long long serialTested = 0, serialProven = 0;
    for (int level = 0; level < 64 && !items.empty() && items.size() < 512 && !found.load(); ++level) {
        next.clear();
        for (const Item& item : items) expand(item, next, serialTested, serialProven);
        items.swap(next);
    }
    tested += serialTested;
    proven += serialProven;
    const int itemCount = static_cast<int>(items.size());
#pragma omp parallel for schedule(dynamic, 1) if (itemCount > 1 && movedTriangles.size() > 256)
    for (int i = 0; i < itemCount; ++i) {
        if (found.load(std::memory_order_relaxed)) continue;
        thread_local std::vector<Item> stack;
        stack.clear();
        stack.push_back(items[static_cast<size_t>(i)]);
        long long local = 0, localProven = 0;
        while (!stack.empty() && !found.load(std::memory_order_relaxed)) {
            const Item item = stack.back();
            stack.pop_back();
            expand(item, stack, local, localProven);
        }
        tested += local;
        proven += localProven;
    }
    const int count = static_cast<int>(movedTriangles.size());
    for (int v : moved) movedVertexFlag_[v] = 0;
    for (int t : movedTriangles) movedTriangleFlag_[t] = 0;
    if (allMoved) std::fill(nodeMoved_.begin(), nodeMoved_.end(), 0);
    for (int index : markedNodes) nodeMoved_[index] = 0;
    result.found = found.load();
    result.pair = hit;
    result.trianglesMoved = count;
    result.pairsTested = tested.load();
    result.pairsProvenByStar = proven.load();
    result.patchesProven = patches.load();
    result.trianglesInProvenPatches = patchTriangles.load();
    result.milliseconds = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return result;
}

std::vector<TrianglePairHit> SelfIntersectionIndex::allIntersections(const Positions& positions, const Triangles& triangles, size_t limit,
                                                                      double nearTolerance, std::vector<TrianglePairHit>* near) {
    std::vector<TrianglePairHit> hits;
    if (near) near->clear();
    const int nt = static_cast<int>(triangles.rows());
    if (nt < 2 || limit == 0 || nodes_.empty()) return hits;
    refit(positions, triangles);
    // Every triangle against the hierarchy (its box grown by the near tolerance); a pair is kept from its lower id.
    const auto now = [&](int v) -> Eigen::Vector3d { return positions.row(v).transpose(); };
    const double tolerance = near ? std::max(nearTolerance, 0.0) : 0.0;
    const Eigen::Vector3d grow = Eigen::Vector3d::Constant(tolerance);
    std::atomic<size_t> total{0};
#pragma omp parallel
    {
        std::vector<TrianglePairHit> local, localNear;
#pragma omp for schedule(dynamic, 256)
        for (int e = 0; e < nt; ++e) {
            const int a = leafTriangles_[e];  // in leaf order, so neighbouring queries share cached nodes
            if (total.load(std::memory_order_relaxed) >= limit) continue;
            Eigen::AlignedBox3d box = triangleBox(positions, triangles, a);
            box.min() -= grow;
            box.max() += grow;
            const TriangleCorners cornersA = corners(triangles, a, now);
            const Eigen::Vector3d centroid = (cornersA.point[0] + cornersA.point[1] + cornersA.point[2]) / 3.0;
            forEachCandidate(box, [&](int b) {
                if (b <= a || !overlaps(triangleBox(positions, triangles, b), box)) return true;
                const TriangleCorners cornersB = corners(triangles, b, now);
                if (trianglesIntersect(cornersA, cornersB)) {
                    local.push_back({a, b, centroid});
                    ++total;
                } else if (near && trianglesWithin(cornersA, cornersB, tolerance)) {
                    localNear.push_back({a, b, centroid});
                }
                return true;
            });
        }
#pragma omp critical(sculpt_self_intersections_merge)
        {
            hits.insert(hits.end(), local.begin(), local.end());
            if (near) near->insert(near->end(), localNear.begin(), localNear.end());
        }
    }
    std::sort(hits.begin(), hits.end(), byIds);
    if (near) std::sort(near->begin(), near->end(), byIds);
    if (hits.size() > limit) hits.resize(limit);
    return hits;
}

std::vector<TrianglePairHit> SelfIntersectionIndex::intersectionsOfChanged(const Positions& positions, const Triangles& triangles,
                                                                           const std::vector<std::uint8_t>& changed) const {
    std::vector<TrianglePairHit> hits;
    const int nt = static_cast<int>(triangles.rows());
    const int built = static_cast<int>(leafOfTriangle_.size());
    assert(nt >= built && changed.size() == static_cast<size_t>(nt));
    const auto isFlagged = [&](int t) { return t >= built || changed[static_cast<size_t>(t)] != 0; };
    std::vector<int> flagged;
    for (int t = 0; t < nt; ++t)
        if (isFlagged(t)) flagged.push_back(t);
    if (flagged.empty()) return hits;
    const auto now = [&](int v) -> Eigen::Vector3d { return positions.row(v).transpose(); };
    // A pair as allIntersections gives it: the lower id first, at its centroid.
    const auto orderedHit = [](int a, const TriangleCorners& ca, int b, const TriangleCorners& cb) {
        const TriangleCorners& low = a < b ? ca : cb;
        return TrianglePairHit{std::min(a, b), std::max(a, b), (low.point[0] + low.point[1] + low.point[2]) / 3.0};
    };
    const int count = static_cast<int>(flagged.size());
    std::vector<Eigen::AlignedBox3d> boxes(static_cast<size_t>(count));
    for (int i = 0; i < count; ++i) boxes[static_cast<size_t>(i)] = triangleBox(positions, triangles, flagged[static_cast<size_t>(i)]);
    // Flagged rows among themselves: sorted by the boxes' low x, each against those that start before it ends.
    std::vector<int> order(static_cast<size_t>(count));
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int b) { return boxes[static_cast<size_t>(a)].min().x() < boxes[static_cast<size_t>(b)].min().x(); });
#pragma omp parallel
    {
        std::vector<TrianglePairHit> local;
#pragma omp for schedule(dynamic, 64)
        for (int i = 0; i < count; ++i) {
            const int a = flagged[static_cast<size_t>(i)];
            const Eigen::AlignedBox3d& box = boxes[static_cast<size_t>(i)];
            const TriangleCorners cornersA = corners(triangles, a, now);
            // against the unflagged rows, as the index holds them
            if (!nodes_.empty())
                forEachCandidate(box, [&](int b) {
                    if (isFlagged(b) || !overlaps(triangleBox(positions, triangles, b), box)) return true;
                    const TriangleCorners cornersB = corners(triangles, b, now);
                    if (trianglesIntersect(cornersA, cornersB)) local.push_back(orderedHit(a, cornersA, b, cornersB));
                    return true;
                });
        }
#pragma omp for schedule(dynamic, 64)
        for (int k = 0; k < count; ++k) {
            const int i = order[static_cast<size_t>(k)];
            const int a = flagged[static_cast<size_t>(i)];
            const Eigen::AlignedBox3d& box = boxes[static_cast<size_t>(i)];
            const TriangleCorners cornersA = corners(triangles, a, now);
            for (int l = k + 1; l < count; ++l) {
                const int j = order[static_cast<size_t>(l)];
                if (boxes[static_cast<size_t>(j)].min().x() > box.max().x()) break;
                if (!overlaps(boxes[static_cast<size_t>(j)], box)) continue;
                const int b = flagged[static_cast<size_t>(j)];
                const TriangleCorners cornersB = corners(triangles, b, now);
                if (trianglesIntersect(cornersA, cornersB)) local.push_back(orderedHit(a, cornersA, b, cornersB));
            }
        }
#pragma omp critical(sculpt_self_intersections_merge)
        hits.insert(hits.end(), local.begin(), local.end());
    }
    std::sort(hits.begin(), hits.end(), byIds);
    return hits;
}

std::vector<TrianglePairHit> findSelfIntersections(const Positions& positions, const Triangles& triangles, size_t limit) {
    SelfIntersectionIndex index;
    index.build(positions, triangles);
    return index.allIntersections(positions, triangles, limit);
}

}  // namespace sculpt::core
