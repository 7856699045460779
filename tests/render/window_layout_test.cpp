// Issue: panels hide what they should show. At 1280 x 800 and larger, with every section of both side panels
// open, the det J overlay on and a status message long enough to wrap: no panel covers the det J legend (its
// rectangle computed here from render::buildJacobianLegend's own triangles) or reaches under the status line,
// a panel whose content is taller than the room it has scrolls (a scrollbar, so the content is reachable), the
// two panels do not overlap, and the history list keeps its current entry in view as steps are added and
// undone. Driven through SculptApp's keys; a screenshot of each layout is written for a person to look at.
#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>
#include <string>

#include <imgui.h>
#include <imgui_internal.h>

#include "app/window/sculpt_app.h"
#include "app/window/tool_commands.h"
#include "gl_test_support.h"
#include "io/png_image.h"
#include "offscreen_window.h"
#include "render/legend.h"
#include "window_test_support.h"

using namespace sculpt;

namespace {

void key(app::SculptApp& a, app::Key k, app::Modifiers m = {}) { a.onKey({k, app::KeyAction::Press, m}, {}); }

// Opens every collapsing header of a window (the sections are top-level items of the panel's window).
void openSections(const char* windowName, std::initializer_list<const char*> headers) {
    ImGuiWindow* window = ImGui::FindWindowByName(windowName);
    REQUIRE(window != nullptr);
    for (const char* header : headers) window->StateStorage.SetInt(ImHashStr(header, 0, window->ID), 1);
}

ImRect rectOf(const char* windowName) {
    const ImGuiWindow* window = ImGui::FindWindowByName(windowName);
    REQUIRE(window != nullptr);
    return window->Rect();
}

// The legend's rectangle: the bounding box of its triangles' pixel positions.
ImRect legendRect(int width, int height, float insetBottom) {
    const std::vector<float> v = render::buildJacobianLegend(width, height, 1.0f, insetBottom, 2.0f);
    REQUIRE(!v.empty());
    ImRect r(ImVec2(1e9f, 1e9f), ImVec2(-1e9f, -1e9f));
    for (size_t i = 0; i + 1 < v.size(); i += render::kOverlayFloats) r.Add(ImVec2(v[i], v[i + 1]));
    return r;
}

// A panel is reachable: all its content fits, or it scrolls.
void checkReachable(const char* windowName) {
    const ImGuiWindow* window = ImGui::FindWindowByName(windowName);
    REQUIRE(window != nullptr);
    INFO(windowName << ": content " << window->ContentSize.y << " px in " << window->InnerRect.GetHeight() << " px");
    if (window->ContentSize.y > window->InnerRect.GetHeight() + 1.0f) CHECK(window->ScrollbarY);
}

}  // namespace

TEST_CASE("window layout: no panel hides the det J legend or reaches under the status line, and each is reachable", "[gl][layout]") {
    struct Size { int width, height; };
    for (const Size size : {Size{1280, 800}, Size{1600, 900}, Size{1920, 1080}}) {
        for (const bool latticeTool : {false, true}) {
            app::SculptApp sculptApp;
            test::OffscreenWindow window;
            if (!test::openWindowWithDefaultMesh(window, sculptApp, size.width, size.height)) return;
            app::AppState& state = sculptApp.state();
            app::Overlays overlays = state.overlays;
            overlays.jacobian = true;
            app::setOverlays(state, overlays);
            if (latticeTool) key(sculptApp, app::Key::Tab);
            REQUIRE(window.frame().ok);
            openSections("###tools", {"Brush", "Handles and pins", "Selection", "Lattice set-up", "Lattices"});
            openSections("###sidebar", {"Statistics", "Overlays", "Injectivity", "History"});
            // Steps enough to fill the history list: moves of one control point, typed.
            state.tools.lattice.points = {state.session.lattice().controlPointCount() / 2};
            const bool wasLattice = state.tools.mode == app::ToolMode::Lattice;
            if (!wasLattice) key(sculptApp, app::Key::Tab);
            for (int step = 0; step < 12; ++step) {
                key(sculptApp, app::Key::G);
                key(sculptApp, app::Key::X);
                for (app::Key k : {app::Key::Digit0, app::Key::Period, app::Key::Digit0, static_cast<app::Key>(static_cast<int>(app::Key::Digit0) + 2)})
                    key(sculptApp, k);
                key(sculptApp, app::Key::Enter);
                REQUIRE(state.session.history().cursor() == step + 1);
            }
            if (!wasLattice) key(sculptApp, app::Key::Tab);
            app::setStatus(state, "A status message long enough to wrap onto a second and a third line of the status bar "
                                  "at every window size tried here, so the status line grows upward and the panels "
                                  "above it must end higher: " + std::string(200, 'x'), false);
            for (int f = 0; f < 4; ++f) REQUIRE(window.frame().ok);
            INFO(size.width << " x " << size.height << (latticeTool ? ", lattice tool" : ", sculpt tool"));
            const float statusTop = static_cast<float>(size.height) - state.statusLineHeight;
            CHECK(state.statusLineHeight > ImGui::GetFrameHeight() * 2.0f);  // it did wrap
            const ImRect sidebar = rectOf("###sidebar"), tools = rectOf("###tools");
            const ImRect legend = legendRect(size.width, size.height, state.statusLineHeight);
            CHECK(sidebar.Max.y <= statusTop);
            CHECK(tools.Max.y <= statusTop);
            CHECK_FALSE(tools.Overlaps(legend));
            CHECK_FALSE(sidebar.Overlaps(legend));
            CHECK_FALSE(sidebar.Overlaps(tools));
            checkReachable("###sidebar");
            checkReachable("###tools");
            // The history list shows its current entry, after new steps and after undoing most of them.
            CHECK(state.historyCurrentVisible);
            for (int u = 0; u < 10; ++u) key(sculptApp, app::Key::Z, [] { app::Modifiers m; m.control = true; return m; }());
            for (int f = 0; f < 3; ++f) REQUIRE(window.frame().ok);
            CHECK(state.session.history().cursor() == 2);
            CHECK(state.historyCurrentVisible);
            if (size.width == 1280) {
                render::Rgba8Image image;
                REQUIRE(window.frame(&image).ok);
                const std::filesystem::path dir = test::glTestOutputDir();
                const std::string name = std::string("layout_1280x800_") + (latticeTool ? "lattice" : "sculpt") + ".png";
                REQUIRE(io::writePng((dir / name).string(), image.width, image.height, image.pixels.data()).ok);
                WARN("layout written to " << (dir / name).string());
            }
        }
    }
}

// Issue: the right-hand hint still read "Drag: box select..." after switching to the sculpt tool, until the mouse
// moved. The hint follows the tool (Tab or the Tools panel's radio buttons), the brush and the undo at once.
TEST_CASE("window layout: the cursor's hint follows a tool switch without a mouse move", "[gl][layout]") {
    app::SculptApp sculptApp;
    test::OffscreenWindow window;
    if (!test::openWindowWithDefaultMesh(window, sculptApp, 1280, 800)) return;
    app::AppState& state = sculptApp.state();
    // The cursor over empty view, away from the panels and the mesh.
    sculptApp.onMouseMove({640.0, 760.0, {}}, {});
    REQUIRE(window.frame().ok);
    const std::string sculptHint = state.tools.hint;
    REQUIRE(sculptHint.rfind("Off the mesh: a drag here sculpts nothing", 0) == 0);
    for (int round = 0; round < 3; ++round) {
        key(sculptApp, app::Key::Tab);  // the key
        REQUIRE(window.frame().ok);
        CHECK(state.tools.mode == app::ToolMode::Lattice);
        CHECK(state.tools.hint.rfind("Drag: box select", 0) == 0);
        app::setToolMode(state, app::ToolMode::Sculpt);  // what the Tools panel's radio button calls
        REQUIRE(window.frame().ok);
        CHECK(state.tools.hint == sculptHint);
    }
    // Brush kind: the Hammer's hint at once.
    state.tools.brush.kind = app::BrushTool::Kind::Hammer;
    REQUIRE(window.frame().ok);
    CHECK(state.tools.hint.rfind("Click: raise", 0) == 0);
}
