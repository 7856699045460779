// Navigating the 3D view as Blender does: orbit, pan, zoom toward the cursor, the numpad's axis views (1
// front, 3 right, 7 top; with Ctrl the opposite side), numpad 5 orthographic / perspective, and framing
// (F or Home: everything; numpad .: the selected control points in the lattice tool, else everything).
//
// The world is Y-up (the camera orbits about +Y), so Blender's Z-up views map as: front looks along -Z (eye
// on +Z, X to the right), right looks along -X, top looks down -Y with -Z up on the screen.
//
// Auto perspective (Blender's default): an axis view turns the projection orthographic, and orbiting away from
// it turns perspective back on, unless the user chose orthographic himself (numpad 5).
#pragma once

#include "app/window/app_state.h"

namespace sculpt::app {

enum class AxisView { Front, Right, Top };

// Points the camera along an axis (opposite: the back, left or bottom view), keeping target and distance.
void setAxisView(AppState& state, AxisView view, bool opposite);
// Numpad 5: orthographic <-> perspective; the user's choice (orbiting keeps it).
void toggleOrthographic(AppState& state);
// Orbit by a cursor move of (dx, dy) pixels; the pitch stops at +-90 degrees.
void orbitView(AppState& state, double dx, double dy);
// Pan: the point under the cursor stays under it.
void panView(AppState& state, double dx, double dy);
// Wheel: `notches` towards the screen (positive) zoom in, and the point under the cursor (x, y) at the
// target's depth stays under the cursor. Zoom limits are relative to the content (1e-3 to 1e3 of its radius).
void zoomView(AppState& state, double x, double y, double notches);
// Numpad .: the lattice tool's selected control points fill the view (else what frameMesh frames); the
// near/far planes still hold the whole content.
void frameSelected(AppState& state);

}  // namespace sculpt::app
