#include "app/cli_options.h"

#include <cmath>
#include <dlfcn.h>
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
           "  sculpt --headless [--input MESH.obj] [--weld] --script OPS.json --output OUT.obj\n"
           "         [--report REPORT.json] [--save-session SESSION.json] [--screenshot OUT.png [--size WxH]\n"
           "         [--camera yaw,pitch,distance] [--overlay jacobian|affected|lattice|wireframe|colors]...]\n"
           "         [--gl-backend auto|osmesa|egl]\n"
           "  --weld: vertices at exactly the same position become one on load (a triangle soup made one surface)\n"
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
        else if (arg == "--weld") o.weld = true;
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

std::string bundledAssetsFolder(const char* argv0) {
    namespace fs = std::filesystem;
    std::error_code ec;
    // The file this code runs in: the Python module's .so (dladdr), else the executable (/proc/self/exe, or argv0).
    fs::path self;
    Dl_info info{};
    if (dladdr(reinterpret_cast<void*>(&bundledAssetsFolder), &info) != 0 && info.dli_fname && *info.dli_fname) {
        const fs::path object(info.dli_fname);
        if (object.extension() == ".so") self = fs::absolute(object, ec);
    }
    if (self.empty()) self = fs::read_symlink("/proc/self/exe", ec);
    if (self.empty() && argv0) self = fs::absolute(argv0, ec);
    // Installed (cmake --install, the Debian package, pip): PREFIX/share/dmffd-sculpt/assets, found from
    // PREFIX/bin/sculpt or PREFIX/lib/python3/dist-packages/sculpt*.so (a venv: lib/python3.X/site-packages).
    fs::path up = self.parent_path();
    for (int level = 0; level < 4 && !up.empty(); ++level, up = up.parent_path()) {
        const fs::path installed = up / "share" / "dmffd-sculpt" / "assets";
        if (fs::exists(installed / "default.obj", ec)) return installed.string();
    }
    // A build tree or a moved binary: assets beside it or one level up; else the source tree's.
    for (const fs::path& candidate : {self.parent_path() / "assets", self.parent_path().parent_path() / "assets"})
        if (!self.empty() && fs::exists(candidate / "default.obj", ec)) return candidate.string();
    return SCULPT_SOURCE_ASSETS;
}

std::string defaultMeshPath(const char* argv0) {
    return (std::filesystem::path(bundledAssetsFolder(argv0)) / "default.obj").string();
}

}  // namespace sculpt::app
