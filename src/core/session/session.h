// Session: the engine's document. One mesh, the lattice it is embedded in, and the history of manipulations.
// Every user action (window or script) is one of the commands below; the GUI keeps no engine state.
//
// Positions follow design.md's data flow: rest positions X0 at lattice set-up, x = X0 + sum R delta,
// re-evaluated only for the cells whose support contains a changed control point.
//
// The cage and its layers. The lattice the user set up (the "cage") is the user's object (design.md): it is
// never replaced behind their back. Deformations that need a lattice of their own are *layers* applied after
// the cage, in order: the mesh shown is  x = L_k( ... L_1( C(X0) ) ),  C the cage's FFD of the rest positions.
// - Adaptive subdivision (Gain & Dodgson 2001, section 8, Appendix): an operation that fails the injectivity
//   test is split into two halves applied one after another, recursively up to the maximum depth; each half
//   after the first is applied in a fresh regular lattice around the mesh the earlier steps produced (a new
//   layer), so the composition of injective steps is injective. If the depth is exhausted the operation is
//   rejected and nothing changes.
// - A brush drag (brush.h) is solved in a region-of-interest lattice around the grabbed point (a layer).
// Every operation starts in the cage: a drag is solved there through the layers (its source and target are
// traced back through them by Newton's method), and a control-point edit moves the cage's points as they are
// shown, carried through the layers (cagePoints()). Setting up a new lattice freezes the cage with its layers
// (a "frame") and puts a fresh cage around the mesh.
//
// Undo is the inverse manipulation: in the cage it subtracts the step's control displacement (Hu et al. 2001,
// section 4: the group inverse omega(S, -rho)) and carries the change through the layers; a step that made a
// layer removes it, which recomputes the vertices it moved from the layers below; leaving a frozen frame
// inverts its injective FFDs per vertex by Newton's method (injectivity is what makes the inverse exist). The
// history holds operations and small lattices, never copies of the mesh.
#pragma once

#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/deform/brush.h"
#include "core/deform/brush_field.h"
#include "core/deform/direct_manipulation.h"
#include "core/volume/embedding.h"
#include "core/injectivity/injectivity.h"
#include "core/volume/lattice.h"
#include "core/mesh_types.h"
#include "core/session/cage_pins.h"
#include "core/session/drag_state.h"
#include "core/session/refiner.h"
#include "core/session/stroke.h"
#include "core/session/tool_library.h"
#include "core/session/tspline_tools.h"
#include "core/session/history.h"
#include "core/session/lattice_stack.h"
#include "core/session/operation.h"
#include "core/deform/refinement.h"
#include "core/injectivity/self_intersection.h"
#include "core/status.h"
#include "core/tspline/tspline_volume.h"

namespace sculpt::core {

// A session's mesh (Session::mesh()). Rows are vertices, in world units.
struct SessionMesh {
    Positions original;   // as setMesh was given it (its fingerprint is meshAsSet().fingerprint)
    Positions rest;       // #V x 3: X0, what the cage deforms (design.md: x = X0 + sum R delta)
    Positions positions;  // #V x 3: x, as shown: the rest positions through the cage and its layers
    Triangles triangles;  // #F x 3 vertex indices
    // Changes whenever `rest` or its embedding in the cage change (a mesh set, a lattice set up, a frame
    // entered or left, a refinement, a weight edit that moves the rest surface): a view that deforms the rest
    // mesh itself (the renderer's GPU path) uploads it again. Within one session only: compare it together
    // with the session's identity.
    std::uint64_t restVersion = 0;
    bool empty() const { return rest.rows() == 0; }  // no mesh is set
};

// The vertices whose position the last command changed (for sparse normal and buffer updates).
struct MovedVertices {
    std::vector<int> vertices;
    bool all = false;  // every vertex may have changed (a frame was entered or left), listed or not
};

class Session {
public:
    // Replaces the mesh (rest = current positions) and embeds it in a new lattice with `settings`; clears
    // the history. On failure nothing changes.
    Status setMesh(const Positions& positions, const Triangles& triangles, const LatticeSettings& settings = {});

    // Puts a fresh lattice with new settings around the current (deformed) mesh, as an undoable operation.
    Status setupLattice(const LatticeSettings& settings, OpReport& report);

    // The lattice tools of any shape and the frozen one (Coquillart 1990, EFFD; tool_library.h).
    ToolLibrary tools() { return ToolLibrary(*this); }
    const ToolLibrary tools() const { return ToolLibrary(const_cast<Session&>(*this)); }
    // The weighted T-spline tools: set-up, subdivision, sculpting by weights (Song & Yang 2005; tspline_tools.h).
    TSplineTools tspline() { return TSplineTools(*this); }
    const TSplineTools tspline() const { return TSplineTools(const_cast<Session&>(*this)); }

    // The injectivity test of every later step. Off is a plain FFD (Sederberg & Parry, as PyGeM): a lattice set
    // up from then on does not pin the boundary of a lattice that holds only part of the mesh
    // (cage_pins.h), so every control point can move and the vertices outside stay where they are. A
    // test switched on pins that boundary again at once (what is already displaced stays).
    void setInjectivity(const InjectivitySettings& settings);
    const InjectivitySettings& injectivity() const { return injectivity_; }

    // Moves each constraint's source (a point in the current deformed space inside the lattice) onto its
    // target with the least lattice change (Hu et al. 2001 eq. 7 / 12), subdivided into injective steps as
    // needed. Bad input (empty list, non-finite coordinates, a source outside the lattice) returns an error
    // and changes nothing; an operation that cannot be made injective is reported Rejected and changes nothing.
    // With a brush (brush.h): the targets are scaled by its strength (the history keeps them as asked), mirror
    // images are added for its symmetry (planes through meshAsSet().symmetryCentre), and with a radius the drag
    // is a brush stroke (stroke.h) that moves nothing farther than 1.25 radius from a source's path. A bad brush
    // is an error.
    Status drag(const std::vector<PointConstraint>& constraints, OpReport& report, const BrushSettings& brush = {});
    // Drags a mesh vertex to target.
    Status dragVertex(int vertex, const Eigen::Vector3d& target, OpReport& report, const BrushSettings& brush = {});
    // Moves control points (ids as Lattice::index) to absolute positions, or by offsets when relative.
    // values: #indices x 3. Pinned points, ids out of range or non-finite values are errors.
    Status moveControlPoints(const std::vector<int>& indices, const Eigen::MatrixX3d& values, bool relative,
                             OpReport& report);
    // Makes the operations history()[first, history().cursor()) one history entry (an interactive operation
    // made of their steps, undone and redone as one), e.g. a replayed interactive drag; operations that change the
    // lattice tools or freeze / unfreeze one are kept whole as the entry's `parts`. The cursor must be at the
    // end of the history. label empty: the first operation's.
    Status groupOperations(int first, const std::string& label);
    // Applies a recorded operation exactly as it was applied when recorded: its steps (fresh frames and
    // control displacements), no solve and no test, and pushes it onto the history. For a replay on the mesh
    // the recording was made on (the same meshAsSet().fingerprint). cancelled: the steps of an interactive
    // drag that was taken back, applied and taken back again (nothing is pushed). Fails, changing nothing, on a
    // step whose control point ids or settings do not fit.
    Status replayOperation(const Operation& operation, bool cancelled, OpReport& report);
    // Undo / redo the last operation; with nothing to undo or redo, report.status = NoOp (not an error).
    Status undo(OpReport& report);
    Status redo(OpReport& report);

    // The drag in progress (stroke.h): begin / beginAt / beginControl, update, end, cancel. The window's mouse
    // drags and a script's drag (above, a stroke of one update) run it.
    Stroke stroke() { return Stroke(*this); }
    const Stroke stroke() const { return Stroke(const_cast<Session&>(*this)); }

    // Vertices left behind by the cage: those resting outside its box (which it never moves) that share a
    // triangle with a vertex inside it that the cage has moved from its rest point (a spike pulled out of the
    // box, whose base then moved with a cage edit). The window names them after a drag. One pass over the
    // vertices and the triangles, evaluating the cage only at corners of triangles the box's boundary cuts; 0
    // for a lattice of another kind (its volume holds what it deforms).
    int verticesLeftOutsideCage() const;

    // Keeps, per vertex, the product of the det J of every frozen frame (the Jacobian of the total
    // deformation since the mesh was set is that times the current lattice's det J). Costs a det J per vertex
    // moved in a frame when the frame is frozen or left, so it is off unless a view asks for it.
    void setTrackJacobian(bool track);
    // det J of the whole deformation since setMesh at every vertex (1 = unchanged, <= 0 would be a fold).
    // Tracking must be on for frames frozen before now to count.
    std::vector<double> totalJacobianDeterminants() const;

    // Pins and unpins of the cage's control points (cage_pins.h).
    CagePins pins() { return CagePins(*this); }
    const CagePins pins() const { return CagePins(const_cast<Session&>(*this)); }

    // Lattice parameters of a vertex (from its rest position: exact). Fails if the vertex is outside the box.
    Status parametersOfVertex(int vertex, Eigen::Vector3d& params) const;

    // The mesh: where its vertices are now, at rest and as set, its triangles, the rest data's version.
    const SessionMesh& mesh() const { return mesh_; }
    const Lattice& lattice() const { return stack_.lattice(); }  // the cage (cage().lattice())
    // The cage, its layers and frozen frames, and the composition through them (lattice_stack.h).
    const LatticeStack& cage() const { return stack_; }
    // The operations, the cursor (entries [0, cursor) are applied) and the journal: every command since setMesh,
    // in order, what recordSession writes (history.h).
    const History& history() const { return history_; }
    // The mesh as set: its fingerprint, symmetry centre, and the crossings and degenerate triangles it came with
    // (operation.h).
    const MeshAsSet& meshAsSet() const { return asSet_; }
    // Where the mirror planes of a symmetric drag or stroke are now (brush.h): the planes through the centre of
    // the mesh's bounds at load, carried by the deformation since, as Blender keeps them in the object's own
    // space: a move or turn of the whole cage moves and turns them (exactly, for a rigid or affine cage motion;
    // otherwise by the deformation's derivative at the centre, its rotation part). Planes of the loaded mesh
    // while nothing has moved it.
    SymmetryFrame symmetryFrame() const;
    // Bytes held by the history (operations and frozen frames), not counting the mesh itself.
    size_t historyBytes() const;
    // The vertices whose position the last command changed (for sparse normal and buffer updates).
    const MovedVertices& lastMoved() const { return lastMoved_; }

private:
    // A brush a drag may use: validateBrush, and a radius within 1000 x the mesh's diagonal (the error names the
    // radius that reaches every vertex).
    Status checkBrush(const BrushSettings& brush) const;
    // State kept while an operation is being applied, so a rejection restores everything bitwise.
    struct Snapshot {
        bool saved = false;
        Positions positions, cageOut;
        Lattice cage;
        size_t layerCount = 0;
        bool layerActive = false;
        Lattice activeLayer;        // with layerActive: the newest layer's lattice
        Embedding layerEmbedding;   // with layerActive
    };
    struct Progress {
        explicit Progress(Snapshot& scratch) : snapshot(scratch) { snapshot.saved = false; }
        Operation* operation = nullptr;
        bool appliedInCurrentFrame = false;  // a step of this operation already changed the active lattice
        bool pendingFreshFrame = false;      // a layer was entered and no step has been applied in it yet
        Step pendingFrame;                   // that layer's placement (Step::frameMin, frameMax, ...)
        Snapshot& snapshot;  // the session's scratch_, reused so large copies do not fault in fresh pages
        StepFailure failure;                                        // the last step that failed
        StepFailure firstFailure;                                   // what first made it subdivide
        double injectivityMs = 0.0;
        double triangleMs = 0.0;
        std::vector<int> moved;
        bool movedAll = false;
    };

    // Reports an operation applied in one step that moved the vertices `moved` (in any order, repeats allowed):
    // they become lastMoved_.vertices, and the report says applied, injective (or not checked), 1 step, their count.
    void reportSingleStep(std::vector<int> moved, OpReport& report);
    // The injectivity test (Gain & Dodgson 2001) of `cells` of `lattice` in the session's mode: true when
    // certified, the checks are off, or `cells` is empty; else `failure` names the cell (a tensor net's [i,j,k],
    // another volume's chunk) and where it is. The test's time is added to injectivityMs.
    bool certifyCells(const Lattice& lattice, const std::vector<int>& cells, StepFailure& failure, double& injectivityMs) const;
    // No triangle among the vertices `changed` crosses one it did not cross at the rows of before_ (the
    // positions before the step at those vertices): true, or `failure` names the pair and where it was.
    // The time is added to injectivityMs and triangleMs.
    bool noNewCrossing(const std::vector<int>& changed, StepFailure& failure, double& injectivityMs, double& triangleMs);
    // Applies delta to the lattice and the mesh if every check passes: the injectivity test of the cells it
    // reaches (Gain & Dodgson 2001), the free boundary's self-overlap, and no new crossing of triangles;
    // otherwise leaves lattice and positions bitwise as they were and says why. Moved vertices are appended
    // to `moved`. keep = false: a probe; everything is put back even when the checks pass. The checks' time is
    // added to injectivityMs, the triangle check's share also to triangleMs.
    bool tryDelta(const ControlDelta& delta, std::vector<int>* moved, StepFailure& failure, double& injectivityMs,
                  double& triangleMs, bool keep = true);
    // Several layers that show as one result (a brush update's layers: brush_field.h): the triangle check of each
    // tryDelta (keep = true) is deferred to finishDeferredTriangles, which checks the union of the vertices they
    // moved against their rows as the first of them found them. The mesh shows only that result, and each layer's
    // map is injective on its own (their composition is), so what the layers between would show is not checked:
    // a bend made in two layers (along and across a mirror plane, a widening then its pull) may pass through a
    // state whose flat triangles cross where the result's do not.
    void beginDeferredTriangles();
    // The deferred check (true when no triangle among the layers' vertices crosses one it did not cross before
    // them, or `failure` says which); ends the deferral either way. The caller takes the layers back on false.
    bool finishDeferredTriangles(StepFailure& failure, double& injectivityMs, double& triangleMs);
    // Ends a deferral without its check (the layers were taken back).
    void abandonDeferredTriangles();
    // The largest fraction s in [0, 1] of `delta` (to 1/1024) that passes tryDelta, applied (bisection on the move:
    // design.md "The cage is the user's object": a control-point edit stops at the injective limit).
    double applyLargestInjectiveFraction(const ControlDelta& delta, std::vector<int>* moved, StepFailure& failure,
                                         double& injectivityMs, double& triangleMs);
    // The index of the triangle check learns which vertices moved (nullptr: all of them).
    void positionsChanged(const std::vector<int>* vertices);
    // What the active lattice's evaluation writes: the cage's output under layers, else the positions.
    Positions& activeOutput() { return stack_.cageUnderLayers() ? stack_.cageOut_ : mesh_.positions; }
    // mesh_.positions[v] = cageOut_[v] carried through every layer, for the listed vertices.
    void refreshLayerOutput(const std::vector<int>& vertices);
    // Puts a new layer after the others and makes it active: a recorded one (redo, replay, or a brush region
    // placed by applyBrushPulls), or a fresh regular lattice with the cage's settings around the mesh the active
    // lattice deforms. placed: its placement for the step that will be applied in it.
    Status enterLayer(Progress* progress, Step* placed, const Step* recorded);
    // Removes the newest layer: the vertices it moved get their positions from the layers below.
    void popLayer(std::vector<int>* moved) { popLayers(1, moved); }
    // Removes the newest `count` layers at once: the vertices they moved are carried once through the layers
    // left, not once per layer removed (undoing a 10-step subdivided drag: no layer left to carry them through,
    // where popping one by one took 9 + 8 + ... + 1 layer evaluations per vertex).
    void popLayers(size_t count, std::vector<int>* moved);
    // Detail travels with the surface (issue "Sculpting as a sculptor expects", point 1): the layers' change
    // becomes part of the rest shape the cage deforms. Every vertex a layer moved gets the cage parameters of
    // where it is now (Newton's method, locateDeformedPoint: the cage is injective, so they exist) and the
    // rest point there; the layers are removed and the mesh keeps its positions. A later edit of the cage
    // then carries the sculpted detail with the surface. Returns false (nothing changed) if a moved vertex has
    // no preimage in the cage; the caller marks the operation's last step baked. An adaptive subdivision's fresh
    // lattices (Gain & Dodgson 2001, section 8) are baked too, but only when every vertex they moved rests
    // inside the cage's box afterwards: their lattices grow with the mesh a large drag carries out of the box,
    // and a vertex resting outside would no longer be carried by the cage (then they stay after it).
    bool bakeLayers(const std::vector<Step>& steps);
    // The same for every layer there is (redo and replay of a step recorded baked); outside: Step::bakedOutside.
    // allowOutside = false: refused (false, nothing changed) if a moved vertex would rest outside the cage's box.
    bool bakeAllLayers(std::vector<int>* outside = nullptr, bool allowOutside = true);
    // bakeAllLayers if `step` was baked; bakeLastStep: for an operation's last step (after its refinement).
    void bakeAfter(const Step& step);
    void bakeLastStep(const Operation& operation);
    // The inverse, before the baked step steps[last] is undone: the layers of steps (first, last] are put back
    // after the cage and each vertex they moved gets its rest point back (through the layers' inverse, then
    // the cage's, both by Newton), so the state is as it was before bakeLayers.
    void unbakeLayers(const std::vector<Step>& steps, size_t last);
    void saveSnapshot(Snapshot& snapshot);
    // Multiplies (or divides) frozenJacobian_ by the det J of the layers at each vertex (when tracking).
    void accumulateLayersJacobian(bool divide);
    bool injectSubdiv(Manipulation& m, int depth, Progress& progress);
    // A reason no deformation could do this drag (its sources cannot move, or a target outside a lattice whose
    // boundary is pinned), in the user's words with what to do; empty if there is none.
    std::string unreachableDragCause(const Manipulation& m) const;
    bool tryStep(Manipulation& m, int depth, Progress& progress);
    // Freezes the cage with its layers and puts a fresh cage with `settings` around the mesh (a set-up);
    // `placed` gets its placement. recorded: place it as that step recorded (redo, replay).
    void enterNewCage(const LatticeSettings& settings, Step* placed, const Step* recorded = nullptr);
    void leaveCage();
    void restoreSnapshot(Snapshot& snapshot);
    // How close two mirrored sources must come to count as one (mirrorConstraints).
    double mirrorMergeDistance(const BrushSettings& brush) const;
    // Keeps the first `userConstraints` residuals (the constraints the user gave) and judges the fit on them.
    void trimResiduals(OpReport& report, size_t userConstraints) const;
    // A control point a user edit may move: inside the lattice and not pinned (the error names it).
    Status checkMovable(int idx) const;
    // Adds sign * delta to the lattice and re-evaluates the affected cells; moved vertices are appended.
    void applyDelta(const ControlDelta& delta, double sign, std::vector<int>* moved);
    void pushOperation(Operation operation);
    // Undoes the steps last to first (their inverse manipulations), appending what moved to lastMoved_.vertices. A run of
    // fresh-frame steps (an adaptive subdivision's sub-steps, one layer each) is popped at once (popLayers).
    void undoSteps(const std::vector<Step>& steps);
    // The same, after clearing lastMoved_.vertices.
    void revertSteps(const std::vector<Step>& steps);
    // An operation's steps and its tool / frozen-tool change, forwards (redo) or backwards (undo); a group's
    // parts in order (reverse order backwards). Refinements are not touched.
    void undoOperationBody(const Operation& operation);
    void redoOperationBody(const Operation& operation);
    // How many vertices the last command moved (all of them when a frame was entered or left).
    int movedCount() const;
    // What undo and redo report: report.verticesMoved, the vertices whose rows differ from `before`, bitwise,
    // among the rows both have; report.verticesAdded and verticesRemoved, the rows a refinement added or took
    // away. The changed and added rows are kept as lastMoved_.vertices, unless lastMoved_.all says a frame was
    // entered or left (a view then refreshes everything, whatever the count).
    void countChangedVertices(const Positions& before, OpReport& report);
    void redoStep(const Step& step);

    SessionMesh mesh_;  // mesh()
    InjectivitySettings injectivity_;
    Snapshot scratch_;
    IncrementScratch increment_;
    MeshAsSet asSet_;  // meshAsSet()
    SymmetryFrame symmetryRest_;  // the mirror planes in the cage's rest space (symmetryFrame); frames keep theirs
    History history_;  // the operations and the journal (history.h)
    MovedVertices lastMoved_;  // lastMoved()
    bool trackJacobian_ = false;
    std::vector<double> frozenJacobian_;  // #V, product of the frozen frames' det J (when tracking)
    SelfIntersectionIndex meshIndex_;     // broad phase of the triangle check, refitted where vertices move
    Positions before_;                    // #V: the rows of the vertices a step moves, as they were before it
    // beginDeferredTriangles: the vertices the deferred layers moved, and which of them have their row in before_.
    bool deferTriangles_ = false;
    std::vector<int> deferredChanged_;
    std::vector<std::uint8_t> deferredSaved_;
    // Parts touching at load and where (self_intersection.h), carried across refinements.
    SelfIntersectionIndex::LoadContacts loadContacts_;
    void accumulateFrameJacobian(bool divide);

    DragState drag_;            // the drag in progress (stroke.h)
    ToolLibrary::State tools_;  // the lattice tools (tool_library.h)
    friend class Stroke;
    friend class ToolLibrary;
    friend class TSplineTools;
    // While applyBrushPulls runs: the vertices its regions can reach (ascending), the only ones a region layer
    // entered then embeds and the only ones popping its layers can move (a stroke's region holds thousands of a
    // million vertices).
    const std::vector<int>* layerCandidates_ = nullptr;
    // While applyBrushPulls runs, its layers popped down to none: the cage's output is kept (it equals the
    // positions then, and nothing but the stroke moves them before its next layer), so entering that layer
    // copies no million rows (brush_move_1m: a 24 MB copy into fresh pages, and their release, each update).
    bool cageOutKept_ = false;

public:
    // Refinement where the surface stretches (Coquillart 1990, 3.4; refiner.h): refine, the automatic setting,
    // the splits applied, the topology's version.
    Refiner refinement() { return Refiner(*this); }
    const Refiner refinement() const { return Refiner(const_cast<Session&>(*this)); }

private:
    Refiner::State refinement_;  // refiner.h
    LatticeStack stack_;         // the cage, its layers and frames (lattice_stack.h)
    friend class Refiner;
    friend class CagePins;
};

// Inverts an injective lattice deformation per point: finds X with X + sum R(t(X)) delta = y for each row y of
// `deformed` (Newton from X = y; a point whose displacement is exactly zero is its own preimage, which keeps
// untouched vertices bitwise identical). Points outside the box are unchanged, or with `collar` (a cage that
// carries one, LatticeStack::carriesCollar) the collar's preimage (collarPreimage, embedding.h). Parallel.
// rest: resized to match; reusing the same buffer avoids faulting in fresh pages on every undo.
void invertDeformation(const Lattice& lattice, const Positions& deformed, Positions& rest, bool collar = false);

}  // namespace sculpt::core
