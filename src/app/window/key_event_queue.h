// Key events for Dear ImGui 1.86 (Debian's), which keeps only the keys' current state (io.KeysDown) and no
// queue of events: a key pressed and released between two frames is never seen down, so an Enter tapped in a
// text field was lost on a slow frame. This queue keeps the events in the order they came and delivers them
// no faster than a frame can see them: an event for a key that already changed state since the last frame
// waits, with every event after it, for the next frame (ImGui >= 1.87's input queue trickles the same way).
//
// Delivery is the caller's: the GLFW loop passes the event to ImGui's GLFW callback (which then calls the
// app's), the tests set io.KeysDown and call SculptApp::onKey.
#pragma once

#include <deque>
#include <functional>
#include <set>

namespace sculpt::app {

class KeyEventQueue {
public:
    // A key (any id, e.g. the GLFW key code) went down or up (changesState; a repeat does not): delivered now,
    // or kept for a later frame.
    void push(int key, bool changesState, std::function<void()> deliver);
    // After each frame (ImGui has seen the keys' state): delivers the waiting events in order until one must
    // wait for the frame after.
    void frameDone();
    bool empty() const { return waiting_.empty(); }

private:
    struct Waiting {
        int key;
        bool changesState;
        std::function<void()> deliver;
    };
    std::set<int> changed_;  // keys that went down or up since the last frameDone
    std::deque<Waiting> waiting_;
};

}  // namespace sculpt::app
