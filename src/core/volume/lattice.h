// The control lattice: a tensor-product NURBS volume around (part of) the mesh.
// Hu et al. 2001, eq. 1-2: Q(u,v,w) = sum_ijk P_ijk R_ijk(u,v,w),
// R_ijk = W_ijk B_i(u) B_j(v) B_k(w) / sum W B B B.
// The lattice stores its control points as rest position P0 (Greville grid in the box, implicit) plus an
// accumulated displacement; the deformed image of a point with parameters t is
//   x(t) = X0 + sum R_ijk(t) delta_ijk,
// i.e. the displacement field is evaluated and added to the rest position (design.md step 6), which keeps
// untouched vertices bitwise unchanged.
#pragma once

#include <array>
#include <string>
#include <cstdint>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "core/spline/bspline_basis.h"
#include "core/volume/lattice_net.h"
#include "core/mesh_types.h"
#include "core/status.h"
#include "core/volume/volume.h"

namespace sculpt::core {

struct LatticeSettings {
    std::array<int, 3> resolution{8, 8, 8};  // control points per axis, in [degree+1, 64]
    std::array<int, 3> degree{3, 3, 3};      // per axis, in [1, 5]
    double padding = 0.05;                   // added on every side, as a fraction of the box diagonal; >= 0
    bool hasRegion = false;                  // false: the box is the mesh bounds
    Eigen::Vector3d regionMin = Eigen::Vector3d::Zero();  // with hasRegion: the user-given box (then padded)
    Eigen::Vector3d regionMax = Eigen::Vector3d::Zero();
    int pinLayers = 0;                       // pin the k outer layers of control points, k in [0, 3]
    // A lattice of any kind (volume.h; e.g. a net of any shape, lattice_net.h, Coquillart 1990), placed where
    // it is in world space. When set, resolution, degree, padding and region are the volume's (the fields
    // above are ignored except pinLayers, which counts layers from the volume's outer surface only).
    std::shared_ptr<const Volume> volume;
};

// Checks ranges and finiteness; the message names the offending field.
Status validateLatticeSettings(const LatticeSettings& settings);
// Control points per axis of the lattice these settings make (the net's counts, or the resolution).
// A volume that is not one tensor product reports {controlPointCount, 1, 1}.
std::array<int, 3> latticeCounts(const LatticeSettings& settings);

// Every field equal (the same control point ids and placement rule); nets compared by value.
bool sameLatticeSettings(const LatticeSettings& a, const LatticeSettings& b);
// Two nets with the same counts, degrees, multiplicities, rest points, weights and welds (bitwise).
bool sameLatticeNet(const LatticeNet& a, const LatticeNet& b);
// Two volumes of the same kind and the same control points, weights and welds (bitwise; tensor nets by
// sameLatticeNet).
bool sameVolume(const Volume& a, const Volume& b);

struct Lattice {
    std::array<int, 3> count{};   // control points per axis
    std::array<int, 3> degree{};
    std::array<SplineAxis, 3> axes;
    Eigen::Vector3d boxMin = Eigen::Vector3d::Zero();
    Eigen::Vector3d boxMax = Eigen::Vector3d::Ones();
    // A box lattice may be turned: row a of boxAxes is the unit world direction of parameter axis a (an
    // orthonormal, right-handed frame), boxMin/boxMax are in box coordinates b = boxAxes * x, and the control
    // displacements stay world vectors. The brush aligns its region with the pull this way (brush_field.h).
    // Not turned (the identity): the cage, subdivision layers, every net.
    Eigen::Matrix3d boxAxes = Eigen::Matrix3d::Identity();
    bool boxTurned() const { return boxAxes != Eigen::Matrix3d::Identity(); }
    std::vector<double> weights;        // #P NURBS weights W_ijk (all 1 unless the user changes them)
    bool rational = false;              // some weight differs from 1
    Positions displacement;             // #P x 3, delta_ijk accumulated since set-up
    std::vector<std::uint8_t> pinned;   // #P, 1 = the solver never moves this control point
    // A lattice of another kind (volume.h): rest control points, weights, welds and chunks come from the
    // volume, parameters of rest points from freezing, boxMin/boxMax are its bounds. Null: the box lattice
    // (the fast path). Welded control points always carry equal displacements (ControlDeltas are expanded to
    // every id of a weld group by expandWelds) and equal pins. A tensor-product volume (tensorNet) also fills
    // count, degree and axes; another kind has count {#P, 1, 1} and its cells are its chunks.
    std::shared_ptr<const Volume> volume;
    // The volume as one tensor-product net (null for the box lattice and for other kinds).
    const LatticeNet* tensorNet() const { return volume ? volume->tensorNet() : nullptr; }

    int controlPointCount() const { return count[0] * count[1] * count[2]; }
    int index(int i, int j, int k) const { return i + count[0] * (j + count[1] * k); }
    std::array<int, 3> ijk(int index) const;
    // How a user names control point `index`: "[i,j,k]" in a tensor lattice (the box, or a tensor net), its id
    // otherwise (a T-spline's anchor, a composite's point), where [i,0,0] would only confuse.
    std::string controlPointName(int index) const;
    std::array<int, 3> spans() const { return {axes[0].spans, axes[1].spans, axes[2].spans}; }
    // Cells: knot-span triples of a tensor lattice, a volume's chunks otherwise.
    int cellCount() const { return volume && !volume->tensorNet() ? volume->chunkCount() : axes[0].spans * axes[1].spans * axes[2].spans; }
    double diagonal() const { return (boxMax - boxMin).norm(); }
    // P0_ijk: the rest position, boxMin + greville * size per axis (a net lattice: the net's point).
    Eigen::Vector3d restControlPoint(int index) const;
    // The representative of control point `index`'s weld group (itself when not welded).
    int representative(int index) const { return volume ? volume->representativeOf(index) : index; }
    // P0 + delta.
    Eigen::Vector3d controlPoint(int index) const { return restControlPoint(index) + displacement.row(index).transpose(); }
};

// Builds the lattice around `points` (or settings' region), padded; flat or degenerate bounds (a plane, a
// line, a single point) get a usable box (each side at least 1e-3 of the diagonal, or 1 if all points
// coincide). Fails on invalid settings, an empty point set, or non-finite points. Pins the outer layers.
Status makeLattice(const LatticeSettings& settings, const Positions& points, Lattice& out);

// The box makeLattice would use: settings' region or the points' bounds, made non-degenerate, padded.
Status latticeBox(const LatticeSettings& settings, const Positions& points, Eigen::Vector3d& boxMin, Eigen::Vector3d& boxMax);

// A lattice in exactly the given box (settings' region and padding are ignored), pins from pinLayers.
Status makeLatticeInBox(const LatticeSettings& settings, const Eigen::Vector3d& boxMin, const Eigen::Vector3d& boxMax,
                        Lattice& out);

// Turns a box lattice: `axes` (rows: the world directions of parameter axes u, v, w) must be orthonormal and
// right-handed to 1e-12 (fails otherwise, lattice untouched); boxMin/boxMax are then read in box coordinates.
// The identity un-turns it, and any lattice takes it; a lattice of another kind (volume) cannot be turned.
Status turnBoxLattice(Lattice& lattice, const Eigen::Matrix3d& axes);
// Box coordinates of a world point (boxAxes * x; x itself for an unturned lattice), and back.
inline Eigen::Vector3d toBoxCoordinates(const Lattice& lattice, const Eigen::Vector3d& x) {
    return lattice.boxTurned() ? Eigen::Vector3d(lattice.boxAxes * x) : x;
}
inline Eigen::Vector3d fromBoxCoordinates(const Lattice& lattice, const Eigen::Vector3d& b) {
    return lattice.boxTurned() ? Eigen::Vector3d(lattice.boxAxes.transpose() * b) : b;
}
// The deformation's Jacobian dx/dX0 = I + M A from M = dD/dt diag(1 / size), the displacement's derivatives
// along the box's axes (A = boxAxes = db/dX0; I + M for an unturned lattice).
inline Eigen::Matrix3d worldJacobian(const Lattice& lattice, const Eigen::Matrix3d& m) {
    return Eigen::Matrix3d::Identity() + (lattice.boxTurned() ? Eigen::Matrix3d(m * lattice.boxAxes) : m);
}
// The world axis-aligned bounds of the lattice's box (of its turned box: the bounds of its 8 corners).
void worldBoxBounds(const Lattice& lattice, Eigen::Vector3d& lo, Eigen::Vector3d& hi);
// The same for a box [boxMin, boxMax] in the coordinates of `axes` (rows: world directions).
void turnedBoxBounds(const Eigen::Matrix3d& axes, const Eigen::Vector3d& boxMin, const Eigen::Vector3d& boxMax, Eigen::Vector3d& lo,
                     Eigen::Vector3d& hi);
// Where the lattice's map can differ from the identity or put a point: the world bounds of its box and of its
// displaced control points (the convex hull property of the B-spline volume). Outside it the map is the identity.
void deformationBounds(const Lattice& lattice, Eigen::Vector3d& lo, Eigen::Vector3d& hi);
// The same deformation seen in box coordinates: an unturned copy whose displacements are boxAxes * delta. Its
// Jacobian is boxAxes J boxAxes^T, so det J and every injectivity verdict are the turned lattice's.
Lattice unturnedLattice(const Lattice& lattice);

// Parameters t in [0,1]^3 of a rest-space point, by the linear map of the box (O(1), no iteration).
// Returns false (t untouched) for points outside the closed box; points on a face get exactly 0 or 1.
// A net lattice freezes the point (freezePoint: Newton per chunk, Coquillart 1990, 3.3); false outside it.
bool restParameters(const Lattice& lattice, const Eigen::Vector3d& point, Eigen::Vector3d& params);

// restParameters of a box lattice for a point given in box coordinates (toBoxCoordinates).
bool restParametersInBox(const Lattice& lattice, const Eigen::Vector3d& boxPoint, Eigen::Vector3d& params);

// R_ijk(t) for the (p+1)(q+1)(r+1) control points whose basis is non-zero at t (Hu et al. 2001, eq. 2).
// Welded control points are reported once, on their representative, with the sum of their basis functions
// (Coquillart 1990, 3.1.2: merged points act as one control point).
void supportWeights(const Lattice& lattice, const Eigen::Vector3d& params, SupportWeights& out);

// The rest point with parameters t: X0(t) = boxMin + t * size for the box lattice, Q0(t) for a net lattice
// (lattice_net.h). Undeformed, the deformation is the identity, so this is also where t's point is at rest.
Eigen::Vector3d restPoint(const Lattice& lattice, const Eigen::Vector3d& params);

// sum_ijk R_ijk(t) delta_ijk.
Eigen::Vector3d displacementAt(const Lattice& lattice, const Eigen::Vector3d& params);

// The map of a layer (a lattice applied after the cage: operation.h, Layer), world units in and out: point +
// displacementAt(t(point)) inside its box (restParameters), the point itself outside.
Eigen::Vector3d layerImage(const Lattice& lattice, const Eigen::Vector3d& point);

// The NURBS volume itself, Q(t) = sum R_ijk(t) (P0_ijk + delta_ijk) (eq. 1). Equals the rest point for an
// undeformed lattice with unit weights.
Eigen::Vector3d volumePoint(const Lattice& lattice, const Eigen::Vector3d& params);

// The deformation of rest space, x(X0) = X0 + displacementAt(t(X0)), and its Jacobian dx/dX0 at the point
// with parameters t. Rational weights are differentiated with the quotient rule. A net lattice:
// dQ/dt (dQ0/dt)^-1; on a collapsed axis, pole or centre (dQ0/dt singular) it is I where the displacement is
// locally constant and otherwise not finite (the map need not be differentiable there: its derivative
// depends on the direction); jacobianDeterminant (injectivity.h) gives det J's limit there.
void deformationJacobian(const Lattice& lattice, const Eigen::Vector3d& params, Eigen::Vector3d& displacement,
                         Eigen::Matrix3d& jacobian);

// Damped Newton for the preimage of a box lattice's map, in box coordinates (toBoxCoordinates): from `rest`
// (inside the box), steps of at most a quarter of the diagonal, each halved until |x + D(x) - target| drops
// (once only below roundingLevel, where nothing improves any more), until it is <= tolerance or
// `iterations` are done. rest and params get the last iterate; returns its residual (world units).
double newtonPreimageInBox(const Lattice& lattice, const Eigen::Vector3d& target, Eigen::Vector3d& rest, Eigen::Vector3d& params,
                           double tolerance, double roundingLevel, int iterations);

// Finds the rest-space parameters whose deformed image is `deformedPoint` by damped Newton iteration
// (newtonPreimageInBox) from the fixed-point guess y - D(y), then from the point's own box parameters. Fails
// if the point is outside the deformed lattice, or the iteration does not converge to tolerance * diagonal.
Status locateDeformedPoint(const Lattice& lattice, const Eigen::Vector3d& deformedPoint, Eigen::Vector3d& params,
                           double tolerance = 1e-12);

// True if control point `index` lies in one of the `layers` outer layers (the pin_layers rule).
bool inOuterLayers(const Lattice& lattice, int index, int layers);
// The same for the lattice these settings make (a net lattice: layers from its boundary faces only).
bool inPinLayers(const LatticeSettings& settings, int index);
// The same for grid position c = (i,j,k) of a count[0] x count[1] x count[2] lattice.
bool inOuterLayers(const std::array<int, 3>& count, const std::array<int, 3>& c, int layers);
// Grid position (i,j,k) of control point id `index` (Lattice::index's inverse) in a lattice of `count` points.
std::array<int, 3> gridIjk(const std::array<int, 3>& count, int index);

// Every control point's current position Q_ijk = P0_ijk + delta_ijk, one row per id (Lattice::index).
Positions controlPointPositions(const Lattice& lattice);

// Ids of the control points whose displacement is not exactly zero, ascending.
std::vector<int> displacedControlPoints(const Lattice& lattice);

// True if no control point on the lattice's outer faces has moved: the clamped volume then maps its box
// onto itself, so points outside the box are neither moved nor the image of a point inside it.
bool boundaryUnmoved(const Lattice& lattice);

// True if every control point displacement is exactly zero.
bool isUndeformed(const Lattice& lattice);

// ---- drawing and picking (the window's lattice overlay) ----
// The control net's edges: pairs {a, b} (a < b) of control point ids joined along a grid line, each weld
// group drawn once on its representative (Lattice::representative), so merged points have no edge between
// them and a welded seam or axis is not drawn twice. Sorted, unique.
std::vector<std::array<int, 2>> controlNetEdges(const Lattice& lattice);

// The chunk edges of the deformed volume, x(t) = X0(t) + sum R(t) delta (restPoint + displacementAt), as
// polylines: every parameter line along one axis through the knot values of the other two (the curved
// edges of a cylinder's or sphere's chunks), `samplesPerSpan` >= 1 segments per knot span. A periodic axis'
// closing knot line is the seam and is not repeated; lines that collapse to a point (a cylinder's axis
// along its angle, a pole) are left out. Each polyline: rows = points, 3 columns.
std::vector<Positions> chunkEdgeCurves(const Lattice& lattice, int samplesPerSpan);

}  // namespace sculpt::core
