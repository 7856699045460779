// A net lattice as a Volume (volume.h; Coquillart 1990, EFFD 3.1-3.3): its basis and evaluation, the locator
// that freezes points, its chunks and their Bezier form (for the injectivity test), and its placement.
#include "core/volume/lattice_net.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "core/spline/bernstein.h"
#include "core/volume/lattice_net_internal.h"
#include "core/volume/volume_kinds.h"

namespace sculpt::core {

using lattice_net_detail::NetBases;
using lattice_net_detail::netBases;

// ---- LatticeNet as a Volume ----------------------------------------------------------------------------------

bool LatticeNet::inSurfaceLayers(int id, int layers) const {
    const std::array<int, 3> c = slotIjk(id);
    for (int a = 0; a < 3; ++a)
        if ((boundaryFace[a][0] && c[a] < layers) || (boundaryFace[a][1] && c[a] >= count[a] - layers)) return true;
    return false;
}

std::vector<std::array<int, 2>> LatticeNet::controlNetEdgeList() const {
    std::vector<std::array<int, 2>> edges;
    for (int k = 0; k < count[2]; ++k)
        for (int j = 0; j < count[1]; ++j)
            for (int i = 0; i < count[0]; ++i) {
                const int s = slot(i, j, k);
                if (i + 1 < count[0]) edges.push_back({s, slot(i + 1, j, k)});
                if (j + 1 < count[1]) edges.push_back({s, slot(i, j + 1, k)});
                if (k + 1 < count[2]) edges.push_back({s, slot(i, j, k + 1)});
            }
    return edges;
}

void LatticeNet::basisAt(const Eigen::Vector3d& t, SupportWeights& out) const {
    NetBases b;
    netBases(*this, t, false, b);
    out.count = 0;
    double sum = 0.0;
    for (int k = 0; k <= degree[2]; ++k)
        for (int j = 0; j <= degree[1]; ++j)
            for (int i = 0; i <= degree[0]; ++i) {
                const int s = slot(b.first[0] + i, b.first[1] + j, b.first[2] + k);
                const double w = weights[static_cast<size_t>(s)] * b.value[0][i] * b.value[1][j] * b.value[2][k];
                out.index[out.count] = s;
                out.weight[out.count] = w;
                sum += w;
                ++out.count;
            }
    // Hu et al. 2001, eq. 2's denominator; skipped for a polynomial net so it stays the exact B-spline.
    if (rational)
        for (int c = 0; c < out.count; ++c) out.weight[c] /= sum;
}

void LatticeNet::evaluate(const Positions& points, const Eigen::Vector3d& t, Eigen::Vector3d& value, Eigen::Matrix3d* derivative) const {
    evaluateNetVolume(*this, points, t, value, derivative);
}

bool LatticeNet::freeze(const Eigen::Vector3d& x, Eigen::Vector3d& t) const { return freezePoint(*this, rest, restIndex, x, t); }

namespace {

class NetLocator final : public Volume::Locator {
public:
    NetLocator(const LatticeNet& net, const Positions& points) : net_(net), points_(points), index_(buildChunkIndex(net, points)) {}
    bool freeze(const Eigen::Vector3d& x, Eigen::Vector3d& t) const override { return freezePoint(net_, points_, index_, x, t); }

private:
    const LatticeNet& net_;
    Positions points_;
    ChunkIndex index_;
};

}  // namespace

std::unique_ptr<Volume::Locator> LatticeNet::locatorFor(const Positions& points) const {
    return std::make_unique<NetLocator>(*this, points);
}

int LatticeNet::chunkOf(const Eigen::Vector3d& t, Eigen::Vector3d& local) const {
    if (!(t.array() >= 0.0).all() || !(t.array() <= 1.0).all()) return -1;  // also NaN
    std::array<int, 3> c{};
    for (int a = 0; a < 3; ++a) c[a] = axes[a].locate(t[a], local[a]);
    return c[0] + axes[0].spans * (c[1] + axes[1].spans * c[2]);
}

Eigen::Vector3d LatticeNet::chunkParameters(int chunk, const Eigen::Vector3d& local) const {
    const std::array<int, 3> c = chunkIjk(chunk);
    Eigen::Vector3d t;
    for (int a = 0; a < 3; ++a) t[a] = std::min(1.0, (c[a] + local[a]) / axes[a].spans);
    return t;
}

void LatticeNet::chunkSupport(int chunk, std::vector<int>& ids) const {
    const std::array<int, 3> c = chunkIjk(chunk);
    ids.clear();
    for (int k = 0; k <= degree[2]; ++k)
        for (int j = 0; j <= degree[1]; ++j)
            for (int i = 0; i <= degree[0]; ++i)
                ids.push_back(slot(axes[0].first(c[0]) + i, axes[1].first(c[1]) + j, axes[2].first(c[2]) + k));
    std::sort(ids.begin(), ids.end());
}

void LatticeNet::bezierChunk(int chunk, const Positions* displacement, BezierChunk& out) const {
    bezierChunkWith(chunk, displacement ? displacement->data() : nullptr, out);
}

void LatticeNet::bezierChunkWith(int chunk, const double* displacement, BezierChunk& out) const {
    const std::array<int, 3> c = chunkIjk(chunk);
    const int n0 = degree[0] + 1, n1 = degree[1] + 1, n2 = degree[2] + 1;
    const int n = n0 * n1 * n2;
    out.degree = degree;
    if (out.points.size() < 4 * static_cast<size_t>(n)) out.points.resize(4 * static_cast<size_t>(n));
    double* control = out.points.data();
    const double firstWeight = weights[static_cast<size_t>(slot(axes[0].first(c[0]), axes[1].first(c[1]), axes[2].first(c[2])))];
    bool polynomial = true;
    for (int k = 0; k < n2; ++k)
        for (int j = 0; j < n1; ++j)
            for (int i = 0; i < n0; ++i) {
                const int s = slot(axes[0].first(c[0]) + i, axes[1].first(c[1]) + j, axes[2].first(c[2]) + k);
                const int e = i + n0 * (j + n1 * k);
                const double w = weights[static_cast<size_t>(s)];
                for (int comp = 0; comp < 3; ++comp) control[comp * n + e] = rest(s, comp) + (displacement ? displacement[3 * static_cast<size_t>(s) + comp] : 0.0);
                control[3 * n + e] = w;
                polynomial = polynomial && w == firstWeight;
            }
    out.polynomial = polynomial;
    const int components = polynomial ? 3 : 4;
    if (polynomial) {
        std::fill(control + 3 * n, control + 4 * n, 1.0);
    } else {
        for (int e = 0; e < n; ++e)
            for (int comp = 0; comp < 3; ++comp) control[comp * n + e] *= control[3 * n + e];
    }
    // Separable B-spline -> Bezier conversion along u, v, w (each span's own matrix).
    thread_local std::vector<double> temp;
    temp.resize(4 * static_cast<size_t>(n));
    const double* mu = toBezier[0].data() + static_cast<size_t>(c[0]) * n0 * n0;
    const double* mv = toBezier[1].data() + static_cast<size_t>(c[1]) * n1 * n1;
    const double* mw = toBezier[2].data() + static_cast<size_t>(c[2]) * n2 * n2;
    for (int line = 0; line < components * n1 * n2; ++line) {  // u: control -> temp
        const double* in = control + n0 * line;
        double* o = temp.data() + n0 * line;
        for (int l = 0; l < n0; ++l) {
            double sum = 0.0;
            for (int i = 0; i < n0; ++i) sum += mu[l * n0 + i] * in[i];
            o[l] = sum;
        }
    }
    for (int comp = 0; comp < components; ++comp)  // v: temp -> control
        for (int k = 0; k < n2; ++k)
            for (int m = 0; m < n1; ++m)
                for (int l = 0; l < n0; ++l) {
                    double sum = 0.0;
                    for (int j = 0; j < n1; ++j) sum += mv[m * n1 + j] * temp[comp * n + l + n0 * (j + n1 * k)];
                    control[comp * n + l + n0 * (m + n1 * k)] = sum;
                }
    const int plane = n0 * n1;
    for (int comp = 0; comp < components; ++comp)  // w: control -> temp -> control
        for (int o = 0; o < n2; ++o)
            for (int e = 0; e < plane; ++e) {
                double sum = 0.0;
                for (int k = 0; k < n2; ++k) sum += mw[o * n2 + k] * control[comp * n + e + plane * k];
                temp[comp * n + e + plane * o] = sum;
            }
    std::copy(temp.begin(), temp.begin() + components * n, control);
    for (int a = 0; a < 3; ++a) {
        out.parameterScale[a] = 1.0 / axes[a].spans;
        for (int side = 0; side < 2; ++side) {
            const bool onFace = c[a] == (side == 0 ? 0 : axes[a].spans - 1);
            out.collapse[a][side] = onFace && !periodic[a] && !boundaryFace[a][side] ? collapsedAlong[a][side] : 0;
        }
    }
}

void LatticeNet::chunksAlong(int chunk, int axis, std::vector<int>& row, bool& closed) const {
    std::array<int, 3> c = chunkIjk(chunk);
    row.clear();
    for (int s = 0; s < axes[axis].spans; ++s) {
        c[axis] = s;
        row.push_back(c[0] + axes[0].spans * (c[1] + axes[1].spans * c[2]));
    }
    closed = periodic[axis];
}

std::vector<std::array<Eigen::Vector3d, 2>> LatticeNet::chunkEdgeLines() const {
    std::vector<std::array<Eigen::Vector3d, 2>> lines;
    const std::array<int, 3> sp = spans();
    for (int a = 0; a < 3; ++a) {
        const int b = (a + 1) % 3, c = (a + 2) % 3;
        for (int kc = 0; kc <= sp[c] - (periodic[c] ? 1 : 0); ++kc)
            for (int kb = 0; kb <= sp[b] - (periodic[b] ? 1 : 0); ++kb) {
                Eigen::Vector3d from, to;
                from[a] = 0.0, to[a] = 1.0;
                from[b] = to[b] = static_cast<double>(kb) / sp[b];
                from[c] = to[c] = static_cast<double>(kc) / sp[c];
                lines.push_back({from, to});
            }
    }
    return lines;
}

Status LatticeNet::placed(const Eigen::Vector3d& point, const Eigen::Vector3d& normal, double size, std::shared_ptr<const Volume>& out) const {
    LatticeNet moved;
    if (Status s = placeLatticeNet(*this, point, normal, size, moved); !s) return s;
    out = std::make_shared<const LatticeNet>(std::move(moved));
    return Status::success();
}

}  // namespace sculpt::core
