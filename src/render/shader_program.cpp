#include "render/shader_program.h"

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "render/embedded_shaders.h"

namespace sculpt::render {

namespace {

std::string shaderLog(const GlFunctions& gl, GLuint shader) {
    GLint length = 0;
    gl.GetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
    if (length <= 1) return "(no log)";
    std::vector<char> log(static_cast<size_t>(length));
    gl.GetShaderInfoLog(shader, length, nullptr, log.data());
    return std::string(log.data());
}

std::string programLog(const GlFunctions& gl, GLuint program) {
    GLint length = 0;
    gl.GetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
    if (length <= 1) return "(no log)";
    std::vector<char> log(static_cast<size_t>(length));
    gl.GetProgramInfoLog(program, length, nullptr, log.data());
    return std::string(log.data());
}

Status compileStage(const GlFunctions& gl, GLenum stage, const std::string& label, std::string_view source,
                    std::string_view defines, GLuint& shader) {
    shader = gl.CreateShader(stage);
    if (shader == 0) return Status::error("glCreateShader failed for " + label);
    // note: the preamble is a separate string, so the driver's line numbers are off by its line count;
    // the message says so rather than rewriting the log.
    const std::string preamble = shaderPreamble() + std::string(defines);
    const GLchar* strings[2] = {preamble.c_str(), source.data()};
    const GLint lengths[2] = {static_cast<GLint>(preamble.size()), static_cast<GLint>(source.size())};
    gl.ShaderSource(shader, 2, strings, lengths);
    gl.CompileShader(shader);
    GLint compiled = GL_FALSE;
    gl.GetShaderiv(shader, GL_COMPILE_STATUS, &compiled);
    if (compiled != GL_TRUE) {
        const std::string log = shaderLog(gl, shader);
        gl.DeleteShader(shader);
        shader = 0;
        return Status::error("shader '" + label + "' failed to compile (log line numbers include a " +
                             std::to_string(std::count(preamble.begin(), preamble.end(), '\n')) +
                             "-line preamble):\n" + log);
    }
    return Status::success();
}

}  // namespace

std::string shaderPreamble() {
    std::string text = "#version 330 core\n";
    const auto define = [&](const char* name, AttributeLocation location) {
        text += "#define ";
        text += name;
        text += ' ';
        text += std::to_string(static_cast<unsigned>(location));
        text += '\n';
    };
    define("ATTRIB_POSITION", kAttribPosition);
    define("ATTRIB_NORMAL", kAttribNormal);
    define("ATTRIB_JACOBIAN", kAttribJacobian);
    define("ATTRIB_AFFECTED", kAttribAffected);
    define("ATTRIB_VERTEX_COLOR", kAttribVertexColor);
    define("ATTRIB_LATTICE_CELL", kAttribLatticeCell);
    define("ATTRIB_SEGMENT_START", kAttribSegmentStart);
    define("ATTRIB_SEGMENT_END", kAttribSegmentEnd);
    define("ATTRIB_COLOR_START", kAttribColorStart);
    define("ATTRIB_COLOR_END", kAttribColorEnd);
    define("ATTRIB_MARKER_CENTER", kAttribMarkerCenter);
    define("ATTRIB_MARKER_COLOR", kAttribMarkerColor);
    define("ATTRIB_MARKER_STYLE", kAttribMarkerStyle);
    define("ATTRIB_OVERLAY_PIXEL", kAttribOverlayPixel);
    define("ATTRIB_OVERLAY_COLOR", kAttribOverlayColor);
    define("ATTRIB_OVERLAY_FILL", kAttribOverlayFill);
    return text;
}

Status buildProgram(const GlFunctions& gl, std::string_view name, std::string_view vertexSource,
                    std::string_view fragmentSource, GLuint& program) {
    return buildProgram(gl, name, vertexSource, fragmentSource, ProgramOptions{}, program);
}

Status buildProgram(const GlFunctions& gl, std::string_view name, std::string_view vertexSource,
                    std::string_view fragmentSource, const ProgramOptions& options, GLuint& program) {
    program = 0;
    const std::string base(name);
    GLuint vertexShader = 0, fragmentShader = 0;
    if (Status status = compileStage(gl, GL_VERTEX_SHADER, base + ".vert", vertexSource, options.defines, vertexShader);
        !status)
        return status;
    if (Status status = compileStage(gl, GL_FRAGMENT_SHADER, base + ".frag", fragmentSource, options.defines, fragmentShader);
        !status) {
        gl.DeleteShader(vertexShader);
        return status;
    }
    const GLuint linked = gl.CreateProgram();
    gl.AttachShader(linked, vertexShader);
    gl.AttachShader(linked, fragmentShader);
    if (!options.feedbackVaryings.empty()) {
        std::vector<const GLchar*> names;
        for (const std::string& varying : options.feedbackVaryings) names.push_back(varying.c_str());
        gl.TransformFeedbackVaryings(linked, GLsizei(names.size()), names.data(), GL_INTERLEAVED_ATTRIBS);
    }
    gl.LinkProgram(linked);
    // Flagged for deletion; freed with the program.
    gl.DeleteShader(vertexShader);
    gl.DeleteShader(fragmentShader);
    GLint ok = GL_FALSE;
    gl.GetProgramiv(linked, GL_LINK_STATUS, &ok);
    if (ok != GL_TRUE) {
        const std::string log = programLog(gl, linked);
        gl.DeleteProgram(linked);
        return Status::error("program '" + base + "' failed to link:\n" + log);
    }
    program = linked;
    return Status::success();
}

namespace {

// Replaces each line `#include "file.glsl"` of source with the embedded shaders/file.glsl.
Status resolveIncludes(std::string_view fileName, std::string_view source, std::string& resolved) {
    constexpr std::string_view kDirective = "#include \"";
    resolved.clear();
    size_t lineStart = 0;
    while (lineStart < source.size()) {
        size_t lineEnd = source.find('\n', lineStart);
        lineEnd = lineEnd == std::string_view::npos ? source.size() : lineEnd + 1;
        const std::string_view line = source.substr(lineStart, lineEnd - lineStart);
        if (line.substr(0, kDirective.size()) == kDirective) {
            const size_t close = line.find('"', kDirective.size());
            const std::string included(line.substr(kDirective.size(), close == std::string_view::npos ? 0 : close - kDirective.size()));
            const std::string_view text = embeddedShaderSource(included);
            if (text.empty())
                return Status::error(std::string(fileName) + ": no embedded shaders/" + included + " to include");
            resolved += text;
            resolved += '\n';
        } else {
            resolved += line;
        }
        lineStart = lineEnd;
    }
    return Status::success();
}

}  // namespace

Status buildEmbeddedProgram(const GlFunctions& gl, std::string_view name, GLuint& program) {
    return buildEmbeddedProgram(gl, name, ProgramOptions{}, program);
}

Status buildEmbeddedProgram(const GlFunctions& gl, std::string_view name, const ProgramOptions& options, GLuint& program) {
    program = 0;
    const std::string base(name);
    std::string vertexSource, fragmentSource;
    for (const auto& [file, out] : {std::pair{base + ".vert", &vertexSource}, std::pair{base + ".frag", &fragmentSource}}) {
        const std::string_view source = embeddedShaderSource(file);
        if (source.empty()) return Status::error("no embedded shaders/" + base + ".vert and .frag in this binary");
        if (Status status = resolveIncludes(file, source, *out); !status) return status;
    }
    return buildProgram(gl, name, vertexSource, fragmentSource, options, program);
}

}  // namespace sculpt::render
