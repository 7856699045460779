#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "core/spline/bernstein.h"
#include "../test_support.h"

using namespace sculpt;
using namespace sculpt::core;

namespace {

// Independent oracle: the Bernstein basis from its definition C(n,i) x^i (1-x)^(n-i), with C(n,i) from the
// product formula (not the table under test).
double binomialByProduct(int n, int k) {
    double c = 1.0;
    for (int i = 1; i <= k; ++i) c = c * (n - k + i) / i;
    return c;
}

double bernsteinBasis(int n, int i, double x) {
    return binomialByProduct(n, i) * std::pow(x, i) * std::pow(1.0 - x, n - i);
}

double directEvaluate(const BernsteinTensor& f, const Eigen::Vector3d& x) {
    double sum = 0.0;
    for (int k = 0; k <= f.degree[2]; ++k)
        for (int j = 0; j <= f.degree[1]; ++j)
            for (int i = 0; i <= f.degree[0]; ++i)
                sum += f.at(i, j, k) * bernsteinBasis(f.degree[0], i, x[0]) * bernsteinBasis(f.degree[1], j, x[1]) *
                       bernsteinBasis(f.degree[2], k, x[2]);
    return sum;
}

BernsteinTensor randomTensor(std::mt19937& rng, int maxDegree) {
    BernsteinTensor f(
        {test::randomInt(rng, 0, maxDegree), test::randomInt(rng, 0, maxDegree), test::randomInt(rng, 0, maxDegree)});
    std::uniform_real_distribution<double> d(-1.0, 1.0);
    for (double& c : f.coefficients) c = d(rng);
    return f;
}

// Sum of |coefficients|: bounds |f| on the box, a scale for tolerances.
double magnitude(const BernsteinTensor& f) {
    double m = 0.0;
    for (double c : f.coefficients) m += std::abs(c);
    return m;
}

}  // namespace

TEST_CASE("bernstein: binomial table matches the product formula", "[core]") {
    for (int n = 0; n <= kMaxBernsteinDegree; ++n) {
        double rowSum = 0.0;
        for (int k = 0; k <= n; ++k) {
            REQUIRE(binomial(n, k) == binomialByProduct(n, k));
            rowSum += binomial(n, k);
        }
        REQUIRE(rowSum == std::ldexp(1.0, n));
        REQUIRE(binomial(n, -1) == 0.0);
        REQUIRE(binomial(n, n + 1) == 0.0);
    }
}

TEST_CASE("bernstein: monomial to Bernstein conversion preserves the polynomial", "[core]") {
    std::mt19937 rng(301);
    std::uniform_real_distribution<double> d(-2.0, 2.0), unit(0.0, 1.0);
    for (int degree = 0; degree <= 14; ++degree)
        for (int trial = 0; trial < 20; ++trial) {
            double monomial[kMaxBernsteinDegree + 1], bernstein[kMaxBernsteinDegree + 1];
            for (int k = 0; k <= degree; ++k) monomial[k] = d(rng);
            monomialToBernstein(monomial, degree, bernstein);
            for (int sample = 0; sample < 10; ++sample) {
                const double x = sample == 0 ? 0.0 : (sample == 1 ? 1.0 : unit(rng));
                double horner = monomial[degree];
                for (int k = degree - 1; k >= 0; --k) horner = horner * x + monomial[k];
                double direct = 0.0;
                for (int l = 0; l <= degree; ++l) direct += bernstein[l] * bernsteinBasis(degree, l, x);
                REQUIRE(evaluateBernstein1(bernstein, degree, x) == Approx(horner).margin(1e-12 * (1 << degree)));
                REQUIRE(direct == Approx(horner).margin(1e-12 * (1 << degree)));
            }
        }
}

TEST_CASE("bernstein: de Casteljau evaluation equals the basis sum, corners interpolate, convex hull bounds",
          "[core]") {
    std::mt19937 rng(302);
    for (int trial = 0; trial < 200; ++trial) {
        const BernsteinTensor f = randomTensor(rng, 8);
        const double scale = magnitude(f);
        for (int sample = 0; sample < 20; ++sample) {
            const Eigen::Vector3d x = test::randomParams(rng);
            const double value = bernsteinEvaluate(f, x);
            REQUIRE(value == Approx(directEvaluate(f, x)).margin(1e-13 * scale));
            double lo = 0.0, hi = 0.0;
            bernsteinCoefficientRange(f.coefficients.data(), f.degree, lo, hi);
            REQUIRE(value >= lo - 1e-14 * scale);
            REQUIRE(value <= hi + 1e-14 * scale);
        }
        for (int corner = 0; corner < 8; ++corner) {
            const Eigen::Vector3d x(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1);
            const double expected =
                f.at((corner & 1) * f.degree[0], ((corner >> 1) & 1) * f.degree[1], ((corner >> 2) & 1) * f.degree[2]);
            REQUIRE(bernsteinEvaluate(f, x) == Approx(expected).margin(1e-15 * scale));
        }
    }
}

TEST_CASE("bernstein: product of two tensors evaluates to the product of their values", "[core]") {
    std::mt19937 rng(303);
    for (int trial = 0; trial < 200; ++trial) {
        const BernsteinTensor f = randomTensor(rng, 7), g = randomTensor(rng, 7);
        const BernsteinTensor fg = bernsteinProduct(f, g);
        for (int a = 0; a < 3; ++a) REQUIRE(fg.degree[a] == f.degree[a] + g.degree[a]);
        const double scale = magnitude(f) * magnitude(g);
        for (int sample = 0; sample < 20; ++sample) {
            const Eigen::Vector3d x = test::randomParams(rng);
            REQUIRE(directEvaluate(fg, x) == Approx(directEvaluate(f, x) * directEvaluate(g, x)).margin(1e-12 * scale));
        }
        // Commutative, and the constant 1 is the identity.
        const BernsteinTensor gf = bernsteinProduct(g, f);
        for (size_t c = 0; c < fg.coefficients.size(); ++c)
            REQUIRE(gf.coefficients[c] == Approx(fg.coefficients[c]).margin(1e-14 * scale));
        BernsteinTensor one({0, 0, 0});
        one.coefficients[0] = 1.0;
        const BernsteinTensor f1 = bernsteinProduct(f, one);
        for (size_t c = 0; c < f.coefficients.size(); ++c)
            REQUIRE(f1.coefficients[c] == Approx(f.coefficients[c]).margin(1e-15 * scale));
    }
}

TEST_CASE("bernstein: the raw kernels accumulate signed products (a*b - c*d)", "[core]") {
    std::mt19937 rng(304);
    for (int trial = 0; trial < 50; ++trial) {
        const BernsteinDegree da{test::randomInt(rng, 0, 4), test::randomInt(rng, 0, 4), test::randomInt(rng, 0, 4)};
        const BernsteinDegree db{test::randomInt(rng, 0, 4), test::randomInt(rng, 0, 4), test::randomInt(rng, 0, 4)};
        BernsteinTensor a(da), b(db), c(da), d(db);
        std::uniform_real_distribution<double> u(-1.0, 1.0);
        for (BernsteinTensor* t : {&a, &b, &c, &d})
            for (double& x : t->coefficients) x = u(rng);
        BernsteinTensor out({da[0] + db[0], da[1] + db[1], da[2] + db[2]});
        BernsteinTensor as = a, bs = b, cs = c, ds = d;
        scaleToBinomialForm(as.coefficients.data(), da);
        scaleToBinomialForm(bs.coefficients.data(), db);
        scaleToBinomialForm(cs.coefficients.data(), da);
        scaleToBinomialForm(ds.coefficients.data(), db);
        convolveAddScaled(as.coefficients.data(), da, bs.coefficients.data(), db, 1.0, out.coefficients.data());
        convolveAddScaled(cs.coefficients.data(), da, ds.coefficients.data(), db, -1.0, out.coefficients.data());
        unscaleFromBinomialForm(out.coefficients.data(), out.degree);
        for (int sample = 0; sample < 10; ++sample) {
            const Eigen::Vector3d x = test::randomParams(rng);
            const double expected =
                directEvaluate(a, x) * directEvaluate(b, x) - directEvaluate(c, x) * directEvaluate(d, x);
            REQUIRE(directEvaluate(out, x) == Approx(expected).margin(1e-11));
        }
        // Scaling then unscaling gives the coefficients back.
        unscaleFromBinomialForm(as.coefficients.data(), da);
        for (size_t i = 0; i < a.coefficients.size(); ++i)
            REQUIRE(as.coefficients[i] == Approx(a.coefficients[i]).margin(1e-15));
    }
}

TEST_CASE("bernstein: de Casteljau subdivision gives the two pieces of the polynomial", "[core]") {
    std::mt19937 rng(305);
    std::uniform_real_distribution<double> split(0.05, 0.95);
    for (int trial = 0; trial < 200; ++trial) {
        const BernsteinTensor f = randomTensor(rng, 14);
        const double scale = magnitude(f);
        const int axis = trial % 3;
        const double at = trial % 2 ? 0.5 : split(rng);
        BernsteinTensor left, right;
        bernsteinSplit(f, axis, at, left, right);
        REQUIRE(left.degree == f.degree);
        for (int sample = 0; sample < 20; ++sample) {
            const Eigen::Vector3d x = test::randomParams(rng);
            Eigen::Vector3d xl = x, xr = x;
            xl[axis] = at * x[axis];
            xr[axis] = at + (1.0 - at) * x[axis];
            REQUIRE(bernsteinEvaluate(left, x) == Approx(directEvaluate(f, xl)).margin(1e-12 * scale));
            REQUIRE(bernsteinEvaluate(right, x) == Approx(directEvaluate(f, xr)).margin(1e-12 * scale));
        }
        // The pieces meet at the split: left's last layer equals right's first layer exactly.
        for (int k = 0; k <= f.degree[2]; ++k)
            for (int j = 0; j <= f.degree[1]; ++j)
                for (int i = 0; i <= f.degree[0]; ++i) {
                    int l[3] = {i, j, k}, r[3] = {i, j, k};
                    if (l[axis] != 0) continue;
                    l[axis] = f.degree[axis];
                    REQUIRE(left.at(l[0], l[1], l[2]) == right.at(r[0], r[1], r[2]));
                }
    }
}

TEST_CASE("bernstein: degree elevation keeps the polynomial and tightens the hull", "[core]") {
    std::mt19937 rng(306);
    for (int trial = 0; trial < 200; ++trial) {
        const BernsteinTensor f = randomTensor(rng, 8);
        const double scale = magnitude(f);
        const int axis = trial % 3;
        const BernsteinTensor raised = bernsteinElevate(f, axis);
        REQUIRE(raised.degree[axis] == f.degree[axis] + 1);
        for (int sample = 0; sample < 20; ++sample) {
            const Eigen::Vector3d x = test::randomParams(rng);
            REQUIRE(directEvaluate(raised, x) == Approx(directEvaluate(f, x)).margin(1e-13 * scale));
        }
        double lo = 0.0, hi = 0.0, raisedLo = 0.0, raisedHi = 0.0;
        bernsteinCoefficientRange(f.coefficients.data(), f.degree, lo, hi);
        bernsteinCoefficientRange(raised.coefficients.data(), raised.degree, raisedLo, raisedHi);
        REQUIRE(raisedLo >= lo - 1e-15);  // elevated coefficients are convex combinations of the old ones
        REQUIRE(raisedHi <= hi + 1e-15);
    }
}

TEST_CASE("bernstein: dividing by a face factor undoes the product with x^m or (1-x)^m", "[core][bernstein]") {
    std::mt19937 rng(77);
    for (int trial = 0; trial < 60; ++trial) {
        BernsteinTensor g({test::randomInt(rng, 0, 6), test::randomInt(rng, 0, 6), test::randomInt(rng, 0, 6)});
        for (double& c : g.coefficients) c = std::uniform_real_distribution<double>(-1.0, 1.0)(rng);
        const int axis = test::randomInt(rng, 0, 2), side = test::randomInt(rng, 0, 1), power = test::randomInt(rng, 1, 3);
        // The factor as a Bernstein polynomial of degree `power` along the axis: x^m = b_m^m, (1-x)^m = b_0^m.
        BernsteinDegree factorDegree{0, 0, 0};
        factorDegree[axis] = power;
        BernsteinTensor factor(factorDegree);
        factor.coefficients[side == 0 ? power : 0] = 1.0;
        const BernsteinTensor f = bernsteinProduct(factor, g);
        BernsteinTensor quotient(g.degree);
        const double gain = divideBernsteinByFace(f.coefficients.data(), f.degree, axis, side, power, quotient.coefficients.data());
        REQUIRE(gain >= 1.0);
        for (size_t c = 0; c < g.coefficients.size(); ++c) REQUIRE(quotient.coefficients[c] == Approx(g.coefficients[c]).margin(1e-12));
    }
}
