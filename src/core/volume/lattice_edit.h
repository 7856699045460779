// Editing a lattice that is not frozen (Coquillart 1990, EFFD, 3.1.4: "Valid editing methods include moving
// (...) points (...) either alone or as a group, merging, inserting (by subdividing the lattice) and removing
// points").
//
// Every edit is a pure function: it reads a finished LatticeNet (lattice_net.h) and writes a new finished one
// to `out`. The input is never changed; on failure the Status names what is wrong (the slot, axis or slice,
// and why) and `out` is left untouched. Slot ids are the net's grid ids, i + count0 * (j + count1 * k).
//
// Welds (3.1.2, 3.1.4) are kept as the net's weld groups: a group is one control point whose basis function
// is the sum of its slots' (lattice_net.h). Moving any slot of a group moves the group; merging makes a group.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "core/volume/lattice_net.h"
#include "core/status.h"

namespace sculpt::core {

// Moves control points by `offset` (world units). `slots`: ids in [0, #slots), duplicates allowed; a slot of a
// weld group moves its whole group (welded points stay one point), once however many of its slots are listed.
// Weights and welds are kept. Fails on an empty list, an id out of range, a non-finite offset, or a rest
// net that is no longer valid (a chunk folded or flat: finishLatticeNet's message).
Status moveNetPoints(const LatticeNet& net, const std::vector<int>& slots, const Eigen::Vector3d& offset, LatticeNet& out);

// Merges (welds) the control points of `slots` into one (3.1.4, Fig. 3-4): every slot of every group the list
// touches joins one weld group, placed at the plain mean of the distinct points merged (a group counts once),
// whose basis function is the sum of the merged ones. Weights are kept (the rational basis R_s = W_s B_s / W
// does not depend on positions, so the merged point's basis is exactly the sum). Fails on an id out of
// range, fewer than 2 distinct points (after groups are taken into account), or a rest net that is no
// longer valid (merging points across a chunk flattens it).
Status mergeNetPoints(const LatticeNet& net, const std::vector<int>& slots, LatticeNet& out);

// Inserts points by subdividing the lattice along `axis` (0 u, 1 v, 2 w): every knot span is split at its
// middle, i.e. each span midpoint is inserted as a knot `multiplicity` times by Boehm's algorithm (The NURBS
// Book, A5.1, applied to the homogeneous points (W P, W) so rational nets stay exact). The volume does not
// change: Q'(t) = Q(t) for every t, to rounding. Spans along the axis double; the count becomes
// splineAxisCount(2 spans, degree, multiplicity).
// An axis of general (non-uniform) knots gets each span's midpoint (in the knot parameter) once.
// Welds are carried structurally: each new point is a combination of old weld groups (the Boehm coefficients
// times the weights), and two new points are welded iff their combinations are the same, so the cylinder's
// axis, the poles, the centre and a periodic seam stay welded while points that merely happen to coincide
// (never welded before) stay apart. Welded points are made exactly equal. Fails when the axis would pass 64
// control points.
Status refineNetAxis(const LatticeNet& net, int axis, LatticeNet& out);

// Inserts points by splitting the lattice at one parameter (3.1.4: "inserting (by subdividing the lattice)"):
// the knot at lattice parameter `at` along `axis` (in (0,1); the chunk floor(at * spans) is split at its local
// coordinate, see bspline_basis.h for the lattice and knot parameters) is inserted `times` times by Boehm's
// algorithm on the homogeneous points, so the volume does not change: Q'(t') = Q(t) for the same knot
// parameter, to rounding. `at` on an existing knot raises its multiplicity. The axis gains `times` control
// points and, unless `at` was a knot, one knot span; its knots become general (LatticeNet::knots) unless they
// are uniform again. Welds are carried structurally, as by refineNetAxis. Fails, saying why, on an axis out
// of range, `at` outside (0, 1) or not finite, `times` outside [1, degree], a knot whose multiplicity would
// pass the degree, or more than 64 control points on the axis.
Status insertNetKnot(const LatticeNet& net, int axis, double at, int times, LatticeNet& out);

// Removes the slice `index` (0 <= index < count[axis]) of the grid along `axis` (a tensor-product lattice can
// only lose a whole slice). Weld groups keep their remaining slots (the representative is their smallest new
// id). Fails, saying why, when: the index or axis is out of range; the axis would have fewer than degree+1
// points; the count no longer makes whole knot spans of the axis' multiplicity (splineAxisCountValid: an axis
// with interior knots of multiplicity m > 1 can only change by m points per span; an axis of general knots
// instead loses the interior knot nearest the slice's Greville abscissa); the slice is the seam of a
// periodic axis (removing it would open the closed lattice); the slice is a collapsed face (the cylinder's
// axis, a ball's centre or pole: removing it would open a hole through the lattice); or the remaining rest
// net is not valid.
Status removeNetSlice(const LatticeNet& net, int axis, int index, LatticeNet& out);

// One edit of a list (the script op edit_lattice's "edits").
struct NetEdit {
    enum class Kind { Move, Merge, Refine, Insert, Remove };
    Kind kind = Kind::Move;
    std::vector<int> slots;                             // Move, Merge
    Eigen::Vector3d offset = Eigen::Vector3d::Zero();   // Move
    int axis = 0;                                       // Refine, Insert, Remove
    double at = 0.5;                                    // Insert: the lattice parameter along the axis
    int times = 1;                                      // Insert: how often the knot is inserted
    int index = 0;                                      // Remove: the slice
};

// Applies `edits` in order, each to the result of the one before. On failure the message starts with
// "edits[N]: " (N the failing edit) and `out` is untouched.
Status applyNetEdits(const LatticeNet& net, const std::vector<NetEdit>& edits, LatticeNet& out);

}  // namespace sculpt::core
