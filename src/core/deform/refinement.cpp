// Refinement where the surface stretches: Coquillart 1990, "Extended Free-Form Deformation", section 3.4
// (subdivision after Griessmair and Purgathofer 1989, "Deformation of solids with trivariate B-splines"),
// with conforming longest-edge bisection (Rivara 1984, "Algorithms for refining triangular grids suitable
// for adaptive and multigrid techniques"; the LEPP form: Rivara 1997).
#include "core/deform/refinement.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <functional>
#include <unordered_map>

namespace sculpt::core {

namespace {

using Corners = std::array<int, 3>;

std::uint64_t edgeKey(int a, int b) {
    if (a > b) std::swap(a, b);
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

bool repeatsVertex(const Corners& t) { return t[0] == t[1] || t[1] == t[2] || t[2] == t[0]; }

// The local corner k of t with {t[k], t[k+1]} = {a, b}; -1 if t has no such edge.
int edgeCorner(const Corners& t, int a, int b) {
    for (int k = 0; k < 3; ++k) {
        const int u = t[k], v = t[(k + 1) % 3];
        if ((u == a && v == b) || (u == b && v == a)) return k;
    }
    return -1;
}

// A triangle list with its edge-to-triangles map, halved edge by edge (applyEdgeSplits, refineMesh).
class SplittableMesh {
public:
    SplittableMesh(const Triangles& triangles, int vertexCount) : vertexCount_(vertexCount) {
        triangles_.resize(static_cast<size_t>(triangles.rows()));
        edges_.reserve(static_cast<size_t>(triangles.rows()) * 2);
        for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
            triangles_[static_cast<size_t>(t)] = {triangles(t, 0), triangles(t, 1), triangles(t, 2)};
            link(static_cast<int>(t));
        }
    }

    int vertexCount() const { return vertexCount_; }
    int triangleCount() const { return static_cast<int>(triangles_.size()); }
    const Corners& triangle(int t) const { return triangles_[static_cast<size_t>(t)]; }

    // The triangles having edge {a, b} (null: none).
    const std::vector<int>* trianglesOf(int a, int b) const {
        const auto it = edges_.find(edgeKey(a, b));
        return it == edges_.end() || it->second.empty() ? nullptr : &it->second;
    }

    // Splits edge {a, b} at a new vertex (id vertexCount()); false if there is no such edge. Each triangle
    // having it is halved (TriangleHalving), in ascending id; `halved` gets the ids of the triangles changed
    // or appended.
    bool split(int a, int b, std::vector<TriangleHalving>* log, std::vector<int>* halved) {
        const auto it = edges_.find(edgeKey(a, b));
        if (it == edges_.end() || it->second.empty()) return false;
        std::vector<int> incident = std::move(it->second);
        edges_.erase(it);
        // note: sorted, so the result does not depend on the order the map happened to collect them in (a
        // replay of several refinements at once equals the refinements one after another).
        std::sort(incident.begin(), incident.end());
        const int m = vertexCount_++;
        for (int t : incident) {
            const Corners old = triangles_[static_cast<size_t>(t)];
            const int k = edgeCorner(old, a, b);
            assert(k >= 0);
            const int q = old[(k + 1) % 3], o = old[(k + 2) % 3], p = old[k];
            const int appended = static_cast<int>(triangles_.size());
            Corners half = old;
            half[static_cast<size_t>(k)] = m;
            triangles_[static_cast<size_t>(t)][static_cast<size_t>((k + 1) % 3)] = m;
            triangles_.push_back(half);
            // t keeps {o, p}; {q, o} moves to the appended half; the three new edges.
            std::vector<int>& qo = edges_[edgeKey(q, o)];
            *std::find(qo.begin(), qo.end(), t) = appended;
            edges_[edgeKey(p, m)].push_back(t);
            edges_[edgeKey(m, q)].push_back(appended);
            std::vector<int>& mo = edges_[edgeKey(m, o)];
            mo.push_back(t);
            mo.push_back(appended);
            if (log) log->push_back({t, k, appended});
            if (halved) {
                halved->push_back(t);
                halved->push_back(appended);
            }
        }
        return true;
    }

    void copyTo(Triangles& out) const {
        out.resize(static_cast<Eigen::Index>(triangles_.size()), 3);
        for (size_t t = 0; t < triangles_.size(); ++t)
            for (int k = 0; k < 3; ++k) out(static_cast<Eigen::Index>(t), k) = triangles_[t][static_cast<size_t>(k)];
    }

private:
    void link(int t) {
        const Corners& c = triangles_[static_cast<size_t>(t)];
        if (repeatsVertex(c)) return;  // not a surface triangle: never halved (see applyEdgeSplits)
        for (int k = 0; k < 3; ++k) edges_[edgeKey(c[static_cast<size_t>(k)], c[static_cast<size_t>((k + 1) % 3)])].push_back(t);
    }

    std::vector<Corners> triangles_;
    std::unordered_map<std::uint64_t, std::vector<int>> edges_;
    int vertexCount_ = 0;
};

// The deviation of one flat triangle (corner images a, b, c) from a quadratic patch through the images of
// its edge midpoints (ab, bc, ca) and centroid: 4/3 of the worst midpoint (header note), or the centroid's
// own value if larger.
double quadraticDeviation(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c, const Eigen::Vector3d& ab,
                          const Eigen::Vector3d& bc, const Eigen::Vector3d& ca, const Eigen::Vector3d& centroid) {
    const double midpoints = std::max({(ab - 0.5 * (a + b)).norm(), (bc - 0.5 * (b + c)).norm(), (ca - 0.5 * (c + a)).norm()});
    return std::max(midpoints * (4.0 / 3.0), (centroid - (a + b + c) / 3.0).norm());
}

// The images triangleDeviation samples, for a triangle with corners 0, 1, 2 (edge k runs from corner k to
// k + 1; m_k is its midpoint).
struct TriangleSamples {
    std::array<std::array<Eigen::Vector3d, 3>, 3> edge;  // edge k at 1/4, 1/2, 3/4 of the way from corner k
    std::array<Eigen::Vector3d, 3> inner;                // midpoint of m_k and m_{k+1}
    std::array<Eigen::Vector3d, 4> centroid;             // of the corner sub-triangle (r_j, m_j, m_{j-1}); [3]: (m_0, m_1, m_2)
};

// The rest points of TriangleSamples::inner and ::centroid (the edge points come from edgeSamplePoints).
void innerSamplePoints(const Eigen::Vector3d r[3], std::array<Eigen::Vector3d, 7>& points) {
    const Eigen::Vector3d m[3] = {0.5 * (r[0] + r[1]), 0.5 * (r[1] + r[2]), 0.5 * (r[2] + r[0])};
    for (int k = 0; k < 3; ++k) points[static_cast<size_t>(k)] = 0.5 * (m[k] + m[(k + 1) % 3]);
    for (int j = 0; j < 3; ++j) points[static_cast<size_t>(3 + j)] = (r[j] + m[j] + m[(j + 2) % 3]) / 3.0;
    points[6] = (m[0] + m[1] + m[2]) / 3.0;
}

// The rest points at 1/4, 1/2, 3/4 from ra to rb. note: the middle one is exactly the vertex a split puts
// there (appendSplitMidpoints), whichever way the edge is walked.
std::array<Eigen::Vector3d, 3> edgeSamplePoints(const Eigen::Vector3d& ra, const Eigen::Vector3d& rb) {
    const Eigen::Vector3d mid = 0.5 * (ra + rb);
    return {0.5 * (ra + mid), mid, 0.5 * (mid + rb)};
}

// triangleDeviation from the samples: the triangle split 1-to-4 (virtually); on each part S the error is at
// most S's quadratic deviation from the flat triangle through S's corner images, plus the largest error at
// S's corners (the difference of the two flat triangles is linear, so largest at a corner). Half the size,
// the quadratic model is four times as close; cubic B-spline pieces a triangle spans are seen.
double deviationFromSamples(const Eigen::Vector3d x[3], const TriangleSamples& s) {
    const Eigen::Vector3d m[3] = {s.edge[0][1], s.edge[1][1], s.edge[2][1]};
    double cornerError[3];
    for (int k = 0; k < 3; ++k) cornerError[k] = (m[k] - 0.5 * (x[k] + x[(k + 1) % 3])).norm();
    double worst = 0.0;
    for (int j = 0; j < 3; ++j) {
        const int previous = (j + 2) % 3;
        // (x_j, m_j, m_prev): edges x_j-m_j (edge j at 1/4), m_j-m_prev (inner[prev]), m_prev-x_j (edge prev at 3/4).
        const double part = quadraticDeviation(x[j], m[j], m[previous], s.edge[static_cast<size_t>(j)][0], s.inner[static_cast<size_t>(previous)],
                                               s.edge[static_cast<size_t>(previous)][2], s.centroid[static_cast<size_t>(j)]);
        worst = std::max(worst, part + std::max(cornerError[j], cornerError[previous]));
    }
    const double middle = quadraticDeviation(m[0], m[1], m[2], s.inner[0], s.inner[1], s.inner[2], s.centroid[3]);
    return std::max(worst, middle + std::max({cornerError[0], cornerError[1], cornerError[2]}));
}

}  // namespace

std::vector<int> seamCopiesOf(const Positions& rest, const std::vector<int>& among) {
    struct PointHash {
        size_t operator()(const std::array<double, 3>& p) const {
            size_t h = 0;
            for (double x : p) h = h * 1000003u ^ std::hash<double>()(x);
            return h;
        }
    };
    const auto point = [&rest](Eigen::Index v) {
        std::array<double, 3> p;
        for (int k = 0; k < 3; ++k) p[static_cast<size_t>(k)] = rest(v, k) == 0.0 ? 0.0 : rest(v, k);  // (-0 is +0)
        return p;
    };
    // The points that matter, each with the first vertex found there (scanning in id order: the smallest).
    std::unordered_map<std::array<double, 3>, int, PointHash> first;
    Eigen::RowVector3d lo = Eigen::RowVector3d::Constant(INFINITY), hi = -lo;  // the box of the points that matter
    if (among.empty()) {
        first.reserve(static_cast<size_t>(rest.rows()));
    } else {
        first.reserve(among.size());
        for (int v : among) {
            first.emplace(point(v), -1);
            lo = lo.cwiseMin(rest.row(v));
            hi = hi.cwiseMax(rest.row(v));
        }
    }
    std::vector<int> canonical(static_cast<size_t>(rest.rows()));
    bool shared = false;
    for (Eigen::Index v = 0; v < rest.rows(); ++v) {
        int id = static_cast<int>(v);
        if (among.empty()) {
            id = first.emplace(point(v), id).first->second;
        } else if (!((rest.row(v).array() >= lo.array()).all() && (rest.row(v).array() <= hi.array()).all())) {
            // (outside their box: not one of them)
        } else if (const auto found = first.find(point(v)); found != first.end()) {
            if (found->second < 0) found->second = id;
            id = found->second;
        }
        shared = shared || id != static_cast<int>(v);
        canonical[static_cast<size_t>(v)] = id;
    }
    if (!shared) canonical.clear();
    return canonical;
}

Triangles weldedAtSeams(const Triangles& triangles, const std::vector<int>& canonical) {
    if (canonical.empty()) return triangles;
    Triangles welded(triangles.rows(), 3);
    for (Eigen::Index t = 0; t < triangles.rows(); ++t)
        for (int k = 0; k < 3; ++k) welded(t, k) = canonical[static_cast<size_t>(triangles(t, k))];
    return welded;
}

std::vector<EdgeSplit> splitsOnSeamCopies(const Triangles& triangles, int vertexCount, const std::vector<int>& canonical,
                                          const std::vector<EdgeSplit>& welded) {
    if (canonical.empty() || welded.empty()) return welded;
    assert(canonical.size() == static_cast<size_t>(vertexCount));
    // Only triangles with an edge whose two corners' copies a welded split joins can be halved (a new vertex
    // lies only in triangles halved before): the simulation runs on those alone.
    std::vector<std::uint8_t> named(static_cast<size_t>(vertexCount), 0);
    for (const EdgeSplit& s : welded)
        for (int v : {s.a, s.b})
            if (v < vertexCount) named[static_cast<size_t>(v)] = 1;
    Triangles involved(triangles.rows(), 3);
    Eigen::Index count = 0;
    for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
        int hits = 0;
        for (int k = 0; k < 3; ++k) hits += named[static_cast<size_t>(canonical[static_cast<size_t>(triangles(t, k))])];
        if (hits >= 2) involved.row(count++) = triangles.row(t);
    }
    involved.conservativeResize(count, 3);
    SplittableMesh mesh(involved, vertexCount);
    // Each vertex's welded id (new ones: the welded split's), and per welded edge the mesh's edges on it.
    std::vector<int> weldedOf(canonical);
    std::unordered_map<std::uint64_t, std::vector<std::uint64_t>> onEdge;
    const auto note = [&](int t) {
        const Corners& c = mesh.triangle(t);
        if (repeatsVertex(c)) return;
        for (int k = 0; k < 3; ++k) {
            const int a = c[static_cast<size_t>(k)], b = c[static_cast<size_t>((k + 1) % 3)];
            std::vector<std::uint64_t>& list = onEdge[edgeKey(weldedOf[static_cast<size_t>(a)], weldedOf[static_cast<size_t>(b)])];
            if (std::find(list.begin(), list.end(), edgeKey(a, b)) == list.end()) list.push_back(edgeKey(a, b));
        }
    };
    for (int t = 0; t < mesh.triangleCount(); ++t) note(t);
    std::vector<EdgeSplit> out;
    std::vector<int> halved;
    for (size_t k = 0; k < welded.size(); ++k) {
        const int middle = vertexCount + static_cast<int>(k);
        assert(welded[k].a < middle && welded[k].b < middle);
        const auto found = onEdge.find(edgeKey(welded[k].a, welded[k].b));
        if (found == onEdge.end()) continue;
        const std::vector<std::uint64_t> copies = found->second;  // (copied: the splits note new edges)
        for (std::uint64_t edge : copies) {
            const int a = static_cast<int>(edge >> 32), b = static_cast<int>(edge & 0xffffffffu);
            halved.clear();
            if (!mesh.split(a, b, nullptr, &halved)) continue;  // (split before, as another copy's)
            out.push_back({a, b});
            weldedOf.push_back(middle);
            for (int t : halved) note(t);
        }
    }
    return out;
}

Status validateRefinementOptions(const RefinementOptions& options) {
    if (!std::isfinite(options.tolerance) || options.tolerance <= 0.0)
        return Status::error("refinement tolerance must be a finite number > 0 (a fraction of the bounding-box diagonal), got " +
                             std::to_string(options.tolerance));
    if (options.maxRounds < 1 || options.maxRounds > 64) return Status::error("refinement max_rounds must be in [1, 64]");
    if (options.maxVertices < 1) return Status::error("refinement max_vertices must be >= 1");
    if (!std::isfinite(options.shortestEdge) || options.shortestEdge < 0.0) return Status::error("refinement's shortest edge must be a finite number >= 0");
    return Status::success();
}

double triangleDeviation(const Eigen::Vector3d& restA, const Eigen::Vector3d& restB, const Eigen::Vector3d& restC,
                         const Eigen::Vector3d& currentA, const Eigen::Vector3d& currentB, const Eigen::Vector3d& currentC,
                         const RestImage& image) {
    const Eigen::Vector3d r[3] = {restA, restB, restC}, x[3] = {currentA, currentB, currentC};
    TriangleSamples samples;
    for (int k = 0; k < 3; ++k) {
        const std::array<Eigen::Vector3d, 3> points = edgeSamplePoints(r[k], r[(k + 1) % 3]);
        for (int i = 0; i < 3; ++i) samples.edge[static_cast<size_t>(k)][static_cast<size_t>(i)] = image(points[static_cast<size_t>(i)]);
    }
    std::array<Eigen::Vector3d, 7> inner;
    innerSamplePoints(r, inner);
    for (int i = 0; i < 3; ++i) samples.inner[static_cast<size_t>(i)] = image(inner[static_cast<size_t>(i)]);
    for (int i = 0; i < 4; ++i) samples.centroid[static_cast<size_t>(i)] = image(inner[static_cast<size_t>(3 + i)]);
    return deviationFromSamples(x, samples);
}

Status applyEdgeSplits(Triangles& triangles, int vertexCount, const std::vector<EdgeSplit>& splits,
                       std::vector<TriangleHalving>* halvings) {
    for (size_t k = 0; k < splits.size(); ++k) {
        const int count = vertexCount + static_cast<int>(k);
        const EdgeSplit& s = splits[k];
        if (s.a < 0 || s.b < 0 || s.a >= count || s.b >= count || s.a == s.b)
            return Status::error("split " + std::to_string(k) + ": vertices " + std::to_string(s.a) + " and " + std::to_string(s.b) +
                                 " are not two vertices of the mesh (it has " + std::to_string(count) + " at that point)");
    }
    SplittableMesh mesh(triangles, vertexCount);
    std::vector<TriangleHalving> log;
    for (size_t k = 0; k < splits.size(); ++k)
        if (!mesh.split(splits[k].a, splits[k].b, &log, nullptr))
            return Status::error("split " + std::to_string(k) + ": vertices " + std::to_string(splits[k].a) + " and " +
                                 std::to_string(splits[k].b) + " share no edge at that point");
    mesh.copyTo(triangles);
    if (halvings) *halvings = std::move(log);
    return Status::success();
}

void revertEdgeSplits(Triangles& triangles, const std::vector<TriangleHalving>& halvings) {
    // Last halving first: a half that was halved again is whole again before its own halving is undone.
    for (auto h = halvings.rbegin(); h != halvings.rend(); ++h) {
        const int next = (h->corner + 1) % 3;
        assert(h->appended < triangles.rows() && h->triangle < h->appended);
        triangles(h->triangle, next) = triangles(h->appended, next);  // the corner the new vertex replaced
    }
    const Eigen::Index kept = triangles.rows() - static_cast<Eigen::Index>(halvings.size());
    assert(kept >= 0);
    triangles.conservativeResize(kept, 3);
}

Status refineMesh(const Positions& rest, const Positions& current, const Triangles& triangles, const RestImage& image,
                  const RefinementOptions& options, RefinementResult& result) {
    if (Status s = validateRefinementOptions(options); !s) return s;
    if (rest.rows() != current.rows()) return Status::error("rest and current positions differ in count");
    if (triangles.size() > 0 && (triangles.minCoeff() < 0 || triangles.maxCoeff() >= rest.rows()))
        return Status::error("a triangle's vertex id is out of range");
    if (!image) return Status::error("no map from rest space to the current shape");

    RefinementResult out;
    std::vector<Eigen::Vector3d> restPoints(static_cast<size_t>(rest.rows())), currentPoints(static_cast<size_t>(rest.rows()));
    for (Eigen::Index v = 0; v < rest.rows(); ++v) {
        restPoints[static_cast<size_t>(v)] = rest.row(v).transpose();
        currentPoints[static_cast<size_t>(v)] = current.row(v).transpose();
    }
    double diagonal = 0.0;
    if (current.rows() > 0) diagonal = (current.colwise().maxCoeff() - current.colwise().minCoeff()).norm();
    out.toleranceWorld = options.tolerance * diagonal;
    // note: a triangle no longer than this in rest space is not split. A smooth deformation would have to
    // stretch it by 1 / tolerance for it to stray that far; where one does (the image jumps, e.g. at the box
    // of a lattice whose outer control points moved, outside which nothing moves), splitting never converges.
    const double restDiagonal = rest.rows() > 0 ? (rest.colwise().maxCoeff() - rest.colwise().minCoeff()).norm() : 0.0;
    const double shortestSplit = options.shortestEdge > 0.0 ? options.shortestEdge : options.tolerance * restDiagonal;

    SplittableMesh mesh(triangles, static_cast<int>(rest.rows()));
    // Per edge of the mesh, once evaluated: the images at 1/4, 1/2, 3/4 from its smaller vertex id to the
    // other (shared by its triangles; the middle one is where a split puts the new vertex).
    std::unordered_map<std::uint64_t, std::array<Eigen::Vector3d, 3>> edgeImages;
    std::vector<double> deviation(static_cast<size_t>(mesh.triangleCount()), 0.0);
    std::vector<std::uint8_t> stale(deviation.size(), 1);  // deviation not computed for the triangle as it is now
    const auto restPoint = [&](int v) -> const Eigen::Vector3d& { return restPoints[static_cast<size_t>(v)]; };

    // Evaluates every stale triangle (triangleDeviation) from the images of its samples, in parallel.
    const auto evaluate = [&]() {
        std::vector<int> list;
        for (int t = 0; t < mesh.triangleCount(); ++t)
            if (stale[static_cast<size_t>(t)]) {
                stale[static_cast<size_t>(t)] = 0;
                deviation[static_cast<size_t>(t)] = 0.0;
                if (!repeatsVertex(mesh.triangle(t))) list.push_back(t);
            }
        const std::array<Eigen::Vector3d, 3> unevaluated{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
        std::vector<std::uint64_t> keys;
        std::vector<Eigen::Vector3d> points;  // 3 per new edge
        for (int t : list) {
            const Corners& c = mesh.triangle(t);
            for (int k = 0; k < 3; ++k) {
                const int a = std::min(c[static_cast<size_t>(k)], c[static_cast<size_t>((k + 1) % 3)]);
                const int b = std::max(c[static_cast<size_t>(k)], c[static_cast<size_t>((k + 1) % 3)]);
                if (edgeImages.emplace(edgeKey(a, b), unevaluated).second) {
                    keys.push_back(edgeKey(a, b));
                    for (const Eigen::Vector3d& p : edgeSamplePoints(restPoint(a), restPoint(b))) points.push_back(p);
                }
            }
        }
        const int pointCount = static_cast<int>(points.size());
#pragma omp parallel for schedule(dynamic, 64) if (pointCount > 256)
        for (int i = 0; i < pointCount; ++i) points[static_cast<size_t>(i)] = image(points[static_cast<size_t>(i)]);
        for (size_t i = 0; i < keys.size(); ++i) edgeImages[keys[i]] = {points[3 * i], points[3 * i + 1], points[3 * i + 2]};
        // The edge samples in each triangle's own direction (edge k from corner k).
        std::vector<TriangleSamples> samples(list.size());
        for (size_t i = 0; i < list.size(); ++i) {
            const Corners& c = mesh.triangle(list[i]);
            for (int k = 0; k < 3; ++k) {
                const int a = c[static_cast<size_t>(k)], b = c[static_cast<size_t>((k + 1) % 3)];
                const std::array<Eigen::Vector3d, 3>& e = edgeImages.at(edgeKey(a, b));
                for (int j = 0; j < 3; ++j) samples[i].edge[static_cast<size_t>(k)][static_cast<size_t>(j)] = e[static_cast<size_t>(a < b ? j : 2 - j)];
            }
        }
        const int listCount = static_cast<int>(list.size());
#pragma omp parallel for schedule(dynamic, 32) if (listCount > 64)
        for (int i = 0; i < listCount; ++i) {
            const Corners& c = mesh.triangle(list[static_cast<size_t>(i)]);
            const Eigen::Vector3d r[3] = {restPoint(c[0]), restPoint(c[1]), restPoint(c[2])};
            const Eigen::Vector3d x[3] = {currentPoints[static_cast<size_t>(c[0])], currentPoints[static_cast<size_t>(c[1])],
                                          currentPoints[static_cast<size_t>(c[2])]};
            std::array<Eigen::Vector3d, 7> inner;
            innerSamplePoints(r, inner);
            TriangleSamples& sample = samples[static_cast<size_t>(i)];
            for (int j = 0; j < 3; ++j) sample.inner[static_cast<size_t>(j)] = image(inner[static_cast<size_t>(j)]);
            for (int j = 0; j < 4; ++j) sample.centroid[static_cast<size_t>(j)] = image(inner[static_cast<size_t>(3 + j)]);
            deviation[static_cast<size_t>(list[static_cast<size_t>(i)])] = deviationFromSamples(x, sample);
        }
    };
    const auto worst = [&](int* over) {
        double w = 0.0;
        int count = 0;
        for (double d : deviation) {
            w = std::max(w, d);
            count += d > out.toleranceWorld;
        }
        if (over) *over = count;
        return w;
    };

    const auto restLengthSq = [&](int a, int b) { return (restPoint(a) - restPoint(b)).squaredNorm(); };
    // The longest edge of t in rest space, as its local corner; ties go to the larger id pair, so "longer" is a
    // strict order on edges and a longest-edge path never comes back (it ends).
    // note: in rest space, where each split puts its vertex at the edge's midpoint, Rivara's bound holds: the
    // triangles keep their angles and the edges shrink. In the current shape the new vertex is the image of
    // that midpoint, not the midpoint of the edge's image: where a field squeezes space to a quarter along one
    // direction (brush_field.h, ahead of a long pull), the current shape's longest edge was split again and
    // again towards a fixed pair of points (a stroke's plan on CGAL's camel held 6,852 triangles with coinciding
    // corners). The image of a well-shaped rest triangle is as well shaped as the map's gradient allows; a
    // triangle stretched along one edge is split again in a later round while it strays over the tolerance.
    const auto longestCorner = [&](int t) {
        const Corners& c = mesh.triangle(t);
        int best = 0;
        double bestLength = -1.0;
        std::uint64_t bestKey = 0;
        for (int k = 0; k < 3; ++k) {
            const int a = c[static_cast<size_t>(k)], b = c[static_cast<size_t>((k + 1) % 3)];
            const double length = restLengthSq(a, b);
            const std::uint64_t key = edgeKey(a, b);
            if (length > bestLength || (length == bestLength && key > bestKey)) {
                best = k;
                bestLength = length;
                bestKey = key;
            }
        }
        return best;
    };

    std::vector<std::uint8_t> halvedThisRound;
    std::vector<int> halved;
    // Splits edge {a, b}: the new vertex at the image of the rest midpoint. False at the vertex limit.
    const auto splitEdge = [&](int a, int b) {
        if (mesh.vertexCount() >= options.maxVertices) return false;
        const std::uint64_t key = edgeKey(a, b);
        const Eigen::Vector3d restMiddle = 0.5 * (restPoint(a) + restPoint(b));
        const auto cached = edgeImages.find(key);
        const Eigen::Vector3d currentMiddle = cached != edgeImages.end() ? cached->second[1] : image(restMiddle);
        if (cached != edgeImages.end()) edgeImages.erase(cached);
        halved.clear();
        [[maybe_unused]] const bool ok = mesh.split(a, b, nullptr, &halved);
        assert(ok);
        out.splits.push_back({a, b});
        restPoints.push_back(restMiddle);
        currentPoints.push_back(currentMiddle);
        deviation.resize(static_cast<size_t>(mesh.triangleCount()), 0.0);
        stale.resize(deviation.size(), 1);
        halvedThisRound.resize(deviation.size(), 1);
        for (int t : halved) {
            stale[static_cast<size_t>(t)] = 1;
            halvedThisRound[static_cast<size_t>(t)] = 1;
        }
        return true;
    };
    // Rivara's LEPP bisection of t: follow the longest-edge propagation path from t to its terminal edge (the
    // longest edge of both triangles sharing it, or a boundary edge), split that, and repeat until t itself
    // is halved. False at the vertex limit.
    // note: in rest space the path's edges shrink with every split, so it ends (Rivara); in the current shape
    // a jump in the image keeps an edge across it long however often it is split, and the path could go on
    // splitting there forever. So no edge shorter than shortestSplit in rest space is split, and after
    // kMaxPathSplits splits (or where the path ends at such an edge) t's longest rest-space edge is split: it
    // is long enough, or t would not be over the tolerance and splittable. Conforming either way.
    constexpr int kMaxPathSplits = 16;
    const double shortestSq = shortestSplit * shortestSplit;
    const auto bisect = [&](int t) {
        for (int splits = 0; !halvedThisRound[static_cast<size_t>(t)]; ++splits) {
            int a = -1, b = -1;
            // (the path's edges grow strictly, so it ends; the step count guards against a non-finite image)
            for (int at = t, step = 0; splits < kMaxPathSplits && step < mesh.triangleCount(); ++step) {  // the path, until kMaxPathSplits were made
                const int k = longestCorner(at);
                const Corners& c = mesh.triangle(at);
                const int u = c[static_cast<size_t>(k)], v = c[static_cast<size_t>((k + 1) % 3)];
                const std::vector<int>* sharing = mesh.trianglesOf(u, v);
                int neighbour = -1;
                if (sharing && sharing->size() == 2) neighbour = (*sharing)[0] == at ? (*sharing)[1] : (*sharing)[0];
                bool terminal = neighbour < 0;
                if (!terminal) {
                    const int kn = longestCorner(neighbour);
                    const Corners& cn = mesh.triangle(neighbour);
                    terminal = edgeKey(cn[static_cast<size_t>(kn)], cn[static_cast<size_t>((kn + 1) % 3)]) == edgeKey(u, v);
                }
                if (terminal) {
                    if (restLengthSq(u, v) >= shortestSq) {
                        a = u;
                        b = v;
                    }
                    break;
                }
                at = neighbour;
            }
            if (a < 0) {
                const Corners& c = mesh.triangle(t);
                int k = 0;
                for (int j = 1; j < 3; ++j)
                    if (restLengthSq(c[static_cast<size_t>(j)], c[static_cast<size_t>((j + 1) % 3)]) >
                        restLengthSq(c[static_cast<size_t>(k)], c[static_cast<size_t>((k + 1) % 3)]))
                        k = j;
                a = c[static_cast<size_t>(k)];
                b = c[static_cast<size_t>((k + 1) % 3)];
            }
            if (!splitEdge(a, b)) return false;
        }
        return true;
    };

    evaluate();
    out.worstBefore = worst(nullptr);
    for (;;) {
        std::vector<int> over;
        int smallest = 0;  // over the tolerance, but too small to split
        for (int t = 0; t < mesh.triangleCount(); ++t) {
            if (!(deviation[static_cast<size_t>(t)] > out.toleranceWorld)) continue;
            const Corners& c = mesh.triangle(t);
            double longest = 0.0;
            for (int k = 0; k < 3; ++k)
                longest = std::max(longest, (restPoint(c[static_cast<size_t>(k)]) - restPoint(c[static_cast<size_t>((k + 1) % 3)])).squaredNorm());
            if (longest >= shortestSq) over.push_back(t);
            else ++smallest;
        }
        if (over.empty()) {
            out.converged = smallest == 0;
            if (smallest > 0) out.stopped = "smallest size";
            break;
        }
        if (out.rounds == options.maxRounds) {
            out.stopped = "max rounds";
            break;
        }
        ++out.rounds;
        halvedThisRound.assign(static_cast<size_t>(mesh.triangleCount()), 0);
        bool limit = false;
        for (int t : over) {
            if (!bisect(t)) {
                limit = true;
                break;
            }
        }
        evaluate();
        if (limit) {
            out.stopped = "max vertices";
            break;
        }
    }
    out.worstAfter = worst(&out.trianglesOver);

    out.rest.resize(static_cast<Eigen::Index>(restPoints.size()), 3);
    out.current.resize(out.rest.rows(), 3);
    for (size_t v = 0; v < restPoints.size(); ++v) {
        out.rest.row(static_cast<Eigen::Index>(v)) = restPoints[v].transpose();
        out.current.row(static_cast<Eigen::Index>(v)) = currentPoints[v].transpose();
    }
    mesh.copyTo(out.triangles);
    result = std::move(out);
    return Status::success();
}

}  // namespace sculpt::core
