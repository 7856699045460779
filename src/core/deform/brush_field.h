// The brush's pull: a displacement field that carries a grabbed point as far as it is pulled, moves the
// surface around it by the falloff curve, is injective by construction, and moves nothing farther than
// 1.25 radius from the path of the grabbed point (issue "Sculpting as a sculptor expects", points 2 and 3).
//
// For a grabbed point s pulled by the vector d = |d| e, the field is u(x) = |d| phi(x) e with, for
// z = (x - s) . e and f the falloff's profile (brushProfile: 1 at 0, 0 from 1 on, non-increasing):
//   behind s (z <= 0):  phi(x) = f(|x - s| / r),
//   ahead (z > 0), at lateral distance l from the pull's line:
//                       phi(x) = max over 0 <= z' <= z of  f(|(l, z')| / r) - k (z - z') / |d|,
//                       k = max(0.7, |d| / (|d| + 0.75 r)),
// i.e. the least function at or above the falloff of the rest distance whose share falls by at most k / |d|
// per unit along the pull. Hence:
//   - the grabbed point moves by d (phi(s) = 1), and every point behind it (a convex patch pulled outward, or
//     anything a short pull reaches) moves by f(|x - s| / r) d: the falloff curve of the rest distance;
//   - a field parallel to one direction has det J = 1 + e . grad(u . e) (the matrix determinant lemma); along
//     e, phi rises behind s and falls by at most k / |d| ahead, so det J >= 1 - k >= 0.75 r / (|d| + 0.75 r) > 0
//     at any pull length: the field is injective (Gain & Dodgson 2001, Theorem 1). What lies ahead within the
//     radius (a concave spot, another limb) is pushed on just enough that the pulled surface never passes it;
//   - phi vanishes unless l < r and -r < z < |d| / k <= |d| + 0.75 r: within 1.25 r of the segment s, s + d.
// The field lives in a region-of-interest lattice (a layer after the cage, session.h): cubic, 8 knot spans a
// radius (coarser where that would need more than 64 control points an axis), whose control points are free
// only where their whole basis support lies within 1.25 radius of a segment, so nothing beyond moves whatever
// the coefficients. The coefficients are the field at the Greville points (the Schoenberg quasi-interpolant:
// on uniform knots a positive convolution, which keeps the bound on the derivative along e), scaled so each
// grabbed point lands exactly (Hu et al. 2001, eq. 7 corrects what a scale cannot: mirror images whose regions
// overlap, and held points inside a region).
#pragma once

#include <vector>

#include <Eigen/Core>

#include "core/deform/brush.h"
#include "core/deform/direct_manipulation.h"
#include "core/volume/lattice.h"
#include "core/status.h"

namespace sculpt::core {

// One grabbed point of a stroke: where it was when the stroke began (world) and how far it is pulled (world
// units; zero for a held point, which must stay).
struct BrushPull {
    Eigen::Vector3d source = Eigen::Vector3d::Zero();
    Eigen::Vector3d pull = Eigen::Vector3d::Zero();
    bool moving() const { return pull.squaredNorm() > 0.0; }
};

constexpr int kBrushFieldSpansPerRadius = 8;
constexpr double kBrushReach = 1.25;  // in radii, from the segment of each pull
// Two moving pulls that share a direction and whose sources are at most this far apart (in radii) are carried
// by one ridge along the segment between them (brushFieldDelta): a point grabbed beside a mirror plane makes
// one bump with its image, not two peaks.
constexpr double kBrushBridgeDistance = 0.5;
// Refinement under a pull (Stroke::applyBrushPulls): where the mesh's triangles would cross under a pull whose
// field is injective, the triangles it bends more than this share of the radius from flat are split, and the pull
// tried again; up to kBrushRefinements times, each to half the tolerance before.
constexpr double kBrushRefineTolerance = 0.02;
constexpr int kBrushRefinements = 2;
constexpr double kBrushRefineShortestEdge = 0.04;  // in radii: no shorter rest-space edge is split

// The falloff as the field uses it: brushProfile, with sharp's peak rounded (inside 0.25 the parabola 1 - 7 x^2,
// which meets (1 - x)^2 there: 0.03 RMS after the spline's smoothing, 0.06 with the flat-topped parabola scaled
// by 1 / 0.85 before) and medium's rim slope limited to 6 (min(sqrt(1 - x^2), 6 (1 - x)), meeting it at
// x = 35 / 37: 0.02 RMS from the curve over a disc; 3 before, 0.07), so the spline that carries it has no dip
// along the pull. x in radii.
double brushFieldProfile(BrushFalloff falloff, double x);
// The slope k above.
double brushFieldSlope(double pullLength, double radius);
// phi(x) above, in [0, 1]: the share of the pull that the point x moves. radius > 0.
double brushFieldWeight(const BrushPull& pull, double radius, BrushFalloff falloff, const Eigen::Vector3d& x);

// The direction several moving pulls share, when every two of them are within 25 degrees of each other
// (mirror images of a pull along, or nearly along, the mirror plane): the unit sum of their directions; one
// moving pull: its own direction; zero otherwise. A field along it with the share u(x) = max_k |d_k| phi_k(x)
// keeps each pull's slope bound, so det J = 1 + e . grad u >= 1 - max_k k_k > 0 (brushFieldDelta): images
// within reach of each other are pulled by one field instead of holding each other back.
Eigen::Vector3d sharedPullDirection(const std::vector<BrushPull>& pulls);

// The widening ahead of a long pull (issue "Sculpting as a sculptor expects", point 3). Along the pull a field
// parallel to it may fall by at most 1 / |d| per unit (det J = 1 + e . grad(u . e) > 0), while the falloff falls
// by up to 1.5 / r: a surface that lies ahead of the grabbed point within the radius (the walls of a hollow, an
// overhang) is carried by the column (brushFieldWeight) at up to 15 times its falloff, a profile 0.16-0.20 from
// the curve for 3-radius pulls out of hollows in CGAL's elephant and camel. Before the pull, the space ahead is
// widened about the pull's line instead: a radial map (l, theta, z) -> (l + E(l, z), theta, z) in cylindrical
// coordinates about the line (z along the pull from the source, l the lateral distance), with E the least
// lateral push that brings each point out to where the column's share is at most the falloff of its rest
// distance from the source, f(|(l, z)| / r) + 0.02, bounded so that
//   - l + E rises with l at least 0.4 per unit (E falls by at most 0.6 per unit outward): each half-line from the
//     axis maps monotonically into itself, det J = (1 + E / l)(1 + dE/dl) >= 0.4: injective;
//   - E <= 2 l (nothing leaves the axis) and E = 0 beyond l = 0.85 r, for z <= 0 and for z >= 1.25 r (ramped in
//     from z = r): nothing moves beyond the pull's reach, and a point behind the source keeps the falloff.
// The radial map is carried by two fields each parallel to one lateral axis of the pull's region (u, then v:
// the second is the radial map after the inverse of the first), so the directional bound proves each layer as
// it proves the pull's. The pull's own field then acts on the widened space: the surface ahead moves by
// nearly its falloff along the pull, and sideways out of the way of the surface pulled through it.
// E is tabulated over l in [0, 1.25 r] and z in [0, 1.25 r] and read bilinearly (piecewise linear in l, so the
// bound on its slope holds between the nodes).
struct BrushWidening {
    Eigen::Vector3d source = Eigen::Vector3d::Zero(), direction = Eigen::Vector3d::UnitZ();
    double radius = 1.0;
    int lateralNodes = 0, axialNodes = 0;  // table size; 0: no widening
    double lateralStep = 0.0, axialStep = 0.0;
    std::vector<double> push;  // E at (lateral i, axial j): push[i + lateralNodes * j], world units
    bool empty() const { return lateralNodes == 0; }
    // l + E(l, z) for a point at lateral distance l >= 0 and axial distance z from the source (world units).
    double widenedLateral(double lateral, double axial) const;
};
// The widening ahead of `pull` (moving) for the brush's radius (> 0) and falloff; empty when the column is
// within 0.02 radius of the widened space everywhere (a short pull: the column is the falloff there).
BrushWidening brushWidening(const BrushPull& pull, double radius, BrushFalloff falloff);
// The control displacement of one of the widening's two layers in `region` (pullRegionLattice's placement for
// the one pull `widening` was made for, its lateral axes u, v its box's first two axes): axis 0 moves every free
// control point's rest (Greville) point x along u by x_u (l' / l - 1), l' = widenedLateral; axis 1 moves y along
// v by y_v (l' / l - 1) with l, l' taken at U^-1(y), the point the first layer moved to y (found by bisection:
// U is monotone along u). Fails when the region's box is not turned to the widening's pull.
Status brushWideningDelta(const Lattice& region, const BrushWidening& widening, int axis, ControlDelta& out);

// Distance from x to the segment from a to b (a == b: to the point).
double segmentDistance(const Eigen::Vector3d& x, const Eigen::Vector3d& a, const Eigen::Vector3d& b);

// The region lattice of a stroke: a cubic box lattice around every moving pull's capsule (its segment grown
// by 1.25 radius), turned so that its w axis is the pulls' shared direction where they have one
// (sharedPullDirection), whose free control points are those with the whole basis support within 1.25 radius
// of one moving pull's segment. Fails on no moving pull, non-finite input, or a radius that is not finite and > 0.
// spansPerRadius: the knot spacing's target (brushFieldSpansPerRadius).
Status pullRegionLattice(const std::vector<BrushPull>& pulls, double radius, RegionLattice& out, int spansPerRadius = kBrushFieldSpansPerRadius);
// Knot spans a radius for a falloff's field: 8, and 12 for medium, whose rim is steep (sqrt(1 - x^2) is 0.44
// at 0.9 radius). The free control points end where their support would reach beyond 1.25 radius (0.82 radius
// out diagonally at 8 spans a radius, 0.96 at 12), and the spline falls to 0 over two spans from there: at 8
// spans medium's profile was 0.12 RMS from its curve on any surface, 0.02-0.03 at 12 (CGAL's elephant). The
// finer grid costs about 3.4 times the control points (a 3-radius medium pull: 24 -> 190 ms on 2 cores).
int brushFieldSpansPerRadius(BrushFalloff falloff);

// The control displacement of the stroke in `region` (made from pullRegionLattice's placement, every point
// but the free ones pinned): the fields of the moving pulls at the free control points' rest (Greville)
// positions, scaled per pull so each moving source lands on source + pull (several pulls with a shared
// direction e: one field along e, max_k |d_k| phi_k, one scale; two pulls in opposite directions along one
// line e, each source on the side it is pulled to (mirror images pulled apart across their plane): one field
// along e, S(t) |d_side| phi_side with S = clamp(t / delta, -1, 1), t the signed distance along e from the
// sources' midpoint, delta half their distance, side the pull on t's side; det J >= 1 - k as for one pull,
// one scale; two pulls along one line towards each other, each source at h from their midpoint (mirror images
// pulled inward beside their plane): one field along e, each side the falloff of the distance behind its source
// and, ahead of it, the falloff of the lateral distance times a ramp to 0 over min(h, |d| + 0.75 r), the two
// ramps apart; det J >= 1 - |d| / min(h, |d| + 0.75 r), > 0 while the pull stops short of the midpoint, one
// scale), then corrected by the minimum-norm
// solution (Hu et al. 2001, eq. 7 / 12) for what the scales leave: the held sources' displacement and the
// cross-talk of overlapping regions. residual: the largest distance of a source from its target afterwards
// (world units; 0 up to rounding unless the free points cannot reach a source).
Status brushFieldDelta(const Lattice& region, const std::vector<BrushPull>& pulls, double radius, BrushFalloff falloff,
                       ControlDelta& out, double& residual);

}  // namespace sculpt::core
