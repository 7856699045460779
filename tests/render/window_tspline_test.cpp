// Weighted T-splines in the window (Song & Yang 2005, seed 002; issue 11, point 7): the Lattices panel's
// T-spline section, clicked with synthetic Dear ImGui input as a user clicks it, runs the script ops
// (setup_tspline, subdivide_cells, with unfreeze / freeze around a frozen tool) and each is undone exactly;
// only the control points of non-empty cells are drawn and picked (Fig. 10); cells chosen on the mesh are
// subdivided (Fig. 11); the overlay marks every T-junction (Fig. 9), counted here from the lattice's edges.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <set>
#include <string>
#include <vector>

#include <imgui.h>

#include "app/scene_builder.h"
#include "app/window/picking.h"
#include "app/window/sculpt_app.h"
#include "app/window/tools.h"
#include "app/window/tspline_commands.h"
#include "io/script.h"
#include "core/tspline/tspline_view.h"
#include "gl_test_support.h"
#include "io/obj_mesh.h"
#include "io/png_image.h"
#include "offscreen_window.h"
#include "render/overlay_geometry.h"
#include "render/palette.h"
#include "window_test_support.h"

using namespace sculpt;

namespace {

constexpr int kWidth = 960, kHeight = 1400;  // tall: the Tools window shows the T-spline section unscrolled

std::string potPath() { return std::string(SCULPT_SOURCE_DIR) + "/assets/examples/pot.obj"; }

void loadPot(app::SculptApp& sculptApp) {
    const Status loaded = sculptApp.loadMesh(potPath());
    INFO(loaded.message);
    REQUIRE(loaded.ok);
    sculptApp.onFramebufferSize({kWidth, kHeight});
    app::frameMesh(sculptApp.state());
}

const core::TSplineVolume& toolVolume(const core::Session& session, int index) {
    REQUIRE(index >= 0);
    REQUIRE(index < static_cast<int>(session.tools().list().size()));
    const core::TSplineVolume* tspline = core::asTSpline(session.tools().list()[static_cast<size_t>(index)].volume.get());
    REQUIRE(tspline != nullptr);
    return *tspline;
}

struct Ui {
    app::SculptApp sculptApp;
    test::OffscreenWindow window;
    bool open() {
        const Status opened = window.open(sculptApp, kWidth, kHeight, 0);
        if (!opened) {
            WARN("no EGL context, frames skipped: " << opened.message);
            return false;
        }
        loadPot(sculptApp);
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
        frame();  // auto-resize and the recorded rectangles settle a frame later
    }
    app::LatticesPanelState::ItemRect rect(const std::string& label) {
        const std::vector<app::LatticesPanelState::ItemRect>& items = sculptApp.state().lattices.items;
        const auto item = std::find_if(items.begin(), items.end(), [&](const auto& r) { return r.label == label; });
        INFO("Lattices panel item " << label);
        REQUIRE(item != items.end());
        return *item;
    }
    void click(const std::string& label) {
        const app::LatticesPanelState::ItemRect item = rect(label);
        clickAt(0.5f * (item.x0 + item.x1), 0.5f * (item.y0 + item.y1));
    }
    // A click in the 3D view (not on a panel), as the window delivers it.
    void clickView(double x, double y) {
        sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Press, x, y, {}}, {});
        sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Release, x, y, {}}, {});
        frame();
    }
    void undo() { sculptApp.onKey({app::Key::Z, app::KeyAction::Press, {false, true, false, false}}, {}); }
};

// A session on the pot with a frozen T-spline of `depth` (and the 100:1 weights of sec. 4).
core::Session potSession(int depth) {
    core::Session session;
    {
        app::SculptApp loader;
        loadPot(loader);
        session = std::move(loader.state().session);
    }
    core::TSplineSetup setup;
    setup.octree.octree.depth = depth;
    core::OpReport report;
    REQUIRE(session.tspline().setup(setup, report).ok);
    INFO(report.reason);
    REQUIRE(report.status == core::OpStatus::Applied);
    return session;
}

// pot.json's lattice (Fig. 12): depth 2 in the region round the pot, then the cell at (0.52, 0, 0.4) on its belly
// subdivided (Fig. 11) and frozen again: T-junctions round that cell.
core::Session locallySubdividedPot() {
    core::Session session;
    {
        app::SculptApp loader;
        loadPot(loader);
        session = std::move(loader.state().session);
    }
    core::TSplineSetup setup;
    setup.octree.octree.depth = 2;
    setup.hasRegion = true;
    setup.regionMin = Eigen::Vector3d(-0.8, -0.8, -0.1);
    setup.regionMax = Eigen::Vector3d(0.8, 0.8, 1.3);
    setup.name = "pot";
    core::OpReport report;
    REQUIRE(session.tspline().setup(setup, report).ok);
    REQUIRE(session.tools().unfreeze(report).ok);
    REQUIRE(session.tspline().subdivideCells(0, {}, {Eigen::Vector3d(0.52, 0, 0.4)}, true, report).ok);
    INFO(report.reason);
    REQUIRE(report.status == core::OpStatus::Applied);
    REQUIRE(session.tools().freeze(0, 0, report).ok);
    REQUIRE(session.tools().frozen() == 0);
    return session;
}

// T-junctions counted from the T-lattice's edges (independently of core::tJunctionVertices, which looks at the
// cells round a vertex): a vertex with fewer edges than its place allows, one per axis direction in which the
// domain goes on (6 inside, 5 on a face, 4 on an edge, 3 at a corner).
std::set<int> tJunctionsByEdgeCount(const core::TLattice& lattice, const std::vector<std::array<int, 2>>& edges) {
    std::vector<int> degree(lattice.vertices.size(), 0);
    for (const auto& edge : edges) {
        ++degree[static_cast<size_t>(edge[0])];
        ++degree[static_cast<size_t>(edge[1])];
    }
    std::set<int> junctions;
    for (size_t v = 0; v < lattice.vertices.size(); ++v) {
        int full = 0;
        for (int a = 0; a < 3; ++a) full += (lattice.vertices[v][a] > 0) + (lattice.vertices[v][a] < lattice.fineCount[a]);
        if (degree[v] < full) junctions.insert(static_cast<int>(v));
    }
    return junctions;
}

}  // namespace

TEST_CASE("window tspline: Set up T-spline adds and freezes the lattice the panel asks for, undo takes it back", "[gl][tspline]") {
    Ui ui;
    if (!ui.open()) return;
    app::AppState& state = ui.sculptApp.state();
    core::Session& session = state.session;
    ui.click("Lattices");
    const Positions before = session.mesh().positions;
    const size_t history = session.history().size();
    state.tspline.depth = 3;
    state.tspline.weightRatio = 50.0;
    ui.frame();
    ui.click("Set up T-spline");
    INFO(state.status);
    CHECK_FALSE(state.statusIsError);
    REQUIRE(session.tools().list().size() == 1);
    CHECK(session.tools().frozen() == 0);
    CHECK(state.lattices.selectedTool == 0);
    CHECK(app::latticeShown(state));  // the lattice just frozen is on screen
    CHECK(session.history().size() == history + 1);  // adding the tool and freezing it: one entry
    CHECK(session.mesh().positions == before);            // setting up never moves the mesh
    // The lattice sec. 4 builds around these vertices at depth 3 with weights 50:1, built here on its own.
    const core::TSplineVolume& made = toolVolume(session, 0);
    core::TSplineOctreeSettings settings;
    settings.octree.depth = 3;
    settings.weightRatio = 50.0;
    std::shared_ptr<const core::TSplineVolume> expected;
    REQUIRE(core::makeOctreeTSplineVolume(before, settings, expected).ok);
    CHECK(made.lattice().cells.size() == expected->lattice().cells.size());
    CHECK(made.controlWeights() == expected->controlWeights());
    const std::set<double> levels(made.controlWeights().begin(), made.controlWeights().end());
    CHECK(levels == std::set<double>{1.0, 5.0, 50.0});  // 50:1, falling off by 10 per ring
    CHECK(made.restBounds().isApprox(expected->restBounds(), 1e-12));

    ui.undo();  // the set-up: the freeze and the tool, one history entry
    CHECK(session.tools().frozen() == -1);
    CHECK(session.tools().list().empty());
    CHECK(session.mesh().positions == before);
    ui.frame();

    // A box region: the lattice is placed exactly there. One holding no vertex is refused on the status line.
    ui.click("tspline box");
    REQUIRE(state.tspline.customRegion);
    CHECK(state.tspline.regionFilled);  // starts from the mesh's padded bounds
    state.tspline.regionMin = Eigen::Vector3d(5, 5, 5);
    state.tspline.regionMax = Eigen::Vector3d(6, 6, 6);
    ui.click("Set up T-spline");
    CHECK(state.statusIsError);
    CHECK(state.status.find("holds none of the mesh's") != std::string::npos);
    CHECK(session.tools().list().empty());
    state.tspline.regionMin = Eigen::Vector3d(-0.8, -0.8, 0.5);
    state.tspline.regionMax = Eigen::Vector3d(0.8, 0.8, 1.3);
    state.tspline.depth = 2;
    ui.frame();
    ui.click("Set up T-spline");
    INFO(state.status);
    REQUIRE(session.tools().list().size() == 1);
    CHECK(session.tools().list()[0].name == "tspline");
    CHECK(toolVolume(session, 0).restBounds().min().isApprox(Eigen::Vector3d(-0.8, -0.8, 0.5), 1e-12));
    CHECK(toolVolume(session, 0).restBounds().max().isApprox(Eigen::Vector3d(0.8, 0.8, 1.3), 1e-12));
    // A second set-up gets a name of its own.
    ui.click("tspline mesh bounds");
    ui.click("Set up T-spline");
    REQUIRE(session.tools().list().size() == 2);
    CHECK(session.tools().list()[1].name == "tspline 2");
    CHECK(session.tools().frozen() == 1);
}

TEST_CASE("window tspline: only the control points of non-empty cells are drawn and picked", "[gl][tspline]") {
    app::SculptApp sculptApp;
    loadPot(sculptApp);
    app::AppState& state = sculptApp.state();
    app::setupTSplineCommand(state);  // the panel's defaults: depth 3, 100:1, the mesh's bounds
    INFO(state.status);
    core::Session& session = state.session;
    REQUIRE(session.tools().frozen() == 0);
    sculptApp.onKey({app::Key::Tab, app::KeyAction::Press, {}}, {});
    REQUIRE(state.tools.mode == app::ToolMode::Lattice);
    REQUIRE(app::latticeShown(state));

    // Shown: exactly the heavy control points (sec. 4 set them from the same cells), less the boundary copies.
    const core::TSplineVolume& tspline = toolVolume(session, 0);
    const std::vector<double>& weights = tspline.controlWeights();
    const std::vector<std::uint8_t> shown = app::shownControlPoints(state);
    REQUIRE(shown.size() == weights.size());
    int heavyShown = 0, light = 0;
    for (size_t s = 0; s < weights.size(); ++s) {
        const bool copy = tspline.basis().anchors[s].boundaryCopy != 0;
        CHECK(bool(shown[s]) == (weights[s] == 100.0 && !copy));
        heavyShown += shown[s];
        light += weights[s] == 1.0;
    }
    REQUIRE(heavyShown > 0);
    REQUIRE(light > 0);
    // What is drawn is what is picked.
    const render::SceneData scene = app::sceneFromSession(session, app::SceneRequest{});
    CHECK(scene.lattice.drawn == std::vector<std::uint8_t>(shown.begin(), shown.end()));

    // Points whose marker has no shown point within 12 px (the pick radius is 9): a click there is unambiguous.
    const Positions points = session.cage().cagePoints();
    const auto isolated = [&](size_t s) {
        const Eigen::Vector2d at = test::pixelOf(state, points.row(static_cast<Eigen::Index>(s)).transpose());
        if (at.x() < 20 || at.y() < 20 || at.x() > kWidth - 420 || at.y() > kHeight - 60) return false;  // off the panels
        for (size_t r = 0; r < shown.size(); ++r)
            if (r != s && shown[r] && (test::pixelOf(state, points.row(static_cast<Eigen::Index>(r)).transpose()) - at).norm() < 12.0) return false;
        return true;
    };
    int lightClicked = 0;
    for (size_t s = 0; s < weights.size() && lightClicked < 3; ++s) {
        if (weights[s] != 1.0 || tspline.basis().anchors[s].boundaryCopy != 0 || !isolated(s)) continue;
        const Eigen::Vector2d at = test::pixelOf(state, points.row(static_cast<Eigen::Index>(s)).transpose());
        sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Press, at.x(), at.y(), {}}, {});
        CHECK_FALSE(state.drag.active);
        sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Release, at.x(), at.y(), {}}, {});
        CHECK(state.tools.lattice.points.empty());
        ++lightClicked;
    }
    CHECK(lightClicked == 3);
    size_t heavy = weights.size();
    for (size_t s = 0; s < weights.size() && heavy == weights.size(); ++s)
        if (shown[s] && isolated(s)) heavy = s;
    REQUIRE(heavy < weights.size());
    // A heavy point: selected, and dragged 5 px through the control-point command path (one undo step).
    const Positions before = session.mesh().positions;
    const size_t history = session.history().size();
    const Eigen::Vector2d start = test::pixelOf(state, points.row(static_cast<Eigen::Index>(heavy)).transpose());
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Press, start.x(), start.y(), {}}, {});
    REQUIRE(state.drag.active);
    CHECK(state.tools.lattice.points == std::vector<int>{static_cast<int>(heavy)});
    sculptApp.onMouseMove({start.x(), start.y() - 5.0, {}}, {});
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Release, start.x(), start.y() - 5.0, {}}, {});
    INFO(state.status);
    CHECK(session.history().size() == history + 1);
    CHECK(session.lattice().displacement.row(static_cast<Eigen::Index>(heavy)).norm() > 0.0);
    CHECK((session.mesh().positions - before).rowwise().norm().maxCoeff() > 1e-4);
    // Select all (A) takes the shown points only.
    sculptApp.onKey({app::Key::A, app::KeyAction::Press, {}}, {});
    CHECK(state.tools.lattice.points.size() == static_cast<size_t>(heavyShown));
    sculptApp.onKey({app::Key::Escape, app::KeyAction::Press, {}}, {});
    sculptApp.onKey({app::Key::Z, app::KeyAction::Press, {false, true, false, false}}, {});
    CHECK((session.mesh().positions - before).cwiseAbs().maxCoeff() < 1e-9);
}

TEST_CASE("window tspline: cells chosen on the mesh are subdivided, and undo restores the lattice exactly", "[gl][tspline]") {
    Ui ui;
    if (!ui.open()) return;
    app::AppState& state = ui.sculptApp.state();
    core::Session& session = state.session;
    ui.click("Lattices");
    state.tspline.depth = 2;
    ui.frame();
    ui.click("Set up T-spline");
    REQUIRE(session.tools().frozen() == 0);
    const std::shared_ptr<const core::Volume> coarse = session.tools().list()[0].volume;
    const size_t cellsBefore = toolVolume(session, 0).lattice().cells.size();
    // Nothing chosen yet: Subdivide is disabled, and the command says what to do.
    ui.click("Subdivide");
    CHECK(toolVolume(session, 0).lattice().cells.size() == cellsBefore);
    app::subdivideChosenCellsCommand(state);
    CHECK(state.statusIsError);
    // A refusal of the engine (here a cell it does not have) takes the unfreeze back: nothing changes.
    const int cursor = session.history().cursor();
    state.tspline.chosenCells = {100000};
    app::subdivideChosenCellsCommand(state);
    CHECK(state.statusIsError);
    CHECK(state.status.find("does not exist") != std::string::npos);
    CHECK(session.tools().frozen() == 0);
    CHECK(session.history().cursor() == cursor);
    CHECK(session.tools().list()[0].volume == coarse);
    state.tspline.chosenCells.clear();

    ui.click("Choose cells");
    REQUIRE(state.tspline.picking);
    // A click on the pot: the cell holding the parameters of the point clicked (found here from the deformed
    // point, Session::parametersOfCurrentPoint).
    const double x = 0.5 * (kWidth - 400), y = 0.5 * kHeight;
    app::Ray ray;
    REQUIRE(app::rayThroughPixel(state.camera, kWidth, kHeight, x, y, ray));
    const app::SurfaceHit hit = app::intersectMesh(ray, session.mesh().positions, session.mesh().triangles);
    REQUIRE(hit.triangle >= 0);
    Eigen::Vector3d params;
    REQUIRE(session.cage().parametersOfCurrentPoint(hit.point, params).ok);
    const int history = session.history().cursor();
    ui.clickView(x, y);
    INFO(state.status);
    REQUIRE(state.tspline.chosenCells.size() == 1);
    const core::TLattice& lattice = toolVolume(session, 0).lattice();
    const int cell = state.tspline.chosenCells[0];
    for (int a = 0; a < 3; ++a) {
        CHECK(lattice.knotValue[a][lattice.cellLo(cell)[a]] <= params[a] + 1e-9);
        CHECK(params[a] <= lattice.knotValue[a][lattice.cellHi(cell)[a]] + 1e-9);
    }
    CHECK(session.history().cursor() == history);  // choosing changes nothing
    // Drawn: the cell's 12 edges in the selection colour.
    render::LatticeView overlay;
    app::addTSplineOverlays(state, overlay);
    CHECK(overlay.chosenCells.size() == 12);
    ui.clickView(x, y);  // a second click drops it
    CHECK(state.tspline.chosenCells.empty());
    ui.clickView(x, y);
    REQUIRE(state.tspline.chosenCells == std::vector<int>{cell});
    render::Rgba8Image picture;
    REQUIRE(ui.window.frame(&picture).ok);
    io::writePng(test::glTestOutputDir() + "/window_tspline_chosen_cell.png", picture.width, picture.height, picture.pixels.data());

    // Subdivide: unfreeze, subdivide_cells, freeze (three history operations); the shape stays.
    const Positions before = session.mesh().positions;
    ui.click("Subdivide");
    INFO(state.status);
    CHECK_FALSE(state.statusIsError);
    REQUIRE(session.tools().frozen() == 0);
    const size_t cellsAfter = toolVolume(session, 0).lattice().cells.size();
    CHECK(cellsAfter >= cellsBefore + 7);  // the cell became 8, more with the balance
    CHECK(session.history().cursor() == history + 1);  // unfreeze, subdivide, freeze: one entry
    CHECK((session.mesh().positions - before).cwiseAbs().maxCoeff() == 0.0);
    CHECK(state.tspline.chosenCells.empty());
    CHECK_FALSE(state.tspline.picking);
    // The finer cells hold the mesh: their control points are the heavy ones again.
    const std::vector<std::uint8_t>& shown = app::tsplineShownControlPoints(state);
    const core::TSplineVolume& finer = toolVolume(session, 0);
    for (size_t s = 0; s < shown.size(); ++s)
        if (finer.basis().anchors[s].boundaryCopy == 0) CHECK(bool(shown[s]) == (finer.controlWeights()[s] == 100.0));

    ui.undo();  // the freeze, the subdivision and the unfreeze
    CHECK(session.tools().frozen() == 0);
    CHECK(session.tools().list()[0].volume == coarse);  // the very lattice it was
    CHECK(toolVolume(session, 0).lattice().cells.size() == cellsBefore);
    CHECK(session.mesh().positions == before);

    // A tool that is not frozen (selected in the list): its cells are chosen where it is drawn at rest, its
    // T-junctions show while choosing, and Subdivide is subdivide_cells alone, one history operation.
    ui.frame();
    ui.click("Unfreeze");
    REQUIRE(session.tools().frozen() == -1);
    REQUIRE(app::tsplineTarget(state) == 0);
    ui.click("Choose cells");
    REQUIRE(state.tspline.picking);
    ui.clickView(x, y);
    REQUIRE(state.tspline.chosenCells.size() == 1);
    CHECK(state.tspline.chosenCells[0] == core::cellAtRestPoint(toolVolume(session, 0), hit.point));
    const int unfrozenHistory = session.history().cursor();
    ui.click("Subdivide");
    INFO(state.status);
    CHECK(session.history().cursor() == unfrozenHistory + 1);
    CHECK(session.tools().frozen() == -1);
    const core::TSplineVolume& atRest = toolVolume(session, 0);
    CHECK(atRest.lattice().cells.size() > cellsBefore);
    ui.click("Choose cells");  // the finer tool's T-junctions, at its rest control points
    render::LatticeView resting;
    app::addTSplineOverlays(state, resting);
    CHECK(resting.tJunctions.rows() == static_cast<Eigen::Index>(core::tJunctionVertices(atRest.lattice()).size()));
    CHECK(resting.tJunctions.rows() > 0);
    REQUIRE(ui.window.frame(&picture).ok);
    io::writePng(test::glTestOutputDir() + "/window_tspline_unfrozen.png", picture.width, picture.height, picture.pixels.data());
    ui.sculptApp.onKey({app::Key::Escape, app::KeyAction::Press, {}}, {});
    CHECK_FALSE(state.tspline.picking);
    ui.undo();
    CHECK(session.tools().list()[0].volume == coarse);
}

TEST_CASE("window tspline: the overlay marks every T-junction of the frozen T-lattice", "[gl][tspline]") {
    for (const bool local : {true, false}) {
        const core::Session session = local ? locallySubdividedPot() : potSession(4);
        const core::TSplineVolume* tspline = core::asTSpline(session.lattice().volume.get());
        REQUIRE(tspline != nullptr);
        const core::TSplineBasis& basis = tspline->basis();
        const std::set<int> junctions = tJunctionsByEdgeCount(basis.lattice, basis.latticeEdges);
        INFO((local ? "pot.json's locally subdivided lattice" : "depth 4") << ": " << junctions.size() << " T-junctions");
        REQUIRE(!junctions.empty());
        const std::vector<int> found = core::tJunctionVertices(basis.lattice);
        CHECK(std::set<int>(found.begin(), found.end()) == junctions);

        // The drawn markers: one diamond of the T-junction colour at the control point of each.
        const render::SceneData scene = app::sceneFromSession(session, app::SceneRequest{});
        std::vector<float> edges, markers;
        render::Bounds bounds;
        REQUIRE(render::buildLatticeInstances(scene.lattice, {}, edges, markers, bounds).ok);
        const Positions points = session.cage().cagePoints();
        std::multiset<std::array<float, 3>> diamonds, expected;
        for (size_t m = 0; m + render::kMarkerFloats <= markers.size(); m += render::kMarkerFloats)
            if (markers[m + 8] == 2.0f) {
                CHECK(markers[m + 3] == render::kTJunctionColor.r);
                diamonds.insert({markers[m], markers[m + 1], markers[m + 2]});
            }
        for (int v : junctions) {
            const Eigen::RowVector3d p = points.row(core::vertexAnchor(basis, v));
            expected.insert({float(p.x()), float(p.y()), float(p.z())});
        }
        CHECK(diamonds.size() == junctions.size());
        CHECK(diamonds == expected);
    }
}

// Song & Yang 2005, Fig. 10-11 on the pot of Fig. 12: pot.json's lattice (depth 2, then the cell on the belly at
// (0.52, 0, 0.4) subdivided), frozen, seen from the side with its rim to the left. The mesh shows through the
// T-lattice's grey edges; the yellow diamonds are its T-junctions, where the lines of the finer cells round the
// subdivided one end; only the control points of cells holding the mesh are drawn (dark dots; none on the box's
// faces: the boundary copies stay hidden). Regenerate: SCULPT_UPDATE_GOLDEN=1 gl_tests "[tspline][golden]".
TEST_CASE("golden: the T-lattice of the locally subdivided pot with its T-junctions", "[gl][golden][tspline]") {
    const core::Session session = locallySubdividedPot();
    render::ScreenshotOptions options;
    options.width = 800;
    options.height = 500;
    options.yawDeg = 70.0f;  // the subdivided cell (at +x) towards the top, its T-junctions in front and behind
    options.pitchDeg = -25.0f;
    options.distance = 4.0;
    options.pixelScale = 1.0f;  // markers as big as in the window
    options.overlays.lattice = true;
    render::Rgba8Image image;
    REQUIRE(test::glTestRenderer().renderScene(app::sceneFromSession(session, app::SceneRequest{}), options, image).ok);
    test::checkGolden(image, "tspline_pot_lattice");
}
