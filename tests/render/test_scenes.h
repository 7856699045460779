// The scenes of the golden tests (and of the hidden [showcase] test that renders them large).
#pragma once

#include <algorithm>
#include <cmath>

#include <filesystem>
#include <string>

#include "io/obj_mesh.h"
#include "render/scene.h"
#include "test_meshes.h"

namespace sculpt::test {

inline std::string defaultMeshPath() { return std::string(SCULPT_SOURCE_DIR) + "/assets/default.obj"; }
inline bool haveDefaultMesh() { return std::filesystem::exists(defaultMeshPath()); }

// assets/default.obj (the bundled mesh the app opens with). status says why if it could not be loaded.
inline render::SceneData defaultMeshScene(Status& status) {
    io::ObjMesh mesh;
    status = io::loadObj(defaultMeshPath(), mesh);
    render::SceneData scene;
    scene.positions = mesh.positions;
    scene.triangles = mesh.triangles;
    return scene;
}

inline render::SceneData blobScene(int subdivisions = 4) {
    TestMesh mesh = makeBlob(subdivisions);
    render::SceneData scene;
    scene.positions = std::move(mesh.positions);
    scene.triangles = std::move(mesh.triangles);
    return scene;
}

// The vertex that is furthest along `direction` (a deterministic, visible point on the surface).
inline Eigen::Index extremeVertex(const Positions& positions, const Eigen::Vector3d& direction) {
    Eigen::Index best = 0;
    (positions * direction).maxCoeff(&best);
    return best;
}

// Blob in a padded 5 x 4 x 4 lattice: the bottom layer pinned, four control points near the upper front
// selected, and one constraint pulling a surface point outward.
inline render::SceneData latticeScene() {
    render::SceneData scene = blobScene();
    const Eigen::Vector3d lo = scene.positions.colwise().minCoeff().transpose();
    const Eigen::Vector3d hi = scene.positions.colwise().maxCoeff().transpose();
    const Eigen::Vector3d pad = 0.08 * (hi - lo);
    scene.lattice = makeBoxLattice(lo - pad, hi + pad, 5, 4, 4);
    const int count = int(scene.lattice.controlPoints.rows());
    scene.lattice.selected.assign(size_t(count), 0);
    scene.lattice.pinned.assign(size_t(count), 0);
    const auto index = [&](int i, int j, int k) { return i + 5 * (j + 4 * k); };
    for (int k = 0; k < 4; ++k)
        for (int i = 0; i < 5; ++i) scene.lattice.pinned[size_t(index(i, 0, k))] = 1;
    for (int i = 2; i <= 3; ++i)
        for (int k = 2; k <= 3; ++k) scene.lattice.selected[size_t(index(i, 2, k))] = 1;
    const Eigen::Index source = extremeVertex(scene.positions, Eigen::Vector3d(0.6, 0.5, 0.62).normalized());
    scene.constraints.sources = scene.positions.row(source);
    scene.constraints.targets = scene.positions.row(source) * 1.35;
    return scene;
}

// Synthetic det J (until the engine provides one): a ramp along x from contraction (1/5) to expansion (5),
// with a fold-over cap (det J < 0) on top.
inline render::SceneData jacobianScene() {
    render::SceneData scene = blobScene();
    const double xMin = scene.positions.col(0).minCoeff(), xMax = scene.positions.col(0).maxCoeff();
    const double yMax = scene.positions.col(1).maxCoeff();
    scene.jacobianDet.resize(size_t(scene.positions.rows()));
    for (Eigen::Index v = 0; v < scene.positions.rows(); ++v) {
        const double s = 2.0 * (scene.positions(v, 0) - xMin) / (xMax - xMin) - 1.0;  // -1 .. 1
        double det = std::pow(5.0, s);
        if (scene.positions(v, 1) > 0.8 * yMax) det = -0.3;
        scene.jacobianDet[size_t(v)] = float(det);
    }
    return scene;
}

inline render::SceneData wireframeScene() { return blobScene(2); }

// Affected-region weights falling off smoothly around a constraint's source, as a local FFD support would.
inline render::SceneData affectedScene() {
    render::SceneData scene = blobScene();
    const Eigen::Index source = extremeVertex(scene.positions, Eigen::Vector3d(0.6, 0.5, 0.62).normalized());
    const Eigen::RowVector3d center = scene.positions.row(source);
    scene.affectedWeight.resize(size_t(scene.positions.rows()));
    for (Eigen::Index v = 0; v < scene.positions.rows(); ++v) {
        const double t = std::clamp((scene.positions.row(v) - center).norm() / 1.0, 0.0, 1.0);
        scene.affectedWeight[size_t(v)] = float(1.0 - t * t * (3.0 - 2.0 * t));
    }
    scene.constraints.sources = center;
    scene.constraints.targets = center * 1.35;
    return scene;
}

}  // namespace sculpt::test
