// Headless OpenGL 3.3 core contexts: OSMesa (software, always available with libosmesa6) and EGL without
// any window system (surfaceless / device platform: reaches a GPU where there is one), chosen at run time.
//
// note: why both libraries are opened with dlopen at run time instead of linked. A binary that links libGL
// (or libOpenGL) and libOSMesa routes every gl* call to the glvnd stubs and OSMesa renders nothing. We
// instead dlopen libOSMesa.so.8 or libEGL.so.1 when a context is requested and take every GL entry point
// from that library's own getProcAddress (OSMesaGetProcAddress / eglGetProcAddress) into a GlFunctions
// table. So one binary offers both backends with no link-order trap, links no GL library at all, and
// still starts (and reports a clear error) on a machine missing one of them. The alternative, an OSMesa
// shared module beside an EGL-linked binary, needs two build flavours and an install layout for no gain.
#pragma once

#include <memory>
#include <string>
#include <string_view>

#include "core/status.h"
#include "render/gl_proc.h"

namespace sculpt::render {

struct GlFunctions;

enum class GlBackend {
    Auto,    // EGL first (uses a GPU if there is one), then OSMesa
    OSMesa,  // libOSMesa.so.8, software (llvmpipe)
    Egl,     // libEGL.so.1: device platform, then Mesa surfaceless, then the default display
};

// "auto" | "osmesa" | "egl" (the CLI's --gl-backend values). Unknown text: error listing the choices.
Status parseGlBackend(std::string_view text, GlBackend& backend);
const char* glBackendName(GlBackend backend);

// Several contexts, of either backend, may live in one process. On one thread, switch between them with
// makeCurrent(). In a process with a window: OSMesa works while the window's context exists; EGL needs the
// window's (GLX) context released on this thread first (glvnd refuses otherwise, EGL_BAD_ACCESS).
class OffscreenContext {
public:
    // Creates a context (GL >= 3.3 core) and makes it current on this thread. No default framebuffer worth
    // drawing into: render into a RenderTarget. With Auto, the message on failure lists why each backend failed.
    static Status create(GlBackend requested, std::unique_ptr<OffscreenContext>& context);
    ~OffscreenContext();  // destroys the context; if it was current, no context is current afterwards
    OffscreenContext(const OffscreenContext&) = delete;
    OffscreenContext& operator=(const OffscreenContext&) = delete;

    Status makeCurrent();
    GlBackend backend() const;            // the one actually in use (never Auto)
    GlGetProc getProcAddress() const;     // OSMesaGetProcAddress or eglGetProcAddress
    const GlFunctions& gl() const;        // loaded from getProcAddress()
    // e.g. "osmesa | Mesa | llvmpipe (LLVM 15.0.6, 256 bits) | 4.5 (Core Profile) Mesa 22.3.6"
    const std::string& description() const;
    std::string rendererName() const;     // glGetString(GL_RENDERER)

    struct Backend;  // one implementation per library (osmesa_context.cpp, egl_context.cpp)

private:
    OffscreenContext() = default;
    std::unique_ptr<Backend> backend_;
    std::unique_ptr<GlFunctions> gl_;
    std::string description_;
};

}  // namespace sculpt::render
