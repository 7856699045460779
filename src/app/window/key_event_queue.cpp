#include "app/window/key_event_queue.h"

#include <utility>

namespace sculpt::app {

void KeyEventQueue::push(int key, bool changesState, std::function<void()> deliver) {
    if (waiting_.empty() && !(changesState && changed_.count(key))) {
        if (changesState) changed_.insert(key);
        deliver();
        return;
    }
    waiting_.push_back({key, changesState, std::move(deliver)});
}

void KeyEventQueue::frameDone() {
    changed_.clear();
    while (!waiting_.empty()) {
        Waiting& next = waiting_.front();
        if (next.changesState && changed_.count(next.key)) return;
        if (next.changesState) changed_.insert(next.key);
        const std::function<void()> deliver = std::move(next.deliver);
        waiting_.pop_front();
        deliver();
    }
}

}  // namespace sculpt::app
