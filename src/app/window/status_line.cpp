#include <imgui.h>

#include "app/window/panels.h"

namespace sculpt::app {

void drawStatusLine(AppState& state) {
    const ImGuiViewport* viewport = ImGui::GetMainViewport();
    const float height = ImGui::GetFrameHeight() + 2.0f * ImGui::GetStyle().WindowPadding.y;
    ImGui::SetNextWindowPos(ImVec2(viewport->Pos.x, viewport->Pos.y + viewport->Size.y - height));
    ImGui::SetNextWindowSize(ImVec2(viewport->Size.x, height));
    ImGui::SetNextWindowBgAlpha(0.95f);
    ImGui::Begin("##status", nullptr,
                 ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoSavedSettings |
                     ImGuiWindowFlags_NoFocusOnAppearing | ImGuiWindowFlags_NoBringToFrontOnFocus);
    const ImVec4 colour = state.statusIsError ? ImVec4(1.0f, 0.45f, 0.4f, 1.0f) : ImVec4(0.75f, 0.85f, 0.95f, 1.0f);
    ImGui::AlignTextToFramePadding();
    ImGui::TextColored(colour, "%s", state.statusIsError ? "!" : ">");
    ImGui::SameLine();
    ImGui::TextUnformatted(state.status.c_str());
    // What the cursor would do where it is, right-aligned, when there is room for it.
    if (!state.tools.hint.empty()) {
        const float hintWidth = ImGui::CalcTextSize(state.tools.hint.c_str()).x;
        const float right = ImGui::GetWindowContentRegionMax().x;
        ImGui::SameLine();
        if (ImGui::GetCursorPosX() + ImGui::GetFontSize() + hintWidth <= right) {
            ImGui::SetCursorPosX(right - hintWidth);
            ImGui::TextDisabled("%s", state.tools.hint.c_str());
        }
    }
    ImGui::End();
}

}  // namespace sculpt::app
