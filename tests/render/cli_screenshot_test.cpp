// The headless command line's screenshots: real PNG files from a script's screenshot ops and --screenshot.
#include <catch2/catch.hpp>

#include <array>
#include <filesystem>
#include <fstream>

#include <unistd.h>

#include "app/cli_options.h"
#include "app/headless.h"
#include "io/png_image.h"
#include "test_meshes.h"

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

TEST_CASE("cli: --overlay colors draws a scan's vertex colours, before and after an edit, without it the clay", "[gl]") {
    const fs::path dir = fs::temp_directory_path() / ("sculpt_cli_colours_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    // A coloured PLY sphere: green, as a scan of a green object would be.
    const test::TestMesh sphere = test::makeUvSphere(40, 21);
    const std::string ply = (dir / "scan.ply").string();
    {
        std::ofstream out(ply);
        out << "ply\nformat ascii 1.0\nelement vertex " << sphere.positions.rows()
            << "\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\nproperty uchar green\n"
               "property uchar blue\nelement face "
            << sphere.triangles.rows() << "\nproperty list uchar int vertex_indices\nend_header\n";
        for (Eigen::Index v = 0; v < sphere.positions.rows(); ++v)
            out << sphere.positions(v, 0) << ' ' << sphere.positions(v, 1) << ' ' << sphere.positions(v, 2) << " 30 200 40\n";
        for (Eigen::Index t = 0; t < sphere.triangles.rows(); ++t)
            out << "3 " << sphere.triangles(t, 0) << ' ' << sphere.triangles(t, 1) << ' ' << sphere.triangles(t, 2) << '\n';
    }
    const std::string before = (dir / "before.png").string(), coloured = (dir / "coloured.png").string(),
                      clay = (dir / "clay.png").string();
    std::ofstream((dir / "ops.json").string()) << R"({"ops": [ {"op": "screenshot", "path": ")" << before << R"("},
        {"op": "drag_vertex", "vertex": 400, "target": [0.3, 0.3, 1.2]} ]})";
    const std::string script = (dir / "ops.json").string(), output = (dir / "out.ply").string();
    const auto run = [&](const std::string& png, bool colours) {
        std::vector<const char*> argv{"sculpt", "--headless", "--input", ply.c_str(), "--script", script.c_str(),
                                      "--output", output.c_str(), "--screenshot", png.c_str(), "--size", "160x100"};
        if (colours) argv.insert(argv.end(), {"--overlay", "colors"});
        app::CliOptions options;
        REQUIRE(app::parseCommandLine(static_cast<int>(argv.size()), argv.data(), options).ok);
        REQUIRE(app::runHeadless(options, "sculpt") == app::kExitOk);
    };
    const auto centre = [](const std::string& path) {
        int width = 0, height = 0;
        std::vector<std::uint8_t> rgba;
        REQUIRE(io::readPng(path, width, height, rgba).ok);
        const std::uint8_t* p = &rgba[4 * (size_t(height / 2) * size_t(width) + size_t(width / 2))];
        return std::array<int, 3>{p[0], p[1], p[2]};
    };
    run(coloured, true);
    for (const std::string& path : {before, coloured}) {
        const std::array<int, 3> c = centre(path);
        INFO(path << ": " << c[0] << " " << c[1] << " " << c[2]);
        CHECK(c[1] > c[0] + 40);
        CHECK(c[1] > c[2] + 40);
    }
    run(clay, false);
    const std::array<int, 3> c = centre(clay);
    INFO(c[0] << " " << c[1] << " " << c[2]);
    CHECK(c[1] < c[0] + 20);  // the clay: no green cast
    fs::remove_all(dir);
}
