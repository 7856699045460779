#include "app/window/glfw_main.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <ctime>
#include <fstream>
#include <cstdlib>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_internal.h>

#include "app/cli_options.h"
#include "app/frame_pacer.h"
#include "app/headless.h"
#include "app/window/key_event_queue.h"
#include "app/window/sculpt_app.h"
#include "app/window/ui_style.h"
#include "io/png_image.h"
#include "render/framebuffer_readback.h"
#include "render/gl_functions.h"
#include "render/render_target.h"

namespace sculpt::app {
namespace {

constexpr int kExitNoDisplay = 2;

// Everything the GLFW callbacks need, reached through glfwGetWindowUserPointer.
struct WindowContext {
    SculptApp* app = nullptr;
    GLFWwindow* window = nullptr;
    KeyEventQueue keys;  // key events on their way to ImGui's GLFW callback, one state change per key and frame
    FramePacer pacer;    // when to draw: after input, while something runs; otherwise the loop sleeps
};

// Every event the window gets may change what is drawn: the next frames are drawn (frame_pacer.h).
void noteActivity(GLFWwindow* window) { static_cast<WindowContext*>(glfwGetWindowUserPointer(window))->pacer.noteActivity(); }

SculptApp& appOf(GLFWwindow* window) { return *static_cast<WindowContext*>(glfwGetWindowUserPointer(window))->app; }

CaptureFlags captureFlags() { return SculptApp::uiCapture(); }

Modifiers modifiersOf(int mods) {
    return Modifiers{(mods & GLFW_MOD_SHIFT) != 0, (mods & GLFW_MOD_CONTROL) != 0, (mods & GLFW_MOD_ALT) != 0,
                     (mods & GLFW_MOD_SUPER) != 0};
}

Modifiers currentModifiers(GLFWwindow* window) {
    auto down = [window](int a, int b) {
        return glfwGetKey(window, a) == GLFW_PRESS || glfwGetKey(window, b) == GLFW_PRESS;
    };
    return Modifiers{down(GLFW_KEY_LEFT_SHIFT, GLFW_KEY_RIGHT_SHIFT), down(GLFW_KEY_LEFT_CONTROL, GLFW_KEY_RIGHT_CONTROL),
                     down(GLFW_KEY_LEFT_ALT, GLFW_KEY_RIGHT_ALT), down(GLFW_KEY_LEFT_SUPER, GLFW_KEY_RIGHT_SUPER)};
}

// Window coordinates -> framebuffer pixels (they differ on HiDPI screens).
void toFramebuffer(GLFWwindow* window, double& x, double& y) {
    int ww = 0, wh = 0, fw = 0, fh = 0;
    glfwGetWindowSize(window, &ww, &wh);
    glfwGetFramebufferSize(window, &fw, &fh);
    if (ww > 0 && wh > 0) {
        x *= static_cast<double>(fw) / ww;
        y *= static_cast<double>(fh) / wh;
    }
}

void onGlfwError(int code, const char* description) {
    std::cerr << "sculpt: GLFW error " << code << ": " << description << "\n";
}

// note: these are installed before ImGui_ImplGlfw_InitForOpenGL(window, true), which chains to them. ImGui's
// backend (1.86) only notes the events; its WantCapture flags are computed at the next NewFrame, for where the
// cursor was at the last one. So mouse events ask SculptApp::uiCaptureAt for their own point: a press whose
// move (off the panel whose button was just clicked, onto the mesh) came in the same frame is still a press.
// Mouse moves are coalesced: of the moves one glfwPollEvents delivers, only the last reaches the app, before
// the next button, scroll or key event and after the poll. A stroke update rebuilds the stroke from where it
// began to the cursor, so the moves in between change nothing; processed one by one, a stroke that stops
// short (each update bisects the pull) fell seconds behind the mouse on a 26k-vertex scan.
struct PendingMove {
    bool pending = false;
    MouseMoveEvent event;
    CaptureFlags capture;
};
PendingMove gPendingMove;

void flushMove(GLFWwindow* window) {
    if (!gPendingMove.pending) return;
    gPendingMove.pending = false;
    appOf(window).onMouseMove(gPendingMove.event, gPendingMove.capture);
}

void onMouseButton(GLFWwindow* window, int button, int action, int mods) {
    noteActivity(window);
    flushMove(window);
    MouseButtonEvent event;
    if (button == GLFW_MOUSE_BUTTON_LEFT) event.button = MouseButton::Left;
    else if (button == GLFW_MOUSE_BUTTON_RIGHT) event.button = MouseButton::Right;
    else if (button == GLFW_MOUSE_BUTTON_MIDDLE) event.button = MouseButton::Middle;
    else return;
    event.action = action == GLFW_PRESS ? ButtonAction::Press : ButtonAction::Release;
    glfwGetCursorPos(window, &event.x, &event.y);
    const CaptureFlags capture = SculptApp::uiCaptureAt(event.x, event.y);  // window pixels, as ImGui's
    toFramebuffer(window, event.x, event.y);
    event.modifiers = modifiersOf(mods);
    appOf(window).onMouseButton(event, capture);
}

void onCursorPos(GLFWwindow* window, double x, double y) {
    noteActivity(window);
    MouseMoveEvent event;
    event.x = x;
    event.y = y;
    toFramebuffer(window, event.x, event.y);
    event.modifiers = currentModifiers(window);
    gPendingMove = {true, event, captureFlags()};
}

void onScroll(GLFWwindow* window, double dx, double dy) {
    noteActivity(window);
    flushMove(window);
    double x = 0.0, y = 0.0;
    glfwGetCursorPos(window, &x, &y);
    appOf(window).onScroll({dx, dy}, SculptApp::uiCaptureAt(x, y));
}

void onKey(GLFWwindow* window, int key, int /*scancode*/, int action, int mods) {
    KeyEvent event;
    switch (key) {
        case GLFW_KEY_A: event.key = Key::A; break;
        case GLFW_KEY_F: event.key = Key::F; break;
        case GLFW_KEY_G: event.key = Key::G; break;
        case GLFW_KEY_L: event.key = Key::L; break;
        case GLFW_KEY_N: event.key = Key::N; break;
        case GLFW_KEY_O: event.key = Key::O; break;
        case GLFW_KEY_P: event.key = Key::P; break;
        case GLFW_KEY_Q: event.key = Key::Q; break;
        case GLFW_KEY_R: event.key = Key::R; break;
        case GLFW_KEY_S: event.key = Key::S; break;
        case GLFW_KEY_X: event.key = Key::X; break;
        case GLFW_KEY_Y: event.key = Key::Y; break;
        case GLFW_KEY_Z: event.key = Key::Z; break;
        case GLFW_KEY_TAB: event.key = Key::Tab; break;
        case GLFW_KEY_DELETE: event.key = Key::Delete; break;
        case GLFW_KEY_BACKSPACE: event.key = Key::Backspace; break;
        case GLFW_KEY_ENTER: case GLFW_KEY_KP_ENTER: event.key = Key::Enter; break;
        case GLFW_KEY_ESCAPE: event.key = Key::Escape; break;
        case GLFW_KEY_HOME: event.key = Key::Home; break;
        case GLFW_KEY_PERIOD: event.key = Key::Period; break;
        case GLFW_KEY_MINUS: event.key = Key::Minus; break;
        case GLFW_KEY_KP_DECIMAL: event.key = Key::NumpadDecimal; break;
        case GLFW_KEY_KP_SUBTRACT: event.key = Key::NumpadMinus; break;
        default:
            if (key >= GLFW_KEY_0 && key <= GLFW_KEY_9)
                event.key = static_cast<Key>(static_cast<int>(Key::Digit0) + (key - GLFW_KEY_0));
            else if (key >= GLFW_KEY_KP_0 && key <= GLFW_KEY_KP_9)
                event.key = static_cast<Key>(static_cast<int>(Key::Numpad0) + (key - GLFW_KEY_KP_0));
            else
                return;
    }
    event.action = action == GLFW_PRESS ? KeyAction::Press
                 : action == GLFW_REPEAT ? KeyAction::Repeat : KeyAction::Release;
    event.modifiers = modifiersOf(mods);
    flushMove(window);
    appOf(window).onKey(event, captureFlags());
}

// Installed over ImGui's own key callback: the event reaches it (and through it onKey above) via the queue.
void onKeyQueued(GLFWwindow* window, int key, int scancode, int action, int mods) {
    noteActivity(window);
    auto* context = static_cast<WindowContext*>(glfwGetWindowUserPointer(window));
    context->keys.push(key, action != GLFW_REPEAT, [=] { ImGui_ImplGlfw_KeyCallback(window, key, scancode, action, mods); });
}

void onFramebufferSize(GLFWwindow* window, int width, int height) {
    noteActivity(window);
    appOf(window).onFramebufferSize({width, height});
}

// The close button never closes by itself: the app asks about unsaved changes and the loop ends only once
// it approves (SculptApp::quitApproved).
void onWindowClose(GLFWwindow* window) {
    noteActivity(window);
    glfwSetWindowShouldClose(window, GLFW_FALSE);
    appOf(window).requestQuit();
}

void onDrop(GLFWwindow* window, int count, const char** paths) {
    noteActivity(window);
    flushMove(window);
    appOf(window).onDropFiles(std::vector<std::string>(paths, paths + count));
}

// The window was uncovered or must be redrawn for another reason the system knows; typed characters (ImGui's
// own callback reads them) and the cursor entering or leaving, focus: each may change what is drawn.
void onRefresh(GLFWwindow* window) { noteActivity(window); }
void onChar(GLFWwindow* window, unsigned int codepoint) {
    noteActivity(window);
    ImGui_ImplGlfw_CharCallback(window, codepoint);
}
void onCursorEnter(GLFWwindow* window, int entered) {
    noteActivity(window);
    ImGui_ImplGlfw_CursorEnterCallback(window, entered);
}
void onFocus(GLFWwindow* window, int focused) {
    noteActivity(window);
    ImGui_ImplGlfw_WindowFocusCallback(window, focused);
}

// CPU time of the whole process (every thread: the worker, llvmpipe's), seconds.
double processCpuSeconds() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

int envInt(const char* name, int fallback) {
    const char* value = std::getenv(name);
    return value && *value ? std::atoi(value) : fallback;
}

Status saveBackBuffer(const render::GlFunctions& gl, int width, int height, const std::string& path) {
    render::Rgba8Image image;
    if (Status s = render::readBoundFramebuffer(gl, width, height, image); !s) return s;
    return io::writePng(path, image.width, image.height, image.pixels.data());
}

// Creates the window and makes its context current. samples < 0: 4x MSAA on a GPU, none on a software
// rasterizer. note: llvmpipe pays for every sample in full (a 20k-triangle frame at 1280x800 took ~90 ms with
// 4x MSAA under Xvfb), so there the window is recreated without it; SCULPT_WINDOW_MSAA=N overrides.
GLFWwindow* createWindow(int samples) {
    glfwWindowHint(GLFW_SAMPLES, samples < 0 ? 4 : samples);
    GLFWwindow* window = glfwCreateWindow(1280, 800, "DMFFD Sculpt", nullptr, nullptr);
    if (!window) return nullptr;
    glfwMakeContextCurrent(window);
    if (samples >= 0) return window;
    using GetString = const unsigned char* (*)(unsigned int);
    const auto getString = reinterpret_cast<GetString>(glfwGetProcAddress("glGetString"));
    const unsigned char* renderer = getString ? getString(0x1F01 /* GL_RENDERER */) : nullptr;
    const std::string name = renderer ? reinterpret_cast<const char*>(renderer) : "";
    if (name.find("llvmpipe") == std::string::npos && name.find("softpipe") == std::string::npos) return window;
    glfwDestroyWindow(window);
    return createWindow(0);
}

}  // namespace

int runWindow(const std::string& meshPath) {
    SculptApp app;
    // A file that cannot be opened at all is a command-line error, said before any window appears. Reading
    // and checking it (seconds for a 1M-vertex mesh) happens once the window is up, on the worker thread of
    // File > Open with its progress popup; a mesh that turns out bad is then reported in the window.
    if (std::ifstream probe(meshPath, std::ios::binary); !probe) {
        std::cerr << "sculpt: cannot open " << meshPath << ": " << std::strerror(errno) << "\n";
        return kExitBadInput;
    }
    glfwSetErrorCallback(onGlfwError);
    if (!glfwInit()) {
        std::cerr << "sculpt: cannot open a window (no display?). To run without one use\n"
                     "  sculpt --headless [--input MESH] --script OPS.json --output OUT [--screenshot OUT.png]\n"
                     "  (meshes: .obj .ply .stl .gltf .glb .off, the format from the extension)\n"
                     "or start the window under a virtual display: xvfb-run -a sculpt [MESH]\n";
        return kExitNoDisplay;
    }
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_SCALE_TO_MONITOR, GLFW_TRUE);
    GLFWwindow* window = createWindow(envInt("SCULPT_WINDOW_MSAA", -1));
    if (!window) {
        std::cerr << "sculpt: cannot create an OpenGL 3.3 core window; use --headless without one.\n";
        glfwTerminate();
        return kExitNoDisplay;
    }
    glfwSwapInterval(1);  // vsync

    WindowContext context;
    context.app = &app;
    context.window = window;
    glfwSetWindowUserPointer(window, &context);
    glfwSetMouseButtonCallback(window, onMouseButton);
    glfwSetCursorPosCallback(window, onCursorPos);
    glfwSetScrollCallback(window, onScroll);
    glfwSetKeyCallback(window, onKey);
    glfwSetFramebufferSizeCallback(window, onFramebufferSize);
    glfwSetWindowCloseCallback(window, onWindowClose);
    glfwSetDropCallback(window, onDrop);

    float scaleX = 1.0f, scaleY = 1.0f;
    glfwGetWindowContentScale(window, &scaleX, &scaleY);
    createUiContext(scaleX);
    ImGui_ImplGlfw_InitForOpenGL(window, true);  // chains its callbacks to ours (onKey included)
    glfwSetKeyCallback(window, onKeyQueued);
    // Installed over ImGui's own (which they call): they wake the frame pacer too.
    glfwSetCharCallback(window, onChar);
    glfwSetCursorEnterCallback(window, onCursorEnter);
    glfwSetWindowFocusCallback(window, onFocus);
    glfwSetWindowRefreshCallback(window, onRefresh);

    int exitCode = kExitOk;
    if (Status s = app.initGraphics(reinterpret_cast<render::GlGetProc>(glfwGetProcAddress)); !s) {
        std::cerr << "sculpt: " << s.message << "\n";
        exitCode = kExitInternal;
    }
    app.renderer().setPixelScale(scaleX);
    render::GlFunctions gl;
    const bool haveGl = exitCode == kExitOk &&
                        render::loadGlFunctions(reinterpret_cast<render::GlGetProc>(glfwGetProcAddress), gl).ok;

    int width = 0, height = 0;
    glfwGetFramebufferSize(window, &width, &height);
    app.onFramebufferSize({width, height});

    const int maxFrames = envInt("SCULPT_WINDOW_FRAMES", 0);
    // An engine step (a drag's move, a transform, undo) that takes longer than a frame at 30 Hz goes on drawing
    // the last applied frame with its progress (engine_job.h). SCULPT_ENGINE_WAIT_MS sets the wait; a scripted
    // run (SCULPT_WINDOW_FRAMES) waits for every step unless it is set, so its frames are the same on any machine.
    const int waitMs = envInt("SCULPT_ENGINE_WAIT_MS", maxFrames > 0 ? -1 : 33);
    app.setEngineWait(waitMs < 0 ? std::numeric_limits<double>::infinity() : waitMs / 1000.0);
    app.setEngineWake([] { glfwPostEmptyEvent(); });
    // The mesh (or session) given on the command line opens like File > Open. A scripted run (the test
    // hooks below) waits for it, so its frames and its drag see the mesh.
    if (app.files().startOpen(app.state(), meshPath) && maxFrames > 0) app.files().finishJob(app.state());
    const char* screenshot = std::getenv("SCULPT_WINDOW_SCREENSHOT");
    const bool autoDrag = envInt("SCULPT_WINDOW_AUTODRAG", 0) != 0;
    int frame = 0, dragFrames = 0, busyFrames = 0;
    double dragSeconds = 0.0, longestBusyGap = 0.0;
    auto last = std::chrono::steady_clock::now();
    std::string title;
    // SCULPT_WINDOW_IDLE_SECONDS=N: once the mesh is open and its first frames drawn, measure N seconds with no
    // input (the process's CPU time, the frames drawn), print them and close (the benchmark's window_idle).
    const double idleSeconds = envInt("SCULPT_WINDOW_IDLE_SECONDS", 0);
    bool idleStarted = false;
    double idleCpuStart = 0.0;
    long idleFramesStart = 0;
    std::chrono::steady_clock::time_point idleStart;
    FramePacer& pacer = context.pacer;
    bool wasBusy = false;
    int popupsBefore = 0;
    ImGuiID topPopupBefore = 0;
    while (exitCode == kExitOk && !glfwWindowShouldClose(window) && !app.quitApproved()) {
        // The window draws when something changes (frame_pacer.h). note: while a load or save runs on the
        // worker thread the scene does not change; at most ~15 frames a second (its progress popup) leave the
        // cores to the worker (llvmpipe renders on the CPU: at full rate a 1M-vertex load took 4x as long).
        FrameNeeds needs = app.frameNeeds();
        needs.everyFrame = needs.everyFrame || maxFrames > 0 || autoDrag;
        double deadline = 0.0;
        if (idleSeconds > 0.0 && !idleStarted && !app.files().busy() && !pacer.settling()) {
            idleStarted = true;
            idleStart = std::chrono::steady_clock::now();
            idleCpuStart = processCpuSeconds();
            idleFramesStart = pacer.framesDrawn();
        }
        if (idleStarted) {
            const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - idleStart).count();
            if (elapsed >= idleSeconds) {
                std::printf("sculpt: idle %.1f s: %.2f%% of one core, %ld frames drawn\n", elapsed,
                            100.0 * (processCpuSeconds() - idleCpuStart) / elapsed, pacer.framesDrawn() - idleFramesStart);
                std::fflush(stdout);
                break;
            }
            deadline = idleSeconds - elapsed;
        }
        const FramePacer::Plan plan = pacer.plan(needs, deadline);
        if (plan.wait == FramePacer::Wait::Poll) glfwPollEvents();
        else if (plan.wait == FramePacer::Wait::Timeout) glfwWaitEventsTimeout(plan.seconds);
        else glfwWaitEvents();
        // Woken only for the measurement's end, with nothing new to draw: no frame.
        if (plan.wait == FramePacer::Wait::Timeout && needs.withinSeconds <= 0.0 && !pacer.settling()) continue;
        flushMove(window);
        if (!app.engineBusy() && app.windowTitle() != title) {  // "name*" while there are unsaved changes
            title = app.windowTitle();
            glfwSetWindowTitle(window, title.c_str());
        }
        glfwGetFramebufferSize(window, &width, &height);
        if (width <= 0 || height <= 0) {  // minimised: wait instead of spinning
            glfwWaitEventsTimeout(0.1);
            continue;
        }
        if (autoDrag && maxFrames > 3) {
            // Press on the centre at frame 1, move up then back one event per frame, release one frame before
            // the last: the panels grow on release and Dear ImGui's auto-resize settles a frame later, so the
            // screenshot of the last frame shows them whole.
            const double cx = 0.5 * width, cy = 0.5 * height;
            const int span = maxFrames - 3;
            if (frame == 1) app.onMouseButton({MouseButton::Left, ButtonAction::Press, cx, cy, {}}, {});
            else if (frame > 1 && frame < maxFrames - 2) {
                const double phase = static_cast<double>(frame - 1) / span;
                app.onMouseMove({cx, cy - 0.25 * height * std::sin(3.14159265358979 * phase), {}}, {});
            } else if (frame == maxFrames - 2) {
                app.onMouseButton({MouseButton::Left, ButtonAction::Release, cx, cy, {}}, {});
            }
        }
        ImGui_ImplGlfw_NewFrame();
        if (Status s = app.renderFrame(width, height); !s) std::cerr << "sculpt: draw: " << s.message << "\n";
        pacer.frameDrawn();
        // A job that ended or a popup that opened or closed in this frame (a prompt answered, a progress popup
        // done) changed what the next frames show without an event: they are drawn too.
        const bool busyNow = app.files().busy() || app.engineBusy();
        // One prompt can give way to another in the same frame ("Don't save" closes the prompt and opens the file
        // dialog: a new user saw the empty prompt stay for seconds), so the top popup counts, not only how many;
        // and a modal's dimmed background fades in over frames of its own.
        const ImGuiContext* imgui = ImGui::GetCurrentContext();
        const int popupsNow = imgui ? imgui->OpenPopupStack.Size : 0;
        const ImGuiID topPopupNow = popupsNow > 0 ? imgui->OpenPopupStack.back().PopupId : 0;
        const bool fading = imgui && imgui->DimBgRatio > 0.0f && imgui->DimBgRatio < 1.0f;
        if (busyNow != wasBusy || popupsNow != popupsBefore || topPopupNow != topPopupBefore || fading) pacer.noteActivity();
        wasBusy = busyNow;
        popupsBefore = popupsNow;
        topPopupBefore = topPopupNow;
        // Keys held back for this frame reach ImGui and the app now: the frames after must see them.
        if (!context.keys.empty()) pacer.noteActivity();
        context.keys.frameDone();
        ++frame;
        const bool lastFrame = maxFrames > 0 && frame >= maxFrames;
        if (lastFrame && screenshot && haveGl) {
            if (Status s = saveBackBuffer(gl, width, height, screenshot); !s)
                std::cerr << "sculpt: screenshot: " << s.message << "\n";
            else
                std::cout << "sculpt: wrote " << screenshot << "\n";
        }
        glfwSwapBuffers(window);
        const auto now = std::chrono::steady_clock::now();
        const double gap = std::chrono::duration<double>(now - last).count();
        if (app.engineBusy()) {  // a frame drawn while the engine worked (the state is the worker's)
            ++busyFrames;
            longestBusyGap = std::max(longestBusyGap, gap);
        } else if (app.state().drag.active) {
            dragSeconds += gap;
            ++dragFrames;
        }
        last = now;
        if (lastFrame) glfwSetWindowShouldClose(window, GLFW_TRUE);
    }
    app.waitForEngine();
    if (autoDrag && busyFrames > 0)
        std::printf("sculpt: autodrag %d frames drawn while the engine worked, longest gap between them %.1f ms\n",
                    busyFrames, 1000.0 * longestBusyGap);
    if (autoDrag && dragFrames > 0)
        std::printf("sculpt: autodrag %d frames while dragging, %.1f fps (%.1f ms per frame), %d vertices, %d triangles\n",
                    dragFrames, dragFrames / dragSeconds, 1000.0 * dragSeconds / dragFrames,
                    static_cast<int>(app.state().session.mesh().positions.rows()),
                    static_cast<int>(app.state().session.mesh().triangles.rows()));

    app.releaseGraphics();
    ImGui_ImplGlfw_Shutdown();
    destroyUiContext();
    glfwDestroyWindow(window);
    glfwTerminate();
    return exitCode;
}

}  // namespace sculpt::app
