// What the renderer draws for a session: the mesh, the lattice, the last drag's constraints and the
// optional per-vertex fields (det J, affected region). Shared by the headless screenshots and the window.
// A frozen lattice of any shape is drawn by its control net (each weld group once), its curved chunk edges
// (core/cage_view.h), and the lattice tools not frozen by their rest chunk edges.
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
    // A lattice of any shape (EFFD): segments per knot span of its curved chunk edges, and of the rest
    // chunk edges of the lattice tools that are not frozen (drawn dim with the lattice).
    int curveSamplesPerSpan = 8;
    bool latticeTools = true;
};

render::SceneData sceneFromSession(const core::Session& session, const SceneRequest& request);

}  // namespace sculpt::app
