// Editing a lattice that is not frozen (Coquillart 1990, EFFD, 3.1.4; core/volume/lattice_edit.h): moving, merging,
// inserting points by refinement (Boehm's knot insertion: the volume does not change) and removing slices,
// over random nets of every predefined kind with fixed seeds, each against an independent computation.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>

#include "core/volume/lattice.h"
#include "core/volume/lattice_edit.h"
#include "core/volume/lattice_net.h"

using namespace sculpt;
using namespace sculpt::core;

namespace {

double uniform(std::mt19937& rng, double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); }
int uniformInt(std::mt19937& rng, int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); }

Eigen::Matrix3d randomRotation(std::mt19937& rng) {
    std::normal_distribution<double> g(0.0, 1.0);
    return Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized().toRotationMatrix();
}

// A random valid net: 0 parallelepiped, 1 cylinder, 2 sphere, 3 extrusion of a wavy profile. Random placement,
// size, chunks and degrees (few chunks, so a refinement stays within 64 points per axis).
LatticeNet randomNet(std::mt19937& rng, int kind) {
    const double size = std::pow(10.0, uniform(rng, -2, 2));
    const Eigen::Vector3d centre = size * Eigen::Vector3d(uniform(rng, -3, 3), uniform(rng, -3, 3), uniform(rng, -3, 3));
    const Eigen::Matrix3d rotation = randomRotation(rng);
    LatticeNet net;
    Status s;
    switch (kind) {
        case 0: {
            Eigen::Matrix3d edges = rotation * Eigen::Vector3d(size * uniform(rng, 0.3, 2), size * uniform(rng, 0.3, 2), size * uniform(rng, 0.3, 2)).asDiagonal();
            edges.col(2) += 0.3 * size * Eigen::Vector3d(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1)).cwiseProduct(rotation.col(0));
            if (edges.determinant() < 0) edges.col(2) = -edges.col(2);
            s = makeParallelepipedNet(centre, edges, {uniformInt(rng, 1, 4), uniformInt(rng, 1, 4), uniformInt(rng, 1, 4)},
                                      {uniformInt(rng, 1, 4), uniformInt(rng, 1, 4), uniformInt(rng, 1, 4)}, net);
            break;
        }
        case 1:
            s = makeCylinderNet(centre, rotation.col(2), size, size * uniform(rng, 0.5, 3),
                                {uniformInt(rng, 1, 3), uniformInt(rng, 3, 10), uniformInt(rng, 1, 3)}, {uniformInt(rng, 1, 3), uniformInt(rng, 1, 3)}, net);
            break;
        case 2:
            s = makeSphereNet(centre, rotation.col(1), size, {uniformInt(rng, 1, 3), uniformInt(rng, 3, 8), uniformInt(rng, 2, 6)},
                              uniformInt(rng, 1, 3), net);
            break;
        default: {
            PlanarNet profile = makeRectangleNet({-size, -0.5 * size}, {size, 0.5 * size}, {uniformInt(rng, 1, 3), uniformInt(rng, 1, 3)},
                                                 {uniformInt(rng, 1, 3), uniformInt(rng, 1, 3)});
            for (auto& p : profile.points) p.y() += 0.3 * size * std::sin(p.x() / size * 2.0);
            s = makeExtrusionNet(profile, centre, rotation.col(0), rotation.col(1), size * rotation.col(2), uniformInt(rng, 1, 3),
                                 uniformInt(rng, 1, 3), net);
            break;
        }
    }
    INFO(s.message);
    REQUIRE(s);
    return net;
}

Eigen::Vector3d volumeAt(const LatticeNet& net, const Positions& points, const Eigen::Vector3d& t) {
    Eigen::Vector3d q;
    evaluateNetVolume(net, points, t, q);
    return q;
}

Eigen::Vector3d randomParameter(std::mt19937& rng) { return {uniform(rng, 0, 1), uniform(rng, 0, 1), uniform(rng, 0, 1)}; }

// The rest points with `delta` added to every slot of the weld groups of `slots` (a displacement of those
// control points as the lattice defines it: welded slots move together).
Positions displaced(const LatticeNet& net, const std::vector<int>& slots, const Eigen::Vector3d& delta) {
    std::vector<char> moved(net.slotCount(), 0);
    for (int s : slots) moved[net.weldedTo[s]] = 1;
    Positions p = net.rest;
    for (int s = 0; s < net.slotCount(); ++s)
        if (moved[net.weldedTo[s]]) p.row(s) += delta.transpose();
    return p;
}

// A cylinder's or ball's net after an edit: every slot with r index 0 in a slice is one point (the axis, the
// centre), and the periodic seam (the last angle slice) is welded to the first.
void requireAxisAndSeamWelded(const LatticeNet& net) {
    for (int k = 0; k < net.count[2]; ++k)
        for (int j = 0; j < net.count[1]; ++j) REQUIRE(net.weldedTo[net.slot(0, j, k)] == net.weldedTo[net.slot(0, 0, k)]);
    for (int k = 0; k < net.count[2]; ++k)
        for (int i = 0; i < net.count[0]; ++i) REQUIRE(net.weldedTo[net.slot(i, net.count[1] - 1, k)] == net.weldedTo[net.slot(i, 0, k)]);
}

// A ring of degree-1 chunks (a hollow polygonal cylinder: radii 0.5 and 1, `sides` sides) whose angle axis is
// periodic with multiplicity 1, so a slice of it can be removed; the seam is welded, nothing else.
LatticeNet polygonRing(int sides) {
    LatticeNet net;
    net.kind = "net";
    net.count = {2, sides + 1, 2};
    net.degree = {1, 1, 1};
    net.rest.resize(net.slotCount(), 3);
    for (int k = 0; k < 2; ++k)
        for (int j = 0; j <= sides; ++j)
            for (int i = 0; i < 2; ++i) {
                const double angle = 2.0 * 3.14159265358979323846 * (j % sides) / sides;
                const double r = i == 0 ? 0.5 : 1.0;
                net.rest.row(net.slot(i, j, k)) = Eigen::RowVector3d(r * std::cos(angle), r * std::sin(angle), k);
            }
    weldCoincidentSlots(net);
    REQUIRE(finishLatticeNet(net));
    return net;
}

}  // namespace

TEST_CASE("lattice edit: refining any axis of any kind of net leaves the volume unchanged", "[netedit]") {
    std::mt19937 rng(4101);
    int refined = 0;
    for (int kind = 0; kind < 4; ++kind)
        for (int trial = 0; trial < 6; ++trial) {
            const LatticeNet net = randomNet(rng, kind);
            const LatticeNet copy = net;
            for (int axis = 0; axis < 3; ++axis) {
                LatticeNet fine;
                const Status s = refineNetAxis(net, axis, fine);
                INFO("kind " << kind << " trial " << trial << " axis " << axis << ": " << s.message);
                REQUIRE(s);
                ++refined;
                REQUIRE(sameLatticeNet(net, copy));  // the input is untouched
                // Counts: the spans double along the axis, the other axes keep theirs.
                REQUIRE(fine.axes[axis].spans == 2 * net.axes[axis].spans);
                REQUIRE(fine.count[axis] == splineAxisCount(2 * net.axes[axis].spans, net.degree[axis], net.multiplicity[axis]));
                for (int b = 0; b < 3; ++b)
                    if (b != axis) REQUIRE(fine.count[b] == net.count[b]);
                REQUIRE(fine.degree == net.degree);
                REQUIRE(fine.multiplicity == net.multiplicity);
                // The volume, at 200 random parameters: Q'(t) = Q(t) to rounding (the knot vectors of the
                // refined axis contain the old knots, so the same t is the same point of the volume).
                const double tolerance = 1e-12 * net.diagonal();
                for (int sample = 0; sample < 200; ++sample) {
                    const Eigen::Vector3d t = randomParameter(rng);
                    REQUIRE((volumeAt(fine, fine.rest, t) - volumeAt(net, net.rest, t)).norm() <= tolerance);
                }
                // Freezing in the refined net (its own chunk index) finds the same parameters (away from the
                // seam and the collapsed faces, where a point has several).
                for (int sample = 0; sample < 10; ++sample) {
                    const Eigen::Vector3d t = Eigen::Vector3d::Constant(0.1) + 0.8 * randomParameter(rng);
                    Eigen::Vector3d frozen;
                    REQUIRE(freezePoint(fine, fine.rest, fine.restIndex, volumeAt(net, net.rest, t), frozen));
                    REQUIRE((frozen - t).cwiseAbs().maxCoeff() <= 1e-8);
                }
                // The weld structure is the same lattice's: seams stay seams, collapsed faces stay collapsed.
                REQUIRE(fine.periodic == net.periodic);
                REQUIRE(fine.collapsedAlong == net.collapsedAlong);
                REQUIRE(fine.boundaryFace == net.boundaryFace);
                REQUIRE(fine.weldGroups.size() >= net.weldGroups.size());
            }
        }
    REQUIRE(refined == 72);
}

TEST_CASE("lattice edit: refinement welds by structure so every old deformation is a deformation of the refined net", "[netedit]") {
    std::mt19937 rng(4102);
    for (int kind = 1; kind < 3; ++kind)
        for (int trial = 0; trial < 5; ++trial) {
            const LatticeNet net = randomNet(rng, kind);
            // Displace a few random control points (as the lattice does: a welded group moves as one) by a
            // small amount, and refine the displaced net too: its welds are the refined rest net's (they
            // depend on the structure, not on where the points are), and its volume is the displaced volume.
            std::vector<int> slots;
            for (int m = 0; m < 4; ++m) slots.push_back(uniformInt(rng, 0, net.slotCount() - 1));
            LatticeNet moved;
            REQUIRE(moveNetPoints(net, slots, 0.02 * net.diagonal() * Eigen::Vector3d(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1)), moved));
            for (int axis = 0; axis < 3; ++axis) {
                LatticeNet fineRest, fineMoved;
                REQUIRE(refineNetAxis(net, axis, fineRest));
                REQUIRE(refineNetAxis(moved, axis, fineMoved));
                INFO("kind " << kind << " axis " << axis);
                REQUIRE(fineMoved.weldedTo == fineRest.weldedTo);
                for (int sample = 0; sample < 50; ++sample) {
                    const Eigen::Vector3d t = randomParameter(rng);
                    REQUIRE((volumeAt(fineMoved, fineMoved.rest, t) - volumeAt(moved, moved.rest, t)).norm() <= 1e-12 * net.diagonal());
                }
                requireAxisAndSeamWelded(fineRest);
            }
        }
}

TEST_CASE("lattice edit: refinement does not weld points that merely coincide", "[netedit]") {
    // A cylinder whose axis and seam points were never welded: they coincide, but they are separate control
    // points, and the refined net must keep every new point separate too (coincident or not).
    LatticeNet cylinder;
    REQUIRE(makeCylinderNet(Eigen::Vector3d(0.1, 0.2, 0.3), Eigen::Vector3d(0.3, 1, 0.2), 0.8, 1.5, {2, 5, 2}, {2, 2}, cylinder));
    LatticeNet unwelded = cylinder;
    for (int s = 0; s < unwelded.slotCount(); ++s) unwelded.weldedTo[s] = s;
    REQUIRE(finishLatticeNet(unwelded));
    REQUIRE(unwelded.weldGroups.empty());
    for (int axis = 0; axis < 3; ++axis) {
        LatticeNet fine, fineWelded;
        REQUIRE(refineNetAxis(unwelded, axis, fine));
        REQUIRE(refineNetAxis(cylinder, axis, fineWelded));
        INFO("axis " << axis);
        REQUIRE(fine.weldGroups.empty());
        REQUIRE(fine.count == fineWelded.count);
        REQUIRE_FALSE(fineWelded.weldGroups.empty());
        // The same points, to rounding: only the welds differ.
        REQUIRE((fine.rest - fineWelded.rest).cwiseAbs().maxCoeff() <= 1e-12 * cylinder.diagonal());
    }
}

TEST_CASE("lattice edit: refinement keeps the structure of a hand-welded net", "[netedit]") {
    // Two neighbouring points of a box merged by the user: after refinement, the new points that are
    // combinations of that one merged point only are welded to it, the others are not.
    LatticeNet box;
    REQUIRE(makeParallelepipedNet(Eigen::Vector3d::Zero(), Eigen::Matrix3d::Identity(), {3, 2, 2}, {1, 2, 2}, box));
    LatticeNet merged;
    REQUIRE(mergeNetPoints(box, {box.slot(1, 1, 1), box.slot(2, 1, 1)}, merged));
    LatticeNet fine;
    REQUIRE(refineNetAxis(merged, 0, fine));
    // Degree 1 along u: the new point at the middle of span 1 (between old slots 1 and 2) is the merged point.
    REQUIRE(fine.count[0] == 7);
    const int rep = fine.weldedTo[fine.slot(2, 1, 1)];
    REQUIRE(fine.weldedTo[fine.slot(3, 1, 1)] == rep);
    REQUIRE(fine.weldedTo[fine.slot(4, 1, 1)] == rep);
    REQUIRE(fine.weldedTo[fine.slot(1, 1, 1)] != rep);
    REQUIRE(fine.weldedTo[fine.slot(5, 1, 1)] != rep);
    REQUIRE(fine.weldGroups.size() == 1);
}

TEST_CASE("lattice edit: moving a slot moves its weld group and nothing else", "[netedit]") {
    std::mt19937 rng(4103);
    for (int kind = 0; kind < 4; ++kind)
        for (int trial = 0; trial < 5; ++trial) {
            const LatticeNet net = randomNet(rng, kind);
            std::vector<int> slots;
            const int picks = uniformInt(rng, 1, 4);
            for (int m = 0; m < picks; ++m) slots.push_back(uniformInt(rng, 0, net.slotCount() - 1));
            slots.push_back(slots.front());  // a duplicate moves once
            const Eigen::Vector3d offset = 0.01 * net.diagonal() * Eigen::Vector3d(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
            LatticeNet moved;
            REQUIRE(moveNetPoints(net, slots, offset, moved));
            REQUIRE(moved.weldedTo == net.weldedTo);
            REQUIRE(moved.weights == net.weights);
            std::vector<char> inGroup(net.slotCount(), 0);
            for (int s : slots) inGroup[net.weldedTo[s]] = 1;
            for (int s = 0; s < net.slotCount(); ++s) {
                const Eigen::RowVector3d expected = inGroup[net.weldedTo[s]] ? Eigen::RowVector3d(net.rest.row(s) + offset.transpose())
                                                                             : Eigen::RowVector3d(net.rest.row(s));
                REQUIRE(moved.rest.row(s) == expected);
                REQUIRE(moved.rest.row(s) == moved.rest.row(moved.weldedTo[s]));  // welded points stay one point
            }
        }
    // The cylinder's axis: moving one slot of slice k moves every slot (0, j, k).
    LatticeNet cylinder, moved;
    REQUIRE(makeCylinderNet(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 1.0, 2.0, {2, 6, 2}, {2, 2}, cylinder));
    REQUIRE(moveNetPoints(cylinder, {cylinder.slot(0, 3, 1)}, Eigen::Vector3d(0.05, 0, 0), moved));
    for (int j = 0; j < cylinder.count[1]; ++j) {
        REQUIRE(moved.rest(moved.slot(0, j, 1), 0) == cylinder.rest(cylinder.slot(0, j, 1), 0) + 0.05);
        REQUIRE(moved.rest.row(moved.slot(0, j, 0)) == cylinder.rest.row(cylinder.slot(0, j, 0)));
    }
}

TEST_CASE("lattice edit: a merged point's basis is the sum of the merged ones", "[netedit]") {
    std::mt19937 rng(4104);
    int merges = 0;
    for (int kind = 0; kind < 4; ++kind)
        for (int trial = 0; trial < 12; ++trial) {
            const LatticeNet net = randomNet(rng, kind);
            // Neighbouring slots along a random axis (merging far points usually folds a chunk).
            const int axis = uniformInt(rng, 0, 2);
            std::array<int, 3> ijk{uniformInt(rng, 0, net.count[0] - 1), uniformInt(rng, 0, net.count[1] - 1), uniformInt(rng, 0, net.count[2] - 1)};
            ijk[axis] = uniformInt(rng, 0, net.count[axis] - 2);
            std::vector<int> slots{net.slot(ijk[0], ijk[1], ijk[2])};
            ++ijk[axis];
            slots.push_back(net.slot(ijk[0], ijk[1], ijk[2]));
            std::vector<int> groups{net.weldedTo[slots[0]], net.weldedTo[slots[1]]};
            if (groups[0] == groups[1]) {
                LatticeNet out = net;
                const Status s = mergeNetPoints(net, slots, out);
                REQUIRE_FALSE(s);  // one point already: nothing to merge
                REQUIRE(s.message.find("at least 2 distinct points") != std::string::npos);
                REQUIRE(sameLatticeNet(out, net));
                continue;
            }
            LatticeNet merged;
            const Status s = mergeNetPoints(net, slots, merged);
            if (!s) {  // a chunk became flat or folded: refused with the reason
                REQUIRE(s.message.find("leaves an invalid lattice") != std::string::npos);
                continue;
            }
            ++merges;
            // Every slot of both groups is one point, at the plain mean of the two.
            const Eigen::RowVector3d mean = 0.5 * (net.rest.row(groups[0]) + net.rest.row(groups[1]));
            const int rep = std::min(groups[0], groups[1]);
            int members = 0;
            for (int s2 = 0; s2 < net.slotCount(); ++s2) {
                const bool inMerged = net.weldedTo[s2] == groups[0] || net.weldedTo[s2] == groups[1];
                if (inMerged) {
                    ++members;
                    REQUIRE(merged.weldedTo[s2] == rep);
                    REQUIRE(merged.rest.row(s2) == mean);
                } else {
                    REQUIRE(merged.weldedTo[s2] == net.weldedTo[s2]);
                    REQUIRE(merged.rest.row(s2) == net.rest.row(s2));
                }
            }
            REQUIRE(members >= 2);
            // The merged control point's basis is the sum of the former ones: a displacement delta of it moves
            // the volume by sum over the former groups g of (the old volume with g displaced - the old volume).
            const Eigen::Vector3d delta = 0.1 * net.diagonal() * Eigen::Vector3d(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
            const Positions mergedMoved = displaced(merged, {rep}, delta);
            const Positions oldMoved0 = displaced(net, {groups[0]}, delta), oldMoved1 = displaced(net, {groups[1]}, delta);
            for (int sample = 0; sample < 50; ++sample) {
                const Eigen::Vector3d t = randomParameter(rng);
                const Eigen::Vector3d mergedChange = volumeAt(merged, mergedMoved, t) - volumeAt(merged, merged.rest, t);
                const Eigen::Vector3d sum = (volumeAt(net, oldMoved0, t) - volumeAt(net, net.rest, t)) +
                                            (volumeAt(net, oldMoved1, t) - volumeAt(net, net.rest, t));
                REQUIRE((mergedChange - sum).norm() <= 1e-12 * net.diagonal());
            }
        }
    REQUIRE(merges >= 20);
}

TEST_CASE("lattice edit: merging slots already in groups merges the groups", "[netedit]") {
    // The cylinder's axis in slice 0 (one group) and the axis in slice 1 (another): merged, every axis slot of
    // both slices is one point, at the mean of the two axis points (each group counted once).
    LatticeNet cylinder, merged;
    REQUIRE(makeCylinderNet(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 1.0, 2.0, {2, 6, 3}, {2, 1}, cylinder));
    REQUIRE(mergeNetPoints(cylinder, {cylinder.slot(0, 2, 1), cylinder.slot(0, 4, 2)}, merged));
    const Eigen::RowVector3d mean = 0.5 * (cylinder.rest.row(cylinder.slot(0, 0, 1)) + cylinder.rest.row(cylinder.slot(0, 0, 2)));
    const int rep = cylinder.slot(0, 0, 1);
    for (int k = 1; k <= 2; ++k)
        for (int j = 0; j < cylinder.count[1]; ++j) {
            REQUIRE(merged.weldedTo[merged.slot(0, j, k)] == rep);
            REQUIRE(merged.rest.row(merged.slot(0, j, k)) == mean);
        }
    REQUIRE(merged.weldGroups.size() == cylinder.weldGroups.size() - 1);
}

TEST_CASE("lattice edit: removing a slice keeps the other points, their welds and a valid lattice", "[netedit]") {
    std::mt19937 rng(4105);
    int removed = 0;
    for (int kind = 0; kind < 4; ++kind)
        for (int trial = 0; trial < 8; ++trial) {
            const LatticeNet net = randomNet(rng, kind);
            for (int axis = 0; axis < 3; ++axis) {
                const int index = uniformInt(rng, 0, net.count[axis] - 1);
                LatticeNet out;
                const Status s = removeNetSlice(net, axis, index, out);
                const bool tooFew = net.count[axis] - 1 < net.degree[axis] + 1;
                const bool multiplicity = !tooFew && !splineAxisCountValid(net.count[axis] - 1, net.degree[axis], net.multiplicity[axis]);
                const bool seam = net.periodic[axis] && (index == 0 || index == net.count[axis] - 1);
                const bool collapsed = (index == 0 && net.collapsedAlong[axis][0]) || (index == net.count[axis] - 1 && net.collapsedAlong[axis][1]);
                INFO("kind " << kind << " axis " << axis << " index " << index << ": " << s.message);
                if (tooFew || multiplicity || seam || collapsed) {
                    REQUIRE_FALSE(s);
                    REQUIRE(s.message.find("slice " + std::to_string(index)) != std::string::npos);
                    if (tooFew) REQUIRE(s.message.find("needs at least") != std::string::npos);
                    else if (multiplicity) REQUIRE(s.message.find("per knot span") != std::string::npos);
                    else if (seam) REQUIRE(s.message.find("seam") != std::string::npos);
                    else REQUIRE(s.message.find("collapsed face") != std::string::npos);
                    continue;
                }
                if (!s) {  // the remaining rest net folds: said so
                    REQUIRE(s.message.find("leaves an invalid lattice") != std::string::npos);
                    continue;
                }
                ++removed;
                std::array<int, 3> expected = net.count;
                --expected[axis];
                REQUIRE(out.count == expected);
                REQUIRE(out.axes[axis].spans == net.axes[axis].spans - 1);
                // The other slots, in order, with their points, weights and weld groups.
                int t = 0;
                for (int k = 0; k < net.count[2]; ++k)
                    for (int j = 0; j < net.count[1]; ++j)
                        for (int i = 0; i < net.count[0]; ++i) {
                            const std::array<int, 3> ijk{i, j, k};
                            if (ijk[axis] == index) continue;
                            const int s2 = net.slot(i, j, k);
                            REQUIRE(out.rest.row(t) == net.rest.row(s2));
                            REQUIRE(out.weights[t] == net.weights[s2]);
                            ++t;
                        }
                REQUIRE(t == out.slotCount());
                REQUIRE(out.periodic == net.periodic);
            }
        }
    REQUIRE(removed >= 20);

    // A cylinder: a z slice goes (its axis point with it), the others keep their axis welded; the axis itself
    // and the angle slices (multiplicity 2) cannot go.
    LatticeNet cylinder, out;
    REQUIRE(makeCylinderNet(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 1.0, 2.0, {2, 6, 3}, {2, 1}, cylinder));
    REQUIRE(removeNetSlice(cylinder, 2, 1, out));
    REQUIRE(out.count[2] == 3);
    REQUIRE(out.collapsedAlong == cylinder.collapsedAlong);
    REQUIRE(out.periodic[1]);
    Status s = removeNetSlice(cylinder, 0, 0, out);
    REQUIRE(s.message.find("collapsed face") != std::string::npos);
    s = removeNetSlice(cylinder, 1, 3, out);
    REQUIRE(s.message.find("per knot span") != std::string::npos);

    // A periodic axis of multiplicity 1: an interior slice goes and the ring stays closed; the seam does not.
    const LatticeNet ring = polygonRing(7);
    REQUIRE(ring.periodic[1]);
    REQUIRE(removeNetSlice(ring, 1, 3, out));
    REQUIRE(out.count[1] == 7);
    REQUIRE(out.periodic[1]);
    s = removeNetSlice(ring, 1, 0, out);
    REQUIRE_FALSE(s);
    REQUIRE(s.message == "cannot remove slice 0 along v: it is the seam of the closed (periodic) axis, welded to slice 7; removing it would open the lattice");
    s = removeNetSlice(ring, 1, 7, out);
    REQUIRE(s.message.find("seam") != std::string::npos);
}

TEST_CASE("lattice edit: bad edits are refused with the reason and change nothing", "[netedit]") {
    LatticeNet box;
    REQUIRE(makeParallelepipedNet(Eigen::Vector3d::Zero(), Eigen::Matrix3d::Identity(), {1, 1, 1}, {1, 1, 1}, box));
    REQUIRE(box.slotCount() == 8);
    LatticeNet fine;
    REQUIRE(makeParallelepipedNet(Eigen::Vector3d::Zero(), Eigen::Matrix3d::Identity(), {40, 1, 1}, {1, 1, 1}, fine));
    const LatticeNet boxCopy = box, fineCopy = fine;
    LatticeNet sentinel;
    REQUIRE(makeSphereNet(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 1.0, {1, 3, 2}, 1, sentinel));
    const LatticeNet sentinelCopy = sentinel;
    struct Case {
        Status status;
        std::string message;
    };
    const double nan = std::numeric_limits<double>::quiet_NaN();
    std::vector<Case> cases;
    cases.push_back({moveNetPoints(box, {2, 17}, Eigen::Vector3d(0, 0, 1), sentinel), "slot 17 is out of range (the lattice has 8 points)"});
    cases.push_back({moveNetPoints(box, {-1}, Eigen::Vector3d(0, 0, 1), sentinel), "slot -1 is out of range"});
    cases.push_back({moveNetPoints(box, {}, Eigen::Vector3d(0, 0, 1), sentinel), "at least one slot"});
    cases.push_back({moveNetPoints(box, {1}, Eigen::Vector3d(0, nan, 1), sentinel), "finite"});
    cases.push_back({moveNetPoints(box, {1, 3, 5, 7}, Eigen::Vector3d(-2, 0, 0), sentinel), "moving slots 1, 3, 5, 7 leaves an invalid lattice: lattice chunk [0,0,0] is left-handed"});
    cases.push_back({mergeNetPoints(box, {3, 3}, sentinel), "at least 2 distinct points"});
    cases.push_back({mergeNetPoints(box, {3, 64}, sentinel), "slot 64 is out of range"});
    cases.push_back({mergeNetPoints(box, {0, 1, 2, 3, 4, 5}, sentinel), "merging slots 0, 1, 2, 3, 4, 5 leaves an invalid lattice: lattice chunk [0,0,0] is flat"});
    cases.push_back({refineNetAxis(box, 3, sentinel), "axis 3 is out of range"});
    cases.push_back({refineNetAxis(fine, 0, sentinel), "would make 81 control points"});
    cases.push_back({removeNetSlice(box, 0, 0, sentinel), "needs at least 2"});
    cases.push_back({removeNetSlice(fine, 0, 41, sentinel), "slice 41 along u is out of range (the lattice has 41 slices along u)"});
    cases.push_back({removeNetSlice(fine, -1, 0, sentinel), "axis -1 is out of range"});
    std::vector<NetEdit> edits(2);
    edits[0].kind = NetEdit::Kind::Refine;
    edits[1].kind = NetEdit::Kind::Merge;
    edits[1].slots = {5};
    cases.push_back({applyNetEdits(box, edits, sentinel), "edits[1]: merging needs at least 2 distinct points"});
    for (const Case& c : cases) {
        INFO(c.message << " / got: " << c.status.message);
        REQUIRE_FALSE(c.status);
        REQUIRE(c.status.message.find(c.message) != std::string::npos);
    }
    REQUIRE(sameLatticeNet(box, boxCopy));
    REQUIRE(sameLatticeNet(fine, fineCopy));
    REQUIRE(sameLatticeNet(sentinel, sentinelCopy));  // `out` untouched on failure
}

TEST_CASE("lattice edit: a list of edits applies in order", "[netedit]") {
    LatticeNet box;
    REQUIRE(makeParallelepipedNet(Eigen::Vector3d(1, 2, 3), Eigen::Matrix3d::Identity() * 2.0, {2, 2, 2}, {2, 2, 2}, box));
    std::vector<NetEdit> edits(3);
    edits[0].kind = NetEdit::Kind::Refine;
    edits[0].axis = 2;
    edits[1].kind = NetEdit::Kind::Move;
    edits[1].slots = {0};
    edits[1].offset = Eigen::Vector3d(0.1, 0, 0);
    edits[2].kind = NetEdit::Kind::Remove;
    edits[2].axis = 2;
    edits[2].index = 3;
    LatticeNet out, step1, step2, step3;
    REQUIRE(applyNetEdits(box, edits, out));
    REQUIRE(refineNetAxis(box, 2, step1));
    REQUIRE(moveNetPoints(step1, {0}, Eigen::Vector3d(0.1, 0, 0), step2));
    REQUIRE(removeNetSlice(step2, 2, 3, step3));
    REQUIRE(sameLatticeNet(out, step3));
    REQUIRE(out.count == std::array<int, 3>{4, 4, 5});
}

TEST_CASE("lattice edit: a merge that folds a chunk at rest is refused and changes nothing", "[netedit]") {
    std::mt19937 rng(515);
    for (int trial = 0; trial < 10; ++trial) {
        LatticeNet box;
        const std::array<int, 3> chunks{uniformInt(rng, 1, 3), uniformInt(rng, 1, 3), uniformInt(rng, 1, 3)};
        REQUIRE(makeParallelepipedNet(Eigen::Vector3d::Zero(), Eigen::Vector3d(1.0, 1.5, 2.0).asDiagonal(), chunks,
                                      {uniformInt(rng, 1, 3), uniformInt(rng, 1, 3), uniformInt(rng, 1, 3)}, box));
        const LatticeNet before = box;
        LatticeNet out;
        out.kind = "sentinel";
        // Opposite corners merged: the corner chunks turn inside out.
        const Status merged = mergeNetPoints(box, {0, box.slotCount() - 1}, out);
        INFO(merged.message);
        REQUIRE_FALSE(merged);
        REQUIRE(merged.message.find("leaves an invalid lattice") != std::string::npos);
        REQUIRE(out.kind == "sentinel");
        REQUIRE(sameLatticeNet(box, before));
    }
}

namespace {

// The parameter of `fine` (after knot insertion along `axis`) of the point with parameter t in `net`: the
// same knot parameter along that axis (bspline_basis.h: lattice and knot parameters).
Eigen::Vector3d sameKnotParameter(const LatticeNet& net, const LatticeNet& fine, int axis, Eigen::Vector3d t) {
    t[axis] = fine.axes[axis].latticeParameter(net.axes[axis].knotParameter(t[axis]));
    return t;
}

}  // namespace

TEST_CASE("lattice edit: inserting a knot at any parameter splits one chunk and leaves the volume unchanged", "[netedit]") {
    std::mt19937 rng(4111);
    int inserted = 0, raised = 0;
    for (int kind = 0; kind < 4; ++kind)
        for (int trial = 0; trial < 5; ++trial) {
            LatticeNet net = randomNet(rng, kind);
            // Two insertions in a row per axis, so the second one splits a net whose knots are already general.
            for (int round = 0; round < 2; ++round)
                for (int axis = 0; axis < 3; ++axis) {
                    const SplineAxis& old = net.axes[axis];
                    // Half the time a point inside a chunk, else an existing interior chunk boundary (a knot whose
                    // multiplicity goes up) where there is one.
                    double at = uniform(rng, 0.01, 0.99);
                    const bool onKnot = old.spans > 1 && uniformInt(rng, 0, 1) == 1;
                    if (onKnot) at = static_cast<double>(uniformInt(rng, 1, old.spans - 1)) / old.spans;
                    const double tau = old.knotParameter(at);
                    const int present = static_cast<int>(std::count(old.knots.begin(), old.knots.end(), tau));
                    const int times = uniformInt(rng, 1, old.degree);
                    LatticeNet fine;
                    const Status s = insertNetKnot(net, axis, at, times, fine);
                    INFO("kind " << kind << " trial " << trial << " axis " << axis << " at " << at << " times " << times << ": " << s.message);
                    if (present + times > old.degree || old.count + times > kMaxControlPointsPerAxis) {
                        REQUIRE_FALSE(s);
                        continue;
                    }
                    REQUIRE(s);
                    ++inserted;
                    raised += present > 0 ? 1 : 0;
                    // One more knot span unless the knot was there already; `times` more points along the axis.
                    REQUIRE(fine.axes[axis].spans == old.spans + (present > 0 ? 0 : 1));
                    REQUIRE(fine.count[axis] == old.count + times);
                    REQUIRE(std::count(fine.axes[axis].knots.begin(), fine.axes[axis].knots.end(), tau) == present + times);
                    for (int b = 0; b < 3; ++b)
                        if (b != axis) {
                            REQUIRE(fine.count[b] == net.count[b]);
                            REQUIRE(fine.axes[b].knots == net.axes[b].knots);
                        }
                    // The volume at 200 random parameters, compared at the same knot parameter: unchanged to rounding.
                    const double tolerance = 1e-12 * net.diagonal();
                    for (int sample = 0; sample < 200; ++sample) {
                        const Eigen::Vector3d t = randomParameter(rng);
                        REQUIRE((volumeAt(fine, fine.rest, sameKnotParameter(net, fine, axis, t)) - volumeAt(net, net.rest, t)).norm() <=
                                tolerance);
                    }
                    // The split chunk's two halves meet at the inserted knot: the old chunk's boundary parameters map
                    // onto the new chunk boundaries.
                    if (present == 0) {
                        const double u = fine.axes[axis].latticeParameter(tau) * fine.axes[axis].spans;
                        REQUIRE(std::abs(u - std::round(u)) <= 1e-9);
                    }
                    // Freezing in the refined net finds the same point (away from seams and collapsed faces).
                    for (int sample = 0; sample < 5; ++sample) {
                        const Eigen::Vector3d t = Eigen::Vector3d::Constant(0.1) + 0.8 * randomParameter(rng);
                        Eigen::Vector3d frozen;
                        REQUIRE(freezePoint(fine, fine.rest, fine.restIndex, volumeAt(net, net.rest, t), frozen));
                        REQUIRE((volumeAt(fine, fine.rest, frozen) - volumeAt(net, net.rest, t)).norm() <= 1e-10 * net.diagonal());
                    }
                    // Seams stay seams, collapsed faces stay collapsed.
                    REQUIRE(fine.periodic == net.periodic);
                    REQUIRE(fine.collapsedAlong == net.collapsedAlong);
                    REQUIRE(fine.boundaryFace == net.boundaryFace);
                    net = std::move(fine);
                }
        }
    REQUIRE(inserted >= 60);  // of 120 tries; the others pass the degree's multiplicity and are refused (checked above)
    REQUIRE(raised >= 5);
}

TEST_CASE("lattice edit: a knot inserted into a moved net gives the moved volume, welds by structure", "[netedit]") {
    std::mt19937 rng(4112);
    for (int kind = 1; kind < 3; ++kind)
        for (int trial = 0; trial < 4; ++trial) {
            const LatticeNet net = randomNet(rng, kind);
            // A random move of 4 points that keeps the net valid (a move that folds a chunk is refused; draw again).
            LatticeNet moved;
            for (int attempt = 0; attempt < 20; ++attempt) {
                std::vector<int> slots;
                for (int m = 0; m < 4; ++m) slots.push_back(uniformInt(rng, 0, net.slotCount() - 1));
                if (moveNetPoints(net, slots, 0.02 * net.diagonal() * Eigen::Vector3d(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1)), moved))
                    break;
            }
            REQUIRE(moved.slotCount() == net.slotCount());
            for (int axis = 0; axis < 3; ++axis) {
                const double at = uniform(rng, 0.05, 0.95);
                LatticeNet fineRest, fineMoved;
                REQUIRE(insertNetKnot(net, axis, at, 1, fineRest));
                REQUIRE(insertNetKnot(moved, axis, at, 1, fineMoved));
                INFO("kind " << kind << " axis " << axis);
                REQUIRE(fineMoved.weldedTo == fineRest.weldedTo);
                for (int sample = 0; sample < 50; ++sample) {
                    const Eigen::Vector3d t = randomParameter(rng);
                    REQUIRE((volumeAt(fineMoved, fineMoved.rest, sameKnotParameter(moved, fineMoved, axis, t)) - volumeAt(moved, moved.rest, t)).norm() <=
                            1e-12 * net.diagonal());
                }
                requireAxisAndSeamWelded(fineRest);
            }
        }
}

TEST_CASE("lattice edit: knot insertion refuses bad parameters and keeps the net", "[netedit]") {
    LatticeNet box;
    REQUIRE(makeParallelepipedNet(Eigen::Vector3d::Zero(), Eigen::Matrix3d::Identity(), {2, 2, 2}, {2, 2, 2}, box));
    const LatticeNet copy = box;
    LatticeNet out = box;
    auto refused = [&](int axis, double at, int times, const std::string& words) {
        const Status s = insertNetKnot(box, axis, at, times, out);
        INFO(s.message);
        REQUIRE_FALSE(s);
        REQUIRE(s.message.find(words) != std::string::npos);
        REQUIRE(sameLatticeNet(box, copy));
        REQUIRE(sameLatticeNet(out, copy));  // untouched on failure
    };
    refused(3, 0.5, 1, "axis 3");
    refused(0, 0.0, 1, "strictly inside");
    refused(0, 1.0, 1, "strictly inside");
    refused(0, std::nan(""), 1, "strictly inside");
    refused(0, 0.3, 0, "times");
    refused(0, 0.3, 3, "times");
    // 0.5 is a knot of multiplicity 1 of degree 2: once more is allowed, twice more is not.
    refused(1, 0.5, 2, "multiplicity 1 already");
    LatticeNet twice;
    REQUIRE(insertNetKnot(box, 1, 0.5, 1, twice));
    REQUIRE(twice.axes[1].spans == 2);
    LatticeNet third;
    const Status s = insertNetKnot(twice, 1, 0.5, 1, third);
    REQUIRE_FALSE(s);
    REQUIRE(s.message.find("multiplicity 2 already") != std::string::npos);
    // 64 points per axis at most.
    LatticeNet wide;
    REQUIRE(makeParallelepipedNet(Eigen::Vector3d::Zero(), Eigen::Matrix3d::Identity(), {63, 1, 1}, {1, 1, 1}, wide));
    REQUIRE(wide.count[0] == 64);
    const Status tooMany = insertNetKnot(wide, 0, 0.3, 1, out);
    REQUIRE_FALSE(tooMany);
    REQUIRE(tooMany.message.find("at most 64") != std::string::npos);
}

TEST_CASE("lattice edit: a slice of an axis with general knots can be removed", "[netedit]") {
    std::mt19937 rng(4113);
    for (int trial = 0; trial < 10; ++trial) {
        LatticeNet net = randomNet(rng, 0);
        const int axis = uniformInt(rng, 0, 2);
        LatticeNet split;
        REQUIRE(insertNetKnot(net, axis, uniform(rng, 0.1, 0.9), 1, split));
        REQUIRE_FALSE(split.knots[axis].empty());
        const int index = uniformInt(rng, 1, split.count[axis] - 2);
        LatticeNet reduced;
        const Status s = removeNetSlice(split, axis, index, reduced);
        INFO(s.message);
        REQUIRE(s);
        REQUIRE(reduced.count[axis] == split.count[axis] - 1);
        REQUIRE(reduced.axes[axis].knots.size() == split.axes[axis].knots.size() - 1);
        REQUIRE(splineKnotsProblem(reduced.axes[axis].knots, reduced.count[axis], reduced.degree[axis]).empty());
    }
}
