#include <string>

#include <imgui.h>

#include "app/window/panels.h"
#include "core/tspline/tspline_view.h"

namespace sculpt::app {

void drawStatsPanel(AppState& state) {
    if (!ImGui::CollapsingHeader("Statistics", ImGuiTreeNodeFlags_DefaultOpen)) return;
    const core::Session& session = state.session;
    const core::Lattice& lattice = session.lattice();
    const core::LatticeSettings& settings = session.cage().settings();
    if (ImGui::BeginTable("stats", 2, ImGuiTableFlags_SizingStretchProp)) {
        auto row = [](const char* name, const char* format, auto... values) {
            ImGui::TableNextRow();
            ImGui::TableSetColumnIndex(0);
            ImGui::TextDisabled("%s", name);
            ImGui::TableSetColumnIndex(1);
            ImGui::Text(format, values...);
        };
        row("Vertices", "%d", static_cast<int>(session.mesh().positions.rows()));
        row("Triangles", "%d", static_cast<int>(session.mesh().triangles.rows()));
        // note: a frozen lattice of any shape has its own degrees per axis (the settings' are the box's); its kind
        // is in the Lattices panel.
        const core::TSplineVolume* tspline = core::asTSpline(lattice.volume.get());
        if (tspline)  // no grid: its cells (a count of #P x 1 x 1 said nothing)
            row("Lattice", "T-spline, %d cells", static_cast<int>(tspline->lattice().cells.size()));
        else if (lattice.volume && !lattice.tensorNet())
            row("Lattice", "%s, %d points", lattice.volume->kindName().c_str(), lattice.controlPointCount());
        else if (lattice.volume)
            row("Lattice", "%d x %d x %d, degree %d/%d/%d", lattice.count[0], lattice.count[1], lattice.count[2],
                lattice.degree[0], lattice.degree[1], lattice.degree[2]);
        else
            row("Lattice", "%d x %d x %d, degree %d", lattice.count[0], lattice.count[1], lattice.count[2],
                settings.degree[0]);
        row("Lattice frames", "%d", session.cage().frameDepth() + 1);
        if (ImGui::IsItemHovered())
            ImGui::SetTooltip("How many lattices the history has used: an edit that would fold the mesh in one\n"
                              "lattice is split into steps that each pass, each later one in a fresh lattice (a frame)\n"
                              "around the shape the earlier steps made. 1: everything in the first lattice.");
        // note: the CPU path uploads positions and normals too; the count is the vertices sent, which includes
        // the neighbours whose normals a move changed (more than the vertices an undo reports as moved).
        const auto uploadTooltip = [] {
            if (ImGui::IsItemHovered())
                ImGui::SetTooltip("The time of the last upload to the GPU, and the vertices whose positions and normals it\n"
                                  "sent: those that moved and their neighbours, whose normals changed (an undo counts only\n"
                                  "the moved ones). The GPU path sends the lattices' control points instead.");
        };
        if (state.stats.hideTimings) {
            row("Solve", "%s", "-- ms");
            row("Upload to GPU", "-- ms (%d vtx)", state.stats.lastUploadVertices);
            uploadTooltip();
            row("Draw calls", "%s", "-- ms");
            row("Frame rate", "%s", "-- fps");
        } else {
            // (no command on this mesh yet: nothing to time, not the last mesh's figure)
            if (state.hasReport) row("Solve", "%.2f ms", state.stats.solveMs);
            else row("Solve", "%s", "none yet");
            row("Upload to GPU", "%.2f ms (%d vtx)", state.stats.updateMs, state.stats.lastUploadVertices);
            uploadTooltip();
            row("Draw calls", "%.2f ms", state.stats.renderMs);
            // Only while frames follow each other by themselves (a drag, an orbit, a transform): the last frame before
            // the window sleeps cannot know it is the last, and its rate would stay on screen.
            const bool moving = state.drag.active || state.transform.active || state.navigation != Navigation::None;
            if (!moving || state.stats.afterIdle || state.stats.frameMs <= 0.0)
                row("Frame rate", "%s", "idle (draws on change)");
            else
                row("Frame rate", "%.1f fps (%.1f ms)", 1000.0 / state.stats.frameMs, state.stats.frameMs);
        }
        row("Deformed on", "%s", state.stats.deformationPath.c_str());
        if (ImGui::IsItemHovered())
            ImGui::SetTooltip("Where the mesh on screen is deformed: on the CPU (positions, normals and their upload\n"
                              "each frame) or in the GPU's vertex shader from the rest mesh (only the lattices go up\n"
                              "each frame). A big mesh's first drag times both and keeps the faster, for drag frames\n"
                              "and for still ones. Picking, saving and the injectivity checks always use the engine's\n"
                              "exact positions.\n\n%s",
                              state.stats.hideTimings ? "" : state.stats.deformationDetails.c_str());
        row("History", "%.1f KiB", static_cast<double>(session.historyBytes()) / 1024.0);
        ImGui::EndTable();
    }
}

}  // namespace sculpt::app
