// One lattice cell in Bezier form: the building blocks of the injectivity tests (Gain & Dodgson 2001,
// sections 6 and 7) and the pointwise Jacobian determinant.
//
// Inside cell (su, sv, sw) the displacement field D(t) = sum R_ijk(t) delta_ijk of a polynomial lattice is a
// tensor-product polynomial of degree (p, q, r) in the local coordinates x_a = t_a * S_a - s_a in [0,1]
// (S = spans per axis). Its Bezier control points follow from the per-span basis polynomials of
// SplineAxis (monomial -> Bernstein), so no knot insertion is needed (section 6, step 3).
//
// The deformation is x(X0) = X0 + D(t(X0)) with t = (X0 - boxMin) / size, so its Jacobian is
//   J = I + dD/dt diag(1/size),   column a:  J_a = e_a + (S_a / size_a) dD/dx_a,
// and det J = 1 exactly for an undeformed cell. Column a is the hodograph of the cell along axis a (up to
// the positive factor size_a / S_a); its Bezier control vectors are
//   e_a + (S_a p_a / size_a) (Dbez_{..,l+1,..} - Dbez_{..,l,..})   (the hodograph of a Bezier volume),
// the vectors whose conic hulls section 7 bounds, and det J = J_u . (J_v x J_w) (eq. 9) is a polynomial of
// degree (3p-1, 3q-1, 3r-1) whose Bezier form section 6 subdivides.
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

#include "core/spline/bernstein.h"
#include "core/volume/lattice.h"

namespace sculpt::core {

// Largest per-cell array sizes, for callers that keep fixed workspaces.
constexpr int kMaxCellControlPoints = (kMaxDegree + 1) * (kMaxDegree + 1) * (kMaxDegree + 1);
constexpr int kMaxDeterminantCoefficients = (3 * kMaxDegree) * (3 * kMaxDegree) * (3 * kMaxDegree);

// Per lattice: for every axis and span, the (p+1) x (p+1) matrix taking the span's B-spline control values
// to its Bezier control values: bez_l = sum_i toBezier[a][(span * (p+1) + l) * (p+1) + i] * ctrl_{span+i}.
struct CellBezierBasis {
    std::array<int, 3> degree{};
    std::array<int, 3> spans{};
    std::array<double, 3> hodographScale{};  // S_a p_a / size_a (see above)
    std::array<std::vector<double>, 3> toBezier;
};

CellBezierBasis makeCellBezierBasis(const Lattice& lattice);

// note: the Bezier form, hodographs and determinant below are the box lattice's (J = I + dD/dt diag(1/size));
// a net lattice's chunks have their own (injectivity_net.h). cellIsPolynomial, cellIsUndeformed and
// jacobianDeterminantInCell hold for every kind of lattice (a cell of a net lattice is a chunk; its support
// starts at SplineAxis::first of each span).

// True if the Bezier form below describes the cell exactly: the lattice is polynomial there, i.e. all
// weights of the cell's (p+1)(q+1)(r+1) control points are equal (then R_ijk = B_i B_j B_k in the cell,
// whatever the common weight). False for a cell of a rational lattice with differing weights.
bool cellIsPolynomial(const Lattice& lattice, const std::array<int, 3>& cell);

// True if every control point displacement in the cell's support is exactly zero (det J == 1 there).
bool cellIsUndeformed(const Lattice& lattice, const std::array<int, 3>& cell);

// Box lattice only (asserted). Bezier control points of the displacement over the cell, for a polynomial cell:
// bezier[c * n + l + (p+1) * (m + (q+1) * o)] for coordinate c in {0,1,2}, n = (p+1)(q+1)(r+1).
// bezier must hold 3 n doubles.
void cellBezierDisplacement(const Lattice& lattice, const CellBezierBasis& basis, const std::array<int, 3>& cell,
                            double* bezier);

// The conic hulls of section 7 (step 2a): sinSquared[a] = the largest sin^2 of the angle between a Bezier
// control vector of J_a and the axis e_a, from the output of cellBezierDisplacement. Returns false (the
// Appendix's FindDeviation "fail") if some control vector has a component along its own axis <= 0; then
// sinSquared is unspecified.
bool cellHodographCones(const CellBezierBasis& basis, const double* bezier, std::array<double, 3>& sinSquared);
// The same test in the frame of the cell's mean Jacobian M (column a: the mean of J_a's Bezier control vectors):
// the cones around e_a of the vectors M^-1 h (det(M^-1 J) = det J / det M). A rigid motion or uniform scaling of
// the cell is certified at any angle (M^-1 J = I). False also when det M <= 0 (then nothing is said).
bool cellHodographConesInMeanFrame(const CellBezierBasis& basis, const double* bezier, std::array<double, 3>& sinSquared);

// Bezier control vectors of the Jacobian columns J_a over the cell (see the top of this file), from the
// output of cellBezierDisplacement. column[a] receives 3 blocks (x, y, z components) of
// bernsteinCoefficientCount(columnDegree(basis, a)) doubles each.
BernsteinDegree columnDegree(const CellBezierBasis& basis, int axis);
void cellJacobianColumns(const CellBezierBasis& basis, const double* bezier, double* const column[3]);

// det J over the cell as a Bernstein polynomial of degree (3p-1, 3q-1, 3r-1) (section 6, eq. 5-8 in Bezier
// form), built as J_u . (J_v x J_w) with products in the scaled form. `columns` as from
// cellJacobianColumns; `scratch` holds at least 3 * kMaxDeterminantCoefficients doubles; determinant
// receives bernsteinCoefficientCount(determinantDegree(basis)) values.
BernsteinDegree determinantDegree(const CellBezierBasis& basis);
void cellDeterminantBernstein(const CellBezierBasis& basis, double* const columns[3], double* scratch,
                              double* determinant);

// Convenience for tests and tools: det J of one polynomial cell of a box lattice as a BernsteinTensor
// (allocates; a net lattice's chunk: netChunkDeterminantBernstein).
BernsteinTensor cellJacobianDeterminantBernstein(const Lattice& lattice, const std::array<int, 3>& cell);

// det of the deformation Jacobian at local coordinates `local` in [0,1]^3 of the given cell, with that
// cell's polynomials (so a point on a cell face is evaluated from this side; it matters for degree 1,
// where the Jacobian jumps across faces). Rational lattices are handled with the quotient rule. A net
// lattice: det(dQ/dt) / det(dQ0/dt), with its limit on a collapsed face (netJacobianDeterminantInChunk).
double jacobianDeterminantInCell(const Lattice& lattice, const std::array<int, 3>& cell, const Eigen::Vector3d& local);

}  // namespace sculpt::core
