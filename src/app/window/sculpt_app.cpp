#include "app/window/sculpt_app.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <utility>

#include <imgui.h>
#include <imgui_impl_opengl3.h>
#include <imgui_internal.h>

#include "app/scene_builder.h"
#include "core/volume/cage_view.h"
#include "app/window/lattice_commands.h"
#include "app/window/panels.h"
#include "app/window/picking.h"
#include "app/window/tool_commands.h"
#include "app/window/tspline_commands.h"
#include "app/window/view_navigation.h"
#include "app/file_browser.h"
#include "io/mesh_format.h"
#include "render/legend.h"

namespace sculpt::app {
namespace {

double millisecondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}


bool shortcutModifier(const Modifiers& m) { return m.control || m.super; }

}  // namespace

CaptureFlags SculptApp::uiCapture() {
    if (!ImGui::GetCurrentContext()) return {};
    const ImGuiIO& io = ImGui::GetIO();
    return {io.WantCaptureMouse, io.WantCaptureKeyboard || io.WantTextInput || ImGui::IsAnyItemActive()};
}

CaptureFlags SculptApp::uiCaptureAt(double x, double y) {
    CaptureFlags capture = uiCapture();
    if (!ImGui::GetCurrentContext()) return capture;
    const ImGuiContext& g = *ImGui::GetCurrentContext();
    const ImGuiIO& io = g.IO;
    // As ImGui's NewFrame decides io.WantCaptureMouse (imgui.cpp 1.86, UpdateHoveredWindowAndCaptureFlags),
    // but at the event's point: an open popup takes every click (one outside closes it), a button ImGui owns
    // keeps the mouse ImGui's, and otherwise the windows of the last frame (what the user sees) decide.
    bool claimed = g.OpenPopupStack.Size > 0;
    for (int b = 0; b < IM_ARRAYSIZE(io.MouseDown); ++b) claimed = claimed || (io.MouseDown[b] && io.MouseDownOwned[b]);
    const ImVec2 point(static_cast<float>(x), static_cast<float>(y));
    for (int i = g.Windows.Size - 1; i >= 0 && !claimed; --i) {
        const ImGuiWindow* window = g.Windows[i];
        if (!window->Active || window->Hidden || (window->Flags & ImGuiWindowFlags_NoMouseInputs)) continue;
        ImRect bounds = window->OuterRectClipped;
        const bool resizable = !(window->Flags & (ImGuiWindowFlags_ChildWindow | ImGuiWindowFlags_NoResize |
                                                  ImGuiWindowFlags_AlwaysAutoResize));
        bounds.Expand(resizable ? g.WindowsHoverPadding : g.Style.TouchExtraPadding);  // ImGui's own hover margins
        claimed = bounds.Contains(point);
    }
    capture.mouse = claimed;
    return capture;
}

Status SculptApp::loadMesh(const std::string& path) { return files_.loadMeshNow(state_, path); }

void SculptApp::onDropFiles(const std::vector<std::string>& paths) {
    if (holdInput(HeldInput(paths))) return;
    for (const std::string& path : paths)
        if (io::isMeshPath(path) || hasExtension(path, {".json"})) return files_.openPath(state_, path);
    if (!paths.empty()) setStatus(state_, std::string("Drop a mesh (") + io::meshExtensionList() + ") or a .json session to open it.", true);
}

void SculptApp::requestQuit() {
    if (!holdInput(HeldInput())) files_.requestQuit(state_);
}

void SculptApp::onFramebufferSize(const FramebufferSizeEvent& event) {
    if (holdInput(HeldInput(event))) return;
    state_.framebufferWidth = std::max(event.width, 0);
    state_.framebufferHeight = std::max(event.height, 0);
}

void SculptApp::onMouseButton(const MouseButtonEvent& event, CaptureFlags capture) {
    if (holdInput(HeldInput(event, capture))) return;
    // What may take the engine long: a transform's confirm or cancel, a drag's end (its steps are recorded,
    // a brush stroke's layers baked).
    const bool left = event.button == MouseButton::Left;
    if (state_.transform.active && event.action == ButtonAction::Press)
        return runEngineStep("Finishing the transform", [this, event, capture] { handleMouseButton(event, capture); });
    if (state_.drag.active && left && event.action == ButtonAction::Release)
        return runEngineStep("Finishing the drag", [this, event, capture] { handleMouseButton(event, capture); });
    handleMouseButton(event, capture);
}

void SculptApp::handleMouseButton(const MouseButtonEvent& event, CaptureFlags capture) {
    state_.cursorX = event.x;
    state_.cursorY = event.y;
    if (state_.transform.active) {  // G / R / S running: a left click confirms, a right click cancels, anywhere
        if (event.action == ButtonAction::Press && event.button == MouseButton::Left) confirmTransform(state_);
        else if (event.action == ButtonAction::Press && event.button == MouseButton::Right) cancelTransform(state_);
        return;
    }
    if (event.action == ButtonAction::Release) {
        // note: releases always reach us, even over a panel, so a drag or orbit never gets stuck.
        if (event.button == MouseButton::Left) releaseTool();
        if (event.button == MouseButton::Middle || event.button == MouseButton::Left)
            state_.navigation = Navigation::None;
        return;
    }
    if (brushMouseButton(event)) return;  // a click ends an F / Shift+F brush resize
    if (capture.mouse || state_.drag.active || state_.navigation != Navigation::None) return;
    if (files_.blocksInput()) return;  // a load or save runs, or a file question is open
    if (event.button == MouseButton::Middle) {
        state_.navigation = event.modifiers.shift ? Navigation::Pan : Navigation::Orbit;
    } else if (event.button == MouseButton::Left) {
        if (event.modifiers.alt) state_.navigation = event.modifiers.shift ? Navigation::Pan : Navigation::Orbit;
        else if (placeLatticeAtPixel(state_, event.x, event.y)) return;  // the Lattices panel's "Place" waits for it
        else if (chooseCellAtPixel(state_, event.x, event.y)) return;   // the T-spline section's "Choose cells"
        else if (state_.tools.mode == ToolMode::Lattice) pressLattice(event);
        else pressSculpt(event);
    }
}

void SculptApp::onMouseMove(const MouseMoveEvent& event, CaptureFlags capture) {
    if (holdInput(HeldInput(event, capture))) return;
    // A drag's move or a transform's new pose: the engine solves and certifies it.
    if (state_.drag.active || state_.transform.active)
        return runEngineStep(state_.transform.active ? "Certifying the transform" : "Certifying the move",
                             [this, event, capture] { handleMouseMove(event, capture); });
    handleMouseMove(event, capture);
}

void SculptApp::handleMouseMove(const MouseMoveEvent& event, CaptureFlags capture) {
    // note: moves are ours while a drag or orbit we started is in progress, wherever the cursor is (ImGui
    // does not claim a mouse button pressed outside its windows); otherwise moves only track the cursor.
    const double dx = event.x - state_.cursorX, dy = event.y - state_.cursorY;
    state_.cursorX = event.x;
    state_.cursorY = event.y;
    if (brushMouseMove(event.x, event.y)) return;  // F / Shift+F: the brush radius or strength follows
    if (state_.transform.active) {
        transformMouseMove(state_, event.x, event.y);
    } else if (!state_.drag.active && !state_.tools.lattice.boxActive && state_.navigation == Navigation::None && capture.mouse) {
        // Over a panel: a click there is the panel's, so nothing under the panel is offered (no pick ring, no
        // hint naming a control point, no brush circle).
        state_.tools.hint.clear();
        state_.tools.lattice.hovered = -1;
        state_.tools.brush.hover = false;
    } else if (state_.drag.active || state_.tools.lattice.boxActive || state_.navigation == Navigation::None) {
        moveTool(event.x, event.y);
    } else if (state_.navigation == Navigation::Orbit) {
        orbitView(state_, dx, dy);
    } else if (state_.navigation == Navigation::Pan) {
        panView(state_, dx, dy);
    }
}

void SculptApp::onScroll(const ScrollEvent& event, CaptureFlags capture) {
    if (holdInput(HeldInput(event, capture))) return;
    if (capture.mouse || state_.transform.active) return;
    zoomView(state_, state_.cursorX, state_.cursorY, event.dy);
}

void SculptApp::onKey(const KeyEvent& event, CaptureFlags capture) {
    if (holdInput(HeldInput(event, capture))) return;
    // A transform's keys (typed values, axes, Enter, Esc), Esc during a drag, undo and redo: engine steps.
    const bool taken = capture.keyboard || event.action == KeyAction::Release;
    const bool shortcut = shortcutModifier(event.modifiers);
    const bool undoRedo = shortcut && (event.key == Key::Z || event.key == Key::Y);
    if (!taken && (state_.transform.active || state_.drag.active || undoRedo)) {
        const std::string what = state_.transform.active ? "Certifying the transform"
                               : state_.drag.active      ? "Finishing the drag"
                               : event.key == Key::Y || event.modifiers.shift ? "Redoing"
                                                                              : "Undoing";
        return runEngineStep(what, [this, event, capture] { handleKey(event, capture); });
    }
    handleKey(event, capture);
}

void SculptApp::handleKey(const KeyEvent& event, CaptureFlags capture) {
    if (capture.keyboard || event.action == KeyAction::Release) return;
    if (state_.transform.active) return transformKey(state_, event);  // every key, until confirmed or cancelled
    if (files_.onKey(state_, event)) return;  // Ctrl+O / S / Shift+S / Q, or ignored while files are busy
    if (keyTool(event)) return;  // Tab, G, R, S, P, A, Esc / Delete of the editing tools
    const Modifiers& m = event.modifiers;
    const bool shortcut = shortcutModifier(m);
    // note: undo and redo repeat while held; the view keys act once per press.
    if (event.action != KeyAction::Press && event.key != Key::Z && event.key != Key::Y) return;
    switch (event.key) {
        case Key::Z:
            if (shortcut && m.shift) redoCommand(state_);
            else if (shortcut) undoCommand(state_);
            break;
        case Key::Y:
            if (shortcut) redoCommand(state_);
            break;
        case Key::F:
        case Key::Home:
            if (!shortcut) frameMesh(state_);
            break;
        case Key::NumpadDecimal: frameSelected(state_); break;
        case Key::Numpad1: setAxisView(state_, AxisView::Front, shortcut); break;
        case Key::Numpad3: setAxisView(state_, AxisView::Right, shortcut); break;
        case Key::Numpad7: setAxisView(state_, AxisView::Top, shortcut); break;
        case Key::Numpad5: toggleOrthographic(state_); break;
        default: break;
    }
}

Status SculptApp::initGraphics(render::GlGetProc getProc) {
    if (Status s = renderer_.init(getProc); !s) return s;
    files_.initGraphics(getProc);
    state_.gpu.mesh = true;
    state_.gpu.fields = true;
    if (ImGui::GetCurrentContext() && !imguiBackendReady_) {
        if (!ImGui_ImplOpenGL3_Init("#version 330 core"))
            return Status::error("Dear ImGui's OpenGL3 backend could not load GL (see its message above)");
        imguiBackendReady_ = true;
    }
    return Status::success();
}

void SculptApp::releaseGraphics() {
    waitForEngine();
    freeUiPicture();
    if (imguiBackendReady_) ImGui_ImplOpenGL3_Shutdown();
    imguiBackendReady_ = false;
    renderer_.release();
}

void SculptApp::syncGpu() {
    if (!renderer_.initialized()) return;
    const auto start = std::chrono::steady_clock::now();
    PendingGpuUpdate& gpu = state_.gpu;
    const core::Session& session = state_.session;
    bool uploaded = false, positionsUploaded = false;
    // The GPU path (deformation_path.h) where the chooser wants it and the renderer can take the lattices: a box
    // cage and box layers after it (a brush's region, a subdivision's steps).
    std::vector<const core::Lattice*> layers;
    for (const core::Layer& layer : session.cage().layers()) layers.push_back(&layer.lattice);
    std::string gpuProblem = render::Renderer::gpuDeformationProblem(session.lattice(), layers);
    // The shader carries what lies in the cage's box only; its collar (embedding.h) is evaluated here.
    if (const int collar = session.cage().embedding().collarCount(); gpuProblem.empty() && collar > 0)
        gpuProblem = std::to_string(collar) + (collar == 1 ? " vertex rests" : " vertices rest") + " outside the lattice's box (its collar carries them)";
    const bool freshMesh = gpu.mesh;  // a new mesh or session, or a new context (not only a refinement)
    // A refinement (or its undo) changes the triangles: a full upload.
    if (session.refinement().topologyVersion() != uploadedTopology_) gpu.mesh = true;
    if (gpu.mesh) {
        // A new mesh is measured afresh; a refinement keeps the decision unless it made a small mesh big.
        const int vertexCount = static_cast<int>(session.mesh().positions.rows());
        if (freshMesh || !state_.deformationPath.decidedFor(vertexCount)) state_.deformationPath.reset(vertexCount);
    }
    // A drag's frames and the others (still, or the view moving) each take the path the chooser found faster.
    const DeformationPathChooser& chooser = state_.deformationPath;
    const bool dragging = state_.drag.active;
    const bool wantGpu = gpuProblem.empty() && !session.mesh().empty() &&
                         (dragging ? chooser.dragPath() : chooser.restPath()) == DeformationPath::Gpu;
    const auto allVertices = [&session] {
        std::vector<int> all(static_cast<size_t>(session.mesh().positions.rows()));
        std::iota(all.begin(), all.end(), 0);
        return all;
    };
    const auto reportGpu = [&](const Status& s) {
        if (!s) setStatus(state_, "GPU update failed: " + s.message, true);
    };
    // The rest mesh and its cells go up once per rest mesh; then only the control displacements.
    // Should it fail (it checks every value), the CPU path takes over for this mesh, with the reason shown.
    const auto enterGpuPath = [&] {
        uploadedRest_ = session.mesh().restVersion;
        if (Status s = renderer_.setGpuDeformation(session.lattice(), session.cage().embedding(), session.mesh().rest, layers); !s) {
            reportGpu(s);
            state_.deformationPath.force(DeformationPath::Cpu);
            reportGpu(renderer_.gpuDeformationActive() ? renderer_.clearGpuDeformation(session.mesh().positions)
                                                       : renderer_.updatePositions(session.mesh().positions, allVertices()));
        }
    };
    // The path changes (the chooser switched, the lattice became another kind): every vertex is redrawn.
    if (!gpu.mesh && wantGpu != renderer_.gpuDeformationActive()) gpu.allPositions = true;
    if (gpu.mesh) {
        uploadedTopology_ = session.refinement().topologyVersion();
        reportGpu(renderer_.setMesh(session.mesh().positions, session.mesh().triangles));
        // The file's own colours (a scan's), carried through refinement; cleared by setMesh otherwise.
        if (const std::shared_ptr<const io::ObjMesh>& source = files_.document().mesh; source && renderer_.vertexCount() > 0)
            reportGpu(renderer_.setVertexColors(sessionVertexColors(*source, session)));
        state_.meshHasVertexColors = renderer_.hasVertexColors();
        if (wantGpu && renderer_.vertexCount() > 0) enterGpuPath();
        gpu.mesh = false;
        gpu.fields = true;
        uploaded = positionsUploaded = true;
    } else if (gpu.allPositions || !gpu.vertices.empty()) {
        if (wantGpu) {
            // A cage of another shape under the same rest mesh (which the update refuses) is set up afresh too.
            if (!renderer_.gpuDeformationActive() || session.mesh().restVersion != uploadedRest_ ||
                !renderer_.updateGpuDeformation(session.lattice(), layers))
                enterGpuPath();
        } else if (renderer_.gpuDeformationActive()) {
            reportGpu(renderer_.clearGpuDeformation(session.mesh().positions));
        } else {
            reportGpu(renderer_.updatePositions(session.mesh().positions, gpu.allPositions ? allVertices() : gpu.vertices));
        }
        uploaded = positionsUploaded = true;
    }
    // The stats panel: the path in a few words, the story in its tooltip (a small mesh's reason first).
    const bool possible = gpuProblem.empty() || !chooser.measuresThisMesh();
    state_.stats.deformationPath = possible ? chooser.label(dragging) : "CPU";
    state_.stats.deformationDetails = possible ? chooser.describe() : "The CPU path: " + gpuProblem + ".";
    // While the chooser measures, a drag frame in which the mesh moved is timed from here to the end of its draw,
    // and the first still frame on each path from the draw to its end.
    framePath_ = renderer_.gpuDeformationActive() ? DeformationPath::Gpu : DeformationPath::Cpu;
    measuringFrame_ = positionsUploaded && dragging && chooser.deciding() && gpuProblem.empty();
    if (measuringFrame_) frameStart_ = start;
    stillFrame_ = !dragging && state_.navigation == Navigation::None && gpuProblem.empty() && chooser.wantsStillFrame(framePath_);
    gpu.allPositions = false;
    gpu.vertices.clear();
    if (gpu.fields) {
        const Overlays& o = state_.overlays;
        SceneRequest request;
        request.jacobian = o.jacobian;
        request.affected = o.affected;
        request.lastDragConstraints = false;
        request.mesh = false;  // the GPU has the mesh; only the overlays are wanted here
        const bool showLattice = latticeShown(state_);
        // A net lattice: exactly the points the lattice tool picks (one per weld group, outer only; a T-spline's
        // of non-empty cells, cached, so they are not found again for every frame of a drag).
        if (session.lattice().volume) request.drawnControlPoints = shownControlPoints(state_);
        if (showLattice) {
            clampLatticeSelection(state_);
            request.selectedControlPoints.assign(static_cast<size_t>(session.lattice().controlPointCount()), 0);
            for (int id : state_.tools.lattice.points) request.selectedControlPoints[static_cast<size_t>(id)] = 1;
            // note: in the lattice tool the affected region shows what the selection would move.
            if (state_.tools.mode == ToolMode::Lattice) request.affectedControlPoints = state_.tools.lattice.points;
        }
        // note: only the overlays asked for are computed, and not the mesh (a 1M-vertex copy per dragged frame).
        render::LatticeView lattice;
        std::vector<float> jacobian, affected;
        if (showLattice || o.jacobian || o.affected) {
            render::SceneData scene = sceneFromSession(session, request);
            if (showLattice) lattice = std::move(scene.lattice);
            lattice.outerOnly = o.latticeOuterOnly;
            if (showLattice && !state_.lattices.showTools) lattice.toolCurves.clear();
            jacobian = std::move(scene.jacobianDet);
            affected = std::move(scene.affectedWeight);
        }
        // With the Lattice overlay off, the lattice tools that are not frozen still show where they are (the
        // Lattices panel's "Show tools"): only their rest chunk edges, no cage.
        if (!showLattice && latticeToolsShown(state_))
            for (size_t t = 0; t < session.tools().list().size(); ++t)
                if (static_cast<int>(t) != session.tools().frozen())
                    for (Positions& curve : restToolLines(session.tools().list()[t].volume, SceneRequest{}.curveSamplesPerSpan))
                        lattice.toolCurves.push_back(std::move(curve));
        // Weighted T-splines: the cells chosen for subdivision, and a tool's T-junctions while choosing.
        if (showLattice || tsplineOverlaysShown(state_)) addTSplineOverlays(state_, lattice);
        renderer_.setLattice(lattice);
        renderer_.setJacobianField(jacobian);
        renderer_.setAffectedWeights(affected);
        const render::ConstraintView constraints = constraintView();
        renderer_.setConstraints(constraints);
        gpu.fields = false;
        uploaded = true;
    }
    if (uploaded) state_.stats.updateMs = millisecondsSince(start);
    if (positionsUploaded) state_.stats.lastUploadVertices = renderer_.lastUpload().verticesUploaded;
}

Status SculptApp::renderFrame(int width, int height) {
    if (width <= 0 || height <= 0) return Status::success();  // minimised: nothing to draw, nothing to divide by
    if (pollEngine()) return drawBusyFrame(width, height);    // the state is the worker's
    if (state_.framebufferWidth != width || state_.framebufferHeight != height)
        onFramebufferSize({width, height});
    files_.poll(state_);  // installs a finished background load before the upload below
    // The surface under the cursor moved (undo, redo, a script): the brush circle goes where it now is.
    const PendingGpuUpdate& gpu = state_.gpu;
    if (state_.tools.brush.hover && !state_.drag.active && (gpu.mesh || gpu.allPositions || !gpu.vertices.empty()))
        updateBrushHover(state_.cursorX, state_.cursorY);
    syncGpu();
    // The hint says what the cursor would do where it is now: also after a tool switch (Tab, the Tools panel),
    // a change of brush, an undo, not only after the next mouse move.
    if (!state_.drag.active && !state_.transform.active && !state_.tools.lattice.boxActive &&
        state_.navigation == Navigation::None)
        updateHint(state_.cursorX, state_.cursorY);
    const auto start = std::chrono::steady_clock::now();
    render::DrawOptions options;
    options.wireframe = state_.overlays.wireframe;
    // Exactly what the Overlays panel's checkbox says, or only the lattice tools (then nothing else is in
    // the lattice layer).
    options.lattice = latticeShown(state_) || latticeToolsShown(state_) || tsplineOverlaysShown(state_);
    options.jacobian = state_.overlays.jacobian;
    options.affected = state_.overlays.affected;
    options.vertexColors = state_.overlays.vertexColors;
    options.constraints = true;  // the drag's constraints, placed handles and pins (empty: nothing drawn)
    // While the shape or the view moves, a large mesh is drawn as its decimated proxy; the first frame
    // after the motion stops draws it whole.
    options.proxy = state_.drag.active || state_.navigation != Navigation::None;
    options.uiInsetBottom = state_.statusLineHeight;
    state_.legendHeight = options.jacobian ? render::jacobianLegendHeight(renderer_.pixelScale()) : 0.0f;
    const auto drawStart = std::chrono::steady_clock::now();
    Status drawn = renderer_.draw(state_.camera, options, width, height);
    if (measuringFrame_ || stillFrame_) {
        renderer_.finish();  // the GPU's share of the frame counts too
        if (measuringFrame_) state_.deformationPath.addDragFrame(framePath_, millisecondsSince(frameStart_));
        if (stillFrame_) state_.deformationPath.addStillFrame(framePath_, millisecondsSince(drawStart));
        measuringFrame_ = stillFrame_ = false;
    }
    files_.afterSceneDrawn(state_, width, height);  // a requested screenshot: the scene without the UI
    if (imguiBackendReady_ && ImGui::GetCurrentContext()) {
        // The frame rate of frames drawn one after another; a longer gap was the window asleep.
        const double gap = ImGui::GetIO().DeltaTime;
        FrameStats& stats = state_.stats;
        stats.afterIdle = gap > FrameStats::kIdleGapSeconds;
        if (!stats.afterIdle) stats.frameMs = stats.frameMs > 0.0 ? 0.9 * stats.frameMs + 100.0 * gap : 1000.0 * gap;
        ImGui_ImplOpenGL3_NewFrame();
        ImGui::NewFrame();
        drawUi();
        ImGui::Render();
        ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    }
    keepFrameView(options);
    state_.stats.renderMs = millisecondsSince(start);
    // Undo, redo or a history entry clicked in this frame: an engine step, now that the frame is drawn.
    if (const int target = std::exchange(state_.historyRequest, -1); target >= 0 && target != state_.session.history().cursor()) {
        const int from = state_.session.history().cursor();
        runEngineStep(target == from - 1 ? "Undoing" : target == from + 1 ? "Redoing" : "Going to history step " + std::to_string(target),
                      [this, target] { jumpToHistory(state_, target); });
    }
    if (!job_.running()) replayHeldInput();  // input held while the last step ran, now that its result is drawn
    return drawn;
}

// ---- engine steps off the main thread (engine_job.h) -------------------------------------------------------

SculptApp::~SculptApp() {
    job_.collect();  // the worker owns state_ until it returns
    freeUiPicture();
}

bool SculptApp::holdInput(const HeldInput& input) {
    if (replaying_ || (!job_.running() && heldInput_.empty())) return false;
    if (input.kind == HeldInput::Kind::Move && !heldInput_.empty() && heldInput_.back().kind == HeldInput::Kind::Move)
        heldInput_.back() = input;
    else
        heldInput_.push_back(input);
    return true;
}

void SculptApp::dispatch(const HeldInput& input) {
    switch (input.kind) {
        case HeldInput::Kind::Button: onMouseButton(input.button, input.capture); break;
        case HeldInput::Kind::Move: onMouseMove(input.move, input.capture); break;
        case HeldInput::Kind::Scroll: onScroll(input.scroll, input.capture); break;
        case HeldInput::Kind::Key: onKey(input.key, input.capture); break;
        case HeldInput::Kind::Drop: onDropFiles(input.paths); break;
        case HeldInput::Kind::Quit: requestQuit(); break;
        case HeldInput::Kind::Size: onFramebufferSize(input.size); break;
    }
}

void SculptApp::runEngineStep(std::string what, std::function<void()> step) {
    // note: input is held while a step runs, so none should be running here; if one were, it ends first rather
    // than this step being dropped (EngineJob::start refuses a second job).
    if (job_.running()) finishEngineStep();
    auto work = [this, step = std::move(step)] {
        if (stepHook_) stepHook_();
        step();
    };
    if (job_.start(std::move(work), std::move(what), engineWaitSeconds_, engineWake_)) finishEngineStep();
    else keepUiPicture();  // it runs on: the busy frames draw the last frame's UI again
}

void SculptApp::finishEngineStep() {
    const std::string what = job_.what();
    freeUiPicture();
    if (const std::string error = job_.collect(); !error.empty())
        setStatus(state_, what + " stopped with an error: " + error + ". Undo takes back what it changed.", true);
    state_.gpu.fields = true;
}

bool SculptApp::pollEngine() {
    if (!job_.running()) return false;
    if (!job_.finished()) return true;
    finishEngineStep();
    return false;  // this frame shows what the step applied; the held input runs after it (replayHeldInput)
}

void SculptApp::replayHeldInput() {
    // The held input, in order, until one starts a step that is still running. note: only after a frame drawn
    // from the applied state: replayed at once, a stroke whose every move outlasts the wait chained step after
    // step, and the window showed the frame from before the stroke until the mouse stopped.
    while (!heldInput_.empty() && !job_.running()) {
        const HeldInput input = heldInput_.front();
        heldInput_.pop_front();
        replaying_ = true;
        dispatch(input);
        replaying_ = false;
    }
}

void SculptApp::waitForEngine() {
    while (job_.running() || !heldInput_.empty()) {
        if (job_.running()) finishEngineStep();  // collect() waits for the worker
        replayHeldInput();
    }
}

std::string SculptApp::engineProgress() const {
    const double seconds = job_.elapsedSeconds();
    if (!job_.running() || seconds < kProgressDelaySeconds) return {};
    char text[160];
    std::snprintf(text, sizeof text, "%s... %.1f s", job_.what().c_str(), seconds);
    return text;
}

void SculptApp::freeUiPicture() {
    for (ImDrawList* list : lastUi_) IM_DELETE(list);
    lastUi_.clear();
}

void SculptApp::keepFrameView(const render::DrawOptions& options) {
    lastCamera_ = state_.camera;
    lastOptions_ = options;
    lastStatusLineHeight_ = state_.statusLineHeight;
    haveFrameView_ = true;
}

void SculptApp::keepUiPicture() {
    // note: only when a step goes on past its wait, not every frame: Dear ImGui keeps the last frame's draw data
    // until its next NewFrame, and every step starts after a frame's Render (between frames, or at its end).
    freeUiPicture();
    if (!imguiBackendReady_ || !ImGui::GetCurrentContext()) return;
    if (const ImDrawData* data = ImGui::GetDrawData(); data && data->Valid) {
        for (int l = 0; l < data->CmdListsCount; ++l) lastUi_.push_back(data->CmdLists[l]->CloneOutput());
        lastUiPos_ = data->DisplayPos;
        lastUiSize_ = data->DisplaySize;
        lastUiScale_ = data->FramebufferScale;
    }
}

Status SculptApp::drawBusyFrame(int width, int height) {
    // Nothing here reads state_: the scene is what the GPU holds from the last applied frame, drawn with that
    // frame's camera and options, and the UI is that frame's draw lists.
    // note: a large mesh as its decimated proxy, as during a drag: a full 832k-triangle frame took ~0.5 s on
    // llvmpipe, so the first busy frames of a step came late and the box showed up only after them.
    render::DrawOptions options = lastOptions_;
    options.proxy = true;
    Status drawn = renderer_.draw(lastCamera_, options, width, height);
    if (!imguiBackendReady_ || !ImGui::GetCurrentContext() || !haveFrameView_) return drawn;
    ImGui_ImplOpenGL3_NewFrame();
    // The progress box (drawn outside a Dear ImGui frame, so the panels keep what they were: a click held
    // meanwhile is judged against the windows the user saw), bottom centre above the status line.
    ImDrawList progress(ImGui::GetDrawListSharedData());
    progress._ResetForNewFrame();
    const std::string text = engineProgress();
    progressBox_ = ImVec4(0.0f, 0.0f, 0.0f, 0.0f);
    if (!text.empty()) {
        const float w = static_cast<float>(width), h = static_cast<float>(height);
        ImFont* font = ImGui::GetFont();
        const float size = ImGui::GetFontSize();
        const std::string note = "The view shows the last applied shape; input waits its turn.";
        const ImVec2 first = font->CalcTextSizeA(size, w, 0.0f, text.c_str());
        const ImVec2 second = font->CalcTextSizeA(size, w, 0.0f, note.c_str());
        const float pad = 0.6f * size, barHeight = 0.35f * size;
        const float boxW = std::max(first.x, second.x) + 2.0f * pad;
        const float boxH = first.y + second.y + barHeight + 4.0f * pad;
        const ImVec2 lo(std::round(0.5f * (w - boxW)), std::round(h - lastStatusLineHeight_ - boxH - size));
        const ImVec2 hi(lo.x + boxW, lo.y + boxH);
        progressBox_ = ImVec4(lo.x, lo.y, hi.x, hi.y);
        progress.PushTextureID(ImGui::GetIO().Fonts->TexID);
        progress.PushClipRect(ImVec2(0.0f, 0.0f), ImVec2(w, h));
        progress.AddRectFilled(lo, hi, IM_COL32(32, 34, 38, 240), 0.25f * size);
        progress.AddRect(lo, hi, IM_COL32(96, 100, 108, 255), 0.25f * size);
        progress.AddText(font, size, ImVec2(lo.x + pad, lo.y + pad), IM_COL32(235, 235, 235, 255), text.c_str());
        progress.AddText(font, size, ImVec2(lo.x + pad, lo.y + 2.0f * pad + first.y), IM_COL32(170, 174, 180, 255), note.c_str());
        // An indeterminate bar: a segment sweeping the track once a second.
        const ImVec2 track(lo.x + pad, hi.y - pad - barHeight), trackEnd(hi.x - pad, hi.y - pad);
        const float span = trackEnd.x - track.x, segment = 0.25f * span;
        const float phase = static_cast<float>(std::fmod(job_.elapsedSeconds(), 1.0));
        const float x0 = track.x + phase * (span + segment) - segment;
        progress.AddRectFilled(track, trackEnd, IM_COL32(60, 63, 70, 255));
        progress.AddRectFilled(ImVec2(std::max(track.x, x0), track.y), ImVec2(std::min(trackEnd.x, x0 + segment), trackEnd.y),
                               IM_COL32(66, 150, 250, 255));
    }
    std::vector<ImDrawList*> lists = lastUi_;
    if (!progress.VtxBuffer.empty()) lists.push_back(&progress);
    ImDrawData data;
    data.Valid = true;
    data.CmdLists = lists.data();
    data.CmdListsCount = static_cast<int>(lists.size());
    for (const ImDrawList* list : lists) {
        data.TotalVtxCount += list->VtxBuffer.Size;
        data.TotalIdxCount += list->IdxBuffer.Size;
    }
    data.DisplayPos = lastUiPos_;
    data.DisplaySize = lastUiSize_;
    data.FramebufferScale = lastUiScale_;
    ImGui_ImplOpenGL3_RenderDrawData(&data);
    return drawn;
}

FrameNeeds SculptApp::frameNeeds() const {
    FrameNeeds needs;
    const auto within = [&needs](double seconds) {
        needs.withinSeconds = needs.withinSeconds > 0.0 ? std::min(needs.withinSeconds, seconds) : seconds;
    };
    if (files_.busy()) within(1.0 / 15.0);
    // An engine step on the worker: its progress moves (the worker wakes the loop when it ends).
    if (job_.running()) within(1.0 / 20.0);
    if (!heldInput_.empty()) within(1.0 / 60.0);  // a step just ended: its frame, then the input that waited
    // Dear ImGui's caret is on for 0.8 s of every 1.2 s.
    if (ImGui::GetCurrentContext() && ImGui::GetIO().WantTextInput) within(0.4);
    return needs;
}

void SculptApp::drawUi() {
    files_.drawMenuBar(state_);
    // Tab is the tool switch, as in Blender: it never walks the keyboard into the panels' fields (a click
    // on a checkbox followed by Tab once put "Max depth" into typing mode, and the next digit changed it).
    ImGui::PushAllowKeyboardFocus(false);
    beginSidebar(state_);
    drawStatsPanel(state_);
    drawOverlaysPanel(state_);
    drawInjectivityPanel(state_);
    drawHistoryPanel(state_);
    endSidebar();
    drawToolsWindow(state_, &files_);
    ImGui::PopAllowKeyboardFocus();
    drawTransformOverlay(state_);
    drawStatusLine(state_);
    files_.drawModals(state_);
}

}  // namespace sculpt::app
