// Weighted T-spline volumes (Song & Yang 2005, "Free-form deformation with weighted T-spline", seed 002): a
// Volume kind (volume.h) whose control points hang on a T-lattice (tspline_lattice.h), so the lattice can be
// fine near the model and coarse elsewhere (Fig. 9-11).
//
//   Q(t) = sum_s W_s P_s B_s(t) / sum_r W_r B_r(t)                      (eq. 5, 8)
//   B_s(u, v, w) = N[u_s](u) N[v_s](v) N[w_s](w)                         (eq. 6)
// N[k] the cubic B-spline on the 5 local knots k = [k0 .. k4] (eq. 7), inferred from the T-lattice by the knot
// rule of 3.2.2: the anchor (a vertex) is k2; k3, k4 are the first two knot planes (cell faces) a ray from the
// anchor crosses in +t_a, k1, k0 those in -t_a; where the ray leaves the domain the boundary repeats.
//
// Boundary (a choice of ours, stated): a vertex on the domain boundary t_a = 0 gets the local knots
// [0 0 0 k3 k4], whose B-spline vanishes on t_a = 0 (a triple knot is C0). With the vertices alone sum W B would
// be 0 on the whole boundary, Q undefined there, and a lattice without T-junctions would not be the clamped
// tensor NURBS volume the paper says it reduces to (3.2.2). So each vertex on a boundary face also anchors a
// *boundary copy* per boundary axis, with local knots [0 0 0 0 k3] along that axis (the knot of multiplicity 4
// of a clamped B-spline; at t_a = 1: [k1 1 1 1 1]): the zero-width layer of cells that clamped T-splines add
// at an open boundary. A vertex on an edge of the domain has 4 anchors, a corner 8. With them a T-lattice of
// n_u x n_v x n_w equal cells is exactly the clamped uniform cubic NURBS net of n + 3 points per axis (the
// engine's makeSplineAxis), and the boundary faces of Q are the T-spline surfaces of the copies.
//
// Bezier elements (the chunks): each cell split at every local knot of the blending functions over it, so each
// B_s is one polynomial on each element (Bezier extraction); Bernstein coefficients by blossoming.
// Parameters t are in [0,1]^3 (the T-lattice's domain).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/volume/lattice_net.h"
#include "core/mesh_types.h"
#include "core/status.h"
#include "core/tspline/tspline_lattice.h"
#include "core/volume/volume.h"

namespace sculpt::core {

// A blending function's anchor: a T-lattice vertex, or one of its boundary copies.
struct TSplineAnchor {
    int vertex = 0;                 // into TLattice::vertices
    std::uint8_t boundaryCopy = 0;  // bit a: the copy across the boundary face t_a = 0 or 1 (the vertex is on it)
    std::array<std::array<int, 5>, 3> knots{};  // local knot vectors per axis, fine coordinates (eq. 7)
};

// The parameter-space half of a T-spline volume, independent of control point positions and weights: the
// anchors (control point id = anchor index), their local knot vectors, the Bezier elements and the anchors
// whose blending function is non-zero on each (shared between volumes on the same T-lattice).
struct TSplineBasis {
    TLattice lattice;                       // finished
    std::vector<TSplineAnchor> anchors;     // ordered by vertex (TLattice::vertices order), then boundaryCopy
    std::vector<std::array<int, 8>> anchorOfVertex;  // per vertex and boundaryCopy mask: the anchor, or -1
    std::vector<std::array<std::array<double, 5>, 3>> knotValues;  // per anchor and axis, the local knots as parameters
    // Per anchor, axis and knot span j (0..3): the span's cubic piece in powers of x = t_a - k_j (from its
    // blossoms; zero on an empty span), for fast evaluation.
    std::vector<std::array<std::array<std::array<double, 4>, 4>, 3>> piecePowers;
    bool partitionOfUnity = false;          // no T-junction: sum B = 1 (the tensor B-spline case)
    // Elements: per cell an n0 x n1 x n2 grid between the cell's splits (fine coordinates, both ends included).
    std::vector<int> cellElementStart;      // #cells + 1
    std::vector<std::array<int, 3>> cellSplitStart;  // per cell, per axis: offset into `splits`
    std::vector<std::array<int, 3>> cellSplitCount;  // per cell, per axis: number of splits (elements + 1)
    std::vector<int> splits;
    std::vector<int> elementCell;                    // #elements
    std::vector<std::array<int, 3>> elementLo, elementHi;  // fine coordinates
    std::vector<int> supportStart, supportIds;       // CSR: anchors non-zero on element e, ascending
    std::vector<int> anchorElementStart, anchorElements;  // the inverse CSR: elements where anchor s is non-zero, ascending
    int maxSupport = 0;
    // T-lattice edges between adjacent vertices (cell edges split at T-junctions), each once: {vertex, vertex}.
    std::vector<std::array<int, 2>> latticeEdges;
    // The control net's edges between anchors (TSplineVolume::controlNetEdgeList): the lattice edges repeated on
    // every boundary-copy layer, plus each boundary copy joined to the anchor it copies.
    std::vector<std::array<int, 2>> controlNetEdges() const;

    int elementCount() const { return static_cast<int>(elementCell.size()); }
    int anchorCount() const { return static_cast<int>(anchors.size()); }
    // The element holding t (each axis: the fine voxel, then the split interval; a point on a shared face goes to
    // the element above it, t_a = 1 to the last) and t's local coordinates in it. -1 for t outside [0,1]^3 or
    // not finite.
    int elementOf(const Eigen::Vector3d& t, Eigen::Vector3d& local) const;
    Eigen::Vector3d elementMin(int e) const;
    Eigen::Vector3d elementMax(int e) const;
    // Greville parameters of an anchor: per axis (k1 + k2 + k3) / 3 (the rest map is the identity where the
    // lattice has no T-junction and the weights are equal; Greville abscissae of the cubic B-splines).
    Eigen::Vector3d grevilleParameters(int anchor) const;
    // B_s (eq. 6) of the anchors supported on element e at t (in or on the element; the element's polynomial is
    // used, so on a face it is the one-sided value), in supportIds order; gradient (d/dt) if not null.
    void blendingValues(int e, const Eigen::Vector3d& t, double* values, Eigen::Vector3d* gradients) const;
};

// Builds the basis of `lattice` (finished by finishTLattice, or finished here). Fails on an invalid lattice
// (finishTLattice's errors), or when more than 216 blending functions overlap an element (SupportWeights'
// capacity; a 2:1-balanced octree stays below it: the message names the cell and says so).
Status buildTSplineBasis(const TLattice& lattice, std::shared_ptr<const TSplineBasis>& out);

// The cubic B-spline on local knots k (5 values, non-decreasing) restricted to its knot span j (k[j] < k[j+1]):
// its blossom at (x1, x2, x3) (de Boor's algorithm with one argument per level). The Bernstein coefficients
// of the piece over [a, b] within the span are blossom(a,a,a), (a,a,b), (a,b,b), (b,b,b); the value at u is
// blossom(u,u,u).
double cubicBlossom(const double* knots, int span, double x1, double x2, double x3);
// The piece's value at u and derivative d/du (u may lie outside the span: the polynomial is extended).
void cubicPiece(const double* knots, int span, double u, double& value, double& derivative);

class TSplineVolume final : public Volume {
public:
    // The volume with control points `points` (#anchors x 3, world, finite) and weights (#anchors, > 0 finite).
    // Fails with a message naming what is wrong, and when det dQ/dt > 0 is not proven on every element
    // (checkTSplineRestVolume: the control points fold or mirror the volume somewhere, or the proof is
    // undecided), so a volume that exists is a valid rest volume: freezing has one answer everywhere.
    static Status make(std::shared_ptr<const TSplineBasis> basis, Positions points, std::vector<double> weights,
                       std::shared_ptr<const TSplineVolume>& out);

    const TSplineBasis& basis() const { return *basis_; }
    const std::shared_ptr<const TSplineBasis>& sharedBasis() const { return basis_; }
    const TLattice& lattice() const { return basis_->lattice; }

    // ---- Volume ----
    const std::string& kindName() const override { return kind_; }
    // The similarity applied to every control point; the T-lattice (parameter space) and weights are kept.
    Status placed(const Eigen::Vector3d& point, const Eigen::Vector3d& normal, double size, std::shared_ptr<const Volume>& out) const override;
    const TSplineVolume* tsplineVolume() const override { return this; }
    int controlPointCount() const override { return static_cast<int>(rest_.rows()); }
    const Positions& restControlPoints() const override { return rest_; }
    const std::vector<double>& controlWeights() const override { return weights_; }
    // Weights differ, or the T-lattice has T-junctions (then sum B is not 1 and R is a quotient of eq. 5 even
    // with equal weights).
    bool isRational() const override { return rational_; }
    int representativeOf(int id) const override { return id; }
    const std::vector<std::vector<int>>& weldGroupList() const override { return noWelds_; }
    Eigen::AlignedBox3d restBounds() const override { return bounds_; }
    // The boundary copies: the outer faces of Q are made of their blending functions only.
    bool onOuterSurface(int id) const override { return layer_[static_cast<size_t>(id)] == 0; }
    // Layers counted over the control net's edges from the boundary copies.
    bool inSurfaceLayers(int id, int layers) const override { return layers > 0 && layer_[static_cast<size_t>(id)] < layers; }
    // The T-lattice's edges between adjacent vertices, repeated on each boundary copy layer, plus each boundary
    // copy joined to the anchor it copies (the tensor net's edges where there is no T-junction).
    std::vector<std::array<int, 2>> controlNetEdgeList() const override { return netEdges_; }
    // R_s = W_s B_s / sum W B (eq. 5) of the anchors supported on t's element (at most basis().maxSupport).
    void basisAt(const Eigen::Vector3d& t, SupportWeights& out) const override;
    // Eq. 5 and its derivative by the quotient rule; t clamped into [0,1]^3.
    void evaluate(const Positions& points, const Eigen::Vector3d& t, Eigen::Vector3d& value,
                  Eigen::Matrix3d* derivative = nullptr) const override;
    // Sec. 5 (eq. 8), by Newton's method instead of the paper's conjugate gradients, from the point's parameters
    // under the affine map that fits the control points to their Greville parameters best (the rest map itself
    // where there are no T-junctions and equal weights; within ~0.1 of it otherwise: 2-3 Newton steps). A start
    // that does not converge falls back on the candidates: elements from a grid index over their control points'
    // bounds (convex hull), Newton from each candidate's centre over the whole domain, then from the centres of
    // its 8 and 64 sub-boxes, the first candidate (lowest element id) that converges giving t. Pseudo-inverse steps
    // where dQ/dt is nearly singular, backtracking where a step does not reduce |Q - x|; converged: |Q(t) - x| at
    // rounding level (4e-15 of the diagonal, or stalled below 1e-13 of it). Deterministic; the rest volume is
    // proven not to fold (make), so a converged t is the only one. False outside the volume or for a non-finite x.
    bool freeze(const Eigen::Vector3d& x, Eigen::Vector3d& t) const override;
    std::unique_ptr<Locator> locatorFor(const Positions& points) const override;
    int chunkCount() const override { return basis_->elementCount(); }
    int chunkOf(const Eigen::Vector3d& t, Eigen::Vector3d& local) const override { return basis_->elementOf(t, local); }
    Eigen::Vector3d chunkParameters(int chunk, const Eigen::Vector3d& local) const override;
    void chunkSupport(int chunk, std::vector<int>& ids) const override;
    void chunksOfControlPoints(const std::vector<int>& ids, std::vector<int>& chunks) const override;
    // Bezier extraction: the element's homogeneous Bernstein points sum_s W_s P_s b_s and weights sum_s W_s b_s,
    // b_s = B_s's tensor Bernstein coefficients on the element (from its spans' pieces, equal to the blossoms to
    // rounding). Polynomial (points divided through, w = 1) when the weights are equal and sum W b is constant on
    // the element (to 1e-13). note: ~2-3 us for the ~70 blending functions over an element of an octree volume.
    void bezierChunk(int chunk, const Positions* displacement, BezierChunk& out) const override;
    // Just the chunk itself (no periodic axis, no collapsed face).
    void chunksAlong(int chunk, int axis, std::vector<int>& row, bool& closed) const override;
    // The T-lattice's cell edges (split at T-junctions) in parameters, each once.
    std::vector<std::array<Eigen::Vector3d, 2>> chunkEdgeLines() const override;

    // What freezing needs to know of a set of control points (#anchors x 3).
    struct FreezeIndex {
        ChunkIndex elements;                                       // each element's control-point bounds
        Eigen::Matrix3d inverse = Eigen::Matrix3d::Identity();     // Newton's first start: inverse (x - offset)
        Eigen::Vector3d offset = Eigen::Vector3d::Zero();
        bool affine = false;                                       // false: no usable affine fit, candidates only
    };
    // The same freezing with other control points and their index (freeze, locatorFor).
    bool freezeWith(const Positions& points, const FreezeIndex& index, const Eigen::Vector3d& x, Eigen::Vector3d& t) const;
    // The index of control points `points`: the element index and the least-squares affine map P_s ~ A g_s + b
    // of the anchors' Greville parameters g_s (inverted).
    FreezeIndex buildFreezeIndex(const Positions& points) const;
    // The element index alone: each element's control-point bounds.
    ChunkIndex buildElementIndex(const Positions& points) const;

private:
    std::string kind_ = "tspline";
    std::shared_ptr<const TSplineBasis> basis_;
    Positions rest_;
    std::vector<double> weights_;
    bool rational_ = false, equalWeights_ = true;
    Eigen::AlignedBox3d bounds_;
    std::vector<int> layer_;
    std::vector<std::array<int, 2>> netEdges_;
    std::vector<std::vector<int>> noWelds_;
    FreezeIndex restIndex_;
};

// ---- making T-spline volumes --------------------------------------------------------------------------------

// The T-spline volume of `lattice` over the world box `box`: control points at the anchors' Greville
// parameters mapped affinely onto the box, weights `weights` (#anchors; empty: all 1). With equal weights and
// no T-junction the rest volume is the identity map of the box; otherwise it maps [0,1]^3 onto the box (its
// boundary faces lie on the box's faces) but not linearly, and freezing finds each point's parameters.
Status makeTSplineVolumeInBox(const TLattice& lattice, const Eigen::AlignedBox3d& box, const std::vector<double>& weights,
                              std::shared_ptr<const TSplineVolume>& out);

struct TSplineOctreeSettings {
    TLatticeOctreeSettings octree;   // root grid, depth, balance
    double weightRatio = 100.0;      // sec. 4: weight of control points of non-empty cells : the far ones' (1); > 0
    // Weight balance (tspline_rest.cpp explains it): control points joined by an edge of the control net differ
    // in weight by at most this factor, so the heavy weight falls off ring by ring away from the non-empty cells
    // (100:1 with step 10: 100, 10, 1) instead of jumping 100:1 across one knot interval, which folds the rest
    // volume at T-junctions. > 1; a step >= the ratio is the paper's two levels.
    double weightStep = 10.0;
    double padding = 0.05;           // the box: the points' bounds grown by this fraction of their diagonal per side
};

// What an octree set-up (or a subdivision) did about the weights.
struct TSplineWeightOutcome {
    double weightRatio = 1.0;    // the heavy : light ratio the volume has (the requested one unless reduced)
    bool ratioReduced = false;   // the requested ratio folded the rest volume even with the weight balance
    std::string message;         // empty, or says which ratio was asked for, why it was reduced and to what
};

// Sec. 4 / Fig. 9-10: the octree T-lattice of `points` (#P x 3, mesh vertices) in their padded bounds, and its
// volume (makeTSplineVolumeInBox) with weight weightRatio on every control point anchored at a vertex of a
// non-empty cell (a corner or a T-junction on its boundary; boundary copies alike), falling off by weightStep
// per ring of the control net to 1 (balancedTSplineWeights). If that rest volume is not proven free of folds
// (checkTSplineRestVolume) the ratio is reduced, by bisection on its logarithm, to the largest tried that is
// (within a factor 1.05), and `outcome` says so. `box` (if not null) gets the box used. Fails on no finite
// point, settings out of range, or a lattice whose volume folds even with equal weights.
Status makeOctreeTSplineVolume(const Positions& points, const TSplineOctreeSettings& settings, std::shared_ptr<const TSplineVolume>& out,
                               Eigen::AlignedBox3d* box = nullptr, TSplineWeightOutcome* outcome = nullptr);

// The same in a given world box (sec. 4 and 6, step 1: "the initial region of the model to be deformed"): the
// points inside `box` (closed) shape the octree, the others are ignored; settings.padding is not used. Fails
// on a bad box or settings out of range (makeOctreeTLattice's errors), a weight ratio not finite and > 0, or a
// weight step not finite and > 1.
Status makeOctreeTSplineVolumeInBox(const Positions& points, const Eigen::AlignedBox3d& box, const TSplineOctreeSettings& settings,
                                    std::shared_ptr<const TSplineVolume>& out, TSplineWeightOutcome* outcome = nullptr);

// The finite points' bounds grown by padding x their diagonal per side (a flat or single point set still gets a
// box with volume): the box makeOctreeTSplineVolume uses. Fails when no point is finite.
Status paddedPointBounds(const Positions& points, double padding, Eigen::AlignedBox3d& out);

// Sec. 6 step 2 / Fig. 11: `volume` with the chosen cells (ids of its T-lattice) subdivided by the octree, then
// 2:1-balanced if `balance` (subdivideTLatticeCells). The control points are placed again, at the Greville
// parameters of the finer lattice under the affine map that takes the old Greville parameters onto the old
// control points (so the volume keeps its box and placement); the weights are again sec. 4's, balanced: the
// volume's largest weight on the control points of cells holding one of `points` (#P x 3, world: the mesh; cells
// found through the inverse of that map, as makeOctreeTLattice finds them), falling off by `weightStep` per ring
// to its smallest (balancedTSplineWeights), the ratio reduced as makeOctreeTSplineVolume does if that folds.
// Fails (out unchanged) on bad cell ids, a cell at kMaxTLatticeLevel, a lattice whose blending functions would
// overlap too much (buildTSplineBasis), or control points that are not an affine image of the Greville
// parameters to 1e-9 of the diagonal (points moved one by one: placing them again would lose that shape).
Status subdivideTSplineVolume(const TSplineVolume& volume, const std::vector<int>& cells, bool balance, const Positions& points,
                              std::shared_ptr<const TSplineVolume>& out, TSplineWeightOutcome* outcome = nullptr,
                              double weightStep = 10.0);

// ---- the rest volume must not fold (tspline_rest.cpp) --------------------------------------------------------

// Sec. 4's weights with the weight balance: `heavy` on the anchors flagged in `heavyAnchors` (#anchors), and on
// the others heavy / step^d (d: their distance in edges of the control net from a flagged anchor), but never
// past `light` (so far ones get `light`); heavy < light falls the other way. step > 1 (asserted); no flagged
// anchor: all `light`.
std::vector<double> balancedTSplineWeights(const TSplineBasis& basis, const std::vector<std::uint8_t>& heavyAnchors, double heavy, double light,
                                           double step);

// The outcome of proveChunkJacobian on one chunk.
struct ChunkJacobianProof {
    // Proven: det dQ/dt > 0 on the closed chunk. Fold: det dQ/dt <= 0 evaluated at `local` (value). Undecided: the
    // limits were reached with boxes left (value: the least det sampled, at local). NotApplicable: the chunk is not
    // cubic, or has a collapsed face (the proof needs neither; the Bernstein form of det decides those).
    enum Kind { Proven, Fold, Undecided, NonFinite, NotApplicable } kind = Proven;
    bool byHull = false;     // proven on the whole chunk, without subdivision
    long long boxes = 0;     // subdivision boxes looked at (0 when byHull)
    Eigen::Vector3d local = Eigen::Vector3d::Constant(0.5);  // the chunk's local coordinates in [0,1]^3
    double value = 0.0;                                        // det dQ/dt there
};

// The proof of checkTSplineRestVolume (tspline_rest.cpp, steps 1-3: the Jacobian hull of the homogeneous Bezier
// points, preconditioned by dQ/dt at the box centre, then de Casteljau halving to 2^-8 of the chunk / 1024 boxes)
// on one cubic chunk of any volume, with its control points at rest (displacement null) or moved by
// `displacement` (#controlPointCount x 3). The hull is taken in the frame of dQ/dt at each box's centre, so a
// rigid motion or a uniform scaling of the chunk is proven as its rest is (Gain & Dodgson 2001, Theorem 1: det J =
// det dQ/dt / det dQ0/dt, of one sign when both are positive). Deterministic; thread-safe (thread-local scratch).
ChunkJacobianProof proveChunkJacobian(const Volume& volume, int chunk, const Positions* displacement);

// What checkTSplineRestVolume did.
struct TSplineRestCheckStats {
    int elementsChecked = 0;
    int elementsByJacobianHull = 0;   // proven by the enclosure of dQ0/dt's column directions on the whole element
    int elementsBySubdivision = 0;    // proven by the same on the boxes of its de Casteljau subdivision
    long long subdivisionBoxes = 0;   // boxes those looked at
    double milliseconds = 0.0;
};

// Proves det dQ0/dt > 0 on every chosen element (ids; empty: all) of `volume`'s rest volume, on the closed
// element, exactly up to a rounding guard (never proven without a proof; tspline_rest.cpp): by an enclosure of
// the directions of dQ0/dt's columns (their numerators W^2 dQ0/dt_a in Bernstein form) on the whole element, or
// where that does not decide, on the boxes of its de Casteljau subdivision (halved along one axis at a time, to
// 2^-8 of the element per axis and 1024 boxes per element). Fails, naming the lowest such element, its T-lattice cell and level, the
// parameters and the value, when a point with det dQ0/dt <= 0 is found (the volume folds or is mirrored there),
// or when the proof stays undecided at the limits (saying so, with the least det sampled). Deterministic;
// parallel over elements (OpenMP). Call it again after changing weights or control points by hand (make() does).
// note: ~10 us per element on one core (the default mesh at depth 5: 22.7k elements, ~0.1-0.15 s on 2 cores).
Status checkTSplineRestVolume(const TSplineVolume& volume, const std::vector<int>& elements = {}, TSplineRestCheckStats* stats = nullptr);

}  // namespace sculpt::core
