#include "render/render_target.h"

#include <algorithm>
#include <cstring>
#include <string>

namespace sculpt::render {

namespace {

std::string framebufferStatusText(GLenum status) {
    switch (status) {
        case GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT: return "incomplete attachment";
        case GL_FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT: return "missing attachment";
        case GL_FRAMEBUFFER_UNSUPPORTED: return "unsupported format combination";
        case GL_FRAMEBUFFER_INCOMPLETE_MULTISAMPLE: return "inconsistent sample counts";
        default: return "status " + std::to_string(status);
    }
}

}  // namespace

Status RenderTarget::resize(int width, int height, int samples) {
    if (width <= 0 || height <= 0)
        return Status::error("viewport size " + std::to_string(width) + " x " + std::to_string(height) +
                             " is empty: width and height must be at least 1");
    if (width == width_ && height == height_ && samples == requestedSamples_) return Status::success();
    GLint maxSize = 0, maxSamples = 0;
    gl_.GetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &maxSize);
    gl_.GetIntegerv(GL_MAX_SAMPLES, &maxSamples);
    if (width > maxSize || height > maxSize)
        return Status::error("viewport size " + std::to_string(width) + " x " + std::to_string(height) +
                             " exceeds this GL's limit of " + std::to_string(maxSize));
    release();
    // note: 0 means a plain single-sample renderbuffer; asking for 1 sample gets an MSAA buffer on some drivers.
    const int sampleCount = samples > 1 ? std::min(samples, int(maxSamples)) : 0;

    gl_.GenFramebuffers(1, &drawFramebuffer_);
    gl_.BindFramebuffer(GL_FRAMEBUFFER, drawFramebuffer_);
    gl_.GenRenderbuffers(1, &colorBuffer_);
    gl_.BindRenderbuffer(GL_RENDERBUFFER, colorBuffer_);
    gl_.RenderbufferStorageMultisample(GL_RENDERBUFFER, sampleCount, GL_RGBA8, width, height);
    gl_.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colorBuffer_);
    gl_.GenRenderbuffers(1, &depthBuffer_);
    gl_.BindRenderbuffer(GL_RENDERBUFFER, depthBuffer_);
    gl_.RenderbufferStorageMultisample(GL_RENDERBUFFER, sampleCount, GL_DEPTH24_STENCIL8, width, height);
    gl_.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, depthBuffer_);
    GLenum status = gl_.CheckFramebufferStatus(GL_FRAMEBUFFER);
    if (status == GL_FRAMEBUFFER_COMPLETE && sampleCount > 0) {
        gl_.GenFramebuffers(1, &resolveFramebuffer_);
        gl_.BindFramebuffer(GL_FRAMEBUFFER, resolveFramebuffer_);
        gl_.GenRenderbuffers(1, &resolveBuffer_);
        gl_.BindRenderbuffer(GL_RENDERBUFFER, resolveBuffer_);
        gl_.RenderbufferStorageMultisample(GL_RENDERBUFFER, 0, GL_RGBA8, width, height);
        gl_.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, resolveBuffer_);
        status = gl_.CheckFramebufferStatus(GL_FRAMEBUFFER);
    }
    gl_.BindRenderbuffer(GL_RENDERBUFFER, 0);
    gl_.BindFramebuffer(GL_FRAMEBUFFER, 0);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
        release();
        return Status::error("offscreen framebuffer " + std::to_string(width) + " x " + std::to_string(height) +
                             " is not complete: " + framebufferStatusText(status));
    }
    width_ = width;
    height_ = height;
    samples_ = sampleCount;
    requestedSamples_ = samples;
    return Status::success();
}

void RenderTarget::bind() const {
    gl_.BindFramebuffer(GL_FRAMEBUFFER, drawFramebuffer_);
    gl_.Viewport(0, 0, width_, height_);
}

Status RenderTarget::read(Rgba8Image& image) const {
    if (drawFramebuffer_ == 0) return Status::error("offscreen framebuffer not allocated");
    GLuint readFramebuffer = drawFramebuffer_;
    if (resolveFramebuffer_ != 0) {
        gl_.BindFramebuffer(GL_READ_FRAMEBUFFER, drawFramebuffer_);
        gl_.BindFramebuffer(GL_DRAW_FRAMEBUFFER, resolveFramebuffer_);
        gl_.BlitFramebuffer(0, 0, width_, height_, 0, 0, width_, height_, GL_COLOR_BUFFER_BIT, GL_NEAREST);
        readFramebuffer = resolveFramebuffer_;
    }
    gl_.BindFramebuffer(GL_READ_FRAMEBUFFER, readFramebuffer);
    image.width = width_;
    image.height = height_;
    const size_t rowBytes = size_t(width_) * 4;
    image.pixels.resize(rowBytes * size_t(height_));
    gl_.PixelStorei(GL_PACK_ALIGNMENT, 1);
    gl_.ReadPixels(0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, image.pixels.data());
    gl_.BindFramebuffer(GL_FRAMEBUFFER, 0);
    const GLenum error = gl_.GetError();
    if (error != GL_NO_ERROR) return Status::error("reading the offscreen framebuffer failed: GL error " +
                                                   std::to_string(error));
    // GL rows are bottom-up; flip in place to top-down.
    std::vector<std::uint8_t> row(rowBytes);
    for (int y = 0; y < height_ / 2; ++y) {
        std::uint8_t* top = image.pixels.data() + size_t(y) * rowBytes;
        std::uint8_t* bottom = image.pixels.data() + size_t(height_ - 1 - y) * rowBytes;
        std::memcpy(row.data(), top, rowBytes);
        std::memcpy(top, bottom, rowBytes);
        std::memcpy(bottom, row.data(), rowBytes);
    }
    return Status::success();
}

void RenderTarget::release() {
    if (drawFramebuffer_) gl_.DeleteFramebuffers(1, &drawFramebuffer_);
    if (resolveFramebuffer_) gl_.DeleteFramebuffers(1, &resolveFramebuffer_);
    if (colorBuffer_) gl_.DeleteRenderbuffers(1, &colorBuffer_);
    if (depthBuffer_) gl_.DeleteRenderbuffers(1, &depthBuffer_);
    if (resolveBuffer_) gl_.DeleteRenderbuffers(1, &resolveBuffer_);
    drawFramebuffer_ = resolveFramebuffer_ = colorBuffer_ = depthBuffer_ = resolveBuffer_ = 0;
    width_ = height_ = samples_ = 0;
    requestedSamples_ = -1;
}

}  // namespace sculpt::render
