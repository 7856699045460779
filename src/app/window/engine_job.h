// EngineJob: one engine step (a drag's move, a transform's pose, an undo) run on a worker thread, so the window
// keeps drawing while the engine certifies it (issue: responsive while the engine works).
//
// The rule that makes it safe without locks in the engine: while a job runs, the worker owns the AppState (the
// session in it) and nothing else touches it. The main thread draws the last applied frame again (the scene
// from what the GPU already holds, the UI from a copy of the last frame's draw lists) with the job's progress
// over it, and holds input back (SculptApp queues it and replays it in order once the job ends). So the
// window never shows a value that was not applied: what it shows is the last frame drawn from applied state.
//
// A job the caller waits for (start's waitSeconds) and that ends in time is indistinguishable from a call on
// the calling thread; only a longer one leaves the window to draw its progress.
#pragma once

#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

namespace sculpt::app {

class EngineJob {
public:
    EngineJob() = default;
    ~EngineJob();  // waits for a running job (its work owns state the destructor's owner is about to free)
    EngineJob(const EngineJob&) = delete;
    EngineJob& operator=(const EngineJob&) = delete;

    // Runs `work` and waits for it at most waitSeconds. waitSeconds = infinity: on the calling thread (no
    // worker, as a plain call); otherwise on a new worker thread. `what` names it in the progress ("Certifying
    // the move"). onDone, if set, is called on the worker as the work returns (the window wakes its loop with
    // it). Returns true if the job ended within the wait (then collect() has nothing left to do but report),
    // false if it still runs. A job must not be started while another runs (running()): that returns false
    // and runs nothing.
    bool start(std::function<void()> work, std::string what, double waitSeconds, std::function<void()> onDone = {});

    // Started and not yet collected: the worker may still own the state.
    bool running() const { return started_; }
    // The running job's work has returned (collect() will not block). False when none runs.
    bool finished() const;
    // Joins the job (waiting if its work still runs). Returns what the work threw ("" if nothing), and leaves
    // running() false. Nothing to collect: "".
    std::string collect();

    // The running job's name and its time so far, seconds (0 when none runs).
    const std::string& what() const { return what_; }
    double elapsedSeconds() const;

private:
    std::thread thread_;
    mutable std::mutex mutex_;
    std::condition_variable doneSignal_;
    bool done_ = false;     // guarded by mutex_
    std::string error_;     // guarded by mutex_; the work's exception message
    bool started_ = false;  // main thread only
    std::string what_;
    std::chrono::steady_clock::time_point start_;
};

}  // namespace sculpt::app
