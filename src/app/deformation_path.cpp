#include "app/deformation_path.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace sculpt::app {

namespace {

const char* nameOf(DeformationPath path) { return path == DeformationPath::Gpu ? "GPU" : "CPU"; }

}  // namespace

void DeformationPathChooser::reset(int vertexCount) {
    vertexCount_ = std::max(vertexCount, 0);
    frames_ = {};
    still_ = {-1.0, -1.0};
    skipNext_ = true;
    started_ = false;
    forced_ = false;
    deciding_ = measured();
    measuring_ = DeformationPath::Gpu;  // measured first: where a real GPU stays
    decided_ = DeformationPath::Cpu;
}

void DeformationPathChooser::force(DeformationPath path) {
    decided_ = path;
    deciding_ = false;
    forced_ = true;
}

DeformationPath DeformationPathChooser::dragPath() const { return deciding_ ? measuring_ : decided_; }

DeformationPath DeformationPathChooser::restPath() const {
    if (forced_) return decided_;
    if (deciding_ || decided_ == DeformationPath::Cpu) return DeformationPath::Cpu;
    const double gpu = still_[1], cpu = still_[0];
    if (gpu < 0.0) return DeformationPath::Gpu;  // to time its still frame once
    return cpu < 0.0 || gpu <= 1.25 * cpu ? DeformationPath::Gpu : DeformationPath::Cpu;
}

void DeformationPathChooser::addDragFrame(DeformationPath path, double milliseconds) {
    if (!deciding_ || path != measuring_ || !std::isfinite(milliseconds) || milliseconds < 0.0) return;
    started_ = true;
    if (skipNext_) {
        skipNext_ = false;
        return;
    }
    std::vector<double>& frames = frames_[slot(path)];
    frames.push_back(milliseconds);
    if (int(frames.size()) < kFramesPerPath) return;
    if (frames_[slot(DeformationPath::Cpu)].size() < size_t(kFramesPerPath)) {
        measuring_ = DeformationPath::Cpu;  // now measure the other one
        skipNext_ = true;
        return;
    }
    deciding_ = false;
    decided_ = medianMs(DeformationPath::Gpu) < medianMs(DeformationPath::Cpu) ? DeformationPath::Gpu : DeformationPath::Cpu;
}

bool DeformationPathChooser::wantsStillFrame(DeformationPath path) const { return measured() && !forced_ && still_[slot(path)] < 0.0; }

void DeformationPathChooser::addStillFrame(DeformationPath path, double milliseconds) {
    if (!wantsStillFrame(path) || !std::isfinite(milliseconds) || milliseconds < 0.0) return;
    still_[slot(path)] = milliseconds;
}

double DeformationPathChooser::medianMs(DeformationPath path) const {
    std::vector<double> frames = frames_[slot(path)];
    if (frames.empty()) return -1.0;
    std::nth_element(frames.begin(), frames.begin() + std::ptrdiff_t(frames.size() / 2), frames.end());
    return frames[frames.size() / 2];
}

std::string DeformationPathChooser::label(bool dragging) const {
    if (forced_) return std::string(nameOf(decided_)) + " (chosen)";
    if (deciding_) {
        if (dragging) return std::string(nameOf(measuring_)) + " (timing)";
        return started_ ? "CPU (timing)" : "CPU";  // at rest on the CPU until both are timed
    }
    const DeformationPath rest = restPath();
    if (decided_ == rest) return nameOf(rest);
    return std::string(nameOf(decided_)) + " drag, " + nameOf(rest) + " rest";
}

std::string DeformationPathChooser::describe() const {
    char text[400];
    if (forced_) {
        std::snprintf(text, sizeof text, "The %s path, chosen.", nameOf(decided_));
        return text;
    }
    if (!measured()) return "A small mesh: the CPU path, either would take a fraction of a millisecond.";
    std::string out;
    const auto milliseconds = [&](double ms) {  // a median or a still frame; negative: none yet
        if (ms < 0.0) return std::string("not timed");
        std::snprintf(text, sizeof text, "%.1f ms", ms);
        return std::string(text);
    };
    if (deciding_ && !started_) {
        out = "The first drag on this mesh will be timed on both paths; the CPU path until then.\n";
    } else if (deciding_) {
        const int counted = int(frames_[slot(measuring_)].size());
        std::snprintf(text, sizeof text,
                      "Timing drag frames on both paths: the %s path now, %d of %d frames (the GPU first). Keep "
                      "dragging to finish; at rest the CPU path meanwhile.\n",
                      nameOf(measuring_), counted, kFramesPerPath);
        out = text;
    } else
        out = std::string("While dragging: the ") + nameOf(decided_) + " path. At rest: the " + nameOf(restPath()) + " path.\n";
    out += "Drag frames (median): GPU " + milliseconds(medianMs(DeformationPath::Gpu)) + ", CPU " +
           milliseconds(medianMs(DeformationPath::Cpu)) + ".\n";
    out += "Still frames: GPU " + milliseconds(stillMs(DeformationPath::Gpu)) + ", CPU " +
           milliseconds(stillMs(DeformationPath::Cpu)) + ".";
    return out;
}

}  // namespace sculpt::app
