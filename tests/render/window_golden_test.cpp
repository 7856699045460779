// Full window frames (scene + Dear ImGui sidebar + status line) of the default mesh, driven by synthetic
// events through the same SculptApp code the GLFW window uses, rendered offscreen (EGL, see
// offscreen_window.h) and compared with tests/golden/window_ui.png (thresholds: gl_test_support.cpp).
//
// What makes a frame reproducible: the stats panel's times and frame rate vary run to run, so
// FrameStats::hideTimings shows "--" instead; io.DeltaTime is fixed; a fresh ImGui context per test with no
// imgui.ini; no MSAA (as the window on a software rasterizer); ImGui never sees the synthetic mouse, so
// nothing is hovered. Regenerate after an intended UI change (then look at the picture):
//     SCULPT_UPDATE_GOLDEN=1 ./build/tests/render/gl_tests "[golden]"
// Where EGL is missing these tests warn and skip.
#include <catch2/catch.hpp>

#include <string>

#include "app/window/sculpt_app.h"
#include "gl_test_support.h"
#include "io/obj_mesh.h"
#include "io/png_image.h"
#include "offscreen_window.h"

using namespace sculpt;

namespace {

// The window's default size, so the golden shows the layout users see (and any clipping in it).
constexpr int kWidth = 1280, kHeight = 800;

// Loads assets/default.obj and opens the offscreen window; false (with a warning) where EGL is missing.
// note: the mesh goes in by app::setMesh, not SculptApp::loadMesh, so the menu bar shows no file path: the
// checkout's absolute path would make the picture differ from machine to machine.
bool openDefault(app::SculptApp& sculptApp, test::OffscreenWindow& window) {
    io::ObjMesh mesh;
    const Status loaded = io::loadObj(std::string(SCULPT_SOURCE_DIR) + "/assets/default.obj", mesh);
    INFO(loaded.message);
    REQUIRE(loaded.ok);
    REQUIRE(app::setMesh(sculptApp.state(), mesh.positions, mesh.triangles, "default.obj").ok);
    sculptApp.onFramebufferSize({kWidth, kHeight});
    app::frameMesh(sculptApp.state());
    sculptApp.state().stats.hideTimings = true;
    if (Status s = window.open(sculptApp, kWidth, kHeight, 1); !s) {
        WARN("EGL unavailable, window frames not tested: " << s.message);
        return false;
    }
    return true;
}

void frame(test::OffscreenWindow& window, render::Rgba8Image* image = nullptr) {
    const Status drawn = window.frame(image);
    INFO(drawn.message);
    REQUIRE(drawn.ok);
}

// Two frames: the first after a change lets auto-sized windows measure their new content, the second
// draws them at that size (Dear ImGui's AlwaysAutoResize settles one frame late).
void settledFrame(test::OffscreenWindow& window, render::Rgba8Image& image) {
    frame(window);
    frame(window, &image);
}

// A left-drag from the centre of the view 150 px up in 10 moves, a frame after every move (as the window
// draws between mouse events), then the release. Long enough to change the silhouette, so the drag shows.
void dragUp(app::SculptApp& sculptApp, test::OffscreenWindow& window) {
    const double cx = 0.5 * kWidth, cy = 0.5 * kHeight;
    sculptApp.state().tools.brush.radiusPixels = 200.0;  // a broad pull, as wide as the 150-pixel move
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Press, cx, cy, {}}, {});
    REQUIRE(sculptApp.state().drag.active);
    for (int m = 1; m <= 10; ++m) {
        sculptApp.onMouseMove({cx, cy - 15.0 * m, {}}, {});
        frame(window);
    }
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Release, cx, cy - 150.0, {}}, {});
}

void savePicture(const render::Rgba8Image& image, const std::string& name) {
    const std::string path = test::glTestOutputDir() + "/" + name + ".png";
    const Status written = io::writePng(path, image.width, image.height, image.pixels.data());
    INFO(written.message);
    CHECK(written.ok);
}

}  // namespace

TEST_CASE("window golden: the full UI after a synthetic drag on the default mesh", "[gl][golden]") {
    app::SculptApp sculptApp;
    test::OffscreenWindow window;
    if (!openDefault(sculptApp, window)) return;
    app::AppState& state = sculptApp.state();
    const Positions original = state.session.mesh().positions;
    render::Rgba8Image image;
    settledFrame(window, image);  // the first frame builds the font atlas

    dragUp(sculptApp, window);
    INFO("status: " << state.status);
    REQUIRE(state.session.history().size() == 1);
    REQUIRE_FALSE(state.statusIsError);
    // The mesh changed where it was grabbed (window_app_test.cpp checks the geometry in detail).
    CHECK((state.session.mesh().positions - original).cwiseAbs().maxCoeff() > 0.0);
    settledFrame(window, image);
    savePicture(image, "window_ui_frame");
    test::checkGolden(image, "window_ui");
}

TEST_CASE("window golden: undoing a drag restores the picture from before it", "[gl]") {
    app::SculptApp sculptApp;
    test::OffscreenWindow window;
    if (!openDefault(sculptApp, window)) return;
    app::AppState& state = sculptApp.state();
    const Positions original = state.session.mesh().positions;
    render::Rgba8Image before, dragged, undone;
    settledFrame(window, before);
    const std::vector<std::uint8_t> uiBefore = window.uiMask();

    dragUp(sculptApp, window);
    REQUIRE(state.session.history().size() == 1);
    settledFrame(window, dragged);
    std::vector<std::uint8_t> ui = window.uiMask();

    app::KeyEvent undo;
    undo.key = app::Key::Z;
    undo.modifiers.control = true;
    sculptApp.onKey(undo, {});
    REQUIRE(state.session.history().cursor() == 0);
    const double diagonal = (original.colwise().maxCoeff() - original.colwise().minCoeff()).norm();
    CHECK((state.session.mesh().positions - original).cwiseAbs().maxCoeff() <= 1e-9 * diagonal);
    // The cursor off the mesh, as before the drag (no mouse event yet: no brush circle), so only the mesh is compared.
    sculptApp.onMouseMove({0.5 * kWidth, kHeight - 60.0, {}}, {});
    settledFrame(window, undone);

    // The panels say different things before and after (status line, history list), so only the viewport
    // is compared: every pixel outside the UI windows of all three frames.
    const std::vector<std::uint8_t> uiUndone = window.uiMask();
    for (size_t p = 0; p < ui.size(); ++p) ui[p] |= uiBefore[p] | uiUndone[p];
    long viewport = 0;
    for (std::uint8_t covered : ui) viewport += covered == 0;
    INFO("viewport pixels compared: " << viewport);
    REQUIRE(viewport > kWidth * kHeight / 3);  // the UI is a sidebar and a status line, not the whole window

    const double dragChanged = test::differingFraction(before, dragged, ui);
    const double undoLeft = test::differingFraction(before, undone, ui);
    if (undoLeft > test::goldenMaxDifferingFraction() || dragChanged <= test::goldenMaxDifferingFraction()) {
        savePicture(before, "window_undo_before");
        savePicture(dragged, "window_undo_dragged");
        savePicture(undone, "window_undo_after");
    }
    INFO("pictures (on failure) in " << test::glTestOutputDir() << "/window_undo_*.png");
    // The drag is visible to the comparison (else the check below would prove nothing)...
    CHECK(dragChanged > test::goldenMaxDifferingFraction());
    // ...and the undo takes every viewport pixel back, within the golden threshold.
    CHECK(undoLeft <= test::goldenMaxDifferingFraction());
}

TEST_CASE("window golden: handles, pins and the lattice tool with a selection", "[gl][golden]") {
    app::SculptApp sculptApp;
    test::OffscreenWindow window;
    if (!openDefault(sculptApp, window)) return;
    app::AppState& state = sculptApp.state();
    render::Rgba8Image image;
    settledFrame(window, image);
    const double cx = 0.5 * kWidth, cy = 0.5 * kHeight;
    app::Modifiers shift, control;
    shift.shift = true;
    control.control = true;
    auto click = [&](double x, double y, app::Modifiers m) {
        sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Press, x, y, m}, {});
        sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Release, x, y, m}, {});
    };
    click(cx - 120, cy - 60, shift);   // two handles
    click(cx + 100, cy - 90, shift);
    click(cx - 20, cy + 110, control); // a pin
    REQUIRE(state.tools.handles.size() == 3);
    // Drag the handles together 80 px up: the pin holds.
    double hx = 0, hy = 0;
    REQUIRE(app::projectToPixel(state.camera, kWidth, kHeight,
                                app::handlePosition(state.tools.handles[0], state.session.mesh().positions, state.session.mesh().triangles), hx, hy));
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Press, hx, hy, {}}, {});
    REQUIRE(state.drag.active);
    for (int m = 1; m <= 8; ++m) {
        sculptApp.onMouseMove({hx, hy - 10.0 * m, {}}, {});
        frame(window);
    }
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Release, hx, hy - 80, {}}, {});
    REQUIRE(state.session.history().size() == 1);
    // The lattice tool: a box selection over the upper middle, the selection pinned.
    sculptApp.onKey({app::Key::Tab, app::KeyAction::Press, {}}, {});
    REQUIRE(state.tools.mode == app::ToolMode::Lattice);
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Press, cx - 200, 60, {}}, {});
    sculptApp.onMouseMove({cx + 200, cy - 120, {}}, {});
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Release, cx + 200, cy - 120, {}}, {});
    REQUIRE_FALSE(state.tools.lattice.points.empty());
    sculptApp.onKey({app::Key::P, app::KeyAction::Press, {}}, {});
    sculptApp.onMouseMove({cx + 300, cy + 200, {}}, {});  // the hint for empty space
    settledFrame(window, image);
    savePicture(image, "window_tools_frame");
    test::checkGolden(image, "window_tools");
}
