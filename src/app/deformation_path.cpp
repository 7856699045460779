#include "app/deformation_path.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace sculpt::app {

namespace {

size_t slot(DeformationPath path) { return path == DeformationPath::Gpu ? 1 : 0; }

}  // namespace

void DeformationPathChooser::reset(int vertexCount) {
    vertexCount_ = std::max(vertexCount, 0);
    frames_ = {};
    skipNext_ = true;
    forced_ = false;
    deciding_ = vertexCount_ > 0 && vertexCount_ >= minVertices_;
    // Measured meshes start on the GPU path (where a real GPU leaves it); small ones stay on the CPU.
    path_ = deciding_ ? DeformationPath::Gpu : DeformationPath::Cpu;
}

void DeformationPathChooser::addFrame(DeformationPath path, double milliseconds) {
    if (!deciding_ || path != path_ || !std::isfinite(milliseconds) || milliseconds < 0.0) return;
    if (skipNext_) {
        skipNext_ = false;
        return;
    }
    std::vector<double>& frames = frames_[slot(path)];
    frames.push_back(milliseconds);
    if (int(frames.size()) < kFramesPerPath) return;
    if (frames_[slot(DeformationPath::Cpu)].size() < size_t(kFramesPerPath)) {
        path_ = DeformationPath::Cpu;  // now measure the other one
        skipNext_ = true;
        return;
    }
    deciding_ = false;
    path_ = medianMs(DeformationPath::Gpu) < medianMs(DeformationPath::Cpu) ? DeformationPath::Gpu : DeformationPath::Cpu;
}

double DeformationPathChooser::medianMs(DeformationPath path) const {
    std::vector<double> frames = frames_[slot(path)];
    if (frames.empty()) return -1.0;
    std::nth_element(frames.begin(), frames.begin() + std::ptrdiff_t(frames.size() / 2), frames.end());
    return frames[frames.size() / 2];
}

std::string DeformationPathChooser::describe() const {
    const char* name = path_ == DeformationPath::Gpu ? "GPU (vertex shader)" : "CPU";
    char text[160];
    if (forced_)
        std::snprintf(text, sizeof text, "%s (chosen)", name);
    else if (deciding_)
        std::snprintf(text, sizeof text, "%s, measuring both", name);
    else if (medianMs(DeformationPath::Gpu) >= 0.0 && medianMs(DeformationPath::Cpu) >= 0.0)
        std::snprintf(text, sizeof text, "%s: %.1f ms a frame vs %.1f on the %s", name,
                      medianMs(path_), medianMs(path_ == DeformationPath::Gpu ? DeformationPath::Cpu : DeformationPath::Gpu),
                      path_ == DeformationPath::Gpu ? "CPU" : "GPU");
    else if (vertexCount_ < minVertices_)
        std::snprintf(text, sizeof text, "%s (a small mesh)", name);
    else
        std::snprintf(text, sizeof text, "%s", name);
    return text;
}

}  // namespace sculpt::app
