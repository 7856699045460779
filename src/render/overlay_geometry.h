// CPU side of the lattice and constraint overlays: validates the plain scene structs and turns them into
// the per-instance arrays the line and point shaders draw (one quad per segment / marker).
#pragma once

#include <vector>

#include "core/status.h"
#include "render/camera.h"
#include "render/scene.h"

namespace sculpt::render {

inline constexpr int kLineFloats = 14;   // per segment: start xyz, end xyz, colour at start rgba, at end rgba
// per marker: centre xyz, colour rgba, diameter (pixels), shape (0 disc, 1 square, 2 diamond), depth fade (0 none, 1 fainter
// further from the eye, like the lattice edges: the renderer's kLatticeFarAlpha; 1 and 2 shrink where markers
// crowd, 2 without the fade)
inline constexpr int kMarkerFloats = 10;

// Positions in the arrays are in `frame`'s local coordinates (camera.h: world minus origin, over scale,
// subtracted in double before the conversion to float); sizes are pixels, so nothing here is in world units.

// Whether grid position (i, j, k) of an nu x nv x nw lattice lies on its outer faces.
inline bool onLatticeBoundary(int i, int j, int k, int nu, int nv, int nw) {
    return i == 0 || j == 0 || k == 0 || i == nu - 1 || j == nv - 1 || k == nw - 1;
}

// Edges between neighbouring control points (i+1, j+1, k+1) and one marker per control point (plain points
// first, then pinned, then selected, so the ones the user works with draw on top). With lattice.outerOnly,
// only the edges and points on the outer faces, and every selected point. nu = nv = nw = 0 gives
// empty arrays. A lattice of any shape (netEdges or curves given): the net edges instead of the grid's,
// then the curves (kLatticeCurveColor); control points whose `drawn` flag is 0 are left out, and the edges
// to them unless edgesOfHiddenPoints. Then the tool curves, dim (kLatticeToolColor), with or without control
// points, then the chosen cells' edges (kChosenCellColor). A T-spline's T-junctions are diamond markers
// (kTJunctionColor) before every control point, so the points draw over them. bounds: of the control points,
// T-junctions and polylines, world units. Fails, leaving the outputs unchanged, on inconsistent sizes, a net
// edge outside the control points or non-finite points.
Status buildLatticeInstances(const LatticeView& lattice, const LocalFrame& frame, std::vector<float>& edges,
                             std::vector<float>& markers, Bounds& bounds);

// The brush outline's segments (a closed loop), one red-to-blue segment per constraint, then the axis lines in
// their axes' colours; the source markers, then the target markers. Fails, leaving the outputs unchanged, on
// different source/target counts, non-finite points or an axis line's axis outside 0-2.
Status buildConstraintInstances(const ConstraintView& constraints, const LocalFrame& frame,
                                std::vector<float>& segments, std::vector<float>& markers);

// How much the plain (unselected) control-point markers shrink where they crowd on screen, so that a small or
// fine lattice never buries the mesh under a cloud of dots. Crowding: the mean over the markers of the share
// of the cells around each (one marker wide, within two diameters) that hold another marker. Up to
// kCrowdedMarkerShare (palette.h) the markers keep their size; beyond it they shrink with the square root of
// the excess (their area falls back to that share), never below kMinCrowdedMarkerScale. Markers drawn at the
// same place crowd nothing.
// pixels: the centres of the markers on screen, pixels; diameter: a plain marker's, pixels (> 0).
// Returns a factor in [kMinCrowdedMarkerScale, 1]; 1 for fewer than two markers.
float crowdedMarkerScale(const std::vector<glm::vec2>& pixels, float diameter);

// Error naming the first non-finite row of points ("<what> row 7 is not finite ..."), or success.
Status checkFinite(const Positions& points, const char* what);

}  // namespace sculpt::render
