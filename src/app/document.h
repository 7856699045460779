// The window's document: the files the work came from and goes to, and whether it changed since it was last
// loaded or saved. The shape itself lives in the core::Session (house style 9); this is file bookkeeping only.
//
// note: "modified" compares the session's applied history with a mark taken at the last load or save, not a
// counter bumped by every command: whatever changes the history (drags, undo, history clicks, panels added
// later) is seen without each of them having to report it, and undoing back to the saved state is clean again.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "core/session/session.h"
#include "io/obj_mesh.h"

namespace sculpt::app {

// The applied part of a session's history, summarised: how many entries are applied and a 64-bit fingerprint
// of their contents (kind, label, constraints, control points and offsets, settings, the steps' constraints
// and frames). Two marks are equal when the same operations were applied in the same order, which for the
// deterministic engine means the same shape.
struct HistoryMark {
    int cursor = 0;
    std::uint64_t fingerprint = 0;
    bool operator==(const HistoryMark& other) const { return cursor == other.cursor && fingerprint == other.fingerprint; }
    bool operator!=(const HistoryMark& other) const { return !(*this == other); }
};
// O(size of the applied operations' user input), independent of the mesh size; microseconds for 1000 drags.
HistoryMark markHistory(const core::Session& session);

struct Document {
    std::string sourcePath;          // the OBJ the session's history starts from ("" = none yet)
    std::string meshPath;            // where "Save mesh" writes; the source at first
    bool meshPathConfirmed = false;  // "Save mesh" may write meshPath without asking (false while it is the
                                     // source: replacing the original input asks once)
    bool sourceOverwritten = false;  // the source file now holds a deformed shape (a session saved from here
                                     // then carries its own copy of the undeformed mesh)
    std::string sessionPath;         // the last session file opened or saved
    std::shared_ptr<const io::ObjMesh> mesh;  // polygons, groups, texture coordinates of the source, kept for
                                              // a faithful save; shared read-only with background saves
    bool welded = false;             // its coincident vertices were welded on load (a saved session says so)
    HistoryMark saved;               // the history when last loaded or saved
};

// True when the session's applied history differs from document.saved, or a drag is in progress.
bool isModified(const Document& document, const core::Session& session);

}  // namespace sculpt::app
