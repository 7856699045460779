// OPS.json scripts and REPORT.json reports (docs/scripting.md, "Script format").
#pragma once

#include <string>

#include "io/script.h"
#include "core/status.h"

namespace sculpt::io {

// Parses a script. Unknown fields, wrong types, non-finite numbers and out-of-range settings are errors
// whose message names the file, the field path (e.g. "ops[2].constraints[0].target") and what was expected.
// `out` is untouched on failure.
Status parseScript(const std::string& text, const std::string& displayName, io::Script& out);
Status loadScript(const std::string& path, io::Script& out);

// A script as JSON text in the format parseScript reads (numbers printed so they round-trip exactly).
std::string scriptToJson(const io::Script& script);

// The file a script's "mesh" names: as written when absolute, else relative to the folder of the script file
// at scriptPath. Empty when the script names no mesh.
std::string resolveScriptMesh(const io::Script& script, const std::string& scriptPath);
// How a script saved at scriptPath names meshPath: relative to the script's folder (so a folder holding both
// can be moved), or absolute when no relative path exists (another drive or root).
std::string scriptRelativeMeshPath(const std::string& meshPath, const std::string& scriptPath);

// The report as JSON text: the input and output files, the lattice, and per op its status, reason,
// residuals, control points changed, vertices moved and wall time.
struct ReportContext {
    std::string input;
    std::string script;
    std::string output;
    int vertexCount = 0;
    int triangleCount = 0;
    double diagonal = 0.0;
};
std::string reportToJson(const io::ScriptReport& report, const core::Session& session, const ReportContext& context);

// Reads a whole file; the error names the path and the reason.
Status readTextFile(const std::string& path, std::string& out);

}  // namespace sculpt::io
