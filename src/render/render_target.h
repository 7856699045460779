// An offscreen framebuffer: multisampled colour + depth renderbuffers, resolved into a single-sample
// colour buffer before readback.
#pragma once

#include <cstdint>
#include <vector>

#include "render/gl_functions.h"

namespace sculpt::render {

// 8-bit RGBA pixels, rows top-down (row 0 is the top of the picture), 4 * width * height bytes.
struct Rgba8Image {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> pixels;
};

class RenderTarget {
public:
    // Needs a current context; keeps a copy of gl.
    explicit RenderTarget(const GlFunctions& gl) : gl_(gl) {}
    ~RenderTarget() = default;  // release() must be called with the context current (no GL in destructors)
    RenderTarget(const RenderTarget&) = delete;
    RenderTarget& operator=(const RenderTarget&) = delete;

    // (Re)allocates for width x height with `samples` per pixel (clamped to GL_MAX_SAMPLES; <= 1 = no MSAA).
    // Does nothing if already that size. Fails on a non-positive or too large size, or an incomplete FBO.
    Status resize(int width, int height, int samples);
    // Binds the (multisampled) draw framebuffer and sets the viewport.
    void bind() const;
    // Resolves the samples and reads the picture back, top-down. Leaves framebuffer 0 bound.
    Status read(Rgba8Image& image) const;
    void release();

    int width() const { return width_; }
    int height() const { return height_; }
    int samples() const { return samples_; }  // actually allocated; 0 = single-sample

private:
    GlFunctions gl_;
    int width_ = 0, height_ = 0, samples_ = 0, requestedSamples_ = -1;
    GLuint drawFramebuffer_ = 0, colorBuffer_ = 0, depthBuffer_ = 0;
    GLuint resolveFramebuffer_ = 0, resolveBuffer_ = 0;  // only when multisampled
};

}  // namespace sculpt::render
