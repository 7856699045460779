// Weighted T-spline tools in scripts (Song & Yang 2005, seed 002): setup_tspline (sec. 4 / sec. 6 steps 1-3)
// builds and freezes an octree T-spline around the mesh, drags on it meet their targets under the exact
// injectivity test, undo restores the mesh, subdivide_cells (sec. 6 step 2, Fig. 11) edits an unfrozen tool,
// bad requests change nothing, and recordings (which write the resulting tools explicitly) replay bitwise.
#include <catch2/catch.hpp>

#include <memory>
#include <string>

#include "../core/mesh_fixtures.h"
#include "io/script.h"
#include "core/session/session.h"
#include "core/tspline/tspline_volume.h"
#include "io/lattice_json.h"
#include "io/script_json.h"
#include "replay_support.h"

using namespace sculpt;
using namespace sculpt::core;
using namespace sculpt::io;

namespace {

struct Mesh {
    Positions positions;
    Triangles triangles;
};

// A sphere of radius 1, a little off the origin so no vertex lies on a knot plane by symmetry.
Mesh sphereMesh(int levels) {
    Mesh mesh;
    test::icosphere(levels, 1.0, Eigen::Vector3d(0.013, -0.007, 0.004), mesh.positions, mesh.triangles);
    return mesh;
}

Script parse(const std::string& text) {
    Script script;
    const Status parsed = io::parseScript(text, "tspline.json", script);
    INFO(parsed.message);
    REQUIRE(parsed);
    return script;
}

// Runs `text` on `session`; `ran` gets runScript's status.
ScriptReport run(Session& session, const std::string& text, Status& ran) {
    const Script script = parse(text);
    session.setInjectivity(script.injectivity);
    ScriptReport report;
    ran = runScript(session, script, report);
    return report;
}

Session sessionOn(const Mesh& mesh) {
    Session session;
    REQUIRE(session.setMesh(mesh.positions, mesh.triangles, LatticeSettings{}));
    return session;
}

double diagonalOf(const Positions& positions) { return (positions.colwise().maxCoeff() - positions.colwise().minCoeff()).norm(); }

const TSplineVolume& tsplineOf(const Session& session, int index) {
    const auto* volume = dynamic_cast<const TSplineVolume*>(session.tools().list()[static_cast<size_t>(index)].volume.get());
    REQUIRE(volume);
    return *volume;
}

}  // namespace

TEST_CASE("tspline script: setup_tspline freezes an octree T-spline and multi-point drags with pins meet their targets", "[tspline][io][script][session]") {
    const Mesh mesh = sphereMesh(3);
    Session session = sessionOn(mesh);
    const double diagonal = diagonalOf(mesh.positions);
    Status ran;
    ScriptReport report = run(session, R"({"injectivity": {"mode": "exact"}, "ops": [{"op": "setup_tspline", "depth": 3}]})", ran);
    INFO(ran.message);
    REQUIRE(ran);
    INFO(report.ops[0].reason);
    REQUIRE(report.ops[0].status == OpStatus::Applied);
    // One history entry: the tool added and frozen, undone together (Operation::parts).
    REQUIRE(session.history().size() == 1);
    REQUIRE(session.history()[0].parts.size() == 2);
    REQUIRE(session.tools().list().size() == 1);
    REQUIRE(session.tools().list()[0].name == "tspline");
    REQUIRE(session.tools().frozen() == 0);
    REQUIRE(session.cage().embedding().insideCount() == static_cast<int>(mesh.positions.rows()));  // the padded box holds every vertex
    REQUIRE(session.mesh().positions == mesh.positions);  // freezing moves nothing
    // Sec. 4: every cell holding a vertex at the full depth, weights 100:1, balanced (100, 10 next to them, 1).
    const TSplineVolume& volume = tsplineOf(session, 0);
    REQUIRE(volume.lattice().maxLevel == 3);
    int heavy = 0;
    for (double w : volume.controlWeights()) {
        REQUIRE((w == 1.0 || w == 10.0 || w == 100.0));
        heavy += w == 100.0;
    }
    REQUIRE(heavy > 0);
    REQUIRE(heavy < volume.controlPointCount());
    // The default region: the mesh's bounds grown by 5% of their diagonal on every side.
    const Eigen::AlignedBox3d bounds = volume.restBounds();
    const Eigen::Vector3d lo = mesh.positions.colwise().minCoeff().transpose(), hi = mesh.positions.colwise().maxCoeff().transpose();
    REQUIRE((bounds.min() - (lo.array() - 0.05 * diagonal).matrix()).norm() <= 1e-12 * diagonal);
    REQUIRE((bounds.max() - (hi.array() + 0.05 * diagonal).matrix()).norm() <= 1e-12 * diagonal);

    // Multi-point drags: two vertices pulled, two held where they are (pins), solved together (Hu et al. eq. 12)
    // on the weighted T-spline's basis and certified by the exact test on its Bezier elements.
    const int pulled[2][2] = {{12, 200}, {57, 431}};
    const int held[2][2] = {{3, 90}, {140, 377}};
    const Eigen::Vector3d moves[2][2] = {{Eigen::Vector3d(0.08, 0.05, -0.04), Eigen::Vector3d(-0.06, 0.03, 0.07)},
                                         {Eigen::Vector3d(0.0, -0.09, 0.05), Eigen::Vector3d(0.07, 0.02, 0.0)}};
    for (int drag = 0; drag < 2; ++drag) {
        std::vector<PointConstraint> constraints;
        std::vector<int> vertices;
        for (int k = 0; k < 2; ++k) {
            const Eigen::Vector3d at = session.mesh().positions.row(pulled[drag][k]).transpose();
            constraints.push_back({at, at + moves[drag][k]});
            vertices.push_back(pulled[drag][k]);
        }
        for (int k = 0; k < 2; ++k) {
            const Eigen::Vector3d at = session.mesh().positions.row(held[drag][k]).transpose();
            constraints.push_back({at, at});
            vertices.push_back(held[drag][k]);
        }
        OpReport dragged;
        REQUIRE(session.drag(constraints, dragged));
        INFO(dragged.reason << " / " << dragged.injectivity);
        REQUIRE(dragged.status == OpStatus::Applied);
        REQUIRE(dragged.injectivity.find("unsupported") == std::string::npos);
        REQUIRE(dragged.injectivity == "injective");
        REQUIRE_FALSE(dragged.rankDeficient);
        for (size_t k = 0; k < constraints.size(); ++k)
            REQUIRE((session.mesh().positions.row(vertices[k]).transpose() - constraints[k].target).norm() <= 1e-9 * diagonal);
    }
    const Positions sculpted = session.mesh().positions;
    REQUIRE((sculpted - mesh.positions).cwiseAbs().maxCoeff() > 0.03);

    // Undo: the drags are the inverse manipulation, then the freeze and the tool go.
    OpReport undone;
    REQUIRE(session.undo(undone));
    REQUIRE(session.undo(undone));
    REQUIRE((session.mesh().positions - mesh.positions).cwiseAbs().maxCoeff() <= 1e-9 * diagonal);
    REQUIRE(session.undo(undone));  // the set-up: the freeze and the tool at once
    REQUIRE(session.tools().frozen() == -1);
    REQUIRE(session.tools().list().empty());
    REQUIRE(session.history().cursor() == 0);
    REQUIRE((session.mesh().positions - mesh.positions).cwiseAbs().maxCoeff() <= 1e-9 * diagonal);
    for (int k = 0; k < 3; ++k) REQUIRE(session.redo(undone));
    REQUIRE(session.tools().frozen() == 0);
    REQUIRE(session.mesh().positions == sculpted);

    // The recording writes the tool explicitly (add_lattice with the "tspline" JSON, then freeze) and replays
    // bitwise through its JSON text, without generating the octree again.
    const Script recorded = recordSession(session);
    REQUIRE(recorded.ops[0].kind == ScriptOp::Kind::AddLattice);
    REQUIRE(recorded.ops[1].kind == ScriptOp::Kind::Freeze);
    REQUIRE(recorded.ops[2].kind == ScriptOp::Kind::Group);
    Script parsed;
    const Session replayed = test::replayThroughJson(recorded, mesh.positions, mesh.triangles, parsed);
    REQUIRE(replayed.mesh().positions == sculpted);
    REQUIRE(replayed.tools().frozen() == 0);
    REQUIRE(replayed.history().size() == session.history().size());
    REQUIRE(io::volumeJson(*replayed.tools().list()[0].volume).dump() == io::volumeJson(volume).dump());
}

TEST_CASE("tspline script: setup_tspline in a region deforms only inside it and can leave the tool unfrozen", "[tspline][io][script][session]") {
    const Mesh mesh = sphereMesh(3);
    Session session = sessionOn(mesh);
    Status ran;
    run(session, R"({"ops": [{"op": "setup_tspline", "depth": 2, "weight_ratio": 50, "root": [2, 1, 1],
        "region": {"min": [0.2, -1.2, -1.2], "max": [1.2, 1.2, 1.2]}, "name": "cap", "freeze": false}]})", ran);
    INFO(ran.message);
    REQUIRE(ran);
    REQUIRE(session.history().size() == 1);
    REQUIRE(session.tools().frozen() == -1);
    REQUIRE(session.tools().list()[0].name == "cap");
    const TSplineVolume& volume = tsplineOf(session, 0);
    REQUIRE(volume.lattice().rootCount == std::array<int, 3>{2, 1, 1});
    REQUIRE(volume.restBounds().min().isApprox(Eigen::Vector3d(0.2, -1.2, -1.2), 1e-12));
    for (double w : volume.controlWeights()) REQUIRE((w == 1.0 || w == 5.0 || w == 50.0));  // 50:1, balanced by 10
    // Frozen afterwards: a drag at the cap moves nothing outside the region.
    OpReport applied;
    REQUIRE(session.tools().freeze(0, 0, applied));
    REQUIRE(applied.status == OpStatus::Applied);
    Eigen::Index rightmost = 0;
    mesh.positions.col(0).maxCoeff(&rightmost);
    const Eigen::Vector3d target = mesh.positions.row(rightmost).transpose() + Eigen::Vector3d(0.08, 0.02, 0.0);
    REQUIRE(session.dragVertex(static_cast<int>(rightmost), target, applied));
    INFO(applied.reason);
    REQUIRE(applied.status == OpStatus::Applied);
    REQUIRE((session.mesh().positions.row(rightmost).transpose() - target).norm() <= 1e-9);
    for (Eigen::Index v = 0; v < mesh.positions.rows(); ++v)
        if (mesh.positions(v, 0) < 0.2) REQUIRE(session.mesh().positions.row(v) == mesh.positions.row(v));
}

TEST_CASE("tspline script: subdivide_cells refines the picked cells of an unfrozen tool and replays bitwise", "[tspline][io][script][session]") {
    const Mesh mesh = sphereMesh(3);
    Session session = sessionOn(mesh);
    Status ran;
    run(session, R"({"ops": [{"op": "setup_tspline", "depth": 2, "freeze": false}]})", ran);
    INFO(ran.message);
    REQUIRE(ran);
    const std::shared_ptr<const Volume> coarse = session.tools().list()[0].volume;
    const TSplineVolume& before = tsplineOf(session, 0);
    // The leaf cell holding the point (1, 0, 0): found through the rest volume's parameters.
    const Eigen::Vector3d at(1.013, -0.007, 0.004);
    Eigen::Vector3d t, local;
    REQUIRE(before.freeze(at, t));
    const int picked = before.basis().elementCell[static_cast<size_t>(before.basis().elementOf(t, local))];
    REQUIRE(before.lattice().cells[static_cast<size_t>(picked)].level == 2);
    ScriptReport report = run(session, R"({"ops": [{"op": "subdivide_cells", "index": 0, "at": [[1.013, -0.007, 0.004]]},
        {"op": "subdivide_cells", "index": 0, "cells": [0], "balance": true}]})", ran);
    INFO(ran.message);
    REQUIRE(ran);
    INFO(report.ops[0].reason);
    REQUIRE(report.ops[0].status == OpStatus::Applied);
    REQUIRE(session.history().size() == 3);
    const TSplineVolume& after = tsplineOf(session, 0);
    REQUIRE(after.lattice().maxLevel == 3);
    REQUIRE(tlatticeBalanced(after.lattice()));
    REQUIRE(after.lattice().cells.size() >= before.lattice().cells.size() + 14);
    // The point's cell is now at level 3; the volume keeps its box; the weights stay sec. 4's, balanced.
    REQUIRE(after.freeze(at, t));
    REQUIRE(after.lattice().cells[static_cast<size_t>(after.basis().elementCell[static_cast<size_t>(after.basis().elementOf(t, local))])].level == 3);
    REQUIRE(after.restBounds().min().isApprox(before.restBounds().min(), 1e-12));
    REQUIRE(after.restBounds().max().isApprox(before.restBounds().max(), 1e-12));
    for (double w : after.controlWeights()) REQUIRE((w == 1.0 || w == 10.0 || w == 100.0));
    // Then frozen and dragged at the refined spot; the recording replays it bitwise (tools written explicitly).
    report = run(session, R"({"injectivity": {"mode": "exact"}, "ops": [{"op": "freeze", "index": 0},
        {"op": "drag", "constraints": [{"source": [1.013, -0.007, 0.004], "target": [1.1, 0.02, 0.0]}]}]})", ran);
    INFO(ran.message);
    REQUIRE(ran);
    REQUIRE(report.ops[1].status == OpStatus::Applied);
    const Script recorded = recordSession(session);
    Script parsed;
    const Session replayed = test::replayThroughJson(recorded, mesh.positions, mesh.triangles, parsed);
    REQUIRE(replayed.mesh().positions == session.mesh().positions);
    REQUIRE(io::volumeJson(*replayed.tools().list()[0].volume).dump() == io::volumeJson(*session.tools().list()[0].volume).dump());
    // Undo back to before the subdivisions: the coarse tool itself again.
    OpReport undone;
    for (int k = 0; k < 4; ++k) REQUIRE(session.undo(undone));
    REQUIRE(session.tools().list()[0].volume == coarse);
    REQUIRE((session.mesh().positions - mesh.positions).cwiseAbs().maxCoeff() <= 1e-9 * diagonalOf(mesh.positions));
}

TEST_CASE("tspline script: bad setup_tspline and subdivide_cells requests name the field and change nothing", "[tspline][io][script][session]") {
    // Parse errors name the field.
    const std::pair<const char*, const char*> bad[] = {
        {R"({"op": "setup_tspline"})", "ops[0].depth"},
        {R"({"op": "setup_tspline", "depth": 0})", "ops[0].depth"},
        {R"({"op": "setup_tspline", "depth": 7})", "ops[0].depth"},
        {R"({"op": "setup_tspline", "depth": 2, "weight_ratio": -1})", "ops[0].weight_ratio"},
        {R"({"op": "setup_tspline", "depth": 2, "weight_ratio": "a"})", "ops[0].weight_ratio"},
        {R"({"op": "setup_tspline", "depth": 2, "root": [1, 0, 1]})", "ops[0].root[1]"},
        {R"({"op": "setup_tspline", "depth": 2, "region": {"min": [0, 0, 0], "max": [1, 0, 1]}})", "ops[0].region"},
        {R"({"op": "setup_tspline", "depth": 2, "region": {"min": [0, 0, 0]}})", "ops[0].region.max"},
        {R"({"op": "setup_tspline", "depth": 2, "freeze": 1})", "ops[0].freeze"},
        {R"({"op": "setup_tspline", "depth": 2, "levels": 1})", "ops[0].levels"},
        {R"({"op": "subdivide_cells", "index": 0})", "ops[0]"},
        {R"({"op": "subdivide_cells", "index": 0, "cells": [-1]})", "ops[0].cells[0]"},
        {R"({"op": "subdivide_cells", "index": 0, "at": [[0, 0]]})", "ops[0].at[0]"},
    };
    for (const auto& [op, field] : bad) {
        Script script;
        const Status parsed = io::parseScript(std::string(R"({"ops": [)") + op + "]}", "bad.json", script);
        INFO(op << " -> " << parsed.message);
        REQUIRE_FALSE(parsed);
        REQUIRE(parsed.message.find(std::string("bad.json: ") + field + ":") == 0);
    }
    // Run-time errors: the session is left as it was.
    const Mesh mesh = sphereMesh(2);
    Session session = sessionOn(mesh);
    Status ran;
    run(session, R"({"ops": [{"op": "setup_tspline", "depth": 2, "name": "frozen one"},
        {"op": "add_lattice", "name": "box", "lattice": {"kind": "parallelepiped", "origin": [-2, -2, -2], "edges": [[4, 0, 0], [0, 4, 0], [0, 0, 4]], "chunks": [1, 1, 1], "degree": [2, 2, 2]}},
        {"op": "setup_tspline", "depth": 1, "freeze": false}]})", ran);
    INFO(ran.message);
    REQUIRE(ran);
    const size_t entries = session.history().size();
    const std::pair<const char*, const char*> refused[] = {
        {R"({"op": "setup_tspline", "depth": 2, "region": {"min": [3, 3, 3], "max": [4, 4, 4]}})", "region: holds none of the mesh's"},
        {R"({"op": "subdivide_cells", "index": 0, "cells": [0]})", "is frozen: unfreeze it"},
        {R"({"op": "subdivide_cells", "index": 1, "cells": [0]})", "not a T-spline"},
        {R"({"op": "subdivide_cells", "index": 3, "cells": [0]})", "index: there is no lattice 3"},
        {R"({"op": "subdivide_cells", "index": 2, "cells": [0, 8]})", "cells[1]: cell 8 does not exist"},
        {R"({"op": "subdivide_cells", "index": 2, "at": [[5, 5, 5]]})", "at[0]: (5, 5, 5) is outside lattice tspline"},
    };
    for (const auto& [op, message] : refused) {
        run(session, std::string(R"({"ops": [)") + op + "]}", ran);
        INFO(op << " -> " << ran.message);
        REQUIRE_FALSE(ran);
        REQUIRE(ran.message.find(message) != std::string::npos);
        REQUIRE(session.history().size() == entries);
        REQUIRE(session.tools().list().size() == 3);
        REQUIRE(session.mesh().positions == mesh.positions);
    }
    // A tool whose points were moved one by one is not re-placed behind the user's back.
    const TSplineVolume& tool = tsplineOf(session, 2);
    Positions moved = tool.restControlPoints();
    moved.row(moved.rows() / 2) += Eigen::RowVector3d(0.01, 0, 0);
    std::shared_ptr<const TSplineVolume> edited;
    REQUIRE(TSplineVolume::make(tool.sharedBasis(), moved, tool.controlWeights(), edited));
    OpReport report;
    REQUIRE(session.tools().edit(2, {"tspline", edited}, report));
    const Status refusedMoved = session.tspline().subdivideCells(2, {0}, {}, true, report);
    INFO(refusedMoved.message);
    REQUIRE_FALSE(refusedMoved);
    REQUIRE(refusedMoved.message.find("rest layout") != std::string::npos);
}
