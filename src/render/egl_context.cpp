// OffscreenContext backend over EGL without a window system, opened with dlopen (see offscreen_context.h).
// Displays are tried in this order, the first that gives a GL 3.3 core context wins:
//  1. EGL_EXT_platform_device: each enumerated device (NVIDIA's headless path; Mesa lists its DRM devices
//     and a software device),
//  2. EGL_MESA_platform_surfaceless (Mesa without a GPU: llvmpipe),
//  3. eglGetDisplay(EGL_DEFAULT_DISPLAY) (some NVIDIA drivers answer here without X).
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <dlfcn.h>

#include <cstdio>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

#include "render/offscreen_backend.h"

namespace sculpt::render {

namespace {

struct EglLibrary {
    void* handle = nullptr;
    std::string error;
    PFNEGLGETPROCADDRESSPROC getProcAddress = nullptr;
    PFNEGLGETERRORPROC getError = nullptr;
    PFNEGLGETDISPLAYPROC getDisplay = nullptr;
    PFNEGLINITIALIZEPROC initialize = nullptr;
    PFNEGLQUERYSTRINGPROC queryString = nullptr;
    PFNEGLBINDAPIPROC bindApi = nullptr;
    PFNEGLCHOOSECONFIGPROC chooseConfig = nullptr;
    PFNEGLCREATECONTEXTPROC createContext = nullptr;
    PFNEGLDESTROYCONTEXTPROC destroyContext = nullptr;
    PFNEGLMAKECURRENTPROC makeCurrent = nullptr;
    PFNEGLGETCURRENTCONTEXTPROC getCurrentContext = nullptr;
    PFNEGLCREATEPBUFFERSURFACEPROC createPbufferSurface = nullptr;
    PFNEGLDESTROYSURFACEPROC destroySurface = nullptr;
    // Extensions (may stay null).
    PFNEGLGETPLATFORMDISPLAYEXTPROC getPlatformDisplay = nullptr;
    PFNEGLQUERYDEVICESEXTPROC queryDevices = nullptr;
};

// Opened once per process and never closed (see osmesa_context.cpp).
const EglLibrary& eglLibrary() {
    static const EglLibrary library = [] {
        EglLibrary lib;
        lib.handle = dlopen("libEGL.so.1", RTLD_NOW | RTLD_LOCAL);
        if (!lib.handle) {
            const char* why = dlerror();
            lib.error = why ? why : "dlopen(libEGL.so.1) failed";
            return lib;
        }
        const auto load = [&](auto& function, const char* symbol) {
            function = reinterpret_cast<std::remove_reference_t<decltype(function)>>(dlsym(lib.handle, symbol));
            if (!function) lib.error += std::string(lib.error.empty() ? "" : "; ") + "no " + symbol;
        };
        load(lib.getProcAddress, "eglGetProcAddress");
        load(lib.getError, "eglGetError");
        load(lib.getDisplay, "eglGetDisplay");
        load(lib.initialize, "eglInitialize");
        load(lib.queryString, "eglQueryString");
        load(lib.bindApi, "eglBindAPI");
        load(lib.chooseConfig, "eglChooseConfig");
        load(lib.createContext, "eglCreateContext");
        load(lib.destroyContext, "eglDestroyContext");
        load(lib.makeCurrent, "eglMakeCurrent");
        load(lib.getCurrentContext, "eglGetCurrentContext");
        load(lib.createPbufferSurface, "eglCreatePbufferSurface");
        load(lib.destroySurface, "eglDestroySurface");
        if (lib.getProcAddress) {
            lib.getPlatformDisplay =
                reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(lib.getProcAddress("eglGetPlatformDisplayEXT"));
            lib.queryDevices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(lib.getProcAddress("eglQueryDevicesEXT"));
        }
        return lib;
    }();
    return library;
}

bool hasExtension(const char* list, const char* name) {
    if (!list) return false;
    const size_t length = std::strlen(name);
    for (const char* at = std::strstr(list, name); at; at = std::strstr(at + 1, name))
        if ((at == list || at[-1] == ' ') && (at[length] == ' ' || at[length] == '\0')) return true;
    return false;
}

std::string eglErrorText(EGLint error) {
    char text[16];
    std::snprintf(text, sizeof text, "0x%04X", unsigned(error));
    return text;
}

class EglBackend final : public OffscreenContext::Backend {
public:
    EglBackend(const EglLibrary& library, EGLDisplay display, EGLContext context, EGLSurface surface,
               std::string platform)
        : library_(library), display_(display), context_(context), surface_(surface), platform_(std::move(platform)) {}
    ~EglBackend() override {
        if (processExiting()) return;  // the driver may already be torn down (see offscreen_backend.h)
        if (library_.getCurrentContext() == context_)
            library_.makeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        if (surface_ != EGL_NO_SURFACE) library_.destroySurface(display_, surface_);
        library_.destroyContext(display_, context_);
        // note: the display is not terminated: EGL hands out one display per platform and device, so another
        // context of this process may still use it. An initialised display costs nothing at exit.
    }
    Status makeCurrent() override {
        // note: glvnd skips eglMakeCurrent when it believes the context is current already. An OSMesa
        // context made current on this thread in between changes Mesa's own current-context state behind
        // glvnd's back (both use libglapi), so GL calls would then reach no context. Releasing first forces
        // the driver to bind again.
        if (library_.getCurrentContext() == context_)
            library_.makeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        if (!library_.makeCurrent(display_, surface_, surface_, context_)) {
            const EGLint error = library_.getError();
            // note: glvnd refuses to make an EGL context current while a GLX context (e.g. a GLFW window's)
            // is current on this thread.
            return Status::error("eglMakeCurrent failed: EGL error " + eglErrorText(error) +
                                 (error == EGL_BAD_ACCESS ? " (a window's GLX context is current on this thread: "
                                                            "release it first, or use the osmesa backend)"
                                                          : ""));
        }
        return Status::success();
    }
    GlGetProc getProcAddress() const override { return reinterpret_cast<GlGetProc>(library_.getProcAddress); }
    GlBackend kind() const override { return GlBackend::Egl; }
    std::string platform() const override { return platform_; }

private:
    const EglLibrary& library_;
    EGLDisplay display_;
    EGLContext context_;
    EGLSurface surface_;
    std::string platform_;
};

// Initialises `display` and makes a 3.3 core context current on it; appends the reason to `why` on failure.
bool tryDisplay(const EglLibrary& egl, EGLDisplay display, const std::string& platform,
                std::unique_ptr<OffscreenContext::Backend>& backend, std::string& why) {
    const auto fail = [&](const std::string& step) {
        why += "; " + platform + ": " + step + " failed (EGL error " + eglErrorText(egl.getError()) + ")";
        return false;
    };
    if (display == EGL_NO_DISPLAY) return fail("getting the display");
    EGLint major = 0, minor = 0;
    if (!egl.initialize(display, &major, &minor)) return fail("eglInitialize");
    if (!egl.bindApi(EGL_OPENGL_API)) return fail("eglBindAPI(EGL_OPENGL_API)");
    const char* extensions = egl.queryString(display, EGL_EXTENSIONS);
    const bool surfaceless = hasExtension(extensions, "EGL_KHR_surfaceless_context");

    const EGLint pbufferConfig[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT,
                                    EGL_RED_SIZE, 8, EGL_GREEN_SIZE, 8, EGL_BLUE_SIZE, 8, EGL_NONE};
    const EGLint anyConfig[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
    EGLConfig config = nullptr;
    EGLint configCount = 0;
    bool havePbufferConfig = egl.chooseConfig(display, pbufferConfig, &config, 1, &configCount) && configCount > 0;
    if (!havePbufferConfig) {
        configCount = 0;
        if (!(egl.chooseConfig(display, anyConfig, &config, 1, &configCount) && configCount > 0)) {
            if (!hasExtension(extensions, "EGL_KHR_no_config_context")) return fail("eglChooseConfig (OpenGL)");
            config = EGL_NO_CONFIG_KHR;
        }
    }
    if (!surfaceless && !havePbufferConfig) return fail("finding a surfaceless or pbuffer configuration");

    const EGLint contextAttributes[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 3,
                                        EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                        EGL_NONE};
    EGLContext context = egl.createContext(display, config, EGL_NO_CONTEXT, contextAttributes);
    if (context == EGL_NO_CONTEXT) return fail("eglCreateContext (OpenGL 3.3 core)");
    EGLSurface surface = EGL_NO_SURFACE;
    if (!surfaceless) {
        const EGLint pbufferAttributes[] = {EGL_WIDTH, 16, EGL_HEIGHT, 16, EGL_NONE};
        surface = egl.createPbufferSurface(display, config, pbufferAttributes);
        if (surface == EGL_NO_SURFACE) {
            egl.destroyContext(display, context);
            return fail("eglCreatePbufferSurface");
        }
    }
    auto created = std::make_unique<EglBackend>(egl, display, context, surface, platform);
    if (Status status = created->makeCurrent(); !status) {
        why += "; " + platform + ": " + status.message;
        return false;
    }
    backend = std::move(created);
    return true;
}

}  // namespace

Status createEglBackend(std::unique_ptr<OffscreenContext::Backend>& backend) {
    const EglLibrary& egl = eglLibrary();
    if (!egl.handle || !egl.error.empty())
        return Status::error("EGL not available (" + egl.error + "); install libegl1 and a driver (libegl-mesa0)");
    // Client extensions (EGL 1.5 / EGL_EXT_client_extensions); null on old implementations.
    const char* clientExtensions = egl.queryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    std::string why;
    if (egl.getPlatformDisplay && egl.queryDevices && hasExtension(clientExtensions, "EGL_EXT_platform_device")) {
        EGLDeviceEXT devices[16];
        EGLint deviceCount = 0;
        if (egl.queryDevices(16, devices, &deviceCount)) {
            for (EGLint d = 0; d < deviceCount; ++d) {
                const EGLDisplay display = egl.getPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[d], nullptr);
                if (tryDisplay(egl, display, "egl/device" + std::to_string(d), backend, why)) return Status::success();
            }
        }
        if (deviceCount == 0) why += "; egl/device: no devices";
    }
    if (egl.getPlatformDisplay && hasExtension(clientExtensions, "EGL_MESA_platform_surfaceless")) {
        const EGLDisplay display = egl.getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
        if (tryDisplay(egl, display, "egl/surfaceless", backend, why)) return Status::success();
    }
    if (tryDisplay(egl, egl.getDisplay(EGL_DEFAULT_DISPLAY), "egl/default", backend, why)) return Status::success();
    return Status::error("EGL: no display gave an OpenGL 3.3 core context" + why);
}

}  // namespace sculpt::render
