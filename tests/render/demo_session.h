// The default mesh after the drags of assets/demo.json, through the same script runner the headless CLI uses,
// with det J tracked: the scene of the engine's goldens (session_golden_test.cpp, gpu_deformation_test.cpp).
#pragma once

#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "app/scene_builder.h"
#include "io/script.h"
#include "core/session/session.h"
#include "io/obj_mesh.h"
#include "io/script_json.h"
#include "gl_test_support.h"

namespace sculpt::test {

inline core::Session demoSession() {
    io::ObjMesh mesh;
    const Status loaded = io::loadObj(std::string(SCULPT_SOURCE_DIR) + "/assets/default.obj", mesh);
    INFO(loaded.message);
    REQUIRE(loaded.ok);
    io::Script script;
    const Status parsed = io::loadScript(std::string(SCULPT_SOURCE_DIR) + "/assets/demo.json", script);
    INFO(parsed.message);
    REQUIRE(parsed.ok);
    core::Session session;
    REQUIRE(session.setMesh(mesh.positions, mesh.triangles, script.lattice).ok);
    session.setInjectivity(script.injectivity);
    session.setTrackJacobian(true);
    io::ScriptReport report;
    REQUIRE(io::runScript(session, script, report).ok);
    return session;
}

// The golden picture of `session` (320 x 200, the det J and lattice overlays as asked) through the test
// renderer. With gpuLayers, drawn through the GPU path (Renderer::setGpuDeformation with the session's cage,
// embedding, rest mesh and these layers) instead of the engine's positions.
inline render::Rgba8Image renderSession(const core::Session& session, bool jacobian, bool lattice,
                                        const std::vector<const core::Lattice*>* gpuLayers = nullptr) {
    app::SceneRequest request;
    request.jacobian = jacobian;
    render::ScreenshotOptions options;
    options.width = 320;
    options.height = 200;
    options.overlays.jacobian = jacobian;
    options.overlays.lattice = lattice;
    render::Rgba8Image image;
    render::OffscreenRenderer& offscreen = glTestRenderer();
    Status status = offscreen.renderScene(app::sceneFromSession(session, request), options, image);
    if (status && gpuLayers) {
        status = offscreen.renderer().setGpuDeformation(session.lattice(), session.cage().embedding(), session.mesh().rest, *gpuLayers);
        const render::Camera camera =
            render::screenshotCamera(offscreen.renderer().meshBounds(), offscreen.renderer().latticeBounds(), options);
        if (status) status = offscreen.render(camera, options.overlays, options.width, options.height, options.samples, &image);
    }
    INFO(status.message);
    REQUIRE(status.ok);
    return image;
}

}  // namespace sculpt::test
