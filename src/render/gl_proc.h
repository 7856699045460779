// The type of a GL context's getProcAddress, without any GL header (so it can be included beside <GL/gl.h>).
#pragma once

namespace sculpt::render {

// Same shape as glfwGetProcAddress, OSMesaGetProcAddress and eglGetProcAddress.
using GlProc = void (*)();
using GlGetProc = GlProc (*)(const char* name);

}  // namespace sculpt::render
