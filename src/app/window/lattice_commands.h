// Commands of the Lattices panel (lattices of any shape, Coquillart 1990 "EFFD", seed 004, 3.1-3.4). Each is
// the session command a script's op issues (add_lattice with "place", edit_lattice, remove_lattice, freeze,
// unfreeze: src/core/session/script.cpp), so every change is a history operation (undoable, recorded in sessions);
// like the commands of app_state.h each keeps the status line and the pending GPU update in step.
#pragma once

#include <string>

#include <Eigen/Core>

#include <vector>

#include "app/window/app_state.h"
#include "core/volume/lattice_edit.h"
#include "core/status.h"

namespace sculpt::app {

// Reads every *.lattice.json of `folder` (sorted by file name) into the panel's library, after the entries
// already there. A file that cannot be read is left out and named on the status line; a missing folder is
// no error (the user's is made by the first save).
void loadLatticeLibrary(AppState& state, const std::string& folder);
// The library the panel lists: the shipped folder, then the user's (userLatticeFolder).
void loadLatticeLibraries(AppState& state);
// The shipped library folder (assets/lattices beside the default mesh). Read-only to the app: a save there
// is refused (saveLatticeToolCommand).
std::string latticeLibraryFolder();
// The user's own library folder, where "Save to library" writes: $XDG_DATA_HOME/dmffd-sculpt/lattices, or
// ~/.local/share/dmffd-sculpt/lattices when XDG_DATA_HOME is unset or relative (XDG Base Directory spec).
// Empty when neither is known. Not created here.
std::string userLatticeFolder();
// Whether `path` lies in the shipped library folder (compared after resolving links and "..").
bool inShippedLatticeLibrary(const std::string& path);
// A name for tool `toolName` saved into `folder` that no library entry and no file there has yet: the tool's
// own name when it is free, else the next of "cylinder 2", "cylinder 3", ... (a name that ends in a number
// counts on from it: "cylinder 2" -> "cylinder 3"). Path separators in it become '-', so it is a file name.
std::string freshLatticeName(const AppState& state, const std::string& toolName, const std::string& folder);
// The library name of a lattice file: its file name without ".lattice.json" ("cylinder 2.lattice.json" -> "cylinder 2").
std::string latticeNameOfPath(const std::string& path);
// Adds a library file the user opened (the file dialog) to the library and chooses it; false, with the
// reason on the status line, when it cannot be read.
bool openLatticeFile(AppState& state, const std::string& path);

// Session::tools().add of library entry `entry` as it is (no placement).
void addLatticeFromLibrary(AppState& state, int entry);
// The positioning command (3.2, core::placeVolume): the net's bounds centre to `point`, its z axis onto
// `normal`, its bounds diagonal `size` (world units); then added as a new tool named `name` (editIndex < 0,
// Session::tools().add) or replacing tool editIndex's net (Session::tools().edit).
void placeLatticeCommand(AppState& state, const core::Volume& volume, const std::string& name, int editIndex,
                         const Eigen::Vector3d& point, const Eigen::Vector3d& normal, double size);
// Session::tools().freeze / unfreeze / remove. The control-point selection is cleared
// (its ids belonged to the other lattice).
void freezeLatticeCommand(AppState& state, int index, int pinLayers);
void unfreezeLatticeCommand(AppState& state);
void removeLatticeToolCommand(AppState& state, int index);
// edit_lattice with "edits" (core/volume/lattice_edit.h) on tool `index`, which must not be frozen: the script op
// itself (io::runScriptOp), one history operation. `what` names it on the status line ("Inserted a knot
// at u = 0.3 in cylinder"); a refusal gives its reason there.
void editLatticeNetCommand(AppState& state, int index, const std::vector<core::NetEdit>& edits, const std::string& what);
// Writes tool `index` to `path` as a library file named `name` (empty: the tool's name) with
// io::writeLatticeFile (atomic: an existing file is never damaged by a failed save), and lists it in the
// library (replacing the entry of the same path). A path in the shipped library (inShippedLatticeLibrary) is
// refused: shipped tools are never overwritten. The error also goes to the status line.
Status saveLatticeToolCommand(AppState& state, int index, const std::string& path, const std::string& name = {});

// "Place at picked point": the next left click on the mesh places (state.lattices.placing). Esc cancels.
void beginPlacingLattice(AppState& state, LatticesPanelState::Placing what);
void cancelPlacingLattice(AppState& state);
// The pending placement at framebuffer pixel (x, y): the surface point under it and the normal of the hit
// triangle (turned towards the camera), the size the panel sets (placementSize). True when the click was
// taken (on the mesh or not: a click beside the mesh says so and keeps waiting).
bool placeLatticeAtPixel(AppState& state, double x, double y);
// The size "Place" gives: placeSizeFraction of the mesh's bounds diagonal.
double placementSize(const AppState& state);

// The status line after a lattice command: the engine's own account where it gives one (freeze: "froze
// 812 of 2562 vertices in lattice cylinder"), after `done`; a refusal or error by reportOperation. Applied:
// the session's moves noted for the GPU. show: turn the current tool's Lattice overlay on, so the user sees
// the lattice just frozen (tools that are not frozen show without it: latticeToolsShown).
void reportLatticeOperation(AppState& state, const core::OpReport& report, const Status& status, const std::string& done,
                            bool show = false);

// "cylinder, 3 x 12 x 3 points (37 after welds), degree 2/2/2": what the panel lists for a net.
std::string describeLattice(const core::Volume& volume);

}  // namespace sculpt::app
