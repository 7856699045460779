#include "app/window/file_dialog.h"

#include <algorithm>
#include <cstdio>

#include <imgui.h>
#include <imgui_stdlib.h>

namespace sculpt::app {
namespace {

std::string sizeText(std::uintmax_t bytes) {
    char text[32];
    if (bytes >= (1u << 20)) std::snprintf(text, sizeof text, "%.1f MiB", static_cast<double>(bytes) / (1 << 20));
    else if (bytes >= 1024) std::snprintf(text, sizeof text, "%.1f KiB", static_cast<double>(bytes) / 1024);
    else std::snprintf(text, sizeof text, "%d B", static_cast<int>(bytes));
    return text;
}

}  // namespace

void FileDialog::open(FileDialogMode mode, const std::string& title, const std::vector<std::string>& extensions,
                      const std::string& folder, const std::string& name) {
    open_ = true;
    justOpened_ = true;
    mode_ = mode;
    title_ = title;
    extensions_ = extensions;
    nameBuffer_ = name;
    error_.clear();
    replacePath_.clear();
    accepted_.clear();
    enterFolder(folder.empty() ? "." : folder);
}

void FileDialog::close() {
    open_ = false;
    replacePath_.clear();
}

void FileDialog::refresh() {
    listing_ = listFolder(listing_.folder, extensions_);
    selected_ = -1;
}

void FileDialog::enterFolder(const std::string& folder) {
    const std::string previous = listing_.folder;
    FolderListing listing = listFolder(folder, extensions_);
    if (!listing.error.empty() && !previous.empty()) {
        error_ = listing.error;  // stay where we were; an unreadable folder is a message, never a crash
        return;
    }
    listing_ = std::move(listing);
    error_ = listing_.error;
    selected_ = -1;
}

bool FileDialog::accept(const std::string& path) {
    accepted_ = path;
    open_ = false;
    replacePath_.clear();
    error_.clear();
    return true;
}

bool FileDialog::submit(const std::string& typed) {
    if (!open_) return false;
    error_.clear();
    replacePath_.clear();
    if (typed.empty()) {
        error_ = mode_ == FileDialogMode::Open ? "Choose a file." : "Type a file name.";
        return false;
    }
    std::string path = joinPath(listing_.folder, typed);
    if (mode_ == FileDialogMode::Open) {
        const OpenCheck check = checkOpenPath(path);
        if (check.isFolder) {
            enterFolder(path);
            nameBuffer_.clear();
            return false;
        }
        if (!check.ok) {
            error_ = check.error;
            return false;
        }
        return accept(path);
    }
    const SaveCheck folderCheck = checkSavePath(path);
    if (folderCheck.verdict == SaveVerdict::EnterFolder) {
        enterFolder(path);
        nameBuffer_.clear();
        return false;
    }
    path = withDefaultExtension(path, extensions_.empty() ? std::string() : extensions_.front(), extensions_);
    const SaveCheck check = checkSavePath(path);
    switch (check.verdict) {
        case SaveVerdict::Write: return accept(path);
        case SaveVerdict::ConfirmReplace: replacePath_ = path; return false;
        case SaveVerdict::EnterFolder:
            enterFolder(path);
            nameBuffer_.clear();
            return false;
        case SaveVerdict::Refuse: error_ = check.error; return false;
    }
    return false;
}

bool FileDialog::confirmReplace(bool yes) {
    if (replacePath_.empty()) return false;
    if (yes) return accept(replacePath_);
    replacePath_.clear();
    return false;
}

bool FileDialog::draw() {
    const std::string popupId = title_ + "###file_dialog";
    if (!open_) {
        // Closed outside draw() (close() on quit, submit() from a test): ImGui's modal is still open and would
        // take every click. note: BeginPopupModal returns false at once when it is not open.
        if (ImGui::BeginPopupModal(popupId.c_str(), nullptr, ImGuiWindowFlags_NoSavedSettings)) {
            ImGui::CloseCurrentPopup();
            ImGui::EndPopup();
        }
        return false;
    }
    if (!ImGui::IsPopupOpen("###file_dialog")) ImGui::OpenPopup(popupId.c_str());
    const float em = ImGui::GetFontSize();
    const ImGuiViewport* viewport = ImGui::GetMainViewport();
    ImGui::SetNextWindowPos(viewport->GetCenter(), ImGuiCond_Appearing, ImVec2(0.5f, 0.5f));
    ImGui::SetNextWindowSize(ImVec2(std::min(40.0f * em, viewport->Size.x - 2 * em),
                                    std::min(28.0f * em, viewport->Size.y - 2 * em)),
                             ImGuiCond_Appearing);
    bool accepted = false;
    if (!ImGui::BeginPopupModal(popupId.c_str(), nullptr, ImGuiWindowFlags_NoSavedSettings)) return false;

    // The folder line: parent button, then the folder itself.
    if (ImGui::Button("Up")) enterFolder(parentFolder(listing_.folder));
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("Parent folder");
    ImGui::SameLine();
    if (ImGui::Button("Refresh")) refresh();
    ImGui::SameLine();
    ImGui::TextDisabled("in");
    ImGui::SameLine();
    ImGui::TextUnformatted(listing_.folder.c_str());

    // The list: folders first ("name/"), then files with their sizes.
    const float footer = 3.2f * ImGui::GetFrameHeightWithSpacing() + (error_.empty() ? 0.0f : ImGui::GetTextLineHeightWithSpacing());
    std::string enter;
    if (ImGui::BeginChild("##entries", ImVec2(0.0f, -footer), true)) {
        if (listing_.entries.empty())
            ImGui::TextDisabled("%s", listing_.error.empty() ? "(no folders or matching files here)" : "(cannot be read)");
        for (int i = 0; i < static_cast<int>(listing_.entries.size()); ++i) {
            const FolderEntry& entry = listing_.entries[static_cast<size_t>(i)];
            const std::string label = (entry.isFolder ? entry.name + "/" : entry.name) + "##e" + std::to_string(i);
            if (entry.isFolder) ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(0.55f, 0.75f, 1.0f, 1.0f));
            const bool clicked = ImGui::Selectable(label.c_str(), selected_ == i, ImGuiSelectableFlags_AllowDoubleClick |
                                                                                   ImGuiSelectableFlags_SpanAllColumns);
            if (entry.isFolder) ImGui::PopStyleColor();
            if (!entry.isFolder) {
                ImGui::SameLine(ImGui::GetWindowContentRegionMax().x - 6.0f * em);
                ImGui::TextDisabled("%s", sizeText(entry.bytes).c_str());
            }
            if (clicked) {
                selected_ = i;
                if (!entry.isFolder) nameBuffer_ = entry.name;
                if (ImGui::IsMouseDoubleClicked(ImGuiMouseButton_Left)) enter = entry.name;
            }
        }
    }
    ImGui::EndChild();
    if (!enter.empty()) {
        const FolderEntry* entry = nullptr;
        for (const FolderEntry& e : listing_.entries)
            if (e.name == enter) entry = &e;
        if (entry && entry->isFolder) enterFolder(joinPath(listing_.folder, enter));
        else accepted = submit(enter);
    }

    // The path field: a name in this folder or any path; Enter accepts.
    ImGui::AlignTextToFramePadding();
    ImGui::TextUnformatted(mode_ == FileDialogMode::Save ? "Save as" : "File");
    ImGui::SameLine();
    ImGui::SetNextItemWidth(-1.0f);
    if (justOpened_) ImGui::SetKeyboardFocusHere();
    justOpened_ = false;
    const bool entered = ImGui::InputText("##path", &nameBuffer_, ImGuiInputTextFlags_EnterReturnsTrue);
    if (entered && replacePath_.empty()) {
        accepted = submit(nameBuffer_) || accepted;
        ImGui::SetKeyboardFocusHere(-1);  // keep typing after an error
    }
    if (!error_.empty()) ImGui::TextColored(ImVec4(1.0f, 0.45f, 0.4f, 1.0f), "%s", error_.c_str());

    if (!replacePath_.empty()) {
        ImGui::TextColored(ImVec4(1.0f, 0.8f, 0.35f, 1.0f), "%s already exists. Replace it?",
                           fileNameOfPath(replacePath_).c_str());
        if (ImGui::Button("Replace")) accepted = confirmReplace(true);
        ImGui::SameLine();
        if (ImGui::Button("Keep it")) confirmReplace(false);
    } else {
        std::string filter;
        for (const std::string& extension : extensions_) filter += (filter.empty() ? "" : " ") + extension;
        ImGui::TextDisabled("Filter: %s", extensions_.empty() ? "all files" : filter.c_str());
        ImGui::SameLine(ImGui::GetWindowContentRegionMax().x - 11.0f * em);
        if (ImGui::Button(mode_ == FileDialogMode::Save ? "Save" : "Open", ImVec2(5.0f * em, 0.0f)))
            accepted = submit(nameBuffer_) || accepted;
        ImGui::SameLine();
        if (ImGui::Button("Cancel", ImVec2(5.0f * em, 0.0f)) ||
            ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Escape), false))
            close();
    }
    if (!open_) ImGui::CloseCurrentPopup();
    ImGui::EndPopup();
    return accepted;
}

}  // namespace sculpt::app
