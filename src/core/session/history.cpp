#include "core/session/history.h"

#include <utility>

namespace sculpt::core {

void History::push(Operation operation) {
    entries_.resize(static_cast<size_t>(cursor_));  // a new operation after undo drops the redo branch
    JournalEntry entry;
    entry.operation = operation;
    journal_.push_back(std::move(entry));
    entries_.push_back(std::move(operation));
    cursor_ = static_cast<int>(entries_.size());
}

const Operation& History::stepBack() {
    journal_.push_back(JournalEntry{JournalEntry::Kind::Undo, {}, 0, {}, {}, {}});
    return entries_[static_cast<size_t>(--cursor_)];
}

const Operation& History::stepForward() {
    journal_.push_back(JournalEntry{JournalEntry::Kind::Redo, {}, 0, {}, {}, {}});
    return entries_[static_cast<size_t>(cursor_++)];
}

void History::replaceTail(int first, Operation merged) {
    entries_.resize(static_cast<size_t>(first));
    entries_.push_back(std::move(merged));
    cursor_ = static_cast<int>(entries_.size());
    journal_.push_back(JournalEntry{JournalEntry::Kind::Group, {}, first, entries_.back().label, {}, {}});
}

void History::note(JournalEntry entry, bool coalesce) {
    if (coalesce && !journal_.empty() && journal_.back().kind == entry.kind) journal_.back() = std::move(entry);
    else journal_.push_back(std::move(entry));
}

void History::clear() {
    entries_.clear();
    cursor_ = 0;
    journal_.clear();
}

}  // namespace sculpt::core
