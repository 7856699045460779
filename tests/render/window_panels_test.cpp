// The panels and the keyboard, driven like a user drives them: Dear ImGui gets synthetic mouse and key input
// (io.MousePos / MouseDown / KeysDown, as its GLFW backend sets them), the app gets the same keys through
// SculptApp::onKey with SculptApp::uiCapture(), as glfw_main.cpp passes them. Checks: rows of the Tools window
// keep their place, a focused text field keeps every key from the 3D view, the number fields of one panel
// all turn into text fields on a double-click, and a key pressed and released within one frame still counts.
#include <catch2/catch.hpp>

#include <filesystem>
#include <string>

#include <imgui.h>
#include <imgui_internal.h>

#include "app/window/key_event_queue.h"
#include "app/window/sculpt_app.h"
#include "gl_test_support.h"
#include "io/png_image.h"
#include "offscreen_window.h"
#include "window_test_support.h"

using namespace sculpt;

namespace {

constexpr int kWidth = 960, kHeight = 600;
constexpr int kEnterIndex = 257;  // where io.KeysDown keeps Enter (GLFW's code, as the GLFW backend maps it)
// Where the Tools window's number fields are in the lattice tool at 960 x 600 (the layout is fixed: one font,
// no imgui.ini), the first box of each row.
constexpr float kFieldX = 703.0f;
constexpr float kResolutionY = 234.0f, kDegreeY = 263.0f, kPaddingY = 292.0f, kPinnedLayersY = 321.0f;

struct Ui {
    app::SculptApp sculptApp;
    test::OffscreenWindow window;
    // The window with the default mesh; latticeTool: switched to it, with its panels laid out (two frames:
    // auto-resize settles a frame later).
    bool open(bool latticeTool) {
        if (!test::openWindowWithDefaultMesh(window, sculptApp, kWidth, kHeight)) return false;
        ImGui::GetIO().KeyMap[ImGuiKey_Enter] = kEnterIndex;
        if (latticeTool) {
            appKey(app::Key::Tab);
            frame();
            frame();
        }
        return true;
    }
    void frame(render::Rgba8Image* image = nullptr) { REQUIRE(window.frame(image).ok); }
    // A click (two frames: down, up) at a pixel; twice for a double-click.
    void click(float x, float y, int clicks = 1) {
        ImGuiIO& io = ImGui::GetIO();
        io.MousePos = ImVec2(x, y);
        for (int c = 0; c < clicks; ++c) {
            io.MouseDown[0] = true;
            frame();
            io.MouseDown[0] = false;
            frame();
        }
    }
    // A key for the app as glfw_main passes it: what ImGui claims now decides.
    void appKey(app::Key key, app::Modifiers m = {}) {
        sculptApp.onKey({key, app::KeyAction::Press, m}, app::SculptApp::uiCapture());
    }
};

float toolsWindowHeight() {
    const ImGuiWindow* tools = ImGui::FindWindowByName("###tools");
    REQUIRE(tools != nullptr);
    return tools->Size.y;
}

// True when the active item is a text field being edited (a number field turned into one included).
bool textFieldActive() {
    const ImGuiContext& g = *ImGui::GetCurrentContext();
    return g.ActiveId != 0 && g.InputTextState.ID == g.ActiveId;
}

}  // namespace

TEST_CASE("window panels: the Tools window's rows keep their place as the selection and its pins change", "[gl]") {
    Ui ui;
    if (!ui.open(true)) return;
    app::AppState& state = ui.sculptApp.state();
    const core::Lattice& lattice = state.session.lattice();
    const std::vector<int> selection = {lattice.index(2, 2, 2), lattice.index(3, 2, 2)};
    std::vector<float> heights;
    // none selected; two unpinned; one of them pinned; both pinned; none again
    for (int step = 0; step < 5; ++step) {
        state.tools.lattice.points = step == 0 || step == 4 ? std::vector<int>{} : selection;
        REQUIRE(state.session.pins().set(selection, false).ok);
        if (step == 2) REQUIRE(state.session.pins().set({selection[0]}, true).ok);
        if (step == 3) REQUIRE(state.session.pins().set(selection, true).ok);
        ui.frame();
        ui.frame();  // auto-resize settles a frame later
        heights.push_back(toolsWindowHeight());
    }
    for (float h : heights) CHECK(h == heights.front());
}

TEST_CASE("window panels: a text field being edited keeps every key from the 3D view", "[gl]") {
    Ui ui;
    if (!ui.open(true)) return;
    app::AppState& state = ui.sculptApp.state();
    ui.appKey(app::Key::Numpad1);  // not captured: the front view
    CHECK(state.camera.orthographic);
    ui.appKey(app::Key::Numpad5);
    const render::Camera camera = state.camera;
    // A double-click on the first Resolution box; the keys come right after the frame that activated it, before
    // the next NewFrame would update io.WantCaptureKeyboard.
    ImGuiIO& io = ImGui::GetIO();
    io.MousePos = ImVec2(kFieldX, kResolutionY);
    io.MouseDown[0] = true;
    ui.frame();
    io.MouseDown[0] = false;
    ui.frame();
    io.MouseDown[0] = true;
    ui.frame();
    REQUIRE(textFieldActive());
    CHECK(app::SculptApp::uiCapture().keyboard);
    app::Modifiers control;
    control.control = true;
    for (app::Key key : {app::Key::G, app::Key::R, app::Key::S, app::Key::Digit1, app::Key::Numpad1, app::Key::Numpad5,
                         app::Key::NumpadDecimal, app::Key::Home, app::Key::Tab, app::Key::Escape})
        ui.appKey(key);
    ui.appKey(app::Key::A, control);
    ui.appKey(app::Key::A);
    CHECK_FALSE(state.transform.active);
    CHECK(state.tools.lattice.points.empty());
    CHECK(state.tools.mode == app::ToolMode::Lattice);
    CHECK(state.camera.yawDeg == camera.yawDeg);
    CHECK(state.camera.orthographic == camera.orthographic);
    CHECK(state.camera.target == camera.target);
    io.MouseDown[0] = false;
    ui.frame();
}

TEST_CASE("window panels: every number field of the lattice set-up turns into a text field on a double-click", "[gl]") {
    Ui ui;
    if (!ui.open(true)) return;
    for (const float y : {kResolutionY, kDegreeY, kPaddingY, kPinnedLayersY}) {
        INFO("row at y = " << y);
        ui.click(kFieldX, y, 2);
        CHECK(textFieldActive());
        ui.click(800.0f, 130.0f);  // on the selection line: leaves the field
        CHECK_FALSE(textFieldActive());
    }
}

TEST_CASE("window panels: Enter pressed and released within one frame in the Open dialog's name field opens the file", "[gl]") {
    const std::string path = test::glTestOutputDir() + "/tapped_enter.obj";
    std::filesystem::copy_file(std::string(SCULPT_SOURCE_DIR) + "/assets/default.obj", path,
                               std::filesystem::copy_options::overwrite_existing);
    for (const bool queued : {false, true}) {
        INFO((queued ? "through KeyEventQueue" : "straight to io.KeysDown"));
        Ui ui;
        if (!ui.open(false)) return;
        app::AppState& state = ui.sculptApp.state();
        app::Modifiers control;
        control.control = true;
        ui.appKey(app::Key::O, control);
        REQUIRE(ui.sculptApp.files().dialog().isOpen());
        ui.frame();
        ui.frame();  // the name field takes the keyboard focus
        REQUIRE(textFieldActive());
        ImGui::GetIO().AddInputCharactersUTF8(path.c_str());
        ui.frame();
        // Enter down and up between two frames, as a quick tap on a slow frame arrives.
        app::KeyEventQueue keys;
        ImGuiIO& io = ImGui::GetIO();
        for (const bool down : {true, false}) {
            const auto deliver = [&, down] {
                io.KeysDown[kEnterIndex] = down;
                ui.sculptApp.onKey({app::Key::Enter, down ? app::KeyAction::Press : app::KeyAction::Release, {}},
                                   app::SculptApp::uiCapture());
            };
            if (queued) keys.push(kEnterIndex, true, deliver);
            else deliver();
        }
        for (int f = 0; f < 3; ++f) {
            ui.frame();
            keys.frameDone();
        }
        ui.sculptApp.files().finishJob(state);
        if (queued) {
            CHECK_FALSE(ui.sculptApp.files().dialog().isOpen());
            CHECK(state.meshName == "tapped_enter.obj");
        } else {  // what Dear ImGui 1.86 does with it alone: the tap is lost
            CHECK(ui.sculptApp.files().dialog().isOpen());
            CHECK(state.meshName == "default.obj");
        }
    }
}
