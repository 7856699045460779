#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>

#include "core/spline/bspline_basis.h"

using namespace sculpt::core;

TEST_CASE("bspline_basis: per-span polynomials equal Cox-de Boor everywhere", "[core]") {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (int p = kMinDegree; p <= kMaxDegree; ++p) {
        for (int count : {p + 1, p + 2, p + 5, 17, 64}) {
            const SplineAxis axis = makeSplineAxis(count, p);
            for (int sample = 0; sample < 200; ++sample) {
                double u = unit(rng);
                if (sample == 0) u = 0.0;
                if (sample == 1) u = 1.0;
                if (sample == 2) u = 1.0 / axis.spans;  // on an interior knot
                const std::vector<double> reference = basisReference(axis, u);
                double local = 0.0;
                const int span = axis.locate(u, local);
                double values[kMaxDegree + 1];
                axis.evaluate(span, local, values);
                std::vector<double> dense(count, 0.0);
                for (int i = 0; i <= p; ++i) dense[span + i] = values[i];
                double sum = 0.0;
                for (int i = 0; i < count; ++i) {
                    REQUIRE(dense[i] == Approx(reference[i]).margin(1e-13));
                    // Horner rounding of the degree-5 monomial form near a span end leaves values of order 1e-14 where
                    // the basis is exactly 0 (measured worst: -1.3e-14); anything larger would be a wrong coefficient.
                    REQUIRE(dense[i] >= -5e-14);
                    sum += dense[i];
                }
                REQUIRE(sum == Approx(1.0).margin(1e-13));  // partition of unity
            }
        }
    }
}

TEST_CASE("bspline_basis: Greville abscissae give linear precision", "[core]") {
    std::mt19937 rng(12);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (int p = kMinDegree; p <= kMaxDegree; ++p)
        for (int count = p + 1; count <= kMaxControlPointsPerAxis; count += 7) {
            const SplineAxis axis = makeSplineAxis(count, p);
            for (int sample = 0; sample < 100; ++sample) {
                const double u = sample == 0 ? 0.0 : sample == 1 ? 1.0 : unit(rng);
                double local = 0.0;
                const int span = axis.locate(u, local);
                double values[kMaxDegree + 1];
                axis.evaluate(span, local, values);
                double image = 0.0;
                for (int i = 0; i <= p; ++i) image += axis.greville[span + i] * values[i];
                REQUIRE(image == Approx(u).margin(1e-14));
            }
        }
}

TEST_CASE("bspline_basis: derivative matches central differences", "[core]") {
    std::mt19937 rng(13);
    std::uniform_real_distribution<double> unit(0.05, 0.95);
    for (int p = kMinDegree; p <= kMaxDegree; ++p) {
        const SplineAxis axis = makeSplineAxis(p + 6, p);
        for (int sample = 0; sample < 50; ++sample) {
            const double u = unit(rng);
            const double h = 1e-6;
            const std::vector<double> plus = basisReference(axis, u + h), minus = basisReference(axis, u - h);
            double local = 0.0;
            const int span = axis.locate(u, local);
            double derivative[kMaxDegree + 1];
            axis.evaluateDerivative(span, local, derivative);
            for (int i = 0; i <= p; ++i) {
                // Basis functions of degree 1 have kinks at knots; skip samples that straddle one.
                double l1 = 0.0, l2 = 0.0;
                if (axis.locate(u + h, l1) != span || axis.locate(u - h, l2) != span) continue;
                REQUIRE(derivative[i] == Approx((plus[span + i] - minus[span + i]) / (2 * h)).margin(1e-5));
            }
        }
    }
}

namespace {

// A random clamped knot vector of `count` points of degree p: interior knots drawn at random, some repeated (up
// to the degree), sorted.
std::vector<double> randomKnots(std::mt19937& rng, int count, int p) {
    std::uniform_real_distribution<double> unit(0.02, 0.98);
    std::vector<double> interior;
    while (static_cast<int>(interior.size()) < count - p - 1) {
        const double k = unit(rng);
        const int repeat = std::min<int>(std::uniform_int_distribution<int>(1, p)(rng), count - p - 1 - static_cast<int>(interior.size()));
        for (int r = 0; r < repeat; ++r) interior.push_back(k);
    }
    std::sort(interior.begin(), interior.end());
    std::vector<double> knots(static_cast<size_t>(p) + 1, 0.0);
    knots.insert(knots.end(), interior.begin(), interior.end());
    knots.insert(knots.end(), static_cast<size_t>(p) + 1, 1.0);
    return knots;
}

}  // namespace

TEST_CASE("bspline_basis: general knot vectors in the lattice parameter equal Cox-de Boor in the knot parameter", "[core]") {
    std::mt19937 rng(14);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    int axes = 0;
    for (int p = kMinDegree; p <= kMaxDegree; ++p)
        for (int count : {p + 1, p + 2, p + 4, 11, 30}) {
            const std::vector<double> knots = randomKnots(rng, count, p);
            REQUIRE(splineKnotsProblem(knots, count, p).empty());
            const SplineAxis axis = makeSplineAxisFromKnots(knots, p);
            ++axes;
            REQUIRE(axis.count == count);
            REQUIRE_FALSE(axis.uniform());
            REQUIRE(axis.breaks.front() == 0.0);
            REQUIRE(axis.breaks.back() == 1.0);
            for (int sample = 0; sample < 100; ++sample) {
                const double u = sample == 0 ? 0.0 : sample == 1 ? 1.0 : unit(rng);
                const double tau = axis.knotParameter(u);
                REQUIRE(axis.latticeParameter(tau) == Approx(u).margin(1e-12));
                const std::vector<double> reference = basisReference(axis, tau);
                double local = 0.0;
                const int span = axis.locate(u, local);
                double values[kMaxDegree + 1], derivative[kMaxDegree + 1];
                axis.evaluate(span, local, values);
                axis.evaluateDerivative(span, local, derivative);
                std::vector<double> dense(static_cast<size_t>(count), 0.0);
                for (int i = 0; i <= p; ++i) dense[static_cast<size_t>(axis.first(span) + i)] = values[i];
                double sum = 0.0, image = 0.0;
                for (int i = 0; i < count; ++i) {
                    REQUIRE(dense[static_cast<size_t>(i)] == Approx(reference[static_cast<size_t>(i)]).margin(1e-12));
                    sum += dense[static_cast<size_t>(i)];
                    image += axis.greville[static_cast<size_t>(i)] * dense[static_cast<size_t>(i)];
                }
                REQUIRE(sum == Approx(1.0).margin(1e-13));
                REQUIRE(image == Approx(tau).margin(1e-13));  // linear precision in the knot parameter
                // d/du = d/dtau * dtau/du: the Cox-de Boor difference in tau times the span's width ratio.
                const double width = axis.breaks[static_cast<size_t>(span) + 1] - axis.breaks[static_cast<size_t>(span)];
                const double h = 1e-6 * width;
                if (local < 0.01 || local > 0.99) continue;
                const std::vector<double> plus = basisReference(axis, tau + h), minus = basisReference(axis, tau - h);
                for (int i = 0; i <= p; ++i)
                    REQUIRE(derivative[i] == Approx((plus[static_cast<size_t>(axis.first(span) + i)] - minus[static_cast<size_t>(axis.first(span) + i)]) /
                                                    (2 * h) * width * axis.spans)
                                                 .epsilon(1e-5)
                                                 .margin(1e-4));
                // supportSpans agrees with where each function is non-zero.
                for (int i = 0; i <= p; ++i) {
                    int lo = 0, hi = 0;
                    axis.supportSpans(axis.first(span) + i, lo, hi);
                    REQUIRE(lo <= span);
                    REQUIRE(span <= hi);
                }
            }
        }
    REQUIRE(axes == 25);
}

TEST_CASE("bspline_basis: bad knot vectors are named", "[core]") {
    auto problem = [](std::vector<double> knots, int count, int degree) { return splineKnotsProblem(knots, count, degree); };
    REQUIRE(problem({0, 0, 0.5, 1, 1}, 3, 1).empty());
    REQUIRE(problem({0, 0, 0.5, 1}, 3, 1).find("knots") != std::string::npos);                // too few
    REQUIRE(problem({0, 0, 0.6, 0.5, 1, 1}, 4, 1).find("smaller") != std::string::npos);      // decreasing
    REQUIRE(problem({0, 0.1, 0.5, 1, 1}, 3, 1).find("clamped") != std::string::npos);          // not clamped
    REQUIRE(problem({0, 0, 0.5, 0.5, 1, 1}, 4, 1).find("repeated 2 times") != std::string::npos);
    REQUIRE(problem({0, 0, std::nan(""), 1, 1}, 3, 1).find("not finite") != std::string::npos);
    REQUIRE(problem({0, 0, 0.5, 1, 1}, 3, 9).find("degree") != std::string::npos);
}
