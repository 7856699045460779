// Embedding of mesh vertices in the lattice, and evaluation of the deformed positions.
//
// Each vertex inside the box gets its parameters by the box's linear map (O(1), no iteration) and its cell
// (knot-span triple). Vertices are binned by cell once: rest positions do not change while sculpting, so
// the hot loop walks cells and, inside a cell, vertices whose 64 (cubic) control points are the same;
// that lets the kernel keep the cell's control displacements in registers and vectorise over vertices
// (design.md, "Numbers to keep in mind").
#pragma once

#include <cstdint>
#include <vector>

#include "core/volume/lattice.h"
#include "core/mesh_types.h"

namespace sculpt::core {

struct Embedding {
    int vertexCount = 0;
    std::vector<int> order;      // ids of the vertices inside the box, grouped by cell (original order within a cell)
    std::vector<int> cellStart;  // cellCount + 1 offsets into order
    // Per entry of `order` (structure of arrays, so the kernel reads them with unit stride):
    std::vector<double> localX, localY, localZ;  // local coordinates in [0,1] inside the cell
    std::vector<double> restX, restY, restZ;     // rest positions
    int insideCount() const { return static_cast<int>(order.size()); }
    // Working storage kept between re-embeddings (fresh pages cost ~10 us each on this machine class).
    std::vector<int> scratchCell, scratchCursor;
    std::vector<double> scratchParams;  // net lattices: 3 frozen parameters per vertex (NaN outside)
    // The collar (embedCollar): vertices resting outside a box lattice's box that it still carries, each with
    // the cell and the parameters p of its nearest point on the box (clamped t) and its rest position X0.
    // Empty for every embedding but a cage's that holds the whole mesh.
    std::vector<int> collarVertex, collarCell;
    std::vector<Eigen::Vector3d> collarParams, collarRest;
    int collarCount() const { return static_cast<int>(collarVertex.size()); }
};

// rest: #V x 3. Vertices outside the lattice box are left out (they never move). A net lattice freezes every
// vertex by Newton's method (Coquillart 1990, 3.3; freezePoint), in parallel; vertices outside every chunk
// are left out.
Embedding embedVertices(const Lattice& lattice, const Positions& rest);
// The same, refilling `embedding` in place and reusing its storage (no page faults when re-embedding a
// mesh of the same size, as adaptive subdivision does).
void embedVertices(const Lattice& lattice, const Positions& rest, Embedding& embedding);
// The same for a box lattice, testing only the vertices in `candidates` (ascending ids; every vertex inside the
// box that the lattice can move must be among them): the others are left out as if outside. A brush stroke's
// region holds a few thousand of a million vertices. A net lattice tests every vertex.
void embedVertices(const Lattice& lattice, const Positions& rest, Embedding& embedding, const std::vector<int>& candidates);

// The collar of a box lattice: every vertex of `rest` outside the box (embedding.order has the rest) is carried
// by the box surface's first-order extension, collarPoint. A sculpted spike pulled out of the cage's box then
// travels with the cage: a rigid or affine cage motion moves it by the same motion, exactly. Replaces the
// collar `embedding` had; a lattice of another kind (net, chunks) or a turned box gets none.
void embedCollar(const Lattice& lattice, const Positions& rest, Embedding& embedding);
// The cage's map outside its box (Sederberg & Parry 1986's FFD continued by its Taylor expansion at the box):
// x = C(P) + J(P) (X0 - P) = X0 + D(p) + (J(p) - I)(X0 - P), with p = clamp(t(X0), 0, 1) the parameters of the
// nearest box point P = X0(p), D = sum R(p) delta (Hu et al. 2001 eq. 1) and J = dx/dX0 (deformationJacobian).
// Continuous with the FFD on the box's faces; X0 itself where the lattice is undeformed (bitwise); C itself
// for X0 inside. Units: world. Box lattices only (the result is X0 + D(p) otherwise).
Eigen::Vector3d collarPoint(const Lattice& lattice, const Eigen::Vector3d& params, const Eigen::Vector3d& rest);
// The same for a rest point X0 anywhere, p its parameters clamped to the box (C itself inside it).
Eigen::Vector3d collarImage(const Lattice& lattice, const Eigen::Vector3d& rest);
// Its inverse for a point y: the X0 outside the box with collarPoint(p(X0), X0) = y, by Newton's method with
// J(p) as the derivative (exact across the box's face, first-order along it), from X0 = y - D(p(y)). False if
// it does not converge to 1e-13 x diagonal, or converges into the box (then the FFD's own preimage holds).
bool collarPreimage(const Lattice& lattice, const Eigen::Vector3d& y, Eigen::Vector3d& rest);
// The vertices of `cells` (ascending), the collar's among them, appended to `out`.
void appendVerticesOfCells(const Embedding& embedding, const std::vector<int>& cells, std::vector<int>& out);

// Lattice parameters of entry `entry` of `order`, which lies in cell `cell` (from its local coordinates).
Eigen::Vector3d embeddedParameters(const Lattice& lattice, const Embedding& embedding, int cell, int entry);

// Cells (linear index su + Su*(sv + Sv*sw)) whose evaluation depends on any of the given control points:
// the cells within `degree` spans of the point along each axis. Sorted, unique.
std::vector<int> cellsInfluencedBy(const Lattice& lattice, const std::vector<int>& controlPoints);

// positions[v] = rest[v] + sum R_ijk(t_v) delta_ijk for every embedded vertex (in parallel).
// positions must be #V x 3; rows of vertices outside the box are not written.
void evaluateAll(const Lattice& lattice, const Embedding& embedding, Positions& positions);

// The same, for the vertices of the given cells only (the sparse update after a local change).
// If movedVertices is not null, the ids of the vertices written are appended to it.
void evaluateCells(const Lattice& lattice, const Embedding& embedding, const std::vector<int>& cells,
                   Positions& positions, std::vector<int>* movedVertices = nullptr);

// The same update for a change `delta` of a polynomial lattice (unit weights), already added to `lattice`:
// positions += sum R_c(t) delta_c over the changed control points only, for the vertices of the cells they
// reach (Hu et al. 2001 eq. 1 is linear in the control points). Much cheaper than re-evaluating those
// cells in full: an outer cell of a drag holds one changed layer of its (p+1)^3 support. Rational lattices
// (and empty deltas) fall back to evaluateCells. scratch: #P x 3 and #P bytes, kept between calls.
struct IncrementScratch {
    Positions increment;
    std::vector<std::uint8_t> changed;
};
void evaluateIncrement(const Lattice& lattice, const Embedding& embedding, const std::vector<int>& controlPoints,
                       const Positions& deltas, double sign, Positions& positions, IncrementScratch& scratch,
                       std::vector<int>* movedVertices = nullptr);

// How much the given control points influence each vertex: weights[v] = sum of R_c(t_v) over those control
// points c, in [0, 1] for unit weights (1 where they carry the whole deformation, 0 outside their support).
// The region a drag or a control-point selection affects (Hsu et al. 1992 highlight it). weights: #V values.
void controlPointInfluence(const Lattice& lattice, const Embedding& embedding, const std::vector<int>& controlPoints,
                           std::vector<float>& weights);

// For benchmarks: what evaluateAll would cost with the mesh stored in cell order (sculpt_bench
// eval_full_8_in_cell_order: the cost of the scatter to the mesh's order). Entry e of embedding.order goes to
// row e of out (insideCount x 3, row-major). Writes nothing for a chunked volume or a lattice of mixed degrees
// (not this kernel's fast path).
void evaluateAllInCellOrder(const Lattice& lattice, const Embedding& embedding, double* out);

// Name of the kernel variant chosen for this CPU ("avx2-fma" or "generic"), for reports and benchmarks.
const char* evaluationKernelName();

}  // namespace sculpt::core
