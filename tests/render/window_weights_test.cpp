// The window's hammer and crimp (sculpting by weights, Song & Yang 2005 sec. 1 and 6): with a frozen weighted
// T-spline, a click with the Hammer brush raises the clicked vertex by the height step, Ctrl+click lowers it
// back, the Crimp brush broadens the bump with its height kept; each is one undo step made by the script op.
#include <catch2/catch.hpp>

#include "app/window/sculpt_app.h"
#include "app/window/tools.h"
#include "io/script.h"
#include "window_test_support.h"

using namespace sculpt;

namespace {

constexpr int kWidth = 960, kHeight = 600;

void click(app::SculptApp& sculptApp, double x, double y, bool control = false) {
    app::MouseButtonEvent event{app::MouseButton::Left, app::ButtonAction::Press, x, y, {}};
    event.modifiers.control = control;
    sculptApp.onMouseButton(event, {});
    event.action = app::ButtonAction::Release;
    sculptApp.onMouseButton(event, {});
}

// The vertex the window's weight tools act on for a click at the viewport's centre, and its height.
double heightOf(const core::Session& session, int vertex, const Eigen::Vector3d& n) {
    return n.dot((session.mesh().positions.row(vertex) - session.mesh().rest.row(vertex)).transpose());
}

}  // namespace

TEST_CASE("window weights: the hammer raises and lowers the clicked vertex by the step, the crimp broadens with the height kept", "[gl][weights]") {
    app::SculptApp sculptApp;
    test::loadDefaultMesh(sculptApp, kWidth, kHeight);
    app::AppState& state = sculptApp.state();
    io::ScriptOp setup;
    setup.kind = io::ScriptOp::Kind::SetupTSpline;
    setup.tspline.octree.octree.depth = 3;
    setup.tspline.octree.weightRatio = 10.0;
    core::OpReport report;
    REQUIRE(io::runScriptOp(state.session, setup, report));
    REQUIRE(report.status == core::OpStatus::Applied);
    const size_t history = state.session.history().size();
    const double diagonal = test::boundsDiagonal(state.session.mesh().positions);

    app::BrushTool& brush = state.tools.brush;
    brush.kind = app::BrushTool::Kind::Hammer;
    brush.limited = false;  // the strongest control point only
    brush.hammerStep = 0.01;
    const double cx = 0.5 * kWidth, cy = 0.5 * kHeight;
    click(sculptApp, cx, cy);
    INFO(state.status);
    REQUIRE(state.session.history().size() == history + 1);
    const core::Operation& hammered = state.session.history().back();
    REQUIRE(hammered.kind == core::OperationKind::WeightEdit);
    REQUIRE(hammered.weightTool.tool == core::WeightToolSettings::Tool::Hammer);
    const int vertex = hammered.weightTool.vertex;
    core::TSplineTools::Bump bump;
    core::WeightToolSettings at = hammered.weightTool;
    REQUIRE(state.session.tspline().bumpAt(at, bump));
    CHECK(heightOf(state.session, vertex, bump.direction) == Approx(0.01 * diagonal).margin(1e-9 * diagonal));
    // Crimp: broader, same height at the vertex.
    brush.kind = app::BrushTool::Kind::Crimp;
    brush.crimpFactor = 1.2;
    const double before = heightOf(state.session, vertex, bump.direction);
    click(sculptApp, cx, cy);
    INFO(state.status);
    REQUIRE(state.session.history().size() == history + 2);
    CHECK(state.session.history().back().weightTool.tool == core::WeightToolSettings::Tool::Crimp);
    REQUIRE(state.session.tspline().bumpAt(at, bump));
    CHECK(heightOf(state.session, vertex, bump.direction) == Approx(before).margin(1e-9 * diagonal));
    // Ctrl+click with the hammer lowers the clicked vertex (the surface under the cursor has moved: it may be
    // another one) by one step, along its bump's direction (which the hammer keeps).
    brush.kind = app::BrushTool::Kind::Hammer;
    const Positions positionsBefore = state.session.mesh().positions, restBefore = state.session.mesh().rest;
    click(sculptApp, cx, cy, true);
    REQUIRE(state.session.history().size() == history + 3);
    INFO(state.status);
    at = state.session.history().back().weightTool;
    REQUIRE(state.session.undo(report));  // the bump's direction before the click (it turns over below zero)
    REQUIRE(state.session.tspline().bumpAt(at, bump));
    REQUIRE(state.session.redo(report));
    // (the step is a fraction of the mesh's size as it is when clicked)
    const double lowered =
        bump.direction.dot((positionsBefore.row(at.vertex) - restBefore.row(at.vertex)).transpose()) - 0.01 * test::boundsDiagonal(positionsBefore);
    CHECK(heightOf(state.session, at.vertex, bump.direction) == Approx(lowered).margin(1e-9 * diagonal));
    // Three undo steps return the mesh bitwise.
    for (int k = 0; k < 3; ++k) REQUIRE(state.session.undo(report));
    CHECK(state.session.mesh().positions == state.session.mesh().rest);
}
