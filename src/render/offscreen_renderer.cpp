#include "render/offscreen_renderer.h"

#include <algorithm>

#include "io/png_image.h"
#include "render/gl_functions.h"
#include "render/offscreen_backend.h"

namespace sculpt::render {

Camera screenshotCamera(const Bounds& meshBounds, const Bounds& latticeBounds, const ScreenshotOptions& options) {
    Camera camera;
    if (options.yawDeg) camera.yawDeg = *options.yawDeg;
    if (options.pitchDeg) camera.pitchDeg = *options.pitchDeg;
    Bounds content = meshBounds;
    if (options.overlays.lattice) content.add(latticeBounds);
    const float aspect = options.height > 0 ? float(options.width) / float(options.height) : 1.0f;
    camera.frame(content, aspect);
    if (options.distance) camera.distance = *options.distance;
    // A user-chosen distance may put the eye outside the framed range; keep the near/far planes around
    // everything that can be seen from there.
    camera.sceneRadius = std::max(camera.sceneRadius, 0.5 * camera.distance);
    return camera;
}

float screenshotPixelScale(const ScreenshotOptions& options) {
    if (options.pixelScale > 0.0f) return options.pixelScale;
    return std::clamp(float(options.height) / 800.0f, 0.5f, 4.0f);
}

Status OffscreenRenderer::create(GlBackend backend, std::unique_ptr<OffscreenRenderer>& renderer) {
    std::unique_ptr<OffscreenRenderer> created(new OffscreenRenderer());
    if (Status status = OffscreenContext::create(backend, created->context_); !status) return status;
    created->renderer_ = std::make_unique<Renderer>();
    if (Status status = created->renderer_->init(created->context_->gl()); !status) return status;
    created->target_ = std::make_unique<RenderTarget>(created->context_->gl());
    renderer = std::move(created);
    return Status::success();
}

OffscreenRenderer::~OffscreenRenderer() {
    // GL objects go before their context; only possible while it is current. At process exit the
    // driver may be gone already: leave everything to the operating system.
    if (context_ && !processExiting() && context_->makeCurrent()) {
        if (renderer_) renderer_->release();
        if (target_) target_->release();
    }
}

Status OffscreenRenderer::makeCurrent() { return context_->makeCurrent(); }
Renderer& OffscreenRenderer::renderer() { return *renderer_; }
const OffscreenContext& OffscreenRenderer::context() const { return *context_; }

Status OffscreenRenderer::render(const Camera& camera, const DrawOptions& options, int width, int height,
                                 int samples, Rgba8Image* image) {
    if (Status status = target_->resize(width, height, samples); !status) return status;
    target_->bind();
    if (Status status = renderer_->draw(camera, options, width, height); !status) return status;
    if (image) return target_->read(*image);
    context_->gl().Finish();
    return Status::success();
}

Status OffscreenRenderer::renderScene(const SceneData& scene, const ScreenshotOptions& options, Rgba8Image& image) {
    if (options.width < 1 || options.height < 1)
        return Status::error("screenshot size " + std::to_string(options.width) + " x " +
                             std::to_string(options.height) + " is empty: width and height must be at least 1");
    if (Status status = renderer_->setScene(scene); !status) return status;
    const Camera camera = screenshotCamera(renderer_->meshBounds(), renderer_->latticeBounds(), options);
    renderer_->setPixelScale(screenshotPixelScale(options));
    return render(camera, options.overlays, options.width, options.height, options.samples, &image);
}

Status OffscreenRenderer::screenshot(const SceneData& scene, const ScreenshotOptions& options,
                                     const std::string& pngPath) {
    Rgba8Image image;
    if (Status status = renderScene(scene, options, image); !status) return status;
    return io::writePng(pngPath, image.width, image.height, image.pixels.data());
}

Status renderScreenshot(const SceneData& scene, const ScreenshotOptions& options, const std::string& pngPath) {
    if (options.width < 1 || options.height < 1)
        return Status::error("screenshot size " + std::to_string(options.width) + " x " +
                             std::to_string(options.height) + " is empty: width and height must be at least 1");
    std::unique_ptr<OffscreenRenderer> renderer;
    if (Status status = OffscreenRenderer::create(options.backend, renderer); !status) return status;
    return renderer->screenshot(scene, options, pngPath);
}

}  // namespace sculpt::render
