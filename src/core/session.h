// Session: the engine's document. One mesh, one lattice around it, and the history of manipulations.
// Every user action (window or script) is one of the commands below; the GUI keeps no engine state.
//
// Positions follow design.md's data flow: rest positions X0 at lattice set-up, x = X0 + sum R delta,
// re-evaluated only for the cells whose support contains a changed control point.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/direct_manipulation.h"
#include "core/embedding.h"
#include "core/lattice.h"
#include "core/mesh_types.h"
#include "core/status.h"

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
};

enum class OperationKind { Drag, ControlPointEdit };

// One history entry: the manipulation, enough to apply it again or its inverse, never a copy of the mesh.
// Within one lattice the manipulations form a commutative group (Hu et al. 2001, section 4): eq. 7 and 12
// are linear in the displacements D, so the inverse manipulation omega(S, -D) is exactly -delta.
struct Operation {
    OperationKind kind = OperationKind::Drag;
    std::string label;                         // e.g. "drag (2 points)", for history lists
    std::vector<Eigen::Vector3d> sourceParams; // drags: the constrained points' lattice parameters
    Eigen::MatrixX3d displacements;            // drags: total displacement of each source (h x 3)
    ControlDelta delta;                        // the lattice change the manipulation made
};

class Session {
public:
    // Replaces the mesh (rest = current positions) and embeds it in a new lattice with `settings`; clears
    // the history. On failure nothing changes.
    Status setMesh(const Positions& positions, const Triangles& triangles, const LatticeSettings& settings = {});

    // Puts a fresh lattice around the current (deformed) mesh: it becomes the new rest state. Clears history.
    Status setupLattice(const LatticeSettings& settings);

    // Moves each constraint's source (a point in the current deformed space inside the lattice) onto its
    // target with the least lattice change (Hu et al. 2001 eq. 7 / 12). Bad input (empty list, non-finite
    // coordinates, a source outside the lattice) returns an error and changes nothing.
    Status drag(const std::vector<PointConstraint>& constraints, OpReport& report);
    // Drags a mesh vertex to target (its lattice parameters are exact: no search).
    Status dragVertex(int vertex, const Eigen::Vector3d& target, OpReport& report);
    // Moves control points (ids as Lattice::index) to absolute positions, or by offsets when relative.
    // values: #indices x 3. Pinned points, ids out of range or non-finite values are errors.
    Status moveControlPoints(const std::vector<int>& indices, const Eigen::MatrixX3d& values, bool relative,
                             OpReport& report);
    // Undo / redo the last operation; with nothing to undo or redo, report.status = NoOp (not an error).
    Status undo(OpReport& report);
    Status redo(OpReport& report);

    // Interactive drag: the sources are fixed at begin, every update moves them to new targets by an
    // incremental manipulation, and end() records the whole drag as one history entry.
    Status beginDrag(const std::vector<Eigen::Vector3d>& sourceParams);
    Status updateDrag(const std::vector<Eigen::Vector3d>& targets, OpReport& report);
    void endDrag();
    bool dragging() const { return dragActive_; }

    // Pins or unpins control points (ids as Lattice::index). Not an operation on the shape.
    Status setPinned(const std::vector<int>& indices, bool pinned);

    // Lattice parameters of a point of the current (deformed) shape, e.g. a picked surface point.
    Status parametersOfCurrentPoint(const Eigen::Vector3d& point, Eigen::Vector3d& params) const;
    // Lattice parameters of a vertex (from its rest position: exact). Fails if the vertex is outside the box.
    Status parametersOfVertex(int vertex, Eigen::Vector3d& params) const;
    // Where the point with parameters t currently is: X0(t) + sum R(t) delta.
    Eigen::Vector3d currentImage(const Eigen::Vector3d& params) const;

    bool hasMesh() const { return rest_.rows() > 0; }
    const Positions& positions() const { return positions_; }
    const Positions& restPositions() const { return rest_; }
    const Triangles& triangles() const { return triangles_; }
    const Lattice& lattice() const { return lattice_; }
    const LatticeSettings& latticeSettings() const { return settings_; }
    const Embedding& embedding() const { return embedding_; }
    const std::vector<Operation>& history() const { return history_; }
    int historyCursor() const { return cursor_; }  // entries [0, cursor) are applied
    // Vertices whose position the last command changed (for sparse normal and buffer updates).
    const std::vector<int>& lastMovedVertices() const { return lastMoved_; }

private:
    // Adds sign * delta to the lattice and re-evaluates the affected cells.
    void applyDelta(const ControlDelta& delta, double sign);
    void pushOperation(Operation operation);
    Status validateSource(const Eigen::Vector3d& params, int constraint) const;

    Positions rest_, positions_;
    Triangles triangles_;
    LatticeSettings settings_;
    Lattice lattice_;
    Embedding embedding_;
    std::vector<Operation> history_;
    int cursor_ = 0;
    std::vector<int> lastMoved_;

    bool dragActive_ = false;
    DirectManipulationData dragData_;
    Operation dragOperation_;
};

}  // namespace sculpt::core
