// The window's file commands (issue item 8): open and save OBJ meshes, save and open sessions, save a
// screenshot of the 3D view, quit, and drag-and-drop, with the guarantees a modelling tool owes its user:
//
//   - Nothing is lost silently: opening another mesh or session, dropping a file or quitting with unsaved
//     changes asks "Save changes to X?" [Save] [Don't save] [Cancel]; a Save that fails keeps the question
//     (and the work) and says why.
//   - Nothing is overwritten silently: every Save dialog asks "Replace?" for an existing file, and the first
//     "Save mesh" over the original input asks once (the session's history starts from that file).
//   - Long work does not freeze the window: loading (OBJ parse, lattice embedding, replaying a session) and
//     saving run on a worker thread on data of their own (a separate Session, a copy of the positions), while
//     the window keeps drawing a progress popup with a Cancel button for loads. The app's session is only
//     touched on the main thread, when poll() installs a finished load; sculpting input is ignored meanwhile.
//   - Saves are atomic (io::writeFileAtomically): a failed save never damages the existing file, the error
//     goes to the status line and the document stays modified.
//
// A session file is what `sculpt --headless --save-session` writes (io::recordSession) plus "mesh", the
// OBJ it applies to, relative to the session file. Opening it loads that mesh and replays the operations, so
// the history comes back as real undoable operations.
#pragma once

#include <chrono>
#include <functional>
#include <future>
#include <memory>
#include <string>
#include <vector>

#include "app/document.h"
#include "app/window/app_state.h"
#include "app/window/file_dialog.h"
#include "app/window/input_events.h"
#include "render/gl_proc.h"

namespace sculpt::render {
struct GlFunctions;
}

namespace sculpt::app {

// What waits behind the unsaved-changes prompt (or a save started from it).
struct PendingAction {
    enum class Kind { None, Quit, OpenMeshDialog, OpenSessionDialog, OpenPath };
    Kind kind = Kind::None;
    std::string path;  // OpenPath: an .obj mesh or a .json session
};

enum class PromptChoice { Save, DontSave, Cancel };

// Progress of the background job, written by the worker, read by the UI.
struct JobProgress;
struct JobResult;

class FileCommands {
public:
    FileCommands();
    ~FileCommands();  // cancels a running load and waits for the worker (a save is allowed to finish)
    FileCommands(const FileCommands&) = delete;
    FileCommands& operator=(const FileCommands&) = delete;

    // Loads an OBJ on the calling thread through the same install as the background path (start-up, tests).
    // On failure nothing changes.
    Status loadMeshNow(AppState& state, const std::string& path);

    // --- Commands (menu items, shortcuts, drops). Each respects a running job and unsaved changes.
    void openMesh(AppState& state);                            // prompt if modified, then the Open dialog
    void openSession(AppState& state);                         // prompt if modified, then the Open dialog
    void openPath(AppState& state, const std::string& path);   // a mesh (.obj) or session (.json); prompt first
    void saveMesh(AppState& state);                            // to the document's mesh path (asks the first
                                                               // time that is the original input)
    void saveMeshAs(AppState& state);                          // Save dialog
    void saveSession(AppState& state);                         // Save dialog (pre-filled with the last one)
    void saveScreenshot(AppState& state);                      // Save dialog; captured at the next frame
    // Lattices panel (lattice_commands.h): Open dialog for a *.lattice.json to add to the library, and Save
    // dialog for lattice tool `tool` (written at once, atomically).
    void openLatticeFile(AppState& state);
    void saveLatticeFile(AppState& state, int tool);
    void requestQuit(AppState& state);                         // prompt if modified, then quitApproved()

    // --- Without dialogs (what the dialogs call once a path is chosen; tests call them directly).
    // Starts a background load of a mesh or session; no prompt (the caller has asked). False if busy.
    bool startOpen(AppState& state, const std::string& path);
    // Starts a background save; the path was confirmed (dialog, "Replace?"). False if busy or nothing to save.
    bool startSaveMesh(AppState& state, const std::string& path);
    bool startSaveSession(AppState& state, const std::string& path);
    // The next frame's scene (without UI) is written to path (PNG) by afterSceneDrawn.
    void requestScreenshot(const std::string& path);

    // --- Prompts and questions.
    bool promptOpen() const { return prompt_.kind != PendingAction::Kind::None; }
    const PendingAction& prompt() const { return prompt_; }
    const std::string& promptError() const { return promptError_; }
    // "Save changes to copy2.obj before quitting?": the prompt's question, naming the document as it is now.
    std::string promptQuestion(const AppState& state) const;
    void answerPrompt(AppState& state, PromptChoice choice);
    bool replaceOriginalOpen() const { return replaceOriginal_; }
    // "Replace the original mesh?": 0 = replace, 1 = save as, 2 = cancel.
    void answerReplaceOriginal(AppState& state, int choice);
    FileDialog& dialog() { return dialog_; }
    // An error shown in a popup (a mesh or session that could not be opened); empty when none.
    const std::string& message() const { return message_; }
    void dismissMessage() { message_.clear(); }
    // Whatever the open dialog's accepted path is for (what dialog().submit accepted): does it.
    void dialogAccepted(AppState& state);

    // --- Per frame.
    // Installs a finished job's result (main thread), runs what waited for it, refreshes state.modified.
    void poll(AppState& state);
    // Blocks until the running job (if any) is done and installed (tests, shutdown).
    void finishJob(AppState& state);
    bool busy() const;
    bool loading() const;  // busy with a load (what Cancel stops)
    // File > Weld coincident vertices on open (io/mesh_weld.h): the next meshes opened are welded; off at start.
    bool weldOnOpen() const { return weldOnOpen_; }
    void setWeldOnOpen(bool weld) { weldOnOpen_ = weld; }
    void cancelJob();
    float jobFraction() const;
    std::string jobLabel() const;
    // Input that must not reach the sculpting code: a job runs, or a modal question or dialog is open.
    bool blocksInput() const;
    bool quitApproved() const { return quitApproved_; }
    const Document& document() const { return document_; }
    bool modified(const AppState& state) const;
    // "DMFFD Sculpt - default.obj*" (the star: unsaved changes).
    std::string windowTitle(const AppState& state) const;
    // Ctrl+O, Ctrl+S, Ctrl+Shift+S, Ctrl+Q (Ctrl or Super). Returns true when the key was used or must be
    // ignored (a job runs or a modal is open), so the caller does not act on it.
    bool onKey(AppState& state, const KeyEvent& event);

    // --- Graphics (the screenshot readback).
    void initGraphics(render::GlGetProc getProc);
    // Called right after the scene is drawn, before the UI: captures a requested screenshot of the bound
    // framebuffer (width x height) and writes it in the background.
    void afterSceneDrawn(AppState& state, int width, int height);

    // --- UI (Dear ImGui).
    void drawMenuBar(AppState& state);
    void drawModals(AppState& state);

private:
    bool weldOnOpen_ = false;
    enum class JobKind { LoadMesh, OpenSession, SaveMesh, SaveSession, SaveScreenshot };
    enum class DialogPurpose { OpenMesh, OpenSession, SaveMeshAs, SaveSession, SaveScreenshot, OpenLattice, SaveLattice };
    struct Job;
    bool ask(AppState& state, const PendingAction& action);  // true: nothing to ask, go ahead
    void proceed(AppState& state, const PendingAction& action);
    void saveMeshThen(AppState& state, const PendingAction& then);
    void openDialog(DialogPurpose purpose, const PendingAction& then = {});
    bool startSave(AppState& state, JobKind kind, const std::string& path, const PendingAction& then);
    void startJob(AppState& state, JobKind kind, const std::string& path, std::function<JobResult(JobProgress&)> work);
    void install(AppState& state, Job& job, JobResult& result);
    std::string startFolder() const;

    Document document_;
    FileDialog dialog_;
    DialogPurpose dialogPurpose_ = DialogPurpose::OpenMesh;
    PendingAction dialogThen_;   // run after a save chosen in the dialog succeeds (from the prompt)
    PendingAction prompt_;
    std::string promptError_;
    bool replaceOriginal_ = false;
    PendingAction replaceThen_;
    std::string messageTitle_, message_;  // an error worth a popup (a session that cannot be opened)
    std::unique_ptr<Job> job_;
    PendingAction afterJob_;  // quit requested while a job ran
    std::string screenshotPath_;
    int latticeToSave_ = -1;  // SaveLattice: the lattice tool's index, the fresh name the file gets by
    std::string latticeToSaveName_;  // default (freshLatticeName) and the folder the dialog opens in (the
    std::string latticeSaveFolder_;  // user's library, userLatticeFolder)
    std::unique_ptr<render::GlFunctions> gl_;
    bool quitApproved_ = false;
};

}  // namespace sculpt::app
