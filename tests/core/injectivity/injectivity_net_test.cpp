// Injectivity tests on net lattices (lattices of any shape, lattice_net.h): the chunk determinant in
// Bernstein form against pointwise evaluation, the verdicts against dense sampling of det(dQ/dt), the
// collapsed axis and poles of cylinders and spheres, and det J per point and per vertex.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>

#include <Eigen/Geometry>
#include <Eigen/LU>

#include "core/deform/direct_manipulation.h"
#include "core/volume/embedding.h"
#include "core/injectivity/injectivity.h"
#include "core/injectivity/injectivity_cell.h"
#include "core/injectivity/injectivity_net.h"
#include "core/volume/lattice.h"
#include "core/volume/lattice_net.h"
#include "../test_support.h"

using namespace sculpt;
using namespace sculpt::core;

namespace {

constexpr double kPi = 3.14159265358979323846;

Lattice latticeOf(const LatticeNet& net) {
    LatticeSettings settings;
    settings.volume = std::make_shared<LatticeNet>(net);
    Lattice lattice;
    REQUIRE(makeLatticeInBox(settings, {}, {}, lattice));
    return lattice;
}

Eigen::Matrix3d randomRotation(std::mt19937& rng) {
    std::normal_distribution<double> normal;
    Eigen::Quaterniond q(normal(rng), normal(rng), normal(rng), normal(rng));
    q.normalize();
    return q.toRotationMatrix();
}

// A parallelepiped in a random orientation, with a little shear.
LatticeNet randomParallelepiped(std::mt19937& rng) {
    Eigen::Matrix3d edges = randomRotation(rng) * test::randomVector(rng, 0.5, 2.0).asDiagonal();
    edges.col(2) += 0.2 * edges.col(0);
    std::array<int, 3> chunks{}, degree{};
    for (int a = 0; a < 3; ++a) {
        chunks[a] = test::randomInt(rng, 1, 3);
        degree[a] = test::randomInt(rng, 1, 3);
    }
    LatticeNet net;
    REQUIRE(makeParallelepipedNet(test::randomVector(rng, -2.0, 2.0), edges, chunks, degree, net));
    return net;
}

LatticeNet randomCylinder(std::mt19937& rng) {
    LatticeNet net;
    const std::array<int, 3> chunks{test::randomInt(rng, 1, 2), test::randomInt(rng, 3, 5), test::randomInt(rng, 1, 2)};
    const std::array<int, 2> degree{test::randomInt(rng, 1, 3), test::randomInt(rng, 1, 3)};
    REQUIRE(makeCylinderNet(test::randomVector(rng, -1.0, 1.0), randomRotation(rng).col(0),
                            std::uniform_real_distribution<double>(0.5, 2.0)(rng), std::uniform_real_distribution<double>(0.5, 3.0)(rng),
                            chunks, degree, net));
    return net;
}

LatticeNet randomSphere(std::mt19937& rng) {
    LatticeNet net;
    const std::array<int, 3> chunks{test::randomInt(rng, 1, 2), test::randomInt(rng, 3, 4), test::randomInt(rng, 2, 3)};
    REQUIRE(makeSphereNet(test::randomVector(rng, -1.0, 1.0), randomRotation(rng).col(2),
                          std::uniform_real_distribution<double>(0.5, 2.0)(rng), chunks, test::randomInt(rng, 1, 3), net));
    return net;
}

// An extrusion of a rectangle, slanted, with random weights half the time (a rational net without welds).
LatticeNet randomExtrusion(std::mt19937& rng) {
    const std::array<int, 2> chunks{test::randomInt(rng, 1, 3), test::randomInt(rng, 1, 3)};
    const std::array<int, 2> degree{test::randomInt(rng, 1, 3), test::randomInt(rng, 1, 3)};
    PlanarNet profile = makeRectangleNet(Eigen::Vector2d(-1.0, -0.5), Eigen::Vector2d(1.0, 0.7), chunks, degree);
    if (test::randomInt(rng, 0, 1))
        for (double& w : profile.weights) w = std::uniform_real_distribution<double>(0.5, 2.0)(rng);
    const Eigen::Matrix3d frame = randomRotation(rng);
    LatticeNet net;
    REQUIRE(makeExtrusionNet(profile, test::randomVector(rng, -1.0, 1.0), frame.col(0), frame.col(1),
                             1.5 * frame.col(2) + 0.3 * frame.col(0), test::randomInt(rng, 1, 3), test::randomInt(rng, 1, 3), net));
    return net;
}

LatticeNet randomNet(std::mt19937& rng, int kind) {
    switch (kind % 4) {
        case 0: return randomParallelepiped(rng);
        case 1: return randomCylinder(rng);
        case 2: return randomSphere(rng);
        default: return randomExtrusion(rng);
    }
}

// Gives every slot of a weld group its representative's displacement (welded points act as one).
void weldDisplacements(Lattice& lattice) {
    for (int s = 0; s < lattice.controlPointCount(); ++s) lattice.displacement.row(s) = lattice.displacement.row(lattice.representative(s));
}

// A typical control point spacing of the net.
double spacing(const LatticeNet& net) {
    return net.diagonal() / std::max({net.count[0], net.count[1], net.count[2]});
}

// Moves each weld group with probability `fraction` by up to `amplitude` spacings per axis.
void displaceRandomly(std::mt19937& rng, Lattice& lattice, double amplitude, double fraction) {
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const double step = amplitude * spacing(*lattice.tensorNet());
    for (int s = 0; s < lattice.controlPointCount(); ++s)
        if (lattice.representative(s) == s && unit(rng) < fraction)
            lattice.displacement.row(s) = step * test::randomVector(rng, -1.0, 1.0).transpose();
    weldDisplacements(lattice);
}

Positions movedPoints(const Lattice& lattice) { return lattice.tensorNet()->rest + lattice.displacement; }

// The least det(dQ/dt) over n^3 points strictly inside each chunk (never on a face, so a collapsed axis at
// rest does not count), by evaluateNetVolume, and where it is.
double sampledMinimum(const Lattice& lattice, int n, Eigen::Vector3d* where = nullptr) {
    const Positions points = movedPoints(lattice);
    const std::array<int, 3> spans = lattice.spans();
    double minimum = std::numeric_limits<double>::infinity();
    for (int w = 0; w < spans[2]; ++w)
        for (int v = 0; v < spans[1]; ++v)
            for (int u = 0; u < spans[0]; ++u)
                for (int k = 0; k < n; ++k)
                    for (int j = 0; j < n; ++j)
                        for (int i = 0; i < n; ++i) {
                            const Eigen::Vector3d t((u + (i + 0.5) / n) / spans[0], (v + (j + 0.5) / n) / spans[1],
                                                    (w + (k + 0.5) / n) / spans[2]);
                            Eigen::Vector3d q;
                            Eigen::Matrix3d d;
                            evaluateNetVolume(*lattice.tensorNet(), points, t, q, &d);
                            if (d.determinant() < minimum) {
                                minimum = d.determinant();
                                if (where) *where = t;
                            }
                        }
    return minimum;
}

// The chunk's homogeneous volume H = (W Q, W) and its t-derivatives at local coordinates, from the basis
// functions directly (independent of the Bezier machinery).
void homogeneousAt(const Lattice& lattice, const Positions& points, const std::array<int, 3>& chunk, const Eigen::Vector3d& local,
                   Eigen::Vector4d& h, Eigen::Matrix<double, 4, 3>& dh) {
    double value[3][kMaxDegree + 1], derivative[3][kMaxDegree + 1];
    for (int a = 0; a < 3; ++a) {
        lattice.axes[a].evaluate(chunk[a], local[a], value[a]);
        lattice.axes[a].evaluateDerivative(chunk[a], local[a], derivative[a]);
    }
    h.setZero();
    dh.setZero();
    for (int k = 0; k <= lattice.degree[2]; ++k)
        for (int j = 0; j <= lattice.degree[1]; ++j)
            for (int i = 0; i <= lattice.degree[0]; ++i) {
                const int s = lattice.index(lattice.axes[0].first(chunk[0]) + i, lattice.axes[1].first(chunk[1]) + j,
                                            lattice.axes[2].first(chunk[2]) + k);
                Eigen::Vector4d p;
                p << lattice.weights[s] * points.row(s).transpose(), lattice.weights[s];
                h += value[0][i] * value[1][j] * value[2][k] * p;
                dh.col(0) += derivative[0][i] * value[1][j] * value[2][k] * p;
                dh.col(1) += value[0][i] * derivative[1][j] * value[2][k] * p;
                dh.col(2) += value[0][i] * value[1][j] * derivative[2][k] * p;
            }
}

// The factor the chunk determinant was divided by, at local x.
double dividedFactor(const NetChunkDeterminantInfo& info, const Eigen::Vector3d& x) {
    double factor = 1.0;
    for (int a = 0; a < 3; ++a) factor *= std::pow(x[a], info.divided[a][0]) * std::pow(1.0 - x[a], info.divided[a][1]);
    return factor;
}

std::array<int, 3> randomChunk(std::mt19937& rng, const Lattice& lattice) {
    return {test::randomInt(rng, 0, lattice.axes[0].spans - 1), test::randomInt(rng, 0, lattice.axes[1].spans - 1),
            test::randomInt(rng, 0, lattice.axes[2].spans - 1)};
}

int chunkIndex(const Lattice& lattice, const std::array<int, 3>& c) {
    return c[0] + lattice.axes[0].spans * (c[1] + lattice.axes[1].spans * c[2]);
}

}  // namespace

TEST_CASE("injectivity net: the chunk determinant in Bernstein form is det4[Hu Hv Hw H] = W^4 det(dQ/dt)", "[injectivity][net]") {
    std::mt19937 rng(1001);
    int rationalChunks = 0, polynomialChunks = 0, dividedChunks = 0;
    for (int trial = 0; trial < 48; ++trial) {
        Lattice lattice = latticeOf(randomNet(rng, trial));
        displaceRandomly(rng, lattice, 0.4, 0.7);
        const Positions points = movedPoints(lattice);
        for (int c = 0; c < 3; ++c) {
            const std::array<int, 3> chunk = randomChunk(rng, lattice);
            NetChunkDeterminantInfo info;
            const BernsteinTensor det = netChunkDeterminantBernstein(lattice, chunk, true, &info);
            REQUIRE(info.weldsHold);
            (info.rational ? rationalChunks : polynomialChunks)++;
            for (int a = 0; a < 3; ++a) dividedChunks += info.divided[a][0] + info.divided[a][1] > 0 ? 1 : 0;
            for (int a = 0; a < 3; ++a)
                REQUIRE(info.degree[a] == (info.rational ? 4 : 3) * lattice.degree[a] - 1 - info.divided[a][0] - info.divided[a][1]);
            for (int sample = 0; sample < 20; ++sample) {
                const Eigen::Vector3d x = test::randomVector(rng, 0.05, 0.95);
                Eigen::Vector4d h;
                Eigen::Matrix<double, 4, 3> dh;
                homogeneousAt(lattice, points, chunk, x, h, dh);
                Eigen::Matrix4d m;
                m << dh, h;
                // det(dQ/dt) from the quotient rule, by evaluateNetVolume.
                Eigen::Vector3d t, q;
                for (int a = 0; a < 3; ++a) t[a] = (chunk[a] + x[a]) / lattice.axes[a].spans;
                Eigen::Matrix3d d;
                evaluateNetVolume(*lattice.tensorNet(), points, t, q, &d);
                const double w4 = std::pow(h[3], 4);
                const double expected = info.rational ? m.determinant() : d.determinant();
                const double value = bernsteinEvaluate(det, x) * dividedFactor(info, x);
                const double scale = std::pow(dh.cwiseAbs().maxCoeff(), 3) * std::max(1.0, std::abs(h[3]));
                REQUIRE(value == Approx(expected).margin(1e-9 * scale));
                if (info.rational) REQUIRE(m.determinant() == Approx(w4 * d.determinant()).margin(1e-9 * scale));
                if (std::abs(expected) > 1e-6 * scale) REQUIRE((value > 0.0) == (expected > 0.0));
            }
        }
    }
    REQUIRE(rationalChunks > 20);
    REQUIRE(polynomialChunks > 20);
    REQUIRE(dividedChunks > 10);
}

TEST_CASE("injectivity net: verdicts agree with dense sampling of det(dQ/dt) on random nets", "[injectivity][net]") {
    std::mt19937 rng(1002);
    int certified = 0, folds = 0;
    for (int trial = 0; trial < 64; ++trial) {
        Lattice lattice = latticeOf(randomNet(rng, trial));
        const double amplitude = std::array<double, 4>{0.05, 0.3, 0.8, 2.0}[(trial / 4) % 4];
        displaceRandomly(rng, lattice, amplitude, 0.5);
        const InjectivityResult exact = checkInjectivityExact(lattice);
        const double sampled = sampledMinimum(lattice, 5);
        INFO("trial " << trial << " kind " << lattice.tensorNet()->kind << " verdict " << injectivityVerdictName(exact.verdict) << ": "
                      << exact.message << "; sampled min " << sampled);
        REQUIRE(exact.verdict != InjectivityVerdict::Unsupported);
        if (exact.certified) {
            REQUIRE(sampled > 0.0);
            REQUIRE(exact.minDeterminantFound > 0.0);
            ++certified;
        }
        if (sampled < 0.0) REQUIRE(exact.verdict == InjectivityVerdict::Fold);
        if (exact.verdict == InjectivityVerdict::Fold) {
            ++folds;
            REQUIRE(exact.failingCell >= 0);
            REQUIRE(exact.failingParams.allFinite());
            REQUIRE(jacobianDeterminantInCell(lattice, exact.failingCellIjk, exact.failingLocalParams) <= 1e-9);
            REQUIRE_FALSE(exact.message.empty());
            // Independently: det(dQ/dt) by evaluateNetVolume just inside the failing chunk, next to the point.
            Eigen::Vector3d t;
            for (int a = 0; a < 3; ++a)
                t[a] = (exact.failingCellIjk[a] + std::clamp(exact.failingLocalParams[a], 1e-9, 1.0 - 1e-9)) / lattice.axes[a].spans;
            Eigen::Vector3d q;
            Eigen::Matrix3d d;
            evaluateNetVolume(*lattice.tensorNet(), movedPoints(lattice), t, q, &d);
            REQUIRE(d.determinant() <= 1e-6 * std::pow(lattice.tensorNet()->diagonal(), 3));
        }
        // The conic mode runs the exact test on nets.
        const InjectivityResult conic = checkInjectivityConic(lattice);
        REQUIRE(conic.verdict == exact.verdict);
        REQUIRE(conic.failingCell == exact.failingCell);
    }
    REQUIRE(certified > 15);
    REQUIRE(folds > 10);
}

TEST_CASE("injectivity net: pushing an interior control point through its neighbours folds", "[injectivity][net]") {
    std::mt19937 rng(1003);
    for (int trial = 0; trial < 16; ++trial) {
        LatticeNet net;
        if (trial % 2 == 0) {
            REQUIRE(makeParallelepipedNet(test::randomVector(rng, -1.0, 1.0), randomRotation(rng) * Eigen::Vector3d(1.0, 1.5, 2.0).asDiagonal(),
                                          {2, 2, 2}, {2, 2, 2}, net));
        } else {
            REQUIRE(makeCylinderNet(Eigen::Vector3d::Zero(), randomRotation(rng).col(0), 1.0, 2.0, {2, 4, 2}, {2, 2}, net));
        }
        Lattice lattice = latticeOf(net);
        // An interior slot (not welded), pushed two grid steps along its own first axis' direction.
        const int i = 1 + trial % 2, j = 2, k = 2;
        const int s = net.slot(i, j, k);
        REQUIRE(lattice.representative(s) == s);
        const Eigen::Vector3d along = (net.rest.row(net.slot(i + 1, j, k)) - net.rest.row(net.slot(i - 1, j, k))).transpose();
        lattice.displacement.row(s) = (2.0 * along).transpose();
        const InjectivityResult exact = checkInjectivityExact(lattice);
        INFO(net.kind << ": " << exact.message);
        REQUIRE(exact.verdict == InjectivityVerdict::Fold);
        REQUIRE(exact.minDeterminantFound < 0.0);
        REQUIRE(sampledMinimum(lattice, 5) < 0.0);
        REQUIRE(checkInjectivity(lattice, InjectivityMode::Conic).verdict == InjectivityVerdict::Fold);
        // Only the chunks the slot reaches are looked at, and they give the same verdict.
        const std::vector<int> influenced = cellsInfluencedBy(lattice, {s});
        REQUIRE(checkInjectivityExact(lattice, {}, influenced).verdict == InjectivityVerdict::Fold);
        std::vector<int> others;
        for (int c = 0; c < lattice.cellCount(); ++c)
            if (!std::binary_search(influenced.begin(), influenced.end(), c)) others.push_back(c);
        if (!others.empty()) {
            const InjectivityResult away = checkInjectivityExact(lattice, {}, others);
            REQUIRE(away.certified);
            REQUIRE(away.cellsDeformed == 0);
        }
    }
}

TEST_CASE("injectivity net: cylinders and spheres at rest and moved rigidly are certified with their axis and poles", "[injectivity][net]") {
    std::mt19937 rng(1004);
    for (int trial = 0; trial < 24; ++trial) {
        Lattice lattice = latticeOf(trial % 2 ? randomCylinder(rng) : randomSphere(rng));
        INFO(lattice.tensorNet()->kind << " trial " << trial);
        // At rest nothing is deformed: certified without looking.
        REQUIRE(checkInjectivityExact(lattice).certified);
        // The rest chunks themselves: the face-divided determinant is positive on every closed chunk.
        const NetChunkBasis basis = makeNetChunkBasis(lattice);
        NetChunkWorkspace work;
        std::vector<double> coefficients(kMaxNetDeterminantCoefficients);
        int divided = 0;
        for (int chunk = 0; chunk < lattice.cellCount(); ++chunk) {
            const std::array<int, 3> c{chunk % lattice.axes[0].spans, (chunk / lattice.axes[0].spans) % lattice.axes[1].spans,
                                       chunk / (lattice.axes[0].spans * lattice.axes[1].spans)};
            NetChunkDeterminantInfo info;
            netChunkDeterminantBernstein(lattice, basis, c, false, work, coefficients.data(), info);
            REQUIRE(info.weldsHold);
            for (int a = 0; a < 3; ++a) divided += info.divided[a][0] + info.divided[a][1];
            // Corner values (the polynomial interpolates its corners) are positive, faces included.
            double lo = 0.0, hi = 0.0;
            bernsteinCoefficientRange(coefficients.data(), info.degree, lo, hi);
            for (int corner = 0; corner < 8; ++corner)
                REQUIRE(evaluateBernstein(coefficients.data(), info.degree,
                                          Eigen::Vector3d(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1)) > 0.0);
        }
        REQUIRE(divided > 0);
        // A rigid motion moves every control point (every chunk is checked) and keeps det J == 1.
        const Eigen::Matrix3d rotation = randomRotation(rng);
        const Eigen::Vector3d shift = test::randomVector(rng, -1.0, 1.0);
        for (int s = 0; s < lattice.controlPointCount(); ++s)
            lattice.displacement.row(s) =
                (rotation * lattice.tensorNet()->rest.row(s).transpose() + shift - lattice.tensorNet()->rest.row(s).transpose()).transpose();
        const InjectivityResult moved = checkInjectivityExact(lattice);
        INFO(moved.message);
        REQUIRE(moved.certified);
        REQUIRE(moved.cellsDeformed == lattice.cellCount());
        REQUIRE(moved.minDeterminantFound == Approx(1.0).epsilon(1e-6));
        REQUIRE(checkInjectivityConic(lattice).certified);
    }
}

TEST_CASE("injectivity net: the cylinder's axis moved along itself stays certified and pushed through the wall folds", "[injectivity][net]") {
    LatticeNet net;
    const Eigen::Vector3d axis = Eigen::Vector3d(0.3, -0.2, 1.0).normalized();
    REQUIRE(makeCylinderNet(Eigen::Vector3d(0.5, 0.1, -0.3), axis, 1.0, 3.0, {2, 4, 3}, {2, 2}, net));
    Lattice lattice = latticeOf(net);
    const int middle = net.count[2] / 2;
    const int axisSlot = net.slot(0, 0, middle);
    REQUIRE(net.weldedTo[axisSlot] == axisSlot);
    std::vector<int> group;
    for (int j = 0; j < net.count[1]; ++j) group.push_back(net.slot(0, j, middle));
    for (int s : group) REQUIRE(net.weldedTo[s] == axisSlot);
    const double zStep = 3.0 / (net.count[2] - 1);
    SECTION("along the axis") {
        for (double amount : {0.1, 0.3}) {
            ControlDelta delta;
            delta.indices = {axisSlot};
            delta.deltas = (amount * zStep * axis).transpose();
            expandWelds(lattice, delta);
            REQUIRE(delta.indices.size() == group.size());
            lattice.displacement.setZero();
            applyControlDelta(lattice, delta);
            const InjectivityResult exact = checkInjectivityExact(lattice);
            INFO(exact.message);
            REQUIRE(exact.certified);
            REQUIRE(sampledMinimum(lattice, 6) > 0.0);
            REQUIRE(exact.cellsDeformed > 0);
        }
    }
    SECTION("through the outer wall") {
        const Eigen::Vector3d across = (net.rest.row(net.slot(net.count[0] - 1, 0, middle)) - net.rest.row(axisSlot)).transpose();
        for (int s : group) lattice.displacement.row(s) = (1.5 * across).transpose();
        const InjectivityResult exact = checkInjectivityExact(lattice);
        INFO(exact.message);
        REQUIRE(exact.verdict == InjectivityVerdict::Fold);
        REQUIRE(sampledMinimum(lattice, 6) < 0.0);
    }
    SECTION("welded points that part are reported, not certified") {
        lattice.displacement.row(group[1]) = (0.1 * axis).transpose();
        const InjectivityResult exact = checkInjectivityExact(lattice);
        REQUIRE_FALSE(exact.certified);
        REQUIRE(exact.verdict == InjectivityVerdict::Undecided);
        REQUIRE(exact.message.find("welded") != std::string::npos);
    }
}

TEST_CASE("injectivity net: det J per point is det(dQ/dt) / det(dQ0/dt) and matches finite differences", "[injectivity][net]") {
    std::mt19937 rng(1005);
    for (int trial = 0; trial < 24; ++trial) {
        Lattice lattice = latticeOf(randomNet(rng, trial));
        displaceRandomly(rng, lattice, 0.2, 0.6);
        const LatticeNet& net = *lattice.tensorNet();
        const Positions points = movedPoints(lattice);
        for (int sample = 0; sample < 20; ++sample) {
            const std::array<int, 3> chunk = randomChunk(rng, lattice);
            const Eigen::Vector3d local = test::randomVector(rng, 0.2, 0.8);
            Eigen::Vector3d t;
            for (int a = 0; a < 3; ++a) t[a] = (chunk[a] + local[a]) / lattice.axes[a].spans;
            const double det = jacobianDeterminant(lattice, t);
            REQUIRE(det == Approx(jacobianDeterminantInCell(lattice, chunk, local)).epsilon(1e-12));
            // The same from deformationJacobian.
            Eigen::Vector3d displacement;
            Eigen::Matrix3d jacobian;
            deformationJacobian(lattice, t, displacement, jacobian);
            REQUIRE(det == Approx(jacobian.determinant()).epsilon(1e-9).margin(1e-12));
            // And by central differences of x(X0) = X0 + D(t(X0)) (t by freezing).
            Eigen::Vector3d rest;
            evaluateNetVolume(net, net.rest, t, rest);
            const double h = 1e-5 * net.diagonal();
            Eigen::Matrix3d numeric;
            bool frozen = true;
            for (int a = 0; a < 3; ++a) {
                Eigen::Vector3d plus = rest, minus = rest, tp, tm;
                plus[a] += h;
                minus[a] -= h;
                frozen = frozen && restParameters(lattice, plus, tp) && restParameters(lattice, minus, tm);
                if (!frozen) break;
                numeric.col(a) = ((plus + displacementAt(lattice, tp)) - (minus + displacementAt(lattice, tm))) / (2.0 * h);
            }
            if (frozen) REQUIRE(det == Approx(numeric.determinant()).epsilon(1e-4).margin(1e-6));
        }
        // A chunk with no moved control point: exactly 1.
        lattice.displacement.setZero();
        REQUIRE(jacobianDeterminant(lattice, test::randomParams(rng)) == 1.0);
    }
}

TEST_CASE("injectivity net: vertex det J uses frozen parameters and is finite on the axis and poles", "[injectivity][net]") {
    std::mt19937 rng(1006);
    for (int trial = 0; trial < 12; ++trial) {
        Lattice lattice = latticeOf(trial % 2 ? randomCylinder(rng) : randomSphere(rng));
        const LatticeNet& net = *lattice.tensorNet();
        // Vertices: random points of the volume, plus the collapsed ones (axis, centre, poles) and one outside.
        Positions rest(64, 3);
        for (int v = 0; v < 48; ++v) {
            Eigen::Vector3d q;
            evaluateNetVolume(net, net.rest, test::randomParams(rng), q);
            rest.row(v) = q.transpose();
        }
        for (int v = 48; v < 63; ++v) {
            Eigen::Vector3d t = test::randomParams(rng);
            t[v % 2 == 0 ? 0 : 2] = (v % 3 == 0 && trial % 2 == 0) ? 1.0 : 0.0;  // the axis / centre / a pole
            Eigen::Vector3d q;
            evaluateNetVolume(net, net.rest, t, q);
            rest.row(v) = q.transpose();
        }
        rest.row(63) = (net.bounds.max() + Eigen::Vector3d::Constant(1.0)).transpose();
        std::vector<double> det;
        vertexJacobianDeterminants(lattice, rest, det);
        for (double value : det) REQUIRE(value == 1.0);
        // Move only the control points of one chunk's neighbourhood: vertices elsewhere keep exactly 1.
        const int moved = net.slot(1, 1, 1);
        lattice.displacement.row(moved) = (0.05 * spacing(net) * test::randomVector(rng, -1.0, 1.0)).transpose();
        weldDisplacements(lattice);
        vertexJacobianDeterminants(lattice, rest, det);
        const std::vector<int> influenced = cellsInfluencedBy(lattice, {moved});
        for (int v = 0; v < rest.rows(); ++v) {
            REQUIRE(std::isfinite(det[v]));
            Eigen::Vector3d t;
            if (!restParameters(lattice, rest.row(v).transpose(), t)) {
                REQUIRE(det[v] == 1.0);
                continue;
            }
            std::array<int, 3> chunk;
            Eigen::Vector3d local;
            for (int a = 0; a < 3; ++a) chunk[a] = lattice.axes[a].locate(t[a], local[a]);
            if (!std::binary_search(influenced.begin(), influenced.end(), chunkIndex(lattice, chunk))) REQUIRE(det[v] == 1.0);
            else REQUIRE(det[v] == jacobianDeterminant(lattice, t));
            REQUIRE(det[v] > 0.0);
        }
        // A rigid translation moves every chunk: det J is 1 everywhere, on the axis by the limit.
        for (int s = 0; s < lattice.controlPointCount(); ++s) lattice.displacement.row(s) = Eigen::RowVector3d(0.3, -0.2, 0.1);
        vertexJacobianDeterminants(lattice, rest, det);
        for (int v = 0; v < rest.rows(); ++v) REQUIRE(det[v] == Approx(1.0).epsilon(1e-9));
    }
}

TEST_CASE("injectivity net: the tolerance bounds det J itself on a uniformly scaled sphere and cylinder", "[injectivity][net]") {
    std::mt19937 rng(1008);
    for (int trial = 0; trial < 6; ++trial) {
        Lattice lattice = latticeOf(trial % 2 ? randomCylinder(rng) : randomSphere(rng));
        const Eigen::Vector3d centre = lattice.tensorNet()->bounds.center();
        const double scale = 0.9;  // det J = 0.729 everywhere, the axis and poles included
        for (int s = 0; s < lattice.controlPointCount(); ++s)
            lattice.displacement.row(s) = (scale - 1.0) * (lattice.tensorNet()->rest.row(s) - centre.transpose());
        ExactOptions options;
        options.tolerance = 0.7;
        const InjectivityResult loose = checkInjectivityExact(lattice, options);
        INFO(lattice.tensorNet()->kind << ": " << loose.message);
        REQUIRE(loose.certified);
        REQUIRE(loose.determinantLowerBound == 0.7);
        REQUIRE(loose.minDeterminantFound == Approx(0.729).epsilon(1e-9));
        options.tolerance = 0.75;
        const InjectivityResult strict = checkInjectivityExact(lattice, options);
        REQUIRE(strict.verdict == InjectivityVerdict::Fold);
        REQUIRE(strict.minDeterminantFound == Approx(0.729).epsilon(1e-9));
        REQUIRE(strict.message.find("not above the tolerance") != std::string::npos);
    }
}

TEST_CASE("injectivity net: a cylinder wall wound twice round its axis has det J > 0 yet is not certified", "[injectivity][net]") {
    // One radial chunk of degree 1: Q = (1 - r) A(z) + r W(theta, z), so det(dQ/dt) = r det[W - A, W_theta, A'] is
    // positive wherever the wall turns monotonically round the axis, whether it goes round once or twice. Twice
    // is a double cover near the axis (2:1): the winding count must refuse it.
    LatticeNet net;
    const Eigen::Vector3d axis = Eigen::Vector3d(0.2, 0.1, 1.0).normalized();
    REQUIRE(makeCylinderNet(Eigen::Vector3d(0.1, -0.2, 0.3), axis, 1.0, 2.0, {1, 6, 1}, {1, 1}, net));
    Lattice lattice = latticeOf(net);
    Eigen::Vector3d e1, e2;
    {
        const Eigen::Vector3d onWall = (net.rest.row(net.slot(1, 0, 0)) - net.rest.row(net.slot(0, 0, 0))).transpose();
        e1 = onWall.normalized();
        e2 = axis.cross(e1);
    }
    for (int k = 0; k < net.count[2]; ++k)
        for (int j = 0; j < net.count[1]; ++j) {
            const int s = net.slot(1, j, k);
            const Eigen::Vector3d centre = net.rest.row(net.slot(0, j, k)).transpose();
            const Eigen::Vector3d radial = net.rest.row(s).transpose() - centre;
            const double angle = std::atan2(radial.dot(e2), radial.dot(e1));
            const double distance = j % 2 ? 2.0 : 1.0;  // arc middles: 1 / cos(60 degrees) for 120 degree arcs
            const Eigen::Vector3d wound = centre + distance * (std::cos(2.0 * angle) * e1 + std::sin(2.0 * angle) * e2);
            lattice.displacement.row(s) = (wound - net.rest.row(s).transpose()).transpose();
        }
    weldDisplacements(lattice);
    REQUIRE(sampledMinimum(lattice, 6) > 0.0);
    const InjectivityResult exact = checkInjectivityExact(lattice);
    INFO(exact.message);
    REQUIRE_FALSE(exact.certified);
    REQUIRE(exact.verdict == InjectivityVerdict::Undecided);
    REQUIRE(exact.message.find("turns 2 times") != std::string::npos);
    REQUIRE(exact.failingLocalParams[0] == 0.0);
    // The same wall wound once (the rest shape moved rigidly) passes, and so does its turn count.
    const NetChunkBasis basis = makeNetChunkBasis(lattice);
    NetChunkWorkspace work;
    double turns = 0.0;
    REQUIRE(netRingWinding(lattice, basis, {0, 0, 0}, 0, 0, work, turns));
    REQUIRE(std::abs(turns) == Approx(2.0));
    lattice.displacement.setZero();
    REQUIRE(netRingWinding(lattice, basis, {0, 3, 0}, 0, 0, work, turns));
    REQUIRE(std::abs(turns) == Approx(1.0));
}

TEST_CASE("injectivity net: deformationJacobian is the identity on the axis of an undeformed chunk", "[injectivity][net]") {
    LatticeNet net;
    REQUIRE(makeCylinderNet(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 1.0, 2.0, {2, 4, 2}, {2, 2}, net));
    Lattice lattice = latticeOf(net);
    lattice.displacement.row(net.slot(net.count[0] - 1, 2, net.count[2] - 1)) = Eigen::RowVector3d(0.1, 0.0, 0.0);  // far away
    for (double z : {0.1, 0.3}) {
        Eigen::Vector3d displacement;
        Eigen::Matrix3d jacobian;
        deformationJacobian(lattice, Eigen::Vector3d(0.0, 0.3, z), displacement, jacobian);
        REQUIRE(jacobian == Eigen::Matrix3d::Identity());
        REQUIRE(jacobianDeterminant(lattice, Eigen::Vector3d(0.0, 0.3, z)) == 1.0);
    }
}

TEST_CASE("injectivity net: non-finite displacements are never certified, on the axis or off it", "[injectivity][net]") {
    LatticeNet net;
    REQUIRE(makeCylinderNet(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 1.0, 2.0, {2, 4, 2}, {2, 2}, net));
    for (int i : {0, 1}) {
        Lattice lattice = latticeOf(net);
        lattice.displacement.row(net.slot(i, 0, 1)) = Eigen::RowVector3d(std::nan(""), 0.0, 0.0);
        weldDisplacements(lattice);
        for (InjectivityMode mode : {InjectivityMode::Conic, InjectivityMode::Exact}) {
            const InjectivityResult result = checkInjectivity(lattice, mode);
            REQUIRE_FALSE(result.certified);
            REQUIRE(result.verdict == InjectivityVerdict::Undecided);
            REQUIRE(result.message.find("non-finite") != std::string::npos);
        }
    }
}
