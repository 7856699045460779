// Commands of the editing tools that panels and keys share (implemented in tool_input.cpp). Like the commands
// of app_state.h, each keeps the status line and the pending GPU update in step with the session.
#pragma once

#include "app/window/app_state.h"

namespace sculpt::app {

// Sculpt or lattice tool (Tab toggles); ignored during a drag.
void setToolMode(AppState& state, ToolMode mode);
// Lattice tool: pins the selected control points, or unpins them if all of them are pinned (P).
void togglePinsOfSelection(AppState& state);
// Selects every control point (or none).
void selectAllControlPoints(AppState& state, bool all);
// Drops selected ids the current lattice does not have (after a re-setup or its undo).
void clampLatticeSelection(AppState& state);
// Puts "N control points selected ..." on the status line.
void describeLatticeSelection(AppState& state);
// Removes every placed handle and pin.
void clearHandles(AppState& state);
// The hammer or crimp (state.tools.brush.kind) at mesh vertex `vertex` through the script op itself
// (io::runScriptOp: one undo step), with the control points within `radius` (world units; 0: the strongest
// one); `invert`: lower instead of raise, sharpen instead of broaden. Says on the status line what happened.
void weightToolCommand(AppState& state, int vertex, double radius, bool invert);
// Puts a fresh lattice with `settings` around the current mesh, as an undoable operation (Session::setupLattice).
void setupLatticeCommand(AppState& state, const core::LatticeSettings& settings);

}  // namespace sculpt::app
