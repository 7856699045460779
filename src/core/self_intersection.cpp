// Self-intersection check of the triangle mesh (design.md, "The guarantee is about what the user sees").
// Broad phase: a median-split BVH over triangle boxes, refitted where vertices moved. Narrow phase: exact
// predicates (triangle_pair.cpp, on CGAL).
#include "core/self_intersection.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <numeric>

#include "core/triangle_pair.h"

namespace sculpt::core {

namespace {

constexpr int kLeafSize = 8;

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
    slotBoxes_.clear();
    leafTriangles_.clear();
    leafOfTriangle_.clear();
    vertexTriangleStart_.clear();
    vertexTriangles_.clear();
    dirtyTriangles_.clear();
    dirtyFlag_.clear();
    movedVertexFlag_.clear();
    movedTriangleFlag_.clear();
    nodeMoved_.clear();
    closedFan_.clear();
    starOk_.clear();
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
    orderFans(triangles);
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

Eigen::AlignedBox3d SelfIntersectionIndex::leafBox(const Node& node, const Positions& positions, const Triangles& triangles) {
    // The leaf's triangles' boxes are kept in leaf order (slotBoxes_) for the pair tests that read them.
    Eigen::AlignedBox3d box;
    for (int e = node.first; e < node.first + node.count; ++e) {
        slotBoxes_[static_cast<size_t>(e)] = triangleBox(positions, triangles, leafTriangles_[e]);
        box.extend(slotBoxes_[static_cast<size_t>(e)]);
    }
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
    slotBoxes_.resize(leafTriangles_.size());
    if (allDirty_) {
        // The leaves on both threads, then (children always come after their parent) one backward sweep of the
        // inner nodes.
        const int nodeCount = static_cast<int>(nodes_.size());
#pragma omp parallel for schedule(static, 4096) if (nodeCount > 20000)
        for (int index = 0; index < nodeCount; ++index)
            if (nodes_[index].count > 0) nodes_[index].box = leafBox(nodes_[index], positions, triangles);
        for (int index = nodeCount - 1; index >= 0; --index) {
            Node& node = nodes_[index];
            if (node.count == 0) node.box = nodes_[node.first].box.merged(nodes_[node.first + 1].box);
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

void SelfIntersectionIndex::orderFans(const Triangles& triangles) {
    // Each vertex's triangles in order round it (triangle (v, a, b) is followed by the one that starts with b),
    // when they close one consistently oriented fan; otherwise (a boundary, a non-manifold or inconsistently
    // oriented vertex) closedFan_ stays 0 and its pairs are always tested.
    const int nv = static_cast<int>(vertexTriangleStart_.size()) - 1;
    closedFan_.assign(static_cast<size_t>(nv), 0);
    std::vector<int> ordered;
    for (int v = 0; v < nv; ++v) {
        const int first = vertexTriangleStart_[v], count = vertexTriangleStart_[v + 1] - first;
        if (count < 3) continue;
        const auto after = [&](int t, int offset) {
            for (int k = 0; k < 3; ++k)
                if (triangles(t, k) == v) return triangles(t, (k + offset) % 3);
            return -1;
        };
        ordered.assign(1, vertexTriangles_[first]);
        bool closed = true;
        while (closed && static_cast<int>(ordered.size()) < count) {
            const int end = after(ordered.back(), 2);
            int nextTriangle = -1;
            for (int s = first; s < first + count; ++s) {
                const int t = vertexTriangles_[s];
                if (after(t, 1) != end) continue;
                if (nextTriangle >= 0 || std::find(ordered.begin(), ordered.end(), t) != ordered.end()) closed = false;
                nextTriangle = t;
            }
            if (nextTriangle < 0) closed = false;
            else ordered.push_back(nextTriangle);
        }
        if (!closed || after(ordered.back(), 2) != after(ordered.front(), 1)) continue;
        std::copy(ordered.begin(), ordered.end(), vertexTriangles_.begin() + first);
        closedFan_[v] = 1;
    }
}

bool SelfIntersectionIndex::starEmbedded(const Positions& positions, const Triangles& triangles, int w) const {
    // Pairs of triangles that share a vertex w can only cross inside w's star. The star is embedded (no two of its
    // triangles meet beyond what they share) when its projection along a normal n is one-to-one: every projected
    // triangle (w, p_i, p_i+1) positively oriented, so the angle round w grows by less than pi per triangle, and
    // the link polygon winds once round w. Rounding: each orientation must exceed 1e-9 of the product of its
    // lengths, and no link point may lie within 1e-9 of its length of the ray the winding is counted on.
    if (!closedFan_[w]) return false;
    const int first = vertexTriangleStart_[w], count = vertexTriangleStart_[w + 1] - first;
    const Eigen::Vector3d centre = positions.row(w).transpose();
    const auto linkPoint = [&](int t) {
        for (int k = 0; k < 3; ++k)
            if (triangles(t, k) == w) return Eigen::Vector3d(positions.row(triangles(t, (k + 1) % 3)).transpose() - centre);
        return Eigen::Vector3d(Eigen::Vector3d::Zero());
    };
    constexpr int kMaxFan = 32;
    if (count > kMaxFan) return false;
    Eigen::Vector3d link[kMaxFan];
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();
    for (int i = 0; i < count; ++i) link[i] = linkPoint(vertexTriangles_[first + i]);
    for (int i = 0; i < count; ++i) normal += link[i].cross(link[(i + 1) % count]);
    const double length = normal.norm();
    if (!(length > 0.0) || !std::isfinite(length)) return false;
    normal /= length;
    const Eigen::Vector3d e1 = normal.unitOrthogonal(), e2 = normal.cross(e1);
    double x[kMaxFan], y[kMaxFan], r[kMaxFan];
    for (int i = 0; i < count; ++i) {
        x[i] = link[i].dot(e1), y[i] = link[i].dot(e2);
        r[i] = link[i].norm();
        if (!(std::abs(y[i]) > 1e-9 * r[i])) return false;
    }
    int windings = 0;
    for (int i = 0; i < count; ++i) {
        const int j = (i + 1) % count;
        if (!(x[i] * y[j] - y[i] * x[j] > 1e-9 * r[i] * r[j])) return false;
        windings += y[i] < 0.0 && y[j] > 0.0;
    }
    return windings == 1;
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

    // The stars of the moved triangles' corners that are still embedded after the step (starEmbedded): the pairs
    // sharing such a vertex cannot cross, and are not tested.
    if (starOk_.size() != movedVertexFlag_.size()) starOk_.assign(movedVertexFlag_.size(), 0);
    std::vector<int> starVertices;
    if (allMoved) {
        // Every vertex that has a triangle.
        for (int v = 0; v < static_cast<int>(starOk_.size()); ++v)
            if (vertexTriangleStart_[v + 1] > vertexTriangleStart_[v]) starOk_[v] = 2, starVertices.push_back(v);
    } else {
        for (int t : movedTriangles)
            for (int k = 0; k < 3; ++k) {
                const int v = triangles(t, k);
                if (starOk_[v] == 0) starOk_[v] = 2, starVertices.push_back(v);  // 2: seen, not (yet) proven
            }
    }
    const int cornerCount = static_cast<int>(starVertices.size());
#pragma omp parallel for schedule(static) if (cornerCount > 4096)
    for (int c = 0; c < cornerCount; ++c)
        if (starEmbedded(positions, triangles, starVertices[static_cast<size_t>(c)])) starOk_[starVertices[static_cast<size_t>(c)]] = 1;

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
        for (int i = 0; i < countA; ++i) {
            const int a = leafTriangles_[na.first + i];
            const bool movedA = movedTriangleFlag_[a] != 0;
            const int corner[3] = {triangles(a, 0), triangles(a, 1), triangles(a, 2)};
            // Which of them have a star proven embedded: a pair sharing one of those is proven.
            bool cornerProven[3];
            for (int k = 0; k < 3; ++k) cornerProven[k] = starOk_[corner[k]] == 1;
            // a's plane now, once for all its partners: b wholly on one side of it cannot meet a. The side of q is
            // the sign of n . (q - p0), n = (p1 - p0) x (p2 - p0); computed, it is within 8 eps |p1 - p0| |p2 - p0|
            // |q - p0| of the exact value (each rounding relative to its own result), so a margin of 1e-13 of
            // that product decides it for certain (the same sign as the exact orientation predicate).
            const Eigen::Vector3d p0 = now(corner[0]);
            const Eigen::Vector3d edge1 = now(corner[1]) - p0, edge2 = now(corner[2]) - p0;
            const Eigen::Vector3d normal = edge1.cross(edge2);
            const double lengths = 1e-13 * edge1.lpNorm<1>() * edge2.lpNorm<1>();
            for (int j = nb ? 0 : i + 1; j < countB; ++j) {
                const int b = leafTriangles_[(nb ? nb->first : na.first) + j];
                if (!movedA && !movedTriangleFlag_[b]) continue;
                if (!overlaps(boxA[i], boxB[j])) continue;
                const int b0 = triangles(b, 0), b1 = triangles(b, 1), b2 = triangles(b, 2);
                bool shares = false, byStar = false;
                for (int k = 0; k < 3; ++k) {
                    const bool shared = corner[k] == b0 || corner[k] == b1 || corner[k] == b2;
                    shares = shares || shared;
                    byStar = byStar || (shared && cornerProven[k]);
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
                // It intersects now; it is new only if it did not before the move.
                if (trianglesIntersect(corners(triangles, a, then), corners(triangles, b, then))) continue;
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
    for (int v : starVertices) starOk_[v] = 0;
    result.found = found.load();
    result.pair = hit;
    result.trianglesMoved = count;
    result.pairsTested = tested.load();
    result.pairsProvenByStar = proven.load();
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
