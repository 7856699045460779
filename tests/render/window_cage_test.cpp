// The cage stays as the user shaped it (issue "A window a sculptor keeps using", point 1): a control-point
// drag through a fold stops at the limit and is never replaced by a fresh lattice; after sculpting drags that
// needed layers of their own, the lattice tool shows and edits the user's cage as the layers carry it.
#include <catch2/catch.hpp>

#include <random>

#include "app/scene_builder.h"
#include "app/window/sculpt_app.h"
#include "app/window/tools.h"
#include "window_test_support.h"

using namespace sculpt;

using test::pixelOf;

namespace {

constexpr int kWidth = 960, kHeight = 600;

void key(app::SculptApp& sculptApp, app::Key k) {
    app::KeyEvent event;
    event.key = k;
    sculptApp.onKey(event, {});
}

void undo(app::SculptApp& sculptApp) {
    app::KeyEvent event;
    event.key = app::Key::Z;
    event.modifiers.control = true;
    sculptApp.onKey(event, {});
}

}  // namespace

TEST_CASE("window cage: a control point dragged through a fold follows, stops at the limit, and one undo restores it", "[gl]") {
    std::mt19937 rng(907);
    int stopped = 0;
    for (int trial = 0; trial < 4; ++trial) {
        app::SculptApp sculptApp;
        test::loadDefaultMesh(sculptApp, kWidth, kHeight);
        app::AppState& state = sculptApp.state();
        const Positions original = state.session.mesh().positions;
        const Positions cage = state.session.cage().cagePoints();
        const core::LatticeSettings settings = state.session.cage().settings();
        key(sculptApp, app::Key::Tab);
        REQUIRE(state.tools.mode == app::ToolMode::Lattice);
        // An interior control point, picked by clicking its marker (the one nearest the eye if several overlap).
        const core::Lattice& lattice = state.session.lattice();
        const int i = std::uniform_int_distribution<int>(2, lattice.count[0] - 3)(rng);
        const int j = std::uniform_int_distribution<int>(2, lattice.count[1] - 3)(rng);
        const int k = std::uniform_int_distribution<int>(2, lattice.count[2] - 3)(rng);
        const Eigen::Vector2d start = pixelOf(state, cage.row(lattice.index(i, j, k)).transpose());
        sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Press, start.x(), start.y(), {}}, {});
        if (!state.drag.active) continue;  // a marker in front of it was unselected: picked, not grabbed
        REQUIRE(state.tools.lattice.points.size() == 1);
        const int id = state.tools.lattice.points.front();
        const Eigen::Vector2d grabbed = pixelOf(state, cage.row(id).transpose());
        // Up the screen, 8 px a move, far past the neighbouring control points.
        Eigen::Vector2d last = grabbed;
        bool limitReached = false;
        double followedPixels = 0.0;
        for (int m = 1; m <= 60; ++m) {
            const Eigen::Vector2d cursor(grabbed.x(), grabbed.y() - 8.0 * m);
            sculptApp.onMouseMove({cursor.x(), cursor.y(), {}}, {});
            const Eigen::Vector2d shown = pixelOf(state, state.session.cage().cagePoints().row(id).transpose());
            INFO("trial " << trial << " move " << m << ": " << state.status);
            // Never a fresh lattice: the cage is the one set up, with no frame or layer added.
            CHECK(state.session.cage().frameDepth() == 0);
            CHECK(state.session.cage().settings().resolution == settings.resolution);
            if (!limitReached && (shown - cursor).norm() > 0.5) {
                limitReached = true;
                // It stopped short of the cursor, and says why.
                CHECK(state.status.find("Stopped where the lattice would fold") != std::string::npos);
                CHECK(shown.y() <= last.y() + 1e-6);  // it did not jump back
            }
            if (!limitReached) {
                followedPixels = grabbed.y() - shown.y();
            } else {
                // Past the limit nothing moves it further up, and nothing jumps.
                CHECK(shown.y() >= cursor.y());
                CHECK((shown - last).norm() <= 8.0 + 1e-6);
            }
            last = shown;
        }
        sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Release, grabbed.x(), grabbed.y() - 480.0, {}}, {});
        if (!limitReached) continue;
        ++stopped;
        CHECK(followedPixels >= 8.0);  // it did follow before it stopped
        REQUIRE(state.session.history().size() == 1);  // one edit, no set-up
        CHECK(state.session.history().front().kind == core::OperationKind::ControlPointEdit);
        for (const core::JournalEntry& entry : state.session.history().journal())
            CHECK(entry.operation.kind != core::OperationKind::LatticeSetup);
        undo(sculptApp);
        const double diagonal = test::boundsDiagonal(original);
        CHECK((state.session.cage().cagePoints() - cage).cwiseAbs().maxCoeff() <= 1e-12 * diagonal);
        CHECK((state.session.mesh().positions - original).cwiseAbs().maxCoeff() <= 1e-9 * diagonal);
        CHECK(state.session.history().cursor() == 0);
    }
    CHECK(stopped >= 2);
}

TEST_CASE("window cage: after sculpting drags in several steps the lattice tool shows and moves the cage the layers carried", "[gl]") {
    app::SculptApp sculptApp;
    test::loadDefaultMesh(sculptApp, kWidth, kHeight);
    app::AppState& state = sculptApp.state();
    const core::LatticeSettings settings = state.session.cage().settings();
    const Positions restCage = state.session.cage().cagePoints();
    // A long pull with the whole cage (no brush radius): more than one injective step, so layers are added.
    state.tools.brush.limited = false;
    const double cx = 0.5 * kWidth, cy = 0.5 * kHeight;
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Press, cx, cy, {}}, {});
    REQUIRE(state.drag.active);
    for (int m = 1; m <= 20; ++m) sculptApp.onMouseMove({cx, cy - 15.0 * m, {}}, {});
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Release, cx, cy - 300.0, {}}, {});
    REQUIRE(state.session.history().size() == 1);
    INFO(state.status);
    REQUIRE(!state.session.cage().layers().empty());
    CHECK(state.session.cage().settings().resolution == settings.resolution);  // the same cage, not a new one

    // The cage drawn is the user's, carried through the layers: not the layers' regular grid.
    key(sculptApp, app::Key::Tab);
    app::SceneRequest request;
    const render::SceneData scene = app::sceneFromSession(state.session, request);
    CHECK(scene.lattice.nu == settings.resolution[0]);
    const Positions shown = state.session.cage().cagePoints();
    CHECK((scene.lattice.controlPoints - shown).cwiseAbs().maxCoeff() == 0.0);
    CHECK((shown - restCage).cwiseAbs().maxCoeff() > 1e-3 * test::boundsDiagonal(restCage));

    // A selected control point follows the cursor as shown, and the next drag is solved in the cage again.
    const core::Lattice& lattice = state.session.lattice();
    int id = -1;
    for (int c = 0; c < lattice.controlPointCount() && id < 0; ++c) {
        const std::array<int, 3> ijk = lattice.ijk(c);
        if (ijk[0] == 4 && ijk[1] == 6 && ijk[2] == 4) id = c;
    }
    REQUIRE(id >= 0);
    state.tools.lattice.points = {id};
    const Eigen::Vector2d at = pixelOf(state, shown.row(id).transpose());
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Press, at.x(), at.y(), {}}, {});
    if (state.drag.active && state.tools.lattice.points == std::vector<int>{id}) {
        const size_t layers = state.session.cage().layers().size();
        sculptApp.onMouseMove({at.x() + 5.0, at.y() - 4.0, {}}, {});
        if (state.lastReport.status == core::OpStatus::Applied && state.lastReport.fractionApplied == 1.0)
            CHECK((pixelOf(state, state.session.cage().cagePoints().row(id).transpose()) - Eigen::Vector2d(at.x() + 5.0, at.y() - 4.0)).norm() < 0.05);
        sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Release, at.x() + 5.0, at.y() - 4.0, {}}, {});
        CHECK(state.session.cage().layers().size() == layers);  // the layers stay as they were
    }
}

TEST_CASE("window cage: in an orthographic view a click picks the control point nearest the eye", "[gl]") {
    app::SculptApp sculptApp;
    test::loadDefaultMesh(sculptApp, kWidth, kHeight);
    app::AppState& state = sculptApp.state();
    key(sculptApp, app::Key::Tab);
    for (app::Key view : {app::Key::Numpad1, app::Key::Numpad3, app::Key::Numpad7}) {
        key(sculptApp, view);  // an axis view: orthographic, so every point has the same clip w
        REQUIRE(state.camera.orthographic);
        const Positions points = state.session.cage().cagePoints();
        const core::Lattice& lattice = state.session.lattice();
        // A column of points one behind the other along the view axis projects to one pixel.
        const Eigen::Vector3d toEye(state.camera.towardEye().x, state.camera.towardEye().y, state.camera.towardEye().z);
        const Eigen::Vector2d at = pixelOf(state, points.row(lattice.index(4, 4, 4)).transpose());
        const int picked = app::controlPointAtPixel(points, {}, state.camera, kWidth, kHeight, at.x(), at.y(), 9.0);
        REQUIRE(picked >= 0);
        for (Eigen::Index p = 0; p < points.rows(); ++p)
            if ((pixelOf(state, points.row(p).transpose()) - at).norm() < 0.5)
                CHECK(points.row(p).dot(toEye.transpose()) <= points.row(picked).dot(toEye.transpose()) + 1e-12);
    }
}
