#include "render/offscreen_context.h"

#include <atomic>
#include <cstdlib>

#include "render/gl_functions.h"
#include "render/offscreen_backend.h"

namespace sculpt::render {

namespace {

std::atomic<bool> gProcessExiting{false};

}  // namespace

bool processExiting() { return gProcessExiting.load(); }

void watchProcessExit() {
    // note: exit handlers run in reverse order of registration, so one registered after Mesa's (which
    // exist once a context was created) runs before Mesa destroys its screens and threads.
    static const bool installed = [] { return std::atexit([] { gProcessExiting.store(true); }) == 0; }();
    (void)installed;
}

Status parseGlBackend(std::string_view text, GlBackend& backend) {
    if (text == "auto") backend = GlBackend::Auto;
    else if (text == "osmesa") backend = GlBackend::OSMesa;
    else if (text == "egl") backend = GlBackend::Egl;
    else return Status::error("unknown GL backend '" + std::string(text) + "': expected auto, osmesa or egl");
    return Status::success();
}

const char* glBackendName(GlBackend backend) {
    switch (backend) {
        case GlBackend::Auto: return "auto";
        case GlBackend::OSMesa: return "osmesa";
        case GlBackend::Egl: return "egl";
    }
    return "?";
}

Status OffscreenContext::create(GlBackend requested, std::unique_ptr<OffscreenContext>& context) {
    std::unique_ptr<Backend> backend;
    std::string why;
    // note: Auto prefers EGL because it is the path that reaches a GPU; without one both give llvmpipe.
    if (requested == GlBackend::Egl || requested == GlBackend::Auto) {
        Status status = createEglBackend(backend);
        if (!status) {
            if (requested == GlBackend::Egl) return status;
            why = status.message;
        }
    }
    if (!backend) {
        Status status = createOsMesaBackend(backend);
        if (!status) return why.empty() ? status : Status::error(why + "\n" + status.message);
    }
    watchProcessExit();
    std::unique_ptr<OffscreenContext> created(new OffscreenContext());
    created->backend_ = std::move(backend);
    created->gl_ = std::make_unique<GlFunctions>();
    if (Status status = loadGlFunctions(created->backend_->getProcAddress(), *created->gl_); !status)
        return status;
    std::string description;
    if (Status status = checkGlVersion(*created->gl_, &description); !status)
        return Status::error(created->backend_->platform() + ": " + status.message);
    created->description_ = created->backend_->platform() + " | " + description;
    context = std::move(created);
    return Status::success();
}

OffscreenContext::~OffscreenContext() = default;

Status OffscreenContext::makeCurrent() { return backend_->makeCurrent(); }
GlBackend OffscreenContext::backend() const { return backend_->kind(); }
GlGetProc OffscreenContext::getProcAddress() const { return backend_->getProcAddress(); }
const GlFunctions& OffscreenContext::gl() const { return *gl_; }
const std::string& OffscreenContext::description() const { return description_; }

std::string OffscreenContext::rendererName() const {
    const GLubyte* name = gl_->GetString(GL_RENDERER);
    return name ? reinterpret_cast<const char*>(name) : "";
}

}  // namespace sculpt::render
