// Clamped uniform B-spline basis along one lattice axis, in the per-span polynomial form the
// evaluation kernels use (no divisions of Cox-de Boor in the hot loop), plus a Cox-de Boor reference.
//
// Hu et al. 2001, eq. 2 builds the NURBS volume from these univariate bases B_{i,p}.
// Knots: p+1 zeros, uniform interior knots, p+1 ones, so the image fills the whole lattice box
// (Hsu et al. 1992: border control points of multiplicity) and, with control points at the
// Greville abscissae, sum_i xi_i B_i(u) = u exactly (linear precision: the undeformed lattice is the identity).
#pragma once

#include <vector>

namespace sculpt::core {

constexpr int kMinDegree = 1;
constexpr int kMaxDegree = 5;
constexpr int kMaxControlPointsPerAxis = 64;

// One axis of the lattice. count control points, degree p, spans non-empty knot intervals ("knot spans", one
// chunk of the volume each), each of width 1/spans in the parameter u in [0,1]. Interior knots j/spans have
// multiplicity m in [1, p]: m = 1 is the box lattice's uniform B-spline (spans = count - p); m = p makes
// every span a separate Bezier piece joined C0 (spans = (count - 1) / p), which exact rational circles need
// (Coquillart 1990, 3.1.1: only rational splines give exact circles; Piegl & Tiller, The NURBS Book, 7.5).
struct SplineAxis {
    int count = 0;
    int degree = 0;
    int spans = 0;
    int multiplicity = 1;
    // The first of the degree+1 basis functions that are non-zero on `span`: span * multiplicity.
    int first(int span) const { return span * multiplicity; }
    // The knot spans [lo, hi] where basis function f is non-zero.
    void supportSpans(int f, int& lo, int& hi) const;
    // coefficients[(span * (degree+1) + i) * (degree+1) + k]: coefficient of x^k of basis function
    // (span + i) on that span, where x = u * spans - span in [0,1] is the local coordinate.
    std::vector<double> coefficients;
    std::vector<double> knots;     // count + degree + 1 values
    std::vector<double> greville;  // count values: xi_i = (t_{i+1} + ... + t_{i+p}) / p

    // The span containing u (clamped into [0, spans-1], so u == 1 lies in the last span) and the local x.
    int locate(double u, double& local) const;
    // values[0..degree] = B_{span+i}(u) at local coordinate x of span.
    void evaluate(int span, double local, double* values) const;
    // derivatives[0..degree] = dB_{span+i}/du (chain rule through x = u * spans - span).
    void evaluateDerivative(int span, double local, double* derivatives) const;
};

// count in [degree+1, kMaxControlPointsPerAxis], degree in [kMinDegree, kMaxDegree], multiplicity in
// [1, degree] with (count - 1 - degree) divisible by multiplicity (asserted; validate user input before
// calling, e.g. with splineAxisCountValid).
SplineAxis makeSplineAxis(int count, int degree, int multiplicity = 1);
// Whether makeSplineAxis accepts these numbers.
bool splineAxisCountValid(int count, int degree, int multiplicity);
// Control points of an axis with `spans` knot spans: spans * multiplicity + degree + 1 - multiplicity.
inline int splineAxisCount(int spans, int degree, int multiplicity) { return spans * multiplicity + degree + 1 - multiplicity; }

// Reference Cox-de Boor evaluation of all count basis functions at u (tests use it as an oracle).
std::vector<double> basisReference(const SplineAxis& axis, double u);

}  // namespace sculpt::core
