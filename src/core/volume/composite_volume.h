// Composite lattices (Coquillart 1990, 3.1.2 and 3.1.4): several elementary lattices welded together into one
// control volume, e.g. the "8" of Fig. 9 (two discs merged at the centre of the figure, Fig. 4). A Volume kind
// (volume.h) that is not one tensor product: the engine reaches it only through the interface.
//
// Control point ids are the blocks' slots one after another (block b's slot s is offset(b) + s). The welding
// operation merges the points of the blocks that coincide (3.1.4: "realised by merging the points of each
// lattice"), on top of each block's own welds: a welded group acts as one control point whose basis function
// is the sum of its members'. Blocks should meet only on their faces; where their volumes overlap, a point
// belongs to the first block that holds it.
//
// Parameters: block b's parameter t in [0,1]^3 is (2 b + t_u, t_v, t_w), so each block keeps its own domain
// and chunk ids follow the blocks' (block b's chunk c is chunkOffset(b) + c).
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "core/volume/lattice_net.h"
#include "core/status.h"
#include "core/volume/volume.h"

namespace sculpt::core {

class CompositeVolume final : public Volume {
public:
    // The composite of `blocks` (each finished, at least two), welding every pair of points of different blocks
    // that coincide to `tolerance` x the composite's diagonal. Fails if fewer than two blocks are given, a
    // block is null, or no two blocks share a point (they would not be welded: use separate lattices).
    static Status make(std::vector<std::shared_ptr<const LatticeNet>> blocks, std::shared_ptr<const CompositeVolume>& out,
                       double tolerance = 1e-12);

    const std::vector<std::shared_ptr<const LatticeNet>>& blocks() const { return blocks_; }
    int offset(int block) const { return offsets_[static_cast<size_t>(block)]; }
    int chunkOffset(int block) const { return chunkOffsets_[static_cast<size_t>(block)]; }
    // The block holding parameter t (-1 outside every block's domain) and t in that block's own [0,1]^3.
    int blockOf(const Eigen::Vector3d& t, Eigen::Vector3d& blockT) const;
    // Points welded across blocks (the seams where the elementary lattices meet).
    int crossWeldCount() const { return crossWelds_; }

    // ---- Volume ----
    const std::string& kindName() const override { return kind_; }
    // Each part by the composite's similarity (placeLatticeNet per part).
    Status placed(const Eigen::Vector3d& point, const Eigen::Vector3d& normal, double size, std::shared_ptr<const Volume>& out) const override;
    const CompositeVolume* compositeVolume() const override { return this; }
    int controlPointCount() const override { return static_cast<int>(rest_.rows()); }
    const Positions& restControlPoints() const override { return rest_; }
    const std::vector<double>& controlWeights() const override { return weights_; }
    bool isRational() const override { return rational_; }
    int representativeOf(int id) const override { return weldedTo_[static_cast<size_t>(id)]; }
    const std::vector<std::vector<int>>& weldGroupList() const override { return groups_; }
    Eigen::AlignedBox3d restBounds() const override { return bounds_; }
    // On the composite's outer surface: some copy lies on an outer face of its part that is not a joint (a face
    // whose every point is welded to another part lies inside the composite: two boxes sharing a face). The
    // point where two discs touch stays on the surface.
    bool onOuterSurface(int id) const override;
    bool inSurfaceLayers(int id, int layers) const override;
    std::vector<std::array<int, 2>> controlNetEdgeList() const override;
    void basisAt(const Eigen::Vector3d& t, SupportWeights& out) const override;
    void evaluate(const Positions& points, const Eigen::Vector3d& t, Eigen::Vector3d& value,
                  Eigen::Matrix3d* derivative = nullptr) const override;
    bool freeze(const Eigen::Vector3d& x, Eigen::Vector3d& t) const override;
    std::unique_ptr<Locator> locatorFor(const Positions& points) const override;
    int chunkCount() const override { return chunkOffsets_.back(); }
    int chunkOf(const Eigen::Vector3d& t, Eigen::Vector3d& local) const override;
    Eigen::Vector3d chunkParameters(int chunk, const Eigen::Vector3d& local) const override;
    void chunkSupport(int chunk, std::vector<int>& ids) const override;
    void bezierChunk(int chunk, const Positions* displacement, BezierChunk& out) const override;
    void chunksAlong(int chunk, int axis, std::vector<int>& row, bool& closed) const override;
    std::vector<std::array<Eigen::Vector3d, 2>> chunkEdgeLines() const override;

private:
    int blockOfChunk(int chunk) const;
    int blockOfId(int id) const;
    // Some copy of `id` lies within `layers` layers of an outer face of its part that is not a joint.
    bool nearOpenFace(int id, int layers) const;

    std::string kind_ = "composite";
    std::vector<std::shared_ptr<const LatticeNet>> blocks_;
    std::vector<int> offsets_, chunkOffsets_;  // blocks + 1 entries
    Positions rest_;
    std::vector<double> weights_;
    bool rational_ = false;
    std::vector<int> weldedTo_;
    std::vector<std::vector<int>> groups_;
    std::vector<std::array<std::array<bool, 2>, 3>> jointFace_;  // per part: the face is wholly welded to other parts
    int crossWelds_ = 0;
    Eigen::AlignedBox3d bounds_;
};

}  // namespace sculpt::core
