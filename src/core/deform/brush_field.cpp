// The brush's pull field and its region lattice (brush_field.h).
#include "core/deform/brush_field.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <Eigen/Dense>

namespace sculpt::core {

double segmentDistance(const Eigen::Vector3d& x, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    const Eigen::Vector3d ab = b - a;
    const double length2 = ab.squaredNorm();
    const double s = length2 > 0.0 ? std::clamp((x - a).dot(ab) / length2, 0.0, 1.0) : 0.0;
    return (x - (a + s * ab)).norm();
}

Eigen::Vector3d sharedPullDirection(const std::vector<BrushPull>& pulls) {
    std::vector<Eigen::Vector3d> directions;
    for (const BrushPull& p : pulls)
        if (p.moving()) directions.push_back(p.pull.normalized());
    if (directions.empty()) return Eigen::Vector3d::Zero();
    if (directions.size() == 1) return directions.front();
    constexpr double kCosine = 0.9063077870366499;  // cos 25 degrees
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (size_t a = 0; a < directions.size(); ++a) {
        for (size_t b = a + 1; b < directions.size(); ++b)
            if (directions[a].dot(directions[b]) < kCosine) return Eigen::Vector3d::Zero();
        sum += directions[a];
    }
    return sum.normalized();
}

double brushFieldSlope(double pullLength, double radius) {
    // At most 0.7 (det J >= 0.3: margin for the spline's smoothing); steeper only where the ramp must end within 1.25 radius of the segment.
    return std::max(0.7, pullLength / (pullLength + 0.75 * radius));
}

double brushFieldProfile(BrushFalloff falloff, double x) {
    // The spline that carries the field smooths it over a knot span; a profile with a corner (sharp's peak) or an
    // unbounded slope (medium's rim) would be smoothed into a dip along the pull. Rounded there, within 0.1.
    x = std::clamp(x, 0.0, 1.0);
    switch (falloff) {
        case BrushFalloff::Smooth: return brushProfile(falloff, x);
        case BrushFalloff::Medium: return std::min(brushProfile(falloff, x), 6.0 * (1.0 - x));  // meets it at x = 35 / 37
        case BrushFalloff::Sharp: {
            // (1 - x)^2 beyond a, inside it the parabola through its value at a with the same peak: 1 at 0, no
            // scale. (A parabola meeting it with its slope peaks at 1 - a and needed the rest scaled by 1 / (1 - a),
            // which moved the whole bump 18% above the curve: 0.06-0.10 RMS.)
            constexpr double a = 0.25;
            return x >= a ? (1.0 - x) * (1.0 - x) : 1.0 - (2.0 / a - 1.0) * x * x;
        }
    }
    return 0.0;
}

double brushFieldWeight(const BrushPull& pull, double radius, BrushFalloff falloff, const Eigen::Vector3d& x) {
    const double length = pull.pull.norm();
    if (!(length > 0.0)) return 0.0;
    const Eigen::Vector3d e = pull.pull / length;
    const Eigen::Vector3d offset = x - pull.source;
    const double z = offset.dot(e);
    if (z <= 0.0) return brushFieldProfile(falloff, offset.norm() / radius);  // behind: the falloff of the rest distance
    const double lateral = (offset - z * e).norm();
    if (lateral >= radius) return 0.0;
    // Ahead: the least function above the falloff whose share falls by at most k / |d| per unit along e,
    // phi(z) = max over 0 <= z' <= z of f(|(lateral, z')| / r) - k (z - z') / |d|.
    const double k = brushFieldSlope(length, radius) / length;
    const auto h = [&](double at) { return brushFieldProfile(falloff, std::sqrt(lateral * lateral + at * at) / radius) + k * at; };
    constexpr int samples = 12;
    double best = h(z), bestAt = z;
    for (int i = 0; i < samples; ++i) {
        const double at = z * i / samples;
        const double value = h(at);
        if (value > best) {
            best = value;
            bestAt = at;
        }
    }
    // Golden-section refinement around the best sample (h is unimodal there for the falloff curves).
    double lo = std::max(0.0, bestAt - z / samples), hi = std::min(z, bestAt + z / samples);
    constexpr double golden = 0.6180339887498949;
    for (int i = 0; i < 12; ++i) {
        const double a = hi - golden * (hi - lo), b = lo + golden * (hi - lo);
        if (h(a) > h(b)) hi = b;
        else lo = a;
    }
    best = std::max(best, h(0.5 * (lo + hi)));
    return std::clamp(best - k * z, 0.0, 1.0);
}

namespace {
constexpr double kWideningShareTolerance = 0.02;  // the share above the falloff the column may keep ahead
constexpr double kWideningFall = 0.6;             // E falls by at most this per unit outward: d(l + E)/dl >= 0.4
constexpr double kWideningRatio = 2.0;            // E <= 2 l: nothing leaves the pull's line
constexpr double kWideningLateral = 0.85;         // in radii: E = 0 beyond (free points' supports reach 1.25)
constexpr double kWideningAxial = 1.25;           // in radii: E = 0 ahead beyond, ramped in from 1 radius
constexpr int kWideningLateralSpans = 50, kWideningAxialSpans = 40;
}  // namespace

double BrushWidening::widenedLateral(double lateral, double axial) const {
    if (empty() || !(axial > 0.0) || !(lateral > 0.0)) return lateral;
    const double li = lateral / lateralStep, zj = axial / axialStep;
    if (li >= lateralNodes - 1 || zj >= axialNodes - 1) return lateral;
    const int i = static_cast<int>(li), j = static_cast<int>(zj);
    const double t = li - i, s = zj - j;
    const auto at = [&](int a, int b) { return push[static_cast<size_t>(a + lateralNodes * b)]; };
    const double below = (1.0 - t) * at(i, j) + t * at(i + 1, j), above = (1.0 - t) * at(i, j + 1) + t * at(i + 1, j + 1);
    return lateral + (1.0 - s) * below + s * above;
}

BrushWidening brushWidening(const BrushPull& pull, double radius, BrushFalloff falloff) {
    BrushWidening out;
    if (!pull.moving() || !(radius > 0.0) || !std::isfinite(radius) || !pull.source.allFinite() || !pull.pull.allFinite()) return out;
    out.source = pull.source;
    out.direction = pull.pull.normalized();
    out.radius = radius;
    const Eigen::Vector3d across = out.direction.unitOrthogonal();
    const int nl = kWideningLateralSpans + 1, nz = kWideningAxialSpans + 1;
    const double dl = kBrushReach * radius / kWideningLateralSpans, dz = kWideningAxial * radius / kWideningAxialSpans;
    std::vector<double> push(static_cast<size_t>(nl * nz), 0.0), column(static_cast<size_t>(nl));
    double largest = 0.0;
    for (int j = 1; j < nz; ++j) {
        const double z = j * dz;
        for (int i = 0; i < nl; ++i)
            column[static_cast<size_t>(i)] = brushFieldWeight(pull, radius, falloff, pull.source + z * out.direction + (i * dl) * across);
        // 1 up to 1 radius ahead, falling smoothly to 0 at 1.25 radius.
        const double x = std::clamp((kWideningAxial * radius - z) / ((kWideningAxial - 1.0) * radius), 0.0, 1.0);
        const double ramp = x * x * (3.0 - 2.0 * x);
        // E*: the least l' >= l where the column's share (falling in l') is at most the falloff of the rest
        // distance, read linearly between the nodes; then the bounds, then the least E above it that falls by at
        // most kWideningFall per unit outward.
        double previous = 0.0;
        for (int i = 0; i < nl; ++i) {
            const double l = i * dl;
            const double target = brushFieldProfile(falloff, std::hypot(l, z) / radius) + kWideningShareTolerance;
            double needed = 0.0;
            if (column[static_cast<size_t>(i)] > target) {
                int m = i + 1;
                while (m < nl && column[static_cast<size_t>(m)] > target) ++m;
                const double hi = column[static_cast<size_t>(m - 1)], lo = m < nl ? column[static_cast<size_t>(m)] : 0.0;
                needed = (m - 1) * dl + dl * (hi - target) / std::max(hi - lo, 1e-300) - l;
            }
            needed = std::min({needed * ramp, kWideningRatio * l, kWideningFall * std::max(0.0, kWideningLateral * radius - l)});
            const double value = std::max({needed, previous - kWideningFall * dl, 0.0});
            push[static_cast<size_t>(i + nl * j)] = value;
            previous = value;
            largest = std::max(largest, value);
        }
    }
    if (!(largest > 0.01 * radius)) return out;  // a short pull: the column is the falloff ahead
    out.lateralNodes = nl;
    out.axialNodes = nz;
    out.lateralStep = dl;
    out.axialStep = dz;
    out.push = std::move(push);
    return out;
}

Status brushWideningDelta(const Lattice& region, const BrushWidening& widening, int axis, ControlDelta& out) {
    out = ControlDelta{};
    if (widening.empty()) return Status::success();
    if (axis != 0 && axis != 1) return Status::error("a widening layer moves along the region's first or second axis");
    const Eigen::Vector3d u = region.boxAxes.row(0).transpose(), v = region.boxAxes.row(1).transpose(), e = region.boxAxes.row(2).transpose();
    if (!(e.dot(widening.direction) > 1.0 - 1e-9)) return Status::error("the widening's region is not turned to its pull");
    // x_u (l' / l - 1): the radial map's component along u at lateral offset (a, b).
    const auto stretch = [&](double a, double b, double z) {
        const double l = std::hypot(a, b);
        return l > 0.0 ? a * (widening.widenedLateral(l, z) / l - 1.0) : 0.0;
    };
    std::vector<int> indices;
    std::vector<Eigen::Vector3d> moves;
    const int n = region.controlPointCount();
    for (int idx = 0; idx < n; ++idx) {
        if (region.pinned[static_cast<size_t>(idx)]) continue;
        const Eigen::Vector3d offset = region.restControlPoint(idx) - widening.source;
        const double a = offset.dot(u), b = offset.dot(v), z = offset.dot(e);
        double move = 0.0;
        if (axis == 0) {
            move = stretch(a, b, z);
        } else {
            // The point the first layer moved to (a, b): a0 + stretch(a0) = a, monotone in a0, |a0| <= |a|.
            double lo = -std::abs(a), hi = std::abs(a);
            for (int iteration = 0; iteration < 60 && hi - lo > 1e-15 * widening.radius; ++iteration) {
                const double mid = 0.5 * (lo + hi);
                if (mid + stretch(mid, b, z) < a) lo = mid;
                else hi = mid;
            }
            move = stretch(b, 0.5 * (lo + hi), z);  // symmetric in its two lateral arguments
        }
        if (move != 0.0) {
            indices.push_back(idx);
            moves.push_back(move * (axis == 0 ? u : v));
        }
    }
    out.indices = std::move(indices);
    out.deltas.resize(static_cast<Eigen::Index>(moves.size()), 3);
    for (size_t c = 0; c < moves.size(); ++c) out.deltas.row(static_cast<Eigen::Index>(c)) = moves[c].transpose();
    if (!out.deltas.allFinite()) return Status::error("the brush's widening is not finite");
    return Status::success();
}

int brushFieldSpansPerRadius(BrushFalloff falloff) { return falloff == BrushFalloff::Medium ? 12 : kBrushFieldSpansPerRadius; }

Status pullRegionLattice(const std::vector<BrushPull>& pulls, double radius, RegionLattice& out, int spansPerRadius) {
    if (!std::isfinite(radius) || radius <= 0.0) return Status::error("brush radius must be a finite number > 0");
    const double reach = kBrushReach * radius;
    std::vector<const BrushPull*> moving;
    for (const BrushPull& p : pulls) {
        if (!p.source.allFinite() || !p.pull.allFinite()) return Status::error("a brush pull has non-finite coordinates");
        if (p.moving()) moving.push_back(&p);
    }
    if (moving.empty()) return Status::error("a brush stroke needs a grabbed point that moves");
    RegionLattice region;
    // One moving pull: the box is turned so that its w axis is the pull. Along a parameter axis the spline's
    // derivative is a convex combination of the divided differences of its coefficients (de Boor), and those
    // of the field's samples at the Greville points are means of the field's own derivative along the pull:
    // det J = 1 + e . grad(u . e) keeps the field's bound for every falloff, however steep across the pull.
    // The box is also no larger than the capsule's: |d| + 2.5 r long, 2.5 r wide.
    // Several pulls sharing a direction (mirror images along the plane): turned to it alike.
    if (const Eigen::Vector3d shared = sharedPullDirection(pulls); shared.squaredNorm() > 0.0) {
        const Eigen::Vector3d e = moving.size() == 1 ? Eigen::Vector3d(moving.front()->pull.normalized()) : shared;
        const Eigen::Vector3d u = e.unitOrthogonal(), v = e.cross(u);
        region.axes.row(0) = u.transpose();
        region.axes.row(1) = v.transpose();
        region.axes.row(2) = e.transpose();
    }
    // The segments in box coordinates.
    std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> segments;
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = Eigen::Vector3d::Constant(-INFINITY);
    for (const BrushPull* p : moving) {
        const Eigen::Vector3d a = region.axes * p->source, b = region.axes * (p->source + p->pull);
        segments.emplace_back(a, b);
        lo = lo.cwiseMin(a.cwiseMin(b));
        hi = hi.cwiseMax(a.cwiseMax(b));
    }
    constexpr int degree = 3;
    region.settings.degree = {degree, degree, degree};
    region.settings.padding = 0.0;
    region.settings.pinLayers = 0;
    // One knot spacing for every axis (the field's derivative bound holds best on cubes), the finest of
    // 8 spans a radius that keeps every axis within 64 control points.
    double span = radius / std::max(spansPerRadius, 1);
    for (int a = 0; a < 3; ++a) span = std::max(span, (hi[a] - lo[a] + 2.0 * reach) / (kMaxControlPointsPerAxis - degree));
    for (int a = 0; a < 3; ++a) {
        const double extent = hi[a] - lo[a] + 2.0 * reach;
        const int spans = std::clamp(static_cast<int>(std::ceil(extent / span - 1e-9)), 1, kMaxControlPointsPerAxis - degree);
        const double width = spans * span;
        const double middle = 0.5 * (lo[a] + hi[a]);
        region.boxMin[a] = middle - 0.5 * width;
        region.boxMax[a] = middle + 0.5 * width;
        region.settings.resolution[a] = spans + degree;
    }
    std::array<SplineAxis, 3> axes;
    for (int a = 0; a < 3; ++a) axes[a] = makeSplineAxis(region.settings.resolution[a], degree);
    const std::array<int, 3> count = region.settings.resolution;
    for (int k = 0; k < count[2]; ++k)
        for (int j = 0; j < count[1]; ++j)
            for (int i = 0; i < count[0]; ++i) {
                const std::array<int, 3> c{i, j, k};
                Eigen::Vector3d supportLo, supportHi;
                for (int a = 0; a < 3; ++a) {
                    const double size = region.boxMax[a] - region.boxMin[a];
                    supportLo[a] = region.boxMin[a] + axes[a].knots[static_cast<size_t>(c[a])] * size;
                    supportHi[a] = region.boxMin[a] + axes[a].knots[static_cast<size_t>(c[a] + degree + 1)] * size;
                }
                // The distance to a segment is convex, so its largest value on the support box is at a corner.
                bool free = false;
                for (const auto& [a, b] : segments) {
                    bool inside = true;
                    for (int corner = 0; corner < 8 && inside; ++corner) {
                        const Eigen::Vector3d x(corner & 1 ? supportHi[0] : supportLo[0], corner & 2 ? supportHi[1] : supportLo[1],
                                                corner & 4 ? supportHi[2] : supportLo[2]);
                        // note: on the capsule's side the distance is the lateral one whatever the corner's w, so every
                        // point of a column along the pull must get the same answer; the grid is centred on the
                        // segment, and ties (a corner at exactly 1.25 r) fall on the inside instead of to rounding.
                        inside = segmentDistance(x, a, b) <= reach * (1.0 + 1e-9);
                    }
                    if (inside) {
                        free = true;
                        break;
                    }
                }
                if (free) region.freePoints.push_back(i + count[0] * (j + count[1] * k));
            }
    out = std::move(region);
    return Status::success();
}

Status brushFieldDelta(const Lattice& region, const std::vector<BrushPull>& pulls, double radius, BrushFalloff falloff,
                       ControlDelta& out, double& residual) {
    const int n = region.controlPointCount();
    std::vector<int> free;
    for (int idx = 0; idx < n; ++idx)
        if (!region.pinned[static_cast<size_t>(idx)]) free.push_back(idx);
    // Sources inside the region, with their parameters; a source outside it is where the layer is the identity.
    std::vector<size_t> constrained;
    std::vector<Eigen::Vector3d> params;
    for (size_t p = 0; p < pulls.size(); ++p) {
        Eigen::Vector3d t;
        if (restParameters(region, pulls[p].source, t)) {
            constrained.push_back(p);
            params.push_back(t);
        } else if (pulls[p].moving()) {
            return Status::error("a grabbed point lies outside its brush region");
        }
    }
    // Each moving pull's field at the free control points' Greville points, and its value at every source.
    std::vector<size_t> moving;
    for (size_t p = 0; p < pulls.size(); ++p)
        if (pulls[p].moving()) moving.push_back(p);
    const size_t m = moving.size();
    // Several pulls with a shared direction e: each field is taken along e (the pull's part along it), so
    // every one keeps its slope bound along the one axis the region is turned to.
    const Eigen::Vector3d shared = m > 1 ? sharedPullDirection(pulls) : Eigen::Vector3d::Zero();
    const bool joint = shared.squaredNorm() > 0.0;
    std::vector<Eigen::VectorXd> fields(m, Eigen::VectorXd::Zero(static_cast<Eigen::Index>(free.size())));
    for (size_t k = 0; k < m; ++k) {
        const BrushPull& p = pulls[moving[k]];
        const BrushPull along{p.source, joint ? Eigen::Vector3d(p.pull.dot(shared) * shared) : p.pull};
        for (size_t c = 0; c < free.size(); ++c)
            fields[k][static_cast<Eigen::Index>(c)] = brushFieldWeight(along, radius, falloff, region.restControlPoint(free[c]));
    }
    std::vector<int> slot(static_cast<size_t>(n), -1);
    for (size_t c = 0; c < free.size(); ++c) slot[static_cast<size_t>(free[c])] = static_cast<int>(c);
    // The basis at each constrained source (once: the scales and the correction read it), and each moving
    // pull's row among the constrained sources.
    std::vector<SupportWeights> supports(constrained.size());
    for (size_t i = 0; i < constrained.size(); ++i) supportWeights(region, params[i], supports[i]);
    std::vector<size_t> rowOf(m);
    for (size_t i = 0; i < m; ++i)
        rowOf[i] = static_cast<size_t>(std::find(constrained.begin(), constrained.end(), moving[i]) - constrained.begin());
    // The spline of free-point coefficients `coefficient(c)` at constrained source i, summed onto `sum` (a zero).
    const auto splineAt = [&](size_t i, auto sum, const auto& coefficient) {
        for (int s = 0; s < supports[i].count; ++s) {
            const int c = slot[static_cast<size_t>(supports[i].index[s])];
            if (c >= 0) sum += supports[i].weight[s] * coefficient(c);
        }
        return sum;
    };
    Positions dense = Positions::Zero(static_cast<Eigen::Index>(free.size()), 3);
    // Two pulls along one line in opposite directions, each source on the side it is pulled to (mirror images
    // pulled apart across their plane): one field along the line, u = S(t) a_side phi_side(x) e, with t the
    // signed distance along e from the midpoint of the sources, S = clamp(t / delta, -1, 1) (delta: half their
    // distance along e) and side the pull on t's side. Between the sources S rises and each side's phi rises
    // toward its source (it is the falloff of the distance there), beyond a source S = 1 and phi keeps its slope
    // bound, so e . grad(u . e) >= -k and det J >= 1 - k > 0 (brushFieldWeight): injective at any pull length,
    // where a sum of the two fields would meet each source less its neighbour's share, and scaling that up to
    // the pull folds the space beside close images at once.
    // The field `along` (per free point) along `line` for two pulls on that line: one scale (the quasi-interpolant
    // lowers a peak), least squares over the two sources; the correction below meets what is left.
    Eigen::Vector3d line = Eigen::Vector3d::Zero();
    const auto alongLine = [&](const Eigen::VectorXd& along) {
        double num = 0.0, den = 0.0;
        for (size_t i = 0; i < 2; ++i) {
            const double atSource = splineAt(rowOf[i], 0.0, [&](int c) { return along[c]; });
            num += atSource * pulls[moving[i]].pull.dot(line);
            den += atSource * atSource;
        }
        const double scale = den > 0.0 && std::isfinite(num / den) ? num / den : 1.0;
        for (size_t c = 0; c < free.size(); ++c) dense.row(static_cast<Eigen::Index>(c)) = (scale * along[static_cast<Eigen::Index>(c)]) * line.transpose();
    };
    bool opposed = false, converging = false;
    if (m == 2 && !joint) {
        const BrushPull& p0 = pulls[moving[0]];
        const BrushPull& p1 = pulls[moving[1]];
        line = p0.pull.normalized();
        const bool alongOneLine = line.dot(p1.pull.normalized()) <= -1.0 + 1e-9;
        opposed = alongOneLine && (p0.source - p1.source).dot(line) > 1e-9 * radius;
        converging = alongOneLine && (p1.source - p0.source).dot(line) > 1e-9 * radius;
    }
    if (converging) {
        // Two pulls along one line towards each other (mirror images pulled inward beside their plane, each at
        // distance h from the midpoint): each side's field is the falloff of the distance behind its source and,
        // ahead of it, the falloff of the lateral distance times a ramp that falls to 0 over
        // L = min(h, |d| + 0.75 r) (so the two ramps never overlap, and nothing beyond 1.25 r of the pull's segment
        // moves). At any point one side's field acts, rising towards its source from behind and falling by at most
        // 1 / L per unit ahead, so e . grad(u . e) >= -|d| / L and det J >= 1 - |d| / L > 0 while |d| < h: every
        // pull that stops short of the midpoint (the mirror plane) is injective, where the two fields summed, each
        // falling by up to k / |d| ahead, fold the space between them at once (k >= 0.7: 1 - 2k < 0).
        const BrushPull& p0 = pulls[moving[0]];
        const BrushPull& p1 = pulls[moving[1]];
        const double h = 0.5 * (p1.source - p0.source).dot(line);
        const auto side = [&](const BrushPull& p, const Eigen::Vector3d& e, const Eigen::Vector3d& x) {
            const Eigen::Vector3d offset = x - p.source;
            const double z = offset.dot(e), lateral = (offset - z * e).norm();
            if (z <= 0.0) return brushFieldProfile(falloff, offset.norm() / radius);
            const double ramp = std::min(h, p.pull.norm() + 0.75 * radius);
            return brushFieldProfile(falloff, lateral / radius) * std::max(0.0, 1.0 - z / ramp);
        };
        Eigen::VectorXd along = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(free.size()));
        for (size_t c = 0; c < free.size(); ++c) {
            const Eigen::Vector3d x = region.restControlPoint(free[c]);
            along[static_cast<Eigen::Index>(c)] = p0.pull.norm() * side(p0, line, x) - p1.pull.norm() * side(p1, -line, x);
        }
        alongLine(along);
    } else if (opposed) {
        const BrushPull& p0 = pulls[moving[0]];
        const BrushPull& p1 = pulls[moving[1]];
        const double middle = 0.5 * (p0.source + p1.source).dot(line), half = 0.5 * (p0.source - p1.source).dot(line);
        Eigen::VectorXd along = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(free.size()));
        for (size_t c = 0; c < free.size(); ++c) {
            const double t = region.restControlPoint(free[c]).dot(line) - middle;
            const double ramp = std::clamp(t / half, -1.0, 1.0);
            along[static_cast<Eigen::Index>(c)] =
                ramp * (t >= 0.0 ? p0.pull.norm() * fields[0][static_cast<Eigen::Index>(c)] : p1.pull.norm() * fields[1][static_cast<Eigen::Index>(c)]);
        }
        alongLine(along);
    } else if (joint) {
        // One field along the shared direction: the largest pull share at each point (max keeps every pull's
        // slope bound along e; a sum would add them). Each source's own pull is met where its field is largest;
        // what is across e and what the neighbour's field adds are left to the correction below.
        Eigen::VectorXd along = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(free.size()));
        for (size_t c = 0; c < free.size(); ++c)
            for (size_t k = 0; k < m; ++k)
                along[static_cast<Eigen::Index>(c)] = std::max(along[static_cast<Eigen::Index>(c)], fields[k][static_cast<Eigen::Index>(c)] * pulls[moving[k]].pull.dot(shared));
        // Two sources within half a radius (a point grabbed just beside a mirror plane and its image): the max
        // of their two bumps dips between them (to f(d / 2r) of the pull: 0.87 at d = 0.45 r), and the user sees
        // two peaks where they grabbed one. The field is the max over sources all along the segment between
        // them instead: a ridge, one bump. Each has the slope bound along e, so their max keeps it; each
        // vanishes beyond a radius of its segment, within 1.12 r of the two sources' (free as theirs are).
        if (m == 2 && (pulls[moving[0]].source - pulls[moving[1]].source).norm() <= kBrushBridgeDistance * radius) {
            const double share = 0.5 * (pulls[moving[0]].pull.dot(shared) + pulls[moving[1]].pull.dot(shared));
            constexpr int kBridgeSources = 7;
            for (int b = 1; b <= kBridgeSources; ++b) {
                const double s = static_cast<double>(b) / (kBridgeSources + 1);
                const BrushPull bridge{(1.0 - s) * pulls[moving[0]].source + s * pulls[moving[1]].source, share * shared};
                for (size_t c = 0; c < free.size(); ++c)
                    along[static_cast<Eigen::Index>(c)] =
                        std::max(along[static_cast<Eigen::Index>(c)], share * brushFieldWeight(bridge, radius, falloff, region.restControlPoint(free[c])));
            }
        }
        // One scale for the field (the quasi-interpolant lowers a peak), least squares over the moving sources'
        // pulls along e: mirror images are met exactly by it, the rest by the correction.
        double num = 0.0, den = 0.0;
        for (size_t i = 0; i < m; ++i) {
            const double atSource = splineAt(rowOf[i], 0.0, [&](int c) { return along[c]; });
            num += atSource * pulls[moving[i]].pull.dot(shared);
            den += atSource * atSource;
        }
        const double scale = den > 0.0 && std::isfinite(num / den) ? num / den : 1.0;
        for (size_t c = 0; c < free.size(); ++c) dense.row(static_cast<Eigen::Index>(c)) = (scale * along[static_cast<Eigen::Index>(c)]) * shared.transpose();
    } else {
        // Scales: each moving source's displacement along its own pull equals the pull's length; field k's
        // spline at a source is the quasi-interpolant's value (partition of unity).
        Eigen::MatrixXd a = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(m), static_cast<Eigen::Index>(m));
        Eigen::VectorXd b(static_cast<Eigen::Index>(m));
        for (size_t i = 0; i < m; ++i) {
            const Eigen::Vector3d e = pulls[moving[i]].pull.normalized();
            for (size_t k = 0; k < m; ++k)
                a(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(k)) =
                    splineAt(rowOf[i], 0.0, [&](int c) { return fields[k][c]; }) * pulls[moving[k]].pull.dot(e);
            b[static_cast<Eigen::Index>(i)] = pulls[moving[i]].pull.norm();
        }
        Eigen::VectorXd scale = Eigen::VectorXd::Ones(static_cast<Eigen::Index>(m));
        const Eigen::FullPivLU<Eigen::MatrixXd> lu(a);
        if (m > 0 && lu.rank() == static_cast<Eigen::Index>(m)) scale = lu.solve(b);
        if (!scale.allFinite()) scale = Eigen::VectorXd::Ones(static_cast<Eigen::Index>(m));
        for (size_t k = 0; k < m; ++k)
            dense += (scale[static_cast<Eigen::Index>(k)] * fields[k]) * pulls[moving[k]].pull.transpose();
    }
    // What the scales leave (held sources, crossing regions): the minimum-norm correction (Hu et al. eq. 12).
    const auto sourceResiduals = [&](Eigen::MatrixX3d& rows) {
        rows.resize(static_cast<Eigen::Index>(constrained.size()), 3);
        for (size_t i = 0; i < constrained.size(); ++i) {
            const Eigen::Vector3d moved = splineAt(i, Eigen::Vector3d(Eigen::Vector3d::Zero()), [&](int c) { return Eigen::Vector3d(dense.row(c).transpose()); });
            rows.row(static_cast<Eigen::Index>(i)) = (pulls[constrained[i]].pull - moved).transpose();
        }
    };
    Eigen::MatrixX3d rows;
    sourceResiduals(rows);
    if (rows.rows() > 0 && rows.rowwise().norm().maxCoeff() > 1e-13 * radius) {
        DirectManipulationData data;
        if (Status s = precomputeDirectManipulation(region, params, data); !s) return s;
        const DirectManipulationResult solved = solveDirectManipulation(data, rows);
        for (size_t c = 0; c < solved.delta.indices.size(); ++c) {
            const int at = slot[static_cast<size_t>(solved.delta.indices[c])];
            if (at >= 0) dense.row(at) += solved.delta.deltas.row(static_cast<Eigen::Index>(c));
        }
        sourceResiduals(rows);
    }
    residual = rows.rows() > 0 ? rows.rowwise().norm().maxCoeff() : 0.0;
    if (!dense.allFinite()) return Status::error("the brush field is not finite");
    out = ControlDelta{};
    for (size_t c = 0; c < free.size(); ++c)
        if (dense.row(static_cast<Eigen::Index>(c)).squaredNorm() > 0.0) out.indices.push_back(free[c]);
    out.deltas.resize(static_cast<Eigen::Index>(out.indices.size()), 3);
    for (size_t c = 0; c < out.indices.size(); ++c)
        out.deltas.row(static_cast<Eigen::Index>(c)) = dense.row(slot[static_cast<size_t>(out.indices[c])]);
    return Status::success();
}

}  // namespace sculpt::core
