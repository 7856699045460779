#include <catch2/catch.hpp>

#include <random>

#include "core/deform/vertex_normals.h"
#include "../mesh_fixtures.h"
#include "../test_support.h"

using namespace sculpt;

TEST_CASE("vertex_normals: sparse update after moving some vertices equals a full recomputation", "[core]") {
    std::mt19937 rng(71);
    for (int levels : {1, 2, 3, 4}) {
        Positions positions;
        Triangles triangles;
        test::icosphere(levels, 1.0, Eigen::Vector3d::Zero(), positions, triangles);
        const core::VertexTriangles adjacency = core::buildVertexTriangles(static_cast<int>(positions.rows()), triangles);
        Positions normals;
        core::computeVertexNormals(positions, triangles, normals);
        // Outward unit normals on a sphere.
        for (Eigen::Index v = 0; v < positions.rows(); ++v) {
            REQUIRE(normals.row(v).norm() == Approx(1.0));
            REQUIRE(normals.row(v).dot(positions.row(v)) > 0.9);
        }
        for (int round = 0; round < 5; ++round) {
            std::vector<int> changed;
            for (int c = 0; c < test::randomInt(rng, 1, 30); ++c) {
                const int v = test::randomInt(rng, 0, static_cast<int>(positions.rows()) - 1);
                positions.row(v) += 0.05 * test::randomVector(rng, -1, 1).transpose();
                changed.push_back(v);
            }
            core::updateVertexNormals(positions, triangles, adjacency, changed, normals);
            Positions full;
            core::computeVertexNormals(positions, triangles, full);
            REQUIRE((normals - full).cwiseAbs().maxCoeff() <= 1e-15);
        }
    }
    // Degenerate triangles never produce NaN.
    Positions flat = Positions::Zero(3, 3);
    Triangles one(1, 3);
    one << 0, 1, 2;
    Positions normals;
    core::computeVertexNormals(flat, one, normals);
    REQUIRE(normals.allFinite());
}

TEST_CASE("vertex_normals: the full update with a kept adjacency equals the one-off computation bit for bit", "[core]") {
    // Icospheres of 42 to 40962 vertices (the last over the parallel threshold), randomly jittered, with random
    // extra triangles (degenerate ones, repeated ones, isolated vertices) so rings are irregular; computed
    // twice with one adjacency, so its kept scratch is reused.
    std::mt19937 rng(72);
    for (int levels : {1, 3, 6}) {
        Positions positions;
        Triangles triangles;
        test::icosphere(levels, 1.0, Eigen::Vector3d::Zero(), positions, triangles);
        const int n = static_cast<int>(positions.rows());
        positions.conservativeResize(n + 5, 3);  // five vertices no triangle uses
        for (int v = n; v < n + 5; ++v) positions.row(v) = test::randomVector(rng, -1, 1).transpose();
        const Eigen::Index base = triangles.rows();
        triangles.conservativeResize(base + 40, 3);
        for (Eigen::Index t = base; t < base + 40; ++t)
            for (int c = 0; c < 3; ++c) triangles(t, c) = t % 4 == 0 && c == 2 ? triangles(t, 0) : test::randomInt(rng, 0, n - 1);
        const core::VertexTriangles adjacency = core::buildVertexTriangles(static_cast<int>(positions.rows()), triangles);
        for (int round = 0; round < 2; ++round) {
            for (int v = 0; v < n; ++v) positions.row(v) += 0.02 * test::randomVector(rng, -1, 1).transpose();
            Positions oneOff, kept;
            core::computeVertexNormals(positions, triangles, oneOff);
            core::computeVertexNormals(positions, triangles, adjacency, kept);
            REQUIRE(kept.rows() == positions.rows());
            REQUIRE(kept == oneOff);
            REQUIRE(kept.allFinite());
        }
    }
}
