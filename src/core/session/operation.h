// What the session's commands take and give (session.h): point constraints, the report of an operation, the
// history's operations and their injective steps (Gain & Dodgson 2001, section 8: a manipulation split into
// steps), the journal of what was asked, and the layers and frozen frames of the lattice stack.
#pragma once

#include <algorithm>

#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/deform/brush.h"
#include "core/deform/brush_field.h"
#include "core/deform/direct_manipulation.h"
#include "core/deform/refinement.h"
#include "core/injectivity/injectivity.h"
#include "core/mesh_types.h"
#include "core/status.h"
#include "core/tspline/tspline_volume.h"
#include "core/volume/lattice.h"

namespace sculpt::core {

// A point constraint in world space: the point currently at `source` should end up at `target`.
struct PointConstraint {
    Eigen::Vector3d source = Eigen::Vector3d::Zero();
    Eigen::Vector3d target = Eigen::Vector3d::Zero();
};

enum class OpStatus { Applied, Rejected, NoOp };
const char* opStatusName(OpStatus status);

// What one command did, for the report and the status line.
struct OpReport {
    std::string op;                  // "drag", "drag_vertex", "move_control_point", "undo", "redo", ...
    OpStatus status = OpStatus::NoOp;
    std::string reason;              // why it was rejected or did nothing
    std::vector<double> residuals;   // per constraint, world units (drags)
    bool rankDeficient = false;      // the constraints could not all be met exactly (least-squares result)
    int controlPointsChanged = 0;
    int verticesMoved = 0;
    double wallMs = 0.0;
    // Injectivity (Gain & Dodgson 2001): the verdict of the test, how many injective steps the operation was
    // split into (1 = not subdivided), the deepest recursion level used, and the time spent testing.
    std::string injectivity;         // "injective", "not checked" (mode off), or why it was rejected
    int subSteps = 0;
    int depthReached = 0;
    double injectivityMs = 0.0;
    // What stopped a step (or made the operation subdivide): "lattice" (det J test), "boundary" (the free
    // lattice boundary would overlap itself), "triangles" (two triangles would cross), or empty.
    std::string refusedBy;
    // What the test found there, in words (stepFailureWords): "part 1 (80 triangles) and part 2 (80 triangles)
    // would cross (of the mesh's 2 parts) near (...)", "the lattice would fold over itself near (...)"; the
    // window quotes it (a transform's stop names the parts). Empty with refusedBy.
    std::string failureWords;
    double triangleCheckMs = 0.0;    // the triangle check's share of the time
    // A control-point edit stopped short of where it was asked, at the last injective position along the
    // move: the fraction of the move applied (1 = all of it).
    double fractionApplied = 1.0;
    // Refinement (refine, or a drag or edit refined automatically): what it added, and the largest deviation
    // of a triangle from its curved image afterwards (world units; refinement.h).
    int verticesAdded = 0;
    int trianglesAdded = 0;
    int verticesRemoved = 0;  // undo of a refinement (or of a stroke that split the mesh): the vertices it took away
    double deviation = 0.0;
};

enum class OperationKind { Drag, ControlPointEdit, LatticeSetup, LatticeTools, Refine, WeightEdit };

// A lattice tool associated with the mesh (Coquillart 1990, 3.2: a list of lattices per surface, one frozen at
// a time): a named lattice of any shape, placed in world space. Editing it never touches the mesh.
struct LatticeTool {
    std::string name;
    std::shared_ptr<const Volume> volume;  // any kind (volume.h): a net, a composite, ...
};

// Session::tspline().setup's settings (Song & Yang 2005, sec. 4 and sec. 6 steps 1-3).
constexpr int kMaxTSplineSetupDepth = 6;
constexpr int kMaxTSplineSetupRootCells = 16;
struct TSplineSetup {
    // octree.depth: levels of subdivision of the cells holding a vertex, 1 to kMaxTSplineSetupDepth;
    // octree.rootCount: the initial lattice, 1 to kMaxTSplineSetupRootCells cells per axis (default 1 x 1 x 1);
    // weightRatio (100): heavy : light weights (sec. 4); padding (0.05): the default region's margin.
    TSplineOctreeSettings octree;
    // The initial region (sec. 4: "the region may cover the whole model or just some parts of it"). false: the
    // mesh's bounds grown by octree.padding x their diagonal on every side, so no vertex lies on its boundary.
    bool hasRegion = false;
    Eigen::Vector3d regionMin = Eigen::Vector3d::Zero(), regionMax = Eigen::Vector3d::Zero();
    std::string name;     // the tool's name; empty: "tspline"
    bool freeze = true;   // freeze the new tool (no pin layers) after adding it
};

// Why a step of an operation was not applied: what failed, in the engine's terms, and where on the mesh.
struct StepFailure {
    // Lattice: a point with det J <= 0 was evaluated (a fold). Uncertified: the injectivity tests stayed undecided
    // after escalating (conic to exact, deeper subdivision) and found no fold: not proven, not known to fold.
    // MirrorPlane: a symmetric stroke's pull would carry the grabbed point onto or across a mirror plane, where it
    // meets its own mirror image (an injective symmetric deformation keeps each side of the plane on its side),
    // so the fold or crossing found there cannot be avoided; `technical` keeps what the test found.
    enum class Cause { None, SourceLeft, Lattice, Uncertified, Boundary, Triangles, MirrorPlane } cause = Cause::None;
    std::string technical;  // e.g. "conic test fails in cell [2,4,1] (...)"
    // Triangles, on a mesh of several parts: which block it, e.g. "part 2 (340 triangles) and part 5 (1200
    // triangles) would cross (of the mesh's 12 parts)"; empty otherwise.
    std::string parts;
    std::string plane;  // MirrorPlane: which plane, "X", "Y" or "Z"
    Eigen::Vector3d where = Eigen::Vector3d::Constant(NAN);  // world point near the failure (current shape)
};
// "lattice" (a fold), "uncertified", "boundary", "triangles", "symmetry" (MirrorPlane), "source" or ""
// (OpReport::refusedBy).
const char* stepFailureCauseName(StepFailure::Cause cause);
// Where a move stopped short, e.g. "where the lattice would fold", "where the deformation could no longer be
// certified" (report reasons: "stopped " + this).
std::string stepStopWords(StepFailure::Cause cause);
// What would happen, in the user's words, e.g. "the surface would pass through itself near (0.1, 0.2, 0.3)".
std::string stepFailureWords(const StepFailure& failure, bool drag);
// What the user can do about it, e.g. "try a smaller move, a finer lattice, or a finer mesh there".
std::string stepFailureAdvice(StepFailure::Cause cause);

// A change of the frozen weighted T-spline's weights (Song & Yang 2005, eq. 5: Q(t) = sum W P B / sum W B,
// sec. 6 step 4: "modify the control points or weights"), applied before the step's control displacement.
struct WeightChange {
    std::vector<int> ids;               // control points (T-spline anchors), ascending, each once
    std::vector<double> before, after;  // their weights (finite, > 0)
    bool empty() const { return ids.empty(); }
};
// What applying a weight change overwrote, to undo it bitwise. Made again by redo and replay; never recorded.
struct WeightUndo {
    std::vector<int> vertices;                   // the vertices in the changed control points' support
    std::vector<int> entries;                    // their entries in the embedding (which keeps rest rows too)
    Positions rest, output, positions;           // their rows before (output: the cage's output under layers)
    std::vector<double> jacobian;                // frozenJacobian_ before (when tracking det J)
    ControlDelta displacement;                   // the displaced control points' displacements before
    std::shared_ptr<const Volume> volume;        // the frozen volume before
};

// The sculpting-by-weights tools (Song & Yang 2005 sec. 1 and 6, after Noble & Gordon 1999) as the user asked
// for them (what a recording writes and a replay on another mesh decides again). Exact definitions:
// Session::tspline().sculptWeights and docs/tsplines.md "Sculpting by weights".
struct WeightToolSettings {
    enum class Tool { SetWeights, Hammer, Crimp };
    Tool tool = Tool::SetWeights;
    // SetWeights: control point ids (anchors of the frozen T-spline) and their new weights (finite, > 0).
    std::vector<int> ids;
    std::vector<double> weights;
    // Hammer, Crimp: the picked mesh vertex, and the control points that make the bump: `controlPoint` if >= 0,
    // else every visible control point (of a non-empty cell) whose blending function is non-zero at the vertex
    // and whose rest position lies within `radius` (world units) of the vertex's rest position (the same points
    // however far the bump has grown), plus always the strongest there: the one whose
    // displacement moves the vertex most (R_s |delta_s|), or with no displacement yet the largest R_s.
    int vertex = -1;
    int controlPoint = -1;
    double radius = 0.0;
    // Hammer: the vertex's height after (world units along the bump direction) if hasHeight, else the bump
    // scaled by `scale` (finite; 0 flattens it, negative turns it over).
    bool hasHeight = false;
    double height = 0.0;
    double scale = 1.0;
    // Crimp: the bump's width at half height is multiplied by widthFactor (finite, > 0), its height kept.
    double widthFactor = 1.0;
};

struct WeightBump;  // tspline_weights.cpp

// One injective deformation: a control displacement in the cage, or in a layer the step made.
struct Step {
    bool freshFrame = false;   // a new layer (subdivision or brush region) was put after the cage and its
                               // layers before this step, and `delta` is its displacement
    bool newCage = false;      // a lattice set-up: the cage was frozen with its layers and a fresh cage put
                               // around the mesh; `delta` is in the new cage
    LatticeSettings settings;  // with freshFrame or newCage: the settings of that lattice
    // With freshFrame or newCage: the box it was placed in, and whether it kept the cage's pin edits (same
    // settings); redo and replay place it exactly there instead of deciding again.
    Eigen::Vector3d frameMin = Eigen::Vector3d::Zero(), frameMax = Eigen::Vector3d::Zero();
    // With freshFrame: the layer box's axes (Lattice::boxAxes; frameMin/frameMax are in its coordinates). A brush
    // region is aligned with its pull; every other layer has the identity.
    Eigen::Matrix3d frameAxes = Eigen::Matrix3d::Identity();
    bool framePinsKept = false;
    // A brush's region-of-interest layer: every control point is pinned except `regionFree` (brush.h).
    bool region = false;
    std::vector<int> regionFree;
    ControlDelta delta;        // the change of the control points (cage, or the layer this step made)
    // After this step the layers (those this operation made, since the last baked step) were put into the rest
    // shape the cage deforms (Session::bakeLayers); undo takes them out again first.
    bool baked = false;
    // Set when baked (made again by redo and replay, never recorded): the vertices whose rest point was outside
    // the cage's box before, which unbaking puts outside again (once the cage's boundary has moved, a point
    // outside the box can also be the image of one inside).
    mutable std::vector<int> bakedOutside;
    std::vector<PointConstraint> constraints;  // drags: where the sources were before and after the step
    WeightChange weights;      // a weight change of the frozen T-spline, applied before `delta` (in the cage)
    mutable std::shared_ptr<WeightUndo> weightUndo;  // set when `weights` is applied; what undo puts back
};

// One history entry: the manipulation as the user gave it (to record and replay it) and the injective
// steps it was applied as (to undo and redo it).
struct Operation {
    OperationKind kind = OperationKind::Drag;
    std::string label;                            // e.g. "drag (2 points)", for history lists
    std::vector<PointConstraint> constraints;     // Drag: world-space sources and targets when it was applied
    std::vector<int> controlPoints;               // ControlPointEdit: ids, and offsets (#ids x 3)
    Eigen::MatrixX3d offsets;
    LatticeSettings settings;                     // LatticeSetup
    std::vector<Step> steps;
    int depthReached = 0;
    bool interactive = false;  // an interactive drag (recorded step by step: its increments were tested apart)
    std::vector<int> pinToggles;  // control points whose pin differed from the pin layers when it was applied
    BrushSettings brush;          // Drag: the brush it was asked with (radius 0: none)
    // LatticeTools: tool `toolIndex` of the list went from toolBefore to toolAfter (a null net: it did not
    // exist; add appends, remove erases). LatticeSetup by freeze / unfreeze: the frozen tool before and after
    // (-1: the box lattice).
    int toolIndex = -1;
    LatticeTool toolBefore, toolAfter;
    int frozenBefore = -1, frozenAfter = -1;
    RefinementRecord refinement;  // edges split after the steps: a Refine, or an edit refined automatically
    // Edges split before the steps: a brush stroke refined under its pull, where its field bends the mesh's
    // triangles so far from flat that they would cross (Stroke::applyBrushPulls). Applied to the mesh as it was
    // when the stroke began (redo and replay split them first), removed after the steps are undone.
    RefinementRecord refinementBefore;
    WeightToolSettings weightTool;  // WeightEdit: the tool as asked
    // A group of operations that change the lattice tools or the frozen one (e.g. setup_tspline: add the tool,
    // freeze it): the operations themselves, undone in reverse and redone in order as one history entry. Their
    // refinements are this operation's `refinement`; `steps` is empty.
    std::vector<Operation> parts;

    // How many injective steps it was applied as (Gain & Dodgson 2001's subdivision; OpReport::subSteps): its
    // steps, except that a brush stroke's are its region layers (a field per pull, brush_field.h, each proven
    // whole), which are one step (a history read "brush drag, symmetric in X [2 steps]" for one stroke).
    int injectiveSteps() const {
        const bool brushLayers = !steps.empty() && std::all_of(steps.begin(), steps.end(), [](const Step& step) { return step.region; });
        return brushLayers ? 1 : static_cast<int>(steps.size());
    }
};

// One command as the session carried it out, in order: what a recording writes so that a replay on the same
// mesh does exactly what was done (design.md: "A recording records what was applied, not what was asked").
struct JournalEntry {
    enum class Kind {
        Operation,      // `operation` was applied (with its steps) and pushed onto the history
        Undo, Redo,     // of the last / next history entry
        CancelledDrag,  // `operation`'s steps were applied by an interactive drag, then taken back (Esc)
        Group,          // history entries [groupFirst, end) became one (label)
        Pins,           // the pins became the pin layers with `pinToggles` flipped
        Refinement      // the refinement setting became `refinement` (Session::refinement().set)
    };
    Kind kind = Kind::Operation;
    Operation operation;
    int groupFirst = 0;
    std::string label;
    std::vector<int> pinToggles;
    LatticeSettings settings;  // Pins: the settings of the lattice the pins are in (resolution, pin layers)
    RefinementSettings refinement = {};  // Refinement (the "= {}" keeps brace-initialised entries warning-free)
};

// A lattice applied after the cage (subdivision's fresh lattices, brush regions). Its own rest space is its
// input: x -> x + sum R(t(x)) delta, the identity outside its box.
struct Layer {
    Lattice lattice;
    LatticeSettings settings;
};

// What Session::setMesh found in the mesh it was given (Session::meshAsSet()); fixed until the next setMesh.
struct MeshAsSet {
    // A hash of the mesh as set (positions bit for bit and triangles), naming it in recordings: a replay on the
    // mesh with this fingerprint repeats the recorded steps exactly.
    std::string fingerprint;
    // The plane centre of symmetric drags: the centre of the mesh's bounding box.
    Eigen::Vector3d symmetryCentre = Eigen::Vector3d::Zero();
    // Intersecting triangle pairs (a self-intersecting input; these never count against an operation). Pairs
    // with a degenerate triangle in them are not counted here but in degenerateTriangles: triangles with no area
    // (collinear or coincident corners, decided exactly).
    int intersectingPairs = 0;
    int degenerateTriangles = 0;
    // Pairs that do not intersect but touch to within SelfIntersectionIndex::kNearContactTolerance of the
    // diagonal (a sliver folded over its neighbour): contacts too, which may shift as they move.
    int nearContactPairs = 0;
};

// A cage that was replaced by a fresh one (lattice set-up), kept compactly so undo can return to it.
struct FrozenFrame {
    LatticeSettings settings;
    Eigen::Vector3d boxMin, boxMax;
    ControlDelta displacement;     // its non-zero control displacements at the time it was frozen
    std::vector<int> pinToggles;   // control points whose pin differs from the settings' pin layers
    std::vector<Layer> layers;     // the layers it had
    bool collar = false;           // it carried a collar (LatticeStack::carriesCollar)
    SymmetryFrame symmetry;        // the mirror planes in its rest space (Session::symmetryFrame)
};

}  // namespace sculpt::core
