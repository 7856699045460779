#include "render/framebuffer_readback.h"

#include <cstring>
#include <string>
#include <vector>

namespace sculpt::render {

Status readBoundFramebuffer(const GlFunctions& gl, int width, int height, Rgba8Image& image) {
    if (width <= 0 || height <= 0) return Status::error("screenshot of an empty framebuffer");
    for (int i = 0; i < 16 && gl.GetError() != GL_NO_ERROR; ++i) {
    }  // errors of earlier calls are not ours to report
    GLint drawBinding = 0, readBinding = 0, sampleBuffers = 0;
    gl.GetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &drawBinding);
    gl.GetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &readBinding);
    gl.GetIntegerv(GL_SAMPLE_BUFFERS, &sampleBuffers);
    const GLuint source = static_cast<GLuint>(drawBinding);
    GLuint resolveFramebuffer = 0, resolveBuffer = 0;
    if (source != 0 && sampleBuffers > 0) {
        gl.GenFramebuffers(1, &resolveFramebuffer);
        gl.GenRenderbuffers(1, &resolveBuffer);
        gl.BindRenderbuffer(GL_RENDERBUFFER, resolveBuffer);
        gl.RenderbufferStorageMultisample(GL_RENDERBUFFER, 0, GL_RGBA8, width, height);
        gl.BindRenderbuffer(GL_RENDERBUFFER, 0);
        gl.BindFramebuffer(GL_DRAW_FRAMEBUFFER, resolveFramebuffer);
        gl.FramebufferRenderbuffer(GL_DRAW_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, resolveBuffer);
        gl.BindFramebuffer(GL_READ_FRAMEBUFFER, source);
        gl.BlitFramebuffer(0, 0, width, height, 0, 0, width, height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
        gl.BindFramebuffer(GL_READ_FRAMEBUFFER, resolveFramebuffer);
    } else {
        // note: the default read buffer of a double-buffered window is GL_BACK, the frame just drawn.
        gl.BindFramebuffer(GL_READ_FRAMEBUFFER, source);
    }
    const size_t rowBytes = static_cast<size_t>(width) * 4;
    std::vector<std::uint8_t> pixels(rowBytes * static_cast<size_t>(height));
    gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
    gl.ReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, pixels.data());
    const GLenum error = gl.GetError();
    gl.BindFramebuffer(GL_DRAW_FRAMEBUFFER, source);
    gl.BindFramebuffer(GL_READ_FRAMEBUFFER, static_cast<GLuint>(readBinding));
    if (resolveFramebuffer) gl.DeleteFramebuffers(1, &resolveFramebuffer);
    if (resolveBuffer) gl.DeleteRenderbuffers(1, &resolveBuffer);
    if (error != GL_NO_ERROR) return Status::error("reading the framebuffer failed: GL error " + std::to_string(error));
    // glReadPixels is bottom-up; the image is top-down.
    std::vector<std::uint8_t> row(rowBytes);
    for (int y = 0; y < height / 2; ++y) {
        std::uint8_t* top = pixels.data() + static_cast<size_t>(y) * rowBytes;
        std::uint8_t* bottom = pixels.data() + static_cast<size_t>(height - 1 - y) * rowBytes;
        std::memcpy(row.data(), top, rowBytes);
        std::memcpy(top, bottom, rowBytes);
        std::memcpy(bottom, row.data(), rowBytes);
    }
    for (size_t p = 3; p < pixels.size(); p += 4) pixels[p] = 255;
    image.width = width;
    image.height = height;
    image.pixels = std::move(pixels);
    return Status::success();
}

}  // namespace sculpt::render
