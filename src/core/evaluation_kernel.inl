// Body of the evaluation kernel, included by evaluation_kernel_generic.cpp and evaluation_kernel_avx2.cpp
// (the latter compiled with -mavx2 -mfma). Define SCULPT_KERNEL_NAME before including.
//
// Per cell: gather the (p+1)^3 control displacements once (homogeneous W*delta and W when rational,
// Hu et al. 2001 eq. 2), then for each vertex evaluate the three univariate bases from their per-span
// polynomials (Horner, no divisions) and contract the tensor product axis by axis:
//   (p+1)^3 * 3 + (p+1)^2 * 3 + (p+1) * 3 multiply-adds, vectorised across the vertices of the cell.
#include <algorithm>
#include <cstdint>
#include <cstring>

#include "core/evaluation_kernel.h"

namespace sculpt::core::detail {

namespace {

// Four vertices per step in GCC/Clang vector extensions: AVX2 registers in the -mavx2 build, SSE2 pairs in
// the generic one. Written out explicitly because the compiler does not vectorise the scalar form across
// vertices (per-lane basis arrays and the scatter to the original vertex order defeat it).
typedef double Lanes __attribute__((vector_size(32)));

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
    // The cell's (p+1)^3 control displacements, broadcast once per cell so the contraction below is one
    // fused multiply-add with a memory operand per term.
    alignas(32) Lanes block[N][N][N][H];
    for (int k = 0; k < N; ++k)
        for (int j = 0; j < N; ++j)
            for (int i = 0; i < N; ++i) {
                const int idx = lattice.index(lattice.axes[0].first(su) + i, lattice.axes[1].first(sv) + j, lattice.axes[2].first(sw) + k);
                const double w = Rational ? lattice.weights[idx] : 1.0;
                for (int c = 0; c < 3; ++c) block[k][j][i][c] = Lanes{} + w * lattice.displacement(idx, c);
                if constexpr (Rational) block[k][j][i][3] = Lanes{} + w;
            }
    double cu[N][N], cv[N][N], cw[N][N];
    std::copy_n(lattice.axes[0].coefficients.data() + static_cast<size_t>(su) * N * N, N * N, &cu[0][0]);
    std::copy_n(lattice.axes[1].coefficients.data() + static_cast<size_t>(sv) * N * N, N * N, &cv[0][0]);
    std::copy_n(lattice.axes[2].coefficients.data() + static_cast<size_t>(sw) * N * N, N * N, &cw[0][0]);

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
        Lanes bu[N], bv[N], bw[N];
        for (int i = 0; i < N; ++i) {  // per-span polynomials, Horner
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
        Lanes sum[H] = {};
        for (int k = 0; k < N; ++k) {
            Lanes sk[H] = {};
            for (int j = 0; j < N; ++j) {
                Lanes sj[H] = {};
                for (int i = 0; i < N; ++i)
                    for (int c = 0; c < H; ++c) sj[c] += bu[i] * block[k][j][i][c];
                for (int c = 0; c < H; ++c) sk[c] += bv[j] * sj[c];
            }
            for (int c = 0; c < H; ++c) sum[c] += bw[k] * sk[c];
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
