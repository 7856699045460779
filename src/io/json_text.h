// Parsing JSON text with errors a user can act on: the file, the line and, where the text is well formed up to
// the fault, the field path of the value at fault (scripts, sessions and lattice files share it).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "core/status.h"

namespace sculpt::io {

// Parses `text` into `out`. On failure (malformed text, or a number too large for a double such as 1e999) the
// message is "displayName:LINE: PATH: invalid JSON (reason)", PATH the field path of the value being read
// ("ops[2].lattice.radius"; left out at the top level), and `out` is untouched. Never throws.
Status parseJsonText(const std::string& text, const std::string& displayName, nlohmann::json& out);

// The 1-based line of byte offset `byte` in `text`.
int lineOfByte(const std::string& text, size_t byte);

}  // namespace sculpt::io
