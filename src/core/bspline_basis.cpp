// Clamped uniform B-spline bases as per-span polynomials.
// The per-span coefficients are obtained by running the triangular Cox-de Boor scheme
// (Piegl & Tiller, The NURBS Book, A2.2) on polynomials in the local coordinate instead of numbers:
// every quantity in it is a polynomial of degree <= p in x, and the divisors are knot differences only.
#include "core/bspline_basis.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace sculpt::core {

namespace {

using Poly = std::vector<double>;  // coefficients of x^0..x^p

}  // namespace

bool splineAxisCountValid(int count, int degree, int multiplicity) {
    return degree >= kMinDegree && degree <= kMaxDegree && multiplicity >= 1 && multiplicity <= degree &&
           count >= degree + 1 && count <= kMaxControlPointsPerAxis && (count - 1 - degree) % multiplicity == 0;
}

void SplineAxis::supportSpans(int f, int& lo, int& hi) const {
    // f is non-zero on span s iff first(s) <= f <= first(s) + p.
    lo = std::max(0, (f - degree + multiplicity - 1) / multiplicity);
    if (f - degree < 0) lo = 0;
    hi = std::min(spans - 1, f / multiplicity);
}

SplineAxis makeSplineAxis(int count, int degree, int multiplicity) {
    assert(splineAxisCountValid(count, degree, multiplicity));
    SplineAxis axis;
    axis.count = count;
    axis.degree = degree;
    axis.multiplicity = multiplicity;
    axis.spans = (count - 1 - degree) / multiplicity + 1;
    const int p = degree;
    const int spans = axis.spans;

    // Knot k: p+1 zeros, then interior knot j/spans repeated `multiplicity` times, then p+1 ones.
    auto knotNumerator = [&](int k) { return k <= p ? 0 : std::min(spans, (k - p - 1) / multiplicity + 1); };
    axis.knots.resize(static_cast<size_t>(count + p + 1));
    for (int i = 0; i < count + p + 1; ++i) axis.knots[i] = static_cast<double>(knotNumerator(i)) / spans;
    axis.greville.resize(count);
    for (int i = 0; i < count; ++i) {
        // note: summing integer knot numerators keeps xi exact-ish: xi_i = (sum of interior indices) / (p * spans)
        int numerator = 0;
        for (int k = 1; k <= p; ++k) numerator += knotNumerator(i + k);
        axis.greville[i] = static_cast<double>(numerator) / (static_cast<double>(p) * spans);
    }

    const int n = p + 1;
    axis.coefficients.assign(static_cast<size_t>(spans) * n * n, 0.0);
    for (int s = 0; s < spans; ++s) {
        const int knotSpan = axis.first(s) + p;  // t_{knotSpan} <= u < t_{knotSpan+1}
        const double spanStart = static_cast<double>(s) / spans;
        const double width = 1.0 / spans;
        // u as a polynomial of x: u = spanStart + width * x
        auto uMinus = [&](double knot) { return Poly{spanStart - knot, width}; };
        std::vector<Poly> basis(n, Poly(n, 0.0));
        basis[0][0] = 1.0;
        std::vector<Poly> left(n), right(n);
        for (int j = 1; j <= p; ++j) {
            left[j] = uMinus(axis.knots[knotSpan + 1 - j]);               // u - t_{span+1-j}
            Poly r = uMinus(axis.knots[knotSpan + j]);                    // u - t_{span+j}
            right[j] = Poly{-r[0], -r[1]};                                // t_{span+j} - u
            Poly saved(n, 0.0);
            for (int r0 = 0; r0 < j; ++r0) {
                const double denominator = axis.knots[knotSpan + r0 + 1] - axis.knots[knotSpan + 1 - j + r0];
                Poly temp = basis[r0];
                for (double& c : temp) c /= denominator;
                Poly next = saved;
                // next += right[r0+1] * temp; saved = left[j-r0] * temp (degree grows by one per level)
                Poly newSaved(n, 0.0);
                for (int k = 0; k < n; ++k) {
                    if (temp[k] == 0.0) continue;
                    next[k] += right[r0 + 1][0] * temp[k];
                    if (k + 1 < n) next[k + 1] += right[r0 + 1][1] * temp[k];
                    newSaved[k] += left[j - r0][0] * temp[k];
                    if (k + 1 < n) newSaved[k + 1] += left[j - r0][1] * temp[k];
                }
                basis[r0] = next;
                saved = newSaved;
            }
            basis[j] = saved;
        }
        for (int i = 0; i < n; ++i)
            for (int k = 0; k < n; ++k) axis.coefficients[(static_cast<size_t>(s) * n + i) * n + k] = basis[i][k];
    }
    return axis;
}

int SplineAxis::locate(double u, double& local) const {
    const double scaled = u * spans;
    // note: truncation is floor for u >= 0 (and much cheaper than a libm call); u < 0 clamps to span 0.
    int span = scaled > 0.0 ? static_cast<int>(scaled) : 0;
    span = std::min(span, spans - 1);
    local = scaled - span;
    return span;
}

void SplineAxis::evaluate(int span, double local, double* values) const {
    const int n = degree + 1;
    const double* c = coefficients.data() + static_cast<size_t>(span) * n * n;
    for (int i = 0; i < n; ++i) {
        const double* ci = c + i * n;
        double value = ci[degree];
        for (int k = degree - 1; k >= 0; --k) value = value * local + ci[k];  // Horner
        values[i] = value;
    }
}

void SplineAxis::evaluateDerivative(int span, double local, double* derivatives) const {
    const int n = degree + 1;
    const double* c = coefficients.data() + static_cast<size_t>(span) * n * n;
    for (int i = 0; i < n; ++i) {
        const double* ci = c + i * n;
        double value = degree * ci[degree];
        for (int k = degree - 1; k >= 1; --k) value = value * local + k * ci[k];
        derivatives[i] = value * spans;  // dx/du = spans
    }
}

std::vector<double> basisReference(const SplineAxis& axis, double u) {
    // Textbook recursion over all functions: N_{i,0} = [t_i <= u < t_{i+1}], with the last
    // non-empty interval closed on the right so u == 1 is covered.
    const std::vector<double>& t = axis.knots;
    const int p = axis.degree;
    const int m = static_cast<int>(t.size()) - 1;
    std::vector<double> N(m, 0.0);
    for (int i = 0; i < m; ++i) {
        const bool lastNonEmpty = (t[i] < t[i + 1]) && (t[i + 1] == 1.0);
        if ((t[i] <= u && u < t[i + 1]) || (lastNonEmpty && u == 1.0)) N[i] = 1.0;
    }
    for (int k = 1; k <= p; ++k) {
        for (int i = 0; i + k < m; ++i) {
            double value = 0.0;
            if (t[i + k] != t[i]) value += (u - t[i]) / (t[i + k] - t[i]) * N[i];
            if (t[i + k + 1] != t[i + 1]) value += (t[i + k + 1] - u) / (t[i + k + 1] - t[i + 1]) * N[i + 1];
            N[i] = value;
        }
    }
    N.resize(axis.count);
    return N;
}

}  // namespace sculpt::core
