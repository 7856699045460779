#include <imgui.h>

#include "app/window/panels.h"

namespace sculpt::app {

void drawInjectivityPanel(AppState& state) {
    if (!ImGui::CollapsingHeader("Injectivity", ImGuiTreeNodeFlags_DefaultOpen)) return;
    core::InjectivitySettings settings = state.session.injectivity();
    int mode = static_cast<int>(settings.mode);
    bool changed = false;
    changed |= ImGui::RadioButton("Off", &mode, static_cast<int>(core::InjectivityMode::Off));
    ImGui::SameLine();
    changed |= ImGui::RadioButton("Conic", &mode, static_cast<int>(core::InjectivityMode::Conic));
    ImGui::SameLine();
    changed |= ImGui::RadioButton("Exact", &mode, static_cast<int>(core::InjectivityMode::Exact));
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("Conic: fast sufficient test (Gain & Dodgson 2001, Appendix).\n"
                          "Exact: det J in Bernstein form, subdivided (section 6).");
    ImGui::SetNextItemWidth(-ImGui::CalcTextSize("Max depth").x - ImGui::GetStyle().ItemInnerSpacing.x);
    changed |= ImGui::SliderInt("Max depth", &settings.maxDepth, 0, 12);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("How often a move that would fold may be halved into smaller steps, each free of folds, before it is refused.");
    if (changed) {
        settings.mode = static_cast<core::InjectivityMode>(mode);
        setInjectivityCommand(state, settings);
    }
}

}  // namespace sculpt::app
