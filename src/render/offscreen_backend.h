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

// Each creates a GL 3.3 core context and makes it current; on failure says why (library missing, ...).
Status createOsMesaBackend(std::unique_ptr<OffscreenContext::Backend>& backend);
Status createEglBackend(std::unique_ptr<OffscreenContext::Backend>& backend);

}  // namespace sculpt::render
