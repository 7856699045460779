// Screenshots of whatever framebuffer is bound for drawing: the window's back buffer or an offscreen FBO.
#pragma once

#include "core/status.h"
#include "render/gl_functions.h"
#include "render/render_target.h"

namespace sculpt::render {

// Reads the lower-left width x height pixels of the framebuffer currently bound for drawing into image, rows
// top-down, alpha forced to 255 (the scene's alpha is not meant as transparency). A multisampled FBO is
// resolved through a temporary single-sample one first (glReadPixels refuses multisampled FBOs; the default
// framebuffer resolves by itself). The read and draw framebuffer bindings are restored. Needs a current
// context; fails on a non-positive size or a GL error, leaving image unchanged.
Status readBoundFramebuffer(const GlFunctions& gl, int width, int height, Rgba8Image& image);

}  // namespace sculpt::render
