// Commands of the Lattices panel's T-spline section (weighted T-spline FFD, Song & Yang 2005, seed 002). Each
// change is the script op itself run through io::runScriptOp (setup_tspline, subdivide_cells, and unfreeze /
// freeze around a subdivision of the frozen tool), so the window does what a script does and every op is a
// history operation; like the commands of app_state.h each keeps the status line and the GPU update in step.
// Also what the window draws and picks of T-splines (Fig. 9-11), from core/tspline/tspline_view.h.
#pragma once

#include <cstdint>
#include <vector>

#include "app/window/app_state.h"
#include "core/tspline/tspline_view.h"
#include "render/scene.h"

namespace sculpt::app {

// setup_tspline with the panel's depth, weight ratio and region (its box when customRegion, else the mesh's
// bounds padded), named "tspline" (or "tspline 2", ... when taken), frozen (no pin layers): two history
// operations, adding the tool and freezing it. The new tool is selected and the Lattice overlay turned on.
// A refusal (a region holding no vertex, a ratio <= 0, ...) goes to the status line and changes nothing.
void setupTSplineCommand(AppState& state);

// The mesh's bounds padded as setup_tspline pads them (core::paddedPointBounds, 0.05 of the diagonal): what
// the region fields start from. False with no mesh.
bool meshRegion(const AppState& state, Eigen::Vector3d& min, Eigen::Vector3d& max);
// The region fields set to the bounds of the lattice tool's selected control points (as shown), grown by 0.05
// of their diagonal so points on them count; false, with the reason on the status line, for fewer than two
// selected points or a flat box.
bool regionFromSelection(AppState& state);

// The T-spline tool the cell choice acts on: the selected tool when it is a T-spline, else the frozen tool when
// it is one, else -1.
int tsplineTarget(const AppState& state);
// state.tspline.chosenCells, dropped when the target's volume is no longer the one they were chosen in (an
// undo, a subdivision, another tool selected). Call before reading them.
void validateChosenCells(AppState& state);

// "Choose cells": the next left clicks on the mesh add (or drop) the cell under the click (Fig. 11). Esc or
// the button again ends it. Nothing to choose from (no T-spline tool) is said on the status line.
void beginChoosingCells(AppState& state);
void endChoosingCells(AppState& state);
// While choosing: the cell of the target T-spline under framebuffer pixel (x, y), toggled in the choice. The
// cell is found from the hit point's rest position in the frozen cage (the parameters the mesh has there), or
// from the hit point itself in a tool that is not frozen (at rest where it is drawn). True when the click was
// taken (on the mesh or not).
bool chooseCellAtPixel(AppState& state, double x, double y);

// subdivide_cells on the target with the chosen cells and the panel's balance. A frozen target is unfrozen
// first and frozen again after (with the pin layers it had): the engine subdivides only a tool that is not
// frozen, since the vertices' parameters change. Three history operations then, each undone on its own; the
// deformation made in the tool stays in the mesh, and the finer lattice starts at rest around it. A refusal
// undoes the unfreeze, so nothing changes, and goes to the status line.
void subdivideChosenCellsCommand(AppState& state);

// Per control point of the session's cage, 1 for those of a frozen T-spline's non-empty cells (sec. 4, Fig. 10;
// boundary copies excluded, core::tsplineCageView), cached in state.tsplineShown; empty when the cage is not
// a T-spline.
const std::vector<std::uint8_t>& tsplineShownControlPoints(const AppState& state);

// The T-spline parts of the lattice overlay: the chosen cells' edges (between the control points of their
// corners, as shown) and, for a target that is not frozen, its T-junctions at rest. Appended to `lattice`.
void addTSplineOverlays(const AppState& state, render::LatticeView& lattice);
// Whether addTSplineOverlays draws anything (the lattice layer must be on for it).
bool tsplineOverlaysShown(const AppState& state);

}  // namespace sculpt::app
