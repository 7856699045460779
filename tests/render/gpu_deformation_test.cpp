// The deformation evaluated in the vertex shader (Renderer::setGpuDeformation, shaders/mesh.vert) against the
// engine's CPU evaluation: positions and normals read back by transform feedback and compared with an
// independent computation in double (evaluateAll; cof(J) n0 from deformationJacobian), over random box lattices
// of every degree, rational ones, partial boxes and meshes at any scale; and the pictures of both paths.
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <tuple>

#include <catch2/catch.hpp>
#include <Eigen/Geometry>

#include "app/scene_builder.h"
#include "core/volume/embedding.h"
#include "core/volume/lattice.h"
#include "core/volume/lattice_net.h"
#include "io/script.h"
#include "core/session/session.h"
#include "core/deform/vertex_normals.h"
#include "demo_session.h"
#include "gl_test_support.h"
#include "io/obj_mesh.h"
#include "io/png_image.h"
#include "io/script_json.h"
#include "test_meshes.h"

using namespace sculpt;
using namespace sculpt::test;

namespace {

void requireOk(const Status& status) {
    INFO(status.message);
    REQUIRE(status.ok);
}

// A random box lattice around (part of) `rest`: degrees 1-5, 2-9 spans, random displacements of up to
// `strength` of the diagonal, and random NURBS weights when `rational`.
core::Lattice randomLattice(std::mt19937& rng, const Positions& rest, bool partialBox, bool rational, double strength) {
    std::uniform_int_distribution<int> degreeOf(1, 5), spansOf(1, 6);
    core::LatticeSettings settings;
    for (int a = 0; a < 3; ++a) {
        settings.degree[size_t(a)] = degreeOf(rng);
        settings.resolution[size_t(a)] = settings.degree[size_t(a)] + spansOf(rng);
    }
    if (partialBox) {  // a box over part of the mesh: the vertices outside never move
        const Eigen::Vector3d lo = rest.colwise().minCoeff().transpose(), hi = rest.colwise().maxCoeff().transpose();
        std::uniform_real_distribution<double> cut(0.3, 0.7);
        settings.hasRegion = true;
        settings.regionMin = lo;
        settings.regionMax = hi;
        const int axis = int(rng() % 3);
        settings.regionMax[axis] = lo[axis] + cut(rng) * (hi[axis] - lo[axis]);
        settings.padding = 0.0;
    }
    core::Lattice lattice;
    requireOk(core::makeLattice(settings, rest, lattice));
    std::normal_distribution<double> gauss(0.0, strength * lattice.diagonal() / 3.0);
    for (int i = 0; i < lattice.controlPointCount(); ++i)
        for (int c = 0; c < 3; ++c) lattice.displacement(i, c) = gauss(rng);
    if (rational) {
        std::uniform_real_distribution<double> weight(0.4, 2.5);
        for (double& w : lattice.weights) w = weight(rng);
        lattice.rational = true;
    }
    return lattice;
}

// A blob at a random scale and place (the GPU works in a local frame: camera.h).
Positions placedBlob(std::mt19937& rng, int subdivisions, Triangles& triangles) {
    TestMesh mesh = makeBlob(subdivisions);
    std::uniform_real_distribution<double> exponent(-3.0, 3.0), offset(-1.0, 1.0);
    const double scale = std::pow(10.0, exponent(rng));
    const Eigen::RowVector3d shift(offset(rng) * 1e3 * scale, offset(rng) * 1e3 * scale, offset(rng) * 1e3 * scale);
    triangles = mesh.triangles;
    Positions placed = mesh.positions * scale;
    placed.rowwise() += shift;
    return placed;
}

// The engine's deformed positions: rest + sum R(t) delta for the embedded vertices (evaluateAll).
Positions evaluated(const core::Lattice& lattice, const core::Embedding& embedding, const Positions& rest) {
    Positions out = rest;
    core::evaluateAll(lattice, embedding, out);
    return out;
}

// Each point carried through the layers in order, as Session::pushThroughLayers does (parameters by each layer
// box's linear map, the identity outside it); with jacobians (one per point), each layer's Jacobian multiplied on.
void pushThroughLayers(const std::vector<core::Lattice>& layers, Positions& points, std::vector<Eigen::Matrix3d>* jacobians) {
    for (Eigen::Index v = 0; v < points.rows(); ++v)
        for (const core::Lattice& layer : layers) {
            Eigen::Vector3d t, displacement;
            if (!core::restParameters(layer, points.row(v).transpose(), t)) continue;
            if (jacobians) {
                Eigen::Matrix3d step;
                core::deformationJacobian(layer, t, displacement, step);
                (*jacobians)[size_t(v)] = step * (*jacobians)[size_t(v)];
            }
            points.row(v) += core::displacementAt(layer, t).transpose();
        }
}

// The deformed normal the vertex shader should give: cof(J) n0, normalised, from the engine's Jacobian.
Eigen::Vector3d expectedNormal(const core::Lattice& lattice, const Eigen::Vector3d& params, const Eigen::Vector3d& restNormal) {
    Eigen::Vector3d displacement;
    Eigen::Matrix3d jacobian;
    core::deformationJacobian(lattice, params, displacement, jacobian);
    const Eigen::Vector3d n = jacobian.determinant() * jacobian.inverse().transpose() * restNormal;
    return n.normalized();
}

render::Camera cameraFor(const render::Renderer& renderer, int width, int height) {
    render::ScreenshotOptions options;
    options.width = width;
    options.height = height;
    return render::screenshotCamera(renderer.meshBounds(), renderer.latticeBounds(), options);
}

render::Rgba8Image draw(const render::Camera& camera, const render::DrawOptions& options, int width, int height) {
    render::Rgba8Image image;
    requireOk(glTestRenderer().render(camera, options, width, height, 4, &image));
    return image;
}

}  // namespace

TEST_CASE("GPU deformation: the vertex shader's positions and normals are the engine's, any degree, rational, any scale",
          "[gl][gpu_deformation]") {
    render::Renderer& renderer = glTestRenderer().renderer();
    std::mt19937 rng(20261201);
    int outsideSeen = 0;
    for (int trial = 0; trial < 24; ++trial) {
        Triangles triangles;
        const Positions rest = placedBlob(rng, 2 + trial % 3, triangles);
        const bool partial = trial % 3 == 1, rational = trial % 4 >= 2;
        const core::Lattice lattice = randomLattice(rng, rest, partial, rational, 0.08);
        INFO("trial " << trial << ": degrees " << lattice.degree[0] << lattice.degree[1] << lattice.degree[2] << ", counts "
                      << lattice.count[0] << " " << lattice.count[1] << " " << lattice.count[2]
                      << (rational ? ", rational" : "") << (partial ? ", partial box" : ""));
        const core::Embedding embedding = core::embedVertices(lattice, rest);
        Positions deformed = evaluated(lattice, embedding, rest);
        Positions restNormals;
        core::computeVertexNormals(rest, triangles, restNormals);

        requireOk(renderer.setMesh(rest, triangles));
        requireOk(renderer.setGpuDeformation(lattice, embedding, rest));
        REQUIRE(renderer.gpuDeformationActive());
        Positions gpuPositions, gpuNormals;
        requireOk(renderer.captureGpuDeformation(gpuPositions, gpuNormals));
        REQUIRE(gpuPositions.rows() == rest.rows());

        // Float arithmetic in a frame about the mesh: a few float ulps of the mesh's size.
        const double size = (rest.colwise().maxCoeff() - rest.colwise().minCoeff()).norm();
        double worstPosition = 0.0, worstNormal = 0.0;
        for (int cell = 0; cell + 1 < int(embedding.cellStart.size()); ++cell)
            for (int e = embedding.cellStart[size_t(cell)]; e < embedding.cellStart[size_t(cell) + 1]; ++e) {
                const int v = embedding.order[size_t(e)];
                worstPosition = std::max(worstPosition, (gpuPositions.row(v) - deformed.row(v)).norm() / size);
                const Eigen::Vector3d expected =
                    expectedNormal(lattice, core::embeddedParameters(lattice, embedding, cell, e), restNormals.row(v).transpose());
                worstNormal = std::max(worstNormal, (gpuNormals.row(v).transpose() - expected).norm());
            }
        // Outside the box: the rest position and normal, untouched.
        std::vector<std::uint8_t> inside(size_t(rest.rows()), 0);
        for (int v : embedding.order) inside[size_t(v)] = 1;
        for (int v = 0; v < rest.rows(); ++v)
            if (!inside[size_t(v)]) {
                ++outsideSeen;
                worstPosition = std::max(worstPosition, (gpuPositions.row(v) - rest.row(v)).norm() / size);
                worstNormal = std::max(worstNormal, (gpuNormals.row(v) - restNormals.row(v)).norm());
            }
        CHECK(worstPosition < 2e-6);
        CHECK(worstNormal < 2e-4);

        // A second frame: only the displacements change, and the capture follows.
        core::Lattice moved = lattice;
        moved.displacement *= -0.5;
        requireOk(renderer.updateGpuDeformation(moved));
        CHECK(renderer.lastUpload().controlPointsUploaded == lattice.controlPointCount());
        CHECK_FALSE(renderer.lastUpload().fullUpload);
        deformed = evaluated(moved, embedding, rest);
        requireOk(renderer.captureGpuDeformation(gpuPositions, gpuNormals));
        CHECK((gpuPositions - deformed).rowwise().norm().maxCoeff() / size < 2e-6);
    }
    CHECK(outsideSeen > 100);  // the partial boxes did leave vertices out
}

TEST_CASE("GPU deformation: both paths draw the same picture, and the CPU path comes back exactly", "[gl][gpu_deformation]") {
    render::Renderer& renderer = glTestRenderer().renderer();
    std::mt19937 rng(7);
    constexpr int kWidth = 240, kHeight = 160;
    for (int trial = 0; trial < 6; ++trial) {
        INFO("trial " << trial);
        Triangles triangles;
        const Positions rest = placedBlob(rng, 4, triangles);
        const core::Lattice lattice = randomLattice(rng, rest, trial % 2 == 1, trial % 3 == 2, 0.1);
        const core::Embedding embedding = core::embedVertices(lattice, rest);
        const Positions deformed = evaluated(lattice, embedding, rest);

        requireOk(renderer.setMesh(deformed, triangles));
        const render::Camera camera = cameraFor(renderer, kWidth, kHeight);
        std::vector<int> all(size_t(rest.rows()));
        for (int v = 0; v < int(rest.rows()); ++v) all[size_t(v)] = v;
        for (const bool wireframe : {false, true}) {
            render::DrawOptions options;
            options.wireframe = wireframe;
            requireOk(renderer.setMesh(rest, triangles));
            const render::Rgba8Image undeformed = draw(camera, options, kWidth, kHeight);
            requireOk(renderer.updatePositions(deformed, all));
            const render::Rgba8Image cpu = draw(camera, options, kWidth, kHeight);
            requireOk(renderer.setGpuDeformation(lattice, embedding, rest));
            const render::Rgba8Image gpu = draw(camera, options, kWidth, kHeight);
            CHECK(differingFraction(undeformed, cpu) > 0.002);  // the deformation shows ...
            CHECK(differingFraction(gpu, cpu) <= goldenMaxDifferingFraction());  // ... and looks the same either way
            // Back to the CPU path: exactly the CPU picture (the same frame, the same normals).
            requireOk(renderer.clearGpuDeformation(deformed));
            CHECK_FALSE(renderer.gpuDeformationActive());
            const render::Rgba8Image back = draw(camera, options, kWidth, kHeight);
            CHECK(differingFraction(back, cpu) == 0.0);
        }
    }
}

TEST_CASE("GPU deformation: goldens of the demo session drawn through the GPU path", "[gl][gpu_deformation][golden]") {
    const core::Session session = demoSession();
    // The demo's drags were subdivided: the mesh shown is the cage's map followed by the steps' layers.
    std::vector<const core::Lattice*> layers;
    for (const core::Layer& layer : session.cage().layers()) layers.push_back(&layer.lattice);
    CHECK_FALSE(layers.empty());
    REQUIRE(render::Renderer::gpuDeformationProblem(session.lattice(), layers).empty());
    for (const auto& [name, jacobian, lattice] : {std::tuple{"scripted_drag", false, false},
                                                  std::tuple{"scripted_drag_lattice", false, true},
                                                  std::tuple{"scripted_drag_jacobian", true, false}}) {
        INFO(name);
        const render::Rgba8Image gpu = renderSession(session, jacobian, lattice, &layers);
        checkGolden(gpu, name);
        // Kept for a look: what the GPU path drew.
        io::writePng(glTestOutputDir() + "/gpu_path_" + name + ".png", gpu.width, gpu.height, gpu.pixels.data());
    }
}

TEST_CASE("GPU deformation: bad input is refused by name and changes nothing", "[gl][gpu_deformation]") {
    render::Renderer& renderer = glTestRenderer().renderer();
    std::mt19937 rng(11);
    Triangles triangles;
    const Positions rest = placedBlob(rng, 3, triangles);
    const core::Lattice lattice = randomLattice(rng, rest, false, false, 0.05);
    const core::Embedding embedding = core::embedVertices(lattice, rest);
    constexpr int kWidth = 120, kHeight = 90;

    requireOk(renderer.setMesh(rest, triangles));
    const render::Camera camera = cameraFor(renderer, kWidth, kHeight);
    // Off: the per-frame update and the capture refuse.
    CHECK_FALSE(renderer.updateGpuDeformation(lattice).ok);
    Positions p, n;
    CHECK_FALSE(renderer.captureGpuDeformation(p, n).ok);
    Status status;

    // Another kind of lattice (a cylinder of seed 004) stays on the CPU path, and says why.
    {
        auto cylinder = std::make_shared<core::LatticeNet>();
        const Eigen::Vector3d lo = rest.colwise().minCoeff().transpose(), hi = rest.colwise().maxCoeff().transpose();
        requireOk(core::makeCylinderNet(0.5 * (lo + hi) - Eigen::Vector3d(0, 0, hi.z() - lo.z()), Eigen::Vector3d::UnitZ(),
                                        (hi - lo).norm(), 2.0 * (hi.z() - lo.z()), {1, 4, 2}, {2, 2}, *cylinder));
        core::LatticeSettings settings;
        settings.volume = cylinder;
        core::Lattice net;
        requireOk(core::makeLattice(settings, rest, net));
        const std::string problem = render::Renderer::gpuDeformationProblem(net);
        CHECK(problem.find("cylinder") != std::string::npos);
        status = renderer.setGpuDeformation(net, core::embedVertices(net, rest), rest);
        CHECK_FALSE(status.ok);
        CHECK(status.message.find(problem) != std::string::npos);
        CHECK_FALSE(renderer.gpuDeformationActive());
    }
    // The box lattice with a non-finite displacement or weight, or of the wrong size.
    core::Lattice bad = lattice;
    bad.displacement(3, 1) = std::numeric_limits<double>::quiet_NaN();
    status = renderer.setGpuDeformation(bad, embedding, rest);
    CHECK_FALSE(status.ok);
    CHECK(status.message.find("not finite") != std::string::npos);
    CHECK_FALSE(renderer.gpuDeformationActive());
    bad = lattice;
    bad.weights[0] = 0.0;
    CHECK_FALSE(renderer.setGpuDeformation(bad, embedding, rest).ok);
    Positions shortRest = rest.topRows(rest.rows() - 1);
    status = renderer.setGpuDeformation(lattice, embedding, shortRest);
    CHECK_FALSE(status.ok);
    CHECK(status.message.find("vertices") != std::string::npos);
    Positions nanRest = rest;
    nanRest(5, 2) = std::numeric_limits<double>::infinity();
    CHECK_FALSE(renderer.setGpuDeformation(lattice, embedding, nanRest).ok);
    // An embedding made for another lattice.
    core::LatticeSettings other;
    other.resolution = {lattice.count[0] + 1, lattice.count[1], lattice.count[2]};
    other.degree = lattice.degree;
    core::Lattice otherLattice;
    requireOk(core::makeLattice(other, rest, otherLattice));
    status = renderer.setGpuDeformation(lattice, core::embedVertices(otherLattice, rest), rest);
    CHECK_FALSE(status.ok);
    CHECK(status.message.find("another lattice") != std::string::npos);
    CHECK_FALSE(renderer.gpuDeformationActive());
    const render::Rgba8Image before = draw(camera, {}, kWidth, kHeight);

    // On: updatePositions refuses (the buffer holds rest positions), so does a lattice of another shape or a NaN.
    requireOk(renderer.setGpuDeformation(lattice, embedding, rest));
    const render::Rgba8Image on = draw(camera, {}, kWidth, kHeight);
    CHECK_FALSE(renderer.updatePositions(rest, {0, 1, 2}).ok);
    CHECK_FALSE(renderer.updateGpuDeformation(otherLattice).ok);
    bad = lattice;
    bad.displacement(0, 0) = std::numeric_limits<double>::infinity();
    CHECK_FALSE(renderer.updateGpuDeformation(bad).ok);
    CHECK(differingFraction(draw(camera, {}, kWidth, kHeight), on) == 0.0);
    CHECK_FALSE(renderer.clearGpuDeformation(shortRest).ok);
    CHECK_FALSE(renderer.clearGpuDeformation(nanRest).ok);
    CHECK(renderer.gpuDeformationActive());
    // setMesh leaves the GPU path.
    requireOk(renderer.setMesh(rest, triangles));
    CHECK_FALSE(renderer.gpuDeformationActive());
    CHECK(differingFraction(draw(camera, {}, kWidth, kHeight), before) == 0.0);
}

TEST_CASE("GPU deformation: layers after the cage compose as the engine's, random layers of any degree",
          "[gl][gpu_deformation]") {
    render::Renderer& renderer = glTestRenderer().renderer();
    std::mt19937 rng(424242);
    for (int trial = 0; trial < 12; ++trial) {
        Triangles triangles;
        const Positions rest = placedBlob(rng, 3, triangles);
        const core::Lattice cage = randomLattice(rng, rest, trial % 2 == 1, trial % 3 == 0, 0.05);
        const core::Embedding embedding = core::embedVertices(cage, rest);
        Positions expected = evaluated(cage, embedding, rest);
        // 1 to 4 layers, each a box lattice over part of the shape as it is after the ones before it.
        std::vector<core::Lattice> layerLattices;
        // (A brush stroke adds a layer per mouse move: the last trial has 40.)
        const int layerCount = trial == 11 ? 40 : 1 + trial % 4;
        for (int k = 0; k < layerCount; ++k) {
            // As the engine's layers: the outer control points stay, so the layer is continuous across its box.
            core::Lattice layer = randomLattice(rng, expected, true, k % 2 == 1, layerCount > 4 ? 0.01 : 0.05);
            for (int i = 0; i < layer.controlPointCount(); ++i)
                if (core::inOuterLayers(layer, i, 1)) layer.displacement.row(i).setZero();
            if (k % 3 == 1) {
                // Turned about its centre, as a brush stroke's layer is turned to its pull (core/volume/lattice.h).
                std::uniform_real_distribution<double> unit(-1.0, 1.0);
                Eigen::Quaterniond turn(unit(rng), unit(rng), unit(rng), unit(rng));
                turn.normalize();
                const Eigen::Matrix3d axes = turn.toRotationMatrix();
                const Eigen::Vector3d centre = 0.5 * (layer.boxMin + layer.boxMax), shift = axes * centre - centre;
                layer.boxMin += shift;
                layer.boxMax += shift;
                REQUIRE(core::turnBoxLattice(layer, axes));
            }
            layerLattices.push_back(std::move(layer));
        }
        std::vector<const core::Lattice*> layers;
        for (const core::Lattice& layer : layerLattices) layers.push_back(&layer);
        // The engine's composition (Session::pushThroughLayers) and Jacobian, in double.
        Positions restNormals;
        core::computeVertexNormals(rest, triangles, restNormals);
        std::vector<Eigen::Matrix3d> jacobians(size_t(rest.rows()), Eigen::Matrix3d::Identity());
        for (int cell = 0; cell + 1 < int(embedding.cellStart.size()); ++cell)
            for (int e = embedding.cellStart[size_t(cell)]; e < embedding.cellStart[size_t(cell) + 1]; ++e) {
                Eigen::Vector3d displacement;
                core::deformationJacobian(cage, core::embeddedParameters(cage, embedding, cell, e), displacement,
                                          jacobians[size_t(embedding.order[size_t(e)])]);
            }
        pushThroughLayers(layerLattices, expected, &jacobians);

        requireOk(renderer.setMesh(rest, triangles));
        requireOk(renderer.setGpuDeformation(cage, embedding, rest, layers));
        Positions gpuPositions, gpuNormals;
        requireOk(renderer.captureGpuDeformation(gpuPositions, gpuNormals));
        const double size = (rest.colwise().maxCoeff() - rest.colwise().minCoeff()).norm();
        double worstPosition = 0.0, worstNormal = 0.0;
        int nearBoundary = 0;
        for (int v = 0; v < rest.rows(); ++v) {
            const double error = (gpuPositions.row(v) - expected.row(v)).norm() / size;
            const Eigen::Matrix3d& j = jacobians[size_t(v)];
            const Eigen::Vector3d n = (j.determinant() * j.inverse().transpose() * restNormals.row(v).transpose()).normalized();
            const double normalError = (gpuNormals.row(v).transpose() - n).norm();
            worstPosition = std::max(worstPosition, error);
            // A point on a layer's box face (the random boxes are cut through the shape's extreme vertices) may fall
            // on the other side of it in float: the position is continuous there, its derivative is not. Such
            // normals are counted, not compared.
            if (normalError > 2e-4) {
                ++nearBoundary;
                continue;
            }
            worstNormal = std::max(worstNormal, normalError);
        }
        INFO("trial " << trial << ", " << layerCount << " layers");
        CHECK(nearBoundary <= std::max<int>(4, int(rest.rows() / 200)));
        CHECK(worstPosition < 2e-6);
        CHECK(worstNormal < 2e-4);

        // A frame in which only the last layer moved sends only its control points, and the shader follows.
        core::Lattice& last = layerLattices.back();
        last.displacement *= 0.5;
        requireOk(renderer.updateGpuDeformation(cage, layers));
        CHECK_FALSE(renderer.lastUpload().fullUpload);
        CHECK(renderer.lastUpload().controlPointsUploaded > 0);
        CHECK(renderer.lastUpload().controlPointsUploaded <= last.controlPointCount());
        Positions halved = evaluated(cage, embedding, rest);
        pushThroughLayers(layerLattices, halved, nullptr);
        requireOk(renderer.captureGpuDeformation(gpuPositions, gpuNormals));
        CHECK((gpuPositions - halved).rowwise().norm().maxCoeff() / size < 2e-6);
        // The per-frame update takes other layers (one fewer) without a new rest upload.
        layers.pop_back();
        requireOk(renderer.updateGpuDeformation(cage, layers));
        CHECK_FALSE(renderer.lastUpload().fullUpload);
    }
}

TEST_CASE("GPU deformation: a session's drags, brush layers included, draw where the engine put the mesh",
          "[gl][gpu_deformation]") {
    render::Renderer& renderer = glTestRenderer().renderer();
    std::mt19937 rng(99);
    TestMesh mesh = makeBlob(4);
    core::Session session;
    requireOk(session.setMesh(mesh.positions, mesh.triangles));
    const std::uint64_t restBefore = session.mesh().restVersion;
    const double diagonal = (mesh.positions.colwise().maxCoeff() - mesh.positions.colwise().minCoeff()).norm();
    std::uniform_int_distribution<int> vertexOf(0, int(mesh.positions.rows()) - 1);
    std::normal_distribution<double> gauss(0.0, 0.08 * diagonal);
    int layered = 0;
    for (int step = 0; step < 10; ++step) {
        const int vertex = vertexOf(rng);
        const Eigen::Vector3d target = session.mesh().positions.row(vertex).transpose() + Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng));
        core::BrushSettings brush;
        if (step % 2 == 1) brush.radius = 0.2 * diagonal;  // "Limit to radius": a region layer
        core::OpReport report;
        requireOk(session.dragVertex(vertex, target, report, brush));
        std::vector<const core::Lattice*> layers;
        for (const core::Layer& layer : session.cage().layers()) layers.push_back(&layer.lattice);
        layered = std::max(layered, int(layers.size()));
        REQUIRE(render::Renderer::gpuDeformationProblem(session.lattice(), layers).empty());
        requireOk(renderer.setMesh(session.mesh().positions, session.mesh().triangles));
        requireOk(renderer.setGpuDeformation(session.lattice(), session.cage().embedding(), session.mesh().rest, layers));
        Positions gpuPositions, gpuNormals;
        requireOk(renderer.captureGpuDeformation(gpuPositions, gpuNormals));
        INFO("step " << step << ", " << layers.size() << " layers");
        CHECK((gpuPositions - session.mesh().positions).rowwise().norm().maxCoeff() < 4e-6 * diagonal);
        // The normals agree with the CPU path's area-weighted ones of the same mesh to shading accuracy.
        const Positions& cpuNormals = renderer.normals();
        double sumAngle = 0.0;
        for (int v = 0; v < gpuNormals.rows(); ++v)
            sumAngle += std::acos(std::clamp(gpuNormals.row(v).dot(cpuNormals.row(v)), -1.0, 1.0));
        CHECK(sumAngle / double(gpuNormals.rows()) < 0.05);  // radians, on average
    }
    // Layers (a subdivided drag's) and strokes baked into the rest shape: both are what the GPU path deforms.
    CHECK((layered > 0 || session.mesh().restVersion > restBefore));
}
