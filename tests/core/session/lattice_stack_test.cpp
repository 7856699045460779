// LatticeStack (lattice_stack.h): the composition through the cage and its layers, checked against the mesh the
// session keeps, after random drags (some subdivided into fresh layers), brush strokes (region layers baked into
// the rest shape), control-point moves, lattice set-ups (frozen frames) and undos, on icospheres of three sizes.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>

#include "core/session/session.h"
#include "../mesh_fixtures.h"

using namespace sculpt;
using namespace sculpt::core;

namespace {

double diagonalOf(const Positions& p) { return (p.colwise().maxCoeff() - p.colwise().minCoeff()).norm(); }

// The stack's queries against the session's mesh; returns the worst error of each, as a share of the diagonal.
struct StackErrors {
    double restImage = 0.0;      // |imageOfRestPoint(X0_v) - x_v|, every vertex
    double currentPoint = 0.0;   // |currentImage(parametersOfCurrentPoint(x_v)) - x_v|, vertices inside the cage
    double pulled = 0.0;         // |pushThroughLayers(pullThroughLayers(x_v)) - x_v|, vertices, with layers
    int located = 0;             // vertices parametersOfCurrentPoint found
};

StackErrors stackErrors(const Session& session, std::mt19937& rng) {
    const LatticeStack& stack = session.cage();
    const double diagonal = diagonalOf(session.mesh().positions);
    StackErrors e;
    for (Eigen::Index v = 0; v < session.mesh().positions.rows(); ++v) {
        const Eigen::Vector3d x = session.mesh().positions.row(v).transpose();
        e.restImage = std::max(e.restImage, (stack.imageOfRestPoint(session.mesh().rest.row(v).transpose()) - x).norm() / diagonal);
    }
    std::uniform_int_distribution<Eigen::Index> vertex(0, session.mesh().positions.rows() - 1);
    for (int k = 0; k < 20; ++k) {
        const Eigen::Index v = vertex(rng);
        Eigen::Vector3d rest;
        // Only vertices well inside the cage's box: near its faces Newton may start outside.
        if (!session.parametersOfVertex(static_cast<int>(v), rest).ok || (rest.array() < 0.05).any() || (rest.array() > 0.95).any()) continue;
        const Eigen::Vector3d x = session.mesh().positions.row(v).transpose();
        Eigen::Vector3d t;
        if (!stack.parametersOfCurrentPoint(x, t).ok) continue;
        ++e.located;
        e.currentPoint = std::max(e.currentPoint, (stack.currentImage(t) - x).norm() / diagonal);
    }
    const Positions shown = stack.cagePoints();
    REQUIRE(shown.rows() == stack.lattice().controlPointCount());
    for (Eigen::Index p = 0; p < shown.rows(); ++p)  // the definition, bit for bit
        REQUIRE(shown.row(p).transpose() == stack.pushThroughLayers(stack.lattice().controlPoint(static_cast<int>(p))));
    // A point of the surface traced back through the layers (as a drag's target is) is carried onto itself again.
    for (int k = 0; k < 20 && !stack.layers().empty(); ++k) {
        const Eigen::Vector3d x = session.mesh().positions.row(vertex(rng)).transpose();
        Eigen::Vector3d back;
        REQUIRE(stack.pullThroughLayers(x, back, stack.layers().size()));
        e.pulled = std::max(e.pulled, (stack.pushThroughLayers(back) - x).norm() / diagonal);
    }
    return e;
}

}  // namespace

TEST_CASE("lattice stack: the composition through cage, layers and frames agrees with the mesh after random operations", "[core]") {
    int withLayers = 0, withFrames = 0, located = 0, checked = 0;
    for (unsigned seed = 1; seed <= 6; ++seed) {
        std::mt19937 rng(seed);
        const int levels = 1 + static_cast<int>(seed % 3);  // 42, 162 or 642 vertices
        Positions positions;
        Triangles triangles;
        test::icosphere(levels, 1.0, Eigen::Vector3d::Zero(), positions, triangles);
        Session session;
        LatticeSettings settings;
        const int resolution = 4 + static_cast<int>(seed % 3);
        settings.resolution = {resolution, resolution, resolution};
        REQUIRE(session.setMesh(positions, triangles, settings).ok);
        std::uniform_real_distribution<double> unit(-1.0, 1.0), share(0.0, 1.0);
        for (int op = 0; op < 10; ++op) {
            OpReport report;
            const int v = std::uniform_int_distribution<int>(0, static_cast<int>(session.mesh().positions.rows()) - 1)(rng);
            const Eigen::Vector3d x = session.mesh().positions.row(v).transpose();
            const Eigen::Vector3d direction = Eigen::Vector3d(unit(rng), unit(rng), unit(rng)).normalized();
            switch (std::uniform_int_distribution<int>(0, 4)(rng)) {
                case 0:  // a drag, subdivided into fresh layers when one step would fold
                    REQUIRE(session.dragVertex(v, x + (0.2 + 0.8 * share(rng)) * direction, report).ok);
                    break;
                case 1: {  // a brush stroke: a region layer, baked into the rest shape when it ends
                    BrushSettings brush;
                    brush.radius = 0.3 + 0.3 * share(rng);
                    REQUIRE(session.dragVertex(v, x + brush.radius * share(rng) * x.normalized(), report, brush).ok);
                    break;
                }
                case 2: {  // a control point moved through the layers
                    const int p = std::uniform_int_distribution<int>(0, session.lattice().controlPointCount() - 1)(rng);
                    if (session.lattice().pinned[static_cast<size_t>(p)]) break;
                    Eigen::MatrixX3d by(1, 3);
                    by.row(0) = 0.1 * direction.transpose();
                    REQUIRE(session.moveControlPoints({p}, by, true, report).ok);
                    break;
                }
                case 3: {  // a set-up: the cage and its layers become a frozen frame
                    LatticeSettings fresh;
                    const int r = 4 + static_cast<int>(rng() % 4);
                    fresh.resolution = {r, r, r};
                    const Status s = session.setupLattice(fresh, report);
                    INFO(s.message);
                    REQUIRE(s.ok);
                    break;
                }
                default:
                    REQUIRE(session.undo(report).ok);
            }
            if (!session.cage().layers().empty()) ++withLayers;
            if (session.cage().frameDepth() > static_cast<int>(session.cage().layers().size())) ++withFrames;
            const StackErrors e = stackErrors(session, rng);
            INFO("seed " << seed << ", op " << op << ": " << report.op << " " << report.reason << "; layers " << session.cage().layers().size()
                         << ", depth " << session.cage().frameDepth());
            CHECK(e.restImage <= 1e-9);
            CHECK(e.currentPoint <= 1e-8);
            CHECK(e.pulled <= 1e-8);
            located += e.located;
            ++checked;
        }
    }
    INFO(checked << " states checked, " << withLayers << " with layers, " << withFrames << " with frozen frames");
    // The random operations reached the cases the stack exists for.
    REQUIRE(withLayers > 0);
    REQUIRE(withFrames > 0);
    REQUIRE(located > 5 * checked);
}
