// The volume interface (volume.h): the engine's generic paths for a volume that is not one tensor product
// (cells = its chunks, evaluation through basisAt) against the tensor fast path of the same net. The wrapper
// below forwards every call to a LatticeNet but hides tensorNet(), as a T-spline or composite volume would.
#include <catch2/catch.hpp>

#include <memory>
#include <random>

#include "core/deform/direct_manipulation.h"
#include "core/volume/embedding.h"
#include "core/injectivity/injectivity.h"
#include "core/volume/lattice.h"
#include "core/volume/lattice_net.h"

using namespace sculpt;
using namespace sculpt::core;

namespace {

class OpaqueVolume final : public Volume {
public:
    explicit OpaqueVolume(std::shared_ptr<const LatticeNet> net) : net_(std::move(net)) {}
    const std::string& kindName() const override { return net_->kindName(); }
    int controlPointCount() const override { return net_->controlPointCount(); }
    const Positions& restControlPoints() const override { return net_->restControlPoints(); }
    const std::vector<double>& controlWeights() const override { return net_->controlWeights(); }
    bool isRational() const override { return net_->isRational(); }
    int representativeOf(int id) const override { return net_->representativeOf(id); }
    const std::vector<std::vector<int>>& weldGroupList() const override { return net_->weldGroupList(); }
    Eigen::AlignedBox3d restBounds() const override { return net_->restBounds(); }
    bool onOuterSurface(int id) const override { return net_->onOuterSurface(id); }
    bool inSurfaceLayers(int id, int layers) const override { return net_->inSurfaceLayers(id, layers); }
    std::vector<std::array<int, 2>> controlNetEdgeList() const override { return net_->controlNetEdgeList(); }
    void basisAt(const Eigen::Vector3d& t, SupportWeights& out) const override { net_->basisAt(t, out); }
    void evaluate(const Positions& points, const Eigen::Vector3d& t, Eigen::Vector3d& value, Eigen::Matrix3d* derivative) const override {
        net_->evaluate(points, t, value, derivative);
    }
    bool freeze(const Eigen::Vector3d& x, Eigen::Vector3d& t) const override { return net_->freeze(x, t); }
    std::unique_ptr<Locator> locatorFor(const Positions& points) const override { return net_->locatorFor(points); }
    int chunkCount() const override { return net_->chunkCount(); }
    int chunkOf(const Eigen::Vector3d& t, Eigen::Vector3d& local) const override { return net_->chunkOf(t, local); }
    Eigen::Vector3d chunkParameters(int chunk, const Eigen::Vector3d& local) const override { return net_->chunkParameters(chunk, local); }
    void chunkSupport(int chunk, std::vector<int>& ids) const override { net_->chunkSupport(chunk, ids); }
    void bezierChunk(int chunk, const Positions* displacement, BezierChunk& out) const override { net_->bezierChunk(chunk, displacement, out); }
    void chunksAlong(int chunk, int axis, std::vector<int>& row, bool& closed) const override { net_->chunksAlong(chunk, axis, row, closed); }
    std::vector<std::array<Eigen::Vector3d, 2>> chunkEdgeLines() const override { return net_->chunkEdgeLines(); }

private:
    std::shared_ptr<const LatticeNet> net_;
};

// The same net as a lattice with the tensor fast path and as one without it.
void tensorAndOpaque(const LatticeNet& net, Lattice& tensor, Lattice& opaque) {
    const auto shared = std::make_shared<const LatticeNet>(net);
    LatticeSettings tensorSettings, opaqueSettings;
    tensorSettings.volume = shared;
    opaqueSettings.volume = std::make_shared<const OpaqueVolume>(shared);
    REQUIRE(makeLattice(tensorSettings, Positions::Zero(1, 3), tensor));
    REQUIRE(makeLattice(opaqueSettings, Positions::Zero(1, 3), opaque));
}

double uniform(std::mt19937& rng, double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); }
int uniformInt(std::mt19937& rng, int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); }

}  // namespace

TEST_CASE("volume interface: a volume without the tensor fast path deforms and solves as the tensor net does", "[core][volume]") {
    std::mt19937 rng(2211);
    for (int trial = 0; trial < 12; ++trial) {
        LatticeNet net;
        const double size = std::pow(10.0, uniform(rng, -1, 1));
        Status s;
        if (trial % 2 == 0)
            s = makeCylinderNet(Eigen::Vector3d::Zero(), Eigen::Vector3d(uniform(rng, -1, 1), uniform(rng, -1, 1), 1.0), size, 2 * size,
                                {uniformInt(rng, 1, 3), uniformInt(rng, 3, 8), uniformInt(rng, 1, 3)}, {uniformInt(rng, 1, 3), uniformInt(rng, 1, 3)}, net);
        else
            s = makeSphereNet(Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 1, 0), size, {uniformInt(rng, 1, 3), uniformInt(rng, 3, 6), uniformInt(rng, 2, 4)},
                              uniformInt(rng, 1, 3), net);
        REQUIRE(s);
        Lattice tensor, opaque;
        tensorAndOpaque(net, tensor, opaque);
        REQUIRE(opaque.tensorNet() == nullptr);
        REQUIRE(opaque.cellCount() == tensor.cellCount());
        // Random points in and around the volume.
        const int n = 400;
        Positions rest(n, 3);
        for (int v = 0; v < n; ++v)
            for (int a = 0; a < 3; ++a) rest(v, a) = uniform(rng, net.bounds.min()[a], net.bounds.max()[a]) * 1.05;
        const Embedding et = embedVertices(tensor, rest), eo = embedVertices(opaque, rest);
        REQUIRE(eo.insideCount() == et.insideCount());
        // A multi-point drag solved on each (Hu et al. 2001, eq. 12): the same control delta.
        std::vector<Eigen::Vector3d> params;
        for (int f = 0; f < 3; ++f) params.emplace_back(uniform(rng, 0.3, 0.9), uniform(rng, 0, 1), uniform(rng, 0.1, 0.9));
        Eigen::MatrixX3d moves = Eigen::MatrixX3d::Random(3, 3) * 0.05 * size;
        const DirectManipulationResult rt = directManipulation(tensor, params, moves), ro = directManipulation(opaque, params, moves);
        REQUIRE(rt.delta.indices == ro.delta.indices);
        REQUIRE((rt.delta.deltas - ro.delta.deltas).cwiseAbs().maxCoeff() <= 1e-12 * size);
        applyControlDelta(tensor, rt.delta, 1.0);
        applyControlDelta(opaque, ro.delta, 1.0);
        // Evaluated through the chunks (generic) and through the tensor kernels: the same positions.
        Positions pt = rest, po = rest;
        evaluateAll(tensor, et, pt);
        evaluateAll(opaque, eo, po);
        REQUIRE((pt - po).cwiseAbs().maxCoeff() <= 1e-12 * size);
        // The sparse update touches the cells whose support holds a moved point, on both paths.
        std::vector<int> moved = rt.delta.indices;
        REQUIRE(cellsInfluencedBy(tensor, moved) == cellsInfluencedBy(opaque, moved));
        // Targets met exactly through the generic path.
        for (int f = 0; f < 3; ++f) {
            const Eigen::Vector3d before = restPoint(opaque, params[static_cast<size_t>(f)]);
            const Eigen::Vector3d after = before + displacementAt(opaque, params[static_cast<size_t>(f)]);
            REQUIRE((after - before - moves.row(f).transpose()).norm() <= 1e-12 * size);
        }
        // The Jacobian and drawing go through the interface as well.
        for (int sample = 0; sample < 20; ++sample) {
            const Eigen::Vector3d t(uniform(rng, 0.2, 1), uniform(rng, 0, 1), uniform(rng, 0.1, 0.9));
            Eigen::Vector3d dt, dopq;
            Eigen::Matrix3d jt, jo;
            deformationJacobian(tensor, t, dt, jt);
            deformationJacobian(opaque, t, dopq, jo);
            REQUIRE((jt - jo).cwiseAbs().maxCoeff() <= 1e-9 * jt.cwiseAbs().maxCoeff());
        }
        REQUIRE(controlNetEdges(tensor) == controlNetEdges(opaque));
        REQUIRE(chunkEdgeCurves(tensor, 4).size() == chunkEdgeCurves(opaque, 4).size());
    }
}

TEST_CASE("volume interface: the exact injectivity test on a volume's Bezier chunks matches the tensor net's", "[core][volume]") {
    std::mt19937 rng(4711);
    int folds = 0, certified = 0;
    for (int trial = 0; trial < 16; ++trial) {
        LatticeNet net;
        REQUIRE(makeCylinderNet(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 1.0, 2.0,
                                {uniformInt(rng, 1, 2), uniformInt(rng, 3, 8), uniformInt(rng, 1, 2)}, {2, 2}, net));
        Lattice tensor, opaque;
        tensorAndOpaque(net, tensor, opaque);
        // Move a few weld groups (the axis included) by amounts from gentle to folding.
        const double amplitude = 0.1 * (1 + trial % 8);
        ControlDelta delta;
        for (int m = 0; m < 3; ++m) {
            const int id = net.representativeOf(uniformInt(rng, 0, net.slotCount() - 1));
            if (std::find(delta.indices.begin(), delta.indices.end(), id) != delta.indices.end()) continue;
            delta.indices.push_back(id);
        }
        std::sort(delta.indices.begin(), delta.indices.end());
        delta.deltas = Eigen::MatrixX3d::Random(static_cast<Eigen::Index>(delta.indices.size()), 3) * amplitude;
        expandWelds(tensor, delta);
        applyControlDelta(tensor, delta, 1.0);
        applyControlDelta(opaque, delta, 1.0);
        const InjectivityResult rt = checkInjectivityExact(tensor), ro = checkInjectivityExact(opaque);
        INFO("trial " << trial << ": " << rt.message << " / " << ro.message);
        REQUIRE(rt.verdict == ro.verdict);
        REQUIRE(rt.failingCell == ro.failingCell);
        REQUIRE(rt.cellsDeformed == ro.cellsDeformed);
        folds += rt.verdict == InjectivityVerdict::Fold;
        certified += rt.certified;
        // det J per point agrees away from the collapsed axis.
        for (int sample = 0; sample < 10; ++sample) {
            const Eigen::Vector3d t(uniform(rng, 0.1, 1), uniform(rng, 0, 1), uniform(rng, 0, 1));
            const double a = jacobianDeterminant(tensor, t), b = jacobianDeterminant(opaque, t);
            REQUIRE(std::abs(a - b) <= 1e-8 * std::max(1.0, std::abs(a)));
        }
    }
    REQUIRE(folds > 0);
    REQUIRE(certified > 0);
}
