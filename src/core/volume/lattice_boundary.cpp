// The deformed lattice boundary as a closed triangle surface, and its self-intersections (global
// injectivity with a free boundary; see lattice_boundary.h).
#include "core/volume/lattice_boundary.h"

#include <array>

namespace sculpt::core {

void latticeBoundarySurface(const Lattice& lattice, int samplesPerSpan, Positions& positions, Triangles& triangles) {
    std::array<int, 3> n;  // sample nodes per axis
    for (int a = 0; a < 3; ++a) n[a] = lattice.axes[a].spans * samplesPerSpan + 1;
    // Ids of the grid nodes on the box's boundary; interior nodes get none.
    std::vector<int> id(static_cast<size_t>(n[0]) * n[1] * n[2], -1);
    const auto node = [&](int i, int j, int k) -> int& { return id[static_cast<size_t>(i) + static_cast<size_t>(n[0]) * (j + static_cast<size_t>(n[1]) * k)]; };
    std::vector<Eigen::Vector3d> points;
    const LatticeNet* net = lattice.tensorNet();
    assert(net || !lattice.volume);  // tensor kinds only (header)
    // A net lattice's sample nodes that are one point of the volume share one id: the periodic seam's last
    // slice is its first, and on a collapsed face (a cylinder's axis, a pole) the collapsed direction has one
    // node. Its surface is only its boundary faces (not the seam, not the collapsed ones).
    const auto canonical = [&](std::array<int, 3> g) {
        if (!net) return g;
        for (int pass = 0; pass < 2; ++pass)
            for (int a = 0; a < 3; ++a) {
                if (net->periodic[a] && g[a] == n[a] - 1) g[a] = 0;
                for (int side = 0; side < 2; ++side)
                    if (g[a] == (side ? n[a] - 1 : 0))
                        for (int b = 0; b < 3; ++b)
                            if (net->collapsedAlong[a][side] & (1 << b)) g[b] = 0;
            }
        return g;
    };
    for (int k = 0; k < n[2]; ++k)
        for (int j = 0; j < n[1]; ++j)
            for (int i = 0; i < n[0]; ++i) {
                if (i != 0 && j != 0 && k != 0 && i != n[0] - 1 && j != n[1] - 1 && k != n[2] - 1) continue;
                const std::array<int, 3> c = canonical({i, j, k});
                if (c != std::array<int, 3>{i, j, k}) continue;  // its canonical node (visited first: smaller ids) has the id
                const Eigen::Vector3d t(static_cast<double>(i) / (n[0] - 1), static_cast<double>(j) / (n[1] - 1),
                                        static_cast<double>(k) / (n[2] - 1));
                node(i, j, k) = static_cast<int>(points.size());
                if (net) {
                    Eigen::Vector3d rest;
                    evaluateNetVolume(*net, net->rest, t, rest);
                    points.push_back(rest + displacementAt(lattice, t));
                } else {
                    points.push_back(restPoint(lattice, t) + displacementAt(lattice, t));
                }
            }
    for (int k = 0; k < n[2]; ++k)
        for (int j = 0; j < n[1]; ++j)
            for (int i = 0; i < n[0]; ++i)
                if (node(i, j, k) < 0) {
                    const std::array<int, 3> c = canonical({i, j, k});
                    if (c != std::array<int, 3>{i, j, k}) node(i, j, k) = node(c[0], c[1], c[2]);
                }
    positions.resize(static_cast<Eigen::Index>(points.size()), 3);
    for (size_t v = 0; v < points.size(); ++v) positions.row(static_cast<Eigen::Index>(v)) = points[v].transpose();

    std::vector<std::array<int, 3>> tris;
    // One face of the box: axis `a` fixed at `side` (0 or n-1), the other two axes (b, c) running.
    for (int a = 0; a < 3; ++a) {
        const int b = (a + 1) % 3, c = (a + 2) % 3;
        for (int side = 0; side < 2; ++side) {
            if (net && !net->boundaryFace[a][side]) continue;
            for (int u = 0; u + 1 < n[b]; ++u)
                for (int w = 0; w + 1 < n[c]; ++w) {
                    const auto at = [&](int uu, int ww) {
                        std::array<int, 3> g;
                        g[a] = side ? n[a] - 1 : 0;
                        g[b] = uu;
                        g[c] = ww;
                        return node(g[0], g[1], g[2]);
                    };
                    const int p00 = at(u, w), p10 = at(u + 1, w), p11 = at(u + 1, w + 1), p01 = at(u, w + 1);
                    // (b, c, a) is right-handed: counter-clockwise in (b, c) faces +a; the low side faces -a.
                    const auto add = [&](int x, int y, int z) {
                        if (x != y && y != z && x != z) tris.push_back({x, y, z});  // collapsed corners drop
                    };
                    if (side) {
                        add(p00, p10, p11);
                        add(p00, p11, p01);
                    } else {
                        add(p00, p11, p10);
                        add(p00, p01, p11);
                    }
                }
        }
    }
    triangles.resize(static_cast<Eigen::Index>(tris.size()), 3);
    for (size_t t = 0; t < tris.size(); ++t)
        for (int k = 0; k < 3; ++k) triangles(static_cast<Eigen::Index>(t), k) = tris[t][k];
}

std::vector<TrianglePairHit> boundarySelfIntersections(const Lattice& lattice, int samplesPerSpan) {
    Positions positions;
    Triangles triangles;
    latticeBoundarySurface(lattice, samplesPerSpan, positions, triangles);
    return findSelfIntersections(positions, triangles);
}

}  // namespace sculpt::core
