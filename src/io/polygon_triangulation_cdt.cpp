// The general polygon triangulation: a constrained Delaunay triangulation of the polygon's edges in the
// plane of its Newell normal (CGAL's Constrained_Delaunay_triangulation_2 with exact predicates; see the
// CGAL 2D Triangulation manual, "Constrained Delaunay Triangulations" and its polygon_triangulation example),
// keeping the triangles where the polygon's winding number is 1. CGAL is compiled in this file only.
//
// note: the example marks the inside by nesting parity (each constrained edge crossed flips in/out). The
// winding number is used instead, counting each polygon edge with its direction: it gives the same answer for
// simple polygons, and also the right one for a polygon with a hole joined by a doubled bridge edge (a
// "keyhole"), where parity would call the whole polygon outside the bridge.
#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>
#include <exception>
#include <new>
#include <unordered_map>
#include <utility>

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Spatial_sort_traits_adapter_2.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <CGAL/property_map.h>
#include <CGAL/spatial_sort.h>

#include <Eigen/Geometry>

#include "io/polygon_triangulation_detail.h"

namespace sculpt::io::detail {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_2;
using VertexBase = CGAL::Triangulation_vertex_base_with_info_2<int, Kernel>;  // info: the first corner there
using FaceBaseWithInfo = CGAL::Triangulation_face_base_with_info_2<int, Kernel>;  // info: winding number
using FaceBase = CGAL::Constrained_triangulation_face_base_2<Kernel, FaceBaseWithInfo>;
using DataStructure = CGAL::Triangulation_data_structure_2<VertexBase, FaceBase>;
// note: constraints may meet at corners and overlap along collinear edges (no new points needed); edges
// that cross would need a new vertex, which a face of a mesh cannot get: CGAL throws and the polygon fails.
using Triangulation = CGAL::Constrained_Delaunay_triangulation_2<
    Kernel, DataStructure, CGAL::No_constraint_intersection_requiring_constructions_tag>;
using VertexHandle = Triangulation::Vertex_handle;
using FaceHandle = Triangulation::Face_handle;

constexpr int kUnvisited = INT_MIN;

std::uint64_t edgeKey(int from, int to) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(from)) << 32) | static_cast<std::uint32_t>(to);
}

// The triangulation's vertex after `from` on the straight way to `to`: `to` itself when they share an edge,
// else the neighbour on the segment between them (a corner lying on the polygon edge split it there).
VertexHandle nextAlong(const Triangulation& triangulation, VertexHandle from, VertexHandle to) {
    const Kernel kernel;
    Triangulation::Vertex_circulator neighbour = triangulation.incident_vertices(from), done = neighbour;
    VertexHandle between;
    do {
        if (triangulation.is_infinite(neighbour)) continue;
        if (neighbour == to) return to;
        const Point& p = from->point();
        const Point& q = neighbour->point();
        const Point& r = to->point();
        if (between == VertexHandle() && kernel.orientation_2_object()(p, q, r) == CGAL::COLLINEAR &&
            kernel.collinear_are_ordered_along_line_2_object()(p, q, r))
            between = neighbour;
    } while (++neighbour != done);
    return between;
}

Status triangulate(const UnitCorners& unit, const Eigen::Vector3d& normal, std::vector<CornerTriangle>& triangles) {
    const int n = static_cast<int>(unit.size());
    // An orthonormal (u, v) in the plane with u x v = normal, so counter-clockwise in (u, v) is
    // counter-clockwise about the normal.
    const Eigen::Vector3d axis = normal.normalized();
    Eigen::Index least = 0;
    axis.cwiseAbs().minCoeff(&least);
    const Eigen::Vector3d u = axis.cross(Eigen::Vector3d::Unit(least)).normalized();
    const Eigen::Vector3d v = axis.cross(u);
    std::vector<Point> points;
    points.reserve(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i) {
        const Eigen::Vector3d q = unit[i];
        const double x = q.dot(u), y = q.dot(v);
        if (!std::isfinite(x) || !std::isfinite(y)) return Status::error("the polygon has a non-finite corner");
        points.emplace_back(x, y);
    }

    // Corners inserted in spatial order (as CGAL's own range insertion does) with the previous vertex's face
    // as the hint: O(N log N) expected instead of a walk from far away for every point.
    std::vector<std::size_t> order(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i) order[static_cast<size_t>(i)] = static_cast<std::size_t>(i);
    using PointMap = CGAL::Pointer_property_map<Point>::type;
    CGAL::spatial_sort(order.begin(), order.end(),
                       CGAL::Spatial_sort_traits_adapter_2<Kernel, PointMap>(CGAL::make_property_map(points)));
    Triangulation triangulation;
    std::vector<VertexHandle> vertexOf(static_cast<size_t>(n));
    FaceHandle hint;
    for (std::size_t i : order) {
        const auto before = triangulation.number_of_vertices();
        const VertexHandle vertex = triangulation.insert(points[i], hint);
        if (triangulation.number_of_vertices() != before) vertex->info() = static_cast<int>(i);
        vertexOf[i] = vertex;
        hint = vertex->face();
    }
    if (triangulation.dimension() < 2) return Status::error("the polygon has zero area (its corners are on one line)");

    for (int i = 0; i < n; ++i) {
        const VertexHandle a = vertexOf[static_cast<size_t>(i)], b = vertexOf[static_cast<size_t>((i + 1) % n)];
        if (a != b) triangulation.insert_constraint(a, b);  // a repeated corner adds no edge
    }

    // How many polygon edges run along each triangulation edge, by direction (key: from, to vertex infos).
    std::unordered_map<std::uint64_t, int> edgeCount;
    edgeCount.reserve(static_cast<size_t>(2 * n));
    const int maxSteps = static_cast<int>(triangulation.number_of_vertices());
    for (int i = 0; i < n; ++i) {
        const VertexHandle a = vertexOf[static_cast<size_t>(i)], b = vertexOf[static_cast<size_t>((i + 1) % n)];
        VertexHandle at = a;
        for (int step = 0; at != b; ++step) {
            const VertexHandle next = nextAlong(triangulation, at, b);
            if (next == VertexHandle() || step > maxSteps)
                return Status::error("internal error: a polygon edge is missing from its triangulation");
            ++edgeCount[edgeKey(at->info(), next->info())];
            at = next;
        }
    }
    const auto count = [&](VertexHandle from, VertexHandle to) {
        if (triangulation.is_infinite(from) || triangulation.is_infinite(to)) return 0;
        const auto found = edgeCount.find(edgeKey(from->info(), to->info()));
        return found == edgeCount.end() ? 0 : found->second;
    };

    // Winding numbers: 0 outside (the infinite faces); crossing an edge s -> t from its left side to its
    // right side lowers the winding number by the edges running s -> t and raises it by those running t -> s.
    for (auto face = triangulation.all_faces_begin(); face != triangulation.all_faces_end(); ++face)
        face->info() = kUnvisited;
    std::vector<FaceHandle> stack{triangulation.infinite_face()};
    triangulation.infinite_face()->info() = 0;
    while (!stack.empty()) {
        const FaceHandle face = stack.back();
        stack.pop_back();
        for (int i = 0; i < 3; ++i) {
            const VertexHandle s = face->vertex(Triangulation::ccw(i)), t = face->vertex(Triangulation::cw(i));
            const int winding = face->info() - count(s, t) + count(t, s);
            const FaceHandle neighbour = face->neighbor(i);
            if (neighbour->info() == kUnvisited) {
                neighbour->info() = winding;
                stack.push_back(neighbour);
            } else if (neighbour->info() != winding) {
                return Status::error("internal error: inconsistent winding numbers in a polygon triangulation");
            }
        }
    }

    std::vector<CornerTriangle> inside;
    for (auto face = triangulation.finite_faces_begin(); face != triangulation.finite_faces_end(); ++face) {
        const int winding = face->info();
        if (winding == 0) continue;
        if (winding != 1)
            return Status::error(winding < 0 ? "parts of the polygon wind the other way"
                                             : "parts of the polygon overlap");
        inside.push_back({face->vertex(0)->info(), face->vertex(1)->info(), face->vertex(2)->info()});
    }
    if (inside.empty()) return Status::error("the polygon has zero area");
    triangles.swap(inside);
    return Status::success();
}

}  // namespace

Status triangulateUnitPolygonCdt(const UnitCorners& unit, const Eigen::Vector3d& normal,
                                 std::vector<CornerTriangle>& triangles) {
    triangles.clear();
    try {
        return triangulate(unit, normal, triangles);
    } catch (const Triangulation::Intersection_of_constraints_exception&) {
        return Status::error("the polygon crosses itself");
    } catch (const std::bad_alloc&) {
        throw;
    } catch (const std::exception& e) {
        // CGAL's failed preconditions (never expected here) and anything else: a failed polygon, not a crash.
        return Status::error(std::string("the polygon could not be triangulated (") + e.what() + ")");
    }
}

}  // namespace sculpt::io::detail
