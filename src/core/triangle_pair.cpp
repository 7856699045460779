// Exact triangle-pair intersection for the mesh self-intersection check, on CGAL's exact predicates.
// The case analysis (shared edge: coplanar and folded; shared vertex: an opposite edge pierces the other
// triangle; otherwise any common point) follows CGAL Polygon_mesh_processing's do_faces_intersect. It lives
// in its own translation unit because CGAL's headers are slow to compile.
#include "core/triangle_pair.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/intersections.h>

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

}  // namespace

bool trianglesIntersect(const TriangleCorners& a, const TriangleCorners& b) {
    // Which corners the two share, by vertex id: sharedA[i] = the corner of b with a's vertex i, or -1.
    int sharedA[3] = {-1, -1, -1};
    int shared = 0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            if (a.vertex[i] >= 0 && a.vertex[i] == b.vertex[j]) {
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

}  // namespace sculpt::core
