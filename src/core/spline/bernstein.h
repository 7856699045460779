// Bernstein (Bezier) polynomials on [0,1] and tensor-product Bernstein polynomials on [0,1]^3: the small
// toolkit behind the exact injectivity test (Gain & Dodgson 2001, section 6). There det J of a lattice cell
// is formed as products of the Bezier forms of the partial derivatives and then subdivided by de Casteljau
// until the signs of its coefficients decide (steps 3 and 4 of section 6).
//
// A trivariate polynomial of degree n = (n0, n1, n2) is
//   f(x, y, z) = sum_ijk c_ijk b_i^n0(x) b_j^n1(y) b_k^n2(z),   b_i^n(x) = C(n,i) x^i (1-x)^(n-i),
// with c_ijk stored at i + (n0+1) * (j + (n1+1) * k) (the lattice's own index order). Properties used by
// the callers: the corner coefficients are the values at the corners of the box, and min c <= f <= max c
// (convex hull: the b's are >= 0 and sum to 1).
//
// Two layers: raw kernels on caller-owned arrays (no allocation, for the per-cell hot loop) and value-type
// wrappers on BernsteinTensor for one-off use and tests.
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>

namespace sculpt::core {

// Largest degree per axis the kernels accept (det J of a quintic lattice has degree 3*5-1 = 14 per axis;
// the binomial table goes further so products of products stay in range).
constexpr int kMaxBernsteinDegree = 31;

using BernsteinDegree = std::array<int, 3>;

// C(n, k) for 0 <= k <= n <= kMaxBernsteinDegree, exact in double (table built once); 0 for k outside
// [0, n]. n out of range is asserted.
double binomial(int n, int k);

// (n0+1)(n1+1)(n2+1).
inline int bernsteinCoefficientCount(const BernsteinDegree& degree) {
    return (degree[0] + 1) * (degree[1] + 1) * (degree[2] + 1);
}

// ---- univariate ---------------------------------------------------------------------------------------

// Bernstein coefficients of the degree-n polynomial sum_k monomial[k] x^k (n+1 values in, n+1 out; the
// arrays must not overlap). x^k = sum_{l>=k} C(l,k)/C(n,k) b_l^n(x) (Farin, Curves and Surfaces for CAGD).
void monomialToBernstein(const double* monomial, int degree, double* bernstein);

// Value at x of the univariate Bernstein polynomial with degree+1 coefficients, by de Casteljau.
double evaluateBernstein1(const double* coefficients, int degree, double x);

// ---- trivariate raw kernels (caller-owned storage, no allocation) -------------------------------------

// Value at x in [0,1]^3 by de Casteljau along each axis (x outside [0,1]^3 extrapolates).
double evaluateBernstein(const double* coefficients, const BernsteinDegree& degree, const Eigen::Vector3d& x);

// Min and max coefficient: bounds of the polynomial over the box (convex hull property).
void bernsteinCoefficientRange(const double* coefficients, const BernsteinDegree& degree, double& minimum,
                               double& maximum);

// Scaled ("binomial") form: c_ijk * C(n0,i) C(n1,j) C(n2,k). In this form a product of two polynomials is a
// plain convolution of the coefficient arrays, since b_i^m b_j^n = C(m,i) C(n,j) / C(m+n,i+j) b_{i+j}^{m+n}.
void scaleToBinomialForm(double* coefficients, const BernsteinDegree& degree);
void unscaleFromBinomialForm(double* coefficients, const BernsteinDegree& degree);

// out += sign * (a * b), all three in scaled form; out has degree degreeA + degreeB (each <=
// kMaxBernsteinDegree, asserted) and must not overlap a or b.
void convolveAddScaled(const double* a, const BernsteinDegree& degreeA, const double* b, const BernsteinDegree& degreeB,
                       double sign, double* out);

// De Casteljau subdivision along one axis (0, 1, 2) at parameter `at` in (0,1): `left` gets the piece over
// [0, at] and `right` the piece over [at, 1] of that axis, each re-parametrised to [0,1] and of the same
// degree. in, left and right must not overlap.
void splitBernstein(const double* in, const BernsteinDegree& degree, int axis, double at, double* left, double* right);

// The same polynomial with its degree raised by one along `axis`: out has degree + e_axis (Farin, degree elevation:
// c'_i = i/(n+1) c_{i-1} + (1 - i/(n+1)) c_i). in and out must not overlap.
void elevateBernstein(const double* in, const BernsteinDegree& degree, int axis, double* out);

// Exact division by a factor vanishing on a face of the box: f = x^power g (side 0, the face x_axis = 0) or
// f = (1 - x)^power g (side 1, x_axis = 1), f of degree n along `axis` (power <= n, asserted). out = g, of
// degree n - power along `axis`: x^m b_j^(n-m) = C(n-m, j) / C(n, j+m) b_(j+m)^n, so
//   side 0: g_j = f_(j+m) C(n, j+m) / C(n-m, j),   side 1: g_j = f_j C(n, j) / C(n-m, j).
// The m layers of f that the factor makes zero (i < m, or i > n - m) are not read: the caller asserts they
// vanish in exact arithmetic. Returns the largest multiplier C(n, .) / C(n-m, .) used (for rounding bounds).
// in and out must not overlap.
double divideBernsteinByFace(const double* in, const BernsteinDegree& degree, int axis, int side, int power, double* out);

// ---- value type ---------------------------------------------------------------------------------------

struct BernsteinTensor {
    BernsteinDegree degree{0, 0, 0};
    std::vector<double> coefficients;  // bernsteinCoefficientCount(degree) values, layout as above

    BernsteinTensor() : coefficients(1, 0.0) {}
    explicit BernsteinTensor(const BernsteinDegree& d) : degree(d), coefficients(bernsteinCoefficientCount(d), 0.0) {}
    int index(int i, int j, int k) const { return i + (degree[0] + 1) * (j + (degree[1] + 1) * k); }
    double& at(int i, int j, int k) { return coefficients[index(i, j, k)]; }
    double at(int i, int j, int k) const { return coefficients[index(i, j, k)]; }
};

double bernsteinEvaluate(const BernsteinTensor& f, const Eigen::Vector3d& x);
// f * g, of degree f.degree + g.degree.
BernsteinTensor bernsteinProduct(const BernsteinTensor& f, const BernsteinTensor& g);
// The two halves of f split along `axis` at `at` (see splitBernstein).
void bernsteinSplit(const BernsteinTensor& f, int axis, double at, BernsteinTensor& left, BernsteinTensor& right);
// f with its degree raised by one along `axis`.
BernsteinTensor bernsteinElevate(const BernsteinTensor& f, int axis);

}  // namespace sculpt::core
