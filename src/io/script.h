// The script language: the operation list a script (or a recorded session) asks the engine to do, the report of
// what each operation did, and the runner and recorder. Each op is one entry of the table in script_ops.h (its
// name, JSON fields read and written, how it runs as a Session command, how it is recorded); the engine
// (core/session) knows commands, not scripts. Parsing and printing the JSON: script_json.h.
#pragma once

#include <array>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/injectivity/injectivity.h"
#include "core/volume/lattice.h"
#include "core/volume/lattice_edit.h"
#include "core/session/session.h"
#include "core/status.h"

namespace sculpt::io {

struct ScriptOp {
    enum class Kind {
        Drag, DragVertex, MoveControlPoint, Undo, Redo, Screenshot, SetupLattice, SetPins, BeginGroup, EndGroup, Group,
        AddLattice, EditLattice, RemoveLattice, Freeze, Unfreeze, Refine, SetRefinement, SetupTSpline, SubdivideCells,
        SetWeights, Hammer, Crimp
    };
    Kind kind = Kind::Undo;
    std::vector<core::PointConstraint> constraints;  // Drag
    int vertex = -1;                               // DragVertex
    Eigen::Vector3d target = Eigen::Vector3d::Zero();
    core::BrushSettings brush;                     // Drag, DragVertex: radius, strength, falloff, symmetry
    std::vector<std::array<int, 3>> controlPoints;   // MoveControlPoint: (i,j,k) per point; SetPins: points to pin
    std::vector<std::array<int, 3>> unpinned;      // SetPins: pin-layer points to unpin (the rest: the layers)
    Eigen::MatrixX3d values;                       //   "to" positions or "by" offsets, one row per point
    bool relative = false;                         //   true for "by"
    std::string path;                              // Screenshot: where to write (handled by the caller's hook)
    std::string label;                             // BeginGroup: the history entry's name (empty: the first op's)
    bool hasSettings = false;                      // SetupLattice: new settings, or (false) a fresh lattice
    core::LatticeSettings settings;                //   with the current ones around the current shape
    int groupFirst = 0;                            // Group: history entries [groupFirst, end) become one (label)
    core::LatticeTool tool;                        // AddLattice, EditLattice: the lattice tool (already placed);
                                                   //   EditLattice: a null net = the tool's current net, an
                                                   //   empty name = the tool's current name
    std::vector<core::NetEdit> netEdits;           // EditLattice: edits applied in order to that net (3.1.4)
    int toolIndex = -1;                            // EditLattice, RemoveLattice, Freeze, SubdivideCells: which tool
    int pinLayers = 0;                             // Freeze: outer layers kept fixed (from its boundary faces)
    double tolerance = 0.0;                        // Refine: fraction of the diagonal (0: the session's setting)
    core::RefinementSettings refinement;           // SetRefinement: Session::refinement().set
    core::TSplineSetup tspline;                    // SetupTSpline: Session::tspline().setup
    std::vector<int> cells;                        // SubdivideCells: T-lattice cell ids of tool toolIndex,
    std::vector<Eigen::Vector3d> cellPoints;       //   and world points whose leaf cells are subdivided ("at")
    bool balance = true;                           //   then the 2:1 balance
    core::WeightToolSettings weightTool;           // SetWeights, Hammer, Crimp: Session::tspline().sculptWeights
                                                   //   (its tool field is set from the kind)
    // Recordings: what the operation was applied as (its steps: fresh frames and control displacements). A
    // replay on the mesh it was recorded on applies these exactly instead of deciding again.
    bool hasApplied = false;
    core::Operation applied;
    bool cancelled = false;  // an interactive drag that was taken back (Esc): applied, then undone
};

const char* scriptOpName(ScriptOp::Kind kind);

struct Script {
    std::string mesh;  // optional: the mesh the script applies to, as written (relative to the script's folder)
    // Recordings: Session::meshAsSet().fingerprint of the mesh recorded on. When the session's mesh has this
    // fingerprint, ops with recorded steps are replayed exactly (Session::replayOperation); on any other mesh
    // the ops are decided again for that mesh (Coquillart's recording operator).
    std::string meshFingerprint;
    // The mesh's coincident vertices are welded on load (io/mesh_weld.h) before the ops run: a session recorded
    // on a welded mesh names its vertices as welded ("weld": true in the JSON; the command line's --weld).
    bool weldMesh = false;
    core::LatticeSettings lattice;
    core::InjectivitySettings injectivity;  // applies to every operation of the script
    std::vector<ScriptOp> ops;
};

// Every command of a session (Session::history().journal()) as a script that replays it: the lattice placed in
// the box the session started with, the injectivity settings, the mesh's fingerprint, and every operation, undo, redo,
// pin change and taken-back drag in order, each operation with the steps it was applied as. Replayed on the
// same mesh it gives the same vertices bit for bit; on another mesh the operations are decided again.
Script recordSession(const core::Session& session);

struct ScriptReport {
    std::vector<core::OpReport> ops;
};

// Called for screenshot ops with the session as it is at that point of the script.
using ScreenshotHook = std::function<Status(const core::Session& session, const ScriptOp& op)>;

// Called before op `done` of `total` (and once with done == total at the end); returning false stops the
// script there (a long replay in the window can be cancelled).
using ScriptProgress = std::function<bool(size_t done, size_t total)>;

// Runs one op on the session as runScript does (deciding it again; a recorded op's "applied" steps are not
// replayed): the window's commands go through this, so they are the script ops themselves. report.op is the
// op's name (scriptOpName), whichever command ran it. Fails as the op's command fails.
Status runScriptOp(core::Session& session, const ScriptOp& op, core::OpReport& report);

// Runs the ops in order on a session whose mesh and lattice are already set up. Stops at the first op with
// bad input and returns its error prefixed with "op N (kind): "; the report then holds the ops before it.
// Stopped by `progress`: returns an error saying so.
Status runScript(core::Session& session, const Script& script, ScriptReport& report, const ScreenshotHook& screenshot = {},
                 const ScriptProgress& progress = {});

}  // namespace sculpt::io
