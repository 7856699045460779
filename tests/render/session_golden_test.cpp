// Golden images of what the engine produces: the default mesh after the scripted drags of assets/demo.json
// (through the same script runner and scene builder the headless CLI uses), with the engine's own det J.
#include <catch2/catch.hpp>

#include "app/scene_builder.h"
#include "core/script.h"
#include "core/session.h"
#include "gl_test_support.h"
#include "io/obj_mesh.h"
#include "io/script_json.h"

using namespace sculpt;

namespace {

core::Session demoSession() {
    io::ObjMesh mesh;
    const Status loaded = io::loadObj(std::string(SCULPT_SOURCE_DIR) + "/assets/default.obj", mesh);
    INFO(loaded.message);
    REQUIRE(loaded.ok);
    core::Script script;
    const Status parsed = io::loadScript(std::string(SCULPT_SOURCE_DIR) + "/assets/demo.json", script);
    INFO(parsed.message);
    REQUIRE(parsed.ok);
    core::Session session;
    REQUIRE(session.setMesh(mesh.positions, mesh.triangles, script.lattice).ok);
    session.setInjectivity(script.injectivity);
    session.setTrackJacobian(true);
    core::ScriptReport report;
    REQUIRE(core::runScript(session, script, report).ok);
    return session;
}

render::Rgba8Image renderSession(const core::Session& session, bool jacobian, bool lattice) {
    app::SceneRequest request;
    request.jacobian = jacobian;
    render::ScreenshotOptions options;
    options.width = 320;
    options.height = 200;
    options.overlays.jacobian = jacobian;
    options.overlays.lattice = lattice;
    render::Rgba8Image image;
    const Status status = test::glTestRenderer().renderScene(app::sceneFromSession(session, request), options, image);
    INFO(status.message);
    REQUIRE(status.ok);
    return image;
}

}  // namespace

TEST_CASE("golden: the default mesh after the demo script's drags, with its constraint", "[gl][golden]") {
    const core::Session session = demoSession();
    test::checkGolden(renderSession(session, false, false), "scripted_drag");
    test::checkGolden(renderSession(session, false, true), "scripted_drag_lattice");
}

TEST_CASE("golden: the engine's det J of the demo deformation", "[gl][golden]") {
    test::checkGolden(renderSession(demoSession(), true, false), "scripted_drag_jacobian");
}
