// The T-spline section's commands (Song & Yang 2005, seed 002): sec. 4 / sec. 6 steps 1-3 (setup_tspline),
// sec. 6 step 2 / Fig. 11 (cells chosen on the mesh, subdivide_cells), and what the window draws and picks of
// a T-spline (Fig. 9-10, core/tspline/tspline_view.h). Every change is a script op run through io::runScriptOp.
#include "app/window/tspline_commands.h"

#include <algorithm>
#include <string>

#include "app/window/lattice_commands.h"
#include "app/window/picking.h"
#include "app/window/tool_commands.h"
#include "app/window/tools.h"
#include "io/script.h"
#include "core/tspline/tspline_volume.h"

namespace sculpt::app {
namespace {

const core::TSplineVolume* targetVolume(const AppState& state, int target) {
    const std::vector<core::LatticeTool>& tools = state.session.tools().list();
    return target >= 0 && target < static_cast<int>(tools.size()) ? core::asTSpline(tools[static_cast<size_t>(target)].volume.get()) : nullptr;
}

// "tspline", or "tspline 2", "tspline 3", ... when a tool has that name already.
std::string freshToolName(const AppState& state, const std::string& base) {
    const std::vector<core::LatticeTool>& tools = state.session.tools().list();
    const auto taken = [&](const std::string& name) {
        return std::any_of(tools.begin(), tools.end(), [&](const core::LatticeTool& t) { return t.name == name; });
    };
    if (!taken(base)) return base;
    for (int n = 2;; ++n)
        if (!taken(base + " " + std::to_string(n))) return base + " " + std::to_string(n);
}

std::string cellsText(size_t count) { return std::to_string(count) + (count == 1 ? " cell" : " cells"); }

}  // namespace

bool meshRegion(const AppState& state, Eigen::Vector3d& min, Eigen::Vector3d& max) {
    if (state.session.mesh().empty()) return false;
    Eigen::AlignedBox3d box;
    if (!core::paddedPointBounds(state.session.mesh().positions, core::TSplineOctreeSettings{}.padding, box)) return false;
    min = box.min();
    max = box.max();
    return true;
}

bool regionFromSelection(AppState& state) {
    clampLatticeSelection(state);
    const std::vector<int>& selected = state.tools.lattice.points;
    if (selected.size() < 2) {
        setStatus(state, "Select two or more control points with the lattice tool first (Tab, then click or drag a box): "
                         "the region becomes their bounds.", true);
        return false;
    }
    const Positions points = state.session.cage().cagePoints();
    Eigen::AlignedBox3d box;
    for (int id : selected) box.extend(points.row(id).transpose());
    const double diagonal = box.diagonal().norm();
    if (!(diagonal > 0.0)) {
        setStatus(state, "The selected control points are all at one place: select points that span a box.", true);
        return false;
    }
    // note: grown a little, so mesh vertices on the selection's faces count as inside.
    TSplinePanelState& panel = state.tspline;
    panel.regionMin = box.min().array() - 0.05 * diagonal;
    panel.regionMax = box.max().array() + 0.05 * diagonal;
    panel.customRegion = panel.regionFilled = true;
    setStatus(state, "The T-spline region is the box of the " + std::to_string(selected.size()) + " selected control points.", false);
    return true;
}

void setupTSplineCommand(AppState& state) {
    if (state.drag.active) return;
    const TSplinePanelState& panel = state.tspline;
    io::ScriptOp op;
    op.kind = io::ScriptOp::Kind::SetupTSpline;
    op.tspline.octree.octree.depth = panel.depth;
    op.tspline.octree.weightRatio = panel.weightRatio;
    op.tspline.hasRegion = panel.customRegion;
    op.tspline.regionMin = panel.regionMin;
    op.tspline.regionMax = panel.regionMax;
    op.tspline.name = freshToolName(state, "tspline");
    op.tspline.freeze = true;
    core::OpReport report;
    const Status s = io::runScriptOp(state.session, op, report);
    if (s && report.status == core::OpStatus::Applied) {
        state.tools.lattice.points.clear();  // their ids belonged to the lattice before
        state.lattices.selectedTool = static_cast<int>(state.session.tools().list().size()) - 1;

    }
    reportLatticeOperation(state, report, s, "Set up a weighted T-spline", true);
}

int tsplineTarget(const AppState& state) {
    const int selected = state.lattices.selectedTool;
    if (targetVolume(state, selected)) return selected;
    const int frozen = state.session.tools().frozen();
    return targetVolume(state, frozen) ? frozen : -1;
}

void validateChosenCells(AppState& state) {
    TSplinePanelState& panel = state.tspline;
    const int target = tsplineTarget(state);
    const std::shared_ptr<const core::Volume> volume = target >= 0 ? state.session.tools().list()[static_cast<size_t>(target)].volume : nullptr;
    if (panel.cellsVolume == volume) return;
    if (!panel.chosenCells.empty()) state.gpu.fields = true;
    panel.chosenCells.clear();
    panel.cellsVolume = volume;
}

void beginChoosingCells(AppState& state) {
    validateChosenCells(state);
    const int target = tsplineTarget(state);
    if (target < 0) {
        setStatus(state, "No T-spline lattice to choose cells of: set one up (Set up T-spline) or select one in the list.", true);
        return;
    }
    state.lattices.placing = LatticesPanelState::Placing::None;  // one pending click at a time
    state.tspline.picking = true;
    state.gpu.fields = true;
    setStatus(state, "Click on the mesh to choose the cells of " + state.session.tools().list()[static_cast<size_t>(target)].name +
                         " there (a click on a chosen one drops it); then Subdivide. Esc ends.", false);
}

void endChoosingCells(AppState& state) {
    if (!state.tspline.picking) return;
    state.tspline.picking = false;
    state.gpu.fields = true;
    setStatus(state, "Choosing cells ended: " + cellsText(state.tspline.chosenCells.size()) + " chosen.", false);
}

bool chooseCellAtPixel(AppState& state, double x, double y) {
    TSplinePanelState& panel = state.tspline;
    if (!panel.picking || state.session.mesh().empty()) return false;
    validateChosenCells(state);
    const int target = tsplineTarget(state);
    const core::TSplineVolume* tspline = targetVolume(state, target);
    if (!tspline) {
        panel.picking = false;
        setStatus(state, "The T-spline lattice is gone (undone or removed): choosing cells ended.", true);
        return true;
    }
    Ray ray;
    if (!rayThroughPixel(state.camera, state.framebufferWidth, state.framebufferHeight, x, y, ray)) return true;
    const core::Session& session = state.session;
    const SurfaceHit hit = intersectMesh(ray, session.mesh().positions, session.mesh().triangles);
    if (hit.triangle < 0) {
        setStatus(state, "Click on the mesh to choose the cell there (Esc ends).", true);
        return true;
    }
    // The frozen cage: the parameters the mesh has there, from its rest position (the cage's own space). A tool
    // that is not frozen: the point itself, in the tool at rest where it is drawn.
    Eigen::Vector3d point = hit.point;
    if (target == session.tools().frozen()) {
        point.setZero();
        for (int corner = 0; corner < 3; ++corner)
            point += hit.barycentric[corner] * session.mesh().rest.row(session.mesh().triangles(hit.triangle, corner)).transpose();
    }
    const int cell = core::cellAtRestPoint(*tspline, point);
    const std::string& name = session.tools().list()[static_cast<size_t>(target)].name;
    if (cell < 0) {
        setStatus(state, "The mesh there is outside lattice " + name + ": choose a cell inside it.", true);
        return true;
    }
    const bool dropped = std::binary_search(panel.chosenCells.begin(), panel.chosenCells.end(), cell);
    toggleInSelection(panel.chosenCells, cell);
    state.gpu.fields = true;
    const core::TLatticeCell& c = tspline->lattice().cells[static_cast<size_t>(cell)];
    setStatus(state, std::string(dropped ? "Dropped" : "Chose") + " cell " + std::to_string(cell) + " of " + name + " (level " +
                         std::to_string(c.level) + "): " + cellsText(panel.chosenCells.size()) + " chosen. Subdivide splits them; Esc ends.",
              false);
    return true;
}

void subdivideChosenCellsCommand(AppState& state) {
    if (state.drag.active) return;
    validateChosenCells(state);
    TSplinePanelState& panel = state.tspline;
    const int target = tsplineTarget(state);
    if (target < 0) {
        setStatus(state, "No T-spline lattice to subdivide: set one up first.", true);
        return;
    }
    if (panel.chosenCells.empty()) {
        setStatus(state, "Choose the cells to subdivide first: Choose cells, then click on the mesh.", true);
        return;
    }
    core::Session& session = state.session;
    const std::string name = session.tools().list()[static_cast<size_t>(target)].name;
    const bool frozen = session.tools().frozen() == target;
    const int pinLayers = session.cage().settings().pinLayers;
    // note: the engine subdivides only a tool that is not frozen (the vertices' parameters change), so a frozen
    // one is unfrozen around it. The unfreeze keeps the shape; a refused subdivision takes it back.
    const int firstOperation = session.history().cursor();
    if (frozen) {
        io::ScriptOp unfreeze;
        unfreeze.kind = io::ScriptOp::Kind::Unfreeze;
        core::OpReport report;
        const Status s = io::runScriptOp(session, unfreeze, report);
        state.tools.lattice.points.clear();
        if (!s || report.status != core::OpStatus::Applied) {
            reportOperation(state, report, s, "Unfreezing " + name + " to subdivide it");
            return;
        }
        noteSessionMoved(state);
    }
    io::ScriptOp subdivide;
    subdivide.kind = io::ScriptOp::Kind::SubdivideCells;
    subdivide.toolIndex = target;
    subdivide.cells = panel.chosenCells;
    subdivide.balance = panel.balance;
    core::OpReport subdivided;
    const Status s = io::runScriptOp(session, subdivide, subdivided);
    if (!s || subdivided.status != core::OpStatus::Applied) {
        if (frozen) {
            io::ScriptOp undo;
            undo.kind = io::ScriptOp::Kind::Undo;
            core::OpReport undone;
            if (io::runScriptOp(session, undo, undone) && undone.status == core::OpStatus::Applied) noteSessionMoved(state);
        }
        reportOperation(state, subdivided, s, "Subdividing cells of " + name);
        state.gpu.fields = true;
        return;
    }
    noteSessionMoved(state);
    const size_t count = panel.chosenCells.size();
    panel.chosenCells.clear();
    panel.picking = false;
    if (!frozen) {
        reportLatticeOperation(state, subdivided, s, "Subdivided " + cellsText(count));
        return;
    }
    io::ScriptOp freeze;
    freeze.kind = io::ScriptOp::Kind::Freeze;
    freeze.toolIndex = target;
    freeze.pinLayers = pinLayers;
    core::OpReport refrozen;
    const Status f = io::runScriptOp(session, freeze, refrozen);
    if (!f || refrozen.status != core::OpStatus::Applied) {
        reportOperation(state, refrozen, f, "Subdivided " + cellsText(count) + " of " + name + ", but freezing it again");
        state.gpu.fields = true;
        return;
    }
    // The unfreeze, the subdivision and the freeze are one history entry: one Ctrl+Z takes them back.
    io::ScriptOp group;
    group.kind = io::ScriptOp::Kind::Group;
    group.groupFirst = firstOperation;
    group.label = "subdivide " + cellsText(count) + " of lattice " + name;
    core::OpReport grouped;
    if (const Status g = io::runScriptOp(session, group, grouped); !g) {
        reportOperation(state, grouped, g, "Subdivided " + cellsText(count) + " of " + name + ", but grouping the history");
        return;
    }
    refrozen.reason = subdivided.reason + "; frozen again, at rest around the mesh";
    reportLatticeOperation(state, refrozen, f, "Subdivided " + cellsText(count));
}

const std::vector<std::uint8_t>& tsplineShownControlPoints(const AppState& state) {
    TSplineShownCache& cache = state.tsplineShown;
    const core::Session& session = state.session;
    const std::shared_ptr<const core::Volume>& volume = session.lattice().volume;
    if (!core::asTSpline(volume.get())) {
        cache = TSplineShownCache{};
        return cache.controlPoints;
    }
    if (cache.volume != volume || cache.journal != session.history().journal().size() || cache.fingerprint != session.meshAsSet().fingerprint) {
        cache.volume = volume;
        cache.journal = session.history().journal().size();
        cache.fingerprint = session.meshAsSet().fingerprint;
        cache.controlPoints = core::tsplineCageView(session).controlPoints;
    }
    return cache.controlPoints;
}

bool tsplineOverlaysShown(const AppState& state) {
    const int target = tsplineTarget(state);
    if (target < 0) return false;
    const TSplinePanelState& panel = state.tspline;
    return panel.picking || (!panel.chosenCells.empty() && panel.cellsVolume == state.session.tools().list()[static_cast<size_t>(target)].volume);
}

void addTSplineOverlays(const AppState& state, render::LatticeView& lattice) {
    const int target = tsplineTarget(state);
    const core::TSplineVolume* tspline = targetVolume(state, target);
    if (!tspline) return;
    const core::Session& session = state.session;
    const core::TSplineBasis& basis = tspline->basis();
    const bool frozen = target == session.tools().frozen();
    const Positions points = frozen ? session.cage().cagePoints() : tspline->restControlPoints();
    const TSplinePanelState& panel = state.tspline;
    if (panel.cellsVolume == session.tools().list()[static_cast<size_t>(target)].volume)
        for (int cell : panel.chosenCells)
            for (Positions& segment : core::cellEdgeSegments(basis, cell, points)) lattice.chosenCells.push_back(std::move(segment));
    // The frozen cage has its T-junctions already (scene_builder); a tool at rest shows them while cells are chosen.
    if (frozen || !panel.picking) return;
    const std::vector<int> junctions = core::tJunctionVertices(basis.lattice);
    const Eigen::Index first = lattice.tJunctions.rows();
    lattice.tJunctions.conservativeResize(first + static_cast<Eigen::Index>(junctions.size()), 3);
    for (size_t j = 0; j < junctions.size(); ++j)
        lattice.tJunctions.row(first + static_cast<Eigen::Index>(j)) = points.row(core::vertexAnchor(basis, junctions[j]));
}

}  // namespace sculpt::app
