// NURBS volume lattice (Hu et al. 2001, eq. 1-2) over an axis-aligned box.
#include "core/volume/lattice.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <Eigen/LU>

namespace sculpt::core {

namespace {

bool finite3(const Eigen::Vector3d& v) { return v.allFinite(); }

std::string axisName(int a) { return std::string(1, "uvw"[a]); }

// Non-zero basis values and derivatives along the three axes at t.
struct AxisBases {
    std::array<int, 3> span{};
    double value[3][kMaxDegree + 1] = {};
    double derivative[3][kMaxDegree + 1] = {};
};

AxisBases axisBases(const Lattice& lattice, const Eigen::Vector3d& params, bool withDerivatives) {
    AxisBases b;
    for (int a = 0; a < 3; ++a) {
        double local = 0.0;
        b.span[a] = lattice.axes[a].locate(params[a], local);
        lattice.axes[a].evaluate(b.span[a], local, b.value[a]);
        if (withDerivatives) lattice.axes[a].evaluateDerivative(b.span[a], local, b.derivative[a]);
    }
    return b;
}

}  // namespace

std::array<int, 3> gridIjk(const std::array<int, 3>& count, int idx) {
    return {idx % count[0], (idx / count[0]) % count[1], idx / (count[0] * count[1])};
}

std::array<int, 3> Lattice::ijk(int idx) const { return gridIjk(count, idx); }

std::string Lattice::controlPointName(int idx) const {
    if (volume && !volume->tensorNet()) return std::to_string(idx);
    const std::array<int, 3> c = ijk(idx);
    return "[" + std::to_string(c[0]) + "," + std::to_string(c[1]) + "," + std::to_string(c[2]) + "]";
}

Eigen::Vector3d Lattice::restControlPoint(int idx) const {
    if (volume) return volume->restControlPoints().row(idx).transpose();
    const std::array<int, 3> c = ijk(idx);
    Eigen::Vector3d p;
    for (int a = 0; a < 3; ++a) p[a] = boxMin[a] + axes[a].greville[c[a]] * (boxMax[a] - boxMin[a]);
    return boxTurned() ? Eigen::Vector3d(boxAxes.transpose() * p) : p;
}

Status turnBoxLattice(Lattice& lattice, const Eigen::Matrix3d& axes) {
    if (axes == Eigen::Matrix3d::Identity()) {  // not turned: any lattice
        lattice.boxAxes = axes;
        return Status::success();
    }
    if (lattice.volume) return Status::error("only a box lattice can be turned");
    if (!axes.allFinite() || !(axes * axes.transpose()).isIdentity(1e-12) || !(std::abs(axes.determinant() - 1.0) <= 1e-12))
        return Status::error("a lattice's box axes must be orthonormal and right-handed");
    lattice.boxAxes = axes;
    return Status::success();
}

void turnedBoxBounds(const Eigen::Matrix3d& axes, const Eigen::Vector3d& boxMin, const Eigen::Vector3d& boxMax, Eigen::Vector3d& lo,
                     Eigen::Vector3d& hi) {
    if (axes == Eigen::Matrix3d::Identity()) {
        lo = boxMin;
        hi = boxMax;
        return;
    }
    lo = Eigen::Vector3d::Constant(INFINITY);
    hi = Eigen::Vector3d::Constant(-INFINITY);
    for (int corner = 0; corner < 8; ++corner) {
        const Eigen::Vector3d b(corner & 1 ? boxMax[0] : boxMin[0], corner & 2 ? boxMax[1] : boxMin[1], corner & 4 ? boxMax[2] : boxMin[2]);
        const Eigen::Vector3d x = axes.transpose() * b;
        lo = lo.cwiseMin(x);
        hi = hi.cwiseMax(x);
    }
}

void worldBoxBounds(const Lattice& lattice, Eigen::Vector3d& lo, Eigen::Vector3d& hi) {
    turnedBoxBounds(lattice.boxAxes, lattice.boxMin, lattice.boxMax, lo, hi);
}

void deformationBounds(const Lattice& lattice, Eigen::Vector3d& lo, Eigen::Vector3d& hi) {
    worldBoxBounds(lattice, lo, hi);
    for (int idx : displacedControlPoints(lattice)) {
        lo = lo.cwiseMin(lattice.controlPoint(idx));
        hi = hi.cwiseMax(lattice.controlPoint(idx));
    }
}

Lattice unturnedLattice(const Lattice& lattice) {
    Lattice out = lattice;
    if (!lattice.boxTurned()) return out;
    out.displacement = lattice.displacement * lattice.boxAxes.transpose();  // rows (A delta)^T = delta^T A^T
    out.boxAxes.setIdentity();
    return out;
}

Status validateLatticeSettings(const LatticeSettings& s) {
    if (s.volume) {
        if (s.pinLayers < 0 || s.pinLayers > 3) return Status::error("pin_layers must be in [0, 3]");
        if (s.pinLayers == 0) return Status::success();
        for (int id = 0; id < s.volume->controlPointCount(); ++id)
            if (!s.volume->inSurfaceLayers(id, s.pinLayers)) return Status::success();
        return Status::error("pin_layers " + std::to_string(s.pinLayers) + " would pin every control point of the " +
                             s.volume->kindName() + " lattice");
    }
    for (int a = 0; a < 3; ++a) {
        if (s.degree[a] < kMinDegree || s.degree[a] > kMaxDegree)
            return Status::error("lattice degree along " + axisName(a) + " is " + std::to_string(s.degree[a]) +
                                 "; it must be in [1, 5]");
        if (s.resolution[a] < s.degree[a] + 1 || s.resolution[a] > kMaxControlPointsPerAxis)
            return Status::error("lattice resolution along " + axisName(a) + " is " + std::to_string(s.resolution[a]) +
                                 "; it must be in [degree+1 = " + std::to_string(s.degree[a] + 1) + ", 64]");
        if (2 * s.pinLayers >= s.resolution[a] && s.pinLayers > 0)
            return Status::error("pin_layers " + std::to_string(s.pinLayers) + " would pin every control point along " +
                                 axisName(a) + " (resolution " + std::to_string(s.resolution[a]) + ")");
    }
    if (!std::isfinite(s.padding) || s.padding < 0.0 || s.padding > 10.0)
        return Status::error("lattice padding must be a finite number in [0, 10]");
    if (s.pinLayers < 0 || s.pinLayers > 3) return Status::error("pin_layers must be in [0, 3]");
    if (s.hasRegion) {
        if (!finite3(s.regionMin) || !finite3(s.regionMax)) return Status::error("lattice region has a non-finite corner");
        for (int a = 0; a < 3; ++a)
            if (s.regionMin[a] > s.regionMax[a])
                return Status::error("lattice region min exceeds max along " + std::string(1, "xyz"[a]));
    }
    return Status::success();
}

Status latticeBox(const LatticeSettings& settings, const Positions& points, Eigen::Vector3d& boxMin, Eigen::Vector3d& boxMax) {
    if (Status s = validateLatticeSettings(settings); !s) return s;
    if (settings.volume) {
        boxMin = settings.volume->restBounds().min();
        boxMax = settings.volume->restBounds().max();
        return Status::success();
    }
    Eigen::Vector3d lo, hi;
    if (settings.hasRegion) {
        lo = settings.regionMin;
        hi = settings.regionMax;
    } else {
        if (points.rows() == 0) return Status::error("cannot place a lattice around an empty mesh");
        if (!points.allFinite()) return Status::error("mesh has non-finite vertex coordinates");
        lo = points.colwise().minCoeff().transpose();
        hi = points.colwise().maxCoeff().transpose();
    }
    const double diagonal = (hi - lo).norm();
    // note: a planar mesh has a zero extent and a single point has no extent at all; give each side a
    // minimum size so the parameter map stays finite and the lattice stays usable.
    const double minimumSide = diagonal > 0.0 ? 1e-3 * diagonal : 1.0;
    const double reference = diagonal > 0.0 ? diagonal : 1.0;
    for (int a = 0; a < 3; ++a) {
        const double centre = 0.5 * (lo[a] + hi[a]);
        const double half = 0.5 * std::max(hi[a] - lo[a], minimumSide) + settings.padding * reference;
        lo[a] = centre - half;
        hi[a] = centre + half;
    }
    if (!lo.allFinite() || !hi.allFinite()) return Status::error("the lattice box is not finite");
    boxMin = lo;
    boxMax = hi;
    return Status::success();
}

bool sameLatticeNet(const LatticeNet& a, const LatticeNet& b) {
    return a.count == b.count && a.degree == b.degree && a.multiplicity == b.multiplicity && a.knots == b.knots && a.rest == b.rest &&
           a.weights == b.weights && a.weldedTo == b.weldedTo;
}

bool sameVolume(const Volume& a, const Volume& b) {
    if (&a == &b) return true;
    if (a.tensorNet() || b.tensorNet()) return a.tensorNet() && b.tensorNet() && sameLatticeNet(*a.tensorNet(), *b.tensorNet());
    if (a.kindName() != b.kindName() || a.controlPointCount() != b.controlPointCount()) return false;
    if (a.restControlPoints() != b.restControlPoints() || a.controlWeights() != b.controlWeights()) return false;
    for (int id = 0; id < a.controlPointCount(); ++id)
        if (a.representativeOf(id) != b.representativeOf(id)) return false;
    return true;
}

std::array<int, 3> latticeCounts(const LatticeSettings& settings) {
    if (!settings.volume) return settings.resolution;
    if (const LatticeNet* net = settings.volume->tensorNet()) return net->count;
    return {settings.volume->controlPointCount(), 1, 1};
}

bool sameLatticeSettings(const LatticeSettings& a, const LatticeSettings& b) {
    if (a.volume || b.volume)
        return a.volume && b.volume && a.pinLayers == b.pinLayers && sameVolume(*a.volume, *b.volume);
    return a.resolution == b.resolution && a.degree == b.degree && a.padding == b.padding && a.hasRegion == b.hasRegion &&
           a.regionMin == b.regionMin && a.regionMax == b.regionMax && a.pinLayers == b.pinLayers;
}

Status makeLatticeInBox(const LatticeSettings& settings, const Eigen::Vector3d& boxMin, const Eigen::Vector3d& boxMax,
                        Lattice& out) {
    if (Status s = validateLatticeSettings(settings); !s) return s;
    if (settings.volume) {
        // A lattice of another kind is where its volume is; the box is its bounds (for sizes and the outside test).
        const Volume& volume = *settings.volume;
        Lattice lattice;
        lattice.volume = settings.volume;
        if (const LatticeNet* net = volume.tensorNet()) {
            lattice.count = net->count;
            lattice.degree = net->degree;
            lattice.axes = net->axes;
        } else {
            lattice.count = {volume.controlPointCount(), 1, 1};
        }
        lattice.boxMin = volume.restBounds().min();
        lattice.boxMax = volume.restBounds().max();
        lattice.weights = volume.controlWeights();
        lattice.rational = volume.isRational();
        const int n = lattice.controlPointCount();
        lattice.displacement = Positions::Zero(n, 3);
        lattice.pinned.assign(n, 0);
        for (int idx = 0; idx < n; ++idx) lattice.pinned[idx] = inOuterLayers(lattice, idx, settings.pinLayers) ? 1 : 0;
        // A weld group is one control point: pinned if any of its slots is.
        for (int idx = 0; idx < n; ++idx) lattice.pinned[lattice.representative(idx)] |= lattice.pinned[idx];
        for (int idx = 0; idx < n; ++idx) lattice.pinned[idx] = lattice.pinned[lattice.representative(idx)];
        out = std::move(lattice);
        return Status::success();
    }
    if (!boxMin.allFinite() || !boxMax.allFinite() || !(boxMin.array() < boxMax.array()).all())
        return Status::error("the lattice box must be finite with min < max on every axis");
    Lattice lattice;
    lattice.count = settings.resolution;
    lattice.degree = settings.degree;
    for (int a = 0; a < 3; ++a) lattice.axes[a] = makeSplineAxis(settings.resolution[a], settings.degree[a]);
    lattice.boxMin = boxMin;
    lattice.boxMax = boxMax;
    const int n = lattice.controlPointCount();
    lattice.weights.assign(n, 1.0);
    lattice.displacement = Positions::Zero(n, 3);
    lattice.pinned.assign(n, 0);
    for (int idx = 0; idx < n; ++idx) lattice.pinned[idx] = inOuterLayers(lattice, idx, settings.pinLayers) ? 1 : 0;
    out = std::move(lattice);
    return Status::success();
}

Status makeLattice(const LatticeSettings& settings, const Positions& points, Lattice& out) {
    Eigen::Vector3d lo, hi;
    if (Status s = latticeBox(settings, points, lo, hi); !s) return s;
    return makeLatticeInBox(settings, lo, hi, out);
}

bool restParameters(const Lattice& lattice, const Eigen::Vector3d& point, Eigen::Vector3d& params) {
    if (lattice.volume) return lattice.volume->freeze(point, params);
    return restParametersInBox(lattice, toBoxCoordinates(lattice, point), params);
}

bool restParametersInBox(const Lattice& lattice, const Eigen::Vector3d& point, Eigen::Vector3d& params) {
    Eigen::Vector3d t;
    for (int a = 0; a < 3; ++a) {
        if (!(point[a] >= lattice.boxMin[a] && point[a] <= lattice.boxMax[a])) return false;  // also rejects NaN
        // note: the faces map to exactly 0 and 1 (x - min is exact at x == min; at x == max the quotient of
        // two equal doubles is 1), and the clamp only guards the last ulp.
        t[a] = std::clamp((point[a] - lattice.boxMin[a]) / (lattice.boxMax[a] - lattice.boxMin[a]), 0.0, 1.0);
    }
    params = t;
    return true;
}

void supportWeights(const Lattice& lattice, const Eigen::Vector3d& params, SupportWeights& out) {
    if (lattice.volume) {
        const Volume& volume = *lattice.volume;
        volume.basisAt(params, out);
        if (volume.weldGroupList().empty()) return;
        // Coquillart 1990, 3.1.2: a weld group's basis function is the sum of its ids'.
        int kept = 0;
        for (int c = 0; c < out.count; ++c) {
            const int id = volume.representativeOf(out.index[c]);
            int found = -1;
            for (int d = 0; d < kept; ++d)
                if (out.index[d] == id) found = d;
            if (found >= 0) {
                out.weight[found] += out.weight[c];
            } else {
                out.index[kept] = id;
                out.weight[kept] = out.weight[c];
                ++kept;
            }
        }
        out.count = kept;
        return;
    }
    const AxisBases b = axisBases(lattice, params, false);
    const int nu = lattice.degree[0] + 1, nv = lattice.degree[1] + 1, nw = lattice.degree[2] + 1;
    out.count = 0;
    double sum = 0.0;
    for (int k = 0; k < nw; ++k)
        for (int j = 0; j < nv; ++j)
            for (int i = 0; i < nu; ++i) {
                const int idx = lattice.index(lattice.axes[0].first(b.span[0]) + i, lattice.axes[1].first(b.span[1]) + j, lattice.axes[2].first(b.span[2]) + k);
                const double w = lattice.weights[idx] * b.value[0][i] * b.value[1][j] * b.value[2][k];
                out.index[out.count] = idx;
                out.weight[out.count] = w;
                sum += w;
                ++out.count;
            }
    // Eq. 2's denominator; for unit weights it is 1 up to rounding and the division is skipped so the
    // polynomial case stays exactly the tensor-product B-spline.
    if (lattice.rational)
        for (int c = 0; c < out.count; ++c) out.weight[c] /= sum;
}

Eigen::Vector3d displacementAt(const Lattice& lattice, const Eigen::Vector3d& params) {
    SupportWeights support;
    supportWeights(lattice, params, support);
    Eigen::Vector3d d = Eigen::Vector3d::Zero();
    for (int c = 0; c < support.count; ++c) d += support.weight[c] * lattice.displacement.row(support.index[c]).transpose();
    return d;
}

Eigen::Vector3d layerImage(const Lattice& lattice, const Eigen::Vector3d& point) {
    Eigen::Vector3d t;
    return restParameters(lattice, point, t) ? Eigen::Vector3d(point + displacementAt(lattice, t)) : point;
}

Eigen::Vector3d restPoint(const Lattice& lattice, const Eigen::Vector3d& params) {
    if (!lattice.volume) return fromBoxCoordinates(lattice, lattice.boxMin + params.cwiseProduct(lattice.boxMax - lattice.boxMin));
    Eigen::Vector3d rest;
    lattice.volume->evaluate(lattice.volume->restControlPoints(), params, rest);
    return rest;
}

Eigen::Vector3d volumePoint(const Lattice& lattice, const Eigen::Vector3d& params) {
    SupportWeights support;
    supportWeights(lattice, params, support);
    Eigen::Vector3d q = Eigen::Vector3d::Zero();
    for (int c = 0; c < support.count; ++c) q += support.weight[c] * lattice.controlPoint(support.index[c]);
    return q;
}

void deformationJacobian(const Lattice& lattice, const Eigen::Vector3d& params, Eigen::Vector3d& displacement,
                         Eigen::Matrix3d& jacobian) {
    if (lattice.volume) {
        // x(X0) = X0 + D(t(X0)) with Q0(t(X0)) = X0, so dx/dX0 = I + dD/dt (dQ0/dt)^-1 = dQ/dt (dQ0/dt)^-1
        // (Coquillart 1990, 3.4: the frozen parameters are fixed while the net moves).
        const Volume& volume = *lattice.volume;
        // note: D = sum R delta is the same rational combination as Q0, so one evaluation of each suffices.
        Eigen::Vector3d rest;
        Eigen::Matrix3d restDerivative, displacementDerivative;
        volume.evaluate(volume.restControlPoints(), params, rest, &restDerivative);
        volume.evaluate(lattice.displacement, params, displacement, &displacementDerivative);
        // note: dQ0/dt is singular on a collapsed axis, pole or centre; where the displacement is locally constant
        // (an undeformed chunk) the Jacobian is I there too, without forming 0 * inf.
        if (displacementDerivative.isZero(0.0)) {
            jacobian.setIdentity();
            return;
        }
        jacobian = (restDerivative + displacementDerivative) * restDerivative.inverse();
        return;
    }
    const AxisBases b = axisBases(lattice, params, true);
    const int nu = lattice.degree[0] + 1, nv = lattice.degree[1] + 1, nw = lattice.degree[2] + 1;
    Eigen::Matrix3d dDisplacementDt;
    if (!lattice.rational) {
        // Contract the tensor product one axis at a time (w, then v, then u), carrying value and derivative:
        // about (p+1)^3 * 6 + (p+1)^2 * 9 + (p+1) * 12 multiply-adds instead of (p+1)^3 * 24. Newton's
        // inversion of a frame on undo calls this several times per moved vertex.
        double w0[kMaxDegree + 1][kMaxDegree + 1][3] = {}, w1[kMaxDegree + 1][kMaxDegree + 1][3] = {};
        for (int k = 0; k < nw; ++k)
            for (int j = 0; j < nv; ++j)
                for (int i = 0; i < nu; ++i) {
                    const double* d = &lattice.displacement(lattice.index(lattice.axes[0].first(b.span[0]) + i, lattice.axes[1].first(b.span[1]) + j, lattice.axes[2].first(b.span[2]) + k), 0);
                    for (int c = 0; c < 3; ++c) {
                        w0[i][j][c] += b.value[2][k] * d[c];
                        w1[i][j][c] += b.derivative[2][k] * d[c];
                    }
                }
        double v00[kMaxDegree + 1][3] = {}, v10[kMaxDegree + 1][3] = {}, v01[kMaxDegree + 1][3] = {};
        for (int j = 0; j < nv; ++j)
            for (int i = 0; i < nu; ++i)
                for (int c = 0; c < 3; ++c) {
                    v00[i][c] += b.value[1][j] * w0[i][j][c];
                    v10[i][c] += b.derivative[1][j] * w0[i][j][c];
                    v01[i][c] += b.value[1][j] * w1[i][j][c];
                }
        displacement.setZero();
        dDisplacementDt.setZero();
        for (int i = 0; i < nu; ++i)
            for (int c = 0; c < 3; ++c) {
                displacement[c] += b.value[0][i] * v00[i][c];
                dDisplacementDt(c, 0) += b.derivative[0][i] * v00[i][c];
                dDisplacementDt(c, 1) += b.value[0][i] * v10[i][c];
                dDisplacementDt(c, 2) += b.value[0][i] * v01[i][c];
            }
    } else {
        // Homogeneous sums: numerator N = sum W B B B delta, denominator D = sum W B B B, and their t-gradients.
        Eigen::Vector3d numerator = Eigen::Vector3d::Zero();
        Eigen::Matrix3d numeratorGrad = Eigen::Matrix3d::Zero();  // column a = dN/dt_a
        double denominator = 0.0;
        Eigen::Vector3d denominatorGrad = Eigen::Vector3d::Zero();
        for (int k = 0; k < nw; ++k)
            for (int j = 0; j < nv; ++j)
                for (int i = 0; i < nu; ++i) {
                    const int idx = lattice.index(lattice.axes[0].first(b.span[0]) + i, lattice.axes[1].first(b.span[1]) + j, lattice.axes[2].first(b.span[2]) + k);
                    const double w = lattice.weights[idx];
                    const double basis = b.value[0][i] * b.value[1][j] * b.value[2][k];
                    const Eigen::Vector3d grad(b.derivative[0][i] * b.value[1][j] * b.value[2][k],
                                               b.value[0][i] * b.derivative[1][j] * b.value[2][k],
                                               b.value[0][i] * b.value[1][j] * b.derivative[2][k]);
                    const Eigen::Vector3d delta = lattice.displacement.row(idx).transpose();
                    numerator += w * basis * delta;
                    numeratorGrad += w * delta * grad.transpose();
                    denominator += w * basis;
                    denominatorGrad += w * grad;
                }
        displacement = numerator / denominator;
        dDisplacementDt = (numeratorGrad - displacement * denominatorGrad.transpose()) / denominator;
    }
    const Eigen::Vector3d size = lattice.boxMax - lattice.boxMin;
    // dx/dX0 = I + dD/dt dt/db db/dX0.
    jacobian = worldJacobian(lattice, dDisplacementDt * size.cwiseInverse().asDiagonal());
}

double newtonPreimageInBox(const Lattice& lattice, const Eigen::Vector3d& target, Eigen::Vector3d& rest, Eigen::Vector3d& params,
                           double tolerance, double roundingLevel, int iterations) {
    const double diagonal = lattice.diagonal();
    const Eigen::Vector3d size = lattice.boxMax - lattice.boxMin;
    const auto evaluate = [&](const Eigen::Vector3d& at, Eigen::Vector3d& t, Eigen::Vector3d& residual, Eigen::Matrix3d& jacobian) {
        t = ((at - lattice.boxMin).cwiseQuotient(size)).cwiseMax(0.0).cwiseMin(1.0);
        Eigen::Vector3d displacement;
        deformationJacobian(lattice, t, displacement, jacobian);
        if (lattice.boxTurned()) jacobian = lattice.boxAxes * jacobian * lattice.boxAxes.transpose();
        residual = at + toBoxCoordinates(lattice, displacement) - target;
        return residual.norm();
    };
    Eigen::Vector3d residual;
    Eigen::Matrix3d jacobian;
    double r = evaluate(rest, params, residual, jacobian);
    for (int iteration = 0; iteration < iterations && r > tolerance; ++iteration) {
        const Eigen::Vector3d step = jacobian.partialPivLu().solve(residual);
        if (!step.allFinite()) break;
        double lambda = step.norm() > 0.25 * diagonal ? 0.25 * diagonal / step.norm() : 1.0;
        bool improved = false;
        for (int halving = 0; halving < (r > roundingLevel ? 40 : 1) && !improved; ++halving, lambda *= 0.5) {
            const Eigen::Vector3d candidate = (rest - lambda * step).cwiseMax(lattice.boxMin).cwiseMin(lattice.boxMax);
            Eigen::Vector3d candidateT, candidateResidual;
            Eigen::Matrix3d candidateJacobian;
            const double rc = evaluate(candidate, candidateT, candidateResidual, candidateJacobian);
            if (rc < r) {
                rest = candidate;
                r = rc;
                params = candidateT;
                residual = candidateResidual;
                jacobian = candidateJacobian;
                improved = true;
            }
        }
        if (!improved) break;  // at rounding level: as close as it gets from here
    }
    return r;
}

Status locateDeformedPoint(const Lattice& lattice, const Eigen::Vector3d& deformedPoint, Eigen::Vector3d& params,
                           double tolerance) {
    if (!finite3(deformedPoint)) return Status::error("point has non-finite coordinates");
    if (lattice.volume) {
        if (lattice.volume->locatorFor(lattice.volume->restControlPoints() + lattice.displacement)->freeze(deformedPoint, params))
            return Status::success();
        return Status::error("point (" + std::to_string(deformedPoint.x()) + ", " + std::to_string(deformedPoint.y()) + ", " +
                             std::to_string(deformedPoint.z()) + ") is not inside the deformed lattice");
    }
    const double diagonal = lattice.diagonal();
    // In box coordinates (a turned box: b = A x, the residual A (x + D) - A y, the Jacobian A J A^T). A strongly
    // bent layer (a brush stroke's region, a subdivided drag's lattice) sends a full step from y far past the
    // preimage: the fixed-point guess y - D(y) (off by |D| |grad D|) first.
    const Eigen::Vector3d target = toBoxCoordinates(lattice, deformedPoint);
    const Eigen::Vector3d clamped = target.cwiseMax(lattice.boxMin).cwiseMin(lattice.boxMax);
    Eigen::Vector3d t;
    restParametersInBox(lattice, clamped, t);
    const Eigen::Vector3d guess = clamped - toBoxCoordinates(lattice, displacementAt(lattice, t));
    const Eigen::Vector3d starts[2] = {guess.cwiseMax(lattice.boxMin).cwiseMin(lattice.boxMax), clamped};
    for (const Eigen::Vector3d& start : starts) {
        Eigen::Vector3d rest = start;
        if (newtonPreimageInBox(lattice, target, rest, t, tolerance * diagonal, 1e-13 * diagonal, 80) <= tolerance * diagonal) {
            params = t;
            return Status::success();
        }
    }
    return Status::error("point (" + std::to_string(deformedPoint.x()) + ", " + std::to_string(deformedPoint.y()) + ", " +
                         std::to_string(deformedPoint.z()) + ") is not inside the deformed lattice");
}

bool inOuterLayers(const std::array<int, 3>& count, const std::array<int, 3>& c, int layers) {
    for (int a = 0; a < 3; ++a)
        if (c[a] < layers || c[a] >= count[a] - layers) return true;
    return false;
}

bool inOuterLayers(const Lattice& lattice, int index, int layers) {
    if (!lattice.volume) return inOuterLayers(lattice.count, lattice.ijk(index), layers);
    return lattice.volume->inSurfaceLayers(index, layers);
}

bool inPinLayers(const LatticeSettings& settings, int index) {
    if (settings.volume) return settings.volume->inSurfaceLayers(index, settings.pinLayers);
    return inOuterLayers(settings.resolution, gridIjk(settings.resolution, index), settings.pinLayers);
}

Positions controlPointPositions(const Lattice& lattice) {
    Positions points(lattice.controlPointCount(), 3);
    for (int idx = 0; idx < lattice.controlPointCount(); ++idx) points.row(idx) = lattice.controlPoint(idx).transpose();
    return points;
}

std::vector<int> displacedControlPoints(const Lattice& lattice) {
    std::vector<int> ids;
    for (int idx = 0; idx < lattice.controlPointCount(); ++idx)
        if (!lattice.displacement.row(idx).isZero(0.0)) ids.push_back(idx);
    return ids;
}

bool boundaryUnmoved(const Lattice& lattice) {
    for (int idx : displacedControlPoints(lattice))
        if (lattice.volume ? lattice.volume->onOuterSurface(idx) : inOuterLayers(lattice, idx, 1)) return false;
    return true;
}

bool isUndeformed(const Lattice& lattice) {
    return (lattice.displacement.array() == 0.0).all();
}

std::vector<std::array<int, 2>> controlNetEdges(const Lattice& lattice) {
    std::vector<std::array<int, 2>> edges;
    if (lattice.volume) {
        for (const auto& e : lattice.volume->controlNetEdgeList()) {
            const int p = lattice.representative(e[0]), q = lattice.representative(e[1]);
            if (p != q) edges.push_back({std::min(p, q), std::max(p, q)});
        }
    } else {
        for (int idx = 0; idx < lattice.controlPointCount(); ++idx) {
            const std::array<int, 3> c = lattice.ijk(idx);
            for (int a = 0; a < 3; ++a) {
                if (c[a] + 1 >= lattice.count[a]) continue;
                std::array<int, 3> n = c;
                ++n[a];
                edges.push_back({idx, lattice.index(n[0], n[1], n[2])});
            }
        }
    }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    return edges;
}

std::vector<Positions> chunkEdgeCurves(const Lattice& lattice, int samplesPerSpan) {
    std::vector<Positions> curves;
    samplesPerSpan = std::max(samplesPerSpan, 1);
    const double tiny = 1e-12 * std::max(lattice.diagonal(), 1e-300);
    std::vector<std::array<Eigen::Vector3d, 2>> lines;
    if (lattice.volume) {
        lines = lattice.volume->chunkEdgeLines();
    } else {
        for (int a = 0; a < 3; ++a) {
            const int b = (a + 1) % 3, c = (a + 2) % 3;
            for (int kc = 0; kc <= lattice.axes[c].spans; ++kc)
                for (int kb = 0; kb <= lattice.axes[b].spans; ++kb) {
                    Eigen::Vector3d from, to;
                    from[a] = 0.0, to[a] = 1.0;
                    from[b] = to[b] = static_cast<double>(kb) / lattice.axes[b].spans;
                    from[c] = to[c] = static_cast<double>(kc) / lattice.axes[c].spans;
                    lines.push_back({from, to});
                }
        }
    }
    for (const auto& line : lines) {
        // Samples per chunk crossed: the line's extent in chunks, measured with chunkOf at its ends.
        // (a volume that is not one tensor product: 8 chunks' worth along every line)
        int spans = lattice.volume && !lattice.tensorNet() ? 8 : 1;
        const Eigen::Vector3d direction = line[1] - line[0];
        for (int a = 0; a < 3 && spans == 1; ++a)
            if (direction[a] != 0.0) spans = std::max(spans, static_cast<int>(std::lround(std::abs(direction[a]) * lattice.axes[a].spans)));
        const int samples = spans * samplesPerSpan;
        Positions curve(samples + 1, 3);
        double length = 0.0;
        for (int s = 0; s <= samples; ++s) {
            const Eigen::Vector3d t = line[0] + direction * (static_cast<double>(s) / samples);
            curve.row(s) = (restPoint(lattice, t) + displacementAt(lattice, t)).transpose();
            if (s > 0) length += (curve.row(s) - curve.row(s - 1)).norm();
        }
        if (length > tiny) curves.push_back(std::move(curve));
    }
    return curves;
}

}  // namespace sculpt::core
