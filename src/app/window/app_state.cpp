#include "app/window/app_state.h"

#include <algorithm>
#include <utility>

#include "app/window/tspline_commands.h"
#include "app/window/wording.h"
#include "core/tspline/tspline_view.h"
#include "render/overlay_geometry.h"

namespace sculpt::app {

Status setMesh(AppState& state, const Positions& positions, const Triangles& triangles, const std::string& name,
               const core::LatticeSettings& settings) {
    if (Status s = state.session.setMesh(positions, triangles, settings); !s) return s;
    installSession(state, std::move(state.session), name);
    return Status::success();
}

void installSession(AppState& state, core::Session&& session, const std::string& name) {
    if (&session != &state.session) state.session = std::move(session);
    const Positions& positions = state.session.mesh().positions;
    const Triangles& triangles = state.session.mesh().triangles;
    state.meshName = name;
    state.gpu = PendingGpuUpdate{};
    state.drag = DragState{};
    state.tools.handles.clear();  // they name triangles of the old mesh
    state.tools.lattice = LatticeSelection{};
    state.tools.setupEdited = false;
    state.hasReport = false;
    state.stats.solveMs = 0.0;  // the last mesh's command is not this one's
    state.session.setTrackJacobian(state.overlays.jacobian);
    frameMesh(state);
    setStatus(state, "Loaded " + name + ": " + std::to_string(positions.rows()) + " vertices, " +
                         std::to_string(triangles.rows()) + " triangles.", false);
}

void noteSessionMoved(AppState& state) {
    const core::Session& session = state.session;
    if (session.lastMoved().all) {
        state.gpu.allPositions = true;
        state.gpu.vertices.clear();
    } else if (!state.gpu.allPositions) {
        const std::vector<int>& moved = session.lastMoved().vertices;
        state.gpu.vertices.insert(state.gpu.vertices.end(), moved.begin(), moved.end());
        // note: many small drag moves between two frames could pile up duplicates; past #V the full upload
        // is cheaper than the list anyway.
        if (state.gpu.vertices.size() > static_cast<size_t>(session.mesh().positions.rows())) {
            state.gpu.allPositions = true;
            state.gpu.vertices.clear();
        }
    }
    state.gpu.fields = true;
}

void setStatus(AppState& state, const std::string& text, bool isError) {
    state.status = text;
    state.statusIsError = isError;
    state.statusDetails.clear();
}

void reportOperation(AppState& state, const core::OpReport& report, const Status& status, const std::string& named) {
    state.hasReport = true;
    state.lastReport = report;
    state.stats.solveMs = report.wallMs;
    // In the user's words: what was done, then what happened.
    const std::string what = !named.empty() ? named : commandWords(report.op);
    if (!status) {
        setStatus(state, what + " failed: " + status.message, true);
        return;
    }
    std::string text;
    if (report.status == core::OpStatus::Rejected) {
        text = what + ": " + (report.reason.empty() ? report.injectivity : report.reason);
    } else if (report.status == core::OpStatus::NoOp) {
        text = what + ": nothing to do" + (report.reason.empty() ? "" : " (" + report.reason + ")");
    } else {
        // A command that changes the lattice, the pins or the history only moves no vertex: said so, not "0 moved".
        // A stroke's move past where it stopped holds the surface there: said so, not "done".
        const bool held = (report.op == "drag" || report.op == "drag_vertex") && report.fractionApplied < 1.0;
        text = what + ": " + (report.verticesMoved > 0 ? countOf(static_cast<size_t>(report.verticesMoved), "vertex", "vertices") + " moved"
                              : held                   ? std::string("held where the stroke stopped, no vertex moved")
                                                       : std::string("done, no vertex moved"));
        // A stroke's move that split the mesh under its pull: the vertices it added, apart from those it moved.
        if ((report.op == "drag" || report.op == "drag_vertex") && report.verticesAdded > 0)
            text += ", " + countOf(static_cast<size_t>(report.verticesAdded), "vertex", "vertices") + " added where it split the mesh";
        // Undo and redo of a stroke that split the mesh (or of a refinement): the vertices taken away or put back.
        if ((report.op == "undo" || report.op == "redo") && report.verticesRemoved > 0)
            text += ", " + countOf(static_cast<size_t>(report.verticesRemoved), "vertex", "vertices") + " removed where it split the mesh";
        if ((report.op == "undo" || report.op == "redo") && report.verticesAdded > 0)
            text += ", " + countOf(static_cast<size_t>(report.verticesAdded), "vertex", "vertices") + " added again where it split the mesh";
        // (an undo or redo takes back or makes again the steps the edit was split into: said by the edit itself)
        if (report.subSteps > 1 && report.op != "undo" && report.op != "redo")
            text += ", split into " + std::to_string(report.subSteps) + " steps so that none folds";
        if (!report.injectivity.empty()) text += ", " + checkWords(report.injectivity, state.session.injectivity().checkTriangles);
        // A move stopped short of where it was asked, or constraints met only as closely as possible: say so.
        if (report.fractionApplied < 1.0 || report.rankDeficient) text += ". " + report.reason;
    }
    if (!text.empty() && text.back() != '.') text += '.';  // a sentence, as every other status message
    setStatus(state, text, report.status == core::OpStatus::Rejected);
}

namespace {

// "Undo brush drag" / "Redo move 8 control points along X by 0.5": the command and the history entry it took
// back or made again (the entry at `index`), or the bare command where there is none.
std::string historyCommandWords(const AppState& state, const char* command, int index) {
    const core::History& history = state.session.history();
    if (index < 0 || index >= static_cast<int>(history.size()) || history[static_cast<size_t>(index)].label.empty()) return command;
    return std::string(command) + " " + history[static_cast<size_t>(index)].label;
}

}  // namespace

void undoCommand(AppState& state) {
    if (state.drag.active) return;  // the drag becomes a history entry on release
    core::OpReport report;
    const Status s = state.session.undo(report);
    if (s && report.status == core::OpStatus::Applied) noteSessionMoved(state);
    const bool undone = s && report.status == core::OpStatus::Applied;
    reportOperation(state, report, s, undone ? historyCommandWords(state, "Undo", state.session.history().cursor()) : std::string());
}

void redoCommand(AppState& state) {
    if (state.drag.active) return;
    core::OpReport report;
    const Status s = state.session.redo(report);
    if (s && report.status == core::OpStatus::Applied) noteSessionMoved(state);
    const bool redone = s && report.status == core::OpStatus::Applied;
    reportOperation(state, report, s, redone ? historyCommandWords(state, "Redo", state.session.history().cursor() - 1) : std::string());
}

void jumpToHistory(AppState& state, int cursor) {
    if (state.drag.active) return;
    cursor = std::clamp(cursor, 0, static_cast<int>(state.session.history().size()));
    // note: each undo/redo is one command; stop at the first that does not move the cursor so a failing
    // step cannot loop forever.
    while (state.session.history().cursor() != cursor) {
        const int before = state.session.history().cursor();
        if (before > cursor) undoCommand(state); else redoCommand(state);
        if (state.session.history().cursor() == before) break;
    }
}

void requestHistoryStep(AppState& state, int step) {
    const int from = state.historyRequest >= 0 ? state.historyRequest : state.session.history().cursor();
    requestHistoryJump(state, from + step);
}

void requestHistoryJump(AppState& state, int cursor) {
    if (state.drag.active) return;
    state.historyRequest = std::clamp(cursor, 0, static_cast<int>(state.session.history().size()));
}

void setInjectivityCommand(AppState& state, const core::InjectivitySettings& settings) {
    state.session.setInjectivity(settings);
    setStatus(state, std::string("Injectivity check: ") + core::injectivityModeName(settings.mode) +
                         ", subdivision depth " + std::to_string(settings.maxDepth) + ".", false);
}

void setOverlays(AppState& state, const Overlays& overlays) {
    if (overlays.jacobian != state.overlays.jacobian) state.session.setTrackJacobian(overlays.jacobian);
    state.overlays = overlays;
    state.gpu.fields = true;
}

ToolOverlays& overlaysOfTool(Overlays& overlays, ToolMode mode) {
    return mode == ToolMode::Lattice ? overlays.latticeTool : overlays.sculpt;
}

const ToolOverlays& overlaysOfTool(const Overlays& overlays, ToolMode mode) {
    return mode == ToolMode::Lattice ? overlays.latticeTool : overlays.sculpt;
}

bool latticeShown(const AppState& state) { return overlaysOfTool(state.overlays, state.tools.mode).lattice; }

bool latticeToolsShown(const AppState& state) {
    const int tools = static_cast<int>(state.session.tools().list().size());
    return state.lattices.showTools && tools > (state.session.tools().frozen() >= 0 ? 1 : 0);
}

std::vector<std::uint8_t> shownControlPoints(const AppState& state) {
    const core::Lattice& lattice = state.session.lattice();
    std::vector<std::uint8_t> shown(static_cast<size_t>(lattice.controlPointCount()), 0);
    if (!latticeShown(state)) return shown;
    if (lattice.volume) {
        // A lattice of any shape: one marker per weld group, on its representative (a click on a welded axis
        // or seam picks the group: the engine moves every copy with it); "outer only" keeps the points on the
        // volume's outer surface. A weighted T-spline: only the control points of non-empty cells (Song & Yang
        // 2005, Fig. 10: the light ones are hidden from the user, selected or not); "outer only" keeps those on
        // the T-lattice's outer faces.
        const std::vector<std::uint8_t>& heavy = tsplineShownControlPoints(state);
        const core::TSplineVolume* tspline = heavy.empty() ? nullptr : core::asTSpline(lattice.volume.get());
        const auto pickable = [&](int id) { return lattice.representative(id) == id && (heavy.empty() || heavy[static_cast<size_t>(id)]); };
        const auto outer = [&](int id) {
            return tspline ? core::anchorOnDomainBoundary(tspline->basis(), id) : lattice.volume->onOuterSurface(id);
        };
        for (int id = 0; id < lattice.controlPointCount(); ++id)
            shown[static_cast<size_t>(id)] = pickable(id) && (!state.overlays.latticeOuterOnly || outer(id));
        for (int id : state.tools.lattice.points)
            if (id >= 0 && id < static_cast<int>(shown.size()) && pickable(id)) shown[static_cast<size_t>(id)] = 1;
        return shown;
    }
    for (int k = 0, id = 0; k < lattice.count[2]; ++k)
        for (int j = 0; j < lattice.count[1]; ++j)
            for (int i = 0; i < lattice.count[0]; ++i, ++id)
                shown[static_cast<size_t>(id)] = !state.overlays.latticeOuterOnly ||
                                                 render::onLatticeBoundary(i, j, k, lattice.count[0], lattice.count[1], lattice.count[2]);
    for (int id : state.tools.lattice.points)
        if (id >= 0 && id < static_cast<int>(shown.size())) shown[static_cast<size_t>(id)] = 1;
    return shown;
}

float framebufferAspect(const AppState& state) {
    if (state.framebufferWidth <= 0 || state.framebufferHeight <= 0) return 1.0f;
    return static_cast<float>(state.framebufferWidth) / static_cast<float>(state.framebufferHeight);
}

void frameMesh(AppState& state) {
    render::Bounds bounds = render::boundsOf(state.session.mesh().positions);
    // With the lattice on screen, its box is framed too (its corners stick out of a round mesh's frame).
    if (latticeShown(state))
        bounds.add(render::boundsOf(state.session.cage().cagePoints()));
    state.camera.frame(bounds, framebufferAspect(state));
}

}  // namespace sculpt::app
