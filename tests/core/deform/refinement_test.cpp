// issue 10 point 9: refinement where the surface stretches (Coquillart 1990 section 3.4, after Griessmair and
// Purgathofer). A coarse mesh follows a sharp bump once the triangles whose image strays from flat are split;
// the mesh stays conforming and consistently oriented; undo takes back exactly what was added, bitwise.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include "core/deform/brush_field.h"
#include "core/deform/refinement.h"
#include "core/session/session.h"
#include "../mesh_fixtures.h"
#include "../refinement_checks.h"
#include "../test_support.h"

using namespace sculpt;
using namespace sculpt::core;

namespace {

template <typename Matrix>
bool sameBits(const Matrix& a, const Matrix& b) {
    return a.rows() == b.rows() && a.cols() == b.cols() &&
           std::memcmp(a.data(), b.data(), static_cast<size_t>(a.size()) * sizeof(typename Matrix::Scalar)) == 0;
}

double diagonalOf(const Positions& p) { return (p.colwise().maxCoeff() - p.colwise().minCoeff()).norm(); }

// The plane: a 2 x 1 rectangle in z = 0 made of two quads, as four triangles facing +z.
void twoQuads(Positions& positions, Triangles& triangles) {
    positions.resize(6, 3);
    positions << 0, 0, 0, 1, 0, 0, 2, 0, 0, 0, 1, 0, 1, 1, 0, 2, 1, 0;
    triangles.resize(4, 3);
    triangles << 0, 1, 4, 0, 4, 3, 1, 2, 5, 1, 5, 4;
}

// A lattice fine along x, so one slab of control points is a narrow cylindrical bump.
LatticeSettings ridgeLattice() {
    LatticeSettings settings;
    settings.resolution = {17, 4, 4};
    settings.padding = 0.0;
    settings.pinLayers = 0;
    return settings;
}

// Moves the middle slab of control points (i = count/2, every j and k) up by `height`: z += height B_i(x), a
// ridge across the rectangle (a cylinder's bump) whose crest runs along y.
void raiseRidge(Session& session, double height, OpReport& report) {
    const Lattice& lattice = session.lattice();
    std::vector<int> ids;
    const int i = lattice.count[0] / 2;
    for (int k = 0; k < lattice.count[2]; ++k)
        for (int j = 0; j < lattice.count[1]; ++j) ids.push_back(lattice.index(i, j, k));
    Eigen::MatrixX3d offsets(static_cast<Eigen::Index>(ids.size()), 3);
    offsets.rowwise() = Eigen::RowVector3d(0.0, 0.0, height);
    REQUIRE(session.moveControlPoints(ids, offsets, true, report).ok);
    REQUIRE(report.status == OpStatus::Applied);
    REQUIRE(report.fractionApplied == 1.0);
}

// Every triangle of the session's mesh within `tolerance` (world units), sampled densely.
void requireWithin(const Session& session, double tolerance) {
    const auto image = [&session](const Eigen::Vector3d& x) { return session.cage().imageOfRestPoint(x); };
    const std::vector<double> deviation = test::sampledDeviations(session.mesh().rest, session.mesh().positions, session.mesh().triangles, image, 10);
    double worst = 0.0;
    for (double d : deviation) worst = std::max(worst, d);
    INFO("worst sampled deviation " << worst << ", tolerance " << tolerance);
    REQUIRE(worst <= tolerance);
}

// Conforming (no T-junction, same Euler characteristic, no new non-manifold edge) and consistently oriented.
void requireConforming(const Positions& rest, const Triangles& refined, const Triangles& input) {
    const test::EdgeCensus before = test::edgeCensus(input), after = test::edgeCensus(refined);
    REQUIRE(after.nonManifoldEdges == before.nonManifoldEdges);
    REQUIRE(after.inconsistentEdges == before.inconsistentEdges);
    REQUIRE(after.euler() + refined.rows() == before.euler() + input.rows());
    REQUIRE(after.vertices == before.vertices + (rest.rows() - (input.maxCoeff() + 1)));
    REQUIRE(test::tJunctions(rest, refined) == 0);
}

}  // namespace

TEST_CASE("refinement: a coarse plane under a sharp ridge is refined within the tolerance, undo and redo are bitwise", "[refine]") {
    Positions positions;
    Triangles triangles;
    twoQuads(positions, triangles);
    Session session;
    REQUIRE(session.setMesh(positions, triangles, ridgeLattice()).ok);
    OpReport report;
    raiseRidge(session, 0.5, report);
    const Positions bumped = session.mesh().positions;
    const Triangles coarse = session.mesh().triangles;
    const int historySize = static_cast<int>(session.history().size());
    const double tolerance = 0.002;
    const double world = tolerance * diagonalOf(bumped);

    // The coarse mesh misses the bump: its flat triangles stray from their image by far more than the tolerance.
    {
        const auto image = [&session](const Eigen::Vector3d& x) { return session.cage().imageOfRestPoint(x); };
        const std::vector<double> d = test::sampledDeviations(session.mesh().rest, bumped, coarse, image);
        REQUIRE(*std::max_element(d.begin(), d.end()) > 10.0 * world);
    }

    REQUIRE(session.refinement().refine(tolerance, report).ok);
    REQUIRE(report.status == OpStatus::Applied);
    INFO(report.reason);
    REQUIRE(report.reason.empty());  // converged
    REQUIRE(report.verticesAdded > 0);
    REQUIRE(session.mesh().positions.rows() == 6 + report.verticesAdded);
    REQUIRE(session.mesh().triangles.rows() == 4 + report.trianglesAdded);
    REQUIRE(report.deviation <= world);
    REQUIRE(static_cast<int>(session.history().size()) == historySize + 1);
    REQUIRE(session.history().back().kind == OperationKind::Refine);
    REQUIRE(session.mesh().rest.rows() == session.mesh().positions.rows());
    // The measured error (10 steps per side, 66 points per triangle) is below the tolerance.
    requireWithin(session, world);
    requireConforming(session.mesh().rest, session.mesh().triangles, coarse);
    // The old vertices did not move; the new ones lie on the bump (its image), not on the coarse triangles.
    REQUIRE(sameBits(Positions(session.mesh().positions.topRows(6)), bumped));
    double offCoarse = 0.0;
    for (Eigen::Index v = 6; v < session.mesh().positions.rows(); ++v) {
        const Eigen::Vector3d x = session.cage().imageOfRestPoint(session.mesh().rest.row(v).transpose());
        REQUIRE(sameBits(Eigen::RowVector3d(x.transpose()), Eigen::RowVector3d(session.mesh().positions.row(v))));
        offCoarse = std::max(offCoarse, std::abs(x.z() - 0.0) - 0.0);
    }
    REQUIRE(offCoarse > 0.1);  // the crest is half a unit up; vertices off the flat quads' corners follow it
    const Positions refinedPositions = session.mesh().positions;
    const Triangles refinedTriangles = session.mesh().triangles;

    REQUIRE(session.undo(report).ok);
    REQUIRE(report.status == OpStatus::Applied);
    REQUIRE(sameBits(session.mesh().positions, bumped));
    REQUIRE(sameBits(session.mesh().triangles, coarse));
    REQUIRE(session.mesh().rest.rows() == 6);
    REQUIRE(session.lastMoved().all);
    REQUIRE(session.redo(report).ok);
    REQUIRE(sameBits(session.mesh().positions, refinedPositions));
    REQUIRE(sameBits(session.mesh().triangles, refinedTriangles));
    // Undo both: the flat rectangle again (the ridge's undo is an inverse manipulation: up to rounding).
    REQUIRE(session.undo(report).ok);
    REQUIRE(session.undo(report).ok);
    REQUIRE(sameBits(session.mesh().triangles, triangles));
    REQUIRE((session.mesh().positions - positions).cwiseAbs().maxCoeff() <= 1e-12);
    // Refining what is already flat does nothing.
    REQUIRE(session.refinement().refine(tolerance, report).ok);
    REQUIRE(report.status == OpStatus::NoOp);
}

TEST_CASE("refinement: a bad tolerance is an error and changes nothing", "[refine]") {
    Positions positions;
    Triangles triangles;
    twoQuads(positions, triangles);
    Session session;
    OpReport report;
    REQUIRE_FALSE(session.refinement().refine(0.01, report).ok);  // no mesh
    REQUIRE(session.setMesh(positions, triangles, ridgeLattice()).ok);
    raiseRidge(session, 0.5, report);
    const Positions before = session.mesh().positions;
    for (double bad : {0.0, -0.01, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
        const Status s = session.refinement().refine(bad, report);
        REQUIRE_FALSE(s.ok);
        REQUIRE(s.message.find("tolerance") != std::string::npos);
        REQUIRE(sameBits(session.mesh().positions, before));
        REQUIRE(session.history().size() == 1);
    }
    RefinementSettings settings;
    settings.options.tolerance = -1.0;
    REQUIRE_FALSE(session.refinement().set(settings).ok);
    settings.options.tolerance = 0.01;
    settings.options.maxRounds = 0;
    REQUIRE_FALSE(session.refinement().set(settings).ok);
    REQUIRE_FALSE(session.refinement().settings().automatic);
    // During an interactive drag: an error.
    REQUIRE(session.stroke().beginAt({Eigen::Vector3d(1.0, 0.5, before(1, 2))}, {false}, {}).ok);
    REQUIRE_FALSE(session.refinement().refine(0.01, report).ok);
    session.stroke().end();
}

TEST_CASE("refinement: random meshes under random drags end within the tolerance, conforming, and undo bitwise", "[refine]") {
    std::mt19937 rng(1009);
    struct Case {
        int nx, ny;  // 0: an icosphere
    };
    const Case cases[] = {{1, 1}, {2, 2}, {5, 3}, {8, 8}, {0, 0}, {12, 6}};
    int refined = 0;
    for (const Case& c : cases) {
        for (int trial = 0; trial < 3; ++trial) {
            Positions positions;
            Triangles triangles;
            if (c.nx == 0) test::icosphere(1, 0.7, Eigen::Vector3d(0.2, -0.1, 0.3), positions, triangles);
            else test::jitteredGrid(rng, c.nx, c.ny, 2.0, 1.5, positions, triangles);
            LatticeSettings settings;
            settings.resolution = {test::randomInt(rng, 5, 9), test::randomInt(rng, 5, 9), test::randomInt(rng, 4, 6)};
            // note: pinned outer layers keep every lattice (the cage and the layers subdivision adds) still on its
            // box, so the deformation is continuous; with a free boundary a layer's box can cut through the
            // surface between vertices and the image jumps there (the next test).
            settings.pinLayers = 1;
            Session session;
            REQUIRE(session.setMesh(positions, triangles, settings).ok);
            const double diagonal = diagonalOf(positions);
            OpReport report;
            for (int drag = 0; drag < 2; ++drag) {
                const int v = test::randomInt(rng, 0, static_cast<int>(positions.rows()) - 1);
                const Eigen::Vector3d target = session.mesh().positions.row(v).transpose() + 0.15 * diagonal * test::randomVector(rng, -1, 1);
                REQUIRE(session.dragVertex(v, target, report).ok);
            }
            const Positions dragged = session.mesh().positions;
            const Triangles coarse = session.mesh().triangles;
            const double tolerance = std::uniform_real_distribution<double>(0.002, 0.01)(rng);
            REQUIRE(session.refinement().refine(tolerance, report).ok);
            INFO("case " << c.nx << "x" << c.ny << " trial " << trial << ": " << report.reason);
            REQUIRE(report.status != OpStatus::Rejected);
            if (report.status == OpStatus::NoOp) continue;
            ++refined;
            REQUIRE(report.reason.empty());
            requireWithin(session, tolerance * diagonalOf(dragged));
            requireConforming(session.mesh().rest, session.mesh().triangles, coarse);
            REQUIRE(sameBits(Positions(session.mesh().positions.topRows(dragged.rows())), dragged));
            const Positions after = session.mesh().positions;
            const Triangles afterTriangles = session.mesh().triangles;
            REQUIRE(session.undo(report).ok);
            REQUIRE(sameBits(session.mesh().positions, dragged));
            REQUIRE(sameBits(session.mesh().triangles, coarse));
            REQUIRE(session.redo(report).ok);
            REQUIRE(sameBits(session.mesh().positions, after));
            REQUIRE(sameBits(session.mesh().triangles, afterTriangles));
            // A drag after the refinement moves the new vertices too, and its undo leaves them in place.
            const int v = test::randomInt(rng, 0, static_cast<int>(after.rows()) - 1);
            REQUIRE(session.dragVertex(v, after.row(v).transpose() + 0.05 * diagonal * test::randomVector(rng, -1, 1), report).ok);
            REQUIRE(session.mesh().positions.rows() == after.rows());
            if (report.status == OpStatus::Applied) {
                REQUIRE(session.undo(report).ok);
                REQUIRE(session.mesh().positions.rows() == after.rows());
                REQUIRE((session.mesh().positions - after).cwiseAbs().maxCoeff() <= 1e-9 * diagonal);
            }
            REQUIRE(session.undo(report).ok);
            REQUIRE(sameBits(session.mesh().triangles, coarse));
            REQUIRE(session.mesh().positions.rows() == dragged.rows());
        }
    }
    REQUIRE(refined >= 10);
}

TEST_CASE("refinement: a mesh split at random seams refines as the welded mesh does, every copy of a split edge split alike", "[refine]") {
    // Seams (a soup's, or a mesh split for its normals or texture): vertices at one point. The refinement plans on
    // the mesh welded at them and splits every copy of each split edge at the same rest midpoint; splitting one
    // side only left T-junctions, the other side's straight edge parting from the bent one.
    std::mt19937 rng(31337);
    int refined = 0;
    for (int trial = 0; trial < 6; ++trial) {
        Positions positions;
        Triangles triangles;
        if (trial % 2 == 0) test::icosphere(1 + trial / 2, 0.7, Eigen::Vector3d(0.2, -0.1, 0.3), positions, triangles);
        else test::jitteredGrid(rng, 4 + 2 * trial, 3 + trial, 2.0, 1.5, positions, triangles);
        // Seams: a random third of the triangles get corners of their own, numbered after the mesh's, so each
        // point's first copy is the welded mesh's own vertex.
        Positions seamedPositions = positions;
        Triangles seamed = triangles;
        std::vector<int> origin(static_cast<size_t>(positions.rows()));  // each vertex's welded one
        for (Eigen::Index v = 0; v < positions.rows(); ++v) origin[static_cast<size_t>(v)] = static_cast<int>(v);
        for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
            if (std::uniform_real_distribution<double>(0.0, 1.0)(rng) > 1.0 / 3.0) continue;
            for (int k = 0; k < 3; ++k) {
                seamedPositions.conservativeResize(seamedPositions.rows() + 1, 3);
                seamedPositions.row(seamedPositions.rows() - 1) = positions.row(triangles(t, k));
                seamed(t, k) = static_cast<int>(seamedPositions.rows() - 1);
                origin.push_back(triangles(t, k));
            }
        }
        const std::vector<int> copies = seamCopiesOf(seamedPositions);
        CHECK(copies == origin);
        CHECK(seamCopiesOf(positions).empty());
        // Limited to the points of some vertices (the corners of a random half of the triangles): those points'
        // copies as before, every other vertex its own.
        std::vector<int> among;
        std::vector<std::uint8_t> point(static_cast<size_t>(positions.rows()), 0);  // a welded vertex's point is among
        for (Eigen::Index t = 0; t < seamed.rows(); ++t)
            if (std::uniform_real_distribution<double>(0.0, 1.0)(rng) < 0.5)
                for (int k = 0; k < 3; ++k) among.push_back(seamed(t, k)), point[static_cast<size_t>(origin[static_cast<size_t>(seamed(t, k))])] = 1;
        std::vector<int> expected(origin.size());
        for (size_t v = 0; v < origin.size(); ++v) expected[v] = point[static_cast<size_t>(origin[v])] ? origin[v] : static_cast<int>(v);
        std::vector<int> limited = seamCopiesOf(seamedPositions, among);
        if (limited.empty())  // (no point among them has two copies: every vertex its own)
            for (size_t v = 0; v < origin.size(); ++v) limited.push_back(static_cast<int>(v));
        CHECK(limited == expected);
        REQUIRE(weldedAtSeams(seamed, copies) == triangles);
        LatticeSettings settings;
        settings.resolution = {test::randomInt(rng, 5, 8), test::randomInt(rng, 5, 8), test::randomInt(rng, 4, 6)};
        settings.pinLayers = 1;
        Session welded, split;
        REQUIRE(welded.setMesh(positions, triangles, settings).ok);
        REQUIRE(split.setMesh(seamedPositions, seamed, settings).ok);
        const double diagonal = diagonalOf(positions);
        OpReport report, splitReport;
        for (int drag = 0; drag < 2; ++drag) {
            const int v = test::randomInt(rng, 0, static_cast<int>(positions.rows()) - 1);
            const Eigen::Vector3d target = welded.mesh().positions.row(v).transpose() + 0.15 * diagonal * test::randomVector(rng, -1, 1);
            REQUIRE(welded.dragVertex(v, target, report).ok);
            REQUIRE(split.dragVertex(v, target, splitReport).ok);
            REQUIRE(splitReport.status == report.status);
        }
        const Triangles coarse = split.mesh().triangles;
        const Positions dragged = split.mesh().positions;
        const double tolerance = std::uniform_real_distribution<double>(0.002, 0.01)(rng);
        REQUIRE(welded.refinement().refine(tolerance, report).ok);
        REQUIRE(split.refinement().refine(tolerance, splitReport).ok);
        INFO("trial " << trial << ": " << report.reason << " / " << splitReport.reason);
        REQUIRE(splitReport.status == report.status);
        if (report.status != OpStatus::Applied) continue;
        ++refined;
        // The same surface: each triangle of the seamed result, by its corners' points, is one of the welded
        // result's, and the other way round (as sorted lists of point triples, bit for bit).
        const auto pointTriples = [](const Positions& x, const Triangles& t) {
            std::vector<std::array<double, 9>> out;
            for (Eigen::Index i = 0; i < t.rows(); ++i) {
                std::array<double, 9> p;
                for (int k = 0; k < 3; ++k)
                    for (int c = 0; c < 3; ++c) p[static_cast<size_t>(3 * k + c)] = x(t(i, k), c);
                out.push_back(p);
            }
            std::sort(out.begin(), out.end());
            return out;
        };
        CHECK(pointTriples(split.mesh().positions, split.mesh().triangles) == pointTriples(welded.mesh().positions, welded.mesh().triangles));
        CHECK(splitReport.verticesAdded >= report.verticesAdded);
        // Undo takes every copy's split back, bit for bit.
        REQUIRE(split.undo(splitReport).ok);
        CHECK(sameBits(split.mesh().triangles, coarse));
        CHECK(sameBits(split.mesh().positions, dragged));
    }
    CHECK(refined >= 4);
}

TEST_CASE("refinement: the planner follows an analytic bump, its splits replay, revert and stop at the limits", "[refine]") {
    std::mt19937 rng(2024);
    for (int trial = 0; trial < 6; ++trial) {
        Positions rest;
        Triangles triangles;
        test::jitteredGrid(rng, test::randomInt(rng, 1, 6), test::randomInt(rng, 1, 6), 2.0, 1.0, rest, triangles);
        const double width = std::uniform_real_distribution<double>(0.1, 0.4)(rng);
        const Eigen::Vector3d centre(std::uniform_real_distribution<double>(0.3, 1.7)(rng), 0.5, 0.0);
        const RestImage image = [&](const Eigen::Vector3d& x) {
            const double r2 = (x - centre).head<2>().squaredNorm();
            return Eigen::Vector3d(x + Eigen::Vector3d(0.1 * x.y(), 0.0, 0.6 * std::exp(-r2 / (width * width))));
        };
        Positions current(rest.rows(), 3);
        for (Eigen::Index v = 0; v < rest.rows(); ++v) current.row(v) = image(rest.row(v).transpose()).transpose();
        RefinementOptions options;
        options.tolerance = 0.003;
        RefinementResult result;
        REQUIRE(refineMesh(rest, current, triangles, image, options, result).ok);
        INFO("trial " << trial << ": " << result.stopped);
        REQUIRE(result.converged);
        REQUIRE(result.worstAfter <= result.toleranceWorld);
        REQUIRE(result.worstBefore > result.toleranceWorld);
        REQUIRE(result.rest.rows() == rest.rows() + static_cast<Eigen::Index>(result.splits.size()));
        const std::vector<double> d = test::sampledDeviations(result.rest, result.current, result.triangles, image, 10);
        REQUIRE(*std::max_element(d.begin(), d.end()) <= result.toleranceWorld);
        requireConforming(result.rest, result.triangles, triangles);
        // The splits alone reproduce the refined mesh; the halvings undo it exactly.
        Triangles replayed = triangles;
        std::vector<TriangleHalving> halvings;
        REQUIRE(applyEdgeSplits(replayed, static_cast<int>(rest.rows()), result.splits, &halvings).ok);
        REQUIRE(sameBits(replayed, result.triangles));
        Positions midpoints = rest;
        appendSplitMidpoints(midpoints, result.splits);
        REQUIRE(sameBits(midpoints, result.rest));
        revertEdgeSplits(replayed, halvings);
        REQUIRE(sameBits(replayed, triangles));
        // A split that names no edge is refused, triangles untouched.
        std::vector<EdgeSplit> wrong = result.splits;
        wrong.push_back({0, static_cast<int>(result.rest.rows()) + 5});
        Triangles untouched = triangles;
        REQUIRE_FALSE(applyEdgeSplits(untouched, static_cast<int>(rest.rows()), wrong).ok);
        REQUIRE(sameBits(untouched, triangles));

        // The limits stop it short, still conforming.
        RefinementOptions few = options;
        few.maxVertices = static_cast<int>(rest.rows()) + 3;
        REQUIRE(refineMesh(rest, current, triangles, image, few, result).ok);
        REQUIRE_FALSE(result.converged);
        REQUIRE(result.stopped == "max vertices");
        REQUIRE(result.rest.rows() == few.maxVertices);
        requireConforming(result.rest, result.triangles, triangles);
        RefinementOptions once = options;
        once.maxRounds = 1;
        REQUIRE(refineMesh(rest, current, triangles, image, once, result).ok);
        REQUIRE(result.stopped == "max rounds");
        REQUIRE(result.rounds == 1);
        REQUIRE(result.trianglesOver > 0);
        requireConforming(result.rest, result.triangles, triangles);
    }
    // A jump in the image (as at the box of a lattice whose outer control points moved) is never resolved:
    // the refinement stops at the smallest size, conforming, with a bounded number of vertices.
    {
        Positions rest;
        Triangles triangles;
        test::jitteredGrid(rng, 3, 2, 2.0, 1.0, rest, triangles);
        const RestImage jump = [](const Eigen::Vector3d& x) { return Eigen::Vector3d(x + Eigen::Vector3d(0.0, 0.0, x.x() > 1.03 ? 0.3 : 0.0)); };
        Positions current(rest.rows(), 3);
        for (Eigen::Index v = 0; v < rest.rows(); ++v) current.row(v) = jump(rest.row(v).transpose()).transpose();
        RefinementOptions options;
        options.tolerance = 0.004;
        RefinementResult result;
        REQUIRE(refineMesh(rest, current, triangles, jump, options, result).ok);
        REQUIRE_FALSE(result.converged);
        REQUIRE(result.stopped == "smallest size");
        REQUIRE(result.rest.rows() < 5000);
        requireConforming(result.rest, result.triangles, triangles);
    }
    RefinementOptions bad;
    bad.tolerance = std::numeric_limits<double>::quiet_NaN();
    RefinementResult result;
    Positions rest;
    Triangles triangles;
    twoQuads(rest, triangles);
    REQUIRE_FALSE(refineMesh(rest, rest, triangles, [](const Eigen::Vector3d& x) { return x; }, bad, result).ok);
}

TEST_CASE("refinement: the deviation of a quadratic patch is bounded by the estimate, an affine one has none", "[refine]") {
    std::mt19937 rng(77);
    for (int trial = 0; trial < 200; ++trial) {
        const Eigen::Vector3d a = test::randomVector(rng, -1, 1), b = test::randomVector(rng, -1, 1), c = test::randomVector(rng, -1, 1);
        Eigen::Matrix3d linear = Eigen::Matrix3d::Identity() + 0.3 * Eigen::Matrix3d::Random();
        const Eigen::Vector3d offset = test::randomVector(rng, -1, 1);
        Eigen::Matrix3d quadratic[3];
        for (auto& q : quadratic) q = Eigen::Matrix3d::Random() * 0.5;
        const RestImage affine = [&](const Eigen::Vector3d& x) { return Eigen::Vector3d(linear * x + offset); };
        const RestImage curved = [&](const Eigen::Vector3d& x) {
            return Eigen::Vector3d(linear * x + offset + Eigen::Vector3d(x.dot(quadratic[0] * x), x.dot(quadratic[1] * x), x.dot(quadratic[2] * x)));
        };
        REQUIRE(triangleDeviation(a, b, c, affine(a), affine(b), affine(c), affine) <= 1e-14 * 16);
        const double estimate = triangleDeviation(a, b, c, curved(a), curved(b), curved(c), curved);
        Positions rest(3, 3), current(3, 3);
        rest << a.transpose(), b.transpose(), c.transpose();
        current << curved(a).transpose(), curved(b).transpose(), curved(c).transpose();
        const Triangles one = (Triangles(1, 3) << 0, 1, 2).finished();
        const double sampled = test::sampledDeviations(rest, current, one, curved, 24)[0];
        REQUIRE(sampled <= estimate * (1.0 + 1e-12) + 1e-14);
    }
}

TEST_CASE("refinement: the automatic option refines every edit in the same history entry", "[refine]") {
    Positions positions;
    Triangles triangles;
    twoQuads(positions, triangles);
    Session session;
    REQUIRE(session.setMesh(positions, triangles, ridgeLattice()).ok);
    RefinementSettings settings;
    settings.automatic = true;
    settings.options.tolerance = 0.004;
    REQUIRE(session.refinement().set(settings).ok);
    REQUIRE(session.history().journal().back().kind == JournalEntry::Kind::Refinement);
    OpReport report;
    raiseRidge(session, 0.4, report);
    REQUIRE(report.verticesAdded > 0);
    REQUIRE(session.history().size() == 1);
    REQUIRE(session.history().back().kind == OperationKind::ControlPointEdit);
    REQUIRE_FALSE(session.history().back().refinement.empty());
    requireWithin(session, 0.004 * diagonalOf(session.mesh().positions.topRows(6)));
    const Positions after = session.mesh().positions;
    const Triangles afterTriangles = session.mesh().triangles;
    // One undo takes back the edit and its refinement.
    REQUIRE(session.undo(report).ok);
    REQUIRE(sameBits(session.mesh().triangles, triangles));
    REQUIRE((session.mesh().positions - positions).cwiseAbs().maxCoeff() <= 1e-12);
    REQUIRE(session.redo(report).ok);
    REQUIRE(sameBits(session.mesh().triangles, afterTriangles));
    REQUIRE((session.mesh().positions - after).cwiseAbs().maxCoeff() <= 1e-12);

    // An interactive (control-point) drag is refined when it ends, in its own history entry.
    const int entries = static_cast<int>(session.history().size());
    const int vertices = static_cast<int>(session.mesh().positions.rows());
    std::vector<int> slab;
    for (int k = 0; k < session.lattice().count[2]; ++k)
        for (int j = 0; j < session.lattice().count[1]; ++j) slab.push_back(session.lattice().index(4, j, k));
    REQUIRE(session.stroke().beginControl(slab).ok);
    for (int step = 1; step <= 4; ++step) REQUIRE(session.stroke().updateControl(Eigen::Vector3d(0.0, 0.0, 0.08 * step), report).ok);
    REQUIRE(report.status == OpStatus::Applied);
    REQUIRE(session.mesh().positions.rows() == vertices);  // not while dragging
    session.stroke().end();
    REQUIRE(static_cast<int>(session.history().size()) == entries + 1);
    REQUIRE(session.mesh().positions.rows() > vertices);
    REQUIRE(session.history().back().kind == OperationKind::ControlPointEdit);
    REQUIRE_FALSE(session.history().back().refinement.empty());
    REQUIRE(session.history().back().interactive);
    REQUIRE(session.undo(report).ok);
    REQUIRE(session.mesh().positions.rows() == vertices);
    REQUIRE(sameBits(session.mesh().triangles, afterTriangles));
    // appliedSplits: the mesh as set, split by them, is the session's.
    REQUIRE(session.redo(report).ok);
    Triangles replayed = triangles;
    REQUIRE(applyEdgeSplits(replayed, 6, session.refinement().appliedSplits()).ok);
    REQUIRE(sameBits(replayed, session.mesh().triangles));
}

TEST_CASE("refinement: new vertices follow the cage through its layers and after a lattice set-up", "[refine]") {
    std::mt19937 rng(31);
    Positions positions;
    Triangles triangles;
    test::jitteredGrid(rng, 4, 3, 2.0, 1.5, positions, triangles);
    Session session;
    LatticeSettings settings;
    settings.resolution = {7, 7, 5};
    REQUIRE(session.setMesh(positions, triangles, settings).ok);
    session.setTrackJacobian(true);
    const double diagonal = diagonalOf(positions);
    OpReport report;
    // A brush drag, refined automatically while its layer is there, then baked into the rest shape (an explicit
    // refine afterwards finds the baked surface flat between its vertices); a set-up freezes the cage and starts a
    // new one; another brush drag.
    RefinementSettings automatic;
    automatic.automatic = true;
    automatic.options.tolerance = 0.003;
    REQUIRE(session.refinement().set(automatic).ok);
    BrushSettings brush;
    brush.radius = 0.5;
    REQUIRE(session.dragVertex(7, session.mesh().positions.row(7).transpose() + Eigen::Vector3d(0.0, 0.0, 0.3), report, brush).ok);
    REQUIRE(report.status == OpStatus::Applied);
    REQUIRE(session.cage().layers().empty());
    REQUIRE(session.history().back().steps.back().baked);
    for (Eigen::Index v = 0; v < session.mesh().positions.rows(); ++v)
        REQUIRE((session.cage().imageOfRestPoint(session.mesh().rest.row(v).transpose()) - session.mesh().positions.row(v).transpose()).norm() <= 1e-12 * diagonal);
    REQUIRE(session.mesh().positions.rows() > positions.rows());  // refined with the stroke
    REQUIRE(session.refinement().refine(0.003, report).ok);
    REQUIRE(report.status == OpStatus::NoOp);
    REQUIRE(session.totalJacobianDeterminants().size() == static_cast<size_t>(session.mesh().positions.rows()));
    const Positions refined = session.mesh().positions;
    REQUIRE(session.setupLattice(settings, report).ok);
    const Eigen::Index before = session.mesh().positions.rows();
    REQUIRE(session.dragVertex(12, session.mesh().positions.row(12).transpose() + Eigen::Vector3d(0.1, 0.0, -0.2), report, brush).ok);
    REQUIRE(report.status == OpStatus::Applied);
    REQUIRE(session.mesh().positions.rows() > before);
    for (Eigen::Index v = 0; v < session.mesh().positions.rows(); ++v)
        REQUIRE((session.cage().imageOfRestPoint(session.mesh().rest.row(v).transpose()) - session.mesh().positions.row(v).transpose()).norm() <= 1e-12 * diagonal);
    // Undo everything: the input mesh again.
    while (session.history().cursor() > 0) REQUIRE(session.undo(report).ok);
    REQUIRE(sameBits(session.mesh().triangles, triangles));
    REQUIRE((session.mesh().positions - positions).cwiseAbs().maxCoeff() <= 1e-9 * diagonal);
    while (session.history().cursor() < static_cast<int>(session.history().size())) REQUIRE(session.redo(report).ok);
    REQUIRE(session.mesh().positions.rows() > refined.rows());
    requireConforming(session.mesh().rest, session.mesh().triangles, triangles);
}

TEST_CASE("refinement: the triangle check refuses a refinement that would make the surface cross itself", "[refine]") {
    // Two sheets 0.1 apart; the lattice holds only the lower one. A ridge between the lower sheet's vertices
    // moves none of them (the coarse mesh does not change, so the edit passes), but its image rises through the
    // upper sheet: refined, the lower sheet would cross it.
    Positions positions(12, 3);
    positions << 0, 0, 0, 1, 0, 0, 2, 0, 0, 0, 1, 0, 1, 1, 0, 2, 1, 0,  //
        0, 0, 0.1, 1, 0, 0.1, 2, 0, 0.1, 0, 1, 0.1, 1, 1, 0.1, 2, 1, 0.1;
    Triangles triangles(8, 3);
    triangles << 0, 1, 4, 0, 4, 3, 1, 2, 5, 1, 5, 4, 6, 7, 10, 6, 10, 9, 7, 8, 11, 7, 11, 10;
    LatticeSettings settings;
    settings.resolution = {17, 4, 4};
    settings.padding = 0.0;
    settings.hasRegion = true;
    settings.regionMin = Eigen::Vector3d(0.0, 0.0, -0.04);
    settings.regionMax = Eigen::Vector3d(2.0, 1.0, 0.04);
    for (bool checking : {true, false}) {
        Session session;
        REQUIRE(session.setMesh(positions, triangles, settings).ok);
        if (!checking) session.setInjectivity({InjectivityMode::Off, 6, false});
        const Lattice& lattice = session.lattice();
        std::vector<int> ids;
        for (int k = 0; k < lattice.count[2]; ++k)
            for (int j = 0; j < lattice.count[1]; ++j) ids.push_back(lattice.index(4, j, k));  // near x = 0.5
        Eigen::MatrixX3d offsets(static_cast<Eigen::Index>(ids.size()), 3);
        offsets.rowwise() = Eigen::RowVector3d(0.0, 0.0, 0.3);
        OpReport report;
        REQUIRE(session.moveControlPoints(ids, offsets, true, report).ok);
        REQUIRE(report.status == OpStatus::Applied);
        REQUIRE(sameBits(session.mesh().positions, positions));  // no vertex in reach
        REQUIRE(session.cage().imageOfRestPoint(Eigen::Vector3d(0.5, 0.5, 0.0)).z() > 0.1);
        REQUIRE(session.refinement().refine(0.002, report).ok);
        if (checking) {
            INFO(report.reason);
            REQUIRE(report.status == OpStatus::Rejected);
            REQUIRE(report.refusedBy == "triangles");
            REQUIRE(report.reason.find("pass through itself") != std::string::npos);
            REQUIRE(sameBits(session.mesh().positions, positions));
            REQUIRE(sameBits(session.mesh().triangles, triangles));
            REQUIRE(session.history().size() == 1);
        } else {
            REQUIRE(report.status == OpStatus::Applied);
            REQUIRE(session.mesh().positions.rows() > positions.rows());
        }
    }
}

TEST_CASE("refinement: a group with refinements undoes and redoes as one entry", "[refine]") {
    Positions positions;
    Triangles triangles;
    twoQuads(positions, triangles);
    Session session;
    REQUIRE(session.setMesh(positions, triangles, ridgeLattice()).ok);
    OpReport report;
    raiseRidge(session, 0.3, report);
    REQUIRE(session.refinement().refine(0.003, report).ok);
    raiseRidge(session, 0.1, report);
    REQUIRE(session.refinement().refine(0.002, report).ok);
    const Triangles refined = session.mesh().triangles;
    const Positions shape = session.mesh().positions;
    REQUIRE(session.groupOperations(0, "ridge").ok);
    REQUIRE(session.history().size() == 1);
    REQUIRE(session.history().front().kind == OperationKind::ControlPointEdit);
    REQUIRE(session.undo(report).ok);
    REQUIRE(sameBits(session.mesh().triangles, triangles));
    REQUIRE((session.mesh().positions - positions).cwiseAbs().maxCoeff() <= 1e-12);
    REQUIRE(session.redo(report).ok);
    REQUIRE(sameBits(session.mesh().triangles, refined));
    REQUIRE((session.mesh().positions - shape).cwiseAbs().maxCoeff() <= 1e-12);
    // A set-up after a refinement cannot join its group.
    REQUIRE(session.setupLattice(ridgeLattice(), report).ok);
    REQUIRE_FALSE(session.groupOperations(0, "").ok);
}

// A brush's field squeezes the space ahead of a long pull to a quarter of its length (brush_field.h), so the image
// of a rest edge's midpoint lies far from the middle of the edge's image. Splitting the longest edge of the current
// shape then split the edges of one triangle towards a fixed pair of points, again and again (a stroke's plan on
// CGAL's camel held 6,852 triangles whose corners coincided, and its crossing search took 15 s): the longest-edge
// bisection is made in rest space, where Rivara's bound keeps every triangle's angles.
TEST_CASE("refinement: under a brush field that squeezes space, no split makes triangles with coinciding corners, and rest angles keep Rivara's bound", "[refine]") {
    std::mt19937 rng(4242);
    for (int trial = 0; trial < 12; ++trial) {
        Positions rest;
        Triangles triangles;
        test::icosphere(2 + trial % 2, 1.0, Eigen::Vector3d::Zero(), rest, triangles);
        // A pull of 2-3 radii from a random vertex, along its normal, a tangent or inward, with a random falloff.
        const int v = test::randomInt(rng, 0, static_cast<int>(rest.rows()) - 1);
        const double radius = std::uniform_real_distribution<double>(0.2, 0.5)(rng);
        const Eigen::Vector3d n = rest.row(v).transpose().normalized();
        const Eigen::Vector3d direction = trial % 3 == 0 ? n : trial % 3 == 1 ? n.unitOrthogonal() : Eigen::Vector3d(-n);
        const BrushPull pull{rest.row(v).transpose(), std::uniform_real_distribution<double>(2.0, 3.0)(rng) * radius * direction};
        const BrushFalloff falloff = static_cast<BrushFalloff>(trial / 3 % 3);
        const RestImage image = [&](const Eigen::Vector3d& x) -> Eigen::Vector3d {
            return x + brushFieldWeight(pull, radius, falloff, x) * pull.pull;
        };
        Positions current(rest.rows(), 3);
        for (Eigen::Index r = 0; r < rest.rows(); ++r) current.row(r) = image(rest.row(r).transpose()).transpose();
        RefinementOptions options;
        options.tolerance = 0.02 * radius / diagonalOf(current);
        options.maxRounds = 6;
        options.shortestEdge = 0.04 * radius;
        RefinementResult result;
        REQUIRE(refineMesh(rest, current, triangles, image, options, result).ok);
        INFO("trial " << trial << ": " << result.splits.size() << " splits, " << result.rounds << " rounds");
        REQUIRE(!result.splits.empty());
        requireConforming(result.rest, result.triangles, triangles);
        // The smallest angle of a triangle in rest space; Rivara: longest-edge bisection keeps at least half the
        // smallest angle the mesh began with.
        const auto smallestAngle = [](const Positions& x, const Triangles& t, Eigen::Index row) {
            double smallest = M_PI;
            for (int k = 0; k < 3; ++k) {
                const Eigen::Vector3d a = x.row(t(row, k)).transpose(), b = x.row(t(row, (k + 1) % 3)).transpose(), c = x.row(t(row, (k + 2) % 3)).transpose();
                smallest = std::min(smallest, std::acos(std::clamp((b - a).normalized().dot((c - a).normalized()), -1.0, 1.0)));
            }
            return smallest;
        };
        double before = M_PI, after = M_PI;
        for (Eigen::Index t = 0; t < triangles.rows(); ++t) before = std::min(before, smallestAngle(rest, triangles, t));
        for (Eigen::Index t = 0; t < result.triangles.rows(); ++t) after = std::min(after, smallestAngle(result.rest, result.triangles, t));
        CHECK(after >= 0.5 * before);
        // No triangle has coinciding or collinear corners at the image (the field is injective: det J >= 0.25).
        int degenerate = 0;
        for (Eigen::Index t = 0; t < result.triangles.rows(); ++t) {
            const Eigen::Vector3d a = result.current.row(result.triangles(t, 0)).transpose(), b = result.current.row(result.triangles(t, 1)).transpose(),
                                  c = result.current.row(result.triangles(t, 2)).transpose();
            degenerate += (b - a).cross(c - a).norm() <= 1e-12 * (b - a).squaredNorm() + 1e-300;
        }
        CHECK(degenerate == 0);
    }
}
