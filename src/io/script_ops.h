// The table of script ops, one entry per op: its name (in scripts, recordings and reports), the JSON fields it
// takes besides "op", how it reads and writes them, how it runs on a session, and which history entries it
// records. Everything an op is lives in its entry (script_ops.cpp): the reader (script_json.cpp) looks the op
// up here, refuses any field the entry does not list and lets the entry read the rest; the writer
// (script_json_write.cpp) lets the entry write its fields; runScriptOp and runScript run an op through its
// entry; recordSession writes each history entry as the op whose entry claims it. A test
// (tests/io/script_ops_test.cpp) checks the reader, the writer, the recordings and the docs' op reference
// (docs/scripting.md "Every op", and the page each row points to) against the table.
//
// Internal to io and its tests: the entries read and write nlohmann::json, and a read that fails throws
// json_fields::FieldError (the reader's entry point turns it into a Status naming the field path).
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "io/script.h"

namespace sculpt::io {

struct ScriptOpInfo {
    ScriptOp::Kind kind = ScriptOp::Kind::Undo;
    const char* name = "";
    std::vector<const char*> fields;  // the JSON fields an op of this kind may have, besides "op"
    // Reads the op's fields from `j` (an object holding no field the entry does not list) into `op`, whose kind
    // is set; `path` names the op in errors ("ops[3]"). "applied" and "cancelled" (a recording's steps) are read
    // by the reader for every op that lists them. Throws json_fields::FieldError naming the field and what was
    // expected.
    void (*read)(const nlohmann::json& j, const std::string& path, ScriptOp& op) = nullptr;
    // Writes the op's fields into `j` (which holds "op"; the writer adds "applied" and "cancelled"), so that
    // `read` gives the op back bit for bit.
    void (*write)(const ScriptOp& op, nlohmann::json& j) = nullptr;
    // Runs the op on the session (a Session command; screenshot for the screenshot op): its Status and report
    // are the command's. Null for begin_group and end_group, which runScript keeps itself.
    Status (*run)(core::Session& session, const ScriptOp& op, core::OpReport& report, const ScreenshotHook& screenshot) = nullptr;
    // Whether this op is what a recording writes for `operation` (a history entry); if so, fills the op's
    // fields from it (the recording adds the steps it was applied as). Null: written from the journal instead
    // (pins, groups, settings) or never recorded (drag_vertex is recorded as a drag).
    bool (*record)(const core::Operation& operation, ScriptOp& op) = nullptr;
};

// Every op, one entry per ScriptOp::Kind (in the order the docs list them, for readers).
const std::vector<ScriptOpInfo>& scriptOps();

// The entry of `kind` (every kind has one).
const ScriptOpInfo& scriptOpInfo(ScriptOp::Kind kind);

// The entry named `name`, or null for a name no op has.
const ScriptOpInfo* findScriptOp(const std::string& name);

// "drag, drag_vertex, ...": every op's name, in the table's order (for the unknown-op message).
std::string scriptOpNames();

}  // namespace sculpt::io
