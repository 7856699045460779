// Golden images of what the engine produces: the default mesh after the scripted drags of assets/demo.json
// (through the same script runner and scene builder the headless CLI uses), with the engine's own det J.
#include <catch2/catch.hpp>

#include "app/scene_builder.h"
#include "io/script.h"
#include "core/session/session.h"
#include "demo_session.h"
#include "gl_test_support.h"
#include "io/obj_mesh.h"
#include "io/script_json.h"

using namespace sculpt;
using sculpt::test::demoSession;
using sculpt::test::renderSession;

TEST_CASE("golden: the default mesh after the demo script's drags, with its constraint", "[gl][golden]") {
    const core::Session session = demoSession();
    test::checkGolden(renderSession(session, false, false), "scripted_drag");
    test::checkGolden(renderSession(session, false, true), "scripted_drag_lattice");
}

TEST_CASE("golden: the engine's det J of the demo deformation", "[gl][golden]") {
    test::checkGolden(renderSession(demoSession(), true, false), "scripted_drag_jacobian");
}
