// Exact triangle-pair intersection for the mesh self-intersection check, on CGAL's exact predicates.
// The case analysis (shared edge: coplanar and folded; shared vertex: an opposite edge pierces the other
// triangle; otherwise any common point) follows CGAL Polygon_mesh_processing's do_faces_intersect. It lives
// in its own translation unit because CGAL's headers are slow to compile.
#include "core/injectivity/triangle_pair.h"

#include <cmath>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/intersections.h>
#include <CGAL/squared_distance_3.h>

namespace sculpt::core {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Segment = Kernel::Segment_3;
using Triangle = Kernel::Triangle_3;

Point toPoint(const Eigen::Vector3d& p) { return Point(p.x(), p.y(), p.z()); }

// A triangle as the simplest primitive that has its point set: triangle, segment (collinear corners) or point.
struct Primitive {
    enum class Kind { Dot, Line, Area } kind = Kind::Area;
    Point p[3];
};

Primitive classify(const TriangleCorners& t) {
    Primitive out;
    for (int c = 0; c < 3; ++c) out.p[c] = toPoint(t.point[c]);
    if (!CGAL::collinear(out.p[0], out.p[1], out.p[2])) return out;
    if (out.p[0] == out.p[1] && out.p[1] == out.p[2]) {
        out.kind = Primitive::Kind::Dot;
        return out;
    }
    // Collinear: the segment between the two corners farthest apart holds the third.
    out.kind = Primitive::Kind::Line;
    int far0 = 0, far1 = 1;
    double best = -1.0;
    for (int i = 0; i < 3; ++i)
        for (int j = i + 1; j < 3; ++j) {
            const double d = (t.point[i] - t.point[j]).squaredNorm();
            if (d > best) best = d, far0 = i, far1 = j;
        }
    const Point a = out.p[far0], b = out.p[far1];
    out.p[0] = a;
    out.p[1] = b;
    return out;
}

bool primitivesIntersect(const Primitive& a, const Primitive& b) {
    using K = Primitive::Kind;
    if (a.kind == K::Dot && b.kind == K::Dot) return a.p[0] == b.p[0];
    if (a.kind == K::Dot || b.kind == K::Dot) {
        const Primitive& point = a.kind == K::Dot ? a : b;
        const Primitive& other = a.kind == K::Dot ? b : a;
        if (other.kind == K::Line) return Segment(other.p[0], other.p[1]).has_on(point.p[0]);
        return Triangle(other.p[0], other.p[1], other.p[2]).has_on(point.p[0]);
    }
    if (a.kind == K::Line && b.kind == K::Line)
        return CGAL::do_intersect(Segment(a.p[0], a.p[1]), Segment(b.p[0], b.p[1]));
    if (a.kind == K::Line) return CGAL::do_intersect(Segment(a.p[0], a.p[1]), Triangle(b.p[0], b.p[1], b.p[2]));
    if (b.kind == K::Line) return CGAL::do_intersect(Segment(b.p[0], b.p[1]), Triangle(a.p[0], a.p[1], a.p[2]));
    return CGAL::do_intersect(Triangle(a.p[0], a.p[1], a.p[2]), Triangle(b.p[0], b.p[1], b.p[2]));
}

// The sign of orient3d(a, b, c, d) where plain double arithmetic certifies it, 0 where it cannot: Shewchuk's
// static error bound for the determinant computed from the input coordinates (Shewchuk 1997, "Adaptive
// precision floating-point arithmetic and fast robust geometric predicates", o3derrboundA). Most pairs the
// broad phase hands over are decided here; the rest go to CGAL's exact predicates.
int certifiedOrientation(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c, const Eigen::Vector3d& d) {
    const Eigen::Vector3d ad = a - d, bd = b - d, cd = c - d;
    const double bc = bd.y() * cd.z() - bd.z() * cd.y(), ca = cd.y() * ad.z() - cd.z() * ad.y(), ab = ad.y() * bd.z() - ad.z() * bd.y();
    const double det = ad.x() * bc + bd.x() * ca + cd.x() * ab;
    const double permanent = (std::abs(bd.y() * cd.z()) + std::abs(bd.z() * cd.y())) * std::abs(ad.x()) +
                             (std::abs(cd.y() * ad.z()) + std::abs(cd.z() * ad.y())) * std::abs(bd.x()) +
                             (std::abs(ad.y() * bd.z()) + std::abs(ad.z() * bd.y())) * std::abs(cd.x());
    constexpr double kBound = 7.7715611723761027e-16;  // (7 + 56 eps) eps, eps = 2^-53
    if (det > kBound * permanent) return 1;
    if (-det > kBound * permanent) return -1;
    return 0;
}

// True when the points p[i] (i in `which`) are certified strictly on one side of triangle t's plane.
bool certifiedOneSide(const TriangleCorners& t, const Eigen::Vector3d* points, int count) {
    int first = 0;
    for (int i = 0; i < count; ++i) {
        const int o = certifiedOrientation(t.point[0], t.point[1], t.point[2], points[i]);
        if (o == 0 || (i > 0 && o != first)) return false;
        first = o;
    }
    return true;
}

// 0: certainly no intersection beyond what they share, -1: not decided by the filter.
int quickDecision(const TriangleCorners& a, const TriangleCorners& b) {
    int shared = 0, wa = -1, wb = -1;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            if (a.vertex[i] == b.vertex[j]) ++shared, wa = i, wb = j;
    if (shared == 0) {
        // One triangle wholly on one side of the other's plane: they cannot meet.
        if (certifiedOneSide(a, b.point.data(), 3) || certifiedOneSide(b, a.point.data(), 3)) return 0;
        return -1;
    }
    if (shared == 1) {
        // Each edge opposite the shared vertex must miss the other triangle (see below): certainly so when it
        // lies strictly on one side of that triangle's plane.
        const Eigen::Vector3d oppositeB[2] = {b.point[(wb + 1) % 3], b.point[(wb + 2) % 3]};
        const Eigen::Vector3d oppositeA[2] = {a.point[(wa + 1) % 3], a.point[(wa + 2) % 3]};
        if (certifiedOneSide(a, oppositeB, 2) && certifiedOneSide(b, oppositeA, 2)) return 0;
        return -1;
    }
    if (shared == 2) {
        // Sharing an edge, they meet beyond it only when all four corners are coplanar.
        int ob = 0;
        while (ob < 2 && (b.vertex[ob] == a.vertex[0] || b.vertex[ob] == a.vertex[1] || b.vertex[ob] == a.vertex[2])) ++ob;
        if (certifiedOrientation(a.point[0], a.point[1], a.point[2], b.point[ob]) != 0) return 0;
        return -1;
    }
    return 0;  // the same face twice
}

// The full case analysis on CGAL's exact predicates.
bool exactDecision(const TriangleCorners& a, const TriangleCorners& b) {
    // Which corners the two share, by vertex id: sharedA[i] = the corner of b with a's vertex i, or -1.
    int sharedA[3] = {-1, -1, -1};
    int shared = 0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            if (a.vertex[i] == b.vertex[j]) {
                sharedA[i] = j;
                ++shared;
                break;
            }
    if (shared == 0) return primitivesIntersect(classify(a), classify(b));
    if (shared == 3) return false;  // the same face twice
    const Primitive pa = classify(a), pb = classify(b);
    if (pa.kind != Primitive::Kind::Area || pb.kind != Primitive::Kind::Area) return false;

    if (shared == 2) {
        // Shared edge (u, v): the two can only meet beyond it if they lie in one plane, folded onto the same
        // side of the edge.
        int ua = -1, va = -1, oa = -1;
        for (int i = 0; i < 3; ++i) {
            if (sharedA[i] < 0) oa = i;
            else if (ua < 0) ua = i;
            else va = i;
        }
        int ob = 0;
        while (ob == sharedA[ua] || ob == sharedA[va]) ++ob;
        const Point u = pa.p[ua], v = pa.p[va], x = pa.p[oa], y = pb.p[ob];
        return CGAL::coplanar(u, v, x, y) && CGAL::coplanar_orientation(u, v, x, y) == CGAL::POSITIVE;
    }
    // Shared vertex w: their intersection is convex and holds w, so it holds more than w exactly when the
    // edge opposite w of one triangle meets the other triangle.
    int wa = 0;
    while (sharedA[wa] < 0) ++wa;
    const int wb = sharedA[wa];
    const Segment oppositeA(pa.p[(wa + 1) % 3], pa.p[(wa + 2) % 3]);
    const Segment oppositeB(pb.p[(wb + 1) % 3], pb.p[(wb + 2) % 3]);
    return CGAL::do_intersect(oppositeB, Triangle(pa.p[0], pa.p[1], pa.p[2])) ||
           CGAL::do_intersect(oppositeA, Triangle(pb.p[0], pb.p[1], pb.p[2]));
}

}  // namespace

bool trianglesIntersect(const TriangleCorners& a, const TriangleCorners& bIn) {
    // Corners at the very same position are one vertex whatever their ids: the triangles of a soup (a file that
    // stores each triangle's corners apart) or of a seam split for its normals or texture coordinates touch
    // there as neighbours do, and only what they have in common beyond it counts.
    TriangleCorners b = bIn;
    for (int j = 0; j < 3; ++j) {
        bool byId = false;
        for (int i = 0; i < 3; ++i) byId = byId || (b.vertex[j] >= 0 && b.vertex[j] == a.vertex[i]);
        for (int i = 0; i < 3 && !byId; ++i)
            if (b.point[j] == a.point[i]) {
                b.vertex[j] = a.vertex[i] >= 0 ? a.vertex[i] : -2 - i;  // -2 - i: a's corner i, when a has no ids
                break;
            }
    }
    TriangleCorners aIds = a;
    for (int i = 0; i < 3; ++i)
        if (aIds.vertex[i] < 0) aIds.vertex[i] = -2 - i;
    for (int j = 0; j < 3; ++j)
        if (b.vertex[j] == -1) b.vertex[j] = -10 - j;  // matches none of a's
    if (quickDecision(aIds, b) == 0) return false;
    return exactDecision(aIds, b);
}

bool trianglesWithin(const TriangleCorners& a, const TriangleCorners& b, double tolerance) {
    const Eigen::Vector3d normalA = (a.point[1] - a.point[0]).cross(a.point[2] - a.point[0]);
    const Eigen::Vector3d normalB = (b.point[1] - b.point[0]).cross(b.point[2] - b.point[0]);
    if (!(normalA.squaredNorm() > 0.0) || !(normalB.squaredNorm() > 0.0)) return false;  // no area (or none in doubles)
    // Which corners are one vertex (by id, or at the very same position).
    bool same[3][3], sharedA[3] = {false, false, false}, sharedB[3] = {false, false, false};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            same[i][j] = (a.vertex[i] >= 0 && a.vertex[i] == b.vertex[j]) || a.point[i] == b.point[j];
            if (same[i][j]) sharedA[i] = sharedB[j] = true;
        }
    // Each triangle's corners not shared, beyond `tolerance` on one side of the other's plane: then every
    // corner and edge of the other is too, apart from the shared corners, which lie on that plane (a shared
    // corner's edges run from the plane into the far side). Most neighbours of a curved surface part here.
    const auto parted = [tolerance](const TriangleCorners& plane, const Eigen::Vector3d& normalOfPlane, const TriangleCorners& other,
                                    const bool* shared) {
        const Eigen::Vector3d normal = normalOfPlane.normalized();
        int above = 0, below = 0, free = 0;
        for (int k = 0; k < 3; ++k) {
            if (shared[k]) continue;
            ++free;
            const double side = normal.dot(other.point[k] - plane.point[0]);
            above += side > tolerance;
            below += side < -tolerance;
        }
        return free > 0 && (above == free || below == free);
    };
    if (parted(a, normalA, b, sharedB) || parted(b, normalB, a, sharedA)) return false;
    const double squared = tolerance * tolerance;
    const Triangle ta(toPoint(a.point[0]), toPoint(a.point[1]), toPoint(a.point[2]));
    const Triangle tb(toPoint(b.point[0]), toPoint(b.point[1]), toPoint(b.point[2]));
    // A point beyond `tolerance` outside one of the triangle's edges (in the plane through that edge normal to the
    // triangle) is farther than `tolerance` from it: most corners of a flat neighbour stop here.
    const auto pointNear = [&](const Eigen::Vector3d& p, const TriangleCorners& t, const Eigen::Vector3d& normal, const Triangle& triangle) {
        for (int e = 0; e < 3; ++e) {
            const Eigen::Vector3d edge = t.point[(e + 1) % 3] - t.point[e];
            const Eigen::Vector3d outward = edge.cross(normal).normalized();  // (corners counter-clockwise about normal)
            if (outward.dot(p - t.point[e]) > tolerance) return false;
        }
        return CGAL::to_double(CGAL::squared_distance(toPoint(p), triangle)) <= squared;
    };
    for (int k = 0; k < 3; ++k) {
        if (!sharedB[k] && pointNear(b.point[k], a, normalA, ta)) return true;
        if (!sharedA[k] && pointNear(a.point[k], b, normalB, tb)) return true;
    }
    // Edges i (corners i, i + 1) of a and j of b with no common corner.
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            const int i1 = (i + 1) % 3, j1 = (j + 1) % 3;
            if (same[i][j] || same[i][j1] || same[i1][j] || same[i1][j1]) continue;
            // (apart by more than `tolerance` along an axis: farther)
            const Eigen::Vector3d loA = a.point[i].cwiseMin(a.point[i1]), hiA = a.point[i].cwiseMax(a.point[i1]);
            const Eigen::Vector3d loB = b.point[j].cwiseMin(b.point[j1]), hiB = b.point[j].cwiseMax(b.point[j1]);
            if (((loA.array() - hiB.array()) > tolerance).any() || ((loB.array() - hiA.array()) > tolerance).any()) continue;
            const Segment ea(toPoint(a.point[i]), toPoint(a.point[i1])), eb(toPoint(b.point[j]), toPoint(b.point[j1]));
            if (CGAL::to_double(CGAL::squared_distance(ea, eb)) <= squared) return true;
        }
    return false;
}

Eigen::Vector3d nearestOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
    const Eigen::Vector3d ab = b - a, ac = c - a, normal = ab.cross(ac);
    const double area2 = normal.squaredNorm();
    if (!(area2 > 0.0)) return Eigen::Vector3d::Constant(NAN);
    const Point q = Kernel().construct_projected_point_3_object()(Triangle(toPoint(a), toPoint(b), toPoint(c)), toPoint(p));
    // Barycentric coordinates of q (on the triangle) as ratios of signed areas to the whole (cross products: a
    // sliver's are as accurate as its normal, where the normal equations' d00 d11 - d01^2 would cancel).
    const Eigen::Vector3d aq = Eigen::Vector3d(q.x(), q.y(), q.z()) - a;
    Eigen::Vector3d w(0.0, aq.cross(ac).dot(normal) / area2, ab.cross(aq).dot(normal) / area2);
    w[0] = 1.0 - w[1] - w[2];
    w = w.cwiseMax(0.0);  // rounding of a point on an edge or a corner
    return w / w.sum();
}

bool triangleDegenerate(const TriangleCorners& t) {
    return CGAL::collinear(toPoint(t.point[0]), toPoint(t.point[1]), toPoint(t.point[2]));
}

}  // namespace sculpt::core
