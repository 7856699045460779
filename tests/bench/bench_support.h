// Timing helpers for the benchmark executable: median of repeated runs, one JSON line per case.
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "core/mesh_types.h"

namespace sculpt::bench {

// n points on a slightly bumpy unit sphere in latitude-longitude order (the vertex order of a typical mesh: rows
// of neighbouring vertices, not cell order; every point on the surface, as a scan's).
inline Positions bumpySphere(int n) {
    Positions p(n, 3);
    const int rings = static_cast<int>(std::sqrt(n / 2.0)) + 1;
    const int perRing = (n + rings - 1) / rings;
    for (int v = 0; v < n; ++v) {
        const double theta = M_PI * ((v / perRing) + 0.5) / rings;
        const double phi = 2.0 * M_PI * (v % perRing) / perRing;
        const double r = 1.0 + 0.05 * std::sin(5 * theta) * std::cos(3 * phi);
        p.row(v) << r * std::sin(theta) * std::cos(phi), r * std::sin(theta) * std::sin(phi), r * std::cos(theta);
    }
    return p;
}

// A case is wanted when no filter is given or a filter is a substring of its name; a group (every case whose
// name starts with `name`) also when a filter names one of its cases.
inline bool wantedCase(const std::vector<std::string>& filters, const std::string& name) {
    if (filters.empty()) return true;
    for (const std::string& f : filters)
        if (name.find(f) != std::string::npos || f.rfind(name, 0) == 0) return true;
    return false;
}

// Runs `work` `runs` times (after one warm-up) and returns the median wall time in milliseconds.
inline double medianMs(int runs, const std::function<void()>& work, const std::function<void()>& before = {}) {
    std::vector<double> times;
    for (int r = 0; r <= runs; ++r) {
        if (before) before();
        const auto start = std::chrono::steady_clock::now();
        work();
        const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
        if (r > 0) times.push_back(ms);
    }
    std::sort(times.begin(), times.end());
    return times[times.size() / 2];
}

// The sample at quantile q in [0, 1] of a list (the nearest rank; 0 for none): 0.5 the median, 1 the largest.
inline double percentile(std::vector<double> values, double q) {
    if (values.empty()) return 0.0;
    std::sort(values.begin(), values.end());
    return values[std::min(values.size() - 1, static_cast<size_t>(q * static_cast<double>(values.size())))];
}

// The median of a list of samples (0 for none).
inline double median(std::vector<double> values) { return percentile(std::move(values), 0.5); }

// JSON string contents: quotes and backslashes escaped, control characters dropped.
inline std::string jsonText(const std::string& text) {
    std::string escaped;
    for (char c : text) {
        if (c == '"' || c == '\\') escaped += '\\';
        if (static_cast<unsigned char>(c) >= 0x20) escaped += c;
    }
    return escaped;
}

// A case that could not run, as its JSON line.
inline void printError(std::ostream& out, const char* name, const std::string& message) {
    out << "{\"case\": \"" << name << "\", \"error\": \"" << jsonText(message) << "\"}" << std::endl;
}

inline void printCase(const std::string& name, long long n, double medianMilliseconds, const std::string& extra = "") {
    std::printf("{\"case\": \"%s\", \"n\": %lld, \"median_ms\": %.4f%s}\n", name.c_str(), n, medianMilliseconds,
                extra.empty() ? "" : (", " + extra).c_str());
    std::fflush(stdout);
}

// A closed latitude-longitude sphere mesh of about n vertices (rings x perRing plus the poles). Every ring has the
// same count, so toward the poles the triangles become slivers (width to height sin(latitude)), whose boxes overlap
// many neighbours: harder for the triangle check than a scan (geodesicSphereMesh is the scan-like one).
inline void sphereMesh(int n, Positions& positions, Triangles& triangles) {
    const int rings = static_cast<int>(std::sqrt(n / 2.0)), perRing = 2 * rings;
    positions.resize(rings * perRing + 2, 3);
    for (int r = 0; r < rings; ++r)
        for (int k = 0; k < perRing; ++k) {
            const double theta = M_PI * (r + 1) / (rings + 1), phi = 2.0 * M_PI * k / perRing;
            positions.row(r * perRing + k) << std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta);
        }
    const int north = rings * perRing, south = north + 1;
    positions.row(north) << 0, 0, 1;
    positions.row(south) << 0, 0, -1;
    std::vector<Eigen::Vector3i> tris;
    for (int k = 0; k < perRing; ++k) {
        const int k1 = (k + 1) % perRing;
        tris.emplace_back(north, k, k1);
        tris.emplace_back(south, (rings - 1) * perRing + k1, (rings - 1) * perRing + k);
        for (int r = 0; r + 1 < rings; ++r) {
            const int a = r * perRing + k, b = r * perRing + k1, c = (r + 1) * perRing + k1, d = (r + 1) * perRing + k;
            tris.emplace_back(a, d, c);
            tris.emplace_back(a, c, b);
        }
    }
    triangles.resize(static_cast<Eigen::Index>(tris.size()), 3);
    for (size_t t = 0; t < tris.size(); ++t) triangles.row(static_cast<Eigen::Index>(t)) = tris[t].transpose();
}

}  // namespace sculpt::bench
