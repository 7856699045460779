// Any scale, any place (issue 9, point 5): a mesh 1e-9 or 1e9 across, or a small one far from the origin, is
// framed, drawn, picked and dragged exactly as the same mesh 1 across at the origin. The pictures are compared
// with the unit sphere's (scale invariance), and the window's synthetic drags are measured in pixels.
//
// The limit is double precision, not the renderer: a mesh D across centred C from the origin has its
// coordinates rounded to about C * 1.1e-16, i.e. some D / C * 1e16 steps across. Measured at 1280 x 800
// (sphere 640 pixels across): D / C = 1e-10 (1e-3 at 1e7, tested below) differs from the unit sphere's picture
// in 0.0005% of the pixels and drags land within 0.01 pixel; 1e-12 in 0.02% and within 0.1 pixel; 1e-13 (a
// 1e-6 mesh at 1e7, where one rounding step is a pixel) in 0.2% and within about a pixel; 1e-14 in 1%; at 1e-15
// the shape falls apart into the double grid.
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "app/cli_options.h"
#include "app/headless.h"
#include "app/window/picking.h"
#include "app/window/sculpt_app.h"
#include "app/window/tool_commands.h"
#include "gl_test_support.h"
#include "io/obj_mesh.h"
#include "io/png_image.h"
#include "offscreen_window.h"
#include "render/renderer.h"
#include "test_meshes.h"

using namespace sculpt;

namespace {

struct Placement {
    double diameter;
    Eigen::Vector3d centre;
};

std::string describe(const Placement& p) {
    std::ostringstream out;
    out << "diameter " << p.diameter << " at (" << p.centre.x() << ", " << p.centre.y() << ", " << p.centre.z() << ")";
    return out.str();
}

// The brief's cases: 1e-9 to 1e9 across at the origin, and 1 and 1e-3 across centred at (1e7, 1e7, 1e7).
const std::vector<Placement>& extremePlacements() {
    static const std::vector<Placement> placements = {
        {1e-9, Eigen::Vector3d::Zero()}, {1e-4, Eigen::Vector3d::Zero()}, {1.0, Eigen::Vector3d::Zero()},
        {1e4, Eigen::Vector3d::Zero()},  {1e9, Eigen::Vector3d::Zero()},  {1.0, Eigen::Vector3d::Constant(1e7)},
        {1e-3, Eigen::Vector3d::Constant(1e7)}};
    return placements;
}

// Plus random ones (fixed seed): diameters 10^[-9, 9], centres up to 1e4 diameters away from the origin.
std::vector<Placement> randomPlacements(int count) {
    std::mt19937 rng(905);
    std::uniform_real_distribution<double> exponent(-9.0, 9.0), offset(-1e4, 1e4);
    std::vector<Placement> placements;
    for (int i = 0; i < count; ++i) {
        const double diameter = std::pow(10.0, exponent(rng));
        placements.push_back({diameter, diameter * Eigen::Vector3d(offset(rng), offset(rng), offset(rng))});
    }
    return placements;
}

// unit: positions of a shape about 1 across, centred at the origin; placed: diameter * unit + centre.
Positions place(const Positions& unit, const Placement& p) {
    Positions placed = p.diameter * unit;
    placed.rowwise() += p.centre.transpose();
    return placed;
}

// A unit-diameter scene: a slightly squashed icosphere (so orientation shows), a 4^3 lattice box around it
// with some points selected and pinned, and one constraint on its surface.
render::SceneData unitScene() {
    test::TestMesh sphere = test::makeIcosphere(3, 0.5);
    sphere.positions.col(1) *= 0.8;
    render::SceneData scene;
    scene.positions = sphere.positions;
    scene.triangles = sphere.triangles;
    scene.lattice = test::makeBoxLattice(Eigen::Vector3d(-0.6, -0.5, -0.6), Eigen::Vector3d(0.6, 0.5, 0.6), 4, 4, 4);
    scene.lattice.selected.assign(64, 0);
    scene.lattice.pinned.assign(64, 0);
    scene.lattice.selected[21] = 1;
    scene.lattice.pinned[0] = 1;
    scene.constraints.sources.resize(1, 3);
    scene.constraints.targets.resize(1, 3);
    scene.constraints.sources.row(0) = sphere.positions.row(0);
    scene.constraints.targets.row(0) = 1.4 * sphere.positions.row(0);
    return scene;
}

render::SceneData placedScene(const render::SceneData& unit, const Placement& p) {
    render::SceneData scene = unit;
    scene.positions = place(unit.positions, p);
    scene.lattice.controlPoints = place(unit.lattice.controlPoints, p);
    scene.constraints.sources = place(unit.constraints.sources, p);
    scene.constraints.targets = place(unit.constraints.targets, p);
    return scene;
}

// Fraction of opaque pixels (alpha 255) in a picture drawn without background: the mesh.
double opaqueShare(const render::Rgba8Image& image) {
    size_t opaque = 0;
    for (size_t i = 3; i < image.pixels.size(); i += 4) opaque += image.pixels[i] == 255;
    return double(opaque) / double(size_t(image.width) * size_t(image.height));
}

// The background gradient's colour at row y of a picture `height` tall (shaders/background.*: sRGB mix at
// the pixel centre).
std::array<int, 3> backgroundAt(int y, int height) {
    const double down = (y + 0.5) / height;
    std::array<int, 3> colour{};
    for (int c = 0; c < 3; ++c)
        colour[size_t(c)] = int(std::lround(255.0 * (render::kBackgroundTop[size_t(c)] * (1.0 - down) +
                                                     render::kBackgroundBottom[size_t(c)] * down)));
    return colour;
}

// Fraction of the pixels (where `ignore` is 0; empty: everywhere) that are not the background gradient: the
// mesh, plus the few pixels of markers and lines.
double nonBackgroundShare(const std::uint8_t* rgba, int width, int height, const std::vector<std::uint8_t>& ignore = {}) {
    size_t counted = 0, differing = 0;
    for (int y = 0; y < height; ++y) {
        const std::array<int, 3> background = backgroundAt(y, height);
        for (int x = 0; x < width; ++x) {
            const size_t i = size_t(y) * size_t(width) + size_t(x);
            if (!ignore.empty() && ignore[i]) continue;
            ++counted;
            int difference = 0;
            for (int c = 0; c < 3; ++c) difference = std::max(difference, std::abs(int(rgba[4 * i + size_t(c)]) - background[size_t(c)]));
            differing += difference > 12;  // the gradient is smooth; the clay and the markers are far from it
        }
    }
    return counted ? double(differing) / double(counted) : 0.0;
}

void requireOk(const Status& status) {
    INFO(status.message);
    REQUIRE(status.ok);
}

void writeForALook(const render::Rgba8Image& image, const std::string& name) {
    CHECK(io::writePng(test::glTestOutputDir() + "/" + name, image.width, image.height, image.pixels.data()).ok);
}

}  // namespace

TEST_CASE("any scale: camera framing and near/far planes hold a sphere from 1e-9 to 1e9 and far from the origin", "[gl]") {
    std::vector<Placement> placements = extremePlacements();
    const std::vector<Placement> more = randomPlacements(40);
    placements.insert(placements.end(), more.begin(), more.end());
    const test::TestMesh unit = test::makeIcosphere(2, 0.5);
    for (const Placement& p : placements) {
        INFO(describe(p));
        const render::Bounds bounds = render::boundsOf(place(unit.positions, p));
        for (float aspect : {0.5f, 1.6f}) {
            render::Camera camera;
            camera.frame(bounds, aspect);
            // The framing radius is the sphere's own (no absolute floor), and the distance follows it.
            CHECK(camera.sceneRadius == Approx(0.5 * p.diameter).epsilon(1e-6));
            render::Camera unitCamera;
            unitCamera.frame(render::boundsOf(unit.positions), aspect);
            CHECK(camera.distance / camera.sceneRadius == Approx(unitCamera.distance / unitCamera.sceneRadius).epsilon(1e-6));
            // Every point of the sphere lies inside the view volume (in the camera's own local frame, as the
            // renderer draws), strictly between the near and far planes.
            const render::LocalFrame frame = render::localFrameOf(bounds);
            CHECK(frame.scale == Approx(0.5 * p.diameter).epsilon(1e-6));
            const glm::dmat4 viewProjection = camera.projection(aspect, frame) * camera.view(frame);
            const Positions placed = place(unit.positions, p);
            for (Eigen::Index v = 0; v < placed.rows(); ++v) {
                const glm::dvec4 clip = viewProjection *
                                        glm::dvec4(frame.toLocal(glm::dvec3(placed(v, 0), placed(v, 1), placed(v, 2))), 1.0);
                REQUIRE(clip.w > 0.0);
                CHECK(std::abs(clip.x / clip.w) < 0.85);
                CHECK(std::abs(clip.y / clip.w) < 0.85);
                CHECK(std::abs(clip.z / clip.w) < 0.99);
            }
        }
    }
    // A single point still gets a camera (framing radius relative to where it is), and the empty bounds none.
    for (const glm::dvec3 point : {glm::dvec3(0.0), glm::dvec3(2.5e-8, 0.0, 0.0), glm::dvec3(1e7)}) {
        render::Bounds single;
        single.add(point);
        render::Camera camera;
        camera.frame(single, 1.6f);
        CHECK(camera.distance > 0.0);
        CHECK(std::isfinite(camera.distance));
        CHECK(camera.target == point);
    }
}

TEST_CASE("any scale: screenshots of a sphere with its lattice and a constraint look the same at every scale and place", "[gl]") {
    render::OffscreenRenderer& offscreen = test::glTestRenderer();
    const render::SceneData unit = unitScene();
    render::ScreenshotOptions options;
    options.width = 320;
    options.height = 200;
    options.overlays.lattice = true;
    render::ScreenshotOptions meshOnly = options;
    meshOnly.overlays.lattice = meshOnly.overlays.constraints = meshOnly.overlays.background = false;
    render::Rgba8Image reference, referenceMesh;
    requireOk(offscreen.renderScene(unit, options, reference));
    requireOk(offscreen.renderScene(unit, meshOnly, referenceMesh));
    const double referenceShare = opaqueShare(referenceMesh);
    INFO("the unit sphere covers " << referenceShare << " of the picture");
    CHECK(referenceShare > 0.1);
    CHECK(referenceShare < 0.9);

    std::vector<Placement> placements = extremePlacements();
    const std::vector<Placement> more = randomPlacements(16);
    placements.insert(placements.end(), more.begin(), more.end());
    for (size_t i = 0; i < placements.size(); ++i) {
        const Placement& p = placements[i];
        INFO(describe(p));
        const render::SceneData scene = placedScene(unit, p);
        render::Rgba8Image picture, mesh;
        requireOk(offscreen.renderScene(scene, options, picture));
        requireOk(offscreen.renderScene(scene, meshOnly, mesh));
        // A sensible share of the picture is mesh, the same share as at unit scale ...
        const double share = opaqueShare(mesh);
        CHECK(share > 0.1);
        CHECK(share < 0.9);
        CHECK(share == Approx(referenceShare).margin(0.005));
        // ... and the whole picture (mesh, lattice edges and markers, the constraint) is the unit one: the golden
        // tolerance (a pixel differs above 24/255, at most 1% may) with no slack to spare for a misplaced marker.
        const double differing = test::differingFraction(reference, picture);
        CHECK(differing <= test::goldenMaxDifferingFraction());
        if (i < extremePlacements().size()) writeForALook(picture, "any_scale_" + std::to_string(i) + ".png");
    }
    WARN("pictures at the extreme scales written to " << test::glTestOutputDir() << "/any_scale_*.png");
}

TEST_CASE("any scale: the renderer's local frame follows the mesh, and the lattice without a mesh", "[gl]") {
    render::OffscreenRenderer& offscreen = test::glTestRenderer();
    render::Renderer& renderer = offscreen.renderer();
    const render::SceneData unit = unitScene();
    const Placement far{1e-3, Eigen::Vector3d::Constant(1e7)};
    const render::SceneData placed = placedScene(unit, far);
    render::ScreenshotOptions options;
    options.width = 320;
    options.height = 200;
    options.overlays.lattice = true;
    render::Rgba8Image reference;
    requireOk(offscreen.renderScene(placed, options, reference));
    CHECK(renderer.localFrame().origin.x == Approx(1e7).epsilon(1e-15));
    CHECK(renderer.localFrame().scale == Approx(0.5e-3).epsilon(1e-3));
    const render::Camera camera = render::screenshotCamera(renderer.meshBounds(), renderer.latticeBounds(), options);

    // The overlays set while the unit mesh was on the GPU are re-expressed when the far mesh arrives.
    requireOk(renderer.setMesh(unit.positions, unit.triangles));
    requireOk(renderer.setLattice(placed.lattice));
    requireOk(renderer.setConstraints(placed.constraints));
    requireOk(renderer.setMesh(placed.positions, placed.triangles));
    render::Rgba8Image reordered;
    requireOk(offscreen.render(camera, options.overlays, options.width, options.height, 4, &reordered));
    CHECK(test::differingFraction(reference, reordered) == 0.0);

    // Without a mesh the lattice is the content: a lattice alone far away looks like the unit one.
    render::SceneData latticeOnly = unit, farLatticeOnly = placed;
    latticeOnly.positions.resize(0, 3);
    latticeOnly.triangles.resize(0, 3);
    farLatticeOnly.positions.resize(0, 3);
    farLatticeOnly.triangles.resize(0, 3);
    render::Rgba8Image unitLattice, farLattice;
    requireOk(offscreen.renderScene(latticeOnly, options, unitLattice));
    requireOk(offscreen.renderScene(farLatticeOnly, options, farLattice));
    CHECK(renderer.localFrame().origin.y == Approx(1e7).epsilon(1e-15));
    CHECK(test::differingFraction(unitLattice, farLattice) <= test::goldenMaxDifferingFraction());
}

TEST_CASE("any scale: the headless screenshot of the 25 nm sphere (nano-scale case) shows the sphere", "[gl]") {
    namespace fs = std::filesystem;
    const std::string data = std::string(SCULPT_SOURCE_DIR) + "/tests/render/data/nano_scale";
    const fs::path dir = fs::temp_directory_path() / ("sculpt_nano_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string mesh = data + "/mesh.obj", script = data + "/script.json";
    const std::string output = (dir / "out.obj").string(), png = (dir / "nano.png").string();
    for (const bool lattice : {false, true}) {
        INFO("lattice overlay " << lattice);
        std::vector<const char*> argv{"sculpt", "--headless", "--input", mesh.c_str(), "--script", script.c_str(),
                                      "--output", output.c_str(), "--screenshot", png.c_str(), "--size", "640x400"};
        if (lattice) argv.insert(argv.end(), {"--overlay", "lattice"});
        app::CliOptions options;
        REQUIRE(app::parseCommandLine(static_cast<int>(argv.size()), argv.data(), options).ok);
        REQUIRE(app::runHeadless(options, "sculpt") == app::kExitOk);
        int width = 0, height = 0;
        std::vector<std::uint8_t> rgba;
        REQUIRE(io::readPng(png, width, height, rgba).ok);
        REQUIRE(width == 640);
        REQUIRE(height == 400);
        // Before the fix only the constraint marker showed (0.1% of the picture).
        const double share = nonBackgroundShare(rgba.data(), width, height);
        INFO("not background: " << share);
        CHECK(share > 0.1);
        CHECK(share < 0.9);
        render::Rgba8Image image;
        image.width = width;
        image.height = height;
        image.pixels = rgba;
        writeForALook(image, lattice ? "nano_scale_lattice.png" : "nano_scale.png");
    }
    // The edits themselves stay exact: vertex 3 is on the drag_vertex target (1e-9 of the diameter).
    io::ObjMesh result;
    REQUIRE(io::loadObj(output, result).ok);
    const Eigen::Vector3d target(7.731350152805131e-09, 5.2313501528051305e-09, 1.1888206453689418e-08);
    CHECK((result.positions.row(3).transpose() - target).norm() < 1e-9 * 2.5e-8);
    fs::remove_all(dir);
}

// ---- the window: synthetic input on SculptApp ----------------------------------------------------------------

namespace {

constexpr int kWindowWidth = 960, kWindowHeight = 600;

void loadPlacedSphere(app::SculptApp& sculptApp, const Placement& p) {
    sculptApp.onFramebufferSize({kWindowWidth, kWindowHeight});
    const test::TestMesh unit = test::makeIcosphere(3, 0.5);
    const Status loaded = app::setMesh(sculptApp.state(), place(unit.positions, p), unit.triangles, "sphere");
    INFO(loaded.message);
    REQUIRE(loaded.ok);
}

Eigen::Vector2d pixelOf(const app::AppState& state, const Eigen::Vector3d& point) {
    double x = 0.0, y = 0.0;
    REQUIRE(app::projectToPixel(state.camera, kWindowWidth, kWindowHeight, point, x, y));
    return {x, y};
}

// The same projection, independently: world-space double matrices, no local frame.
Eigen::Vector2d pixelInWorldFrame(const render::Camera& camera, const Eigen::Vector3d& point, double& depth) {
    const glm::dmat4 viewProjection = camera.projection(double(kWindowWidth) / kWindowHeight) * camera.view();
    const glm::dvec4 clip = viewProjection * glm::dvec4(point.x(), point.y(), point.z(), 1.0);
    depth = clip.w;
    return {(clip.x / clip.w * 0.5 + 0.5) * kWindowWidth, (0.5 - clip.y / clip.w * 0.5) * kWindowHeight};
}

void press(app::SculptApp& a, double x, double y, app::Modifiers m = {}, app::MouseButton b = app::MouseButton::Left) {
    a.onMouseButton({b, app::ButtonAction::Press, x, y, m}, {});
}
void release(app::SculptApp& a, double x, double y, app::Modifiers m = {}, app::MouseButton b = app::MouseButton::Left) {
    a.onMouseButton({b, app::ButtonAction::Release, x, y, m}, {});
}

// How far rounding lets positions of this placement be from exact: 1e-9 of the diameter, or a few ulps of the
// centre's coordinates where those are coarser (1e-3 at 1e7: an ulp of 1e7 is 1.9e-9, 1e-6 of the diameter).
double roundingAllowance(const Placement& p) {
    return 1e-9 * p.diameter + 8.0 * std::numeric_limits<double>::epsilon() * p.centre.cwiseAbs().maxCoeff();
}

// Share of the pixels outside the UI's windows that are not background.
double sceneShare(test::OffscreenWindow& window, render::Rgba8Image& image) {
    const Status drawn = window.frame(&image);
    INFO(drawn.message);
    REQUIRE(drawn.ok);
    return nonBackgroundShare(image.pixels.data(), image.width, image.height, window.uiMask());
}

}  // namespace

TEST_CASE("any scale: a drag in the window moves the picked point with the cursor at both extremes", "[gl]") {
    const std::vector<Placement>& placements = extremePlacements();
    for (size_t i = 0; i < placements.size(); ++i) {
        const Placement& p = placements[i];
        INFO(describe(p));
        app::SculptApp sculptApp;
        loadPlacedSphere(sculptApp, p);
        app::AppState& state = sculptApp.state();
        const Positions original = state.session.mesh().positions;
        test::OffscreenWindow window;
        const Status opened = window.open(sculptApp, kWindowWidth, kWindowHeight, 1);
        if (!opened) WARN("EGL unavailable, window frames not drawn: " << opened.message);
        render::Rgba8Image image;
        if (opened) {
            // With the lattice shown (and framed too), and framed on the mesh alone: a sensible share.
            app::Overlays withCage = state.overlays;
            withCage.sculpt.lattice = true;
            app::setOverlays(state, withCage);
            app::frameMesh(state);
            window.frame(nullptr);  // the first frame builds the font atlas
            const double withLattice = sceneShare(window, image);
            writeForALook(image, "any_scale_window_" + std::to_string(i) + ".png");
            app::Overlays plain = state.overlays;
            plain.sculpt.lattice = false;
            app::setOverlays(state, plain);
            app::frameMesh(state);
            const double meshOnly = sceneShare(window, image);
            INFO("scene share with the lattice " << withLattice << ", mesh alone " << meshOnly);
            CHECK(withLattice > 0.1);
            CHECK(withLattice < 0.9);
            CHECK(meshOnly > 0.1);
            CHECK(meshOnly < 0.9);
        }

        // The ray under the cursor hits the near side of the sphere, and that point projects back under it.
        const double cx = 0.5 * kWindowWidth + 17.0, cy = 0.5 * kWindowHeight - 11.0;
        app::Ray ray;
        REQUIRE(app::rayThroughPixel(state.camera, kWindowWidth, kWindowHeight, cx, cy, ray));
        const app::SurfaceHit hit = app::intersectMesh(ray, original, state.session.mesh().triangles);
        REQUIRE(hit.triangle >= 0);
        CHECK(hit.distance < state.camera.distance);
        CHECK((pixelOf(state, hit.point) - Eigen::Vector2d(cx, cy)).norm() < 0.01);

        // The press grabs that point; every move carries it onto the cursor (the drag plane faces the camera).
        // The whole cage moves (no brush radius): the picked corner below must follow too, and these meshes'
        // triangles are wider than a brush.
        state.tools.brush.limited = false;
        press(sculptApp, cx, cy);
        REQUIRE(state.drag.active);
        CHECK((state.session.stroke().sources().front() - hit.point).norm() < 1e-6 * p.diameter);
        const int vertex = state.drag.pickedVertex;
        for (int m = 1; m <= 6; ++m) {
            const Eigen::Vector2d cursor(cx, cy - 10.0 * m);
            sculptApp.onMouseMove({cursor.x(), cursor.y(), {}}, {});
            INFO("move " << m << ": " << state.status);
            REQUIRE(state.hasReport);
            REQUIRE(state.lastReport.status == core::OpStatus::Applied);
            CHECK((pixelOf(state, state.session.stroke().sources().front()) - cursor).norm() < 0.05);
            if (opened && m == 3) window.frame(nullptr);
        }
        if (opened) {
            REQUIRE(window.frame(&image).ok);
            writeForALook(image, "any_scale_window_drag_" + std::to_string(i) + ".png");
        }
        release(sculptApp, cx, cy - 60.0);
        CHECK(state.session.history().size() == 1);
        // The picked vertex (the hit triangle's nearest corner) went up the screen with the cursor's 60 pixels.
        const Eigen::Vector2d before = pixelOf(state, original.row(vertex).transpose());
        const Eigen::Vector2d after = pixelOf(state, state.session.mesh().positions.row(vertex).transpose());
        CHECK(before.y() - after.y() > 30.0);
        CHECK(before.y() - after.y() < 90.0);
        CHECK(std::abs(after.x() - before.x()) < 10.0);
        // Undo brings everything back, to rounding.
        sculptApp.onKey({app::Key::Z, app::KeyAction::Press, [] { app::Modifiers m; m.control = true; return m; }()}, {});
        CHECK(state.session.history().cursor() == 0);
        CHECK((state.session.mesh().positions - original).cwiseAbs().maxCoeff() <= roundingAllowance(p));
    }
    WARN("window frames at the extreme scales written to " << test::glTestOutputDir() << "/any_scale_window_*.png");
}

TEST_CASE("any scale: markers, control points, pan and zoom in the window work at both extremes", "[gl]") {
    for (const Placement& p : extremePlacements()) {
        INFO(describe(p));
        app::SculptApp sculptApp;
        loadPlacedSphere(sculptApp, p);
        app::AppState& state = sculptApp.state();
        const double cx = 0.5 * kWindowWidth, cy = 0.5 * kWindowHeight;
        app::Modifiers shift;
        shift.shift = true;

        // Shift+click places a handle; its marker is picked at that pixel and not two pick radii away.
        const double hx = cx + 40.0, hy = cy + 25.0;
        press(sculptApp, hx, hy, shift);
        release(sculptApp, hx, hy, shift);
        REQUIRE(state.tools.handles.size() == 1);
        const Positions& positions = state.session.mesh().positions;
        const Triangles& triangles = state.session.mesh().triangles;
        CHECK(app::handleAtPixel(state.tools, positions, triangles, state.camera, kWindowWidth, kWindowHeight, hx, hy, 9.0) == 0);
        CHECK(app::handleAtPixel(state.tools, positions, triangles, state.camera, kWindowWidth, kWindowHeight, hx + 18.0, hy, 9.0) == -1);
        // Dragging it (grabbed a little off its centre) carries its surface point onto the cursor.
        press(sculptApp, hx + 2.0, hy - 1.0);
        REQUIRE(state.drag.active);
        CHECK(state.drag.pickedVertex == -1);  // the handle, not the surface under it
        sculptApp.onMouseMove({hx + 2.0, hy - 31.0, {}}, {});
        REQUIRE(state.lastReport.status == core::OpStatus::Applied);
        const Eigen::Vector2d handlePixel = pixelOf(state, state.session.stroke().sources().front());
        CHECK((handlePixel - Eigen::Vector2d(hx + 2.0, hy - 31.0)).norm() < 0.05);
        release(sculptApp, hx + 2.0, hy - 31.0);

        // Lattice tool: a click on the marker of the control point nearest the eye selects exactly that one.
        sculptApp.onKey({app::Key::Tab, app::KeyAction::Press, {}}, {});
        REQUIRE(state.tools.mode == app::ToolMode::Lattice);
        const Positions controlPoints = core::controlPointPositions(state.session.lattice());
        int nearest = -1;
        double nearestDepth = std::numeric_limits<double>::infinity();
        Eigen::Vector2d nearestPixel;
        for (Eigen::Index c = 0; c < controlPoints.rows(); ++c) {
            double depth = 0.0;
            const Eigen::Vector2d pixel = pixelInWorldFrame(state.camera, controlPoints.row(c).transpose(), depth);
            if (depth < nearestDepth) {
                nearest = static_cast<int>(c);
                nearestDepth = depth;
                nearestPixel = pixel;
            }
        }
        press(sculptApp, nearestPixel.x() + 1.5, nearestPixel.y() - 1.5);
        release(sculptApp, nearestPixel.x() + 1.5, nearestPixel.y() - 1.5);
        CHECK(state.tools.lattice.points == std::vector<int>{nearest});
        sculptApp.onKey({app::Key::Tab, app::KeyAction::Press, {}}, {});

        // Pan (Shift+middle drag): the point at the centre follows the cursor exactly, in every unit.
        const Eigen::Vector3d centre(state.camera.target.x, state.camera.target.y, state.camera.target.z);
        press(sculptApp, 100.0, 100.0, shift, app::MouseButton::Middle);
        sculptApp.onMouseMove({130.0, 80.0, shift}, {});
        release(sculptApp, 130.0, 80.0, shift, app::MouseButton::Middle);
        CHECK((pixelOf(state, centre) - Eigen::Vector2d(cx + 30.0, cy - 20.0)).norm() < 0.01);

        // Zoom: a factor per notch, limited relative to the content. (Home first: what it frames depends on whether
        // the current tool shows the lattice.)
        sculptApp.onKey({app::Key::Home, app::KeyAction::Press, {}}, {});
        const double framed = state.camera.distance;
        sculptApp.onScroll({0.0, 1.0}, {});
        CHECK(state.camera.distance == Approx(0.88 * framed).epsilon(1e-12));
        for (int n = 0; n < 100; ++n) sculptApp.onScroll({0.0, -10.0}, {});
        CHECK(state.camera.distance == Approx(1e3 * state.camera.sceneRadius).epsilon(1e-12));
        sculptApp.onKey({app::Key::Home, app::KeyAction::Press, {}}, {});
        CHECK(state.camera.distance == Approx(framed).epsilon(1e-12));
    }
}
