// GLSL sources compiled into the binary from shaders/ (see embed_shaders.cmake).
#pragma once

#include <string_view>

namespace sculpt::render {

struct EmbeddedShader {
    const char* name;    // file name in shaders/, e.g. "mesh.frag"
    const char* source;  // the file's text, verbatim
};

// Defined in the generated embedded_shaders_data.cpp.
extern const EmbeddedShader kEmbeddedShaders[];
extern const int kEmbeddedShaderCount;

// The source of shaders/<fileName>, or an empty view if no such file was embedded.
std::string_view embeddedShaderSource(std::string_view fileName);

}  // namespace sculpt::render
