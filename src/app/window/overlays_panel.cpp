#include <imgui.h>

#include "app/window/panels.h"

namespace sculpt::app {

void drawOverlaysPanel(AppState& state) {
    if (!ImGui::CollapsingHeader("Overlays", ImGuiTreeNodeFlags_DefaultOpen)) return;
    Overlays overlays = state.overlays;
    bool changed = false;
    changed |= ImGui::Checkbox("Wireframe", &overlays.wireframe);
    ImGui::SameLine(0.5f * ImGui::GetContentRegionAvail().x + ImGui::GetStyle().ItemSpacing.x);
    changed |= ImGui::Checkbox("Lattice", &overlays.lattice);
    changed |= ImGui::Checkbox("Jacobian", &overlays.jacobian);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("det J of the whole deformation: blue compressed, white unchanged, red stretched,\n"
                          "magenta where it would fold (det J <= 0).");
    ImGui::SameLine(0.5f * ImGui::GetContentRegionAvail().x + ImGui::GetStyle().ItemSpacing.x);
    changed |= ImGui::Checkbox("Affected region", &overlays.affected);
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("Influence of the control points the last operation moved.");
    if (changed) setOverlays(state, overlays);
    if (ImGui::Button("Frame mesh (F)")) frameMesh(state);
}

}  // namespace sculpt::app
