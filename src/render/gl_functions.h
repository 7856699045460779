// The OpenGL entry points the renderer uses, loaded at run time from the current context's
// getProcAddress (OSMesaGetProcAddress, eglGetProcAddress or glfwGetProcAddress).
//
// note: why a loader of our own instead of linking libGL / libOSMesa. A binary that links libGL (glvnd)
// and libOSMesa gets the glvnd stubs for every gl* symbol and OSMesa then renders nothing (glGetString
// returns NULL). Calling GL only through pointers from the context's own getProcAddress means the
// renderer library links no GL library at all, so one library serves the window (GLFW/GLX), EGL and
// OSMesa, and a headless binary can switch between EGL and OSMesa at run time.
//
// note: this header includes <GL/glcorearb.h> for the PFNGL...PROC types. A translation unit that also
// includes <GL/gl.h> (e.g. through GLFW without GLFW_INCLUDE_NONE) must include this header first, or
// not at all: renderer.h does not need it (Renderer::init takes a GlGetProc).
#pragma once

#include <GL/glcorearb.h>

#include <string>

#include "core/status.h"
#include "render/gl_proc.h"

namespace sculpt::render {

// X(MemberName, PFN_TYPE_INFIX): member `MemberName` has type PFNGL<INFIX>PROC and is loaded from "gl<MemberName>".
#define SCULPT_GL_FUNCTIONS(X)                                        \
    /* state and queries */                                           \
    X(GetString, GETSTRING)                                           \
    X(GetIntegerv, GETINTEGERV)                                       \
    X(GetError, GETERROR)                                             \
    X(Enable, ENABLE)                                                 \
    X(Disable, DISABLE)                                               \
    X(BlendFuncSeparate, BLENDFUNCSEPARATE)                           \
    X(DepthFunc, DEPTHFUNC)                                           \
    X(DepthMask, DEPTHMASK)                                           \
    X(ColorMask, COLORMASK)                                           \
    X(PolygonMode, POLYGONMODE)                                       \
    X(PolygonOffset, POLYGONOFFSET)                                   \
    X(Viewport, VIEWPORT)                                             \
    X(ClearColor, CLEARCOLOR)                                         \
    X(ClearDepth, CLEARDEPTH)                                         \
    X(Clear, CLEAR)                                                   \
    X(Finish, FINISH)                                                 \
    X(PixelStorei, PIXELSTOREI)                                       \
    X(ReadPixels, READPIXELS)                                         \
    /* buffers and vertex arrays */                                   \
    X(GenBuffers, GENBUFFERS)                                         \
    X(DeleteBuffers, DELETEBUFFERS)                                   \
    X(BindBuffer, BINDBUFFER)                                         \
    X(BufferData, BUFFERDATA)                                         \
    X(BufferSubData, BUFFERSUBDATA)                                   \
    X(GetBufferSubData, GETBUFFERSUBDATA)                             \
    X(GenVertexArrays, GENVERTEXARRAYS)                               \
    X(DeleteVertexArrays, DELETEVERTEXARRAYS)                         \
    X(BindVertexArray, BINDVERTEXARRAY)                               \
    X(EnableVertexAttribArray, ENABLEVERTEXATTRIBARRAY)               \
    X(DisableVertexAttribArray, DISABLEVERTEXATTRIBARRAY)             \
    X(VertexAttribPointer, VERTEXATTRIBPOINTER)                       \
    X(VertexAttribDivisor, VERTEXATTRIBDIVISOR)                       \
    X(VertexAttrib1f, VERTEXATTRIB1F)                                 \
    X(BindBufferBase, BINDBUFFERBASE)                                 \
    /* textures (buffer textures feed the vertex-shader deformation) */ \
    X(GenTextures, GENTEXTURES)                                       \
    X(DeleteTextures, DELETETEXTURES)                                 \
    X(BindTexture, BINDTEXTURE)                                       \
    X(ActiveTexture, ACTIVETEXTURE)                                   \
    X(TexBuffer, TEXBUFFER)                                           \
    /* transform feedback (reading back what the vertex shader computed) */ \
    X(TransformFeedbackVaryings, TRANSFORMFEEDBACKVARYINGS)           \
    X(BeginTransformFeedback, BEGINTRANSFORMFEEDBACK)                 \
    X(EndTransformFeedback, ENDTRANSFORMFEEDBACK)                     \
    /* drawing */                                                     \
    X(DrawArrays, DRAWARRAYS)                                         \
    X(DrawElements, DRAWELEMENTS)                                     \
    X(DrawArraysInstanced, DRAWARRAYSINSTANCED)                       \
    /* shaders */                                                     \
    X(CreateShader, CREATESHADER)                                     \
    X(ShaderSource, SHADERSOURCE)                                     \
    X(CompileShader, COMPILESHADER)                                   \
    X(GetShaderiv, GETSHADERIV)                                       \
    X(GetShaderInfoLog, GETSHADERINFOLOG)                             \
    X(DeleteShader, DELETESHADER)                                     \
    X(CreateProgram, CREATEPROGRAM)                                   \
    X(AttachShader, ATTACHSHADER)                                     \
    X(LinkProgram, LINKPROGRAM)                                       \
    X(GetProgramiv, GETPROGRAMIV)                                     \
    X(GetProgramInfoLog, GETPROGRAMINFOLOG)                           \
    X(DeleteProgram, DELETEPROGRAM)                                   \
    X(UseProgram, USEPROGRAM)                                         \
    X(GetUniformLocation, GETUNIFORMLOCATION)                         \
    X(Uniform1i, UNIFORM1I)                                           \
    X(Uniform1f, UNIFORM1F)                                           \
    X(Uniform2f, UNIFORM2F)                                           \
    X(Uniform3f, UNIFORM3F)                                           \
    X(Uniform4f, UNIFORM4F)                                           \
    X(UniformMatrix4fv, UNIFORMMATRIX4FV)                             \
    /* framebuffers */                                                \
    X(GenFramebuffers, GENFRAMEBUFFERS)                               \
    X(DeleteFramebuffers, DELETEFRAMEBUFFERS)                         \
    X(BindFramebuffer, BINDFRAMEBUFFER)                               \
    X(FramebufferRenderbuffer, FRAMEBUFFERRENDERBUFFER)               \
    X(CheckFramebufferStatus, CHECKFRAMEBUFFERSTATUS)                 \
    X(GenRenderbuffers, GENRENDERBUFFERS)                             \
    X(DeleteRenderbuffers, DELETERENDERBUFFERS)                       \
    X(BindRenderbuffer, BINDRENDERBUFFER)                             \
    X(RenderbufferStorageMultisample, RENDERBUFFERSTORAGEMULTISAMPLE) \
    X(BlitFramebuffer, BLITFRAMEBUFFER)

// One pointer per entry point. A plain value: copy it into whatever needs to call GL.
// The pointers are valid for contexts of the implementation they were loaded from.
struct GlFunctions {
#define SCULPT_GL_DECLARE_MEMBER(name, infix) PFNGL##infix##PROC name = nullptr;
    SCULPT_GL_FUNCTIONS(SCULPT_GL_DECLARE_MEMBER)
#undef SCULPT_GL_DECLARE_MEMBER
};

// Fills `out` from getProc. A context must be current (some implementations only answer then).
// Fails, naming every missing entry point, if any is unavailable; `out` is then left unchanged.
Status loadGlFunctions(GlGetProc getProc, GlFunctions& out);

// Version check on the current context: needs OpenGL >= 3.3 (core or compatibility).
// On success writes "vendor | renderer | version" to description (may be null).
Status checkGlVersion(const GlFunctions& gl, std::string* description);

}  // namespace sculpt::render
