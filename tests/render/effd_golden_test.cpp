// Golden images of the EFFD examples (Coquillart 1990): assets/examples/sandpie.json (Fig. 6: a cylindrical
// lattice on a plate, its axis and middle ring pushed) and eight.json (Fig. 9: an "8" pressed into the plate,
// one disc lattice after the other), run through the same script runner the headless CLI uses.
#include <catch2/catch.hpp>

#include "app/scene_builder.h"
#include "core/script.h"
#include "core/session.h"
#include "gl_test_support.h"
#include "io/obj_mesh.h"
#include "io/script_json.h"

using namespace sculpt;

namespace {

core::Session exampleSession(const std::string& name) {
    const std::string folder = std::string(SCULPT_SOURCE_DIR) + "/assets/examples/";
    core::Script script;
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
    core::ScriptReport report;
    const Status ran = core::runScript(session, script, report);
    INFO(ran.message);
    REQUIRE(ran.ok);
    for (const core::OpReport& op : report.ops) {
        INFO(op.op << ": " << op.reason);
        REQUIRE(op.status == core::OpStatus::Applied);
        REQUIRE(op.fractionApplied == 1.0);  // every move went all the way: nothing folded
    }
    REQUIRE(session.frozenTool() == -1);
    return session;
}

render::Rgba8Image renderExample(const core::Session& session) {
    render::ScreenshotOptions options;
    options.width = 320;
    options.height = 200;
    options.yawDeg = 30.0f;
    options.pitchDeg = -55.0f;
    options.distance = 2.6;
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
    REQUIRE(session.positions().col(2).maxCoeff() > 0.1);
    for (Eigen::Index v = 0; v < session.positions().rows(); ++v)
        if (session.originalPositions().row(v).head<2>().norm() > 0.61) REQUIRE(session.positions().row(v) == session.originalPositions().row(v));
    test::checkGolden(renderExample(session), "effd_sandpie");
}

TEST_CASE("golden: eight example, two disc lattices pressed into a plate", "[gl][golden][effd]") {
    const core::Session session = exampleSession("eight.json");
    REQUIRE(session.positions().col(2).minCoeff() < -0.05);
    test::checkGolden(renderExample(session), "effd_eight");
}
