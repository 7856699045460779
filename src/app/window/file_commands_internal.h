// What file_commands.cpp (loading, saving, questions) and file_commands_ui.cpp (the menu bar and the modals)
// share: a background job, its progress and result. Internal to src/app/window.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdio>
#include <future>
#include <memory>
#include <string>
#include <vector>

#include "app/window/file_commands.h"
#include "core/session/session.h"
#include "io/mesh_file.h"
#include "io/mesh_weld.h"

namespace sculpt::app {

enum class JobPhase { ReadingMesh, Embedding, Replaying, Writing };

struct JobProgress {
    io::ObjLoadProgress obj;  // the OBJ loader's fraction, and the cancel flag of every job
    std::atomic<int> phase{static_cast<int>(JobPhase::ReadingMesh)};
    std::atomic<int> opsDone{0}, opsTotal{0};
    bool cancelled() const { return obj.cancel.load(std::memory_order_relaxed); }
};

struct JobResult {
    Status status;
    core::Session session;                    // loads: the prepared session, installed by the main thread
    std::shared_ptr<const io::ObjMesh> mesh;  // loads: the source OBJ
    std::string meshPath;                     // loads: the OBJ the session starts from
    std::vector<std::string> warnings;
    int opsReplayed = 0, opsRejected = 0, screenshotsSkipped = 0;
    bool welded = false;        // loads: the mesh's coincident vertices were welded
    io::WeldReport weld;        // loads: welded, or (not welded) what a weld would join
};

struct FileCommands::Job {
    JobKind kind = JobKind::LoadMesh;
    std::string path;
    std::shared_ptr<JobProgress> progress = std::make_shared<JobProgress>();
    std::future<JobResult> result;
    HistoryMark markAtStart;  // saves: the history the saved data came from
    PendingAction then;       // saves started from the prompt: what to do once saved
    std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
};

}  // namespace sculpt::app

namespace sculpt::app::file_commands_detail {

inline double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// "1.25 s" below 10 s, "12 s" above.
inline std::string secondsText(double seconds) {
    char text[32];
    std::snprintf(text, sizeof text, seconds < 10.0 ? "%.2f s" : "%.0f s", seconds);
    return text;
}

}  // namespace sculpt::app::file_commands_detail
