// det(dQ/dt) of a net lattice chunk in Bernstein form, for the injectivity tests on lattices of any shape.
// J.E. Gain and N.A. Dodgson 2001, "Preventing self-intersection under free-form deformation" (seed 003),
// sections 5-6 (Theorem 1; det J in Bezier form per cell, subdivided), applied to the extended FFD lattices of
// S. Coquillart 1990, "Extended free-form deformation" (seed 004): the deformation of space is Q o Q0^-1, so
// its Jacobian is dQ/dt (dQ0/dt)^-1 and det J has the sign of det(dQ/dt) wherever the rest net is valid.
// Rational chunks use the homogeneous form (Piegl & Tiller, The NURBS Book, 4.2): the 4x4 determinant of
// [H_u, H_v, H_w, H] with H = (W Q, W) is W^4 det(dQ/dt), a polynomial, so no quotient is ever formed.
#include "core/injectivity/injectivity_net.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

#include <Eigen/LU>

namespace sculpt::core {

namespace {

constexpr int kMaxNetMinorCoefficients = (2 * kMaxDegree) * (2 * kMaxDegree) * (2 * kMaxDegree + 1);

int chunkSlot(const Lattice& lattice, const std::array<int, 3>& chunk, int i, int j, int k) {
    return lattice.index(lattice.axes[0].first(chunk[0]) + i, lattice.axes[1].first(chunk[1]) + j,
                         lattice.axes[2].first(chunk[2]) + k);
}

// The net face x_a = side collapsed along axis b: every line of the face along b is one weld group.
bool faceCollapsedAlong(const LatticeNet& net, int a, int side, int b) {
    const int c = 3 - a - b;
    const int ia = side == 0 ? 0 : net.count[a] - 1;
    for (int ic = 0; ic < net.count[c]; ++ic) {
        std::array<int, 3> ijk{};
        ijk[a] = ia, ijk[c] = ic, ijk[b] = 0;
        const int group = net.weldedTo[net.slot(ijk[0], ijk[1], ijk[2])];
        for (int ib = 1; ib < net.count[b]; ++ib) {
            ijk[b] = ib;
            if (net.weldedTo[net.slot(ijk[0], ijk[1], ijk[2])] != group) return false;
        }
    }
    return true;
}

// Column a (a < 3): the hodograph p_a S_a (b_{l+1} - b_l) along a, of each of `components` blocks; column 3
// (rational only): the Bezier points themselves. Returns the largest magnitude written.
double chunkColumn(const CellBezierBasis& basis, const BezierChunk& chunk, int a, int components, const double* bezier, double* column) {
    const BernsteinDegree& d = basis.degree;
    const int n0 = d[0] + 1, n1 = d[1] + 1;
    const int n = n0 * n1 * (d[2] + 1);
    double largest = 0.0;
    if (a == 3) {
        std::copy(bezier, bezier + components * n, column);
        for (int e = 0; e < components * n; ++e) largest = std::max(largest, std::abs(column[e]));
        return largest;
    }
    const BernsteinDegree cd = columnDegree(basis, a);
    const int count = bernsteinCoefficientCount(cd);
    const int stride[3] = {1, n0, n0 * n1};
    const double scale = static_cast<double>(d[a]) / chunk.parameterScale[a];
    for (int c = 0; c < components; ++c) {
        int out = 0;
        for (int k = 0; k <= cd[2]; ++k)
            for (int j = 0; j <= cd[1]; ++j)
                for (int i = 0; i <= cd[0]; ++i, ++out) {
                    const int at = c * n + i + n0 * (j + n1 * k);
                    const double value = scale * (bezier[at + stride[a]] - bezier[at]);
                    column[c * count + out] = value;
                    largest = std::max(largest, std::abs(value));
                }
    }
    return largest;
}

// det4[A, B, C, D] of four polynomial 4-vectors (columns; rows x, y, z, w) by Laplace expansion along the
// first two columns: sum over row pairs (i, j) of sign * (A_i B_j - A_j B_i) (C_k D_l - C_l D_k), (k, l) the
// complementary pair, sign that of the permutation (i, j, k, l). Columns in scaled (binomial) form, column
// e's component r at columns[e] + r * count(degree[e]). out: unscaled, degree the sum of the four.
void determinant4(const std::array<BernsteinDegree, 4>& degree, double* const columns[4], double* minors, double* out) {
    static constexpr int kPairs[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
    static constexpr int kComplement[6] = {5, 4, 3, 2, 1, 0};  // index of the complementary pair
    static constexpr double kSign[6] = {1.0, -1.0, 1.0, 1.0, -1.0, 1.0};
    int count[4];
    for (int e = 0; e < 4; ++e) count[e] = bernsteinCoefficientCount(degree[e]);
    BernsteinDegree ab{}, cd{}, total{};
    for (int a = 0; a < 3; ++a) {
        ab[a] = degree[0][a] + degree[1][a];
        cd[a] = degree[2][a] + degree[3][a];
        total[a] = ab[a] + cd[a];
    }
    const int nab = bernsteinCoefficientCount(ab), ncd = bernsteinCoefficientCount(cd);
    assert(nab <= kMaxNetMinorCoefficients && ncd <= kMaxNetMinorCoefficients);
    double* minorAB = minors;
    double* minorCD = minors + 6 * static_cast<size_t>(kMaxNetMinorCoefficients);
    for (int p = 0; p < 6; ++p) {
        const int i = kPairs[p][0], j = kPairs[p][1];
        double* m = minorAB + p * static_cast<size_t>(kMaxNetMinorCoefficients);
        std::fill(m, m + nab, 0.0);
        convolveAddScaled(columns[0] + i * count[0], degree[0], columns[1] + j * count[1], degree[1], 1.0, m);
        convolveAddScaled(columns[0] + j * count[0], degree[0], columns[1] + i * count[1], degree[1], -1.0, m);
        double* q = minorCD + p * static_cast<size_t>(kMaxNetMinorCoefficients);
        std::fill(q, q + ncd, 0.0);
        convolveAddScaled(columns[2] + i * count[2], degree[2], columns[3] + j * count[3], degree[3], 1.0, q);
        convolveAddScaled(columns[2] + j * count[2], degree[2], columns[3] + i * count[3], degree[3], -1.0, q);
    }
    std::fill(out, out + bernsteinCoefficientCount(total), 0.0);
    for (int p = 0; p < 6; ++p)
        convolveAddScaled(minorAB + p * static_cast<size_t>(kMaxNetMinorCoefficients), ab,
                          minorCD + kComplement[p] * static_cast<size_t>(kMaxNetMinorCoefficients), cd, kSign[p], out);
    unscaleFromBinomialForm(out, total);
}

}  // namespace

NetChunkWorkspace::NetChunkWorkspace()
    : columns(12 * kMaxCellControlPoints),
      scaled(16 * kMaxCellControlPoints),
      minors(12 * static_cast<size_t>(kMaxNetMinorCoefficients)),
      product(kMaxNetDeterminantCoefficients),
      scratch(3 * kMaxDeterminantCoefficients) {}

NetChunkBasis makeNetChunkBasis(const Lattice& lattice) {
    assert(lattice.tensorNet());
    const LatticeNet& net = *lattice.tensorNet();
    NetChunkBasis basis;
    basis.bezier = makeCellBezierBasis(lattice);
    basis.weldTolerance = 1e-9 * net.diagonal();
    if (!net.hasWelds) return basis;
    for (int a = 0; a < 3; ++a) {
        if (net.periodic[a]) continue;  // a seam is no face
        for (int side = 0; side < 2; ++side) {
            if (net.boundaryFace[a][side]) continue;
            int mask = 0;
            for (int b = 0; b < 3; ++b)
                if (b != a && faceCollapsedAlong(net, a, side, b)) mask |= 1 << b;
            basis.collapse[a][side] = mask;
        }
    }
    return basis;
}

int tensorChunkId(const NetChunkBasis& basis, const std::array<int, 3>& chunk) {
    return chunk[0] + basis.bezier.spans[0] * (chunk[1] + basis.bezier.spans[1] * chunk[2]);
}

void netChunkDeterminantBernstein(const Lattice& lattice, const NetChunkBasis& basis, const std::array<int, 3>& chunk,
                                  bool deformed, NetChunkWorkspace& work, double* determinant, NetChunkDeterminantInfo& info) {
    assert(lattice.tensorNet());
    chunkDeterminantBernstein(lattice, tensorChunkId(basis, chunk), basis.weldTolerance, deformed, work, determinant, info);
}

void chunkDeterminantBernstein(const Lattice& lattice, int chunkId, double weldTolerance, bool deformed, NetChunkWorkspace& work,
                               double* determinant, NetChunkDeterminantInfo& info) {
    assert(lattice.volume);
    info = NetChunkDeterminantInfo{};
    // The chunk in Bezier form, through the volume interface (volume.h): Euclidean points of a polynomial
    // chunk, homogeneous (W P, W) ones of a rational chunk.
    const Volume& volume = *lattice.volume;
    BezierChunk& bezier = work.chunk;
    volume.bezierChunk(chunkId, deformed ? &lattice.displacement : nullptr, bezier);
    CellBezierBasis bezierBasis;  // the column and determinant degrees below read only the degree
    bezierBasis.degree = bezier.degree;
    const BernsteinDegree& d = bezierBasis.degree;
    const int n0 = d[0] + 1, n1 = d[1] + 1, n2 = d[2] + 1;
    const int n = n0 * n1 * n2;
    const bool polynomial = bezier.polynomial;
    info.rational = !polynomial;
    const double* points = bezier.points.data();

    // Collapsed faces the chunk lies on, and whether their welded points still coincide (the face's Bezier
    // points along the collapsed direction, as Euclidean points).
    std::array<std::array<int, 2>, 3> divide{};
    for (int a = 0; a < 3; ++a)
        for (int side = 0; side < 2; ++side) {
            const int mask = bezier.collapse[a][side];
            if (mask == 0) continue;
            const int ia = side == 0 ? 0 : d[a];
            bool hold = true;
            for (int b = 0; b < 3 && hold; ++b) {
                if (!(mask & (1 << b))) continue;
                const int c = 3 - a - b;
                for (int ic = 0; ic <= d[c] && hold; ++ic)
                    for (int ib = 1; ib <= d[b] && hold; ++ib) {
                        std::array<int, 3> first{}, other{};
                        first[a] = other[a] = ia, first[c] = other[c] = ic, first[b] = 0, other[b] = ib;
                        const int e0 = first[0] + n0 * (first[1] + n1 * first[2]);
                        const int e1 = other[0] + n0 * (other[1] + n1 * other[2]);
                        for (int comp = 0; comp < 3; ++comp)
                            hold = hold && std::abs(points[comp * n + e1] / points[3 * n + e1] - points[comp * n + e0] / points[3 * n + e0]) <=
                                               weldTolerance;
                    }
            }
            if (hold)
                divide[a][side] = collapseOrder(mask);
            else
                info.weldsHold = false;
        }

    BernsteinDegree degree{};
    if (polynomial) {
        // det(dQ/dt) = Q_u . (Q_v x Q_w): the box lattice's product, on the chunk's own hodographs.
        double* const columns[3] = {work.columns.data(), work.columns.data() + 4 * kMaxCellControlPoints,
                                    work.columns.data() + 8 * kMaxCellControlPoints};
        double bound = 6.0;
        for (int a = 0; a < 3; ++a) bound *= chunkColumn(bezierBasis, bezier, a, 3, points, columns[a]);
        cellDeterminantBernstein(bezierBasis, columns, work.scratch.data(), work.product.data());
        degree = determinantDegree(bezierBasis);
        info.termBound = bound;
    } else {
        // Homogeneous points (W P, W): det4[H_u, H_v, H_w, H] = W^4 det(dQ/dt).
        std::array<BernsteinDegree, 4> degrees{columnDegree(bezierBasis, 0), columnDegree(bezierBasis, 1),
                                               columnDegree(bezierBasis, 2), d};
        double bound = 24.0;
        double* const scaled[4] = {work.scaled.data(), work.scaled.data() + 4 * kMaxCellControlPoints,
                                   work.scaled.data() + 8 * kMaxCellControlPoints,
                                   work.scaled.data() + 12 * kMaxCellControlPoints};
        for (int a = 0; a < 4; ++a) {
            bound *= chunkColumn(bezierBasis, bezier, a, 4, points, scaled[a]);
            const int count = bernsteinCoefficientCount(degrees[a]);
            for (int c = 0; c < 4; ++c) scaleToBinomialForm(scaled[a] + c * count, degrees[a]);
        }
        determinant4(degrees, scaled, work.minors.data(), work.product.data());
        for (int a = 0; a < 3; ++a) degree[a] = 4 * d[a] - 1;
        info.termBound = bound;
    }

    // Divide out the collapsed faces' factors x_a^m or (1 - x_a)^m, exactly (Bernstein form).
    double* current = work.product.data();
    double* other = determinant;
    for (int a = 0; a < 3; ++a)
        for (int side = 0; side < 2; ++side) {
            const int m = divide[a][side];
            if (m == 0) continue;
            if (degree[a] - m < 0) {
                info.weldsHold = false;  // cannot happen for a valid net: a chunk collapsed on both sides
                continue;
            }
            info.termBound *= divideBernsteinByFace(current, degree, a, side, m, other);
            degree[a] -= m;
            info.divided[a][side] = m;
            std::swap(current, other);
        }
    if (current != determinant) std::copy(current, current + bernsteinCoefficientCount(degree), determinant);
    info.degree = degree;
}

BernsteinTensor netChunkDeterminantBernstein(const Lattice& lattice, const std::array<int, 3>& chunk, bool deformed,
                                             NetChunkDeterminantInfo* info) {
    const NetChunkBasis basis = makeNetChunkBasis(lattice);
    NetChunkWorkspace work;
    std::vector<double> coefficients(kMaxNetDeterminantCoefficients);
    NetChunkDeterminantInfo built;
    netChunkDeterminantBernstein(lattice, basis, chunk, deformed, work, coefficients.data(), built);
    BernsteinTensor out(built.degree);
    std::copy(coefficients.begin(), coefficients.begin() + bernsteinCoefficientCount(built.degree), out.coefficients.begin());
    if (info) *info = built;
    return out;
}

void netChunkDerivatives(const Lattice& lattice, const std::array<int, 3>& chunk, const Eigen::Vector3d& local,
                         Eigen::Matrix3d& restDerivative, Eigen::Matrix3d& displacementDerivative) {
    assert(lattice.tensorNet());
    const LatticeNet& net = *lattice.tensorNet();
    double value[3][kMaxDegree + 1], derivative[3][kMaxDegree + 1];
    for (int a = 0; a < 3; ++a) {
        lattice.axes[a].evaluate(chunk[a], local[a], value[a]);
        lattice.axes[a].evaluateDerivative(chunk[a], local[a], derivative[a]);
    }
    // Homogeneous sums N = sum W B P (rest and displacement), W = sum W B, and their t-gradients.
    Eigen::Vector3d restSum = Eigen::Vector3d::Zero(), displacementSum = Eigen::Vector3d::Zero();
    Eigen::Matrix3d restGrad = Eigen::Matrix3d::Zero(), displacementGrad = Eigen::Matrix3d::Zero();
    double weightSum = 0.0;
    Eigen::Vector3d weightGrad = Eigen::Vector3d::Zero();
    for (int k = 0; k <= lattice.degree[2]; ++k)
        for (int j = 0; j <= lattice.degree[1]; ++j)
            for (int i = 0; i <= lattice.degree[0]; ++i) {
                const int s = chunkSlot(lattice, chunk, i, j, k);
                const double w = lattice.weights[s];
                const double basisValue = w * value[0][i] * value[1][j] * value[2][k];
                const Eigen::Vector3d grad = w * Eigen::Vector3d(derivative[0][i] * value[1][j] * value[2][k],
                                                                 value[0][i] * derivative[1][j] * value[2][k],
                                                                 value[0][i] * value[1][j] * derivative[2][k]);
                const Eigen::Vector3d p = net.rest.row(s).transpose();
                const Eigen::Vector3d delta = lattice.displacement.row(s).transpose();
                restSum += basisValue * p;
                displacementSum += basisValue * delta;
                restGrad += p * grad.transpose();
                displacementGrad += delta * grad.transpose();
                weightSum += basisValue;
                weightGrad += grad;
            }
    restDerivative = (restGrad - (restSum / weightSum) * weightGrad.transpose()) / weightSum;
    displacementDerivative = (displacementGrad - (displacementSum / weightSum) * weightGrad.transpose()) / weightSum;
}

namespace {

// The turn of a plane polynomial curve with control vectors v[0..degree] round the origin: split by de
// Casteljau until the control vectors fit in an open half-plane (then the curve stays in their cone, never
// meets the origin, and turns by the angle from its first vector to its last).
bool addCurveTurn(const Eigen::Vector2d* v, int degree, int depth, double& angle) {
    double largest = 0.0;
    for (int m = 0; m <= degree; ++m) largest = std::max(largest, v[m].norm());
    double lo = 0.0, hi = 0.0, last = 0.0;
    bool fits = largest > 0.0;
    for (int m = 0; m <= degree && fits; ++m) {
        if (!(v[m].norm() > 1e-12 * largest)) {
            fits = false;
            break;
        }
        const double relative = std::atan2(v[0].x() * v[m].y() - v[0].y() * v[m].x(), v[0].dot(v[m]));
        lo = std::min(lo, relative);
        hi = std::max(hi, relative);
        last = relative;
    }
    if (fits && hi - lo < 3.14159265358979323846 - 1e-9) {
        angle += last;
        return true;
    }
    if (depth >= 12 || !(largest > 0.0)) return false;
    Eigen::Vector2d work[kMaxDegree + 1], left[kMaxDegree + 1], right[kMaxDegree + 1];
    for (int m = 0; m <= degree; ++m) work[m] = v[m];
    for (int r = 0; r <= degree; ++r) {
        left[r] = work[0];
        right[degree - r] = work[degree - r];
        for (int m = 0; m < degree - r; ++m) work[m] = 0.5 * (work[m] + work[m + 1]);
    }
    return addCurveTurn(left, degree, depth + 1, angle) && addCurveTurn(right, degree, depth + 1, angle);
}

// The value at 0.5 of the univariate Bernstein polynomial of `degree` with coefficients at base + o * stride,
// and (derivative != nullptr) its derivative there.
double bernsteinLineAtHalf(const double* base, int stride, int degree, double* derivative) {
    double coefficients[kMaxDegree + 1], differences[kMaxDegree + 1];
    for (int o = 0; o <= degree; ++o) coefficients[o] = base[o * stride];
    if (derivative) {
        for (int o = 0; o < degree; ++o) differences[o] = degree * (coefficients[o + 1] - coefficients[o]);
        *derivative = degree > 0 ? evaluateBernstein1(differences, degree - 1, 0.5) : 0.0;
    }
    return evaluateBernstein1(coefficients, degree, 0.5);
}

}  // namespace

bool netRingWinding(const Lattice& lattice, const NetChunkBasis& basis, const std::array<int, 3>& chunk, int axis, int side,
                    NetChunkWorkspace& work, double& turns) {
    assert(lattice.tensorNet());
    bool closed = false;
    return chunkRingWinding(lattice, tensorChunkId(basis, chunk), axis, side, basis.weldTolerance, work, turns, closed);
}

bool chunkRingWinding(const Lattice& lattice, int chunkId, int axis, int side, double weldTolerance, NetChunkWorkspace& work,
                      double& turns, bool& closed) {
    assert(lattice.volume);
    const Volume& volume = *lattice.volume;
    const int a = axis;
    volume.bezierChunk(chunkId, &lattice.displacement, work.chunk);
    const int mask = work.chunk.collapse[a][side];
    if (collapseOrder(mask) != 1) return false;
    const int b = (mask & 1) ? 0 : ((mask & 2) ? 1 : 2), c = 3 - a - b;
    const BernsteinDegree d = work.chunk.degree;
    const int n0 = d[0] + 1, n1 = d[1] + 1;
    const int n = n0 * n1 * (d[2] + 1);
    const int stride[3] = {1, n0, n0 * n1};
    const int layer0 = side == 0 ? 0 : d[a], layer1 = side == 0 ? 1 : d[a] - 1;
    std::vector<int> row;
    volume.chunksAlong(chunkId, b, row, closed);
    const int spansB = static_cast<int>(row.size());
    // Per chunk along b: the homogeneous Bezier points of the face layer and the next one, at the middle
    // along c (4 components each, d[b] + 1 of them).
    Eigen::Vector4d face[kMaxDegree + 1], next[kMaxDegree + 1];
    Eigen::Vector3d base = Eigen::Vector3d::Zero(), tangent = Eigen::Vector3d::Zero();
    std::vector<std::array<Eigen::Vector3d, kMaxDegree + 1>> ring(static_cast<size_t>(spansB));
    for (int jb = 0; jb < spansB; ++jb) {
        // Homogeneous Bezier points (a polynomial chunk's have W = 1).
        volume.bezierChunk(row[static_cast<size_t>(jb)], &lattice.displacement, work.chunk);
        if (work.chunk.degree != d) return false;
        double slopes[4] = {0.0, 0.0, 0.0, 0.0};  // d/dx_c of the first face point's components (first piece)
        for (int m = 0; m <= d[b]; ++m) {
            const int start0 = layer0 * stride[a] + m * stride[b], start1 = layer1 * stride[a] + m * stride[b];
            for (int comp = 0; comp < 4; ++comp) {
                const double* block = work.chunk.points.data() + comp * n;
                face[m][comp] = bernsteinLineAtHalf(block + start0, stride[c], d[c], jb == 0 && m == 0 ? &slopes[comp] : nullptr);
                next[m][comp] = bernsteinLineAtHalf(block + start1, stride[c], d[c], nullptr);
            }
        }
        if (jb == 0) {
            // The collapsed line A = N / W along c; A' is parallel to N' W - N W'.
            base = face[0].head<3>() / face[0][3];
            tangent = Eigen::Vector3d(slopes[0], slopes[1], slopes[2]) * face[0][3] - face[0].head<3>() * slopes[3];
        }
        // Every face point is the same point A (the face is collapsed along b); the ring vectors are
        // H1.xyz - H1.w A (a positive multiple of dQ/dx_a, up to the side's sign, as a polynomial curve).
        for (int m = 0; m <= d[b]; ++m) {
            if (!((face[m].head<3>() / face[m][3] - base).norm() <= weldTolerance)) return false;
            ring[static_cast<size_t>(jb)][static_cast<size_t>(m)] = next[m].head<3>() - next[m][3] * base;
        }
    }
    if (!(tangent.norm() > 0.0) || !tangent.allFinite()) return false;
    const Eigen::Vector3d normal = tangent.normalized();
    const Eigen::Vector3d helper = std::abs(normal.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
    const Eigen::Vector3d e1 = (helper - helper.dot(normal) * normal).normalized();
    const Eigen::Vector3d e2 = normal.cross(e1);
    double angle = 0.0;
    for (int jb = 0; jb < spansB; ++jb) {
        Eigen::Vector2d plane[kMaxDegree + 1];
        for (int m = 0; m <= d[b]; ++m) {
            const Eigen::Vector3d& v = ring[static_cast<size_t>(jb)][static_cast<size_t>(m)];
            plane[m] = Eigen::Vector2d(v.dot(e1), v.dot(e2));
        }
        if (!addCurveTurn(plane, d[b], 0, angle)) return false;
    }
    turns = angle / (2.0 * 3.14159265358979323846);
    return std::isfinite(turns);
}

namespace {

// det J near a collapsed face, where det(dQ0/dt) is too small for the plain ratio det / restDet: the ratio of
// the face-divided determinant polynomials of the chunk (deformed over rest; both carry the same factors W^4
// and face powers, so their ratio is det J's limit), else the plain ratio if finite, else 0.
double collapsedFaceRatio(const Lattice& lattice, int chunkId, double weldTolerance, const Eigen::Vector3d& local, double det,
                          double restDet) {
    // note: one workspace per thread, so points on the axis of a big mesh cost two chunk polynomials each,
    // without allocating.
    thread_local NetChunkWorkspace work;
    thread_local std::vector<double> restPolynomial(kMaxNetDeterminantCoefficients), polynomial(kMaxNetDeterminantCoefficients);
    NetChunkDeterminantInfo restInfo, info;
    chunkDeterminantBernstein(lattice, chunkId, weldTolerance, false, work, restPolynomial.data(), restInfo);
    chunkDeterminantBernstein(lattice, chunkId, weldTolerance, true, work, polynomial.data(), info);
    const Eigen::Vector3d x = local.cwiseMax(0.0).cwiseMin(1.0);
    if (restInfo.weldsHold && info.weldsHold && restInfo.degree == info.degree) {
        const double restValue = evaluateBernstein(restPolynomial.data(), restInfo.degree, x);
        const double value = evaluateBernstein(polynomial.data(), info.degree, x);
        if (restValue > 0.0 && std::isfinite(value / restValue)) return value / restValue;
    }
    const double ratio = det / restDet;
    return std::isfinite(ratio) ? ratio : 0.0;
}

}  // namespace

double netJacobianDeterminantInChunk(const Lattice& lattice, const std::array<int, 3>& chunk, const Eigen::Vector3d& local) {
    assert(lattice.tensorNet());
    if (cellIsUndeformed(lattice, chunk)) return 1.0;
    Eigen::Matrix3d rest, displacement;
    netChunkDerivatives(lattice, chunk, local, rest, displacement);
    const double restDet = rest.determinant();
    const double det = (rest + displacement).determinant();
    const double diagonal = lattice.tensorNet()->diagonal();
    // note: dQ0/dt is of the size of the net (t spans [0,1]), so det(dQ0/dt) ~ diagonal^3 away from a
    // collapsed face and falls linearly (or quadratically) towards it; below 1e-8 of that the plain ratio of
    // two small determinants loses digits, and on the face it is 0 / 0.
    if (std::abs(restDet) > 1e-8 * diagonal * diagonal * diagonal) return det / restDet;
    const std::array<int, 3> spans = lattice.spans();
    return collapsedFaceRatio(lattice, chunk[0] + spans[0] * (chunk[1] + spans[1] * chunk[2]), 1e-9 * diagonal, local, det, restDet);
}

double chunkJacobianDeterminant(const Lattice& lattice, int chunkId, const Eigen::Vector3d& local) {
    assert(lattice.volume);
    if (const LatticeNet* net = lattice.tensorNet()) return netJacobianDeterminantInChunk(lattice, net->chunkIjk(chunkId), local);
    const Volume& volume = *lattice.volume;
    thread_local std::vector<int> support;
    volume.chunkSupport(chunkId, support);
    if (std::all_of(support.begin(), support.end(), [&](int id) { return lattice.displacement.row(id).isZero(0.0); })) return 1.0;
    const Eigen::Vector3d x = local.cwiseMax(0.0).cwiseMin(1.0);
    const Eigen::Vector3d t = volume.chunkParameters(chunkId, x);
    Eigen::Vector3d value;
    Eigen::Matrix3d rest, displacement;
    volume.evaluate(volume.restControlPoints(), t, value, &rest);
    volume.evaluate(lattice.displacement, t, value, &displacement);
    const double restDet = rest.determinant();
    const double det = (rest + displacement).determinant();
    const double diagonal = volume.restBounds().diagonal().norm();
    if (std::abs(restDet) > 1e-8 * diagonal * diagonal * diagonal) return det / restDet;
    return collapsedFaceRatio(lattice, chunkId, 1e-9 * diagonal, local, det, restDet);
}

}  // namespace sculpt::core
