#include "app/window/engine_job.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <utility>

namespace sculpt::app {

EngineJob::~EngineJob() { collect(); }

bool EngineJob::start(std::function<void()> work, std::string what, double waitSeconds, std::function<void()> onDone) {
    if (started_) return false;
    what_ = std::move(what);
    start_ = std::chrono::steady_clock::now();
    error_.clear();
    done_ = false;
    started_ = true;
    const auto run = [this, work = std::move(work), onDone = std::move(onDone)] {
        std::string error;
        try {
            work();
        } catch (const std::exception& e) {
            error = e.what();
            if (error.empty()) error = "an unnamed error";
        } catch (...) {
            error = "an unknown error";
        }
        {
            const std::lock_guard<std::mutex> lock(mutex_);
            done_ = true;
            error_ = std::move(error);
        }
        doneSignal_.notify_all();
        if (onDone) onDone();
    };
    if (std::isinf(waitSeconds) && waitSeconds > 0.0) {
        run();
        return true;
    }
    thread_ = std::thread(run);
    std::unique_lock<std::mutex> lock(mutex_);
    return doneSignal_.wait_for(lock, std::chrono::duration<double>(std::max(0.0, waitSeconds)), [this] { return done_; });
}

bool EngineJob::finished() const {
    if (!started_) return false;
    const std::lock_guard<std::mutex> lock(mutex_);
    return done_;
}

std::string EngineJob::collect() {
    if (!started_) return {};
    if (thread_.joinable()) thread_.join();
    started_ = false;
    const std::lock_guard<std::mutex> lock(mutex_);
    return std::exchange(error_, std::string());
}

double EngineJob::elapsedSeconds() const {
    if (!started_) return 0.0;
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

}  // namespace sculpt::app
