// What the renderer draws for a session: the mesh, the lattice, the last drag's constraints and the
// optional per-vertex fields (det J, affected region). Shared by the headless screenshots and the window.
// A frozen lattice of any shape is drawn by its control net (each weld group once), its curved chunk edges
// (core/volume/cage_view.h), and the lattice tools not frozen by their rest chunk edges. A frozen weighted T-spline
// (Song & Yang 2005, Fig. 10) shows only the control points of its non-empty cells, and its T-junctions.
#pragma once

#include <memory>
#include <vector>

#include "core/session/session.h"
#include "io/mesh_file.h"
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
    // The control points drawn of a lattice of any shape (one flag each); empty: computed here (each weld group
    // once; of a frozen T-spline only those of non-empty cells, core/tspline/tspline_view.h). The window passes the
    // points its lattice tool picks, which it keeps cached.
    std::vector<std::uint8_t> drawnControlPoints;
};

render::SceneData sceneFromSession(const core::Session& session, const SceneRequest& request);

// The mesh file's own colours (a scan's: io::meshVertexColours, carried through the session's refinement
// splits) as SceneData::vertexColors takes them: #V x 3 sRGB values for the session's vertices, or empty when
// the file had none or `source` is not the mesh the session was set up from (another vertex count).
std::vector<float> sessionVertexColors(const io::ObjMesh& source, const core::Session& session);

// A lattice tool that is not frozen as it is drawn (dim, at rest): the rest chunk edges of its volume
// (core::restChunkEdges), or of a weighted T-spline its T-lattice between its rest control points (segments).
std::vector<Positions> restToolLines(const std::shared_ptr<const core::Volume>& volume, int samplesPerSpan);

}  // namespace sculpt::app
