// One chunk of a net lattice (lattice_net.h, Coquillart 1990) in Bezier form: det(dQ/dt) as a Bernstein
// polynomial, the building block of the injectivity tests on lattices of any shape (Gain & Dodgson 2001,
// sections 5 and 6, applied in parameter space).
//
// A net lattice deforms space by x(X0) = Q(t(X0)) where Q0(t(X0)) = X0 (the frozen parameters), Q the NURBS
// volume of the moved control points P0_s + delta_s and Q0 that of the rest points. So
//   det J = det(dQ/dt) / det(dQ0/dt),
// and since a valid rest net has det(dQ0/dt) > 0 inside every chunk, det J > 0 there iff det(dQ/dt) > 0:
// Theorem 1 is checked on det(dQ/dt), chunk by chunk (a knot-span triple; SplineAxis::first gives the first of
// its (p+1)(q+1)(r+1) control points, the angle axes of cylinders and spheres have knot multiplicity 2).
//
// Inside a chunk, in its local coordinates x in [0,1]^3:
//  * polynomial chunk (all its weights equal): Q is a tensor-product polynomial of degree (p, q, r) and
//    det(dQ/dt) = Q_u . (Q_v x Q_w) one of degree (3p-1, 3q-1, 3r-1);
//  * rational chunk: with the homogeneous H = (W Q, W) (a polynomial 4-vector of degree (p, q, r)),
//    det4[H_u, H_v, H_w, H] = W^4 det(dQ/dt) (subtract W_a / W times the last column from column a, expand
//    along the last row), a polynomial of degree (4p-1, 4q-1, 4r-1) with the sign of det(dQ/dt).
// The Bezier control points come from the volume interface (Volume::bezierChunk, volume.h: for a net, the
// per-span B-spline -> Bezier matrices, which hold for any multiplicity), so every kind whose chunks are
// Bezier pieces is tested by the same code; the hodograph control vectors along axis a are
// p_a / (dt_a/dx_a) (b_{l+1} - b_l) (derivatives in t, not x).
//
// Collapsed faces. Where the net is collapsed on one of its outer faces (LatticeNet::boundaryFace false and
// not a seam: the cylinder's axis r = 0, a sphere's poles, its centre), Q does not depend on one tangential
// parameter there (order m = 1: every line of the face along that axis is one welded point) or on either
// (m = 2: the face is a single point), so det(dQ/dt) and det(dQ0/dt) vanish on that face like x_a^m (or
// (1 - x_a)^m on the high face) even at rest. The rule: in a chunk on such a face, the determinant polynomial
// is divided exactly by that factor (divideBernsteinByFace), and the chunk is certified iff the quotient is
// > 0 on the closed chunk. That means det J > 0 everywhere off the collapsed face, and on it the limit of
// det J is positive: the deformation keeps the degeneracy (welded points move together, so the face stays
// a curve or a point) and keeps a non-degenerate polar structure there (around the cylinder's axis, the
// first ring of points turns monotonically round the deformed axis). A positive quotient still allows that
// ring to wind twice round an axis or pole (a branched double cover, locally 2:1 on the axis), so on a face
// collapsed along one axis (m = 1) the ring's winding number is also counted (netRingWinding) and must be
// 1 (a closed ring; an open fan must turn less than once). At a face collapsed to a point (m = 2, a sphere's
// centre) nothing more is needed: the directions out of the point then map the sphere of directions onto
// itself as a local diffeomorphism (its poles are covered by the pole faces' count), hence one to one.
// Welded points always carry equal
// displacements; a chunk whose collapsed face's points no longer coincide (to the weld tolerance, 1e-9 of
// the diagonal) is reported, not divided. Only the net's outer faces are looked at for collapse; an
// interior face or a partly collapsed face makes det(dQ0/dt) vanish there and is not certified.
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

#include "core/spline/bernstein.h"
#include "core/injectivity/injectivity_cell.h"
#include "core/volume/lattice.h"

namespace sculpt::core {

// Largest determinant polynomial of a net chunk: degree 4p-1 <= 19 per axis.
constexpr int kMaxNetDeterminantCoefficients = (4 * kMaxDegree) * (4 * kMaxDegree) * (4 * kMaxDegree);

// Per net lattice: the Bezier matrices and the collapsed outer faces.
struct NetChunkBasis {
    CellBezierBasis bezier;  // makeCellBezierBasis of the lattice (its hodographScale is not used here)
    // collapse[a][side]: bit b set if the net's face x_a = side (0 low, 1 high) is collapsed along axis b
    // (every line of the face along b is one weld group); 0 for seams and ordinary faces.
    std::array<std::array<int, 2>, 3> collapse{};
    double weldTolerance = 0.0;  // 1e-9 * the rest net's diagonal (finishLatticeNet's rule for welds)
};

// lattice.net must be set (asserted).
NetChunkBasis makeNetChunkBasis(const Lattice& lattice);

// The collapse order m of a face bit mask (the number of bits set).
inline int collapseOrder(int mask) { return (mask & 1) + ((mask >> 1) & 1) + ((mask >> 2) & 1); }

// What netChunkDeterminantBernstein built.
struct NetChunkDeterminantInfo {
    BernsteinDegree degree{};  // of the coefficients written (after the face divisions)
    bool rational = false;     // det4 form (W^4 det(dQ/dt)); false: det(dQ/dt) itself
    std::array<std::array<int, 2>, 3> divided{};  // the power divided out per axis and side
    // Bound on the magnitude of the terms that make up each coefficient (the number of terms times the product
    // of the columns' largest coefficients, times the division's multipliers): a rounding guard is relative
    // to it.
    double termBound = 0.0;
    bool weldsHold = true;  // false: a collapsed face's welded points no longer coincide (not divided there)
};

// Scratch of netChunkDeterminantBernstein (allocated once; keep one per thread).
struct NetChunkWorkspace {
    BezierChunk chunk;  // Volume::bezierChunk's output
    std::vector<double> columns, scaled, minors, product, scratch;
    NetChunkWorkspace();
};

// The determinant polynomial of chunk (su, sv, sw) (each in [0, spans)) in Bernstein form over the chunk's
// local coordinates: det(dQ/dt) (polynomial chunk) or W^4 det(dQ/dt) (rational chunk), divided by the
// collapsed faces' factors. deformed: Q of P0 + delta; false: the rest volume Q0. determinant receives
// bernsteinCoefficientCount(info.degree) <= kMaxNetDeterminantCoefficients values. Non-finite displacements
// give non-finite coefficients.
void netChunkDeterminantBernstein(const Lattice& lattice, const NetChunkBasis& basis, const std::array<int, 3>& chunk,
                                  bool deformed, NetChunkWorkspace& work, double* determinant, NetChunkDeterminantInfo& info);

// The same for chunk `chunkId` of any volume kind (Volume::bezierChunk; lattice.volume must be set): the
// engine's test for volumes that are not one tensor product. weldTolerance: 1e-9 of the rest diagonal.
void chunkDeterminantBernstein(const Lattice& lattice, int chunkId, double weldTolerance, bool deformed, NetChunkWorkspace& work,
                               double* determinant, NetChunkDeterminantInfo& info);

// Convenience for tests and one-off use (allocates).
BernsteinTensor netChunkDeterminantBernstein(const Lattice& lattice, const std::array<int, 3>& chunk, bool deformed = true,
                                             NetChunkDeterminantInfo* info = nullptr);

// dQ0/dt and dD/dt (D = sum R delta, so dQ/dt is their sum) at local coordinates `local` of the chunk, with
// that chunk's polynomials (a point on a chunk face is seen from this chunk). Rational by the quotient rule.
void netChunkDerivatives(const Lattice& lattice, const std::array<int, 3>& chunk, const Eigen::Vector3d& local,
                         Eigen::Matrix3d& restDerivative, Eigen::Matrix3d& displacementDerivative);

// How many times the deformed volume winds round the collapsed line of the chunk's face (axis, side), a face
// collapsed along exactly one axis b (a cylinder's axis, a sphere's pole): the first ring of points (the
// direction of dQ/dx_axis on the face, a polynomial curve in homogeneous form over the chunks along b) at the
// middle of the chunk along the third axis, projected on the plane normal to the collapsed line, and its
// angle summed piece by piece (pieces split by de Casteljau until their control vectors fit in a half-plane,
// so each piece's turn is the angle between its ends). turns: signed, in whole turns (+-1 at rest for a closed
// ring, whose count is an integer; a fraction for an open fan). Returns false if it cannot be told: the
// collapsed line's tangent or a ring vector vanishes, a piece still straddles after 12 halvings, or the face's
// weights are not separable so its ring is not a single curve.
bool netRingWinding(const Lattice& lattice, const NetChunkBasis& basis, const std::array<int, 3>& chunk, int axis, int side,
                    NetChunkWorkspace& work, double& turns);

// The same for chunk `chunkId` of any volume kind, walking the row of chunks along the collapsed direction
// (Volume::chunksAlong); closed receives whether that row is a ring (then the count must be +-1, else the fan
// must turn less than once).
bool chunkRingWinding(const Lattice& lattice, int chunkId, int axis, int side, double weldTolerance, NetChunkWorkspace& work,
                      double& turns, bool& closed);

// det J = det(dQ/dt) / det(dQ0/dt) at local coordinates of the chunk: exactly 1 if no control point of the
// chunk moved; on (or within 1e-8 relative of) a collapsed face, where det(dQ0/dt) vanishes, the limit, as
// the ratio of the face-divided determinant polynomials (along `local`'s direction; costly: two chunk
// polynomials, ~50 us). Never
// NaN for finite displacements: a point where even the rest quotient is not positive (an invalid rest net)
// gives the plain ratio if finite, else 0.
double netJacobianDeterminantInChunk(const Lattice& lattice, const std::array<int, 3>& chunk, const Eigen::Vector3d& local);
// The same for chunk `chunkId` of any volume kind (lattice.volume set; a tensor net goes to the above).
double chunkJacobianDeterminant(const Lattice& lattice, int chunkId, const Eigen::Vector3d& local);

}  // namespace sculpt::core
