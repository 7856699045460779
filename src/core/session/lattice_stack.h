// LatticeStack: the lattices a session's mesh is deformed by, and the composition through them (session.h, "The
// cage and its layers"). One per Session (Session::cage(), read-only outside the engine).
//  - the cage: the lattice the user set up, with the embedding of the rest mesh in it (design.md: the user's
//    object, never replaced behind their back);
//  - the layers: lattices applied after the cage, in order (an adaptive subdivision's fresh lattices, Gain &
//    Dodgson 2001 section 8; a brush stroke's region lattices): the mesh shown is x = L_k( ... L_1( C(X0) ) );
//  - the frozen frames: earlier cages with their layers, kept compactly so undo can return to them.
// The queries below carry points through that composition: forwards by evaluation (Sederberg & Parry 1986, the
// FFD x = X0 + sum R(t) delta, Hu et al. 2001 eq. 1), backwards per layer by Newton's method (injectivity is what
// makes the inverse exist, Gain & Dodgson 2001). All are const and thread-safe. The session and its concept
// classes (stroke.h, tool_library.h, tspline_tools.h, refiner.h) change the stack as operations apply and undo
// (session_layers.cpp); files: lattice_stack.cpp.
#pragma once

#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "core/mesh_types.h"
#include "core/session/operation.h"
#include "core/status.h"
#include "core/volume/embedding.h"
#include "core/volume/lattice.h"

namespace sculpt::core {

class LatticeStack {
public:
    const Lattice& lattice() const { return lattice_; }         // the cage
    const Embedding& embedding() const { return embedding_; }   // the rest mesh in the cage
    const std::vector<Layer>& layers() const { return layers_; }
    const LatticeSettings& settings() const { return settings_; }  // the cage's
    // The settings and the box of the lattice the session started with (for recordings that replay on other
    // meshes, and for unfreezing).
    const LatticeSettings& initialSettings() const { return initialSettings_; }
    Eigen::Vector3d initialBoxMin() const { return initialBoxMin_; }
    Eigen::Vector3d initialBoxMax() const { return initialBoxMax_; }
    // Lattices composed after the first one: frozen cages and layers.
    int frameDepth() const { return static_cast<int>(frames_.size() + layers_.size()); }

    // The cage's control points as the user sees them: Q_ijk carried through the layers (#P x 3, rows by
    // Lattice::index). Without layers, controlPointPositions(lattice()).
    Positions cagePoints() const;
    // Where the point with cage parameters t currently is: X0(t) + sum R(t) delta, carried through the layers.
    Eigen::Vector3d currentImage(const Eigen::Vector3d& params) const;
    // Cage parameters of a point of the current (deformed) shape, e.g. a picked surface point (traced back
    // through the layers, then the cage, by Newton's method). Fails, naming the point, for one outside the cage
    // or one no point of the layers maps onto.
    Status parametersOfCurrentPoint(const Eigen::Vector3d& point, Eigen::Vector3d& params) const;
    // Where the deformation puts a point of rest space (Session::mesh().rest's space): the cage's FFD
    // (X0 + sum R(t(X0)) delta inside its box; outside, its collar or X0: cageImage), then the layers. A vertex v is at
    // imageOfRestPoint(mesh().rest.row(v)) up to rounding.
    Eigen::Vector3d imageOfRestPoint(const Eigen::Vector3d& rest) const;
    // The cage's part of that: its FFD inside its box, its collar outside (carriesCollar), else the point itself.
    Eigen::Vector3d cageImage(const Eigen::Vector3d& rest) const;
    // x carried through layers [first, end).
    Eigen::Vector3d pushThroughLayers(Eigen::Vector3d x, size_t first = 0) const;
    // The point that layers [0, count) carry onto y (Newton per layer, last first); false if there is none.
    bool pullThroughLayers(const Eigen::Vector3d& y, Eigen::Vector3d& x, size_t count) const;
    // Where the newest `count` layers can move anything (deformationBounds of each, together).
    void newestLayersBounds(size_t count, Eigen::Vector3d& lo, Eigen::Vector3d& hi) const;

    // The cage carries the vertices resting outside its box by its collar (embedding.h, embedCollar) when it is
    // a box lattice that held every vertex when it was set up (setCollarFromSetUp): only a stroke or a bake can
    // then put a vertex outside it, and what is sculpted travels with the cage. A box set up in a region that
    // left vertices out, or a lattice of another kind, leaves what it does not hold where it is.
    bool carriesCollar() const { return collar_; }

private:
    friend class Session;
    friend class Stroke;
    friend class ToolLibrary;
    friend class TSplineTools;
    friend class Refiner;
    friend class CagePins;

    // At set-up, with the rest mesh just embedded (embedVertices): whether the cage carries a collar from now on.
    void setCollarFromSetUp(const Positions& rest) {
        collar_ = !lattice_.volume && !lattice_.boxTurned() && embedding_.insideCount() == static_cast<int>(rest.rows());
    }
    // Embeds the rest mesh in the cage (embedVertices), with the collar where carriesCollar.
    void embedCage(const Positions& rest);

    // The lattice an operation's steps are solved in: the cage, or the newest layer while the operation that
    // made it runs.
    Lattice& activeLattice() { return layerActive_ ? layers_.back().lattice : lattice_; }
    const Lattice& activeLattice() const { return layerActive_ ? layers_.back().lattice : lattice_; }
    const Embedding& activeEmbedding() const { return layerActive_ ? layerEmbedding_ : embedding_; }
    bool cageUnderLayers() const { return !layerActive_ && !layers_.empty(); }
    // The active lattice's image of its rest point with parameters t (before any layer above it).
    Eigen::Vector3d activeImage(const Eigen::Vector3d& params) const;
    // A point of the current shape in the active lattice's output space (traced back through the layers when
    // the cage is active); false where no layer point maps there.
    bool toActiveSpace(const Eigen::Vector3d& point, Eigen::Vector3d& out) const;

    Lattice lattice_;
    Embedding embedding_;
    std::vector<Layer> layers_;
    Positions cageOut_;            // with layers: the cage's image of the rest mesh (the first layer's input)
    bool layerActive_ = false;     // steps are solved in layers_.back() (only during the operation that made it)
    bool collar_ = false;          // carriesCollar
    Embedding layerEmbedding_;     // with layerActive_: that layer's input (the mesh when it was made) embedded
    Positions beforeCage_;         // #V: rows of cageOut_ a step changes, as they were before it
    std::vector<FrozenFrame> frames_;
    LatticeSettings settings_, initialSettings_;
    Eigen::Vector3d initialBoxMin_ = Eigen::Vector3d::Zero(), initialBoxMax_ = Eigen::Vector3d::Zero();
};

}  // namespace sculpt::core
