// The window's overlays as a sculptor meets them, driven with synthetic events: the lattice shown per tool
// and exactly as the Overlays panel says, the outer cage (drawn and picked), and the decimated proxy of a
// large mesh while a drag is in progress. Frames go through an EGL window (offscreen_window.h); where EGL
// is missing the frame checks warn and skip.
#include <catch2/catch.hpp>

#include <array>
#include <filesystem>
#include <fstream>
#include <string>

#include "app/window/sculpt_app.h"
#include "app/window/tool_commands.h"
#include "gl_test_support.h"
#include "io/png_image.h"
#include "offscreen_window.h"
#include "render/overlay_geometry.h"
#include "test_meshes.h"
#include "window_test_support.h"

using namespace sculpt;

namespace {

constexpr int kWidth = 640, kHeight = 400;

void key(app::SculptApp& a, app::Key k) { a.onKey({k, app::KeyAction::Press, {}}, {}); }

render::Rgba8Image frame(test::OffscreenWindow& window) {
    render::Rgba8Image image;
    const Status drawn = window.frame(&image);
    INFO(drawn.message);
    REQUIRE(drawn.ok);
    return image;
}

// Pixel of control point `id` in the app's view.
Eigen::Vector2d pixelOfControlPoint(const app::AppState& state, int id) {
    const Positions points = core::controlPointPositions(state.session.lattice());
    double x = 0.0, y = 0.0;
    REQUIRE(app::projectToPixel(state.camera, kWidth, kHeight, points.row(id).transpose(), x, y));
    return {x, y};
}

}  // namespace

TEST_CASE("window overlays: the lattice is off in the sculpt tool and on in the lattice tool, per tool", "[gl]") {
    app::SculptApp sculptApp;
    test::loadDefaultMesh(sculptApp, kWidth, kHeight);
    app::AppState& state = sculptApp.state();
    CHECK(state.tools.mode == app::ToolMode::Sculpt);
    CHECK_FALSE(app::latticeShown(state));
    key(sculptApp, app::Key::Tab);
    CHECK(app::latticeShown(state));
    // Turned off in the lattice tool, it stays off there and the sculpt tool keeps its own setting.
    app::Overlays overlays = state.overlays;
    app::overlaysOfTool(overlays, app::ToolMode::Lattice).lattice = false;
    app::setOverlays(state, overlays);
    CHECK_FALSE(app::latticeShown(state));
    key(sculptApp, app::Key::Tab);
    CHECK_FALSE(app::latticeShown(state));
    overlays = state.overlays;
    app::overlaysOfTool(overlays, app::ToolMode::Sculpt).lattice = true;
    app::setOverlays(state, overlays);
    CHECK(app::latticeShown(state));
    key(sculptApp, app::Key::Tab);
    CHECK_FALSE(app::latticeShown(state));
}

TEST_CASE("window overlays: what the Lattice checkbox says is what is drawn and picked, in either tool", "[gl]") {
    app::SculptApp sculptApp;
    test::loadDefaultMesh(sculptApp, kWidth, kHeight);
    app::AppState& state = sculptApp.state();
    state.stats.hideTimings = true;
    test::OffscreenWindow window;
    if (Status s = window.open(sculptApp, kWidth, kHeight, 1); !s) {
        WARN("EGL unavailable, window frames not tested: " << s.message);
        return;
    }
    frame(window);  // the font atlas
    const render::Rgba8Image sculptTool = frame(window);
    std::vector<std::uint8_t> ui = window.uiMask();
    key(sculptApp, app::Key::Tab);
    frame(window);
    const render::Rgba8Image latticeOn = frame(window);
    std::vector<std::uint8_t> uiLattice = window.uiMask();
    app::Overlays overlays = state.overlays;
    overlays.latticeTool.lattice = false;
    app::setOverlays(state, overlays);
    frame(window);
    const render::Rgba8Image latticeOff = frame(window);
    const std::vector<std::uint8_t> uiLatticeOff = window.uiMask();  // once: it walks every draw list
    for (size_t p = 0; p < ui.size(); ++p) ui[p] |= uiLattice[p] | uiLatticeOff[p];
    // Outside the panels: the lattice tool with its overlay off draws the scene of the sculpt tool exactly.
    CHECK(test::differingFraction(sculptTool, latticeOn, ui) > 0.02);
    CHECK(test::differingFraction(sculptTool, latticeOff, ui) == 0.0);
    // ... and a click on where a control point is selects nothing: there is nothing drawn to click on.
    const int corner = state.session.lattice().index(0, 0, 0);
    const Eigen::Vector2d at = pixelOfControlPoint(state, corner);
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Press, at.x(), at.y(), {}}, {});
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Release, at.x(), at.y(), {}}, {});
    CHECK(state.tools.lattice.points.empty());
    overlays.latticeTool.lattice = true;
    app::setOverlays(state, overlays);
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Press, at.x(), at.y(), {}}, {});
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Release, at.x(), at.y(), {}}, {});
    CHECK(state.tools.lattice.points == std::vector<int>{corner});
}

TEST_CASE("window overlays: with the outer cage only, inner control points are neither drawn nor picked", "[gl]") {
    app::SculptApp sculptApp;
    test::loadDefaultMesh(sculptApp, kWidth, kHeight);
    app::AppState& state = sculptApp.state();
    key(sculptApp, app::Key::Tab);
    key(sculptApp, app::Key::F);  // frames the lattice too, now that it is shown
    app::Overlays overlays = state.overlays;
    overlays.latticeOuterOnly = true;
    app::setOverlays(state, overlays);
    const core::Lattice& lattice = state.session.lattice();
    const std::vector<std::uint8_t> shown = app::shownControlPoints(state);
    int shownCount = 0;
    for (std::uint8_t s : shown) shownCount += s;
    const int n = lattice.count[0];
    CHECK(shownCount == lattice.controlPointCount() - (n - 2) * (n - 2) * (n - 2));
    CHECK(shown[size_t(lattice.index(0, 3, 4))] == 1);
    CHECK(shown[size_t(lattice.index(3, 3, 4))] == 0);
    // A box over the whole view selects only the outer points.
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Press, 1.0, 1.0, {}}, {});
    sculptApp.onMouseMove({kWidth - 1.0, kHeight - 1.0, {}}, {});
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Release, kWidth - 1.0, kHeight - 1.0, {}}, {});
    CHECK(int(state.tools.lattice.points.size()) == shownCount);
    // A selected inner point stays drawn (and pickable) while it is selected.
    state.tools.lattice.points = {lattice.index(3, 3, 4)};
    CHECK(app::shownControlPoints(state)[size_t(lattice.index(3, 3, 4))] == 1);

    test::OffscreenWindow window;
    if (Status s = window.open(sculptApp, kWidth, kHeight, 1); !s) {
        WARN("EGL unavailable, window frames not tested: " << s.message);
        return;
    }
    frame(window);
    const render::Rgba8Image outer = frame(window);
    overlays.latticeOuterOnly = false;
    app::setOverlays(state, overlays);
    frame(window);
    CHECK(test::differingFraction(outer, frame(window), window.uiMask()) > 0.005);  // the inner cage appeared
}

TEST_CASE("window overlays: a large mesh is drawn as its proxy during a drag, whole after the release", "[gl]") {
    app::SculptApp sculptApp;
    const test::TestMesh sphere = test::makeUvSphere(250, 241);  // 120,000 triangles
    REQUIRE(app::setMesh(sculptApp.state(), sphere.positions, sphere.triangles, "sphere").ok);
    sculptApp.onFramebufferSize({kWidth, kHeight});
    app::frameMesh(sculptApp.state());
    app::AppState& state = sculptApp.state();
    test::OffscreenWindow window;
    if (Status s = window.open(sculptApp, kWidth, kHeight, 1); !s) {
        WARN("EGL unavailable, window frames not tested: " << s.message);
        return;
    }
    const render::Renderer& renderer = sculptApp.renderer();
    frame(window);
    REQUIRE(renderer.proxyTriangleCount() > 0);
    CHECK(renderer.lastDrawnTriangles() == renderer.triangleCount());  // idle: the whole mesh

    const double cx = 0.5 * kWidth, cy = 0.5 * kHeight;
    state.tools.brush.limited = false;  // the whole cage, no brush circle: only the mesh differs between the frames
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Press, cx, cy, {}}, {});
    REQUIRE(state.drag.active);
    render::Rgba8Image dragged;
    for (int m = 1; m <= 5; ++m) {
        sculptApp.onMouseMove({cx, cy - 12.0 * m, {}}, {});
        dragged = frame(window);
        CHECK(renderer.lastDrawnTriangles() == renderer.proxyTriangleCount());
    }
    // The proxy shows the drag's shape: the picture of the same shape drawn whole differs only at the
    // golden tolerance (the silhouette within a pixel), panels aside.
    const std::vector<std::uint8_t> uiDragging = window.uiMask();
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Release, cx, cy - 60.0, {}}, {});
    REQUIRE(state.session.history().size() == 1);
    const render::Rgba8Image released = frame(window);
    CHECK(renderer.lastDrawnTriangles() == renderer.triangleCount());
    std::vector<std::uint8_t> ui = window.uiMask();
    for (size_t p = 0; p < ui.size(); ++p) ui[p] |= uiDragging[p];
    CHECK(test::differingFraction(dragged, released, ui) <= test::goldenMaxDifferingFraction());
    for (const auto& [image, name] : {std::pair<const render::Rgba8Image*, const char*>{&dragged, "proxy_dragging"}, {&released, "proxy_released"}})
        CHECK(io::writePng(test::glTestOutputDir() + "/window_" + name + ".png", image->width, image->height,
                           image->pixels.data()).ok);

    // Orbiting draws the proxy too.
    sculptApp.onMouseButton({app::MouseButton::Middle, app::ButtonAction::Press, cx, cy, {}}, {});
    sculptApp.onMouseMove({cx + 20.0, cy, {}}, {});
    frame(window);
    CHECK(renderer.lastDrawnTriangles() == renderer.proxyTriangleCount());
    sculptApp.onMouseButton({app::MouseButton::Middle, app::ButtonAction::Release, cx + 20.0, cy, {}}, {});
    frame(window);
    CHECK(renderer.lastDrawnTriangles() == renderer.triangleCount());
}

TEST_CASE("window overlays: a scan's vertex colours are drawn, and the Vertex colours checkbox turns them off", "[gl]") {
    app::SculptApp sculptApp;  // outlives the window, whose end releases the app's GL objects
    test::OffscreenWindow window;
    if (!test::openWindowWithDefaultMesh(window, sculptApp, kWidth, kHeight)) return;
    app::AppState& state = sculptApp.state();
    frame(window);
    CHECK_FALSE(state.meshHasVertexColors);  // the default mesh has none: the checkbox is not offered

    // A binary PLY sphere in orange (a scan's colours), written through the program's own PLY writer.
    const test::TestMesh sphere = test::makeUvSphere(48, 25);
    const std::string folder = std::string(SCULPT_GL_TEST_OUTPUT_DIR) + "/window_vertex_colours";
    std::filesystem::create_directories(folder);
    const std::string path = folder + "/orange.ply";
    {
        std::ofstream out(path, std::ios::binary);
        out << "ply\nformat binary_little_endian 1.0\nelement vertex " << sphere.positions.rows()
            << "\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\nproperty uchar green\n"
               "property uchar blue\nelement face "
            << sphere.triangles.rows() << "\nproperty list uchar int vertex_indices\nend_header\n";
        for (Eigen::Index v = 0; v < sphere.positions.rows(); ++v) {
            const float xyz[3] = {float(sphere.positions(v, 0)), float(sphere.positions(v, 1)), float(sphere.positions(v, 2))};
            const unsigned char rgb[3] = {230, 120, 20};
            out.write(reinterpret_cast<const char*>(xyz), sizeof xyz);
            out.write(reinterpret_cast<const char*>(rgb), sizeof rgb);
        }
        for (Eigen::Index t = 0; t < sphere.triangles.rows(); ++t) {
            const unsigned char three = 3;
            const int corners[3] = {sphere.triangles(t, 0), sphere.triangles(t, 1), sphere.triangles(t, 2)};
            out.write(reinterpret_cast<const char*>(&three), 1);
            out.write(reinterpret_cast<const char*>(corners), sizeof corners);
        }
    }
    const Status loaded = sculptApp.loadMesh(path);
    INFO(loaded.message);
    REQUIRE(loaded.ok);
    app::frameMesh(state);
    const auto centre = [&] {
        const render::Rgba8Image image = frame(window);
        const std::uint8_t* p = &image.pixels[(size_t(kHeight / 2) * size_t(kWidth) + size_t(kWidth / 2)) * 4];
        return std::array<int, 3>{p[0], p[1], p[2]};
    };
    std::array<int, 3> c = centre();
    CHECK(state.meshHasVertexColors);
    INFO("coloured: " << c[0] << " " << c[1] << " " << c[2]);
    CHECK(c[0] > c[2] + 80);  // orange: red well over blue
    CHECK(c[1] > c[2] + 30);

    app::Overlays overlays = state.overlays;
    overlays.vertexColors = false;
    app::setOverlays(state, overlays);
    c = centre();
    INFO("clay: " << c[0] << " " << c[1] << " " << c[2]);
    CHECK(c[0] < c[2] + 50);  // the clay is a warm grey, nowhere near that orange

    // Back to a mesh without colours: nothing offered, the clay drawn.
    overlays.vertexColors = true;
    app::setOverlays(state, overlays);
    test::loadDefaultMesh(sculptApp, kWidth, kHeight);
    frame(window);
    CHECK_FALSE(state.meshHasVertexColors);
}
