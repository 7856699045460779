// Weighted T-spline volumes (Song & Yang 2005, seed 002). Properties over random T-lattices (fixed seeds):
// the knot rule against a brute-force ray cast, reduction to the tensor NURBS net without T-junctions, a
// positive partition of unity with the convex hull property, B_s against an independent Cox-de Boor, the
// Jacobian against finite differences, Bezier extraction against evaluation, freezing back, bad lattices
// refused by rule, octree generation (sec. 4) with balanced weights whose rest volume never folds (sampled
// through evaluate(), independently of the proof), folding placements refused, and a session that freezes,
// drags and round-trips JSON.
#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <iostream>
#include <memory>
#include <random>

#include "core/spline/bernstein.h"
#include "core/deform/direct_manipulation.h"
#include "core/volume/embedding.h"
#include "core/injectivity/injectivity.h"
#include "core/volume/lattice.h"
#include "core/volume/lattice_net.h"
#include "core/session/session.h"
#include "core/tspline/tspline_volume.h"
#include "core/volume/volume_kinds.h"
#include "io/lattice_json.h"
#include "../mesh_fixtures.h"

using namespace sculpt;
using namespace sculpt::core;

namespace {

double uniform(std::mt19937& rng, double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); }
int uniformInt(std::mt19937& rng, int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); }

// A T-lattice from a random root grid and `rounds` rounds of random local subdivision (Fig. 11).
TLattice randomLattice(std::mt19937& rng, int rounds, bool balance) {
    TLattice lattice;
    lattice.rootCount = {uniformInt(rng, 1, 3), uniformInt(rng, 1, 3), uniformInt(rng, 1, 3)};
    for (int z = 0; z < lattice.rootCount[2]; ++z)
        for (int y = 0; y < lattice.rootCount[1]; ++y)
            for (int x = 0; x < lattice.rootCount[0]; ++x) lattice.cells.push_back(TLatticeCell{0, {x, y, z}});
    REQUIRE(finishTLattice(lattice));
    for (int round = 0; round < rounds; ++round) {
        std::vector<int> chosen;
        for (int c = 0; c < static_cast<int>(lattice.cells.size()); ++c)
            if (uniform(rng, 0, 1) < 0.25) chosen.push_back(c);
        if (chosen.empty()) chosen.push_back(uniformInt(rng, 0, static_cast<int>(lattice.cells.size()) - 1));
        TLattice finer;
        const Status s = subdivideTLatticeCells(lattice, chosen, balance, finer);
        INFO(s.message);
        REQUIRE(s);
        lattice = finer;
    }
    return lattice;
}

// A volume on `lattice` in a random box, control points jittered by `jitter` x the box and random weights in
// [1/spread, spread]. make() refuses a draw whose rest volume folds (a jitter of 0.05 of the box moves a boundary
// copy past its neighbour a third of a cell away), so such a draw is made again, milder (half the jitter, the
// square root of the spread), until one is valid.
std::shared_ptr<const TSplineVolume> randomVolume(std::mt19937& rng, const TLattice& lattice, double jitter, double spread, double& size) {
    size = std::pow(10.0, uniform(rng, -1, 1));
    const Eigen::Vector3d lo(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
    const Eigen::Vector3d extent(size * uniform(rng, 0.5, 2), size * uniform(rng, 0.5, 2), size * uniform(rng, 0.5, 2));
    std::shared_ptr<const TSplineVolume> placed;
    const Status made = makeTSplineVolumeInBox(lattice, Eigen::AlignedBox3d(lo, lo + extent), {}, placed);
    INFO(made.message);
    REQUIRE(made);
    for (int attempt = 0;; ++attempt) {
        Positions points = placed->restControlPoints();
        std::vector<double> weights(static_cast<size_t>(points.rows()));
        for (Eigen::Index s = 0; s < points.rows(); ++s) {
            for (int a = 0; a < 3; ++a) points(s, a) += jitter * extent[a] * uniform(rng, -1, 1);
            weights[static_cast<size_t>(s)] = std::exp(uniform(rng, -1, 1) * std::log(spread));
        }
        std::shared_ptr<const TSplineVolume> volume;
        const Status s = TSplineVolume::make(placed->sharedBasis(), points, weights, volume);
        INFO("attempt " << attempt << ": " << s.message);
        REQUIRE((s || attempt < 8));
        if (s) return volume;
        jitter *= 0.5;
        spread = std::sqrt(spread);
    }
}

Eigen::Vector3d randomParameters(std::mt19937& rng) { return Eigen::Vector3d(uniform(rng, 0, 1), uniform(rng, 0, 1), uniform(rng, 0, 1)); }

// Brute force of the knot rule (3.2.2): the first knot plane beyond p along `axis`, scanning every fine
// position and every cell (a face of constant t_axis whose closed box holds the point on the ray).
int bruteNextKnot(const TLattice& lattice, const std::array<int, 3>& p, int axis, int direction) {
    for (int x = p[axis] + direction; x >= 0 && x <= lattice.fineCount[axis]; x += direction) {
        std::array<int, 3> q = p;
        q[axis] = x;
        for (int c = 0; c < static_cast<int>(lattice.cells.size()); ++c) {
            const auto lo = lattice.cellLo(c), hi = lattice.cellHi(c);
            bool holds = true;
            for (int a = 0; a < 3; ++a) holds = holds && lo[a] <= q[a] && q[a] <= hi[a];
            if (holds && (lo[axis] == x || hi[axis] == x)) return x;
        }
    }
    return p[axis];  // only reached from the boundary itself
}

// Cox-de Boor for one cubic B-spline on 5 knots (0/0 = 0), at u not on a knot.
double coxDeBoor(const std::array<double, 5>& k, double u) {
    double n[4];
    for (int i = 0; i < 4; ++i) n[i] = k[static_cast<size_t>(i)] <= u && u < k[static_cast<size_t>(i) + 1] ? 1.0 : 0.0;
    for (int p = 1; p <= 3; ++p)
        for (int i = 0; i + p < 4 + 0 && i < 4 - p; ++i) {
            const double left = k[static_cast<size_t>(i + p)] - k[static_cast<size_t>(i)];
            const double right = k[static_cast<size_t>(i + p + 1)] - k[static_cast<size_t>(i + 1)];
            n[i] = (left > 0 ? (u - k[static_cast<size_t>(i)]) / left * n[i] : 0.0) +
                   (right > 0 ? (k[static_cast<size_t>(i + p + 1)] - u) / right * n[i + 1] : 0.0);
        }
    return n[0];
}

Lattice latticeOf(const std::shared_ptr<const Volume>& volume) {
    LatticeSettings settings;
    settings.volume = volume;
    Lattice lattice;
    REQUIRE(makeLattice(settings, Positions::Zero(1, 3), lattice));
    return lattice;
}

}  // namespace

TEST_CASE("tspline: local knot vectors follow the knot rule of a brute-force ray cast", "[tspline]") {
    std::mt19937 rng(1201);
    for (int trial = 0; trial < 8; ++trial) {
        const TLattice lattice = randomLattice(rng, 1 + trial % 3, trial % 2 == 0);
        std::shared_ptr<const TSplineBasis> basis;
        REQUIRE(buildTSplineBasis(lattice, basis));
        const TLattice& l = basis->lattice;
        for (int s = 0; s < basis->anchorCount(); ++s) {
            const TSplineAnchor& anchor = basis->anchors[static_cast<size_t>(s)];
            const auto& p = l.vertices[static_cast<size_t>(anchor.vertex)];
            for (int a = 0; a < 3; ++a) {
                const auto& k = anchor.knots[static_cast<size_t>(a)];
                // Non-decreasing, anchored at the vertex (k2), a boundary copy clamped with multiplicity 4.
                for (int i = 0; i < 4; ++i) REQUIRE(k[static_cast<size_t>(i)] <= k[static_cast<size_t>(i) + 1]);
                if ((anchor.boundaryCopy >> a) & 1) {
                    REQUIRE((p[a] == 0 ? k[3] : k[1]) == p[a]);
                    REQUIRE((p[a] == 0 ? k[0] : k[4]) == p[a]);
                    continue;
                }
                REQUIRE(k[2] == p[a]);
                std::array<int, 3> q = p;
                REQUIRE(k[3] == bruteNextKnot(l, q, a, +1));
                q[a] = k[3];
                REQUIRE(k[4] == bruteNextKnot(l, q, a, +1));
                q = p;
                REQUIRE(k[1] == bruteNextKnot(l, q, a, -1));
                q[a] = k[1];
                REQUIRE(k[0] == bruteNextKnot(l, q, a, -1));
            }
        }
        REQUIRE(basis->maxSupport <= 216);
    }
}

TEST_CASE("tspline: a T-lattice without T-junctions is the clamped tensor NURBS net of the same knots", "[tspline]") {
    std::mt19937 rng(1202);
    for (int trial = 0; trial < 8; ++trial) {
        // Equal cells: a root grid (odd trials) or a whole octree level below one root cell (even trials).
        TLattice lattice;
        std::array<int, 3> chunks{};
        if (trial % 2) {
            lattice.rootCount = {uniformInt(rng, 1, 4), uniformInt(rng, 1, 4), uniformInt(rng, 1, 4)};
            for (int z = 0; z < lattice.rootCount[2]; ++z)
                for (int y = 0; y < lattice.rootCount[1]; ++y)
                    for (int x = 0; x < lattice.rootCount[0]; ++x) lattice.cells.push_back(TLatticeCell{0, {x, y, z}});
            chunks = lattice.rootCount;
        } else {
            const int level = 1 + trial % 4 / 2;
            for (int z = 0; z < (1 << level); ++z)
                for (int y = 0; y < (1 << level); ++y)
                    for (int x = 0; x < (1 << level); ++x) lattice.cells.push_back(TLatticeCell{level, {x, y, z}});
            chunks = {1 << level, 1 << level, 1 << level};
        }
        std::shared_ptr<const TSplineVolume> unit;
        REQUIRE(makeTSplineVolumeInBox(lattice, Eigen::AlignedBox3d(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones()), {}, unit));
        REQUIRE(unit->basis().partitionOfUnity);
        REQUIRE_FALSE(unit->isRational());
        LatticeNet net;
        REQUIRE(makeParallelepipedNet(Eigen::Vector3d::Zero(), Eigen::Matrix3d::Identity(), chunks, {3, 3, 3}, net));
        REQUIRE(unit->controlPointCount() == net.slotCount());
        // Anchors match slots by their Greville points (the parallelepiped's control points).
        std::vector<int> slotOf(static_cast<size_t>(unit->controlPointCount()), -1);
        for (int s = 0; s < unit->controlPointCount(); ++s)
            for (int slot = 0; slot < net.slotCount(); ++slot)
                if ((net.rest.row(slot) - unit->restControlPoints().row(s)).norm() <= 1e-12) slotOf[static_cast<size_t>(s)] = slot;
        for (int slot : slotOf) REQUIRE(slot >= 0);
        // Unit weights: the B-spline lattice, whose rest map is the identity.
        for (int sample = 0; sample < 50; ++sample) {
            const Eigen::Vector3d t = randomParameters(rng);
            Eigen::Vector3d q;
            unit->evaluate(unit->restControlPoints(), t, q);
            REQUIRE((q - t).norm() <= 1e-14);
        }
        // Random points and weights: the NURBS net of the same knots.
        LatticeNet raw = rawNetFields(net);
        for (int slot = 0; slot < net.slotCount(); ++slot) {
            for (int a = 0; a < 3; ++a) raw.rest(slot, a) += uniform(rng, -0.1, 0.1) / chunks[static_cast<size_t>(a)];
            raw.weights[static_cast<size_t>(slot)] = uniform(rng, 0.2, 5);
        }
        REQUIRE(finishLatticeNet(raw));
        Positions points(unit->controlPointCount(), 3);
        std::vector<double> weights(static_cast<size_t>(unit->controlPointCount()));
        for (int s = 0; s < unit->controlPointCount(); ++s) {
            points.row(s) = raw.rest.row(slotOf[static_cast<size_t>(s)]);
            weights[static_cast<size_t>(s)] = raw.weights[static_cast<size_t>(slotOf[static_cast<size_t>(s)])];
        }
        std::shared_ptr<const TSplineVolume> weighted;
        REQUIRE(TSplineVolume::make(unit->sharedBasis(), points, weights, weighted));
        for (int sample = 0; sample < 100; ++sample) {
            const Eigen::Vector3d t = randomParameters(rng);
            Eigen::Vector3d qt, qn;
            Eigen::Matrix3d dt, dn;
            weighted->evaluate(weighted->restControlPoints(), t, qt, &dt);
            evaluateNetVolume(raw, raw.rest, t, qn, &dn);
            REQUIRE((qt - qn).norm() <= 1e-12);
            REQUIRE((dt - dn).cwiseAbs().maxCoeff() <= 1e-11);
            SupportWeights st, sn;
            weighted->basisAt(t, st);
            raw.basisAt(t, sn);
            std::vector<double> byslot(static_cast<size_t>(net.slotCount()), 0.0);
            for (int c = 0; c < st.count; ++c) byslot[static_cast<size_t>(slotOf[static_cast<size_t>(st.index[c])])] += st.weight[c];
            for (int c = 0; c < sn.count; ++c) REQUIRE(std::abs(byslot[static_cast<size_t>(sn.index[c])] - sn.weight[c]) <= 1e-12);
        }
        // The control net is the tensor net's.
        std::vector<std::array<int, 2>> te, ne = net.controlNetEdgeList();
        for (const auto& e : weighted->controlNetEdgeList()) {
            std::array<int, 2> mapped{slotOf[static_cast<size_t>(e[0])], slotOf[static_cast<size_t>(e[1])]};
            if (mapped[0] > mapped[1]) std::swap(mapped[0], mapped[1]);
            te.push_back(mapped);
        }
        for (auto& e : ne)
            if (e[0] > e[1]) std::swap(e[0], e[1]);
        std::sort(te.begin(), te.end());
        std::sort(ne.begin(), ne.end());
        REQUIRE(te == ne);
        for (int s = 0; s < weighted->controlPointCount(); ++s)
            REQUIRE(weighted->onOuterSurface(s) == (net.boundarySlot[static_cast<size_t>(slotOf[static_cast<size_t>(s)])] != 0));
    }
}

TEST_CASE("tspline: on random T-lattices the blending functions are a positive partition of unity in the control points' hull", "[tspline]") {
    std::mt19937 rng(1203);
    for (int trial = 0; trial < 10; ++trial) {
        const TLattice lattice = randomLattice(rng, 1 + trial % 3, trial % 3 != 2);
        double size = 1.0;
        const auto volume = randomVolume(rng, lattice, 0.05, 10.0, size);
        const TSplineBasis& basis = volume->basis();
        const Eigen::AlignedBox3d bounds = volume->restBounds();
        for (int sample = 0; sample < 100; ++sample) {
            const Eigen::Vector3d t = randomParameters(rng);
            SupportWeights support;
            volume->basisAt(t, support);
            REQUIRE(support.count <= 216);
            double sum = 0.0;
            Eigen::Vector3d combination = Eigen::Vector3d::Zero();
            for (int c = 0; c < support.count; ++c) {
                REQUIRE(support.weight[c] >= 0.0);
                sum += support.weight[c];
                combination += support.weight[c] * volume->restControlPoints().row(support.index[c]).transpose();
            }
            REQUIRE(std::abs(sum - 1.0) <= 1e-14);
            Eigen::Vector3d q;
            volume->evaluate(volume->restControlPoints(), t, q);
            REQUIRE((q - combination).norm() <= 1e-13 * size);
            REQUIRE(bounds.contains(q));
            // Every B_s (eq. 6, by Cox-de Boor on its local knots): zero off the element's support list, and the
            // listed ones' values give the same R_s.
            std::vector<double> all(static_cast<size_t>(basis.anchorCount()));
            double denominator = 0.0;
            for (int s = 0; s < basis.anchorCount(); ++s) {
                double b = 1.0;
                for (int a = 0; a < 3; ++a) b *= coxDeBoor(basis.knotValues[static_cast<size_t>(s)][static_cast<size_t>(a)], t[a]);
                all[static_cast<size_t>(s)] = volume->controlWeights()[static_cast<size_t>(s)] * b;
                denominator += all[static_cast<size_t>(s)];
            }
            std::vector<std::uint8_t> listed(all.size(), 0);
            for (int c = 0; c < support.count; ++c) {
                listed[static_cast<size_t>(support.index[c])] = 1;
                REQUIRE(std::abs(all[static_cast<size_t>(support.index[c])] / denominator - support.weight[c]) <= 1e-13);
            }
            for (size_t s = 0; s < all.size(); ++s)
                if (!listed[s]) REQUIRE(all[s] == 0.0);
        }
    }
}

TEST_CASE("tspline: the Jacobian matches central differences", "[tspline]") {
    std::mt19937 rng(1204);
    for (int trial = 0; trial < 8; ++trial) {
        const TLattice lattice = randomLattice(rng, 1 + trial % 3, true);
        double size = 1.0;
        const auto volume = randomVolume(rng, lattice, 0.05, 5.0, size);
        for (int sample = 0; sample < 50; ++sample) {
            const double h = 1e-6;
            const Eigen::Vector3d t(uniform(rng, 2 * h, 1 - 2 * h), uniform(rng, 2 * h, 1 - 2 * h), uniform(rng, 2 * h, 1 - 2 * h));
            Eigen::Vector3d q;
            Eigen::Matrix3d d;
            volume->evaluate(volume->restControlPoints(), t, q, &d);
            for (int a = 0; a < 3; ++a) {
                Eigen::Vector3d plus, minus;
                volume->evaluate(volume->restControlPoints(), t + h * Eigen::Vector3d::Unit(a), plus);
                volume->evaluate(volume->restControlPoints(), t - h * Eigen::Vector3d::Unit(a), minus);
                REQUIRE(((plus - minus) / (2 * h) - d.col(a)).norm() <= 1e-6 * d.norm());
            }
        }
    }
}

TEST_CASE("tspline: Bezier chunks evaluated by de Casteljau equal the volume and chunk ids round-trip", "[tspline]") {
    std::mt19937 rng(1205);
    BezierChunk chunk;
    for (int trial = 0; trial < 10; ++trial) {
        const TLattice lattice = randomLattice(rng, 1 + trial % 3, trial % 4 != 3);
        double size = 1.0;
        const auto volume = trial % 5 == 0 ? randomVolume(rng, lattice, 0.05, 1.0, size) : randomVolume(rng, lattice, 0.05, 10.0, size);
        const double scale = volume->restBounds().diagonal().norm();
        Positions displacement = Positions::Random(volume->controlPointCount(), 3) * 0.1 * size;
        const Positions moved = volume->restControlPoints() + displacement;
        for (int sample = 0; sample < 40; ++sample) {
            const int e = uniformInt(rng, 0, volume->chunkCount() - 1);
            volume->bezierChunk(e, trial % 2 ? &displacement : nullptr, chunk);
            REQUIRE(chunk.degree == std::array<int, 3>{3, 3, 3});
            const Eigen::Vector3d local(uniform(rng, 0.01, 0.99), uniform(rng, 0.01, 0.99), uniform(rng, 0.01, 0.99));
            const Eigen::Vector3d t = volume->chunkParameters(e, local);
            Eigen::Vector3d back;
            REQUIRE(volume->chunkOf(t, back) == e);
            REQUIRE((back - local).norm() <= 1e-12);
            Eigen::Vector3d expected;
            volume->evaluate(trial % 2 ? moved : volume->restControlPoints(), t, expected);
            const double w = evaluateBernstein(chunk.points.data() + 3 * 64, chunk.degree, local);
            Eigen::Vector3d fromChunk;
            for (int c = 0; c < 3; ++c) fromChunk[c] = evaluateBernstein(chunk.points.data() + c * 64, chunk.degree, local) / w;
            REQUIRE((fromChunk - expected).norm() <= 1e-12 * scale);
            const Eigen::Vector3d extent = volume->basis().elementMax(e) - volume->basis().elementMin(e);
            for (int a = 0; a < 3; ++a) REQUIRE(chunk.parameterScale[static_cast<size_t>(a)] == extent[a]);
            if (volume->isRational() && !volume->basis().partitionOfUnity) continue;
            REQUIRE(chunk.polynomial == !volume->isRational());
        }
    }
}

TEST_CASE("tspline: freezing gives back the parameters of rest points and of deformed ones", "[tspline]") {
    std::mt19937 rng(1206);
    for (int trial = 0; trial < 8; ++trial) {
        const TLattice lattice = randomLattice(rng, 1 + trial % 3, true);
        double size = 1.0;
        const auto volume = randomVolume(rng, lattice, 0.02, 3.0, size);
        for (int sample = 0; sample < 60; ++sample) {
            const Eigen::Vector3d t = randomParameters(rng);
            Eigen::Vector3d x, back;
            volume->evaluate(volume->restControlPoints(), t, x);
            REQUIRE(volume->freeze(x, back));
            INFO("t " << t.transpose() << " back " << back.transpose());
            REQUIRE((back - t).norm() <= 1e-12);
        }
        // Outside the box: refused; a non-finite point too.
        Eigen::Vector3d t;
        REQUIRE_FALSE(volume->freeze(volume->restBounds().max() + Eigen::Vector3d::Constant(size), t));
        REQUIRE_FALSE(volume->freeze(Eigen::Vector3d::Constant(std::nan("")), t));
        // The deformed net's locator.
        const Positions moved = volume->restControlPoints() + Positions::Random(volume->controlPointCount(), 3) * 0.005 * size;
        const auto locator = volume->locatorFor(moved);
        for (int sample = 0; sample < 30; ++sample) {
            const Eigen::Vector3d u = randomParameters(rng);
            Eigen::Vector3d x, back;
            volume->evaluate(moved, u, x);
            REQUIRE(locator->freeze(x, back));
            REQUIRE((back - u).norm() <= 1e-11);
        }
    }
}

TEST_CASE("tspline: bad T-lattices are refused with the rule they break", "[tspline]") {
    TLattice good;
    for (int z = 0; z < 2; ++z)
        for (int y = 0; y < 2; ++y)
            for (int x = 0; x < 2; ++x) good.cells.push_back(TLatticeCell{1, {x, y, z}});
    REQUIRE(finishTLattice(good));
    // A missing cell: the hole is not a box cell (rule 1).
    TLattice hole = rawTLatticeFields(good);
    hole.cells.erase(hole.cells.begin() + 5);
    Status s = finishTLattice(hole);
    REQUIRE_FALSE(s);
    REQUIRE(s.message.find("rule 1") != std::string::npos);
    REQUIRE(s.message.find("level 1 (1, 0, 1)") != std::string::npos);
    // A cell over another: edges inside a cell (rule 2), both cells named.
    TLattice overlap = rawTLatticeFields(good);
    overlap.cells.push_back(TLatticeCell{2, {3, 3, 3}});
    s = finishTLattice(overlap);
    REQUIRE_FALSE(s);
    REQUIRE(s.message.find("rule 2") != std::string::npos);
    REQUIRE(s.message.find("cell 8") != std::string::npos);
    REQUIRE(s.message.find("cell 7") != std::string::npos);
    TLattice twice = rawTLatticeFields(good);
    twice.cells.push_back(twice.cells[2]);
    s = finishTLattice(twice);
    REQUIRE_FALSE(s);
    REQUIRE(s.message.find("rule 2") != std::string::npos);
    // Root knot lines that coincide: a zero edge (rule 3).
    TLattice zero;
    zero.rootCount = {3, 1, 1};
    zero.rootKnots[0] = {0.0, 0.5, 0.5, 1.0};
    for (int x = 0; x < 3; ++x) zero.cells.push_back(TLatticeCell{0, {x, 0, 0}});
    s = finishTLattice(zero);
    REQUIRE_FALSE(s);
    REQUIRE(s.message.find("rule 3") != std::string::npos);
    REQUIRE(s.message.find("root cell 1") != std::string::npos);
    zero.rootKnots[0] = {0.0, 0.4, 0.5, 1.0};
    REQUIRE(finishTLattice(zero));
    // Out of range.
    TLattice outside = rawTLatticeFields(good);
    outside.cells[0].index[0] = 2;
    REQUIRE_FALSE(finishTLattice(outside));
    // The JSON reader names the field and the rule.
    std::shared_ptr<const TSplineVolume> volume;
    REQUIRE(makeTSplineVolumeInBox(good, Eigen::AlignedBox3d(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones()), {}, volume));
    nlohmann::json j = io::volumeJson(*volume);
    j["cells"].erase(5);
    std::shared_ptr<const Volume> back;
    s = io::parseVolumeJson(j, "lattice", back);
    REQUIRE_FALSE(s);
    REQUIRE(s.message.find("lattice.cells: rule 1") == 0);
}

TEST_CASE("tspline: octree lattices subdivide the non-empty cells to the depth and stay balanced", "[tspline]") {
    Positions positions;
    Triangles triangles;
    test::icosphere(2, 1.0, Eigen::Vector3d(0.3, -0.2, 0.1), positions, triangles);
    for (int depth = 1; depth <= 3; ++depth) {
        TSplineOctreeSettings settings;
        settings.octree.depth = depth;
        settings.octree.rootCount = {depth == 2 ? 2 : 1, 1, 1};
        std::shared_ptr<const TSplineVolume> volume;
        Eigen::AlignedBox3d box;
        REQUIRE(makeOctreeTSplineVolume(positions, settings, volume, &box));
        const TLattice& lattice = volume->lattice();
        REQUIRE(tlatticeBalanced(lattice));
        // Every cell holding a vertex is at the full depth (Fig. 9).
        for (Eigen::Index v = 0; v < positions.rows(); ++v) {
            Eigen::Vector3d t = (positions.row(v).transpose() - box.min()).cwiseQuotient(box.sizes()), local;
            const int e = volume->basis().elementOf(t, local);
            REQUIRE(lattice.cells[static_cast<size_t>(volume->basis().elementCell[static_cast<size_t>(e)])].level == depth);
        }
        // Weights 100:1 (sec. 4), the heavy ones present, balanced: 100, 10 next to them, 1 further out.
        int heavy = 0;
        for (double w : volume->controlWeights()) {
            REQUIRE((w == 1.0 || w == 10.0 || w == 100.0));
            heavy += w == 100.0;
        }
        REQUIRE(heavy > 0);
        REQUIRE(volume->basis().maxSupport <= 216);
        // The rest volume maps the domain's faces onto the box's faces.
        for (int sample = 0; sample < 20; ++sample) {
            Eigen::Vector3d t(sample % 3 == 0 ? 0.0 : 0.37, sample % 3 == 1 ? 1.0 : 0.61, sample % 3 == 2 ? 0.0 : 0.23), q;
            volume->evaluate(volume->restControlPoints(), t, q);
            const int axis = sample % 3;
            REQUIRE(std::abs(q[axis] - (t[axis] == 0.0 ? box.min()[axis] : box.max()[axis])) <= 1e-12 * box.diagonal().norm());
        }
        // Freezing undoes the non-linear rest map of the 100:1 weights (sec. 5, eq. 8).
        std::mt19937 rng(1209 + depth);
        for (int sample = 0; sample < 100; ++sample) {
            const Eigen::Vector3d t = randomParameters(rng);
            Eigen::Vector3d x, back;
            volume->evaluate(volume->restControlPoints(), t, x);
            REQUIRE(volume->freeze(x, back));
            REQUIRE((back - t).norm() <= 1e-12);
        }
        // Local subdivision (Fig. 11): the chosen cells split, the result balanced and still a valid basis.
        TLattice finer;
        REQUIRE(subdivideTLatticeCells(lattice, {0, static_cast<int>(lattice.cells.size()) - 1}, true, finer));
        REQUIRE(finer.cells.size() >= lattice.cells.size() + 14);
        REQUIRE(tlatticeBalanced(finer));
        std::shared_ptr<const TSplineBasis> basis;
        REQUIRE(buildTSplineBasis(finer, basis));
    }
    // Without balance a lone deep cell next to coarse ones is allowed (the rules hold for any octree).
    TLatticeOctreeSettings unbalanced;
    unbalanced.depth = 4;
    unbalanced.balance = false;
    TLattice lattice;
    REQUIRE(makeOctreeTLattice(Positions::Constant(1, 3, 0.49), Eigen::AlignedBox3d(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones()), unbalanced, lattice));
    REQUIRE_FALSE(tlatticeBalanced(lattice));
    REQUIRE(lattice.cells.size() == 1 + 4 * 7);
    std::shared_ptr<const TSplineBasis> basis;
    REQUIRE(buildTSplineBasis(lattice, basis));
}

TEST_CASE("tspline: the exact and conic injectivity tests on the Bezier elements certify only deformations whose sampled det J is positive", "[tspline]") {
    std::mt19937 rng(1208);
    int certified = 0, folds = 0, conicCertified = 0, rational = 0;
    for (int trial = 0; trial < 10; ++trial) {
        const TLattice lattice = randomLattice(rng, 1, true);
        double size = 1.0;
        const auto volume = randomVolume(rng, lattice, 0.0, trial % 2 ? 1.0 : 4.0, size);
        Lattice deformed = latticeOf(volume);
        ControlDelta delta;
        for (int id = 0; id < volume->controlPointCount() && delta.indices.size() < 3; ++id)
            if (!volume->onOuterSurface(id) && uniform(rng, 0, 1) < 0.2) delta.indices.push_back(id);
        if (delta.indices.empty()) continue;
        delta.deltas = Eigen::MatrixX3d::Random(static_cast<Eigen::Index>(delta.indices.size()), 3) * size * 0.3 * (1 + trial % 5);
        applyControlDelta(deformed, delta, 1.0);
        const InjectivityResult verdict = checkInjectivityExact(deformed);
        INFO("trial " << trial << ": " << verdict.message);
        double least = 1e300;
        for (int sample = 0; sample < 400; ++sample) {
            Eigen::Vector3d d;
            Eigen::Matrix3d jacobian;
            deformationJacobian(deformed, randomParameters(rng), d, jacobian);
            least = std::min(least, jacobian.determinant());
        }
        if (verdict.certified) {
            ++certified;
            REQUIRE(least > 0.0);
        }
        if (least < 0.0) {
            ++folds;
            REQUIRE(verdict.verdict == InjectivityVerdict::Fold);
        }
        // The conic test (Gain & Dodgson 2001, Appendix) on the same rational Bezier elements: sufficient only,
        // so it may refuse what the exact test certifies, but never certify a fold.
        const InjectivityResult conic = checkInjectivityConic(deformed);
        rational += volume->isRational();
        if (conic.certified) {
            ++conicCertified;
            REQUIRE(least > 0.0);
            REQUIRE(verdict.certified);
        }
    }
    REQUIRE(certified > 0);
    REQUIRE(folds > 0);
    REQUIRE(conicCertified > 0);
    REQUIRE(rational > 0);
}

TEST_CASE("tspline: a session freezes a T-spline volume on a mesh, drags meet their targets, and JSON round-trips bitwise", "[tspline]") {
    Positions positions;
    Triangles triangles;
    test::icosphere(3, 1.0, Eigen::Vector3d::Zero(), positions, triangles);
    TSplineOctreeSettings settings;
    settings.octree.depth = 2;
    std::shared_ptr<const TSplineVolume> volume;
    REQUIRE(makeOctreeTSplineVolume(positions, settings, volume));
    REQUIRE(volume->isRational());
    // JSON: written, read and written again, the same text; the same volume.
    const nlohmann::json j = io::volumeJson(*volume);
    REQUIRE(j["kind"] == "tspline");
    std::shared_ptr<const Volume> back;
    REQUIRE(io::parseVolumeJson(nlohmann::json::parse(j.dump()), "lattice", back));
    REQUIRE(io::volumeJson(*back).dump() == j.dump());
    REQUIRE(sameVolume(*back, *volume));
    // Non-uniform root knots survive too; placement keeps the T-lattice and the weights.
    TLattice skewed;
    skewed.rootCount = {3, 1, 2};
    skewed.rootKnots[0] = {0.0, 0.2, 0.7, 1.0};
    skewed.rootKnots[2] = {0.0, 0.35, 1.0};
    for (int z = 0; z < 2; ++z)
        for (int x = 0; x < 3; ++x) skewed.cells.push_back(TLatticeCell{0, {x, 0, z}});
    REQUIRE(finishTLattice(skewed));
    TLattice skewedFiner;
    REQUIRE(subdivideTLatticeCells(skewed, {1}, true, skewedFiner));
    std::shared_ptr<const TSplineVolume> uneven;
    REQUIRE(makeTSplineVolumeInBox(skewedFiner, Eigen::AlignedBox3d(Eigen::Vector3d(-1, 0, 2), Eigen::Vector3d(2, 1, 3)), {}, uneven));
    const nlohmann::json ju = io::volumeJson(*uneven);
    REQUIRE(io::parseVolumeJson(nlohmann::json::parse(ju.dump()), "lattice", back));
    REQUIRE(io::volumeJson(*back).dump() == ju.dump());
    REQUIRE(dynamic_cast<const TSplineVolume&>(*back).lattice().knotValue == uneven->lattice().knotValue);
    std::shared_ptr<const Volume> placed;
    REQUIRE(placeVolume(*uneven, Eigen::Vector3d(3, -2, 1), Eigen::Vector3d(0.3, 0.2, 1), 1.7, placed));
    REQUIRE(placed->kindName() == "tspline");
    REQUIRE(placed->controlWeights() == uneven->controlWeights());
    const int last = uneven->controlPointCount() - 1;
    const double scale = 1.7 / uneven->restBounds().diagonal().norm();  // a similarity
    REQUIRE(std::abs((placed->restControlPoints().row(last) - placed->restControlPoints().row(0)).norm() -
                     scale * (uneven->restControlPoints().row(last) - uneven->restControlPoints().row(0)).norm()) <= 1e-12);
    // Through the explicit solution (Hu et al. 2001, eq. 12) on the generic path: targets met.
    Lattice lattice = latticeOf(volume);
    REQUIRE(lattice.tensorNet() == nullptr);
    std::mt19937 rng(1207);
    std::vector<Eigen::Vector3d> params;
    for (int f = 0; f < 3; ++f) params.emplace_back(uniform(rng, 0.3, 0.7), uniform(rng, 0.3, 0.7), uniform(rng, 0.3, 0.7));
    const Eigen::MatrixX3d moves = Eigen::MatrixX3d::Random(3, 3) * 0.05;
    const DirectManipulationResult result = directManipulation(lattice, params, moves);
    applyControlDelta(lattice, result.delta, 1.0);
    for (int f = 0; f < 3; ++f) REQUIRE((displacementAt(lattice, params[static_cast<size_t>(f)]) - moves.row(f).transpose()).norm() <= 1e-12);
    // In a session: freeze, drag a vertex onto a target, undo.
    Session session;
    REQUIRE(session.setMesh(positions, triangles, LatticeSettings{}));
    OpReport report;
    REQUIRE(session.tools().add({"tspline", volume}, report));
    REQUIRE(session.tools().freeze(0, 0, report));
    REQUIRE(report.status == OpStatus::Applied);
    const int vertex = 7;
    const Eigen::Vector3d target = positions.row(vertex).transpose() + Eigen::Vector3d(0.02, -0.05, 0.03);
    REQUIRE(session.dragVertex(vertex, target, report));
    INFO(report.reason);
    REQUIRE(report.status == OpStatus::Applied);
    REQUIRE((session.mesh().positions.row(vertex).transpose() - target).norm() <= 1e-9);
    REQUIRE(session.undo(report));
    REQUIRE((session.mesh().positions - positions).cwiseAbs().maxCoeff() <= 1e-12);
}
