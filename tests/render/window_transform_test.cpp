// The lattice tool's modal transforms (G, R, S, as in Blender) and the view keys, driven by synthetic events.
// Independent checks: a transform of every control point is an affine map, which a B-spline lattice passes on
// to the mesh exactly (affine invariance), so the mesh is compared with the same map applied to its vertices;
// a typed move is compared with the offset typed; cancel and undo with the start state.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>

#include <Eigen/Geometry>

#include "app/window/picking.h"
#include "app/window/sculpt_app.h"
#include "app/window/tool_commands.h"
#include "io/png_image.h"
#include "offscreen_window.h"
#include "window_test_support.h"

using namespace sculpt;

namespace {

constexpr int kWidth = 960, kHeight = 600;
constexpr double kPi = 3.14159265358979323846;

app::Modifiers controlKey() { app::Modifiers m; m.control = true; return m; }

void key(app::SculptApp& a, app::Key k, app::Modifiers m = {}) { a.onKey({k, app::KeyAction::Press, m}, {}); }

// Types "0.5", "-90" and the like as key presses (main keyboard digits, '.', '-').
void type(app::SculptApp& a, const std::string& text) {
    for (char c : text) {
        if (c >= '0' && c <= '9') key(a, static_cast<app::Key>(static_cast<int>(app::Key::Digit0) + (c - '0')));
        else if (c == '.') key(a, app::Key::Period);
        else if (c == '-') key(a, app::Key::Minus);
    }
}

// The default mesh in the lattice tool with every control point selected.
void startWithAllSelected(app::SculptApp& sculptApp) {
    test::loadDefaultMesh(sculptApp, kWidth, kHeight);
    key(sculptApp, app::Key::Tab);
    key(sculptApp, app::Key::A);
    REQUIRE(sculptApp.state().tools.lattice.points.size() == static_cast<size_t>(sculptApp.state().session.lattice().controlPointCount()));
}

Eigen::Vector3d centroidOf(const Positions& points) { return points.colwise().mean().transpose(); }

// max |q - (A (p - c) + c)| over the rows.
double affineError(const Positions& before, const Positions& after, const Eigen::Matrix3d& map, const Eigen::Vector3d& centre) {
    double error = 0.0;
    for (Eigen::Index r = 0; r < before.rows(); ++r) {
        const Eigen::Vector3d expected = map * (before.row(r).transpose() - centre) + centre;
        error = std::max(error, (after.row(r).transpose() - expected).norm());
    }
    return error;
}

}  // namespace

TEST_CASE("window transform: typed G, R and S move, turn and scale the selection about its median point, one undo step each", "[gl]") {
    app::SculptApp sculptApp;
    startWithAllSelected(sculptApp);
    app::AppState& state = sculptApp.state();
    // note: the exact test, because the conic one is not invariant under rotation: it refuses a whole lattice
    // turned by more than about 45 degrees (measured: 40 passes, 45 stops), though a rigid turn is injective.
    state.session.setInjectivity({core::InjectivityMode::Exact, 6});
    const Positions original = state.session.positions();
    const double diagonal = test::boundsDiagonal(original);
    const double tolerance = 1e-9 * diagonal;

    struct Case {
        const char* keys;  // e.g. "G Z 0.5": the transform key, an axis key or none, the typed value
        app::Key transform;
        app::Key axis;     // Key::Other: none
        std::string value;
        Eigen::Matrix3d map;
        Eigen::Vector3d shift;
    };
    const Eigen::Matrix3d identity = Eigen::Matrix3d::Identity();
    const Case cases[] = {
        {"G Z 0.5", app::Key::G, app::Key::Z, "0.5", identity, Eigen::Vector3d(0, 0, 0.5)},
        {"G -0.25 (X without an axis)", app::Key::G, app::Key::Other, "-0.25", identity, Eigen::Vector3d(-0.25, 0, 0)},
        {"R Z 90", app::Key::R, app::Key::Z, "90", Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix(), Eigen::Vector3d::Zero()},
        {"R X -30", app::Key::R, app::Key::X, "-30", Eigen::AngleAxisd(-kPi / 6, Eigen::Vector3d::UnitX()).toRotationMatrix(), Eigen::Vector3d::Zero()},
        {"S 2", app::Key::S, app::Key::Other, "2", 2.0 * identity, Eigen::Vector3d::Zero()},
        {"S Y 0.5", app::Key::S, app::Key::Y, "0.5", Eigen::Vector3d(1, 0.5, 1).asDiagonal(), Eigen::Vector3d::Zero()},
    };
    int entries = 0;
    for (const Case& c : cases) {
        INFO(c.keys);
        const Positions meshBefore = state.session.positions();
        const Positions latticeBefore = core::controlPointPositions(state.session.lattice());
        const Eigen::Vector3d pivot = centroidOf(latticeBefore);
        // The cursor wanders first: a typed value replaces whatever the mouse did.
        key(sculptApp, c.transform);
        REQUIRE(state.transform.active);
        REQUIRE(state.drag.active);
        sculptApp.onMouseMove({0.5 * kWidth + 37, 0.5 * kHeight - 23, {}}, {});
        if (c.axis != app::Key::Other) key(sculptApp, c.axis);
        type(sculptApp, c.value);
        // The status line reads like Blender's header: "Move Z: [0.5|]".
        const std::string head = std::string(c.transform == app::Key::G ? "Move" : c.transform == app::Key::R ? "Rotate" : "Scale");
        CHECK(state.status.rfind(head, 0) == 0);
        CHECK(state.status.find("[" + c.value + "|]") != std::string::npos);
        const std::string during = state.status;
        INFO(during);
        key(sculptApp, app::Key::Enter);
        CHECK_FALSE(state.transform.active);
        CHECK_FALSE(state.drag.active);
        REQUIRE(state.session.history().size() == static_cast<size_t>(++entries));
        INFO(state.status);
        // Every control point and, by affine invariance, every vertex went through the same map.
        const Positions latticeShifted = latticeBefore.rowwise() + c.shift.transpose();
        CHECK(affineError(latticeShifted, core::controlPointPositions(state.session.lattice()), c.map, pivot + c.shift) <= tolerance);
        const Positions meshShifted = meshBefore.rowwise() + c.shift.transpose();
        CHECK(affineError(meshShifted, state.session.positions(), c.map, pivot + c.shift) <= tolerance);
    }
    // One undo step each, back to the start.
    for (int u = 0; u < entries; ++u) key(sculptApp, app::Key::Z, controlKey());
    CHECK(state.session.historyCursor() == 0);
    CHECK((state.session.positions() - original).cwiseAbs().maxCoeff() <= tolerance);
}

TEST_CASE("window transform: the mouse moves along a locked axis, X Y Z lock and unlock, Backspace and minus edit the value", "[gl]") {
    app::SculptApp sculptApp;
    startWithAllSelected(sculptApp);
    app::AppState& state = sculptApp.state();
    const Positions before = core::controlPointPositions(state.session.lattice());
    const double cx = 0.5 * kWidth, cy = 0.5 * kHeight;
    sculptApp.onMouseMove({cx, cy, {}}, {});
    key(sculptApp, app::Key::G);
    key(sculptApp, app::Key::Y);
    CHECK(state.transform.axis == 1);
    sculptApp.onMouseMove({cx + 5, cy - 60, {}}, {});
    Positions moved = core::controlPointPositions(state.session.lattice()) - before;
    CHECK(moved.col(1).minCoeff() > 0.0);  // up on the screen is up in Y (the default view looks slightly down)
    CHECK(moved.col(1).maxCoeff() - moved.col(1).minCoeff() <= 1e-12);
    CHECK(moved.col(0).cwiseAbs().maxCoeff() == 0.0);
    CHECK(moved.col(2).cwiseAbs().maxCoeff() == 0.0);
    CHECK(state.status.rfind("Move Y: ", 0) == 0);
    key(sculptApp, app::Key::Y);  // the same key again: free in the view plane
    CHECK(state.transform.axis == -1);
    CHECK(state.status.rfind("Move: ", 0) == 0);
    key(sculptApp, app::Key::X);
    CHECK(state.transform.axis == 0);
    type(sculptApp, "12");
    key(sculptApp, app::Key::Minus);
    CHECK(state.status.find("[-12|]") != std::string::npos);
    key(sculptApp, app::Key::Backspace);
    CHECK(state.status.find("[-1|]") != std::string::npos);
    key(sculptApp, app::Key::Backspace);  // nothing typed: the mouse again, negated
    CHECK(state.transform.digits.empty());
    CHECK(state.transform.negate);
    key(sculptApp, app::Key::Backspace);
    CHECK_FALSE(state.transform.negate);
    key(sculptApp, app::Key::Escape);
    CHECK_FALSE(state.transform.active);
}

TEST_CASE("window transform: Esc or a right click cancels exactly and records nothing, shortcuts wait until it ends", "[gl]") {
    for (const bool rightClick : {false, true}) {
        app::SculptApp sculptApp;
        test::loadDefaultMesh(sculptApp, kWidth, kHeight);
        app::AppState& state = sculptApp.state();
        key(sculptApp, app::Key::Tab);
        const core::Lattice& lattice = state.session.lattice();
        state.tools.lattice.points = {lattice.index(3, 3, 3), lattice.index(4, 3, 3), lattice.index(3, 4, 3), lattice.index(4, 4, 4)};
        const Positions original = state.session.positions();
        const Positions originalLattice = core::controlPointPositions(lattice);
        const double cx = 0.5 * kWidth, cy = 0.5 * kHeight;
        sculptApp.onMouseMove({cx + 80, cy, {}}, {});
        key(sculptApp, rightClick ? app::Key::R : app::Key::S);
        REQUIRE(state.transform.active);
        for (int m = 1; m <= 5; ++m) sculptApp.onMouseMove({cx + 80 + 6 * m, cy - 9 * m, {}}, {});
        REQUIRE((state.session.positions() - original).cwiseAbs().maxCoeff() > 0.0);
        key(sculptApp, app::Key::Z, controlKey());  // no undo in the middle of a transform
        key(sculptApp, app::Key::Tab);              // nor a tool change
        CHECK(state.transform.active);
        CHECK(state.tools.mode == app::ToolMode::Lattice);
        if (rightClick) sculptApp.onMouseButton({app::MouseButton::Right, app::ButtonAction::Press, cx, cy, {}}, {});
        else key(sculptApp, app::Key::Escape);
        CHECK_FALSE(state.transform.active);
        CHECK_FALSE(state.drag.active);
        CHECK(state.status.find("cancelled") != std::string::npos);
        CHECK(state.session.history().empty());
        // The control points bitwise (the drag's delta is taken back from zero); the vertices to rounding, as
        // Session::cancelDrag subtracts the delta's effect (its inverse manipulation) rather than copying back.
        const double diagonal = test::boundsDiagonal(original);
        CHECK(core::controlPointPositions(state.session.lattice()) == originalLattice);
        CHECK((state.session.positions() - original).cwiseAbs().maxCoeff() <= 1e-15 * diagonal);
        CHECK(state.tools.lattice.points.size() == 4);  // the selection stays (Esc after the cancel clears it)
        // The release of the right button, and moves after it, change nothing.
        sculptApp.onMouseButton({app::MouseButton::Right, app::ButtonAction::Release, cx, cy, {}}, {});
        sculptApp.onMouseMove({cx + 200, cy + 100, {}}, {});
        CHECK(core::controlPointPositions(state.session.lattice()) == originalLattice);
    }
}

TEST_CASE("window transform: a left click confirms the mouse's move as one undo step, nothing selected says so", "[gl]") {
    app::SculptApp sculptApp;
    test::loadDefaultMesh(sculptApp, kWidth, kHeight);
    app::AppState& state = sculptApp.state();
    key(sculptApp, app::Key::Tab);
    key(sculptApp, app::Key::G);  // nothing selected
    CHECK_FALSE(state.transform.active);
    CHECK(state.statusIsError);
    const core::Lattice& lattice = state.session.lattice();
    state.tools.lattice.points = {lattice.index(3, 3, 3), lattice.index(4, 3, 3)};
    REQUIRE(state.session.setPinned({lattice.index(4, 3, 3)}, true).ok);
    const Positions before = core::controlPointPositions(lattice);
    const double cx = 0.5 * kWidth, cy = 0.5 * kHeight;
    sculptApp.onMouseMove({cx, cy, {}}, {});
    key(sculptApp, app::Key::G);
    REQUIRE(state.transform.active);
    CHECK(state.transform.points == std::vector<int>{lattice.index(3, 3, 3)});  // the pinned one stays
    sculptApp.onMouseMove({cx + 12, cy - 7, {}}, {});
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Press, cx + 12, cy - 7, {}}, {});
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Release, cx + 12, cy - 7, {}}, {});
    CHECK_FALSE(state.transform.active);
    REQUIRE(state.session.history().size() == 1);
    const Positions after = core::controlPointPositions(lattice);
    CHECK((after.row(lattice.index(3, 3, 3)) - before.row(lattice.index(3, 3, 3))).norm() > 0.0);
    CHECK(after.row(lattice.index(4, 3, 3)) == before.row(lattice.index(4, 3, 3)));
    CHECK(state.status.find("one undo step") != std::string::npos);
}

TEST_CASE("window transform: the locked axis is drawn through the pivot in its colour (written for a look)", "[gl]") {
    app::SculptApp sculptApp;
    test::OffscreenWindow window;
    if (!test::openWindowWithDefaultMesh(window, sculptApp, kWidth, kHeight)) return;
    app::AppState& state = sculptApp.state();
    key(sculptApp, app::Key::Tab);
    const core::Lattice& lattice = state.session.lattice();
    state.tools.lattice.points = {lattice.index(3, 3, 3), lattice.index(4, 3, 3), lattice.index(3, 4, 3), lattice.index(4, 4, 3)};
    sculptApp.onMouseMove({0.5 * kWidth, 0.5 * kHeight, {}}, {});
    render::Rgba8Image free, locked, rotating;
    key(sculptApp, app::Key::G);
    REQUIRE(window.frame(&free).ok);
    key(sculptApp, app::Key::X);
    sculptApp.onMouseMove({0.5 * kWidth + 40, 0.5 * kHeight, {}}, {});
    REQUIRE(window.frame(&locked).ok);
    key(sculptApp, app::Key::Escape);
    key(sculptApp, app::Key::R);
    key(sculptApp, app::Key::Z);
    sculptApp.onMouseMove({0.5 * kWidth + 60, 0.5 * kHeight - 80, {}}, {});
    REQUIRE(window.frame(&rotating).ok);
    key(sculptApp, app::Key::Escape);
    // Strong red (X) pixels outside the UI: none while free, a line's worth once X is locked.
    auto redPixels = [&](const render::Rgba8Image& image) {
        const std::vector<std::uint8_t> ui = window.uiMask();
        int count = 0;
        for (int p = 0; p < image.width * image.height; ++p) {
            const std::uint8_t* px = &image.pixels[static_cast<size_t>(p) * 4];
            count += !ui[static_cast<size_t>(p)] && px[0] > 200 && px[1] < 90 && px[2] < 120;
        }
        return count;
    };
    auto bluePixels = [&](const render::Rgba8Image& image) {
        int count = 0;
        for (size_t p = 0; p + 3 < image.pixels.size(); p += 4)
            count += image.pixels[p + 2] > 200 && image.pixels[p] < 80 && image.pixels[p + 1] > 90 && image.pixels[p + 1] < 180;
        return count;
    };
    CHECK(redPixels(free) < 20);
    CHECK(redPixels(locked) > 300);
    CHECK(bluePixels(rotating) > bluePixels(free) + 100);
    const std::string dir = SCULPT_GL_TEST_OUTPUT_DIR;
    io::writePng(dir + "/transform_free.png", free.width, free.height, free.pixels.data());
    io::writePng(dir + "/transform_locked_x.png", locked.width, locked.height, locked.pixels.data());
    io::writePng(dir + "/transform_rotate_z.png", rotating.width, rotating.height, rotating.pixels.data());
    WARN("transform frames written to " << dir << "/transform_*.png");
}

