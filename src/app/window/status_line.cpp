#include <algorithm>

#include <imgui.h>

#include "app/window/panels.h"

namespace sculpt::app {

void drawStatusLine(AppState& state) {
    const ImGuiViewport* viewport = ImGui::GetMainViewport();
    const ImGuiStyle& style = ImGui::GetStyle();
    // The message is never clipped: a long one wraps, and the bar grows upward to hold it.
    const float marker = ImGui::CalcTextSize("!").x + style.ItemSpacing.x;
    const float wrapWidth = std::max(50.0f, viewport->Size.x - 2.0f * style.WindowPadding.x - marker);
    const ImVec2 text = ImGui::CalcTextSize(state.status.c_str(), nullptr, false, wrapWidth);
    const bool oneLine = text.y <= ImGui::GetFontSize() * 1.5f;
    const float height = std::max(ImGui::GetFrameHeight(), text.y) + 2.0f * style.WindowPadding.y;
    state.statusLineHeight = height;
    ImGui::SetNextWindowPos(ImVec2(viewport->Pos.x, viewport->Pos.y + viewport->Size.y - height));
    ImGui::SetNextWindowSize(ImVec2(viewport->Size.x, height));
    ImGui::SetNextWindowBgAlpha(0.95f);
    ImGui::Begin("##status", nullptr,
                 ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoSavedSettings |
                     ImGuiWindowFlags_NoFocusOnAppearing | ImGuiWindowFlags_NoBringToFrontOnFocus);
    const ImVec4 colour = state.statusIsError ? ImVec4(1.0f, 0.45f, 0.4f, 1.0f) : ImVec4(0.75f, 0.85f, 0.95f, 1.0f);
    if (oneLine) ImGui::AlignTextToFramePadding();
    ImGui::TextColored(colour, "%s", state.statusIsError ? "!" : ">");
    ImGui::SameLine();
    ImGui::PushTextWrapPos(0.0f);
    ImGui::TextUnformatted(state.status.c_str());
    ImGui::PopTextWrapPos();
    // Every line the status stands for (all of a load's warnings), or the test's own words for a refusal (which
    // cell, which cones), for whoever wants them, on hover.
    if (ImGui::IsItemHovered() && !state.statusDetails.empty()) {
        ImGui::BeginTooltip();
        ImGui::PushTextWrapPos(0.6f * viewport->Size.x);
        for (const std::string& line : state.statusDetails) ImGui::BulletText("%s", line.c_str());
        ImGui::PopTextWrapPos();
        ImGui::EndTooltip();
    } else if (ImGui::IsItemHovered() && state.hasReport && state.lastReport.status == core::OpStatus::Rejected &&
               !state.lastReport.injectivity.empty()) {
        ImGui::SetTooltip("%s", state.lastReport.injectivity.c_str());
    }
    // What the cursor would do where it is, right-aligned, when there is room for it.
    if (oneLine && !state.tools.hint.empty()) {
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
