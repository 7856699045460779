// The window's own file dialog (Debian has no native dialog library we may use): a Dear ImGui modal with the
// current folder, a path field, the folders and the files of the wanted type, parent-folder navigation; a
// double-click or Enter accepts, errors show inside the dialog, and saving over an existing file asks
// "Replace?" first. What it decides comes from the plain functions of app/file_browser.h; this class keeps
// the dialog's state, and submit() is the same path Enter and a double-click take, so tests drive it
// without clicks.
#pragma once

#include <string>
#include <vector>

#include "app/file_browser.h"

namespace sculpt::app {

enum class FileDialogMode { Open, Save };

class FileDialog {
public:
    // Shows the dialog (drawn by draw() from the next frame). title: "Open mesh"; extensions: {".obj"}, the
    // first is appended to a typed save name without one; folder: where to start ("" = the working folder);
    // name: the file name pre-filled (save).
    void open(FileDialogMode mode, const std::string& title, const std::vector<std::string>& extensions,
              const std::string& folder, const std::string& name = {});
    void close();
    bool isOpen() const { return open_; }

    // Takes typed text (a name in the current folder, or a path) as Enter does. A folder is entered; an open
    // of a readable file or a save that needs no question accepts (isOpen() false, acceptedPath() set); a
    // save over an existing file waits for confirmReplace(); anything else sets error(). Returns accepted.
    bool submit(const std::string& typed);
    // Answers "Replace?": yes accepts, no goes back to the dialog.
    bool confirmReplace(bool yes);
    void enterFolder(const std::string& folder);

    // Draws the modal when open. Returns true on the frame the user accepted a path (acceptedPath()).
    bool draw();

    FileDialogMode mode() const { return mode_; }
    const std::string& title() const { return title_; }
    const std::string& folder() const { return listing_.folder; }
    const FolderListing& listing() const { return listing_; }
    const std::string& error() const { return error_; }
    const std::string& replaceCandidate() const { return replacePath_; }  // non-empty while asking "Replace?"
    const std::string& acceptedPath() const { return accepted_; }
    const std::string& typedName() const { return nameBuffer_; }  // the path field: the name a save proposes

private:
    void refresh();
    bool accept(const std::string& path);

    bool open_ = false;
    bool justOpened_ = false;
    FileDialogMode mode_ = FileDialogMode::Open;
    std::string title_;
    std::vector<std::string> extensions_;
    FolderListing listing_;
    std::string nameBuffer_;  // the path field
    std::string error_;
    std::string replacePath_;
    std::string accepted_;
    int selected_ = -1;
};

}  // namespace sculpt::app
