// Body of the evaluation kernel, included by evaluation_kernel_generic.cpp and evaluation_kernel_avx2.cpp
// (the latter compiled with -mavx2 -mfma). Define SCULPT_KERNEL_NAME before including.
//
// Full evaluation, per cell: the cell's map in power form once (homogeneous W*delta and W when rational, Hu et
// al. 2001 eq. 2), then per vertex three nested Horner schemes, vectorised across the vertices of the cell (see
// powerFormOfCell). The incremental update keeps the basis form: it contracts only the slab of the support
// that holds changed control points.
#include <algorithm>
#include <cstdint>
#include <cstring>

#include "core/spline/evaluation_kernel.h"

namespace sculpt::core::detail {

namespace {

// Four vertices per step in GCC/Clang vector extensions: AVX2 registers in the -mavx2 build, SSE2 pairs in
// the generic one. Written out explicitly because the compiler does not vectorise the scalar form across
// vertices (per-lane basis arrays and the scatter to the original vertex order defeat it).
typedef double Lanes __attribute__((vector_size(32)));

// Power form. On one cell the displacement (Hu et al. 2001 eq. 1; for a rational lattice the numerator and the
// denominator of eq. 2 apart) is a polynomial of degree p in each local coordinate:
//   D(x,y,z) = sum_{a,b,c} M_abc x^a y^b z^c,   M_abc = sum_{i,j,k} Cu[i][a] Cv[j][b] Cw[k][c] P_ijk,
// where C[i][a] is the coefficient of x^a of the cell's i-th basis function (BSplineAxis::coefficients) and P
// the cell's (p+1)^3 control displacements (weighted and with the weight as a fourth coordinate when rational).
// M is formed once per cell; each vertex then costs one Horner scheme per axis: (p+1)^2 p + (p+1) p + p
// multiply-adds per coordinate (cubic: 63, so 189 for x, y, z), against the 3 (p+1)^3 + ... = 288 of
// evaluating the basis and contracting the tensor product.
//
// The powers are of x - 1/2, not x: about the cell's centre every basis function's coefficients are small
// (a Bernstein polynomial's sum of |coefficient| (1/2)^k is 1), so rounding stays at the basis form's level
// even at degree 5, where powers of x on [0, 1] cancel terms of order C(5,2)^3 and lose three digits.
template <int P>
void coefficientsAboutMidpoint(const std::vector<double>& coefficients, int span, double (&c)[P + 1][P + 1]) {
    constexpr int N = P + 1;
    std::copy_n(coefficients.data() + static_cast<size_t>(span) * N * N, N * N, &c[0][0]);
    // Taylor shift x = t + 1/2 by repeated synthetic division (Horner's scheme for the shift).
    for (int i = 0; i < N; ++i)
        for (int k = 0; k < P; ++k)
            for (int d = P - 1; d >= k; --d) c[i][d] += 0.5 * c[i][d + 1];
}

template <int P, int H>
void powerFormOfCell(const Lattice& lattice, int su, int sv, int sw, Lanes (&power)[P + 1][P + 1][P + 1][H]) {
    constexpr int N = P + 1;
    double cu[N][N], cv[N][N], cw[N][N];
    coefficientsAboutMidpoint<P>(lattice.axes[0].coefficients, su, cu);
    coefficientsAboutMidpoint<P>(lattice.axes[1].coefficients, sv, cv);
    coefficientsAboutMidpoint<P>(lattice.axes[2].coefficients, sw, cw);
    double block[N][N][N][H];  // [k][j][i][h]: control displacements, homogeneous when H == 4
    for (int k = 0; k < N; ++k)
        for (int j = 0; j < N; ++j)
            for (int i = 0; i < N; ++i) {
                const int idx = lattice.index(lattice.axes[0].first(su) + i, lattice.axes[1].first(sv) + j, lattice.axes[2].first(sw) + k);
                const double w = H == 4 ? lattice.weights[idx] : 1.0;
                for (int c = 0; c < 3; ++c) block[k][j][i][c] = w * lattice.displacement(idx, c);
                if constexpr (H == 4) block[k][j][i][3] = w;
            }
    // Contract one axis at a time (u, then v, then w): N^4 H multiply-adds each, per cell.
    double tu[N][N][N][H] = {}, tv[N][N][N][H] = {};  // [k][j][a], then [k][b][a]
    for (int k = 0; k < N; ++k)
        for (int j = 0; j < N; ++j)
            for (int a = 0; a < N; ++a)
                for (int i = 0; i < N; ++i)
                    for (int h = 0; h < H; ++h) tu[k][j][a][h] += cu[i][a] * block[k][j][i][h];
    for (int k = 0; k < N; ++k)
        for (int b = 0; b < N; ++b)
            for (int j = 0; j < N; ++j)
                for (int a = 0; a < N; ++a)
                    for (int h = 0; h < H; ++h) tv[k][b][a][h] += cv[j][b] * tu[k][j][a][h];
    for (int c = 0; c < N; ++c)
        for (int b = 0; b < N; ++b)
            for (int a = 0; a < N; ++a)
                for (int h = 0; h < H; ++h) {
                    double m = 0.0;
                    for (int k = 0; k < N; ++k) m += cw[k][c] * tv[k][b][a][h];
                    power[c][b][a][h] = Lanes{} + m;  // broadcast: one memory operand per multiply-add below
                }
}

// InCellOrder: entry v of e.order goes to row v of out (the benchmark's eval_full_8_in_cell_order), not to row
// e.order[v] (the mesh's own order, a scatter).
template <int P, bool Rational, bool InCellOrder = false>
void evaluateCellFixed(const Lattice& lattice, const Embedding& e, int cell, double* out) {
    constexpr int N = P + 1;
    constexpr int H = Rational ? 4 : 3;
    const std::array<int, 3> spans = lattice.spans();
    const int su = cell % spans[0];
    const int sv = (cell / spans[0]) % spans[1];
    const int sw = cell / (spans[0] * spans[1]);
    alignas(32) Lanes power[N][N][N][H];
    powerFormOfCell<P, H>(lattice, su, sv, sw, power);

    const int begin = e.cellStart[cell], end = e.cellStart[cell + 1];
    for (int v = begin; v < end; v += 4) {
        const int lanes = std::min(4, end - v);
        Lanes x{}, y{}, z{};
        if (lanes == 4) {
            std::memcpy(&x, e.localX.data() + v, sizeof x);
            std::memcpy(&y, e.localY.data() + v, sizeof y);
            std::memcpy(&z, e.localZ.data() + v, sizeof z);
        } else {
            for (int l = 0; l < lanes; ++l) {
                x[l] = e.localX[v + l];
                y[l] = e.localY[v + l];
                z[l] = e.localZ[v + l];
            }
        }
        x -= 0.5, y -= 0.5, z -= 0.5;  // powers about the cell's centre (coefficientsAboutMidpoint)
        // Horner in z outermost, y inside it, x innermost.
        Lanes sum[H];
        for (int c = P; c >= 0; --c) {
            Lanes sy[H];
            for (int b = P; b >= 0; --b) {
                Lanes sx[H];
                for (int h = 0; h < H; ++h) sx[h] = power[c][b][P][h];
                for (int a = P - 1; a >= 0; --a)
                    for (int h = 0; h < H; ++h) sx[h] = sx[h] * x + power[c][b][a][h];
                for (int h = 0; h < H; ++h) sy[h] = b == P ? sx[h] : sy[h] * y + sx[h];
            }
            for (int h = 0; h < H; ++h) sum[h] = c == P ? sy[h] : sum[h] * z + sy[h];
        }
        if constexpr (Rational) {
            const Lanes scale = 1.0 / sum[3];
            for (int c = 0; c < 3; ++c) sum[c] *= scale;
        }
        for (int l = 0; l < lanes; ++l) {
            double* o = out + 3 * static_cast<size_t>(InCellOrder ? v + l : e.order[v + l]);
            o[0] = e.restX[v + l] + sum[0][l];
            o[1] = e.restY[v + l] + sum[1][l];
            o[2] = e.restZ[v + l] + sum[2][l];
        }
    }
}

// Incremental update of a polynomial lattice: positions += sum R_c(t) increment_c over the changed control
// points only. `increment` is #P x 3 (zero except at changed points); per cell only the slab of its support
// that holds changed points is contracted, so a drag's outer cells (one changed layer) cost a fraction of
// a full evaluation.
template <int P>
void incrementCellFixed(const Lattice& lattice, const Embedding& e, int cell, const Positions& increment,
                        const std::uint8_t* changed, double* out) {
    constexpr int N = P + 1;
    const std::array<int, 3> spans = lattice.spans();
    const int su = cell % spans[0];
    const int sv = (cell / spans[0]) % spans[1];
    const int sw = cell / (spans[0] * spans[1]);
    int lo[3] = {N, N, N}, hi[3] = {-1, -1, -1};
    alignas(32) Lanes block[N][N][N][3];
    for (int k = 0; k < N; ++k)
        for (int j = 0; j < N; ++j)
            for (int i = 0; i < N; ++i) {
                const int idx = lattice.index(lattice.axes[0].first(su) + i, lattice.axes[1].first(sv) + j, lattice.axes[2].first(sw) + k);
                for (int c = 0; c < 3; ++c) block[k][j][i][c] = Lanes{} + increment(idx, c);
                if (changed[idx]) {
                    lo[0] = std::min(lo[0], i), hi[0] = std::max(hi[0], i);
                    lo[1] = std::min(lo[1], j), hi[1] = std::max(hi[1], j);
                    lo[2] = std::min(lo[2], k), hi[2] = std::max(hi[2], k);
                }
            }
    if (hi[0] < 0) return;
    double cu[N][N], cv[N][N], cw[N][N];
    std::copy_n(lattice.axes[0].coefficients.data() + static_cast<size_t>(su) * N * N, N * N, &cu[0][0]);
    std::copy_n(lattice.axes[1].coefficients.data() + static_cast<size_t>(sv) * N * N, N * N, &cv[0][0]);
    std::copy_n(lattice.axes[2].coefficients.data() + static_cast<size_t>(sw) * N * N, N * N, &cw[0][0]);
    const int begin = e.cellStart[cell], end = e.cellStart[cell + 1];
    for (int v = begin; v < end; v += 4) {
        const int lanes = std::min(4, end - v);
        Lanes x{}, y{}, z{};
        for (int l = 0; l < lanes; ++l) {
            x[l] = e.localX[v + l];
            y[l] = e.localY[v + l];
            z[l] = e.localZ[v + l];
        }
        Lanes bu[N], bv[N], bw[N];
        for (int i = 0; i < N; ++i) {
            Lanes a = Lanes{} + cu[i][P], b = Lanes{} + cv[i][P], c = Lanes{} + cw[i][P];
            for (int d = P - 1; d >= 0; --d) {
                a = a * x + cu[i][d];
                b = b * y + cv[i][d];
                c = c * z + cw[i][d];
            }
            bu[i] = a;
            bv[i] = b;
            bw[i] = c;
        }
        Lanes sum[3] = {};
        for (int k = lo[2]; k <= hi[2]; ++k) {
            Lanes sk[3] = {};
            for (int j = lo[1]; j <= hi[1]; ++j) {
                Lanes sj[3] = {};
                for (int i = lo[0]; i <= hi[0]; ++i)
                    for (int c = 0; c < 3; ++c) sj[c] += bu[i] * block[k][j][i][c];
                for (int c = 0; c < 3; ++c) sk[c] += bv[j] * sj[c];
            }
            for (int c = 0; c < 3; ++c) sum[c] += bw[k] * sk[c];
        }
        for (int l = 0; l < lanes; ++l) {
            double* o = out + 3 * static_cast<size_t>(e.order[v + l]);
            o[0] += sum[0][l];
            o[1] += sum[1][l];
            o[2] += sum[2][l];
        }
    }
}

void incrementCellMixed(const Lattice& lattice, const Embedding& e, int cell, const Positions& increment,
                        const std::uint8_t* changed, double* out) {
    const std::array<int, 3> spans = lattice.spans();
    const int su = cell % spans[0];
    const int sv = (cell / spans[0]) % spans[1];
    const int sw = cell / (spans[0] * spans[1]);
    const int nu = lattice.degree[0] + 1, nv = lattice.degree[1] + 1, nw = lattice.degree[2] + 1;
    for (int v = e.cellStart[cell]; v < e.cellStart[cell + 1]; ++v) {
        double bu[kMaxDegree + 1], bv[kMaxDegree + 1], bw[kMaxDegree + 1];
        lattice.axes[0].evaluate(su, e.localX[v], bu);
        lattice.axes[1].evaluate(sv, e.localY[v], bv);
        lattice.axes[2].evaluate(sw, e.localZ[v], bw);
        double sum[3] = {};
        for (int k = 0; k < nw; ++k)
            for (int j = 0; j < nv; ++j)
                for (int i = 0; i < nu; ++i) {
                    const int idx = lattice.index(lattice.axes[0].first(su) + i, lattice.axes[1].first(sv) + j, lattice.axes[2].first(sw) + k);
                    if (!changed[idx]) continue;
                    const double w = bu[i] * bv[j] * bw[k];
                    for (int c = 0; c < 3; ++c) sum[c] += w * increment(idx, c);
                }
        double* o = out + 3 * static_cast<size_t>(e.order[v]);
        for (int c = 0; c < 3; ++c) o[c] += sum[c];
    }
}

// Any mix of degrees: the same contraction with run-time loop bounds (slower, rarely used).
void evaluateCellMixed(const Lattice& lattice, const Embedding& e, int cell, double* out) {
    const std::array<int, 3> spans = lattice.spans();
    const int su = cell % spans[0];
    const int sv = (cell / spans[0]) % spans[1];
    const int sw = cell / (spans[0] * spans[1]);
    const int nu = lattice.degree[0] + 1, nv = lattice.degree[1] + 1, nw = lattice.degree[2] + 1;
    for (int v = e.cellStart[cell]; v < e.cellStart[cell + 1]; ++v) {
        double bu[kMaxDegree + 1], bv[kMaxDegree + 1], bw[kMaxDegree + 1];
        lattice.axes[0].evaluate(su, e.localX[v], bu);
        lattice.axes[1].evaluate(sv, e.localY[v], bv);
        lattice.axes[2].evaluate(sw, e.localZ[v], bw);
        double sum[4] = {};
        for (int k = 0; k < nw; ++k)
            for (int j = 0; j < nv; ++j)
                for (int i = 0; i < nu; ++i) {
                    const int idx = lattice.index(lattice.axes[0].first(su) + i, lattice.axes[1].first(sv) + j, lattice.axes[2].first(sw) + k);
                    const double w = lattice.weights[idx] * bu[i] * bv[j] * bw[k];
                    for (int c = 0; c < 3; ++c) sum[c] += w * lattice.displacement(idx, c);
                    sum[3] += w;
                }
        const double scale = lattice.rational ? 1.0 / sum[3] : 1.0;
        double* o = out + 3 * static_cast<size_t>(e.order[v]);
        o[0] = e.restX[v] + sum[0] * scale;
        o[1] = e.restY[v] + sum[1] * scale;
        o[2] = e.restZ[v] + sum[2] * scale;
    }
}

template <bool Rational, bool InCellOrder = false>
void evaluateCellDispatch(const Lattice& lattice, const Embedding& e, int cell, double* out) {
    const int p = lattice.degree[0];
    if (lattice.degree[1] != p || lattice.degree[2] != p) {
        if constexpr (!InCellOrder) evaluateCellMixed(lattice, e, cell, out);  // (cell order: fixed degrees only)
        return;
    }
    switch (p) {
        case 1: return evaluateCellFixed<1, Rational, InCellOrder>(lattice, e, cell, out);
        case 2: return evaluateCellFixed<2, Rational, InCellOrder>(lattice, e, cell, out);
        case 3: return evaluateCellFixed<3, Rational, InCellOrder>(lattice, e, cell, out);
        case 4: return evaluateCellFixed<4, Rational, InCellOrder>(lattice, e, cell, out);
        default: return evaluateCellFixed<5, Rational, InCellOrder>(lattice, e, cell, out);
    }
}

void incrementCellDispatch(const Lattice& lattice, const Embedding& e, int cell, const Positions& increment,
                           const std::uint8_t* changed, double* out) {
    const int p = lattice.degree[0];
    if (lattice.degree[1] != p || lattice.degree[2] != p) return incrementCellMixed(lattice, e, cell, increment, changed, out);
    switch (p) {
        case 1: return incrementCellFixed<1>(lattice, e, cell, increment, changed, out);
        case 2: return incrementCellFixed<2>(lattice, e, cell, increment, changed, out);
        case 3: return incrementCellFixed<3>(lattice, e, cell, increment, changed, out);
        case 4: return incrementCellFixed<4>(lattice, e, cell, increment, changed, out);
        default: return incrementCellFixed<5>(lattice, e, cell, increment, changed, out);
    }
}

}  // namespace

void SCULPT_INCREMENT_NAME(const Lattice& lattice, const Embedding& embedding, const int* cells, int cellCount,
                           const Positions& increment, const std::uint8_t* changed, double* positions) {
    long long work = 0;
    for (int c = 0; c < cellCount; ++c) work += embedding.cellStart[cells[c] + 1] - embedding.cellStart[cells[c]];
#pragma omp parallel for schedule(dynamic, 4) if (work > 20000)
    for (int c = 0; c < cellCount; ++c)
        if (embedding.cellStart[cells[c]] != embedding.cellStart[cells[c] + 1])
            incrementCellDispatch(lattice, embedding, cells[c], increment, changed, positions);
}

void SCULPT_KERNEL_NAME(const Lattice& lattice, const Embedding& embedding, const int* cells, int cellCount,
                        double* positions) {
    // note: a small update (a few thousand vertices) is done on the calling thread; waking the team costs
    // more than it saves and, on a busy machine, can cost a scheduler quantum.
    long long work = 0;
    for (int c = 0; c < cellCount; ++c) work += embedding.cellStart[cells[c] + 1] - embedding.cellStart[cells[c]];
#pragma omp parallel for schedule(dynamic, 4) if (work > 20000)
    for (int c = 0; c < cellCount; ++c) {
        if (embedding.cellStart[cells[c]] == embedding.cellStart[cells[c] + 1]) continue;
        if (lattice.rational)
            evaluateCellDispatch<true>(lattice, embedding, cells[c], positions);
        else
            evaluateCellDispatch<false>(lattice, embedding, cells[c], positions);
    }
}

void SCULPT_CELL_ORDER_NAME(const Lattice& lattice, const Embedding& embedding, double* out) {
    const int cellCount = static_cast<int>(embedding.cellStart.size()) - 1;
#pragma omp parallel for schedule(dynamic, 4)
    for (int c = 0; c < cellCount; ++c) {
        if (embedding.cellStart[c] == embedding.cellStart[c + 1]) continue;
        if (lattice.rational)
            evaluateCellDispatch<true, true>(lattice, embedding, c, out);
        else
            evaluateCellDispatch<false, true>(lattice, embedding, c, out);
    }
}

}  // namespace sculpt::core::detail
