// The state of the drag in progress (stroke.h): what Stroke's beginAt / beginControl set, each update reads and
// changes, and end or cancel ends. One per session; a scripted drag is one update of it (Session::drag).
#pragma once

#include <cmath>
#include <vector>

#include <Eigen/Core>

#include "core/deform/brush.h"
#include "core/deform/direct_manipulation.h"
#include "core/mesh_types.h"
#include "core/session/operation.h"

namespace sculpt::core {

// A drag being subdivided (Gain & Dodgson 2001, Appendix, InjectSubdiv): world-space sources and targets.
struct Manipulation {
    std::vector<Eigen::Vector3d> sources, targets;
};

struct DragState {
    bool active = false;
    Operation operation;                       // the history entry it becomes: its steps so far
    DirectManipulationData data;               // the sources' factorisation in the active lattice (Hu et al. eq. 7)
    std::vector<Eigen::Vector3d> sourceWorld;  // where the drag's sources currently are
    std::vector<Eigen::Vector3d> params;       // their parameters in the active lattice
    bool appliedInFrame = false;               // a step of this drag is in the current frame (increments merge)
    // With a brush or symmetry (Stroke::beginAt): the user's sources at the start, what each solved constraint
    // follows, and the brush.
    bool mirrored = false;
    std::vector<Eigen::Vector3d> userStarts;
    std::vector<MirroredConstraint> mirror;
    std::vector<bool> pulled;  // a stroke's, per constraint of `mirror`: pulled (not held)
    BrushSettings brush;
    SymmetryFrame symmetry;  // the mirror planes where the drag began (Session::symmetryFrame)
    std::vector<Eigen::Vector3d> strokeReached;  // applyBrushPulls: where each grabbed image is now
    // The shortest pull (the first moving image's, world units) for which splitting under it did not let the whole
    // pull through: a longer one is not split again in this stroke (each try costs a refinement and its removal,
    // and the mouse keeps moving past such a limit). Infinity: none yet.
    double splitFailedAt = INFINITY;
    // How far past its mirror plane a symmetric pull's target lay (world units) when the whole pull, tried as it
    // is, did not pass (Stroke::updatePulls): one that goes as far or farther is carried only up to the plane
    // without that try. Infinity: none yet.
    double acrossFailedAt = INFINITY;
    // The way the layers in place carried the pull (applyBrushPulls' Mode, as a number; -1: none yet): a later
    // update's search for the last injective point starts in it, where the stroke stopped.
    int strokeMode = -1;
    Eigen::Index rowsAtBegin = 0;  // the mesh's vertices when the stroke began (a move's count of the moved is among them)
    // A stroke's grabbed images (per `mirror` entry) on the mesh where the stroke began: the triangle each lies
    // on and its barycentric weights there (-1: not on the surface, as a mirror image of an asymmetric mesh), so
    // an update can tell how far the flat triangles put it from its target (applyBrushPulls). Empty until the
    // first update.
    std::vector<int> grabbedTriangle;
    std::vector<Eigen::Vector3d> grabbedWeights;
    // The cage's points as shown when a control-point drag began (with layers: the drag moves those).
    Positions controlStart;
    // After the last brush stroke was baked: how many of the vertices it moved rest outside the cage's box
    // (Stroke::verticesOutsideCage).
    int outsideCage = 0;
};

}  // namespace sculpt::core
