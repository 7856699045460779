// Offscreen screenshots of the session for the headless mode (renderer + OSMesa/EGL context), created on
// first use and kept for later screenshot ops. In a build without the renderer, capture() says so.
#pragma once

#include <memory>
#include <string>

#include "app/cli_options.h"
#include "core/session/session.h"
#include "core/status.h"
#include "io/obj_mesh.h"

namespace sculpt::app {

class ScreenshotRenderer {
public:
    explicit ScreenshotRenderer(const CliOptions& options);
    ~ScreenshotRenderer();
    // sourceMesh: the file the session was set up from, whose colours `--overlay colors` draws (null: none).
    Status capture(const core::Session& session, const std::string& pngPath, const io::ObjMesh* sourceMesh = nullptr);

private:
    struct State;
    CliOptions options_;
    std::unique_ptr<State> state_;
};

}  // namespace sculpt::app
