// Lattices of any shape in the window (Coquillart 1990, EFFD, 3.1-3.4; issue point 10): the Lattices panel's
// buttons, clicked with synthetic Dear ImGui input as a user clicks them, issue the session commands the
// script ops issue (add_lattice with "place", freeze, unfreeze) and each is one undoable history entry; a
// frozen cylinder is drawn with curved chunk edges on its circles and each welded point once; a welded point
// picked with the lattice tool and dragged 5 px moves its whole weld group and the mesh.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <set>

#include <imgui.h>

#include "app/scene_builder.h"
#include "app/window/lattice_commands.h"
#include "app/window/picking.h"
#include "app/window/sculpt_app.h"
#include "app/window/tools.h"
#include "core/volume/lattice_net.h"
#include "gl_test_support.h"
#include "io/lattice_file.h"
#include "io/png_image.h"
#include "offscreen_window.h"
#include "render/overlay_geometry.h"
#include "render/palette.h"
#include "window_test_support.h"

using namespace sculpt;

namespace {

constexpr int kWidth = 960, kHeight = 600;

// A cylinder around the y axis through the default mesh, taller than it (its top circle, at y = 1, is above
// the mesh), 3 chunks around (each arc 120 degrees: the control net's chords are far from the circle).
constexpr double kRadius = 0.6;
core::LatticeTool cylinderTool() {
    core::LatticeNet net;
    REQUIRE(core::makeCylinderNet(Eigen::Vector3d(0, -1.0, 0), Eigen::Vector3d::UnitY(), kRadius, 2.0, {2, 3, 2}, {2, 2}, net));
    return {"pie", std::make_shared<const core::LatticeNet>(net)};
}

void addAndFreezeCylinder(core::Session& session) {
    core::OpReport report;
    REQUIRE(session.tools().add(cylinderTool(), report));
    REQUIRE(session.tools().freeze(static_cast<int>(session.tools().list().size()) - 1, 0, report));
    INFO(report.reason);
    REQUIRE(report.status == core::OpStatus::Applied);
}

struct Ui {
    app::SculptApp sculptApp;
    test::OffscreenWindow window;
    // Tall enough that the Tools window shows the whole Lattices section below the brush (a shorter window
    // scrolls it).
    static constexpr int kPanelHeight = 1000;
    bool open() {
        if (!test::openWindowWithDefaultMesh(window, sculptApp, kWidth, kPanelHeight)) return false;
        frame();
        frame();
        return true;
    }
    void frame() { REQUIRE(window.frame().ok); }
    void clickAt(float x, float y) {
        ImGuiIO& io = ImGui::GetIO();
        io.MousePos = ImVec2(x, y);
        io.MouseDown[0] = true;
        frame();
        io.MouseDown[0] = false;
        frame();
        frame();  // auto-resize and the panel's recorded rectangles settle a frame later
    }
    // Where the Lattices panel's item `label` was drawn last frame.
    app::LatticesPanelState::ItemRect rect(const std::string& label) {
        const std::vector<app::LatticesPanelState::ItemRect>& items = sculptApp.state().lattices.items;
        const auto item = std::find_if(items.begin(), items.end(), [&](const auto& r) { return r.label == label; });
        INFO("Lattices panel item " << label);
        REQUIRE(item != items.end());
        return *item;
    }
    // Clicks the Lattices panel's item `label` where it was drawn last frame.
    void click(const std::string& label) {
        const app::LatticesPanelState::ItemRect item = rect(label);
        clickAt(0.5f * (item.x0 + item.x1), 0.5f * (item.y0 + item.y1));
    }
    // Opens the panel (its header) and chooses the shipped cylinder in the library combo.
    void openPanelWithCylinder() {
        click("Lattices");
        REQUIRE(sculptApp.state().lattices.libraryLoaded);
        const std::vector<app::LatticeLibraryEntry>& library = sculptApp.state().lattices.library;
        const auto cylinder = std::find_if(library.begin(), library.end(), [](const auto& e) { return e.name == "cylinder"; });
        REQUIRE(cylinder != library.end());
        sculptApp.state().lattices.libraryChoice = static_cast<int>(cylinder - library.begin());
        frame();
    }
    void appKey(app::Key key, app::Modifiers m = {}) { sculptApp.onKey({key, app::KeyAction::Press, m}, {}); }
    void undo() { appKey(app::Key::Z, {false, true, false, false}); }
    void redo() { appKey(app::Key::Z, {true, true, false, false}); }
};

}  // namespace

TEST_CASE("window lattices: the panel adds, places, freezes and unfreezes through undoable session commands", "[gl][effd]") {
    Ui ui;
    if (!ui.open()) return;
    app::AppState& state = ui.sculptApp.state();
    core::Session& session = state.session;
    ui.click("Lattices");  // the header: the panel opens and reads the shipped library
    REQUIRE(state.lattices.libraryLoaded);
    const std::vector<app::LatticeLibraryEntry>& library = state.lattices.library;
    const auto cylinder = std::find_if(library.begin(), library.end(), [](const auto& e) { return e.name == "cylinder"; });
    REQUIRE(cylinder != library.end());
    state.lattices.libraryChoice = static_cast<int>(cylinder - library.begin());
    ui.frame();

    // Add: add_lattice, one history entry; undo and redo.
    size_t history = session.history().size();
    ui.click("Add");
    INFO(state.status);
    REQUIRE(session.tools().list().size() == 1);
    CHECK(session.tools().list()[0].name == "cylinder");
    CHECK(session.history().size() == history + 1);
    CHECK(app::latticeToolsShown(state));  // drawn (dim, at rest) though the sculpt tool's Lattice overlay is off
    CHECK_FALSE(app::latticeShown(state));
    ui.undo();
    CHECK(session.tools().list().empty());
    ui.redo();
    REQUIRE(session.tools().list().size() == 1);

    // Place at picked point: the next click on the mesh puts the library lattice there, aligned with the normal.
    history = session.history().size();
    ui.click("Place on mesh");
    REQUIRE(state.lattices.placing == app::LatticesPanelState::Placing::LibraryEntry);
    const double x = 0.5 * kWidth, y = 0.5 * Ui::kPanelHeight;
    app::Ray ray;
    REQUIRE(app::rayThroughPixel(state.camera, kWidth, Ui::kPanelHeight, x, y, ray));
    const app::SurfaceHit hit = app::intersectMesh(ray, session.mesh().positions, session.mesh().triangles);
    REQUIRE(hit.triangle >= 0);
    ui.sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Press, x, y, {}}, {});
    ui.sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Release, x, y, {}}, {});
    REQUIRE(session.tools().list().size() == 2);
    CHECK(session.history().size() == history + 1);
    CHECK(state.lattices.placing == app::LatticesPanelState::Placing::None);
    CHECK(session.mesh().positions == session.mesh().original);  // placing never touches the mesh
    const core::LatticeNet& placed = *session.tools().list()[1].volume->tensorNet();
    CHECK((placed.bounds.center() - hit.point).norm() < 1e-9 * test::boundsDiagonal(session.mesh().positions) + 1e-12);
    // Scaled so its own bounds' diagonal (before turning onto the normal) is the panel's size: distances
    // between its points grow by size / the library net's diagonal.
    const core::LatticeNet& original = *cylinder->volume->tensorNet();
    const int last = original.slotCount() - 1;
    CHECK((placed.rest.row(last) - placed.rest.row(0)).norm() ==
          Approx((original.rest.row(last) - original.rest.row(0)).norm() * app::placementSize(state) / original.diagonal()).epsilon(1e-9));
    ui.undo();
    CHECK(session.tools().list().size() == 1);
    ui.redo();
    REQUIRE(session.tools().list().size() == 2);
    ui.frame();

    // Freezing the library cylinder as it came (inside the closed mesh, holding none of its vertices) is an error
    // on the status line, and nothing changes.
    ui.click("tool 0");
    REQUIRE(state.lattices.selectedTool == 0);
    history = session.history().size();
    ui.click("Freeze");
    CHECK(state.statusIsError);
    CHECK(state.status.find("holds none of the mesh's vertices") != std::string::npos);
    CHECK(session.tools().frozen() == -1);
    CHECK(session.history().size() == history);
    // Freeze the placed one, undo, redo; Unfreeze, undo.
    ui.frame();
    ui.click("tool 1");
    REQUIRE(state.lattices.selectedTool == 1);
    ui.click("Freeze");
    INFO(state.status);
    REQUIRE(session.tools().frozen() == 1);
    REQUIRE(session.lattice().volume != nullptr);
    CHECK(session.history().size() == history + 1);
    ui.undo();
    CHECK(session.tools().frozen() == -1);
    CHECK(session.lattice().volume == nullptr);
    ui.redo();
    REQUIRE(session.tools().frozen() == 1);
    ui.frame();
    ui.click("Unfreeze");
    CHECK(session.tools().frozen() == -1);
    CHECK(session.history().size() == history + 2);
    ui.undo();
    CHECK(session.tools().frozen() == 1);
    // A frozen tool cannot be removed: the button is disabled (the engine would refuse it too).
    ui.frame();
    ui.click("Remove");
    CHECK(session.tools().list().size() == 2);

    // Esc takes a waiting placement back; nothing is added.
    history = session.history().size();
    ui.click("Place on mesh");
    REQUIRE(state.lattices.placing == app::LatticesPanelState::Placing::LibraryEntry);
    ui.appKey(app::Key::Escape);
    CHECK(state.lattices.placing == app::LatticesPanelState::Placing::None);
    CHECK(session.history().size() == history);

    // Save to library: the placed tool round-trips through its file; a save that cannot be written says so on
    // the status line and leaves the file that is there as it was.
    const std::string path = test::glTestOutputDir() + "/placed.lattice.json";
    REQUIRE(app::saveLatticeToolCommand(state, 1, path).ok);
    io::LatticeFile file;
    REQUIRE(io::readLatticeFile(path, file).ok);
    CHECK(file.name == "cylinder");
    CHECK(file.volume->restControlPoints() == session.tools().list()[1].volume->restControlPoints());
    CHECK_FALSE(app::saveLatticeToolCommand(state, 1, test::glTestOutputDir() + "/no such folder/x.lattice.json").ok);
    CHECK(state.statusIsError);
    REQUIRE(app::openLatticeFile(state, path));  // and it can be opened into the library again
    CHECK(state.lattices.library[size_t(state.lattices.libraryChoice)].path == path);
}

TEST_CASE("window lattices: a frozen cylinder is drawn with curved edges on its circles and each welded point once", "[gl][effd]") {
    core::Session session;
    {
        app::SculptApp loader;
        test::loadDefaultMesh(loader, kWidth, kHeight);
        session = std::move(loader.state().session);
    }
    addAndFreezeCylinder(session);
    const core::Lattice& lattice = session.lattice();
    const render::SceneData scene = app::sceneFromSession(session, app::SceneRequest{});

    // One marker per weld group (its representative), control-net edges only between representatives.
    std::set<int> groups;
    for (int id = 0; id < lattice.controlPointCount(); ++id) groups.insert(lattice.representative(id));
    std::vector<float> edges, markers;
    render::Bounds bounds;
    REQUIRE(render::buildLatticeInstances(scene.lattice, {}, edges, markers, bounds).ok);
    CHECK(markers.size() == groups.size() * render::kMarkerFloats);
    CHECK(groups.size() < size_t(lattice.controlPointCount()));

    // Drawn from above: the top circle (y = 1, above the mesh) is teal along its whole length.
    render::ScreenshotOptions options;
    options.width = 480;
    options.height = 480;
    options.yawDeg = 20.0f;
    options.pitchDeg = 65.0f;
    options.overlays.lattice = true;
    render::Rgba8Image image;
    render::OffscreenRenderer& renderer = test::glTestRenderer();
    REQUIRE(renderer.renderScene(scene, options, image).ok);
    const render::Camera camera = render::screenshotCamera(renderer.renderer().meshBounds(), renderer.renderer().latticeBounds(), options);
    const auto teal = [&](int px, int py) {
        if (px < 0 || py < 0 || px >= image.width || py >= image.height) return false;
        const std::uint8_t* p = &image.pixels[size_t(4 * (py * image.width + px))];
        return int(p[1]) - int(p[0]) > 40 && int(p[2]) - int(p[0]) > 40;
    };
    const auto tealNear = [&](const Eigen::Vector3d& point, int reach) {
        double px = 0, py = 0;
        REQUIRE(app::projectToPixel(camera, image.width, image.height, point, px, py));
        for (int dy = -reach; dy <= reach; ++dy)
            for (int dx = -reach; dx <= reach; ++dx)
                if (teal(int(std::lround(px)) + dx, int(std::lround(py)) + dy)) return true;
        return false;
    };
    int onCircle = 0;
    constexpr int kSamples = 72;
    for (int s = 0; s < kSamples; ++s) {
        const double angle = 2.0 * M_PI * s / kSamples;
        onCircle += tealNear(Eigen::Vector3d(kRadius * std::cos(angle), 1.0, kRadius * std::sin(angle)), 2);
    }
    INFO(onCircle << " of " << kSamples << " points of the top circle have a teal pixel within 2 px");
    CHECK(onCircle >= kSamples * 9 / 10);  // a few may sit under a control point's marker
    // The control net's chords of the top ring (from an arc's end to its middle control point, 2 R out) are
    // not curves: no teal at their midpoints.
    const Positions cage = session.cage().cagePoints();
    int chords = 0;
    for (int j = 0; j + 1 < lattice.count[1]; ++j) {
        const int a = lattice.index(lattice.count[0] - 1, j, lattice.count[2] - 1), b = lattice.index(lattice.count[0] - 1, j + 1, lattice.count[2] - 1);
        const Eigen::Vector3d middle = 0.5 * (cage.row(a) + cage.row(b)).transpose();
        if (std::hypot(middle.x(), middle.z()) < kRadius * 1.2) continue;
        ++chords;
        CHECK_FALSE(tealNear(middle, 1));
    }
    CHECK(chords >= 3);
}

TEST_CASE("window lattices: a welded point of a frozen cylinder dragged 5 px moves its whole weld group and the mesh", "[gl][effd]") {
    app::SculptApp sculptApp;
    test::loadDefaultMesh(sculptApp, kWidth, kHeight);
    app::AppState& state = sculptApp.state();
    core::Session& session = state.session;
    core::OpReport added;
    REQUIRE(session.tools().add(cylinderTool(), added));
    app::freezeLatticeCommand(state, 0, 0);  // the panel's Freeze
    INFO(state.status);
    REQUIRE(session.tools().frozen() == 0);
    sculptApp.onKey({app::Key::Tab, app::KeyAction::Press, {}}, {});
    REQUIRE(state.tools.mode == app::ToolMode::Lattice);
    const core::Lattice& lattice = session.lattice();
    // The axis point of the second slice: one weld group of every angle's slot, not on a boundary face.
    const int rep = lattice.representative(lattice.index(0, 1, 1));
    std::vector<int> group;
    for (int id = 0; id < lattice.controlPointCount(); ++id)
        if (lattice.representative(id) == rep) group.push_back(id);
    REQUIRE(group.size() == size_t(lattice.count[1]));
    REQUIRE_FALSE(lattice.pinned[size_t(rep)]);
    // What is picked is what is drawn: only representatives are shown.
    const std::vector<std::uint8_t> shown = app::shownControlPoints(state);
    for (int id : group) CHECK(bool(shown[size_t(id)]) == (id == rep));

    const Positions before = session.mesh().positions;
    const size_t history = session.history().size();
    const Eigen::Vector2d start = test::pixelOf(state, session.cage().cagePoints().row(rep).transpose());
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Press, start.x(), start.y(), {}}, {});
    INFO(state.status);
    REQUIRE(state.drag.active);
    REQUIRE(state.tools.lattice.points == std::vector<int>{rep});
    // Pressed: selected, not moving yet (the status line once said "Moving 1 control point..." here, and
    // kept it after a mere click).
    const std::array<int, 3> ijk = lattice.ijk(rep);
    CHECK(state.status == "Selected control point [" + std::to_string(ijk[0]) + "," + std::to_string(ijk[1]) + "," +
                              std::to_string(ijk[2]) + "] - drag to move it, G to grab.");
    sculptApp.onMouseMove({start.x(), start.y() - 5.0, {}}, {});
    CHECK(state.status.rfind("Moving 1 control point: ", 0) == 0);
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Release, start.x(), start.y() - 5.0, {}}, {});
    CHECK(state.status.rfind("Drag recorded as one undo step", 0) == 0);
    CHECK(session.history().size() == history + 1);
    // Every copy of the welded point moved by the same displacement, and the point is drawn where the cursor is.
    const Eigen::RowVector3d moved = lattice.displacement.row(rep);
    CHECK(moved.norm() > 0.0);
    for (int id : group) CHECK(lattice.displacement.row(id) == moved);
    const Eigen::Vector2d shownAt = test::pixelOf(state, session.cage().cagePoints().row(rep).transpose());
    CHECK((shownAt - Eigen::Vector2d(start.x(), start.y() - 5.0)).norm() < 0.05);
    // The mesh followed.
    CHECK((session.mesh().positions - before).rowwise().norm().maxCoeff() > 1e-3);
    sculptApp.onKey({app::Key::Z, app::KeyAction::Press, {false, true, false, false}}, {});
    CHECK((session.mesh().positions - before).cwiseAbs().maxCoeff() < 1e-9);
}

// Issue: the list box and the lines under it changed height with the state (number of tools, the selected
// tool's description, the mode line, the placing prompt), so the buttons jumped as the user clicked. Every
// state below draws them at the same pixels.
TEST_CASE("window lattices: the panel's buttons stay where they are whatever the list and the lines under it say", "[gl][effd]") {
    Ui ui;
    if (!ui.open()) return;
    app::AppState& state = ui.sculptApp.state();
    core::Session& session = state.session;
    ui.openPanelWithCylinder();
    const std::vector<std::string> labels = {"Freeze", "Unfreeze", "Remove", "Move on mesh", "Save to library...", "edit axis",
                                             "Insert knot", "Refine axis", "library", "Open...", "Add", "Place on mesh"};
    const auto layout = [&](const char* name) {
        ui.frame();
        ui.frame();  // the Tools window's auto-resize settles a frame later
        render::Rgba8Image image;
        REQUIRE(ui.window.frame(&image).ok);
        CHECK(io::writePng(test::glTestOutputDir() + "/lattices_panel_" + name + ".png", image.width, image.height,
                           image.pixels.data()).ok);
        std::vector<std::array<float, 4>> rects;
        for (const std::string& label : labels) {
            const app::LatticesPanelState::ItemRect r = ui.rect(label);
            rects.push_back({r.x0, r.y0, r.x1, r.y1});
        }
        return rects;
    };
    const auto reference = layout("empty");  // no tools: "None yet" in the list, the edit-mode line
    ui.click("Add");
    REQUIRE(session.tools().list().size() == 1);
    CHECK(layout("one") == reference);  // one tool, selected: its description under the list
    state.lattices.selectedTool = -1;
    CHECK(layout("unselected") == reference);
    // A ball's description is longer than a cylinder's.
    const std::vector<app::LatticeLibraryEntry>& library = state.lattices.library;
    const auto ball = std::find_if(library.begin(), library.end(), [](const auto& e) { return e.name == "ball"; });
    REQUIRE(ball != library.end());
    for (int t = 0; t < 6; ++t) app::addLatticeFromLibrary(state, static_cast<int>(ball - library.begin()));
    REQUIRE(session.tools().list().size() == 7);  // more than the list's rows: it scrolls
    CHECK(layout("seven") == reference);
    // Frozen (a cylinder around the mesh's middle holds vertices): the mode line names it.
    core::OpReport added;
    REQUIRE(session.tools().add(cylinderTool(), added));
    app::freezeLatticeCommand(state, 7, 0);
    INFO(state.status);
    REQUIRE(session.tools().frozen() == 7);
    state.lattices.selectedTool = 7;
    CHECK(layout("frozen") == reference);
    ui.click("tool 0");
    app::beginPlacingLattice(state, app::LatticesPanelState::Placing::LibraryEntry);  // the orange prompt
    CHECK(layout("placing") == reference);
}

TEST_CASE("window lattices: Insert knot and Refine axis add points to the selected tool without changing its shape", "[gl][effd]") {
    Ui ui;
    if (!ui.open()) return;
    app::AppState& state = ui.sculptApp.state();
    core::Session& session = state.session;
    ui.openPanelWithCylinder();
    ui.click("Add");
    REQUIRE(session.tools().list().size() == 1);
    REQUIRE(state.lattices.selectedTool == 0);
    const std::shared_ptr<const core::Volume> before = session.tools().list()[0].volume;
    const core::LatticeNet& old = *before->tensorNet();
    // Split the axial chunk holding w = 0.3 (the slider's value), as the user sets it.
    state.lattices.editAxis = 2;
    state.lattices.insertAt = 0.3;
    const size_t history = session.history().size();
    ui.frame();
    ui.click("Insert knot");
    INFO(state.status);
    REQUIRE(session.history().size() == history + 1);
    CHECK(state.status.find("Inserted a knot at w = 0.300 in cylinder") != std::string::npos);
    const core::LatticeNet& split = *session.tools().list()[0].volume->tensorNet();
    CHECK(split.count[2] == old.count[2] + 1);
    CHECK(split.axes[2].spans == old.axes[2].spans + 1);
    CHECK(session.mesh().positions == session.mesh().original);  // editing a tool never touches the mesh
    // The same shape: every point of the old volume is a point of the new one at the same knot parameter.
    for (int sample = 0; sample < 50; ++sample) {
        Eigen::Vector3d t(0.02 * sample, 1.0 - 0.019 * sample, std::fmod(0.37 * sample, 1.0));
        Eigen::Vector3d a, b;
        core::evaluateNetVolume(old, old.rest, t, a);
        t[2] = split.axes[2].latticeParameter(old.axes[2].knotParameter(t[2]));
        core::evaluateNetVolume(split, split.rest, t, b);
        CHECK((a - b).norm() <= 1e-12 * old.diagonal());
    }
    // Refine axis halves every chunk of the axis chosen in the combo.
    state.lattices.editAxis = 0;
    ui.frame();
    ui.click("Refine axis");
    CHECK(session.history().size() == history + 2);
    CHECK(session.tools().list()[0].volume->tensorNet()->axes[0].spans == 2 * old.axes[0].spans);
    // Undo takes both back, one at a time, to the very volume added.
    ui.undo();
    ui.undo();
    CHECK(session.tools().list()[0].volume == before);
    // A frozen tool is not edited: the buttons are disabled, a click does nothing.
    core::OpReport added;
    REQUIRE(session.tools().add(cylinderTool(), added));
    app::freezeLatticeCommand(state, 1, 0);
    REQUIRE(session.tools().frozen() == 1);
    state.lattices.selectedTool = 1;
    ui.frame();
    const size_t frozenHistory = session.history().size();
    ui.click("Insert knot");
    CHECK(session.history().size() == frozenHistory);
}

// Issue: a press that came in the same frame as the move carrying the cursor off the panel (just after
// clicking "Move on mesh") onto the mesh was lost: Dear ImGui's io.WantCaptureMouse is computed at NewFrame for
// where the cursor was then (over the button), and the window passed that flag with the press. It now asks
// SculptApp::uiCaptureAt for the press's own point (glfw_main.cpp does the same).
TEST_CASE("window lattices: a press in the same frame as the move off the panel onto the mesh is a press", "[gl][effd]") {
    Ui ui;
    if (!ui.open()) return;
    app::AppState& state = ui.sculptApp.state();
    core::Session& session = state.session;
    ui.openPanelWithCylinder();
    ui.click("Add");
    REQUIRE(session.tools().list().size() == 1);
    REQUIRE(state.lattices.selectedTool == 0);
    ui.click("Move on mesh");
    REQUIRE(state.lattices.placing == app::LatticesPanelState::Placing::Tool);
    // The cursor is still over the button as far as ImGui knows: its flag (what the window used to pass)
    // says the UI has the mouse.
    CHECK(ImGui::GetIO().WantCaptureMouse);
    CHECK(app::SculptApp::uiCapture().mouse);
    // The move to the mesh's middle and the press there, between two frames.
    const double x = 0.5 * kWidth, y = 0.5 * Ui::kPanelHeight;
    CHECK_FALSE(app::SculptApp::uiCaptureAt(x, y).mouse);
    app::Ray ray;
    REQUIRE(app::rayThroughPixel(state.camera, kWidth, Ui::kPanelHeight, x, y, ray));
    const app::SurfaceHit hit = app::intersectMesh(ray, session.mesh().positions, session.mesh().triangles);
    REQUIRE(hit.triangle >= 0);
    const size_t history = session.history().size();
    ui.sculptApp.onMouseMove({x, y, {}}, app::SculptApp::uiCapture());
    ui.sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Press, x, y, {}}, app::SculptApp::uiCaptureAt(x, y));
    ui.sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Release, x, y, {}}, app::SculptApp::uiCaptureAt(x, y));
    INFO(state.status);
    CHECK(state.lattices.placing == app::LatticesPanelState::Placing::None);
    REQUIRE(session.history().size() == history + 1);
    const core::LatticeNet& moved = *session.tools().list()[0].volume->tensorNet();
    CHECK((moved.bounds.center() - hit.point).norm() < 1e-9 * test::boundsDiagonal(session.mesh().positions) + 1e-12);

    // The other way round: the cursor was over the mesh at the last frame, and the press comes on the panel's
    // "Add" button together with the move there. It is the panel's click, not a sculpt drag.
    ImGuiIO& io = ImGui::GetIO();
    io.MousePos = ImVec2(static_cast<float>(x), static_cast<float>(y));
    ui.frame();
    REQUIRE_FALSE(io.WantCaptureMouse);
    const app::LatticesPanelState::ItemRect add = ui.rect("Add");
    const double ax = 0.5 * (add.x0 + add.x1), ay = 0.5 * (add.y0 + add.y1);
    CHECK(app::SculptApp::uiCaptureAt(ax, ay).mouse);
    const Positions before = session.mesh().positions;
    ui.sculptApp.onMouseMove({ax, ay, {}}, app::SculptApp::uiCapture());
    ui.sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Press, ax, ay, {}}, app::SculptApp::uiCaptureAt(ax, ay));
    CHECK_FALSE(state.drag.active);
    ui.sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Release, ax, ay, {}}, app::SculptApp::uiCaptureAt(ax, ay));
    CHECK(session.mesh().positions == before);
    CHECK(session.history().size() == history + 1);

    // Lattice point editing alike: the frozen cylinder's axis point, pressed right after the cursor left the panel.
    core::OpReport added;
    REQUIRE(session.tools().add(cylinderTool(), added));
    app::freezeLatticeCommand(state, 1, 0);
    REQUIRE(session.tools().frozen() == 1);
    ui.appKey(app::Key::Tab);
    REQUIRE(state.tools.mode == app::ToolMode::Lattice);
    ui.frame();
    const app::LatticesPanelState::ItemRect freeze = ui.rect("Freeze");
    io.MousePos = ImVec2(0.5f * (freeze.x0 + freeze.x1), 0.5f * (freeze.y0 + freeze.y1));
    ui.frame();
    REQUIRE(io.WantCaptureMouse);
    const core::Lattice& lattice = session.lattice();
    const int rep = lattice.representative(lattice.index(0, 1, 1));
    const Eigen::Vector2d point = test::pixelOf(state, session.cage().cagePoints().row(rep).transpose());
    ui.sculptApp.onMouseMove({point.x(), point.y(), {}}, app::SculptApp::uiCapture());
    ui.sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Press, point.x(), point.y(), {}},
                               app::SculptApp::uiCaptureAt(point.x(), point.y()));
    CHECK(state.drag.active);
    CHECK(state.tools.lattice.points == std::vector<int>{rep});
    ui.sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Release, point.x(), point.y(), {}},
                               app::SculptApp::uiCaptureAt(point.x(), point.y()));
}

// Issue: a small frozen lattice (a library ball placed at a quarter of the mesh's size) drew a dense cloud of
// control-point markers that hid the mesh. Markers that crowd on screen shrink (render::crowdedMarkerScale,
// the same in screenshots); the box lattice at its usual framing keeps its markers as they were.
TEST_CASE("window lattices: the markers of a small frozen lattice shrink so the mesh shows between them", "[gl][effd]") {
    Ui ui;
    if (!ui.open()) return;
    app::AppState& state = ui.sculptApp.state();
    core::Session& session = state.session;
    ui.appKey(app::Key::Tab);  // the lattice tool: the box lattice drawn
    REQUIRE(app::latticeShown(state));
    ui.frame();
    CHECK(ui.sculptApp.renderer().lastMarkerCrowding() == 1.0f);
    ui.appKey(app::Key::Tab);
    ui.frame();  // the sculpt tool's panel drawn and settled (auto-resize takes a frame), so the Lattices header
    ui.frame();  // is clicked where it now is

    ui.openPanelWithCylinder();
    const std::vector<app::LatticeLibraryEntry>& library = state.lattices.library;
    const auto ball = std::find_if(library.begin(), library.end(), [](const auto& e) { return e.name == "ball"; });
    REQUIRE(ball != library.end());
    state.lattices.libraryChoice = static_cast<int>(ball - library.begin());
    ui.frame();
    ui.click("Place on mesh");
    const double x = 0.5 * kWidth, y = 0.45 * Ui::kPanelHeight;  // between the panels
    ui.sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Press, x, y, {}}, app::SculptApp::uiCaptureAt(x, y));
    ui.sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Release, x, y, {}}, app::SculptApp::uiCaptureAt(x, y));
    REQUIRE(session.tools().list().size() == 1);
    app::freezeLatticeCommand(state, 0, 0);  // the panel's Freeze; turns the Lattice overlay on
    INFO(state.status);
    REQUIRE(session.tools().frozen() == 0);
    REQUIRE(app::latticeShown(state));
    ui.frame();
    render::Rgba8Image image;
    REQUIRE(ui.window.frame(&image).ok);
    CHECK(io::writePng(test::glTestOutputDir() + "/window_small_frozen_ball.png", image.width, image.height, image.pixels.data()).ok);
    const float crowd = ui.sculptApp.renderer().lastMarkerCrowding();
    INFO("marker scale " << crowd);
    CHECK(crowd < 0.8f);
    CHECK(crowd >= render::kMinCrowdedMarkerScale);
    // Selecting every point keeps them at full size (the selection is what the user works with), and the
    // crowding is measured on the unselected ones only.
    ui.appKey(app::Key::Tab);
    ui.appKey(app::Key::A);
    REQUIRE_FALSE(state.tools.lattice.points.empty());
    ui.frame();
    CHECK(ui.sculptApp.renderer().lastMarkerCrowding() == 1.0f);
}

namespace {

// Sets an environment variable for one scope (the user's data folder of the Save-to-library test).
class ScopedEnvironment {
public:
    ScopedEnvironment(const char* name, const std::string& value) : name_(name) {
        const char* old = std::getenv(name);
        had_ = old != nullptr;
        if (had_) old_ = old;
        setenv(name, value.c_str(), 1);
    }
    ~ScopedEnvironment() {
        if (had_) setenv(name_, old_.c_str(), 1);
        else unsetenv(name_);
    }
    ScopedEnvironment(const ScopedEnvironment&) = delete;
    ScopedEnvironment& operator=(const ScopedEnvironment&) = delete;

private:
    const char* name_;
    bool had_ = false;
    std::string old_;
};

std::string fileBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

}  // namespace

// Issue: "Save to library" opened in the shipped assets/lattices with a shipped file's name ("cylinder"),
// inviting the user to replace a shipped tool. It opens in the user's library folder (XDG_DATA_HOME, made on
// demand) with a fresh name; the library lists the shipped and the user's lattices; the shipped folder is
// never written.
TEST_CASE("window lattices: Save to library writes a fresh name to the user's folder and never over a shipped tool", "[gl][effd]") {
    namespace fs = std::filesystem;
    const std::string data = test::glTestOutputDir() + "/xdg-data";
    fs::remove_all(data);
    const ScopedEnvironment xdg("XDG_DATA_HOME", data);
    const std::string userFolder = data + "/dmffd-sculpt/lattices";
    REQUIRE(app::userLatticeFolder() == userFolder);
    REQUIRE_FALSE(fs::exists(userFolder));  // made by the first save, not before
    const std::string shippedCylinder = app::latticeLibraryFolder() + "/cylinder.lattice.json";
    const std::string shippedBytes = fileBytes(shippedCylinder);
    REQUIRE_FALSE(shippedBytes.empty());

    Ui ui;
    if (!ui.open()) return;
    app::AppState& state = ui.sculptApp.state();
    app::FileCommands& files = ui.sculptApp.files();
    ui.openPanelWithCylinder();
    ui.click("Add");
    REQUIRE(state.session.tools().list().size() == 1);
    REQUIRE(state.session.tools().list()[0].name == "cylinder");

    ui.click("Save to library...");
    REQUIRE(files.dialog().isOpen());
    CHECK(files.dialog().mode() == app::FileDialogMode::Save);
    CHECK(fs::is_directory(userFolder));  // made on demand
    CHECK(fs::equivalent(files.dialog().folder(), userFolder));
    CHECK(files.dialog().typedName() == "cylinder 2.lattice.json");  // "cylinder" is the shipped one's name
    REQUIRE(files.dialog().submit(files.dialog().typedName()));
    files.dialogAccepted(state);
    INFO(state.status);
    CHECK_FALSE(state.statusIsError);
    const std::string saved = userFolder + "/cylinder 2.lattice.json";
    io::LatticeFile file;
    REQUIRE(io::readLatticeFile(saved, file).ok);
    CHECK(file.name == "cylinder 2");  // the library's name is the file's
    CHECK(file.volume->restControlPoints() == state.session.tools().list()[0].volume->restControlPoints());
    const std::vector<app::LatticeLibraryEntry>& library = state.lattices.library;
    const auto listed = std::find_if(library.begin(), library.end(), [&](const auto& e) { return fs::path(e.path) == fs::path(saved); });
    REQUIRE(listed != library.end());
    CHECK(listed->name == "cylinder 2");
    // The next save proposes the next name.
    ui.frame();  // the dialog's modal closes
    ui.click("Save to library...");
    REQUIRE(files.dialog().isOpen());
    CHECK(files.dialog().typedName() == "cylinder 3.lattice.json");
    // Typed over a shipped file, "Replace?" answered yes: refused, the shipped file as it was.
    CHECK_FALSE(files.dialog().submit(shippedCylinder));
    CHECK(files.dialog().confirmReplace(true));
    files.dialogAccepted(state);
    CHECK(state.statusIsError);
    CHECK(state.status.find("shipped") != std::string::npos);
    CHECK(fileBytes(shippedCylinder) == shippedBytes);
    CHECK_FALSE(app::saveLatticeToolCommand(state, 0, shippedCylinder).ok);
    CHECK(fileBytes(shippedCylinder) == shippedBytes);

    // A fresh start lists the shipped lattices and the user's (one more written meanwhile by hand).
    app::AppState fresh;
    REQUIRE(io::writeLatticeFile(userFolder + "/my ring.lattice.json", {"my ring", cylinderTool().volume}).ok);
    app::loadLatticeLibraries(fresh);
    std::set<std::string> names;
    for (const app::LatticeLibraryEntry& e : fresh.lattices.library) names.insert(e.name);
    CHECK(names.count("cylinder") == 1);
    CHECK(names.count("ball") == 1);
    CHECK(names.count("cylinder 2") == 1);
    CHECK(names.count("my ring") == 1);
    CHECK(app::freshLatticeName(fresh, "my ring", userFolder) == "my ring 2");
    CHECK(app::freshLatticeName(fresh, "cylinder 2", userFolder) == "cylinder 3");
    CHECK(app::freshLatticeName(fresh, "pie", userFolder) == "pie");
    CHECK(app::freshLatticeName(fresh, "a/b", userFolder) == "a-b");
}

TEST_CASE("golden: a frozen cylinder lattice drawn with curved edges over the default mesh", "[gl][golden][effd]") {
    core::Session session;
    {
        app::SculptApp loader;
        test::loadDefaultMesh(loader, kWidth, kHeight);
        session = std::move(loader.state().session);
    }
    addAndFreezeCylinder(session);
    // The axis of the upper inner slice (y = 0.5) pushed up, as in the sandpie (Fig. 6), and one point of
    // the inner ring out: the mesh's top rises and the chunk edges bend.
    const core::Lattice& lattice = session.lattice();
    core::OpReport report;
    Eigen::MatrixX3d by(2, 3);
    by << 0.0, 0.3, 0.0, 0.2, 0.0, 0.0;
    REQUIRE(session.moveControlPoints({lattice.representative(lattice.index(0, 0, 2)), lattice.index(1, 1, 2)}, by, true, report));
    INFO(report.reason);
    REQUIRE(report.status == core::OpStatus::Applied);
    render::ScreenshotOptions options;
    options.width = 640;
    options.height = 400;
    options.yawDeg = 25.0f;
    options.pitchDeg = 30.0f;
    options.distance = 5.6;
    options.overlays.lattice = true;
    render::Rgba8Image image;
    REQUIRE(test::glTestRenderer().renderScene(app::sceneFromSession(session, app::SceneRequest{}), options, image).ok);
    test::checkGolden(image, "effd_cylinder_lattice");
}
