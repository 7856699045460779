// The volume interface: what the engine needs from a lattice of any kind.
//
// Every deformation of the engine has the form x = X0 + sum_s R_s(t(X0)) delta_s (Hu et al. 2001, eq. 1-2;
// Coquillart 1990, 3.4): a control volume Q(t) = sum R_s(t) P_s over some parameter domain, rest control points
// P0_s, each rest point X0 frozen once to its parameters t with Q0(t) = X0, and displacements delta_s of the
// control points. The explicit solution (Hu et al. 2001, eq. 7 / 12) needs only the basis values R_s(t) at
// the grabbed points; evaluation and the Jacobian need Q and dQ/dt; the injectivity tests (Gain & Dodgson
// 2001, sections 5-6) need each Bezier piece ("chunk") of the volume in Bernstein form; drawing and picking
// need the control points and the net's edges; pins need the boundary. A volume kind implements exactly that:
//
//   - the box lattice (lattice.h; null volume: the engine's fast path, O(1) parameters, vectorised kernels),
//   - LatticeNet (lattice_net.h): one tensor-product NURBS net placed anywhere, the predefined lattices of
//     seed 004 (parallelepiped, cylinder, sphere, prisms) and the nets the user edits,
//   - TSplineVolume (tspline_volume.h): weighted T-spline volumes (Song & Yang 2005) on an octree T-lattice,
//     whose chunks are their Bezier-extracted elements.
//
// Control points are identified by ids 0..controlPointCount()-1. Welded ids (Coquillart 1990, 3.1.2: points
// merged into one control point, whose basis function is the sum of theirs) always carry equal displacements
// and share a representative (the smallest id of the group). Parameters are a point of the kind's own domain
// (Eigen::Vector3d; [0,1]^3 for tensor nets); the engine stores them and hands them back, never interprets them
// except through chunkOf / chunkParameters.
//
// Adding a kind: a class implementing Volume in new files, plus its JSON reader and writer registered in
// io/lattice_json (registerVolumeFormat). Nothing in the session, history, recordings, solver or window
// changes. Kinds whose volume is a single tensor product also return themselves from tensorNet(), which opens
// the vectorised evaluation kernels and the tensor form of the injectivity tests.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/LU>

#include "core/spline/bspline_basis.h"
#include "core/mesh_types.h"
#include "core/status.h"

namespace sculpt::core {

struct LatticeNet;
class CompositeVolume;
class TSplineVolume;

// Up to (kMaxDegree+1)^3 control points with their basis weights R_s at one parameter point.
struct SupportWeights {
    int count = 0;
    std::array<int, 216> index{};
    std::array<double, 216> weight{};
};

// One chunk of a volume in Bezier form over its local coordinates x in [0,1]^3 (Gain & Dodgson 2001,
// section 6: the piece of the volume on which det J is one polynomial).
//   points: 4 blocks of n = (p+1)(q+1)(r+1) values (index l + (p+1) (m + (q+1) o)): x, y, z and w. For a
//   polynomial chunk the first three are the Bezier points and w is 1; for a rational one they are the
//   homogeneous points (W x, W y, W z, W).
//   parameterScale[a]: dt_a / dx_a (the chunk's extent in the volume's parameters), so hodographs in t are
//   p_a / parameterScale[a] times the differences of Bezier points.
//   collapse[a][side]: bit b set if the chunk's face x_a = side is collapsed along axis b: the volume does
//   not depend on x_b there (a cylinder's axis, a pole) because the control points of that face are welded
//   along b. The injectivity tests divide det(dQ/dt) by the face's factor there (injectivity_net.h).
struct BezierChunk {
    std::array<int, 3> degree{};
    bool polynomial = true;
    std::array<double, 3> parameterScale{1.0, 1.0, 1.0};
    std::array<std::array<int, 2>, 3> collapse{};
    std::vector<double> points;  // 4 n values used (it may hold more when reused), see above
};

class Volume {
public:
    virtual ~Volume() = default;

    // The kind's name, as in lattice files ("cylinder", "sphere", "prism", "net", ...).
    virtual const std::string& kindName() const = 0;

    // ---- control points ----
    virtual int controlPointCount() const = 0;
    // P0: #controlPointCount x 3, world units.
    virtual const Positions& restControlPoints() const = 0;
    // NURBS weights W_s > 0, #controlPointCount.
    virtual const std::vector<double>& controlWeights() const = 0;
    // Some weight differs from another (R_s is then a quotient).
    virtual bool isRational() const = 0;
    // The representative (smallest id) of id's weld group; id itself when not welded.
    virtual int representativeOf(int id) const = 0;
    // Weld groups of two or more ids, each sorted (representative first).
    virtual const std::vector<std::vector<int>>& weldGroupList() const = 0;
    // Bounds of the rest control points (the rest volume lies inside: convex hull property, W > 0).
    virtual Eigen::AlignedBox3d restBounds() const = 0;
    // The control point lies on the volume's outer surface (not on a seam or a collapsed face): moving it can
    // move the volume's boundary (lattice_boundary.h), pins count layers from there.
    virtual bool onOuterSurface(int id) const = 0;
    // The control point lies within `layers` layers of control points of the outer surface (pin_layers).
    virtual bool inSurfaceLayers(int id, int layers) const = 0;
    // Pairs of ids joined by an edge of the control net (unwelded ids; lattice.h's controlNetEdges merges them).
    virtual std::vector<std::array<int, 2>> controlNetEdgeList() const = 0;

    // ---- basis and evaluation ----
    // R_s(t) for the control points whose basis is non-zero at t, per id (welded ids separately).
    virtual void basisAt(const Eigen::Vector3d& t, SupportWeights& out) const = 0;
    // Q(t) and, if derivative is not null, dQ/dt (columns d/dt_a) of the volume with control points `points`
    // (#controlPointCount x 3: the rest points, or displacements: Q is linear in them), rational by the quotient
    // rule.
    virtual void evaluate(const Positions& points, const Eigen::Vector3d& t, Eigen::Vector3d& value,
                          Eigen::Matrix3d* derivative = nullptr) const = 0;
    // Freezing (Coquillart 1990, 3.3; Song & Yang 2005, sec. 5): the parameters of rest point x. False for a
    // point outside the volume or a non-finite one (t untouched). Deterministic where chunks overlap.
    virtual bool freeze(const Eigen::Vector3d& x, Eigen::Vector3d& t) const = 0;
    // Freezing in the volume of other control points (#controlPointCount x 3), e.g. the deformed net: a
    // locator built once (its spatial index) and used for many points, from any thread.
    class Locator {
    public:
        virtual ~Locator() = default;
        // As freeze, in that volume.
        virtual bool freeze(const Eigen::Vector3d& x, Eigen::Vector3d& t) const = 0;
    };
    virtual std::unique_ptr<Locator> locatorFor(const Positions& points) const = 0;

    // ---- chunks (Bezier pieces) ----
    virtual int chunkCount() const = 0;
    // The chunk holding parameter t and t's local coordinates in it (a point on a shared face: one
    // deterministic chunk). -1 for parameters outside the domain.
    virtual int chunkOf(const Eigen::Vector3d& t, Eigen::Vector3d& local) const = 0;
    // chunkOf's inverse.
    virtual Eigen::Vector3d chunkParameters(int chunk, const Eigen::Vector3d& local) const = 0;
    // The ids whose basis is non-zero somewhere in the chunk (ascending).
    virtual void chunkSupport(int chunk, std::vector<int>& ids) const = 0;
    // The chunks some of `ids` is non-zero on (ascending, each once): those a change of these control points
    // reaches. This default scans every chunk's support; a volume with an inverse index answers in proportion
    // to what the ids reach.
    virtual void chunksOfControlPoints(const std::vector<int>& ids, std::vector<int>& chunks) const {
        std::vector<std::uint8_t> chosen(static_cast<size_t>(controlPointCount()), 0);
        for (int id : ids) chosen[static_cast<size_t>(id)] = 1;
        std::vector<int> support;
        chunks.clear();
        for (int chunk = 0; chunk < chunkCount(); ++chunk) {
            chunkSupport(chunk, support);
            for (int id : support)
                if (chosen[static_cast<size_t>(id)]) {
                    chunks.push_back(chunk);
                    break;
                }
        }
    }
    // The chunk in Bezier form: of the rest volume, or with the control points moved by `displacement`
    // (#controlPointCount x 3) when it is not null. `out` is reused (no allocation once it is large enough).
    virtual void bezierChunk(int chunk, const Positions* displacement, BezierChunk& out) const = 0;
    // The row of chunks through `chunk` along parameter axis `axis`, in order (the chunk itself included);
    // closed: the row is a ring (a periodic axis: its last chunk joins its first). The injectivity tests walk
    // it to count how often the volume winds round a collapsed line (injectivity_net.h).
    virtual void chunksAlong(int chunk, int axis, std::vector<int>& row, bool& closed) const = 0;
    // Lines of chunk edges in parameter space, for drawing (from, to): each drawn once, seams not repeated.
    virtual std::vector<std::array<Eigen::Vector3d, 2>> chunkEdgeLines() const = 0;

    // This volume as one tensor-product net, or null.
    virtual const LatticeNet* tensorNet() const { return nullptr; }
    // This volume as a weighted T-spline volume (tspline_volume.h), or null: the commands only a T-spline has
    // (subdividing cells, its weights) and its file writer ask this, as tensorNet(), instead of casting.
    virtual const TSplineVolume* tsplineVolume() const { return nullptr; }
    // This volume as welded parts (composite_volume.h), or null.
    virtual const CompositeVolume* compositeVolume() const { return nullptr; }

    // The positioning command (Coquillart 1990, 3.2) for this kind: the same similarity for every control point,
    // which moves the centre of restBounds() to `point`, turns its own z axis onto `normal` (the shortest
    // rotation) and scales the bounds' diagonal to `size`; weights, welds and the parameter space are kept. The
    // arguments are checked by placeVolume (volume_kinds.h), the one caller. A kind that cannot be placed keeps
    // this default: an error naming the kind.
    virtual Status placed(const Eigen::Vector3d& point, const Eigen::Vector3d& normal, double size, std::shared_ptr<const Volume>& out) const;
};

// One Newton step of freezing (Coquillart 1990, 3.3; Song & Yang 2005, sec. 5): dt with dQ/dt dt = residual, by
// LU where dQ/dt (`d`, columns d/dt_a) is well conditioned, else by its pseudo-inverse (singular values below
// 1e-9 of the largest dropped), which moves only along the directions the volume can move in (a cylinder's
// axis, a pole: degenerate chunks). May be non-finite for non-finite input.
Eigen::Vector3d freezingNewtonStep(const Eigen::Matrix3d& d, const Eigen::Vector3d& residual);

// The weld group holding control point `id` (sorted ids, representative first), or null when it is not welded.
inline const std::vector<int>* weldGroupOf(const Volume& volume, int id) {
    const int representative = volume.representativeOf(id);
    if (representative == id && volume.weldGroupList().empty()) return nullptr;
    for (const auto& group : volume.weldGroupList())
        if (group[0] == representative) return &group;
    return nullptr;
}

}  // namespace sculpt::core
