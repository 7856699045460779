// Sculpted detail travels with the surface (issue "Sculpting as a sculptor expects", point 1), and the brush
// reaches as far as it is pulled with the falloff's shape (points 2-3), on real meshes from CGAL's data and on
// spheres. Each property failed before the stroke's layer was baked into the rest shape and the region
// followed the pull.
#include <catch2/catch.hpp>

#include <random>
#include <sstream>

#include <Eigen/Geometry>

#include "../cgal_meshes.h"
#include "core/deform/brush_field.h"
#include "core/session/session.h"
#include "core/deform/vertex_normals.h"
#include "../mesh_fixtures.h"
#include "../test_support.h"
#include "../../test_scale.h"

using namespace sculpt;
using namespace sculpt::core;

namespace {

struct Mesh {
    std::string name;
    Positions positions;
    Triangles triangles;
    Positions normals;
    double diagonal = 0.0;
};

Mesh realMesh(const std::string& name) {
    Mesh m;
    m.name = name;
    std::string error;
    if (!test::loadCgalMesh(name, m.positions, m.triangles, error)) FAIL(error);
    computeVertexNormals(m.positions, m.triangles, m.normals);
    m.diagonal = (m.positions.colwise().maxCoeff() - m.positions.colwise().minCoeff()).norm();
    return m;
}

Mesh sphere() {
    Mesh m;
    m.name = "icosphere";
    test::icosphere(3, 1.0, Eigen::Vector3d(0.2, -0.1, 0.3), m.positions, m.triangles);
    computeVertexNormals(m.positions, m.triangles, m.normals);
    m.diagonal = (m.positions.colwise().maxCoeff() - m.positions.colwise().minCoeff()).norm();
    return m;
}

// The plain falloff shape of a symmetric stroke at its target (each vertex moved by the falloff of its rest distance
// from the grabbed point and from its mirror image, along the mirrored pull, nothing else): true when it crosses
// nothing the mesh did not cross at load (the stroke asks nothing the falloff alone cannot carry).
bool mirroredFalloffShapeClear(const Mesh& mesh, const Eigen::Vector3d& centre, const Eigen::Vector3d& source, const Eigen::Vector3d& target,
                               const BrushSettings& brush, const std::vector<std::pair<int, int>>& atLoad) {
    Positions shape = mesh.positions;
    for (int mask = 0; mask <= 1; ++mask) {
        const Eigen::Vector3d grab = reflectPoint(source, mask, SymmetryFrame{centre}), move = reflectPoint(target, mask, SymmetryFrame{centre}) - grab;
        for (Eigen::Index r = 0; r < shape.rows(); ++r) {
            const double rho = (mesh.positions.row(r).transpose() - grab).norm();
            if (rho < brush.radius) shape.row(r) += brushProfile(brush.falloff, rho / brush.radius) * move.transpose();
        }
    }
    return test::intersectingPairs(shape, mesh.triangles) == atLoad;
}

// A scripted stroke of vertex v to `target` on a fresh session: it applies (in full or stopped short), the grabbed
// point lands on the share it reached, no triangle crosses that did not at load, and undo is exact. True when in full.
bool strokeLandsUncrossed(const Mesh& mesh, int v, const Eigen::Vector3d& target, const BrushSettings& brush, const std::vector<std::pair<int, int>>& atLoad,
                          InjectivityMode mode = InjectivityMode::Conic) {
    const Eigen::Vector3d source = mesh.positions.row(v).transpose();
    Session session;
    REQUIRE(session.setMesh(mesh.positions, mesh.triangles).ok);
    session.setInjectivity({mode, 6});
    OpReport report;
    REQUIRE(session.dragVertex(v, target, report, brush).ok);
    INFO("vertex " << v << ", pull " << (target - source).norm() / brush.radius << " r, radius " << brush.radius / mesh.diagonal << ": " << report.reason);
    REQUIRE(report.status == OpStatus::Applied);
    const Eigen::Vector3d reached = source + report.fractionApplied * (target - source);
    CHECK((session.mesh().positions.row(v).transpose() - reached).norm() <= 1e-9 * mesh.diagonal);
    CHECK(test::intersectingPairs(session.mesh().positions, session.mesh().triangles) == atLoad);
    const bool full = report.fractionApplied == 1.0;  // (undo's report replaces the stroke's)
    OpReport undone;
    REQUIRE(session.undo(undone).ok);
    CHECK((session.mesh().positions - mesh.positions).cwiseAbs().maxCoeff() <= 1e-12 * mesh.diagonal);
    return full;
}

// After a pull of `pull` world units along the unit `direction` that reached `reached` from `source`: CHECKs that
// nothing farther than 1.25 radius from the path moved, and returns the profile: the RMS over the vertices within
// the radius of (displacement along the pull / the pull) - f(rho / r), rho the rest distance from the source
// (measure.py's measure; NaN with no vertex within the radius).
double pullProfile(const Mesh& mesh, const Positions& after, const Eigen::Vector3d& source, const Eigen::Vector3d& reached,
                   const Eigen::Vector3d& direction, double pull, const BrushSettings& brush) {
    double squares = 0.0;
    int within = 0;
    for (Eigen::Index r = 0; r < mesh.positions.rows(); ++r) {
        const Eigen::Vector3d rest = mesh.positions.row(r).transpose();
        const Eigen::Vector3d moved = after.row(r).transpose() - rest;
        if (segmentDistance(rest, source, reached) > kBrushReach * brush.radius) CHECK(moved.norm() == 0.0);
        const double rho = (rest - source).norm();
        if (rho >= brush.radius) continue;
        squares += std::pow(moved.dot(direction) / pull - brushProfile(brush.falloff, rho / brush.radius), 2);
        ++within;
    }
    return within > 0 ? std::sqrt(squares / within) : NAN;
}

std::vector<int> unpinned(const Lattice& lattice) {
    std::vector<int> ids;
    for (int idx = 0; idx < lattice.controlPointCount(); ++idx)
        if (!lattice.pinned[static_cast<size_t>(idx)]) ids.push_back(idx);
    return ids;
}

}  // namespace

TEST_CASE("brush detail: after a stroke, moving the whole cage rigidly moves the sculpted mesh rigidly, and undo and redo are exact", "[core][brush]") {
    // The default cage (padding 0.05): the longer pulls carry the spike out of the cage's box, where the cage's
    // collar carries it (embedding.h, embedCollar). Before the collar, those vertices stayed where they were and
    // the spike tore off the moved mesh. Translations and turns about a random axis, as a user moves a cage.
    std::mt19937 rng(5);
    int outsideTrials = 0;
    for (const Mesh& mesh : {sphere(), realMesh("elephant.off"), realMesh("camel.off")}) {
        for (int trial = 0; trial < 4; ++trial) {
            INFO(mesh.name << " trial " << trial);
            Session session;
            REQUIRE(session.setMesh(mesh.positions, mesh.triangles).ok);
            const Positions original = session.mesh().positions;
            BrushSettings brush;
            brush.radius = (0.05 + 0.03 * (trial % 3)) * mesh.diagonal;
            brush.falloff = static_cast<BrushFalloff>(trial % 3);
            const int v = test::randomInt(rng, 0, static_cast<int>(mesh.positions.rows()) - 1);
            const Eigen::Vector3d target = mesh.positions.row(v).transpose() + (0.4 + trial) * brush.radius * mesh.normals.row(v).transpose();
            OpReport report;
            REQUIRE(session.dragVertex(v, target, report, brush).ok);
            REQUIRE(report.status == OpStatus::Applied);
            const Positions sculpted = session.mesh().positions;
            const double spike = (sculpted.row(v) - original.row(v)).norm();
            CHECK(spike > 0.3 * brush.radius);
            CHECK(session.cage().layers().empty());  // the stroke is part of the rest shape now
            const Lattice& cage = session.lattice();
            bool outside = false;
            for (Eigen::Index r = 0; r < sculpted.rows(); ++r)
                outside = outside || (session.mesh().rest.row(r).transpose().array() > cage.boxMax.array()).any() ||
                          (session.mesh().rest.row(r).transpose().array() < cage.boxMin.array()).any();
            outsideTrials += outside;
            // Every free control point by one rigid motion x -> R (x - c) + c + by.
            const std::vector<int> ids = unpinned(cage);
            const Eigen::Vector3d by = 0.07 * mesh.diagonal * test::randomVector(rng, -1.0, 1.0).normalized();
            const Eigen::Vector3d axis = test::randomVector(rng, -1.0, 1.0).normalized();
            const Eigen::Matrix3d turn = Eigen::AngleAxisd(trial % 2 == 0 ? 0.0 : 0.35, axis).toRotationMatrix();
            const Eigen::Vector3d c = 0.5 * (cage.boxMin + cage.boxMax);
            const Positions points = controlPointPositions(cage);
            Positions displacement(static_cast<Eigen::Index>(ids.size()), 3);
            for (size_t k = 0; k < ids.size(); ++k) {
                const Eigen::Vector3d q = points.row(ids[k]).transpose();
                displacement.row(static_cast<Eigen::Index>(k)) = (turn * (q - c) + c + by - q).transpose();
            }
            REQUIRE(session.moveControlPoints(ids, displacement, true, report).ok);
            REQUIRE(report.status == OpStatus::Applied);
            REQUIRE(report.fractionApplied == 1.0);
            const Positions moved = session.mesh().positions;
            double worst = 0.0;
            for (Eigen::Index r = 0; r < moved.rows(); ++r) {
                const Eigen::Vector3d expected = turn * (sculpted.row(r).transpose() - c) + c + by;
                worst = std::max(worst, (moved.row(r).transpose() - expected).norm());
            }
            CHECK(worst <= 1e-9 * mesh.diagonal);
            CHECK((moved.row(v) - (turn * (original.row(v).transpose() - c) + c + by).transpose()).norm() >= spike - 1e-9 * mesh.diagonal);  // the spike kept its height
            // Undo both: the original to 1e-12 x diagonal; redo both: where they were.
            REQUIRE(session.undo(report).ok);
            REQUIRE(session.undo(report).ok);
            CHECK(report.verticesMoved <= mesh.positions.rows());
            CHECK((session.mesh().positions - original).cwiseAbs().maxCoeff() <= 1e-12 * mesh.diagonal);
            REQUIRE(session.redo(report).ok);
            CHECK((session.mesh().positions - sculpted).cwiseAbs().maxCoeff() <= 1e-12 * mesh.diagonal);
            REQUIRE(session.redo(report).ok);
            CHECK((session.mesh().positions - moved).cwiseAbs().maxCoeff() <= 1e-12 * mesh.diagonal);
        }
    }
    CHECK(outsideTrials >= 4);  // the collar is what carried those spikes
}

TEST_CASE("brush detail: a drag that bends the part carrying a spike carries the spike, its offset from the surface turned with it", "[core][brush]") {
    // Measured: the spike's offset d = x_sculpted - x_plain at the grabbed vertex, the same cage drag applied to
    // the sculpted and to the plain mesh. The cage maps the rest offset by its Jacobian J (to first order), so
    // d_after should be J d_before; we ask its length kept within 25% and its direction within 30 degrees of J d.
    std::mt19937 rng(9);
    for (const Mesh& mesh : {sphere(), realMesh("elephant.off")}) {
        for (int trial = 0; trial < 4; ++trial) {
            INFO(mesh.name << " trial " << trial);
            Session sculpt, plain;
            REQUIRE(sculpt.setMesh(mesh.positions, mesh.triangles).ok);
            REQUIRE(plain.setMesh(mesh.positions, mesh.triangles).ok);
            BrushSettings brush;
            brush.radius = 0.06 * mesh.diagonal;
            const int v = test::randomInt(rng, 0, static_cast<int>(mesh.positions.rows()) - 1);
            const Eigen::Vector3d start = mesh.positions.row(v).transpose();
            OpReport report;
            REQUIRE(sculpt.dragVertex(v, start + 0.5 * brush.radius * mesh.normals.row(v).transpose(), report, brush).ok);
            REQUIRE(report.status == OpStatus::Applied);
            const Eigen::Vector3d before = sculpt.mesh().positions.row(v).transpose() - start;
            // A cage drag of a point near the spike (but outside the brush's reach) moves that part of the mesh.
            int handle = -1;
            for (int attempt = 0; attempt < 10000 && handle < 0; ++attempt) {
                const int h = test::randomInt(rng, 0, static_cast<int>(mesh.positions.rows()) - 1);
                const double d = (mesh.positions.row(h).transpose() - start).norm();
                if (d > 1.5 * brush.radius && d < 0.25 * mesh.diagonal) handle = h;
            }
            REQUIRE(handle >= 0);
            const Eigen::Vector3d to = mesh.positions.row(handle).transpose() + 0.05 * mesh.diagonal * test::randomVector(rng, -1.0, 1.0).normalized();
            OpReport a, b;
            REQUIRE(plain.dragVertex(handle, to, a).ok);
            REQUIRE(sculpt.dragVertex(handle, to, b).ok);
            if (a.status != OpStatus::Applied || b.status != OpStatus::Applied) continue;
            const Eigen::Vector3d after = sculpt.mesh().positions.row(v).transpose() - plain.mesh().positions.row(v).transpose();
            // J at the grabbed point's rest, by central differences of the plain session's cage.
            const Lattice& cage = plain.lattice();
            Eigen::Vector3d t;
            REQUIRE(restParameters(cage, start, t));
            Eigen::Vector3d displacement;
            Eigen::Matrix3d jacobian;
            deformationJacobian(cage, t, displacement, jacobian);
            const Eigen::Vector3d expected = jacobian * before;
            CHECK(std::abs(after.norm() - expected.norm()) <= 0.25 * expected.norm());
            CHECK(after.normalized().dot(expected.normalized()) >= std::cos(30.0 * 3.14159265358979 / 180.0));
        }
    }
}

TEST_CASE("brush reach: on real meshes, pulls of 0.5 to 3 radii along the normal and 1 along a tangent apply in full with the falloff's shape", "[core][brush]") {
    std::mt19937 rng(3);
    int full = 0, total = 0, profiled = 0, withinProfile = 0;
    for (const Mesh& mesh : {realMesh("elephant.off"), realMesh("camel.off"), sphere()}) {
        for (int pick = 0; pick < 3; ++pick) {
            const int v = test::randomInt(rng, 0, static_cast<int>(mesh.positions.rows()) - 1);
            const Eigen::Vector3d n = mesh.normals.row(v).transpose();
            for (double length : {0.5, 1.0, 2.0, 3.0, -1.0}) {
                Session session;
                REQUIRE(session.setMesh(mesh.positions, mesh.triangles).ok);
                BrushSettings brush;
                brush.radius = 0.1 * mesh.diagonal;
                const Eigen::Vector3d direction = length > 0 ? n : n.unitOrthogonal();
                const double pull = std::abs(length) * brush.radius;
                const Eigen::Vector3d source = mesh.positions.row(v).transpose(), target = source + pull * direction;
                OpReport report;
                REQUIRE(session.dragVertex(v, target, report, brush).ok);
                INFO(mesh.name << " vertex " << v << " pull " << length << ": " << report.reason);
                REQUIRE(report.status == OpStatus::Applied);
                ++total;
                const Eigen::Vector3d reached = source + report.fractionApplied * (target - source);
                CHECK((session.mesh().positions.row(v).transpose() - reached).norm() <= 1e-9 * mesh.diagonal);
                if (report.fractionApplied == 1.0) ++full;
                // Nothing beyond 1.25 radius of the path moved; the profile over the radius.
                const double profile = pullProfile(mesh, session.mesh().positions, source, reached, direction, report.fractionApplied * pull, brush);
                if (length > 0 && std::isfinite(profile) && report.fractionApplied == 1.0) {
                    ++profiled;
                    withinProfile += profile <= 0.08;
                }
            }
        }
    }
    INFO(full << " of " << total << " in full; profile within 0.08 in " << withinProfile << " of " << profiled);
    CHECK(full >= total * 85 / 100);
    CHECK(withinProfile >= profiled * 80 / 100);
}

TEST_CASE("brush reach: every falloff keeps its curve over the radius, for normal pulls of 0.1 to 3 radii on real meshes and a sphere", "[core][brush]") {
    // Medium's rim is steep (sqrt(1 - x^2) is 0.44 at 0.9 radius): at 8 knot spans a radius its field ended where the
    // free control points do (0.82-0.9 radius out) and its profile was 0.12 RMS from the curve on any surface.
    std::mt19937 rng(29);
    int full = 0, total = 0, withinProfile = 0;
    double worst = 0.0;
    std::ostringstream pulls;
    for (const Mesh& mesh : {realMesh("elephant.off"), realMesh("camel.off"), sphere()}) {
        for (int pick = 0; pick < 6; ++pick) {
            const int v = test::randomInt(rng, 0, static_cast<int>(mesh.positions.rows()) - 1);
            const Eigen::Vector3d n = mesh.normals.row(v).transpose(), source = mesh.positions.row(v).transpose();
            BrushSettings brush;
            brush.radius = std::uniform_real_distribution<double>(0.05, 0.12)(rng) * mesh.diagonal;
            brush.falloff = static_cast<BrushFalloff>(pick % 3);
            const double length = pick < 3 ? std::uniform_real_distribution<double>(0.1, 1.0)(rng) : std::uniform_real_distribution<double>(1.0, 3.0)(rng);
            const Eigen::Vector3d target = source + length * brush.radius * n;
            Session session;
            REQUIRE(session.setMesh(mesh.positions, mesh.triangles).ok);
            OpReport report;
            REQUIRE(session.dragVertex(v, target, report, brush).ok);
            INFO(mesh.name << " vertex " << v << " pull " << length << " r " << brushFalloffName(brush.falloff) << ": " << report.reason);
            REQUIRE(report.status == OpStatus::Applied);
            ++total;
            if (report.fractionApplied < 1.0) continue;
            ++full;
            CHECK((session.mesh().positions.row(v).transpose() - target).norm() <= 1e-9 * mesh.diagonal);
            const double profile = pullProfile(mesh, session.mesh().positions, source, target, n, length * brush.radius, brush);
            pulls << mesh.name << " vertex " << v << " " << length << " r " << brushFalloffName(brush.falloff) << ": profile " << profile << "\n";
            worst = std::max(worst, profile);
            withinProfile += profile <= 0.08;
        }
    }
    INFO(pulls.str() << full << " of " << total << " in full; profile within 0.08 in " << withinProfile << "; the largest " << worst);
    CHECK(full >= total - 1);
    CHECK(withinProfile == full);
}

TEST_CASE("brush reach: a long normal pull out of a hollow, with surface ahead of the grabbed point within the radius, keeps the falloff's shape", "[core][brush]") {
    // The walls of a hollow and an overhang (an elephant's ear over its shoulder) lie ahead of the grabbed point
    // within the radius: a field along the pull may fall by only 1 / |d| per unit ahead, so it carried them at up
    // to 15 times their falloff (profile 0.13-0.20 for pulls of 2-3 radii) before the space ahead was widened.
    std::mt19937 rng(11);
    int full = 0, total = 0, withinProfile = 0;
    double worst = 0.0;
    std::ostringstream pulls;
    for (const Mesh& mesh : {realMesh("elephant.off"), realMesh("camel.off"), realMesh("armadillo.off")}) {
        const double radius = 0.1 * mesh.diagonal;
        // Hollows: at least 8 vertices within the radius lie ahead of the grabbed point along its normal by more than
        // 0.4 r, off its line by more than 0.15 r; none lies on the line ahead (a sheet across the pull, which
        // the pull must push along, is another case: brush refinement's).
        std::vector<int> hollows;
        for (int tries = 0; tries < 4000 && hollows.size() < 40; ++tries) {
            const int v = test::randomInt(rng, 0, static_cast<int>(mesh.positions.rows()) - 1);
            const Eigen::Vector3d s = mesh.positions.row(v).transpose(), n = mesh.normals.row(v).transpose();
            int ahead = 0;
            bool onLine = false;
            for (Eigen::Index r = 0; r < mesh.positions.rows(); ++r) {
                const Eigen::Vector3d offset = mesh.positions.row(r).transpose() - s;
                const double z = offset.dot(n), lateral = (offset - z * n).norm();
                if (z > 0.1 * radius && z < 3.0 * radius && lateral < 0.15 * radius) onLine = true;
                if (offset.norm() < radius && z > 0.4 * radius && lateral > 0.15 * radius) ++ahead;
            }
            if (ahead >= 8 && !onLine) hollows.push_back(v);
        }
        INFO(mesh.name << ": " << hollows.size() << " hollows found");
        REQUIRE(hollows.size() >= 3);
        const std::vector<std::pair<int, int>> atLoad = test::intersectingPairs(mesh.positions, mesh.triangles);
        for (int pick = 0; pick < 3; ++pick) {
            const int v = hollows[static_cast<size_t>(test::randomInt(rng, 0, static_cast<int>(hollows.size()) - 1))];
            const Eigen::Vector3d n = mesh.normals.row(v).transpose(), source = mesh.positions.row(v).transpose();
            for (double length : {2.0, 3.0}) {
                BrushSettings brush;
                brush.radius = radius;
                brush.falloff = static_cast<BrushFalloff>((pick + static_cast<int>(length)) % 3);
                const Eigen::Vector3d target = source + length * radius * n;
                Session session;
                REQUIRE(session.setMesh(mesh.positions, mesh.triangles).ok);
                OpReport report;
                REQUIRE(session.dragVertex(v, target, report, brush).ok);
                INFO(mesh.name << " vertex " << v << " pull " << length << " r falloff " << static_cast<int>(brush.falloff) << ": " << report.reason);
                REQUIRE(report.status == OpStatus::Applied);
                ++total;
                const Eigen::Vector3d reached = source + report.fractionApplied * (target - source);
                CHECK((session.mesh().positions.row(v).transpose() - reached).norm() <= 1e-9 * mesh.diagonal);
                CHECK(test::intersectingPairs(session.mesh().positions, session.mesh().triangles) == atLoad);
                const double profile = pullProfile(mesh, session.mesh().positions, source, reached, n, report.fractionApplied * length * radius, brush);
                if (report.fractionApplied == 1.0) {
                    ++full;
                    worst = std::max(worst, profile);
                    withinProfile += profile <= 0.08;
                    pulls << mesh.name << " vertex " << v << " " << length << " r " << brushFalloffName(brush.falloff) << ": profile " << profile << "\n";
                }
                REQUIRE(session.undo(report).ok);
                CHECK((session.mesh().positions.topRows(mesh.positions.rows()) - mesh.positions).cwiseAbs().maxCoeff() <= 1e-12 * mesh.diagonal);
            }
        }
    }
    INFO(pulls.str() << full << " of " << total << " in full; profile within 0.08 in " << withinProfile << " of them; the largest " << worst);
    CHECK(full == total);
    CHECK(withinProfile == full);
}

// A vertex on a crease, where a triangle at it faces away from its normal: the surface's normal there (the
// triangles around the grabbed one), not the triangle the grabbed point was found on, decides whether a pull leaves
// the surface and its space ahead is widened. Before, measure.py's default picks on CGAL's femur (vertices 550 and
// 2331, in a hollow by the femur's head) read as pulls 109 degrees from the surface, and the hollow's wall was
// carried at 0.09-0.11 RMS from the falloff for pulls of 2 and 3 radii (6 of the 9 pulls applied in full above 0.08).
// Three of the twelve stop short, before and now (by the triangles: the hollow's wall ahead).
TEST_CASE("brush reach: a long normal pull from a crease in a hollow keeps the falloff's shape as any hollow's does", "[core][brush]") {
    const Mesh mesh = realMesh("femur.off");
    std::ostringstream pulls;
    int full = 0;
    for (int v : {550, 2331}) {
        const Eigen::Vector3d source = mesh.positions.row(v).transpose(), n = mesh.normals.row(v).transpose();
        for (int falloff = 0; falloff < 3; ++falloff)
            for (double length : {2.0, 3.0}) {
                BrushSettings brush;
                brush.radius = 0.1 * mesh.diagonal;
                brush.falloff = static_cast<BrushFalloff>(falloff);
                const Eigen::Vector3d target = source + length * brush.radius * n;
                Session session;
                REQUIRE(session.setMesh(mesh.positions, mesh.triangles).ok);
                OpReport report;
                REQUIRE(session.dragVertex(v, target, report, brush).ok);
                INFO("vertex " << v << " pull " << length << " r " << brushFalloffName(brush.falloff) << ": " << report.reason);
                REQUIRE(report.status == OpStatus::Applied);
                const Eigen::Vector3d reached = source + report.fractionApplied * (target - source);
                CHECK((session.mesh().positions.row(v).transpose() - reached).norm() <= 1e-9 * mesh.diagonal);
                CHECK(test::intersectingPairs(session.mesh().positions, session.mesh().triangles).empty());
                if (report.fractionApplied < 1.0) continue;
                ++full;
                const double profile = pullProfile(mesh, session.mesh().positions, source, target, n, length * brush.radius, brush);
                pulls << "vertex " << v << " " << length << " r " << brushFalloffName(brush.falloff) << ": profile " << profile << "\n";
                CHECK(profile <= 0.08);
            }
    }
    INFO(pulls.str());
    CHECK(full >= 9);
}

// A vertex of a coarse model grabbed and pulled along its own normal: the surface's normal at the grabbed point
// is its corners' vertex normals weighted by where it lies, so a grabbed vertex reads its own. Before, the
// triangles around all three corners of the triangle it was found on were summed, which on a coarse model's
// creases spans half the part: CGAL's anchor.off, vertex 261 (measure.py's default pick) pulled one radius read as
// 21 to 71 degrees off the surface, its space ahead was not widened, and the surface ahead was carried 0.12 to 0.25
// RMS off the falloff for pulls of 1 to 3 radii. Picked here: vertices of the anchor with surface ahead within the
// radius, where the triangles around some triangle at the vertex face more than 45 degrees from its normal, and
// the plain falloff shape at the target does not cross itself (elsewhere the pull must leave that shape): 16 at
// random after measure.py's default picks among them.
TEST_CASE("brush reach: a coarse model's vertex pulled along its own normal keeps the falloff's shape where that shape does not cross", "[core][brush]") {
    std::mt19937 rng(61);
    const Mesh mesh = realMesh("anchor.off");
    const double radius = 0.1 * mesh.diagonal;
    const std::vector<std::pair<int, int>> atLoad = test::intersectingPairs(mesh.positions, mesh.triangles);
    std::vector<std::vector<int>> trianglesAt(static_cast<size_t>(mesh.positions.rows()));
    for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t)
        for (int c = 0; c < 3; ++c) trianglesAt[static_cast<size_t>(mesh.triangles(t, c))].push_back(static_cast<int>(t));
    const auto faceNormal = [&](int t) {
        const auto x = [&](int c) { return Eigen::Vector3d(mesh.positions.row(mesh.triangles(t, c)).transpose()); };
        return Eigen::Vector3d((x(1) - x(0)).cross(x(2) - x(0)));
    };
    // The plain falloff shape of a pull (every vertex moved by f(rho / r) of it) crosses itself.
    const auto falloffShapeCrosses = [&](int v, double length) {
        const Eigen::Vector3d source = mesh.positions.row(v).transpose(), pull = length * radius * mesh.normals.row(v).transpose();
        Positions shape = mesh.positions;
        for (Eigen::Index r = 0; r < shape.rows(); ++r) {
            const double rho = (mesh.positions.row(r).transpose() - source).norm();
            if (rho < radius) shape.row(r) += brushProfile(BrushFalloff::Smooth, rho / radius) * pull.transpose();
        }
        return test::intersectingPairs(shape, mesh.triangles) != atLoad;
    };
    std::vector<int> creases;
    for (Eigen::Index v = 0; v < mesh.positions.rows(); ++v) {
        const Eigen::Vector3d s = mesh.positions.row(v).transpose(), n = mesh.normals.row(v).transpose();
        bool misread = false;
        for (int t : trianglesAt[static_cast<size_t>(v)]) {
            Eigen::Vector3d around = Eigen::Vector3d::Zero();
            std::vector<int> seen;
            for (int c = 0; c < 3; ++c)
                for (int u : trianglesAt[static_cast<size_t>(mesh.triangles(t, c))])
                    if (std::find(seen.begin(), seen.end(), u) == seen.end()) seen.push_back(u), around += faceNormal(u);
            misread = misread || around.normalized().dot(n) < std::sqrt(0.5);
        }
        int ahead = 0;  // (off the pull's line: on it, the pull must push the surface along)
        for (Eigen::Index r = 0; r < mesh.positions.rows(); ++r) {
            const Eigen::Vector3d offset = mesh.positions.row(r).transpose() - s;
            const double z = offset.dot(n);
            ahead += offset.norm() < radius && z > 0.4 * radius && (offset - z * n).norm() > 0.15 * radius;
        }
        if (misread && ahead >= 5) creases.push_back(static_cast<int>(v));
    }
    INFO(creases.size() << " crease vertices with surface ahead");
    REQUIRE(creases.size() >= 6);
    // 16 of them at random, after measure.py's default picks that are among them (its seed 1 draws 137, 64, 261).
    std::shuffle(creases.begin(), creases.end(), rng);
    for (int measured : {137, 64, 261}) {
        const auto at = std::find(creases.begin(), creases.end(), measured);
        if (at != creases.end()) std::rotate(creases.begin(), at, at + 1);
    }
    creases.resize(std::min<size_t>(creases.size(), 19));
    std::ostringstream pulls;
    int tried = 0, full = 0, within = 0;
    for (size_t pick = 0; pick < creases.size(); ++pick) {
        const int v = creases[pick];
        const double length = 1.0;  // (at two radii and more, every such pull's falloff shape crosses itself here)
        if (falloffShapeCrosses(v, length)) continue;
        ++tried;
        const Eigen::Vector3d n = mesh.normals.row(v).transpose(), source = mesh.positions.row(v).transpose(), target = source + length * radius * n;
        BrushSettings brush;
        brush.radius = radius;
        Session session;
        REQUIRE(session.setMesh(mesh.positions, mesh.triangles).ok);
        OpReport report;
        REQUIRE(session.dragVertex(v, target, report, brush).ok);
        INFO("vertex " << v << " pull " << length << " r: " << report.reason);
        REQUIRE(report.status == OpStatus::Applied);
        CHECK(test::intersectingPairs(session.mesh().positions, session.mesh().triangles) == atLoad);
        if (report.fractionApplied < 1.0) continue;
        ++full;
        CHECK((session.mesh().positions.row(v).transpose() - target).norm() <= 1e-9 * mesh.diagonal);
        const double profile = pullProfile(mesh, session.mesh().positions, source, target, n, length * radius, brush);
        pulls << "vertex " << v << " " << length << " r: profile " << profile << "\n";
        within += profile <= 0.08;
    }
    INFO(pulls.str() << full << " of " << tried << " in full, " << within << " within 0.08");
    REQUIRE(tried >= 6);
    CHECK(full == tried);
    CHECK(within == full);
}

TEST_CASE("brush counts: undo and redo of a stroke report the same vertices, those whose positions changed", "[core][brush]") {
    std::mt19937 rng(17);
    const Mesh mesh = realMesh("elephant.off");
    Session session;
    REQUIRE(session.setMesh(mesh.positions, mesh.triangles).ok);
    for (int trial = 0; trial < 6; ++trial) {
        BrushSettings brush;
        brush.radius = (0.04 + 0.02 * trial) * mesh.diagonal;
        brush.symmetry.mirror[0] = trial % 2 == 1;
        const int v = test::randomInt(rng, 0, static_cast<int>(mesh.positions.rows()) - 1);
        const Positions before = session.mesh().positions;
        OpReport stroke, undo, redo;
        REQUIRE(session.dragVertex(v, before.row(v).transpose() + (0.5 + trial * 0.4) * brush.radius * mesh.normals.row(v).transpose(), stroke, brush).ok);
        if (stroke.status != OpStatus::Applied) continue;
        const Positions after = session.mesh().positions;
        int changed = 0;
        for (Eigen::Index r = 0; r < before.rows(); ++r) changed += before.row(r) != after.row(r);
        INFO("trial " << trial);
        CHECK(stroke.verticesMoved == changed);
        REQUIRE(session.undo(undo).ok);
        CHECK((session.mesh().positions - before).cwiseAbs().maxCoeff() <= 1e-12 * mesh.diagonal);
        REQUIRE(session.redo(redo).ok);
        CHECK(undo.verticesMoved == redo.verticesMoved);
        CHECK(undo.verticesMoved <= mesh.positions.rows());
        CHECK(std::abs(undo.verticesMoved - changed) <= changed / 50 + 1);  // the same vertices, up to rounding to zero
    }
}

TEST_CASE("history counts: undo and redo of a lattice set-up and of drags report the vertices whose positions changed", "[core][brush]") {
    // Counted independently, bitwise, from the positions before and after each command. Taking back a set-up
    // leaves a frame: it must count what moved, not every vertex (it once said every vertex moved while the
    // shape stayed put).
    std::mt19937 rng(23);
    const Mesh mesh = realMesh("elephant.off");
    Session session;
    REQUIRE(session.setMesh(mesh.positions, mesh.triangles).ok);
    const auto differing = [](const Positions& a, const Positions& b) {
        int n = 0;
        for (Eigen::Index r = 0; r < std::min(a.rows(), b.rows()); ++r) n += a.row(r) != b.row(r);
        return n + static_cast<int>(std::abs(a.rows() - b.rows()));
    };
    int setupsUndone = 0;
    for (int trial = 0; trial < 4; ++trial) {
        INFO("trial " << trial);
        LatticeSettings settings = session.cage().settings();
        settings.resolution = {5 + trial, 6, 5 + (trial + 1) % 3};
        OpReport report;
        REQUIRE(session.setupLattice(settings, report).ok);
        REQUIRE(report.status == OpStatus::Applied);
        BrushSettings brush;
        if (trial % 2 == 1) brush.radius = 0.08 * mesh.diagonal;
        const int v = test::randomInt(rng, 0, static_cast<int>(mesh.positions.rows()) - 1);
        const Eigen::Vector3d target = session.mesh().positions.row(v).transpose() + 0.03 * mesh.diagonal * mesh.normals.row(v).transpose();
        REQUIRE(session.dragVertex(v, target, report, brush).ok);
        const bool dragged = report.status == OpStatus::Applied;
        // Undo the drag (if it applied) and the set-up, then redo both: each count is what changed.
        std::vector<int> undoCounts;
        for (int step = 0; step < (dragged ? 2 : 1); ++step) {
            const Positions before = session.mesh().positions;
            REQUIRE(session.undo(report).ok);
            CHECK(report.verticesMoved == differing(before, session.mesh().positions));
            CHECK(report.verticesMoved <= session.mesh().positions.rows());
            undoCounts.push_back(report.verticesMoved);
        }
        ++setupsUndone;
        for (int step = 0; step < (dragged ? 2 : 1); ++step) {
            const Positions before = session.mesh().positions;
            REQUIRE(session.redo(report).ok);
            CHECK(report.verticesMoved == differing(before, session.mesh().positions));
        }
        // Taking the set-up back moves vertices by rounding only (Newton's inverse of the frame), some of them
        // bitwise: on this mesh not all (668 of 2,775 in the first trial).
        CHECK(undoCounts.back() < mesh.positions.rows());
    }
    CHECK(setupsUndone == 4);
}

TEST_CASE("brush crossings: strokes on a real mesh make no triangle pair cross, by the independent exact test", "[core][brush]") {
    std::mt19937 rng(2026);
    const Mesh mesh = realMesh("elephant.off");
    const size_t initial = test::intersectingPairs(mesh.positions, mesh.triangles).size();
    Session session;
    REQUIRE(session.setMesh(mesh.positions, mesh.triangles).ok);
    // (stroke 18, vertex 2173, 2.36 radii along the normal, once left a vertex off after undo: Newton along the
    // pull's line cycled; it is safeguarded now.)
    for (int stroke = 0; stroke < 24; ++stroke) {
        BrushSettings brush;
        brush.radius = (0.03 + 0.005 * stroke) * mesh.diagonal;
        brush.falloff = static_cast<BrushFalloff>(stroke % 3);
        brush.symmetry.mirror[0] = stroke % 4 == 3;
        session.setInjectivity({stroke % 2 ? InjectivityMode::Exact : InjectivityMode::Conic, 6});
        const int v = test::randomInt(rng, 0, static_cast<int>(mesh.positions.rows()) - 1);
        const Eigen::Vector3d n = mesh.normals.row(v).transpose();
        const Eigen::Vector3d direction = stroke % 3 == 0 ? n : stroke % 3 == 1 ? n.unitOrthogonal() : Eigen::Vector3d(-n);
        OpReport report;
        REQUIRE(session.dragVertex(v, mesh.positions.row(v).transpose() + (0.2 + 0.12 * stroke) * brush.radius * direction, report, brush).ok);
        INFO("stroke " << stroke << " vertex " << v << ": " << report.reason);
        CHECK(test::intersectingPairs(session.mesh().positions, session.mesh().triangles).size() == initial);
        REQUIRE(session.undo(report).ok);
        CHECK((session.mesh().positions - mesh.positions).cwiseAbs().maxCoeff() <= 1e-12 * mesh.diagonal);
    }
}

TEST_CASE("brush detail: a cage around the mesh carries what a stroke pulled out of its box, and a cage in a region that left vertices out counts what it leaves", "[core][brush]") {
    // A cage set up around the whole mesh carries vertices outside its box by its collar: a stroke reports none
    // left outside, and a translation of the cage moves every vertex by it. A cage set up in a region the user
    // gave that leaves some vertices out (here the mesh's bounds less 2% at both ends of x, unpadded) holds only
    // what lies in it: the session counts the stroke's vertices outside it, and those a cage move leaves next to
    // moved ones, so the window can say so. Counted independently: the cage is undeformed, so a baked vertex
    // rests where it is.
    std::mt19937 rng(41);
    int strokesOut = 0;
    for (const Mesh& mesh : {sphere(), realMesh("elephant.off")}) {
        for (int trial = 0; trial < 12; ++trial) {
            const bool region = trial % 2 == 1;
            INFO(mesh.name << " trial " << trial << (region ? " (region cage)" : " (cage around the mesh)"));
            Session session;
            LatticeSettings cageSettings;
            cageSettings.hasRegion = region;
            cageSettings.regionMin = mesh.positions.colwise().minCoeff().transpose();
            cageSettings.regionMax = mesh.positions.colwise().maxCoeff().transpose();
            const double shrink = 0.02 * (cageSettings.regionMax.x() - cageSettings.regionMin.x());
            cageSettings.regionMin.x() += shrink;
            cageSettings.regionMax.x() -= shrink;
            if (region) cageSettings.padding = 0.0;
            REQUIRE(session.setMesh(mesh.positions, mesh.triangles, cageSettings));
            const int v = std::uniform_int_distribution<int>(0, static_cast<int>(mesh.positions.rows()) - 1)(rng);
            BrushSettings brush;
            brush.radius = (0.04 + 0.02 * (trial / 2)) * mesh.diagonal;
            const Eigen::Vector3d source = mesh.positions.row(v).transpose();
            OpReport report;
            REQUIRE(session.dragVertex(v, source + (0.5 + 0.5 * (trial / 2)) * brush.radius * mesh.normals.row(v).transpose(), report, brush));
            if (report.status != OpStatus::Applied) continue;
            const Lattice& cage = session.lattice();
            int outside = 0;
            for (Eigen::Index r = 0; r < mesh.positions.rows(); ++r) {
                const Eigen::Vector3d x = session.mesh().positions.row(r).transpose();
                outside += session.mesh().positions.row(r) != mesh.positions.row(r) &&
                           ((x.array() < cage.boxMin.array()).any() || (x.array() > cage.boxMax.array()).any());
            }
            CHECK(session.stroke().verticesOutsideCage() == (region ? outside : 0));
            strokesOut += outside > 0;
            // The cage has not moved: nothing is left behind yet.
            CHECK(session.verticesLeftOutsideCage() == 0);
            if (outside == 0) continue;
            // A translation of the cage moves what it holds (and, around the mesh, its collar: everything).
            const Positions before = session.mesh().positions;
            const std::vector<int> ids = unpinned(session.lattice());
            const Eigen::Vector3d by = 0.03 * mesh.diagonal * test::randomVector(rng, -1.0, 1.0).normalized();
            REQUIRE(session.moveControlPoints(ids, by.transpose().replicate(static_cast<Eigen::Index>(ids.size()), 1), true, report).ok);
            if (!region) {
                REQUIRE(report.status == OpStatus::Applied);
                CHECK(report.fractionApplied == 1.0);
                CHECK(((session.mesh().positions - before).rowwise() - by.transpose()).cwiseAbs().maxCoeff() <= 1e-9 * mesh.diagonal);
                CHECK(session.verticesLeftOutsideCage() == 0);
                continue;
            }
            if (report.status != OpStatus::Applied || report.fractionApplied < 1.0) continue;
            // The region cage: the vertices outside its box stay, and those next to moved ones are counted:
            // independently, the unmoved corners of triangles with a moved corner.
            std::vector<std::uint8_t> left(static_cast<size_t>(mesh.positions.rows()), 0);
            for (Eigen::Index f = 0; f < mesh.triangles.rows(); ++f) {
                bool anyMoved = false;
                for (int k = 0; k < 3; ++k) anyMoved = anyMoved || session.mesh().positions.row(mesh.triangles(f, k)) != before.row(mesh.triangles(f, k));
                if (!anyMoved) continue;
                for (int k = 0; k < 3; ++k)
                    if (session.mesh().positions.row(mesh.triangles(f, k)) == before.row(mesh.triangles(f, k))) left[static_cast<size_t>(mesh.triangles(f, k))] = 1;
            }
            const int expected = static_cast<int>(std::count(left.begin(), left.end(), std::uint8_t{1}));
            CHECK(expected > 0);
            CHECK(session.verticesLeftOutsideCage() == expected);
        }
    }
    CHECK(strokesOut >= 6);  // long pulls leave the 5% padding
}

TEST_CASE("brush: mirror images within reach whose pulls part (outward beside the plane) apply in full, split along and across the plane", "[core][brush]") {
    // A normal pull beside the mirror plane of CGAL's camel: the two images' pulls part by more than
    // sharedPullDirection's 25 degrees, so they share no direction, and a layer each, holding the other image
    // inside its region, may fold at once; one layer summing both scaled fields too. The split (the part along
    // the plane, then the opposed part across it: stroke_brush.cpp) is proven layer by layer. Random strokes
    // (fixed seed) whose summed falloff shape crosses nothing new: each lands its images exactly on the share it
    // reached, crosses no triangle and undoes exactly; 38 of the 40 apply in full (31 with a layer each or the
    // summed layer: the other 9 folded near the spine; of the two left, one is pulled onto its mirror plane).
    const Mesh mesh = realMesh("camel.off");
    const Eigen::Vector3d centre = 0.5 * (mesh.positions.colwise().minCoeff() + mesh.positions.colwise().maxCoeff()).transpose();
    const std::vector<std::pair<int, int>> atLoad = test::intersectingPairs(mesh.positions, mesh.triangles);
    std::mt19937 rng(59);
    int full = 0, trials = 0;
    for (int attempt = 0; attempt < 20000 && trials < 40; ++attempt) {
        BrushSettings brush;
        brush.symmetry.mirror[0] = true;
        brush.radius = std::uniform_real_distribution<double>(0.05, 0.1)(rng) * mesh.diagonal;
        brush.falloff = static_cast<BrushFalloff>(test::randomInt(rng, 0, 2));
        const int v = test::randomInt(rng, 0, static_cast<int>(mesh.positions.rows()) - 1);
        const Eigen::Vector3d source = mesh.positions.row(v).transpose(), n = mesh.normals.row(v).transpose();
        const Eigen::Vector3d imageNormal(-n.x(), n.y(), n.z());
        const double offPlane = std::abs(source.x() - centre.x());
        // Within reach of each other (not merged), pulls more than 30 degrees apart.
        if (offPlane < 0.2 * brush.radius || 2.0 * offPlane > 2.0 * kBrushReach * brush.radius || n.dot(imageNormal) > std::cos(30.0 * M_PI / 180.0)) continue;
        const double pull = std::uniform_real_distribution<double>(0.3, 2.5)(rng) * brush.radius;
        // The falloff shape of both images at the target crosses nothing new.
        if (!mirroredFalloffShapeClear(mesh, centre, source, source + pull * n, brush, atLoad)) continue;
        ++trials;
        full += strokeLandsUncrossed(mesh, v, source + pull * n, brush, atLoad);
    }
    CHECK(trials == 40);
    CHECK(full >= 37);
}

// Mirror images within each other's reach pulled long (1 to 3 radii) beside the plane: where one image's pull
// alone applies in full (the same stroke with symmetry off; its falloff shape often crosses, and the field pushes
// what lies ahead), the symmetric stroke does too. Before, every mode folded the space between the images or
// crossed triangles in a state between its layers (strokes_real: CGAL's elephant stroke 71 stopped at 37.5%,
// armadillo stroke 35 at 50.6%, camel stroke 47 at 75%); now the layers' triangles are checked on their result
// (Session::beginDeferredTriangles) and the split is tried in four steps (stroke_brush.cpp, Stepped).
// The strokes are strokes_real's (the same draws: radius 3-15% of the diagonal, pulls of 0.1-3 radii along the
// normal, a tangent and inward, conic and exact), for two seeds, on two real scans; of them, those with symmetry
// whose images lie within each other's reach (not merged on the plane: closer than a quarter knot span they are
// one point), pulled at least one radius, the target on its side of the plane. Each lands, crosses nothing the
// mesh did not cross at load (the independent exact test) and undoes exactly; all but one apply in full (31 of 32;
// 25 before: the armadillo's seed-7 stroke 31, a tangent pull of 2.4 radii 0.18 radius from the plane, still
// stops at 34% where the triangles cross, refined or not).
TEST_CASE("brush: mirror images within reach pulled long beside the plane nearly all apply in full where one image's pull alone does", "[core][brush]") {
    int trials = 0, full = 0;
    std::string shortOnes;
    for (const char* name : {"elephant.off", "armadillo.off"}) {
        const Mesh mesh = realMesh(name);
        const double mirrorX = 0.5 * (mesh.positions.col(0).maxCoeff() + mesh.positions.col(0).minCoeff());
        const std::vector<std::pair<int, int>> atLoad = test::intersectingPairs(mesh.positions, mesh.triangles);
        for (unsigned seed : {2026u, 7u}) {
            std::mt19937 rng(seed);
            std::uniform_real_distribution<double> unit(0.0, 1.0);
            for (int stroke = 0; stroke < test::scaledCount(100, 40); ++stroke) {
                // (drawn as sculpt_bench strokes_real draws them)
                BrushSettings brush;
                brush.radius = (0.03 + 0.12 * unit(rng)) * mesh.diagonal;
                brush.falloff = static_cast<BrushFalloff>(stroke / 3 % 3);
                const int v = std::uniform_int_distribution<int>(0, static_cast<int>(mesh.positions.rows()) - 1)(rng);
                const Eigen::Vector3d n = mesh.normals.row(v).transpose();
                const Eigen::Vector3d direction = stroke % 3 == 0 ? n : stroke % 3 == 1 ? n.unitOrthogonal() : Eigen::Vector3d(-n);
                const double pull = (0.1 + 2.9 * unit(rng)) * brush.radius;
                if (stroke % 4 != 3 || pull < brush.radius) continue;
                const Eigen::Vector3d source = mesh.positions.row(v).transpose(), target = source + pull * direction;
                const double offPlane = source.x() - mirrorX;
                if (std::abs(offPlane) > kBrushReach * brush.radius || 2.0 * std::abs(offPlane) <= 0.25 * brush.radius / kBrushFieldSpansPerRadius) continue;
                if ((target.x() - mirrorX) * offPlane <= 0.0) continue;  // across the plane: no symmetric map carries it
                Session oneSide;
                REQUIRE(oneSide.setMesh(mesh.positions, mesh.triangles).ok);
                oneSide.setInjectivity({stroke % 2 ? InjectivityMode::Exact : InjectivityMode::Conic, 6});
                OpReport report;
                REQUIRE(oneSide.dragVertex(v, target, report, brush).ok);
                if (report.status != OpStatus::Applied || report.fractionApplied < 1.0) continue;  // one image alone stops short
                brush.symmetry.mirror[0] = true;
                ++trials;
                INFO(name << " seed " << seed << " stroke " << stroke << ": " << offPlane / brush.radius << " r from the plane, falloff " << static_cast<int>(brush.falloff));
                if (strokeLandsUncrossed(mesh, v, target, brush, atLoad, stroke % 2 ? InjectivityMode::Exact : InjectivityMode::Conic)) ++full;
                else shortOnes += std::string(name) + " seed " + std::to_string(seed) + " stroke " + std::to_string(stroke) + "; ";
            }
        }
    }
    INFO(full << " of " << trials << " applied in full; short: " << shortOnes);
    CHECK(trials >= 8);
    CHECK(full >= trials - 1);
}

TEST_CASE("brush: mirror images within reach pulled towards each other (inward beside the plane) apply in full up to the plane", "[core][brush]") {
    // An inward pull beside the mirror plane of CGAL's camel (a leg, the neck): the images' pulls across the plane
    // meet head on. Summed, their two fields each fall ahead by up to k / |d| (k >= 0.7), so the space between
    // them folds at once (strokes_real: "the mesh would fold" at 14-88% of such pulls); carried across the plane
    // by one field whose ramps towards the plane never overlap (brushFieldDelta's converging pair) it is
    // injective while the grabbed point stays short of the plane. Random strokes (fixed seed) whose target stays
    // on its side of the plane and whose summed falloff shape crosses nothing new: each lands its images exactly on
    // the share it reached, crosses no triangle and undoes exactly, and nearly all apply in full.
    const Mesh mesh = realMesh("camel.off");
    const Eigen::Vector3d centre = 0.5 * (mesh.positions.colwise().minCoeff() + mesh.positions.colwise().maxCoeff()).transpose();
    const std::vector<std::pair<int, int>> atLoad = test::intersectingPairs(mesh.positions, mesh.triangles);
    std::mt19937 rng(61);
    int full = 0, trials = 0;
    const int wanted = test::scaledCount(30, 8);
    for (int attempt = 0; attempt < 20000 && trials < wanted; ++attempt) {
        BrushSettings brush;
        brush.symmetry.mirror[0] = true;
        brush.radius = std::uniform_real_distribution<double>(0.05, 0.12)(rng) * mesh.diagonal;
        brush.falloff = static_cast<BrushFalloff>(test::randomInt(rng, 0, 2));
        const int v = test::randomInt(rng, 0, static_cast<int>(mesh.positions.rows()) - 1);
        const Eigen::Vector3d source = mesh.positions.row(v).transpose(), inward = -mesh.normals.row(v).transpose();
        const double offPlane = source.x() - centre.x();
        // Within reach of each other (not merged), pulled towards the plane by at least a third of the pull.
        if (std::abs(offPlane) < 0.2 * brush.radius || std::abs(offPlane) > kBrushReach * brush.radius || inward.x() * offPlane > -0.33 * std::abs(offPlane))
            continue;
        // Up to 90% of the way to the plane, and at most 2 radii.
        const double toPlane = std::abs(offPlane / inward.x());
        const double pull = std::uniform_real_distribution<double>(0.2, 0.9)(rng) * std::min(toPlane, 2.0 * brush.radius / 0.9);
        if (!mirroredFalloffShapeClear(mesh, centre, source, source + pull * inward, brush, atLoad)) continue;
        ++trials;
        INFO(offPlane / brush.radius << " r from the plane");
        full += strokeLandsUncrossed(mesh, v, source + pull * inward, brush, atLoad);
    }
    INFO(full << " of " << trials << " applied in full");  // 30 of 30 (26 with the two fields summed)
    CHECK(trials == wanted);
    CHECK(full >= trials - 1);
}

// Mirror images within reach pulled apart are carried in two layers, along the plane then across it
// (stroke_brush.cpp, brushFieldDelta's opposed pair), each mirror symmetric: a symmetric mesh stays symmetric
// to rounding, which a layer per image (the second placed after the first) does not give. An icosphere (symmetric
// in X) with random normal pulls of vertices 0.1 to 1.2 radius from the plane, every falloff: each vertex's
// mirror vertex ends at the mirror of where the vertex ends, to 1e-9 x diagonal; the grabbed point lands.
TEST_CASE("brush: a symmetric pull of mirror images within reach keeps a symmetric mesh symmetric", "[core][brush]") {
    Positions positions;
    Triangles triangles;
    test::icosphere(4, 1.0, Eigen::Vector3d::Zero(), positions, triangles);
    Positions normals;
    computeVertexNormals(positions, triangles, normals);
    const double diagonal = (positions.colwise().maxCoeff() - positions.colwise().minCoeff()).norm();
    // Each vertex's mirror in X (the icosphere has the coordinate planes' symmetry).
    std::vector<int> mirror(static_cast<size_t>(positions.rows()), -1);
    for (Eigen::Index v = 0; v < positions.rows(); ++v) {
        const Eigen::RowVector3d image(-positions(v, 0), positions(v, 1), positions(v, 2));
        Eigen::Index nearest = 0;
        (positions.rowwise() - image).rowwise().squaredNorm().minCoeff(&nearest);
        REQUIRE((positions.row(nearest) - image).norm() <= 1e-12);
        mirror[static_cast<size_t>(v)] = static_cast<int>(nearest);
    }
    std::mt19937 rng(83);
    int trials = 0, full = 0;
    for (int attempt = 0; attempt < 5000 && trials < 12; ++attempt) {
        BrushSettings brush;
        brush.symmetry.mirror[0] = true;
        brush.radius = std::uniform_real_distribution<double>(0.15, 0.35)(rng);
        brush.falloff = static_cast<BrushFalloff>(trials % 3);
        const int v = test::randomInt(rng, 0, static_cast<int>(positions.rows()) - 1);
        const double offPlane = std::abs(positions(v, 0));
        if (offPlane < 0.1 * brush.radius || offPlane > 1.2 * brush.radius) continue;
        ++trials;
        const double pull = std::uniform_real_distribution<double>(0.5, 2.5)(rng) * brush.radius;
        Session session;
        REQUIRE(session.setMesh(positions, triangles).ok);
        const Eigen::Vector3d source = positions.row(v).transpose(), target = source + pull * normals.row(v).transpose();
        OpReport report;
        REQUIRE(session.dragVertex(v, target, report, brush).ok);
        INFO("vertex " << v << ", " << offPlane / brush.radius << " r from the plane, pull " << pull / brush.radius << " r, falloff "
                       << static_cast<int>(brush.falloff) << ": " << report.reason);
        REQUIRE(report.status == OpStatus::Applied);
        full += report.fractionApplied == 1.0;
        const Positions& after = session.mesh().positions;
        CHECK((after.row(v).transpose() - (source + report.fractionApplied * (target - source))).norm() <= 1e-9 * diagonal);
        double asymmetry = 0.0;
        for (Eigen::Index u = 0; u < after.rows(); ++u) {
            const Eigen::RowVector3d image(-after(u, 0), after(u, 1), after(u, 2));
            asymmetry = std::max(asymmetry, (after.row(mirror[static_cast<size_t>(u)]) - image).norm());
        }
        CHECK(asymmetry <= 1e-9 * diagonal);
        CHECK(test::selfIntersectingPairs(after, triangles) == 0);
    }
    CHECK(trials == 12);
    CHECK(full >= 10);
}
