#include "app/window/file_commands.h"
#include "app/window/file_commands_internal.h"
#include "app/window/lattice_commands.h"
#include "app/window/wording.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <system_error>
#include <utility>

#include <imgui.h>

#include "io/script.h"
#include "io/atomic_file.h"
#include "io/mesh_file.h"
#include "io/mesh_weld.h"
#include "io/png_image.h"
#include "io/script_json.h"
#include "render/framebuffer_readback.h"
#include "render/gl_functions.h"

namespace sculpt::app {

using file_commands_detail::secondsSince;
using file_commands_detail::secondsText;

namespace {

namespace fs = std::filesystem;

const std::vector<std::string> kSessionExtensions{".json"};
const std::vector<std::string> kLatticeExtensions{".lattice.json"};
const std::vector<std::string> kImageExtensions{".png"};

bool sameFile(const std::string& a, const std::string& b) {
    std::error_code error;
    const bool same = fs::equivalent(a, b, error);
    return !error && same;
}

// The lattice a newly opened mesh gets: the current resolution, degree, padding and pins, but no region
// (a box of the old mesh means nothing for another one).
core::LatticeSettings settingsForNewMesh(const core::Session& session) {
    core::LatticeSettings settings = !session.mesh().empty() ? session.cage().initialSettings() : core::LatticeSettings{};
    settings.hasRegion = false;
    return settings;
}

// " 2 warnings (point here for all), first: ..." after a load's or a save's status line; "" without warnings.
// The status line's tooltip lists them all (AppState::statusDetails).
std::string warningsText(const std::vector<std::string>& warnings) {
    if (warnings.empty()) return {};
    if (warnings.size() == 1) return " Warning: " + warnings.front();
    return " " + countOf(warnings.size(), "warning") + " (point here for all), first: " + warnings.front();
}

// --- Worker side: these run on the job's thread and touch nothing but their arguments.

Status cancelledStatus(const std::string& path) { return Status::error(path + ": loading cancelled"); }


// Welds the loaded mesh when asked; otherwise counts what a weld would join (the status line offers it).
void weldOrCount(io::ObjMesh& mesh, bool weld, JobResult& result) {
    result.welded = weld;
    if (weld) {
        result.weld = io::weldCoincidentVertices(mesh);
        return;
    }
    result.weld = io::countCoincidentVertices(mesh.positions);
}

JobResult loadMeshWork(const std::string& path, const core::LatticeSettings& settings,
                       const core::InjectivitySettings& injectivity, bool trackJacobian, bool weld, JobProgress& progress) {
    JobResult result;
    io::ObjMesh mesh;
    result.status = io::loadMesh(path, mesh, &result.warnings, &progress.obj);
    if (!result.status) return result;
    weldOrCount(mesh, weld, result);
    if (progress.cancelled()) {
        result.status = cancelledStatus(path);
        return result;
    }
    progress.phase = static_cast<int>(JobPhase::Embedding);
    result.session.setInjectivity(injectivity);
    if (Status s = result.session.setMesh(mesh.positions, mesh.triangles, settings); !s) {
        result.status = Status::error(path + ": " + s.message);
        return result;
    }
    result.session.setTrackJacobian(trackJacobian);
    result.mesh = std::make_shared<const io::ObjMesh>(std::move(mesh));
    result.meshPath = path;
    result.status = progress.cancelled() ? cancelledStatus(path) : Status::success();
    return result;
}

JobResult openSessionWork(const std::string& path, const std::string& fallbackMesh, bool trackJacobian,
                          JobProgress& progress) {
    JobResult result;
    io::Script script;
    if (result.status = io::loadScript(path, script); !result.status) return result;
    std::string meshPath = io::resolveScriptMesh(script, path);
    if (meshPath.empty()) meshPath = fallbackMesh;  // a recording without "mesh" replays on the open mesh
    if (meshPath.empty()) {
        result.status = Status::error(path + ": the session names no mesh (\"mesh\" field) and none is open");
        return result;
    }
    if (const OpenCheck check = checkOpenPath(meshPath); !check.ok) {
        result.status = Status::error(path + ": its mesh " + meshPath + " cannot be opened (" +
                                      (check.isFolder ? std::string("it is a folder") : check.error) + ")");
        return result;
    }
    io::ObjMesh mesh;
    if (Status s = io::loadMesh(meshPath, mesh, &result.warnings, &progress.obj); !s) {
        result.status = Status::error(path + ": its mesh: " + s.message);
        return result;
    }
    weldOrCount(mesh, script.weldMesh, result);  // as it was recorded
    progress.phase = static_cast<int>(JobPhase::Embedding);
    core::Session& session = result.session;
    if (Status s = session.setMesh(mesh.positions, mesh.triangles, script.lattice); !s) {
        result.status = Status::error(path + ": " + meshPath + ": " + s.message);
        return result;
    }
    session.setInjectivity(script.injectivity);
    session.setTrackJacobian(trackJacobian);  // before the replay: frames frozen by it must count
    progress.phase = static_cast<int>(JobPhase::Replaying);
    progress.opsTotal = static_cast<int>(script.ops.size());
    // The progress callback moves the bar and hears Cancel between ops; a recording's screenshot ops are for
    // the command line and are skipped here.
    const io::ScreenshotHook skipScreenshot = [&result](const core::Session&, const io::ScriptOp&) {
        ++result.screenshotsSkipped;
        return Status::success();
    };
    const io::ScriptProgress report = [&progress](size_t done, size_t) {
        progress.opsDone = static_cast<int>(done);
        return !progress.cancelled();
    };
    io::ScriptReport replay;
    if (Status s = io::runScript(session, script, replay, skipScreenshot, report); !s) {
        result.status = progress.cancelled() ? cancelledStatus(path) : Status::error(path + ": " + s.message);
        return result;
    }
    for (const core::OpReport& op : replay.ops) {
        result.opsReplayed += op.op != "screenshot";
        result.opsRejected += op.status == core::OpStatus::Rejected;
    }
    result.mesh = std::make_shared<const io::ObjMesh>(std::move(mesh));
    result.meshPath = meshPath;
    result.status = Status::success();
    return result;
}

}  // namespace

FileCommands::FileCommands() = default;

FileCommands::~FileCommands() {
    if (!job_) return;
    if (job_->kind == JobKind::LoadMesh || job_->kind == JobKind::OpenSession) cancelJob();
    job_->result.wait();
}

// ---------------------------------------------------------------------------------------------- loading

Status FileCommands::loadMeshNow(AppState& state, const std::string& path) {
    if (busy()) return Status::error("another file operation is running");
    JobProgress progress;
    JobResult result = loadMeshWork(path, settingsForNewMesh(state.session), state.session.injectivity(),
                                    state.overlays.jacobian, weldOnOpen_, progress);
    if (!result.status) return result.status;
    Job job;
    job.kind = JobKind::LoadMesh;
    job.path = path;
    install(state, job, result);
    return Status::success();
}

bool FileCommands::startOpen(AppState& state, const std::string& path) {
    if (busy()) {
        setStatus(state, "Wait for the running file operation to finish.", true);
        return false;
    }
    if (state.drag.active) {
        setStatus(state, "Finish the drag first.", true);
        return false;
    }
    const std::string shown = fileNameOfPath(path);
    if (hasExtension(path, kSessionExtensions)) {
        const std::string fallback = document_.sourcePath;
        const bool track = state.overlays.jacobian;
        startJob(state, JobKind::OpenSession, path, [path, fallback, track](JobProgress& progress) {
            return openSessionWork(path, fallback, track, progress);
        });
    } else {
        const core::LatticeSettings settings = settingsForNewMesh(state.session);
        const core::InjectivitySettings injectivity = state.session.injectivity();
        const bool track = state.overlays.jacobian, weld = weldOnOpen_;
        startJob(state, JobKind::LoadMesh, path, [path, settings, injectivity, track, weld](JobProgress& progress) {
            return loadMeshWork(path, settings, injectivity, track, weld, progress);
        });
    }
    setStatus(state, "Opening " + shown + "...", false);
    return true;
}

void FileCommands::startJob(AppState& /*state*/, JobKind kind, const std::string& path,
                            std::function<JobResult(JobProgress&)> work) {
    auto job = std::make_unique<Job>();
    job->kind = kind;
    job->path = path;
    std::shared_ptr<JobProgress> progress = job->progress;
    job->result = std::async(std::launch::async, [work = std::move(work), progress]() { return work(*progress); });
    job_ = std::move(job);
}

// ----------------------------------------------------------------------------------------------- saving

bool FileCommands::startSaveMesh(AppState& state, const std::string& path) {
    return startSave(state, JobKind::SaveMesh, path, {});
}

bool FileCommands::startSaveSession(AppState& state, const std::string& path) {
    return startSave(state, JobKind::SaveSession, path, {});
}

bool FileCommands::startSave(AppState& state, JobKind kind, const std::string& path, const PendingAction& then) {
    if (busy()) {
        setStatus(state, "Wait for the running file operation to finish.", true);
        return false;
    }
    if (!document_.mesh || state.session.mesh().empty()) {
        setStatus(state, "Nothing to save: no mesh is open.", true);
        return false;
    }
    if (state.drag.active) {
        setStatus(state, "Finish the drag first.", true);
        return false;
    }
    const HistoryMark mark = markHistory(state.session);
    std::shared_ptr<const io::ObjMesh> mesh = document_.mesh;
    if (kind == JobKind::SaveMesh) {
        // note: a copy of the positions (24 MB for 1M vertices, a few ms): the worker never reads the session.
        Positions positions = state.session.mesh().positions;
        std::vector<core::EdgeSplit> splits = state.session.refinement().appliedSplits();  // a refined mesh: its splits
        startJob(state, kind, path, [path, mesh, positions = std::move(positions), splits = std::move(splits)](JobProgress& progress) {
            progress.phase = static_cast<int>(JobPhase::Writing);
            JobResult result;
            result.status = io::saveRefinedMesh(path, *mesh, splits, positions, &result.warnings);
            return result;
        });
    } else {
        io::Script script = io::recordSession(state.session);
        script.weldMesh = document_.welded;
        // The session replays from the undeformed source. If that file was overwritten by a save, the session
        // brings its own copy of the undeformed mesh, written next to it.
        std::string basePath;
        Positions original;
        if (document_.sourceOverwritten || document_.sourcePath.empty() ||
            checkOpenPath(document_.sourcePath).ok == false) {
            const fs::path sessionFile(path);
            basePath = (sessionFile.parent_path() / (sessionFile.stem().string() + ".base.obj")).string();
            original = state.session.mesh().original;
            script.mesh = io::scriptRelativeMeshPath(basePath, path);
        } else {
            script.mesh = io::scriptRelativeMeshPath(document_.sourcePath, path);
        }
        std::string text = io::scriptToJson(script);
        startJob(state, kind, path,
                 [path, mesh, basePath, original = std::move(original), text = std::move(text)](JobProgress& progress) {
                     progress.phase = static_cast<int>(JobPhase::Writing);
                     JobResult result;
                     if (!basePath.empty()) {
                         if (result.status = io::saveObj(basePath, *mesh, original); !result.status) return result;
                     }
                     result.status = io::writeFileAtomically(path, text);
                     return result;
                 });
    }
    job_->markAtStart = mark;
    job_->then = then;
    setStatus(state, "Saving " + fileNameOfPath(path) + "...", false);
    return true;
}

void FileCommands::requestScreenshot(const std::string& path) { screenshotPath_ = path; }

void FileCommands::initGraphics(render::GlGetProc getProc) {
    auto gl = std::make_unique<render::GlFunctions>();
    if (render::loadGlFunctions(getProc, *gl).ok) gl_ = std::move(gl);
}

void FileCommands::afterSceneDrawn(AppState& state, int width, int height) {
    if (screenshotPath_.empty()) return;
    const std::string path = std::move(screenshotPath_);
    screenshotPath_.clear();
    if (!gl_) {
        setStatus(state, "Screenshot failed: no OpenGL functions.", true);
        return;
    }
    render::Rgba8Image image;
    if (Status s = render::readBoundFramebuffer(*gl_, width, height, image); !s) {
        setStatus(state, "Screenshot failed: " + s.message, true);
        return;
    }
    auto write = [path, image = std::move(image)](JobProgress& progress) {
        progress.phase = static_cast<int>(JobPhase::Writing);
        JobResult result;
        result.status = io::writePng(path, image.width, image.height, image.pixels.data());
        return result;
    };
    if (busy()) {  // e.g. requested by a test while a save runs: write it here
        JobProgress progress;
        const JobResult result = write(progress);
        setStatus(state, result.status ? "Wrote screenshot " + fileNameOfPath(path) : "Screenshot failed: " + result.status.message,
                  !result.status);
        return;
    }
    startJob(state, JobKind::SaveScreenshot, path, write);
    job_->markAtStart = markHistory(state.session);
}

// ------------------------------------------------------------------------------------- finishing a job

bool FileCommands::busy() const { return job_ != nullptr; }

bool FileCommands::loading() const {
    return job_ && (job_->kind == JobKind::LoadMesh || job_->kind == JobKind::OpenSession);
}

void FileCommands::cancelJob() {
    if (loading()) job_->progress->obj.cancel = true;
}

float FileCommands::jobFraction() const {
    if (!job_) return 0.0f;
    const JobProgress& p = *job_->progress;
    const auto phase = static_cast<JobPhase>(p.phase.load());
    const float obj = p.obj.fraction.load();
    const bool session = job_->kind == JobKind::OpenSession;
    switch (phase) {
        case JobPhase::ReadingMesh: return (session ? 0.6f : 0.85f) * obj;
        case JobPhase::Embedding: return session ? 0.65f : 0.9f;
        case JobPhase::Replaying: {
            const int total = std::max(1, p.opsTotal.load());
            return 0.7f + 0.3f * static_cast<float>(p.opsDone.load()) / static_cast<float>(total);
        }
        case JobPhase::Writing:  // no fraction from the writer: a slow sweep shows it is alive
            return static_cast<float>(std::fmod(secondsSince(job_->start), 1.0));
    }
    return 0.0f;
}

std::string FileCommands::jobLabel() const {
    if (!job_) return {};
    const std::string name = fileNameOfPath(job_->path);
    switch (static_cast<JobPhase>(job_->progress->phase.load())) {
        case JobPhase::ReadingMesh: return std::string("Reading and checking ") + (job_->kind == JobKind::OpenSession ? "the mesh of " : "") + name;
        case JobPhase::Embedding: return "Embedding the mesh in the lattice";
        case JobPhase::Replaying:
            return "Replaying operation " + std::to_string(job_->progress->opsDone.load()) + " of " +
                   std::to_string(job_->progress->opsTotal.load());
        case JobPhase::Writing: return "Writing " + name;
    }
    return {};
}

void FileCommands::poll(AppState& state) {
    if (job_ && job_->result.wait_for(std::chrono::seconds(0)) == std::future_status::ready) {
        std::unique_ptr<Job> job = std::move(job_);
        JobResult result = job->result.get();
        install(state, *job, result);
        if (afterJob_.kind != PendingAction::Kind::None) {
            const PendingAction after = std::exchange(afterJob_, PendingAction{});
            if (after.kind == PendingAction::Kind::Quit) requestQuit(state);
        }
    }
    state.modified = modified(state);
}

void FileCommands::finishJob(AppState& state) {
    if (job_) job_->result.wait();
    poll(state);
}

void FileCommands::install(AppState& state, Job& job, JobResult& result) {
    const std::string name = fileNameOfPath(job.path);
    const std::string took = secondsText(secondsSince(job.start));
    if (!result.status) {
        const bool cancelled = result.status.message.size() >= 9 &&
                               result.status.message.compare(result.status.message.size() - 9, 9, "cancelled") == 0;
        switch (job.kind) {
            case JobKind::LoadMesh:
            case JobKind::OpenSession:
                setStatus(state, cancelled ? "Opening " + name + " cancelled; nothing changed."
                                           : "Could not open " + name + ": " + result.status.message, !cancelled);
                if (!cancelled) {
                    messageTitle_ = job.kind == JobKind::OpenSession ? "Could not open the session" : "Could not open the mesh";
                    message_ = result.status.message + "\n\nNothing was changed.";
                }
                break;
            case JobKind::SaveMesh:
            case JobKind::SaveSession:
                setStatus(state, "Save failed, the file on disk is unchanged and your work is still open: " +
                                     result.status.message, true);
                if (job.then.kind != PendingAction::Kind::None) {  // from the prompt: ask again, saying why
                    prompt_ = job.then;
                    promptError_ = "Save failed: " + result.status.message;
                }
                break;
            case JobKind::SaveScreenshot: setStatus(state, "Screenshot failed: " + result.status.message, true); break;
        }
        return;
    }
    switch (job.kind) {
        case JobKind::LoadMesh:
        case JobKind::OpenSession: {
            const bool session = job.kind == JobKind::OpenSession;
            installSession(state, std::move(result.session), fileNameOfPath(result.meshPath));
            document_ = Document{};
            document_.sourcePath = result.meshPath;
            document_.meshPath = result.meshPath;
            document_.mesh = std::move(result.mesh);
            document_.welded = result.welded;
            if (session) document_.sessionPath = job.path;
            document_.saved = markHistory(state.session);
            const core::Session& s = state.session;
            std::string text = session ? "Opened session " + name + ": " + countOf(s.history().size(), "operation") +
                                             " (" + countOf(static_cast<size_t>(result.opsReplayed), "script op") + ") replayed on " +
                                             fileNameOfPath(result.meshPath)
                                       : "Loaded " + name + ": " + countOf(static_cast<size_t>(s.mesh().positions.rows()), "vertex", "vertices") +
                                             ", " + countOf(static_cast<size_t>(s.mesh().triangles.rows()), "triangle");
            if (result.opsRejected > 0) text += " (" + std::to_string(result.opsRejected) + " refused: the report says why)";
            if (result.screenshotsSkipped > 0) text += ", " + countOf(static_cast<size_t>(result.screenshotsSkipped), "screenshot op") + " skipped";
            text += " in " + took + ".";
            if (s.meshAsSet().degenerateTriangles > 0)
                text += " " + countOf(static_cast<size_t>(s.meshAsSet().degenerateTriangles), "degenerate (zero-area) facet") + " in the file.";
            const io::WeldReport& weld = result.weld;
            const int joined = weld.verticesBefore - weld.verticesAfter;
            if (result.welded && joined > 0)
                text += " Welded " + countOf(static_cast<size_t>(weld.verticesBefore), "vertex", "vertices") + " at " +
                        countOf(static_cast<size_t>(weld.verticesAfter), "position") + " into one surface.";
            else if (!result.welded && joined > 0)
                text += " " + countOf(static_cast<size_t>(joined), "vertex lies", "vertices lie") +
                        " exactly on another (a triangle soup or split seams: drawn faceted, in parts); "
                        "File > Weld coincident vertices on open joins them.";
            if (s.meshAsSet().intersectingPairs > 0)
                text += " The mesh already crosses itself (" + std::to_string(s.meshAsSet().intersectingPairs) +
                        " triangle pairs); only new crossings are refused.";
            setStatus(state, text + warningsText(result.warnings), false);
            state.statusDetails = result.warnings;
            break;
        }
        case JobKind::SaveMesh:
            if (!document_.sourcePath.empty() && sameFile(job.path, document_.sourcePath)) document_.sourceOverwritten = true;
            document_.meshPath = job.path;
            document_.meshPathConfirmed = true;
            state.meshName = fileNameOfPath(job.path);  // the document is now that file: title, sidebar, prompts
            document_.saved = job.markAtStart;
            setStatus(state, "Saved " + name + " (" + countOf(static_cast<size_t>(state.session.mesh().positions.rows()), "vertex", "vertices") + ") in " +
                                 took + "." + warningsText(result.warnings),
                      false);
            state.statusDetails = result.warnings;
            break;
        case JobKind::SaveSession:
            document_.sessionPath = job.path;
            document_.saved = job.markAtStart;
            setStatus(state, "Saved session " + name + " (" + countOf(static_cast<size_t>(state.session.history().cursor()), "operation") +
                                 ") in " + took + ".", false);
            break;
        case JobKind::SaveScreenshot: setStatus(state, "Wrote screenshot " + name + ".", false); break;
    }
    if (job.then.kind != PendingAction::Kind::None) proceed(state, job.then);
}

// -------------------------------------------------------------------------------- questions and commands

bool FileCommands::modified(const AppState& state) const {
    return !state.session.mesh().empty() && isModified(document_, state.session);
}

std::string FileCommands::windowTitle(const AppState& state) const {
    const std::string name = state.meshName.empty() ? std::string("untitled") : state.meshName;
    return "DMFFD Sculpt - " + name + (modified(state) ? "*" : "");
}

std::string FileCommands::promptQuestion(const AppState& state) const {
    const std::string name = state.meshName.empty() ? std::string("the mesh") : state.meshName;
    std::string why;
    switch (prompt_.kind) {
        case PendingAction::Kind::Quit: why = "before quitting"; break;
        case PendingAction::Kind::OpenPath: why = "before opening " + fileNameOfPath(prompt_.path); break;
        default: why = "before opening another file"; break;
    }
    return "Save changes to " + name + " " + why + "?";
}

bool FileCommands::blocksInput() const {
    return busy() || promptOpen() || replaceOriginal_ || dialog_.isOpen() || !message_.empty();
}

std::string FileCommands::startFolder() const {
    if (!document_.meshPath.empty()) return folderOfPath(fs::absolute(document_.meshPath).string());
    return ".";
}

bool FileCommands::ask(AppState& state, const PendingAction& action) {
    if (!modified(state)) return true;
    prompt_ = action;
    promptError_.clear();
    return false;
}

void FileCommands::proceed(AppState& state, const PendingAction& action) {
    switch (action.kind) {
        case PendingAction::Kind::None: break;
        case PendingAction::Kind::Quit: quitApproved_ = true; break;
        case PendingAction::Kind::OpenMeshDialog: openDialog(DialogPurpose::OpenMesh); break;
        case PendingAction::Kind::OpenSessionDialog: openDialog(DialogPurpose::OpenSession); break;
        case PendingAction::Kind::OpenPath: startOpen(state, action.path); break;
    }
}

void FileCommands::openDialog(DialogPurpose purpose, const PendingAction& then) {
    dialogPurpose_ = purpose;
    dialogThen_ = then;
    const std::string folder = startFolder();
    const std::string meshName = fileNameOfPath(document_.meshPath);
    const std::string stem = meshName.empty() ? std::string("untitled") : fs::path(meshName).stem().string();
    switch (purpose) {
        case DialogPurpose::OpenMesh: dialog_.open(FileDialogMode::Open, "Open mesh", io::meshExtensions(), folder); break;
        case DialogPurpose::OpenSession:
            dialog_.open(FileDialogMode::Open, "Open session", kSessionExtensions,
                         document_.sessionPath.empty() ? folder : folderOfPath(document_.sessionPath));
            break;
        case DialogPurpose::SaveMeshAs: {
            // A name typed without an extension keeps the document's format: its extension comes first.
            std::vector<std::string> extensions = io::meshExtensions();
            const auto at = std::find_if(extensions.begin(), extensions.end(),
                                         [&meshName](const std::string& e) { return hasExtension(meshName, {e}); });
            if (at != extensions.end()) std::rotate(extensions.begin(), at, at + 1);
            dialog_.open(FileDialogMode::Save, "Save mesh as", extensions, folder, meshName);
            break;
        }
        case DialogPurpose::SaveSession:
            dialog_.open(FileDialogMode::Save, "Save session", kSessionExtensions,
                         document_.sessionPath.empty() ? folder : folderOfPath(document_.sessionPath),
                         document_.sessionPath.empty() ? stem + ".session.json" : fileNameOfPath(document_.sessionPath));
            break;
        case DialogPurpose::SaveScreenshot:
            dialog_.open(FileDialogMode::Save, "Save screenshot", kImageExtensions, folder, stem + ".png");
            break;
        case DialogPurpose::OpenLattice: {
            // The user's own lattices (the shipped ones are listed in the panel already).
            const std::string user = userLatticeFolder();
            std::error_code ec;
            dialog_.open(FileDialogMode::Open, "Open lattice", kLatticeExtensions,
                         !user.empty() && fs::is_directory(user, ec) ? user : latticeLibraryFolder());
            break;
        }
        case DialogPurpose::SaveLattice:
            // note: the user's folder with a name no library entry has, never the shipped folder with a shipped
            // tool's name (that invited replacing it; saveLatticeToolCommand refuses the shipped folder anyway).
            dialog_.open(FileDialogMode::Save, "Save lattice to library", kLatticeExtensions, latticeSaveFolder_,
                         latticeToSaveName_ + ".lattice.json");
            break;
    }
}

void FileCommands::dialogAccepted(AppState& state) {
    const std::string path = dialog_.acceptedPath();
    const PendingAction then = std::exchange(dialogThen_, PendingAction{});
    if (path.empty()) return;
    switch (dialogPurpose_) {
        case DialogPurpose::OpenMesh:
        case DialogPurpose::OpenSession: startOpen(state, path); break;
        case DialogPurpose::SaveMeshAs: startSave(state, JobKind::SaveMesh, path, then); break;
        case DialogPurpose::SaveSession: startSave(state, JobKind::SaveSession, path, then); break;
        case DialogPurpose::SaveScreenshot: requestScreenshot(path); break;
        case DialogPurpose::OpenLattice: app::openLatticeFile(state, path); break;
        case DialogPurpose::SaveLattice: saveLatticeToolCommand(state, latticeToSave_, path, latticeNameOfPath(path)); break;
    }
}

void FileCommands::openMesh(AppState& state) {
    if (blocksInput()) return;
    if (ask(state, {PendingAction::Kind::OpenMeshDialog, {}})) proceed(state, {PendingAction::Kind::OpenMeshDialog, {}});
}

void FileCommands::openSession(AppState& state) {
    if (blocksInput()) return;
    if (ask(state, {PendingAction::Kind::OpenSessionDialog, {}}))
        proceed(state, {PendingAction::Kind::OpenSessionDialog, {}});
}

void FileCommands::openPath(AppState& state, const std::string& path) {
    if (blocksInput()) {
        setStatus(state, "Finish the current file operation or question first.", true);
        return;
    }
    if (!hasExtension(path, io::meshExtensions()) && !hasExtension(path, kSessionExtensions)) {
        setStatus(state, "Cannot open " + fileNameOfPath(path) + ": only meshes (" + io::meshExtensionList() + ") and .json sessions.", true);
        return;
    }
    const PendingAction action{PendingAction::Kind::OpenPath, path};
    if (ask(state, action)) proceed(state, action);
}

void FileCommands::saveMesh(AppState& state) {
    if (blocksInput()) return;
    saveMeshThen(state, {});
}

void FileCommands::saveMeshThen(AppState& state, const PendingAction& then) {
    if (!document_.mesh) {
        setStatus(state, "Nothing to save: no mesh is open.", true);
        return;
    }
    if (document_.meshPath.empty()) openDialog(DialogPurpose::SaveMeshAs, then);
    else if (!document_.meshPathConfirmed) {
        replaceOriginal_ = true;  // the first save over the input file asks once
        replaceThen_ = then;
    } else {
        startSave(state, JobKind::SaveMesh, document_.meshPath, then);
    }
}

void FileCommands::answerReplaceOriginal(AppState& state, int choice) {
    if (!replaceOriginal_) return;
    replaceOriginal_ = false;
    const PendingAction then = std::exchange(replaceThen_, PendingAction{});
    if (choice == 0) startSave(state, JobKind::SaveMesh, document_.meshPath, then);
    else if (choice == 1) openDialog(DialogPurpose::SaveMeshAs, then);
}

void FileCommands::saveMeshAs(AppState& /*state*/) {
    if (blocksInput()) return;
    openDialog(DialogPurpose::SaveMeshAs);
}

void FileCommands::saveSession(AppState& state) {
    if (blocksInput() || state.session.mesh().empty()) return;
    openDialog(DialogPurpose::SaveSession);
}

void FileCommands::saveScreenshot(AppState& state) {
    if (blocksInput() || state.session.mesh().empty()) return;
    openDialog(DialogPurpose::SaveScreenshot);
}

void FileCommands::openLatticeFile(AppState& /*state*/) {
    if (busy() || dialog_.isOpen()) return;
    openDialog(DialogPurpose::OpenLattice);
}

void FileCommands::saveLatticeFile(AppState& state, int tool) {
    if (busy() || dialog_.isOpen()) return;
    const std::vector<core::LatticeTool>& tools = state.session.tools().list();
    if (tool < 0 || tool >= static_cast<int>(tools.size())) return;
    latticeToSave_ = tool;
    // The user's library folder, made on demand; where it cannot be made, the working folder (and the status
    // line says why).
    latticeSaveFolder_ = userLatticeFolder();
    std::error_code ec;
    if (latticeSaveFolder_.empty() || (fs::create_directories(latticeSaveFolder_, ec), ec)) {
        setStatus(state, latticeSaveFolder_.empty()
                             ? std::string("No home folder (HOME) for your lattice library: choose where to save.")
                             : "Cannot make your lattice library folder " + latticeSaveFolder_ + ": " + ec.message(),
                  true);
        latticeSaveFolder_ = fs::current_path(ec).string();
    }
    latticeToSaveName_ = freshLatticeName(state, tools[static_cast<size_t>(tool)].name, latticeSaveFolder_);
    openDialog(DialogPurpose::SaveLattice);
}

void FileCommands::requestQuit(AppState& state) {
    if (job_) {  // a load is stopped, a save finishes; then the same question
        cancelJob();
        afterJob_ = {PendingAction::Kind::Quit, {}};
        return;
    }
    if (promptOpen() || replaceOriginal_) return;  // already asking
    dialog_.close();
    if (ask(state, {PendingAction::Kind::Quit, {}})) quitApproved_ = true;
}

void FileCommands::answerPrompt(AppState& state, PromptChoice choice) {
    if (!promptOpen()) return;
    const PendingAction action = std::exchange(prompt_, PendingAction{});
    promptError_.clear();
    switch (choice) {
        case PromptChoice::Cancel: setStatus(state, "Cancelled; nothing was closed or opened.", false); break;
        case PromptChoice::DontSave: proceed(state, action); break;
        case PromptChoice::Save: saveMeshThen(state, action); break;
    }
}

bool FileCommands::onKey(AppState& state, const KeyEvent& event) {
    if (blocksInput()) return true;
    if (event.action != KeyAction::Press) return false;
    const Modifiers& m = event.modifiers;
    if (!(m.control || m.super)) return false;
    switch (event.key) {
        case Key::O: openMesh(state); return true;
        case Key::S:
            if (m.shift) saveMeshAs(state);
            else saveMesh(state);
            return true;
        case Key::Q: requestQuit(state); return true;
        default: return false;
    }
}

}  // namespace sculpt::app
