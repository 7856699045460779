#include <algorithm>

#include <imgui.h>

#include "app/window/panels.h"

namespace sculpt::app {

float sidebarWidth() { return 20.0f * ImGui::GetFontSize(); }

float panelMargin() { return 0.6f * ImGui::GetFontSize(); }

float panelMaxHeight(const AppState& state, bool rightSide) {
    const ImGuiViewport* viewport = ImGui::GetMainViewport();
    const float oneLine = ImGui::GetFrameHeight() + 2.0f * ImGui::GetStyle().WindowPadding.y;
    float reserved = std::max(state.statusLineHeight, oneLine) + 2.0f * panelMargin();
    if (rightSide && state.legendHeight > 0.0f) {
        const float scale = state.framebufferWidth > 0 && viewport->Size.x > 0.0f
                                ? viewport->Size.x / static_cast<float>(state.framebufferWidth) : 1.0f;
        reserved += state.legendHeight * scale;
    }
    return std::max(0.0f, viewport->WorkSize.y - reserved);
}

void beginSidebar(AppState& state) {
    const ImGuiViewport* viewport = ImGui::GetMainViewport();
    const float margin = panelMargin();
    // note: the work area, below the main menu bar (file_commands.cpp), so the two never overlap.
    ImGui::SetNextWindowPos(ImVec2(viewport->WorkPos.x + margin, viewport->WorkPos.y + margin));
    ImGui::SetNextWindowSizeConstraints(ImVec2(sidebarWidth(), 0.0f), ImVec2(sidebarWidth(), panelMaxHeight(state, false)));
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
