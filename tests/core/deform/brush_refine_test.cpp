// Refinement under a brush stroke (issue "Sculpting as a sculptor expects", point 2; Stroke::applyBrushPulls,
// Refiner::refineUnderPull): a long pull whose field is injective in space, but whose bend the mesh's long flat
// triangles cannot follow without cutting through each other, splits the triangles under it and applies in full.
// Before, such strokes stopped short "where the surface would pass through itself" (CGAL's elephant: 26 of 100
// in sculpt_bench strokes_real).
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <map>
#include <numeric>
#include <random>

#include "../cgal_meshes.h"
#include "../mesh_fixtures.h"
#include "../refinement_checks.h"
#include "../test_support.h"
#include "../../test_scale.h"
#include "core/deform/brush_field.h"
#include "core/deform/vertex_normals.h"
#include "core/session/session.h"
#include "io/script.h"
#include "io/script_json.h"

using namespace sculpt;
using namespace sculpt::core;

namespace {

struct Pull {
    int vertex = -1;
    Eigen::Vector3d target;
    BrushSettings brush;
};

// One pull of the kinds strokes_real draws (normal, tangent, inward; 2 to 3 radii), on the mesh as it is now.
Pull randomStroke(std::mt19937& rng, const Session& session, const Positions& normals, int index, double diagonal) {
    Pull s;
    s.vertex = test::randomInt(rng, 0, static_cast<int>(normals.rows()) - 1);
    s.brush.radius = std::uniform_real_distribution<double>(0.06, 0.14)(rng) * diagonal;
    s.brush.falloff = static_cast<BrushFalloff>(index % 3);
    const Eigen::Vector3d n = normals.row(s.vertex).transpose();
    const Eigen::Vector3d direction = index % 3 == 0 ? n : index % 3 == 1 ? n.unitOrthogonal() : Eigen::Vector3d(-n);
    const double pull = std::uniform_real_distribution<double>(2.0, 3.0)(rng) * s.brush.radius;
    s.target = session.mesh().positions.row(s.vertex).transpose() + pull * direction;
    return s;
}

// CGAL's elephant (2,775 vertices, coarse), its vertex normals, its bounding diagonal and the crossing pairs it
// was loaded with.
struct Elephant {
    Positions positions, normals;
    Triangles triangles;
    double diagonal = 0.0;
    size_t crossingAtLoad = 0;
};

Elephant loadElephant() {
    Elephant e;
    std::string error;
    const bool loaded = test::loadCgalMesh("elephant.off", e.positions, e.triangles, error);
    INFO(error);
    REQUIRE(loaded);
    computeVertexNormals(e.positions, e.triangles, e.normals);
    e.diagonal = (e.positions.colwise().maxCoeff() - e.positions.colwise().minCoeff()).norm();
    e.crossingAtLoad = test::intersectingPairs(e.positions, e.triangles).size();
    return e;
}

// A session on the mesh with "Split under the brush" on or off.
void startSession(Session& session, const Positions& positions, const Triangles& triangles, bool splitUnderBrush) {
    REQUIRE(session.setMesh(positions, triangles).ok);
    RefinementSettings settings = session.refinement().settings();
    settings.underBrush = splitUnderBrush;
    REQUIRE(session.refinement().set(settings).ok);
}

}  // namespace

TEST_CASE("brush refinement: long pulls the triangles stopped split the mesh under them and apply in full, uncrossed, conforming, undone and replayed exactly", "[core][brush]") {
    std::mt19937 rng(2027);
    const Elephant elephant = loadElephant();
    const Positions& positions = elephant.positions;  // (not structured bindings: C++17 lambdas cannot capture those)
    const Triangles& triangles = elephant.triangles;
    const double diagonal = elephant.diagonal;
    Positions normals;
    computeVertexNormals(positions, triangles, normals);
    const test::EdgeCensus censusAtLoad = test::edgeCensus(triangles);

    Session session;
    REQUIRE(session.setMesh(positions, triangles).ok);
    int refined = 0, stoppedWithout = 0;
    Pull firstSplit;
    for (int index = 0; index < 12 && refined < 3; ++index) {
        const Pull stroke = randomStroke(rng, session, normals, index, diagonal);
        const Positions before = session.mesh().positions;
        const Triangles trianglesBefore = session.mesh().triangles;
        OpReport report;
        REQUIRE(session.dragVertex(stroke.vertex, stroke.target, report, stroke.brush).ok);
        INFO("stroke " << index << " vertex " << stroke.vertex << ": " << report.reason);
        if (report.status == OpStatus::Rejected) {
            // The strokes before squeezed two sheets within a hair of each other where this one pulls (a tangent
            // pull pushes what lies ahead on to a third of its distance): refused, and nothing changed.
            CHECK(report.reason.find("would pass through itself") != std::string::npos);
            CHECK(session.mesh().positions == before);
            CHECK(session.mesh().triangles == trianglesBefore);
            continue;
        }
        REQUIRE(report.status == OpStatus::Applied);
        const Operation& entry = session.history()[static_cast<size_t>(session.history().cursor() - 1)];
        if (entry.refinementBefore.empty()) {
            // Nothing split: the mesh keeps its triangles (a pull that passed, or one that stops short anyway).
            CHECK(session.mesh().triangles == trianglesBefore);
            continue;
        }
        if (refined++ == 0) firstSplit = stroke;
        // Split only where the whole pull then passes: the grabbed point lands on its target.
        CHECK(report.fractionApplied == 1.0);
        CHECK(report.verticesAdded == static_cast<int>(session.mesh().positions.rows() - before.rows()));
        CHECK((session.mesh().positions.row(stroke.vertex).transpose() - stroke.target).norm() <= 1e-9 * diagonal);
        // Conforming and closed as it was (a T-junction or a crack leaves boundary edges; one orientation; the
        // Euler characteristic kept), and uncrossed by the independent exact test.
        const test::EdgeCensus census = test::edgeCensus(session.mesh().triangles);
        CHECK(census.boundaryEdges == censusAtLoad.boundaryEdges);
        CHECK(census.nonManifoldEdges == 0);
        CHECK(census.inconsistentEdges == 0);
        CHECK(census.euler() + session.mesh().triangles.rows() == censusAtLoad.euler() + triangles.rows());
        CHECK(test::intersectingPairs(session.mesh().positions, session.mesh().triangles).size() == elephant.crossingAtLoad);
        // The old vertices beyond 1.25 radius of the pull's path stay where they were.
        const Eigen::Vector3d source = before.row(stroke.vertex).transpose();
        for (Eigen::Index v = 0; v < before.rows(); ++v)
            if (segmentDistance(before.row(v).transpose(), source, stroke.target) > kBrushReach * stroke.brush.radius * (1.0 + 1e-9))
                CHECK(session.mesh().positions.row(v) == before.row(v));

        // The same stroke without splitting stops short, where the triangles would cross.
        {
            Session unsplit;
            startSession(unsplit, positions, triangles, false);
            OpReport r;
            for (int k = 0; k < session.history().cursor() - 1; ++k) {  // the strokes kept so far, as recorded
                const Operation& kept = session.history()[static_cast<size_t>(k)];
                REQUIRE(unsplit.replayOperation(kept, false, r).ok);
            }
            REQUIRE(unsplit.dragVertex(stroke.vertex, stroke.target, r, stroke.brush).ok);
            CHECK(unsplit.mesh().triangles.rows() == trianglesBefore.rows());
            stoppedWithout += r.fractionApplied < 1.0 && r.refusedBy == "triangles";
            // The advice names the setting that is off.
            if (r.fractionApplied < 1.0 && r.refusedBy == "triangles") CHECK(r.reason.find("or turn \"Split under the brush\" on") != std::string::npos);
        }

        // Undo takes back the stroke and its splits; redo puts both back.
        const Positions after = session.mesh().positions;
        const Triangles trianglesAfter = session.mesh().triangles;
        REQUIRE(session.undo(report).ok);
        REQUIRE(session.mesh().positions.rows() == before.rows());
        CHECK(session.mesh().triangles == trianglesBefore);
        CHECK((session.mesh().positions - before).cwiseAbs().maxCoeff() <= 1e-12 * diagonal);
        CHECK(report.verticesMoved <= static_cast<int>(before.rows()));
        // Both ways the same counts: the vertices whose positions changed, and apart from them the split ones
        // (removed by undo, added again by redo).
        const int undone = report.verticesMoved;
        CHECK(undone > 0);
        CHECK(report.verticesRemoved == static_cast<int>(after.rows() - before.rows()));
        CHECK(report.verticesAdded == 0);
        REQUIRE(session.redo(report).ok);
        CHECK(report.verticesMoved == undone);
        CHECK(report.verticesAdded == static_cast<int>(after.rows() - before.rows()));
        CHECK(report.verticesRemoved == 0);
        REQUIRE(session.mesh().positions.rows() == after.rows());
        CHECK(session.mesh().triangles == trianglesAfter);
        CHECK((session.mesh().positions - after).cwiseAbs().maxCoeff() <= 1e-12 * diagonal);
    }
    INFO(refined << " strokes split the mesh; " << stoppedWithout << " of them stop short without splitting");
    REQUIRE(refined >= 3);
    CHECK(stoppedWithout == refined);

    // The first stroke that split, made again interactively (four mouse moves) on the mesh it split, then taken
    // back (Esc): the mesh and the history are as they were.
    {
        Session again;
        REQUIRE(again.setMesh(positions, triangles).ok);
        OpReport report;
        for (size_t k = 0; session.history()[k].refinementBefore.empty(); ++k) REQUIRE(again.replayOperation(session.history()[k], false, report).ok);
        const Positions before = again.mesh().positions;
        const Triangles trianglesBefore = again.mesh().triangles;
        const int cursor = again.history().cursor();
        const Pull& stroke = firstSplit;
        const Eigen::Vector3d source = before.row(stroke.vertex).transpose();
        REQUIRE(again.stroke().beginAt({source}, {}, stroke.brush).ok);
        for (int move = 1; move <= 4; ++move) REQUIRE(again.stroke().update({source + move / 4.0 * (stroke.target - source)}, report).ok);
        CHECK(again.mesh().positions.rows() > before.rows());
        CHECK((again.mesh().positions.row(stroke.vertex).transpose() - stroke.target).norm() <= 1e-9 * diagonal);
        REQUIRE(again.stroke().cancel(report).ok);
        REQUIRE(again.mesh().positions.rows() == before.rows());
        CHECK(again.mesh().triangles == trianglesBefore);
        CHECK((again.mesh().positions - before).cwiseAbs().maxCoeff() <= 1e-12 * diagonal);
        CHECK(again.history().cursor() == cursor);
    }

    // A recording replays the strokes with their splits bit for bit, through the JSON text.
    const io::Script recording = io::recordSession(session);
    io::Script parsed;
    REQUIRE(io::parseScript(io::scriptToJson(recording), "recording", parsed).ok);
    Session replayed;
    REQUIRE(replayed.setMesh(positions, triangles, parsed.lattice).ok);
    replayed.setInjectivity(parsed.injectivity);
    io::ScriptReport scriptReport;
    REQUIRE(io::runScript(replayed, parsed, scriptReport).ok);
    REQUIRE(replayed.mesh().positions.rows() == session.mesh().positions.rows());
    CHECK(replayed.mesh().triangles == session.mesh().triangles);
    CHECK(replayed.mesh().positions == session.mesh().positions);
}

namespace {

// Distance from p to the triangle (a, b, c), computed independently of the stroke's own projection: the foot on
// the triangle's plane where it falls inside (signs of the sub-areas), else the nearest of the three edges.
double distanceToTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
    const auto toSegment = [&](const Eigen::Vector3d& u, const Eigen::Vector3d& v) {
        const double t = std::clamp((p - u).dot(v - u) / std::max((v - u).squaredNorm(), 1e-300), 0.0, 1.0);
        return (u + t * (v - u) - p).norm();
    };
    const Eigen::Vector3d n = (b - a).cross(c - a);
    if (n.squaredNorm() > 0.0) {
        const Eigen::Vector3d foot = p - (p - a).dot(n) / n.squaredNorm() * n;
        if ((b - a).cross(foot - a).dot(n) >= 0.0 && (c - b).cross(foot - b).dot(n) >= 0.0 && (a - c).cross(foot - c).dot(n) >= 0.0)
            return (foot - p).norm();
    }
    return std::min({toSegment(a, b), toSegment(b, c), toSegment(c, a)});
}

double distanceToMesh(const Eigen::Vector3d& p, const Positions& x, const Triangles& triangles) {
    double best = INFINITY;
    for (Eigen::Index t = 0; t < triangles.rows(); ++t)
        best = std::min(best, distanceToTriangle(p, x.row(triangles(t, 0)).transpose(), x.row(triangles(t, 1)).transpose(), x.row(triangles(t, 2)).transpose()));
    return best;
}

}  // namespace

TEST_CASE("brush refinement: a point grabbed inside a coarse mesh's long triangle lands on its target, where the flat mesh is drawn", "[core][brush]") {
    // The window grabs the surface point under the cursor. On a coarse mesh it lies inside a long triangle,
    // whose flat image between its moved corners left the drawn tip 0.27-0.83 radius short of the cursor (a
    // trial on the elephant: a horn's tip 25% short of a 3-radius pull). The triangles under such a pull are
    // split until the flat mesh passes within the refinement's tolerance of the target.
    std::mt19937 rng(4242);
    const Elephant elephant = loadElephant();
    const Positions& positions = elephant.positions;  // (not structured bindings: C++17 lambdas cannot capture those)
    const Triangles& triangles = elephant.triangles;
    const double diagonal = elephant.diagonal;
    // The largest triangles, where the gap shows most.
    std::vector<int> order(static_cast<size_t>(triangles.rows()));
    std::iota(order.begin(), order.end(), 0);
    const auto area = [&](int t) {
        return (positions.row(triangles(t, 1)) - positions.row(triangles(t, 0))).cross(positions.row(triangles(t, 2)) - positions.row(triangles(t, 0))).norm();
    };
    std::sort(order.begin(), order.end(), [&](int a, int b) { return area(a) > area(b); });
    int landed = 0, missedWithout = 0, checked = 0;
    for (int trial = 0; trial < 6; ++trial) {
        const int t = order[static_cast<size_t>(test::randomInt(rng, 0, 99))];
        Eigen::Vector3d w = test::randomVector(rng, 0.2, 1.0);
        w /= w.sum();
        const Eigen::Vector3d a = positions.row(triangles(t, 0)).transpose(), b = positions.row(triangles(t, 1)).transpose(), c = positions.row(triangles(t, 2)).transpose();
        const Eigen::Vector3d source = w[0] * a + w[1] * b + w[2] * c;
        const Eigen::Vector3d normal = (b - a).cross(c - a).normalized();
        BrushSettings brush;
        brush.radius = std::uniform_real_distribution<double>(0.04, 0.08)(rng) * diagonal;
        brush.falloff = static_cast<BrushFalloff>(trial % 3);
        const Eigen::Vector3d direction = trial % 2 == 0 ? normal : Eigen::Vector3d((normal + normal.unitOrthogonal()).normalized());
        const double pull = std::uniform_real_distribution<double>(1.0, 3.0)(rng) * brush.radius;
        const Eigen::Vector3d target = source + pull * direction;
        INFO("trial " << trial << " triangle " << t << " radius " << brush.radius / diagonal << " diagonal, pull " << pull / brush.radius << " radii");
        for (const bool split : {false, true}) {
            Session session;
            startSession(session, positions, triangles, split);
            OpReport report;
            REQUIRE(session.drag({{source, target}}, report, brush).ok);
            if (report.status != OpStatus::Applied || report.fractionApplied < 1.0) continue;  // stopped: not this test's kind
            const double miss = distanceToMesh(target, session.mesh().positions, session.mesh().triangles);
            if (!split) {
                missedWithout += miss > 0.1 * brush.radius;
                continue;
            }
            ++checked;
            CHECK(miss <= 0.025 * brush.radius);
            landed += miss <= 0.025 * brush.radius;
            CHECK(report.verticesAdded > 0);
            CHECK(test::intersectingPairs(session.mesh().positions, session.mesh().triangles).size() <= elephant.crossingAtLoad);
            // Undo takes the splits back with the stroke.
            REQUIRE(session.undo(report).ok);
            CHECK(session.mesh().triangles == triangles);
            CHECK((session.mesh().positions - positions).cwiseAbs().maxCoeff() <= 1e-12 * diagonal);
            CHECK(report.verticesRemoved > 0);
        }
    }
    INFO(checked << " pulls applied in full, " << landed << " landed; " << missedWithout << " missed by over 0.1 radius unsplit");
    CHECK(checked >= 4);
    CHECK(landed == checked);
    CHECK(missedWithout >= 4);  // the test can fail: the flat triangles alone leave the point short
}

TEST_CASE("brush refinement: where a long pull squeezes what lies ahead of it, the triangles that would still cross are split until they do not", "[core][brush]") {
    // The field pushes what lies ahead of a pull on to a quarter of its distance (brush_field.h): the far side of a
    // thin part, a neighbouring limb. Split to 2% and then 1% of the radius, the flat triangles of two sheets
    // squeezed that close still cut through each other (CGAL's armadillo: 10 of 100 strokes_real strokes stopped
    // "where the surface would pass through itself", the camel 15); the triangles of each pair that crosses at the
    // whole pull are bisected again until none does.
    Positions positions;
    Triangles triangles;
    std::string error;
    const bool loaded = test::loadCgalMesh("armadillo.off", positions, triangles, error);
    INFO(error);
    REQUIRE(loaded);
    const double diagonal = (positions.colwise().maxCoeff() - positions.colwise().minCoeff()).norm();
    const size_t crossingAtLoad = test::intersectingPairs(positions, triangles).size();
    Positions normals;
    computeVertexNormals(positions, triangles, normals);
    Session session;
    REQUIRE(session.setMesh(positions, triangles).ok);
    std::mt19937 rng(31);
    const int strokes = test::scaledCount(16, 4);
    int full = 0, split = 0;
    for (int index = 0; index < strokes; ++index) {
        // Inward and sideways pulls of 2-3 radii (index % 3 == 0 would be along the normal: none here).
        const Pull stroke = randomStroke(rng, session, normals, 1 + index % 2, diagonal);
        OpReport report;
        REQUIRE(session.dragVertex(stroke.vertex, stroke.target, report, stroke.brush).ok);
        INFO("stroke " << index << " vertex " << stroke.vertex << ": " << report.reason);
        REQUIRE(report.status == OpStatus::Applied);
        full += report.fractionApplied == 1.0;
        split += report.verticesAdded > 0;
        if (report.fractionApplied == 1.0)
            CHECK((session.mesh().positions.row(stroke.vertex).transpose() - stroke.target).norm() <= 1e-9 * diagonal);
        // Uncrossed by the independent exact test, and undone exactly.
        CHECK(test::intersectingPairs(session.mesh().positions, session.mesh().triangles).size() == crossingAtLoad);
        REQUIRE(session.undo(report).ok);
        REQUIRE(session.mesh().positions.rows() == positions.rows());
        CHECK((session.mesh().positions - positions).cwiseAbs().maxCoeff() <= 1e-12 * diagonal);
    }
    INFO(full << " of " << strokes << " applied in full, " << split << " split the mesh");
    CHECK(split > 0);
    CHECK(full >= strokes - 1);
}

TEST_CASE("brush refinement: on a triangle soup, long pulls split both sides of every seam alike and apply in full, uncrossed, as on the welded mesh", "[core][brush]") {
    // A soup (each triangle with corners of its own, as CAD exports and STL give) or a mesh split at seams for
    // its normals: the two sides of a seam are different vertices at the same points. A split on one side only
    // left the other side's straight edge to part from the bent one, and the two cut through their neighbours:
    // on CGAL's boeing.off (1,477 of 2,741 vertices on another) a one-radius normal pull of vertex 258 stopped
    // at 4.7% with the splits tried. Here the elephant, welded and as a soup, takes the same long pulls.
    std::mt19937 rng(4242);
    const Elephant elephant = loadElephant();
    const Positions& positions = elephant.positions;
    const Triangles& triangles = elephant.triangles;
    const double diagonal = elephant.diagonal;
    Positions normals;
    computeVertexNormals(positions, triangles, normals);
    // The soup: triangle t has corners 3t, 3t + 1, 3t + 2; `copy` is a soup vertex for each welded one.
    Positions soupPositions(3 * triangles.rows(), 3);
    Triangles soupTriangles(triangles.rows(), 3);
    std::vector<int> copy(static_cast<size_t>(positions.rows()), -1);
    for (Eigen::Index t = 0; t < triangles.rows(); ++t)
        for (int k = 0; k < 3; ++k) {
            const int v = static_cast<int>(3 * t + k);
            soupPositions.row(v) = positions.row(triangles(t, k));
            soupTriangles(t, k) = v;
            if (copy[static_cast<size_t>(triangles(t, k))] < 0) copy[static_cast<size_t>(triangles(t, k))] = v;
        }
    REQUIRE(seamCopiesOf(soupPositions).size() == static_cast<size_t>(soupPositions.rows()));
    CHECK(seamCopiesOf(positions).empty());
    // The soup's triangles in the welded numbering, by position (each vertex to the first at its point): a split
    // on one side of a seam only leaves a T-junction, an edge used once.
    const auto weldedCensus = [](const Positions& x, const Triangles& t) {
        std::map<std::array<double, 3>, int> first;  // (an ordered map, apart from the engine's hashing)
        Triangles welded = t;
        for (Eigen::Index i = 0; i < t.rows(); ++i)
            for (int k = 0; k < 3; ++k) {
                const int v = t(i, k);
                welded(i, k) = first.emplace(std::array<double, 3>{x(v, 0), x(v, 1), x(v, 2)}, v).first->second;
            }
        return test::edgeCensus(welded);
    };
    REQUIRE(weldedCensus(soupPositions, soupTriangles).boundaryEdges == 0);

    Session welded, soup;
    REQUIRE(welded.setMesh(positions, triangles).ok);
    REQUIRE(soup.setMesh(soupPositions, soupTriangles).ok);
    int split = 0, inFull = 0;
    for (int index = 0; index < 9; ++index) {
        const Pull stroke = randomStroke(rng, welded, normals, index, diagonal);
        OpReport weldedReport, soupReport;
        REQUIRE(welded.dragVertex(stroke.vertex, stroke.target, weldedReport, stroke.brush).ok);
        REQUIRE(soup.dragVertex(copy[static_cast<size_t>(stroke.vertex)], stroke.target, soupReport, stroke.brush).ok);
        INFO("stroke " << index << " vertex " << stroke.vertex << ": welded " << weldedReport.fractionApplied << " " << weldedReport.reason
                       << "; soup " << soupReport.fractionApplied << " " << soupReport.reason);
        // Whatever the welded mesh carries in full the soup carries in full.
        if (weldedReport.status == OpStatus::Applied && weldedReport.fractionApplied == 1.0) {
            CHECK(soupReport.status == OpStatus::Applied);
            CHECK(soupReport.fractionApplied == 1.0);
        }
        if (soupReport.status == OpStatus::Applied && soupReport.fractionApplied == 1.0) {
            ++inFull;
            CHECK((soup.mesh().positions.row(copy[static_cast<size_t>(stroke.vertex)]).transpose() - stroke.target).norm() <= 1e-9 * diagonal);
        }
        split += soup.history()[static_cast<size_t>(soup.history().cursor() - 1)].refinementBefore.empty() ? 0 : 1;
        // The seams stay closed: every split on one side is made on the other at the same point.
        const test::EdgeCensus census = weldedCensus(soup.mesh().positions, soup.mesh().triangles);
        CHECK(census.boundaryEdges == 0);
        CHECK(census.nonManifoldEdges == 0);
        // No two triangles cross (the independent exact test; a soup's neighbours touch at their shared points).
        CHECK(test::intersectingPairs(soup.mesh().positions, soup.mesh().triangles).size() == elephant.crossingAtLoad);
        // Undone, the soup is as it was (its splits taken back).
        if (index % 3 == 2) {
            const Positions after = soup.mesh().positions;
            REQUIRE(soup.undo(soupReport).ok);
            REQUIRE(soup.redo(soupReport).ok);
            CHECK((soup.mesh().positions - after).cwiseAbs().maxCoeff() <= 1e-12 * diagonal);
        }
    }
    INFO(split << " soup strokes split the mesh; " << inFull << " of 9 applied in full");
    CHECK(split >= 3);
    CHECK(inFull >= 7);
}

namespace {

// A random stroke on the elephant, set up as the window sets one up: the session on the loaded mesh, every other
// stroke under the exact test, every `symmetricEvery`-th symmetric in X (the last of each run).
Pull elephantStroke(std::mt19937& rng, Session& session, const Elephant& elephant, int index, int symmetricEvery) {
    REQUIRE(session.setMesh(elephant.positions, elephant.triangles).ok);
    session.setInjectivity({index % 2 ? InjectivityMode::Exact : InjectivityMode::Conic, 6});
    Pull stroke = randomStroke(rng, session, elephant.normals, index, elephant.diagonal);
    if (index % symmetricEvery == symmetricEvery - 1) stroke.brush.symmetry.mirror[0] = true;
    return stroke;
}

// How far along its line (unit `direction` from `source`, world units) a stroke's grabbed vertex is after a move
// to `target` that applied: checked on the pull's line, at the share the report gives, to 1e-9 x diagonal.
double alongLine(const Session& session, int vertex, const Eigen::Vector3d& source, const Eigen::Vector3d& direction, const Eigen::Vector3d& target,
                 const OpReport& report, double diagonal) {
    const Eigen::Vector3d at = session.mesh().positions.row(vertex).transpose();
    CHECK((at - (source + report.fractionApplied * (target - source))).norm() <= 1e-9 * diagonal);
    return (at - source).dot(direction);
}

}  // namespace

TEST_CASE("brush: a stroke dragged on past where it stops keeps the ground it gained on the pull's line, uncrossed, and Esc restores the mesh", "[core][brush]") {
    // As the window drags: a stroke of eight mouse moves along one line to twice a long pull, so that moves
    // past where the stroke stops search again from where the last left it (Stroke::applyBrushPulls' hint, in
    // the way the last move carried it; the layers found are put back as they passed, not tried again).
    std::mt19937 rng(2031);
    const Elephant elephant = loadElephant();
    const double diagonal = elephant.diagonal;
    const int wanted = test::scaledCount(4, 1);
    int stoppedStrokes = 0, movesPastStop = 0;
    for (int index = 0; index < 40 && stoppedStrokes < wanted; ++index) {
        Session session;
        const Pull stroke = elephantStroke(rng, session, elephant, index, 4);
        const Eigen::Vector3d source = elephant.positions.row(stroke.vertex).transpose();
        const Eigen::Vector3d direction = (stroke.target - source).normalized();
        REQUIRE(session.stroke().beginAt({source}, {}, stroke.brush).ok);
        double gained = 0.0;  // along the line, world units
        bool stopped = false;
        for (int move = 1; move <= 8; ++move) {
            const Eigen::Vector3d target = source + 2.0 * move / 8.0 * (stroke.target - source);
            OpReport report;
            REQUIRE(session.stroke().update({target}, report).ok);
            INFO("stroke " << index << " vertex " << stroke.vertex << " move " << move << ": " << report.fractionApplied << " " << report.reason);
            if (report.status == OpStatus::Rejected) {
                // Nothing of it passes: the stroke stays where the last move left it.
                CHECK(gained == 0.0);
                continue;
            }
            REQUIRE(report.status == OpStatus::Applied);
            // The grabbed vertex is on the pull's line, at the share the report gives, exactly.
            const double along = alongLine(session, stroke.vertex, source, direction, target, report, diagonal);
            CHECK(along >= gained - 1e-9 * diagonal);
            if (stopped) ++movesPastStop;
            // "Split under the brush" is on: the advice does not ask to turn it on.
            if (report.fractionApplied < 1.0) CHECK(report.reason.find("Split under the brush") == std::string::npos);
            stopped = stopped || report.fractionApplied < 1.0;
            gained = std::max(gained, along);
        }
        // Uncrossed by the independent exact test.
        CHECK(test::intersectingPairs(session.mesh().positions, session.mesh().triangles).size() == elephant.crossingAtLoad);
        // Esc: the mesh as it was loaded (splits taken back), the history empty.
        OpReport report;
        REQUIRE(session.stroke().cancel(report).ok);
        REQUIRE(session.mesh().positions.rows() == elephant.positions.rows());
        CHECK(session.mesh().triangles == elephant.triangles);
        CHECK((session.mesh().positions - elephant.positions).cwiseAbs().maxCoeff() <= 1e-12 * diagonal);
        CHECK(session.history().cursor() == 0);
        stoppedStrokes += stopped;
    }
    INFO(stoppedStrokes << " strokes stopped, " << movesPastStop << " moves past their stop");
    REQUIRE(stoppedStrokes == wanted);
    CHECK(movesPastStop >= wanted);
}

TEST_CASE("brush: a stroke that stops then creeps on in small mouse moves keeps the ground it gained", "[core][brush]") {
    // A slow hand: where the stroke stops, each mouse move lengthens the pull by a 128th of the long pull, so
    // the last move's reach is nearly all of the new pull (more than 63/64 of it). Its search must start from
    // there, not over the whole pull again (where a share short of the last may pass first: on CGAL's armadillo
    // a symmetric stroke fell back from 99% to 83% of its pull).
    std::mt19937 rng(2032);
    const Elephant elephant = loadElephant();
    const double diagonal = elephant.diagonal;
    const int wanted = test::scaledCount(5, 2);
    int stoppedStrokes = 0;
    for (int index = 0; index < 60 && stoppedStrokes < wanted; ++index) {
        Session session;
        Pull stroke = elephantStroke(rng, session, elephant, index, 3);
        const Eigen::Vector3d source = elephant.positions.row(stroke.vertex).transpose();
        stroke.target = source + 3.0 * (stroke.target - source);  // long: most stop
        const Eigen::Vector3d direction = (stroke.target - source).normalized();
        REQUIRE(session.stroke().beginAt({source}, {}, stroke.brush).ok);
        OpReport first;
        REQUIRE(session.stroke().update({stroke.target}, first).ok);
        if (first.status != OpStatus::Applied || first.fractionApplied == 1.0 || first.fractionApplied < 0.25) {
            OpReport report;
            REQUIRE(session.stroke().cancel(report).ok);
            continue;
        }
        // Back to where it stopped (the cursor over the grabbed point), then on by a 128th of the pull a move.
        const double stop = first.fractionApplied;
        OpReport back;
        REQUIRE(session.stroke().update({source + stop * (stroke.target - source)}, back).ok);
        REQUIRE(back.status == OpStatus::Applied);
        ++stoppedStrokes;
        double gained = (session.mesh().positions.row(stroke.vertex).transpose() - source).dot(direction);
        for (int move = 1; move <= 6; ++move) {
            const Eigen::Vector3d target = source + (stop + move / 128.0) * (stroke.target - source);
            OpReport report;
            REQUIRE(session.stroke().update({target}, report).ok);
            INFO("stroke " << index << " vertex " << stroke.vertex << " stopped at " << stop << ", back " << back.fractionApplied << ", move " << move
                           << ": " << report.fractionApplied << " " << report.reason);
            REQUIRE(report.status == OpStatus::Applied);
            const double along = alongLine(session, stroke.vertex, source, direction, target, report, diagonal);
            CHECK(along >= gained - 1e-9 * diagonal);
            gained = std::max(gained, along);
        }
        CHECK(test::intersectingPairs(session.mesh().positions, session.mesh().triangles).size() == elephant.crossingAtLoad);
        OpReport report;
        REQUIRE(session.stroke().cancel(report).ok);
        CHECK((session.mesh().positions - elephant.positions).cwiseAbs().maxCoeff() <= 1e-12 * diagonal);
    }
    INFO(stoppedStrokes << " strokes stopped");
    REQUIRE(stoppedStrokes == wanted);
}
