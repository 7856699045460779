#include "app/cli_options.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>

namespace sculpt::app {

namespace {

bool parseInt(const std::string& text, int& out) {
    char* end = nullptr;
    const long value = std::strtol(text.c_str(), &end, 10);
    if (end == text.c_str() || *end != '\0' || value < 1 || value > 16384) return false;
    out = static_cast<int>(value);
    return true;
}

}  // namespace

const char* usageText() {
    return "usage:\n"
           "  sculpt [MESH.obj | SESSION.json]       open the interactive window (on a mesh, or a saved session)\n"
           "  sculpt --headless [--input MESH.obj] --script OPS.json --output OUT.obj\n"
           "         [--report REPORT.json] [--save-session SESSION.json] [--screenshot OUT.png [--size WxH]\n"
           "         [--camera yaw,pitch,distance] [--overlay jacobian|affected|lattice|wireframe|colors]...]\n"
           "         [--gl-backend auto|osmesa|egl]\n"
           "exit codes: 0 success, 2 bad input (nothing written), 3 output could not be written, 1 internal error\n";
}

Status parseCommandLine(int argc, const char* const* argv, CliOptions& out) {
    CliOptions o;
    std::vector<std::string> positional;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        auto value = [&](std::string& target) -> Status {
            if (i + 1 >= argc) return Status::error("option " + arg + " needs a value");
            target = argv[++i];
            return Status::success();
        };
        Status s;
        if (arg == "--headless") o.headless = true;
        else if (arg == "-h" || arg == "--help") o.help = true;
        else if (arg == "--input") s = value(o.input);
        else if (arg == "--script") s = value(o.script);
        else if (arg == "--output") s = value(o.output);
        else if (arg == "--report") s = value(o.report);
        else if (arg == "--save-session") s = value(o.saveSession);
        else if (arg == "--screenshot") s = value(o.screenshot);
        else if (arg == "--gl-backend") {
            s = value(o.glBackend);
            if (s && o.glBackend != "auto" && o.glBackend != "osmesa" && o.glBackend != "egl")
                return Status::error("--gl-backend must be auto, osmesa or egl (got \"" + o.glBackend + "\")");
        } else if (arg == "--size") {
            std::string text;
            s = value(text);
            const size_t x = text.find('x');
            if (s && (x == std::string::npos || !parseInt(text.substr(0, x), o.width) || !parseInt(text.substr(x + 1), o.height)))
                return Status::error("--size expects WxH with 1 <= W,H <= 16384 (got \"" + text + "\")");
        } else if (arg == "--camera") {
            std::string text;
            s = value(text);
            if (s) {
                std::array<double, 3> c{};
                std::istringstream in(text);
                char comma1 = 0, comma2 = 0;
                in >> c[0] >> comma1 >> c[1] >> comma2 >> c[2];
                if (!in || comma1 != ',' || comma2 != ',' || !in.eof() || !std::isfinite(c[0]) || !std::isfinite(c[1]) ||
                    !std::isfinite(c[2]) || c[2] <= 0.0)
                    return Status::error("--camera expects yaw,pitch,distance (degrees, degrees, > 0) (got \"" + text + "\")");
                o.camera = c;
            }
        } else if (arg == "--overlay") {
            std::string name;
            s = value(name);
            if (s && name != "jacobian" && name != "affected" && name != "lattice" && name != "wireframe" && name != "colors")
                return Status::error("--overlay must be jacobian, affected, lattice, wireframe or colors (got \"" + name + "\")");
            o.overlays.push_back(name);
        } else if (!arg.empty() && arg[0] == '-') {
            return Status::error("unknown option " + arg);
        } else {
            positional.push_back(arg);
        }
        if (!s) return s;
    }
    if (o.headless) {
        if (!positional.empty()) return Status::error("unexpected argument " + positional[0] + " (use --input MESH.obj)");
        if (o.script.empty()) return Status::error("--headless needs --script OPS.json");
        if (o.output.empty()) return Status::error("--headless needs --output OUT.obj");
    } else {
        if (positional.size() > 1) return Status::error("give at most one mesh to open");
        if (positional.size() == 1) o.input = positional[0];
    }
    out = std::move(o);
    return Status::success();
}

std::string defaultMeshPath(const char* argv0) {
    namespace fs = std::filesystem;
    const fs::path source = fs::path(SCULPT_SOURCE_ASSETS) / "default.obj";
    std::error_code ec;
    if (fs::exists(source, ec)) return source.string();
    // An installed or moved binary: look beside it and one level up.
    if (argv0) {
        const fs::path exe = fs::absolute(argv0, ec).parent_path();
        for (const fs::path& candidate : {exe / "assets" / "default.obj", exe.parent_path() / "assets" / "default.obj"})
            if (fs::exists(candidate, ec)) return candidate.string();
    }
    return source.string();
}

}  // namespace sculpt::app
