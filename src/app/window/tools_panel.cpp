// The tool window on the right of the viewport: which tool is active, the handles and pins of the sculpt tool,
// the selection and pins of the lattice tool, and the lattice set-up (resolution, degree, padding, pinned
// layers, region of interest). Also draws the lattice tool's selection rectangle over the viewport.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include <imgui.h>

#include "app/window/panels.h"
#include "app/window/tool_commands.h"
#include "app/window/wording.h"
#include "render/camera.h"

namespace sculpt::app {
namespace {

// printf format for a coordinate as large as `magnitude` of a box `size` across: enough significant digits
// to show 1e-4 of the size (4 near the origin, up to 17 for a tiny box far from it).
std::string coordinateFormat(double magnitude, double size) {
    const double ratio = magnitude > 0.0 && size > 0.0 ? magnitude / size : 1.0;
    const int digits = std::clamp(static_cast<int>(std::ceil(std::log10(std::max(ratio, 1.0)))) + 4, 4, 17);
    return "%." + std::to_string(digits) + "g";
}

void helpMarker(const char* text) {
    ImGui::SameLine();
    ImGui::TextDisabled("(?)");
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", text);
}

void drawHandlesSection(AppState& state) {
    ToolState& tools = state.tools;
    const size_t pins = pinCount(tools);
    ImGui::Text("%s, %s", countOf(tools.handles.size() - pins, "handle").c_str(), countOf(pins, "pin").c_str());
    helpMarker("Shift+click on the mesh places a handle (red), Ctrl+click a pin (green square).\n"
               "Dragging a handle moves it (or all handles, see below) while every other handle\n"
               "and pin holds its point: one multi-point manipulation (Hu et al. 2001, eq. 12).\n"
               "Shift+click a marker removes it, Ctrl+click turns a handle into a pin and back.\n"
               "A plain drag on the mesh also keeps every handle and pin in place.");
    if (ImGui::Checkbox("Move handles together (G)", &tools.moveHandlesTogether)) state.gpu.fields = true;
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("On: dragging one handle moves all handles by the same offset.\nOff: the others hold still.");
    ImGui::BeginDisabled(tools.handles.empty() || state.drag.active);
    if (ImGui::Button("Remove all (Esc)")) clearHandles(state);
    ImGui::EndDisabled();
    if (state.drag.active && state.drag.kind == DragKind::Surface && state.hasReport &&
        state.lastReport.rankDeficient)
        ImGui::TextColored(ImVec4(1.0f, 0.75f, 0.3f, 1.0f), "Constraints conflict: least-squares fit");
}

void drawBrushSection(AppState& state) {
    BrushTool& brush = state.tools.brush;
    // Narrow fields, so the labels beside them fit the panel.
    ImGui::PushItemWidth(ImGui::GetContentRegionAvail().x * 0.5f);
    bool changed = ImGui::Checkbox("Limit to radius", &brush.limited);
    helpMarker("On: a drag moves only the surface within the brush radius of the grabbed point, through a\n"
               "small lattice of its own around it whose outer part is pinned, so the edit blends in smoothly.\n"
               "Off: a drag moves the whole lattice (cage) around the mesh.\n"
               "F and a mouse move sets the radius, Shift+F the strength (click keeps, Esc cancels).");
    ImGui::BeginDisabled(!brush.limited);
    float radius = static_cast<float>(brush.radiusPixels);
    if (ImGui::SliderFloat("Radius (F)", &radius, static_cast<float>(kMinBrushPixels), 400.0f, "%.0f px")) {
        brush.radiusPixels = std::clamp(static_cast<double>(radius), kMinBrushPixels, kMaxBrushPixels);
        changed = true;
    }
    ImGui::EndDisabled();
    // A click of the hammer or the crimp has its own amount (the step, the width factor: T-spline section of the
    // Lattices panel); strength and falloff shape a drag only, so they are greyed out then.
    const bool dragBrush = brush.kind == BrushTool::Kind::Drag;
    float strength = static_cast<float>(brush.settings.strength);
    ImGui::BeginDisabled(!dragBrush);
    if (ImGui::SliderFloat("Strength", &strength, 0.01f, 1.0f, "%.2f")) {
        brush.settings.strength = std::clamp(static_cast<double>(strength), 0.01, 1.0);
        changed = true;
    }
    ImGui::EndDisabled();
    if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
        ImGui::SetTooltip(dragBrush ? "How far the grabbed point follows the cursor: 1 = all the way. Shift+F and a mouse move sets it."
                                    : "Clicks hammer or crimp: their step and width factor are in the T-spline section of the Lattices panel.");
    int falloff = static_cast<int>(brush.settings.falloff);
    ImGui::BeginDisabled(!brush.limited || !dragBrush);
    if (ImGui::Combo("Falloff", &falloff, "Smooth\0Medium\0Sharp\0")) {
        brush.settings.falloff = static_cast<core::BrushFalloff>(falloff);
        changed = true;
    }
    ImGui::EndDisabled();
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("The shape of the pull: smooth (cubic), medium (quadratic) or sharp (linear, a peak).");
    ImGui::TextUnformatted("Symmetry");
    for (int a = 0; a < 3; ++a) {
        ImGui::SameLine();
        const char* names[] = {"X", "Y", "Z"};
        bool mirror = brush.settings.symmetry.mirror[static_cast<size_t>(a)];
        if (ImGui::Checkbox(names[a], &mirror)) {
            brush.settings.symmetry.mirror[static_cast<size_t>(a)] = mirror;
            changed = true;
        }
    }
    helpMarker("Mirror every drag in the planes through the centre of the mesh's bounds at load: the mirror\n"
               "image of the grabbed point moves to the mirror image of its target, exactly.");
    // The engine's setting (the script's set_refinement "under_brush"), journaled so recordings keep it.
    core::RefinementSettings refinement = state.session.refinement().settings();
    ImGui::BeginDisabled(!brush.limited || !dragBrush);
    if (ImGui::Checkbox("Split under the brush", &refinement.underBrush)) state.session.refinement().set(refinement);
    ImGui::EndDisabled();
    helpMarker("On: where a long pull would make the mesh's long straight triangles cut through each other,\n"
               "the triangles under the pull are split (part of the stroke: undo removes them) and the pull\n"
               "goes on. Off: the stroke stops short there and the mesh keeps its triangles.");
    ImGui::PopItemWidth();
    if (changed) state.gpu.fields = true;
}

void drawSelectionSection(AppState& state) {
    ToolState& tools = state.tools;
    clampLatticeSelection(state);
    const core::Lattice& lattice = state.session.lattice();
    size_t pinned = 0;
    for (int id : tools.lattice.points) pinned += lattice.pinned[static_cast<size_t>(id)] ? 1 : 0;
    // note: of a lattice of any shape, each weld group counts once (one marker, one pick).
    int selectable = 0;
    for (int id = 0; id < lattice.controlPointCount(); ++id) selectable += lattice.representative(id) == id;
    ImGui::Text("%zu of %d control points selected", tools.lattice.points.size(), selectable);
    helpMarker("Click a control point to select it, Shift+click toggles it, drag a rectangle on\n"
               "empty space to select what it covers (Shift adds). Drag a selected point to move\n"
               "the selection: one undoable edit, tested for injectivity like any other.\n"
               "P pins or unpins the selection: pinned points (grey squares) never move.");
    // note: the line is always there (empty without a selection), so the rows below never jump.
    const size_t selected = tools.lattice.points.size();
    ImGui::TextDisabled("%s", selected == 0 ? "" : pinned == 0 ? "none of them pinned"
                              : pinned == selected && selected > 1 ? "all of them pinned"
                              : (std::to_string(pinned) + " of them pinned").c_str());
    const float third = (ImGui::GetContentRegionAvail().x - 2.0f * ImGui::GetStyle().ItemSpacing.x) / 3.0f;
    ImGui::BeginDisabled(state.drag.active);
    if (ImGui::Button("All (A)", ImVec2(third, 0.0f))) selectAllControlPoints(state, true);
    ImGui::SameLine();
    if (ImGui::Button("None (Esc)", ImVec2(third, 0.0f))) selectAllControlPoints(state, false);
    ImGui::SameLine();
    ImGui::BeginDisabled(tools.lattice.points.empty());
    const bool allPinned = !tools.lattice.points.empty() && pinned == tools.lattice.points.size();
    if (ImGui::Button(allPinned ? "Unpin (P)" : "Pin (P)", ImVec2(third, 0.0f))) togglePinsOfSelection(state);
    ImGui::EndDisabled();
    ImGui::EndDisabled();
}

void drawSetupSection(AppState& state) {
    ToolState& tools = state.tools;
    if (!tools.setupEdited) tools.setup = state.session.cage().settings();
    core::LatticeSettings& s = tools.setup;
    bool edited = false;
    const float labelWidth = ImGui::CalcTextSize("Pinned layers").x + ImGui::GetStyle().ItemInnerSpacing.x;
    ImGui::PushItemWidth(-labelWidth);
    // One kind of control for every number here, as Blender's fields: drag to change, double-click or
    // Ctrl+click to type; typed values are clamped to the range like dragged ones.
    constexpr ImGuiSliderFlags kClamp = ImGuiSliderFlags_AlwaysClamp;
    edited |= ImGui::DragInt3("Resolution", s.resolution.data(), 0.1f, 2, 64, "%d", kClamp);
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("Control points per axis (degree + 1 to 64).");
    edited |= ImGui::DragInt3("Degree", s.degree.data(), 0.05f, 1, 5, "%d", kClamp);
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("Polynomial degree of the B-splines per axis (1 to 5).");
    float padding = static_cast<float>(s.padding);
    if (ImGui::DragFloat("Padding", &padding, 0.002f, 0.0f, 0.5f, "%.3f", kClamp)) {
        s.padding = padding;
        edited = true;
    }
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("Added on every side of the box, as a fraction of its diagonal.");
    edited |= ImGui::DragInt("Pinned layers", &s.pinLayers, 0.05f, 0, 3, "%d", kClamp);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("Pins the k outer layers of control points: the lattice boundary stays fixed,\n"
                          "which makes the injectivity guarantee global.");
    edited |= ImGui::Checkbox("Region of interest", &s.hasRegion);
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("Off: the box is the mesh bounds. On: only the region moves; the rest stays bitwise.");
    if (s.hasRegion) {
        // The corners are world coordinates: doubles (a float rounds a 1e-3 box at 1e7 to whole units), dragged
        // at 0.5% of the lattice's diagonal per pixel, shown with enough digits to tell its corners apart.
        const double diagonal = state.session.lattice().diagonal();
        const float speed = static_cast<float>(0.005 * diagonal);
        const std::string format = coordinateFormat(std::max(s.regionMin.cwiseAbs().maxCoeff(), s.regionMax.cwiseAbs().maxCoeff()), diagonal);
        if (ImGui::DragScalarN("Min", ImGuiDataType_Double, s.regionMin.data(), 3, speed, nullptr, nullptr, format.c_str(),
                               ImGuiSliderFlags_NoRoundToFormat))
            edited = true;
        if (ImGui::DragScalarN("Max", ImGuiDataType_Double, s.regionMax.data(), 3, speed, nullptr, nullptr, format.c_str(),
                               ImGuiSliderFlags_NoRoundToFormat))
            edited = true;
        const Positions& positions = state.session.mesh().positions;
        if (ImGui::Button("Mesh bounds") && positions.rows() > 0) {
            s.regionMin = positions.colwise().minCoeff().transpose();
            s.regionMax = positions.colwise().maxCoeff().transpose();
            edited = true;
        }
        ImGui::SameLine();
        ImGui::BeginDisabled(tools.lattice.points.empty());
        if (ImGui::Button("Selected points")) {
            const double inf = std::numeric_limits<double>::infinity();
            Eigen::Vector3d a = Eigen::Vector3d::Constant(inf), b = Eigen::Vector3d::Constant(-inf);
            const Positions shown = state.session.cage().cagePoints();
            for (int id : tools.lattice.points) {
                const Eigen::Vector3d p = shown.row(id).transpose();
                a = a.cwiseMin(p);
                b = b.cwiseMax(p);
            }
            s.regionMin = a;
            s.regionMax = b;
            edited = true;
        }
        ImGui::EndDisabled();
        if (ImGui::IsItemHovered()) ImGui::SetTooltip("The box around the selected control points (lattice tool).");
    }
    ImGui::PopItemWidth();
    tools.setupEdited |= edited;
    const Status valid = core::validateLatticeSettings(s);
    if (!valid) ImGui::TextColored(ImVec4(1.0f, 0.45f, 0.4f, 1.0f), "%s", valid.message.c_str());
    ImGui::BeginDisabled(!valid || state.drag.active);
    if (ImGui::Button("Apply set-up")) {
        setupLatticeCommand(state, s);
        tools.setupEdited = false;
    }
    ImGui::EndDisabled();
    if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
        ImGui::SetTooltip("A fresh lattice around the current mesh. The shape does not change; undo returns\nto the previous lattice.");
    ImGui::SameLine();
    ImGui::BeginDisabled(!tools.setupEdited);
    if (ImGui::Button("Reset")) tools.setupEdited = false;
    ImGui::EndDisabled();
}

}  // namespace

void drawToolsWindow(AppState& state, FileCommands* files) {
    const ImGuiViewport* viewport = ImGui::GetMainViewport();
    const float margin = panelMargin();
    const float width = toolsWindowWidth();
    ImGui::SetNextWindowPos(ImVec2(viewport->WorkPos.x + viewport->WorkSize.x - width - margin, viewport->WorkPos.y + margin));
    // Above the status line and the det J legend in the corner below it: what is longer scrolls.
    ImGui::SetNextWindowSizeConstraints(ImVec2(width, 0.0f), ImVec2(width, panelMaxHeight(state, true)));
    ImGui::SetNextWindowBgAlpha(0.92f);
    ImGui::Begin("Tools###tools", nullptr,
                 ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse |
                     ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoSavedSettings);
    int mode = static_cast<int>(state.tools.mode);
    ImGui::BeginDisabled(state.drag.active);
    bool changed = ImGui::RadioButton("Sculpt", &mode, static_cast<int>(ToolMode::Sculpt));
    if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled)) ImGui::SetTooltip("Drag points of the mesh (Tab toggles).");
    ImGui::SameLine();
    changed |= ImGui::RadioButton("Lattice", &mode, static_cast<int>(ToolMode::Lattice));
    if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled)) ImGui::SetTooltip("Pick and drag control points (Tab toggles).");
    ImGui::EndDisabled();
    ImGui::SameLine();
    ImGui::TextDisabled("Tab");
    if (changed) setToolMode(state, static_cast<ToolMode>(mode));
    if (state.tools.mode == ToolMode::Sculpt) {
        if (ImGui::CollapsingHeader("Brush", ImGuiTreeNodeFlags_DefaultOpen)) drawBrushSection(state);
        if (ImGui::CollapsingHeader("Handles and pins", ImGuiTreeNodeFlags_DefaultOpen)) drawHandlesSection(state);
    } else {
        if (ImGui::CollapsingHeader("Selection", ImGuiTreeNodeFlags_DefaultOpen)) drawSelectionSection(state);
    }
    if (ImGui::CollapsingHeader("Lattice set-up", state.tools.mode == ToolMode::Lattice ? ImGuiTreeNodeFlags_DefaultOpen : 0))
        drawSetupSection(state);
    // Lattices of any shape: the tools beside the cage they can become.
    if (files) drawLatticesPanel(state, *files);
    ImGui::End();

    // The selection rectangle of the lattice tool, over the 3D view.
    const LatticeSelection& selection = state.tools.lattice;
    // The control point a click would pick, ringed before the click.
    if (state.tools.mode == ToolMode::Lattice && selection.hovered >= 0 && !state.drag.active && !selection.boxActive) {
        double px = 0.0, py = 0.0;
        if (projectToPixel(state.camera, state.framebufferWidth, state.framebufferHeight, selection.hoveredAt, px, py))
            ImGui::GetForegroundDrawList()->AddCircle(framebufferToUi(state, px, py), 0.55f * ImGui::GetFontSize(),
                                                      IM_COL32(255, 255, 255, 230), 0, 2.0f);
    }
    if (selection.boxActive) {
        const ImVec2 a = framebufferToUi(state, selection.boxX0, selection.boxY0);
        const ImVec2 b = framebufferToUi(state, selection.boxX1, selection.boxY1);
        ImDrawList* draw = ImGui::GetForegroundDrawList();
        draw->AddRectFilled(ImVec2(std::min(a.x, b.x), std::min(a.y, b.y)), ImVec2(std::max(a.x, b.x), std::max(a.y, b.y)),
                            IM_COL32(255, 200, 60, 40));
        draw->AddRect(ImVec2(std::min(a.x, b.x), std::min(a.y, b.y)), ImVec2(std::max(a.x, b.x), std::max(a.y, b.y)),
                      IM_COL32(255, 200, 60, 220), 0.0f, 0, 1.5f);
    }
}

float toolsWindowWidth() { return 19.0f * ImGui::GetFontSize(); }

ImVec2 framebufferToUi(const AppState& state, double x, double y) {
    const ImGuiViewport* viewport = ImGui::GetMainViewport();
    const float scale = viewport->Size.x > 0.0f && state.framebufferWidth > 0
                            ? viewport->Size.x / static_cast<float>(state.framebufferWidth) : 1.0f;
    return ImVec2(viewport->Pos.x + static_cast<float>(x) * scale, viewport->Pos.y + static_cast<float>(y) * scale);
}

}  // namespace sculpt::app
