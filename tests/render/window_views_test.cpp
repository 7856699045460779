// The 3D view's keys and wheel as Blender has them (view_navigation.h), driven by synthetic events: numpad
// axis views, orthographic / perspective, zoom toward the cursor, framing. Independent checks: where world
// axes project on the screen, the picking ray through a projected point, the pixel of the point under the
// cursor before and after a zoom.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>

#include "app/window/picking.h"
#include "app/window/sculpt_app.h"
#include "io/png_image.h"
#include "offscreen_window.h"
#include "window_test_support.h"

using namespace sculpt;

namespace {

constexpr int kWidth = 960, kHeight = 600;

app::Modifiers controlKey() { app::Modifiers m; m.control = true; return m; }

void key(app::SculptApp& a, app::Key k, app::Modifiers m = {}) { a.onKey({k, app::KeyAction::Press, m}, {}); }

Eigen::Vector3d toEigen(const glm::dvec3& v) { return {v.x, v.y, v.z}; }

// Screen direction (pixels, y down) of a world direction seen from the camera's target.
Eigen::Vector2d screenDirection(const app::AppState& state, const Eigen::Vector3d& direction) {
    const Eigen::Vector3d target = toEigen(state.camera.target);
    const double step = 0.1 * state.camera.sceneRadius;
    double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    REQUIRE(app::projectToPixel(state.camera, kWidth, kHeight, target, x0, y0));
    REQUIRE(app::projectToPixel(state.camera, kWidth, kHeight, target + step * direction, x1, y1));
    return Eigen::Vector2d(x1 - x0, y1 - y0).normalized();
}

void orbit(app::SculptApp& a, double dx) {
    a.onMouseButton({app::MouseButton::Middle, app::ButtonAction::Press, 400, 300, {}}, {});
    a.onMouseMove({400 + dx, 300, {}}, {});
    a.onMouseButton({app::MouseButton::Middle, app::ButtonAction::Release, 400 + dx, 300, {}}, {});
}

}  // namespace

TEST_CASE("window views: numpad 1 3 7 look along the axes as Blender's front right and top, Ctrl the opposite, 5 toggles orthographic", "[gl]") {
    app::SculptApp sculptApp;
    test::loadDefaultMesh(sculptApp, kWidth, kHeight);
    app::AppState& state = sculptApp.state();
    const Eigen::Vector3d X = Eigen::Vector3d::UnitX(), Y = Eigen::Vector3d::UnitY(), Z = Eigen::Vector3d::UnitZ();
    const Eigen::Vector2d right(1, 0), up(0, -1);
    struct View {
        app::Key key;
        bool control;
        Eigen::Vector3d towardEye, screenRight, screenUp;  // world directions
    };
    // Y-up world: Blender's front (-Y_blender looking +Y) is the eye on +Z, its top the eye on +Y with -Z up.
    const View views[] = {
        {app::Key::Numpad1, false, Z, X, Y},   {app::Key::Numpad1, true, -Z, -X, Y},
        {app::Key::Numpad3, false, X, -Z, Y},  {app::Key::Numpad3, true, -X, Z, Y},
        {app::Key::Numpad7, false, Y, X, -Z},  {app::Key::Numpad7, true, -Y, X, Z},
    };
    for (const View& v : views) {
        INFO("key " << static_cast<int>(v.key) << (v.control ? " with Ctrl" : ""));
        key(sculptApp, v.key, v.control ? controlKey() : app::Modifiers{});
        CHECK((toEigen(state.camera.towardEye()) - v.towardEye).norm() <= 1e-12);
        CHECK(state.camera.orthographic);  // Blender's auto perspective
        CHECK((screenDirection(state, v.screenRight) - right).norm() <= 1e-9);
        CHECK((screenDirection(state, v.screenUp) - up).norm() <= 1e-9);
    }
    orbit(sculptApp, 30);  // leaving an axis view returns to perspective
    CHECK_FALSE(state.camera.orthographic);
    key(sculptApp, app::Key::Numpad5);
    CHECK(state.camera.orthographic);
    orbit(sculptApp, 30);  // the user's choice stays
    CHECK(state.camera.orthographic);
    key(sculptApp, app::Key::Numpad5);
    CHECK_FALSE(state.camera.orthographic);
}

TEST_CASE("window views: picking finds what is drawn under the cursor in both projections, the wheel zooms toward it", "[gl]") {
    for (const bool orthographic : {false, true}) {
        INFO((orthographic ? "orthographic" : "perspective"));
        app::SculptApp sculptApp;
        test::loadDefaultMesh(sculptApp, kWidth, kHeight);
        app::AppState& state = sculptApp.state();
        state.camera.orthographic = orthographic;
        const Positions& positions = state.session.mesh().positions;
        const double diagonal = test::boundsDiagonal(positions);
        // A vertex projected to its pixel: the ray through that pixel passes through the vertex.
        for (Eigen::Index v : {Eigen::Index(0), positions.rows() / 3, positions.rows() - 1}) {
            const Eigen::Vector3d p = positions.row(v).transpose();
            double x = 0, y = 0;
            REQUIRE(app::projectToPixel(state.camera, kWidth, kHeight, p, x, y));
            app::Ray ray;
            REQUIRE(app::rayThroughPixel(state.camera, kWidth, kHeight, x, y, ray));
            const Eigen::Vector3d w = p - ray.origin;
            CHECK((w - w.dot(ray.direction) * ray.direction).norm() <= 1e-9 * diagonal);
            CHECK(w.dot(ray.direction) > 0.0);
        }
        // Zoom in and out at an off-centre cursor: the point under it (at the target's depth) keeps its pixel.
        const double x = 0.5 * kWidth + 170, y = 0.5 * kHeight - 90;
        sculptApp.onMouseMove({x, y, {}}, {});
        app::Ray ray;
        REQUIRE(app::rayThroughPixel(state.camera, kWidth, kHeight, x, y, ray));
        Eigen::Vector3d under;
        REQUIRE(app::intersectPlane(ray, toEigen(state.camera.target), toEigen(state.camera.towardEye()), under));
        for (const double notches : {3.0, -1.0, 10.0}) {
            const double before = state.camera.distance;
            sculptApp.onScroll({0.0, notches}, {});
            CHECK((notches > 0 ? state.camera.distance < before : state.camera.distance > before));
            double px = 0, py = 0;
            REQUIRE(app::projectToPixel(state.camera, kWidth, kHeight, under, px, py));
            CHECK(std::hypot(px - x, py - y) <= 1e-6);
        }
    }
}

TEST_CASE("window views: numpad . frames the selected control points, Home frames everything", "[gl]") {
    app::SculptApp sculptApp;
    test::loadDefaultMesh(sculptApp, kWidth, kHeight);
    app::AppState& state = sculptApp.state();
    key(sculptApp, app::Key::Tab);
    // In the lattice tool the lattice is shown, so "everything" includes it.
    key(sculptApp, app::Key::Home);
    const render::Camera framed = state.camera;
    const core::Lattice& lattice = state.session.lattice();
    const int a = lattice.index(1, 2, 3), b = lattice.index(2, 2, 3);
    state.tools.lattice.points = {a, b};
    key(sculptApp, app::Key::NumpadDecimal);
    const Eigen::Vector3d middle = 0.5 * (lattice.controlPoint(a) + lattice.controlPoint(b));
    CHECK((toEigen(state.camera.target) - middle).norm() <= 1e-12);
    CHECK(state.camera.distance < 0.5 * framed.distance);
    CHECK(state.camera.sceneRadius == framed.sceneRadius);  // the near and far planes still hold everything
    key(sculptApp, app::Key::Home);
    CHECK((toEigen(state.camera.target) - toEigen(framed.target)).norm() <= 1e-12);
    CHECK(state.camera.distance == Approx(framed.distance).epsilon(1e-12));
}

TEST_CASE("window views: the top view, orthographic, renders the mesh and lattice from above (written for a look)", "[gl]") {
    app::SculptApp sculptApp;
    test::OffscreenWindow window;
    if (!test::openWindowWithDefaultMesh(window, sculptApp, kWidth, kHeight)) return;
    key(sculptApp, app::Key::Numpad7);
    render::Rgba8Image image;
    REQUIRE(window.frame(&image).ok);
    // The sphere seen from above covers the centre of the view.
    const size_t centre = (static_cast<size_t>(kHeight / 2) * kWidth + kWidth / 2) * 4;
    CHECK(image.pixels[centre] > 120);
    const std::string dir = SCULPT_GL_TEST_OUTPUT_DIR;
    io::writePng(dir + "/views_top_orthographic.png", image.width, image.height, image.pixels.data());
    WARN("view frame written to " << dir << "/views_top_orthographic.png");
}
