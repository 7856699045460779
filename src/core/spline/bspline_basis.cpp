// Clamped uniform B-spline bases as per-span polynomials.
// The per-span coefficients are obtained by running the triangular Cox-de Boor scheme
// (Piegl & Tiller, The NURBS Book, A2.2) on polynomials in the local coordinate instead of numbers:
// every quantity in it is a polynomial of degree <= p in x, and the divisors are knot differences only.
#include "core/spline/bspline_basis.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <string>

namespace sculpt::core {

namespace {

using Poly = std::vector<double>;  // coefficients of x^0..x^p

}  // namespace

bool splineAxisCountValid(int count, int degree, int multiplicity) {
    return degree >= kMinDegree && degree <= kMaxDegree && multiplicity >= 1 && multiplicity <= degree &&
           count >= degree + 1 && count <= kMaxControlPointsPerAxis && (count - 1 - degree) % multiplicity == 0;
}

void SplineAxis::supportSpans(int f, int& lo, int& hi) const {
    // f is non-zero on span s iff first(s) <= f <= first(s) + p; first is non-decreasing in s.
    lo = 0;
    while (lo < spans - 1 && first(lo) + degree < f) ++lo;
    hi = spans - 1;
    while (hi > 0 && first(hi) > f) --hi;
}

namespace {

// Fills spans, breaks, firstFunction and the per-span polynomial coefficients from axis.knots and degree.
// The per-span coefficients come from the triangular Cox-de Boor scheme (The NURBS Book, A2.2) run on
// polynomials in the local coordinate x: tau = breaks[s] + width * x on span s.
void fillSpans(SplineAxis& axis) {
    const int p = axis.degree;
    const std::vector<double>& knots = axis.knots;
    axis.breaks.clear();
    axis.firstFunction.clear();
    for (int k = p; k < axis.count; ++k)
        if (knots[k] < knots[k + 1]) {  // knot span [t_k, t_{k+1}) is not empty; basis functions k-p .. k live on it
            axis.breaks.push_back(knots[k]);
            axis.firstFunction.push_back(k - p);
        }
    axis.breaks.push_back(knots[axis.count]);
    axis.spans = static_cast<int>(axis.firstFunction.size());
    const int spans = axis.spans;
    const int n = p + 1;
    axis.coefficients.assign(static_cast<size_t>(spans) * n * n, 0.0);
    for (int s = 0; s < spans; ++s) {
        const int knotSpan = axis.first(s) + p;  // t_{knotSpan} <= tau < t_{knotSpan+1}
        // note: uniform axes keep the width 1/spans exactly (not a difference of two rounded knots), so their
        // coefficients are those the box lattice always had.
        const double spanStart = axis.breaks[static_cast<size_t>(s)];
        const double width = axis.uniform() ? 1.0 / spans : axis.breaks[static_cast<size_t>(s) + 1] - spanStart;
        // tau as a polynomial of x: tau = spanStart + width * x
        auto uMinus = [&](double knot) { return Poly{spanStart - knot, width}; };
        std::vector<Poly> basis(n, Poly(n, 0.0));
        basis[0][0] = 1.0;
        std::vector<Poly> left(n), right(n);
        for (int j = 1; j <= p; ++j) {
            left[j] = uMinus(knots[knotSpan + 1 - j]);               // tau - t_{span+1-j}
            Poly r = uMinus(knots[knotSpan + j]);                    // tau - t_{span+j}
            right[j] = Poly{-r[0], -r[1]};                           // t_{span+j} - tau
            Poly saved(n, 0.0);
            for (int r0 = 0; r0 < j; ++r0) {
                const double denominator = knots[knotSpan + r0 + 1] - knots[knotSpan + 1 - j + r0];
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
    axis.greville.resize(axis.count);
    if (axis.uniform()) return;  // makeSplineAxis sets the uniform Greville points from integer knot numerators
    for (int i = 0; i < axis.count; ++i) {
        double sum = 0.0;
        for (int k = 1; k <= p; ++k) sum += knots[i + k];
        axis.greville[i] = sum / p;
    }
}

}  // namespace

SplineAxis makeSplineAxis(int count, int degree, int multiplicity) {
    assert(splineAxisCountValid(count, degree, multiplicity));
    SplineAxis axis;
    axis.count = count;
    axis.degree = degree;
    axis.multiplicity = multiplicity;
    const int spans = (count - 1 - degree) / multiplicity + 1;
    const int p = degree;

    // Knot k: p+1 zeros, then interior knot j/spans repeated `multiplicity` times, then p+1 ones.
    auto knotNumerator = [&](int k) { return k <= p ? 0 : std::min(spans, (k - p - 1) / multiplicity + 1); };
    axis.knots.resize(static_cast<size_t>(count + p + 1));
    for (int i = 0; i < count + p + 1; ++i) axis.knots[i] = static_cast<double>(knotNumerator(i)) / spans;
    fillSpans(axis);
    assert(axis.spans == spans);
    for (int i = 0; i < count; ++i) {
        // note: summing integer knot numerators keeps xi exact-ish: xi_i = (sum of interior indices) / (p * spans)
        int numerator = 0;
        for (int k = 1; k <= p; ++k) numerator += knotNumerator(i + k);
        axis.greville[i] = static_cast<double>(numerator) / (static_cast<double>(p) * spans);
    }
    return axis;
}

std::string splineKnotsProblem(const std::vector<double>& knots, int count, int degree) {
    if (degree < kMinDegree || degree > kMaxDegree)
        return "degree " + std::to_string(degree) + " is outside [" + std::to_string(kMinDegree) + ", " + std::to_string(kMaxDegree) + "]";
    if (count < degree + 1 || count > kMaxControlPointsPerAxis)
        return std::to_string(count) + " control points of degree " + std::to_string(degree) + " (needs " + std::to_string(degree + 1) +
               " to " + std::to_string(kMaxControlPointsPerAxis) + ")";
    const size_t expected = static_cast<size_t>(count + degree + 1);
    if (knots.size() != expected)
        return std::to_string(knots.size()) + " knots; " + std::to_string(count) + " control points of degree " + std::to_string(degree) +
               " need " + std::to_string(expected);
    for (size_t k = 0; k < knots.size(); ++k) {
        if (!std::isfinite(knots[k])) return "knot " + std::to_string(k) + " is not finite";
        if (k > 0 && knots[k] < knots[k - 1]) return "knot " + std::to_string(k) + " is smaller than the knot before it";
    }
    for (int k = 0; k <= degree; ++k)
        if (knots[static_cast<size_t>(k)] != 0.0 || knots[expected - 1 - static_cast<size_t>(k)] != 1.0)
            return "the knot vector is not clamped: its first " + std::to_string(degree + 1) + " knots must be 0 and its last " +
                   std::to_string(degree + 1) + " must be 1";
    for (size_t k = static_cast<size_t>(degree) + 1; k + degree + 1 < expected; ++k) {
        if (!(knots[k] > 0.0 && knots[k] < 1.0)) return "interior knot " + std::to_string(k) + " is not inside (0, 1)";
        size_t repeat = 1;
        while (k + repeat + degree + 1 < expected && knots[k + repeat] == knots[k]) ++repeat;
        if (static_cast<int>(repeat) > degree)
            return "interior knot " + std::to_string(knots[k]) + " is repeated " + std::to_string(repeat) + " times (at most the degree, " +
                   std::to_string(degree) + ", or the volume splits apart)";
        k += repeat - 1;
    }
    return {};
}

SplineAxis makeSplineAxisFromKnots(const std::vector<double>& knots, int degree) {
    SplineAxis axis;
    axis.count = static_cast<int>(knots.size()) - degree - 1;
    axis.degree = degree;
    assert(splineKnotsProblem(knots, axis.count, degree).empty());
    axis.multiplicity = 0;
    axis.knots = knots;
    fillSpans(axis);
    return axis;
}

double SplineAxis::knotParameter(double u) const {
    double local = 0.0;
    if (uniform()) return std::clamp(u, 0.0, 1.0);
    const int s = locate(std::clamp(u, 0.0, 1.0), local);
    const double lo = breaks[static_cast<size_t>(s)], hi = breaks[static_cast<size_t>(s) + 1];
    return lo + (hi - lo) * local;
}

double SplineAxis::latticeParameter(double tau) const {
    tau = std::clamp(tau, 0.0, 1.0);
    if (uniform()) return tau;
    const int s = std::min(spans - 1, static_cast<int>(std::upper_bound(breaks.begin(), breaks.end(), tau) - breaks.begin()) - 1);
    const double lo = breaks[static_cast<size_t>(s)], hi = breaks[static_cast<size_t>(s) + 1];
    return (s + (tau - lo) / (hi - lo)) / spans;
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
