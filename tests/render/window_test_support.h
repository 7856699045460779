// Shared by the window tests that drive SculptApp with synthetic events (Catch2 assertions inside).
#pragma once

#include <string>

#include <catch2/catch.hpp>

#include "app/window/sculpt_app.h"
#include "app/window/tools.h"
#include "offscreen_window.h"

namespace sculpt::test {

// Loads assets/default.obj into the app for a width x height framebuffer and frames it.
inline void loadDefaultMesh(app::SculptApp& sculptApp, int width, int height) {
    const Status loaded = sculptApp.loadMesh(std::string(SCULPT_SOURCE_DIR) + "/assets/default.obj");
    INFO(loaded.message);
    REQUIRE(loaded.ok);
    sculptApp.onFramebufferSize({width, height});
    app::frameMesh(sculptApp.state());
}

// Opens `window` for the app without MSAA (as on a software rasterizer) and loads the default mesh into it;
// false, with a warning, where there is no EGL context (the caller skips its frames then).
inline bool openWindowWithDefaultMesh(OffscreenWindow& window, app::SculptApp& sculptApp, int width, int height) {
    const Status opened = window.open(sculptApp, width, height, 0);
    if (!opened) {
        WARN("no EGL context, frames skipped: " << opened.message);
        return false;
    }
    loadDefaultMesh(sculptApp, width, height);
    return true;
}

// Pixel position of a world point in the app's framebuffer (a point behind the eye fails the test).
inline Eigen::Vector2d pixelOf(const app::AppState& state, const Eigen::Vector3d& point) {
    double x = 0, y = 0;
    REQUIRE(app::projectToPixel(state.camera, state.framebufferWidth, state.framebufferHeight, point, x, y));
    return {x, y};
}

inline double boundsDiagonal(const Positions& p) { return (p.colwise().maxCoeff() - p.colwise().minCoeff()).norm(); }

}  // namespace sculpt::test
