// Stroke: the drag in progress, on the surface (with a brush, symmetry and pins) or of control points. One per
// Session (Session::stroke()); the window's mouse drag and a script's `drag` / `drag_vertex` both run it, a
// scripted drag being a stroke of one update (Session::drag).
//
// The sources are fixed at begin; every update moves them towards new targets by an incremental manipulation
// (Hu et al. 2001, section 4: the increments of one drag add up to one control displacement per lattice, the
// group property omega(S, a) o omega(S, b) = omega(S, a + b)), tested and subdivided like any operation (Gain &
// Dodgson 2001, Appendix, InjectSubdiv); with a brush radius an update is a brush stroke, the pull field of
// brush_field.h in region layers (stroke_brush.cpp). end() makes the whole drag one history entry; cancel()
// takes it back as its inverse manipulation.
//
// Files: stroke.cpp (begin, update, end, cancel, control-point drags), stroke_brush.cpp (a brush stroke's
// update). A Stroke is a handle made per call: its state is the session's DragState (drag_state.h), so a
// session copies and moves as one value; it changes the document through its Session (a friend: the layers, the
// certification and the history are the session's).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/deform/brush.h"
#include "core/deform/brush_field.h"
#include "core/session/drag_state.h"
#include "core/session/operation.h"
#include "core/status.h"

namespace sculpt::core {

class Session;

class Stroke {
public:
    // A handle on `session`'s drag (Session::stroke()); its state is the session's DragState.
    explicit Stroke(Session& session) : s_(session) {}

    // A drag of points given by their cage parameters (each in [0, 1]^3): the sources are fixed at begin, every
    // update moves them towards new targets by an incremental manipulation. Errors (no mesh, a drag already in
    // progress, no source, a parameter outside [0, 1]^3) change nothing.
    Status begin(const std::vector<Eigen::Vector3d>& sourceParams);
    // The same from world points of the current shape, with a brush (strength, symmetry, region; see
    // Session::drag). held: per source, true for one that stays put (a pin): not mirrored, and with a radius left
    // out when it lies outside the brush's region (nothing moves there). update then takes one target per source.
    // Errors: a bad brush (validateBrush; a radius within 1000 x the mesh's diagonal), a non-finite source, a
    // source outside the cage (without a radius), every source held (with a radius).
    Status beginAt(const std::vector<Eigen::Vector3d>& sources, const std::vector<bool>& held, const BrushSettings& brush);
    // Moves the sources towards `targets` (world, one per source given to begin / beginAt). Applied, subdivided,
    // stopped short (a brush stroke: the largest injective share of its pull) or refused (report says which and
    // why; a refused update changes nothing). Errors: no drag in progress, a target count that changed, a
    // non-finite target.
    Status update(const std::vector<Eigen::Vector3d>& targets, OpReport& report);
    // A control-point drag: the points (ids as Lattice::index, not pinned) move together, each update by the
    // offset since beginControl; tested and subdivided like any control-point edit, one history entry.
    Status beginControl(const std::vector<int>& indices);
    Status updateControl(const Eigen::Vector3d& offset, OpReport& report);
    // The same drag with an offset per point (a rotation or scale about a pivot moves each point differently):
    // offsets #points x 3, row r for the r-th smallest id given to beginControl, each since beginControl. The
    // whole change is one move, stopped at the last injective position along it (each point the same fraction
    // of its way).
    Status updateControlPerPoint(const Eigen::MatrixX3d& offsets, OpReport& report);
    // Ends either kind of drag; a drag that changed something becomes one history entry (refined when the
    // refinement is automatic, its brush layers baked into the rest shape).
    void end();
    // Ends the drag by undoing what it applied (its inverse manipulation, step by step), leaving the shape and
    // the history as they were before begin. No drag in progress: NoOp.
    Status cancel(OpReport& report);
    // Names the history entry the drag in progress will become (e.g. "rotate 12 control points about Z by 40
    // deg"). Non-empty; fails when no drag is in progress. The recording and the shape are not affected.
    Status setLabel(const std::string& label);

    bool active() const;
    // Current world positions of the sources (with symmetry, the mirror images too).
    std::vector<Eigen::Vector3d> sources() const;
    // Current world positions of the sources as given to beginAt (without mirror images; a held source left out
    // of a brush drag stays where it was), or sources() after begin.
    std::vector<Eigen::Vector3d> userSources() const;
    // After the last brush stroke was baked into the rest shape (end, a scripted drag with a radius): how many of
    // the vertices it moved now rest outside the box of a cage without a collar (one set up in a region the user
    // gave: LatticeStack::carriesCollar). It does not hold them, so later edits of it leave them where they are
    // (a lattice set-up with more padding takes them in). 0 otherwise: a cage around the whole mesh carries them.
    int verticesOutsideCage() const;

private:
    friend class Session;

    // end()'s work, with what the automatic refinement did going to report when not null.
    void finish(OpReport* report);
    // The state begin's two ways (a stroke, a solved drag) share: the operation, its label, the mirror.
    void startMirrored(const std::string& label, const std::vector<Eigen::Vector3d>& sources, std::vector<MirroredConstraint> mirror,
                       const BrushSettings& brush);
    // Adds an increment applied in the current frame to the operation's last step (or a new one).
    void mergeStep(const ControlDelta& delta);
    // One increment: `delta` in the current frame when that is injective, otherwise m subdivided; merged into
    // the operation. Returns false (report says why, nothing changed) if rejected.
    bool applyIncrement(const ControlDelta& delta, Manipulation& m, OpReport& report);
    // A brush stroke's update: the stroke's pulls towards `targets` (one per DragState::mirror entry), with the report.
    void updatePulls(const std::vector<Eigen::Vector3d>& targets, OpReport& report);
    // One update of a brush stroke (stroke_brush.cpp): `steps` (the stroke's steps: a layer per moving grabbed
    // image, each its own pull; or none) is replaced by the pull field for `pulls` (brush_field.h; each from where
    // the stroke began), or by the largest share of it, to 1/64, that passes every check; with no share passing,
    // the stroke stays as it was. Returns the share applied (0: none of this pull); failure: what stopped it
    // when below 1. Sets the session's last moved vertices. wholeOnly: the whole pull or nothing (1 or 0), with no
    // splits under it and no search for its last injective point.
    double applyBrushPulls(const std::vector<BrushPull>& pulls, const BrushSettings& brush, std::vector<Step>& steps, OpReport& report,
                           StepFailure& failure, bool wholeOnly = false);
    // A control-point drag's increment (per point, in the cage), with the offsets as shown.
    void applyControlDelta(ControlDelta delta, const Eigen::MatrixX3d& shownOffsets, OpReport& report);

    Session& s_;
};

}  // namespace sculpt::core
