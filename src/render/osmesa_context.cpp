// OffscreenContext backend over OSMesa, opened with dlopen (see offscreen_context.h for why).
#include <GL/osmesa.h>
#include <dlfcn.h>

#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

#include "render/offscreen_backend.h"

namespace sculpt::render {

namespace {

struct OsMesaLibrary {
    void* handle = nullptr;
    std::string error;
    OSMesaContext (*createContextAttribs)(const int*, OSMesaContext) = nullptr;
    GLboolean (*makeCurrent)(OSMesaContext, void*, GLenum, GLsizei, GLsizei) = nullptr;
    void (*destroyContext)(OSMesaContext) = nullptr;
    OSMesaContext (*getCurrentContext)() = nullptr;
    OSMESAproc (*getProcAddress)(const char*) = nullptr;
};

// Opened once per process and never closed: Mesa registers exit handlers and thread-local state, which
// makes unloading it unsafe.
const OsMesaLibrary& osMesaLibrary() {
    static const OsMesaLibrary library = [] {
        OsMesaLibrary lib;
        for (const char* name : {"libOSMesa.so.8", "libOSMesa.so.6", "libOSMesa.so"}) {
            lib.handle = dlopen(name, RTLD_NOW | RTLD_LOCAL);
            if (lib.handle) break;
            const char* why = dlerror();
            lib.error += std::string(lib.error.empty() ? "" : "; ") + (why ? why : name);
        }
        if (!lib.handle) return lib;
        const auto load = [&](auto& function, const char* symbol) {
            function = reinterpret_cast<std::remove_reference_t<decltype(function)>>(dlsym(lib.handle, symbol));
            if (!function) lib.error += std::string(lib.error.empty() ? "" : "; ") + "no " + symbol;
        };
        lib.error.clear();
        load(lib.createContextAttribs, "OSMesaCreateContextAttribs");
        load(lib.makeCurrent, "OSMesaMakeCurrent");
        load(lib.destroyContext, "OSMesaDestroyContext");
        load(lib.getCurrentContext, "OSMesaGetCurrentContext");
        load(lib.getProcAddress, "OSMesaGetProcAddress");
        return lib;
    }();
    return library;
}

class OsMesaBackend final : public OffscreenContext::Backend {
public:
    OsMesaBackend(const OsMesaLibrary& library, OSMesaContext context) : library_(library), context_(context) {}
    ~OsMesaBackend() override {
        if (processExiting()) return;  // Mesa may already be torn down (see offscreen_backend.h)
        if (library_.getCurrentContext() == context_) library_.makeCurrent(nullptr, nullptr, 0, 0, 0);
        library_.destroyContext(context_);
    }
    Status makeCurrent() override {
        // note: OSMesa needs a colour buffer to make a context current; we draw into FBOs, so a tiny one
        // serves (its size does not limit FBO sizes).
        if (!library_.makeCurrent(context_, buffer_.data(), GL_UNSIGNED_BYTE, kBufferSize, kBufferSize))
            return Status::error("OSMesaMakeCurrent failed");
        return Status::success();
    }
    GlGetProc getProcAddress() const override { return reinterpret_cast<GlGetProc>(library_.getProcAddress); }
    GlBackend kind() const override { return GlBackend::OSMesa; }
    std::string platform() const override { return "osmesa"; }

private:
    static constexpr int kBufferSize = 16;
    const OsMesaLibrary& library_;
    OSMesaContext context_;
    std::vector<std::uint8_t> buffer_ = std::vector<std::uint8_t>(kBufferSize * kBufferSize * 4);
};

}  // namespace

Status createOsMesaBackend(std::unique_ptr<OffscreenContext::Backend>& backend) {
    const OsMesaLibrary& library = osMesaLibrary();
    if (!library.handle || !library.error.empty())
        return Status::error("OSMesa not available (" + library.error + "); install libosmesa6");
    const int attributes[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 24, OSMESA_STENCIL_BITS, 8,
                              OSMESA_PROFILE, OSMESA_CORE_PROFILE, OSMESA_CONTEXT_MAJOR_VERSION, 3,
                              OSMESA_CONTEXT_MINOR_VERSION, 3, 0};
    OSMesaContext context = library.createContextAttribs(attributes, nullptr);
    if (!context) return Status::error("OSMesaCreateContextAttribs failed to create a 3.3 core context");
    auto created = std::make_unique<OsMesaBackend>(library, context);
    if (Status status = created->makeCurrent(); !status) return status;
    backend = std::move(created);
    return Status::success();
}

}  // namespace sculpt::render
