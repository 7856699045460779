// Refinement where the surface stretches: Coquillart 1990, "Extended Free-Form Deformation", section 3.4
// (subdivision after Griessmair and Purgathofer 1989, "Deformation of solids with trivariate B-splines"),
// with conforming longest-edge bisection (Rivara 1984, "Algorithms for refining triangular grids suitable
// for adaptive and multigrid techniques"; the LEPP form: Rivara 1997).
#include "core/refinement.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <cstdint>
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

// triangleDeviation from the images of the sample points (edge midpoints in corner order: ab, bc, ca).
double deviationFromSamples(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                            const Eigen::Vector3d& imageAB, const Eigen::Vector3d& imageBC, const Eigen::Vector3d& imageCA,
                            const Eigen::Vector3d& imageCentroid) {
    const double midpoints = std::max({(imageAB - 0.5 * (a + b)).norm(), (imageBC - 0.5 * (b + c)).norm(), (imageCA - 0.5 * (c + a)).norm()});
    const double centroid = (imageCentroid - (a + b + c) / 3.0).norm();
    // The quadratic bound (header note): 4/3 of the worst midpoint.
    return std::max(midpoints * (4.0 / 3.0), centroid);
}

}  // namespace

Status validateRefinementOptions(const RefinementOptions& options) {
    if (!std::isfinite(options.tolerance) || options.tolerance <= 0.0)
        return Status::error("refinement tolerance must be a finite number > 0 (a fraction of the bounding-box diagonal), got " +
                             std::to_string(options.tolerance));
    if (options.maxRounds < 1 || options.maxRounds > 64) return Status::error("refinement max_rounds must be in [1, 64]");
    if (options.maxVertices < 1) return Status::error("refinement max_vertices must be >= 1");
    return Status::success();
}

double triangleDeviation(const Eigen::Vector3d& restA, const Eigen::Vector3d& restB, const Eigen::Vector3d& restC,
                         const Eigen::Vector3d& currentA, const Eigen::Vector3d& currentB, const Eigen::Vector3d& currentC,
                         const RestImage& image) {
    return deviationFromSamples(currentA, currentB, currentC, image(0.5 * (restA + restB)), image(0.5 * (restB + restC)),
                                image(0.5 * (restC + restA)), image((restA + restB + restC) / 3.0));
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

void appendSplitMidpoints(Positions& rest, const std::vector<EdgeSplit>& splits) {
    const Eigen::Index first = rest.rows();
    rest.conservativeResize(first + static_cast<Eigen::Index>(splits.size()), 3);
    for (size_t k = 0; k < splits.size(); ++k) {
        const Eigen::Index row = first + static_cast<Eigen::Index>(k);
        assert(splits[k].a >= 0 && splits[k].a < row && splits[k].b >= 0 && splits[k].b < row);
        rest.row(row) = 0.5 * (rest.row(splits[k].a) + rest.row(splits[k].b));
    }
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

    SplittableMesh mesh(triangles, static_cast<int>(rest.rows()));
    std::unordered_map<std::uint64_t, Eigen::Vector3d> midpointImage;  // per edge of the mesh, once evaluated
    std::vector<double> deviation(static_cast<size_t>(mesh.triangleCount()), 0.0);
    std::vector<std::uint8_t> stale(deviation.size(), 1);  // deviation not computed for the triangle as it is now
    const auto restMidpoint = [&](int a, int b) { return Eigen::Vector3d(0.5 * (restPoints[static_cast<size_t>(a)] + restPoints[static_cast<size_t>(b)])); };

    // Evaluates every stale triangle: the images of its edge midpoints (shared with its neighbours and kept
    // for the vertex a split would put there) and of its centroid, in parallel.
    const auto evaluate = [&]() {
        std::vector<int> list;
        for (int t = 0; t < mesh.triangleCount(); ++t)
            if (stale[static_cast<size_t>(t)]) {
                stale[static_cast<size_t>(t)] = 0;
                deviation[static_cast<size_t>(t)] = 0.0;
                if (!repeatsVertex(mesh.triangle(t))) list.push_back(t);
            }
        std::vector<std::uint64_t> keys;
        std::vector<Eigen::Vector3d> points;
        for (int t : list) {
            const Corners& c = mesh.triangle(t);
            for (int k = 0; k < 3; ++k) {
                const int a = c[static_cast<size_t>(k)], b = c[static_cast<size_t>((k + 1) % 3)];
                if (midpointImage.emplace(edgeKey(a, b), Eigen::Vector3d::Zero()).second) {
                    keys.push_back(edgeKey(a, b));
                    points.push_back(restMidpoint(a, b));
                }
            }
        }
        const int pointCount = static_cast<int>(points.size());
#pragma omp parallel for schedule(dynamic, 64) if (pointCount > 256)
        for (int i = 0; i < pointCount; ++i) points[static_cast<size_t>(i)] = image(points[static_cast<size_t>(i)]);
        for (size_t i = 0; i < keys.size(); ++i) midpointImage[keys[i]] = points[i];
        std::vector<std::array<const Eigen::Vector3d*, 3>> samples(list.size());
        for (size_t i = 0; i < list.size(); ++i) {
            const Corners& c = mesh.triangle(list[i]);
            for (int k = 0; k < 3; ++k)
                samples[i][static_cast<size_t>(k)] = &midpointImage.at(edgeKey(c[static_cast<size_t>(k)], c[static_cast<size_t>((k + 1) % 3)]));
        }
        const int listCount = static_cast<int>(list.size());
#pragma omp parallel for schedule(dynamic, 64) if (listCount > 256)
        for (int i = 0; i < listCount; ++i) {
            const Corners& c = mesh.triangle(list[static_cast<size_t>(i)]);
            const Eigen::Vector3d& a = currentPoints[static_cast<size_t>(c[0])];
            const Eigen::Vector3d& b = currentPoints[static_cast<size_t>(c[1])];
            const Eigen::Vector3d& d = currentPoints[static_cast<size_t>(c[2])];
            const Eigen::Vector3d centroid =
                (restPoints[static_cast<size_t>(c[0])] + restPoints[static_cast<size_t>(c[1])] + restPoints[static_cast<size_t>(c[2])]) / 3.0;
            const auto& s = samples[static_cast<size_t>(i)];
            deviation[static_cast<size_t>(list[static_cast<size_t>(i)])] = deviationFromSamples(a, b, d, *s[0], *s[1], *s[2], image(centroid));
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

    // The longest edge of t in the current shape, as its local corner; ties go to the larger id pair, so
    // "longer" is a strict order on edges and a longest-edge path never comes back (it ends).
    const auto longestCorner = [&](int t) {
        const Corners& c = mesh.triangle(t);
        int best = 0;
        double bestLength = -1.0;
        std::uint64_t bestKey = 0;
        for (int k = 0; k < 3; ++k) {
            const int a = c[static_cast<size_t>(k)], b = c[static_cast<size_t>((k + 1) % 3)];
            const double length = (currentPoints[static_cast<size_t>(a)] - currentPoints[static_cast<size_t>(b)]).squaredNorm();
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
        const Eigen::Vector3d restPoint = restMidpoint(a, b);
        const auto cached = midpointImage.find(key);
        const Eigen::Vector3d currentPoint = cached != midpointImage.end() ? cached->second : image(restPoint);
        if (cached != midpointImage.end()) midpointImage.erase(cached);
        halved.clear();
        [[maybe_unused]] const bool ok = mesh.split(a, b, nullptr, &halved);
        assert(ok);
        out.splits.push_back({a, b});
        restPoints.push_back(restPoint);
        currentPoints.push_back(currentPoint);
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
    const auto bisect = [&](int t) {
        while (!halvedThisRound[static_cast<size_t>(t)]) {
            int at = t;
            for (;;) {
                const int k = longestCorner(at);
                const Corners& c = mesh.triangle(at);
                const int a = c[static_cast<size_t>(k)], b = c[static_cast<size_t>((k + 1) % 3)];
                const std::vector<int>* sharing = mesh.trianglesOf(a, b);
                int neighbour = -1;
                if (sharing && sharing->size() == 2) neighbour = (*sharing)[0] == at ? (*sharing)[1] : (*sharing)[0];
                bool terminal = neighbour < 0;
                if (!terminal) {
                    const int kn = longestCorner(neighbour);
                    const Corners& cn = mesh.triangle(neighbour);
                    terminal = edgeKey(cn[static_cast<size_t>(kn)], cn[static_cast<size_t>((kn + 1) % 3)]) == edgeKey(a, b);
                }
                if (terminal) {
                    if (!splitEdge(a, b)) return false;
                    break;
                }
                at = neighbour;
            }
        }
        return true;
    };

    evaluate();
    out.worstBefore = worst(nullptr);
    for (;;) {
        std::vector<int> over;
        for (int t = 0; t < mesh.triangleCount(); ++t)
            if (deviation[static_cast<size_t>(t)] > out.toleranceWorld) over.push_back(t);
        if (over.empty()) {
            out.converged = true;
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
