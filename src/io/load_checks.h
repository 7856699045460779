// Checks every mesh reader makes the same way, with the same words: a file with no surface, and a vertex count
// beyond what the program's int indices hold.
#pragma once

#include <cstdint>
#include <string>

#include "core/status.h"

namespace sculpt::io {

// "name: the file has no faces", naming what it has instead: only lines and points, or `points` points (a
// point cloud), or nothing.
inline Status noSurfaceError(const std::string& name, bool linesOrPoints, size_t points) {
    return Status::error(name + ": the file has no faces" +
                         (linesOrPoints ? " (only lines and points: not a surface)"
                          : points > 0  ? " (" + std::to_string(points) + " points: a point cloud is not a surface)"
                                        : std::string()));
}

// Fails for more vertices than int indices (with room for refinement's new vertices) can number.
inline Status checkVertexTotal(const std::string& name, size_t vertices) {
    if (vertices > static_cast<size_t>(INT32_MAX / 4))
        return Status::error(name + ": " + std::to_string(vertices) + " vertices are more than this program handles");
    return Status::success();
}

}  // namespace sculpt::io
