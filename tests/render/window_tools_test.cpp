// The window's editing tools driven by synthetic events (no GL needed for the events themselves): handles and
// pins of the sculpt tool (multi-point manipulation, Hu et al. 2001 eq. 12) and the lattice tool (pick,
// box-select, drag and pin control points, re-set-up). Independent checks: constraint targets against where
// the engine put the sources, selections against a brute-force projection, undo against the start state.
#include <catch2/catch.hpp>

#include <algorithm>
#include <random>
#include <string>

#include "app/window/picking.h"
#include "app/window/sculpt_app.h"
#include "app/window/tool_commands.h"
#include "io/png_image.h"
#include "offscreen_window.h"
#include "render/palette.h"
#include "window_test_support.h"

using namespace sculpt;

namespace {

constexpr int kWidth = 960, kHeight = 600;

void loadDefault(app::SculptApp& sculptApp) { test::loadDefaultMesh(sculptApp, kWidth, kHeight); }

double diagonalOf(const Positions& p) { return test::boundsDiagonal(p); }

app::Modifiers shiftKey() { app::Modifiers m; m.shift = true; return m; }
app::Modifiers controlKey() { app::Modifiers m; m.control = true; return m; }

void click(app::SculptApp& a, double x, double y, app::Modifiers m = {}) {
    a.onMouseButton({app::MouseButton::Left, app::ButtonAction::Press, x, y, m}, {});
    a.onMouseButton({app::MouseButton::Left, app::ButtonAction::Release, x, y, m}, {});
}

void key(app::SculptApp& a, app::Key k, app::Modifiers m = {}) { a.onKey({k, app::KeyAction::Press, m}, {}); }

// A random pixel whose ray hits the mesh.
bool randomPixelOnMesh(std::mt19937& rng, const app::AppState& state, double& x, double& y) {
    std::uniform_real_distribution<double> ux(0.3 * kWidth, 0.7 * kWidth), uy(0.3 * kHeight, 0.7 * kHeight);
    for (int attempt = 0; attempt < 50; ++attempt) {
        x = ux(rng);
        y = uy(rng);
        app::Ray ray;
        if (!app::rayThroughPixel(state.camera, kWidth, kHeight, x, y, ray)) continue;
        if (app::intersectMesh(ray, state.session.mesh().positions, state.session.mesh().triangles).triangle >= 0) return true;
    }
    return false;
}

}  // namespace

TEST_CASE("window tools: handles move together or alone while the other handles and pins hold", "[gl]") {
    std::mt19937 rng(501);
    int undone = 0;
    for (int trial = 0; trial < 8; ++trial) {
        app::SculptApp sculptApp;
        loadDefault(sculptApp);
        app::AppState& state = sculptApp.state();
        state.session.setInjectivity({core::InjectivityMode::Conic, 6});
        const Positions original = state.session.mesh().positions;
        const double diagonal = diagonalOf(original);
        const int handles = std::uniform_int_distribution<int>(1, 3)(rng), pins = std::uniform_int_distribution<int>(0, 3)(rng);
        for (int h = 0; h < handles + pins; ++h) {
            double x = 0, y = 0;
            REQUIRE(randomPixelOnMesh(rng, state, x, y));
            const size_t before = state.tools.handles.size();
            click(sculptApp, x, y, h < handles ? shiftKey() : controlKey());
            // A click that lands on an existing marker removes or converts it instead; keep the count honest.
            if (state.tools.handles.size() == before) continue;
            CHECK(state.tools.handles.back().pin == (h >= handles));
        }
        CHECK(state.session.history().empty());  // placing markers is not an edit of the shape
        REQUIRE(state.session.mesh().positions == original);
        int first = -1;
        for (size_t i = 0; i < state.tools.handles.size(); ++i)
            if (!state.tools.handles[i].pin) { first = static_cast<int>(i); break; }
        if (first < 0) continue;
        const bool together = trial % 2 == 0;
        if (!together) key(sculptApp, app::Key::G);
        REQUIRE(state.tools.moveHandlesTogether == together);

        // Grab the first handle at its marker and drag it.
        double hx = 0, hy = 0;
        const Eigen::Vector3d grabbed = app::handlePosition(state.tools.handles[first], original, state.session.mesh().triangles);
        REQUIRE(app::projectToPixel(state.camera, kWidth, kHeight, grabbed, hx, hy));
        REQUIRE(app::handleAtPixel(state.tools, original, state.session.mesh().triangles, state.camera, kWidth, kHeight, hx, hy, 9.0) >= 0);
        sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Press, hx, hy, {}}, {});
        REQUIRE(state.drag.active);
        const int grabbedIndex = app::handleAtPixel(state.tools, original, state.session.mesh().triangles, state.camera, kWidth, kHeight, hx, hy, 9.0);
        const double dx = std::uniform_real_distribution<double>(-30, 30)(rng), dy = std::uniform_real_distribution<double>(-40, -10)(rng);
        for (int m = 1; m <= 5; ++m) sculptApp.onMouseMove({hx + dx * m / 5, hy + dy * m / 5, {}}, {});
        const app::DragState drag = state.drag;
        const std::vector<Eigen::Vector3d> sources = state.session.stroke().userSources();
        REQUIRE(sources.size() == state.tools.handles.size());
        const Eigen::Vector3d offset = drag.target - drag.planePoint;
        CHECK(offset.norm() > 1e-3 * diagonal);
        for (size_t c = 0; c < sources.size(); ++c) {
            const app::SurfaceHandle& h = state.tools.handles[static_cast<size_t>(drag.constraintHandles[c])];
            const bool shouldMove = !h.pin && (together || drag.constraintHandles[c] == grabbedIndex);
            const Eigen::Vector3d expected = drag.starts[c] + (shouldMove ? offset : Eigen::Vector3d::Zero());
            CHECK((drag.targets[c] - expected).norm() <= 1e-12 * diagonal);
            if (state.lastReport.status == core::OpStatus::Applied && !state.lastReport.rankDeficient && state.lastReport.fractionApplied == 1.0)
                CHECK((sources[c] - expected).norm() <= 1e-6 * diagonal);  // each constraint met exactly
        }
        sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Release, hx + dx, hy + dy, {}}, {});
        CHECK_FALSE(state.drag.active);
        if (state.session.history().empty()) continue;  // every move refused as folding: nothing changed
        CHECK(state.session.history().size() == 1);
        CHECK(state.session.history().front().constraints.size() == sources.size());
        key(sculptApp, app::Key::Z, controlKey());
        CHECK((state.session.mesh().positions - original).cwiseAbs().maxCoeff() <= 1e-9 * diagonal);
        ++undone;
    }
    CHECK(undone >= 5);  // the trials did exercise the drags, not just skip
}

TEST_CASE("window tools: a plain drag keeps every handle and pin where it is", "[gl]") {
    std::mt19937 rng(502);
    app::SculptApp sculptApp;
    loadDefault(sculptApp);
    app::AppState& state = sculptApp.state();
    const double diagonal = diagonalOf(state.session.mesh().positions);
    state.tools.brush.radiusPixels = 200.0;  // a brush wide enough for the 60-pixel pull
    // Markers left and right of the centre, then a drag from the centre.
    click(sculptApp, 0.5 * kWidth - 120, 0.5 * kHeight, controlKey());
    click(sculptApp, 0.5 * kWidth + 120, 0.5 * kHeight, shiftKey());
    REQUIRE(state.tools.handles.size() == 2);
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Press, 0.5 * kWidth, 0.5 * kHeight, {}}, {});
    REQUIRE(state.drag.active);
    REQUIRE(state.drag.moving == std::vector<int>{0});  // only the grabbed point follows the cursor
    for (int m = 1; m <= 6; ++m) sculptApp.onMouseMove({0.5 * kWidth, 0.5 * kHeight - 10.0 * m, {}}, {});
    const std::vector<Eigen::Vector3d> sources = state.session.stroke().userSources();
    REQUIRE(sources.size() == 3);
    for (size_t c = 1; c < 3; ++c) CHECK((sources[c] - state.drag.starts[c]).norm() <= 1e-6 * diagonal);
    CHECK((sources[0] - state.drag.target).norm() <= 1e-6 * diagonal);
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Release, 0.5 * kWidth, 0.5 * kHeight - 60, {}}, {});
    CHECK(state.session.history().size() == 1);
    CHECK(state.session.history().front().label == "brush drag");  // one point pulled; the two held ones only keep their place

    // Shift+click on a marker removes it, Ctrl+click turns a pin into a handle; Esc removes them all.
    double x = 0, y = 0;
    REQUIRE(app::projectToPixel(state.camera, kWidth, kHeight,
                                app::handlePosition(state.tools.handles[0], state.session.mesh().positions, state.session.mesh().triangles), x, y));
    REQUIRE(state.tools.handles[0].pin);
    click(sculptApp, x, y, controlKey());
    CHECK_FALSE(state.tools.handles[0].pin);
    click(sculptApp, x, y, shiftKey());
    CHECK(state.tools.handles.size() == 1);
    CHECK(state.status.find("Removed a handle (1 marker left)") != std::string::npos);
    // The status names what was removed: the pin in front of a handle in the list.
    state.tools.handles.front().pin = true;
    click(sculptApp, 0.5 * kWidth + 40, 0.5 * kHeight - 80, shiftKey());
    REQUIRE(state.tools.handles.size() == 2);
    REQUIRE_FALSE(state.tools.handles.back().pin);
    REQUIRE(app::projectToPixel(state.camera, kWidth, kHeight,
                                app::handlePosition(state.tools.handles[0], state.session.mesh().positions, state.session.mesh().triangles), x, y));
    click(sculptApp, x, y, shiftKey());
    REQUIRE(state.tools.handles.size() == 1);
    CHECK(state.status.find("Removed a pin (1 marker left)") != std::string::npos);
    key(sculptApp, app::Key::Escape);
    CHECK(state.tools.handles.empty());
    CHECK(state.session.history().size() == 1);  // none of this touched the shape
    (void)rng;
}

TEST_CASE("window tools: the lattice tool picks the control point under the cursor and box-selects what a projection puts inside", "[gl]") {
    std::mt19937 rng(503);
    app::SculptApp sculptApp;
    loadDefault(sculptApp);
    app::AppState& state = sculptApp.state();
    key(sculptApp, app::Key::Tab);
    REQUIRE(state.tools.mode == app::ToolMode::Lattice);
    const Positions points = core::controlPointPositions(state.session.lattice());
    const int n = static_cast<int>(points.rows());
    for (int trial = 0; trial < 30; ++trial) {
        // Click on the projection of a random control point: the picked one is that point, or a marker drawn over
        // it (within a marker's size on screen) and nearer the eye.
        const int target = std::uniform_int_distribution<int>(0, n - 1)(rng);
        double x = 0, y = 0;
        if (!app::projectToPixel(state.camera, kWidth, kHeight, points.row(target).transpose(), x, y)) continue;
        if (x < 0 || y < 0 || x > kWidth || y > kHeight) continue;
        click(sculptApp, x, y);
        REQUIRE(state.tools.lattice.points.size() == 1);
        const int picked = state.tools.lattice.points.front();
        double px = 0, py = 0;
        REQUIRE(app::projectToPixel(state.camera, kWidth, kHeight, points.row(picked).transpose(), px, py));
        CHECK(std::hypot(px - x, py - y) <= render::kControlPointSize + 1e-9);
        if (picked != target) {
            // Nearer the eye: less depth along the view direction (what the depth buffer orders by).
            const glm::dvec3 e = state.camera.eye(), toward = state.camera.towardEye();
            const auto depth = [&](int id) {
                return -((points(id, 0) - e.x) * toward.x + (points(id, 1) - e.y) * toward.y + (points(id, 2) - e.z) * toward.z);
            };
            CHECK(depth(picked) <= depth(target) + 1e-12);
        }
        CHECK(state.session.history().empty());  // a click without a move changes nothing
        // and says so: the point is selected, nothing is "Moving" (it said so once, after a mere click).
        INFO(state.status);
        CHECK(state.status.rfind("Selected control point [", 0) == 0);
        CHECK(state.status.find("Moving") == std::string::npos);
    }
    for (int trial = 0; trial < 20; ++trial) {
        std::uniform_real_distribution<double> ux(0, kWidth), uy(0, kHeight);
        const double x0 = ux(rng), y0 = uy(rng), x1 = ux(rng), y1 = uy(rng);
        if (std::abs(x1 - x0) < 5 || std::abs(y1 - y0) < 5) continue;
        // Start the box on empty space: pressing on a marker would grab it instead.
        if (app::controlPointAtPixel(points, {}, state.camera, kWidth, kHeight, x0, y0, 9.0) >= 0) continue;
        const bool additive = trial % 3 == 2;
        const std::vector<int> before = state.tools.lattice.points;
        const app::Modifiers m = additive ? shiftKey() : app::Modifiers{};
        sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Press, x0, y0, m}, {});
        CHECK(state.tools.lattice.boxActive);
        sculptApp.onMouseMove({0.5 * (x0 + x1), 0.5 * (y0 + y1), m}, {});
        sculptApp.onMouseMove({x1, y1, m}, {});
        sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Release, x1, y1, m}, {});
        std::vector<int> expected = additive ? before : std::vector<int>{};
        for (int p = 0; p < n; ++p) {
            double px = 0, py = 0;
            if (app::projectToPixel(state.camera, kWidth, kHeight, points.row(p).transpose(), px, py) &&
                px >= std::min(x0, x1) && px <= std::max(x0, x1) && py >= std::min(y0, y1) && py <= std::max(y0, y1))
                expected.push_back(p);
        }
        std::sort(expected.begin(), expected.end());
        expected.erase(std::unique(expected.begin(), expected.end()), expected.end());
        CHECK(state.tools.lattice.points == expected);
    }
    key(sculptApp, app::Key::A);
    CHECK(static_cast<int>(state.tools.lattice.points.size()) == n);
    key(sculptApp, app::Key::Escape);
    CHECK(state.tools.lattice.points.empty());
    CHECK(state.session.history().empty());
}

TEST_CASE("window tools: dragging selected control points is one undoable edit, pinned ones stay", "[gl]") {
    std::mt19937 rng(504);
    int edits = 0, unsubdivided = 0;
    for (int trial = 0; trial < 6; ++trial) {
        app::SculptApp sculptApp;
        loadDefault(sculptApp);
        app::AppState& state = sculptApp.state();
        state.session.setInjectivity({core::InjectivityMode::Conic, 6});
        const Positions original = state.session.mesh().positions;
        const double diagonal = diagonalOf(original);
        key(sculptApp, app::Key::Tab);
        const core::Lattice& lattice = state.session.lattice();
        // Select 1-4 interior control points (Shift+click adds), pin one of them when there are several.
        std::vector<int> chosen;
        const int count = std::uniform_int_distribution<int>(1, 4)(rng);
        for (int c = 0; c < count; ++c) {
            const int i = std::uniform_int_distribution<int>(2, lattice.count[0] - 3)(rng);
            const int j = std::uniform_int_distribution<int>(2, lattice.count[1] - 3)(rng);
            const int k = std::uniform_int_distribution<int>(2, lattice.count[2] - 3)(rng);
            chosen.push_back(lattice.index(i, j, k));
        }
        std::sort(chosen.begin(), chosen.end());
        chosen.erase(std::unique(chosen.begin(), chosen.end()), chosen.end());
        state.tools.lattice.points = chosen;  // selection set directly: picking has its own test above
        std::vector<int> pinned;
        if (chosen.size() > 1) {
            REQUIRE(state.session.pins().set({chosen.back()}, true).ok);
            pinned.push_back(chosen.back());
        }
        // Press on the first chosen point's marker, wherever it projects (it may be hidden behind another
        // marker; then the grab picks that one: only check that the drag moves selected, unpinned points).
        const Positions before = core::controlPointPositions(lattice);
        double x = 0, y = 0;
        REQUIRE(app::projectToPixel(state.camera, kWidth, kHeight, before.row(chosen.front()).transpose(), x, y));
        sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Press, x, y, {}}, {});
        if (!state.drag.active) continue;  // the marker under the cursor was a pinned or unselected one
        REQUIRE(state.drag.kind == app::DragKind::Control);
        const std::vector<int> selection = state.tools.lattice.points;
        CHECK(state.status.find("Moving") == std::string::npos);  // pressed, not moved yet
        for (int m = 1; m <= 4; ++m) {
            sculptApp.onMouseMove({x + 6.0 * m, y - 8.0 * m, {}}, {});
            INFO(state.status);
            CHECK(state.status.rfind("Moving ", 0) == 0);  // while it moves
        }
        sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Release, x + 24, y - 32, {}}, {});
        if (state.session.history().empty()) continue;  // refused as folding
        REQUIRE(state.session.history().size() == 1);
        const core::Operation& op = state.session.history().front();
        CHECK(op.kind == core::OperationKind::ControlPointEdit);
        const Positions after = core::controlPointPositions(state.session.lattice());
        ++edits;
        if (state.session.cage().frameDepth() == 0) {  // not subdivided
            ++unsubdivided;  // the moved points all moved by one offset
            Eigen::RowVector3d offset = Eigen::RowVector3d::Zero();
            bool first = true;
            for (int p = 0; p < after.rows(); ++p) {
                const bool movable = std::binary_search(selection.begin(), selection.end(), p) &&
                                     std::find(pinned.begin(), pinned.end(), p) == pinned.end();
                const Eigen::RowVector3d moved = after.row(p) - before.row(p);
                if (!movable) {
                    CHECK(moved.isZero(0.0));
                } else if (first) {
                    offset = moved;
                    first = false;
                    CHECK(offset.norm() > 1e-4 * diagonal);
                } else {
                    CHECK((moved - offset).norm() <= 1e-12 * diagonal);
                }
            }
        }
        key(sculptApp, app::Key::Z, controlKey());
        CHECK((state.session.mesh().positions - original).cwiseAbs().maxCoeff() <= 1e-9 * diagonal);
    }
    CHECK(edits >= 4);
    CHECK(unsubdivided >= 2);
}

TEST_CASE("window tools: P pins the selection, a pinned selection cannot be dragged", "[gl]") {
    app::SculptApp sculptApp;
    loadDefault(sculptApp);
    app::AppState& state = sculptApp.state();
    key(sculptApp, app::Key::Tab);
    key(sculptApp, app::Key::P);  // nothing selected: says so
    CHECK(state.statusIsError);
    const core::Lattice& lattice = state.session.lattice();
    const int id = lattice.index(4, 4, 4);
    state.tools.lattice.points = {id};
    key(sculptApp, app::Key::P);
    CHECK(lattice.pinned[static_cast<size_t>(id)] == 1);
    double x = 0, y = 0;
    REQUIRE(app::projectToPixel(state.camera, kWidth, kHeight, lattice.controlPoint(id), x, y));
    const int under = app::controlPointAtPixel(core::controlPointPositions(lattice), {}, state.camera, kWidth, kHeight, x, y, 9.0);
    state.tools.lattice.points = {under};
    REQUIRE(state.session.pins().set({under}, true).ok);
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Press, x, y, {}}, {});
    CHECK_FALSE(state.drag.active);
    // Selecting a pinned point is what P needs: said, not an error.
    CHECK_FALSE(state.statusIsError);
    CHECK(state.status.find("pinned") != std::string::npos);
    CHECK(state.status.find("P unpins") != std::string::npos);
    sculptApp.onMouseMove({x + 20, y + 20, {}}, {});
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Release, x + 20, y + 20, {}}, {});
    CHECK(state.session.history().empty());
    key(sculptApp, app::Key::P);  // all selected are pinned: P unpins
    CHECK(lattice.pinned[static_cast<size_t>(under)] == 0);
}

TEST_CASE("window tools: the lattice set-up panel's command re-sets up as one undo step and refuses bad settings", "[gl]") {
    app::SculptApp sculptApp;
    loadDefault(sculptApp);
    app::AppState& state = sculptApp.state();
    const Positions original = state.session.mesh().positions;
    state.tools.lattice.points = {state.session.lattice().controlPointCount() - 1};
    core::LatticeSettings settings = state.session.cage().settings();
    settings.resolution = {5, 6, 4};
    settings.degree = {2, 3, 1};
    settings.pinLayers = 1;
    app::setupLatticeCommand(state, settings);
    CHECK_FALSE(state.statusIsError);
    CHECK(state.session.lattice().count == std::array<int, 3>{5, 6, 4});
    CHECK(state.session.history().size() == 1);
    CHECK(state.session.mesh().positions == original);  // a fresh lattice does not move the mesh
    app::clampLatticeSelection(state);
    CHECK(state.tools.lattice.points.empty());  // the old id does not exist in a 5x6x4 lattice

    core::LatticeSettings bad = settings;
    bad.degree = {5, 5, 5};
    bad.resolution = {3, 3, 3};  // fewer control points than degree + 1
    app::setupLatticeCommand(state, bad);
    CHECK(state.statusIsError);
    CHECK(state.status.find("Lattice not changed") != std::string::npos);
    CHECK(state.session.history().size() == 1);
    CHECK(state.session.lattice().count == std::array<int, 3>{5, 6, 4});

    key(sculptApp, app::Key::Z, controlKey());
    CHECK(state.session.lattice().count == std::array<int, 3>{8, 8, 8});
    CHECK(state.session.mesh().positions == original);
}

TEST_CASE("window tools: the status line hint says what the cursor would do", "[gl]") {
    app::SculptApp sculptApp;
    loadDefault(sculptApp);
    app::AppState& state = sculptApp.state();
    sculptApp.onMouseMove({10, 10, {}}, {});
    CHECK(state.tools.hint.rfind("Off the mesh", 0) == 0);  // nothing to sculpt there
    sculptApp.onMouseMove({0.5 * kWidth, 0.5 * kHeight, {}}, {});
    CHECK(state.tools.hint.find("Shift+click: add handle") != std::string::npos);
    click(sculptApp, 0.5 * kWidth, 0.5 * kHeight, shiftKey());
    REQUIRE(state.tools.handles.size() == 1);
    double x = 0, y = 0;
    REQUIRE(app::projectToPixel(state.camera, kWidth, kHeight,
                                app::handlePosition(state.tools.handles[0], state.session.mesh().positions, state.session.mesh().triangles), x, y));
    sculptApp.onMouseMove({x, y, {}}, {});
    // With Limit to radius on (as at start) a handle's drag is a brush stroke; off, it moves the lattice.
    CHECK(state.tools.hint.find("Handle: a drag is a brush stroke") != std::string::npos);
    state.tools.brush.limited = false;
    sculptApp.onMouseMove({x, y, {}}, {});
    CHECK(state.tools.hint.find("Handle: drag to move all handles") != std::string::npos);
    state.tools.brush.limited = true;
    key(sculptApp, app::Key::Tab);
    sculptApp.onMouseMove({2, 2, {}}, {});
    CHECK(state.tools.hint.find("box select") != std::string::npos);
    // Over a panel (the UI claims the mouse) nothing under it is offered: no control point hovered, no hint,
    // no brush circle; off the panel again, the hint is back. Every control point in view, each under a panel.
    int checked = 0;
    const Positions points = core::controlPointPositions(state.session.lattice());
    for (Eigen::Index id = 0; id < points.rows(); id += 7) {
        if (!app::projectToPixel(state.camera, kWidth, kHeight, points.row(id).transpose(), x, y)) continue;
        if (x < 0 || y < 0 || x >= kWidth || y >= kHeight) continue;
        sculptApp.onMouseMove({x, y, {}}, {});
        if (state.tools.lattice.hovered < 0) continue;
        ++checked;
        CHECK(state.tools.hint.find("Control point") != std::string::npos);
        app::CaptureFlags overPanel;
        overPanel.mouse = true;
        sculptApp.onMouseMove({x, y, {}}, overPanel);
        CHECK(state.tools.lattice.hovered == -1);
        CHECK(state.tools.hint.empty());
    }
    CHECK(checked > 0);
    key(sculptApp, app::Key::Tab);
    sculptApp.onMouseMove({0.5 * kWidth, 0.5 * kHeight, {}}, {});
    CHECK(state.tools.brush.hover);
    app::CaptureFlags overPanel;
    overPanel.mouse = true;
    sculptApp.onMouseMove({0.5 * kWidth, 0.5 * kHeight, {}}, overPanel);
    CHECK_FALSE(state.tools.brush.hover);
}

TEST_CASE("window tools: frames of both tools render with their markers (written for a look)", "[gl]") {
    app::SculptApp sculptApp;
    test::OffscreenWindow window;
    const Status opened = window.open(sculptApp, kWidth, kHeight, 0);
    if (!opened) {
        WARN("no EGL context, frame skipped: " << opened.message);
        return;
    }
    loadDefault(sculptApp);
    app::AppState& state = sculptApp.state();
    render::Rgba8Image before, withMarkers, dragging, latticeTool;
    REQUIRE(window.frame(&before).ok);
    click(sculptApp, 0.5 * kWidth - 90, 0.5 * kHeight - 40, shiftKey());
    click(sculptApp, 0.5 * kWidth + 60, 0.5 * kHeight - 60, shiftKey());
    click(sculptApp, 0.5 * kWidth, 0.5 * kHeight + 70, controlKey());
    REQUIRE(state.tools.handles.size() == 3);
    REQUIRE(window.frame(&withMarkers).ok);
    // Pin markers are green squares: some pixel is now clearly green where none was.
    auto greenPixels = [](const render::Rgba8Image& image) {
        int count = 0;
        for (size_t p = 0; p + 3 < image.pixels.size(); p += 4)
            count += image.pixels[p + 1] > 150 && image.pixels[p] < 110 && image.pixels[p + 2] < 140;
        return count;
    };
    CHECK(greenPixels(before) == 0);
    CHECK(greenPixels(withMarkers) > 20);
    double x = 0, y = 0;
    REQUIRE(app::projectToPixel(state.camera, kWidth, kHeight,
                                app::handlePosition(state.tools.handles[0], state.session.mesh().positions, state.session.mesh().triangles), x, y));
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Press, x, y, {}}, {});
    for (int m = 1; m <= 4; ++m) sculptApp.onMouseMove({x, y - 15.0 * m, {}}, {});
    REQUIRE(window.frame(&dragging).ok);
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Release, x, y - 60, {}}, {});
    key(sculptApp, app::Key::Tab);
    state.tools.lattice.points = {state.session.lattice().index(4, 4, 4), state.session.lattice().index(5, 4, 4)};
    state.gpu.fields = true;
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Press, 30, 400, {}}, {});
    sculptApp.onMouseMove({200, 560, {}}, {});
    REQUIRE(window.frame(&latticeTool).ok);
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Release, 200, 560, {}}, {});
    const std::string dir = SCULPT_GL_TEST_OUTPUT_DIR;
    io::writePng(dir + "/tools_markers.png", withMarkers.width, withMarkers.height, withMarkers.pixels.data());
    io::writePng(dir + "/tools_dragging.png", dragging.width, dragging.height, dragging.pixels.data());
    io::writePng(dir + "/tools_lattice.png", latticeTool.width, latticeTool.height, latticeTool.pixels.data());
    WARN("tool frames written to " << dir << "/tools_*.png");
}

TEST_CASE("window tools: Esc during a drag takes it back and records nothing", "[gl]") {
    app::SculptApp sculptApp;
    loadDefault(sculptApp);
    app::AppState& state = sculptApp.state();
    const Positions original = state.session.mesh().positions;
    const double cx = 0.5 * kWidth, cy = 0.5 * kHeight;
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Press, cx, cy, {}}, {});
    REQUIRE(state.drag.active);
    for (int m = 1; m <= 6; ++m) sculptApp.onMouseMove({cx, cy - 20.0 * m, {}}, {});
    REQUIRE((state.session.mesh().positions - original).cwiseAbs().maxCoeff() > 0.0);
    key(sculptApp, app::Key::Escape);
    CHECK_FALSE(state.drag.active);
    CHECK(state.status.find("cancelled") != std::string::npos);
    sculptApp.onMouseMove({cx, cy - 200.0, {}}, {});  // moves after the cancel change nothing
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Release, cx, cy - 200.0, {}}, {});
    CHECK(state.session.history().empty());
    CHECK((state.session.mesh().positions - original).cwiseAbs().maxCoeff() <= 1e-9 * diagonalOf(original));
}
