// What the renderer draws, as plain arrays. Independent of the engine's types (lattice, solver, history):
// the app or CLI copies what it wants shown into these structs.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/mesh_types.h"

namespace sculpt::render {

// The control lattice: an nu x nv x nw grid of control points.
struct LatticeView {
    int nu = 0, nv = 0, nw = 0;  // 0 = no lattice; otherwise each >= 1
    // (nu*nv*nw) x 3; control point (i, j, k) is row i + nu*(j + nv*k).
    Positions controlPoints;
    // Empty, or one entry per control point (nonzero = true). As in Blender's lattice edit mode, selected
    // points are drawn bright orange and larger, the rest small and dark; pinned ones as squares (light blue
    // unless also selected). palette.h has the colours.
    std::vector<std::uint8_t> selected;
    std::vector<std::uint8_t> pinned;
    // Only the control points and edges on the lattice's outer faces (Blender's lattice "Outside"), plus every
    // selected point: a fine lattice's interior hides the mesh. (Grid edges only; a net lattice says what is
    // drawn through `drawn`.)
    bool outerOnly = false;

    // A lattice of any shape (EFFD, Coquillart 1990). All empty for the box lattice, drawn as its grid.
    // Non-empty: these pairs of control point ids (rows above) are the control net's edges, instead of the
    // grid's lines (a welded axis or seam is one point, so the grid's lines would join copies of it).
    std::vector<std::array<int, 2>> netEdges;
    // Polylines (each #samples x 3, world units, finite) drawn as lines of their own colour: the curved chunk
    // edges of the deformed volume (a cylinder's circles).
    std::vector<Positions> curves;
    // Empty (all drawn), or one flag per control point: 0 = never drawn, even when selected (a welded copy is
    // drawn once, on its weld group's representative). Net edges to a point not drawn are left out.
    std::vector<std::uint8_t> drawn;
    // Net edges are drawn between points that are not drawn too: a weighted T-spline hides its light control
    // points (Song & Yang 2005, Fig. 10) but not the T-lattice they hang on.
    bool edgesOfHiddenPoints = false;
    // Polylines drawn dim, without points: lattice tools that are not frozen, at rest, so the user sees where
    // they are. Drawn even with no control points (nu = 0).
    std::vector<Positions> toolCurves;
    // Weighted T-splines (Song & Yang 2005, Fig. 9-10): the T-junctions of the T-lattice (where a line of it
    // ends), #J x 3 world points drawn as diamonds (kTJunctionColor) under the control points, so the user
    // reads where the lattice is finer. Drawn even with no control points (nu = 0).
    Positions tJunctions;
    // Polylines drawn in the selection colour over everything else of the lattice: the edges of the cells
    // chosen for subdivision (Fig. 11).
    std::vector<Positions> chosenCells;
};

// Direct-manipulation constraints (Hu et al. 2001, Fig. 1): each source point S is carried to its target T.
// Besides the constraints being dragged, placed handles (sources waiting to be dragged, seed 000 Fig. 3-4)
// and pins (surface points held where they are) are drawn as markers of their own.
struct ConstraintView {
    Positions sources;  // #C x 3, drawn red
    Positions targets;  // #C x 3, drawn blue, joined to its source by a red-to-blue line
    Positions handles;  // #H x 3, placed handles not being dragged: red discs
    Positions pins;     // #P x 3, pinned surface points: green squares
    Positions outline;  // #O x 3, closed polylines drawn white: the sculpt brush's circle on the surface (and its mirror images)
    int outlineLoop = 0;  // points per closed polyline of `outline` (its rows a multiple of it); 0: one polyline of every row
    // Guide lines of a transform in progress, e.g. the locked axis through the pivot: from, to (finite), and
    // the world axis (0, 1, 2) whose colour they take, red / green / blue as Blender draws X / Y / Z.
    struct AxisLine {
        Eigen::Vector3d from = Eigen::Vector3d::Zero(), to = Eigen::Vector3d::Zero();
        int axis = 0;
    };
    std::vector<AxisLine> axisLines;
};

struct SceneData {
    Positions positions;  // #V x 3; every value finite
    Triangles triangles;  // #F x 3 indices into positions
    // Optional per-vertex fields: empty, or exactly #V values.
    std::vector<float> jacobianDet;     // det J of the deformation at each vertex, relative to rest (1 = unchanged)
    std::vector<float> affectedWeight;  // in [0, 1]: how much a constraint / the selection influences the vertex
    std::vector<float> vertexColors;    // empty or #V x 3 (row-major): the file's colours, sRGB in [0, 1]
    LatticeView lattice;                // nu == 0: none
    ConstraintView constraints;         // empty: none
};

// Which layers draw() shows. Layers whose data is absent are skipped (a Jacobian overlay without a
// jacobianDet field shows the plain material, since det J = 1 everywhere).
struct DrawOptions {
    bool lattice = false;      // lattice edges and control points
    bool constraints = true;   // source/target handles, drawn on top of everything
    bool wireframe = false;    // mesh edges over the shaded surface
    bool jacobian = false;     // per-vertex det J colour map, and its legend (with a mesh and a det J field)
    bool affected = false;     // tint of the affected region
    bool vertexColors = true;  // the mesh's vertex colours as its albedo, where it has them (else the clay)
    bool background = true;    // gradient; false clears to transparent black (alpha 0) for compositing
    // The camera or the shape is moving (a drag, an orbit): draw the mesh's decimated proxy where it has one
    // (a large mesh, see mesh_proxy.h), so software GL keeps up; the full mesh once the motion stops.
    bool proxy = false;
    // Pixels at the bottom of the view covered by a UI drawn over it (the window's status line): the det J
    // legend sits above them.
    float uiInsetBottom = 0.0f;
};

}  // namespace sculpt::render
