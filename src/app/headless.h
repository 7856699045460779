// Headless mode: load a mesh, run an OPS.json script through the engine, write the deformed mesh, the
// report and screenshots. Uses exactly the engine commands the window uses.
#pragma once

#include "app/cli_options.h"

namespace sculpt::app {

enum ExitCode { kExitOk = 0, kExitInternal = 1, kExitBadInput = 2, kExitWriteFailed = 3 };

// Runs the headless job; messages go to stdout (progress) and stderr (errors). Returns the exit code.
int runHeadless(const CliOptions& options, const char* argv0);

}  // namespace sculpt::app
