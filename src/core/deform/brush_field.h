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

// The falloff as the field uses it: brushProfile, with sharp's peak rounded (a flat-topped parabola inside 0.15,
// the rest scaled by 1 / 0.85) and medium's rim slope limited to 3 (min(sqrt(1 - x^2), 3 (1 - x)): 0.07 RMS from the curve over a disc), so the
// spline that carries it has no dip along the pull. x in radii.
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

// Distance from x to the segment from a to b (a == b: to the point).
double segmentDistance(const Eigen::Vector3d& x, const Eigen::Vector3d& a, const Eigen::Vector3d& b);

// The region lattice of a stroke: a cubic box lattice around every moving pull's capsule (its segment grown
// by 1.25 radius), turned so that its w axis is the pulls' shared direction where they have one
// (sharedPullDirection), whose free control points are those with the whole basis support within 1.25 radius
// of one moving pull's segment. Fails on no moving pull, non-finite input, or a radius that is not finite and > 0.
Status pullRegionLattice(const std::vector<BrushPull>& pulls, double radius, RegionLattice& out);

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
