// Private to src/render: the interface the OSMesa and EGL implementations of OffscreenContext share.
// note: kept apart from offscreen_context.cpp because <GL/osmesa.h> pulls in <GL/gl.h>, which cannot share
// a translation unit with <GL/glcorearb.h>.
#pragma once

#include <memory>
#include <string>

#include "core/status.h"
#include "render/offscreen_context.h"

namespace sculpt::render {

struct OffscreenContext::Backend {
    virtual ~Backend() = default;
    virtual Status makeCurrent() = 0;
    virtual GlGetProc getProcAddress() const = 0;
    virtual GlBackend kind() const = 0;
    virtual std::string platform() const = 0;  // "osmesa", "egl/device", "egl/surfaceless", "egl/default"
};

// True once the process has begun exiting (std::exit / return from main). Mesa tears down its drivers in
// its own exit handlers, so contexts still alive then (static OffscreenRenderers) must not touch GL or the
// context any more: they are left to the operating system.
bool processExiting();
// Installs the exit handler behind processExiting(). Called after a context was created, i.e. after the
// library registered its own handlers, so ours runs before them.
void watchProcessExit();

// Each creates a GL 3.3 core context and makes it current; on failure says why (library missing, ...).
Status createOsMesaBackend(std::unique_ptr<OffscreenContext::Backend>& backend);
Status createEglBackend(std::unique_ptr<OffscreenContext::Backend>& backend);

}  // namespace sculpt::render
