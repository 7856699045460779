#include <catch2/catch.hpp>

#include <random>

#include "core/vertex_normals.h"
#include "mesh_fixtures.h"
#include "test_support.h"

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
