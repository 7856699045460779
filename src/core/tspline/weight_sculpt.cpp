#include "core/tspline/weight_sculpt.h"

#include <cmath>
#include <cstdio>
#include <vector>

#include <Eigen/Geometry>

namespace sculpt::core {

double bumpHeight(const BumpSums& sums, size_t c, const Eigen::Vector3d& direction, double beta, double lambda, double mu) {
    const double numerator = direction.dot(sums.othersDisplacement[c]) +
                             beta * (lambda * direction.dot(sums.ownDisplacement[c]) + mu * sums.own[c]);
    return numerator / (sums.others[c] + beta * sums.own[c]);
}

void bumpHeights(const BumpSums& sums, const Eigen::Vector3d& direction, double beta, double lambda, double mu,
                 std::vector<double>& out) {
    out.resize(sums.vertices.size());
    for (size_t c = 0; c < sums.vertices.size(); ++c) out[c] = bumpHeight(sums, c, direction, beta, lambda, mu);
}

double areaAtOrAbove(const Eigen::Vector3d& x0, const Eigen::Vector3d& x1, const Eigen::Vector3d& x2, double h0, double h1, double h2,
                     double level) {
    // Sutherland-Hodgman against the half-plane h >= level (h linear on the triangle).
    const Eigen::Vector3d x[3] = {x0, x1, x2};
    const double f[3] = {h0 - level, h1 - level, h2 - level};
    Eigen::Vector3d polygon[4];
    int count = 0;
    for (int i = 0; i < 3; ++i) {
        const int j = (i + 1) % 3;
        if (f[i] >= 0.0) polygon[count++] = x[i];
        if ((f[i] >= 0.0) != (f[j] >= 0.0)) {
            const double s = f[i] / (f[i] - f[j]);
            polygon[count++] = x[i] + s * (x[j] - x[i]);
        }
    }
    if (count < 3) return 0.0;
    Eigen::Vector3d twiceArea = Eigen::Vector3d::Zero();
    for (int k = 1; k + 1 < count; ++k) twiceArea += (polygon[k] - polygon[0]).cross(polygon[k + 1] - polygon[0]);
    return 0.5 * twiceArea.norm();
}

double equivalentDiameter(const Positions& rest, const Triangles& triangles, const std::vector<int>& triangleIds,
                          const std::vector<double>& heights, double level) {
    double area = 0.0;
    for (int f : triangleIds) {
        const int a = triangles(f, 0), b = triangles(f, 1), c = triangles(f, 2);
        area += areaAtOrAbove(rest.row(a).transpose(), rest.row(b).transpose(), rest.row(c).transpose(), heights[static_cast<size_t>(a)],
                              heights[static_cast<size_t>(b)], heights[static_cast<size_t>(c)], level);
    }
    return 2.0 * std::sqrt(area / M_PI);
}

Status solveCrimpFactor(const std::function<double(double)>& width, double target, double betaMin, double betaMax, double& beta) {
    // The width need not be monotone in beta (the rest surface moves with the weights too), so the factors
    // are scanned on a log grid first, and the bracket nearest beta = 1 is bisected.
    const int steps = 48;
    const double lo = std::log(betaMin), hi = std::log(betaMax);
    std::vector<double> logs(steps + 1), widths(steps + 1);
    double least = INFINITY, most = -INFINITY;
    for (int k = 0; k <= steps; ++k) {
        logs[static_cast<size_t>(k)] = lo + (hi - lo) * k / steps;
        widths[static_cast<size_t>(k)] = width(std::exp(logs[static_cast<size_t>(k)]));
        least = std::min(least, widths[static_cast<size_t>(k)]);
        most = std::max(most, widths[static_cast<size_t>(k)]);
    }
    int bracket = -1;
    for (int k = 0; k < steps; ++k) {
        const double a = widths[static_cast<size_t>(k)] - target, b = widths[static_cast<size_t>(k) + 1] - target;
        if ((a <= 0.0) != (b <= 0.0) || a == 0.0) {
            const double distance = std::min(std::abs(logs[static_cast<size_t>(k)]), std::abs(logs[static_cast<size_t>(k) + 1]));
            if (bracket < 0 || distance < std::min(std::abs(logs[static_cast<size_t>(bracket)]), std::abs(logs[static_cast<size_t>(bracket) + 1])))
                bracket = k;
        }
    }
    if (bracket < 0) {
        char text[200];
        std::snprintf(text, sizeof text, "widths from %.4g to %.4g can be reached by these control points' weights (x%g to x%g), not %.4g", least,
                      most, betaMin, betaMax, target);
        return Status::error(text);
    }
    double a = logs[static_cast<size_t>(bracket)], b = logs[static_cast<size_t>(bracket) + 1];
    const bool rising = widths[static_cast<size_t>(bracket)] <= target;
    for (int iteration = 0; iteration < 100; ++iteration) {
        const double mid = 0.5 * (a + b);
        const double w = width(std::exp(mid));
        if (std::abs(w - target) <= 1e-6 * target) {
            beta = std::exp(mid);
            return Status::success();
        }
        ((w < target) == rising ? a : b) = mid;
    }
    beta = std::exp(0.5 * (a + b));
    return Status::success();
}

}  // namespace sculpt::core
