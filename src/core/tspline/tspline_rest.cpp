// The rest volume of a weighted T-spline (Song & Yang 2005, "Free-form deformation with weighted T-spline",
// seed 002, sec. 4-6): making it (control points at the Greville points of a box, the octree lattices of sec. 4
// and their local subdivision of sec. 6 / Fig. 11, with sec. 4's weights made valid by a weight balance), and the
// exact proof that it does not fold, which freezing (sec. 5, eq. 8) and every injectivity test (Gain & Dodgson
// 2001, seed 003: det J = det dQ/dt / det dQ0/dt) rely on.
//
// Why 100:1 folds. Q0(t) = sum W_s P_s B_s / sum W_s B_s with P_s at the Greville points. Without T-junctions,
// on a line along t_a the volume is a 1-D rational B-spline in t_a whose control values (the Greville abscissae)
// increase, so dQ0_a/dt_a > 0 whatever the weights (rational B-splines are variation diminishing); only the
// cross terms vary with the weights, and measured on uniform lattices with the octree's weight pattern they
// never fold (det >= 0.035 of the box at 100:1). At a T-junction the blending functions over a point come from
// rows with different knots: expressed on the finest grid by knot insertion, B_s = sum_i a_si N_i, the volume is
// a tensor NURBS with weights sum_s W_s a_si and control points sum_s W_s a_si P_s / sum_s W_s a_si, a weighted
// mix of the Greville points of coarse and fine functions. With equal weights the mix stays ordered; when a
// coarse heavy function's tail (weight 100) meets fine light ones (weight 1) the heavy Greville point, a coarse
// knot interval away, dominates the mix and the fine control net is no longer ordered: the rest map shears until
// it folds. Measured on the default mesh: the folds lie in the coarse cells next to the finest band, where the
// heavy share is 0.75-0.9, with off-diagonal dQ0/dt twice the diagonal.
//
// The fix: weight balance. What folds is the jump of the weights between neighbouring blending functions, not
// the ratio between near and far ones (ratio 10 never folded, on any lattice tried). So, as the octree keeps
// neighbouring cells within one level (2:1 balance), the weights keep control points joined by a net edge
// within a factor `weightStep` (10): the heavy weight of sec. 4 falls off ring by ring (100, 10, 1). The heavy
// points keep the paper's 100:1 over the far ones and still dominate the band round the surface. Measured on the
// default mesh (200k samples): 39 folding samples at depth 4 and 51 at depth 5 become none (least det 0.012 and
// 0.018 of the box), and random point clouds at depths 2-5 with ratios 100 and 1000 stop folding; the proof
// accepts 1000:1 on the default mesh at depths 3-5, where the two-level weights only pass below ~35:1. Re-placing the control points instead was tried and
// is worse: a least-squares fit of Q0 to the identity (heavy and light points alike) moves the light points far
// to make up for their small share and folds ~100x more; interpolation at the Greville points (Richardson steps)
// folds more with every step. Where the balance is still not enough, the octree builders reduce the ratio
// (bisection on its logarithm) to the largest value proven valid and say so (makeOctreeTSplineVolume).
//
// The proof, per Bezier element (Volume::bezierChunk: the homogeneous Bernstein points (W P, W) of degree 3):
//  1. dQ0/dt at the element's centre; det <= 0 there is a fold. Precondition by its inverse A and the centre
//     point: N' = A (N - Q0(c) W), so dQ'/dt = A dQ0/dt is the identity at the centre (det A > 0).
//  2. The Jacobian hull: column a of dQ'/dt is M_a / W^2, M_a = N'_a W - N' W_a (3 polynomials of degree 5 in t_a,
//     6 in the others, by Bernstein products), so its direction is that of M_a. With M_aa's coefficients > 0,
//     column a divided by its diagonal entry lies in the box of the ratios M_ia / M_aa of coefficients (convex
//     hull: a ratio of polynomials of one degree, positive denominator coefficients), and det of a matrix with
//     unit diagonal is multilinear in the off-diagonal entries, so its least value over that box is at one of
//     its 64 corners. Least > 0 proves det dQ0/dt > 0 on the closed element. Unlike bounds of N_a / W and
//     W_a / W taken apart, M_a keeps the cancellation between them, so a weight that varies tenfold over the
//     element does not spoil it, and dividing each column by its diagonal entry removes the compression (the
//     rest map squeezes 10-100x across the heavy band), which an enclosure of dQ0/dt itself does not survive
//     (measured: 43% of the elements decided that way, 88-97% this way).
//  3. Otherwise the element's homogeneous Bezier points are halved by de Casteljau (an exact change of
//     parameters; Gain & Dodgson's section 6 subdivision, one axis at a time: the one along which W varies
//     most, which took a third of the boxes octants did) and each box gets steps 1-2, until every box is
//     proven, a box centre has det <= 0 (a fold, confirmed by evaluate()), or boxes of 2^-8 of the element /
//     1024 boxes leave some undecided (refused as such).
// Why not det's own Bernstein coefficients (chunkDeterminantBernstein, W^4 det dQ0/dt of degree 11, as the
// exact injectivity test does)? They decide ~98.5% of the elements at once but cost ~0.3 ms each (7 s for the
// default mesh at depth 5), and their rounding guard is relative to the largest terms over the element, which
// with weights varying 1000:1 over it exceeds the determinant itself: such elements were never certified.
// Rounding: a coefficient counts as positive only above a guard of 1e-10 of the magnitude of the terms it is
// formed from (plus 1e-13 of what N' was computed from), so the proof never certifies a sign that rounding
// could have produced.
#include "core/tspline/tspline_volume.h"

#include <algorithm>
#include <atomic>
#include <cassert>
#include <chrono>
#include <climits>
#include <cmath>
#include <cstdio>
#include <limits>

#include <Eigen/LU>
#include <Eigen/QR>

#include "core/spline/bernstein.h"

namespace sculpt::core {

// ---- making volumes ----------------------------------------------------------------------------------------

Status makeTSplineVolumeInBox(const TLattice& lattice, const Eigen::AlignedBox3d& box, const std::vector<double>& weights,
                              std::shared_ptr<const TSplineVolume>& out) {
    if (box.isEmpty() || !box.min().allFinite() || !box.max().allFinite() || !(box.sizes().array() > 0.0).all())
        return Status::error("a T-spline volume needs a finite box with min < max on every axis");
    std::shared_ptr<const TSplineBasis> basis;
    if (Status s = buildTSplineBasis(lattice, basis); !s) return s;
    const int n = basis->anchorCount();
    Positions points(n, 3);
    for (int s = 0; s < n; ++s) points.row(s) = (box.min() + basis->grevilleParameters(s).cwiseProduct(box.sizes())).transpose();
    std::vector<double> w = weights.empty() ? std::vector<double>(static_cast<size_t>(n), 1.0) : weights;
    return TSplineVolume::make(std::move(basis), std::move(points), std::move(w), out);
}

namespace {

// Sec. 4: the control points of non-empty cells (anchored at a vertex of the closed box of a cell that holds a
// point: a corner or a T-junction on its boundary; boundary copies alike).
std::vector<std::uint8_t> nonEmptyCellAnchors(const TSplineBasis& basis, const std::vector<std::uint8_t>& nonEmpty) {
    const int n = basis.anchorCount();
    std::vector<std::uint8_t> heavy(static_cast<size_t>(n), 0);
    const TLattice& l = basis.lattice;
    for (int s = 0; s < n; ++s) {
        const auto& p = l.vertices[static_cast<size_t>(basis.anchors[static_cast<size_t>(s)].vertex)];
        for (int corner = 0; corner < 8 && !heavy[static_cast<size_t>(s)]; ++corner) {
            std::array<int, 3> doubled{};
            bool inside = true;
            for (int a = 0; a < 3; ++a) {
                doubled[a] = 2 * p[a] + (((corner >> a) & 1) ? 1 : -1);
                inside = inside && doubled[a] > 0 && doubled[a] < 2 * l.fineCount[a];
            }
            heavy[static_cast<size_t>(s)] = inside && nonEmpty[static_cast<size_t>(l.cellAtDoubled(doubled))];
        }
    }
    return heavy;
}

// The volume with sec. 4's balanced weights (light, heavy = light * ratio on `heavyAnchors`); if its rest volume
// folds, the largest ratio between 1 and `ratio` (bisection on the logarithm, to a factor 1.05) whose does not.
Status makeWithValidRatio(const std::shared_ptr<const TSplineBasis>& basis, const Positions& control, const std::vector<std::uint8_t>& heavyAnchors,
                          double light, double ratio, double step, std::shared_ptr<const TSplineVolume>& out, TSplineWeightOutcome* outcome) {
    auto attempt = [&](double r, std::shared_ptr<const TSplineVolume>& made) {
        return TSplineVolume::make(basis, control, balancedTSplineWeights(*basis, heavyAnchors, light * r, light, step), made);
    };
    TSplineWeightOutcome result;
    result.weightRatio = ratio;
    const Status first = attempt(ratio, out);
    if (!first) {
        // Bisection on s in [0, 1] for the ratio ratio^s: s = 1 failed, s = 0 (equal weights) must hold.
        std::shared_ptr<const TSplineVolume> valid;
        if (Status s = attempt(1.0, valid); !s) return Status::error(s.message + " (even with equal weights)");
        double lo = 0.0, hi = 1.0;
        const double logRatio = std::log(ratio);
        while ((hi - lo) * std::abs(logRatio) > std::log(1.05)) {
            const double mid = 0.5 * (lo + hi);
            std::shared_ptr<const TSplineVolume> made;
            if (attempt(std::exp(mid * logRatio), made)) {
                lo = mid;
                valid = std::move(made);
            } else {
                hi = mid;
            }
        }
        out = std::move(valid);
        char text[400];
        std::snprintf(text, sizeof text, "weight ratio %g:1 reduced to %.3g:1, the largest that keeps the rest volume free of folds (%s)", ratio,
                      std::exp(lo * logRatio), first.message.c_str());
        result.weightRatio = std::exp(lo * logRatio);
        result.ratioReduced = true;
        result.message = text;
    }
    if (outcome) *outcome = result;
    return Status::success();
}

}  // namespace

Status makeOctreeTSplineVolumeInBox(const Positions& points, const Eigen::AlignedBox3d& box, const TSplineOctreeSettings& settings,
                                    std::shared_ptr<const TSplineVolume>& out, TSplineWeightOutcome* outcome) {
    if (!(settings.weightRatio > 0.0) || !std::isfinite(settings.weightRatio)) return Status::error("the weight ratio must be finite and > 0");
    if (!(settings.weightStep > 1.0) || !std::isfinite(settings.weightStep)) return Status::error("the weight step must be finite and > 1");
    TLattice lattice;
    std::vector<std::uint8_t> nonEmpty;
    if (Status s = makeOctreeTLattice(points, box, settings.octree, lattice, &nonEmpty); !s) return s;
    std::shared_ptr<const TSplineBasis> basis;
    if (Status s = buildTSplineBasis(lattice, basis); !s) return s;
    const int n = basis->anchorCount();
    Positions control(n, 3);
    for (int s = 0; s < n; ++s) control.row(s) = (box.min() + basis->grevilleParameters(s).cwiseProduct(box.sizes())).transpose();
    return makeWithValidRatio(basis, control, nonEmptyCellAnchors(*basis, nonEmpty), 1.0, settings.weightRatio, settings.weightStep, out, outcome);
}

Status makeOctreeTSplineVolume(const Positions& points, const TSplineOctreeSettings& settings, std::shared_ptr<const TSplineVolume>& out,
                               Eigen::AlignedBox3d* boxOut, TSplineWeightOutcome* outcome) {
    if (!(settings.padding >= 0.0) || !std::isfinite(settings.padding)) return Status::error("the padding must be finite and >= 0");
    Eigen::AlignedBox3d box;
    if (Status s = paddedPointBounds(points, settings.padding, box); !s) return s;
    if (boxOut) *boxOut = box;
    return makeOctreeTSplineVolumeInBox(points, box, settings, out, outcome);
}

Status paddedPointBounds(const Positions& points, double padding, Eigen::AlignedBox3d& out) {
    Eigen::AlignedBox3d box;
    box.setEmpty();
    for (Eigen::Index p = 0; p < points.rows(); ++p)
        if (points.row(p).allFinite()) box.extend(points.row(p).transpose());
    if (box.isEmpty()) return Status::error("an octree T-spline volume needs at least one finite point");
    const double pad = padding * box.diagonal().norm() + (box.diagonal().norm() > 0.0 ? 0.0 : 1.0);
    box.min().array() -= pad;
    box.max().array() += pad;
    for (int a = 0; a < 3; ++a)  // a flat point set still gets a box with volume
        if (!(box.sizes()[a] > 0.0)) {
            box.min()[a] -= 0.5 * box.diagonal().norm();
            box.max()[a] += 0.5 * box.diagonal().norm();
        }
    out = box;
    return Status::success();
}

Status subdivideTSplineVolume(const TSplineVolume& volume, const std::vector<int>& cells, bool balance, const Positions& points,
                              std::shared_ptr<const TSplineVolume>& out, TSplineWeightOutcome* outcome, double weightStep) {
    if (!(weightStep > 1.0) || !std::isfinite(weightStep)) return Status::error("the weight step must be finite and > 1");
    const TSplineBasis& basis = volume.basis();
    const Positions& rest = volume.restControlPoints();
    const int n = basis.anchorCount();
    // The affine map the control points are an image of the Greville parameters by: P_s = A g_s + b (least
    // squares over every point; exact for a generated volume, placed or not).
    Eigen::MatrixXd greville(n, 4);
    for (int s = 0; s < n; ++s) greville.row(s) << basis.grevilleParameters(s).transpose(), 1.0;
    const Eigen::MatrixXd map = greville.colPivHouseholderQr().solve(Eigen::MatrixXd(rest));  // 4 x 3: rows A^T, b^T
    const double diagonal = volume.restBounds().diagonal().norm();
    const double misfit = (greville * map - rest).rowwise().norm().maxCoeff();
    if (!(misfit <= 1e-9 * diagonal))
        return Status::error("its control points are not in their rest layout (an affine image of the Greville points), so "
                             "subdividing would lose their shape: subdivide the lattice before moving its points one by one");
    const Eigen::Matrix3d linear = map.topRows<3>().transpose();
    const Eigen::Vector3d offset = map.row(3).transpose();
    TLattice finer;
    if (Status s = subdivideTLatticeCells(basis.lattice, cells, balance, finer); !s) return s;
    std::shared_ptr<const TSplineBasis> finerBasis;
    if (Status s = buildTSplineBasis(finer, finerBasis); !s) return s;
    // Sec. 4 on the finer lattice (Fig. 11b): the cells holding a point (its parameters under the inverse of the
    // affine map, as makeOctreeTLattice classifies them) get the heavy weight.
    const Eigen::Matrix3d inverse = linear.inverse();
    auto nonEmptyCells = [&](const TLattice& l) {
        std::vector<std::uint8_t> nonEmpty(l.cells.size(), 0);
        for (Eigen::Index p = 0; p < points.rows(); ++p) {
            const Eigen::Vector3d t = inverse * (points.row(p).transpose() - offset);
            if (!t.allFinite() || (t.array() < 0.0).any() || (t.array() > 1.0).any()) continue;
            std::array<int, 3> doubled{};
            for (int a = 0; a < 3; ++a) doubled[a] = 2 * l.fineVoxel(a, t[a]) + 1;
            nonEmpty[static_cast<size_t>(l.cellAtDoubled(doubled))] = 1;
        }
        return nonEmpty;
    };
    // The heavy weight is the one the old volume has on its own non-empty cells' points, and the light one the
    // other extreme: with a ratio below 1 the non-empty cells' points are the lightest, and stay so.
    const std::vector<double>& oldWeights = volume.controlWeights();
    const auto [lightest, heaviest] = std::minmax_element(oldWeights.begin(), oldWeights.end());
    double heavyWeight = *heaviest, lightWeight = *lightest;
    const std::vector<std::uint8_t> oldHeavy = nonEmptyCellAnchors(basis, nonEmptyCells(basis.lattice));
    for (int s = 0; s < n; ++s)
        if (oldHeavy[static_cast<size_t>(s)]) {
            if (oldWeights[static_cast<size_t>(s)] == *lightest && *lightest != *heaviest) std::swap(heavyWeight, lightWeight);
            break;
        }
    const int m = finerBasis->anchorCount();
    Positions control(m, 3);
    for (int s = 0; s < m; ++s) control.row(s) = (linear * finerBasis->grevilleParameters(s) + offset).transpose();
    std::shared_ptr<const TSplineVolume> made;
    const std::vector<std::uint8_t> heavy = nonEmptyCellAnchors(*finerBasis, nonEmptyCells(finerBasis->lattice));
    if (Status s = makeWithValidRatio(finerBasis, control, heavy, lightWeight, heavyWeight / lightWeight, weightStep, made, outcome); !s) return s;
    out = std::move(made);
    return Status::success();
}

// ---- the proof -------------------------------------------------------------------------------------------

std::vector<double> balancedTSplineWeights(const TSplineBasis& basis, const std::vector<std::uint8_t>& heavyAnchors, double heavy, double light,
                                           double step) {
    assert(step > 1.0 && static_cast<int>(heavyAnchors.size()) == basis.anchorCount());
    const int n = basis.anchorCount();
    std::vector<double> weights(static_cast<size_t>(n), light);
    // Rings: breadth-first over the control net from the flagged anchors.
    std::vector<std::vector<int>> neighbours(static_cast<size_t>(n));
    for (const auto& e : basis.controlNetEdges()) {
        neighbours[static_cast<size_t>(e[0])].push_back(e[1]);
        neighbours[static_cast<size_t>(e[1])].push_back(e[0]);
    }
    std::vector<int> ring(static_cast<size_t>(n), -1), queue;
    for (int s = 0; s < n; ++s)
        if (heavyAnchors[static_cast<size_t>(s)]) {
            ring[static_cast<size_t>(s)] = 0;
            queue.push_back(s);
        }
    for (size_t head = 0; head < queue.size(); ++head)
        for (int r : neighbours[static_cast<size_t>(queue[head])])
            if (ring[static_cast<size_t>(r)] < 0) {
                ring[static_cast<size_t>(r)] = ring[static_cast<size_t>(queue[head])] + 1;
                queue.push_back(r);
            }
    // heavy / step^d, clamped at light (heavy * step^d when heavy < light); exact for whole ratios and steps.
    for (int s = 0; s < n; ++s) {
        const int d = ring[static_cast<size_t>(s)];
        if (d < 0) continue;
        const double fall = std::pow(step, d);
        weights[static_cast<size_t>(s)] = heavy >= light ? std::max(light, heavy / fall) : std::min(light, heavy * fall);
    }
    return weights;
}

namespace {

constexpr int kMaxRestSubdivisionDepth = 8;   // boxes of 2^-8 of an element
constexpr int kMaxRestBoxesPerElement = 1024;
constexpr double kHullGuard = 1e-10;          // relative to the magnitude of a product coefficient's terms

using ElementOutcome = ChunkJacobianProof;

// Degree-3 Bernstein basis and its derivative at 1/2.
constexpr double kHalf[4] = {0.125, 0.375, 0.375, 0.125};
constexpr double kHalfDerivative[4] = {-0.75, -0.75, 0.75, 0.75};

// out (3 polynomials of degree 5 along `A`, 6 along the others, scaled form) = Na (x) W - N (x) Wa, with Na, Wa
// the hodographs along A (degree 2 along A, scaled) and N, W of degree 3 (scaled): M_A of the header.
// note: the hot loop of the check; the innermost 4 terms are contiguous, so the AVX2 clone does them at once
// (chosen at run time; no FMA contraction, so both clones give the same bits).
typedef double Double4 __attribute__((vector_size(32), aligned(8), may_alias));  // as in tspline_volume.cpp

// note: clang does not multiversion function templates, so the template is inlined into one cloned function per
// axis (jacobianNumerators0/1/2); each clone compiles its inlined copy for its own target.
template <int A>
__attribute__((always_inline)) inline void jacobianNumeratorsOf(const double* __restrict na, const double* __restrict wa,
                                                                const double* __restrict n, const double* __restrict w,
                                                                double* __restrict out) {
    constexpr int d0 = A == 0 ? 3 : 4, d1 = A == 1 ? 3 : 4, d2 = A == 2 ? 3 : 4;
    constexpr int o0 = d0 + 3, o1 = d1 + 3;
    std::fill(out, out + 3 * 294, 0.0);
    for (int k = 0; k < d2; ++k)
        for (int j = 0; j < d1; ++j)
            for (int i = 0; i < d0; ++i) {
                const int p = i + d0 * (j + d1 * k);
                const double a0 = na[p], a1 = na[48 + p], a2 = na[96 + p], b = wa[p];
                for (int kk = 0; kk < 4; ++kk)
                    for (int jj = 0; jj < 4; ++jj) {
                        const int q = 4 * (jj + 4 * kk);
                        const int o = i + o0 * ((j + jj) + o1 * (k + kk));
                        const Double4 wq = *reinterpret_cast<const Double4*>(w + q);
                        Double4* out0 = reinterpret_cast<Double4*>(out + o);
                        Double4* out1 = reinterpret_cast<Double4*>(out + 294 + o);
                        Double4* out2 = reinterpret_cast<Double4*>(out + 588 + o);
                        *out0 += a0 * wq - *reinterpret_cast<const Double4*>(n + q) * b;
                        *out1 += a1 * wq - *reinterpret_cast<const Double4*>(n + 64 + q) * b;
                        *out2 += a2 * wq - *reinterpret_cast<const Double4*>(n + 128 + q) * b;
                    }
            }
}

__attribute__((target_clones("avx2", "default"))) void jacobianNumerators0(const double* __restrict na, const double* __restrict wa,
                                                                           const double* __restrict n, const double* __restrict w,
                                                                           double* __restrict out) {
    jacobianNumeratorsOf<0>(na, wa, n, w, out);
}
__attribute__((target_clones("avx2", "default"))) void jacobianNumerators1(const double* __restrict na, const double* __restrict wa,
                                                                           const double* __restrict n, const double* __restrict w,
                                                                           double* __restrict out) {
    jacobianNumeratorsOf<1>(na, wa, n, w, out);
}
__attribute__((target_clones("avx2", "default"))) void jacobianNumerators2(const double* __restrict na, const double* __restrict wa,
                                                                           const double* __restrict n, const double* __restrict w,
                                                                           double* __restrict out) {
    jacobianNumeratorsOf<2>(na, wa, n, w, out);
}

// Per axis A, the binomial products C(d0, i) C(d1, j) C(d2, k) of the degree (5 along A, 6 elsewhere) layout: a
// scaled coefficient divided by it is the Bernstein coefficient.
struct NumeratorScales {
    double value[3][296];  // padded like the coefficients (copies of the first)
    NumeratorScales() {
        for (int a = 0; a < 3; ++a) {
            const int d[3] = {a == 0 ? 5 : 6, a == 1 ? 5 : 6, a == 2 ? 5 : 6};
            int e = 0;
            for (int k = 0; k <= d[2]; ++k)
                for (int j = 0; j <= d[1]; ++j)
                    for (int i = 0; i <= d[0]; ++i) value[a][e++] = binomial(d[0], i) * binomial(d[1], j) * binomial(d[2], k);
            value[a][294] = value[a][295] = value[a][0];
        }
    }
};

// Layout tables of the degree-3 element: the scaled form's binomial products, and per axis the hodograph's
// coefficients (degree 2 along it): where each starts in the cubic's layout and its binomial product.
struct CubicTables {
    double scale[64];
    int hodographStart[3][48];
    double hodographScale[3][48];
    CubicTables() {
        for (int k = 0; k < 4; ++k)
            for (int j = 0; j < 4; ++j)
                for (int i = 0; i < 4; ++i) scale[i + 4 * (j + 4 * k)] = binomial(3, i) * binomial(3, j) * binomial(3, k);
        for (int a = 0; a < 3; ++a) {
            int h = 0;
            for (int k = 0; k < 4; ++k)
                for (int j = 0; j < 4; ++j)
                    for (int i = 0; i < 4; ++i) {
                        const int index[3] = {i, j, k};
                        if (index[a] == 3) continue;
                        double product = 1.0;
                        for (int b = 0; b < 3; ++b) product *= binomial(b == a ? 2 : 3, index[b]);
                        hodographStart[a][h] = i + 4 * (j + 4 * k);
                        hodographScale[a][h++] = product;
                    }
        }
    }
};

// The box of column a's off-diagonal ratios M_ba / M_aa and M_ca / M_aa over `count` coefficients (scaled by
// `scales`, or plain if null; count a multiple of 4), each coefficient taken as uncertain by err (times its
// scale). False if some M_aa is not above that guard. box: bLo, bHi, cLo, cHi.
// note: x' / d' over x' in [x - g, x + g], d' in [d - g, d + g] (d - g > 0) lies in [lo, hi] with, for r = 1 / (d - g)
// and 1 / (d + g) >= r (1 - 2 g r): lo = (x - g) r, times (1 - 2 g r) if x - g >= 0; hi = (x + g) r, times
// (1 - 2 g r) if x + g < 0. One division per coefficient, four at a time.
__attribute__((target_clones("avx2", "default"))) bool columnRatioBox(const double* __restrict diagonal, const double* __restrict xb,
                                                                      const double* __restrict xc, const double* __restrict scales, double err,
                                                                      int count, double box[4]) {
    const double inf = std::numeric_limits<double>::infinity();
    Double4 margin = {inf, inf, inf, inf}, bLo = margin, cLo = margin, bHi = -margin, cHi = -margin;
    const Double4 zero = {0.0, 0.0, 0.0, 0.0}, one = {1.0, 1.0, 1.0, 1.0};
    Double4 sum = zero;  // non-finite if any input is (the selects below would skip a NaN)
    for (int e = 0; e < count; e += 4) {
        const Double4 d = *reinterpret_cast<const Double4*>(diagonal + e);
        sum += d + *reinterpret_cast<const Double4*>(xb + e) + *reinterpret_cast<const Double4*>(xc + e);
        const Double4 g = scales ? err * *reinterpret_cast<const Double4*>(scales + e) : Double4{err, err, err, err};
        const Double4 low = d - g;
        margin = low < margin ? low : margin;
        const Double4 r = one / low;
        const Double4 shrink = one - 2.0 * g * r;
        const Double4 xbl = *reinterpret_cast<const Double4*>(xb + e) - g, xbh = *reinterpret_cast<const Double4*>(xb + e) + g;
        const Double4 xcl = *reinterpret_cast<const Double4*>(xc + e) - g, xch = *reinterpret_cast<const Double4*>(xc + e) + g;
        const Double4 lb = xbl >= zero ? xbl * r * shrink : xbl * r, hb = xbh < zero ? xbh * r * shrink : xbh * r;
        const Double4 lc = xcl >= zero ? xcl * r * shrink : xcl * r, hc = xch < zero ? xch * r * shrink : xch * r;
        bLo = lb < bLo ? lb : bLo;
        cLo = lc < cLo ? lc : cLo;
        bHi = hb > bHi ? hb : bHi;
        cHi = hc > cHi ? hc : cHi;
    }
    double least = inf, total = 0.0;
    box[0] = box[2] = inf;
    box[1] = box[3] = -inf;
    for (int l = 0; l < 4; ++l) {
        least = std::min(least, margin[l]);
        total += sum[l];
        box[0] = std::min(box[0], bLo[l]), box[1] = std::max(box[1], bHi[l]);
        box[2] = std::min(box[2], cLo[l]), box[3] = std::max(box[3], cHi[l]);
    }
    return std::isfinite(total) && least > 0.0 && std::isfinite(box[0]) && std::isfinite(box[1]) && std::isfinite(box[2]) && std::isfinite(box[3]);
}

enum class HullVerdict { Proven, FoldAtCentre, Undecided };

// Steps 1-2 of the header on a box's homogeneous Bezier points `p` (x, y, z, w blocks of 64; polynomial: w = 1),
// `extent`: the box's size in parameters per axis. centreDet: det dQ0/dt at the box's centre.
HullVerdict jacobianHullTest(const double* p, const double extent[3], bool polynomial, double& centreDet) {
    const double* w = p + 192;
    // Values and derivatives at the centre (tensor Bernstein sums).
    Eigen::Vector4d value = Eigen::Vector4d::Zero();
    Eigen::Matrix<double, 4, 3> derivative = Eigen::Matrix<double, 4, 3>::Zero();
    for (int k = 0; k < 4; ++k)
        for (int j = 0; j < 4; ++j)
            for (int i = 0; i < 4; ++i) {
                const int e = i + 4 * (j + 4 * k);
                const double b = kHalf[i] * kHalf[j] * kHalf[k];
                const double du = kHalfDerivative[i] * kHalf[j] * kHalf[k], dv = kHalf[i] * kHalfDerivative[j] * kHalf[k],
                             dw = kHalf[i] * kHalf[j] * kHalfDerivative[k];
                for (int c = 0; c < 4; ++c) {
                    const double x = p[c * 64 + e];
                    value[c] += b * x;
                    derivative(c, 0) += du * x;
                    derivative(c, 1) += dv * x;
                    derivative(c, 2) += dw * x;
                }
            }
    for (int a = 0; a < 3; ++a) derivative.col(a) /= extent[a];
    const Eigen::Vector3d centre = value.head<3>() / value[3];
    const Eigen::Matrix3d jacobian = (derivative.topRows<3>() - centre * derivative.row(3)) / value[3];
    centreDet = jacobian.determinant();
    if (!(centreDet > 0.0)) return std::isfinite(centreDet) ? HullVerdict::FoldAtCentre : HullVerdict::Undecided;
    const Eigen::Matrix3d inverse = jacobian.inverse();
    if (!inverse.allFinite()) return HullVerdict::Undecided;
    const Eigen::Matrix3d inverseAbs = inverse.cwiseAbs();
    const double centreAbs = centre.cwiseAbs().maxCoeff();
    // N' = A (N - c W) and W, unscaled, with the magnitude of what N' was formed from (rounding).
    double np[3][64], wv[64];
    double npMax = 0.0, wMax = 0.0, formedMax = 0.0;
    for (int e = 0; e < 64; ++e) {
        const Eigen::Vector3d raw(p[e] - centre[0] * w[e], p[64 + e] - centre[1] * w[e], p[128 + e] - centre[2] * w[e]);
        const Eigen::Vector3d moved = inverse * raw;
        const Eigen::Vector3d formed = inverseAbs * (Eigen::Vector3d(std::abs(p[e]), std::abs(p[64 + e]), std::abs(p[128 + e])) +
                                                     Eigen::Vector3d::Constant(centreAbs * std::abs(w[e])));
        for (int c = 0; c < 3; ++c) {
            np[c][e] = moved[c];
            npMax = std::max(npMax, std::abs(moved[c]));
        }
        formedMax = std::max(formedMax, formed.maxCoeff());
        wv[e] = w[e];
        wMax = std::max(wMax, std::abs(w[e]));
    }
    if (!(npMax < std::numeric_limits<double>::infinity()) || !(wMax < std::numeric_limits<double>::infinity())) return HullVerdict::Undecided;
    // Scaled (binomial) forms of N' and W.
    static const CubicTables tables;
    double ns[3][64], ws[64];
    for (int e = 0; e < 64; ++e) {
        for (int c = 0; c < 3; ++c) ns[c][e] = np[c][e] * tables.scale[e];
        ws[e] = wv[e] * tables.scale[e];
    }
    double offLo[3][3] = {}, offHi[3][3] = {};
    for (int a = 0; a < 3; ++a) {
        const int stride = a == 0 ? 1 : a == 1 ? 4 : 16;
        const double factor = 3.0 / extent[a];
        // Hodographs along a (degree 2 along a), plain and scaled.
        double na[3][48], wa[48], nas[3][48], was[48];
        double naMax = 0.0, waMax = 0.0;
        for (int h = 0; h < 48; ++h) {
            const int e = tables.hodographStart[a][h];
            const double scale = tables.hodographScale[a][h];
            for (int c = 0; c < 3; ++c) {
                na[c][h] = factor * (np[c][e + stride] - np[c][e]);
                naMax = std::max(naMax, std::abs(na[c][h]));
                nas[c][h] = na[c][h] * scale;
            }
            wa[h] = factor * (wv[e + stride] - wv[e]);
            waMax = std::max(waMax, std::abs(wa[h]));
            was[h] = wa[h] * scale;
        }
        static const NumeratorScales numeratorScales;
        double m[3][296];  // 294 coefficients, padded to a multiple of 4 with copies of the first
        int count = 0;
        const double* scales = nullptr;  // none: the coefficients are the Bernstein ones
        if (polynomial) {
            // W = 1: dQ'/dt_a is the hodograph itself.
            for (int c = 0; c < 3; ++c) std::copy(na[c], na[c] + 48, m[c]);
            count = 48;
        } else {
            double product[3 * 294];
            if (a == 0) jacobianNumerators0(nas[0], was, ns[0], ws, product);
            if (a == 1) jacobianNumerators1(nas[0], was, ns[0], ws, product);
            if (a == 2) jacobianNumerators2(nas[0], was, ns[0], ws, product);
            for (int c = 0; c < 3; ++c) {
                std::copy(product + c * 294, product + (c + 1) * 294, m[c]);
                m[c][294] = m[c][295] = m[c][0];
            }
            count = 296;
            scales = numeratorScales.value[a];
        }
        // Each product coefficient is a convex combination of products of factor coefficients, so its terms are
        // at most termBound; N' itself carries the rounding of A (N - c W), relative to `formedMax`.
        const double termBound = polynomial ? naMax : naMax * wMax + npMax * waMax;
        const double formedBound = polynomial ? 2.0 * factor * formedMax : 2.0 * factor * formedMax * wMax + formedMax * waMax;
        const double err = kHullGuard * termBound + 1e-13 * formedBound;
        // Scaled coefficients (the Bernstein ones times their scale) have the same ratios; the guard scales.
        const int b = (a + 1) % 3, c = (a + 2) % 3;  // the off-diagonal rows of column a
        double box[4];
        if (!columnRatioBox(m[a], m[b], m[c], scales, err, count, box)) return HullVerdict::Undecided;
        offLo[b][a] = box[0], offHi[b][a] = box[1], offLo[c][a] = box[2], offHi[c][a] = box[3];
    }
    // det of I + off-diagonal entries is multilinear in them: its least value over the box is at a corner.
    for (int corner = 0; corner < 64; ++corner) {
        Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
        int bit = 0;
        for (int a = 0; a < 3; ++a)
            for (int c = 0; c < 3; ++c) {
                if (c == a) continue;
                d(c, a) = ((corner >> bit) & 1) ? offHi[c][a] : offLo[c][a];
                ++bit;
            }
        if (!(d.determinant() > 1e-9)) return HullVerdict::Undecided;
    }
    return HullVerdict::Proven;
}

// det dQ/dt at an element's local point, of the rest volume (displacement null) or the moved one.
double determinantAt(const Volume& volume, const Positions* displacement, int element, const Eigen::Vector3d& local) {
    const Eigen::Vector3d t = volume.chunkParameters(element, local);
    Eigen::Vector3d q;
    Eigen::Matrix3d d;
    volume.evaluate(volume.restControlPoints(), t, q, &d);
    if (displacement) {
        Eigen::Matrix3d moved;
        volume.evaluate(*displacement, t, q, &moved);
        d += moved;
    }
    return d.determinant();
}

struct SearchBox {
    double lo[3], size[3];  // in the element's coordinates
    int splits;
};

// The axis along which the weight W varies most over the box (the largest relative spread of its Bezier
// coefficients along a line): where the columns of dQ0/dt turn, so where halving helps the hull test most.
int splitAxis(const double* w) {
    int best = 0;
    double bestSpread = -1.0;
    for (int a = 0; a < 3; ++a) {
        const int stride = a == 0 ? 1 : a == 1 ? 4 : 16;
        double spread = 0.0;
        for (int line = 0; line < 16; ++line) {
            const int first = a == 0 ? 4 * line : a == 1 ? line % 4 + 16 * (line / 4) : line;
            double lo = w[first], hi = w[first];
            for (int i = 1; i < 4; ++i) {
                lo = std::min(lo, w[first + i * stride]);
                hi = std::max(hi, w[first + i * stride]);
            }
            spread = std::max(spread, (hi - lo) / lo);
        }
        if (spread > bestSpread) bestSpread = spread, best = a;
    }
    return best;
}

// Step 3 of the header: the element's homogeneous Bezier points halved by de Casteljau (an exact change of
// parameters) along the axis splitAxis picks, each half given the hull test, until every box is proven, a box's
// centre is a fold (confirmed by evaluating dQ0/dt there), or boxes of 2^-8 of the element on an axis / the box
// limit leave some undecided.
void subdivisionSearch(const Volume& volume, const Positions* displacement, int element, const BezierChunk& chunk, std::vector<double>& pool,
                       ElementOutcome& outcome) {
    constexpr int n = 64, block = 4 * n;
    const BernsteinDegree cubic{3, 3, 3};
    const double finest = std::ldexp(1.0, -kMaxRestSubdivisionDepth);
    outcome.kind = ElementOutcome::Proven;
    outcome.value = std::numeric_limits<double>::infinity();
    bool undecided = false;
    pool.assign(chunk.points.begin(), chunk.points.begin() + block);
    std::vector<SearchBox> stack{SearchBox{{0.0, 0.0, 0.0}, {1.0, 1.0, 1.0}, 0}};
    while (!stack.empty()) {
        const SearchBox box = stack.back();
        stack.pop_back();
        const size_t at = stack.size() * block;  // the box's points: the pool is a stack of blocks like `stack`
        const double extent[3] = {chunk.parameterScale[0] * box.size[0], chunk.parameterScale[1] * box.size[1], chunk.parameterScale[2] * box.size[2]};
        const Eigen::Vector3d centre(box.lo[0] + 0.5 * box.size[0], box.lo[1] + 0.5 * box.size[1], box.lo[2] + 0.5 * box.size[2]);
        ++outcome.boxes;
        double centreDet = 0.0;
        if (jacobianHullTest(pool.data() + at, extent, chunk.polynomial, centreDet) == HullVerdict::Proven) continue;
        const double det = determinantAt(volume, displacement, element, centre);
        if (!(det > 0.0)) {
            outcome.kind = std::isfinite(det) ? ElementOutcome::Fold : ElementOutcome::NonFinite;
            outcome.local = centre;
            outcome.value = det;
            return;
        }
        const int axis = splitAxis(pool.data() + at + 3 * n);
        if (box.size[axis] <= finest || outcome.boxes >= kMaxRestBoxesPerElement) {
            undecided = true;
            if (det < outcome.value) outcome.value = det, outcome.local = centre;
            continue;
        }
        // Halves along `axis`, pushed over the parent's block.
        double halves[2 * block];
        for (int c = 0; c < 4; ++c) splitBernstein(pool.data() + at + c * n, cubic, axis, 0.5, halves + c * n, halves + block + c * n);
        pool.resize(at + 2 * block);
        std::copy(halves, halves + 2 * block, pool.begin() + static_cast<std::ptrdiff_t>(at));
        for (int half = 0; half < 2; ++half) {
            SearchBox child = box;
            child.size[axis] *= 0.5;
            child.lo[axis] += half * child.size[axis];
            ++child.splits;
            stack.push_back(child);
        }
    }
    if (undecided) outcome.kind = ElementOutcome::Undecided;
}

std::string formatNumber(double x) {
    char text[32];
    std::snprintf(text, sizeof text, "%.4g", x);
    return text;
}

}  // namespace

ChunkJacobianProof proveChunkJacobian(const Volume& volume, int chunk, const Positions* displacement) {
    thread_local BezierChunk bezier;
    thread_local std::vector<double> pool;
    ChunkJacobianProof outcome;
    volume.bezierChunk(chunk, displacement, bezier);
    bool collapsed = false;
    for (const auto& faces : bezier.collapse) collapsed = collapsed || faces[0] != 0 || faces[1] != 0;
    if (bezier.degree != std::array<int, 3>{3, 3, 3} || collapsed) {
        outcome.kind = ChunkJacobianProof::NotApplicable;
        return outcome;
    }
    double centreDet = 0.0;
    const double extent[3] = {bezier.parameterScale[0], bezier.parameterScale[1], bezier.parameterScale[2]};
    if (jacobianHullTest(bezier.points.data(), extent, bezier.polynomial, centreDet) == HullVerdict::Proven) {
        outcome.byHull = true;
        return outcome;
    }
    subdivisionSearch(volume, displacement, chunk, bezier, pool, outcome);
    return outcome;
}

Status checkTSplineRestVolume(const TSplineVolume& volume, const std::vector<int>& elements, TSplineRestCheckStats* stats) {
    const auto start = std::chrono::steady_clock::now();
    const TSplineBasis& basis = volume.basis();
    std::vector<int> list = elements;
    if (list.empty()) {
        list.resize(static_cast<size_t>(basis.elementCount()));
        for (int e = 0; e < basis.elementCount(); ++e) list[static_cast<size_t>(e)] = e;
    } else {
        std::sort(list.begin(), list.end());
        list.erase(std::unique(list.begin(), list.end()), list.end());
        if (list.front() < 0 || list.back() >= basis.elementCount())
            return Status::error("element " + std::to_string(list.front() < 0 ? list.front() : list.back()) + " does not exist (the T-spline has elements 0 to " +
                                 std::to_string(basis.elementCount() - 1) + ")");
    }
    const int count = static_cast<int>(list.size());
    std::vector<ElementOutcome> outcomes(static_cast<size_t>(count));
    // The lowest failing position: positions beyond it need not be looked at, those before it always are, so the
    // element reported is the lowest failing one whatever the threads' timing.
    std::atomic<int> firstFailure{INT_MAX};
#pragma omp parallel for schedule(dynamic, 16) if (count > 64)
    for (int i = 0; i < count; ++i) {
        if (i > firstFailure.load(std::memory_order_relaxed)) continue;
        const int e = list[static_cast<size_t>(i)];
        ElementOutcome& outcome = outcomes[static_cast<size_t>(i)];
        outcome = proveChunkJacobian(volume, e, nullptr);
        if (outcome.kind != ElementOutcome::Proven) {
            int seen = firstFailure.load(std::memory_order_relaxed);
            while (i < seen && !firstFailure.compare_exchange_weak(seen, i, std::memory_order_relaxed)) {
            }
        }
    }
    const int failed = firstFailure.load();
    if (stats) {
        *stats = TSplineRestCheckStats{};
        for (int i = 0; i < count && i <= failed; ++i) {
            const ElementOutcome& o = outcomes[static_cast<size_t>(i)];
            ++stats->elementsChecked;
            stats->elementsByJacobianHull += o.byHull;
            stats->elementsBySubdivision += !o.byHull && o.kind == ElementOutcome::Proven;
            stats->subdivisionBoxes += o.boxes;
        }
        stats->milliseconds = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    }
    if (failed == INT_MAX) return Status::success();
    const ElementOutcome& o = outcomes[static_cast<size_t>(failed)];
    const int e = list[static_cast<size_t>(failed)];
    const int cell = basis.elementCell[static_cast<size_t>(e)];
    const Eigen::Vector3d t = volume.chunkParameters(e, o.local);
    const std::string where = "element " + std::to_string(e) + " (T-lattice cell " + std::to_string(cell) + ", level " +
                              std::to_string(basis.lattice.cells[static_cast<size_t>(cell)].level) + ") at t = (" + formatNumber(t[0]) + ", " +
                              formatNumber(t[1]) + ", " + formatNumber(t[2]) + ")";
    switch (o.kind) {
        case ElementOutcome::Fold:
            return Status::error("the T-spline rest volume folds or is mirrored: det dQ0/dt = " + formatNumber(o.value) + " <= 0 in " + where);
        case ElementOutcome::NonFinite:
            return Status::error("the T-spline rest volume is not finite in element " + std::to_string(e) + " (T-lattice cell " + std::to_string(cell) + ")");
        default:
            return Status::error("the T-spline rest volume cannot be proven free of folds: det dQ0/dt stays undecided after subdivision to 2^-" +
                                 std::to_string(kMaxRestSubdivisionDepth) + " of the element or " + std::to_string(kMaxRestBoxesPerElement) +
                                 " boxes in " + where + " (least sampled det " + formatNumber(o.value) + ")");
    }
}

}  // namespace sculpt::core
