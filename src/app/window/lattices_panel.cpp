// The Lattices panel (lattices of any shape, Coquillart 1990, 3.1-3.4): the mesh's list of lattice tools, the
// library they come from, placing one on the surface, freezing and unfreezing. Every button is a command of
// lattice_commands.h, i.e. the session command the matching script op issues.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include <imgui.h>

#include "app/window/file_commands.h"
#include "app/window/lattice_commands.h"
#include "app/window/panel_items.h"
#include "app/window/panels.h"

namespace sculpt::app {
namespace {

// The list's height in rows, whatever it holds: more tools scroll, fewer leave it blank, so the buttons under
// it stay where they are as tools come and go.
constexpr int kListRows = 5;

// Draws `text` wrapped to the available width in exactly `lines` lines: a shorter text leaves the rest blank,
// a longer one is cut with "..." (all of it shows on hover). Every state of the panel takes the same height,
// so the buttons below never jump as the selection or the mode changes.
void fixedLines(const std::string& text, int lines, const ImVec4& colour) {
    ImFont* font = ImGui::GetFont();
    const float scale = ImGui::GetFontSize() / font->FontSize;
    const float width = std::max(ImGui::GetContentRegionAvail().x, 1.0f);
    const char* p = text.c_str();
    const char* const end = p + text.size();
    bool cut = false;
    ImGui::BeginGroup();
    for (int line = 0; line < lines; ++line) {
        if (p >= end) {
            ImGui::TextUnformatted("");  // a blank line of the same height
            continue;
        }
        const char* wrap = font->CalcWordWrapPositionA(scale, p, end, width);
        if (wrap <= p) wrap = p + 1;  // a word wider than the panel: a character per line, never stuck
        std::string piece(p, wrap);
        if (!piece.empty() && piece.back() == '\n') piece.pop_back();
        p = wrap;
        while (p < end && (*p == ' ' || *p == '\n')) ++p;
        if (line == lines - 1 && p < end) {
            cut = true;
            while (!piece.empty() && ImGui::CalcTextSize((piece + "...").c_str()).x > width) piece.pop_back();
            while (!piece.empty() && piece.back() == ' ') piece.pop_back();
            piece += "...";
        }
        ImGui::TextColored(colour, "%s", piece.c_str());
    }
    ImGui::EndGroup();
    if (cut && ImGui::IsItemHovered()) ImGui::SetTooltip("%s", text.c_str());
}

}  // namespace

void drawLatticesPanel(AppState& state, FileCommands& files) {
    LatticesPanelState& panel = state.lattices;
    panel.items.clear();
    const bool open = ImGui::CollapsingHeader("Lattices");
    recordItem(panel, "Lattices");
    if (!open) return;
    if (!panel.libraryLoaded) loadLatticeLibraries(state);
    const core::Session& session = state.session;
    const std::vector<core::LatticeTool>& tools = session.tools().list();
    const int frozen = session.tools().frozen();
    const int count = static_cast<int>(tools.size());
    if (panel.selectedTool >= count) panel.selectedTool = count - 1;
    const bool idle = !state.drag.active && !session.mesh().empty();
    const float half = 0.5f * (ImGui::GetContentRegionAvail().x - ImGui::GetStyle().ItemSpacing.x);

    // The mesh's tools: name, shape, and which one is frozen (the cage).
    const float rows = static_cast<float>(kListRows);
    if (ImGui::BeginListBox("##latticeTools", ImVec2(-1.0f, (rows + 0.4f) * ImGui::GetTextLineHeightWithSpacing()))) {
        if (count == 0) ImGui::TextDisabled("None yet: add one below.");
        for (int t = 0; t < count; ++t) {
            const core::LatticeTool& tool = tools[static_cast<size_t>(t)];
            const std::string label = tool.name + (t == frozen ? "  [frozen]" : "") + "##tool" + std::to_string(t);
            if (ImGui::Selectable(label.c_str(), t == panel.selectedTool)) panel.selectedTool = t;
            if (ImGui::IsItemHovered() && tool.volume) ImGui::SetTooltip("%s", describeLattice(*tool.volume).c_str());
            recordItem(panel, "tool " + std::to_string(t));
        }
        ImGui::EndListBox();
    }
    const bool chosen = panel.selectedTool >= 0 && panel.selectedTool < count;
    // Under the list, always two lines each: the selected tool, and which lattice is the cage.
    const ImVec4 text = ImGui::GetStyleColorVec4(ImGuiCol_Text), dim = ImGui::GetStyleColorVec4(ImGuiCol_TextDisabled);
    if (chosen && tools[static_cast<size_t>(panel.selectedTool)].volume)
        fixedLines(describeLattice(*tools[static_cast<size_t>(panel.selectedTool)].volume), 2, text);
    else
        fixedLines(count == 0 ? "Once frozen, a lattice tool deforms the part of the mesh inside it."
                              : "Click a lattice in the list to select it.",
                   2, dim);
    fixedLines(frozen >= 0 ? "Frozen: " + tools[static_cast<size_t>(frozen)].name + " is the cage; drags and the lattice tool work in it."
                           : std::string("Edit mode: the box lattice is the cage."),
               2, dim);

    ImGui::SetNextItemWidth(half);
    if (ImGui::InputInt("Pin layers", &panel.pinLayers)) panel.pinLayers = std::clamp(panel.pinLayers, 0, 2);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("Outer layers of control points kept fixed when frozen (0-2), counted from the\n"
                          "lattice's boundary faces; 2 gives a C1 seam where it crosses the surface.");
    if (panelButton(panel, "Freeze", idle && chosen && panel.selectedTool != frozen, half))
        freezeLatticeCommand(state, panel.selectedTool, panel.pinLayers);
    ImGui::SameLine();
    if (panelButton(panel, "Unfreeze", idle && frozen >= 0, half)) unfreezeLatticeCommand(state);
    if (panelButton(panel, "Remove", idle && chosen && panel.selectedTool != frozen, half))
        removeLatticeToolCommand(state, panel.selectedTool);
    ImGui::SameLine();
    if (panelButton(panel, "Move on mesh", idle && chosen && panel.selectedTool != frozen, half))
        beginPlacingLattice(state, LatticesPanelState::Placing::Tool);
    if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
        ImGui::SetTooltip("The next click on the mesh moves the selected lattice there, along the surface normal.");
    if (panelButton(panel, "Save to library...", chosen, -1.0f)) files.saveLatticeFile(state, panel.selectedTool);

    // Editing the selected tool while it is not frozen (3.1.4): exact knot insertion, which adds points
    // without changing the lattice's shape, at one parameter or halving every chunk of an axis.
    const bool editable = idle && chosen && panel.selectedTool != frozen && tools[static_cast<size_t>(panel.selectedTool)].volume &&
                          tools[static_cast<size_t>(panel.selectedTool)].volume->tensorNet();
    static const char* const kAxes[] = {"u", "v", "w"};
    ImGui::BeginDisabled(!editable);
    ImGui::SetNextItemWidth(0.35f * half);
    ImGui::Combo("##editAxis", &panel.editAxis, kAxes, 3);
    recordItem(panel, "edit axis");
    ImGui::SameLine();
    // note: a double slider, so the knot the script records is the value shown (0.168, not 0.1679999977).
    static const double kAtMin = 0.01, kAtMax = 0.99;
    ImGui::SetNextItemWidth(half - 0.35f * half - ImGui::GetStyle().ItemSpacing.x);
    if (ImGui::SliderScalar("##insertAt", ImGuiDataType_Double, &panel.insertAt, &kAtMin, &kAtMax, "at %.3f"))
        panel.insertAt = std::clamp(std::round(panel.insertAt * 1000.0) / 1000.0, kAtMin, kAtMax);
    recordItem(panel, "insert at");
    ImGui::EndDisabled();
    if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
        ImGui::SetTooltip("Where the knot goes along the axis, as a lattice parameter: chunk s of n covers [s/n, (s+1)/n].\n"
                          "A value on a chunk boundary raises that knot's multiplicity instead.");
    ImGui::SameLine();
    const std::string toolName = chosen ? tools[static_cast<size_t>(panel.selectedTool)].name : std::string();
    if (panelButton(panel, "Insert knot", editable, -1.0f)) {
        core::NetEdit edit;
        edit.kind = core::NetEdit::Kind::Insert;
        edit.axis = panel.editAxis;
        edit.at = panel.insertAt;
        char where[64];
        std::snprintf(where, sizeof where, "%s = %.3f", kAxes[panel.editAxis], panel.insertAt);
        editLatticeNetCommand(state, panel.selectedTool, {edit}, "Inserted a knot at " + std::string(where) + " in " + toolName);
    }
    if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
        ImGui::SetTooltip("Splits one chunk of the selected lattice by exact knot insertion: more control points,\n"
                          "the same shape. Only a lattice that is not frozen can be edited.");
    if (panelButton(panel, "Refine axis", editable, -1.0f)) {
        core::NetEdit edit;
        edit.kind = core::NetEdit::Kind::Refine;
        edit.axis = panel.editAxis;
        editLatticeNetCommand(state, panel.selectedTool, {edit}, "Refined " + std::string(kAxes[panel.editAxis]) + " of " + toolName);
    }
    if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
        ImGui::SetTooltip("Halves every chunk along the axis (exact knot insertion: the shape does not change).");

    // The library: shipped lattices and those opened.
    ImGui::Separator();
    const std::vector<LatticeLibraryEntry>& library = panel.library;
    panel.libraryChoice = std::clamp(panel.libraryChoice, 0, std::max(static_cast<int>(library.size()) - 1, 0));
    const std::string preview = library.empty() ? std::string("(empty)") : library[static_cast<size_t>(panel.libraryChoice)].name;
    ImGui::SetNextItemWidth(half);
    if (ImGui::BeginCombo("##library", preview.c_str())) {
        for (int e = 0; e < static_cast<int>(library.size()); ++e) {
            const std::string label = library[static_cast<size_t>(e)].name + "##lib" + std::to_string(e);
            if (ImGui::Selectable(label.c_str(), e == panel.libraryChoice)) panel.libraryChoice = e;
            if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s\n%s", describeLattice(*library[static_cast<size_t>(e)].volume).c_str(),
                                                          library[static_cast<size_t>(e)].path.c_str());
        }
        ImGui::EndCombo();
    }
    recordItem(panel, "library");
    ImGui::SameLine();
    if (panelButton(panel, "Open...", !files.busy(), half)) files.openLatticeFile(state);
    if (panelButton(panel, "Add", idle && !library.empty(), half)) addLatticeFromLibrary(state, panel.libraryChoice);
    ImGui::SameLine();
    if (panelButton(panel, "Place on mesh", idle && !library.empty(), half))
        beginPlacingLattice(state, LatticesPanelState::Placing::LibraryEntry);
    if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
        ImGui::SetTooltip("The next click on the mesh adds the chosen lattice there: its centre on the surface,\n"
                          "its z axis along the normal, its size \"Place size\" times the mesh's.");
    float fraction = static_cast<float>(panel.placeSizeFraction);
    ImGui::SetNextItemWidth(half);
    if (ImGui::DragFloat("Place size", &fraction, 0.005f, 0.02f, 2.0f, "%.2f"))
        panel.placeSizeFraction = std::clamp(static_cast<double>(fraction), 0.02, 2.0);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("The placed lattice's bounds diagonal, as a fraction of the mesh's (%.4g units now).", placementSize(state));
    if (ImGui::Checkbox("Show tools", &panel.showTools)) state.gpu.fields = true;
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("Draw the lattice tools that are not frozen (dim grey, at rest), even with the Lattice\n"
                          "overlay off, so you see where they are.");
    // Always one line, blank unless a placement waits, so the window's height does not change with it.
    fixedLines(panel.placing != LatticesPanelState::Placing::None ? "Click on the mesh (Esc cancels)." : "", 1,
               ImVec4(1.0f, 0.7f, 0.3f, 1.0f));

    // Weighted T-splines (Song & Yang 2005): set-up and local subdivision, last, so nothing above moves with it.
    drawTSplineSection(state);
}

}  // namespace sculpt::app
