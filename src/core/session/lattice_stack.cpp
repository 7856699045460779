// LatticeStack: the composition through the cage and its layers (lattice_stack.h): forwards by evaluation,
// backwards per layer by Newton's method.
#include "core/session/lattice_stack.h"

#include "core/session/session_internal.h"

namespace sculpt::core {

using detail::vectorText;

Eigen::Vector3d LatticeStack::pushThroughLayers(Eigen::Vector3d x, size_t first) const {
    for (size_t k = first; k < layers_.size(); ++k) x = layerImage(layers_[k].lattice, x);
    return x;
}

bool LatticeStack::pullThroughLayers(const Eigen::Vector3d& y, Eigen::Vector3d& x, size_t count) const {
    Eigen::Vector3d point = y;
    for (size_t k = count; k-- > 0;) {
        const Lattice& layer = layers_[k].lattice;
        // Only the box and the hull of its control points can hold an image of the box (convex hull property).
        Eigen::Vector3d lo, hi;
        deformationBounds(layer, lo, hi);
        Eigen::Vector3d restParams;
        const bool inBox = restParameters(layer, point, restParams);
        if (!((point.array() >= lo.array()).all() && (point.array() <= hi.array()).all())) continue;  // the identity there
        Eigen::Vector3d params;
        if (locateDeformedPoint(layer, point, params)) {
            point = restPoint(layer, params);
            continue;
        }
        // Outside the box a layer is the identity: a point there no box point reaches is its own preimage.
        if (inBox) return false;
    }
    x = point;
    return true;
}

Eigen::Vector3d LatticeStack::activeImage(const Eigen::Vector3d& params) const {
    const Lattice& lattice = activeLattice();
    return restPoint(lattice, params) + displacementAt(lattice, params);
}

bool LatticeStack::toActiveSpace(const Eigen::Vector3d& point, Eigen::Vector3d& out) const {
    if (!cageUnderLayers()) {
        out = point;
        return true;
    }
    return pullThroughLayers(point, out, layers_.size());
}

Eigen::Vector3d LatticeStack::currentImage(const Eigen::Vector3d& params) const {
    const Eigen::Vector3d x = activeImage(params);
    return cageUnderLayers() ? pushThroughLayers(x) : x;
}

Positions LatticeStack::cagePoints() const {
    Positions points = controlPointPositions(lattice_);
    if (!layers_.empty())
        for (Eigen::Index p = 0; p < points.rows(); ++p) points.row(p) = pushThroughLayers(points.row(p).transpose()).transpose();
    return points;
}

void LatticeStack::newestLayersBounds(size_t count, Eigen::Vector3d& lo, Eigen::Vector3d& hi) const {
    lo = Eigen::Vector3d::Constant(INFINITY);
    hi = Eigen::Vector3d::Constant(-INFINITY);
    for (size_t k = layers_.size() - std::min(count, layers_.size()); k < layers_.size(); ++k) {
        Eigen::Vector3d layerLo, layerHi;
        deformationBounds(layers_[k].lattice, layerLo, layerHi);
        lo = lo.cwiseMin(layerLo);
        hi = hi.cwiseMax(layerHi);
    }
}

Eigen::Vector3d LatticeStack::imageOfRestPoint(const Eigen::Vector3d& rest) const {
    // The cage maps its rest space as the vertices' evaluation does (x = X0 + sum R delta; outside the box its
    // collar, or X0 where it carries none); the layers then take the cage's output as they take cageOut_.
    const Eigen::Vector3d x = cageImage(rest);
    return layers_.empty() ? x : pushThroughLayers(x);
}

Eigen::Vector3d LatticeStack::cageImage(const Eigen::Vector3d& rest) const {
    Eigen::Vector3d params;
    if (restParameters(lattice_, rest, params)) return rest + displacementAt(lattice_, params);
    if (!carriesCollar() || !rest.allFinite()) return rest;
    return collarImage(lattice_, rest);
}

void LatticeStack::embedCage(const Positions& rest) {
    embedVertices(lattice_, rest, embedding_);
    if (carriesCollar()) embedCollar(lattice_, rest, embedding_);
}

Status LatticeStack::parametersOfCurrentPoint(const Eigen::Vector3d& point, Eigen::Vector3d& params) const {
    if (!point.allFinite()) return Status::error("point has non-finite coordinates");
    Eigen::Vector3d y;
    if (!toActiveSpace(point, y))
        return Status::error("point " + vectorText(point) + " is not the image of any point inside the lattice");
    const Lattice& lattice = activeLattice();
    if (isUndeformed(lattice)) {
        if (!restParameters(lattice, y, params))
            return Status::error("point " + vectorText(point) + " lies outside the lattice box");
        return Status::success();
    }
    // The deformed image of the box is what the user sees: find the rest point that maps onto this one.
    return locateDeformedPoint(lattice, y, params);
}

}  // namespace sculpt::core
