#include "render/embedded_shaders.h"

namespace sculpt::render {

std::string_view embeddedShaderSource(std::string_view fileName) {
    for (int i = 0; i < kEmbeddedShaderCount; ++i)
        if (fileName == kEmbeddedShaders[i].name) return kEmbeddedShaders[i].source;
    return {};
}

}  // namespace sculpt::render
