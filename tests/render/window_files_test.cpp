// The window's file commands (app/window/file_commands.h) driven like the UI drives them: background opens
// while frames are drawn, saves that never damage the file on disk, unsaved-changes prompts, sessions and
// screenshots. Frames with the UI use EGL as window_app_test.cpp explains; without EGL those parts warn and
// skip, the rest still runs.
#include <catch2/catch.hpp>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <thread>

#include <stdlib.h>

#include <imgui.h>
#include <imgui_internal.h>

#include "app/window/panels.h"
#include "app/window/sculpt_app.h"
#include "app/window/ui_style.h"
#include "io/script.h"
#include "gl_test_support.h"
#include "offscreen_window.h"
#include "io/mesh_file.h"
#include "io/obj_mesh.h"
#include "io/png_image.h"
#include "io/script_json.h"
#include "render/offscreen_context.h"
#include "render/render_target.h"

using namespace sculpt;

namespace {

constexpr int kWidth = 960, kHeight = 600;

struct TempFolder {
    std::string path;
    TempFolder() {
        std::string pattern = test::glTestOutputDir() + "/files_XXXXXX";
        REQUIRE(::mkdtemp(pattern.data()) != nullptr);
        path = pattern;
    }
    ~TempFolder() {
        std::error_code error;
        std::filesystem::remove_all(path, error);
    }
    std::string file(const std::string& name) const { return path + "/" + name; }
};

std::string readBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

std::string defaultMesh() { return std::string(SCULPT_SOURCE_DIR) + "/assets/default.obj"; }

double diagonal(const Positions& p) { return (p.colwise().maxCoeff() - p.colwise().minCoeff()).norm(); }

// An n x n height field (bumpy sheet) written as OBJ text: n^2 vertices, 2 (n-1)^2 triangles.
void writeGridObj(const std::string& path, int n) {
    std::string text;
    text.reserve(static_cast<size_t>(n) * n * 40);
    char line[96];
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const double x = static_cast<double>(i) / (n - 1), y = static_cast<double>(j) / (n - 1);
            const double z = 0.08 * std::sin(9.0 * x) * std::cos(7.0 * y);
            text.append(line, static_cast<size_t>(std::snprintf(line, sizeof line, "v %.6f %.6f %.6f\n", x, y, z)));
        }
    for (int j = 0; j + 1 < n; ++j)
        for (int i = 0; i + 1 < n; ++i) {
            const int a = j * n + i + 1, b = a + 1, c = a + n, d = c + 1;
            text.append(line, static_cast<size_t>(std::snprintf(line, sizeof line, "f %d %d %d\nf %d %d %d\n", a, b, d, a, d, c)));
        }
    std::ofstream(path, std::ios::binary) << text;
}

// Press on the centre, move up, release: one interactive drag (one history entry).
void dragUp(app::SculptApp& sculptApp, double pixels = 60.0) {
    const double cx = 0.5 * kWidth, cy = 0.5 * kHeight;
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Press, cx, cy, {}}, {});
    for (int m = 1; m <= 4; ++m) sculptApp.onMouseMove({cx, cy - pixels * m / 4, {}}, {});
    sculptApp.onMouseButton({app::MouseButton::Left, app::ButtonAction::Release, cx, cy - pixels, {}}, {});
}

void loadDefault(app::SculptApp& sculptApp, const std::string& path = defaultMesh()) {
    const Status loaded = sculptApp.loadMesh(path);
    INFO(loaded.message);
    REQUIRE(loaded.ok);
    sculptApp.onFramebufferSize({kWidth, kHeight});
    app::frameMesh(sculptApp.state());
}

app::KeyEvent ctrlKey(app::Key key, bool shift = false) {
    app::KeyEvent event;
    event.key = key;
    event.modifiers.control = true;
    event.modifiers.shift = shift;
    return event;
}

// The offscreen window (offscreen_window.h) for a test: background jobs are finished before it closes.
struct UiFrames {
    test::OffscreenWindow window;
    app::SculptApp* app = nullptr;

    bool start(app::SculptApp& sculptApp, int w = kWidth, int h = kHeight) {
        if (const Status opened = window.open(sculptApp, w, h, 4); !opened) {
            WARN("EGL unavailable, UI frames not tested: " << opened.message);
            return false;
        }
        app = &sculptApp;
        return true;
    }
    void frame(render::Rgba8Image* image = nullptr) {
        const Status drawn = window.frame(image);
        INFO(drawn.message);
        REQUIRE(drawn.ok);
    }
    ~UiFrames() {
        if (app) app->files().finishJob(app->state());
        window.close();
    }
};

}  // namespace

TEST_CASE("window files: opening an OBJ runs in the background while frames keep being drawn", "[gl]") {
    // SCULPT_FILES_TEST_GRID=1000 measures the 1M-vertex case (docs/window.md, "Files"); the default keeps the test short.
    const char* gridEnv = std::getenv("SCULPT_FILES_TEST_GRID");
    const int n = gridEnv && *gridEnv ? std::atoi(gridEnv) : 300;
    TempFolder folder;
    const std::string big = folder.file("grid.obj");
    writeGridObj(big, n);
    io::ObjMesh expected;
    REQUIRE(io::loadObj(big, expected).ok);

    app::SculptApp sculptApp;
    loadDefault(sculptApp);
    UiFrames frames;
    const bool withUi = frames.start(sculptApp, 480, 300);
    if (withUi) frames.frame();
    app::FileCommands& files = sculptApp.files();
    const auto start = std::chrono::steady_clock::now();
    REQUIRE(files.startOpen(sculptApp.state(), big));
    CHECK(files.busy());
    CHECK(files.blocksInput());
    // Sculpting input is ignored while the load runs.
    const Positions before = sculptApp.state().session.mesh().positions;
    dragUp(sculptApp);
    CHECK(sculptApp.state().session.history().empty());
    CHECK(sculptApp.state().session.mesh().positions == before);

    int framesDuringLoad = 0;
    float lastFraction = 0.0f;
    bool fractionMonotonic = true;
    while (files.busy()) {
        const float fraction = files.jobFraction();
        fractionMonotonic = fractionMonotonic && fraction + 1e-6f >= lastFraction;
        lastFraction = fraction;
        if (withUi) frames.frame();  // polls the job, draws the progress popup
        else files.poll(sculptApp.state());
        ++framesDuringLoad;
        if (!withUi) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    WARN("background open of " << n * n << " vertices, " << 2 * (n - 1) * (n - 1) << " triangles: " << seconds
                               << " s, " << framesDuringLoad << " frames drawn meanwhile ("
                               << framesDuringLoad / seconds << " fps)");
    CHECK(fractionMonotonic);
    CHECK(framesDuringLoad >= 3);
    INFO(sculptApp.state().status);
    REQUIRE(sculptApp.state().session.mesh().positions.rows() == expected.positions.rows());
    CHECK(sculptApp.state().session.mesh().positions == expected.positions);
    CHECK(sculptApp.state().meshName == "grid.obj");
    CHECK_FALSE(sculptApp.state().modified);
    CHECK(files.document().sourcePath == big);
    if (withUi) {
        frames.frame();
        CHECK(sculptApp.renderer().vertexCount() == n * n);
    }
}

TEST_CASE("window files: a cancelled or failed open changes nothing", "[gl]") {
    TempFolder folder;
    app::SculptApp sculptApp;
    loadDefault(sculptApp);
    dragUp(sculptApp);
    REQUIRE(sculptApp.state().session.history().size() == 1);
    const Positions sculpted = sculptApp.state().session.mesh().positions;
    app::FileCommands& files = sculptApp.files();

    // A broken OBJ: the error names the line, a popup says nothing changed.
    std::ofstream(folder.file("bad.obj")) << "v 0 0 0\nv 1 0 0\nf 1 2 7\n";
    REQUIRE(files.startOpen(sculptApp.state(), folder.file("bad.obj")));
    files.finishJob(sculptApp.state());
    CHECK(sculptApp.state().session.mesh().positions == sculpted);
    CHECK(sculptApp.state().session.history().size() == 1);
    CHECK(sculptApp.state().statusIsError);
    CHECK(files.message().find("bad.obj:3") != std::string::npos);
    files.dismissMessage();

    // Cancel as soon as it starts: nothing changes either.
    const std::string big = folder.file("grid.obj");
    writeGridObj(big, 300);
    REQUIRE(files.startOpen(sculptApp.state(), big));
    files.cancelJob();
    files.finishJob(sculptApp.state());
    CHECK(sculptApp.state().session.mesh().positions == sculpted);
    CHECK(sculptApp.state().status.find("cancelled") != std::string::npos);
    CHECK(files.message().empty());
    CHECK(sculptApp.state().modified);
}

TEST_CASE("window files: save, reload, overwrite only after Replace, failures keep file and dirty flag", "[gl]") {
    TempFolder folder;
    const std::string source = folder.file("blob.obj");
    std::filesystem::copy_file(defaultMesh(), source);
    app::SculptApp sculptApp;
    loadDefault(sculptApp, source);
    app::AppState& state = sculptApp.state();
    app::FileCommands& files = sculptApp.files();
    CHECK_FALSE(files.modified(state));
    CHECK(sculptApp.windowTitle() == "DMFFD Sculpt - blob.obj");
    dragUp(sculptApp);
    files.poll(state);
    CHECK(state.modified);
    CHECK(sculptApp.windowTitle() == "DMFFD Sculpt - blob.obj*");

    // Save As through the dialog: a new name writes; an existing one asks first and changes nothing until yes.
    sculptApp.onKey(ctrlKey(app::Key::S, true), {});
    REQUIRE(files.dialog().isOpen());
    CHECK(files.dialog().mode() == app::FileDialogMode::Save);
    const std::string original = readBytes(source);
    CHECK_FALSE(files.dialog().submit("blob.obj"));
    CHECK(files.dialog().replaceCandidate() == source);
    CHECK(files.dialog().isOpen());
    files.dialog().confirmReplace(false);  // "Keep it"
    CHECK(readBytes(source) == original);
    REQUIRE(files.dialog().submit("sculpted"));  // ".obj" appended
    files.dialogAccepted(state);
    files.finishJob(state);
    INFO(state.status);
    const std::string saved = folder.file("sculpted.obj");
    REQUIRE(std::filesystem::exists(saved));
    CHECK_FALSE(state.modified);
    CHECK(readBytes(source) == original);
    io::ObjMesh reread;
    REQUIRE(io::loadObj(saved, reread).ok);
    CHECK(reread.positions == state.session.mesh().positions);  // shortest round-trip printing: exact
    CHECK(files.document().meshPath == saved);

    // Ctrl+S now writes there without asking.
    dragUp(sculptApp, 30.0);
    files.poll(state);
    REQUIRE(state.modified);
    sculptApp.onKey(ctrlKey(app::Key::S), {});
    CHECK_FALSE(files.dialog().isOpen());
    files.finishJob(state);
    CHECK_FALSE(state.modified);
    REQUIRE(io::loadObj(saved, reread).ok);
    CHECK(reread.positions == state.session.mesh().positions);

    // Failures: a folder in the way, a missing folder. The file on disk keeps its bytes, the work stays dirty.
    dragUp(sculptApp, 20.0);
    files.poll(state);
    REQUIRE(state.modified);
    const std::string savedBytes = readBytes(saved);
    std::filesystem::create_directory(folder.file("folder.obj"));
    for (const std::string& bad : {folder.file("folder.obj"), folder.file("missing/x.obj")}) {
        REQUIRE(files.startSaveMesh(state, bad));
        files.finishJob(state);
        INFO(state.status);
        CHECK(state.statusIsError);
        CHECK(state.status.find("Save failed") != std::string::npos);
        CHECK(state.modified);
        CHECK(readBytes(saved) == savedBytes);
    }
    // Undo back to what was saved: clean again; redo: modified.
    app::undoCommand(state);
    files.poll(state);
    CHECK_FALSE(state.modified);
    app::redoCommand(state);
    files.poll(state);
    CHECK(state.modified);
}

TEST_CASE("window files: a PLY is dropped, sculpted and saved as STL and GLB like an OBJ, other files are refused by name",
          "[gl]") {
    TempFolder folder;
    io::ObjMesh obj;
    REQUIRE(io::loadObj(defaultMesh(), obj).ok);
    const std::string ply = folder.file("scan.ply");
    REQUIRE(io::saveMesh(ply, obj, obj.positions).ok);
    app::SculptApp sculptApp;
    app::AppState& state = sculptApp.state();
    app::FileCommands& files = sculptApp.files();
    sculptApp.onDropFiles({folder.file("scene.fbx")});
    CHECK(state.statusIsError);
    CHECK(state.status.find(".obj .ply .stl .gltf .glb") != std::string::npos);
    sculptApp.onDropFiles({ply});
    files.finishJob(state);
    INFO(state.status);
    REQUIRE(!state.session.mesh().empty());
    CHECK(state.session.mesh().positions == obj.positions.cast<float>().cast<double>());  // PLY holds floats
    CHECK(sculptApp.windowTitle() == "DMFFD Sculpt - scan.ply");
    sculptApp.onFramebufferSize({kWidth, kHeight});
    app::frameMesh(state);
    dragUp(sculptApp);
    files.poll(state);
    REQUIRE(state.modified);
    // A name typed without an extension keeps the document's format.
    sculptApp.onKey(ctrlKey(app::Key::S, true), {});
    REQUIRE(files.dialog().isOpen());
    REQUIRE(files.dialog().submit("kept"));
    files.dialogAccepted(state);
    files.finishJob(state);
    CHECK(std::filesystem::exists(folder.file("kept.ply")));
    dragUp(sculptApp, 20.0);
    files.poll(state);
    for (const char* name : {"sculpted.stl", "sculpted.glb"}) {
        sculptApp.onKey(ctrlKey(app::Key::S, true), {});
        REQUIRE(files.dialog().isOpen());
        REQUIRE(files.dialog().submit(name));
        files.dialogAccepted(state);
        files.finishJob(state);
        INFO(state.status);
        CHECK_FALSE(state.statusIsError);
        CHECK_FALSE(state.modified);
        io::ObjMesh back;
        REQUIRE(io::loadMesh(folder.file(name), back).ok);
        CHECK(back.triangles.rows() == state.session.mesh().triangles.rows());
        if (std::string(name) == "sculpted.glb") CHECK(back.positions == state.session.mesh().positions.cast<float>().cast<double>());
        CHECK(sculptApp.windowTitle() == std::string("DMFFD Sculpt - ") + name);
    }
}

TEST_CASE("window files: after Save as the title, the sidebar header and the save prompt name the new file", "[gl]") {
    TempFolder folder;
    const std::string copy1 = folder.file("copy1.obj");
    std::filesystem::copy_file(defaultMesh(), copy1);
    app::SculptApp sculptApp;
    UiFrames frames;
    const bool ui = frames.start(sculptApp);
    loadDefault(sculptApp, copy1);
    app::AppState& state = sculptApp.state();
    app::FileCommands& files = sculptApp.files();
    for (const std::string& name : {std::string("copy2"), std::string("copy3.obj")}) {
        INFO(name);
        dragUp(sculptApp, 30.0);
        sculptApp.onKey(ctrlKey(app::Key::S, true), {});  // Save as
        REQUIRE(files.dialog().isOpen());
        REQUIRE(files.dialog().submit(name));
        files.dialogAccepted(state);
        files.finishJob(state);
        const std::string fileName = name.find(".obj") == std::string::npos ? name + ".obj" : name;
        CHECK(sculptApp.windowTitle() == "DMFFD Sculpt - " + fileName);
        if (ui) frames.frame();
        CHECK(app::sidebarTitle(state) == "DMFFD Sculpt  -  " + fileName);
        dragUp(sculptApp, 20.0);
        files.poll(state);
        CHECK(sculptApp.windowTitle() == "DMFFD Sculpt - " + fileName + "*");
        sculptApp.requestQuit();
        REQUIRE(files.promptOpen());
        CHECK(files.promptQuestion(state) == "Save changes to " + fileName + " before quitting?");
        if (ui) frames.frame();  // the prompt drawn
        files.answerPrompt(state, app::PromptChoice::Cancel);
        CHECK_FALSE(sculptApp.quitApproved());
        // Save as again offers the current name.
        sculptApp.onKey(ctrlKey(app::Key::S, true), {});
        REQUIRE(files.dialog().isOpen());
        files.dialog().close();
    }
}

TEST_CASE("window files: the first Save over the original input asks once", "[gl]") {
    TempFolder folder;
    const std::string source = folder.file("input.obj");
    std::filesystem::copy_file(defaultMesh(), source);
    app::SculptApp sculptApp;
    loadDefault(sculptApp, source);
    app::AppState& state = sculptApp.state();
    app::FileCommands& files = sculptApp.files();
    dragUp(sculptApp);
    const std::string original = readBytes(source);
    sculptApp.onKey(ctrlKey(app::Key::S), {});
    REQUIRE(files.replaceOriginalOpen());
    files.answerReplaceOriginal(state, 2);  // Cancel
    CHECK_FALSE(files.busy());
    CHECK(readBytes(source) == original);
    sculptApp.onKey(ctrlKey(app::Key::S), {});
    REQUIRE(files.replaceOriginalOpen());
    files.answerReplaceOriginal(state, 0);  // Replace
    files.finishJob(state);
    CHECK(readBytes(source) != original);
    CHECK(files.document().sourceOverwritten);
    CHECK_FALSE(state.modified);
    dragUp(sculptApp, 30.0);
    sculptApp.onKey(ctrlKey(app::Key::S), {});
    CHECK_FALSE(files.replaceOriginalOpen());  // asked once
    files.finishJob(state);
    CHECK_FALSE(state.modified);
}

TEST_CASE("window files: quit and open with unsaved changes ask, Cancel keeps everything", "[gl]") {
    TempFolder folder;
    app::SculptApp sculptApp;
    loadDefault(sculptApp);
    app::AppState& state = sculptApp.state();
    app::FileCommands& files = sculptApp.files();

    sculptApp.requestQuit();  // nothing changed: no question
    CHECK(sculptApp.quitApproved());

    app::SculptApp edited;
    loadDefault(edited);
    app::FileCommands& editedFiles = edited.files();
    dragUp(edited);
    edited.onKey(ctrlKey(app::Key::Q), {});  // Ctrl+Q like the close button
    REQUIRE(editedFiles.promptOpen());
    CHECK(editedFiles.prompt().kind == app::PendingAction::Kind::Quit);
    CHECK_FALSE(edited.quitApproved());
    // While the question is open, sculpting input and shortcuts are ignored.
    const Positions sculpted = edited.state().session.mesh().positions;
    dragUp(edited);
    CHECK(edited.state().session.mesh().positions == sculpted);
    editedFiles.answerPrompt(edited.state(), app::PromptChoice::Cancel);
    CHECK_FALSE(editedFiles.promptOpen());
    CHECK_FALSE(edited.quitApproved());
    CHECK(edited.state().session.history().size() == 1);

    // Drop a mesh: the same question; Don't save opens it.
    const std::string other = folder.file("other.obj");
    writeGridObj(other, 20);
    edited.onDropFiles({folder.file("notes.txt"), other});
    REQUIRE(editedFiles.promptOpen());
    CHECK(editedFiles.prompt().path == other);
    editedFiles.answerPrompt(edited.state(), app::PromptChoice::DontSave);
    editedFiles.finishJob(edited.state());
    CHECK(edited.state().meshName == "other.obj");
    CHECK(edited.state().session.history().empty());

    // Save from the prompt when Save needs a new name and the folder is missing: the prompt comes back with why.
    dragUp(edited);
    edited.requestQuit();
    REQUIRE(editedFiles.promptOpen());
    editedFiles.answerPrompt(edited.state(), app::PromptChoice::Save);
    REQUIRE(editedFiles.replaceOriginalOpen());  // other.obj is the input: Save asks once
    editedFiles.answerReplaceOriginal(edited.state(), 1);  // Save as...
    REQUIRE(editedFiles.dialog().isOpen());
    CHECK_FALSE(editedFiles.dialog().submit(folder.file("missing/x.obj")));
    CHECK_FALSE(editedFiles.dialog().error().empty());  // shown inside the dialog
    std::filesystem::create_directory(folder.file("ro.obj"));
    REQUIRE(editedFiles.dialog().submit(folder.file("saved.obj")));
    editedFiles.dialogAccepted(edited.state());
    editedFiles.finishJob(edited.state());
    CHECK(edited.quitApproved());  // saved, then quit
    CHECK(std::filesystem::exists(folder.file("saved.obj")));
    (void)files;
    (void)state;
}

TEST_CASE("window files: a saved session reopens with the same shape and its operations undoable", "[gl]") {
    TempFolder folder;
    const std::string source = folder.file("blob.obj");
    std::filesystem::copy_file(defaultMesh(), source);
    app::SculptApp sculptApp;
    loadDefault(sculptApp, source);
    app::AppState& state = sculptApp.state();
    app::FileCommands& files = sculptApp.files();
    dragUp(sculptApp);
    dragUp(sculptApp, 30.0);
    const Positions sculpted = state.session.mesh().positions;
    const size_t operations = state.session.history().size();
    REQUIRE(operations == 2);
    const std::string sessionPath = folder.file("work.session.json");
    REQUIRE(files.startSaveSession(state, sessionPath));
    files.finishJob(state);
    INFO(state.status);
    CHECK_FALSE(state.modified);
    io::Script script;
    REQUIRE(io::loadScript(sessionPath, script).ok);
    CHECK(script.mesh == "blob.obj");

    app::SculptApp reopened;
    loadDefault(reopened);
    REQUIRE(reopened.files().startOpen(reopened.state(), sessionPath));
    reopened.files().finishJob(reopened.state());
    INFO(reopened.state().status);
    const core::Session& session = reopened.state().session;
    REQUIRE(session.mesh().positions.rows() == sculpted.rows());
    CHECK((session.mesh().positions - sculpted).cwiseAbs().maxCoeff() <= 1e-9 * diagonal(sculpted));
    // An interactive drag is recorded increment by increment inside begin_group / end_group, so it comes back
    // as one undo step again.
    CHECK(session.history().size() == operations);
    CHECK(session.history().cursor() == static_cast<int>(operations));
    for (size_t i = 0; i < operations; ++i)
        CHECK(session.history()[i].steps.size() == state.session.history()[i].steps.size());
    CHECK_FALSE(reopened.state().modified);
    CHECK(reopened.files().document().sessionPath == sessionPath);
    app::jumpToHistory(reopened.state(), 0);
    CHECK((reopened.state().session.mesh().positions - reopened.state().session.mesh().original).cwiseAbs().maxCoeff() <=
          1e-9 * diagonal(sculpted));

    // Errors change nothing: a missing mesh, bad JSON.
    const Positions current = reopened.state().session.mesh().positions;
    std::filesystem::remove(source);
    REQUIRE(reopened.files().startOpen(reopened.state(), sessionPath));
    reopened.files().finishJob(reopened.state());
    CHECK(reopened.files().message().find("blob.obj") != std::string::npos);
    CHECK(reopened.state().session.mesh().positions == current);
    reopened.files().dismissMessage();
    std::ofstream(folder.file("bad.json")) << "{\"ops\": [ {\"op\": \"drag\"} ]";
    REQUIRE(reopened.files().startOpen(reopened.state(), folder.file("bad.json")));
    reopened.files().finishJob(reopened.state());
    CHECK(reopened.files().message().find("invalid JSON") != std::string::npos);
    CHECK(reopened.state().session.mesh().positions == current);
}

TEST_CASE("window files: screenshot of the 3D view, and the menu bar and dialog drawn", "[gl]") {
    TempFolder folder;
    app::SculptApp sculptApp;
    loadDefault(sculptApp);
    UiFrames frames;
    if (!frames.start(sculptApp)) return;
    frames.frame();
    const std::string shot = folder.file("view.png");
    sculptApp.files().requestScreenshot(shot);
    frames.frame();
    sculptApp.files().finishJob(sculptApp.state());
    int w = 0, h = 0;
    std::vector<std::uint8_t> rgba;
    REQUIRE(io::readPng(shot, w, h, rgba).ok);
    CHECK(w == kWidth);
    CHECK(h == kHeight);
    int distinct = 0;
    for (size_t p = 4; p < rgba.size(); p += 4 * 97)
        if (std::abs(rgba[p] - rgba[0]) + std::abs(rgba[p + 1] - rgba[1]) + std::abs(rgba[p + 2] - rgba[2]) > 30) ++distinct;
    CHECK(distinct > 100);  // the mesh on the background, not one colour
    // Without the UI: the sidebar's corner shows the scene's background, not the dark panel.
    const size_t panel = 4 * (static_cast<size_t>(200) * kWidth + 40);
    CHECK(rgba[panel] > 50);

    // The whole window with the menu bar and the Open dialog, for a look (written to the test output folder).
    dragUp(sculptApp);
    sculptApp.files().openSession(sculptApp.state());  // modified: asks first
    REQUIRE(sculptApp.files().promptOpen());
    render::Rgba8Image prompt, dialog;
    frames.frame();
    frames.frame(&prompt);
    sculptApp.files().answerPrompt(sculptApp.state(), app::PromptChoice::DontSave);
    REQUIRE(sculptApp.files().dialog().isOpen());
    sculptApp.files().dialog().enterFolder(std::string(SCULPT_SOURCE_DIR) + "/assets");
    frames.frame();
    frames.frame(&dialog);
    const std::string dir = test::glTestOutputDir();
    CHECK(io::writePng(dir + "/window_files_prompt.png", prompt.width, prompt.height, prompt.pixels.data()).ok);
    CHECK(io::writePng(dir + "/window_files_dialog.png", dialog.width, dialog.height, dialog.pixels.data()).ok);
    WARN("file UI frames written to " << dir << "/window_files_*.png");
    // The menu bar spans the top row; the sidebar starts below it.
    auto pixel = [](const render::Rgba8Image& im, int x, int y) {
        const size_t i = 4 * (static_cast<size_t>(y) * im.width + x);
        return std::array<int, 3>{im.pixels[i], im.pixels[i + 1], im.pixels[i + 2]};
    };
    // The menu bar's dark background at the top, where the scene alone (the screenshot) shows its gradient.
    const size_t top = 4 * (static_cast<size_t>(4) * kWidth + (kWidth - 300));
    CHECK(pixel(prompt, kWidth - 300, 4)[2] + 15 < rgba[top + 2]);
}

// Issue: triangle soups. A PLY soup (every triangle with corners of its own, as Wuson.ply) loads as it is, with the
// status line saying how many vertices lie on others and offering the weld; with File > Weld coincident vertices
// on open it loads as one surface (each position once, in the order of first use), and a session saved from it
// says so and opens welded again, replaying to the same vertices.
TEST_CASE("window files: a triangle soup is offered the weld, and welded on open it is one surface a session reopens", "[gl][weld]") {
    TempFolder folder;
    io::ObjMesh source;
    REQUIRE(io::loadObj(defaultMesh(), source).ok);
    io::ObjMesh soup;
    const Eigen::Index nt = source.triangles.rows();
    soup.positions.resize(3 * nt, 3);
    soup.triangles.resize(nt, 3);
    soup.faceStart.push_back(0);
    soup.groupNames = {""};
    for (Eigen::Index t = 0; t < nt; ++t) {
        for (int k = 0; k < 3; ++k) {
            soup.positions.row(3 * t + k) = source.positions.row(source.triangles(t, k));
            soup.triangles(t, k) = static_cast<int>(3 * t + k);
            soup.cornerVertex.push_back(static_cast<int>(3 * t + k));
            soup.cornerTexcoord.push_back(-1);
            soup.cornerNormal.push_back(-1);
        }
        soup.faceStart.push_back(static_cast<int>(3 * (t + 1)));
        soup.faceGroup.push_back(0);
        soup.faceMaterial.push_back(-1);
        soup.triangleFace.push_back(static_cast<int>(t));
    }
    const std::string path = folder.file("soup.ply");
    std::vector<std::string> warnings;
    REQUIRE(io::saveMesh(path, soup, soup.positions, &warnings).ok);

    app::SculptApp kept;
    REQUIRE(kept.loadMesh(path).ok);
    CHECK(kept.state().session.mesh().positions.rows() == 3 * nt);
    INFO(kept.state().status);
    CHECK(kept.state().status.find("vertices lie exactly on another") != std::string::npos);
    CHECK(kept.state().status.find("File > Weld coincident vertices on open") != std::string::npos);
    CHECK(kept.state().status.find("crosses itself") == std::string::npos);  // a soup is not a crossing

    app::SculptApp welded;
    welded.files().setWeldOnOpen(true);
    REQUIRE(welded.loadMesh(path).ok);
    app::AppState& state = welded.state();
    INFO(state.status);
    CHECK(state.status.find("Welded") != std::string::npos);
    REQUIRE(state.session.mesh().positions.rows() == source.positions.rows());
    // Each position once: the welded vertices are the source's, in the order the soup first uses them.
    std::vector<char> seen(static_cast<size_t>(source.positions.rows()), 0);
    Eigen::Index next = 0;
    for (Eigen::Index t = 0; t < nt; ++t)
        for (int k = 0; k < 3; ++k) {
            const int v = source.triangles(t, k);
            if (seen[static_cast<size_t>(v)]) continue;
            seen[static_cast<size_t>(v)] = 1;
            // PLY stores single precision: compare with the float the file holds.
            for (int c = 0; c < 3; ++c)
                REQUIRE(state.session.mesh().positions(next, c) == static_cast<double>(static_cast<float>(source.positions(v, c))));
            ++next;
        }
    welded.onFramebufferSize({kWidth, kHeight});
    app::frameMesh(state);
    dragUp(welded);
    REQUIRE(state.session.history().cursor() == 1);
    const Positions after = state.session.mesh().positions;
    REQUIRE(welded.files().startSaveSession(state, folder.file("session.json")));
    welded.files().finishJob(state);
    io::Script script;
    REQUIRE(io::loadScript(folder.file("session.json"), script).ok);
    CHECK(script.weldMesh);
    app::SculptApp reopened;  // weld off: the session's own flag welds
    REQUIRE(reopened.files().startOpen(reopened.state(), folder.file("session.json")));
    reopened.files().finishJob(reopened.state());
    INFO(reopened.state().status);
    REQUIRE(reopened.state().session.mesh().positions.rows() == after.rows());
    CHECK(reopened.state().session.mesh().positions == after);
}

// A new user's trip: a load with four warnings said "4 warnings, first: ..." and nothing in the window showed
// the other three. Now every warning is in the status line's tooltip. Random OBJ files (fixed seed) with
// several kinds of warning (line elements, statements the sculptor does not use, unused vertices, faces that
// repeat a vertex): the tooltip shown when the pointer is over the status line lists exactly what the reader
// warned about, and the next status clears it.
TEST_CASE("window files: every warning of a load is listed in the status line's tooltip", "[gl]") {
    app::SculptApp sculptApp;
    test::OffscreenWindow window;
    if (!window.open(sculptApp, kWidth, kHeight, 0)) return;
    TempFolder folder;
    std::mt19937 random(11);
    for (int trial = 0; trial < 4; ++trial) {
        CAPTURE(trial);
        const int n = 4 + trial;
        std::string text;
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) text += "v " + std::to_string(i) + " " + std::to_string(j) + " " + std::to_string((i * j) % 3) + "\n";
        for (int j = 0; j + 1 < n; ++j)
            for (int i = 0; i + 1 < n; ++i) {
                const int a = j * n + i + 1, b = a + 1, c = a + n, d = c + 1;
                text += "f " + std::to_string(a) + " " + std::to_string(b) + " " + std::to_string(d) + "\nf " + std::to_string(a) + " " +
                        std::to_string(d) + " " + std::to_string(c) + "\n";
            }
        // Some of the warnings the reader gives, chosen at random (at least two).
        const unsigned mask = 1u + static_cast<unsigned>(random() % 3u);  // line elements, unused statements, or both
        int kinds = 1;
        text += "v 9 9 9\n";  // an unused vertex
        if (mask & 1u) text += "l 1 2\n", ++kinds;
        if (mask & 2u) text += "bevel on\n", ++kinds;
        const std::string path = folder.file("warned" + std::to_string(trial) + ".obj");
        std::ofstream(path, std::ios::binary) << text;
        std::vector<std::string> expected;
        io::ObjMesh mesh;
        REQUIRE(io::loadMesh(path, mesh, &expected).ok);  // what the reader itself says, independently
        REQUIRE(expected.size() == static_cast<size_t>(kinds));

        REQUIRE(sculptApp.loadMesh(path).ok);
        app::AppState& state = sculptApp.state();
        INFO(state.status);
        CHECK(state.statusDetails == expected);
        CHECK(state.status.find(std::to_string(kinds) + " warnings (point here for all), first: " + expected.front()) != std::string::npos);
        // The pointer over the status line: the tooltip lists them (one bullet each).
        ImGuiIO& io = ImGui::GetIO();
        for (int f = 0; f < 3; ++f) {  // the tooltip appears, then takes its size a frame later
            io.MousePos = ImVec2(40.0f, static_cast<float>(kHeight) - 0.5f * state.statusLineHeight);
            REQUIRE(window.frame().ok);
        }
        const ImGuiWindow* tooltip = ImGui::FindWindowByName("##Tooltip_00");
        REQUIRE(tooltip != nullptr);
        CHECK(tooltip->Active);
        CHECK(tooltip->Size.y > static_cast<float>(kinds) * ImGui::GetFontSize());  // a line for each
        // Away from the status line: no tooltip; a new status: no details.
        io.MousePos = ImVec2(0.5f * kWidth, 0.5f * kHeight);
        REQUIRE(window.frame().ok);
        CHECK(!ImGui::FindWindowByName("##Tooltip_00")->Active);
        app::setStatus(state, "something else", false);
        CHECK(state.statusDetails.empty());
    }
}
