// Command-line options of the sculpt executable, parsed without side effects so tests can check them.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "core/status.h"

namespace sculpt::app {

struct CliOptions {
    bool headless = false;
    bool help = false;
    std::string input;        // mesh; empty = the bundled default mesh
    bool weld = false;        // --weld: coincident vertices welded on load (io/mesh_weld.h); a script's "weld" too
    std::string script;       // OPS.json (headless)
    std::string output;       // OUT.obj (headless)
    std::string report;       // REPORT.json (optional)
    std::string saveSession;  // the applied history as a replayable OPS.json (optional)
    std::string screenshot;   // PNG written after the script (optional)
    int width = 1280, height = 800;
    std::optional<std::array<double, 3>> camera;  // yaw, pitch (degrees), distance
    std::vector<std::string> overlays;            // jacobian | affected | lattice | wireframe | colors (the file's vertex colours)
    std::string glBackend = "auto";               // auto | osmesa | egl
};

// argv[1..argc) -> options. Errors name the offending argument.
Status parseCommandLine(int argc, const char* const* argv, CliOptions& out);

const char* usageText();

// The folder of the bundled assets (default.obj, lattices/, examples/): an installed copy first
// (PREFIX/share/dmffd-sculpt/assets, looked up from the executable or the Python module that runs this code),
// then assets/ beside the binary or one level up (a build tree), then the source tree's. argv0 (may be null)
// is used only where /proc/self/exe cannot be read.
std::string bundledAssetsFolder(const char* argv0);

// The bundled default mesh: bundledAssetsFolder(argv0)/default.obj.
std::string defaultMeshPath(const char* argv0);

}  // namespace sculpt::app
