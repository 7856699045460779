// Headless rendering: a context (OSMesa or EGL), a Renderer and an offscreen multisampled target kept
// together, plus the one-call screenshot the CLI uses.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "core/status.h"
#include "render/camera.h"
#include "render/offscreen_context.h"
#include "render/render_target.h"
#include "render/renderer.h"
#include "render/scene.h"

namespace sculpt::render {

struct ScreenshotOptions {
    int width = 1280;  // pixels, >= 1
    int height = 800;  // pixels, >= 1
    // Camera angles in degrees (see Camera); unset: yaw 30, pitch 20. Distance unset: framed so that the
    // mesh (and the lattice too, when it is drawn) fills the picture with a margin.
    std::optional<float> yawDeg;
    std::optional<float> pitchDeg;
    std::optional<double> distance;       // world units (> 0)
    DrawOptions overlays;                 // lattice, wireframe, jacobian, affected, constraints, background
    GlBackend backend = GlBackend::Auto;  // used by renderScreenshot; an OffscreenRenderer keeps its own
    int samples = 4;                      // MSAA samples per pixel, clamped to what the context offers; 1 = off
    // Multiplies line widths and marker sizes (Renderer::setPixelScale). 0: by picture height, 1 at 800
    // pixels (clamped to 0.5 .. 4), so small pictures are not covered by markers and large ones keep them visible.
    float pixelScale = 0.0f;
};

// The pixel scale a screenshot of these options uses (see ScreenshotOptions::pixelScale).
float screenshotPixelScale(const ScreenshotOptions& options);

// The camera a screenshot of a scene with these bounds uses (see ScreenshotOptions).
Camera screenshotCamera(const Bounds& meshBounds, const Bounds& latticeBounds, const ScreenshotOptions& options);

class OffscreenRenderer {
public:
    // Creates the context (see OffscreenContext::create), the renderer and its shaders. The context is
    // current on this thread afterwards; every member below needs it current (makeCurrent() if another
    // context was made current on this thread since).
    static Status create(GlBackend backend, std::unique_ptr<OffscreenRenderer>& renderer);
    ~OffscreenRenderer();
    OffscreenRenderer(const OffscreenRenderer&) = delete;
    OffscreenRenderer& operator=(const OffscreenRenderer&) = delete;

    Status makeCurrent();
    Renderer& renderer();                    // for incremental updates (setMesh once, updatePositions, ...)
    const OffscreenContext& context() const; // backend, GL strings

    // Draws the renderer's current content at width x height with `samples` MSAA samples. image: the
    // resolved picture, rows top-down; null: no readback, but waits (glFinish) until the frame is done.
    Status render(const Camera& camera, const DrawOptions& options, int width, int height, int samples,
                  Rgba8Image* image);

    // setScene + screenshotCamera + render. options.backend is ignored (the context exists already).
    Status renderScene(const SceneData& scene, const ScreenshotOptions& options, Rgba8Image& image);
    // renderScene, then writes the PNG (atomically, see io::writePng).
    Status screenshot(const SceneData& scene, const ScreenshotOptions& options, const std::string& pngPath);

private:
    OffscreenRenderer() = default;
    std::unique_ptr<OffscreenContext> context_;
    std::unique_ptr<Renderer> renderer_;
    std::unique_ptr<RenderTarget> target_;
};

// One call, for a single screenshot: creates a context of options.backend, renders scene, writes pngPath,
// destroys the context. For several screenshots keep an OffscreenRenderer instead (context creation and
// shader compilation cost ~50-100 ms). Fails without touching pngPath on any error (no GL, empty viewport,
// NaN in the scene, unwritable path).
Status renderScreenshot(const SceneData& scene, const ScreenshotOptions& options, const std::string& pngPath);

}  // namespace sculpt::render
