#include <algorithm>
#include <string>

#include <imgui.h>

#include "app/window/panels.h"

namespace sculpt::app {

std::string historyEntryLabel(const core::Operation& op) {
    std::string label = op.label;
    if (op.injectiveSteps() > 1) label += "  [" + std::to_string(op.injectiveSteps()) + " injective steps]";
    return label;
}

namespace {

// The text broken into lines at spaces so that each fits `width` pixels (a word longer than that keeps its own
// line). note: Dear ImGui's own wrapping also breaks after '.', which split "0.02" in two.
std::string wrapAtSpaces(const std::string& text, float width) {
    std::string out, line;
    size_t start = 0;
    while (start <= text.size()) {
        size_t end = text.find(' ', start);
        if (end == std::string::npos) end = text.size();
        const std::string word = text.substr(start, end - start);
        const std::string candidate = line.empty() ? word : line + " " + word;
        if (!line.empty() && ImGui::CalcTextSize(candidate.c_str()).x > width) {
            out += line + "\n";
            line = word;
        } else {
            line = candidate;
        }
        start = end + 1;
    }
    return out + line;
}

}  // namespace

void drawHistoryPanel(AppState& state) {
    if (!ImGui::CollapsingHeader("History", ImGuiTreeNodeFlags_DefaultOpen)) return;
    const core::Session& session = state.session;
    const int cursor = session.history().cursor();
    const int count = static_cast<int>(session.history().size());
    const float half = 0.5f * (ImGui::GetContentRegionAvail().x - ImGui::GetStyle().ItemSpacing.x);
    ImGui::BeginDisabled(cursor == 0 || state.drag.active);
    if (ImGui::Button("Undo", ImVec2(half, 0.0f))) requestHistoryStep(state, -1);
    ImGui::EndDisabled();
    ImGui::SameLine();
    ImGui::BeginDisabled(cursor == count || state.drag.active);
    if (ImGui::Button("Redo", ImVec2(half, 0.0f))) requestHistoryStep(state, +1);
    ImGui::EndDisabled();

    // Each entry wraps to the list's width (a long name is never cut off), and the list scrolls to the current
    // entry whenever it changes (a new step, an undo), as Blender's undo history does.
    // Up to ten rows, fewer where the sidebar ends sooner (above the status line): the list scrolls, the panel does not
    // hide its newest entries below its own bottom.
    const float row = ImGui::GetTextLineHeightWithSpacing();
    const ImGuiStyle& style = ImGui::GetStyle();
    const float sidebarBottom = ImGui::GetMainViewport()->WorkPos.y + panelMargin() + panelMaxHeight(state, false) - style.WindowPadding.y;
    const float room = sidebarBottom - ImGui::GetCursorScreenPos().y - row - style.ItemSpacing.y;
    const float rows = static_cast<float>(std::min(count + 1, 10)) + 0.4f;
    const float height = std::max(std::min(rows * row, room), std::min(rows, 3.4f) * row);
    if (ImGui::BeginListBox("##history", ImVec2(-1.0f, height))) {
        // note: two frames: the scroll limit of the first is the list's height of the frame before, which lacks a
        // new entry.
        if (ImGui::IsWindowAppearing() || state.historyShownCursor != cursor || state.historyShownCount != count)
            state.historyScrollFrames = 2;
        const bool scroll = state.historyScrollFrames > 0;
        if (scroll) --state.historyScrollFrames;
        state.historyShownCursor = cursor;
        state.historyShownCount = count;
        const float wrap = ImGui::GetContentRegionAvail().x;
        int jumpTo = -1;
        state.historyCurrentVisible = false;
        // Entry i (1-based) is "the state after operation i"; entry 0 is the loaded mesh.
        for (int i = 0; i <= count; ++i) {
            std::string label;
            if (i == 0) {
                label = "Loaded mesh";
            } else {
                label = std::to_string(i) + ". " + historyEntryLabel(session.history()[static_cast<size_t>(i - 1)]);
            }
            label = wrapAtSpaces(label, wrap);
            const ImVec2 size = ImGui::CalcTextSize(label.c_str());
            ImGui::PushID(i);
            if (ImGui::Selectable("##entry", i == cursor, ImGuiSelectableFlags_None, ImVec2(0.0f, size.y)) && i != cursor)
                jumpTo = i;
            ImGui::PopID();
            const ImVec4 colour = ImGui::GetStyleColorVec4(i > cursor ? ImGuiCol_TextDisabled : ImGuiCol_Text);
            ImGui::GetWindowDrawList()->AddText(ImGui::GetItemRectMin(), ImGui::GetColorU32(colour), label.c_str());
            if (i == cursor) {
                if (scroll) ImGui::SetScrollHereY(0.5f);
                else state.historyCurrentVisible = ImGui::IsItemVisible();
            }
        }
        ImGui::EndListBox();
        if (jumpTo >= 0) requestHistoryJump(state, jumpTo);
    }
    ImGui::TextDisabled("Ctrl+Z undo, Ctrl+Shift+Z / Ctrl+Y redo");
}

}  // namespace sculpt::app
