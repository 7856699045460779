// SculptApp: the interactive sculpting application without its window. Owns the AppState (session, camera,
// UI state) and the Renderer; turns plain input events (input_events.h) into engine commands and draws a
// frame (scene + Dear ImGui panels) into the bound framebuffer. The GLFW layer (glfw_main.cpp) and the
// tests (tests/render/window_app_test.cpp) drive the very same object.
//
// Mouse: left-press on the mesh picks the surface point under the cursor and starts an interactive drag
// (Session::beginDrag); every move puts the target where the cursor ray meets the plane through the picked
// point facing the camera and calls Session::updateDrag (live); release ends it (one undo step).
// Middle-drag or Alt+left-drag orbits, Shift+middle-drag pans, the wheel zooms. Keys: Home frames the mesh (F too
// in the lattice tool; in the sculpt tool F sets the brush radius),
// Ctrl+Z undoes, Ctrl+Shift+Z / Ctrl+Y redo. Input the UI claims (CaptureFlags) is left alone.
#pragma once

#include <chrono>
#include <cstdint>

#include <string>
#include <vector>

#include "app/frame_pacer.h"
#include "app/window/app_state.h"
#include "app/window/file_commands.h"
#include "app/window/input_events.h"
#include "core/status.h"
#include "render/gl_proc.h"
#include "render/renderer.h"

namespace sculpt::app {

class SculptApp {
public:
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
    void requestQuit() { files_.requestQuit(state_); }
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

    AppState& state() { return state_; }
    const AppState& state() const { return state_; }
    render::Renderer& renderer() { return renderer_; }

private:
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
    int uploadedTopology_ = -1;  // Session::topologyVersion() of the mesh last uploaded
    std::uint64_t uploadedRest_ = 0;  // Session::restVersion() of the rest mesh on the GPU path
    // A frame the deformation-path chooser times (a drag frame: syncGpu to the end of the draw; a still frame: the
    // draw), and the path it took.
    bool measuringFrame_ = false, stillFrame_ = false;
    std::chrono::steady_clock::time_point frameStart_;
    DeformationPath framePath_ = DeformationPath::Cpu;
    bool imguiBackendReady_ = false;
};

}  // namespace sculpt::app
