#include <algorithm>
#include <string>

#include <imgui.h>

#include "app/window/panels.h"

namespace sculpt::app {

void drawHistoryPanel(AppState& state) {
    if (!ImGui::CollapsingHeader("History", ImGuiTreeNodeFlags_DefaultOpen)) return;
    const core::Session& session = state.session;
    const int cursor = session.historyCursor();
    const int count = static_cast<int>(session.history().size());
    const float half = 0.5f * (ImGui::GetContentRegionAvail().x - ImGui::GetStyle().ItemSpacing.x);
    ImGui::BeginDisabled(cursor == 0 || state.drag.active);
    if (ImGui::Button("Undo", ImVec2(half, 0.0f))) undoCommand(state);
    ImGui::EndDisabled();
    ImGui::SameLine();
    ImGui::BeginDisabled(cursor == count || state.drag.active);
    if (ImGui::Button("Redo", ImVec2(half, 0.0f))) redoCommand(state);
    ImGui::EndDisabled();

    const float rows = static_cast<float>(std::min(count + 1, 10));
    if (ImGui::BeginListBox("##history", ImVec2(-1.0f, (rows + 0.4f) * ImGui::GetTextLineHeightWithSpacing()))) {
        int jumpTo = -1;
        // Entry i (1-based) is "the state after operation i"; entry 0 is the loaded mesh.
        for (int i = 0; i <= count; ++i) {
            std::string label;
            if (i == 0) {
                label = "Loaded mesh";
            } else {
                const core::Operation& op = session.history()[static_cast<size_t>(i - 1)];
                label = std::to_string(i) + ". " + op.label;
                if (op.steps.size() > 1) label += "  [" + std::to_string(op.steps.size()) + " steps]";
            }
            label += "##h" + std::to_string(i);
            const bool undone = i > cursor;
            if (undone) ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyleColorVec4(ImGuiCol_TextDisabled));
            if (ImGui::Selectable(label.c_str(), i == cursor) && i != cursor) jumpTo = i;
            if (undone) ImGui::PopStyleColor();
            if (i == cursor && ImGui::IsWindowAppearing()) ImGui::SetScrollHereY();
        }
        ImGui::EndListBox();
        if (jumpTo >= 0 && !state.drag.active) jumpToHistory(state, jumpTo);
    }
    ImGui::TextDisabled("Ctrl+Z undo, Ctrl+Shift+Z / Ctrl+Y redo");
}

}  // namespace sculpt::app
