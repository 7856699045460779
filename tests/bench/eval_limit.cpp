// Compiled with -mavx2 -mfma (tests/bench/CMakeLists.txt); only called after the run-time check.
#include "eval_limit.h"

#if defined(SCULPT_BENCH_AVX2)
#include <immintrin.h>
#endif

namespace sculpt::bench {

bool limitKernelApplies(const core::Lattice& lattice) {
#if defined(SCULPT_BENCH_AVX2)
    if (!__builtin_cpu_supports("avx2") || !__builtin_cpu_supports("fma")) return false;
    return !lattice.rational && !(lattice.volume && !lattice.tensorNet()) && lattice.degree[0] == 3 &&
           lattice.degree[1] == 3 && lattice.degree[2] == 3;
#else
    (void)lattice;
    return false;
#endif
}

#if defined(SCULPT_BENCH_AVX2)
namespace {

// The span's four cubic basis polynomials in powers of t = x - 1/2 (Taylor shift), as the engine's kernel.
void aboutMidpoint(const std::vector<double>& coefficients, int span, double* c) {
    for (int i = 0; i < 16; ++i) c[i] = coefficients[static_cast<size_t>(span) * 16 + i];
    for (int i = 0; i < 4; ++i)
        for (int k = 0; k < 3; ++k)
            for (int d = 2; d >= k; --d) c[i * 4 + d] += 0.5 * c[i * 4 + d + 1];
}

// M[c][b][a][h] = sum_{i,j,k} Cu[i][a] Cv[j][b] Cw[k][c] P_ijk[h], one axis at a time, broadcast to four lanes.
void cellPowerForm(const core::Lattice& lattice, int su, int sv, int sw, __m256d (&m)[4][4][4][3]) {
    double cu[16], cv[16], cw[16];
    aboutMidpoint(lattice.axes[0].coefficients, su, cu);
    aboutMidpoint(lattice.axes[1].coefficients, sv, cv);
    aboutMidpoint(lattice.axes[2].coefficients, sw, cw);
    const int fu = lattice.axes[0].first(su), fv = lattice.axes[1].first(sv), fw = lattice.axes[2].first(sw);
    double tu[4][4][4][3] = {}, tv[4][4][4][3] = {};
    for (int k = 0; k < 4; ++k)
        for (int j = 0; j < 4; ++j)
            for (int i = 0; i < 4; ++i) {
                const int idx = lattice.index(fu + i, fv + j, fw + k);
                for (int a = 0; a < 4; ++a)
                    for (int h = 0; h < 3; ++h) tu[k][j][a][h] += cu[i * 4 + a] * lattice.displacement(idx, h);
            }
    for (int k = 0; k < 4; ++k)
        for (int j = 0; j < 4; ++j)
            for (int b = 0; b < 4; ++b)
                for (int a = 0; a < 4; ++a)
                    for (int h = 0; h < 3; ++h) tv[k][b][a][h] += cv[j * 4 + b] * tu[k][j][a][h];
    for (int c = 0; c < 4; ++c)
        for (int b = 0; b < 4; ++b)
            for (int a = 0; a < 4; ++a)
                for (int h = 0; h < 3; ++h) {
                    double sum = 0.0;
                    for (int k = 0; k < 4; ++k) sum += cw[k * 4 + c] * tv[k][b][a][h];
                    m[c][b][a][h] = _mm256_set1_pd(sum);
                }
}

// Four vertices' displacements, by Horner in x inside y inside z (in powers of local coordinate - 1/2).
inline void horner4(const __m256d (&m)[4][4][4][3], __m256d x, __m256d y, __m256d z, __m256d (&sum)[3]) {
    const __m256d half = _mm256_set1_pd(0.5);
    x = _mm256_sub_pd(x, half), y = _mm256_sub_pd(y, half), z = _mm256_sub_pd(z, half);
    for (int c = 3; c >= 0; --c) {
        __m256d sy[3];
        for (int b = 3; b >= 0; --b)
            for (int h = 0; h < 3; ++h) {
                __m256d sx = _mm256_fmadd_pd(m[c][b][3][h], x, m[c][b][2][h]);
                sx = _mm256_fmadd_pd(sx, x, m[c][b][1][h]);
                sx = _mm256_fmadd_pd(sx, x, m[c][b][0][h]);
                sy[h] = b == 3 ? sx : _mm256_fmadd_pd(sy[h], y, sx);
            }
        for (int h = 0; h < 3; ++h) sum[h] = c == 3 ? sy[h] : _mm256_fmadd_pd(sum[h], z, sy[h]);
    }
}

}  // namespace
#endif

void evaluateCubicLimit(const core::Lattice& lattice, const core::Embedding& e, double* outX, double* outY,
                        double* outZ) {
#if defined(SCULPT_BENCH_AVX2)
    if (!limitKernelApplies(lattice)) return;
    const std::array<int, 3> spans = lattice.spans();
    const int cellCount = lattice.cellCount();
    double* out[3] = {outX, outY, outZ};
    const double* rest[3] = {e.restX.data(), e.restY.data(), e.restZ.data()};
#pragma omp parallel for schedule(dynamic, 4)
    for (int cell = 0; cell < cellCount; ++cell) {
        const int begin = e.cellStart[cell], end = e.cellStart[cell + 1];
        if (begin == end) continue;
        alignas(32) __m256d m[4][4][4][3];
        cellPowerForm(lattice, cell % spans[0], (cell / spans[0]) % spans[1], cell / (spans[0] * spans[1]), m);
        int v = begin;
        for (; v + 4 <= end; v += 4) {
            __m256d sum[3];
            horner4(m, _mm256_loadu_pd(e.localX.data() + v), _mm256_loadu_pd(e.localY.data() + v),
                    _mm256_loadu_pd(e.localZ.data() + v), sum);
            for (int h = 0; h < 3; ++h) _mm256_storeu_pd(out[h] + v, _mm256_add_pd(_mm256_loadu_pd(rest[h] + v), sum[h]));
        }
        if (v == end) continue;
        alignas(32) double lx[4] = {}, ly[4] = {}, lz[4] = {}, r[3][4];  // the cell's last 1-3 vertices
        for (int l = 0; v + l < end; ++l) lx[l] = e.localX[v + l], ly[l] = e.localY[v + l], lz[l] = e.localZ[v + l];
        __m256d sum[3];
        horner4(m, _mm256_load_pd(lx), _mm256_load_pd(ly), _mm256_load_pd(lz), sum);
        for (int h = 0; h < 3; ++h) {
            _mm256_store_pd(r[h], sum[h]);
            for (int l = 0; v + l < end; ++l) out[h][v + l] = rest[h][v + l] + r[h][l];
        }
    }
#else
    (void)lattice, (void)e, (void)outX, (void)outY, (void)outZ;
#endif
}

}  // namespace sculpt::bench
