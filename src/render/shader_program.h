// GLSL program building: every compile and link log is checked and returned as a Status.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "render/gl_functions.h"

namespace sculpt::render {

// Vertex attribute locations, declared once here. buildProgram prepends them to every shader as
// `#define ATTRIB_<NAME> <n>`, so the GLSL writes `layout(location = ATTRIB_POSITION)`.
enum AttributeLocation : GLuint {
    kAttribPosition = 0,       // mesh: vec3 position
    kAttribNormal = 1,         // mesh: vec3 normal
    kAttribJacobian = 2,       // mesh: float det J relative to rest (1 = unchanged)
    kAttribAffected = 3,       // mesh: float affected-region weight in [0, 1]
    kAttribSegmentStart = 4,   // line (per instance): vec3 start point
    kAttribSegmentEnd = 5,     // line (per instance): vec3 end point
    kAttribColorStart = 6,     // line (per instance): vec4 colour at start
    kAttribColorEnd = 7,       // line (per instance): vec4 colour at end
    kAttribMarkerCenter = 8,   // point (per instance): vec3 centre
    kAttribMarkerColor = 9,    // point (per instance): vec4 fill colour
    kAttribMarkerStyle = 10,   // point (per instance): vec3 (size in pixels, shape: 0 disc 1 square, depth fade)
    kAttribOverlayPixel = 11,  // overlay2d: vec2 window pixel (origin top-left)
    kAttribOverlayColor = 12,  // overlay2d: vec4 colour
    kAttribOverlayFill = 13,   // overlay2d: vec2 (fill kind: 0 colour, 1 det J map, 2 fold stripes; map position)
    kAttribVertexColor = 14,   // mesh: vec3 the file's vertex colour (sRGB in [0, 1])
    kAttribLatticeCell = 15,   // mesh, deformed on the GPU: vec4 (local coordinates in the knot-span cell, cell index)
};

// Variants of one program: text added after the preamble (e.g. "#define GPU_DEFORMATION\n") and the vertex
// shader outputs to capture by transform feedback (interleaved, in this order; set before linking).
struct ProgramOptions {
    std::string defines;
    std::vector<std::string> feedbackVaryings;
};

// The text prepended to every shader: `#version 330 core` and the ATTRIB_* defines above.
std::string shaderPreamble();

// Compiles both stages (preamble prepended) and links them into `program` (0 on failure).
// `name` is used in messages only. On failure the message names the stage and carries the driver's log.
Status buildProgram(const GlFunctions& gl, std::string_view name, std::string_view vertexSource,
                    std::string_view fragmentSource, GLuint& program);
Status buildProgram(const GlFunctions& gl, std::string_view name, std::string_view vertexSource,
                    std::string_view fragmentSource, const ProgramOptions& options, GLuint& program);

// buildProgram with shaders/<name>.vert and shaders/<name>.frag from the embedded table. A line
// `#include "file.glsl"` in either is replaced by that embedded shaders/ file (functions shared by several
// shaders, such as the det J colour map), one level deep; a missing file is an error.
Status buildEmbeddedProgram(const GlFunctions& gl, std::string_view name, GLuint& program);
Status buildEmbeddedProgram(const GlFunctions& gl, std::string_view name, const ProgramOptions& options, GLuint& program);

}  // namespace sculpt::render
