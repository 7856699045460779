// Composite lattices (Coquillart 1990, 3.1.2, 3.1.4): elementary lattices welded into one control volume.
#include "core/volume/composite_volume.h"

#include <Eigen/Geometry>

#include "core/volume/volume_kinds.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace sculpt::core {

namespace {

int findRoot(std::vector<int>& parent, int i) {
    while (parent[static_cast<size_t>(i)] != i) {
        parent[static_cast<size_t>(i)] = parent[static_cast<size_t>(parent[static_cast<size_t>(i)])];
        i = parent[static_cast<size_t>(i)];
    }
    return i;
}

void unite(std::vector<int>& parent, int a, int b) {
    a = findRoot(parent, a), b = findRoot(parent, b);
    if (a != b) parent[static_cast<size_t>(std::max(a, b))] = std::min(a, b);  // the smallest id is the root
}

}  // namespace

Status CompositeVolume::make(std::vector<std::shared_ptr<const LatticeNet>> blocks, std::shared_ptr<const CompositeVolume>& out,
                             double tolerance) {
    if (blocks.size() < 2) return Status::error("a composite lattice needs at least two lattices to weld");
    for (size_t b = 0; b < blocks.size(); ++b)
        if (!blocks[b]) return Status::error("composite part " + std::to_string(b) + " has no lattice");
    auto volume = std::make_shared<CompositeVolume>();
    CompositeVolume& v = *volume;
    v.blocks_ = std::move(blocks);
    v.offsets_.assign(1, 0);
    v.chunkOffsets_.assign(1, 0);
    for (const auto& block : v.blocks_) {
        v.offsets_.push_back(v.offsets_.back() + block->slotCount());
        v.chunkOffsets_.push_back(v.chunkOffsets_.back() + block->LatticeNet::chunkCount());
    }
    const int n = v.offsets_.back();
    v.rest_.resize(n, 3);
    v.weights_.resize(static_cast<size_t>(n));
    v.bounds_.setEmpty();
    std::vector<int> blockOfId(static_cast<size_t>(n));
    for (size_t b = 0; b < v.blocks_.size(); ++b) {
        const LatticeNet& block = *v.blocks_[b];
        v.rest_.middleRows(v.offsets_[b], block.slotCount()) = block.rest;
        std::copy(block.weights.begin(), block.weights.end(), v.weights_.begin() + v.offsets_[b]);
        v.bounds_.extend(block.bounds);
        std::fill(blockOfId.begin() + v.offsets_[b], blockOfId.begin() + v.offsets_[b + 1], static_cast<int>(b));
    }
    v.rational_ = std::any_of(v.weights_.begin(), v.weights_.end(), [&](double w) { return w != v.weights_[0]; });
    // The blocks' own welds, then the points of different blocks that coincide (a sweep along x).
    std::vector<int> parent(static_cast<size_t>(n));
    std::iota(parent.begin(), parent.end(), 0);
    for (size_t b = 0; b < v.blocks_.size(); ++b)
        for (const auto& group : v.blocks_[b]->weldGroups)
            for (int s : group) unite(parent, v.offsets_[b] + group[0], v.offsets_[b] + s);
    const double reach = tolerance * v.bounds_.diagonal().norm();
    std::vector<int> byX(static_cast<size_t>(n));
    std::iota(byX.begin(), byX.end(), 0);
    std::sort(byX.begin(), byX.end(), [&](int a, int b) { return v.rest_(a, 0) < v.rest_(b, 0); });
    for (size_t i = 0; i < byX.size(); ++i)
        for (size_t j = i + 1; j < byX.size() && v.rest_(byX[j], 0) - v.rest_(byX[i], 0) <= reach; ++j) {
            const int a = byX[i], b = byX[j];
            if (blockOfId[static_cast<size_t>(a)] != blockOfId[static_cast<size_t>(b)] && (v.rest_.row(a) - v.rest_.row(b)).norm() <= reach)
                unite(parent, a, b);
        }
    v.weldedTo_.resize(static_cast<size_t>(n));
    std::vector<std::vector<int>> members(static_cast<size_t>(n));
    for (int id = 0; id < n; ++id) {
        v.weldedTo_[static_cast<size_t>(id)] = findRoot(parent, id);
        members[static_cast<size_t>(v.weldedTo_[static_cast<size_t>(id)])].push_back(id);
    }
    std::vector<std::uint8_t> crossWelded(static_cast<size_t>(n), 0);  // welded to a point of another part
    for (auto& group : members) {
        if (group.size() < 2) continue;
        const bool cross = std::any_of(group.begin(), group.end(), [&](int id) { return blockOfId[static_cast<size_t>(id)] != blockOfId[static_cast<size_t>(group[0])]; });
        if (cross) {
            ++v.crossWelds_;
            for (int id : group) crossWelded[static_cast<size_t>(id)] = 1;
        }
        v.groups_.push_back(std::move(group));
    }
    // Joints: outer faces of a part whose every point is welded to another part.
    v.jointFace_.resize(v.blocks_.size());
    for (size_t b = 0; b < v.blocks_.size(); ++b) {
        const LatticeNet& block = *v.blocks_[b];
        for (int a = 0; a < 3; ++a)
            for (int side = 0; side < 2; ++side) {
                bool joint = block.boundaryFace[a][side];
                for (int s = 0; s < block.slotCount() && joint; ++s) {
                    if (block.slotIjk(s)[a] == (side == 0 ? 0 : block.count[a] - 1)) joint = crossWelded[static_cast<size_t>(v.offsets_[b] + s)] != 0;
                }
                v.jointFace_[b][a][side] = joint;
            }
    }
    if (v.crossWelds_ == 0) return Status::error("the composite's lattices share no point, so nothing welds them: place them so they touch");
    out = std::move(volume);
    return Status::success();
}

int CompositeVolume::blockOfId(int id) const {
    return static_cast<int>(std::upper_bound(offsets_.begin(), offsets_.end(), id) - offsets_.begin()) - 1;
}

int CompositeVolume::blockOfChunk(int chunk) const {
    return static_cast<int>(std::upper_bound(chunkOffsets_.begin(), chunkOffsets_.end(), chunk) - chunkOffsets_.begin()) - 1;
}

int CompositeVolume::blockOf(const Eigen::Vector3d& t, Eigen::Vector3d& blockT) const {
    if (!(t.x() >= 0.0) || !t.allFinite()) return -1;
    const int b = std::min(static_cast<int>(t.x() / 2.0), static_cast<int>(blocks_.size()) - 1);
    const double u = t.x() - 2.0 * b;
    if (u > 1.0) return -1;  // between two blocks' domains
    blockT = Eigen::Vector3d(u, t.y(), t.z());
    return b;
}

bool CompositeVolume::nearOpenFace(int id, int layers) const {
    const std::vector<int>* group = weldGroupOf(*this, id);
    const std::vector<int> single{id};
    for (int member : group ? *group : single) {
        const int b = blockOfId(member);
        const LatticeNet& block = *blocks_[static_cast<size_t>(b)];
        const int s = member - offset(b);
        const std::array<int, 3> c = block.slotIjk(s);
        for (int a = 0; a < 3; ++a)
            for (int side = 0; side < 2; ++side) {
                if (!block.boundaryFace[a][side] || jointFace_[static_cast<size_t>(b)][a][side]) continue;
                if (side == 0 ? c[a] < layers : c[a] >= block.count[a] - layers) return true;
            }
    }
    return false;
}

bool CompositeVolume::onOuterSurface(int id) const { return nearOpenFace(id, 1); }

bool CompositeVolume::inSurfaceLayers(int id, int layers) const { return layers > 0 && nearOpenFace(id, layers); }

std::vector<std::array<int, 2>> CompositeVolume::controlNetEdgeList() const {
    std::vector<std::array<int, 2>> edges;
    for (size_t b = 0; b < blocks_.size(); ++b)
        for (const auto& e : blocks_[b]->controlNetEdgeList()) edges.push_back({e[0] + offsets_[b], e[1] + offsets_[b]});
    return edges;
}

void CompositeVolume::basisAt(const Eigen::Vector3d& t, SupportWeights& out) const {
    Eigen::Vector3d blockT;
    const int b = blockOf(t, blockT);
    if (b < 0) {
        out.count = 0;
        return;
    }
    blocks_[static_cast<size_t>(b)]->basisAt(blockT, out);
    for (int c = 0; c < out.count; ++c) out.index[c] += offsets_[static_cast<size_t>(b)];
}

void CompositeVolume::evaluate(const Positions& points, const Eigen::Vector3d& t, Eigen::Vector3d& value, Eigen::Matrix3d* derivative) const {
    Eigen::Vector3d blockT;
    int b = blockOf(t, blockT);
    if (b < 0) {  // outside every domain: the nearest block's clamped evaluation (never NaN)
        b = 0;
        blockT = t.cwiseMax(0.0).cwiseMin(1.0);
    }
    // note: d/dt_u of the composite's parameter is d/du of the block's (t_u = 2 b + u).
    evaluateNetVolume(*blocks_[static_cast<size_t>(b)], points.data() + 3 * static_cast<size_t>(offsets_[static_cast<size_t>(b)]), blockT, value,
                      derivative);
}

bool CompositeVolume::freeze(const Eigen::Vector3d& x, Eigen::Vector3d& t) const {
    for (size_t b = 0; b < blocks_.size(); ++b) {  // the first block that holds x: deterministic
        Eigen::Vector3d blockT;
        if (blocks_[b]->freeze(x, blockT)) {
            t = Eigen::Vector3d(blockT.x() + 2.0 * static_cast<double>(b), blockT.y(), blockT.z());
            return true;
        }
    }
    return false;
}

namespace {

class CompositeLocator final : public Volume::Locator {
public:
    CompositeLocator(const CompositeVolume& volume, const Positions& points) {
        for (size_t b = 0; b < volume.blocks().size(); ++b) {
            const LatticeNet& block = *volume.blocks()[b];
            const Positions rows = points.middleRows(volume.offset(static_cast<int>(b)), block.slotCount());
            locators_.push_back(block.locatorFor(rows));
        }
    }
    bool freeze(const Eigen::Vector3d& x, Eigen::Vector3d& t) const override {
        for (size_t b = 0; b < locators_.size(); ++b) {
            Eigen::Vector3d blockT;
            if (locators_[b]->freeze(x, blockT)) {
                t = Eigen::Vector3d(blockT.x() + 2.0 * static_cast<double>(b), blockT.y(), blockT.z());
                return true;
            }
        }
        return false;
    }

private:
    std::vector<std::unique_ptr<Volume::Locator>> locators_;
};

}  // namespace

std::unique_ptr<Volume::Locator> CompositeVolume::locatorFor(const Positions& points) const {
    return std::make_unique<CompositeLocator>(*this, points);
}

int CompositeVolume::chunkOf(const Eigen::Vector3d& t, Eigen::Vector3d& local) const {
    Eigen::Vector3d blockT;
    const int b = blockOf(t, blockT);
    if (b < 0) return -1;
    const int c = blocks_[static_cast<size_t>(b)]->chunkOf(blockT, local);
    return c < 0 ? -1 : chunkOffsets_[static_cast<size_t>(b)] + c;
}

Eigen::Vector3d CompositeVolume::chunkParameters(int chunk, const Eigen::Vector3d& local) const {
    const int b = blockOfChunk(chunk);
    Eigen::Vector3d t = blocks_[static_cast<size_t>(b)]->chunkParameters(chunk - chunkOffsets_[static_cast<size_t>(b)], local);
    t.x() += 2.0 * b;
    return t;
}

void CompositeVolume::chunkSupport(int chunk, std::vector<int>& ids) const {
    const int b = blockOfChunk(chunk);
    blocks_[static_cast<size_t>(b)]->chunkSupport(chunk - chunkOffsets_[static_cast<size_t>(b)], ids);
    for (int& id : ids) id += offsets_[static_cast<size_t>(b)];
}

void CompositeVolume::bezierChunk(int chunk, const Positions* displacement, BezierChunk& out) const {
    const int b = blockOfChunk(chunk);
    blocks_[static_cast<size_t>(b)]->bezierChunkWith(chunk - chunkOffsets_[static_cast<size_t>(b)],
                                                     displacement ? displacement->data() + 3 * static_cast<size_t>(offsets_[static_cast<size_t>(b)]) : nullptr,
                                                     out);
}

void CompositeVolume::chunksAlong(int chunk, int axis, std::vector<int>& row, bool& closed) const {
    const int b = blockOfChunk(chunk);
    blocks_[static_cast<size_t>(b)]->chunksAlong(chunk - chunkOffsets_[static_cast<size_t>(b)], axis, row, closed);
    for (int& c : row) c += chunkOffsets_[static_cast<size_t>(b)];
}

std::vector<std::array<Eigen::Vector3d, 2>> CompositeVolume::chunkEdgeLines() const {
    std::vector<std::array<Eigen::Vector3d, 2>> lines;
    for (size_t b = 0; b < blocks_.size(); ++b)
        for (auto line : blocks_[b]->chunkEdgeLines()) {
            line[0].x() += 2.0 * static_cast<double>(b);
            line[1].x() += 2.0 * static_cast<double>(b);
            lines.push_back(line);
        }
    return lines;
}

Status CompositeVolume::placed(const Eigen::Vector3d& point, const Eigen::Vector3d& normal, double size,
                               std::shared_ptr<const Volume>& out) const {
    // Each part by the composite's similarity: the part's own placement (its centre to the image of its
    // centre, its diagonal scaled alike) is exactly that similarity restricted to it.
    PlacementSimilarity similarity;
    if (Status s = placementSimilarity(restBounds(), point, normal, size, similarity); !s) return s;
    std::vector<std::shared_ptr<const LatticeNet>> parts;
    for (const auto& block : blocks()) {
        LatticeNet part;
        if (Status s = placeLatticeNet(*block, similarity(block->bounds.center()), normal, similarity.scale * block->diagonal(), part); !s) return s;
        parts.push_back(std::make_shared<const LatticeNet>(std::move(part)));
    }
    std::shared_ptr<const CompositeVolume> moved;
    if (Status s = CompositeVolume::make(std::move(parts), moved); !s) return s;
    out = std::move(moved);
    return Status::success();
}

}  // namespace sculpt::core
