// The Dear ImGui panels of the window, one per file (house style 10). Each reads the AppState and changes it
// only through the commands of app_state.h. They draw inside the sidebar window begun by beginSidebar().
#pragma once

#include <string>

#include <imgui.h>

#include "app/window/app_state.h"

namespace sculpt::app {

class FileCommands;

// The fixed sidebar on the left of the viewport (ui_layout.cpp).
void beginSidebar(AppState& state);
void endSidebar();
// "DMFFD Sculpt  -  copy2.obj*": the sidebar's header (the document's name, * while modified).
std::string sidebarTitle(const AppState& state);

void drawStatsPanel(AppState& state);        // stats_panel.cpp: mesh, lattice, timings, fps
void drawOverlaysPanel(AppState& state);     // overlays_panel.cpp: wireframe, lattice, det J, affected region
void drawInjectivityPanel(AppState& state);  // injectivity_panel.cpp: off / conic / exact, subdivision depth
void drawHistoryPanel(AppState& state);      // history_panel.cpp: undo, redo, the list (click to jump)
// An entry of the history list: the operation's label, and "[N injective steps]" where a drag was split into
// injective steps (a brush stroke's region layers are not counted).
std::string historyEntryLabel(const core::Operation& op);
// lattices_panel.cpp: lattice tools of any shape (list, library, place, freeze / unfreeze, remove, save), the
// last section of the Tools window; its file dialogs are the window's (FileCommands).
void drawLatticesPanel(AppState& state, FileCommands& files);
// tspline_panel.cpp: the Lattices panel's "T-spline" section (weighted T-spline FFD, Song & Yang 2005): set-up
// (depth, region, weight ratio) and the cells chosen on the mesh for local subdivision.
void drawTSplineSection(AppState& state);
void drawStatusLine(AppState& state);        // status_line.cpp: the verdict of the last command, at the bottom

// The tool window on the right (tools_panel.cpp): sculpt / lattice tool, handles and pins, control-point
// selection and pins, lattice set-up, and with `files` the Lattices panel; and the lattice tool's selection
// rectangle.
void drawToolsWindow(AppState& state, FileCommands* files = nullptr);
float toolsWindowWidth();
// A framebuffer pixel (input events, picking) in Dear ImGui's coordinates (they differ on HiDPI screens).
ImVec2 framebufferToUi(const AppState& state, double x, double y);

// Width of the sidebar in pixels (scaled with the font), so the viewport knows what is covered.
float sidebarWidth();
// The gap between a side panel and the view's edges (UI pixels).
float panelMargin();
// The tallest a side panel may be (UI pixels) below the menu bar: it ends above the status line as last drawn (a
// wrapped message makes it taller) and, on the right (rightSide), above the det J legend while it is shown. A
// panel with more content scrolls.
float panelMaxHeight(const AppState& state, bool rightSide);

}  // namespace sculpt::app
