// Shared helpers for the core tests: seeded random lattices, points and meshes.
#pragma once

#include <random>

#include <Eigen/Core>

#include "core/volume/lattice.h"
#include "core/mesh_types.h"

namespace sculpt::test {

inline Eigen::Vector3d randomVector(std::mt19937& rng, double lo, double hi) {
    std::uniform_real_distribution<double> d(lo, hi);
    return {d(rng), d(rng), d(rng)};
}

inline int randomInt(std::mt19937& rng, int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng); }

// Random points in a random box (not unit, not centred) so scale bugs show.
inline Positions randomPoints(std::mt19937& rng, int n, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
    Positions p(n, 3);
    std::uniform_real_distribution<double> d(0.0, 1.0);
    for (int v = 0; v < n; ++v)
        for (int a = 0; a < 3; ++a) p(v, a) = lo[a] + d(rng) * (hi[a] - lo[a]);
    return p;
}

// A lattice with random degrees (uniform or mixed), resolutions and box around random points.
inline core::LatticeSettings randomSettings(std::mt19937& rng, bool mixedDegrees = true) {
    core::LatticeSettings s;
    const int p = randomInt(rng, 1, 5);
    for (int a = 0; a < 3; ++a) {
        s.degree[a] = mixedDegrees ? randomInt(rng, 1, 5) : p;
        s.resolution[a] = randomInt(rng, s.degree[a] + 1, s.degree[a] + 9);
    }
    s.padding = std::uniform_real_distribution<double>(0.0, 0.2)(rng);
    return s;
}

inline core::Lattice randomLattice(std::mt19937& rng, bool mixedDegrees = true, Positions* pointsOut = nullptr) {
    const Eigen::Vector3d lo = randomVector(rng, -5.0, 0.0);
    const Eigen::Vector3d hi = lo + randomVector(rng, 0.5, 4.0);
    const Positions points = randomPoints(rng, 50, lo, hi);
    core::Lattice lattice;
    core::makeLattice(randomSettings(rng, mixedDegrees), points, lattice);
    if (pointsOut) *pointsOut = points;
    return lattice;
}

inline Eigen::Vector3d randomParams(std::mt19937& rng) { return randomVector(rng, 0.0, 1.0); }

// Random displacement on every control point, scaled to the box.
inline void randomDisplacement(std::mt19937& rng, core::Lattice& lattice, double fraction) {
    const double scale = fraction * lattice.diagonal();
    for (int c = 0; c < lattice.controlPointCount(); ++c)
        lattice.displacement.row(c) = scale * randomVector(rng, -1.0, 1.0).transpose();
}

}  // namespace sculpt::test
