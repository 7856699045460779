// Lattices of any shape in the session (Coquillart 1990, EFFD, 3.2-3.4): freezing a lattice tool, deforming
// with it (drags solved on its basis, control-point moves), undo as the inverse manipulation, several lattices
// per mesh one after another, and recordings that replay exactly.
#include <catch2/catch.hpp>

#include <memory>
#include <random>

#include "core/injectivity/injectivity.h"
#include "core/volume/lattice_net.h"
#include "io/script.h"
#include "core/session/session.h"
#include "io/script_json.h"
#include "../mesh_fixtures.h"
#include "../test_support.h"
#include "../../test_scale.h"

using namespace sculpt;
using namespace sculpt::core;
using namespace sculpt::io;

namespace {

// A sphere mesh of radius 1 at the origin and a session on it (box lattice first, as setMesh makes it).
Session sphereSession(int levels, InjectivityMode mode = InjectivityMode::Exact) {
    Positions positions;
    Triangles triangles;
    test::icosphere(levels, 1.0, Eigen::Vector3d::Zero(), positions, triangles);
    Session session;
    LatticeSettings box;
    box.resolution = {5, 5, 5};
    box.degree = {3, 3, 3};
    REQUIRE(session.setMesh(positions, triangles, box));
    InjectivitySettings injectivity;
    injectivity.mode = mode;
    session.setInjectivity(injectivity);
    return session;
}

LatticeTool cylinderTool(std::mt19937& rng) {
    LatticeNet net;
    // A cylinder through the sphere along a random direction, wider than it in part of the runs (so some
    // vertices are outside the lattice and must not move).
    const Eigen::Vector3d axis = test::randomVector(rng, -1, 1).normalized();
    const double radius = std::uniform_real_distribution<double>(0.6, 1.3)(rng);
    REQUIRE(makeCylinderNet(-1.2 * axis, axis, radius, 2.4, {2, 8, 2}, {2, 2}, net));
    return {"cylinder", std::make_shared<const LatticeNet>(std::move(net))};
}

LatticeTool sphereTool() {
    LatticeNet net;
    REQUIRE(makeSphereNet(Eigen::Vector3d(0.3, 0, 0), Eigen::Vector3d::UnitZ(), 1.1, {2, 6, 4}, 2, net));
    return {"ball", std::make_shared<const LatticeNet>(std::move(net))};
}

}  // namespace

// Six trials in two runs of three (each with its own seed), so ctest runs them side by side.
static void runFrozenCylinderDrags(unsigned seed, int firstTrial, int trialCount) {
    std::mt19937 rng(seed);
    const int trials = test::scaledCount(trialCount, 1);
    for (int trial = firstTrial; trial < firstTrial + trials; ++trial) {
        Session session = sphereSession(3);
        const Positions original = session.mesh().positions;
        OpReport report;
        REQUIRE(session.tools().add(cylinderTool(rng), report));
        REQUIRE(session.tools().freeze(0, trial % 2, report));
        REQUIRE(report.status == OpStatus::Applied);
        REQUIRE(session.tools().frozen() == 0);
        REQUIRE(session.lattice().volume);
        REQUIRE(session.mesh().positions == original);  // freezing moves nothing
        // Which vertices are inside the cylinder: only those may ever move.
        std::vector<bool> inside(original.rows());
        for (int v = 0; v < original.rows(); ++v) {
            Eigen::Vector3d t;
            inside[v] = restParameters(session.lattice(), original.row(v).transpose(), t);
        }
        int applied = 0;
        for (int drag = 0; drag < 4; ++drag) {
            int vertex = test::randomInt(rng, 0, static_cast<int>(original.rows()) - 1);
            while (!inside[vertex]) vertex = test::randomInt(rng, 0, static_cast<int>(original.rows()) - 1);
            const Eigen::Vector3d target = session.mesh().positions.row(vertex).transpose() + test::randomVector(rng, -0.15, 0.15);
            REQUIRE(session.dragVertex(vertex, target, report));
            INFO(report.reason << " / " << report.injectivity);
            if (report.status != OpStatus::Applied) continue;
            ++applied;
            if (!report.rankDeficient) REQUIRE((session.mesh().positions.row(vertex).transpose() - target).norm() <= 1e-9);
            // Certified on the net lattice (exact test, rational chunks included).
            REQUIRE(checkInjectivityExact(session.lattice()).verdict != InjectivityVerdict::Fold);
        }
        INFO(report.reason << " / " << report.injectivity);
        CHECK(applied > 0);
        for (int v = 0; v < original.rows(); ++v)
            if (!inside[v]) REQUIRE(session.mesh().positions.row(v) == original.row(v));  // outside every chunk: never moves
        // Unfreeze keeps the shape; undo everything returns to the original mesh.
        const Positions sculpted = session.mesh().positions;
        {
            const Positions restBefore = session.mesh().rest;
            const size_t layersBefore = session.cage().layers().size();
            REQUIRE(session.tools().unfreeze(report));
            REQUIRE(session.undo(report));
            INFO("layers " << layersBefore);
            REQUIRE((session.mesh().rest - restBefore).cwiseAbs().maxCoeff() <= 1e-12);  // the frozen net inverted by Newton
            REQUIRE(session.redo(report));
            REQUIRE(session.undo(report));
        }
        REQUIRE(session.tools().unfreeze(report));
        REQUIRE(session.tools().frozen() == -1);
        REQUIRE(session.mesh().positions == sculpted);
        while (session.history().cursor() > 0) REQUIRE(session.undo(report));
        REQUIRE(session.tools().list().empty());
        REQUIRE((session.mesh().positions - original).cwiseAbs().maxCoeff() <= 1e-9);
    }
}

TEST_CASE("effd session: drags on a frozen cylinder meet their targets and undo restores the mesh, part 1 of 2", "[core][net][effd]") {
    runFrozenCylinderDrags(50, 0, 3);
}
TEST_CASE("effd session: drags on a frozen cylinder meet their targets and undo restores the mesh, part 2 of 2", "[core][net][effd]") {
    runFrozenCylinderDrags(150, 3, 3);
}

TEST_CASE("effd session: several lattices in turn, moved control points, and a recording that replays bitwise", "[core][net][effd]") {
    std::mt19937 rng(51);
    Session session = sphereSession(3, InjectivityMode::Conic);
    OpReport report;
    REQUIRE(session.tools().add(cylinderTool(rng), report));
    REQUIRE(session.tools().add(sphereTool(), report));
    REQUIRE(session.tools().freeze(0, 0, report));
    // Move the cylinder's axis (one welded point per slice) and a ring point.
    const Lattice& cylinder = session.lattice();
    const int axisPoint = cylinder.index(0, 0, 2);
    REQUIRE(session.moveControlPoints({axisPoint}, Eigen::RowVector3d(0.05, 0.02, 0.1), true, report));
    REQUIRE(report.status == OpStatus::Applied);
    for (int j = 0; j < cylinder.count[1]; ++j)  // the whole welded group moved
        REQUIRE(session.lattice().displacement.row(cylinder.index(0, j, 2)) == session.lattice().displacement.row(axisPoint));
    REQUIRE(session.dragVertex(5, session.mesh().positions.row(5).transpose() + Eigen::Vector3d(0, 0, 0.1), report));
    REQUIRE(session.tools().unfreeze(report));
    REQUIRE(session.tools().freeze(1, 1, report));
    REQUIRE(session.tools().frozen() == 1);
    REQUIRE(session.dragVertex(40, session.mesh().positions.row(40).transpose() + Eigen::Vector3d(0.1, 0, 0), report));
    REQUIRE(session.undo(report));
    REQUIRE(session.redo(report));
    const Positions final = session.mesh().positions;

    // The recording replays bitwise on the same mesh, through its JSON text.
    const Script recorded = recordSession(session);
    Script parsed;
    REQUIRE(io::parseScript(io::scriptToJson(recorded), "recording.json", parsed));
    Session replay = sphereSession(3, InjectivityMode::Conic);
    LatticeSettings start = parsed.lattice;
    REQUIRE(replay.setMesh(replay.mesh().original, replay.mesh().triangles, start));
    ScriptReport scriptReport;
    REQUIRE(runScript(replay, parsed, scriptReport));
    REQUIRE(replay.mesh().positions == final);
    REQUIRE(replay.tools().list().size() == 2);
    REQUIRE(replay.tools().frozen() == 1);
    // Undo in the replay walks back through the freezes to the original mesh.
    while (replay.history().cursor() > 0) REQUIRE(replay.undo(report));
    REQUIRE((replay.mesh().positions - replay.mesh().original).cwiseAbs().maxCoeff() <= 1e-9);

    // On another mesh (a finer sphere) the same recording is decided again: the lattices are frozen on it.
    Session other = sphereSession(4, InjectivityMode::Conic);
    REQUIRE(runScript(other, parsed, scriptReport));
    REQUIRE(other.tools().frozen() == 1);
    REQUIRE(other.tools().list().size() == 2);
}

TEST_CASE("effd session: bad lattice input is refused and changes nothing", "[core][net][effd]") {
    Session session = sphereSession(2);
    OpReport report;
    REQUIRE_FALSE(session.tools().add(LatticeTool{"empty", nullptr}, report));
    REQUIRE_FALSE(session.tools().freeze(0, 0, report));
    REQUIRE(session.tools().add(sphereTool(), report));
    REQUIRE(session.tools().freeze(0, 0, report));
    REQUIRE_FALSE(session.tools().edit(0, sphereTool(), report));  // frozen: unfreeze first
    REQUIRE_FALSE(session.tools().remove(0, report));
    REQUIRE(session.history().cursor() == 2);
    Script script;
    const std::string bad = R"({"ops": [{"op": "add_lattice", "lattice": {"kind": "cylinder", "base": [0,0,0], "axis": [0,0,0], "radius": 1, "height": 1, "chunks": [1,4,1]}}]})";
    const Status parsed = io::parseScript(bad, "bad.json", script);
    REQUIRE_FALSE(parsed);
    INFO(parsed.message);
    REQUIRE(parsed.message.find("ops[0].lattice") != std::string::npos);
    REQUIRE(parsed.message.find("axis") != std::string::npos);
}

TEST_CASE("effd session: a welded point pins as one, and pins on a frozen net lattice replay", "[core][net][effd]") {
    std::mt19937 rng(52);
    Session session = sphereSession(3, InjectivityMode::Conic);
    OpReport report;
    REQUIRE(session.tools().add(cylinderTool(rng), report));
    REQUIRE(session.tools().freeze(0, 1, report));
    const Lattice& cylinder = session.lattice();
    // Pinning one slot of the axis pins every slot welded to it: a move through another copy is refused.
    REQUIRE(session.pins().set({cylinder.index(0, 0, 2)}, true));
    for (int j = 0; j < cylinder.count[1]; ++j) REQUIRE(session.lattice().pinned[cylinder.index(0, j, 2)]);
    REQUIRE_FALSE(session.moveControlPoints({cylinder.index(0, 5, 2)}, Eigen::RowVector3d(0, 0, 0.05), true, report));
    // The seam: the last angular slice is the first one.
    const int last = cylinder.count[1] - 1;
    REQUIRE(session.pins().set({cylinder.index(1, last, 2)}, true));
    REQUIRE(session.lattice().pinned[cylinder.index(1, 0, 2)]);
    // Unpinning a pin-layer point and a drag, recorded and replayed through the script's set_pins.
    REQUIRE(session.pins().set({cylinder.index(1, 0, 0)}, false));
    REQUIRE(session.dragVertex(7, session.mesh().positions.row(7).transpose() + Eigen::Vector3d(0.02, 0.03, 0.0), report));
    Script parsed;
    REQUIRE(io::parseScript(io::scriptToJson(recordSession(session)), "recording.json", parsed));
    Session replay = sphereSession(3, InjectivityMode::Conic);
    REQUIRE(replay.setMesh(replay.mesh().original, replay.mesh().triangles, parsed.lattice));
    ScriptReport scriptReport;
    const Status ran = runScript(replay, parsed, scriptReport);
    INFO(ran.message);
    REQUIRE(ran);
    REQUIRE(replay.mesh().positions == session.mesh().positions);
    REQUIRE(replay.lattice().pinned == session.lattice().pinned);
}

TEST_CASE("effd session: bad requests on lattices of any shape are errors that change nothing", "[core][net][effd]") {
    std::mt19937 rng(77);
    for (int trial = 0; trial < 4; ++trial) {
        Session session = sphereSession(2);
        OpReport report;
        // A lattice placed away from the mesh: freezing it is an error naming it, and nothing changes.
        LatticeNet far;
        const Eigen::Vector3d offset = 5.0 * test::randomVector(rng, -1, 1).normalized();
        REQUIRE(makeCylinderNet(offset, Eigen::Vector3d::UnitZ(), 0.5, 1.0, {1, 6, 1}, {2, 2}, far));
        REQUIRE(session.tools().add({"far", std::make_shared<const LatticeNet>(far)}, report));
        const size_t journal = session.history().journal().size();
        const Status frozen = session.tools().freeze(0, 0, report);
        REQUIRE_FALSE(frozen);
        REQUIRE(frozen.message.find("far holds none of the mesh's vertices") != std::string::npos);
        REQUIRE(session.tools().frozen() == -1);
        REQUIRE(session.history().journal().size() == journal);
        REQUIRE_FALSE(session.lattice().volume);
        // A brush radius beyond all scale of the mesh is an error naming the radius.
        const Positions before = session.mesh().positions;
        BrushSettings brush;
        brush.radius = std::pow(10.0, 10 + 50 * trial);
        const Status huge = session.drag({{before.row(0).transpose(), before.row(0).transpose() + Eigen::Vector3d(0, 0, 0.1)}}, report, brush);
        REQUIRE_FALSE(huge);
        REQUIRE(huge.message.find("brush radius") != std::string::npos);
        REQUIRE(huge.message.find("nan") == std::string::npos);
        REQUIRE(session.mesh().positions == before);
    }
}

TEST_CASE("effd session: copies of one welded point move once as the one control point they are", "[core][net][effd]") {
    Session session = sphereSession(3);
    OpReport report;
    LatticeNet net;
    REQUIRE(makeCylinderNet(Eigen::Vector3d(0, 0, -1.3), Eigen::Vector3d::UnitZ(), 1.3, 2.6, {2, 8, 2}, {2, 2}, net));
    REQUIRE(session.tools().add({"pie", std::make_shared<const LatticeNet>(net)}, report));
    REQUIRE(session.tools().freeze(0, 0, report));
    // Slots (0, 0, 2) and (0, 3, 2) are both the axis point of the middle slice.
    const Lattice& lattice = session.lattice();
    const int a = lattice.index(0, 0, 2), b = lattice.index(0, 3, 2);
    REQUIRE(lattice.representative(a) == lattice.representative(b));
    // Different moves for two copies of one point: an error naming both, and nothing changes.
    Eigen::MatrixX3d by(2, 3);
    by << 0.0, 0.0, 0.05, 0.0, 0.02, 0.0;
    const size_t journal = session.history().journal().size();
    const Status conflicting = session.moveControlPoints({a, b}, by, true, report);
    REQUIRE_FALSE(conflicting);
    REQUIRE(conflicting.message.find("[0,0,2] and [0,3,2] are one welded point") != std::string::npos);
    REQUIRE(session.history().journal().size() == journal);
    REQUIRE(isUndeformed(session.lattice()));
    // The same move for both (a whole ring listed, seam included): the point moves once, not twice.
    by.row(1) = by.row(0);
    REQUIRE(session.moveControlPoints({a, b}, by, true, report));
    REQUIRE(report.status == OpStatus::Applied);
    const Eigen::Vector3d moved = session.lattice().displacement.row(a).transpose();
    REQUIRE((moved - Eigen::Vector3d(0.0, 0.0, 0.05)).norm() <= 1e-15);
    // The same id listed twice keeps its meaning from the box lattice: "by" offsets add up.
    Eigen::MatrixX3d twice(2, 3);
    twice << 0.0, 0.01, 0.0, 0.0, 0.01, 0.0;
    REQUIRE(session.moveControlPoints({b, b}, twice, true, report));
    REQUIRE((session.lattice().displacement.row(a).transpose() - Eigen::Vector3d(0.0, 0.02, 0.05)).norm() <= 1e-15);
    for (int s = 0; s < session.lattice().controlPointCount(); ++s)
        if (session.lattice().representative(s) == session.lattice().representative(a))
            REQUIRE(session.lattice().displacement.row(s) == session.lattice().displacement.row(a));
}
