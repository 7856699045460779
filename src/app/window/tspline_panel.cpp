// The Lattices panel's "T-spline" section: weighted T-spline FFD (Song & Yang 2005, seed 002). Set-up (sec. 4,
// sec. 6 steps 1-3: the region, the octree depth, the weight ratio of the control points of non-empty cells)
// and local subdivision of cells chosen on the mesh (sec. 6 step 2, Fig. 11). Every button is a command of
// tspline_commands.h, i.e. the script op itself (setup_tspline, subdivide_cells).
#include <algorithm>
#include <string>

#include <imgui.h>

#include "app/window/panel_items.h"
#include "app/window/panels.h"
#include "app/window/tspline_commands.h"
#include "core/tspline/tspline_volume.h"

namespace sculpt::app {

void drawTSplineSection(AppState& state) {
    LatticesPanelState& items = state.lattices;
    TSplinePanelState& panel = state.tspline;
    ImGui::Separator();
    const bool open = ImGui::TreeNodeEx("T-spline", ImGuiTreeNodeFlags_DefaultOpen | ImGuiTreeNodeFlags_NoTreePushOnOpen);
    recordItem(items, "T-spline");
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("Weighted T-spline lattice (Song & Yang 2005): an octree lattice, fine near the mesh and\n"
                          "coarse elsewhere. Only the control points of cells holding the mesh are shown and move it.");
    if (!open) return;
    const bool idle = !state.drag.active && !state.session.mesh().empty();
    const float half = 0.5f * (ImGui::GetContentRegionAvail().x - ImGui::GetStyle().ItemSpacing.x);

    // ---- set-up (sec. 4) ----
    ImGui::SetNextItemWidth(half);
    ImGui::SliderInt("Depth", &panel.depth, 1, core::kMaxTSplineSetupDepth, "%d", ImGuiSliderFlags_AlwaysClamp);
    recordItem(items, "tspline depth");
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("Levels of octree subdivision: every cell holding a vertex of the mesh is split, this many\n"
                          "times (then neighbours differ by one level at most). 4 on a 3k-vertex mesh: ~2,400 cells.");
    ImGui::SetNextItemWidth(half);
    ImGui::InputDouble("Weight ratio", &panel.weightRatio, 0.0, 0.0, "%.4g");
    recordItem(items, "tspline weight ratio");
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("Weight of the control points of cells holding the mesh : weight of the others (100:1 in\n"
                          "the paper). The light ones only parametrize the space and are hidden.");
    int region = panel.customRegion ? 1 : 0;
    bool regionChanged = ImGui::RadioButton("Mesh bounds", &region, 0);
    recordItem(items, "tspline mesh bounds");
    ImGui::SameLine();
    regionChanged |= ImGui::RadioButton("Box", &region, 1);
    recordItem(items, "tspline box");
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("Only the part of the mesh inside this box is deformed (sec. 4: the initial region).");
    if (regionChanged) {
        panel.customRegion = region == 1;
        if (panel.customRegion && !panel.regionFilled) panel.regionFilled = meshRegion(state, panel.regionMin, panel.regionMax);
    }
    // With the mesh bounds the fields show them (read again after each command: the mesh may have moved).
    if (!panel.customRegion && (panel.regionJournal != state.session.history().journal().size() || panel.regionMesh != state.session.meshAsSet().fingerprint)) {
        panel.regionFilled = meshRegion(state, panel.regionMin, panel.regionMax);
        panel.regionJournal = state.session.history().journal().size();
        panel.regionMesh = state.session.meshAsSet().fingerprint;
    }
    // Always drawn (disabled with the mesh bounds), so the buttons below stay where they are.
    ImGui::BeginDisabled(!panel.customRegion);
    const float speed = static_cast<float>(std::max((panel.regionMax - panel.regionMin).norm(), 1e-3) * 0.002);
    ImGui::SetNextItemWidth(-ImGui::CalcTextSize("Max").x - ImGui::GetStyle().ItemInnerSpacing.x);
    ImGui::DragScalarN("Min", ImGuiDataType_Double, panel.regionMin.data(), 3, speed, nullptr, nullptr, "%.3f");
    recordItem(items, "tspline region min");
    ImGui::SetNextItemWidth(-ImGui::CalcTextSize("Max").x - ImGui::GetStyle().ItemInnerSpacing.x);
    ImGui::DragScalarN("Max", ImGuiDataType_Double, panel.regionMax.data(), 3, speed, nullptr, nullptr, "%.3f");
    recordItem(items, "tspline region max");
    ImGui::EndDisabled();
    if (panelButton(items, "Fit mesh", idle, half)) {
        panel.regionFilled = meshRegion(state, panel.regionMin, panel.regionMax);
        panel.customRegion = panel.regionFilled;
    }
    if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled)) ImGui::SetTooltip("A box: the mesh's bounds, padded, to edit.");
    ImGui::SameLine();
    if (panelButton(items, "Fit selection", idle, half)) regionFromSelection(state);
    if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
        ImGui::SetTooltip("A box: the bounds of the control points selected with the lattice tool (Tab).");
    if (panelButton(items, "Set up T-spline", idle, -1.0f)) setupTSplineCommand(state);
    if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
        ImGui::SetTooltip("Builds the octree lattice around the mesh in the region and freezes it: drags and the\n"
                          "lattice tool then work in it. The shape does not change. One undo step takes it back.");

    // ---- local subdivision (sec. 6 step 2, Fig. 11) ----
    validateChosenCells(state);
    const int target = tsplineTarget(state);
    const std::vector<core::LatticeTool>& tools = state.session.tools().list();
    std::string line = "No T-spline lattice yet.";
    if (target >= 0)
        line = std::to_string(panel.chosenCells.size()) + " of " + std::to_string(core::asTSpline(tools[static_cast<size_t>(target)].volume.get())->lattice().cells.size()) +
               " cells of " + tools[static_cast<size_t>(target)].name + " chosen";
    ImGui::TextDisabled("%s", line.c_str());
    // The mode is on while the button shows pressed.
    if (panel.picking) ImGui::PushStyleColor(ImGuiCol_Button, ImGui::GetStyleColorVec4(ImGuiCol_ButtonActive));
    const bool choose = panelButton(items, "Choose cells", idle && target >= 0, half);
    if (panel.picking) ImGui::PopStyleColor();
    if (choose) panel.picking ? endChoosingCells(state) : beginChoosingCells(state);
    if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
        ImGui::SetTooltip("Then click on the mesh: the cell there is chosen (orange), a second click drops it. Esc ends.");
    ImGui::SameLine();
    if (panelButton(items, "Subdivide", idle && target >= 0 && !panel.chosenCells.empty(), half)) subdivideChosenCellsCommand(state);
    if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
        ImGui::SetTooltip("Splits the chosen cells in 8 (octree). A frozen lattice is unfrozen and frozen again around\n"
                          "it: the shape stays, the finer lattice starts at rest. One undo step takes it back.");
    ImGui::Checkbox("2:1 balance", &panel.balance);
    recordItem(items, "tspline balance");
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("Also split neighbours until cells sharing a point differ by one level at most.");
    ImGui::SameLine();
    if (panelButton(items, "Clear cells", !panel.chosenCells.empty(), -1.0f)) {
        panel.chosenCells.clear();
        state.gpu.fields = true;
    }
    // ---- sculpting by weights (sec. 1 and 6: the hammer and crimp of Noble & Gordon; script ops "hammer" and
    // "crimp"): what a click on the mesh does in the sculpt tool ----
    BrushTool& brush = state.tools.brush;
    const bool frozen = state.session.tools().frozen() >= 0 && state.session.lattice().volume && state.session.lattice().volume->tsplineVolume();
    if (!frozen) brush.kind = BrushTool::Kind::Drag;
    int kind = static_cast<int>(brush.kind);
    ImGui::BeginDisabled(!frozen);
    ImGui::SetNextItemWidth(half);
    if (ImGui::Combo("Click", &kind, "Drags\0Hammers\0Crimps\0")) brush.kind = static_cast<BrushTool::Kind>(kind);
    recordItem(items, "tspline click");
    if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
        ImGui::SetTooltip("What a click on the mesh does in the sculpt tool, on a frozen T-spline:\n"
                          "Hammers: raises the clicked point by the step (Ctrl+click lowers it), keeping the bump's shape.\n"
                          "Crimps: makes the bump there broader by the factor (Ctrl+click: sharper), keeping its height.\n"
                          "Both act on the shown control points within the brush radius (the strongest one if the\n"
                          "radius is off). Drags: the usual direct manipulation.");
    const float third = (ImGui::GetContentRegionAvail().x - ImGui::GetStyle().ItemSpacing.x) * 0.5f;
    ImGui::SetNextItemWidth(third);
    float step = static_cast<float>(100.0 * brush.hammerStep);
    ImGui::BeginDisabled(brush.kind != BrushTool::Kind::Hammer);
    if (ImGui::SliderFloat("##step", &step, 0.1f, 5.0f, "step %.1f %%")) brush.hammerStep = std::clamp(step / 100.0, 0.001, 0.05);
    ImGui::EndDisabled();
    recordItem(items, "tspline step");
    ImGui::SameLine();
    ImGui::SetNextItemWidth(-1.0f);
    float factor = static_cast<float>(brush.crimpFactor);
    ImGui::BeginDisabled(brush.kind != BrushTool::Kind::Crimp);
    if (ImGui::SliderFloat("##factor", &factor, 1.02f, 2.0f, "width x%.2f")) brush.crimpFactor = std::clamp(static_cast<double>(factor), 1.02, 2.0);
    ImGui::EndDisabled();
    recordItem(items, "tspline factor");
    ImGui::EndDisabled();
}

}  // namespace sculpt::app
