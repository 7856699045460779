// Session: the cage, its layers and the frozen frames (session.h, "The cage and its layers"), with the
// det J bookkeeping of the whole composition and the snapshots that let a rejected operation change nothing.
#include <algorithm>
#include <cstdint>

#include "core/injectivity.h"
#include "core/session.h"

namespace sculpt::core {

namespace {

// A step's record of the lattice it put in place (a layer, or with newCage a cage), for redo and replay.
void recordPlacement(Step& step, bool newCage, const LatticeSettings& settings, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                     bool pinsKept) {
    step.newCage = newCage;
    step.freshFrame = !newCage;
    step.settings = settings;
    step.frameMin = lo;
    step.frameMax = hi;
    step.framePinsKept = pinsKept;
}

}  // namespace

// ---- composition through the layers ---------------------------------------------------------------------

Eigen::Vector3d Session::pushThroughLayers(Eigen::Vector3d x, size_t first) const {
    for (size_t k = first; k < layers_.size(); ++k) {
        Eigen::Vector3d t;
        if (restParameters(layers_[k].lattice, x, t)) x += displacementAt(layers_[k].lattice, t);
    }
    return x;
}

bool Session::pullThroughLayers(const Eigen::Vector3d& y, Eigen::Vector3d& x, size_t count) const {
    Eigen::Vector3d point = y;
    for (size_t k = count; k-- > 0;) {
        const Lattice& layer = layers_[k].lattice;
        // Only the box and the hull of its control points can hold an image of the box (convex hull property).
        Eigen::Vector3d lo = layer.boxMin, hi = layer.boxMax;
        for (int idx : displacedControlPoints(layer)) {
            lo = lo.cwiseMin(layer.controlPoint(idx));
            hi = hi.cwiseMax(layer.controlPoint(idx));
        }
        Eigen::Vector3d restParams;
        const bool inBox = layer.volume ? restParameters(layer, point, restParams)
                                     : (point.array() >= layer.boxMin.array()).all() && (point.array() <= layer.boxMax.array()).all();
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

void Session::refreshLayerOutput(const std::vector<int>& vertices) {
    const int count = static_cast<int>(vertices.size());
#pragma omp parallel for schedule(static) if (count > 4096)
    for (int c = 0; c < count; ++c) {
        const int v = vertices[static_cast<size_t>(c)];
        positions_.row(v) = pushThroughLayers(cageOut_.row(v).transpose()).transpose();
    }
}

Eigen::Vector3d Session::activeImage(const Eigen::Vector3d& params) const {
    const Lattice& lattice = activeLattice();
    return restPoint(lattice, params) + displacementAt(lattice, params);
}

bool Session::toActiveSpace(const Eigen::Vector3d& point, Eigen::Vector3d& out) const {
    if (!cageUnderLayers()) {
        out = point;
        return true;
    }
    return pullThroughLayers(point, out, layers_.size());
}

Eigen::Vector3d Session::currentImage(const Eigen::Vector3d& params) const {
    const Eigen::Vector3d x = activeImage(params);
    return cageUnderLayers() ? pushThroughLayers(x) : x;
}

Positions Session::cagePoints() const {
    Positions points = controlPointPositions(lattice_);
    if (!layers_.empty())
        for (Eigen::Index p = 0; p < points.rows(); ++p) points.row(p) = pushThroughLayers(points.row(p).transpose()).transpose();
    return points;
}

// ---- layers ---------------------------------------------------------------------------------------------

Status Session::enterLayer(Progress* progress, Step* placed, const Step* recorded, const BrushSettings* brush,
                           const std::vector<Eigen::Vector3d>* centres) {
    Layer layer;
    LatticeSettings settings = settings_;
    Eigen::Vector3d lo, hi;
    bool pinsKept = false, region = false;
    std::vector<int> free;
    if (recorded) {
        settings = recorded->settings;
        lo = recorded->frameMin;
        hi = recorded->frameMax;
        pinsKept = recorded->framePinsKept;
        region = recorded->region;
        free = recorded->regionFree;
    } else if (brush) {
        RegionLattice placement;
        if (Status s = regionLattice(*centres, brush->radius, brush->falloff, placement); !s) return s;
        settings = placement.settings;
        lo = placement.boxMin;
        hi = placement.boxMax;
        region = true;
        free = std::move(placement.freePoints);
    } else {
        // Adaptive subdivision: a fresh regular lattice with the cage's settings in the active lattice's box,
        // grown to contain the mesh it deforms as that is now. It depends only on the mesh and the settings,
        // so a replay reproduces it. Only the vertices the active lattice deforms count: a lattice around a
        // region of the mesh never grows to take in the rest of it.
        const Lattice& active = activeLattice();
        const Embedding& embedding = activeEmbedding();
        lo = active.boxMin;
        hi = active.boxMax;
        if (embedding.insideCount() > 0) {
            Eigen::Vector3d boundsLo = Eigen::Vector3d::Constant(INFINITY), boundsHi = Eigen::Vector3d::Constant(-INFINITY);
            for (int v : embedding.order) {
                boundsLo = boundsLo.cwiseMin(positions_.row(v).transpose());
                boundsHi = boundsHi.cwiseMax(positions_.row(v).transpose());
            }
            // note: a fixed margin, not the cage's padding: a recording replays the cage in its exact box with
            // padding 0, and the layers must come out the same.
            const double pad = 0.05 * (boundsHi - boundsLo).norm();
            for (int a = 0; a < 3; ++a) {
                if (boundsLo[a] < lo[a]) lo[a] = boundsLo[a] - pad;
                if (boundsHi[a] > hi[a]) hi[a] = boundsHi[a] + pad;
            }
        }
        pinsKept = true;
    }
    if (Status s = makeLatticeInBox(settings, lo, hi, layer.lattice); !s) return s;
    if (region) pinAllBut(layer.lattice, free);
    else if (pinsKept)
        for (int idx : pinToggles()) layer.lattice.pinned[static_cast<size_t>(idx)] ^= 1;
    if (placed) {
        recordPlacement(*placed, false, settings, lo, hi, pinsKept);
        placed->region = region;
        placed->regionFree = free;
    }
    if (layers_.empty()) cageOut_ = positions_;
    layer.settings = settings;
    layers_.push_back(std::move(layer));
    embedVertices(layers_.back().lattice, positions_, layerEmbedding_);
    pinBoundaryIfPartial(layers_.back().lattice, layerEmbedding_);
    layerActive_ = true;
    if (progress) {
        progress->appliedInCurrentFrame = false;
        progress->pendingFreshFrame = true;  // the next step applied belongs to this layer
    }
    return Status::success();
}

void Session::popLayers(size_t count, std::vector<int>* moved) {
    // Only where a layer could have put a vertex can a position change: its box and the hull of its control
    // points (convex hull property of the B-spline volume). A vertex outside that region of the newest layer
    // is where the layer below left it, so outside the union of the removed layers' regions nothing changes.
    count = std::min(count, layers_.size());
    if (count == 0) return;
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = Eigen::Vector3d::Constant(-INFINITY);
    for (size_t k = layers_.size() - count; k < layers_.size(); ++k) {
        const Lattice& layer = layers_[k].lattice;
        lo = lo.cwiseMin(layer.boxMin);
        hi = hi.cwiseMax(layer.boxMax);
        for (int idx : displacedControlPoints(layer)) {
            lo = lo.cwiseMin(layer.controlPoint(idx));
            hi = hi.cwiseMax(layer.controlPoint(idx));
        }
    }
    layers_.resize(layers_.size() - count);
    layerActive_ = false;
    const int n = static_cast<int>(positions_.rows());
    std::vector<std::uint8_t> changed(static_cast<size_t>(n), 0);
#pragma omp parallel for schedule(static) if (n > 4096)
    for (int v = 0; v < n; ++v) {
        const Eigen::Vector3d y = positions_.row(v).transpose();
        if (!((y.array() >= lo.array()).all() && (y.array() <= hi.array()).all())) continue;
        const Eigen::Vector3d x = pushThroughLayers(cageOut_.row(v).transpose());
        if (x != y) {
            positions_.row(v) = x.transpose();
            changed[static_cast<size_t>(v)] = 1;
        }
    }
    std::vector<int> list;
    for (int v = 0; v < n; ++v)
        if (changed[static_cast<size_t>(v)]) list.push_back(v);
    positionsChanged(&list);
    if (moved) moved->insert(moved->end(), list.begin(), list.end());
    if (layers_.empty()) cageOut_.resize(0, 3);
}

// ---- frames (lattice set-ups) ---------------------------------------------------------------------------

void Session::enterNewCage(const LatticeSettings& settings, Step* placed, const Step* recorded) {
    if (trackJacobian_) {
        accumulateFrameJacobian(false);
        accumulateLayersJacobian(false);
    }
    // Freeze the cage compactly: its box, its non-zero control displacements, its pin edits, its layers.
    FrozenFrame frozen;
    frozen.settings = settings_;
    frozen.boxMin = lattice_.boxMin;
    frozen.boxMax = lattice_.boxMax;
    frozen.displacement.indices = displacedControlPoints(lattice_);
    frozen.displacement.deltas.resize(static_cast<Eigen::Index>(frozen.displacement.indices.size()), 3);
    for (size_t c = 0; c < frozen.displacement.indices.size(); ++c)
        frozen.displacement.deltas.row(static_cast<Eigen::Index>(c)) = lattice_.displacement.row(frozen.displacement.indices[c]);
    frozen.pinToggles = pinToggles();
    frozen.layers = std::move(layers_);
    layers_.clear();
    cageOut_.resize(0, 3);
    layerActive_ = false;

    // The new cage is placed as a set-up places it, around the mesh as it is now; with the same settings
    // (same control point ids) it keeps the user's pin edits.
    Eigen::Vector3d lo, hi;
    bool pinsKept = sameLatticeSettings(settings, settings_);
    if (recorded) {
        lo = recorded->frameMin;
        hi = recorded->frameMax;
        pinsKept = recorded->framePinsKept;
    } else {
        latticeBox(settings, positions_, lo, hi);
    }
    if (placed) recordPlacement(*placed, true, settings, lo, hi, pinsKept);
    Lattice fresh;
    makeLatticeInBox(settings, lo, hi, fresh);
    if (pinsKept)
        for (int idx : frozen.pinToggles) fresh.pinned[static_cast<size_t>(idx)] ^= 1;
    frames_.push_back(std::move(frozen));
    settings_ = settings;
    lattice_ = std::move(fresh);
    rest_ = positions_;
    embedVertices(lattice_, rest_, embedding_);
    ++restVersion_;
    pinBoundaryIfPartial(lattice_, embedding_);
    lastMovedAll_ = true;
}

void Session::leaveCage() {
    // The cage being left is (up to rounding) undeformed again and its layers are gone: the mesh is its rest
    // state, which is what the frozen cage and its layers produced. Invert those to get their rest state.
    FrozenFrame frozen = std::move(frames_.back());
    frames_.pop_back();
    positions_ = rest_;
    Lattice previous;
    makeLatticeInBox(frozen.settings, frozen.boxMin, frozen.boxMax, previous);
    for (size_t c = 0; c < frozen.displacement.indices.size(); ++c)
        previous.displacement.row(frozen.displacement.indices[c]) = frozen.displacement.deltas.row(static_cast<Eigen::Index>(c));
    for (int idx : frozen.pinToggles) previous.pinned[static_cast<size_t>(idx)] ^= 1;
    lattice_ = std::move(previous);
    settings_ = frozen.settings;
    layers_ = std::move(frozen.layers);
    layerActive_ = false;
    positionsChanged(nullptr);
    if (layers_.empty()) {
        invertDeformation(lattice_, positions_, rest_);
    } else {
        Positions input = positions_, preimage;
        for (size_t k = layers_.size(); k-- > 0;) {
            invertDeformation(layers_[k].lattice, input, preimage);
            input.swap(preimage);
        }
        cageOut_ = std::move(input);
        invertDeformation(lattice_, cageOut_, rest_);
    }
    embedVertices(lattice_, rest_, embedding_);
    ++restVersion_;
    pinBoundaryIfPartial(lattice_, embedding_);
    if (trackJacobian_) {
        accumulateFrameJacobian(true);
        accumulateLayersJacobian(true);
    }
    lastMovedAll_ = true;
}

// ---- snapshots ------------------------------------------------------------------------------------------

void Session::saveSnapshot(Snapshot& snapshot) {
    if (snapshot.saved) return;
    snapshot.saved = true;
    snapshot.positions = positions_;
    snapshot.cageOut = cageOut_;
    snapshot.cage = lattice_;
    snapshot.layerCount = layers_.size();
    snapshot.layerActive = layerActive_;
    if (layerActive_) {
        snapshot.activeLayer = layers_.back().lattice;
        snapshot.layerEmbedding = layerEmbedding_;
    }
}

void Session::restoreSnapshot(Snapshot& snapshot) {
    if (!snapshot.saved) return;
    layers_.erase(layers_.begin() + static_cast<std::ptrdiff_t>(snapshot.layerCount), layers_.end());
    layerActive_ = snapshot.layerActive;
    if (layerActive_) {
        layers_.back().lattice = snapshot.activeLayer;
        layerEmbedding_ = snapshot.layerEmbedding;
    }
    lattice_ = snapshot.cage;
    positions_ = snapshot.positions;
    cageOut_ = snapshot.cageOut;
    positionsChanged(nullptr);
}

// ---- det J of the whole deformation ---------------------------------------------------------------------

void Session::setTrackJacobian(bool track) {
    if (track && !trackJacobian_) frozenJacobian_.assign(static_cast<size_t>(rest_.rows()), 1.0);
    if (!track) frozenJacobian_.clear();
    trackJacobian_ = track;
}

void Session::accumulateFrameJacobian(bool divide) {
    // Only vertices in cells reached by a non-zero control displacement have det J != 1 in this frame.
    const std::vector<int> cells = cellsInfluencedBy(lattice_, displacedControlPoints(lattice_));
    const int cellCount = static_cast<int>(cells.size());
#pragma omp parallel for schedule(dynamic, 4) if (cellCount > 64)
    for (int c = 0; c < cellCount; ++c) {
        const int cell = cells[static_cast<size_t>(c)];
        for (int s = embedding_.cellStart[cell]; s < embedding_.cellStart[cell + 1]; ++s) {
            const double det = jacobianDeterminant(lattice_, embeddedParameters(lattice_, embedding_, cell, s));
            double& product = frozenJacobian_[static_cast<size_t>(embedding_.order[s])];
            product = divide ? product / det : product * det;
        }
    }
}

namespace {

// The product of the layers' det J along the path of a point from the cage's output (chain rule).
double layersJacobian(const std::vector<Layer>& layers, Eigen::Vector3d x) {
    double product = 1.0;
    for (const Layer& layer : layers) {
        Eigen::Vector3d t, displacement;
        Eigen::Matrix3d jacobian;
        if (!restParameters(layer.lattice, x, t)) continue;
        deformationJacobian(layer.lattice, t, displacement, jacobian);
        product *= jacobian.determinant();
        x += displacement;
    }
    return product;
}

}  // namespace

void Session::accumulateLayersJacobian(bool divide) {
    if (layers_.empty()) return;
    const int n = static_cast<int>(cageOut_.rows());
#pragma omp parallel for schedule(static) if (n > 4096)
    for (int v = 0; v < n; ++v) {
        const double det = layersJacobian(layers_, cageOut_.row(v).transpose());
        double& product = frozenJacobian_[static_cast<size_t>(v)];
        product = divide ? product / det : product * det;
    }
}

std::vector<double> Session::totalJacobianDeterminants() const {
    std::vector<double> det;
    vertexJacobianDeterminants(lattice_, rest_, det);
    if (trackJacobian_)
        for (size_t v = 0; v < det.size(); ++v) det[v] *= frozenJacobian_[v];
    if (!layers_.empty()) {
        const int n = static_cast<int>(cageOut_.rows());
#pragma omp parallel for schedule(static) if (n > 4096)
        for (int v = 0; v < n; ++v) det[static_cast<size_t>(v)] *= layersJacobian(layers_, cageOut_.row(v).transpose());
    }
    return det;
}

}  // namespace sculpt::core
