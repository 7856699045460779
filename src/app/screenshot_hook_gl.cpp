// Offscreen screenshots through the shared renderer (OSMesa or EGL, chosen at run time).
#include <iostream>

#include "app/scene_builder.h"
#include "app/screenshot_hook.h"
#include "render/offscreen_renderer.h"

namespace sculpt::app {

struct ScreenshotRenderer::State {
    std::unique_ptr<render::OffscreenRenderer> renderer;
};

ScreenshotRenderer::ScreenshotRenderer(const CliOptions& options) : options_(options) {}
ScreenshotRenderer::~ScreenshotRenderer() = default;

Status ScreenshotRenderer::capture(const core::Session& session, const std::string& pngPath, const io::ObjMesh* sourceMesh) {
    render::ScreenshotOptions screenshot;
    screenshot.width = options_.width;
    screenshot.height = options_.height;
    if (options_.camera) {
        screenshot.yawDeg = static_cast<float>((*options_.camera)[0]);
        screenshot.pitchDeg = static_cast<float>((*options_.camera)[1]);
        screenshot.distance = (*options_.camera)[2];
    }
    SceneRequest request;
    bool colors = false;
    for (const std::string& overlay : options_.overlays) {
        if (overlay == "colors") colors = true;
        if (overlay == "lattice") screenshot.overlays.lattice = true;
        if (overlay == "wireframe") screenshot.overlays.wireframe = true;
        if (overlay == "jacobian") screenshot.overlays.jacobian = request.jacobian = true;
        if (overlay == "affected") screenshot.overlays.affected = request.affected = true;
    }
    if (!state_) {
        render::GlBackend backend = render::GlBackend::Auto;
        if (Status s = render::parseGlBackend(options_.glBackend, backend); !s) return s;
        auto state = std::make_unique<State>();
        if (Status s = render::OffscreenRenderer::create(backend, state->renderer); !s)
            return Status::error("cannot render " + pngPath + ": " + s.message);
        state_ = std::move(state);
    }
    if (Status s = state_->renderer->makeCurrent(); !s) return s;
    render::SceneData scene = sceneFromSession(session, request);
    if (colors && sourceMesh) scene.vertexColors = sessionVertexColors(*sourceMesh, session);
    return state_->renderer->screenshot(scene, screenshot, pngPath);
}

}  // namespace sculpt::app
