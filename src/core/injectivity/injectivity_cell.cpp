// A lattice cell in Bezier form, its hodographs and det J as a Bernstein polynomial.
// Gain & Dodgson 2001, "Preventing self-intersection under free-form deformation", IEEE TVCG 7(4):
// section 6 (det J in tensor-product form, eq. 5-8, converted to Bezier form per cell, step 3) and
// section 7 (the hodograph control vectors, eq. 9). Instead of the paper's route through Morken's B-spline
// product identities (eq. 6-8) and knot insertion, each cell is converted to Bezier form first (its
// per-span basis polynomials make that a small matrix product) and det J is multiplied out in Bernstein
// form, which gives the same cell-wise Bezier coefficients of eq. 8 directly.
#include "core/injectivity/injectivity_cell.h"
#include "core/injectivity/injectivity_net.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

#include <Eigen/LU>

namespace sculpt::core {

CellBezierBasis makeCellBezierBasis(const Lattice& lattice) {
    CellBezierBasis basis;
    for (int a = 0; a < 3; ++a) {
        const SplineAxis& axis = lattice.axes[a];
        const int p = axis.degree;
        const int n = p + 1;
        basis.degree[a] = p;
        basis.spans[a] = axis.spans;
        basis.hodographScale[a] = axis.spans * p / (lattice.boxMax[a] - lattice.boxMin[a]);
        basis.toBezier[a].assign(static_cast<size_t>(axis.spans) * n * n, 0.0);
        for (int s = 0; s < axis.spans; ++s)
            for (int i = 0; i < n; ++i) {
                // Basis function (s + i) on span s: monomial coefficients in the local x -> Bernstein.
                const double* monomial = axis.coefficients.data() + (static_cast<size_t>(s) * n + i) * n;
                double bernstein[kMaxDegree + 1];
                monomialToBernstein(monomial, p, bernstein);
                for (int l = 0; l < n; ++l) basis.toBezier[a][(static_cast<size_t>(s) * n + l) * n + i] = bernstein[l];
            }
    }
    return basis;
}

bool cellIsPolynomial(const Lattice& lattice, const std::array<int, 3>& cell) {
    if (!lattice.rational) return true;
    // The cell's first control point per axis (SplineAxis::first: the span itself for the box lattice).
    const int i0 = lattice.axes[0].first(cell[0]), j0 = lattice.axes[1].first(cell[1]), k0 = lattice.axes[2].first(cell[2]);
    const double first = lattice.weights[lattice.index(i0, j0, k0)];
    for (int k = 0; k <= lattice.degree[2]; ++k)
        for (int j = 0; j <= lattice.degree[1]; ++j)
            for (int i = 0; i <= lattice.degree[0]; ++i)
                if (lattice.weights[lattice.index(i0 + i, j0 + j, k0 + k)] != first) return false;
    return true;
}

bool cellIsUndeformed(const Lattice& lattice, const std::array<int, 3>& cell) {
    const int i0 = lattice.axes[0].first(cell[0]), j0 = lattice.axes[1].first(cell[1]), k0 = lattice.axes[2].first(cell[2]);
    for (int k = 0; k <= lattice.degree[2]; ++k)
        for (int j = 0; j <= lattice.degree[1]; ++j) {
            const int row = lattice.index(i0, j0 + j, k0 + k);
            for (int i = 0; i <= lattice.degree[0]; ++i)
                for (int c = 0; c < 3; ++c)
                    if (lattice.displacement(row + i, c) != 0.0) return false;
        }
    return true;
}

namespace {

// The per-cell kernels with the number of control points per axis (degree + 1) known at compile time for
// the common uniform degrees (K = 0: taken from the basis at run time), so their short loops unroll.
template <int K0, int K1, int K2>
void bezierDisplacementKernel(const Lattice& lattice, const CellBezierBasis& basis, const std::array<int, 3>& cell,
                              double* bezier) {
    const int n0 = K0 > 0 ? K0 : basis.degree[0] + 1;
    const int n1 = K1 > 0 ? K1 : basis.degree[1] + 1;
    const int n2 = K2 > 0 ? K2 : basis.degree[2] + 1;
    const int n = n0 * n1 * n2;
    const double* mu = basis.toBezier[0].data() + static_cast<size_t>(cell[0]) * n0 * n0;
    const double* mv = basis.toBezier[1].data() + static_cast<size_t>(cell[1]) * n1 * n1;
    const double* mw = basis.toBezier[2].data() + static_cast<size_t>(cell[2]) * n2 * n2;
    // Gather the support's displacements, one block per coordinate, then three separable passes (u, v, w)
    // of the per-span B-spline -> Bezier matrices.
    double control[3 * kMaxCellControlPoints], passU[3 * kMaxCellControlPoints];
    const double* displacement = lattice.displacement.data();  // row-major #P x 3
    for (int k = 0; k < n2; ++k)
        for (int j = 0; j < n1; ++j) {
            const double* row =
                displacement + 3 * static_cast<size_t>(lattice.index(cell[0], cell[1] + j, cell[2] + k));
            for (int i = 0; i < n0; ++i)
                for (int c = 0; c < 3; ++c) control[c * n + i + n0 * (j + n1 * k)] = row[3 * i + c];
        }
    for (int line = 0; line < 3 * n1 * n2; ++line) {  // u: a small matrix-vector product per line
        const double* in = control + n0 * line;
        double* out = passU + n0 * line;
        for (int l = 0; l < n0; ++l) {
            double sum = 0.0;
            for (int i = 0; i < n0; ++i) sum += mu[l * n0 + i] * in[i];
            out[l] = sum;
        }
    }
    double passV[3 * kMaxCellControlPoints];
    for (int c = 0; c < 3; ++c)  // v: rows of n0 scaled and added (vectorises over l)
        for (int k = 0; k < n2; ++k)
            for (int m = 0; m < n1; ++m) {
                double* out = passV + c * n + n0 * (m + n1 * k);
                const double* first = passU + c * n + n0 * n1 * k;
                for (int l = 0; l < n0; ++l) out[l] = mv[m * n1] * first[l];
                for (int j = 1; j < n1; ++j) {
                    const double weight = mv[m * n1 + j];
                    const double* in = first + n0 * j;
                    for (int l = 0; l < n0; ++l) out[l] += weight * in[l];
                }
            }
    const int plane = n0 * n1;
    for (int c = 0; c < 3; ++c)  // w: planes of n0 n1 scaled and added
        for (int o = 0; o < n2; ++o) {
            double* out = bezier + c * n + plane * o;
            const double* first = passV + c * n;
            for (int e = 0; e < plane; ++e) out[e] = mw[o * n2] * first[e];
            for (int k = 1; k < n2; ++k) {
                const double weight = mw[o * n2 + k];
                const double* in = first + plane * k;
                for (int e = 0; e < plane; ++e) out[e] += weight * in[e];
            }
        }
}

// Section 7, step 2a: the largest sin^2 of the angle between a hodograph vector of axis a and that axis.
// note: branch-free (max, and an or-ed failure flag) so the compiler can vectorise it.
template <int K0, int K1, int K2>
bool hodographConesKernel(const CellBezierBasis& basis, const double* bezier, std::array<double, 3>& sinSquared) {
    const int n0 = K0 > 0 ? K0 : basis.degree[0] + 1;
    const int n1 = K1 > 0 ? K1 : basis.degree[1] + 1;
    const int n2 = K2 > 0 ? K2 : basis.degree[2] + 1;
    const int n = n0 * n1 * n2;
    const int stride[3] = {1, n0, n0 * n1};
    bool failed = false;
    for (int a = 0; a < 3; ++a) {
        const double scale = basis.hodographScale[a];
        const int b = (a + 1) % 3, c = (a + 2) % 3;
        const double* along = bezier + a * n;
        const double* sideB = bezier + b * n;
        const double* sideC = bezier + c * n;
        const int step = stride[a];
        double worst = 0.0;
        for (int k = 0; k < n2 - (a == 2); ++k)
            for (int j = 0; j < n1 - (a == 1); ++j)
                for (int i = 0; i < n0 - (a == 0); ++i) {
                    const int at = i + n0 * (j + n1 * k);
                    // J_a's Bezier vector: e_a + (S_a p_a / size_a) (b_{l+1} - b_l) along a.
                    const double axial = 1.0 + scale * (along[at + step] - along[at]);
                    const double db = scale * (sideB[at + step] - sideB[at]);
                    const double dc = scale * (sideC[at + step] - sideC[at]);
                    const double side = db * db + dc * dc;
                    const double norm = side + axial * axial;
                    // Appendix, FindDeviation: a <= 0 -> "fail"; so does a NaN or infinite vector.
                    failed |= !(axial > 0.0 && norm <= std::numeric_limits<double>::max());
                    worst = std::max(worst, side / norm);
                }
        sinSquared[a] = worst;
    }
    return !failed;
}

}  // namespace

void cellBezierDisplacement(const Lattice& lattice, const CellBezierBasis& basis, const std::array<int, 3>& cell,
                            double* bezier) {
    assert(!lattice.volume);
    const std::array<int, 3>& d = basis.degree;
    if (d[0] == d[1] && d[1] == d[2]) switch (d[0]) {
            case 1: return bezierDisplacementKernel<2, 2, 2>(lattice, basis, cell, bezier);
            case 2: return bezierDisplacementKernel<3, 3, 3>(lattice, basis, cell, bezier);
            case 3: return bezierDisplacementKernel<4, 4, 4>(lattice, basis, cell, bezier);
            case 4: return bezierDisplacementKernel<5, 5, 5>(lattice, basis, cell, bezier);
            case 5: return bezierDisplacementKernel<6, 6, 6>(lattice, basis, cell, bezier);
            default: break;
        }
    bezierDisplacementKernel<0, 0, 0>(lattice, basis, cell, bezier);
}

bool cellHodographConesInMeanFrame(const CellBezierBasis& basis, const double* bezier, std::array<double, 3>& sinSquared) {
    // The Bezier vectors of J_a (cellJacobianColumns), in the frame of M, their mean per axis: the vectors M^-1 h.
    // det(M^-1 J) = det J / det M, so with det M > 0 the cones around e_a in that frame prove det J > 0 as section
    // 7's do in the rest frame (the cones' axes give det 1; no choice of vectors in them is coplanar). A rigid
    // motion or uniform scaling R of the cell makes every J = R: M^-1 J = I, certified at any angle.
    double storage[9 * kMaxCellControlPoints];
    double* const column[3] = {storage, storage + 3 * kMaxCellControlPoints, storage + 6 * kMaxCellControlPoints};
    cellJacobianColumns(basis, bezier, column);
    int count[3];
    Eigen::Matrix3d mean = Eigen::Matrix3d::Zero();
    for (int a = 0; a < 3; ++a) {
        count[a] = bernsteinCoefficientCount(columnDegree(basis, a));
        for (int l = 0; l < count[a]; ++l)
            for (int c = 0; c < 3; ++c) mean(c, a) += column[a][c * count[a] + l];
        mean.col(a) /= count[a];
    }
    const double det = mean.determinant();
    if (!(det > 0.0) || !std::isfinite(det)) return false;
    const Eigen::Matrix3d inverse = mean.inverse();
    if (!inverse.allFinite()) return false;
    bool failed = false;
    for (int a = 0; a < 3; ++a) {
        double worst = 0.0;
        for (int l = 0; l < count[a]; ++l) {
            const Eigen::Vector3d h(column[a][l], column[a][count[a] + l], column[a][2 * count[a] + l]);
            const Eigen::Vector3d u = inverse * h;
            const double norm = u.squaredNorm();
            failed |= !(u[a] > 0.0 && norm <= std::numeric_limits<double>::max());
            worst = std::max(worst, (norm - u[a] * u[a]) / norm);
        }
        sinSquared[a] = worst;
    }
    return !failed;
}

bool cellHodographCones(const CellBezierBasis& basis, const double* bezier, std::array<double, 3>& sinSquared) {
    const std::array<int, 3>& d = basis.degree;
    if (d[0] == d[1] && d[1] == d[2]) switch (d[0]) {
            case 1: return hodographConesKernel<2, 2, 2>(basis, bezier, sinSquared);
            case 2: return hodographConesKernel<3, 3, 3>(basis, bezier, sinSquared);
            case 3: return hodographConesKernel<4, 4, 4>(basis, bezier, sinSquared);
            case 4: return hodographConesKernel<5, 5, 5>(basis, bezier, sinSquared);
            case 5: return hodographConesKernel<6, 6, 6>(basis, bezier, sinSquared);
            default: break;
        }
    return hodographConesKernel<0, 0, 0>(basis, bezier, sinSquared);
}

BernsteinDegree columnDegree(const CellBezierBasis& basis, int axis) {
    BernsteinDegree d = basis.degree;
    --d[axis];
    return d;
}

void cellJacobianColumns(const CellBezierBasis& basis, const double* bezier, double* const column[3]) {
    const BernsteinDegree& d = basis.degree;
    const int n0 = d[0] + 1, n1 = d[1] + 1, n2 = d[2] + 1;
    const int n = n0 * n1 * n2;
    const int stride[3] = {1, n0, n0 * n1};
    for (int a = 0; a < 3; ++a) {
        const BernsteinDegree cd = columnDegree(basis, a);
        const int count = bernsteinCoefficientCount(cd);
        const double scale = basis.hodographScale[a];
        int out = 0;
        for (int k = 0; k <= cd[2]; ++k)
            for (int j = 0; j <= cd[1]; ++j)
                for (int i = 0; i <= cd[0]; ++i, ++out) {
                    const int at = i + n0 * (j + n1 * k);
                    // Hodograph of a Bezier volume: p (b_{l+1} - b_l) along the axis; J_a = e_a + dD/dx_a * S_a /
                    // size_a.
                    for (int c = 0; c < 3; ++c) {
                        const double difference = bezier[c * n + at + stride[a]] - bezier[c * n + at];
                        column[a][c * count + out] = (c == a ? 1.0 : 0.0) + scale * difference;
                    }
                }
    }
}

BernsteinDegree determinantDegree(const CellBezierBasis& basis) {
    return {3 * basis.degree[0] - 1, 3 * basis.degree[1] - 1, 3 * basis.degree[2] - 1};
}

void cellDeterminantBernstein(const CellBezierBasis& basis, double* const columns[3], double* scratch,
                              double* determinant) {
    const BernsteinDegree du = columnDegree(basis, 0), dv = columnDegree(basis, 1), dw = columnDegree(basis, 2);
    const BernsteinDegree dx = {dv[0] + dw[0], dv[1] + dw[1], dv[2] + dw[2]};  // J_v x J_w: (2p, 2q-1, 2r-1)
    const BernsteinDegree dd = determinantDegree(basis);
    const int nu = bernsteinCoefficientCount(du), nv = bernsteinCoefficientCount(dv),
              nw = bernsteinCoefficientCount(dw);
    const int nx = bernsteinCoefficientCount(dx), nd = bernsteinCoefficientCount(dd);

    // Scaled copies of the three columns (3 components each), then the cross product, in scratch.
    double* u = scratch;
    double* v = u + 3 * nu;
    double* w = v + 3 * nv;
    double* cross = w + 3 * nw;
    assert(3 * (nu + nv + nw) + 3 * nx <= 3 * kMaxDeterminantCoefficients);
    std::copy(columns[0], columns[0] + 3 * nu, u);
    std::copy(columns[1], columns[1] + 3 * nv, v);
    std::copy(columns[2], columns[2] + 3 * nw, w);
    for (int c = 0; c < 3; ++c) {
        scaleToBinomialForm(u + c * nu, du);
        scaleToBinomialForm(v + c * nv, dv);
        scaleToBinomialForm(w + c * nw, dw);
    }
    std::fill(cross, cross + 3 * nx, 0.0);
    // Eq. 9: det[J_u J_v J_w] = J_u . (J_v x J_w); (J_v x J_w)_c = v_{c+1} w_{c+2} - v_{c+2} w_{c+1}.
    for (int c = 0; c < 3; ++c) {
        const int c1 = (c + 1) % 3, c2 = (c + 2) % 3;
        convolveAddScaled(v + c1 * nv, dv, w + c2 * nw, dw, 1.0, cross + c * nx);
        convolveAddScaled(v + c2 * nv, dv, w + c1 * nw, dw, -1.0, cross + c * nx);
    }
    std::fill(determinant, determinant + nd, 0.0);
    for (int c = 0; c < 3; ++c) convolveAddScaled(u + c * nu, du, cross + c * nx, dx, 1.0, determinant);
    unscaleFromBinomialForm(determinant, dd);
}

BernsteinTensor cellJacobianDeterminantBernstein(const Lattice& lattice, const std::array<int, 3>& cell) {
    const CellBezierBasis basis = makeCellBezierBasis(lattice);
    std::vector<double> bezier(3 * static_cast<size_t>(kMaxCellControlPoints));
    std::vector<double> columnStorage(9 * static_cast<size_t>(kMaxCellControlPoints));
    std::vector<double> scratch(3 * static_cast<size_t>(kMaxDeterminantCoefficients));
    double* columns[3] = {columnStorage.data(), columnStorage.data() + 3 * kMaxCellControlPoints,
                          columnStorage.data() + 6 * kMaxCellControlPoints};
    cellBezierDisplacement(lattice, basis, cell, bezier.data());
    cellJacobianColumns(basis, bezier.data(), columns);
    BernsteinTensor determinant(determinantDegree(basis));
    cellDeterminantBernstein(basis, columns, scratch.data(), determinant.coefficients.data());
    return determinant;
}

double jacobianDeterminantInCell(const Lattice& lattice, const std::array<int, 3>& cell, const Eigen::Vector3d& local) {
    if (lattice.tensorNet()) return netJacobianDeterminantInChunk(lattice, cell, local);
    if (lattice.volume) return chunkJacobianDeterminant(lattice, cell[0], local);  // a chunk id (injectivity.h)
    double value[3][kMaxDegree + 1], derivative[3][kMaxDegree + 1];
    for (int a = 0; a < 3; ++a) {
        lattice.axes[a].evaluate(cell[a], local[a], value[a]);
        lattice.axes[a].evaluateDerivative(cell[a], local[a], derivative[a]);
    }
    const Eigen::Vector3d size = lattice.boxMax - lattice.boxMin;
    if (!lattice.rational) {
        // Polynomial lattice: dD/dt_a = sum B'_a (other B) delta, contracted along u first (per row of the
        // support: one pass for the values, one for the u-derivatives), then v and w together.
        const double* displacement = lattice.displacement.data();  // row-major #P x 3
        double du[3] = {0, 0, 0}, dv[3] = {0, 0, 0}, dw[3] = {0, 0, 0};
        for (int k = 0; k <= lattice.degree[2]; ++k)
            for (int j = 0; j <= lattice.degree[1]; ++j) {
                const double* row =
                    displacement + 3 * static_cast<size_t>(lattice.index(cell[0], cell[1] + j, cell[2] + k));
                double sum[3] = {0, 0, 0}, sumU[3] = {0, 0, 0};
                for (int i = 0; i <= lattice.degree[0]; ++i)
                    for (int c = 0; c < 3; ++c) {
                        sum[c] += value[0][i] * row[3 * i + c];
                        sumU[c] += derivative[0][i] * row[3 * i + c];
                    }
                const double vw = value[1][j] * value[2][k], dvw = derivative[1][j] * value[2][k],
                             vdw = value[1][j] * derivative[2][k];
                for (int c = 0; c < 3; ++c) {
                    du[c] += vw * sumU[c];
                    dv[c] += dvw * sum[c];
                    dw[c] += vdw * sum[c];
                }
            }
        Eigen::Matrix3d m;  // dD/dt diag(1 / size)
        for (int c = 0; c < 3; ++c) {
            m(c, 0) = du[c] / size[0];
            m(c, 1) = dv[c] / size[1];
            m(c, 2) = dw[c] / size[2];
        }
        return worldJacobian(lattice, m).determinant();
    }
    // Rational: homogeneous sums as in deformationJacobian (lattice.cpp): N = sum W B delta, W = sum W B,
    // and their gradients in t.
    Eigen::Vector3d numerator = Eigen::Vector3d::Zero();
    Eigen::Matrix3d numeratorGrad = Eigen::Matrix3d::Zero();  // column a = dN/dt_a
    double denominator = 0.0;
    Eigen::Vector3d denominatorGrad = Eigen::Vector3d::Zero();
    for (int k = 0; k <= lattice.degree[2]; ++k)
        for (int j = 0; j <= lattice.degree[1]; ++j)
            for (int i = 0; i <= lattice.degree[0]; ++i) {
                const int idx = lattice.index(cell[0] + i, cell[1] + j, cell[2] + k);
                const double w = lattice.weights[idx];
                const Eigen::Vector3d grad(derivative[0][i] * value[1][j] * value[2][k],
                                           value[0][i] * derivative[1][j] * value[2][k],
                                           value[0][i] * value[1][j] * derivative[2][k]);
                const Eigen::Vector3d delta = lattice.displacement.row(idx).transpose();
                numerator += w * value[0][i] * value[1][j] * value[2][k] * delta;
                numeratorGrad += w * delta * grad.transpose();
                denominator += w * value[0][i] * value[1][j] * value[2][k];
                denominatorGrad += w * grad;
            }
    // Quotient rule for D = N / W.
    const Eigen::Matrix3d dDisplacementDt =
        (numeratorGrad - (numerator / denominator) * denominatorGrad.transpose()) / denominator;
    return worldJacobian(lattice, dDisplacementDt * size.cwiseInverse().asDiagonal()).determinant();
}

}  // namespace sculpt::core
