// The file commands' UI (file_commands.h): the File and Edit menus, and the modals (the progress of a load or
// save, the unsaved-changes prompt, replacing the original file, messages).
#include "app/window/file_commands.h"
#include "app/window/file_commands_internal.h"
#include "app/window/wording.h"

#include <string>

#include <imgui.h>

namespace sculpt::app {

using file_commands_detail::secondsSince;
using file_commands_detail::secondsText;

namespace {

// Dear ImGui: a centred modal that opens when wanted and closes itself when no longer wanted.
bool beginModal(const char* id, bool wanted) {
    if (wanted && !ImGui::IsPopupOpen(id)) ImGui::OpenPopup(id);
    ImGui::SetNextWindowPos(ImGui::GetMainViewport()->GetCenter(), ImGuiCond_Appearing, ImVec2(0.5f, 0.5f));
    if (!ImGui::BeginPopupModal(id, nullptr, ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoSavedSettings))
        return false;
    if (!wanted) {
        ImGui::CloseCurrentPopup();
        ImGui::EndPopup();
        return false;
    }
    return true;
}

}  // namespace

// ------------------------------------------------------------------------------------------------- UI

void FileCommands::drawMenuBar(AppState& state) {
    if (!ImGui::BeginMainMenuBar()) return;
    const bool idle = !blocksInput();
    const bool hasMesh = !state.session.mesh().empty();
    if (ImGui::BeginMenu("File")) {
        if (ImGui::MenuItem("Open mesh...", "Ctrl+O", false, idle)) openMesh(state);
        if (ImGui::MenuItem("Save mesh", "Ctrl+S", false, idle && document_.mesh != nullptr)) saveMesh(state);
        if (ImGui::MenuItem("Save mesh as...", "Ctrl+Shift+S", false, idle && document_.mesh != nullptr)) saveMeshAs(state);
        ImGui::Separator();
        if (ImGui::MenuItem("Open session...", nullptr, false, idle)) openSession(state);
        if (ImGui::MenuItem("Save session...", nullptr, false, idle && hasMesh)) saveSession(state);
        ImGui::Separator();
        if (ImGui::MenuItem("Save screenshot...", nullptr, false, idle && hasMesh)) saveScreenshot(state);
        ImGui::Separator();
        ImGui::MenuItem("Weld coincident vertices on open", nullptr, &weldOnOpen_);
        if (ImGui::IsItemHovered())
            ImGui::SetTooltip("Corners at exactly the same position become one vertex when a mesh is opened: a triangle\n"
                              "soup (every triangle with corners of its own) is one smooth surface. Saved meshes keep\n"
                              "the vertices in the file's order, the welded ones once. A session remembers it.");
        ImGui::Separator();
        if (ImGui::MenuItem("Quit", "Ctrl+Q")) requestQuit(state);
        ImGui::EndMenu();
    }
    if (ImGui::BeginMenu("Edit")) {
        const int cursor = state.session.history().cursor();
        const int count = static_cast<int>(state.session.history().size());
        const bool canEdit = idle && !state.drag.active;
        if (ImGui::MenuItem("Undo", "Ctrl+Z", false, canEdit && cursor > 0)) requestHistoryStep(state, -1);
        if (ImGui::MenuItem("Redo", "Ctrl+Shift+Z", false, canEdit && cursor < count)) requestHistoryStep(state, +1);
        ImGui::EndMenu();
    }
    if (ImGui::BeginMenu("View")) {
        if (ImGui::MenuItem("Frame mesh", "F", false, hasMesh)) frameMesh(state);
        ImGui::EndMenu();
    }
    // The document on the right: where Save writes, and whether it has unsaved changes.
    const std::string where = document_.meshPath.empty() ? std::string("no file")
                                                         : document_.meshPath + (state.modified ? "  (modified)" : "");
    const float width = ImGui::CalcTextSize(where.c_str()).x;
    ImGui::SameLine(std::max(ImGui::GetCursorPosX() + ImGui::GetFontSize(),
                             ImGui::GetWindowContentRegionMax().x - width - ImGui::GetStyle().ItemSpacing.x));
    ImGui::TextDisabled("%s", where.c_str());
    ImGui::EndMainMenuBar();
}

void FileCommands::drawModals(AppState& state) {
    const float em = ImGui::GetFontSize();
    const bool wantProgress = busy();
    if (beginModal("Working###file_progress", wantProgress)) {
        ImGui::TextUnformatted(jobLabel().c_str());
        const float fraction = jobFraction();
        char overlay[32];
        std::snprintf(overlay, sizeof overlay, "%.0f%%", 100.0 * fraction);
        ImGui::ProgressBar(fraction, ImVec2(24.0f * em, 0.0f), job_->progress->phase.load() ==
                                                                      static_cast<int>(JobPhase::Writing) ? "" : overlay);
        ImGui::TextDisabled("%s", secondsText(secondsSince(job_->start)).c_str());
        if (loading()) {
            ImGui::SameLine(ImGui::GetWindowContentRegionMax().x - 6.0f * em);
            const bool cancelling = job_->progress->cancelled();
            ImGui::BeginDisabled(cancelling);
            if (ImGui::Button(cancelling ? "Stopping" : "Cancel", ImVec2(6.0f * em, 0.0f))) cancelJob();
            ImGui::EndDisabled();
        }
        ImGui::EndPopup();
    }

    const bool wantPrompt = !wantProgress && promptOpen();
    if (beginModal("Unsaved changes###file_prompt", wantPrompt)) {
        ImGui::TextUnformatted(promptQuestion(state).c_str());
        ImGui::TextDisabled("Without saving, the changes since the last save are lost.");
        if (!promptError_.empty()) {
            ImGui::PushTextWrapPos(32.0f * em);
            ImGui::TextColored(ImVec4(1.0f, 0.45f, 0.4f, 1.0f), "%s", promptError_.c_str());
            ImGui::PopTextWrapPos();
        }
        const ImVec2 button(7.0f * em, 0.0f);
        if (ImGui::Button("Save", button)) answerPrompt(state, PromptChoice::Save);
        ImGui::SameLine();
        if (ImGui::Button("Don't save", button)) answerPrompt(state, PromptChoice::DontSave);
        ImGui::SameLine();
        if (ImGui::Button("Cancel", button) || ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Escape), false))
            answerPrompt(state, PromptChoice::Cancel);
        ImGui::EndPopup();
    }

    const bool wantReplace = !wantProgress && !wantPrompt && replaceOriginal_;
    if (beginModal("Replace the original?###file_replace_original", wantReplace)) {
        ImGui::Text("%s is the mesh this work started from.", fileNameOfPath(document_.meshPath).c_str());
        ImGui::TextDisabled("Replacing it keeps the sculpted shape only; Save as keeps the original too.");
        const ImVec2 button(8.0f * em, 0.0f);
        if (ImGui::Button("Replace", button)) answerReplaceOriginal(state, 0);
        ImGui::SameLine();
        if (ImGui::Button("Save as...", button)) answerReplaceOriginal(state, 1);
        ImGui::SameLine();
        if (ImGui::Button("Cancel", button) || ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Escape), false))
            answerReplaceOriginal(state, 2);
        ImGui::EndPopup();
    }

    if (!wantProgress && !wantPrompt && !wantReplace) {
        // note: drawn closed too, so that a dialog closed outside its draw() (close(), submit()) closes its modal.
        const bool wasOpen = dialog_.isOpen();
        if (dialog_.draw()) dialogAccepted(state);
        if (wasOpen && !dialog_.isOpen() && dialog_.acceptedPath().empty()) dialogThen_ = {};  // cancelled
    }

    const bool wantMessage = !wantProgress && !wantPrompt && !wantReplace && !dialog_.isOpen() && !message_.empty();
    if (beginModal((messageTitle_ + "###file_message").c_str(), wantMessage)) {
        ImGui::PushTextWrapPos(36.0f * em);
        ImGui::TextUnformatted(message_.c_str());
        ImGui::PopTextWrapPos();
        if (ImGui::Button("OK", ImVec2(6.0f * em, 0.0f)) ||
            ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Enter), false) ||
            ImGui::IsKeyPressed(ImGui::GetKeyIndex(ImGuiKey_Escape), false))
            message_.clear();
        ImGui::EndPopup();
    }
}

}  // namespace sculpt::app
