// Recording where the Lattices panel's items were drawn (LatticesPanelState::items), so tests click them as a
// user does; shared by its sections (lattices_panel.cpp, tspline_panel.cpp).
#pragma once

#include <string>

#include <imgui.h>

#include "app/window/app_state.h"

namespace sculpt::app {

// Records the last ImGui item's rectangle under `label`.
inline void recordItem(LatticesPanelState& panel, const std::string& label) {
    const ImVec2 a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
    panel.items.push_back({label, a.x, a.y, b.x, b.y});
}

// A button that is recorded where it was drawn and disabled when `enabled` is false; true when pressed.
inline bool panelButton(LatticesPanelState& panel, const char* label, bool enabled, float width = 0.0f) {
    ImGui::BeginDisabled(!enabled);
    const bool pressed = ImGui::Button(label, ImVec2(width, 0.0f));
    ImGui::EndDisabled();
    recordItem(panel, label);
    return pressed && enabled;
}

}  // namespace sculpt::app
