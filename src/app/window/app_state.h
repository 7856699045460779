// The window's state: the engine session, the camera and the UI's own settings. The GUI keeps no engine
// state of its own (house style 9): everything about the shape lives in the Session; the rest is view state.
// The commands below are what the panels and the input handling call; each keeps the status line and the
// pending GPU update in step with the session.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "app/window/tools.h"
#include "app/window/transform_tool.h"
#include "app/deformation_path.h"
#include "core/session/session.h"
#include "render/camera.h"
#include "render/scene.h"

namespace sculpt::app {

// Overlays that belong to one tool: as Blender keeps overlay settings per mode, switching tools switches
// these, and the Overlays panel shows and edits the current tool's. (The sculpt tool's brush circle belongs
// here too.)
struct ToolOverlays {
    bool lattice = false;  // lattice edges and control points
};

// Layers drawn over the shaded mesh.
struct Overlays {
    bool wireframe = false;
    ToolOverlays sculpt;                  // the lattice is off: it would cover the mesh being sculpted
    ToolOverlays latticeTool{true};       // the lattice is what this tool edits
    bool latticeOuterOnly = false;  // only the control points and edges on the lattice's outer faces (Blender's
                                    // lattice "Outside"); selected points always show
    bool jacobian = false;  // det J colour map (turns on Jacobian tracking in the session)
    bool affected = false;  // influence of the last operation's control points
    bool vertexColors = true;  // the mesh file's own colours as the material, where it has them
};

// What the GPU copy of the scene is missing; drained by SculptApp::renderFrame.
struct PendingGpuUpdate {
    bool mesh = true;            // full setMesh (new mesh)
    bool allPositions = false;   // every vertex may have moved (a frame was entered or left)
    std::vector<int> vertices;   // otherwise the moved vertices (duplicates allowed)
    bool fields = true;          // lattice, det J, affected weights, constraints
};

struct FrameStats {
    double solveMs = 0.0;   // last command in the engine (solve + injectivity + evaluation), OpReport::wallMs
    double updateMs = 0.0;  // last GPU update (positions, normals, overlays)
    double renderMs = 0.0;  // CPU time of the last frame's draw calls (scene + UI)
    int lastUploadVertices = 0;
    // The frame rate while frames follow each other (a drag, an orbit): an average of frame intervals under
    // kIdleGapSeconds. After a longer gap the window had slept (it draws on change), and the panel says so
    // instead of a rate averaged over the sleep (a new user saw "0.7 fps" on an idle window).
    static constexpr double kIdleGapSeconds = 0.25;
    double frameMs = 0.0;
    bool afterIdle = true;
    // Which path deforms the mesh on screen, in a few words (DeformationPathChooser::label), and the measurements
    // or the reason behind it (its tooltip).
    std::string deformationPath = "CPU";
    std::string deformationDetails;
    // The stats panel shows "--" for the times and the frame rate, which differ run to run, so a frame is
    // reproducible pixel for pixel (golden-image tests, tests/render/window_golden_test.cpp).
    bool hideTimings = false;
};

enum class DragKind { Surface, Control, Transform };

// A drag in progress. Surface: a multi-point manipulation (the grabbed point or handles move with the
// cursor, the other handles and pins are held); Control: the selected control points move with the cursor.
// Either way the cursor moves in the plane through the grabbed point facing the camera. Transform: a modal
// G / R / S of the lattice tool (AppState::transform holds its state; only `active` and `kind` are used).
struct DragState {
    bool active = false;
    DragKind kind = DragKind::Surface;
    int pickedVertex = -1;                                  // corner of the hit triangle nearest the hit (-1: a handle)
    Eigen::Vector3d planePoint = Eigen::Vector3d::Zero();   // the grabbed point when picked
    Eigen::Vector3d planeNormal = Eigen::Vector3d::UnitZ(); // towards the camera at the time of the pick
    Eigen::Vector3d target = Eigen::Vector3d::Zero();       // where the cursor puts the grabbed point
    std::vector<Eigen::Vector3d> starts;   // Surface: each constraint's source at the press
    std::vector<Eigen::Vector3d> targets;  // Surface: each constraint's current target
    std::vector<int> moving;               // Surface: constraints that follow the cursor (the rest are held)
    std::vector<int> controlPoints;        // Control: the control points that move (the selection less its pins)
    std::vector<int> constraintHandles;    // Surface: per constraint, its handle (ToolState::handles) or -1
    int moves = 0, refused = 0;                             // updates, and how many were rejected
    // Updates that did not go all the way, by what stopped them (OpReport::refusedBy: "lattice" a fold,
    // "uncertified" undecided tests, "triangles" a crossing, "boundary", "symmetry" a grabbed point pulled onto
    // its mirror plane, anything else), applied short or refused (status line).
    int stoppedShort = 0, byFold = 0, byUncertified = 0, byCrossing = 0, byBoundary = 0, byMirror = 0, byOther = 0;
    double brushRadius = 0.0;  // Surface: the brush radius of this drag in world units (0: the whole cage)
    int grabbedConstraint = 0; // Surface: the constraint the cursor carries (the brush circle follows it)
    // The mesh at the press, so the end of the drag says how many vertices it moved in all: the count its undo
    // reports (each move's own report counts what that move changed).
    Positions before;
};

enum class Navigation { None, Orbit, Pan };

// A lattice of the library (Coquillart 1990, 3.2: lattices are tools kept apart from any mesh): a shipped
// assets/lattices/*.lattice.json or one the user opened.
struct LatticeLibraryEntry {
    std::string path;
    std::string name;
    std::shared_ptr<const core::Volume> volume;  // any kind (core/volume/volume.h)
};

// The Lattices panel's view state (lattices_panel.cpp); the lattice tools themselves live in the Session.
struct LatticesPanelState {
    std::vector<LatticeLibraryEntry> library;
    bool libraryLoaded = false;   // the shipped folder was read (once, when the panel first shows)
    int libraryChoice = 0;        // the entry "Add" and "Place" use
    int selectedTool = -1;        // the row of the session's tool list that Freeze, Remove, Save, Move act on
    double placeSizeFraction = 0.25;  // "Place": the tool's bounds diagonal, as a fraction of the mesh's
    bool showTools = true;        // draw the tools that are not frozen (dim, at rest), even with the Lattice overlay off
    int pinLayers = 0;            // Freeze: outer layers pinned, 0-2
    int editAxis = 0;             // "Insert knot" / "Refine axis": 0 u, 1 v, 2 w
    double insertAt = 0.5;        // "Insert knot": the lattice parameter along editAxis, in (0, 1)
    // "Place at picked point" waiting for its click on the mesh: a library entry is added there, or the
    // selected tool is moved there (edit_lattice).
    enum class Placing { None, LibraryEntry, Tool } placing = Placing::None;
    // Where the panel's header and buttons were drawn last frame (Dear ImGui pixels, by label), so tests
    // click them as a user does.
    struct ItemRect {
        std::string label;
        float x0 = 0.0f, y0 = 0.0f, x1 = 0.0f, y1 = 0.0f;
    };
    std::vector<ItemRect> items;
};

// The Lattices panel's T-spline section (Song & Yang 2005, seed 002; tspline_panel.cpp, tspline_commands.h):
// the set-up fields (sec. 4, sec. 6 steps 1-3) and the cells chosen for local subdivision (sec. 6, Fig. 11).
struct TSplinePanelState {
    int depth = 3;               // levels of octree subdivision of the cells holding the mesh, 1 .. 6
    double weightRatio = 100.0;  // heavy : light weights (sec. 4: "the ratio of them is 100:1")
    // The initial region (sec. 4): false, the mesh's bounds padded (the engine's default); true, the box below.
    bool customRegion = false;
    Eigen::Vector3d regionMin = Eigen::Vector3d::Zero(), regionMax = Eigen::Vector3d::Zero();
    bool regionFilled = false;   // min / max hold a box (the mesh's, padded, the first time a box is asked for)
    // With the mesh bounds, min / max show them: the session's journal length and mesh they were read at.
    size_t regionJournal = 0;
    std::string regionMesh;
    bool balance = true;         // subdividing: then the 2:1 balance (subdivide_cells "balance")
    bool picking = false;        // "Choose cells": a left click on the mesh adds or drops the cell under it
    std::vector<int> chosenCells;                     // cell ids of cellsVolume's T-lattice, sorted
    std::shared_ptr<const core::Volume> cellsVolume;  // the T-spline they belong to (a change of it drops them)
};

// The frozen T-spline's control points the window draws and picks (core::tsplineCageView), kept while the
// cage, the history and the mesh stay: the lattice tool asks on every mouse move.
struct TSplineShownCache {
    std::shared_ptr<const core::Volume> volume;  // held, so no other volume can take its address
    size_t journal = 0;
    std::string fingerprint;
    std::vector<std::uint8_t> controlPoints;
};

struct AppState {
    core::Session session;
    render::Camera camera;
    Overlays overlays;
    std::string meshName;
    bool modified = false;  // unsaved changes (kept current by FileCommands::poll, file_commands.h)
    int framebufferWidth = 0, framebufferHeight = 0;
    float statusLineHeight = 0.0f;  // pixels, as last drawn: the scene's det J legend sits above it
    // The history panel: the current entry and the count it last scrolled to, and whether the current entry was
    // in the list's view in the last frame that did not scroll (tests read it).
    int historyShownCursor = -1, historyShownCount = -1, historyScrollFrames = 0;
    bool historyCurrentVisible = false;
    // The history position a panel or the Edit menu asked for (-1: none): the app goes there after the frame, as
    // an engine step (engine_job.h), not in the middle of drawing the panels.
    int historyRequest = -1;
    float legendHeight = 0.0f;      // framebuffer pixels the det J legend takes above the status line; 0: not drawn

    std::string status = "Left-drag on the mesh to sculpt. Middle-drag or Alt+left-drag orbits, Shift+middle "
                         "pans, wheel zooms, Home frames. F sets the brush radius.";
    bool statusIsError = false;
    // Lines the status stands for in full (every warning of a load or save): its tooltip. setStatus clears them.
    std::vector<std::string> statusDetails;
    bool hasReport = false;
    core::OpReport lastReport;

    FrameStats stats;
    // Chooses between deforming the mesh on the CPU and in the vertex shader by timing frames of both
    // (deformation_path.h); reset with every new mesh.
    DeformationPathChooser deformationPath;
    PendingGpuUpdate gpu;
    bool meshHasVertexColors = false;  // the GPU has the file's colours for this mesh (set by each mesh upload)
    DragState drag;
    ToolState tools;
    TransformState transform;
    LatticesPanelState lattices;
    TSplinePanelState tspline;
    mutable TSplineShownCache tsplineShown;  // a cache only: never state of the shape (house style 9)
    Navigation navigation = Navigation::None;
    bool orthographicByAxisView = false;  // a numpad view made the camera orthographic; orbiting undoes it
    double cursorX = 0.0, cursorY = 0.0;
};

// Replaces the session's mesh (new lattice with `settings`, empty history) and frames it. On failure nothing changes.
Status setMesh(AppState& state, const Positions& positions, const Triangles& triangles, const std::string& name,
               const core::LatticeSettings& settings = {});

// Replaces the whole session with one prepared elsewhere (a background load: mesh set, maybe operations
// replayed) and frames it; the same bookkeeping as setMesh.
void installSession(AppState& state, core::Session&& session, const std::string& name);

// Records what the last session command moved into state.gpu (sparse when the session says so).
void noteSessionMoved(AppState& state);
// Puts a command's report on the status line ("what: verdict (why)"). what: the user's words for the operation
// ("Moving 2 control points"); empty: report.op in words (commandWords, wording.h: "Control point move").
void reportOperation(AppState& state, const core::OpReport& report, const Status& status, const std::string& what = {});
void setStatus(AppState& state, const std::string& text, bool isError);

void undoCommand(AppState& state);
void redoCommand(AppState& state);
// Undoes or redoes until historyCursor() == cursor (clamped to [0, history size]).
void jumpToHistory(AppState& state, int cursor);
// Asks for one undo (-1) or redo (+1) step, or a jump to `cursor`, from the panels (historyRequest).
void requestHistoryStep(AppState& state, int step);
void requestHistoryJump(AppState& state, int cursor);
void setInjectivityCommand(AppState& state, const core::InjectivitySettings& settings);
void setOverlays(AppState& state, const Overlays& overlays);
// The overlays of a tool (the Overlays panel shows the current tool's).
ToolOverlays& overlaysOfTool(Overlays& overlays, ToolMode mode);
const ToolOverlays& overlaysOfTool(const Overlays& overlays, ToolMode mode);
// Whether the lattice is drawn now: the current tool's Lattice overlay, nothing else.
bool latticeShown(const AppState& state);
// Whether lattice tools that are not frozen are drawn (dim, at rest): the Lattices panel's "Show tools" and
// at least one such tool.
bool latticeToolsShown(const AppState& state);
// One flag per control point of the session's lattice: drawn by the lattice overlay, and so pickable by the
// lattice tool (none while the overlay is off; with latticeOuterOnly the outer ones and the selected ones).
// A net lattice (EFFD): only the representative of each weld group, so welded points are one marker.
std::vector<std::uint8_t> shownControlPoints(const AppState& state);
// Points the camera at the current mesh so it fills the view (aspect of the current framebuffer).
void frameMesh(AppState& state);

// Aspect ratio of the framebuffer, 1 when it is empty (minimised window): never 0, inf or NaN.
float framebufferAspect(const AppState& state);

}  // namespace sculpt::app
