#include <catch2/catch.hpp>

#include <random>

#include "core/bspline_basis.h"

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
