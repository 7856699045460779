#include "render/gl_functions.h"

#include <cstdio>
#include <string>

namespace sculpt::render {

Status loadGlFunctions(GlGetProc getProc, GlFunctions& out) {
    if (getProc == nullptr) return Status::error("loadGlFunctions: no getProcAddress function given");
    GlFunctions loaded;
    std::string missing;
#define SCULPT_GL_LOAD_MEMBER(name, infix)                                            \
    loaded.name = reinterpret_cast<PFNGL##infix##PROC>(getProc("gl" #name));          \
    if (loaded.name == nullptr) missing += (missing.empty() ? "gl" #name : ", gl" #name);
    SCULPT_GL_FUNCTIONS(SCULPT_GL_LOAD_MEMBER)
#undef SCULPT_GL_LOAD_MEMBER
    if (!missing.empty()) return Status::error("OpenGL entry points not available: " + missing);
    out = loaded;
    return Status::success();
}

Status checkGlVersion(const GlFunctions& gl, std::string* description) {
    const auto text = [&](GLenum name) {
        const GLubyte* value = gl.GetString(name);
        return value ? std::string(reinterpret_cast<const char*>(value)) : std::string();
    };
    const std::string version = text(GL_VERSION);
    if (version.empty()) return Status::error("glGetString(GL_VERSION) returned nothing: is a context current?");
    GLint major = 0, minor = 0;
    gl.GetIntegerv(GL_MAJOR_VERSION, &major);
    gl.GetIntegerv(GL_MINOR_VERSION, &minor);
    if (major < 3 || (major == 3 && minor < 3))
        return Status::error("OpenGL 3.3 is required, the context has " + version);
    if (description) *description = text(GL_VENDOR) + " | " + text(GL_RENDERER) + " | " + version;
    return Status::success();
}

}  // namespace sculpt::render
