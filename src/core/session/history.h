// The history of a session and its journal (design.md "What undo means"): the operations in order, entries
// [0, cursor) applied and the rest redoable, and every command as it was carried out (what a recording
// writes, recordSession). It holds no geometry and applies nothing: the session takes an entry back or
// applies it again (inverse manipulations, Hu et al. 2001, section 4) and moves the cursor here.
#pragma once

#include <cstddef>
#include <vector>

#include "core/session/operation.h"

namespace sculpt::core {

class History {
public:
    // Entries [0, cursor()) are applied; [cursor(), size) can be redone.
    const std::vector<Operation>& entries() const { return entries_; }
    int cursor() const { return cursor_; }
    bool atEnd() const { return cursor_ == static_cast<int>(entries_.size()); }
    // Every command since the mesh was set, in order.
    const std::vector<JournalEntry>& journal() const { return journal_; }
    // The entries read as a sequence (history()[i], size(), back(), a range-for).
    size_t size() const { return entries_.size(); }
    bool empty() const { return entries_.empty(); }
    const Operation& operator[](size_t i) const { return entries_[i]; }
    const Operation& front() const { return entries_.front(); }
    const Operation& back() const { return entries_.back(); }
    std::vector<Operation>::const_iterator begin() const { return entries_.begin(); }
    std::vector<Operation>::const_iterator end() const { return entries_.end(); }

    // An applied operation: the redo branch is dropped, the operation appended (cursor at the end) and
    // journaled as applied.
    void push(Operation operation);
    // Moves the cursor back over the last applied entry and returns it (for the session to take back);
    // journaled as an undo. Precondition: cursor() > 0.
    const Operation& stepBack();
    // Moves the cursor over the next entry and returns it (for the session to apply again); journaled as a
    // redo. Precondition: !atEnd().
    const Operation& stepForward();
    // Entries [first, cursor()) become `merged` (the cursor at the end, which it must be), journaled as a
    // group of that label. 0 <= first <= cursor().
    void replaceTail(int first, Operation merged);
    // Entry i, for a group to move its steps out (0 <= i < size).
    Operation& entry(int i) { return entries_[static_cast<size_t>(i)]; }
    // The last entry and its journal record (the command that pushed it), for a command built on another one
    // (freeze on a set-up, subdividing cells on a tool edit) to rename it. Precondition: an entry was just pushed.
    Operation& last() { return entries_.back(); }
    Operation& lastJournaled() { return journal_.back().operation; }
    // A command that is no history entry (pins, the refinement setting, a drag taken back). With `coalesce`, it
    // replaces the last record when that is of the same kind (only where consecutive changes ended counts).
    void note(JournalEntry entry, bool coalesce);
    // Empty history and journal (a new mesh).
    void clear();

private:
    std::vector<Operation> entries_;
    int cursor_ = 0;
    std::vector<JournalEntry> journal_;
};

}  // namespace sculpt::core
