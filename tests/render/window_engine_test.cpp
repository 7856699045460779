// Engine steps off the main thread (engine_job.h): while a drag's move, a transform or an undo is certified on
// the worker, the window draws the last applied frame with the step's progress, and input waits its turn.
// Checked against an independent run: the same input given to a second app that runs every step on the calling
// thread (the moves the busy window coalesced given once) must end in bitwise the same mesh, cage and history.
// The worker is held at the start of chosen steps by a gate (setEngineStepHook), so what the window draws
// meanwhile is looked at deterministically, on any machine speed.
#include <catch2/catch.hpp>

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "app/window/picking.h"
#include "app/window/sculpt_app.h"
#include "app/window/app_state.h"
#include "io/png_image.h"
#include "offscreen_window.h"
#include "render/render_target.h"
#include "window_test_support.h"

using namespace sculpt;

namespace {

constexpr int kWidth = 960, kHeight = 600;

// Holds the worker at the start of each step while closed; counts the steps that reached it. allow(n) lets n
// more steps through while closed.
class Gate {
public:
    void close() {
        const std::lock_guard<std::mutex> lock(mutex_);
        open_ = false;
        permits_ = 0;
    }
    void open() {
        {
            const std::lock_guard<std::mutex> lock(mutex_);
            open_ = true;
        }
        changed_.notify_all();
    }
    void allow(int steps) {
        {
            const std::lock_guard<std::mutex> lock(mutex_);
            permits_ += steps;
        }
        changed_.notify_all();
    }
    void pass() {  // on the worker
        std::unique_lock<std::mutex> lock(mutex_);
        ++arrived_;
        changed_.notify_all();
        changed_.wait(lock, [this] { return open_ || permits_ > 0; });
        if (!open_) --permits_;
    }
    // Waits (at most 60 s) until `count` steps have reached the gate in all.
    bool waitArrived(int count) {
        std::unique_lock<std::mutex> lock(mutex_);
        return changed_.wait_for(lock, std::chrono::seconds(60), [&] { return arrived_ >= count; });
    }
    int arrived() {
        const std::lock_guard<std::mutex> lock(mutex_);
        return arrived_;
    }

private:
    std::mutex mutex_;
    std::condition_variable changed_;
    bool open_ = true;
    int permits_ = 0;
    int arrived_ = 0;
};

// Pixels that differ between two frames outside the box (x0, y0, x1, y1), grown by 2 px for the border's
// anti-aliasing.
int differingOutside(const render::Rgba8Image& a, const render::Rgba8Image& b, ImVec4 box) {
    int count = 0;
    const bool haveBox = box.z > box.x;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x) {
            if (haveBox && x >= box.x - 2 && x <= box.z + 2 && y >= box.y - 2 && y <= box.w + 2) continue;
            const size_t i = 4 * (static_cast<size_t>(y) * static_cast<size_t>(a.width) + static_cast<size_t>(x));
            for (int c = 0; c < 3; ++c) count += a.pixels[i + c] != b.pixels[i + c] ? 1 : 0;
        }
    return count;
}

int differingInside(const render::Rgba8Image& a, const render::Rgba8Image& b, ImVec4 box) {
    int count = 0;
    for (int y = static_cast<int>(box.y); y < static_cast<int>(box.w); ++y)
        for (int x = static_cast<int>(box.x); x < static_cast<int>(box.z); ++x) {
            const size_t i = 4 * (static_cast<size_t>(y) * static_cast<size_t>(a.width) + static_cast<size_t>(x));
            count += a.pixels[i] != b.pixels[i] ? 1 : 0;
        }
    return count;
}

// Frames until the held input and the steps it starts are done (at most 60 s).
void drawUntilIdle(test::OffscreenWindow& window, app::SculptApp& sculptApp) {
    const auto start = std::chrono::steady_clock::now();
    while (sculptApp.engineBusy() || sculptApp.heldInputCount() > 0) {
        REQUIRE(window.frame().ok);
        REQUIRE(std::chrono::steady_clock::now() - start < std::chrono::seconds(60));
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    REQUIRE(window.frame().ok);
}

void requireSameResult(const app::SculptApp& busy, const app::SculptApp& reference) {
    const core::Session& a = busy.state().session;
    const core::Session& b = reference.state().session;
    REQUIRE(a.mesh().positions.rows() == b.mesh().positions.rows());
    CHECK(a.mesh().positions == b.mesh().positions);  // bitwise: the same steps in the same order
    CHECK(a.cage().cagePoints() == b.cage().cagePoints());
    REQUIRE(a.history().size() == b.history().size());
    for (size_t h = 0; h < a.history().size(); ++h) CHECK(a.history()[h].label == b.history()[h].label);
    CHECK(a.history().cursor() == b.history().cursor());
    CHECK(busy.state().drag.active == reference.state().drag.active);
    CHECK(busy.state().transform.active == reference.state().transform.active);
}

// The default mesh in a window's app and in a reference app; every step of the window's app runs on the worker
// (no wait) and is held at the gate while it is closed. The gate outlives the apps (declared first).
struct HeldWindow {
    Gate gate;
    app::SculptApp sculptApp, reference;
    test::OffscreenWindow window;
    ~HeldWindow() { gate.open(); }  // a test that stopped with the gate closed: its step ends, the window closes
    bool open() {
        if (!test::openWindowWithDefaultMesh(window, sculptApp, kWidth, kHeight)) return false;
        test::loadDefaultMesh(reference, kWidth, kHeight);
        sculptApp.setEngineStepHook([this] { gate.pass(); });
        sculptApp.setEngineWait(0.0);
        return true;
    }
};

app::KeyEvent press(app::Key key, bool control = false, bool shift = false) {
    app::KeyEvent event;
    event.key = key;
    event.modifiers.control = control;
    event.modifiers.shift = shift;
    return event;
}

}  // namespace

TEST_CASE("window engine: while a drag's move is certified on the worker the window draws the last applied frame and its progress, input waits, and the result is the synchronous one", "[gl]") {
    HeldWindow fixture;
    if (!fixture.open()) return;
    app::SculptApp &sculptApp = fixture.sculptApp, &reference = fixture.reference;
    test::OffscreenWindow& window = fixture.window;
    Gate& gate = fixture.gate;
    REQUIRE(window.frame().ok);

    std::mt19937 random(20261205);
    std::uniform_real_distribution<double> offset(-70.0, 70.0), spot(-60.0, 60.0);
    int stepsSeen = 0;
    for (int stroke = 0; stroke < 4; ++stroke) {
        CAPTURE(stroke);
        const double x0 = 0.5 * kWidth + spot(random), y0 = 0.5 * kHeight + spot(random);
        const app::MouseButtonEvent down{app::MouseButton::Left, app::ButtonAction::Press, x0, y0, {}};
        sculptApp.onMouseButton(down, {});
        reference.onMouseButton(down, {});
        REQUIRE(sculptApp.state().drag.active == reference.state().drag.active);
        if (!sculptApp.state().drag.active) continue;  // missed the mesh
        render::Rgba8Image applied, busyFrame, later;
        REQUIRE(window.frame(&applied).ok);  // the last frame drawn from applied state
        const Positions before = sculptApp.state().session.mesh().positions;

        // The first move's step is held at the gate: the window keeps drawing what was applied.
        gate.close();
        const double dx = offset(random), dy = offset(random);
        const app::MouseMoveEvent first{x0 + 0.25 * dx, y0 + 0.25 * dy, {}};
        sculptApp.onMouseMove(first, {});
        REQUIRE(gate.waitArrived(++stepsSeen));
        REQUIRE(sculptApp.engineBusy());
        REQUIRE(window.frame(&busyFrame).ok);
        CHECK(differingOutside(applied, busyFrame, sculptApp.progressBox()) == 0);
        // Input meanwhile is held, in order, the moves coalesced into the last.
        app::MouseMoveEvent last = first;
        for (int m = 2; m <= 6; ++m) {
            last = {x0 + dx * m / 6.0, y0 + dy * m / 6.0, {}};
            sculptApp.onMouseMove(last, {});
        }
        const app::MouseButtonEvent up{app::MouseButton::Left, app::ButtonAction::Release, last.x, last.y, {}};
        sculptApp.onMouseButton(up, {});
        CHECK(sculptApp.heldInputCount() == 2);
        CHECK(sculptApp.state().session.mesh().positions == before);  // the worker waits at the gate: nothing moved yet
        // Past the progress delay the box shows over the same picture, and says what runs.
        std::this_thread::sleep_for(std::chrono::duration<double>(app::SculptApp::kProgressDelaySeconds + 0.05));
        REQUIRE(window.frame(&later).ok);
        const ImVec4 box = sculptApp.progressBox();
        REQUIRE(box.z > box.x);
        CHECK(differingOutside(applied, later, box) == 0);
        CHECK(differingInside(applied, later, box) > 0);
        CHECK(sculptApp.engineProgress().rfind("Certifying the move... ", 0) == 0);
        if (stroke == 0)  // to look at
            io::writePng(std::string(SCULPT_GL_TEST_OUTPUT_DIR) + "/window_engine_busy.png", later.width, later.height, later.pixels.data());

        gate.open();
        drawUntilIdle(window, sculptApp);
        stepsSeen = gate.arrived();
        // The reference gets what the busy window ran: the first move, the last, the release.
        reference.onMouseMove(first, {});
        reference.onMouseMove(last, {});
        reference.onMouseButton(up, {});
        requireSameResult(sculptApp, reference);
        CHECK(sculptApp.state().status == reference.state().status);

        // An undo and a redo typed while the undo is held: both run, in order.
        if (stroke % 2 == 1) {
            gate.close();
            sculptApp.onKey(press(app::Key::Z, true), {});
            REQUIRE(gate.waitArrived(++stepsSeen));
            sculptApp.onKey(press(app::Key::Z, true, true), {});
            CHECK(sculptApp.heldInputCount() == 1);
            gate.open();
            drawUntilIdle(window, sculptApp);
            stepsSeen = gate.arrived();
            reference.onKey(press(app::Key::Z, true), {});
            reference.onKey(press(app::Key::Z, true, true), {});
            requireSameResult(sculptApp, reference);
        }
    }
    REQUIRE(!sculptApp.state().session.history().empty());  // the strokes did something to compare

    // The history panel's Undo (or the Edit menu's) asks during the frame; the step runs after it, on the worker.
    gate.close();
    app::requestHistoryStep(sculptApp.state(), -1);
    render::Rgba8Image asked, held;
    REQUIRE(window.frame(&asked).ok);
    REQUIRE(gate.waitArrived(++stepsSeen));
    CHECK(sculptApp.engineBusy());
    REQUIRE(window.frame(&held).ok);
    CHECK(differingOutside(asked, held, sculptApp.progressBox()) == 0);
    gate.open();
    drawUntilIdle(window, sculptApp);
    reference.onKey(press(app::Key::Z, true), {});
    requireSameResult(sculptApp, reference);
}

TEST_CASE("window engine: a typed rotation held on the worker keeps the applied readout on screen, takes its keys in order and ends as the synchronous one", "[gl]") {
    HeldWindow fixture;
    if (!fixture.open()) return;
    app::SculptApp &sculptApp = fixture.sculptApp, &reference = fixture.reference;
    test::OffscreenWindow& window = fixture.window;
    Gate& gate = fixture.gate;
    for (app::SculptApp* a : {&sculptApp, &reference}) {
        a->onKey(press(app::Key::Tab), {});
        a->onKey(press(app::Key::A), {});
    }
    REQUIRE(window.frame().ok);

    // Random axes and angles (fixed seed): R, the axis, the digits, Enter, with the axis key's step held.
    std::mt19937 random(7);
    std::uniform_int_distribution<int> axis(0, 2), degrees(5, 40);
    for (int trial = 0; trial < 3; ++trial) {
        CAPTURE(trial);
        const app::Key axisKey = axis(random) == 0 ? app::Key::X : axis(random) == 1 ? app::Key::Y : app::Key::Z;
        const std::string digits = std::to_string(degrees(random));
        std::vector<app::KeyEvent> keys{press(app::Key::R), press(axisKey)};
        for (char c : digits) keys.push_back(press(static_cast<app::Key>(static_cast<int>(app::Key::Digit0) + (c - '0'))));
        keys.push_back(press(app::Key::Enter));

        sculptApp.onKey(keys[0], {});  // R starts the transform (no step yet)
        REQUIRE(sculptApp.state().transform.active);
        render::Rgba8Image applied, busyFrame;
        REQUIRE(window.frame(&applied).ok);
        gate.close();
        const int before = gate.arrived();
        sculptApp.onKey(keys[1], {});
        REQUIRE(gate.waitArrived(before + 1));
        for (size_t k = 2; k < keys.size(); ++k) sculptApp.onKey(keys[k], {});
        CHECK(sculptApp.heldInputCount() == keys.size() - 2);
        REQUIRE(window.frame(&busyFrame).ok);
        CHECK(differingOutside(applied, busyFrame, sculptApp.progressBox()) == 0);
        gate.open();
        drawUntilIdle(window, sculptApp);
        for (const app::KeyEvent& k : keys) reference.onKey(k, {});
        requireSameResult(sculptApp, reference);
        CHECK(sculptApp.state().status == reference.state().status);
        CHECK(sculptApp.state().status.rfind("Rotated ", 0) == 0);
    }
}

TEST_CASE("window engine: each step's result is drawn before the input held meanwhile starts the next step", "[gl]") {
    HeldWindow fixture;
    if (!fixture.open()) return;
    app::SculptApp &sculptApp = fixture.sculptApp, &reference = fixture.reference;
    test::OffscreenWindow& window = fixture.window;
    Gate& gate = fixture.gate;
    const double x0 = 0.5 * kWidth, y0 = 0.5 * kHeight;
    const app::MouseButtonEvent down{app::MouseButton::Left, app::ButtonAction::Press, x0, y0, {}};
    sculptApp.onMouseButton(down, {});
    reference.onMouseButton(down, {});
    REQUIRE(sculptApp.state().drag.active);
    render::Rgba8Image before, shown;
    REQUIRE(window.frame(&before).ok);
    // A stroke of moves that each outlast the wait: every move arrives while the step before it runs.
    gate.close();
    int arrived = 0;
    for (int m = 1; m <= 5; ++m) {
        CAPTURE(m);
        const Positions appliedBefore = reference.state().session.mesh().positions;  // moves 1 .. m-1
        const app::MouseMoveEvent move{x0, y0 - 12.0 * m, {}};
        sculptApp.onMouseMove(move, {});
        reference.onMouseMove(move, {});
        if (m == 1) {
            REQUIRE(gate.waitArrived(++arrived));  // the first move's step waits at the gate
            continue;
        }
        CHECK(sculptApp.heldInputCount() == 1);  // this move waits for the step of the one before
        gate.allow(1);  // that step runs to its end; the next waits at the gate again
        // Frames until the held move has started its step: the frame that collected the step before it drew
        // that step's result, and the held move started only after it.
        const auto start = std::chrono::steady_clock::now();
        while (gate.arrived() < arrived + 1) {
            REQUIRE(window.frame(&shown).ok);
            REQUIRE(std::chrono::steady_clock::now() - start < std::chrono::seconds(60));
        }
        ++arrived;
        // The worker waits at the gate before touching anything: the state is that of moves 1 .. m-1, and the
        // frame drawn before this step started shows it (the stroke grew since the frame before).
        CHECK(sculptApp.state().session.mesh().positions == appliedBefore);
        CHECK(differingOutside(before, shown, {0.0f, 0.0f, 0.0f, 0.0f}) > 0);
        before = shown;
    }
    gate.open();
    drawUntilIdle(window, sculptApp);
    const app::MouseButtonEvent up{app::MouseButton::Left, app::ButtonAction::Release, x0, y0 - 60.0, {}};
    sculptApp.onMouseButton(up, {});
    reference.onMouseButton(up, {});
    drawUntilIdle(window, sculptApp);
    requireSameResult(sculptApp, reference);
}
