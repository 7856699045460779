// SculptApp's editing tools (tools.h): the mouse and keys of the sculpt tool (grab, handles, pins) and of the
// lattice tool (pick, box-select, drag and pin control points). Navigation, files and undo stay in sculpt_app.cpp.
#include <algorithm>
#include <cstdio>
#include <string>

#include <glm/glm.hpp>

#include "app/window/lattice_commands.h"
#include "app/window/picking.h"
#include "app/window/sculpt_app.h"
#include "app/window/tool_commands.h"
#include "app/window/tspline_commands.h"
#include "app/window/wording.h"
#include "render/palette.h"

namespace sculpt::app {
namespace {

constexpr double kPickRadius = 9.0;  // pixels (times the pixel scale) around a marker that grab it

// The drag plane's normal. note: from the camera's angles, not eye() - target, which at 1e7 from the origin
// would carry the rounding of both.
Eigen::Vector3d towardsEye(const render::Camera& camera) {
    const glm::dvec3 d = camera.towardEye();
    return Eigen::Vector3d(d.x, d.y, d.z);
}

// Lattice parameters of a surface point: the lattice's own inverse where it converges, otherwise the
// barycentric mix of the corners' parameters (exact while the lattice is at rest). False outside the lattice.
bool surfaceParameters(const core::Session& session, const SurfaceHandle& handle, const Eigen::Vector3d& world,
                       Eigen::Vector3d& params) {
    if (session.cage().parametersOfCurrentPoint(world, params)) return true;
    params.setZero();
    for (int c = 0; c < 3; ++c) {
        Eigen::Vector3d corner;
        if (!session.parametersOfVertex(session.mesh().triangles(handle.triangle, c), corner)) return false;
        params += handle.barycentric[c] * corner;
    }
    return true;
}

}  // namespace

double SculptApp::pickRadius() const { return kPickRadius * static_cast<double>(renderer_.pixelScale()); }

int SculptApp::controlPointUnderCursor(const Positions& points, double x, double y) const {
    // Markers closer than a marker's size overlap on screen: there a free point wins, then the front one (tools.h).
    const double overlap = render::kControlPointSize * static_cast<double>(renderer_.pixelScale());
    return controlPointAtPixel(points, shownControlPoints(state_), state_.camera, state_.framebufferWidth,
                               state_.framebufferHeight, x, y, pickRadius(), state_.session.lattice().pinned, overlap);
}

// ---- commands shared with the panels (tool_commands.h) ------------------------------------------------------

void setToolMode(AppState& state, ToolMode mode) {
    if (state.drag.active || state.tools.mode == mode) return;
    state.tools.mode = mode;
    state.tools.lattice.boxActive = false;
    state.gpu.fields = true;
    setStatus(state, mode == ToolMode::Lattice
                         ? "Lattice tool: click selects, Shift+click toggles, drag a box to select several, drag a point "
                           "to move the selection, P pins. Tab: sculpt."
                         : "Sculpt tool: drag the mesh. Shift+click places a handle, Ctrl+click a pin. Tab: lattice tool.",
              false);
}

void clampLatticeSelection(AppState& state) {
    std::vector<int>& selection = state.tools.lattice.points;
    const int count = state.session.lattice().controlPointCount();
    selection.erase(std::remove_if(selection.begin(), selection.end(), [count](int id) { return id < 0 || id >= count; }),
                    selection.end());
}

void describeLatticeSelection(AppState& state) {
    clampLatticeSelection(state);
    const std::vector<int>& points = state.tools.lattice.points;
    if (points.empty()) {
        setStatus(state, "No control point selected.", false);
        return;
    }
    size_t pinned = 0;
    for (int id : points) pinned += state.session.lattice().pinned[static_cast<size_t>(id)] ? 1 : 0;
    std::string text = countOf(points.size(), "control point") + " selected";
    if (points.size() == 1) {
        const std::array<int, 3> ijk = state.session.lattice().ijk(points.front());
        text += " [" + std::to_string(ijk[0]) + "," + std::to_string(ijk[1]) + "," + std::to_string(ijk[2]) + "]";
    }
    if (pinned > 0) text += ", " + std::to_string(pinned) + " pinned";
    setStatus(state, text + ". Drag one to move them, P pins or unpins.", false);
}

void selectAllControlPoints(AppState& state, bool all) {
    std::vector<int>& points = state.tools.lattice.points;
    points.clear();
    if (all) {
        // note: of a net lattice only the weld groups' representatives (the points drawn), each group once; of a
        // weighted T-spline only the control points of non-empty cells (the others are never shown).
        const core::Lattice& lattice = state.session.lattice();
        const std::vector<std::uint8_t>& heavy = tsplineShownControlPoints(state);
        for (int id = 0; id < lattice.controlPointCount(); ++id)
            if (lattice.representative(id) == id && (heavy.empty() || heavy[static_cast<size_t>(id)])) points.push_back(id);
    }
    state.gpu.fields = true;
    describeLatticeSelection(state);
}

void togglePinsOfSelection(AppState& state) {
    clampLatticeSelection(state);
    const std::vector<int>& points = state.tools.lattice.points;
    if (points.empty()) {
        setStatus(state, "Select control points first (click, Shift+click, or drag a box), then press P.", true);
        return;
    }
    bool allPinned = true;
    for (int id : points) allPinned = allPinned && state.session.lattice().pinned[static_cast<size_t>(id)];
    if (Status s = state.session.pins().set(points, !allPinned); !s) {
        setStatus(state, "Cannot change the pins: " + s.message, true);
        return;
    }
    state.gpu.fields = true;
    setStatus(state, std::string(allPinned ? "Unpinned " : "Pinned ") + countOf(points.size(), "control point") +
                         (allPinned ? "." : ": the solver will not move them."),
              false);
}

void clearHandles(AppState& state) {
    state.tools.handles.clear();
    state.gpu.fields = true;
    setStatus(state, "Handles and pins removed.", false);
}

void setupLatticeCommand(AppState& state, const core::LatticeSettings& settings) {
    if (state.drag.active) return;
    if (Status s = core::validateLatticeSettings(settings); !s) {
        setStatus(state, "Lattice not changed: " + s.message, true);
        return;
    }
    core::OpReport report;
    const Status s = state.session.setupLattice(settings, report);
    if (s && report.status == core::OpStatus::Applied) noteSessionMoved(state);
    reportOperation(state, report, s);
    clampLatticeSelection(state);
    state.gpu.fields = true;
}

// ---- sculpt tool ------------------------------------------------------------------------------------------

void SculptApp::pressSculpt(const MouseButtonEvent& event) {
    core::Session& session = state_.session;
    ToolState& tools = state_.tools;
    if (session.mesh().empty()) return;
    const int width = state_.framebufferWidth, height = state_.framebufferHeight;
    const int handle = handleAtPixel(tools, session.mesh().positions, session.mesh().triangles, state_.camera, width, height,
                                     event.x, event.y, pickRadius());
    const bool shift = event.modifiers.shift, control = event.modifiers.control || event.modifiers.super;
    if (handle >= 0 && (shift || control)) {
        SurfaceHandle& h = tools.handles[static_cast<size_t>(handle)];
        if (shift) {
            const std::string what = h.pin ? "pin" : "handle";  // read before the erase invalidates h
            tools.handles.erase(tools.handles.begin() + handle);
            setStatus(state_, "Removed a " + what + " (" + countOf(tools.handles.size(), "marker") + " left).", false);
        } else {
            h.pin = !h.pin;
            setStatus(state_, h.pin ? "The handle is now a pin: it holds its point while you drag others."
                                    : "The pin is now a handle: drag it to move its point.", false);
        }
        state_.gpu.fields = true;
        return;
    }
    if (handle >= 0) {
        const SurfaceHandle& h = tools.handles[static_cast<size_t>(handle)];
        if (h.pin) {
            setStatus(state_, "Pins hold their point still. Ctrl+click the pin to turn it into a handle, Shift+click removes it.", false);
            return;
        }
        std::vector<int> moving;
        for (size_t i = 0; i < tools.handles.size(); ++i)
            if (!tools.handles[i].pin && (tools.moveHandlesTogether || static_cast<int>(i) == handle))
                moving.push_back(static_cast<int>(i));
        beginSculpt(-1, Eigen::Vector3d::Zero(), handle, moving);
        return;
    }
    Ray ray;
    if (!rayThroughPixel(state_.camera, width, height, event.x, event.y, ray)) return;
    const SurfaceHit hit = intersectMesh(ray, session.mesh().positions, session.mesh().triangles);
    if (hit.triangle < 0) {
        // Nothing to grab there; said, so that a drag begun just off the silhouette is not taken for a stroke
        // (a trial pressed Ctrl+Z after one and undid an earlier stroke).
        setStatus(state_, "Nothing under the cursor to sculpt: start a stroke on the mesh. Middle-drag orbits, the wheel zooms.", false);
        return;
    }
    if (tools.brush.kind != BrushTool::Kind::Drag) {
        // The hammer or crimp at the clicked triangle's corner nearest the hit.
        int corner = 0;
        hit.barycentric.maxCoeff(&corner);
        weightToolCommand(state_, session.mesh().triangles(hit.triangle, corner), brushForDrag(hit.point).radius, control);
        return;
    }
    if (shift || control) {
        SurfaceHandle placed;
        placed.triangle = hit.triangle;
        placed.barycentric = hit.barycentric;
        placed.pin = control;
        Eigen::Vector3d params;
        if (!surfaceParameters(session, placed, hit.point, params)) {
            setStatus(state_, "This point lies outside the lattice: it cannot move, so it needs no pin or handle.", true);
            return;
        }
        tools.handles.push_back(placed);
        state_.gpu.fields = true;
        const size_t pins = pinCount(tools);
        // With "Limit to radius" on a handle's drag is a brush stroke: only pins within its reach hold there.
        setStatus(state_,
                  std::string(control ? "Pin placed" : "Handle placed") + " (" + countOf(tools.handles.size() - pins, "handle") + ", " + countOf(pins, "pin") +
                      "). " +
                      (tools.brush.limited ? std::string("With Limit to radius on its drag is a brush stroke; turn that off to drag the lattice, pins holding.")
                                           : "Drag a handle to move " + std::string(tools.moveHandlesTogether ? "all handles together" : "it alone") +
                                                 " (G toggles); pins hold still."),
                  false);
        return;
    }
    beginSculpt(hit.triangle, hit.barycentric, -1, {});
}

void SculptApp::beginSculpt(int triangle, const Eigen::Vector3d& barycentric, int grabbedHandle, const std::vector<int>& movingHandles) {
    core::Session& session = state_.session;
    const ToolState& tools = state_.tools;
    DragState drag;
    std::vector<Eigen::Vector3d> sources;
    std::vector<bool> held;
    // The grabbed point's brush: with a radius the drag is solved in a region lattice around it, so points
    // outside the cage can be grabbed too; without one, in the cage.
    Eigen::Vector3d grabbedPoint = triangle >= 0 ? handlePosition(SurfaceHandle{triangle, barycentric, false}, session.mesh().positions, session.mesh().triangles)
                                                 : Eigen::Vector3d(handlePosition(tools.handles[static_cast<size_t>(grabbedHandle)], session.mesh().positions, session.mesh().triangles));
    const core::BrushSettings brush = brushForDrag(grabbedPoint);
    // The constraint list: the grabbed surface point (if any) first, then every handle and pin; those not
    // moving with the cursor are held where they are (seed 000 Fig. 3-4: fixed points are constraints too).
    auto add = [&](const SurfaceHandle& h, bool moving, int handleIndex) {
        const Eigen::Vector3d world = handlePosition(h, session.mesh().positions, session.mesh().triangles);
        Eigen::Vector3d t;
        if (!brush.active() && !surfaceParameters(session, h, world, t)) return false;
        if (moving) drag.moving.push_back(static_cast<int>(sources.size()));
        sources.push_back(world);
        held.push_back(!moving);
        drag.constraintHandles.push_back(handleIndex);
        return true;
    };
    if (triangle >= 0) {
        SurfaceHandle grabbed;
        grabbed.triangle = triangle;
        grabbed.barycentric = barycentric;
        if (!add(grabbed, true, -1)) {
            // A collar point (a stroke pulled it out of the cage's box): carried by the cage, but no drag is solved there.
            setStatus(state_, session.cage().carriesCollar()
                                  ? "Cannot grab this point without a radius: a stroke pulled it out of the lattice's box, which carries it "
                                    "along but solves drags only inside. Turn on Limit to radius (the brush), or set up a lattice around the mesh as it is now."
                                  : "Cannot grab this point: it lies outside the lattice.",
                      true);
            return;
        }
        int corner = 0;
        barycentric.maxCoeff(&corner);
        drag.pickedVertex = session.mesh().triangles(triangle, corner);
    }
    for (size_t i = 0; i < tools.handles.size(); ++i) {
        const bool moving = std::find(movingHandles.begin(), movingHandles.end(), static_cast<int>(i)) != movingHandles.end();
        if (!add(tools.handles[i], moving, static_cast<int>(i)) && moving) {
            setStatus(state_, "Cannot drag this handle: it lies outside the lattice.", true);
            return;
        }
    }
    if (Status s = session.stroke().beginAt(sources, held, brush); !s) {
        setStatus(state_, "Cannot grab this point: " + s.message, true);
        return;
    }
    drag.active = true;
    drag.kind = DragKind::Surface;
    drag.before = session.mesh().positions;
    drag.starts = session.stroke().userSources();
    drag.brushRadius = brush.radius;
    const int grabbedConstraint = triangle >= 0 ? 0
        : static_cast<int>(std::find(drag.constraintHandles.begin(), drag.constraintHandles.end(), grabbedHandle) - drag.constraintHandles.begin());
    drag.grabbedConstraint = grabbedConstraint;
    drag.planePoint = drag.starts[static_cast<size_t>(grabbedConstraint)];
    drag.planeNormal = towardsEye(state_.camera);
    drag.target = drag.planePoint;
    drag.targets = drag.starts;
    state_.drag = drag;
    state_.gpu.fields = true;
    const size_t heldCount = drag.starts.size() - drag.moving.size();
    std::string text = triangle >= 0 ? "Dragging vertex " + std::to_string(drag.pickedVertex)
                                     : "Dragging " + countOf(drag.moving.size(), "handle");
    if (heldCount > 0) text += " (" + countOf(heldCount, "point") + " held)";
    setStatus(state_, text + "...", false);
}

void SculptApp::updateSculpt(double x, double y) {
    DragState& drag = state_.drag;
    Ray ray;
    Eigen::Vector3d cursor;
    if (!rayThroughPixel(state_.camera, state_.framebufferWidth, state_.framebufferHeight, x, y, ray) ||
        !intersectPlane(ray, drag.planePoint, drag.planeNormal, cursor))
        return;
    drag.target = cursor;
    const Eigen::Vector3d offset = cursor - drag.planePoint;
    drag.targets = drag.starts;
    for (int c : drag.moving) drag.targets[static_cast<size_t>(c)] += offset;
    core::OpReport report;
    const Status s = drag.kind == DragKind::Surface ? state_.session.stroke().update(drag.targets, report)
                                                    : state_.session.stroke().updateControl(offset, report);
    ++drag.moves;
    if (s && report.status == core::OpStatus::Applied) noteSessionMoved(state_);
    if (!s || report.status == core::OpStatus::Rejected) ++drag.refused;
    const bool stopped = s && report.status == core::OpStatus::Applied && report.fractionApplied < 1.0;
    if (stopped) ++drag.stoppedShort;
    if (!s || report.status == core::OpStatus::Rejected || stopped) {
        const std::string& by = report.refusedBy;
        ++(by == "lattice"       ? drag.byFold
           : by == "uncertified" ? drag.byUncertified
           : by == "triangles"   ? drag.byCrossing
           : by == "boundary"    ? drag.byBoundary
           : by == "symmetry"    ? drag.byMirror
                                 : drag.byOther);
    }
    // A brush stroke's move: its counts are this move's, the stroke's whole are said when it ends (a trial read
    // "1451 vertices moved" during a stroke that ended "815 vertices moved").
    reportOperation(state_, report, s,
                    drag.kind == DragKind::Control ? "Moving " + countOf(drag.controlPoints.size(), "control point")
                    : drag.brushRadius > 0.0       ? std::string("This move")
                                                   : std::string());
    state_.gpu.fields = true;
}

void SculptApp::endSculpt() {
    // note: the journal, not the history's size: after an undo a new entry replaces the redo branch.
    const size_t before = state_.session.history().journal().size();
    state_.session.stroke().end();
    const DragState finished = state_.drag;
    state_.drag = DragState{};
    state_.gpu.fields = true;
    updateBrushHover(state_.cursorX, state_.cursorY);  // the circle goes back under the cursor
    const bool recorded = state_.session.history().journal().size() > before;
    if (finished.moves == 0) return;  // a click (selecting, placing): its own message stays
    // With symmetry, the mirror images were pulled too: said, as the history entry says it.
    const core::Symmetry& symmetry = state_.tools.brush.settings.symmetry;
    const std::string mirrored = symmetry.any() ? "symmetric in " + core::symmetryText(symmetry, true) + ", " : std::string();
    std::string text = recorded ? "Drag recorded as one undo step (" + mirrored + countOf(static_cast<size_t>(finished.moves), "move")
                                : "Drag changed nothing (" + mirrored + countOf(static_cast<size_t>(finished.moves), "move");
    // The vertices the whole drag moved (bitwise, as undo counts them; a refinement that added vertices: the
    // ones the mesh had).
    const Positions& now = state_.session.mesh().positions;
    if (recorded && finished.before.rows() > 0 && finished.before.rows() <= now.rows()) {
        size_t changed = 0;
        for (Eigen::Index v = 0; v < finished.before.rows(); ++v) changed += finished.before.row(v) != now.row(v);
        text += ", " + countOf(changed, "vertex", "vertices") + " moved";
        // A long pull split the triangles under it (Split under the brush): the vertices it added.
        if (now.rows() > finished.before.rows())
            text += ", " + countOf(static_cast<size_t>(now.rows() - finished.before.rows()), "vertex", "vertices") + " added where it split the mesh";
    }
    // What stopped the moves that did not go all the way, each named as what it is.
    std::vector<std::string> parts;
    if (finished.stoppedShort > 0) parts.push_back(std::to_string(finished.stoppedShort) + " stopped short");
    if (finished.refused > 0) parts.push_back(std::to_string(finished.refused) + " refused");
    if (!parts.empty()) {
        std::vector<std::string> causes;
        // note: the words of stopCauseWords, as the status of each move and of a transform say them.
        // (a brush stroke's lattice is the brush's own region: the mesh would fold, as each move's status says)
        if (finished.byFold > 0)
            causes.push_back(std::to_string(finished.byFold) + " where " +
                             (finished.brushRadius > 0.0 ? std::string("the mesh would fold over itself") : stopCauseWords("lattice")));
        if (finished.byUncertified > 0) causes.push_back(std::to_string(finished.byUncertified) + " where " + stopCauseWords("uncertified"));
        if (finished.byCrossing > 0) causes.push_back(std::to_string(finished.byCrossing) + " where " + stopCauseWords("triangles"));
        if (finished.byBoundary > 0) causes.push_back(std::to_string(finished.byBoundary) + " where " + stopCauseWords("boundary"));
        if (finished.byMirror > 0) causes.push_back(std::to_string(finished.byMirror) + " where the grabbed point would meet its mirror image");
        if (finished.byOther > 0) causes.push_back(std::to_string(finished.byOther) + " for another reason");
        text += ", " + parts[0] + (parts.size() > 1 ? " and " + parts[1] : std::string());
        for (size_t c = 0; c < causes.size(); ++c) text += (c == 0 ? ": " : ", ") + causes[c];
    }
    text += ").";
    // The last move is where the stroke ends: how far it went, if not all the way.
    if (state_.hasReport && state_.lastReport.status == core::OpStatus::Applied && state_.lastReport.fractionApplied < 1.0) {
        char share[96];
        std::snprintf(share, sizeof share, " The last move went %.0f%% of the way to the cursor.", 100.0 * state_.lastReport.fractionApplied);
        text += share;
    }
    if (const int outside = state_.session.stroke().verticesOutsideCage(); recorded && outside > 0)
        text += " " + countOf(static_cast<size_t>(outside), "vertex", "vertices") + " of the stroke now " + (outside == 1 ? "lies" : "lie") +
                " outside the lattice's box: later lattice edits do not carry " + (outside == 1 ? "it" : "them") +
                " (Lattice set-up with more padding takes them in).";
    else if (const int left = recorded && finished.brushRadius == 0.0 ? state_.session.verticesLeftOutsideCage() : 0; left > 0)
        text += " " + countOf(static_cast<size_t>(left), "vertex", "vertices") + " outside the lattice's box stayed where " +
                (left == 1 ? "it was" : "they were") + " while the surface next to " + (left == 1 ? "it" : "them") +
                " moved: the lattice moves only what lies in its box (Lattice set-up with more padding takes them in).";
    if (finished.refused > 0 && state_.hasReport && state_.lastReport.status == core::OpStatus::Rejected) {
        std::string why = state_.lastReport.reason.empty() ? state_.lastReport.injectivity : state_.lastReport.reason;
        if (why.rfind("refused: ", 0) == 0) why.erase(0, 9);  // "Last move refused: refused: ..." said it twice
        text += " Last move refused: " + why;
    }
    setStatus(state_, text, finished.refused > 0 && !recorded);
}

void SculptApp::cancelSculpt() {
    core::OpReport report;
    const Status s = state_.session.stroke().cancel(report);
    if (s && report.status == core::OpStatus::Applied) noteSessionMoved(state_);
    state_.drag = DragState{};
    state_.gpu.fields = true;
    if (!s) setStatus(state_, "Cannot cancel the drag: " + s.message, true);
    else setStatus(state_, "Drag cancelled (Esc): everything is as it was before it.", false);
}

// ---- lattice tool -----------------------------------------------------------------------------------------

void SculptApp::pressLattice(const MouseButtonEvent& event) {
    core::Session& session = state_.session;
    if (session.mesh().empty()) return;
    clampLatticeSelection(state_);
    LatticeSelection& selection = state_.tools.lattice;
    const Positions points = session.cage().cagePoints();
    const int hit = controlPointUnderCursor(points, event.x, event.y);
    const bool shift = event.modifiers.shift;
    if (hit < 0) {  // on empty space: a selection rectangle
        selection.boxActive = true;
        selection.boxAdditive = shift;
        selection.boxX0 = selection.boxX1 = event.x;
        selection.boxY0 = selection.boxY1 = event.y;
        return;
    }
    const bool wasSelected = std::binary_search(selection.points.begin(), selection.points.end(), hit);
    if (shift) {
        toggleInSelection(selection.points, hit);
        state_.gpu.fields = true;
        describeLatticeSelection(state_);
        if (wasSelected) return;  // Shift+click on a selected point only deselects it
    } else if (!wasSelected) {
        selection.points = {hit};
        state_.gpu.fields = true;
    }
    std::vector<int> movable;
    for (int id : selection.points)
        if (!session.lattice().pinned[static_cast<size_t>(id)]) movable.push_back(id);
    if (movable.empty()) {
        // Selecting a pinned point is what P needs: said, not an error.
        setStatus(state_, selection.points.size() == 1
                              ? "Selected control point " + session.lattice().controlPointName(selection.points.front()) +
                                    ": it is pinned and holds still; P unpins it."
                              : "The selected control points are all pinned and hold still; P unpins them.",
                  false);
        return;
    }
    if (Status s = session.stroke().beginControl(movable); !s) {
        setStatus(state_, "Cannot move the control points: " + s.message, true);
        return;
    }
    DragState drag;
    drag.active = true;
    drag.kind = DragKind::Control;
    drag.before = session.mesh().positions;
    drag.planePoint = points.row(hit).transpose();
    drag.planeNormal = towardsEye(state_.camera);
    drag.target = drag.planePoint;
    drag.controlPoints = movable;
    state_.drag = drag;
    state_.gpu.fields = true;
    // note: nothing has moved yet (a click only selects): "Moving" is said by updateSculpt, once it moves.
    const size_t pinned = selection.points.size() - movable.size();
    std::string text;
    if (selection.points.size() == 1) {
        text = "Selected control point " + session.lattice().controlPointName(selection.points.front()) + " - drag to move it, G to grab.";
    } else {
        text = "Selected " + countOf(selection.points.size(), "control point") + " - drag one to move them, G to grab" +
               (pinned > 0 ? " (" + countOf(pinned, "pinned point") + (pinned == 1 ? " stays)." : " stay).") : std::string("."));
    }
    setStatus(state_, text, false);
}

void SculptApp::finishBoxSelection() {
    LatticeSelection& selection = state_.tools.lattice;
    selection.boxActive = false;
    const bool click = std::abs(selection.boxX1 - selection.boxX0) < 3.0 && std::abs(selection.boxY1 - selection.boxY0) < 3.0;
    if (click) {
        if (!selection.boxAdditive && !selection.points.empty()) {
            selection.points.clear();
            setStatus(state_, "Selection cleared.", false);
        }
    } else {
        const std::vector<int> inside = controlPointsInRectangle(
            state_.session.cage().cagePoints(), shownControlPoints(state_), state_.camera, state_.framebufferWidth,
            state_.framebufferHeight, selection.boxX0, selection.boxY0, selection.boxX1, selection.boxY1);
        if (!selection.boxAdditive) selection.points.clear();
        addToSelection(selection.points, inside);
        describeLatticeSelection(state_);
    }
    state_.gpu.fields = true;
}

// ---- shared -----------------------------------------------------------------------------------------------

void SculptApp::moveTool(double x, double y) {
    LatticeSelection& selection = state_.tools.lattice;
    if (state_.drag.active) {
        updateSculpt(x, y);
        return;
    }
    if (selection.boxActive) {
        selection.boxX1 = x;
        selection.boxY1 = y;
        return;
    }
    updateBrushHover(x, y);
    updateHint(x, y);  // after the circle: off the mesh the hint says a drag sculpts nothing
}

void SculptApp::updateHint(double x, double y) {
    const core::Session& session = state_.session;
    ToolState& tools = state_.tools;
    tools.lattice.hovered = -1;
    if (session.mesh().empty() || state_.navigation != Navigation::None) {
        tools.hint.clear();
        return;
    }
    const int width = state_.framebufferWidth, height = state_.framebufferHeight;
    if (tools.mode == ToolMode::Sculpt && tools.brush.resize != BrushTool::Resize::None) {
        // F or Shift+F is resizing the brush (a trial read "Drag: sculpt ..." here while resizing).
        tools.hint = "Click or Enter: keep it. Esc or right click: put it back.";
        return;
    }
    if (tools.mode == ToolMode::Sculpt) {
        const int handle = handleAtPixel(tools, session.mesh().positions, session.mesh().triangles, state_.camera, width, height, x, y, pickRadius());
        if (handle >= 0 && tools.handles[static_cast<size_t>(handle)].pin)
            tools.hint = "Pin: holds its point. Ctrl+click: make it a handle. Shift+click: remove.";
        else if (handle >= 0 && tools.brush.limited)
            tools.hint = "Handle: a drag is a brush stroke (Limit to radius is on). Ctrl+click: pin. Shift+click: remove.";
        else if (handle >= 0)
            tools.hint = std::string("Handle: drag to move ") + (tools.moveHandlesTogether ? "all handles" : "it") +
                         " (G). Ctrl+click: make it a pin. Shift+click: remove.";
        else if (state_.tspline.picking)
            tools.hint = "Click: choose the cell there (again: drop it). Esc: done choosing.";
        else if (tools.brush.kind == BrushTool::Kind::Hammer)
            tools.hint = "Click: raise the surface there by the step. Ctrl+click: lower it. Tab: lattice tool.";
        else if (tools.brush.kind == BrushTool::Kind::Crimp)
            tools.hint = "Click: broaden the bump there, height kept. Ctrl+click: sharpen it. Tab: lattice tool.";
        else if (tools.brush.limited && !tools.brush.hover)
            // Off the mesh (the brush circle finds no surface under the cursor) a drag sculpts nothing.
            tools.hint = "Off the mesh: a drag here sculpts nothing. Middle-drag: orbit. Wheel: zoom.";
        else
            tools.hint = std::string(tools.brush.limited ? "Drag: sculpt within the brush radius (F: radius)."
                                                         : "Drag: deform with the whole lattice (\"Limit to radius\" is off).") +
                         " Shift+click: add handle. Ctrl+click: add pin. Tab: lattice tool.";
    } else {
        // note: the hover test projects every control point; at 64^3 that is ~2 ms, acceptable for a hint.
        const Positions points = session.cage().cagePoints();
        const int hit = controlPointUnderCursor(points, x, y);
        tools.lattice.hovered = hit;
        if (hit >= 0) tools.lattice.hoveredAt = points.row(hit).transpose();
        const bool pinned = hit >= 0 && session.lattice().pinned[static_cast<size_t>(hit)];
        tools.hint = hit >= 0 ? "Control point " + session.lattice().controlPointName(hit) +
                                    (pinned ? " (pinned): click selects, P unpins." : ": click selects, Shift+click toggles, drag moves the selection, P pins.")
                              : "Drag: box select (Shift adds). Click: clear selection. A: select all. Tab: sculpt tool.";
    }
}

void SculptApp::releaseTool() {
    if (state_.drag.active && state_.drag.kind != DragKind::Transform) endSculpt();
    if (state_.tools.lattice.boxActive) finishBoxSelection();
}

bool SculptApp::keyTool(const KeyEvent& event) {
    const Modifiers& m = event.modifiers;
    const bool shortcut = m.control || m.super;
    if (state_.drag.active && event.key == Key::Escape && event.action == KeyAction::Press) {
        cancelSculpt();
        return true;
    }
    if (state_.lattices.placing != LatticesPanelState::Placing::None && event.key == Key::Escape && event.action == KeyAction::Press) {
        cancelPlacingLattice(state_);  // the Lattices panel's "Place" waited for a click
        return true;
    }
    if (state_.tspline.picking && event.key == Key::Escape && event.action == KeyAction::Press) {
        endChoosingCells(state_);  // the T-spline section's "Choose cells" took the clicks
        return true;
    }
    if (brushKey(event)) return true;  // F / Shift+F: brush radius and strength (sculpt tool)
    if (state_.drag.active || event.action != KeyAction::Press) return false;
    ToolState& tools = state_.tools;
    switch (event.key) {
        case Key::Tab:
            if (shortcut) return false;
            setToolMode(state_, tools.mode == ToolMode::Sculpt ? ToolMode::Lattice : ToolMode::Sculpt);
            return true;
        case Key::G:
        case Key::R:
        case Key::S:
            if (shortcut || state_.navigation != Navigation::None) return false;
            if (tools.mode == ToolMode::Lattice) {  // Blender's grab, rotate, scale (transform_tool.h)
                beginTransform(state_, event.key == Key::G ? TransformKind::Move
                                       : event.key == Key::R ? TransformKind::Rotate : TransformKind::Scale,
                               state_.cursorX, state_.cursorY);
                return true;
            }
            if (event.key != Key::G) return false;
            tools.moveHandlesTogether = !tools.moveHandlesTogether;
            setStatus(state_, tools.moveHandlesTogether ? "Dragging a handle moves all handles together."
                                                        : "Dragging a handle moves it alone; the others hold.", false);
            return true;
        case Key::P:
            if (shortcut || tools.mode != ToolMode::Lattice) return false;
            togglePinsOfSelection(state_);
            return true;
        case Key::A:
            if (tools.mode != ToolMode::Lattice) return false;
            selectAllControlPoints(state_, !m.alt);
            return true;
        case Key::Escape:
        case Key::Delete:
        case Key::Backspace:
            if (shortcut) return false;
            if (tools.mode == ToolMode::Lattice) {
                tools.lattice.boxActive = false;
                tools.lattice.points.clear();
                setStatus(state_, "Selection cleared.", false);
            } else {
                if (tools.handles.empty()) return false;
                clearHandles(state_);
            }
            state_.gpu.fields = true;
            return true;
        default:
            return false;
    }
}

render::ConstraintView SculptApp::constraintView() const {
    render::ConstraintView view;
    const core::Session& session = state_.session;
    const ToolState& tools = state_.tools;
    const DragState& drag = state_.drag;
    if (session.mesh().empty()) return view;
    std::vector<Eigen::Vector3d> sources, targets, handles, pins;
    std::vector<bool> drawn(tools.handles.size(), false);
    // The brush circle: on the surface under the cursor, or around the grabbed point while dragging.
    const auto circle = [](const Eigen::Vector3d& centre, const Eigen::Vector3d& normal, double radius) {
        const Eigen::Vector3d u = normal.unitOrthogonal(), v = normal.cross(u).normalized();
        constexpr int kSegments = 64;
        Positions loop(kSegments, 3);
        for (int k = 0; k < kSegments; ++k) {
            const double angle = 2.0 * 3.14159265358979323846 * k / kSegments;
            loop.row(k) = (centre + radius * (std::cos(angle) * u + std::sin(angle) * v)).transpose();
        }
        return loop;
    };
    // With symmetry, the circle's mirror images too (in the session's mirror planes), so the user sees where the
    // mirrored stroke will pull: a trial looked for the mirror image of a stroke and could not find it.
    // (`facing`: the circles face the eye, as while dragging; otherwise each lies on the mirrored surface)
    const auto withMirrors = [&](const Eigen::Vector3d& centre, const Eigen::Vector3d& normal, double radius, bool facing) {
        // The stroke's own mirroring (mirrorConstraints): the centre first (mask 0), then each image, an image
        // on the circle's centre itself (the grabbed point on a plane) drawn once.
        const core::SymmetryFrame frame = session.symmetryFrame();
        const std::vector<core::MirroredConstraint> images = core::mirrorConstraints({centre}, {}, tools.brush.settings.symmetry, frame, 1e-3 * radius);
        std::vector<Positions> loops;
        for (const core::MirroredConstraint& image : images)
            loops.push_back(circle(image.source, facing ? normal : core::reflectVector(normal, image.images.front().second, frame), radius));
        Positions all(static_cast<Eigen::Index>(loops.size()) * loops.front().rows(), 3);
        for (size_t k = 0; k < loops.size(); ++k) all.middleRows(static_cast<Eigen::Index>(k) * loops.front().rows(), loops.front().rows()) = loops[k];
        view.outlineLoop = static_cast<int>(loops.front().rows());
        view.outline = std::move(all);
    };
    if (tools.mode == ToolMode::Sculpt && drag.active && drag.kind == DragKind::Surface && drag.brushRadius > 0.0) {
        const std::vector<Eigen::Vector3d> current = session.stroke().userSources();
        const glm::dvec3 eye = state_.camera.towardEye();
        if (static_cast<size_t>(drag.grabbedConstraint) < current.size())
            withMirrors(current[static_cast<size_t>(drag.grabbedConstraint)], Eigen::Vector3d(eye.x, eye.y, eye.z), drag.brushRadius, true);
    } else if (tools.mode == ToolMode::Sculpt && !drag.active && tools.brush.hover && tools.brush.hoverRadius > 0.0) {
        withMirrors(tools.brush.hoverPoint, tools.brush.hoverNormal, tools.brush.hoverRadius, false);
    }
    if (drag.active && drag.kind == DragKind::Surface) {
        const std::vector<Eigen::Vector3d> current = session.stroke().userSources();
        for (size_t c = 0; c < current.size() && c < drag.targets.size(); ++c) {
            const int handle = drag.constraintHandles[c];
            const bool moving = std::find(drag.moving.begin(), drag.moving.end(), static_cast<int>(c)) != drag.moving.end();
            if (moving) {
                sources.push_back(current[c]);
                targets.push_back(drag.targets[c]);
            } else if (handle >= 0 && tools.handles[static_cast<size_t>(handle)].pin) {
                pins.push_back(current[c]);
            } else {
                handles.push_back(current[c]);
            }
            if (handle >= 0) drawn[static_cast<size_t>(handle)] = true;
        }
    }
    for (size_t i = 0; i < tools.handles.size(); ++i) {
        if (drawn[i]) continue;
        const Eigen::Vector3d p = handlePosition(tools.handles[i], session.mesh().positions, session.mesh().triangles);
        (tools.handles[i].pin ? pins : handles).push_back(p);
    }
    auto toRows = [](const std::vector<Eigen::Vector3d>& points) {
        Positions rows(static_cast<Eigen::Index>(points.size()), 3);
        for (size_t i = 0; i < points.size(); ++i) rows.row(static_cast<Eigen::Index>(i)) = points[i].transpose();
        return rows;
    };
    view.sources = toRows(sources);
    view.targets = toRows(targets);
    view.handles = toRows(handles);
    view.pins = toRows(pins);
    appendTransformGuides(state_, view);
    return view;
}

}  // namespace sculpt::app
