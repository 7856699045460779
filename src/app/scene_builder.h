// What the renderer draws for a session: the mesh, the lattice, the last drag's constraints and the
// optional per-vertex fields (det J, affected region). Shared by the headless screenshots and the window.
#pragma once

#include <vector>

#include "core/session.h"
#include "render/scene.h"

namespace sculpt::app {

struct SceneRequest {
    bool mesh = true;                      // copy positions and triangles (a caller that has them uploaded: false)
    bool jacobian = false;                 // compute det J per vertex (current lattice, relative to its rest)
    bool affected = false;                 // compute the influence of `affectedControlPoints` (or the last operation's)
    std::vector<int> affectedControlPoints;
    std::vector<std::uint8_t> selectedControlPoints;  // empty or one per control point
    bool lastDragConstraints = true;       // show the last applied drag's sources (red) and targets (blue)
};

render::SceneData sceneFromSession(const core::Session& session, const SceneRequest& request);

}  // namespace sculpt::app
