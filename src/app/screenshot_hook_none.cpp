// Screenshot hook for builds without the renderer (SCULPT_BUILD_GL=OFF).
#include "app/screenshot_hook.h"

namespace sculpt::app {

struct ScreenshotRenderer::State {};

ScreenshotRenderer::ScreenshotRenderer(const CliOptions& options) : options_(options) {}
ScreenshotRenderer::~ScreenshotRenderer() = default;

Status ScreenshotRenderer::capture(const core::Session&, const std::string& pngPath, const io::ObjMesh*) {
    return Status::error("cannot write " + pngPath + ": this build has no renderer (configure with SCULPT_BUILD_GL=ON)");
}

}  // namespace sculpt::app
