// Refiner: refinement where the surface stretches (Coquillart 1990, section 3.4, after Griessmair and
// Purgathofer 1989), as history operations of the session. One per Session (Session::refinement()).
// Triangles whose image strays from flat are split at their rest-space edge midpoints, each new vertex put where
// the deformation takes that rest point (LatticeStack::imageOfRestPoint, Session::cage()). A topology change is
// an operation like any other: undo removes exactly the vertices and triangles it added (the others come back
// bitwise, in their order), redo and replay split the same edges again. Only the cage and its layers are
// followed: frozen frames are part of the rest mesh. The geometry is deform/refinement.h's; files: refiner.cpp.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "core/deform/refinement.h"
#include "core/session/operation.h"
#include "core/status.h"

namespace sculpt::core {

class Session;

class Refiner {
public:
    // The setting and the topology's version, kept by the session (a session copies and moves as one value).
    struct State {
        RefinementSettings settings;
        int topologyVersion = 0;
    };
    // A handle on `session`'s refinement (Session::refinement()), made per call.
    explicit Refiner(Session& session) : s_(session) {}

    // Splits the triangles whose image strays from their flat triangle by more than tolerance times the
    // current bounding-box diagonal (refineMesh, with the limits of settings().options), as one undoable
    // operation (OperationKind::Refine). Bad tolerance (<= 0, not finite), no mesh or a drag in progress: an
    // error, nothing changes. Nothing over the tolerance: NoOp. With the triangle check on
    // (InjectivitySettings), a refinement that would make two triangles cross that did not before is Rejected
    // and changes nothing. report: verticesAdded, trianglesAdded, deviation; reason says when a limit stopped
    // it short.
    Status refine(double tolerance, OpReport& report);
    // The refinement setting. automatic: every applied drag or control-point edit (interactive ones when they
    // end) is followed by a refinement with these options, in the same history entry. Not an operation on the
    // shape; journaled so recordings keep it. Bad options: an error, nothing changes.
    Status set(const RefinementSettings& settings);
    const RefinementSettings& settings() const;
    // The splits of the applied history entries, in order: the mesh as set, split by these (applyEdgeSplits),
    // is Session::mesh().triangles. What a writer needs to carry per-corner data (texture coordinates) over.
    std::vector<EdgeSplit> appliedSplits() const;
    // Changes whenever Session::mesh().triangles does (a refinement applied or taken back): a view re-uploads the
    // mesh.
    int topologyVersion() const;

private:
    friend class Session;
    friend class Stroke;

    // Plans (refineMesh) and applies a refinement with `options`; fills record and report. False if nothing
    // was applied (nothing over the tolerance, or refused by the triangle check: report says so).
    bool refineNow(const RefinementOptions& options, RefinementRecord& record, OpReport& report);
    // An applied drag or edit about to be pushed: refined when the setting is automatic (report may be null).
    void afterEdit(Operation& operation, OpReport* report);
    // apply, then the triangle check of the new vertices against where they lay on the flat triangles they split:
    // true, or (a new crossing) everything taken back, `record` emptied and report saying why.
    bool applyChecked(RefinementRecord& record, OpReport& report);
    // A brush stroke's refinement under its pull (Stroke::applyBrushPulls): splits the mesh's triangles listed in
    // `triangles` (ids) where their image under `target` (rest point -> world, the shape at the stroke's whole
    // pull) strays from flat by more than `tolerance` (world units), as refineMesh does (longest-edge bisection,
    // at most 6 rounds, no rest edge shorter than `shortestEdge` split (world units, > 0), and at most 4 times the
    // listed triangles' vertices plus 5000 more, within settings().options.maxVertices); then, where two of the
    // split triangles still cross at the target while they did not before (the field squeezes the space ahead of a
    // long pull to a quarter: brush_field.h), those two are bisected again, down to a quarter of `shortestEdge`,
    // up to 8 rounds while the crossings become fewer. Applied now (each new vertex where the
    // deformation as it is now takes its rest point) with the triangle check, and appended to `record` (splits
    // and halvings). False when nothing was split or the check refused it (nothing changed then);
    // report.verticesAdded and trianglesAdded grow by what was added.
    bool refineUnderPull(const std::vector<int>& triangles, const RestImage& target, double tolerance, double shortestEdge,
                         RefinementRecord& record, OpReport& report);
    // Splits record.splits (filling record.halvings) and brings every per-vertex array of the session along.
    void apply(RefinementRecord& record);
    // The inverse of apply (no-op for an empty record).
    void remove(const RefinementRecord& record);
    // What apply and remove end with once the per-vertex arrays have `count` rows: the scratch rows, the cage's
    // embedding, the triangle check's index and its load contacts, the versions a view watches.
    void finishTopologyChange(Eigen::Index count);
    // Re-applies an operation's recorded refinement after its steps (redo, replay; no-op when empty).
    void reapply(Operation& operation) {
        if (!operation.refinement.empty()) apply(operation.refinement);
    }
    // A group redoes its steps, then its refinements: none may come before a lattice set-up in it (whose rest
    // positions would then lack the refined vertices' images), and only its first operation may be a stroke
    // refined under its pull (Operation::refinementBefore, split before the group's steps).
    Status checkGroup(int first) const;
    // A recorded refinement fits the mesh as it is now (replay): the one under a stroke, then the one after it;
    // a cancelled drag has none after it.
    Status checkRecorded(const Operation& operation, bool cancelled) const;

    Session& s_;
};

}  // namespace sculpt::core
