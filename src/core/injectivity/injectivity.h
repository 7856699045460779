// Injectivity (freedom from self-intersection) of the lattice deformation, after Gain & Dodgson 2001,
// "Preventing self-intersection under free-form deformation" (seed 003).
//
// Theorem 1 (section 5): a C1 deformation is injective if det J > 0 everywhere (with the boundary caveat
// under InjectivityResult::boundaryFixed). Two tests of that, per lattice cell:
//   * conic  (section 7, Appendix "InjectiveTest"): bounds the hodograph control vectors of each cell by
//            cones around the axes; O(cells), sufficient only: "not certified" does not mean "folds".
//   * exact  (section 6): det J of each cell in Bernstein form, subdivided by de Casteljau until every box
//            is proven positive or a point with det J <= 0 is found. Necessary and sufficient up to the
//            subdivision depth limit and rounding; it never certifies what it has not proven.
// Both cover polynomial box lattices (all weights equal in a cell). A cell of a rational box lattice with
// differing weights is reported as Unsupported (not certified) rather than guessed at.
//
// Net lattices (lattice.net set: lattices of any shape, Coquillart 1990) are checked chunk by chunk on
// det(dQ/dt), whose sign is det J's (det J = det(dQ/dt) / det(dQ0/dt), the rest net has det(dQ0/dt) > 0):
// polynomial chunks as a Bernstein polynomial of degree (3p-1, 3q-1, 3r-1), rational chunks (cylinders,
// spheres, weighted nets) through the homogeneous det4[H_u, H_v, H_w, H] = W^4 det(dQ/dt) of degree
// (4p-1, 4q-1, 4r-1), so no rational net chunk is Unsupported. On a collapsed outer face (a cylinder's axis,
// a sphere's poles and centre) the determinant vanishes even at rest; it is divided exactly by x_a^m there and
// the chunk is certified iff the quotient is positive (injectivity_net.h states the rule). The conic test's
// cones are around the axes of a box lattice's rest hodographs, which a curved net does not have: on a net
// lattice checkInjectivityConic runs the exact test (its verdicts are the exact test's).
//
// The engine calls checkInjectivity() after every change; pass the cells whose support contains changed
// control points (cellsInfluencedBy in embedding.h) to check only those.
#pragma once

#include <array>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/volume/lattice.h"
#include "core/mesh_types.h"

namespace sculpt::core {

enum class InjectivityMode { Off, Conic, Exact };

// "off", "conic", "exact".
const char* injectivityModeName(InjectivityMode mode);
// Parses exactly those names; returns false (mode untouched) for anything else.
bool parseInjectivityMode(const std::string& name, InjectivityMode& mode);

struct InjectivitySettings {
    InjectivityMode mode = InjectivityMode::Conic;
    // Depth of the adaptive subdivision of a failing manipulation (section 8, Appendix "InjectSubdiv"):
    // how many times the Session may halve a drag before rejecting it. Not used by the tests below.
    int maxDepth = 6;
    // With a test on (conic or exact), also check the triangle mesh itself: an operation that makes two
    // triangles cross that did not cross before is subdivided or refused like a failing lattice test
    // (self_intersection.h). Off only to measure what it costs.
    bool checkTriangles = true;
};

enum class InjectivityVerdict {
    Certified,     // det J > 0 proven in every checked cell: injective there (Theorem 1)
    NotCertified,  // conic test: some cell's cones overlap; the deformation may still be injective
    Fold,          // exact test: a point with det J <= tolerance was found (failingParams): with det J < 0 the
                   // deformation folds (not injective); in [0, tolerance] it is degenerate or nearly so
    Undecided,     // exact test: subdivision or work limit reached with coefficients still straddling zero
                   // and no fold point found, or non-finite displacements; treated as not certified
    Unsupported,   // a checked cell of a box lattice is rational (differing weights): nothing proven there
};
const char* injectivityVerdictName(InjectivityVerdict verdict);

struct InjectivityResult {
    bool certified = false;  // verdict == Certified; false means only "not proven injective" unless Fold
    InjectivityVerdict verdict = InjectivityVerdict::Undecided;
    // The reported cell (-1 / {-1,-1,-1} if none): for Fold the lowest-index cell with a fold, otherwise the
    // lowest-index failing cell.
    int failingCell = -1;
    std::array<int, 3> failingCellIjk{-1, -1, -1};
    // Lattice parameters t in [0,1]^3 of the reported point, and the same point in the cell's local
    // coordinates [0,1]^3. Fold: a point where det J <= tolerance (evaluate it with
    // jacobianDeterminantInCell(failingCellIjk, failingLocalParams): on a cell face that is the side the
    // test saw). Undecided: the sampled point of least det J in the undecided boxes. NotCertified (conic)
    // and Unsupported: the cell centre. NaN when nothing failed.
    Eigen::Vector3d failingParams = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
    Eigen::Vector3d failingLocalParams = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
    // Exact test: the least det J among the points it evaluated (Bezier box corners, i.e. cell corners and
    // subdivision points). For Fold it is the value at the reported point; otherwise over every checked
    // cell (undeformed cells contribute 1). An upper bound of the true minimum. +inf for the conic test.
    // Net lattices: det J evaluated at each chunk's corner of least determinant polynomial (moved 1e-3 of the
    // chunk off a collapsed face).
    double minDeterminantFound = std::numeric_limits<double>::infinity();
    // Exact test, Certified: det J >= this everywhere in the checked cells (least coefficient of the boxes
    // that proved positive). -inf otherwise. Net lattices: the tolerance (the test proves det J > tolerance
    // through det(dQ/dt) - tolerance det(dQ0/dt) > 0, not a bound of det J itself); 1 if no chunk moved.
    double determinantLowerBound = -std::numeric_limits<double>::infinity();
    // No control point of the outer layer has moved, so the box's faces map onto themselves. Only then does
    // det J > 0 give global injectivity (a local homeomorphism that is one-to-one on the boundary is
    // one-to-one: Meisters & Olech, the paper's [24]; section 5's remark on the seam with the space around
    // the hyperpatch). Otherwise "certified" means locally injective: a lattice bent round until two of its
    // ends overlap has det J > 0 everywhere. Pinning the outer layer (LatticeSettings::pinLayers >= 1)
    // keeps this true. Not set by InjectivityMode::Off.
    bool boundaryFixed = false;
    int cellsChecked = 0;   // cells in the request (all cells for an empty list)
    int cellsDeformed = 0;  // of those, cells with a non-zero displacement in their support (the rest: det J == 1)
    long long boxesExamined = 0;  // exact test: Bezier boxes looked at, cells included
    double milliseconds = 0.0;    // wall time of the check
    std::string message;          // human-readable verdict, names the cell and point; empty when certified
};

// Options of the exact test.
struct ExactOptions {
    // Octree levels below each cell (section 6, step 4): boxes of 2^-10 of a cell. A box whose coefficients
    // still straddle zero at this depth, with no sampled det J <= tolerance, makes the verdict Undecided
    // (not certified): the test never reports injective without a proof.
    int maxSubdivisionDepth = 10;
    // det J must exceed this everywhere. 0 is Theorem 1's condition det J > 0; a positive value (det J is 1
    // for the undeformed lattice) also rejects nearly degenerate deformations. A sampled value <= tolerance
    // is reported as a Fold.
    double tolerance = 0.0;
    // Relative rounding guard: a box is proven positive only if its least coefficient exceeds
    // tolerance + roundingGuard * (a bound on the magnitude of the terms of det J in that cell), so rounding
    // in forming the coefficients cannot certify a sign it has not got.
    double roundingGuard = 1e-12;
    // Work limit per cell, in boxes; exceeding it makes the verdict Undecided (a zero set of det J that is
    // tangent along a surface would otherwise cost 4^depth boxes).
    int maxBoxesPerCell = 20000;
};

// det of the deformation Jacobian dx/dX0 at lattice parameters t in [0,1]^3 (1 for the undeformed lattice;
// rational lattices by the quotient rule). On an interior knot the cell above is used (SplineAxis::locate).
// A net lattice: det(dQ/dt) / det(dQ0/dt), exactly 1 in a chunk with no moved control point, and its limit
// (finite) on a collapsed axis, pole or centre, approached along the parameters t (on the axis the limit
// depends on the angle t gives: the deformation need not be differentiable there).
double jacobianDeterminant(const Lattice& lattice, const Eigen::Vector3d& params);

// out[v] = det J of this lattice's deformation at rest vertex v (#V values), for the renderer's colour map;
// 1 for vertices outside the lattice box (they never move) and, exactly, for vertices in cells with no
// moved control point (those are not evaluated). Parallel over vertices (OpenMP). rest: #V x 3. A net
// lattice freezes (restParameters) only the vertices that some deformed chunk's bounds hold (~1-5 us each).
// note: ~0.2 us per evaluated vertex (cubic, one core); with composed frames (Session) the total det J is
// the product over the frames.
void vertexJacobianDeterminants(const Lattice& lattice, const Positions& rest, std::vector<double>& out);

// Conic-hull hodograph test (section 7, Appendix InjectiveTest) on the Bezier hodographs of each cell.
// cells: linear cell indices (su + S0*(sv + S1*sw)) to check, each in [0, cellCount) (asserted); empty =
// all cells. Verdicts: Certified, NotCertified, Unsupported. A net lattice: the exact test instead (its
// verdicts, its message with "(net lattice: the conic test runs the exact test)" added).
InjectivityResult checkInjectivityConic(const Lattice& lattice, const std::vector<int>& cells = {});

// Exact test (section 6). cells as above. Verdicts: Certified, Fold, Undecided, Unsupported (a fold found
// in any cell takes precedence over the others). A net lattice's cells are its chunks; verdicts Certified,
// Fold, Undecided (also for a chunk on a collapsed face whose welded control points no longer coincide).
// note: ~25 us per deformed chunk of a rational (2,2,2) cylinder net (one core), ~1.5x a cubic box cell.
InjectivityResult checkInjectivityExact(const Lattice& lattice, const ExactOptions& options = {},
                                        const std::vector<int>& cells = {});

// The directional bound: a sufficient test for cells whose control displacements all lie along one line.
// In a cell of a polynomial box lattice where every displaced control point of the support moves along the
// same unit vector e (delta_c = s_c e), J = I + e grad(s)^T, so det J = 1 + e . grad s (the matrix determinant
// lemma) = sum_a e_a (e . J_a) with J_a the Jacobian's columns, whose Bezier control vectors are the cell's
// hodographs (section 7). Each e . J_a raised to the cell's degree along a, their weighted sum is det J in
// Bernstein form, cancellation kept; a cell whose least coefficient exceeds 1e-9 is proven to have det J > 0 (Gain & Dodgson 2001, Theorem 1),
// as is a cell with no displaced control point (det J = 1). The brush's pull fields (brush_field.h) are of
// this kind, and certify here in O(coefficients) where the Bernstein test would subdivide. Displacements along
// one of the box's axes a (the brush's layers) are proven first by the least divided difference
// p (w_i - w_{i-1}) / (t_{i+p} - t_i) of their component w along a (de Boor: dw/du_a is everywhere a convex
// combination of them): over the whole lattice at once (O(control points); every cell proven when
// 1 + least / extent_a > 1e-9), else over each cell's support before its Bernstein form.
// Returns the cells of `cells` this does not prove (to pass to checkInjectivity), in order; every cell for a
// net lattice, a rational lattice or an axis with a general knot vector.
std::vector<int> cellsLeftByDirectionalBound(const Lattice& lattice, const std::vector<int>& cells);

// The engine's entry point: Off -> Certified without looking; Conic / Exact as above (default options).
// note: an empty `cells` means all cells, so a caller with nothing changed should skip the call rather
// than pass an empty list.
InjectivityResult checkInjectivity(const Lattice& lattice, InjectivityMode mode);
InjectivityResult checkInjectivity(const Lattice& lattice, InjectivityMode mode, const std::vector<int>& cells);

}  // namespace sculpt::core
