// The sculpting brush: a drag limited to a radius around the grabbed point, with a strength, a falloff and
// mirror symmetry, built from the seeds' own tools (issue "A window a sculptor keeps using", point 2):
// - the radius sets a region-of-interest lattice around the grabbed point(s) for that drag: a regular
//   lattice in a box padded by a quarter of the radius, whose control points are all pinned except those
//   whose whole basis support lies within 1.25 radius of a grabbed point. The deformation is then zero
//   outside that ball and its seam with the untouched mesh is as smooth as the basis (C^(p-1));
// - the falloff is the lattice's degree and knot spacing: the min-norm solution (Hu et al. 2001, eq. 7)
//   moves the grabbed point's support, so the bump is the basis functions' shape over (p+1) knot spans;
// - symmetry is a multi-point drag (Hu et al. 2001, eq. 12) whose extra constraints are the mirror images
//   of the grabbed point and its target; the explicit solution meets all of them exactly.
// The region lattice is applied after the user's cage (session.h, "layers"): the cage stays as shaped.
#pragma once

#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/volume/lattice.h"
#include "core/status.h"

namespace sculpt::core {

enum class BrushFalloff { Smooth, Medium, Sharp };
// "smooth", "medium", "sharp".
const char* brushFalloffName(BrushFalloff falloff);
// Parses a name brushFalloffName gives; the error lists the accepted names.
Status parseBrushFalloff(const std::string& name, BrushFalloff& out);

// Mirror planes: axis a is mirrored in the plane through the frame's centre whose normal is column a of its
// axes (SymmetryFrame). At load: the planes x_a = centre_a through the centre of the mesh's bounding box
// (Session::meshAsSet().symmetryCentre); the planes are the mesh's own, so where the cage moves or turns the
// mesh they move and turn with it (Session::symmetryFrame).
struct Symmetry {
    std::array<bool, 3> mirror{false, false, false};
    bool any() const { return mirror[0] || mirror[1] || mirror[2]; }
};
// "x", "y", "z" or combinations such as "xz" (any order, each letter once; "" = none). The error names the
// offending letter.
Status parseSymmetry(const std::string& text, Symmetry& out);
// The script's spelling ("x", "xz"); with `planes`, the window's (its Symmetry checkboxes: "X", "XZ").
std::string symmetryText(const Symmetry& symmetry, bool planes = false);

struct BrushSettings {
    double radius = 0.0;        // world units; 0 = no brush: the drag is solved in the whole cage
    BrushFalloff falloff = BrushFalloff::Smooth;
    double strength = 1.0;      // in (0, 1]: the fraction of the cursor's motion the grabbed point makes
    Symmetry symmetry;
    bool active() const { return radius > 0.0; }
    // Where the strength takes a pull from `source` towards `target`: source + strength (target - source).
    Eigen::Vector3d scaledTarget(const Eigen::Vector3d& source, const Eigen::Vector3d& target) const {
        return source + strength * (target - source);
    }
    // The inverse: the target asked for, given where the pull got (`reached`); `reached` itself at strength 1.
    // What a drag records, so that a replay that solves it again scales it once.
    Eigen::Vector3d askedTarget(const Eigen::Vector3d& source, const Eigen::Vector3d& reached) const {
        return strength == 1.0 ? reached : Eigen::Vector3d(source + (reached - source) / strength);
    }
};
// Finite radius >= 0, strength in (0, 1]; the message names the field.
Status validateBrush(const BrushSettings& brush);

// One constraint of a drag after symmetry: its source, and the user constraints and mirror masks (bit a set:
// reflected in plane a) whose targets it follows. Most stand for one image; a mirrored source that falls
// within the merge distance of another (a point on a mirror plane) is merged with it, and its target is the
// mean of the images' targets, so the drag never asks one point to go two ways.
struct MirroredConstraint {
    Eigen::Vector3d source = Eigen::Vector3d::Zero();
    std::vector<std::pair<int, int>> images;  // (user constraint, mirror mask)
};
// The constraints of a drag with their mirror images added: for every non-empty subset of the mirrored axes,
// each constraint not `held` reflected in those planes (held constraints, e.g. pins, are not mirrored). The
// user's constraints come first, in order.
// Where the mirror planes are (world units): through `centre`, plane a with the unit normal axes.col(a) (the
// columns orthonormal). The identity axes give the axis-aligned planes x_a = centre_a, computed exactly so.
struct SymmetryFrame {
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();
};
std::vector<MirroredConstraint> mirrorConstraints(const std::vector<Eigen::Vector3d>& sources, const std::vector<bool>& held,
                                                  const Symmetry& symmetry, const SymmetryFrame& frame, double mergeDistance);
// The point p reflected in the planes of `mask` (bit a: plane a) of `frame`.
Eigen::Vector3d reflectPoint(const Eigen::Vector3d& p, int mask, const SymmetryFrame& frame);
// A vector (a move) reflected in those planes: the reflection's linear part.
Eigen::Vector3d reflectVector(const Eigen::Vector3d& d, int mask, const SymmetryFrame& frame);
// The target of a constraint given the user's sources and targets (one each per user constraint): its source
// moved by the mean of its images' moves, each reflected by its mask (for a source on the images: the mean of
// the mirrored targets).
Eigen::Vector3d mirroredTarget(const MirroredConstraint& constraint, const std::vector<Eigen::Vector3d>& userTargets,
                               const std::vector<Eigen::Vector3d>& userSources, const SymmetryFrame& frame);

// The falloff's profile: the fraction of the grabbed point's move wanted at distance x (in radii) from it,
// 1 at 0 and 0 at 1, as Blender's brush curves: smooth 1 - (3x^2 - 2x^3), medium (sphere) sqrt(1 - x^2),
// sharp (1 - x)^2.
double brushProfile(BrushFalloff falloff, double x);
// The region-of-interest lattice of a brush stroke (pullRegionLattice, brush_field.h).
struct RegionLattice {
    LatticeSettings settings;       // resolution and degree (pin layers 0: the pins are `freePoints`' complement)
    Eigen::Vector3d boxMin = Eigen::Vector3d::Zero(), boxMax = Eigen::Vector3d::Zero();  // in box coordinates
    Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();  // the box's axes (Lattice::boxAxes): turned to a pull
    std::vector<int> freePoints;    // sorted ids of the control points that may move; every other one is pinned
};
// Pins every control point of `lattice` except `freePoints` (ids in range).
void pinAllBut(Lattice& lattice, const std::vector<int>& freePoints);

}  // namespace sculpt::core
