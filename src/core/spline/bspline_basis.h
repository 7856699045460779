// Clamped B-spline basis along one lattice axis, in the per-span polynomial form the evaluation kernels use
// (no divisions of Cox-de Boor in the hot loop), plus a Cox-de Boor reference.
//
// Hu et al. 2001, eq. 2 builds the NURBS volume from these univariate bases B_{i,p}.
// Knots: p+1 zeros, interior knots, p+1 ones, so the image fills the whole lattice box (Hsu et al. 1992:
// border control points of multiplicity) and, with control points at the Greville abscissae,
// sum_i xi_i B_i(tau) = tau exactly (linear precision: the undeformed box lattice is the identity).
//
// Two parameters: the *knot parameter* tau, in which the knots are given, and the *lattice parameter* u in
// [0,1], in which every knot span has the same width 1/spans (span s is u in [s/spans, (s+1)/spans], and
// tau = breaks[s] + (breaks[s+1] - breaks[s]) (u spans - s) on it). The engine stores and evaluates lattice
// parameters, so the kernels find a span and its local coordinate x = u spans - s without a search. For the
// uniform knots of the box lattice the two coincide. For the non-uniform knots that exact knot insertion at
// any parameter makes (Coquillart 1990, 3.1.4; lattice_edit.h) the map tau(u) is piecewise linear and
// increasing: the volume as a point set, and every deformation x = X0 + sum R_s(t(X0)) delta_s, are the same
// in either parameter (t(X0) is found by freezing, in whichever parameter the volume is evaluated), and
// det dQ/du = det dQ/dtau times positive span-width factors, so injectivity verdicts are the same too.
#pragma once

#include <string>
#include <vector>

namespace sculpt::core {

constexpr int kMinDegree = 1;
constexpr int kMaxDegree = 5;
constexpr int kMaxControlPointsPerAxis = 64;

// One axis of the lattice. count control points, degree p, spans non-empty knot intervals ("knot spans", one
// chunk of the volume each), each of width 1/spans in the lattice parameter u in [0,1].
// Uniform axes (makeSplineAxis): interior knots j/spans of multiplicity m in [1, p]: m = 1 is the box
// lattice's uniform B-spline (spans = count - p); m = p makes every span a separate Bezier piece joined C0
// (spans = (count - 1) / p), which exact rational circles need (Coquillart 1990, 3.1.1: only rational
// splines give exact circles; Piegl & Tiller, The NURBS Book, 7.5).
// General axes (makeSplineAxisFromKnots): any clamped knot vector with interior multiplicities <= p.
struct SplineAxis {
    int count = 0;
    int degree = 0;
    int spans = 0;
    int multiplicity = 1;            // uniform axes: the interior knots' multiplicity; 0 for a general knot vector
    std::vector<int> firstFunction;  // #spans: the first of the degree+1 basis functions non-zero on each span
    std::vector<double> breaks;      // #spans + 1: the distinct knots (knot parameter), 0 ... 1
    // The first of the degree+1 basis functions that are non-zero on `span`.
    int first(int span) const { return firstFunction[static_cast<size_t>(span)]; }
    bool uniform() const { return multiplicity > 0; }
    // The knot spans [lo, hi] where basis function f is non-zero.
    void supportSpans(int f, int& lo, int& hi) const;
    // coefficients[(span * (degree+1) + i) * (degree+1) + k]: coefficient of x^k of basis function
    // (first(span) + i) on that span, where x = u * spans - span in [0,1] is the local coordinate.
    std::vector<double> coefficients;
    std::vector<double> knots;     // count + degree + 1 values (knot parameter)
    std::vector<double> greville;  // count values (knot parameter): xi_i = (t_{i+1} + ... + t_{i+p}) / p

    // The knot parameter tau of lattice parameter u in [0,1] (clamped), and its inverse.
    double knotParameter(double u) const;
    double latticeParameter(double tau) const;

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
// An axis of the clamped knot vector `knots` (knot parameter; count = #knots - degree - 1), valid by
// splineKnotsProblem (asserted).
SplineAxis makeSplineAxisFromKnots(const std::vector<double>& knots, int degree);
// Empty when `knots` is a valid clamped knot vector of `count` control points of `degree`: count + degree + 1
// finite non-decreasing values, the first degree+1 equal to 0 and the last degree+1 equal to 1, interior knots
// in (0, 1) each of multiplicity <= degree, count in [degree+1, kMaxControlPointsPerAxis], degree in
// [kMinDegree, kMaxDegree]; otherwise what is wrong, in words.
std::string splineKnotsProblem(const std::vector<double>& knots, int count, int degree);
// Control points of an axis with `spans` knot spans: spans * multiplicity + degree + 1 - multiplicity.
inline int splineAxisCount(int spans, int degree, int multiplicity) { return spans * multiplicity + degree + 1 - multiplicity; }

// Reference Cox-de Boor evaluation of all count basis functions at knot parameter u (tests use it as an oracle).
std::vector<double> basisReference(const SplineAxis& axis, double u);

}  // namespace sculpt::core
