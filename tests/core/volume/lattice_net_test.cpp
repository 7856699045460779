// Net lattices (Coquillart 1990, EFFD): predefined shapes, welding, freezing by Newton (3.3), and the
// oriented parallelepiped against the box lattice in the box's own frame (PyGeM's oriented FFD set-up).
#include <catch2/catch.hpp>

#include <cmath>
#include <memory>
#include <random>
#include <set>

#include "core/deform/direct_manipulation.h"
#include "core/volume/embedding.h"
#include "core/volume/lattice.h"
#include "core/volume/lattice_net.h"

using namespace sculpt;
using namespace sculpt::core;

namespace {

constexpr double kPi = 3.14159265358979323846;

Eigen::Matrix3d randomRotation(std::mt19937& rng) {
    std::normal_distribution<double> g(0.0, 1.0);
    Eigen::Quaterniond q(g(rng), g(rng), g(rng), g(rng));
    return q.normalized().toRotationMatrix();
}

double uniform(std::mt19937& rng, double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); }
int uniformInt(std::mt19937& rng, int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); }

// A random valid net of every predefined kind, with its parameter axes' special roles.
struct RandomNet {
    LatticeNet net;
    int collapsedAxis = -1;  // parameter whose 0 face is collapsed (cylinder r, sphere r)
    int periodicAxis = -1;   // theta
    int polarAxis = -1;      // sphere phi: both faces are poles
};

RandomNet randomNet(std::mt19937& rng, int kind) {
    RandomNet r;
    // note: placed within a few sizes of the origin, as a lattice around a mesh is; far away, the absolute
    // rounding of coordinates (eps |x|) alone exceeds 1e-12 of a small chunk.
    const double size = std::pow(10.0, uniform(rng, -2, 2));
    const Eigen::Vector3d centre = size * Eigen::Vector3d(uniform(rng, -3, 3), uniform(rng, -3, 3), uniform(rng, -3, 3));
    const Eigen::Matrix3d rotation = randomRotation(rng);
    Status s;
    switch (kind) {
        case 0: {
            Eigen::Matrix3d edges = rotation * Eigen::Vector3d(size * uniform(rng, 0.3, 2), size * uniform(rng, 0.3, 2), size * uniform(rng, 0.3, 2)).asDiagonal();
            edges.col(2) += 0.3 * size * Eigen::Vector3d(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1)).cwiseProduct(rotation.col(0));
            if (edges.determinant() < 0) edges.col(2) = -edges.col(2);
            s = makeParallelepipedNet(centre, edges, {uniformInt(rng, 1, 4), uniformInt(rng, 1, 4), uniformInt(rng, 1, 4)},
                                      {uniformInt(rng, 1, 3), uniformInt(rng, 1, 3), uniformInt(rng, 1, 3)}, r.net);
            break;
        }
        case 1:
            s = makeCylinderNet(centre, rotation.col(2), size, size * uniform(rng, 0.5, 3),
                                {uniformInt(rng, 1, 3), uniformInt(rng, 3, 12), uniformInt(rng, 1, 3)}, {uniformInt(rng, 1, 3), uniformInt(rng, 1, 3)}, r.net);
            r.collapsedAxis = 0;
            r.periodicAxis = 1;
            break;
        case 2:
            s = makeSphereNet(centre, rotation.col(1), size, {uniformInt(rng, 1, 3), uniformInt(rng, 3, 8), uniformInt(rng, 2, 6)},
                              uniformInt(rng, 1, 3), r.net);
            r.collapsedAxis = 0;
            r.periodicAxis = 1;
            r.polarAxis = 2;
            break;
        default: {
            PlanarNet profile = makeRectangleNet({-size, -0.5 * size}, {size, 0.5 * size}, {uniformInt(rng, 1, 3), uniformInt(rng, 1, 3)},
                                                 {uniformInt(rng, 1, 3), uniformInt(rng, 1, 3)});
            for (auto& p : profile.points) p.y() += 0.3 * size * std::sin(p.x() / size * 2.0);  // a wavy profile
            s = makeExtrusionNet(profile, centre, rotation.col(0), rotation.col(1), size * rotation.col(2), uniformInt(rng, 1, 3),
                                 uniformInt(rng, 1, 3), r.net);
            break;
        }
    }
    INFO(s.message);
    REQUIRE(s);
    return r;
}

// Parameters in parameter space compared modulo the lattice's symmetries: the periodic seam, and the
// parameters that are undefined on a collapsed face (theta on the axis; theta and phi at the centre;
// theta at a pole).
double parameterError(const RandomNet& r, const Eigen::Vector3d& expected, const Eigen::Vector3d& got) {
    const std::array<int, 3> spans = r.net.spans();
    double error = 0.0;
    const bool onCentre = r.collapsedAxis >= 0 && expected[r.collapsedAxis] == 0.0;
    const bool onPole = r.polarAxis >= 0 && (expected[r.polarAxis] == 0.0 || expected[r.polarAxis] == 1.0);
    for (int a = 0; a < 3; ++a) {
        if (onCentre && a != r.collapsedAxis && (r.polarAxis >= 0 || a == r.periodicAxis)) continue;
        if (onPole && a == r.periodicAxis) continue;
        double d = std::abs(expected[a] - got[a]);
        if (a == r.periodicAxis) d = std::min(d, 1.0 - d);
        error = std::max(error, d * spans[a]);  // in chunk sizes
    }
    return error;
}

}  // namespace

TEST_CASE("net lattice: the predefined shapes are exact at rest (circles, spheres, planes)", "[core][net]") {
    LatticeNet cylinder, sphere;
    REQUIRE(makeCylinderNet({1, 2, 3}, {0, 0, 2}, 2.0, 4.0, {2, 12, 1}, {2, 2}, cylinder));
    REQUIRE(makeSphereNet({1, 2, 3}, {0, 1, 0}, 3.0, {2, 6, 4}, 2, sphere));
    std::mt19937 rng(40);
    for (int sample = 0; sample < 500; ++sample) {
        const Eigen::Vector3d t(uniform(rng, 0, 1), uniform(rng, 0, 1), uniform(rng, 0, 1));
        Eigen::Vector3d q;
        evaluateNetVolume(cylinder, cylinder.rest, t, q);
        // distance from the axis is r * radius exactly (rational arcs), height is z * height.
        REQUIRE(std::hypot(q.x() - 1, q.y() - 2) == Approx(2.0 * t[0]).margin(1e-13));
        REQUIRE(q.z() - 3 == Approx(4.0 * t[2]).margin(1e-13));
        evaluateNetVolume(sphere, sphere.rest, t, q);
        REQUIRE((q - Eigen::Vector3d(1, 2, 3)).norm() == Approx(3.0 * t[0]).margin(1e-13));
    }
    // The welds: the axis is one point per z slice, the seam is welded, the cylinder has 3 boundary faces.
    REQUIRE(cylinder.periodic[1]);
    REQUIRE_FALSE(cylinder.periodic[0]);
    REQUIRE_FALSE(cylinder.boundaryFace[0][0]);  // the axis
    REQUIRE(cylinder.boundaryFace[0][1]);
    REQUIRE_FALSE(cylinder.boundaryFace[1][0]);  // the seam
    REQUIRE(cylinder.boundaryFace[2][0]);
    REQUIRE(cylinder.boundaryFace[2][1]);
    REQUIRE(sphere.periodic[1]);
    REQUIRE_FALSE(sphere.boundaryFace[2][0]);  // poles
    REQUIRE_FALSE(sphere.boundaryFace[2][1]);
    REQUIRE(sphere.boundaryFace[0][1]);
}

TEST_CASE("net lattice: freezing returns every point's own parameters, axis and seam included", "[core][net]") {
    std::mt19937 rng(41);
    for (int trial = 0; trial < 40; ++trial) {
        const RandomNet r = randomNet(rng, trial % 4);
        INFO("kind " << r.net.kind << " trial " << trial);
        for (int sample = 0; sample < 150; ++sample) {
            Eigen::Vector3d t(uniform(rng, 0, 1), uniform(rng, 0, 1), uniform(rng, 0, 1));
            // Special places: faces, chunk boundaries, the collapsed axis, the seam, the poles.
            if (sample % 5 == 0) t[sample % 3] = static_cast<double>(uniformInt(rng, 0, r.net.spans()[sample % 3])) / r.net.spans()[sample % 3];
            if (sample % 7 == 0 && r.collapsedAxis >= 0) t[r.collapsedAxis] = 0.0;
            if (sample % 11 == 0 && r.periodicAxis >= 0) t[r.periodicAxis] = sample % 2 ? 1.0 : 0.0;
            if (sample % 13 == 0 && r.polarAxis >= 0) t[r.polarAxis] = sample % 2 ? 1.0 : 0.0;
            // note: near the collapsed axis theta is ill-conditioned (an error eps in x is eps / r in theta),
            // so interior samples keep r away from it and the axis itself is compared without theta.
            if (r.collapsedAxis >= 0 && t[r.collapsedAxis] != 0.0) t[r.collapsedAxis] = std::max(t[r.collapsedAxis], 0.05);
            if (r.polarAxis >= 0 && t[r.polarAxis] != 0.0 && t[r.polarAxis] != 1.0) t[r.polarAxis] = std::clamp(t[r.polarAxis], 0.03, 0.97);
            Eigen::Vector3d x, back;
            evaluateNetVolume(r.net, r.net.rest, t, x);
            REQUIRE(freezePoint(r.net, r.net.rest, r.net.restIndex, x, back));
            INFO("t = " << t.transpose() << " back = " << back.transpose());
            REQUIRE(parameterError(r, t, back) <= 1e-12);
            Eigen::Vector3d image;
            evaluateNetVolume(r.net, r.net.rest, back, image);
            REQUIRE((image - x).norm() <= 1e-13 * r.net.diagonal());
            // Deterministic: the same answer again.
            Eigen::Vector3d again;
            REQUIRE(freezePoint(r.net, r.net.rest, r.net.restIndex, x, again));
            REQUIRE(again == back);
        }
        // Points outside: beyond the bounds, and (for round lattices) outside the round wall but inside the bounds.
        Eigen::Vector3d t;
        REQUIRE_FALSE(freezePoint(r.net, r.net.rest, r.net.restIndex, r.net.bounds.max() + Eigen::Vector3d::Constant(r.net.diagonal()), t));
        if (r.collapsedAxis >= 0) {
            Eigen::Vector3d corner;
            evaluateNetVolume(r.net, r.net.rest, Eigen::Vector3d(1.0, 0.125, 0.5), corner);
            Eigen::Vector3d centre;
            evaluateNetVolume(r.net, r.net.rest, Eigen::Vector3d(0.0, 0.125, 0.5), centre);
            REQUIRE_FALSE(freezePoint(r.net, r.net.rest, r.net.restIndex, centre + 1.02 * (corner - centre), t));
        }
    }
}

TEST_CASE("net lattice: an undeformed net lattice is the identity on a mesh, and outside points stay", "[core][net]") {
    std::mt19937 rng(42);
    for (int trial = 0; trial < 12; ++trial) {
        const RandomNet r = randomNet(rng, trial % 4);
        LatticeSettings settings;
        settings.volume = std::make_shared<LatticeNet>(r.net);
        Lattice lattice;
        REQUIRE(makeLatticeInBox(settings, {}, {}, lattice));
        Positions rest(300, 3);
        for (int v = 0; v < rest.rows(); ++v)
            for (int a = 0; a < 3; ++a) rest(v, a) = uniform(rng, r.net.bounds.min()[a], r.net.bounds.max()[a]);
        const Embedding e = embedVertices(lattice, rest);
        // Displace a random interior control point group, evaluate, and compare with the volume itself.
        const int slot = uniformInt(rng, 0, r.net.slotCount() - 1);
        ControlDelta delta;
        delta.indices = {lattice.representative(slot)};
        delta.deltas = Eigen::RowVector3d(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1)) * 0.05 * r.net.diagonal();
        expandWelds(lattice, delta);
        applyControlDelta(lattice, delta);
        Positions positions = rest;
        evaluateAll(lattice, e, positions);
        const Positions moved = r.net.rest + lattice.displacement;
        int inside = 0;
        for (int v = 0; v < rest.rows(); ++v) {
            Eigen::Vector3d t;
            if (!restParameters(lattice, rest.row(v).transpose(), t)) {
                REQUIRE(positions.row(v) == rest.row(v));  // outside every chunk: bitwise unchanged
                continue;
            }
            ++inside;
            Eigen::Vector3d expected;
            evaluateNetVolume(r.net, moved, t, expected);
            REQUIRE((positions.row(v).transpose() - expected).norm() <= 1e-12 * r.net.diagonal());
        }
        REQUIRE(inside > 0);
    }
}

TEST_CASE("net lattice: welded points act as one control point and the solver meets targets exactly", "[core][net]") {
    std::mt19937 rng(43);
    for (int trial = 0; trial < 20; ++trial) {
        const RandomNet r = randomNet(rng, 1 + trial % 2);  // cylinders and spheres: axis, seam and poles
        LatticeSettings settings;
        settings.volume = std::make_shared<LatticeNet>(r.net);
        Lattice lattice;
        REQUIRE(makeLatticeInBox(settings, {}, {}, lattice));
        // Sources on the axis and the seam, where welds matter.
        std::vector<Eigen::Vector3d> params = {Eigen::Vector3d(0.0, 0.3, 0.5), Eigen::Vector3d(0.6, 0.0, 0.4)};
        Eigen::MatrixX3d displacements(2, 3);
        displacements << 0.1, -0.05, 0.02, -0.03, 0.04, 0.06;
        displacements *= r.net.diagonal();
        const DirectManipulationResult solved = directManipulation(lattice, params, displacements);
        applyControlDelta(lattice, solved.delta);
        // Every weld group moved as one.
        for (const auto& group : r.net.weldGroups)
            for (int s : group) REQUIRE(lattice.displacement.row(s) == lattice.displacement.row(group[0]));
        // The constraints hold on the volume itself (independent evaluation of Q - Q0).
        const Positions moved = r.net.rest + lattice.displacement;
        for (int f = 0; f < 2; ++f) {
            Eigen::Vector3d before, after;
            evaluateNetVolume(r.net, r.net.rest, params[f], before);
            evaluateNetVolume(r.net, moved, params[f], after);
            REQUIRE((after - before - displacements.row(f).transpose()).norm() <= 1e-12 * r.net.diagonal());
        }
        // The axis stays one point per slice and the seam stays closed: theta = 0 and theta = 1 agree.
        Eigen::Vector3d a, b;
        evaluateNetVolume(r.net, moved, Eigen::Vector3d(0.7, 0.0, 0.3), a);
        evaluateNetVolume(r.net, moved, Eigen::Vector3d(0.7, 1.0, 0.3), b);
        REQUIRE((a - b).norm() <= 1e-13 * r.net.diagonal());
        evaluateNetVolume(r.net, moved, Eigen::Vector3d(0.0, 0.1, 0.3), a);
        evaluateNetVolume(r.net, moved, Eigen::Vector3d(0.0, 0.8, 0.3), b);
        REQUIRE((a - b).norm() <= 1e-13 * r.net.diagonal());
    }
}

TEST_CASE("net lattice: an oriented parallelepiped gives the box lattice's result in the box frame (PyGeM set-up)", "[core][net]") {
    // PyGeM's test_ffd_sphere_mod: a 3 x 2 x 2 Bernstein box, origin (-20, -55, -45), lengths (45, 90, 90),
    // rotated by Ry(10) then Rz(15); control point (2, 0, 0) moved by (0.8, -0.5, -1.0) box lengths along
    // the box's own axes. The box lattice reproduces PyGeM's stored output (shared/cases/README.md) once the
    // points are taken into the box frame by hand; the parallelepiped must give the same natively.
    const double deg = kPi / 180.0;
    const Eigen::Matrix3d rotation =
        (Eigen::AngleAxisd(10 * deg, Eigen::Vector3d::UnitY()) * Eigen::AngleAxisd(15 * deg, Eigen::Vector3d::UnitZ())).toRotationMatrix();
    const Eigen::Vector3d origin(-20, -55, -45), lengths(45, 90, 90), move(0.8, -0.5, -1.0);
    LatticeNet net;
    REQUIRE(makeParallelepipedNet(origin, rotation * lengths.asDiagonal(), {1, 1, 1}, {2, 1, 1}, net));
    LatticeSettings netSettings;
    netSettings.volume = std::make_shared<LatticeNet>(net);
    Lattice oriented;
    REQUIRE(makeLatticeInBox(netSettings, {}, {}, oriented));
    oriented.displacement.row(oriented.index(2, 0, 0)) = (rotation * lengths.cwiseProduct(move)).transpose();
    LatticeSettings boxSettings;
    boxSettings.resolution = {3, 2, 2};
    boxSettings.degree = {2, 1, 1};
    Lattice box;
    REQUIRE(makeLatticeInBox(boxSettings, Eigen::Vector3d::Zero(), lengths, box));
    box.displacement.row(box.index(2, 0, 0)) = lengths.cwiseProduct(move).transpose();

    std::mt19937 rng(44);
    Positions world(2000, 3), local(2000, 3);
    for (int v = 0; v < world.rows(); ++v) {
        // A sphere of points around the box like PyGeM's, some outside it.
        const Eigen::Vector3d inBox = lengths.cwiseProduct(Eigen::Vector3d(uniform(rng, -0.2, 1.2), uniform(rng, -0.2, 1.2), uniform(rng, -0.2, 1.2)));
        local.row(v) = inBox.transpose();
        world.row(v) = (origin + rotation * inBox).transpose();
    }
    Positions worldOut = world, localOut = local;
    evaluateAll(oriented, embedVertices(oriented, world), worldOut);
    evaluateAll(box, embedVertices(box, local), localOut);
    double worst = 0.0;
    for (int v = 0; v < world.rows(); ++v) {
        const Eigen::Vector3d expected = origin + rotation * localOut.row(v).transpose();
        worst = std::max(worst, (worldOut.row(v).transpose() - expected).norm());
    }
    INFO("largest difference " << worst);
    REQUIRE(worst <= 1e-11);  // coordinates of size 100: a few hundred ulps
}

TEST_CASE("net lattice: drawing shows merged points once and the chunks' edges as exact curves", "[core][net]") {
    std::mt19937 rng(1044);
    for (int trial = 0; trial < 24; ++trial) {
        const int kind = trial % 4;
        const RandomNet r = randomNet(rng, kind);
        LatticeSettings settings;
        settings.volume = std::make_shared<LatticeNet>(r.net);
        Lattice lattice;
        REQUIRE(makeLattice(settings, Positions::Zero(1, 3), lattice));
        // Every edge joins two distinct representatives, once; every grid neighbour pair of distinct groups is there.
        const std::vector<std::array<int, 2>> edges = controlNetEdges(lattice);
        std::set<std::array<int, 2>> seen(edges.begin(), edges.end());
        REQUIRE(seen.size() == edges.size());
        for (const auto& e : edges) {
            REQUIRE(e[0] < e[1]);
            REQUIRE(lattice.representative(e[0]) == e[0]);
            REQUIRE(lattice.representative(e[1]) == e[1]);
        }
        for (int idx = 0; idx < lattice.controlPointCount(); ++idx) {
            const std::array<int, 3> c = lattice.ijk(idx);
            for (int a = 0; a < 3; ++a) {
                if (c[a] + 1 >= lattice.count[a]) continue;
                std::array<int, 3> n = c;
                ++n[a];
                const int p = lattice.representative(idx), q = lattice.representative(lattice.index(n[0], n[1], n[2]));
                if (p != q) REQUIRE(seen.count({std::min(p, q), std::max(p, q)}) == 1);
            }
        }
        // Chunk edges lie on the volume: on a cylinder, the rest curves along the angle are exact circles
        // (rational arcs), so every sample is at the knot radius from the axis.
        const std::vector<Positions> curves = chunkEdgeCurves(lattice, 6);
        REQUIRE(!curves.empty());
        for (const Positions& curve : curves) REQUIRE(curve.allFinite());
        if (kind == 1) {
            const Eigen::Vector3d base = r.net.rest.row(0).transpose();  // slot 0 lies on the axis (r = 0, z = 0)
            const Eigen::Vector3d top = r.net.rest.row(r.net.slot(0, 0, r.net.count[2] - 1)).transpose();
            const Eigen::Vector3d axis = (top - base).normalized();
            int circles = 0;
            for (const Positions& curve : curves) {
                double lo = 1e300, hi = 0.0;
                for (int s = 0; s < curve.rows(); ++s) {
                    const Eigen::Vector3d d = curve.row(s).transpose() - base;
                    const double radius = (d - d.dot(axis) * axis).norm();
                    lo = std::min(lo, radius), hi = std::max(hi, radius);
                }
                // a curve through the angle is closed (first = last sample) and of constant radius
                if ((curve.row(0) - curve.row(curve.rows() - 1)).norm() < 1e-9 * lattice.diagonal() && lo > 1e-6 * lattice.diagonal()) {
                    ++circles;
                    REQUIRE(hi - lo <= 1e-12 * lattice.diagonal());
                }
            }
            const std::array<int, 3> spans = r.net.spans();
            REQUIRE(circles == spans[0] * (spans[2] + 1));
        }
    }
}
