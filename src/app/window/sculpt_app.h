// SculptApp: the interactive sculpting application without its window. Owns the AppState (session, camera,
// UI state) and the Renderer; turns plain input events (input_events.h) into engine commands and draws a
// frame (scene + Dear ImGui panels) into the bound framebuffer. The GLFW layer (glfw_main.cpp) and the
// tests (tests/render/window_app_test.cpp) drive the very same object.
//
// Mouse: left-press on the mesh picks the surface point under the cursor and starts an interactive drag
// (Session::stroke().beginAt); every move puts the target where the cursor ray meets the plane through the picked
// point facing the camera and calls Session::stroke().update (live); release ends it (one undo step).
// Middle-drag or Alt+left-drag orbits, Shift+middle-drag pans, the wheel zooms. Keys: Home frames the mesh (F too
// in the lattice tool; in the sculpt tool F sets the brush radius),
// Ctrl+Z undoes, Ctrl+Shift+Z / Ctrl+Y redo. Input the UI claims (CaptureFlags) is left alone.
#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <imgui.h>

#include "app/frame_pacer.h"
#include "app/window/app_state.h"
#include "app/window/engine_job.h"
#include "app/window/file_commands.h"
#include "app/window/input_events.h"
#include "core/status.h"
#include "render/gl_proc.h"
#include "render/renderer.h"

namespace sculpt::app {

class SculptApp {
public:
    SculptApp() = default;
    ~SculptApp();
    SculptApp(const SculptApp&) = delete;
    SculptApp& operator=(const SculptApp&) = delete;

    // Loads an OBJ into the session (new lattice, empty history) and frames it. On failure nothing changes.
    Status loadMesh(const std::string& path);

    void onFramebufferSize(const FramebufferSizeEvent& event);
    void onMouseButton(const MouseButtonEvent& event, CaptureFlags capture);
    void onMouseMove(const MouseMoveEvent& event, CaptureFlags capture);
    void onScroll(const ScrollEvent& event, CaptureFlags capture);
    void onKey(const KeyEvent& event, CaptureFlags capture);

    // With a GL >= 3.3 context current and a Dear ImGui context created (createUiContext): initialises the
    // renderer (entry points from getProc) and ImGui's OpenGL3 backend.
    Status initGraphics(render::GlGetProc getProc);
    // Frees the GL objects and shuts the ImGui renderer backend down (context still current).
    void releaseGraphics();

    // Draws one frame into the bound framebuffer, width x height pixels: the scene, then the UI. The caller
    // has started the platform side of the ImGui frame (ImGui_ImplGlfw_NewFrame, or io.DisplaySize and
    // io.DeltaTime set by hand). A 0 x 0 (minimised) framebuffer draws nothing. Returns the renderer's error.
    Status renderFrame(int width, int height);

    // Files (file_commands.h): menu bar, dialogs, unsaved-changes prompts, background loads and saves.
    FileCommands& files() { return files_; }
    // The window's close button: asks about unsaved changes; the loop ends once quitApproved().
    void requestQuit();
    bool quitApproved() const { return files_.quitApproved(); }
    // Files dropped on the window: the first .obj or .json opens (after the unsaved-changes prompt).
    void onDropFiles(const std::vector<std::string>& paths);
    std::string windowTitle() const { return files_.windowTitle(state_); }
    // What the next frames need when no input comes (frame_pacer.h): a frame every 1/15 s while a load or save
    // runs (its progress popup), every 0.4 s while a text field has the caret (it blinks); otherwise none, and
    // the window sleeps until an event.
    FrameNeeds frameNeeds() const;

    // What Dear ImGui claims right now (the current context; none: nothing). Keyboard: also while any item is
    // active or wants text, since io.WantCaptureKeyboard is computed at NewFrame from the frame before and
    // events arrive between frames: the keys typed right after a click into a field go to the field.
    static CaptureFlags uiCapture();
    // The same for a mouse button or wheel event at (x, y) (Dear ImGui's coordinates: window pixels). Mouse:
    // whether a UI window drawn last frame lies under (x, y), an ImGui popup is open, or a button ImGui took
    // is still down. note: not io.WantCaptureMouse, which NewFrame computed for where the cursor was then: a
    // press that arrives in the same frame as the move that carried the cursor off a panel (its button just
    // clicked) onto the mesh was taken for the panel's and lost, and one from the mesh onto a panel sculpted.
    static CaptureFlags uiCaptureAt(double x, double y);

    // Engine steps off the main thread (engine_job.h): a drag's move, a transform's pose, undo and redo, a
    // drag's end. seconds: how long the event that starts a step waits for it before the window draws the
    // step's progress instead. Infinity (the default, and the tests' unless they set it): every step runs on
    // the calling thread as a plain call. The window sets 1/30 s.
    void setEngineWait(double seconds) { engineWaitSeconds_ = seconds; }
    // Called on the worker as a step ends (the window posts an empty event: its loop may be asleep).
    void setEngineWake(std::function<void()> wake) { engineWake_ = std::move(wake); }
    // A step runs on the worker: until this is false the state (state(), the session) is the worker's; the
    // frames meanwhile show the last applied one, and events wait in order (moves coalesced) for their turn.
    bool engineBusy() const { return job_.running(); }
    size_t heldInputCount() const { return heldInput_.size(); }
    // Waits for the running step, then runs the held input (and the steps it starts) to the end.
    void waitForEngine();
    // What a busy frame shows: "Certifying the move... 1.2 s" (nothing while no step runs or for the first
    // kProgressDelaySeconds of one: a quick step does not flash a box).
    static constexpr double kProgressDelaySeconds = 0.15;
    std::string engineProgress() const;
    // Where the last busy frame drew the progress box, pixels (x0, y0, x1, y1); all 0 when it drew none.
    ImVec4 progressBox() const { return progressBox_; }
    // Tests: called on the worker before each step's work (a test holds a step there to look at the window).
    void setEngineStepHook(std::function<void()> hook) { stepHook_ = std::move(hook); }

    AppState& state() { return state_; }
    const AppState& state() const { return state_; }
    render::Renderer& renderer() { return renderer_; }

private:
    // Input held back while a step runs (engineBusy), replayed in order when it ends.
    struct HeldInput {
        enum class Kind { Button, Move, Scroll, Key, Drop, Quit, Size } kind = Kind::Quit;
        HeldInput() = default;  // Quit
        HeldInput(const MouseButtonEvent& e, CaptureFlags c) : kind(Kind::Button), button(e), capture(c) {}
        HeldInput(const MouseMoveEvent& e, CaptureFlags c) : kind(Kind::Move), move(e), capture(c) {}
        HeldInput(const ScrollEvent& e, CaptureFlags c) : kind(Kind::Scroll), scroll(e), capture(c) {}
        HeldInput(const KeyEvent& e, CaptureFlags c) : kind(Kind::Key), key(e), capture(c) {}
        explicit HeldInput(const FramebufferSizeEvent& e) : kind(Kind::Size), size(e) {}
        explicit HeldInput(std::vector<std::string> dropped) : kind(Kind::Drop), paths(std::move(dropped)) {}
        MouseButtonEvent button;
        MouseMoveEvent move;
        ScrollEvent scroll;
        KeyEvent key;
        FramebufferSizeEvent size;
        std::vector<std::string> paths;
        CaptureFlags capture;
    };
    // Holds `input` if a step runs or earlier input still waits; true if held. A move replaces a move held
    // last (a stroke update rebuilds the stroke up to the cursor: the moves in between change nothing).
    bool holdInput(const HeldInput& input);
    void dispatch(const HeldInput& input);
    // The handlers proper, run when the input's turn comes.
    void handleMouseButton(const MouseButtonEvent& event, CaptureFlags capture);
    void handleMouseMove(const MouseMoveEvent& event, CaptureFlags capture);
    void handleKey(const KeyEvent& event, CaptureFlags capture);
    // Runs `step` as an engine step (on the worker unless the wait is infinite), named `what` in the progress.
    void runEngineStep(std::string what, std::function<void()> step);
    // Collects a finished step (its error, if it threw, goes to the status line).
    void finishEngineStep();
    // Collects a finished step; true while a step still runs (then the frame is a busy one).
    bool pollEngine();
    // Runs the held input in order until one starts a step that still runs; called after a frame that showed
    // the last step's result.
    void replayHeldInput();
    // A frame while a step runs: the last applied scene and UI, and the progress over them.
    Status drawBusyFrame(int width, int height);
    // Keeps what drawBusyFrame draws again: the frame just drawn's camera, options and status line height (every
    // frame, a few bytes), and its UI's draw lists (keepUiPicture, copied when a step runs on past its wait).
    void keepFrameView(const render::DrawOptions& options);
    void keepUiPicture();
    void freeUiPicture();

    // The editing tools (tool_input.cpp).
    void pressSculpt(const MouseButtonEvent& event);
    void pressLattice(const MouseButtonEvent& event);
    // triangle >= 0: grab that surface point; otherwise grabbedHandle. movingHandles follow the cursor too.
    void beginSculpt(int triangle, const Eigen::Vector3d& barycentric, int grabbedHandle, const std::vector<int>& movingHandles);
    void updateSculpt(double x, double y);
    void endSculpt();
    void cancelSculpt();  // Esc during a drag: the session takes the drag back
    void moveTool(double x, double y);
    void releaseTool();
    bool keyTool(const KeyEvent& event);
    void updateHint(double x, double y);
    void finishBoxSelection();
    double pickRadius() const;
    // The control point a click at (x, y) picks (-1: none): of the drawn markers under the cursor, a free one before
    // a pinned one, then the nearest the eye (controlPointAtPixel). points: the cage as drawn (cagePoints).
    int controlPointUnderCursor(const Positions& points, double x, double y) const;
    render::ConstraintView constraintView() const;
    // The sculpt brush (brush_tool.cpp): F / Shift+F resizing, the circle under the cursor, and the brush a
    // drag grabbing `at` gets (its radius in world units there).
    bool brushKey(const KeyEvent& event);
    bool brushMouseButton(const MouseButtonEvent& event);
    bool brushMouseMove(double x, double y);
    void updateBrushHover(double x, double y);
    // The mesh surface under pixel (x, y): the point and the triangle's unit normal; false if none.
    bool surfaceUnderPixel(double x, double y, Eigen::Vector3d& point, Eigen::Vector3d& normal) const;
    core::BrushSettings brushForDrag(const Eigen::Vector3d& at) const;
    void syncGpu();
    void drawUi();

    AppState state_;
    FileCommands files_;
    render::Renderer renderer_;
    int uploadedTopology_ = -1;  // Session::refinement().topologyVersion() of the mesh last uploaded
    std::uint64_t uploadedRest_ = 0;  // Session::mesh().restVersion of the rest mesh on the GPU path
    // A frame the deformation-path chooser times (a drag frame: syncGpu to the end of the draw; a still frame: the
    // draw), and the path it took.
    bool measuringFrame_ = false, stillFrame_ = false;
    std::chrono::steady_clock::time_point frameStart_;
    DeformationPath framePath_ = DeformationPath::Cpu;
    bool imguiBackendReady_ = false;

    // The last frame drawn from applied state (drawBusyFrame draws it again).
    render::Camera lastCamera_;
    render::DrawOptions lastOptions_;
    std::vector<ImDrawList*> lastUi_;  // owned copies (ImDrawList::CloneOutput)
    ImVec2 lastUiPos_, lastUiSize_, lastUiScale_;
    float lastStatusLineHeight_ = 0.0f;
    ImVec4 progressBox_{0.0f, 0.0f, 0.0f, 0.0f};
    bool haveFrameView_ = false;

    double engineWaitSeconds_ = std::numeric_limits<double>::infinity();
    std::function<void()> engineWake_, stepHook_;
    std::deque<HeldInput> heldInput_;
    bool replaying_ = false;
    // Last: destroyed first, so a running step ends before the state it owns is freed.
    EngineJob job_;
};

}  // namespace sculpt::app
