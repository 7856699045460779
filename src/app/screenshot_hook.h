// Offscreen screenshots of the session for the headless mode (renderer + OSMesa/EGL context), created on
// first use and kept for later screenshot ops. In a build without the renderer, capture() says so.
#pragma once

#include <memory>
#include <string>

#include "app/cli_options.h"
#include "core/session.h"
#include "core/status.h"

namespace sculpt::app {

class ScreenshotRenderer {
public:
    explicit ScreenshotRenderer(const CliOptions& options);
    ~ScreenshotRenderer();
    Status capture(const core::Session& session, const std::string& pngPath);

private:
    struct State;
    CliOptions options_;
    std::unique_ptr<State> state_;
};

}  // namespace sculpt::app
