// Bernstein polynomial toolkit for the exact injectivity test (Gain & Dodgson 2001, section 6, steps 3-4):
// products in the scaled (binomial) form, de Casteljau subdivision and evaluation, degree elevation.
// Standard Bezier algebra; see G. Farin, Curves and Surfaces for CAGD (de Casteljau, degree elevation,
// products of Bernstein polynomials).
#include "core/spline/bernstein.h"

#include <algorithm>
#include <cassert>

namespace sculpt::core {

namespace {

constexpr int kTableSize = kMaxBernsteinDegree + 1;

struct BinomialTable {
    double value[kTableSize][kTableSize] = {};
    BinomialTable() {
        // Pascal's triangle: sums of integers below 2^53, so every entry is exact.
        for (int n = 0; n < kTableSize; ++n) {
            value[n][0] = value[n][n] = 1.0;
            for (int k = 1; k < n; ++k) value[n][k] = value[n - 1][k - 1] + value[n - 1][k];
        }
    }
};

const BinomialTable& binomials() {
    static const BinomialTable table;
    return table;
}

// Stride of `axis` in the coefficient layout and the number of lines along it.
int axisStride(const BernsteinDegree& degree, int axis) {
    int stride = 1;
    for (int a = 0; a < axis; ++a) stride *= degree[a] + 1;
    return stride;
}

// Calls line(offset) for the first element of every line of coefficients running along `axis`.
template <class Line>
void forEachLine(const BernsteinDegree& degree, int axis, Line&& line) {
    const int stride = axisStride(degree, axis);
    const int length = degree[axis] + 1;
    const int total = bernsteinCoefficientCount(degree);
    // Lines start at offsets whose `axis` digit is zero: blocks of `stride` consecutive starts, one block
    // every stride * length coefficients.
    for (int block = 0; block < total; block += stride * length)
        for (int inner = 0; inner < stride; ++inner) line(block + inner);
}

}  // namespace

double binomial(int n, int k) {
    assert(n >= 0 && n <= kMaxBernsteinDegree);
    if (k < 0 || k > n) return 0.0;
    return binomials().value[n][k];
}

void monomialToBernstein(const double* monomial, int degree, double* bernstein) {
    assert(degree >= 0 && degree <= kMaxBernsteinDegree);
    const BinomialTable& table = binomials();
    for (int l = 0; l <= degree; ++l) {
        double sum = 0.0;
        for (int k = 0; k <= l; ++k) sum += table.value[l][k] / table.value[degree][k] * monomial[k];
        bernstein[l] = sum;
    }
}

double evaluateBernstein1(const double* coefficients, int degree, double x) {
    assert(degree >= 0 && degree <= kMaxBernsteinDegree);
    double work[kTableSize] = {};
    for (int i = 0; i <= degree; ++i) work[i] = coefficients[i];
    const double oneMinus = 1.0 - x;
    for (int r = 1; r <= degree; ++r)
        for (int i = 0; i <= degree - r; ++i) work[i] = oneMinus * work[i] + x * work[i + 1];
    return work[0];
}

double evaluateBernstein(const double* coefficients, const BernsteinDegree& degree, const Eigen::Vector3d& x) {
    const int n0 = degree[0] + 1, n1 = degree[1] + 1, n2 = degree[2] + 1;
    // Collapse x, then y, then z: (n1 n2) univariate evaluations, then n2, then one.
    double plane[kTableSize * kTableSize];
    for (int k = 0; k < n2; ++k)
        for (int j = 0; j < n1; ++j)
            plane[j + n1 * k] = evaluateBernstein1(coefficients + n0 * (j + n1 * k), degree[0], x[0]);
    double line[kTableSize];
    for (int k = 0; k < n2; ++k) line[k] = evaluateBernstein1(plane + n1 * k, degree[1], x[1]);
    return evaluateBernstein1(line, degree[2], x[2]);
}

void bernsteinCoefficientRange(const double* coefficients, const BernsteinDegree& degree, double& minimum,
                               double& maximum) {
    const int count = bernsteinCoefficientCount(degree);
    double lo = coefficients[0], hi = coefficients[0];
    for (int c = 1; c < count; ++c) {
        lo = std::min(lo, coefficients[c]);
        hi = std::max(hi, coefficients[c]);
    }
    minimum = lo;
    maximum = hi;
}

void scaleToBinomialForm(double* coefficients, const BernsteinDegree& degree) {
    const BinomialTable& table = binomials();
    int c = 0;
    for (int k = 0; k <= degree[2]; ++k)
        for (int j = 0; j <= degree[1]; ++j) {
            const double jk = table.value[degree[1]][j] * table.value[degree[2]][k];
            for (int i = 0; i <= degree[0]; ++i, ++c) coefficients[c] *= table.value[degree[0]][i] * jk;
        }
}

void unscaleFromBinomialForm(double* coefficients, const BernsteinDegree& degree) {
    const BinomialTable& table = binomials();
    int c = 0;
    for (int k = 0; k <= degree[2]; ++k)
        for (int j = 0; j <= degree[1]; ++j) {
            const double jk = table.value[degree[1]][j] * table.value[degree[2]][k];
            // note: dividing (not multiplying by a reciprocal) keeps coefficients whose scaled value is an
            // exact multiple of the binomials exact, e.g. the constant 1 of an undeformed cell.
            for (int i = 0; i <= degree[0]; ++i, ++c) coefficients[c] /= table.value[degree[0]][i] * jk;
        }
}

namespace {

// The convolution with the innermost length B0 known at compile time (0: run-time b0), so the short inner
// loop (2..15 terms) is unrolled and vectorised.
template <int B0>
void convolveLines(const double* a, const BernsteinDegree& degreeA, const double* b, const BernsteinDegree& degreeB,
                   double sign, double* out) {
    const int a0 = degreeA[0] + 1, a1 = degreeA[1] + 1, a2 = degreeA[2] + 1;
    const int b0 = B0 > 0 ? B0 : degreeB[0] + 1, b1 = degreeB[1] + 1, b2 = degreeB[2] + 1;
    const int o0 = a0 + b0 - 1, o1 = a1 + b1 - 1;
    for (int ka = 0; ka < a2; ++ka)
        for (int ja = 0; ja < a1; ++ja)
            for (int ia = 0; ia < a0; ++ia) {
                const double value = sign * a[ia + a0 * (ja + a1 * ka)];
                if (value == 0.0) continue;  // note: hodographs of partly undeformed cells have many zeros
                for (int kb = 0; kb < b2; ++kb)
                    for (int jb = 0; jb < b1; ++jb) {
                        const double* bLine = b + b0 * (jb + b1 * kb);
                        double* outLine = out + ia + o0 * ((ja + jb) + o1 * (ka + kb));
                        for (int ib = 0; ib < b0; ++ib) outLine[ib] += value * bLine[ib];
                    }
            }
}

}  // namespace

void convolveAddScaled(const double* a, const BernsteinDegree& degreeA, const double* b, const BernsteinDegree& degreeB,
                       double sign, double* out) {
    assert(degreeA[0] + degreeB[0] <= kMaxBernsteinDegree && degreeA[1] + degreeB[1] <= kMaxBernsteinDegree &&
           degreeA[2] + degreeB[2] <= kMaxBernsteinDegree);
    switch (degreeB[0] + 1) {
        case 1: return convolveLines<1>(a, degreeA, b, degreeB, sign, out);
        case 2: return convolveLines<2>(a, degreeA, b, degreeB, sign, out);
        case 3: return convolveLines<3>(a, degreeA, b, degreeB, sign, out);
        case 4: return convolveLines<4>(a, degreeA, b, degreeB, sign, out);
        case 5: return convolveLines<5>(a, degreeA, b, degreeB, sign, out);
        case 6: return convolveLines<6>(a, degreeA, b, degreeB, sign, out);
        case 7: return convolveLines<7>(a, degreeA, b, degreeB, sign, out);
        case 8: return convolveLines<8>(a, degreeA, b, degreeB, sign, out);
        case 9: return convolveLines<9>(a, degreeA, b, degreeB, sign, out);
        case 10: return convolveLines<10>(a, degreeA, b, degreeB, sign, out);
        case 11: return convolveLines<11>(a, degreeA, b, degreeB, sign, out);
        default: return convolveLines<0>(a, degreeA, b, degreeB, sign, out);
    }
}

void splitBernstein(const double* in, const BernsteinDegree& degree, int axis, double at, double* left, double* right) {
    assert(axis >= 0 && axis < 3);
    const int n = degree[axis];
    const int stride = axisStride(degree, axis);
    const double oneMinus = 1.0 - at;
    const bool midpoint = at == 0.5;
    forEachLine(degree, axis, [&](int start) {
        double work[kTableSize] = {};  // note: zeroed only to quiet GCC 12's may-be-uninitialized analysis
        for (int i = 0; i <= n; ++i) work[i] = in[start + i * stride];
        left[start] = work[0];
        right[start + n * stride] = work[n];
        for (int r = 1; r <= n; ++r) {
            if (midpoint)  // exact halving: the common case of the octree subdivision
                for (int i = 0; i <= n - r; ++i) work[i] = 0.5 * (work[i] + work[i + 1]);
            else
                for (int i = 0; i <= n - r; ++i) work[i] = oneMinus * work[i] + at * work[i + 1];
            left[start + r * stride] = work[0];
            right[start + (n - r) * stride] = work[n - r];
        }
    });
}

void elevateBernstein(const double* in, const BernsteinDegree& degree, int axis, double* out) {
    assert(axis >= 0 && axis < 3 && degree[axis] < kMaxBernsteinDegree);
    BernsteinDegree raised = degree;
    ++raised[axis];
    const int n = degree[axis];
    const int inStride = axisStride(degree, axis);
    const int outStride = axisStride(raised, axis);
    // Line starts correspond one to one between the two layouts: enumerate the coordinates of the other
    // two axes explicitly.
    const int other0 = axis == 0 ? 1 : 0, other1 = axis == 2 ? 1 : 2;
    for (int q = 0; q <= degree[other1]; ++q)
        for (int p = 0; p <= degree[other0]; ++p) {
            int inIndex[3], outIndex[3];
            inIndex[axis] = outIndex[axis] = 0;
            inIndex[other0] = outIndex[other0] = p;
            inIndex[other1] = outIndex[other1] = q;
            const int inStart = inIndex[0] + (degree[0] + 1) * (inIndex[1] + (degree[1] + 1) * inIndex[2]);
            const int outStart = outIndex[0] + (raised[0] + 1) * (outIndex[1] + (raised[1] + 1) * outIndex[2]);
            for (int i = 0; i <= n + 1; ++i) {
                const double alpha = static_cast<double>(i) / (n + 1);
                const double previous = i > 0 ? in[inStart + (i - 1) * inStride] : 0.0;
                const double current = i <= n ? in[inStart + i * inStride] : 0.0;
                out[outStart + i * outStride] = alpha * previous + (1.0 - alpha) * current;
            }
        }
}

double divideBernsteinByFace(const double* in, const BernsteinDegree& degree, int axis, int side, int power, double* out) {
    assert(axis >= 0 && axis < 3 && power >= 0 && power <= degree[axis]);
    const BinomialTable& table = binomials();
    const int n = degree[axis];
    BernsteinDegree reduced = degree;
    reduced[axis] -= power;
    double multiplier[kTableSize];
    double largest = 0.0;
    for (int j = 0; j <= n - power; ++j) {
        const int source = side == 0 ? j + power : j;
        multiplier[j] = table.value[n][source] / table.value[n - power][j];
        largest = std::max(largest, multiplier[j]);
    }
    const int shift = side == 0 ? power : 0;
    int c = 0;
    for (int k = 0; k <= reduced[2]; ++k)
        for (int j = 0; j <= reduced[1]; ++j)
            for (int i = 0; i <= reduced[0]; ++i, ++c) {
                int at[3] = {i, j, k};
                const int layer = at[axis];
                at[axis] += shift;
                out[c] = in[at[0] + (degree[0] + 1) * (at[1] + (degree[1] + 1) * at[2])] * multiplier[layer];
            }
    return largest;
}

double bernsteinEvaluate(const BernsteinTensor& f, const Eigen::Vector3d& x) {
    return evaluateBernstein(f.coefficients.data(), f.degree, x);
}

BernsteinTensor bernsteinProduct(const BernsteinTensor& f, const BernsteinTensor& g) {
    BernsteinTensor product({f.degree[0] + g.degree[0], f.degree[1] + g.degree[1], f.degree[2] + g.degree[2]});
    std::vector<double> fs = f.coefficients, gs = g.coefficients;
    scaleToBinomialForm(fs.data(), f.degree);
    scaleToBinomialForm(gs.data(), g.degree);
    convolveAddScaled(fs.data(), f.degree, gs.data(), g.degree, 1.0, product.coefficients.data());
    unscaleFromBinomialForm(product.coefficients.data(), product.degree);
    return product;
}

void bernsteinSplit(const BernsteinTensor& f, int axis, double at, BernsteinTensor& left, BernsteinTensor& right) {
    left = BernsteinTensor(f.degree);
    right = BernsteinTensor(f.degree);
    splitBernstein(f.coefficients.data(), f.degree, axis, at, left.coefficients.data(), right.coefficients.data());
}

BernsteinTensor bernsteinElevate(const BernsteinTensor& f, int axis) {
    BernsteinDegree raised = f.degree;
    ++raised[axis];
    BernsteinTensor out(raised);
    elevateBernstein(f.coefficients.data(), f.degree, axis, out.coefficients.data());
    return out;
}

}  // namespace sculpt::core
