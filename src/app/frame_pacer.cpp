#include "app/frame_pacer.h"

namespace sculpt::app {

FramePacer::Plan FramePacer::plan(const FrameNeeds& needs, double deadlineSeconds) const {
    if (needs.everyFrame || settleFrames_ > 0) return {Wait::Poll, 0.0};
    double seconds = needs.withinSeconds > 0.0 ? needs.withinSeconds : 0.0;
    if (deadlineSeconds > 0.0) seconds = seconds > 0.0 ? std::min(seconds, deadlineSeconds) : deadlineSeconds;
    if (seconds > 0.0) return {Wait::Timeout, seconds};
    return {Wait::Forever, 0.0};
}

}  // namespace sculpt::app
