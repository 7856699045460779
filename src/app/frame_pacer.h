// When the window draws (issue: an idle window sleeps). Like every desktop program the window draws when
// something changes, not at the display rate: llvmpipe draws on the CPU, so a polling loop kept 1.7 of two
// cores busy with nothing happening, and on a GPU it keeps the GPU busy.
//
// The main loop asks plan() how to wait before each frame:
//   - Poll: draw the next frame at once. After any input event or change of scene (noteActivity) the next
//     kSettleFrames frames are drawn: Dear ImGui lays out a window's new size, hover and focus a frame or two
//     after the event that caused them.
//   - Timeout: wait for an event at most `seconds`, then draw: while something animates or runs without input
//     (a load's progress popup, a text field's caret, a frame the deformation-path chooser times).
//   - Forever: nothing to draw until an event comes (glfwWaitEvents).
// No GLFW here: the loop feeds it and waits as told; tests drive it with plain values.
#pragma once

#include <algorithm>

namespace sculpt::app {

// What the app needs from the next frames, asked once a frame (SculptApp::frameNeeds).
struct FrameNeeds {
    bool everyFrame = false;        // draw continuously (a scripted test run, a drag the loop drives itself)
    double withinSeconds = 0.0;     // > 0: draw again at most this long after the last frame; 0: no such need
};

class FramePacer {
public:
    static constexpr int kSettleFrames = 3;

    enum class Wait { Poll, Timeout, Forever };
    struct Plan {
        Wait wait = Wait::Forever;
        double seconds = 0.0;  // Timeout only: > 0
    };

    // Input arrived or the scene changed: the next kSettleFrames frames are drawn.
    void noteActivity() { settleFrames_ = kSettleFrames; }
    // A frame was drawn.
    void frameDrawn() {
        settleFrames_ = std::max(0, settleFrames_ - 1);
        ++framesDrawn_;
    }
    // How to wait before the next frame, for what the app needs now. deadlineSeconds > 0: wake at most this
    // long from now whatever else holds (a measurement that ends at a given time).
    Plan plan(const FrameNeeds& needs, double deadlineSeconds = 0.0) const;

    // Frames drawn since construction (the idle measurement counts them).
    long framesDrawn() const { return framesDrawn_; }
    // Whether frames are still owed to the last activity.
    bool settling() const { return settleFrames_ > 0; }

private:
    int settleFrames_ = kSettleFrames;  // the first frames after the window opens
    long framesDrawn_ = 0;
};

}  // namespace sculpt::app
