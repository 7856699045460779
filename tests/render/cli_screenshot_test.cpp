// The headless command line's screenshots: real PNG files from a script's screenshot ops and --screenshot.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

#include <unistd.h>

#include "app/cli_options.h"
#include "app/headless.h"
#include "io/png_image.h"

namespace fs = std::filesystem;
using namespace sculpt;

TEST_CASE("cli: screenshot ops and --screenshot write framed PNGs of the requested size", "[gl]") {
    const fs::path dir = fs::temp_directory_path() / ("sculpt_cli_png_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string before = (dir / "before.png").string(), after = (dir / "after.png").string();
    std::ofstream((dir / "ops.json").string()) << R"({"ops": [ {"op": "screenshot", "path": ")" << before << R"("},
        {"op": "drag_vertex", "vertex": 4968, "target": [-0.04, 0.02, 1.4]} ]})";
    const std::string script = (dir / "ops.json").string(), output = (dir / "out.obj").string();
    std::vector<const char*> argv{"sculpt", "--headless", "--script", script.c_str(), "--output", output.c_str(),
                                  "--screenshot", after.c_str(), "--size", "200x120", "--overlay", "jacobian",
                                  "--overlay", "lattice", "--camera", "40,25,6"};
    app::CliOptions options;
    REQUIRE(app::parseCommandLine(static_cast<int>(argv.size()), argv.data(), options).ok);
    REQUIRE(app::runHeadless(options, "sculpt") == app::kExitOk);
    for (const std::string& path : {before, after}) {
        int width = 0, height = 0;
        std::vector<std::uint8_t> rgba;
        REQUIRE(io::readPng(path, width, height, rgba).ok);
        REQUIRE(width == 200);
        REQUIRE(height == 120);
        // The mesh is in the picture: the centre pixel is not the background gradient's grey-blue.
        const std::uint8_t* centre = &rgba[4 * (60 * 200 + 100)];
        REQUIRE(int(centre[0]) > int(centre[2]));
    }
    fs::remove_all(dir);
}
