// Composite lattices (Coquillart 1990, 3.1.2, 3.1.4): elementary nets welded where they meet act as one
// control volume. Properties over random composites (fixed seeds): welds, partition of unity, freezing back,
// C0 across a welded face under deformation, the explicit solution meeting targets through the generic path,
// the exact injectivity test against sampled det J, JSON round trips and placement.
#include <catch2/catch.hpp>

#include <cmath>
#include <memory>
#include <random>

#include "core/volume/composite_volume.h"
#include "core/deform/direct_manipulation.h"
#include "core/volume/embedding.h"
#include "core/injectivity/injectivity.h"
#include "core/volume/lattice.h"
#include "core/session/session.h"
#include "core/volume/volume_kinds.h"
#include "io/lattice_json.h"
#include "../mesh_fixtures.h"

using namespace sculpt;
using namespace sculpt::core;

namespace {

double uniform(std::mt19937& rng, double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); }
int uniformInt(std::mt19937& rng, int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); }

// Two boxes sharing the face x = 0 (same grid on it), or two discs touching at the origin.
std::shared_ptr<const CompositeVolume> randomComposite(std::mt19937& rng, int kind, double& size) {
    size = std::pow(10.0, uniform(rng, -1, 1));
    std::vector<std::shared_ptr<const LatticeNet>> parts;
    if (kind == 0) {
        const std::array<int, 3> chunksLeft{uniformInt(rng, 1, 3), uniformInt(rng, 1, 3), uniformInt(rng, 1, 3)};
        const std::array<int, 3> degree{uniformInt(rng, 1, 3), uniformInt(rng, 1, 3), uniformInt(rng, 1, 3)};
        std::array<int, 3> chunksRight = chunksLeft;
        chunksRight[0] = uniformInt(rng, 1, 3);
        std::array<int, 3> degreeRight = degree;
        degreeRight[0] = uniformInt(rng, 1, 3);
        const double width = size * uniform(rng, 0.5, 2), height = size * uniform(rng, 0.5, 2);
        LatticeNet left, right;
        Eigen::Matrix3d edges = Eigen::Vector3d(size, width, height).asDiagonal();
        REQUIRE(makeParallelepipedNet(Eigen::Vector3d(-size, 0, 0), edges, chunksLeft, degree, left));
        edges(0, 0) = size * uniform(rng, 0.5, 2);
        REQUIRE(makeParallelepipedNet(Eigen::Vector3d(0, 0, 0), edges, chunksRight, degreeRight, right));
        parts = {std::make_shared<const LatticeNet>(left), std::make_shared<const LatticeNet>(right)};
    } else {
        const std::array<int, 3> chunks{uniformInt(rng, 1, 3), 4 * uniformInt(rng, 1, 3), uniformInt(rng, 1, 2)};
        LatticeNet a, b;
        REQUIRE(makeCylinderNet(Eigen::Vector3d(0, size, -0.5 * size), Eigen::Vector3d::UnitZ(), size, size, chunks, {2, 2}, a));
        REQUIRE(makeCylinderNet(Eigen::Vector3d(0, -size, -0.5 * size), Eigen::Vector3d::UnitZ(), size, size, chunks, {2, 2}, b));
        parts = {std::make_shared<const LatticeNet>(a), std::make_shared<const LatticeNet>(b)};
    }
    std::shared_ptr<const CompositeVolume> composite;
    const Status made = CompositeVolume::make(parts, composite);
    INFO(made.message);
    REQUIRE(made);
    return composite;
}

Lattice latticeOf(const std::shared_ptr<const Volume>& volume) {
    LatticeSettings settings;
    settings.volume = volume;
    Lattice lattice;
    REQUIRE(makeLattice(settings, Positions::Zero(1, 3), lattice));
    return lattice;
}

Eigen::Vector3d randomParameters(std::mt19937& rng, const CompositeVolume& composite) {
    const int block = uniformInt(rng, 0, static_cast<int>(composite.blocks().size()) - 1);
    return Eigen::Vector3d(2.0 * block + uniform(rng, 0, 1), uniform(rng, 0, 1), uniform(rng, 0, 1));
}

}  // namespace

TEST_CASE("composite lattice: welded where the parts meet, a partition of unity, and points freeze back", "[core][composite]") {
    std::mt19937 rng(9090);
    for (int trial = 0; trial < 16; ++trial) {
        double size = 1.0;
        const auto composite = randomComposite(rng, trial % 2, size);
        REQUIRE(composite->crossWeldCount() > 0);
        if (trial % 2 == 0) {
            // Every point of the shared face is welded to the other part's point there.
            const LatticeNet& left = *composite->blocks()[0];
            for (int k = 0; k < left.count[2]; ++k)
                for (int j = 0; j < left.count[1]; ++j) {
                    const int id = left.slot(left.count[0] - 1, j, k);
                    const std::vector<int>* group = weldGroupOf(*composite, id);
                    REQUIRE(group);
                    REQUIRE(group->back() >= composite->offset(1));
                    // The joint lies inside the composite: only its border is on the outer surface.
                    const bool border = j == 0 || k == 0 || j == left.count[1] - 1 || k == left.count[2] - 1;
                    REQUIRE(composite->onOuterSurface(id) == border);
                    REQUIRE(composite->onOuterSurface(group->back()) == border);
                }
        }
        const Lattice lattice = latticeOf(composite);
        REQUIRE(lattice.tensorNet() == nullptr);
        for (int sample = 0; sample < 100; ++sample) {
            const Eigen::Vector3d t = randomParameters(rng, *composite);
            SupportWeights support;
            supportWeights(lattice, t, support);
            double sum = 0.0;
            for (int c = 0; c < support.count; ++c) {
                REQUIRE(support.weight[c] >= -1e-15);
                REQUIRE(lattice.representative(support.index[c]) == support.index[c]);
                sum += support.weight[c];
            }
            REQUIRE(std::abs(sum - 1.0) <= 1e-14);
            // Freezing the rest point gives parameters of the same point (the first part holding it).
            const Eigen::Vector3d x = restPoint(lattice, t);
            Eigen::Vector3d back;
            REQUIRE(restParameters(lattice, x, back));
            REQUIRE((restPoint(lattice, back) - x).norm() <= 1e-12 * lattice.diagonal());
        }
        // Two parts that do not touch cannot be welded.
        std::shared_ptr<const CompositeVolume> apart;
        LatticeNet moved = *composite->blocks()[1];
        moved.rest.rowwise() += Eigen::RowVector3d(0, 0, 10 * size);
        REQUIRE(finishLatticeNet(moved));
        const Status refused = CompositeVolume::make({composite->blocks()[0], std::make_shared<const LatticeNet>(moved)}, apart);
        REQUIRE_FALSE(refused);
        REQUIRE(refused.message.find("share no point") != std::string::npos);
    }
}

TEST_CASE("composite lattice: a deformation stays continuous across the welded face and drags meet their targets", "[core][composite]") {
    std::mt19937 rng(4242);
    for (int trial = 0; trial < 12; ++trial) {
        double size = 1.0;
        const auto composite = randomComposite(rng, 0, size);
        Lattice lattice = latticeOf(composite);
        // A multi-point drag solved on the composite's basis (Hu et al. 2001, eq. 12): targets met exactly.
        std::vector<Eigen::Vector3d> params;
        for (int f = 0; f < 3; ++f) params.push_back(randomParameters(rng, *composite));
        const Eigen::MatrixX3d moves = Eigen::MatrixX3d::Random(3, 3) * 0.05 * size;
        const DirectManipulationResult result = directManipulation(lattice, params, moves);
        applyControlDelta(lattice, result.delta, 1.0);
        for (int f = 0; f < 3; ++f)
            REQUIRE((displacementAt(lattice, params[static_cast<size_t>(f)]) - moves.row(f).transpose()).norm() <= 1e-12 * size);
        // Welded copies carry equal displacements.
        for (const auto& group : composite->weldGroupList())
            for (int id : group) REQUIRE(lattice.displacement.row(id) == lattice.displacement.row(group[0]));
        // On the shared face x = 0, the left part's u = 1 and the right part's u = 0 give the same deformed point.
        for (int sample = 0; sample < 50; ++sample) {
            const double v = uniform(rng, 0, 1), w = uniform(rng, 0, 1);
            const Eigen::Vector3d fromLeft(1.0, v, w), fromRight(2.0, v, w);
            const Eigen::Vector3d a = restPoint(lattice, fromLeft) + displacementAt(lattice, fromLeft);
            const Eigen::Vector3d b = restPoint(lattice, fromRight) + displacementAt(lattice, fromRight);
            REQUIRE((a - b).norm() <= 1e-12 * lattice.diagonal());
        }
    }
}

TEST_CASE("composite lattice: the exact test certifies only deformations whose sampled det J is positive", "[core][composite]") {
    std::mt19937 rng(31337);
    int certified = 0, rejected = 0;
    for (int trial = 0; trial < 16; ++trial) {
        double size = 1.0;
        const auto composite = randomComposite(rng, trial % 2, size);
        Lattice lattice = latticeOf(composite);
        // Move a few interior (not outer-surface) points by growing amounts.
        ControlDelta delta;
        for (int id = 0; id < composite->controlPointCount() && delta.indices.size() < 3; ++id)
            if (!composite->onOuterSurface(id) && lattice.representative(id) == id && uniform(rng, 0, 1) < 0.3) delta.indices.push_back(id);
        if (delta.indices.empty()) continue;
        delta.deltas = Eigen::MatrixX3d::Random(static_cast<Eigen::Index>(delta.indices.size()), 3) * size * 0.15 * (1 + trial % 6);
        expandWelds(lattice, delta);
        applyControlDelta(lattice, delta, 1.0);
        const InjectivityResult verdict = checkInjectivityExact(lattice);
        INFO("trial " << trial << ": " << verdict.message);
        // det J sampled by central differences of the deformation x(X0) = X0 + D(t(X0)) in parameter space:
        // det(dx/dt) / det(dX0/dt).
        double least = 1e300;
        for (int sample = 0; sample < 400; ++sample) {
            const Eigen::Vector3d t = randomParameters(rng, *composite);
            Eigen::Vector3d d;
            Eigen::Matrix3d jacobian;
            deformationJacobian(lattice, t, d, jacobian);
            if (jacobian.allFinite()) least = std::min(least, jacobian.determinant());
        }
        if (verdict.certified) {
            ++certified;
            REQUIRE(least > 0.0);
        } else {
            ++rejected;
        }
        if (least < 0.0) REQUIRE(verdict.verdict == InjectivityVerdict::Fold);
    }
    REQUIRE(certified > 0);
    REQUIRE(rejected > 0);
}

TEST_CASE("composite lattice: JSON round trip, placement, and a session that freezes, drags and undoes", "[core][composite][effd]") {
    std::mt19937 rng(777);
    double size = 1.0;
    const auto composite = randomComposite(rng, 1, size);
    const nlohmann::json j = io::volumeJson(*composite);
    REQUIRE(j["kind"] == "composite");
    std::shared_ptr<const Volume> back;
    REQUIRE(io::parseVolumeJson(j, "lattice", back));
    REQUIRE(sameVolume(*back, *composite));
    REQUIRE(back->weldGroupList() == composite->weldGroupList());
    nlohmann::json bad = j;
    bad["parts"].erase(1);
    const Status one = io::parseVolumeJson(bad, "lattice", back);
    REQUIRE_FALSE(one);
    REQUIRE(one.message.find("lattice.parts") == 0);
    // Placed anywhere at any size: still welded the same way.
    std::shared_ptr<const Volume> placed;
    REQUIRE(placeVolume(*composite, Eigen::Vector3d(3, -2, 1), Eigen::Vector3d(0.3, 0.2, 1), 1.7, placed));
    REQUIRE(placed->weldGroupList() == composite->weldGroupList());
    // A similarity: distances scale by size / the composite's diagonal (measured before turning onto the normal).
    const int last = composite->controlPointCount() - 1;
    const double scale = 1.7 / composite->restBounds().diagonal().norm();
    REQUIRE(std::abs((placed->restControlPoints().row(last) - placed->restControlPoints().row(0)).norm() -
                     scale * (composite->restControlPoints().row(last) - composite->restControlPoints().row(0)).norm()) <= 1e-12);
    // In a session: the two discs over a sphere, a drag on a vertex inside, undo.
    Positions positions;
    Triangles triangles;
    test::icosphere(3, 1.0, Eigen::Vector3d::Zero(), positions, triangles);
    Session session;
    REQUIRE(session.setMesh(positions, triangles, LatticeSettings{}));
    InjectivitySettings injectivity;
    injectivity.mode = InjectivityMode::Exact;
    session.setInjectivity(injectivity);
    std::shared_ptr<const Volume> eight;
    REQUIRE(placeVolume(*composite, Eigen::Vector3d(0, 0, 0.9), Eigen::Vector3d::UnitZ(), 1.6, eight));
    OpReport report;
    REQUIRE(session.tools().add({"eight", eight}, report));
    REQUIRE(session.tools().freeze(0, 0, report));
    REQUIRE(report.status == OpStatus::Applied);
    int vertex = -1;
    for (int v = 0; v < positions.rows() && vertex < 0; ++v) {
        Eigen::Vector3d t;
        if (restParameters(session.lattice(), positions.row(v).transpose(), t)) {
            // well inside a disc: its radial parameter below 0.6
            Eigen::Vector3d blockT;
            if (composite->blockOf(t, blockT) >= 0 && blockT.x() < 0.6) vertex = v;
        }
    }
    REQUIRE(vertex >= 0);
    const Eigen::Vector3d target = positions.row(vertex).transpose() + Eigen::Vector3d(0, 0, -0.05);
    REQUIRE(session.dragVertex(vertex, target, report));
    INFO(report.reason);
    REQUIRE(report.status == OpStatus::Applied);
    REQUIRE((session.mesh().positions.row(vertex).transpose() - target).norm() <= 1e-9);
    // The outer surface of a composite stays put.
    for (int id = 0; id < session.lattice().controlPointCount(); ++id)
        if (eight->onOuterSurface(id)) REQUIRE(session.lattice().displacement.row(id).isZero(0.0));
    REQUIRE(session.undo(report));
    REQUIRE((session.mesh().positions - positions).cwiseAbs().maxCoeff() <= 1e-12);
}
