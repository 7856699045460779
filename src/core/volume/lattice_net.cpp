// Net lattices of any shape (Coquillart 1990, EFFD): predefined shapes (3.1.1, 3.1.3), welding (3.1.2),
// and freezing by Newton's method (3.3). The net as a Volume (evaluation, chunks, Bezier form): lattice_net_volume.cpp.
#include "core/volume/lattice_net.h"

#include "core/spline/bernstein.h"
#include "core/volume/lattice_net_internal.h"
#include "core/volume/volume_kinds.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include <Eigen/LU>
#include <Eigen/SVD>

namespace sculpt::core {

using lattice_net_detail::NetBases;
using lattice_net_detail::netBases;

namespace {

constexpr double kPi = 3.14159265358979323846;

// Rest positions of one axis' control points for `chunks` uniform spans of `degree` (Greville points: the
// volume is then linear in that parameter, sum xi_i B_i(u) = u).
std::vector<double> grevillePoints(int chunks, int degree) {
    return makeSplineAxis(chunks + degree, degree).greville;
}

// A circular arc of `chunks` rational quadratic Bezier pieces from angle `start` through `sweep`: 2 chunks + 1
// control points (x, y) and weights; the arc middles are pushed out by 1 / cos(alpha / 2) and weighted
// cos(alpha / 2) (The NURBS Book, 7.5). Exact: every point of the curve is on the unit circle.
void circularArc(int chunks, double start, double sweep, std::vector<Eigen::Vector2d>& points, std::vector<double>& weights) {
    const double alpha = sweep / chunks;
    points.assign(2 * chunks + 1, Eigen::Vector2d::Zero());
    weights.assign(2 * chunks + 1, 1.0);
    for (int c = 0; c <= chunks; ++c) {
        const double angle = start + c * alpha;
        points[2 * c] = Eigen::Vector2d(std::cos(angle), std::sin(angle));
        if (c < chunks) {
            const double middle = angle + 0.5 * alpha;
            const double w = std::cos(0.5 * alpha);
            points[2 * c + 1] = Eigen::Vector2d(std::cos(middle), std::sin(middle)) / w;
            weights[2 * c + 1] = w;
        }
    }
}

// Two unit vectors completing `axis` (unit) to a right-handed frame (e1, e2, axis).
void completeFrame(const Eigen::Vector3d& axis, Eigen::Vector3d& e1, Eigen::Vector3d& e2) {
    const Eigen::Vector3d helper = std::abs(axis.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
    e1 = (helper - helper.dot(axis) * axis).normalized();
    e2 = axis.cross(e1);
}

bool finitePositive(double v) { return std::isfinite(v) && v > 0.0; }

Status checkChunks(const std::array<int, 3>& chunks, const std::array<int, 3>& degree, const std::array<int, 3>& multiplicity) {
    for (int a = 0; a < 3; ++a) {
        if (degree[a] < kMinDegree || degree[a] > kMaxDegree)
            return Status::error("lattice degree along " + parameterAxisName(a) + " is " + std::to_string(degree[a]) + "; it must be in [1, 5]");
        const int count = chunks[a] < 1 ? 0 : splineAxisCount(chunks[a], degree[a], multiplicity[a]);
        if (chunks[a] < 1 || count > kMaxControlPointsPerAxis)
            return Status::error("lattice chunks along " + parameterAxisName(a) + " is " + std::to_string(chunks[a]) +
                                 "; it must be at least 1 with at most 64 control points per axis");
    }
    return Status::success();
}

// A net of count[0] x count[1] x count[2] slots whose point and weight come from `slot(i, j, k, point, weight)`,
// with coincident slots welded, finished (validated and indexed).
template <class SlotFunction>
Status buildGridNet(const std::string& kind, const std::array<int, 3>& count, const std::array<int, 3>& degree,
                    const std::array<int, 3>& multiplicity, SlotFunction slot, LatticeNet& out) {
    LatticeNet net;
    net.kind = kind;
    net.count = count;
    net.degree = degree;
    net.multiplicity = multiplicity;
    net.rest.resize(net.slotCount(), 3);
    net.weights.resize(net.slotCount());
    for (int k = 0; k < count[2]; ++k)
        for (int j = 0; j < count[1]; ++j)
            for (int i = 0; i < count[0]; ++i) {
                Eigen::Vector3d point;
                double weight = 1.0;
                slot(i, j, k, point, weight);
                net.rest.row(net.slot(i, j, k)) = point.transpose();
                net.weights[net.slot(i, j, k)] = weight;
            }
    weldCoincidentSlots(net);
    if (Status s = finishLatticeNet(net); !s) return s;
    out = std::move(net);
    return Status::success();
}

double restOrientationAt(const LatticeNet& net, const Eigen::Vector3d& t) {
    Eigen::Vector3d q;
    Eigen::Matrix3d d;
    evaluateNetVolume(net, net.rest, t, q, &d);
    return d.determinant();
}

}  // namespace

void ChunkIndex::candidates(const Eigen::Vector3d& x, std::vector<int>& out) const {
    out.clear();
    if (gridStart.empty() || !bounds.contains(x)) return;
    int g[3];
    const Eigen::Vector3d size = bounds.sizes();
    for (int a = 0; a < 3; ++a) {
        const double u = size[a] > 0.0 ? (x[a] - bounds.min()[a]) / size[a] : 0.0;
        g[a] = std::clamp(static_cast<int>(u * gridSize[a]), 0, gridSize[a] - 1);
    }
    const int cell = g[0] + gridSize[0] * (g[1] + gridSize[1] * g[2]);
    for (int s = gridStart[cell]; s < gridStart[cell + 1]; ++s)
        if (chunkBounds[gridChunks[s]].contains(x)) out.push_back(gridChunks[s]);
}

ChunkIndex buildChunkIndex(const LatticeNet& net, const Positions& points) {
    ChunkIndex index;
    const std::array<int, 3> spans = net.spans();
    const int chunks = net.chunkCount();
    index.chunkBounds.resize(chunks);
    index.bounds.setEmpty();
    for (int i = 0; i < points.rows(); ++i) index.bounds.extend(points.row(i).transpose());
    // note: a chunk lies in the convex hull of the (p+1)(q+1)(r+1) control points its basis functions belong
    // to (B-spline convex hull property; weights > 0 keep it for NURBS). Padded for rounding.
    const double pad = 1e-9 * std::max(index.bounds.diagonal().norm(), 1e-300);
    for (int w = 0; w < spans[2]; ++w)
        for (int v = 0; v < spans[1]; ++v)
            for (int u = 0; u < spans[0]; ++u) {
                Eigen::AlignedBox3d box;
                box.setEmpty();
                for (int k = 0; k <= net.degree[2]; ++k)
                    for (int j = 0; j <= net.degree[1]; ++j)
                        for (int i = 0; i <= net.degree[0]; ++i)
                            box.extend(points.row(net.slot(net.axes[0].first(u) + i, net.axes[1].first(v) + j, net.axes[2].first(w) + k))
                                           .transpose());
                box.min().array() -= pad;
                box.max().array() += pad;
                index.chunkBounds[u + spans[0] * (v + spans[1] * w)] = box;
            }
    index.bounds.min().array() -= pad;
    index.bounds.max().array() += pad;
    const int perAxis = std::clamp(static_cast<int>(std::ceil(2.0 * std::cbrt(static_cast<double>(chunks)))), 1, 64);
    index.gridSize = {perAxis, perAxis, perAxis};
    const int cells = perAxis * perAxis * perAxis;
    const Eigen::Vector3d size = index.bounds.sizes();
    std::vector<std::vector<int>> lists(cells);
    for (int c = 0; c < chunks; ++c) {
        int lo[3], hi[3];
        for (int a = 0; a < 3; ++a) {
            const double inv = size[a] > 0.0 ? perAxis / size[a] : 0.0;
            lo[a] = std::clamp(static_cast<int>((index.chunkBounds[c].min()[a] - index.bounds.min()[a]) * inv), 0, perAxis - 1);
            hi[a] = std::clamp(static_cast<int>((index.chunkBounds[c].max()[a] - index.bounds.min()[a]) * inv), 0, perAxis - 1);
        }
        for (int z = lo[2]; z <= hi[2]; ++z)
            for (int y = lo[1]; y <= hi[1]; ++y)
                for (int x = lo[0]; x <= hi[0]; ++x) lists[x + perAxis * (y + perAxis * z)].push_back(c);
    }
    index.gridStart.assign(cells + 1, 0);
    for (int g = 0; g < cells; ++g) index.gridStart[g + 1] = index.gridStart[g] + static_cast<int>(lists[g].size());
    index.gridChunks.reserve(index.gridStart.back());
    for (const auto& list : lists) index.gridChunks.insert(index.gridChunks.end(), list.begin(), list.end());
    return index;
}

void weldCoincidentSlots(LatticeNet& net, double tolerance) {
    const int n = static_cast<int>(net.rest.rows());
    net.weldedTo.resize(n);
    std::iota(net.weldedTo.begin(), net.weldedTo.end(), 0);
    Eigen::AlignedBox3d box;
    box.setEmpty();
    for (int s = 0; s < n; ++s) box.extend(net.rest.row(s).transpose());
    const double limit = tolerance * std::max(box.diagonal().norm(), 1e-300);
    // Sort by x so only near neighbours are compared (O(n log n) for a lattice's few thousand slots).
    std::vector<int> order(n);
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int b) { return net.rest(a, 0) < net.rest(b, 0); });
    for (int a = 0; a < n; ++a)
        for (int b = a + 1; b < n && net.rest(order[b], 0) - net.rest(order[a], 0) <= limit; ++b) {
            const int s = order[a], t = order[b];
            if ((net.rest.row(s) - net.rest.row(t)).norm() > limit) continue;
            // Union by the smaller representative.
            int rs = s, rt = t;
            while (net.weldedTo[rs] != rs) rs = net.weldedTo[rs];
            while (net.weldedTo[rt] != rt) rt = net.weldedTo[rt];
            if (rs != rt) net.weldedTo[std::max(rs, rt)] = std::min(rs, rt);
        }
    for (int s = 0; s < n; ++s) {
        int r = s;
        while (net.weldedTo[r] != r) r = net.weldedTo[r];
        net.weldedTo[s] = r;
    }
}

LatticeNet rawNetFields(const LatticeNet& net) {
    LatticeNet copy;
    copy.kind = net.kind;
    copy.count = net.count;
    copy.degree = net.degree;
    copy.multiplicity = net.multiplicity;
    copy.knots = net.knots;
    copy.rest = net.rest;
    copy.weights = net.weights;
    copy.weldedTo = net.weldedTo;
    return copy;
}

Status finishLatticeNet(LatticeNet& net) {
    if (Status s = checkChunks({1, 1, 1}, net.degree, {1, 1, 1}); !s) return s;
    for (int a = 0; a < 3; ++a) {
        if (!net.knots[a].empty()) {
            if (const std::string problem = splineKnotsProblem(net.knots[a], net.count[a], net.degree[a]); !problem.empty())
                return Status::error("lattice axis " + parameterAxisName(a) + " knots: " + problem);
            // One volume, one form: knots that are the uniform ones of the axis' multiplicity are not stored.
            if (splineAxisCountValid(net.count[a], net.degree[a], net.multiplicity[a]) &&
                makeSplineAxis(net.count[a], net.degree[a], net.multiplicity[a]).knots == net.knots[a])
                net.knots[a].clear();
            continue;
        }
        if (!splineAxisCountValid(net.count[a], net.degree[a], net.multiplicity[a]))
            return Status::error("lattice axis " + parameterAxisName(a) + ": " + std::to_string(net.count[a]) + " control points of degree " +
                                 std::to_string(net.degree[a]) + " with knot multiplicity " + std::to_string(net.multiplicity[a]) +
                                 " do not make whole knot spans (at most 64 per axis)");
    }
    const int n = net.slotCount();
    if (net.rest.rows() != n || net.rest.cols() != 3)
        return Status::error("lattice has " + std::to_string(net.rest.rows()) + " control points; its counts need " + std::to_string(n));
    if (!net.rest.allFinite()) return Status::error("lattice has a non-finite control point");
    if (net.weights.empty()) net.weights.assign(n, 1.0);
    if (static_cast<int>(net.weights.size()) != n) return Status::error("lattice needs one weight per control point");
    for (double w : net.weights)
        if (!finitePositive(w)) return Status::error("lattice weights must be finite and > 0");
    if (net.weldedTo.empty()) {
        net.weldedTo.resize(n);
        std::iota(net.weldedTo.begin(), net.weldedTo.end(), 0);
    }
    if (static_cast<int>(net.weldedTo.size()) != n) return Status::error("lattice welds need one entry per control point");
    for (int s = 0; s < n; ++s)
        if (net.weldedTo[s] < 0 || net.weldedTo[s] >= n || net.weldedTo[net.weldedTo[s]] != net.weldedTo[s] || net.weldedTo[s] > s)
            return Status::error("lattice weld of control point " + std::to_string(s) + " does not name its group's smallest id");
    for (int a = 0; a < 3; ++a) {
        net.axes[a] = net.knots[a].empty() ? makeSplineAxis(net.count[a], net.degree[a], net.multiplicity[a])
                                           : makeSplineAxisFromKnots(net.knots[a], net.degree[a]);
        // Basis function (first(s) + i) on span s: monomial coefficients in the local x -> Bernstein (knot
        // insertion to Bezier form, per span).
        const SplineAxis& axis = net.axes[a];
        const int p = axis.degree, m = p + 1;
        net.toBezier[a].assign(static_cast<size_t>(axis.spans) * m * m, 0.0);
        for (int sp = 0; sp < axis.spans; ++sp)
            for (int i = 0; i < m; ++i) {
                double bernstein[kMaxDegree + 1];
                monomialToBernstein(axis.coefficients.data() + (static_cast<size_t>(sp) * m + i) * m, p, bernstein);
                for (int l = 0; l < m; ++l) net.toBezier[a][(static_cast<size_t>(sp) * m + l) * m + i] = bernstein[l];
            }
    }
    net.rational = std::any_of(net.weights.begin(), net.weights.end(), [&](double w) { return w != net.weights[0]; });
    net.bounds.setEmpty();
    for (int s = 0; s < n; ++s) net.bounds.extend(net.rest.row(s).transpose());
    const double diagonal = net.bounds.diagonal().norm();
    if (!(diagonal > 0.0)) return Status::error("lattice control points all coincide");
    // note: det dQ/dt is of the size of diagonal^3 (and the exact test's polynomials of its fourth power), so
    // beyond 1e75 its arithmetic overflows; below 1e-75 it underflows.
    if (!(diagonal < 1e75) || !(diagonal > 1e-75))
        return Status::error("lattice size " + std::to_string(diagonal) + " (diagonal) is out of range: use sizes between 1e-75 and 1e75");
    // Weld groups; welded slots act as one control point, so they must be one point at rest.
    net.weldGroups.clear();
    {
        std::vector<std::vector<int>> groups(n);
        for (int s = 0; s < n; ++s) groups[net.weldedTo[s]].push_back(s);
        for (auto& g : groups)
            if (g.size() > 1) {
                for (int s : g)
                    if ((net.rest.row(s) - net.rest.row(g[0])).norm() > 1e-9 * diagonal)
                        return Status::error("welded control points " + std::to_string(g[0]) + " and " + std::to_string(s) +
                                             " are not at the same place");
                net.weldGroups.push_back(g);
            }
    }
    net.hasWelds = !net.weldGroups.empty();
    // Seams and collapsed faces.
    for (int a = 0; a < 3; ++a) {
        const int b = (a + 1) % 3, c = (a + 2) % 3;
        auto slotAt = [&](int ia, int ib, int ic) {
            std::array<int, 3> ijk{};
            ijk[a] = ia, ijk[b] = ib, ijk[c] = ic;
            return net.slot(ijk[0], ijk[1], ijk[2]);
        };
        bool seam = true;
        for (int ic = 0; ic < net.count[c] && seam; ++ic)
            for (int ib = 0; ib < net.count[b] && seam; ++ib)
                seam = net.weldedTo[slotAt(0, ib, ic)] == net.weldedTo[slotAt(net.count[a] - 1, ib, ic)];
        net.periodic[a] = seam;
        for (int side = 0; side < 2; ++side) {
            const int ia = side == 0 ? 0 : net.count[a] - 1;
            // Collapsed along b: every line of the face along b is one welded point (along c likewise).
            auto collapsed = [&](bool alongB) {
                const int lines = alongB ? net.count[c] : net.count[b];
                const int length = alongB ? net.count[b] : net.count[c];
                for (int l = 0; l < lines; ++l)
                    for (int m = 1; m < length; ++m) {
                        const int s0 = alongB ? slotAt(ia, 0, l) : slotAt(ia, l, 0);
                        const int s1 = alongB ? slotAt(ia, m, l) : slotAt(ia, l, m);
                        if (net.weldedTo[s0] != net.weldedTo[s1]) return false;
                    }
                return true;
            };
            const bool alongB = collapsed(true), alongC = collapsed(false);
            net.collapsedAlong[a][side] = (alongB ? 1 << b : 0) | (alongC ? 1 << c : 0);
            net.boundaryFace[a][side] = !seam && !alongB && !alongC;
        }
    }
    net.boundarySlot.assign(n, 0);
    for (int s = 0; s < n; ++s) {
        const std::array<int, 3> ijk = net.slotIjk(s);
        for (int a = 0; a < 3; ++a)
            if ((ijk[a] == 0 && net.boundaryFace[a][0]) || (ijk[a] == net.count[a] - 1 && net.boundaryFace[a][1])) net.boundarySlot[s] = 1;
    }
    for (const auto& g : net.weldGroups) {  // a group is on the boundary if any of its slots is
        bool any = false;
        for (int s : g) any = any || net.boundarySlot[s];
        for (int s : g) net.boundarySlot[s] = any ? 1 : 0;
    }
    net.restIndex = buildChunkIndex(net, net.rest);
    // A valid lattice is right-handed at rest: det dQ0/dt > 0 inside every chunk (zero is allowed only on a
    // collapsed face). Sampled at 27 points inside each chunk (local 0.1, 0.5, 0.9 per axis: off the faces,
    // where a collapsed face has det 0), so an edit that folds a chunk (two far points merged) is refused.
    const std::array<int, 3> spans = net.spans();
    static constexpr double kSamples[3] = {0.1, 0.5, 0.9};
    for (int w = 0; w < spans[2]; ++w)
        for (int v = 0; v < spans[1]; ++v)
            for (int u = 0; u < spans[0]; ++u)
                for (int sample = 0; sample < 27; ++sample) {
                    const Eigen::Vector3d t((u + kSamples[sample % 3]) / spans[0], (v + kSamples[(sample / 3) % 3]) / spans[1],
                                            (w + kSamples[sample / 9]) / spans[2]);
                    const double det = restOrientationAt(net, t);
                    if (!(det > 0.0))
                        return Status::error("lattice chunk [" + std::to_string(u) + "," + std::to_string(v) + "," + std::to_string(w) +
                                             "] is " + (det < 0.0 ? "left-handed or folded" : "flat") +
                                             " at rest (det dQ/dt = " + std::to_string(det) + "): reorder its axes or move its points");
                }
    return Status::success();
}

void evaluateNetVolume(const LatticeNet& net, const Positions& points, const Eigen::Vector3d& t, Eigen::Vector3d& value,
                       Eigen::Matrix3d* derivative) {
    evaluateNetVolume(net, points.data(), t, value, derivative);
}

void evaluateNetVolume(const LatticeNet& net, const double* points, const Eigen::Vector3d& t, Eigen::Vector3d& value,
                       Eigen::Matrix3d* derivative) {
    NetBases b;
    const bool withDerivative = derivative != nullptr;
    netBases(net, t, withDerivative, b);
    const int nu = net.degree[0] + 1, nv = net.degree[1] + 1, nw = net.degree[2] + 1;
    // Homogeneous sums H = sum W B (P, 1) and their t-derivatives (Hu et al. 2001, eq. 1-2), contracted one axis
    // at a time (u, then v, then w): h[0] = H, h[1..3] = dH/dt_a.
    const double* p = points;  // row-major #slots x 3
    double h[4][4] = {};
    for (int k = 0; k < nw; ++k) {
        double hv[3][4] = {};  // sum over j of: B_j * A, B'_j * A, B_j * Au
        for (int j = 0; j < nv; ++j) {
            double a[4] = {}, au[4] = {};
            const int row = net.slot(b.first[0], b.first[1] + j, b.first[2] + k);
            for (int i = 0; i < nu; ++i) {
                const int s = row + i;
                const double w = net.weights[static_cast<size_t>(s)];
                const double* q = p + 3 * static_cast<size_t>(s);
                const double wb = w * b.value[0][i];
                a[0] += wb * q[0], a[1] += wb * q[1], a[2] += wb * q[2], a[3] += wb;
                if (withDerivative) {
                    const double wd = w * b.derivative[0][i];
                    au[0] += wd * q[0], au[1] += wd * q[1], au[2] += wd * q[2], au[3] += wd;
                }
            }
            const double bj = b.value[1][j], dj = withDerivative ? b.derivative[1][j] : 0.0;
            for (int c = 0; c < 4; ++c) {
                hv[0][c] += bj * a[c];
                hv[1][c] += bj * au[c];
                hv[2][c] += dj * a[c];
            }
        }
        const double bk = b.value[2][k], dk = withDerivative ? b.derivative[2][k] : 0.0;
        for (int c = 0; c < 4; ++c) {
            h[0][c] += bk * hv[0][c];
            h[1][c] += bk * hv[1][c];
            h[2][c] += bk * hv[2][c];
            h[3][c] += dk * hv[0][c];
        }
    }
    const double inverse = 1.0 / h[0][3];
    value = Eigen::Vector3d(h[0][0], h[0][1], h[0][2]) * inverse;
    if (derivative)  // quotient rule: d(N/W) = (dN - Q dW) / W
        for (int a = 0; a < 3; ++a)
            for (int c = 0; c < 3; ++c) (*derivative)(c, a) = (h[a + 1][c] - value[c] * h[a + 1][3]) * inverse;
}

namespace {

// Newton's method for Q(t) = x inside the parameter box [lo, hi] (a chunk), from `start`. Converged: the
// residual reaches `tight` (rounding level), or stalls there below `loose`.
bool newtonInChunk(const LatticeNet& net, const Positions& points, const Eigen::Vector3d& x, const Eigen::Vector3d& lo,
                   const Eigen::Vector3d& hi, const Eigen::Vector3d& start, double tight, double loose, Eigen::Vector3d& t) {
    Eigen::Vector3d u = start, best = start;
    const Eigen::Vector3d width = hi - lo;
    double bestResidual = std::numeric_limits<double>::infinity();
    int stalled = 0;
    for (int iteration = 0; iteration < 60 && stalled < 4; ++iteration) {
        Eigen::Vector3d q;
        Eigen::Matrix3d d;
        evaluateNetVolume(net, points, u, q, &d);
        const Eigen::Vector3d residual = x - q;
        const double r = residual.norm();
        if (r < bestResidual) {
            // note: a step that gains less than a tenth is a stall (rounding level or a point outside the chunk).
            stalled = r > 0.9 * bestResidual ? stalled + 1 : 0;
            bestResidual = r;
            best = u;
        } else {
            ++stalled;
        }
        if (r <= tight) break;
        // Full-rank steps by LU; near-singular Jacobians (a collapsed axis or pole) by the pseudo-inverse, which
        // moves only along the directions the volume can move in (3.3: degenerate chunks).
        Eigen::Vector3d step = freezingNewtonStep(d, residual);
        if (!step.allFinite()) break;
        // Damped: at most half the chunk per axis per iteration, and stay in the chunk.
        for (int a = 0; a < 3; ++a) step[a] = std::clamp(step[a], -0.5 * width[a], 0.5 * width[a]);
        u += step;
        for (int a = 0; a < 3; ++a) {
            // Over the whole domain a periodic axis wraps round its seam instead of stopping there.
            if (net.periodic[a] && lo[a] == 0.0 && hi[a] == 1.0) u[a] -= std::floor(u[a]);
            u[a] = std::clamp(u[a], lo[a], hi[a]);
        }
    }
    t = best;
    return bestResidual <= loose;
}

}  // namespace

bool freezePoint(const LatticeNet& net, const Positions& points, const ChunkIndex& index, const Eigen::Vector3d& x,
                 Eigen::Vector3d& t) {
    if (!x.allFinite()) return false;
    thread_local std::vector<int> candidates;
    index.candidates(x, candidates);
    if (candidates.empty()) return false;
    const double diagonal = std::max(index.bounds.diagonal().norm(), 1e-300);
    const double tight = 4e-15 * diagonal + 8.0 * std::numeric_limits<double>::epsilon() * x.cwiseAbs().maxCoeff();
    const double loose = 1e-13 * diagonal + 64.0 * std::numeric_limits<double>::epsilon() * x.cwiseAbs().maxCoeff();
    const std::array<int, 3> spans = net.spans();
    auto chunkBox = [&](int chunk, Eigen::Vector3d& lo, Eigen::Vector3d& hi) {
        const int c[3] = {chunk % spans[0], (chunk / spans[0]) % spans[1], chunk / (spans[0] * spans[1])};
        for (int a = 0; a < 3; ++a) {
            lo[a] = static_cast<double>(c[a]) / spans[a];
            hi[a] = c[a] + 1 == spans[a] ? 1.0 : static_cast<double>(c[a] + 1) / spans[a];
        }
    };
    // Pass 1: Newton over the whole parameter domain from each candidate chunk's centre (it may walk into a
    // neighbouring chunk: the answer is the same point of the volume). The first candidate that converges
    // gives the answer, so a point on a chunk face or in overlapping chunks always gets the same one.
    const Eigen::Vector3d zero = Eigen::Vector3d::Zero(), one = Eigen::Vector3d::Ones();
    bool allStoppedOnBoundary = true;
    for (int chunk : candidates) {
        Eigen::Vector3d lo, hi;
        chunkBox(chunk, lo, hi);
        Eigen::Vector3d end;
        if (newtonInChunk(net, points, x, zero, one, 0.5 * (lo + hi), tight, loose, end)) {
            t = end;
            return true;
        }
        // note: for a point outside the volume Newton walks to the volume's outer surface and stops there
        // (the clamp); only a start that stalled elsewhere needs the finer starts below.
        bool onBoundary = false;
        for (int a = 0; a < 3; ++a)
            onBoundary = onBoundary || (end[a] == 0.0 && net.boundaryFace[a][0]) || (end[a] == 1.0 && net.boundaryFace[a][1]);
        allStoppedOnBoundary = allStoppedOnBoundary && onBoundary;
    }
    if (allStoppedOnBoundary) return false;
    // Pass 2 (3.3: "subdivide the chunk for a better start"): inside each chunk, from the centres of its 8
    // octants, then of its 64 sub-boxes.
    for (int level = 2; level <= 4; level *= 2)
        for (int chunk : candidates) {
            Eigen::Vector3d lo, hi;
            chunkBox(chunk, lo, hi);
            for (int s = 0; s < level * level * level; ++s) {
                const Eigen::Vector3d local((s % level + 0.5) / level, ((s / level) % level + 0.5) / level, (s / (level * level) + 0.5) / level);
                if (newtonInChunk(net, points, x, lo, hi, lo + (hi - lo).cwiseProduct(local), tight, loose, t)) return true;
            }
        }
    return false;
}

Status placeLatticeNet(const LatticeNet& tool, const Eigen::Vector3d& point, const Eigen::Vector3d& normal, double size,
                       LatticeNet& out) {
    PlacementSimilarity similarity;
    if (Status s = placementSimilarity(tool.bounds, point, normal, size, similarity); !s) return s;
    LatticeNet net = rawNetFields(tool);
    for (Eigen::Index s = 0; s < tool.rest.rows(); ++s) net.rest.row(s) = similarity(tool.rest.row(s).transpose()).transpose();
    // note: welded points coincide before the similarity, so they coincide after it up to rounding; make them
    // exactly equal again.
    for (const auto& group : tool.weldGroups)
        for (int s : group) net.rest.row(s) = net.rest.row(group[0]);
    if (Status st = finishLatticeNet(net); !st) return st;
    out = std::move(net);
    return Status::success();
}

// ---- predefined lattices -----------------------------------------------------------------------------

Status makeParallelepipedNet(const Eigen::Vector3d& origin, const Eigen::Matrix3d& edges, const std::array<int, 3>& chunks,
                             const std::array<int, 3>& degree, LatticeNet& out) {
    if (Status s = checkChunks(chunks, degree, {1, 1, 1}); !s) return s;
    if (!origin.allFinite() || !edges.allFinite()) return Status::error("parallelepiped has a non-finite origin or edge");
    const double det = edges.determinant();
    if (!(det > 1e-12 * edges.colwise().norm().prod()))
        return Status::error("parallelepiped edges must be non-zero, not coplanar, and right-handed (det > 0)");
    std::array<std::vector<double>, 3> g;
    std::array<int, 3> count{};
    for (int a = 0; a < 3; ++a) {
        g[a] = grevillePoints(chunks[a], degree[a]);
        count[a] = static_cast<int>(g[a].size());
    }
    return buildGridNet("parallelepiped", count, degree, {1, 1, 1}, [&](int i, int j, int k, Eigen::Vector3d& point, double&) {
        point = origin + edges * Eigen::Vector3d(g[0][i], g[1][j], g[2][k]);
    }, out);
}

Status makeCylinderNet(const Eigen::Vector3d& base, const Eigen::Vector3d& axis, double radius, double height,
                       const std::array<int, 3>& chunks, const std::array<int, 2>& degree, LatticeNet& out) {
    if (chunks[1] < 3) return Status::error("a cylindrical lattice needs at least 3 angular chunks (arcs of at most 120 degrees)");
    if (Status s = checkChunks(chunks, {degree[0], 2, degree[1]}, {1, 2, 1}); !s) return s;
    if (!base.allFinite() || !axis.allFinite() || !(axis.norm() > 0.0)) return Status::error("cylinder axis must be finite and non-zero");
    if (!finitePositive(radius) || !finitePositive(height)) return Status::error("cylinder radius and height must be finite and > 0");
    const Eigen::Vector3d e3 = axis.normalized();
    Eigen::Vector3d e1, e2;
    completeFrame(e3, e1, e2);
    std::vector<Eigen::Vector2d> arc;
    std::vector<double> arcWeights;
    circularArc(chunks[1], 0.0, 2.0 * kPi, arc, arcWeights);
    const std::vector<double> gr = grevillePoints(chunks[0], degree[0]), gz = grevillePoints(chunks[2], degree[1]);
    const std::array<int, 3> count{static_cast<int>(gr.size()), static_cast<int>(arc.size()), static_cast<int>(gz.size())};
    return buildGridNet("cylinder", count, {degree[0], 2, degree[1]}, {1, 2, 1}, [&](int i, int j, int k, Eigen::Vector3d& point, double& weight) {
        // note: the seam slice is the first one exactly (no cos(2 pi) rounding) and the axis is exactly on the
        // axis, so the welds are exact.
        const Eigen::Vector2d c = j + 1 == count[1] ? arc[0] : arc[j];
        point = base + gz[k] * height * e3 + (i == 0 ? Eigen::Vector3d::Zero() : Eigen::Vector3d(gr[i] * radius * (c.x() * e1 + c.y() * e2)));
        weight = arcWeights[j];
    }, out);
}

Status makeSphereNet(const Eigen::Vector3d& centre, const Eigen::Vector3d& axis, double radius, const std::array<int, 3>& chunks,
                     int radialDegree, LatticeNet& out) {
    if (chunks[1] < 3) return Status::error("a spherical lattice needs at least 3 angular chunks");
    if (chunks[2] < 2) return Status::error("a spherical lattice needs at least 2 polar chunks (arcs of at most 90 degrees)");
    if (Status s = checkChunks(chunks, {radialDegree, 2, 2}, {1, 2, 2}); !s) return s;
    if (!centre.allFinite() || !axis.allFinite() || !(axis.norm() > 0.0)) return Status::error("sphere axis must be finite and non-zero");
    if (!finitePositive(radius)) return Status::error("sphere radius must be finite and > 0");
    const Eigen::Vector3d e3 = axis.normalized();
    Eigen::Vector3d e1, e2;
    completeFrame(e3, e1, e2);
    std::vector<Eigen::Vector2d> arc, profile;
    std::vector<double> arcWeights, profileWeights;
    circularArc(chunks[1], 0.0, 2.0 * kPi, arc, arcWeights);
    circularArc(chunks[2], -0.5 * kPi, kPi, profile, profileWeights);
    profile.front() = Eigen::Vector2d(0.0, -1.0);
    profile.back() = Eigen::Vector2d(0.0, 1.0);
    const std::vector<double> gr = grevillePoints(chunks[0], radialDegree);
    const std::array<int, 3> count{static_cast<int>(gr.size()), static_cast<int>(arc.size()), static_cast<int>(profile.size())};
    return buildGridNet("sphere", count, {radialDegree, 2, 2}, {1, 2, 2}, [&](int i, int j, int k, Eigen::Vector3d& point, double& weight) {
        const Eigen::Vector2d c = j + 1 == count[1] ? arc[0] : arc[j];
        const Eigen::Vector3d direction = profile[k].x() * (c.x() * e1 + c.y() * e2) + profile[k].y() * e3;
        point = centre + (i == 0 ? 0.0 : gr[i] * radius) * direction;
        weight = arcWeights[j] * profileWeights[k];
    }, out);
}

PlanarNet makeRectangleNet(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, const std::array<int, 2>& chunks,
                           const std::array<int, 2>& degree) {
    PlanarNet net;
    net.degree = degree;
    const std::vector<double> gu = grevillePoints(chunks[0], degree[0]), gv = grevillePoints(chunks[1], degree[1]);
    net.count = {static_cast<int>(gu.size()), static_cast<int>(gv.size())};
    for (int j = 0; j < net.count[1]; ++j)
        for (int i = 0; i < net.count[0]; ++i)
            net.points.push_back(Eigen::Vector2d(lo.x() + gu[i] * (hi.x() - lo.x()), lo.y() + gv[j] * (hi.y() - lo.y())));
    net.weights.assign(net.points.size(), 1.0);
    return net;
}

Status makeLoftNet(const PlanarNet& profile, const std::vector<Positions>& sections, int degree, LatticeNet& out) {
    const int perSection = profile.count[0] * profile.count[1];
    if (static_cast<int>(profile.points.size()) != perSection || static_cast<int>(profile.weights.size()) != perSection)
        return Status::error("2D lattice needs count[0] x count[1] points and weights");
    if (degree < kMinDegree || degree > kMaxDegree) return Status::error("loft degree must be in [1, 5]");
    if (static_cast<int>(sections.size()) < degree + 1 || static_cast<int>(sections.size()) > kMaxControlPointsPerAxis)
        return Status::error("a loft of degree " + std::to_string(degree) + " needs " + std::to_string(degree + 1) + " to 64 sections");
    LatticeNet net;
    net.kind = "loft";
    net.degree = {profile.degree[0], profile.degree[1], degree};
    net.multiplicity = {profile.multiplicity[0], profile.multiplicity[1], 1};
    net.count = {profile.count[0], profile.count[1], static_cast<int>(sections.size())};
    net.rest.resize(net.slotCount(), 3);
    net.weights.resize(net.slotCount());
    for (int k = 0; k < net.count[2]; ++k) {
        if (sections[k].rows() != perSection || sections[k].cols() != 3)
            return Status::error("loft section " + std::to_string(k) + " needs " + std::to_string(perSection) + " points");
        for (int s = 0; s < perSection; ++s) {
            net.rest.row(s + perSection * k) = sections[k].row(s);
            net.weights[s + perSection * k] = profile.weights[s];
        }
    }
    weldCoincidentSlots(net);
    if (Status s = finishLatticeNet(net); !s) return s;
    out = std::move(net);
    return Status::success();
}

Status makeExtrusionNet(const PlanarNet& profile, const Eigen::Vector3d& origin, const Eigen::Vector3d& uAxis,
                        const Eigen::Vector3d& vAxis, const Eigen::Vector3d& direction, int chunks, int degree,
                        LatticeNet& out) {
    if (!origin.allFinite() || !uAxis.allFinite() || !vAxis.allFinite() || !direction.allFinite())
        return Status::error("extrusion has a non-finite origin, axis or direction");
    const Eigen::Vector3d u = uAxis.normalized();
    const Eigen::Vector3d v = (vAxis - vAxis.dot(u) * u).normalized();
    if (!u.allFinite() || !v.allFinite() || !(std::abs(u.cross(v).dot(direction)) > 1e-12 * direction.norm()))
        return Status::error("extrusion needs two independent plane axes and a direction out of their plane");
    if (chunks < 1 || degree < kMinDegree || degree > kMaxDegree || chunks + degree > kMaxControlPointsPerAxis)
        return Status::error("extrusion needs at least 1 chunk of degree 1 to 5 (at most 64 control points)");
    const int perSection = profile.count[0] * profile.count[1];
    if (static_cast<int>(profile.points.size()) != perSection) return Status::error("2D lattice needs count[0] x count[1] points");
    const std::vector<double> g = grevillePoints(chunks, degree);
    std::vector<Positions> sections;
    for (double gk : g) {
        Positions section(perSection, 3);
        for (int s = 0; s < perSection; ++s)
            section.row(s) = (origin + profile.points[s].x() * u + profile.points[s].y() * v + gk * direction).transpose();
        sections.push_back(std::move(section));
    }
    LatticeNet net;
    if (Status s = makeLoftNet(profile, sections, degree, net); !s) return s;
    net.kind = "prism";
    out = std::move(net);
    return Status::success();
}

namespace lattice_net_detail {

void netBases(const LatticeNet& net, const Eigen::Vector3d& t, bool derivatives, NetBases& b) {
    for (int a = 0; a < 3; ++a) {
        double local = 0.0;
        const int span = net.axes[a].locate(std::clamp(t[a], 0.0, 1.0), local);
        b.first[a] = net.axes[a].first(span);
        net.axes[a].evaluate(span, local, b.value[a]);
        if (derivatives) net.axes[a].evaluateDerivative(span, local, b.derivative[a]);
    }
}

}  // namespace lattice_net_detail

}  // namespace sculpt::core
