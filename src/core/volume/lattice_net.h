// Lattices of any shape: extended free-form deformation (Coquillart 1990, "EFFD", seed 004).
//
// A lattice is a trivariate tensor-product NURBS volume Q(t) = sum R_s(t) P_s over t in [0,1]^3 (Hu et al.
// 2001, eq. 1-2). The box lattice (lattice.h) places its control points P0_s on a regular grid in an
// axis-aligned box, so a point's parameters follow from the box's linear map. A *net* lattice places them
// anywhere: a parallelepiped in any orientation, a cylinder, a sphere, a prism extruded or lofted from 2D
// lattices (3.1.1, 3.1.3), or a net the user edited (3.1.4). Such a lattice has to be *frozen* (3.3): each
// point X0 inside gets the parameters t with Q0(t) = X0 by Newton's method per chunk (one Bezier piece of the
// volume, a knot-span triple). After that it deforms exactly like the box lattice: x = X0 + sum R_s(t) delta_s
// (3.4), so the explicit solution (Hu et al. 2001, eq. 7 / 12), the evaluation kernels, history and undo
// are shared by every kind.
//
// Welded control points (3.1.2, 3.1.4) are grid slots that act as one control point: the cylinder's axis,
// a sphere's poles and centre, the seam of a periodic (closed) angle axis, points merged by the user. Every
// slot of a weld group carries the same displacement, and the group's basis function is the sum of its
// slots' (supportWeights reports it on the group's representative, the smallest slot id).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/spline/bspline_basis.h"
#include "core/mesh_types.h"
#include "core/status.h"
#include "core/volume/volume.h"

namespace sculpt::core {

// The name of parameter axis `axis` (0, 1, 2) in messages: "u", "v" or "w".
inline std::string parameterAxisName(int axis) { return std::string(1, "uvw"[axis]); }

// A spatial index of a net's chunks: the bounds of every chunk's control points (a chunk lies in their
// convex hull, weights > 0), and a uniform grid over all of them listing the chunks that overlap each grid
// cell, so a point's candidate chunks cost O(1) to find.
struct ChunkIndex {
    std::vector<Eigen::AlignedBox3d> chunkBounds;
    Eigen::AlignedBox3d bounds;
    std::array<int, 3> gridSize{1, 1, 1};
    std::vector<int> gridStart, gridChunks;  // CSR: chunks of grid cell g are gridChunks[gridStart[g] .. gridStart[g+1])
    // Candidate chunks of x, ascending ids (empty outside the bounds).
    void candidates(const Eigen::Vector3d& x, std::vector<int>& out) const;
};

// The rest shape of a net lattice: one tensor-product NURBS volume placed anywhere, the Volume kind of every
// lattice of seed 004 (volume.h). Immutable once built (shared between the copies of a Lattice, its layers and
// the history); edits make a new one. Chunk id = su + S_u (sv + S_v sw); control point id = slot.
struct LatticeNet final : Volume {
    std::string kind = "net";        // "parallelepiped", "cylinder", "sphere", "prism", "loft", "net"
    std::array<int, 3> count{};      // grid slots per axis
    std::array<int, 3> degree{};
    std::array<int, 3> multiplicity{1, 1, 1};  // interior knot multiplicity per axis of uniform knots (SplineAxis)
    // Per axis: a general clamped knot vector (count + degree + 1 knot parameters, splineKnotsProblem), as exact
    // knot insertion at any parameter makes (lattice_edit.h); empty: the uniform knots of count, degree and
    // multiplicity. finishLatticeNet empties it when it equals those uniform knots, so one volume has one form.
    std::array<std::vector<double>, 3> knots;
    std::array<SplineAxis, 3> axes;
    Positions rest;                  // #slots x 3, P0 per slot, slot id = i + count0 * (j + count1 * k)
    std::vector<double> weights;     // #slots, > 0 (NURBS weights W_s)
    bool rational = false;           // some weight differs from another
    std::vector<int> weldedTo;       // #slots: the representative (smallest slot) of the slot's weld group
    bool hasWelds = false;
    std::vector<std::vector<int>> weldGroups;  // groups of two or more slots, each sorted (representative first)
    std::array<bool, 3> periodic{};  // the axis is closed: its last slice is welded onto its first (the seam)
    // Per axis and side (0 low, 1 high): the face is part of the volume's outer surface, i.e. neither a seam
    // nor collapsed (a cylinder's axis, a sphere's pole). Pinning and the boundary rule use only these.
    std::array<std::array<bool, 2>, 3> boundaryFace{};
    std::array<std::array<int, 2>, 3> collapsedAlong{};  // per face: bit b set = every line along axis b is one point
    std::vector<std::uint8_t> boundarySlot;  // #slots: the slot lies on a boundary face
    ChunkIndex restIndex;            // derived (finishLatticeNet): the rest net's chunk index
    Eigen::AlignedBox3d bounds;      // of the rest control points

    // Derived: per axis, the B-spline -> Bezier matrices of every knot span (span s: (p+1) x (p+1) row-major at
    // s (p+1)^2, row l = Bernstein coefficient l of the span's basis functions).
    std::array<std::vector<double>, 3> toBezier;

    int slotCount() const { return count[0] * count[1] * count[2]; }
    int slot(int i, int j, int k) const { return i + count[0] * (j + count[1] * k); }
    // slot's inverse: the grid indices (i, j, k) of slot id s.
    std::array<int, 3> slotIjk(int s) const { return {s % count[0], (s / count[0]) % count[1], s / (count[0] * count[1])}; }
    std::array<int, 3> spans() const { return {axes[0].spans, axes[1].spans, axes[2].spans}; }
    double diagonal() const { return bounds.diagonal().norm(); }
    std::array<int, 3> chunkIjk(int chunk) const {
        return {chunk % axes[0].spans, (chunk / axes[0].spans) % axes[1].spans, chunk / (axes[0].spans * axes[1].spans)};
    }

    // ---- Volume (volume.h) ----
    const std::string& kindName() const override { return kind; }
    int controlPointCount() const override { return slotCount(); }
    const Positions& restControlPoints() const override { return rest; }
    const std::vector<double>& controlWeights() const override { return weights; }
    bool isRational() const override { return rational; }
    int representativeOf(int id) const override { return hasWelds ? weldedTo[static_cast<size_t>(id)] : id; }
    const std::vector<std::vector<int>>& weldGroupList() const override { return weldGroups; }
    Eigen::AlignedBox3d restBounds() const override { return bounds; }
    bool onOuterSurface(int id) const override { return boundarySlot[static_cast<size_t>(id)] != 0; }
    // Layers counted from the boundary faces only (not from a seam or a collapsed face).
    bool inSurfaceLayers(int id, int layers) const override;
    std::vector<std::array<int, 2>> controlNetEdgeList() const override;
    void basisAt(const Eigen::Vector3d& t, SupportWeights& out) const override;
    void evaluate(const Positions& points, const Eigen::Vector3d& t, Eigen::Vector3d& value,
                  Eigen::Matrix3d* derivative = nullptr) const override;
    bool freeze(const Eigen::Vector3d& x, Eigen::Vector3d& t) const override;
    std::unique_ptr<Locator> locatorFor(const Positions& points) const override;
    int chunkCount() const override { return axes[0].spans * axes[1].spans * axes[2].spans; }
    int chunkOf(const Eigen::Vector3d& t, Eigen::Vector3d& local) const override;
    Eigen::Vector3d chunkParameters(int chunk, const Eigen::Vector3d& local) const override;
    void chunkSupport(int chunk, std::vector<int>& ids) const override;
    // Knot insertion to Bezier form per axis (toBezier); collapse = collapsedAlong on the net's outer faces.
    void bezierChunk(int chunk, const Positions* displacement, BezierChunk& out) const override;
    // The same with the displacement as row-major #slots x 3 doubles (or null): a block of a composite.
    void bezierChunkWith(int chunk, const double* displacement, BezierChunk& out) const;
    void chunksAlong(int chunk, int axis, std::vector<int>& row, bool& closed) const override;
    std::vector<std::array<Eigen::Vector3d, 2>> chunkEdgeLines() const override;
    const LatticeNet* tensorNet() const override { return this; }
    // placeLatticeNet, below.
    Status placed(const Eigen::Vector3d& point, const Eigen::Vector3d& normal, double size, std::shared_ptr<const Volume>& out) const override;
};

// Validates the raw fields (counts, degrees, multiplicities or knot vectors, rest #slots x 3 finite, weights > 0
// finite, weldedTo in range) and fills the derived ones: axes, rational, weld groups, boundary faces and slots,
// chunk bounds and the grid index. Welded slots must coincide at rest (to 1e-9 of the diagonal).
// Fails with a message naming the field; `net` is then unspecified.
Status finishLatticeNet(LatticeNet& net);

// A copy of the raw fields of `net` (kind, counts, degrees, multiplicities, knots, rest points, weights, welds: what
// finishLatticeNet reads), without its derived data: the start of an edit.
LatticeNet rawNetFields(const LatticeNet& net);

// Welds every group of slots whose rest points coincide to `tolerance` * diagonal (the predefined lattices'
// axis, poles, centre and seam). Call before finishLatticeNet.
void weldCoincidentSlots(LatticeNet& net, double tolerance = 1e-12);

// ---- predefined lattices (3.1.1, 3.1.3, Fig. 2) ---------------------------------------------------------
// Every constructor takes the number of chunks (knot spans) per axis and fails with a clear message on
// non-finite or degenerate input; none needs a mesh.

// A parallelepiped: P0(t) = origin + edges * t (edges' columns are the three edge vectors, right-handed,
// det > 0). Control points at the Greville points of a uniform clamped B-spline of `degree` per axis, so the
// rest volume is the affine map itself. PyGeM's oriented FFD box is origin + R diag(lengths).
Status makeParallelepipedNet(const Eigen::Vector3d& origin, const Eigen::Matrix3d& edges, const std::array<int, 3>& chunks,
                             const std::array<int, 3>& degree, LatticeNet& out);

// A cylinder around `axis` (any non-zero direction) from `base` to base + height * axis/|axis|, of
// `radius`: parameters (r, theta, z). theta is periodic (the seam is welded) and built from rational
// quadratic arcs, so rest circles are exact (weights cos(alpha/2) at the arc middles); the axis (r = 0) is
// one welded point per z slice. chunks = {radial, angular >= 3, axial}; degree = {radial, axial} in [1, 5].
Status makeCylinderNet(const Eigen::Vector3d& base, const Eigen::Vector3d& axis, double radius, double height,
                       const std::array<int, 3>& chunks, const std::array<int, 2>& degree, LatticeNet& out);

// A ball of `radius` around `centre`: parameters (r, theta in [0, 2 pi) periodic, phi from the south pole to
// the north pole along `axis`), a surface of revolution of rational arcs (weights w_theta * w_phi). The
// centre is one welded point, each pole one welded point per radial slice. chunks = {radial, angular >= 3,
// polar >= 2}; radialDegree in [1, 5].
Status makeSphereNet(const Eigen::Vector3d& centre, const Eigen::Vector3d& axis, double radius,
                     const std::array<int, 3>& chunks, int radialDegree, LatticeNet& out);

// A 2D lattice in a plane: a tensor-product NURBS surface net of count[0] x count[1] points (2D
// coordinates, row u fastest), weights and knot multiplicities per axis (1 or the degree).
struct PlanarNet {
    std::array<int, 2> count{};
    std::array<int, 2> degree{};
    std::array<int, 2> multiplicity{1, 1};
    std::vector<Eigen::Vector2d> points;
    std::vector<double> weights;
};
// A regular 2D grid over [lo, hi] with `chunks` spans of `degree` per axis.
PlanarNet makeRectangleNet(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, const std::array<int, 2>& chunks,
                           const std::array<int, 2>& degree);

// Prismatic lattice by extrusion (3.1.1, Fig. 2): the 2D lattice placed at `origin` in the plane spanned by
// uAxis, vAxis (orthonormalised), swept along `direction` (not in that plane) with `chunks` spans of `degree`.
Status makeExtrusionNet(const PlanarNet& profile, const Eigen::Vector3d& origin, const Eigen::Vector3d& uAxis,
                        const Eigen::Vector3d& vAxis, const Eigen::Vector3d& direction, int chunks, int degree,
                        LatticeNet& out);

// Prismatic lattice by loft (3.1.4, the "S" of Fig. 8): sections[k] is the k-th slice of control points
// (count[0] x count[1] world points each, same counts and weights as `profile`), interpolated along w with
// `degree` (sections.size() >= degree + 1).
Status makeLoftNet(const PlanarNet& profile, const std::vector<Positions>& sections, int degree, LatticeNet& out);

// The positioning command (Coquillart 1990, 3.2): the lattice moved so that the centre of its bounds is at
// `point`, its own z axis turned onto `normal` (the shortest rotation), and scaled so its bounds' diagonal
// is `size`. Weights and welds are kept. Fails on a zero normal or a size that is not finite and > 0.
Status placeLatticeNet(const LatticeNet& tool, const Eigen::Vector3d& point, const Eigen::Vector3d& normal, double size,
                       LatticeNet& out);

// ---- evaluation and freezing (3.3) ----------------------------------------------------------------------

// Q(t) and dQ/dt (columns = d/dt_a) of the net with control points `points` (#slots x 3: the rest net, or the
// rest net plus the displacements), rational by the quotient rule. t in [0,1]^3 (clamped).
void evaluateNetVolume(const LatticeNet& net, const Positions& points, const Eigen::Vector3d& t, Eigen::Vector3d& value,
                       Eigen::Matrix3d* derivative = nullptr);
// The same with the points as row-major #slots x 3 doubles (a block of a longer array).
void evaluateNetVolume(const LatticeNet& net, const double* points, const Eigen::Vector3d& t, Eigen::Vector3d& value,
                       Eigen::Matrix3d* derivative = nullptr);

// The chunk index of the net with control points `points` (#slots x 3).
ChunkIndex buildChunkIndex(const LatticeNet& net, const Positions& points);

// Freezing: the parameters t with Q(t) = x, Q the volume of `points` (#slots x 3) indexed by `index`
// (buildChunkIndex of the same points). Candidate chunks come from the grid index (those whose control-point bounds contain x), lowest chunk id first; in each, Newton's
// method starts at the chunk centre and, where it does not converge, at the centres of the chunk's octants
// and then of its 64 sub-boxes; steps use the pseudo-inverse of dQ/dt where it is (nearly) singular (the
// cylinder's axis). The first chunk holding a solution gives the answer (deterministic for points on a
// chunk face or in overlapping chunks). Converged means |Q(t) - x| reaches rounding level (4e-15 of the
// diagonal), or stalls below 1e-13 of it. Returns false for
// points outside every chunk (they do not move) and for non-finite x.
// For the rest net: freezePoint(net, net.rest, net.restIndex, x, t).
bool freezePoint(const LatticeNet& net, const Positions& points, const ChunkIndex& index, const Eigen::Vector3d& x,
                 Eigen::Vector3d& t);

}  // namespace sculpt::core
