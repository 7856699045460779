// Self-intersection of the triangle mesh the user sees and saves.
//
// det J > 0 (Gain & Dodgson 2001, Theorem 1) certifies the continuous map; the user sees straight triangles
// between the mapped vertices, and under strong compression those can cross even where the map is injective
// (design.md, "The guarantee is about what the user sees"). So every operation is also checked on the
// triangles it moved, against every triangle near them: a pair that intersects afterwards and did not before
// is a new self-intersection, and the operation is subdivided or refused like one that fails the
// injectivity test. Pairs that already intersected (a mesh that self-intersects when loaded) do not count.
//
// Broad phase: a bounding-volume hierarchy over the triangles' boxes, refitted (not rebuilt) where vertices
// moved, so a local drag costs in proportion to the triangles it moved, and collided with itself. A node whose patch
// projects as a height field (patchEmbedded) and a vertex whose star does (starEmbedded) are proven free of
// crossings without enumerating their pairs. Narrow phase: CGAL's exact predicates (triangle_pair.h).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/mesh_types.h"

namespace sculpt::core {

// A pair of intersecting triangles (ids, first < second) and a point where they are (the first's centroid).
struct TrianglePairHit {
    int first = -1, second = -1;
    Eigen::Vector3d where = Eigen::Vector3d::Zero();
};

// Every intersecting pair of triangles of the mesh (what they share by vertex id or by position does not count:
// a triangle soup is not a crossing), sorted,
// at most `limit` of them. positions: #V x 3; triangles: #T x 3 with ids in range (asserted). Parallel.
std::vector<TrianglePairHit> findSelfIntersections(const Positions& positions, const Triangles& triangles,
                                                   size_t limit = static_cast<size_t>(-1));

// The persistent broad phase of the per-operation check: a BVH over the current triangles plus the
// vertex-to-triangle adjacency. The owner tells it which vertices moved (lazily refitted on the next query).
class SelfIntersectionIndex {
public:
    // (Re)builds for this mesh. O(T log T).
    void build(const Positions& positions, const Triangles& triangles);
    void clear();
    bool built() const { return !nodes_.empty(); }

    // The positions of these vertices changed since the index last saw them; refitted on the next query.
    void verticesMoved(const std::vector<int>& vertices);
    void allVerticesMoved() { allDirty_ = true; }

    struct Result {
        bool found = false;        // a new intersecting pair exists
        TrianglePairHit pair;      // the first one found (which one, when several, is not specified)
        int trianglesMoved = 0;    // triangles with a moved corner: the ones tested
        long long pairsTested = 0; // exact narrow-phase tests
        // Box-overlapping pairs sharing a vertex whose star is embedded after the step (its projection along its
        // normal is one-to-one), so they cannot cross: not tested.
        long long pairsProvenByStar = 0;
        // Hierarchy nodes whose patch was proven free of crossings as a whole (patchEmbedded), and the triangles
        // in them: none of their pairs among themselves was looked at.
        int patchesProven = 0;
        long long trianglesInProvenPatches = 0;
        double milliseconds = 0.0;
    };
    // Looks for a pair of triangles, at least one with a vertex in `moved`, that intersects at `positions`
    // and did not intersect before the move: `before` holds the old rows of the moved vertices (other rows
    // are not read; every other vertex is where it was). positions, before: #V x 3; triangles: those given
    // to build(). Refits the moved triangles first. Cost: the moved triangles times the triangles near each.
    Result findNewIntersection(const Positions& positions, const Triangles& triangles, const std::vector<int>& moved,
                               const Positions& before);

    // Parts: the mesh's connected pieces (triangles joined by a shared vertex id or a shared position), numbered
    // 0 .. partCount() - 1 in the order of their lowest triangle. A CAD assembly is many parts, a scan one.
    int partCount() const { return partCount_; }
    int partOfTriangle(int t) const { return partOfTriangle_[static_cast<size_t>(t)]; }
    int partTriangleCount(int part) const { return partSizes_[static_cast<size_t>(part)]; }

    // The contacts the mesh was loaded with (pairs: the intersecting pairs then, e.g. from allIntersections): two
    // parts that touch or overlap at load (the parts of an assembly, modelled in contact), or a part that crosses
    // itself, keep touching as they move. Afterwards a new intersecting pair of triangles of two parts (or one)
    // in such a contact, both triangles within kContactRings rings of triangles of that contact, is the old
    // contact shifted to neighbouring triangles, not a new crossing: findNewIntersection does not report it.
    // Anything else still is (a crossing away from the contact). Cleared by build().
    // The contacts are kept by vertex so that they outlive a rebuild (a refinement adds vertices, renumbers
    // triangles): zoneVertex #V flags the corners of the contact's triangles and their rings; partPairs holds a
    // vertex of each of two parts in contact.
    static constexpr int kContactRings = 2;
    // Pairs within this share of the mesh's bounding-box diagonal at load touch as the intersecting ones do
    // (allIntersections' near pairs): a sliver folded over its neighbour 1e-8 of the diagonal above its face (CGAL's
    // mannequin-devil.off), or a CAD seam's near-equal vertices (4e-6 of the diagonal apart), crosses under any move.
    static constexpr double kNearContactTolerance = 1e-5;
    struct LoadContacts {
        std::vector<std::uint8_t> zoneVertex;
        std::vector<std::pair<int, int>> partPairs;
        bool empty() const { return partPairs.empty(); }
    };
    LoadContacts findLoadContacts(const std::vector<TrianglePairHit>& pairs, const Triangles& triangles) const;
    // Applies contacts found on this mesh (or carried over a refinement: zoneVertex #V of the mesh built).
    void setLoadContacts(const LoadContacts& contacts, const Triangles& triangles);
    // Whether the new pair (a, b) is such a shifted contact.
    bool shiftedLoadContact(int a, int b) const;

    // Every intersecting pair at `positions` (as findSelfIntersections), using this index (refitted first).
    // With `near`, also every pair that does not intersect but comes within `nearTolerance` (world units) of each
    // other apart from what they share (trianglesWithin: a sliver folded over its neighbour), sorted: these touch
    // as the intersecting ones do (Session adds both to the load contacts; kNearContactTolerance).
    std::vector<TrianglePairHit> allIntersections(const Positions& positions, const Triangles& triangles,
                                                  size_t limit = static_cast<size_t>(-1), double nearTolerance = 0.0,
                                                  std::vector<TrianglePairHit>* near = nullptr);

    // Every intersecting pair (as allIntersections) of the mesh `triangles` at `positions` that holds a triangle
    // flagged in `changed` (#T of `triangles`, nonzero: flagged), sorted, where this index was built on an earlier
    // state of the same mesh whose rows `triangles` still holds where unflagged, at the same vertex positions
    // (a mesh split since: rows halved in place or appended, vertices appended, none moved). The pairs of two
    // unflagged rows are the built mesh's and are not looked at. A flagged row against the rest: through this
    // index; flagged rows among themselves: by a sweep over their boxes. Fewer rows than the index was built
    // on, or a flag vector of another size, is a caller's error (asserted).
    std::vector<TrianglePairHit> intersectionsOfChanged(const Positions& positions, const Triangles& triangles,
                                                        const std::vector<std::uint8_t>& changed) const;

    // Triangles that have vertex v as a corner (CSR): ids vertexTriangles_[start[v] .. start[v+1]).
    template <typename F>
    void forEachTriangleOf(int v, F f) const {
        for (int s = vertexTriangleStart_[v]; s < vertexTriangleStart_[v + 1]; ++s) f(vertexTriangles_[s]);
    }

    // Calls f(t) for every triangle t in a leaf whose box overlaps `box` (a superset of the triangles whose
    // own box overlaps it, as of the last refit); f returns false to stop the walk.
    template <typename F>
    void forEachCandidate(const Eigen::AlignedBox3d& box, F f) const {
        if (nodes_.empty()) return;
        int stack[128];
        int top = 0;
        stack[top++] = 0;
        while (top > 0) {
            const Node& node = nodes_[stack[--top]];
            if ((node.box.min().array() > box.max().array()).any() || (box.min().array() > node.box.max().array()).any()) continue;
            if (node.count == 0) {
                stack[top++] = node.first;
                stack[top++] = node.first + 1;
                continue;
            }
            for (int e = node.first; e < node.first + node.count; ++e)
                if (!f(leafTriangles_[e])) return;
        }
    }

private:
    struct Node {
        Eigen::AlignedBox3d box;
        int first = 0;   // leaf: first entry of leafTriangles_; inner: index of the left child (right = first + 1)
        int count = 0;   // leaf: triangle count (> 0); inner: 0
        int parent = -1;
        int rangeFirst = 0, rangeCount = 0;  // the subtree's triangles: leafTriangles_[rangeFirst, + rangeCount)
        // A cone holding the normals of the subtree's triangles (axis unit, half-angle in radians; pi when unknown or
        // wider), merged bottom-up at refit: which patches are worth trying as height fields.
        Eigen::Vector3d coneAxis = Eigen::Vector3d::UnitZ();
        double coneAngle = 3.2;
    };
    void refit(const Positions& positions, const Triangles& triangles);
    void refitLeaf(Node& node, const Positions& positions, const Triangles& triangles);

    void buildParts(const Positions& positions, const Triangles& triangles);
    int partCount_ = 0;
    std::vector<int> partOfTriangle_, partOfVertex_, partSizes_;
    std::vector<std::uint8_t> contactZone_;             // #T (or empty): within kContactRings of a load contact
    std::vector<std::pair<int, int>> contactPartPairs_;  // sorted (lower, higher) parts in contact at load
    std::vector<Node> nodes_;
    std::vector<int> leafTriangles_;   // triangle ids in leaf order
    std::vector<Eigen::AlignedBox3d> slotBoxes_;  // their boxes, in the same order, as of the last refit
    std::vector<int> leafOfTriangle_;  // #T: the node holding each triangle
    std::vector<int> vertexTriangleStart_, vertexTriangles_;
    std::vector<int> dirtyTriangles_;
    std::vector<std::uint8_t> dirtyFlag_;  // #T
    bool allDirty_ = false;
    std::vector<std::uint8_t> movedVertexFlag_, movedTriangleFlag_;  // scratch, all zero between queries
    void orderFans(const Triangles& triangles);
    bool starEmbedded(const Positions& positions, const Triangles& triangles, int vertex) const;
    bool starProven(const Positions& positions, const Triangles& triangles, int vertex);
    void buildPatchBoundaries(const Triangles& triangles);
    bool patchEmbedded(const Positions& positions, int node) const;
    void mergeCone(Node& node) const;
    std::vector<Eigen::Vector3d> slotNormals_;  // leaf order: (p1 - p0) x (p2 - p0) / (|p1 - p0| |p2 - p0|), as of the last refit
    // The boundary chain of each node's patch with at least kPatchMinimum triangles (CSR over nodes): the directed
    // edges (by vertex id) of its triangles that no opposite edge of the patch cancels, repeated by multiplicity.
    std::vector<int> patchBoundaryStart_;
    std::vector<std::array<int, 2>> patchBoundary_;
    std::uint32_t starGeneration_ = 0;
    std::vector<std::uint8_t> refitFlag_;  // #nodes scratch of the partial refit, zero between refits
    std::vector<std::uint32_t> starStamp_;  // #V: (generation << 1) | embedded, for the query of that generation
    std::vector<std::uint8_t> closedFan_;  // #V: the vertex's triangles close one oriented fan (ordered round it)
    std::vector<std::uint8_t> nodeMoved_;                            // #nodes: holds a moved triangle (scratch, zero between queries)
};

}  // namespace sculpt::core
