// Polygon triangulation checked against independent computations: the polygons are made in 2D (where their
// shoelace area and orientation are known exactly), then rotated into 3D and bent slightly out of their plane.
// A triangulation is right when (1) every triangle faces along the known polygon normal, (2) the triangle
// areas, projected onto the known plane, add up to the shoelace area, and (3) every polygon edge is an edge
// of exactly one triangle, running the same way, and every other triangle edge is shared by exactly two
// triangles running opposite ways (so the triangles form one disc bounded by the polygon, not overlapping).
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>
#include <catch2/catch.hpp>

#include "io/polygon_triangulation.h"

using sculpt::Positions;
using sculpt::Status;
using sculpt::io::CornerTriangle;

namespace {

constexpr double kPi = 3.14159265358979323846;

// A polygon made in the xy plane, then placed in 3D: point = rotation * (x, y, bend) + offset.
struct TestPolygon {
    std::vector<Eigen::Vector2d> flat;  // corners in the plane, in order
    double shoelaceArea = 0.0;          // signed: > 0 counter-clockwise (of flat)
    double scale = 1.0;                 // of the placed polygon: its area is shoelaceArea * scale^2
    Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
    Positions corners;                  // N x 3
    Eigen::Vector3d normal() const {    // of the polygon's winding, unit
        return rotation.col(2) * (shoelaceArea > 0.0 ? 1.0 : -1.0);
    }
};

double shoelace(const std::vector<Eigen::Vector2d>& flat) {
    double twice = 0.0;
    for (size_t i = 0; i < flat.size(); ++i) {
        const Eigen::Vector2d& a = flat[i];
        const Eigen::Vector2d& b = flat[(i + 1) % flat.size()];
        twice += a.x() * b.y() - a.y() * b.x();
    }
    return 0.5 * twice;
}

Eigen::Matrix3d randomRotation(std::mt19937_64& random) {
    std::normal_distribution<double> gauss;
    Eigen::Quaterniond q(gauss(random), gauss(random), gauss(random), gauss(random));
    return q.normalized().toRotationMatrix();
}

// bend: out-of-plane offset of each corner, as a fraction of the polygon's size (0 = planar).
TestPolygon place(std::vector<Eigen::Vector2d> flat, std::mt19937_64& random, double bend, double scale = 1.0,
                  Eigen::Vector3d offset = Eigen::Vector3d::Zero()) {
    TestPolygon polygon;
    polygon.flat = std::move(flat);
    polygon.shoelaceArea = shoelace(polygon.flat);
    polygon.scale = scale;
    polygon.rotation = randomRotation(random);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    polygon.corners.resize(static_cast<Eigen::Index>(polygon.flat.size()), 3);
    for (size_t i = 0; i < polygon.flat.size(); ++i) {
        const Eigen::Vector3d local(polygon.flat[i].x(), polygon.flat[i].y(), bend * unit(random));
        polygon.corners.row(static_cast<Eigen::Index>(i)) = (scale * (polygon.rotation * local) + offset).transpose();
    }
    return polygon;
}

// Star-shaped about the origin: strictly increasing angles, radii in [minRadius, 1] (1 = convex, on a circle).
std::vector<Eigen::Vector2d> starPolygon(std::mt19937_64& random, int n, double minRadius, bool clockwise) {
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<double> angles(static_cast<size_t>(n));
    // Jittered but strictly increasing: corner i in its own sector.
    for (int i = 0; i < n; ++i) angles[static_cast<size_t>(i)] = 2.0 * kPi * (i + 0.1 + 0.8 * unit(random)) / n;
    std::vector<Eigen::Vector2d> flat;
    for (int i = 0; i < n; ++i) {
        const double r = minRadius + (1.0 - minRadius) * unit(random);
        const double a = angles[static_cast<size_t>(i)];
        flat.emplace_back(r * std::cos(a), r * std::sin(a));
    }
    if (clockwise) std::reverse(flat.begin(), flat.end());
    return flat;
}

// A comb: `teeth` rectangular teeth on a base, deeply concave and not star-shaped.
std::vector<Eigen::Vector2d> combPolygon(int teeth) {
    std::vector<Eigen::Vector2d> flat{{0.0, 0.0}, {2.0 * teeth - 1.0, 0.0}};
    for (int t = teeth - 1; t >= 0; --t) {
        const double x = 2.0 * t;
        flat.emplace_back(x + 1.0, 1.0);
        flat.emplace_back(x + 1.0, 5.0);
        flat.emplace_back(x, 5.0);
        flat.emplace_back(x, 1.0);
    }
    flat.pop_back();  // the last tooth's inner corner would sit on the base edge's end: (0, 1) -> (0, 0)
    return flat;
}

// A square spiral strip of width 1 around a centre line turning left `segments` times (arms 2 apart), the
// walls mitred at the corners: neither convex nor star-shaped.
std::vector<Eigen::Vector2d> spiralPolygon(int segments) {
    const Eigen::Vector2d directions[4] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
    std::vector<Eigen::Vector2d> centre{{0, 0}};
    for (int k = 0; k < segments; ++k) centre.push_back(centre.back() + directions[k % 4] * (2.0 * (k / 2 + 1)));
    const auto left = [&](int k) {  // unit left normal of segment k
        const Eigen::Vector2d d = directions[k % 4];
        return Eigen::Vector2d(-d.y(), d.x());
    };
    std::vector<Eigen::Vector2d> inner, outer;
    for (int i = 0; i <= segments; ++i) {
        const Eigen::Vector2d offset = 0.5 * (left(std::max(i - 1, 0)) + left(std::min(i, segments - 1)));
        const Eigen::Vector2d miter = (i == 0 || i == segments) ? Eigen::Vector2d(0.5 * left(std::min(i, segments - 1)))
                                                                : offset;
        inner.push_back(centre[static_cast<size_t>(i)] + miter);
        outer.push_back(centre[static_cast<size_t>(i)] - miter);
    }
    std::vector<Eigen::Vector2d> flat = inner;
    flat.insert(flat.end(), outer.rbegin(), outer.rend());
    return flat;
}

double projectedArea(const Positions& corners, const CornerTriangle& t, const Eigen::Vector3d& normal) {
    const Eigen::Vector3d a = corners.row(t[0]).transpose(), b = corners.row(t[1]).transpose(),
                          c = corners.row(t[2]).transpose();
    return 0.5 * (b - a).cross(c - a).dot(normal);
}

// The three properties of the file comment; expectedCount < 0: do not check the triangle count.
void requireExactCover(const TestPolygon& polygon, const std::vector<CornerTriangle>& triangles,
                       int expectedCount) {
    const int n = static_cast<int>(polygon.corners.rows());
    if (expectedCount >= 0) REQUIRE(static_cast<int>(triangles.size()) == expectedCount);
    const Eigen::Vector3d normal = polygon.normal();
    const double area = std::abs(polygon.shoelaceArea) * polygon.scale * polygon.scale;
    double sum = 0.0;
    std::map<std::pair<int, int>, int> directed;
    for (const CornerTriangle& t : triangles) {
        for (int k = 0; k < 3; ++k) {
            REQUIRE(t[k] >= 0);
            REQUIRE(t[k] < n);
            ++directed[{t[k], t[(k + 1) % 3]}];
        }
        const double a = projectedArea(polygon.corners, t, normal);
        INFO("triangle " << t[0] << " " << t[1] << " " << t[2] << " area " << a);
        REQUIRE(a > 0.0);  // faces along the polygon normal, never flipped or degenerate
        sum += a;
    }
    REQUIRE(std::abs(sum - area) <= 1e-9 * area);
    for (int i = 0; i < n; ++i) {
        // The polygon's own edges in the direction of its winding (reversed list for a clockwise one is the
        // same polygon: the triangles run counter-clockwise about its normal either way).
        const int from = i, to = (i + 1) % n;
        const auto along = directed.find({from, to});
        REQUIRE(along != directed.end());
        REQUIRE(along->second == 1);
        REQUIRE(directed.count({to, from}) == 0);
        directed.erase(along);
    }
    for (const auto& [edge, count] : directed) {
        INFO("inner edge " << edge.first << " -> " << edge.second);
        REQUIRE(count == 1);
        const auto opposite = directed.find({edge.second, edge.first});
        REQUIRE(opposite != directed.end());
        REQUIRE(opposite->second == 1);
    }
}

std::vector<CornerTriangle> triangulate(const Positions& corners) {
    std::vector<CornerTriangle> triangles;
    const Status status = sculpt::io::triangulatePolygon(corners, triangles);
    INFO(status.message);
    REQUIRE(status.ok);
    return triangles;
}

std::vector<CornerTriangle> triangulateCdt(const Positions& corners) {
    std::vector<CornerTriangle> triangles;
    const Status status = sculpt::io::triangulatePolygonCdt(corners, sculpt::io::polygonNormal(corners), triangles);
    INFO(status.message);
    REQUIRE(status.ok);
    return triangles;
}

}  // namespace

TEST_CASE("polygon: random star-shaped polygons, convex and concave, planar and bent, are covered exactly") {
    int tested = 0;
    for (int n : {3, 4, 5, 6, 8, 13, 31, 100, 1000}) {
        for (int seed = 0; seed < 12; ++seed) {
            std::mt19937_64 random(1000 * n + seed);
            const bool convex = seed % 3 == 0;
            const bool clockwise = seed % 2 == 1;
            const double bend = seed % 4 == 2 ? 1e-3 : (seed % 4 == 3 ? 1e-6 : 0.0);
            const double minRadius = convex ? 1.0 : (seed % 3 == 1 ? 0.5 : 0.05);
            const TestPolygon polygon = place(starPolygon(random, n, minRadius, clockwise), random, bend);
            INFO("n " << n << " seed " << seed << (convex ? " convex" : " concave") << (clockwise ? " cw" : " ccw")
                      << " bend " << bend);
            // Newell's normal agrees with the known one (bent polygons: up to the bend).
            const Eigen::Vector3d newell = sculpt::io::polygonNormal(polygon.corners).normalized();
            REQUIRE(newell.dot(polygon.normal()) > 1.0 - 1e-3);
            requireExactCover(polygon, triangulate(polygon.corners), n - 2);
            requireExactCover(polygon, triangulateCdt(polygon.corners), n - 2);
            ++tested;
        }
    }
    REQUIRE(tested == 9 * 12);
}

TEST_CASE("polygon: a convex polygon keeps the fan from its first corner") {
    std::mt19937_64 random(7);
    for (int n : {4, 5, 9, 64}) {
        const TestPolygon polygon = place(starPolygon(random, n, 1.0, false), random, 0.0);
        const std::vector<CornerTriangle> triangles = triangulate(polygon.corners);
        REQUIRE(static_cast<int>(triangles.size()) == n - 2);
        for (int i = 0; i < n - 2; ++i) REQUIRE(triangles[static_cast<size_t>(i)] == CornerTriangle{0, i + 1, i + 2});
    }
}

TEST_CASE("polygon: the concave U of the handed-over case covers area 7, not 9") {
    // The U of shared/cases/concave-polygon: 3 x 3 with a 1 x 2 notch open at the top.
    const std::vector<Eigen::Vector2d> u{{0, 0}, {3, 0}, {3, 3}, {2, 3}, {2, 1}, {1, 1}, {1, 3}, {0, 3}};
    Positions corners(8, 3);
    for (int i = 0; i < 8; ++i) corners.row(i) << u[static_cast<size_t>(i)].x(), u[static_cast<size_t>(i)].y(), 0.0;
    TestPolygon polygon;
    polygon.flat = u;
    polygon.shoelaceArea = shoelace(u);
    polygon.corners = corners;
    REQUIRE(polygon.shoelaceArea == 7.0);
    const std::vector<CornerTriangle> triangles = triangulate(corners);
    requireExactCover(polygon, triangles, 6);
    // The fan from corner 0 would have used the diagonals 0-2 and 0-3, which cross the notch.
    for (const CornerTriangle& t : triangles)
        for (int k = 0; k < 3; ++k) {
            const int a = std::min(t[k], t[(k + 1) % 3]), b = std::max(t[k], t[(k + 1) % 3]);
            REQUIRE_FALSE((a == 0 && (b == 2 || b == 3)));
        }
}

TEST_CASE("polygon: combs, spirals, collinear corners and a keyhole") {
    std::mt19937_64 random(42);
    SECTION("comb") {
        for (int teeth : {2, 5, 40}) {
            const std::vector<Eigen::Vector2d> flat = combPolygon(teeth);
            const TestPolygon polygon = place(flat, random, 1e-4, 3.0, {5, -2, 1});
            requireExactCover(polygon, triangulate(polygon.corners), static_cast<int>(flat.size()) - 2);
        }
    }
    SECTION("spiral") {
        for (int segments : {3, 6, 17}) {
            const std::vector<Eigen::Vector2d> flat = spiralPolygon(segments);
            const TestPolygon polygon = place(flat, random, 0.0);
            requireExactCover(polygon, triangulate(polygon.corners), static_cast<int>(flat.size()) - 2);
        }
    }
    SECTION("collinear corners along the edges give no degenerate triangle") {
        // A square with 3 extra corners on every side, and the same turned into an L.
        std::vector<Eigen::Vector2d> square;
        const Eigen::Vector2d corner[4] = {{0, 0}, {4, 0}, {4, 4}, {0, 4}};
        for (int side = 0; side < 4; ++side)
            for (int k = 0; k < 4; ++k)
                square.push_back(corner[side] + (corner[(side + 1) % 4] - corner[side]) * (k / 4.0));
        const TestPolygon polygon = place(square, random, 0.0);
        requireExactCover(polygon, triangulate(polygon.corners), 14);
        const std::vector<Eigen::Vector2d> l{{0, 0}, {1, 0}, {2, 0}, {3, 0}, {3, 1}, {2, 1}, {1, 1}, {1, 2}, {1, 3}, {0, 3}, {0, 2}, {0, 1}};
        const TestPolygon lPolygon = place(l, random, 0.0);
        requireExactCover(lPolygon, triangulate(lPolygon.corners), 10);
    }
    SECTION("keyhole: a square with a square hole joined by a doubled bridge edge") {
        // Outer 0..3 counter-clockwise, bridge to the hole, hole clockwise, back over the bridge.
        const std::vector<Eigen::Vector2d> flat{{0, 0}, {6, 0}, {6, 6}, {0, 6}, {0, 0}, {2, 2}, {2, 4}, {4, 4}, {4, 2}, {2, 2}};
        const TestPolygon polygon = place(flat, random, 0.0);
        std::vector<CornerTriangle> triangles = triangulate(polygon.corners);
        double sum = 0.0;
        for (const CornerTriangle& t : triangles) {
            const double a = projectedArea(polygon.corners, t, polygon.normal());
            REQUIRE(a > 0.0);
            sum += a;
        }
        REQUIRE(sum == Approx(36.0 - 4.0).epsilon(1e-12));
    }
}

TEST_CASE("polygon: huge and tiny coordinates, far from the origin, and a huge polygon") {
    std::mt19937_64 random(3);
    for (double scale : {1e-300, 1e-9, 1.0, 1e9, 1e300}) {
        INFO("scale " << scale);
        const TestPolygon polygon = place(starPolygon(random, 40, 0.3, false), random, 1e-3, scale,
                                          Eigen::Vector3d(0.25, -0.5, 0.125) * scale);
        const std::vector<CornerTriangle> triangles = triangulate(polygon.corners);
        REQUIRE(triangles.size() == 38);
        for (const CornerTriangle& t : triangles) REQUIRE(projectedArea(polygon.corners / scale, t, polygon.normal()) > 0.0);
    }
    // Far from the origin relative to its size.
    const TestPolygon far = place(starPolygon(random, 30, 0.3, false), random, 0.0, 1.0, {1e6, 2e6, -3e6});
    TestPolygon centred = far;
    centred.corners.rowwise() -= Eigen::RowVector3d(1e6, 2e6, -3e6);
    const std::vector<CornerTriangle> farTriangles = triangulate(far.corners);
    REQUIRE(farTriangles.size() == 28);
    for (const CornerTriangle& t : farTriangles) REQUIRE(projectedArea(centred.corners, t, far.normal()) > 0.0);

    // 100 000 corners, concave (about 0.4 s here: O(N log N)).
    const TestPolygon huge = place(starPolygon(random, 100000, 0.5, false), random, 0.0);
    requireExactCover(huge, triangulate(huge.corners), 100000 - 2);
}

TEST_CASE("polygon: degenerate and self-crossing polygons fail with a reason, never crash") {
    std::vector<CornerTriangle> triangles{{9, 9, 9}};
    const auto fails = [&](const std::vector<Eigen::Vector3d>& points, const std::string& fragment) {
        Positions corners(static_cast<Eigen::Index>(points.size()), 3);
        for (size_t i = 0; i < points.size(); ++i) corners.row(static_cast<Eigen::Index>(i)) = points[i].transpose();
        triangles = {{9, 9, 9}};
        const Status status = sculpt::io::triangulatePolygon(corners, triangles);
        INFO(status.message);
        REQUIRE_FALSE(status.ok);
        REQUIRE(status.message.find(fragment) != std::string::npos);
        REQUIRE(triangles.empty());
    };
    const double nan = std::nan("");
    const double inf = std::numeric_limits<double>::infinity();
    fails({{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {3, 3, 3}}, "zero area");             // collinear
    fails({{1, 2, 3}, {1, 2, 3}, {1, 2, 3}, {1, 2, 3}, {1, 2, 3}}, "zero area");  // one point
    fails({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}},
          "overlap");                                                           // winds twice
    fails({{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {1, -1, 0}, {0, 2, 0}}, "crosses itself");
    fails({{0, 0, 0}, {1, 0, 0}, {nan, 1, 0}, {0, 1, 0}}, "non-finite");
    fails({{0, 0, 0}, {1, 0, 0}, {1, inf, 0}, {0, 1, 0}}, "non-finite");
    fails({{0, 0, 0}, {1, 0, 0}}, "at least 3");
    // A bow tie: the two halves' areas cancel (zero area), or, made lopsided, it crosses itself.
    fails({{0, 0, 0}, {1, 1, 0}, {1, 0, 0}, {0, 1, 0}}, "zero area");
    fails({{0, 0, 0}, {2, 1, 0}, {2, 0, 0}, {0, 1, 0}, {-1, 0.5, 0}}, "crosses itself");
    // A pentagram turns left at every corner but winds twice.
    std::vector<Eigen::Vector3d> star;
    for (int i = 0; i < 5; ++i) star.emplace_back(std::cos(4.0 * kPi * i / 5), std::sin(4.0 * kPi * i / 5), 0.0);
    fails(star, "crosses itself");
    // A triangle is itself, even a degenerate one.
    Positions flat(3, 3);
    flat << 0, 0, 0, 1, 1, 1, 2, 2, 2;
    REQUIRE(sculpt::io::triangulatePolygon(flat, triangles).ok);
    REQUIRE(triangles == std::vector<CornerTriangle>{{0, 1, 2}});
}
