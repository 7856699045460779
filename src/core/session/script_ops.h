// The table of script ops, one entry per op: its name (in scripts, recordings and reports), the JSON fields it
// takes besides "op", how it runs on a session, and which history entries it records. The reader
// (io/script_json.cpp) looks ops up here, refuses any other field, and names the known ops from it;
// runScriptOp and runScript run an op through its entry; recordSession writes each history entry as the op
// whose entry claims it; a test checks the reader, the writer and the docs' op reference (docs/scripting.md
// "Every op", and the page each row points to) against it.
#pragma once

#include <string>
#include <vector>

#include "core/session/script.h"

namespace sculpt::core {

struct ScriptOpInfo {
    ScriptOp::Kind kind = ScriptOp::Kind::Undo;
    const char* name = "";
    std::vector<const char*> fields;  // the JSON fields an op of this kind may have, besides "op"
    // Runs the op on the session (a Session command; screenshot for the screenshot op): its Status and report
    // are the command's. Null for begin_group and end_group, which runScript keeps itself.
    Status (*run)(Session& session, const ScriptOp& op, OpReport& report, const ScreenshotHook& screenshot) = nullptr;
    // Whether this op is what a recording writes for `operation` (a history entry); if so, fills the op's
    // fields from it (the recording adds the steps it was applied as). Null: written from the journal instead
    // (pins, groups, settings) or never recorded (drag_vertex is recorded as a drag).
    bool (*record)(const Operation& operation, ScriptOp& op) = nullptr;
};

// Every op, one entry per ScriptOp::Kind (in the order the docs list them, for readers).
const std::vector<ScriptOpInfo>& scriptOps();

// The entry of `kind` (every kind has one).
const ScriptOpInfo& scriptOpInfo(ScriptOp::Kind kind);

// The entry named `name`, or null for a name no op has.
const ScriptOpInfo* findScriptOp(const std::string& name);

// "drag, drag_vertex, ...": every op's name, in the table's order (for the unknown-op message).
std::string scriptOpNames();

}  // namespace sculpt::core
