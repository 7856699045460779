#include <imgui.h>

#include "app/window/panels.h"

namespace sculpt::app {

float sidebarWidth() { return 20.0f * ImGui::GetFontSize(); }

void beginSidebar(AppState& state) {
    const ImGuiViewport* viewport = ImGui::GetMainViewport();
    const float margin = 0.6f * ImGui::GetFontSize();
    const float statusHeight = ImGui::GetFrameHeightWithSpacing() + 2.0f * ImGui::GetStyle().WindowPadding.y;
    // note: the work area, below the main menu bar (file_commands.cpp), so the two never overlap.
    ImGui::SetNextWindowPos(ImVec2(viewport->WorkPos.x + margin, viewport->WorkPos.y + margin));
    ImGui::SetNextWindowSizeConstraints(ImVec2(sidebarWidth(), 0.0f),
                                        ImVec2(sidebarWidth(), viewport->WorkSize.y - statusHeight - 2.0f * margin));
    ImGui::SetNextWindowBgAlpha(0.92f);
    ImGui::Begin((sidebarTitle(state) + "###sidebar").c_str(), nullptr,
                 ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse |
                     ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoSavedSettings);
}

void endSidebar() { ImGui::End(); }

std::string sidebarTitle(const AppState& state) {
    return "DMFFD Sculpt" + (state.meshName.empty() ? std::string() : "  -  " + state.meshName) + (state.modified ? "*" : "");
}

}  // namespace sculpt::app
