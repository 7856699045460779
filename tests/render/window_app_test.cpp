// The window's application logic (SculptApp) driven by synthetic input events, and full frames (scene +
// Dear ImGui UI) rendered offscreen. No display needed.
//
// note: which GL context the UI frames use. Dear ImGui's prebuilt OpenGL3 backend (Debian's libimgui.a) loads
// GL itself through dlopen("libGL.so.1") + glXGetProcAddressARB. Under GLVND those entry points dispatch to
// whatever context is current, GLX or EGL, so the backend works unchanged in an EGL surfaceless context,
// the same object code the window uses. Under OSMesa its loader fails (OSMesa is not reached through GLVND);
// compiling the backend source a second time with a custom loader would test different code than ships.
// So these frames use EGL (Mesa's surfaceless platform: llvmpipe here, a GPU where there is one); where EGL
// is missing the frame test warns and skips, and the event tests above it still run.
#include <catch2/catch.hpp>

#include <cmath>
#include <memory>
#include <string>

#include <random>

#include <imgui.h>

#include "app/window/picking.h"
#include "app/window/sculpt_app.h"
#include "app/window/ui_style.h"
#include "app/window/wording.h"
#include "gl_test_support.h"
#include "offscreen_window.h"
#include "window_test_support.h"
#include "io/png_image.h"
#include "io/script_ops.h"
#include "render/offscreen_context.h"
#include "render/render_target.h"

using namespace sculpt;

namespace {

constexpr int kWidth = 960, kHeight = 600;

void loadDefault(app::SculptApp& sculptApp) { test::loadDefaultMesh(sculptApp, kWidth, kHeight); }

double diagonal(const Positions& p) { return test::boundsDiagonal(p); }

app::KeyEvent ctrlKey(app::Key key, bool shift = false) {
    app::KeyEvent event;
    event.key = key;
    event.modifiers.control = true;
    event.modifiers.shift = shift;
    return event;
}

// Press on the framebuffer centre, move 60 px up in `moves` steps, release. Returns the last target.
Eigen::Vector3d dragUp(app::SculptApp& sculptApp, app::CaptureFlags capture, int moves = 6) {
    const double cx = 0.5 * kWidth, cy = 0.5 * kHeight;
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Press, cx, cy, {}}, capture);
    for (int m = 1; m <= moves; ++m) sculptApp.onMouseMove({cx, cy - 60.0 * m / moves, {}}, capture);
    const Eigen::Vector3d target = sculptApp.state().drag.target;
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Release, cx, cy - 60.0, {}}, capture);
    return target;
}

}  // namespace

TEST_CASE("window: a drag on the mesh moves the picked point toward the cursor, one undo step", "[gl]") {
    app::SculptApp sculptApp;
    loadDefault(sculptApp);
    app::AppState& state = sculptApp.state();
    const Positions original = state.session.mesh().positions;

    // The centre of the view hits the mesh, and the press starts a drag there.
    app::Ray ray;
    REQUIRE(app::rayThroughPixel(state.camera, kWidth, kHeight, 0.5 * kWidth, 0.5 * kHeight, ray));
    const app::SurfaceHit hit = app::intersectMesh(ray, original, state.session.mesh().triangles);
    REQUIRE(hit.triangle >= 0);
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Press, 0.5 * kWidth, 0.5 * kHeight, {}}, {});
    REQUIRE(state.drag.active);
    const int vertex = state.drag.pickedVertex;
    CHECK(vertex == hit.nearestCorner);
    // The drag's source is the hit point.
    REQUIRE(state.session.stroke().sources().size() == 1);
    CHECK((state.session.stroke().sources().front() - hit.point).norm() < 1e-6 * diagonal(original));
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Release, 0.5 * kWidth, 0.5 * kHeight, {}}, {});
    CHECK(state.session.history().empty());  // a click without a move records nothing

    const Eigen::Vector3d target = dragUp(sculptApp, {});
    const Eigen::Vector3d before = original.row(vertex).transpose();
    const Eigen::Vector3d after = state.session.mesh().positions.row(vertex).transpose();
    INFO("status: " << state.status);
    CHECK((after - target).norm() < 0.5 * (before - target).norm());
    const glm::dvec3 up = state.camera.up();
    const Eigen::Vector3d screenUp(up.x, up.y, up.z);
    CHECK((after - before).dot(screenUp) > 0.05 * diagonal(original));
    // The whole drag is one history entry.
    CHECK(state.session.history().size() == 1);
    CHECK(state.session.history().cursor() == 1);
    CHECK_FALSE(state.drag.active);

    // The drag's end says how many vertices it moved in all: those whose positions changed, the count its
    // undo reports (each move's own report counts only what that move changed).
    size_t changed = 0;
    for (Eigen::Index v = 0; v < original.rows(); ++v) changed += original.row(v) != state.session.mesh().positions.row(v);
    const std::string dragStatus = state.status;
    CHECK(dragStatus.find(", " + std::to_string(changed) + " vertices moved)") != std::string::npos);

    // Ctrl+Z restores the positions; Ctrl+Shift+Z and Ctrl+Y redo.
    const Positions dragged = state.session.mesh().positions;
    sculptApp.onKey(ctrlKey(app::Key::Z), {});
    CHECK(state.session.history().cursor() == 0);
    CHECK((state.session.mesh().positions - original).cwiseAbs().maxCoeff() <= 1e-9 * diagonal(original));
    // The status line names the command in words and counts what it moved.
    INFO("status: " << state.status);
    // ... and which history entry it took back.
    const std::string label = state.session.history()[static_cast<size_t>(state.session.history().cursor())].label;
    CHECK_FALSE(label.empty());
    CHECK(state.status == "Undo " + label + ": " + std::to_string(state.lastReport.verticesMoved) + " vertices moved.");
    CHECK(state.lastReport.verticesMoved > 1);
    CHECK(static_cast<size_t>(state.lastReport.verticesMoved) == changed);
    sculptApp.onKey(ctrlKey(app::Key::Z, true), {});
    CHECK(state.session.history().cursor() == 1);
    CHECK((state.session.mesh().positions - dragged).cwiseAbs().maxCoeff() <= 1e-9 * diagonal(original));
    // The redo names the entry too, and never says the steps again ("split into ... steps" is the edit's own).
    CHECK(state.status == "Redo " + label + ": " + std::to_string(changed) + " vertices moved.");
    sculptApp.onKey(ctrlKey(app::Key::Z), {});
    sculptApp.onKey(ctrlKey(app::Key::Y), {});
    CHECK(state.session.history().cursor() == 1);
    // Jumping in the history list is undo/redo until there.
    app::jumpToHistory(state, 0);
    CHECK(state.session.history().cursor() == 0);
    app::jumpToHistory(state, 1);
    CHECK(state.session.history().cursor() == 1);
}

TEST_CASE("window: a move the injectivity test refuses changes nothing and the status line says why", "[gl]") {
    app::SculptApp sculptApp;
    loadDefault(sculptApp);
    app::AppState& state = sculptApp.state();
    const Positions original = state.session.mesh().positions;
    core::InjectivitySettings strict;
    strict.mode = core::InjectivityMode::Conic;
    strict.maxDepth = 0;  // no subdivision: a large move must be refused outright
    app::setInjectivityCommand(state, strict);
    state.tools.brush.limited = false;  // the whole cage: its fold, not the brush's reach
    const double cx = 0.5 * kWidth, cy = 0.5 * kHeight;
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Press, cx, cy, {}}, {});
    REQUIRE(state.drag.active);
    sculptApp.onMouseMove({cx, cy - 0.45 * kHeight, {}}, {});  // far: folds the lattice
    INFO("status: " << state.status);
    REQUIRE(state.hasReport);
    CHECK(state.lastReport.status == core::OpStatus::Rejected);
    CHECK(state.statusIsError);
    // In the user's words: refused, what would happen and near where, what to try.
    CHECK(state.status.find("Refused: the mesh would fold over itself near (") != std::string::npos);
    CHECK(state.status.find("try a smaller move") != std::string::npos);
    CHECK(state.status.find("cell") == std::string::npos);       // the test's own terms stay in the report
    CHECK(state.status.find("hodograph") == std::string::npos);
    CHECK(state.session.mesh().positions == original);
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Release, cx, cy - 0.45 * kHeight, {}}, {});
    CHECK(state.session.history().empty());
    CHECK(state.status.find("refused") != std::string::npos);
}

TEST_CASE("window: input the UI captures does not sculpt or undo", "[gl]") {
    app::SculptApp sculptApp;
    loadDefault(sculptApp);
    app::AppState& state = sculptApp.state();
    const Positions original = state.session.mesh().positions;
    app::CaptureFlags uiHasMouse;
    uiHasMouse.mouse = true;
    dragUp(sculptApp, uiHasMouse);
    CHECK(state.session.history().empty());
    CHECK(state.session.mesh().positions == original);
    const double distance = state.camera.distance;
    sculptApp.onScroll({0.0, 2.0}, uiHasMouse);
    CHECK(state.camera.distance == distance);
    sculptApp.onScroll({0.0, 2.0}, {});
    CHECK(state.camera.distance < distance);

    dragUp(sculptApp, {});
    REQUIRE(state.session.history().cursor() == 1);
    app::CaptureFlags uiHasKeyboard;
    uiHasKeyboard.keyboard = true;
    sculptApp.onKey(ctrlKey(app::Key::Z), uiHasKeyboard);
    CHECK(state.session.history().cursor() == 1);
}

TEST_CASE("window: orbit, pan and a minimised (0 x 0) framebuffer keep the camera finite", "[gl]") {
    app::SculptApp sculptApp;
    loadDefault(sculptApp);
    app::AppState& state = sculptApp.state();
    const float yaw = state.camera.yawDeg;
    app::Modifiers alt;
    alt.alt = true;
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Press, 100, 100, alt}, {});
    sculptApp.onMouseMove({140, 120, alt}, {});
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Release, 140, 120, alt}, {});
    CHECK(state.camera.yawDeg != yaw);
    CHECK(state.session.history().empty());
    const glm::dvec3 target = state.camera.target;
    app::Modifiers shift;
    shift.shift = true;
    sculptApp.onMouseButton({app::MouseButton::Middle, app::ButtonAction::Press, 100, 100, shift}, {});
    sculptApp.onMouseMove({130, 100, shift}, {});
    sculptApp.onMouseButton({app::MouseButton::Middle, app::ButtonAction::Release, 130, 100, shift}, {});
    CHECK(state.camera.target != target);

    sculptApp.onFramebufferSize({0, 0});
    CHECK(app::framebufferAspect(state) == 1.0f);
    sculptApp.onKey({app::Key::F, app::KeyAction::Press, {}}, {});
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Press, 0, 0, {}}, {});
    sculptApp.onMouseMove({0, -10, {}}, {});
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Release, 0, -10, {}}, {});
    sculptApp.onScroll({0.0, -3.0}, {});
    CHECK(std::isfinite(state.camera.distance));
    CHECK(std::isfinite(state.camera.target.x));
    CHECK(state.session.history().empty());
    CHECK(sculptApp.renderFrame(0, 0).ok);  // draws nothing, touches no GL
}

TEST_CASE("window: full frames with the UI render offscreen, drag updates are sparse", "[gl]") {
    app::SculptApp sculptApp;
    loadDefault(sculptApp);
    test::OffscreenWindow window;
    if (const Status opened = window.open(sculptApp, kWidth, kHeight, 4); !opened) {
        WARN("EGL unavailable, UI frames not tested: " << opened.message);
        return;
    }
    auto frame = [&](render::Rgba8Image* image) {
        const Status drawn = window.frame(image);
        INFO(drawn.message);
        REQUIRE(drawn.ok);
    };
    render::Rgba8Image image;
    frame(nullptr);  // the first frame builds the font atlas
    frame(&image);
    const int vertexCount = static_cast<int>(sculptApp.state().session.mesh().positions.rows());
    CHECK(sculptApp.renderer().vertexCount() == vertexCount);

    // Drag with a frame after every move, on a 16^3 lattice where a drag is local: each move uploads only
    // the vertices it moved (plus their one-ring for the normals), not the whole buffer.
    core::LatticeSettings fine;
    fine.resolution = {16, 16, 16};
    const Positions positions = sculptApp.state().session.mesh().positions;
    const Triangles triangles = sculptApp.state().session.mesh().triangles;
    REQUIRE(app::setMesh(sculptApp.state(), positions, triangles, "default.obj", fine).ok);
    frame(nullptr);
    const double cx = 0.5 * kWidth, cy = 0.5 * kHeight;
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Press, cx, cy, {}}, {});
    REQUIRE(sculptApp.state().drag.active);
    for (int m = 1; m <= 6; ++m) {
        sculptApp.onMouseMove({cx, cy - 10.0 * m, {}}, {});
        frame(nullptr);
        const render::UploadStats upload = sculptApp.renderer().lastUpload();
        const core::Session& session = sculptApp.state().session;
        INFO("move " << m << ": the session moved " << session.lastMoved().vertices.size() << " vertices (all: "
             << session.lastMoved().all << "), " << upload.verticesUploaded << " uploaded in " << upload.ranges << " ranges");
        CHECK(upload.verticesUploaded > 0);
        if (!session.lastMoved().all) {
            CHECK_FALSE(upload.fullUpload);
            CHECK(upload.verticesUploaded < vertexCount / 4);
        }
    }
    CHECK(sculptApp.renderer().positions().isApprox(sculptApp.state().session.mesh().positions));
    render::Rgba8Image dragging;
    frame(&dragging);  // with the source (red) and target (blue) handles
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Release, cx, cy - 60.0, {}}, {});
    app::Overlays overlays;
    overlays.wireframe = true;
    overlays.jacobian = true;
    app::setOverlays(sculptApp.state(), overlays);
    render::Rgba8Image after;
    frame(nullptr);
    frame(&after);

    const std::string dir = sculpt::test::glTestOutputDir();
    CHECK(io::writePng(dir + "/window_frame.png", image.width, image.height, image.pixels.data()).ok);
    CHECK(io::writePng(dir + "/window_frame_dragging.png", dragging.width, dragging.height, dragging.pixels.data()).ok);
    CHECK(io::writePng(dir + "/window_frame_after.png", after.width, after.height, after.pixels.data()).ok);
    WARN("window frames written to " << dir << "/window_frame*.png");

    // The sidebar (top-left) is drawn over the background: its pixels are the panel colour, not the gradient.
    auto pixel = [](const render::Rgba8Image& im, int x, int y) {
        const size_t i = 4 * (static_cast<size_t>(y) * im.width + x);
        return std::array<int, 3>{im.pixels[i], im.pixels[i + 1], im.pixels[i + 2]};
    };
    const auto panel = pixel(image, 40, 200);
    CHECK(panel[0] < 50);  // panel background ~ (28, 31, 36); the gradient there is ~ (80, 85, 93)
    // The status line at the bottom spans the width.
    const auto status = pixel(image, kWidth - 20, kHeight - 5);
    CHECK(status[2] < 50);
    // The mesh covers the centre (not the background's grey-blue).
    const auto centre = pixel(image, kWidth / 2 + 100, kHeight / 2);
    const auto background = pixel(image, kWidth - 5, 5);
    CHECK(std::abs(centre[0] - background[0]) + std::abs(centre[1] - background[1]) +
              std::abs(centre[2] - background[2]) > 30);

    CHECK(sculptApp.renderFrame(0, 0).ok);
}

// A new user saw "Frame rate 0.7 fps" on an idle window: the window draws on change, so the gap before a frame
// can be seconds of sleep. The rate is of frames that follow each other; after a gap the panel says idle.
TEST_CASE("window: the frame rate counts frames drawn one after another, and a frame after sleeping is idle", "[gl]") {
    app::SculptApp sculptApp;
    test::OffscreenWindow window;
    if (!test::openWindowWithDefaultMesh(window, sculptApp, kWidth, kHeight)) return;
    ImGuiIO& io = ImGui::GetIO();
    const app::FrameStats& stats = sculptApp.state().stats;
    std::mt19937 random(5);
    for (int trial = 0; trial < 5; ++trial) {
        const float interval = std::uniform_real_distribution<float>(0.004f, 0.2f)(random);
        io.DeltaTime = 1.5f + static_cast<float>(trial);  // seconds asleep before this frame
        REQUIRE(window.frame().ok);
        CHECK(stats.afterIdle);
        io.DeltaTime = interval;
        for (int f = 0; f < 80; ++f) REQUIRE(window.frame().ok);
        CHECK(!stats.afterIdle);
        CHECK(stats.frameMs == Approx(1000.0 * interval).epsilon(0.01));  // the sleep is not in the average
    }
    io.DeltaTime = 1.0f / 60.0f;
}

TEST_CASE("window: the status line names every engine command in words, and a command that moves no vertex says so", "[gl]") {
    app::SculptApp sculptApp;
    loadDefault(sculptApp);
    app::AppState& state = sculptApp.state();
    // Every op of the script table that reports under its own name has words of its own: none is shown as the
    // script's snake_case name.
    for (const io::ScriptOpInfo& info : io::scriptOps()) {
        const std::string words = app::commandWords(info.name);
        INFO(info.name << " -> " << words);
        if (info.kind == io::ScriptOp::Kind::BeginGroup || info.kind == io::ScriptOp::Kind::EndGroup ||
            info.kind == io::ScriptOp::Kind::Group || info.kind == io::ScriptOp::Kind::SetPins ||
            info.kind == io::ScriptOp::Kind::SetRefinement || info.kind == io::ScriptOp::Kind::Screenshot)
            continue;  // settings and groups: the window reports these with words of its own
        CHECK(words != info.name);
        CHECK(words.find('_') == std::string::npos);
    }
    core::OpReport report;
    report.op = "setup_lattice";
    report.status = core::OpStatus::Applied;
    report.verticesMoved = 0;
    app::reportOperation(state, report, Status::success());
    CHECK(state.status == "Lattice set-up: done, no vertex moved.");
    CHECK_FALSE(state.statusIsError);
    report.op = "redo";
    report.verticesMoved = 1;
    app::reportOperation(state, report, Status::success());
    CHECK(state.status == "Redo: 1 vertex moved.");
    // A stroke's move past where it stopped, which left the surface where it was: held, not "done".
    report.op = "drag";
    report.verticesMoved = 0;
    report.fractionApplied = 0.868;
    report.reason = "Stopped at 86.8% of the pull, the last injective point: beyond it the mesh would fold over itself near (1, 2, 3).";
    app::reportOperation(state, report, Status::success(), "This move");
    CHECK(state.status == "This move: held where the stroke stopped, no vertex moved. " + report.reason);
    report.fractionApplied = 1.0;
    report.reason.clear();
    report.op = "freeze";
    app::reportOperation(state, report, Status::error("lattice 3 does not exist"));
    CHECK(state.status == "Freezing the lattice failed: lattice 3 does not exist");
    CHECK(state.statusIsError);
    CHECK(app::commandWords("no_such_command") == "no_such_command");
}

// The Statistics panel's "Solve" is the last command's time on this mesh: opening another mesh clears it (a trial
// saw the camel's 7.39 ms still shown after the armadillo opened).
TEST_CASE("window: opening another mesh clears the last command's solve time", "[gl]") {
    app::SculptApp sculptApp;
    loadDefault(sculptApp);
    app::AppState& state = sculptApp.state();
    dragUp(sculptApp, {});
    REQUIRE(state.hasReport);
    CHECK(state.stats.solveMs > 0.0);
    REQUIRE(sculptApp.loadMesh(std::string(SCULPT_SOURCE_DIR) + "/assets/default.obj").ok);
    CHECK_FALSE(state.hasReport);
    CHECK(state.stats.solveMs == 0.0);
}
