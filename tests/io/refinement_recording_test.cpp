// issue 10 point 9, the files: a recorded session with refinements replays to the same mesh bit for bit, and a
// refined mesh saves as OBJ with the texture coordinates interpolated at every split (seams kept apart).
#include <catch2/catch.hpp>

#include <cstring>
#include <random>

#include "../core/refinement_checks.h"
#include "../core/test_support.h"
#include "io/script.h"
#include "core/session/session.h"
#include "io/obj_mesh.h"
#include "io/obj_refine.h"
#include "io/script_json.h"
#include "io_test_support.h"
#include "replay_support.h"

using namespace sculpt;
using namespace sculpt::core;
using namespace sculpt::io;

namespace {

template <typename Matrix>
bool sameBits(const Matrix& a, const Matrix& b) {
    return a.rows() == b.rows() && a.cols() == b.cols() &&
           std::memcmp(a.data(), b.data(), static_cast<size_t>(a.size()) * sizeof(typename Matrix::Scalar)) == 0;
}

// The control point whose rest position is nearest x = `x` on the middle row, and its whole slab (every j, k).
std::vector<int> slabNear(const Lattice& lattice, double x) {
    int best = 0;
    for (int i = 1; i < lattice.count[0]; ++i)
        if (std::abs(lattice.restControlPoint(lattice.index(i, 0, 0)).x() - x) <
            std::abs(lattice.restControlPoint(lattice.index(best, 0, 0)).x() - x))
            best = i;
    std::vector<int> ids;
    for (int k = 0; k < lattice.count[2]; ++k)
        for (int j = 0; j < lattice.count[1]; ++j) ids.push_back(lattice.index(best, j, k));
    return ids;
}

void raise(Session& session, const std::vector<int>& ids, double height) {
    Eigen::MatrixX3d offsets(static_cast<Eigen::Index>(ids.size()), 3);
    offsets.rowwise() = Eigen::RowVector3d(0.0, 0.0, height);
    OpReport report;
    REQUIRE(session.moveControlPoints(ids, offsets, true, report).ok);
    REQUIRE(report.status == OpStatus::Applied);
}

}  // namespace

TEST_CASE("refinement recording: a session with refinements replays to the same vertices and triangles bitwise", "[refine]") {
    // Control-point edits in the cage (what replays bit for bit, docs/scripting.md "Recording"), an explicit refine, the
    // automatic option, undo and redo.
    Positions positions(6, 3);
    positions << 0, 0, 0, 1, 0, 0, 2, 0, 0, 0, 1, 0, 1, 1, 0, 2, 1, 0;
    Triangles triangles(4, 3);
    triangles << 0, 1, 4, 0, 4, 3, 1, 2, 5, 1, 5, 4;
    LatticeSettings settings;
    settings.resolution = {17, 4, 4};
    settings.padding = 0.0;
    Session session;
    REQUIRE(session.setMesh(positions, triangles, settings).ok);
    OpReport report;
    raise(session, slabNear(session.lattice(), 1.0), 0.4);
    REQUIRE(session.refinement().refine(0.003, report).ok);
    REQUIRE(report.status == OpStatus::Applied);
    RefinementSettings automatic;
    automatic.automatic = true;
    automatic.options.tolerance = 0.003;
    REQUIRE(session.refinement().set(automatic).ok);
    raise(session, slabNear(session.lattice(), 0.5), -0.2);  // refined automatically, one history entry
    REQUIRE(session.history().back().refinement.splits.size() > 0);
    REQUIRE(session.undo(report).ok);
    REQUIRE(session.redo(report).ok);
    raise(session, slabNear(session.lattice(), 1.5), 0.25);
    REQUIRE(session.undo(report).ok);  // undone, then dropped by the next operation
    automatic.automatic = false;
    REQUIRE(session.refinement().set(automatic).ok);
    REQUIRE(session.refinement().refine(0.001, report).ok);
    REQUIRE(report.status == OpStatus::Applied);

    const Script recording = recordSession(session);
    const std::string text = io::scriptToJson(recording);
    REQUIRE(text.find("\"refine\"") != std::string::npos);
    REQUIRE(text.find("\"set_refinement\"") != std::string::npos);
    REQUIRE(text.find("\"splits\"") != std::string::npos);
    Script parsed;
    Session replayed = test::replayThroughJson(recording, positions, triangles, parsed);
    REQUIRE(sameBits(replayed.mesh().positions, session.mesh().positions));
    REQUIRE(sameBits(replayed.mesh().rest, session.mesh().rest));
    REQUIRE(sameBits(replayed.mesh().triangles, session.mesh().triangles));
    REQUIRE(replayed.history().size() == session.history().size());
    REQUIRE(replayed.history().cursor() == session.history().cursor());
    REQUIRE(replayed.refinement().settings().automatic == session.refinement().settings().automatic);
    // Both undo alike, down to the mesh as set.
    while (session.history().cursor() > 0) {
        REQUIRE(session.undo(report).ok);
        REQUIRE(replayed.undo(report).ok);
        REQUIRE(sameBits(replayed.mesh().positions, session.mesh().positions));
        REQUIRE(sameBits(replayed.mesh().triangles, session.mesh().triangles));
    }
    REQUIRE(sameBits(session.mesh().triangles, triangles));
}

TEST_CASE("refinement recording: random drags and refinements replay to the same triangles, vertices to 1e-12", "[refine]") {
    // Subdivided drags replay one step per lattice and round differently in the last bits (docs/scripting.md,
    // "Recording"); the refinements on top of them split the same edges.
    std::mt19937 rng(4242);
    for (int trial = 0; trial < 4; ++trial) {
        Positions positions;
        Triangles triangles;
        test::jitteredGrid(rng, test::randomInt(rng, 2, 5), test::randomInt(rng, 2, 4), 2.0, 1.2, positions, triangles);
        LatticeSettings settings;
        settings.resolution = {9, 6, 5};
        settings.pinLayers = 1;
        Session session;
        REQUIRE(session.setMesh(positions, triangles, settings).ok);
        const double diagonal = session.lattice().diagonal();
        OpReport report;
        const auto randomDrag = [&] {
            const int v = test::randomInt(rng, 0, static_cast<int>(session.mesh().positions.rows()) - 1);
            REQUIRE(session.dragVertex(v, session.mesh().positions.row(v).transpose() + 0.08 * diagonal * test::randomVector(rng, -1, 1), report).ok);
        };
        randomDrag();
        REQUIRE(session.refinement().refine(0.004, report).ok);
        randomDrag();  // moves the refined mesh
        RefinementSettings automatic;
        automatic.automatic = true;
        automatic.options.tolerance = 0.004;
        REQUIRE(session.refinement().set(automatic).ok);
        randomDrag();
        REQUIRE(session.undo(report).ok);
        REQUIRE(session.redo(report).ok);
        randomDrag();
        REQUIRE(session.mesh().positions.rows() > positions.rows());

        const Script recording = recordSession(session);
        Script parsed;
        Session replayed = test::replayThroughJson(recording, positions, triangles, parsed);
        REQUIRE(sameBits(replayed.mesh().triangles, session.mesh().triangles));
        REQUIRE((replayed.mesh().positions - session.mesh().positions).cwiseAbs().maxCoeff() <= 1e-12 * diagonal);
        REQUIRE(replayed.history().size() == session.history().size());

        // On another mesh the recorded refinements do not apply: they are decided again.
        Positions other = positions;
        other.col(2) *= 0.5;
        Session elsewhere;
        REQUIRE(elsewhere.setMesh(other, triangles, parsed.lattice).ok);
        ScriptReport scriptReport;
        const Status ran = runScript(elsewhere, parsed, scriptReport);
        INFO(ran.message);
        REQUIRE(ran.ok);
    }
}

TEST_CASE("refinement recording: script ops refine and set_refinement, and their bad input", "[refine]") {
    Positions positions(6, 3);
    positions << 0, 0, 0, 1, 0, 0, 2, 0, 0, 0, 1, 0, 1, 1, 0, 2, 1, 0;
    Triangles triangles(4, 3);
    triangles << 0, 1, 4, 0, 4, 3, 1, 2, 5, 1, 5, 4;
    const std::string script = R"({"lattice": {"resolution": [17, 4, 4], "padding": 0, "pin_layers": 0},
        "ops": [{"op": "set_refinement", "automatic": true, "tolerance": 0.004, "max_rounds": 30},
                {"op": "move_control_point", "indices": [[8,0,0],[8,1,0],[8,2,0],[8,3,0],[8,0,1],[8,1,1],[8,2,1],[8,3,1],
                                                         [8,0,2],[8,1,2],[8,2,2],[8,3,2],[8,0,3],[8,1,3],[8,2,3],[8,3,3]],
                 "by": [0, 0, 0.4]},
                {"op": "refine", "tolerance": 0.002},
                {"op": "undo"}, {"op": "redo"}]})";
    Script parsed;
    const Status read = io::parseScript(script, "refine.json", parsed);
    INFO(read.message);
    REQUIRE(read.ok);
    Session session;
    REQUIRE(session.setMesh(positions, triangles, parsed.lattice).ok);
    ScriptReport report;
    const Status ran = runScript(session, parsed, report);
    INFO(ran.message);
    REQUIRE(ran.ok);
    REQUIRE(report.ops[1].verticesAdded > 0);  // the edit, refined automatically
    REQUIRE(report.ops[2].status == OpStatus::Applied);
    REQUIRE(report.ops[2].verticesAdded > 0);
    REQUIRE(session.history().size() == 2);
    REQUIRE(session.refinement().settings().options.maxRounds == 30);
    const std::string reportText = io::reportToJson(report, session, {});
    REQUIRE(reportText.find("\"vertices_added\"") != std::string::npos);

    for (const char* bad : {R"({"ops": [{"op": "refine", "tolerance": 0}]})", R"({"ops": [{"op": "refine", "tolerance": -1}]})",
                            R"({"ops": [{"op": "refine", "tolerance": "x"}]})", R"({"ops": [{"op": "refine", "tol": 0.1}]})",
                            R"({"ops": [{"op": "set_refinement", "tolerance": 0}]})",
                            R"({"ops": [{"op": "set_refinement", "max_rounds": 0}]})",
                            R"({"ops": [{"op": "set_refinement", "automatic": 1}]})"}) {
        Script s;
        const Status status = io::parseScript(bad, "bad.json", s);
        INFO(bad << " -> " << status.message);
        REQUIRE_FALSE(status.ok);
        REQUIRE(status.message.find("ops[0]") != std::string::npos);
    }
    // A recorded refinement that does not fit the mesh is refused before anything changes.
    Script recorded = recordSession(session);
    std::string text = io::scriptToJson(recorded);
    Script tampered;
    REQUIRE(io::parseScript(text, "recording.json", tampered).ok);
    for (ScriptOp& op : tampered.ops)
        if (op.kind == ScriptOp::Kind::Refine) op.applied.refinement.splits.push_back({0, 100000});
    Session fresh;
    REQUIRE(fresh.setMesh(positions, triangles, tampered.lattice).ok);
    ScriptReport tamperedReport;
    const Status refused = runScript(fresh, tampered, tamperedReport);
    REQUIRE_FALSE(refused.ok);
    REQUIRE(refused.message.find("refinement") != std::string::npos);
}

TEST_CASE("refinement OBJ: a refined mesh saves with texture coordinates interpolated at the splits, seams kept", "[refine]") {
    // Quads A (x in [0,1]) and B (x in [1,2]) share the edge x = 1 but not its texture coordinates (a seam):
    // A maps (x, y) -> (x, y), B maps (x, y) -> (x + 1, y). Quad C, far away, maps (x, y) -> ((x - 5) / 2, y / 2).
    const std::string text =
        "# two quads with a seam and one far away\n"
        "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nv 1 1 0\nv 2 1 0\nv 5 0 0\nv 6 0 0\nv 6 1 0\nv 5 1 0\n"
        "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
        "vt 2 0\nvt 3 0\nvt 3 1\nvt 2 1\n"
        "vt 0 0\nvt 0.5 0\nvt 0.5 0.5\nvt 0 0.5\n"
        "g quads\nf 1/1 2/2 5/3 4/4\nf 2/5 3/6 6/7 5/8\ng far\nf 7/9 8/10 9/11 10/12\n";
    const auto expected = [](const Eigen::Vector3d& rest, double centroidX) -> Eigen::Vector2d {
        if (centroidX < 1.0) return {rest.x(), rest.y()};
        if (centroidX < 2.0) return {rest.x() + 1.0, rest.y()};
        return {(rest.x() - 5.0) / 2.0, rest.y() / 2.0};
    };
    io::ObjMesh mesh;
    REQUIRE(io::loadObjFromText(text, "seam.obj", "", mesh, nullptr).ok);
    LatticeSettings settings;
    settings.resolution = {25, 4, 4};
    settings.padding = 0.0;
    settings.pinLayers = 0;
    Session session;
    REQUIRE(session.setMesh(mesh.positions, mesh.triangles, settings).ok);
    raise(session, slabNear(session.lattice(), 1.0), 0.3);
    OpReport report;
    REQUIRE(session.refinement().refine(0.002, report).ok);
    REQUIRE(report.status == OpStatus::Applied);
    const std::vector<EdgeSplit> splits = session.refinement().appliedSplits();
    REQUIRE(splits.size() == static_cast<size_t>(report.verticesAdded));

    test::TempFolder folder("refine_obj");
    const std::string path = folder.file("refined.obj");
    const Status saved = io::saveRefinedObj(path, mesh, splits, session.mesh().positions);
    INFO(saved.message);
    REQUIRE(saved.ok);
    io::ObjMesh back;
    REQUIRE(io::loadObj(path, back).ok);
    REQUIRE(sameBits(back.positions, session.mesh().positions));  // shortest round-trip numbers
    REQUIRE(back.triangles.rows() == session.mesh().triangles.rows());
    REQUIRE(back.groupNames == mesh.groupNames);
    const Positions& rest = session.mesh().rest;
    int farQuads = 0, newCorners = 0;
    bool seamLeft = false, seamRight = false;
    for (int f = 0; f < back.faceCount(); ++f) {
        const int first = back.faceStart[static_cast<size_t>(f)], end = back.faceStart[static_cast<size_t>(f) + 1];
        double centroidX = 0.0;
        for (int c = first; c < end; ++c) centroidX += rest(back.cornerVertex[static_cast<size_t>(c)], 0) / (end - first);
        if (centroidX > 4.0) {
            // Untouched by the refinement: still the quad it was, in its group.
            REQUIRE(end - first == 4);
            REQUIRE(back.groupNames[static_cast<size_t>(back.faceGroup[static_cast<size_t>(f)])] == "far");
            ++farQuads;
        } else {
            REQUIRE(end - first == 3);
            REQUIRE(back.groupNames[static_cast<size_t>(back.faceGroup[static_cast<size_t>(f)])] == "quads");
        }
        // Orientation kept: the rest-space normal of every face points along +z like the input's.
        const Eigen::Vector3d p0 = rest.row(back.cornerVertex[static_cast<size_t>(first)]).transpose();
        const Eigen::Vector3d p1 = rest.row(back.cornerVertex[static_cast<size_t>(first) + 1]).transpose();
        const Eigen::Vector3d p2 = rest.row(back.cornerVertex[static_cast<size_t>(first) + 2]).transpose();
        REQUIRE((p1 - p0).cross(p2 - p0).z() > 0.0);
        for (int c = first; c < end; ++c) {
            const int v = back.cornerVertex[static_cast<size_t>(c)];
            const int vt = back.cornerTexcoord[static_cast<size_t>(c)];
            REQUIRE(vt >= 0);
            const Eigen::Vector2d uv(back.texcoords(vt, 0), back.texcoords(vt, 1));
            const Eigen::Vector3d restPoint = rest.row(v).transpose();
            INFO("face " << f << " vertex " << v << " at " << restPoint.transpose() << ": uv " << uv.transpose());
            REQUIRE((uv - expected(restPoint, centroidX)).norm() <= 1e-12);
            if (v >= mesh.vertexCount()) ++newCorners;
            if (restPoint.x() == 1.0 && restPoint.y() > 0.0 && restPoint.y() < 1.0) {
                (centroidX < 1.0 ? seamLeft : seamRight) = true;
            }
        }
    }
    REQUIRE(farQuads == 1);
    REQUIRE(newCorners > 0);
    REQUIRE(seamLeft);   // a vertex split on the seam has u = 1 in A's triangles...
    REQUIRE(seamRight);  // ...and u = 2 in B's
    // Unrefined, the save is the loaded text with the moved numbers replaced (the source kept).
    std::string unrefined;
    REQUIRE(io::serializeObj(mesh, mesh.positions, unrefined).ok);
    REQUIRE(unrefined == text);
    REQUIRE(io::saveRefinedObj(folder.file("same.obj"), mesh, {}, mesh.positions).ok);
    REQUIRE(test::readBytes(folder.file("same.obj")) == text);
    // Splits that do not fit the mesh: an error, nothing written.
    REQUIRE_FALSE(io::saveRefinedObj(folder.file("bad.obj"), mesh, {{0, 9}}, session.mesh().positions).ok);
}
