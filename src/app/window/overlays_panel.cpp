#include <imgui.h>

#include "app/window/panels.h"

namespace sculpt::app {

void drawOverlaysPanel(AppState& state) {
    if (!ImGui::CollapsingHeader("Overlays", ImGuiTreeNodeFlags_DefaultOpen)) return;
    Overlays overlays = state.overlays;
    bool changed = false;
    changed |= ImGui::Checkbox("Wireframe", &overlays.wireframe);
    ImGui::SameLine(0.5f * ImGui::GetContentRegionAvail().x + ImGui::GetStyle().ItemSpacing.x);
    // note: the lattice setting is the current tool's (on in the lattice tool, off in the sculpt tool by default).
    ToolOverlays& tool = overlaysOfTool(overlays, state.tools.mode);
    changed |= ImGui::Checkbox("Lattice", &tool.lattice);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("Kept per tool: on in the lattice tool, off in the sculpt tool until you turn it on.");
    changed |= ImGui::Checkbox("Jacobian", &overlays.jacobian);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("det J of the whole deformation on a log scale (legend at the lower right): blue\n"
                          "compressed, clay unchanged, red stretched, full colour at 1/2 and 2 and beyond;\n"
                          "magenta stripes where it would fold (det J <= 0).");
    ImGui::SameLine(0.5f * ImGui::GetContentRegionAvail().x + ImGui::GetStyle().ItemSpacing.x);
    changed |= ImGui::Checkbox("Affected region", &overlays.affected);
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("Influence of the control points the last operation moved.");
    ImGui::BeginDisabled(!tool.lattice);
    changed |= ImGui::Checkbox("Outer cage only", &overlays.latticeOuterOnly);
    ImGui::EndDisabled();
    if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
        ImGui::SetTooltip("Only the control points and edges on the lattice's outer faces (and the selected ones);\n"
                          "the lattice tool picks only what is drawn.");
    if (state.meshHasVertexColors) {  // only a mesh whose file has colours (a scan's) offers them
        ImGui::SameLine(0.5f * ImGui::GetContentRegionAvail().x + ImGui::GetStyle().ItemSpacing.x);
        changed |= ImGui::Checkbox("Vertex colours", &overlays.vertexColors);
        if (ImGui::IsItemHovered())
            ImGui::SetTooltip("The file's own vertex colours as the material (off: the clay). The Jacobian map\n"
                              "replaces them while it is on.");
    }
    if (changed) setOverlays(state, overlays);
    if (ImGui::Button("Frame mesh (Home)")) frameMesh(state);
}

}  // namespace sculpt::app
