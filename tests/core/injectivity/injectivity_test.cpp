#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include <omp.h>

#include <Eigen/LU>

#include "core/volume/embedding.h"
#include "core/injectivity/injectivity.h"
#include "core/injectivity/injectivity_cell.h"
#include "core/volume/lattice.h"
#include "../test_support.h"

using namespace sculpt;
using namespace sculpt::core;

namespace {

// A lattice with random degrees in [1,5] (mixed or uniform) and 1..maxSpans spans per axis, in a random box.
Lattice smallLattice(std::mt19937& rng, int maxSpans, bool mixedDegrees = true) {
    LatticeSettings settings;
    const int uniform = test::randomInt(rng, 1, 5);
    for (int a = 0; a < 3; ++a) {
        settings.degree[a] = mixedDegrees ? test::randomInt(rng, 1, 5) : uniform;
        settings.resolution[a] = settings.degree[a] + test::randomInt(rng, 1, maxSpans);
    }
    settings.padding = 0.0;
    const Eigen::Vector3d lo = test::randomVector(rng, -3.0, 1.0);
    const Eigen::Vector3d hi = lo + test::randomVector(rng, 0.5, 3.0);
    Positions corners(2, 3);
    corners.row(0) = lo.transpose();
    corners.row(1) = hi.transpose();
    Lattice lattice;
    makeLattice(settings, corners, lattice);
    return lattice;
}

Eigen::Vector3d cellSize(const Lattice& lattice) {
    return (lattice.boxMax - lattice.boxMin)
        .cwiseQuotient(Eigen::Vector3d(lattice.axes[0].spans, lattice.axes[1].spans, lattice.axes[2].spans));
}

// Moves each control point with probability `fraction` by up to `amplitude` cells along each axis.
void displaceRandomly(std::mt19937& rng, Lattice& lattice, double amplitude, double fraction) {
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const Eigen::Vector3d cell = cellSize(lattice);
    for (int c = 0; c < lattice.controlPointCount(); ++c) {
        if (unit(rng) >= fraction) continue;
        lattice.displacement.row(c) = (amplitude * cell.cwiseProduct(test::randomVector(rng, -1.0, 1.0))).transpose();
    }
}

// Least det J over an n^3 grid of lattice parameters (faces included) and where it is.
double sampledMinimum(const Lattice& lattice, int n, Eigen::Vector3d* where = nullptr) {
    double minimum = std::numeric_limits<double>::infinity();
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const Eigen::Vector3d t(i / (n - 1.0), j / (n - 1.0), k / (n - 1.0));
                const double value = jacobianDeterminant(lattice, t);
                if (value < minimum) {
                    minimum = value;
                    if (where) *where = t;
                }
            }
    return minimum;
}

// x(X0) = X0 + displacementAt(t(X0)): the deformation, for finite differences.
Eigen::Vector3d deformed(const Lattice& lattice, const Eigen::Vector3d& rest) {
    const Eigen::Vector3d t = (rest - lattice.boxMin).cwiseQuotient(lattice.boxMax - lattice.boxMin);
    return rest + displacementAt(lattice, t);
}

// A point strictly inside a random cell (local coordinates in [0.1, 0.9]), so central differences stay in
// one polynomial piece even for degree 1.
Eigen::Vector3d interiorParams(std::mt19937& rng, const Lattice& lattice) {
    Eigen::Vector3d t;
    for (int a = 0; a < 3; ++a) {
        const int span = test::randomInt(rng, 0, lattice.axes[a].spans - 1);
        t[a] = (span + std::uniform_real_distribution<double>(0.1, 0.9)(rng)) / lattice.axes[a].spans;
    }
    return t;
}

void makeRational(std::mt19937& rng, Lattice& lattice) {
    std::uniform_real_distribution<double> w(0.5, 2.0);
    for (double& weight : lattice.weights) weight = w(rng);
    lattice.rational = true;
}

}  // namespace

TEST_CASE("injectivity: mode names round-trip and unknown names are refused", "[core]") {
    for (InjectivityMode mode : {InjectivityMode::Off, InjectivityMode::Conic, InjectivityMode::Exact}) {
        InjectivityMode parsed = mode == InjectivityMode::Off ? InjectivityMode::Exact : InjectivityMode::Off;
        REQUIRE(parseInjectivityMode(injectivityModeName(mode), parsed));
        REQUIRE(parsed == mode);
    }
    InjectivityMode mode = InjectivityMode::Conic;
    for (const char* bad : {"", "Conic", "EXACT", "none", "exact ", "0"}) {
        REQUIRE_FALSE(parseInjectivityMode(bad, mode));
        REQUIRE(mode == InjectivityMode::Conic);
    }
    REQUIRE(InjectivitySettings{}.mode == InjectivityMode::Conic);
}

TEST_CASE("injectivity: det J is exactly 1 for the undeformed lattice, rational or not", "[core]") {
    std::mt19937 rng(401);
    for (int trial = 0; trial < 40; ++trial) {
        Lattice lattice = test::randomLattice(rng);
        if (trial % 2) makeRational(rng, lattice);
        for (int sample = 0; sample < 50; ++sample)
            REQUIRE(jacobianDeterminant(lattice, test::randomParams(rng)) == 1.0);
        for (InjectivityMode mode : {InjectivityMode::Conic, InjectivityMode::Exact}) {
            const InjectivityResult result = checkInjectivity(lattice, mode);
            REQUIRE(result.certified);
            REQUIRE(result.verdict == InjectivityVerdict::Certified);
            REQUIRE(result.cellsChecked == lattice.cellCount());
            REQUIRE(result.cellsDeformed == 0);
            REQUIRE(result.failingCell == -1);
            REQUIRE(result.message.empty());
        }
        const InjectivityResult exact = checkInjectivityExact(lattice);
        REQUIRE(exact.minDeterminantFound == 1.0);
        REQUIRE(exact.determinantLowerBound == 1.0);
    }
}

TEST_CASE("injectivity: jacobianDeterminant equals deformationJacobian and finite differences of displacementAt",
          "[core]") {
    std::mt19937 rng(402);
    for (int trial = 0; trial < 60; ++trial) {
        Lattice lattice = test::randomLattice(rng);
        if (trial % 3 == 2) makeRational(rng, lattice);
        test::randomDisplacement(rng, lattice, 0.03);
        const Eigen::Vector3d size = lattice.boxMax - lattice.boxMin;
        for (int sample = 0; sample < 20; ++sample) {
            const Eigen::Vector3d t = interiorParams(rng, lattice);
            const double det = jacobianDeterminant(lattice, t);
            Eigen::Vector3d displacement;
            Eigen::Matrix3d jacobian;
            deformationJacobian(lattice, t, displacement, jacobian);
            REQUIRE(det == Approx(jacobian.determinant()).epsilon(1e-12).margin(1e-12));
            // Central differences in rest space; the step is small against a cell.
            const Eigen::Vector3d rest = lattice.boxMin + t.cwiseProduct(size);
            Eigen::Matrix3d numeric;
            for (int a = 0; a < 3; ++a) {
                const double h = 1e-5 * size[a] / lattice.axes[a].spans;
                Eigen::Vector3d step = Eigen::Vector3d::Zero();
                step[a] = h;
                numeric.col(a) = (deformed(lattice, rest + step) - deformed(lattice, rest - step)) / (2.0 * h);
            }
            REQUIRE(det == Approx(numeric.determinant()).epsilon(1e-6).margin(1e-7));
        }
    }
}

TEST_CASE("injectivity: a cell's Bezier forms reproduce the displacement and det J pointwise", "[core]") {
    std::mt19937 rng(403);
    for (int trial = 0; trial < 40; ++trial) {
        Lattice lattice = smallLattice(rng, 3);
        displaceRandomly(rng, lattice, trial % 2 ? 0.3 : 1.5, 1.0);
        const CellBezierBasis basis = makeCellBezierBasis(lattice);
        const BernsteinDegree dd = determinantDegree(basis);
        for (int a = 0; a < 3; ++a) REQUIRE(dd[a] == 3 * lattice.degree[a] - 1);
        const Eigen::Vector3d cell = cellSize(lattice);
        const double displacementScale = lattice.displacement.cwiseAbs().maxCoeff();
        for (int c = 0; c < lattice.cellCount(); ++c) {
            const std::array<int, 3> ijk = {c % lattice.axes[0].spans,
                                            (c / lattice.axes[0].spans) % lattice.axes[1].spans,
                                            c / (lattice.axes[0].spans * lattice.axes[1].spans)};
            std::vector<double> bezier(3 * kMaxCellControlPoints);
            cellBezierDisplacement(lattice, basis, ijk, bezier.data());
            const BernsteinTensor det = cellJacobianDeterminantBernstein(lattice, ijk);
            REQUIRE(det.degree == dd);
            double detScale = 0.0;
            for (double value : det.coefficients) detScale = std::max(detScale, std::abs(value));
            for (int sample = 0; sample < 10; ++sample) {
                Eigen::Vector3d local = test::randomParams(rng);
                if (sample == 0) local = Eigen::Vector3d::Zero();
                const Eigen::Vector3d t((ijk[0] + local[0]) / lattice.axes[0].spans,
                                        (ijk[1] + local[1]) / lattice.axes[1].spans,
                                        (ijk[2] + local[2]) / lattice.axes[2].spans);
                const Eigen::Vector3d expected = displacementAt(lattice, t);
                const int n = bernsteinCoefficientCount(lattice.degree);
                for (int k = 0; k < 3; ++k)
                    REQUIRE(evaluateBernstein(bezier.data() + k * n, lattice.degree, local) ==
                            Approx(expected[k]).margin(1e-12 * displacementScale));
                REQUIRE(bernsteinEvaluate(det, local) ==
                        Approx(jacobianDeterminantInCell(lattice, ijk, local)).margin(1e-10 * std::max(1.0, detScale)));
            }
        }
        (void)cell;
    }
}

TEST_CASE("injectivity: undeformed and slightly displaced lattices are certified by both tests", "[core]") {
    std::mt19937 rng(404);
    for (int trial = 0; trial < 60; ++trial) {
        Lattice lattice = smallLattice(rng, 5, trial % 2 == 0);
        displaceRandomly(rng, lattice, 0.02, trial % 3 == 0 ? 0.2 : 1.0);
        const InjectivityResult conic = checkInjectivityConic(lattice);
        const InjectivityResult exact = checkInjectivityExact(lattice);
        INFO("degrees " << lattice.degree[0] << lattice.degree[1] << lattice.degree[2] << ": " << conic.message
                        << exact.message);
        REQUIRE(conic.certified);
        REQUIRE(exact.certified);
        REQUIRE(exact.determinantLowerBound > 0.0);
        REQUIRE(exact.determinantLowerBound <= exact.minDeterminantFound);
        REQUIRE(std::isnan(exact.failingParams.x()));
        REQUIRE(exact.milliseconds >= 0.0);
    }
}

TEST_CASE(
    "injectivity: against dense sampling, the exact test never certifies a fold and agrees where the conic "
    "test certifies",
    "[core]") {
    std::mt19937 rng(405);
    const double amplitudes[] = {0.05, 0.2, 0.4, 0.7, 1.0, 1.6};
    int bothCertified = 0, exactOnly = 0, folds = 0, samplingFolds = 0, foldsBetweenSamples = 0, undecided = 0;
    const int trials = 120;
    for (int trial = 0; trial < trials; ++trial) {
        Lattice lattice = smallLattice(rng, 3, trial % 4 != 0);
        displaceRandomly(rng, lattice, amplitudes[trial % 6], trial % 5 == 0 ? 0.3 : 1.0);
        Eigen::Vector3d where = Eigen::Vector3d::Zero();
        const double sampled = sampledMinimum(lattice, 20, &where);
        const InjectivityResult conic = checkInjectivityConic(lattice);
        const InjectivityResult exact = checkInjectivityExact(lattice);
        INFO("trial " << trial << ", degrees " << lattice.degree[0] << lattice.degree[1] << lattice.degree[2]
                      << ", sampled min det J " << sampled << " at " << where.transpose()
                      << "; exact: " << exact.message);
        if (sampled <= 0.0) {
            ++samplingFolds;
            REQUIRE_FALSE(exact.certified);
            REQUIRE_FALSE(conic.certified);
        }
        if (conic.certified) {
            REQUIRE(exact.certified);
            REQUIRE(sampled > 0.0);
            // Each Bernstein coefficient of det J is a positive combination of det[J_u J_v J_w] of control
            // vectors from the three cones, so a conic certificate makes every cell positive at the root.
            REQUIRE(exact.boxesExamined == exact.cellsDeformed);
        }
        if (exact.certified) {
            REQUIRE(sampled > 0.0);
            REQUIRE(exact.determinantLowerBound > 0.0);
            REQUIRE(exact.determinantLowerBound <= sampled * (1.0 + 1e-9));
            ++(conic.certified ? bothCertified : exactOnly);
        } else if (exact.verdict == InjectivityVerdict::Fold) {
            ++folds;
            if (sampled > 0.0) ++foldsBetweenSamples;
            REQUIRE(exact.failingCell >= 0);
            REQUIRE(exact.minDeterminantFound <= 0.0);
            // The reported point really has det J <= 0 (evaluated independently, on the side the test saw).
            const double atPoint = jacobianDeterminantInCell(lattice, exact.failingCellIjk, exact.failingLocalParams);
            REQUIRE(atPoint <= 1e-9);
            for (int a = 0; a < 3; ++a) {
                REQUIRE(exact.failingParams[a] >= 0.0);
                REQUIRE(exact.failingParams[a] <= 1.0);
            }
        } else {
            REQUIRE(exact.verdict == InjectivityVerdict::Undecided);
            ++undecided;
        }
    }
    // Every kind of case occurred, so the properties above were not checked vacuously.
    INFO("both " << bothCertified << ", exact only " << exactOnly << ", folds " << folds << " (between samples "
                 << foldsBetweenSamples << "), sampling folds " << samplingFolds << ", undecided " << undecided);
    REQUIRE(bothCertified >= 10);
    REQUIRE(exactOnly >= 5);
    REQUIRE(folds >= 20);
    REQUIRE(samplingFolds >= 20);
    REQUIRE(undecided <= trials / 20);
}

TEST_CASE("injectivity: a control point pushed through its neighbours folds, and the exact test says where", "[core]") {
    std::mt19937 rng(406);
    for (int trial = 0; trial < 30; ++trial) {
        LatticeSettings settings;
        for (int a = 0; a < 3; ++a) {
            settings.degree[a] = trial < 15 ? 1 + trial % 5 : test::randomInt(rng, 1, 5);
            settings.resolution[a] = settings.degree[a] + 4;
        }
        Positions corners(2, 3);
        corners << -1.0, 0.0, 2.0, 1.0, 3.0, 2.5;
        Lattice lattice;
        REQUIRE(makeLattice(settings, corners, lattice).ok);
        const int axis = trial % 3;
        const double sign = (trial / 3) % 2 ? 1.0 : -1.0;
        const int i = lattice.count[0] / 2, j = lattice.count[1] / 2, k = lattice.count[2] / 2;
        const int id = lattice.index(i, j, k);
        // Push it far enough that det J = 1 + (d / size) B_i'(t) B_j(v) B_k(w) reaches -2 on the line through the
        // point: with wide high-degree bases that is well past its neighbours (a few spacings for degree 1).
        const std::array<int, 3> ijk{i, j, k};
        double slope = 0.0, across = 1.0;
        for (int a = 0; a < 3; ++a) {
            const SplineAxis& spline = lattice.axes[a];
            if (a == axis) {
                for (int s = 0; s <= 400; ++s) {
                    double local = 0.0;
                    const int span = spline.locate(s / 400.0, local);
                    double derivative[kMaxDegree + 1];
                    spline.evaluateDerivative(span, local, derivative);
                    if (ijk[a] >= span && ijk[a] <= span + spline.degree)
                        slope = std::max(slope, std::abs(derivative[ijk[a] - span]));
                }
            } else {
                across *= basisReference(spline, spline.greville[ijk[a]])[ijk[a]];
            }
        }
        const double push = 3.0 / (slope * across) * (lattice.boxMax[axis] - lattice.boxMin[axis]);
        const double spacing = (lattice.axes[axis].greville[ijk[axis] + 1] - lattice.axes[axis].greville[ijk[axis]]) *
                               (lattice.boxMax[axis] - lattice.boxMin[axis]);
        REQUIRE(push > spacing);  // through its neighbour
        lattice.displacement(id, axis) = sign * push;

        const InjectivityResult exact = checkInjectivityExact(lattice);
        const InjectivityResult conic = checkInjectivityConic(lattice);
        INFO("degrees " << lattice.degree[0] << lattice.degree[1] << lattice.degree[2] << ", axis " << axis << ": "
                        << exact.message);
        REQUIRE(sampledMinimum(lattice, 20) < 0.0);  // the fold is real
        REQUIRE(exact.verdict == InjectivityVerdict::Fold);
        REQUIRE_FALSE(exact.certified);
        REQUIRE_FALSE(conic.certified);
        REQUIRE(conic.verdict == InjectivityVerdict::NotCertified);
        REQUIRE(jacobianDeterminantInCell(lattice, exact.failingCellIjk, exact.failingLocalParams) <= 1e-9);
        // The fold is inside the moved point's support.
        const std::vector<int> influenced = cellsInfluencedBy(lattice, {id});
        REQUIRE(std::find(influenced.begin(), influenced.end(), exact.failingCell) != influenced.end());
        // From a smooth lattice the global parameters give the same point.
        if (lattice.degree[0] > 1 && lattice.degree[1] > 1 && lattice.degree[2] > 1)
            REQUIRE(jacobianDeterminant(lattice, exact.failingParams) <= 1e-9);
        REQUIRE_FALSE(exact.message.empty());
        // Repeated (parallel) runs report the same place.
        const InjectivityResult again = checkInjectivityExact(lattice);
        REQUIRE(again.failingCell == exact.failingCell);
        REQUIRE(again.failingParams == exact.failingParams);
    }
}

TEST_CASE("injectivity: at the subdivision limit the exact test says undecided, never injective", "[core]") {
    std::mt19937 rng(407);
    int found = 0;
    for (int trial = 0; trial < 400 && found < 5; ++trial) {
        Lattice lattice = smallLattice(rng, 3);
        displaceRandomly(rng, lattice, trial % 2 ? 0.2 : 0.3, 1.0);
        const InjectivityResult full = checkInjectivityExact(lattice);
        // Wanted: injective, but only provable after subdividing.
        if (!full.certified || full.boxesExamined == full.cellsDeformed) continue;
        ++found;
        ExactOptions shallow;
        shallow.maxSubdivisionDepth = 0;
        const InjectivityResult limited = checkInjectivityExact(lattice, shallow);
        REQUIRE_FALSE(limited.certified);
        REQUIRE(limited.verdict == InjectivityVerdict::Undecided);
        REQUIRE(limited.failingCell >= 0);
        REQUIRE(limited.minDeterminantFound > 0.0);  // no fold was seen
        REQUIRE(limited.message.find("undecided") != std::string::npos);
        ExactOptions budget;
        budget.maxBoxesPerCell = 1;
        REQUIRE(checkInjectivityExact(lattice, budget).verdict == InjectivityVerdict::Undecided);
        // A positive tolerance above the least det J turns it into a fold report.
        ExactOptions strict;
        strict.tolerance = full.minDeterminantFound * 1.01;
        const InjectivityResult tolerant = checkInjectivityExact(lattice, strict);
        REQUIRE_FALSE(tolerant.certified);
        REQUIRE(tolerant.verdict == InjectivityVerdict::Fold);
        REQUIRE(tolerant.minDeterminantFound <= strict.tolerance);
    }
    REQUIRE(found == 5);
}

TEST_CASE("injectivity: checking only the cells a change influences gives the same verdict", "[core]") {
    std::mt19937 rng(408);
    for (int trial = 0; trial < 20; ++trial) {
        LatticeSettings settings;
        const int p = 1 + trial % 5;
        settings.degree = {p, p, p};
        settings.resolution = {p + 5, p + 4, p + 6};
        Lattice lattice;
        REQUIRE(makeLattice(settings, test::randomPoints(rng, 20, {0, 0, 0}, {2, 1, 1}), lattice).ok);
        // Fold near one corner: one control point pushed far.
        const int id = lattice.index(1, 1, 1);
        const Eigen::Vector3d cell = cellSize(lattice);
        lattice.displacement.row(id) = (5.0 * cell).transpose();
        const std::vector<int> changed = cellsInfluencedBy(lattice, {id});
        std::vector<int> others;
        for (int c = 0; c < lattice.cellCount(); ++c)
            if (!std::binary_search(changed.begin(), changed.end(), c)) others.push_back(c);

        for (InjectivityMode mode : {InjectivityMode::Conic, InjectivityMode::Exact}) {
            const InjectivityResult full = checkInjectivity(lattice, mode);
            const InjectivityResult local = checkInjectivity(lattice, mode, changed);
            REQUIRE_FALSE(full.certified);
            REQUIRE(local.verdict == full.verdict);
            REQUIRE(local.failingCell == full.failingCell);
            REQUIRE(local.cellsChecked == static_cast<int>(changed.size()));
            if (!others.empty()) {
                const InjectivityResult rest = checkInjectivity(lattice, mode, others);
                REQUIRE(rest.certified);
                REQUIRE(rest.cellsDeformed == 0);
            }
            // Off looks at nothing.
            REQUIRE(checkInjectivity(lattice, InjectivityMode::Off).certified);
            REQUIRE(checkInjectivity(lattice, InjectivityMode::Off, changed).certified);
        }
    }
}

TEST_CASE("injectivity: rational cells are reported unsupported, uniform weights count as polynomial", "[core]") {
    std::mt19937 rng(409);
    for (int trial = 0; trial < 10; ++trial) {
        Lattice lattice = smallLattice(rng, 4);
        const int id = lattice.index(lattice.count[0] / 2, lattice.count[1] / 2, lattice.count[2] / 2);
        // Uniform weight 2: R_ijk = B_i B_j B_k, so the polynomial tests apply and certify a small change.
        for (double& w : lattice.weights) w = 2.0;
        lattice.rational = true;
        displaceRandomly(rng, lattice, 0.02, 1.0);
        REQUIRE(checkInjectivityConic(lattice).certified);
        REQUIRE(checkInjectivityExact(lattice).certified);
        // One differing weight: the cells around it are not certified (the tests do not cover them).
        lattice.weights[id] = 3.0;
        const std::vector<int> around = cellsInfluencedBy(lattice, {id});
        for (const InjectivityResult& result : {checkInjectivityConic(lattice), checkInjectivityExact(lattice)}) {
            REQUIRE_FALSE(result.certified);
            REQUIRE(result.verdict == InjectivityVerdict::Unsupported);
            REQUIRE(std::find(around.begin(), around.end(), result.failingCell) != around.end());
            REQUIRE(result.message.find("weights") != std::string::npos);
        }
        // Cells away from it are still checked normally.
        std::vector<int> away;
        for (int c = 0; c < lattice.cellCount(); ++c)
            if (!std::binary_search(around.begin(), around.end(), c)) away.push_back(c);
        if (!away.empty()) REQUIRE(checkInjectivityExact(lattice, {}, away).certified);
        // Undeformed, any weights: det J == 1, certified.
        lattice.displacement.setZero();
        REQUIRE(checkInjectivityExact(lattice).certified);
    }
}

TEST_CASE("injectivity: per-vertex det J for the colour map", "[core]") {
    std::mt19937 rng(410);
    Positions points;
    Lattice lattice = test::randomLattice(rng, true, &points);
    test::randomDisplacement(rng, lattice, 0.02);
    const Eigen::Vector3d lo = lattice.boxMin - 0.2 * (lattice.boxMax - lattice.boxMin);
    const Eigen::Vector3d hi = lattice.boxMax + 0.2 * (lattice.boxMax - lattice.boxMin);
    const Positions rest = test::randomPoints(rng, 2000, lo, hi);
    std::vector<double> dets;
    vertexJacobianDeterminants(lattice, rest, dets);
    REQUIRE(dets.size() == 2000);
    int inside = 0;
    for (int v = 0; v < 2000; ++v) {
        Eigen::Vector3d t;
        if (restParameters(lattice, rest.row(v).transpose(), t)) {
            ++inside;
            REQUIRE(dets[v] == jacobianDeterminant(lattice, t));
        } else {
            REQUIRE(dets[v] == 1.0);
        }
    }
    REQUIRE(inside > 100);
    REQUIRE(inside < 2000);
}

TEST_CASE("injectivity: results do not depend on the number of threads", "[core]") {
    std::mt19937 rng(411);
    const int threads = omp_get_max_threads();
    for (int trial = 0; trial < 6; ++trial) {
        // Big enough for the parallel paths (hundreds of cells), some folded, some not.
        LatticeSettings settings;
        settings.resolution = {14, 13, 12};
        Lattice lattice;
        REQUIRE(makeLattice(settings, test::randomPoints(rng, 10, {0, 0, 0}, {1, 2, 1}), lattice).ok);
        displaceRandomly(rng, lattice, trial % 2 ? 0.05 : 0.4, trial < 4 ? 1.0 : 0.05);
        omp_set_num_threads(1);
        const InjectivityResult conicSerial = checkInjectivityConic(lattice);
        const InjectivityResult exactSerial = checkInjectivityExact(lattice);
        omp_set_num_threads(std::max(2, threads));
        const InjectivityResult conicParallel = checkInjectivityConic(lattice);
        const InjectivityResult exactParallel = checkInjectivityExact(lattice);
        omp_set_num_threads(threads);
        REQUIRE(conicSerial.verdict == conicParallel.verdict);
        REQUIRE(conicSerial.failingCell == conicParallel.failingCell);
        REQUIRE(exactSerial.verdict == exactParallel.verdict);
        REQUIRE(exactSerial.failingCell == exactParallel.failingCell);
        REQUIRE(exactSerial.minDeterminantFound == exactParallel.minDeterminantFound);
        if (exactSerial.verdict == InjectivityVerdict::Fold)
            REQUIRE(exactSerial.failingParams == exactParallel.failingParams);
        if (exactSerial.certified) REQUIRE(exactSerial.determinantLowerBound == exactParallel.determinantLowerBound);
    }
}

TEST_CASE("injectivity: non-finite displacements are never certified", "[core]") {
    std::mt19937 rng(412);
    for (int trial = 0; trial < 12; ++trial) {
        const double bad =
            trial % 3 == 0 ? std::nan("") : (trial % 3 == 1 ? 1.0 : -1.0) * std::numeric_limits<double>::infinity();
        Lattice lattice = smallLattice(rng, 3);
        displaceRandomly(rng, lattice, 0.01, 1.0);
        lattice.displacement(test::randomInt(rng, 0, lattice.controlPointCount() - 1), trial % 3) = bad;
        const InjectivityResult conic = checkInjectivityConic(lattice);
        const InjectivityResult exact = checkInjectivityExact(lattice);
        REQUIRE_FALSE(conic.certified);
        REQUIRE_FALSE(exact.certified);
        REQUIRE(exact.verdict == InjectivityVerdict::Undecided);
        REQUIRE(exact.message.find("non-finite") != std::string::npos);
    }
}

TEST_CASE("injectivity: boundaryFixed tells whether the box faces stay in place", "[core]") {
    std::mt19937 rng(413);
    LatticeSettings settings;
    settings.resolution = {7, 6, 8};
    settings.pinLayers = 1;
    Lattice lattice;
    REQUIRE(makeLattice(settings, test::randomPoints(rng, 10, {0, 0, 0}, {1, 1, 1}), lattice).ok);
    const Eigen::Vector3d cell = cellSize(lattice);
    for (int c = 0; c < lattice.controlPointCount(); ++c)  // the solver's rule: pinned points never move
        if (!lattice.pinned[c])
            lattice.displacement.row(c) = (0.02 * cell.cwiseProduct(test::randomVector(rng, -1, 1))).transpose();
    REQUIRE(checkInjectivityConic(lattice).boundaryFixed);
    REQUIRE(checkInjectivityExact(lattice).boundaryFixed);
    lattice.displacement(lattice.index(0, 3, 3), 0) = 0.01 * cell[0];  // a face point moves
    REQUIRE_FALSE(checkInjectivityConic(lattice).boundaryFixed);
    REQUIRE_FALSE(checkInjectivityExact(lattice).boundaryFixed);
}
