#include "app/window/ui_style.h"

#include <fstream>

#include <imgui.h>

namespace sculpt::app {
namespace {

bool fileExists(const char* path) { return std::ifstream(path).good(); }

void applyTheme(ImGuiStyle& style) {
    ImGui::StyleColorsDark(&style);
    style.WindowRounding = 6.0f;
    style.ChildRounding = 4.0f;
    style.FrameRounding = 4.0f;
    style.GrabRounding = 4.0f;
    style.PopupRounding = 4.0f;
    style.ScrollbarRounding = 6.0f;
    style.TabRounding = 4.0f;
    style.WindowBorderSize = 0.0f;
    style.FrameBorderSize = 0.0f;
    style.WindowPadding = ImVec2(10.0f, 10.0f);
    style.FramePadding = ImVec2(8.0f, 4.0f);
    style.ItemSpacing = ImVec2(8.0f, 6.0f);
    style.WindowTitleAlign = ImVec2(0.0f, 0.5f);
    ImVec4* c = style.Colors;
    // A neutral slate palette with one blue accent, close to the viewport's background gradient.
    const ImVec4 accent(0.26f, 0.52f, 0.86f, 1.0f);
    c[ImGuiCol_WindowBg] = ImVec4(0.11f, 0.12f, 0.14f, 1.0f);
    // Dialogs and menus opaque (ImGui's default popup is 94% opaque: the mesh showed through the Open dialog's
    // file list), and what a modal dialog covers dimmed enough to read as inactive.
    c[ImGuiCol_PopupBg] = ImVec4(0.13f, 0.14f, 0.16f, 1.0f);
    c[ImGuiCol_ModalWindowDimBg] = ImVec4(0.0f, 0.0f, 0.0f, 0.45f);
    c[ImGuiCol_TitleBg] = ImVec4(0.09f, 0.10f, 0.12f, 1.0f);
    c[ImGuiCol_TitleBgActive] = ImVec4(0.09f, 0.10f, 0.12f, 1.0f);
    c[ImGuiCol_FrameBg] = ImVec4(0.18f, 0.19f, 0.22f, 1.0f);
    c[ImGuiCol_FrameBgHovered] = ImVec4(0.23f, 0.25f, 0.29f, 1.0f);
    c[ImGuiCol_FrameBgActive] = ImVec4(0.27f, 0.29f, 0.34f, 1.0f);
    c[ImGuiCol_Header] = ImVec4(0.20f, 0.22f, 0.26f, 1.0f);
    c[ImGuiCol_HeaderHovered] = ImVec4(0.25f, 0.28f, 0.33f, 1.0f);
    c[ImGuiCol_HeaderActive] = ImVec4(accent.x, accent.y, accent.z, 0.6f);
    c[ImGuiCol_Button] = ImVec4(0.21f, 0.23f, 0.27f, 1.0f);
    c[ImGuiCol_ButtonHovered] = ImVec4(accent.x, accent.y, accent.z, 0.7f);
    c[ImGuiCol_ButtonActive] = accent;
    c[ImGuiCol_CheckMark] = ImVec4(0.45f, 0.68f, 1.0f, 1.0f);
    c[ImGuiCol_SliderGrab] = accent;
    c[ImGuiCol_SliderGrabActive] = ImVec4(0.45f, 0.68f, 1.0f, 1.0f);
    c[ImGuiCol_Separator] = ImVec4(0.25f, 0.27f, 0.31f, 1.0f);
    c[ImGuiCol_Text] = ImVec4(0.90f, 0.91f, 0.93f, 1.0f);
    c[ImGuiCol_TextDisabled] = ImVec4(0.55f, 0.58f, 0.63f, 1.0f);
}

}  // namespace

void createUiContext(float scale) {
    if (!(scale > 0.0f)) scale = 1.0f;
    ImGui::CreateContext();
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr;  // the layout is fixed; do not litter the working directory
    ImGuiStyle& style = ImGui::GetStyle();
    applyTheme(style);
    style.ScaleAllSizes(scale);
    const char* font = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
    // note: AddFontFromFileTTF asserts on a missing file, so check first and keep the built-in font otherwise.
    if (fileExists(font)) io.Fonts->AddFontFromFileTTF(font, 15.0f * scale);
}

void destroyUiContext() {
    if (ImGui::GetCurrentContext()) ImGui::DestroyContext();
}

}  // namespace sculpt::app
