// Golden images of the example scripts, run through the same script runner the headless CLI uses. EFFD
// (Coquillart 1990): assets/examples/sandpie.json (Fig. 6: a cylindrical lattice on a plate, its axis and
// middle ring pushed) and eight.json (Fig. 9: an "8" pressed into the plate by a composite of two discs).
// Weighted T-splines (Song & Yang 2005): pot.json (Fig. 12: an octree T-spline around a pot, its rim pulled
// out and up, then a bump on the belly after the cells there were subdivided) and local_detail.json (Fig. 14:
// finer cells at one end of a plate, a drag there that moves only that end).
#include <catch2/catch.hpp>

#include "app/scene_builder.h"
#include "io/script.h"
#include "core/session/session.h"
#include "core/tspline/tspline_volume.h"
#include "gl_test_support.h"
#include "io/obj_mesh.h"
#include "io/script_json.h"

using namespace sculpt;

namespace {

// Runs assets/examples/NAME as the headless CLI does; every op must be applied whole (every move went all the
// way: nothing folded) and, with `oneStep`, certified in one step with its targets met to 1e-9.
core::Session exampleSession(const std::string& name, bool oneStep = false) {
    const std::string folder = std::string(SCULPT_SOURCE_DIR) + "/assets/examples/";
    io::Script script;
    const Status parsed = io::loadScript(folder + name, script);
    INFO(parsed.message);
    REQUIRE(parsed.ok);
    io::ObjMesh mesh;
    const Status loaded = io::loadObj(io::resolveScriptMesh(script, folder + name), mesh);
    INFO(loaded.message);
    REQUIRE(loaded.ok);
    core::Session session;
    REQUIRE(session.setMesh(mesh.positions, mesh.triangles, script.lattice).ok);
    session.setInjectivity(script.injectivity);
    io::ScriptReport report;
    const Status ran = io::runScript(session, script, report);
    INFO(ran.message);
    REQUIRE(ran.ok);
    for (const core::OpReport& op : report.ops) {
        INFO(op.op << ": " << op.reason << " / " << op.injectivity);
        REQUIRE(op.status == core::OpStatus::Applied);
        REQUIRE(op.fractionApplied == 1.0);
        if (!oneStep) continue;
        REQUIRE(op.subSteps <= 1);
        for (double residual : op.residuals) REQUIRE(residual <= 1e-9);
    }
    REQUIRE(session.tools().frozen() == -1);
    return session;
}

render::Rgba8Image renderExample(const core::Session& session, float yaw = 30.0f, float pitch = -55.0f, double distance = 2.6) {
    render::ScreenshotOptions options;
    options.width = 320;
    options.height = 200;
    options.yawDeg = yaw;
    options.pitchDeg = pitch;
    options.distance = distance;
    options.overlays.wireframe = true;
    render::Rgba8Image image;
    const Status status = test::glTestRenderer().renderScene(app::sceneFromSession(session, app::SceneRequest{}), options, image);
    INFO(status.message);
    REQUIRE(status.ok);
    return image;
}

}  // namespace

TEST_CASE("golden: sandpie example, a cylindrical lattice's axis and middle ring pushed up", "[gl][golden][effd]") {
    const core::Session session = exampleSession("sandpie.json");
    // The peak is where the axis went; the plate outside the cylinder did not move.
    REQUIRE(session.mesh().positions.col(2).maxCoeff() > 0.1);
    for (Eigen::Index v = 0; v < session.mesh().positions.rows(); ++v)
        if (session.mesh().original.row(v).head<2>().norm() > 0.61) REQUIRE(session.mesh().positions.row(v) == session.mesh().original.row(v));
    test::checkGolden(renderExample(session), "effd_sandpie");
}

TEST_CASE("golden: eight example, two disc lattices pressed into a plate", "[gl][golden][effd]") {
    const core::Session session = exampleSession("eight.json");
    REQUIRE(session.mesh().positions.col(2).minCoeff() < -0.05);
    test::checkGolden(renderExample(session), "effd_eight");
}

// Weighted T-spline examples (Song & Yang 2005): pot.json (Fig. 12: a global, then a local deformation of a
// surface of revolution) and local_detail.json (Fig. 14: finer control at one end).
TEST_CASE("golden: pot example, a T-spline's rim pulled out then a bump on finer cells", "[gl][golden][tspline]") {
    const core::Session session = exampleSession("pot.json", true);
    const Positions& now = session.mesh().positions;
    const Positions& original = session.mesh().original;
    // The rim went out and up, the base stayed, and the belly at +x stands out by the bump.
    REQUIRE(now.col(2).maxCoeff() > original.col(2).maxCoeff() + 0.05);
    for (Eigen::Index v = 0; v < now.rows(); ++v)
        if (original(v, 2) < 0.01) REQUIRE((now.row(v) - original.row(v)).norm() < 0.02);
    Eigen::Index belly = 0;
    (original.rowwise() - Eigen::RowVector3d(0.52, 0, 0.4)).rowwise().squaredNorm().minCoeff(&belly);
    REQUIRE(now(belly, 0) > original(belly, 0) + 0.07);
    test::checkGolden(renderExample(session, 30.0f, -70.0f, 3.2), "tspline_pot");
}

TEST_CASE("golden: local detail example, finer T-spline cells at one end of a plate", "[gl][golden][tspline]") {
    const core::Session session = exampleSession("local_detail.json", true);
    const Positions& now = session.mesh().positions;
    const Positions& original = session.mesh().original;
    // Only that end moved: the plate at x < 0.2 by less than 1e-4 of the lift, and nothing at all (rounding) where
    // no moved control point's blending function reaches: vertices whose parameters lie outside the support
    // boxes (local knot vectors, eq. 7) of every control point the drag moved (the cage's displacements before
    // the unfreeze; the drag was one step in the frozen tool, no fresh frame).
    REQUIRE(now.col(2).maxCoeff() > 0.14);
    const auto* tool = dynamic_cast<const core::TSplineVolume*>(session.tools().list()[0].volume.get());
    REQUIRE(tool);
    const core::Operation& drag = session.history()[3];
    REQUIRE(drag.kind == core::OperationKind::Drag);
    REQUIRE(drag.steps.size() == 1);
    REQUIRE_FALSE(drag.steps[0].freshFrame);
    REQUIRE_FALSE(drag.steps[0].newCage);
    const std::vector<int>& moved = drag.steps[0].delta.indices;
    REQUIRE(!moved.empty());
    REQUIRE(moved.size() < static_cast<size_t>(tool->controlPointCount()) / 4);
    int untouched = 0;
    for (Eigen::Index v = 0; v < now.rows(); ++v) {
        const double distance = (now.row(v) - original.row(v)).norm();
        INFO("vertex " << v << " at x " << original(v, 0) << " moved " << distance);
        if (original(v, 0) < 0.2) REQUIRE(distance <= 1.5e-5);
        Eigen::Vector3d t;
        REQUIRE(tool->freeze(original.row(v).transpose(), t));  // its frozen parameters
        bool reached = false;
        for (int s : moved) {
            const auto& knots = tool->basis().knotValues[static_cast<size_t>(s)];
            bool inside = true;
            for (int a = 0; a < 3; ++a) inside = inside && t[a] > knots[a][0] && t[a] < knots[a][4];
            reached = reached || inside;
        }
        if (!reached) {
            ++untouched;
            REQUIRE(distance <= 1e-12);
        }
    }
    REQUIRE(untouched > now.rows() / 4);  // the far half of the plate, at least
    test::checkGolden(renderExample(session, 30.0f, -55.0f, 3.6), "tspline_local_detail");
}
