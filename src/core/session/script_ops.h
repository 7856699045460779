// The table of script ops: each op's name (in scripts, recordings and reports) and the JSON fields it takes
// besides "op". The reader (io/script_json.cpp) looks ops up here, refuses any other field, and names the
// known ops from it; scriptOpName reads the names from it; a test checks the docs' op reference
// (docs/scripting.md "Every op", and the page each row points to) against it.
#pragma once

#include <string>
#include <vector>

#include "core/session/script.h"

namespace sculpt::core {

struct ScriptOpInfo {
    ScriptOp::Kind kind = ScriptOp::Kind::Undo;
    const char* name = "";
    std::vector<const char*> fields;  // the JSON fields an op of this kind may have, besides "op"
};

// Every op, one entry per ScriptOp::Kind, in the order the docs list them.
const std::vector<ScriptOpInfo>& scriptOps();

// The entry of `kind` (every kind has one).
const ScriptOpInfo& scriptOpInfo(ScriptOp::Kind kind);

// The entry named `name`, or null for a name no op has.
const ScriptOpInfo* findScriptOp(const std::string& name);

// "drag, drag_vertex, ...": every op's name, in the table's order (for the unknown-op message).
std::string scriptOpNames();

}  // namespace sculpt::core
