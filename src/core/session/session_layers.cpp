// Session: the cage, its layers and the frozen frames (session.h, "The cage and its layers"), with the
// det J bookkeeping of the whole composition and the snapshots that let a rejected operation change nothing.
#include <algorithm>
#include <cstdint>

#include <Eigen/SVD>

#include "core/injectivity/injectivity.h"
#include "core/session/session.h"

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
    step.frameAxes.setIdentity();
}

}  // namespace

// ---- composition through the layers ---------------------------------------------------------------------

void Session::refreshLayerOutput(const std::vector<int>& vertices) {
    const int count = static_cast<int>(vertices.size());
#pragma omp parallel for schedule(static) if (count > 4096)
    for (int c = 0; c < count; ++c) {
        const int v = vertices[static_cast<size_t>(c)];
        mesh_.positions.row(v) = stack_.pushThroughLayers(stack_.cageOut_.row(v).transpose()).transpose();
    }
}

// ---- layers ---------------------------------------------------------------------------------------------

Status Session::enterLayer(Progress* progress, Step* placed, const Step* recorded) {
    Layer layer;
    LatticeSettings settings = stack_.settings_;
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
    } else {
        // Adaptive subdivision: a fresh regular lattice with the cage's settings in the active lattice's box,
        // grown to contain the mesh it deforms as that is now. It depends only on the mesh and the settings,
        // so a replay reproduces it. Only the vertices the active lattice deforms count: a lattice around a
        // region of the mesh never grows to take in the rest of it.
        const Lattice& active = stack_.activeLattice();
        const Embedding& embedding = stack_.activeEmbedding();
        lo = active.boxMin;
        hi = active.boxMax;
        if (embedding.insideCount() > 0) {
            Eigen::Vector3d boundsLo = Eigen::Vector3d::Constant(INFINITY), boundsHi = Eigen::Vector3d::Constant(-INFINITY);
            for (int v : embedding.order) {
                boundsLo = boundsLo.cwiseMin(mesh_.positions.row(v).transpose());
                boundsHi = boundsHi.cwiseMax(mesh_.positions.row(v).transpose());
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
    if (recorded)  // a brush region is turned to its pull
        if (Status s = turnBoxLattice(layer.lattice, recorded->frameAxes); !s) return s;
    if (region) pinAllBut(layer.lattice, free);
    else if (pinsKept)
        for (int idx : pins().toggles()) layer.lattice.pinned[static_cast<size_t>(idx)] ^= 1;
    if (placed) {
        recordPlacement(*placed, false, settings, lo, hi, pinsKept);
        placed->region = region;
        placed->regionFree = free;
    }
    if (stack_.layers_.empty() && !(cageOutKept_ && stack_.cageOut_.rows() == mesh_.positions.rows())) stack_.cageOut_ = mesh_.positions;
    cageOutKept_ = false;
    layer.settings = settings;
    stack_.layers_.push_back(std::move(layer));
    if (region && layerCandidates_) embedVertices(stack_.layers_.back().lattice, mesh_.positions, stack_.layerEmbedding_, *layerCandidates_);
    else embedVertices(stack_.layers_.back().lattice, mesh_.positions, stack_.layerEmbedding_);
    pins().pinBoundaryIfPartial(stack_.layers_.back().lattice, stack_.layerEmbedding_);
    stack_.layerActive_ = true;
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
    count = std::min(count, stack_.layers_.size());
    if (count == 0) return;
    Eigen::Vector3d lo, hi;
    stack_.newestLayersBounds(count, lo, hi);
    stack_.layers_.resize(stack_.layers_.size() - count);
    stack_.layerActive_ = false;
    // In a brush stroke only its candidates can have moved (applyBrushPulls: its layers are its regions).
    const std::vector<int>* among = layerCandidates_;
    const int n = among ? static_cast<int>(among->size()) : static_cast<int>(mesh_.positions.rows());
    std::vector<std::uint8_t> changed(static_cast<size_t>(n), 0);
#pragma omp parallel for schedule(static) if (n > 4096)
    for (int c = 0; c < n; ++c) {
        const int v = among ? (*among)[static_cast<size_t>(c)] : c;
        const Eigen::Vector3d y = mesh_.positions.row(v).transpose();
        if (!((y.array() >= lo.array()).all() && (y.array() <= hi.array()).all())) continue;
        const Eigen::Vector3d x = stack_.pushThroughLayers(stack_.cageOut_.row(v).transpose());
        if (x != y) {
            mesh_.positions.row(v) = x.transpose();
            changed[static_cast<size_t>(c)] = 1;
        }
    }
    std::vector<int> list;
    for (int c = 0; c < n; ++c)
        if (changed[static_cast<size_t>(c)]) list.push_back(among ? (*among)[static_cast<size_t>(c)] : c);
    positionsChanged(&list);
    if (moved) moved->insert(moved->end(), list.begin(), list.end());
    if (stack_.layers_.empty()) {
        if (layerCandidates_) cageOutKept_ = true;
        else stack_.cageOut_.resize(0, 3);
    }
}

// ---- frames (lattice set-ups) ---------------------------------------------------------------------------

void Session::enterNewCage(const LatticeSettings& settings, Step* placed, const Step* recorded) {
    if (trackJacobian_) {
        accumulateFrameJacobian(false);
        accumulateLayersJacobian(false);
    }
    // Freeze the cage compactly: its box, its non-zero control displacements, its pin edits, its layers.
    FrozenFrame frozen;
    frozen.settings = stack_.settings_;
    frozen.boxMin = stack_.lattice_.boxMin;
    frozen.boxMax = stack_.lattice_.boxMax;
    frozen.displacement.indices = displacedControlPoints(stack_.lattice_);
    frozen.displacement.deltas.resize(static_cast<Eigen::Index>(frozen.displacement.indices.size()), 3);
    for (size_t c = 0; c < frozen.displacement.indices.size(); ++c)
        frozen.displacement.deltas.row(static_cast<Eigen::Index>(c)) = stack_.lattice_.displacement.row(frozen.displacement.indices[c]);
    frozen.pinToggles = pins().toggles();
    frozen.layers = std::move(stack_.layers_);
    frozen.collar = stack_.carriesCollar();
    // The new cage's rest space is the shape as it is now: the mirror planes are where the deformation put them.
    frozen.symmetry = symmetryRest_;
    symmetryRest_ = symmetryFrame();
    stack_.layers_.clear();
    stack_.cageOut_.resize(0, 3);
    stack_.layerActive_ = false;

    // The new cage is placed as a set-up places it, around the mesh as it is now; with the same settings
    // (same control point ids) it keeps the user's pin edits.
    Eigen::Vector3d lo, hi;
    bool pinsKept = sameLatticeSettings(settings, stack_.settings_);
    if (recorded) {
        lo = recorded->frameMin;
        hi = recorded->frameMax;
        pinsKept = recorded->framePinsKept;
    } else {
        latticeBox(settings, mesh_.positions, lo, hi);
    }
    if (placed) recordPlacement(*placed, true, settings, lo, hi, pinsKept);
    Lattice fresh;
    makeLatticeInBox(settings, lo, hi, fresh);
    if (pinsKept)
        for (int idx : frozen.pinToggles) fresh.pinned[static_cast<size_t>(idx)] ^= 1;
    stack_.frames_.push_back(std::move(frozen));
    stack_.settings_ = settings;
    stack_.lattice_ = std::move(fresh);
    mesh_.rest = mesh_.positions;
    embedVertices(stack_.lattice_, mesh_.rest, stack_.embedding_);
    stack_.setCollarFromSetUp(mesh_.rest);  // every vertex it holds is inside: no collar to embed yet
    ++mesh_.restVersion;
    pins().pinBoundaryIfPartial(stack_.lattice_, stack_.embedding_);
    lastMoved_.all = true;
}

void Session::leaveCage() {
    // The cage being left is (up to rounding) undeformed again and its layers are gone: the mesh is its rest
    // state, which is what the frozen cage and its layers produced. Invert those to get their rest state.
    FrozenFrame frozen = std::move(stack_.frames_.back());
    stack_.frames_.pop_back();
    mesh_.positions = mesh_.rest;
    Lattice previous;
    makeLatticeInBox(frozen.settings, frozen.boxMin, frozen.boxMax, previous);
    for (size_t c = 0; c < frozen.displacement.indices.size(); ++c)
        previous.displacement.row(frozen.displacement.indices[c]) = frozen.displacement.deltas.row(static_cast<Eigen::Index>(c));
    for (int idx : frozen.pinToggles) previous.pinned[static_cast<size_t>(idx)] ^= 1;
    stack_.lattice_ = std::move(previous);
    stack_.settings_ = frozen.settings;
    stack_.collar_ = frozen.collar;
    symmetryRest_ = frozen.symmetry;
    stack_.layers_ = std::move(frozen.layers);
    stack_.layerActive_ = false;
    positionsChanged(nullptr);
    if (stack_.layers_.empty()) {
        invertDeformation(stack_.lattice_, mesh_.positions, mesh_.rest, stack_.carriesCollar());
    } else {
        Positions input = mesh_.positions, preimage;
        for (size_t k = stack_.layers_.size(); k-- > 0;) {
            invertDeformation(stack_.layers_[k].lattice, input, preimage);
            input.swap(preimage);
        }
        stack_.cageOut_ = std::move(input);
        invertDeformation(stack_.lattice_, stack_.cageOut_, mesh_.rest, stack_.carriesCollar());
    }
    stack_.embedCage(mesh_.rest);
    ++mesh_.restVersion;
    pins().pinBoundaryIfPartial(stack_.lattice_, stack_.embedding_);
    if (trackJacobian_) {
        accumulateFrameJacobian(true);
        accumulateLayersJacobian(true);
    }
    lastMoved_.all = true;
}

// ---- snapshots ------------------------------------------------------------------------------------------

void Session::saveSnapshot(Snapshot& snapshot) {
    if (snapshot.saved) return;
    snapshot.saved = true;
    snapshot.positions = mesh_.positions;
    snapshot.cageOut = stack_.cageOut_;
    snapshot.cage = stack_.lattice_;
    snapshot.layerCount = stack_.layers_.size();
    snapshot.layerActive = stack_.layerActive_;
    if (stack_.layerActive_) {
        snapshot.activeLayer = stack_.layers_.back().lattice;
        snapshot.layerEmbedding = stack_.layerEmbedding_;
    }
}

void Session::restoreSnapshot(Snapshot& snapshot) {
    if (!snapshot.saved) return;
    stack_.layers_.erase(stack_.layers_.begin() + static_cast<std::ptrdiff_t>(snapshot.layerCount), stack_.layers_.end());
    stack_.layerActive_ = snapshot.layerActive;
    if (stack_.layerActive_) {
        stack_.layers_.back().lattice = snapshot.activeLayer;
        stack_.layerEmbedding_ = snapshot.layerEmbedding;
    }
    stack_.lattice_ = snapshot.cage;
    mesh_.positions = snapshot.positions;
    stack_.cageOut_ = snapshot.cageOut;
    positionsChanged(nullptr);
}

// ---- det J of the whole deformation ---------------------------------------------------------------------

void Session::setTrackJacobian(bool track) {
    if (track && !trackJacobian_) frozenJacobian_.assign(static_cast<size_t>(mesh_.rest.rows()), 1.0);
    if (!track) frozenJacobian_.clear();
    trackJacobian_ = track;
}

void Session::accumulateFrameJacobian(bool divide) {
    // Only vertices in cells reached by a non-zero control displacement have det J != 1 in this frame.
    const std::vector<int> cells = cellsInfluencedBy(stack_.lattice_, displacedControlPoints(stack_.lattice_));
    const int cellCount = static_cast<int>(cells.size());
#pragma omp parallel for schedule(dynamic, 4) if (cellCount > 64)
    for (int c = 0; c < cellCount; ++c) {
        const int cell = cells[static_cast<size_t>(c)];
        for (int s = stack_.embedding_.cellStart[cell]; s < stack_.embedding_.cellStart[cell + 1]; ++s) {
            const double det = jacobianDeterminant(stack_.lattice_, embeddedParameters(stack_.lattice_, stack_.embedding_, cell, s));
            double& product = frozenJacobian_[static_cast<size_t>(stack_.embedding_.order[s])];
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
    if (stack_.layers_.empty()) return;
    const int n = static_cast<int>(stack_.cageOut_.rows());
#pragma omp parallel for schedule(static) if (n > 4096)
    for (int v = 0; v < n; ++v) {
        const double det = layersJacobian(stack_.layers_, stack_.cageOut_.row(v).transpose());
        double& product = frozenJacobian_[static_cast<size_t>(v)];
        product = divide ? product / det : product * det;
    }
}

std::vector<double> Session::totalJacobianDeterminants() const {
    std::vector<double> det;
    vertexJacobianDeterminants(stack_.lattice_, mesh_.rest, det);
    if (trackJacobian_)
        for (size_t v = 0; v < det.size(); ++v) det[v] *= frozenJacobian_[v];
    if (!stack_.layers_.empty()) {
        const int n = static_cast<int>(stack_.cageOut_.rows());
#pragma omp parallel for schedule(static) if (n > 4096)
        for (int v = 0; v < n; ++v) det[static_cast<size_t>(v)] *= layersJacobian(stack_.layers_, stack_.cageOut_.row(v).transpose());
    }
    return det;
}

// ---- the mirror planes ---------------------------------------------------------------------------------

SymmetryFrame Session::symmetryFrame() const {
    if (stack_.layers_.empty() && isUndeformed(stack_.lattice_)) return symmetryRest_;  // exactly as they rest
    SymmetryFrame frame;
    const Eigen::Vector3d c = symmetryRest_.centre;
    frame.centre = stack_.imageOfRestPoint(c);
    // The derivative at the centre by central differences (exact for an affine map up to rounding), then the
    // rotation nearest to it times the rest axes (the polar decomposition's orthogonal factor, by the SVD).
    const double h = 1e-4 * std::max(stack_.lattice_.diagonal(), 1e-300);
    Eigen::Matrix3d jacobian;
    for (int a = 0; a < 3; ++a) {
        Eigen::Vector3d e = Eigen::Vector3d::Zero();
        e[a] = h;
        jacobian.col(a) = (stack_.imageOfRestPoint(c + e) - stack_.imageOfRestPoint(c - e)) / (2.0 * h);
    }
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(jacobian * symmetryRest_.axes, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d u = svd.matrixU();
    if ((u * svd.matrixV().transpose()).determinant() < 0.0) u.col(2) = -u.col(2);
    frame.axes = u * svd.matrixV().transpose();
    if (!frame.centre.allFinite() || !frame.axes.allFinite()) return symmetryRest_;
    return frame;
}

// ---- baking layers into the rest shape -----------------------------------------------------------------

namespace {

// The rest point the cage carries onto y: X0 with C(X0) = y (Newton, tight tolerance first), or a point outside
// the box: the one the cage's collar carries onto y (collarPreimage) where it has one, else y itself (a cage
// without a collar leaves every point outside its box where it is). Once the cage has moved, a point can have
// a preimage on both sides; `outsideFirst` picks the one on the side the vertex's rest point was on, so baking
// and unbaking a vertex keep it on its side. False if none.
bool cagePreimage(const Lattice& cage, bool collar, const Eigen::Vector3d& y, bool outsideFirst, Eigen::Vector3d& rest) {
    const bool outside = !cage.volume && ((y.array() < cage.boxMin.array()).any() || (y.array() > cage.boxMax.array()).any());
    const auto beyond = [&] {
        if (collar && collarPreimage(cage, y, rest)) return true;
        if (!outside) return false;
        rest = y;
        return true;
    };
    if (outsideFirst && beyond()) return true;
    Eigen::Vector3d t;
    if (locateDeformedPoint(cage, y, t, 1e-15) || locateDeformedPoint(cage, y, t, 1e-12)) {
        rest = restPoint(cage, t);
        return true;
    }
    return !outsideFirst && beyond();
}

bool outsideBox(const Lattice& cage, const Eigen::Vector3d& rest) {
    return !cage.volume && ((rest.array() < cage.boxMin.array()).any() || (rest.array() > cage.boxMax.array()).any());
}

// The unit direction every displaced control point of `lattice` moves along, or zero if they do not share one
// (a brush stroke's pull field has one: brush_field.h).
Eigen::Vector3d sharedDirection(const Lattice& lattice) {
    double largest = 0.0;
    Eigen::Vector3d e = Eigen::Vector3d::Zero();
    const std::vector<int> displaced = displacedControlPoints(lattice);
    for (int idx : displaced) {
        const double norm = lattice.displacement.row(idx).norm();
        if (norm > largest) {
            largest = norm;
            e = lattice.displacement.row(idx).transpose() / norm;
        }
    }
    for (int idx : displaced) {
        const Eigen::Vector3d d = lattice.displacement.row(idx).transpose();
        if ((d - d.dot(e) * e).norm() > 1e-12 * largest) return Eigen::Vector3d::Zero();
    }
    return e;
}

// The preimage x of y under a layer that moves every point along e: x = y - lambda e with
// g(lambda) = lambda - e . u(y - lambda e) = 0, and g' = 1 + e . grad(u . e) = det J > 0 (the field is
// injective), so g is increasing and a safeguarded Newton iteration on the bracket [-M, M] (M: the largest
// control displacement, which bounds u by the convex hull property) always converges.
bool invertParallelLayer(const Lattice& layer, const Eigen::Vector3d& e, double bound, const Eigen::Vector3d& y, Eigen::Vector3d& x) {
    const auto g = [&](double lambda, double* slope) {
        const Eigen::Vector3d p = y - lambda * e;
        Eigen::Vector3d t;
        if (!restParameters(layer, p, t)) {
            if (slope) *slope = 1.0;
            return lambda;
        }
        Eigen::Vector3d displacement;
        Eigen::Matrix3d jacobian;
        deformationJacobian(layer, t, displacement, jacobian);
        if (slope) *slope = e.dot(jacobian * e);
        return lambda - e.dot(displacement);
    };
    double lo = -bound, hi = bound, lambda = 0.0, previous = INFINITY;
    for (int iteration = 0; iteration < 200; ++iteration) {
        double slope = 1.0;
        const double value = g(lambda, &slope);
        if (value == 0.0) break;
        (value < 0.0 ? lo : hi) = lambda;
        double next = lambda - value / slope;
        // Newton where it converges; bisection where it leaves the bracket or does not halve |g| (it can cycle
        // between the steep and the flat side of the root).
        if (!(next > lo && next < hi) || !std::isfinite(next) || std::abs(value) > 0.5 * previous) next = 0.5 * (lo + hi);
        previous = std::abs(value);
        if (std::abs(next - lambda) <= 1e-17 * std::max(1.0, bound) || hi - lo <= 4e-16 * std::max(1.0, bound)) {
            lambda = next;
            break;
        }
        lambda = next;
    }
    x = y - lambda * e;
    return std::isfinite(lambda) && std::abs(g(lambda, nullptr)) <= 1e-12 * std::max(1.0, bound);
}

double cageJacobianAt(const Lattice& cage, const Eigen::Vector3d& rest) {
    Eigen::Vector3d t;
    return restParameters(cage, rest, t) ? jacobianDeterminant(cage, t) : 1.0;
}

}  // namespace

int Session::verticesLeftOutsideCage() const {
    // A cage with a collar carries every vertex (embedding.h, embedCollar): none is left behind.
    if (stack_.lattice_.volume || stack_.carriesCollar() || mesh_.triangles.rows() == 0) return 0;
    const int n = static_cast<int>(mesh_.rest.rows());
    std::vector<std::uint8_t> outside(static_cast<size_t>(n), 0);
    bool any = false;
    for (int v = 0; v < n; ++v) any = (outside[static_cast<size_t>(v)] = outsideBox(stack_.lattice_, mesh_.rest.row(v).transpose())) || any;
    if (!any) return 0;
    // An inside corner the cage moved: its cage image differs from its rest point.
    const auto cageMoved = [&](int u) {
        Eigen::Vector3d t;
        return restParameters(stack_.lattice_, mesh_.rest.row(u).transpose(), t) && displacementAt(stack_.lattice_, t).squaredNorm() > 0.0;
    };
    std::vector<std::uint8_t> left(static_cast<size_t>(n), 0);
    for (Eigen::Index f = 0; f < mesh_.triangles.rows(); ++f) {
        int outsideCorners = 0;
        for (int k = 0; k < 3; ++k) outsideCorners += outside[static_cast<size_t>(mesh_.triangles(f, k))];
        if (outsideCorners == 0 || outsideCorners == 3) continue;  // the cage's seam runs through mixed triangles only
        bool movedInside = false;
        for (int k = 0; k < 3 && !movedInside; ++k)
            movedInside = !outside[static_cast<size_t>(mesh_.triangles(f, k))] && cageMoved(mesh_.triangles(f, k));
        if (!movedInside) continue;
        for (int k = 0; k < 3; ++k)
            if (outside[static_cast<size_t>(mesh_.triangles(f, k))]) left[static_cast<size_t>(mesh_.triangles(f, k))] = 1;
    }
    return static_cast<int>(std::count(left.begin(), left.end(), std::uint8_t{1}));
}

bool Session::bakeLayers(const std::vector<Step>& steps) {
    // Only an operation's own layers (fresh-frame steps since its last baked step): layers an earlier operation
    // could not bake stay after the cage, and so then do these.
    // note: an adaptive subdivision's fresh lattices grow to hold the mesh as the drag carries it out of the cage's
    // box; baked, such vertices would rest outside the cage, which would then no longer carry them (a large drag
    // on the default mesh: 604 of its vertices). Those stay after the cage; the others are baked.
    size_t own = 0;
    bool subdivision = false;
    for (size_t k = steps.size(); k-- > 0 && (k + 1 == steps.size() || !steps[k].baked);) {
        subdivision = subdivision || (steps[k].freshFrame && !steps[k].region);
        own += steps[k].freshFrame && steps[k].weights.empty();
    }
    if (own != stack_.layers_.size()) return false;
    return bakeAllLayers(&steps.back().bakedOutside, !subdivision);
}

bool Session::bakeAllLayers(std::vector<int>* outside, bool allowOutside) {
    if (stack_.layers_.empty() || stack_.layerActive_) return false;
    const int n = static_cast<int>(mesh_.positions.rows());
    // Exactly the vertices some layer moved: their output differs from the cage's.
    std::vector<int> moved;
    for (int v = 0; v < n; ++v)
        if (mesh_.positions.row(v) != stack_.cageOut_.row(v)) moved.push_back(v);
    Positions rest(static_cast<Eigen::Index>(moved.size()), 3);
    bool ok = true;
    const int count = static_cast<int>(moved.size());
#pragma omp parallel for schedule(static) if (count > 2048) reduction(&& : ok)
    for (int c = 0; c < count; ++c) {
        Eigen::Vector3d x = Eigen::Vector3d::Zero();
        const int v = moved[static_cast<size_t>(c)];
        const bool found = cagePreimage(stack_.lattice_, stack_.carriesCollar(), mesh_.positions.row(v).transpose(), outsideBox(stack_.lattice_, mesh_.rest.row(v).transpose()), x);
        ok = ok && found;
        rest.row(c) = x.transpose();
    }
    if (!ok) return false;  // the layers stay after the cage, as before
    if (!allowOutside)
        for (int c = 0; c < count; ++c)
            if (outsideBox(stack_.lattice_, rest.row(c).transpose())) return false;
    if (trackJacobian_) {
        // The det J map multiplies the cage's det J at the rest point by frozenJacobian_: keep the product.
        for (int c = 0; c < count; ++c) {
            const int v = moved[static_cast<size_t>(c)];
            const double before = cageJacobianAt(stack_.lattice_, mesh_.rest.row(v).transpose()) * layersJacobian(stack_.layers_, stack_.cageOut_.row(v).transpose());
            const double after = cageJacobianAt(stack_.lattice_, rest.row(c).transpose());
            frozenJacobian_[static_cast<size_t>(v)] *= before / after;
        }
    }
    if (outside) {
        outside->clear();
        for (int v : moved)
            if (outsideBox(stack_.lattice_, mesh_.rest.row(v).transpose())) outside->push_back(v);
    }
    drag_.outsideCage = 0;
    for (int c = 0; c < count; ++c) {
        mesh_.rest.row(moved[static_cast<size_t>(c)]) = rest.row(c);
        drag_.outsideCage += !stack_.carriesCollar() && outsideBox(stack_.lattice_, rest.row(c).transpose());
    }
    stack_.layers_.clear();
    stack_.cageOut_.resize(0, 3);
    stack_.embedCage(mesh_.rest);
    ++mesh_.restVersion;
    return true;
}

void Session::unbakeLayers(const std::vector<Step>& steps, size_t last) {
    // The layers baked at steps[last]: the fresh-frame steps after the previous baked one.
    size_t first = last;
    while (first > 0 && !steps[first - 1].baked) --first;
    stack_.layerActive_ = false;
    for (size_t k = first; k <= last; ++k) {
        if (!steps[k].freshFrame || !steps[k].weights.empty()) continue;
        enterLayer(nullptr, nullptr, &steps[k]);
        applyControlDelta(stack_.layers_.back().lattice, steps[k].delta, 1.0);
        stack_.layerActive_ = false;
    }
    if (stack_.layers_.empty()) return;
    if (stack_.cageOut_.rows() != mesh_.positions.rows()) stack_.cageOut_ = mesh_.positions;
    Eigen::Vector3d lo, hi;
    stack_.newestLayersBounds(stack_.layers_.size(), lo, hi);
    // A stroke's layer moves along one line: inverted along it (always converges); other layers by Newton.
    std::vector<Eigen::Vector3d> directions;
    std::vector<double> bounds;
    std::vector<std::uint8_t> boundaryMoved;
    for (const Layer& layer : stack_.layers_) {
        directions.push_back(sharedDirection(layer.lattice));
        bounds.push_back(layer.lattice.displacement.rowwise().norm().maxCoeff() * (1.0 + 1e-9));
        boundaryMoved.push_back(!boundaryUnmoved(layer.lattice));
    }
    const auto invert = [&](const Eigen::Vector3d& y, Eigen::Vector3d& x) {
        x = y;
        for (size_t k = stack_.layers_.size(); k-- > 0;) {
            const Lattice& layer = stack_.layers_[k].lattice;
            Eigen::Vector3d below = x;
            Eigen::Vector3d inBox;
            if (boundaryMoved[k] && !restParameters(layer, x, inBox)) {
                // Outside the box of a layer whose boundary moved (an adaptive subdivision's fresh lattice, placed
                // around the whole mesh, moves its outer control points too): the point is where the layer carried
                // a point of its box, not a point the layer left alone, since the layer's box held every vertex
                // when it was entered. Along the line (below) the identity outside the box is a second root at the
                // point itself, which undid nothing: a drag's undo left a fin of 61 vertices on the camel's head.
                Eigen::Vector3d params;
                if (locateDeformedPoint(layer, x, params, 1e-15) || locateDeformedPoint(layer, x, params)) below = restPoint(layer, params);
            } else if (directions[k].squaredNorm() > 0.0) {
                if (!invertParallelLayer(layer, directions[k], bounds[k], x, below)) return false;
            } else {
                // Newton to the last bit (undo is exact to 1e-12 x diagonal over many strokes); outside the region
                // of the box and the displaced control points' hull, the layer is the identity.
                Eigen::Vector3d regionLo, regionHi, params;
                deformationBounds(layer, regionLo, regionHi);
                if ((x.array() >= regionLo.array()).all() && (x.array() <= regionHi.array()).all()) {
                    if (locateDeformedPoint(layer, x, params, 1e-15) || locateDeformedPoint(layer, x, params)) below = restPoint(layer, params);
                    else if (restParameters(layer, x, params)) return false;
                }
            }
            // A point the layer left where it was (no displacement at its preimage) comes back as itself bitwise,
            // not moved by Newton's last bits.
            Eigen::Vector3d at;
            const bool fixed = (below - x).norm() <= 1e-14 * layer.diagonal() && restParameters(layer, below, at) && displacementAt(layer, at).isZero(0.0);
            if (!fixed) x = below;
        }
        return true;
    };
    const int n = static_cast<int>(mesh_.positions.rows());
#pragma omp parallel for schedule(static) if (n > 4096)
    for (int v = 0; v < n; ++v) {
        const Eigen::Vector3d y = mesh_.positions.row(v).transpose();
        if (!((y.array() >= lo.array()).all() && (y.array() <= hi.array()).all())) continue;
        Eigen::Vector3d x = y, rest = y;
        const bool inverted = invert(y, x);
        const bool wasOutside = std::binary_search(steps[last].bakedOutside.begin(), steps[last].bakedOutside.end(), v);
        if (!inverted || x == y || !cagePreimage(stack_.lattice_, stack_.carriesCollar(), x, wasOutside, rest)) continue;
        if (trackJacobian_) {
            const double baked = cageJacobianAt(stack_.lattice_, mesh_.rest.row(v).transpose());
            const double unbaked = cageJacobianAt(stack_.lattice_, rest) * layersJacobian(stack_.layers_, x);
            frozenJacobian_[static_cast<size_t>(v)] *= baked / unbaked;
        }
        mesh_.rest.row(v) = rest.transpose();
        stack_.cageOut_.row(v) = x.transpose();
    }
    stack_.embedCage(mesh_.rest);
    ++mesh_.restVersion;
}

}  // namespace sculpt::core
