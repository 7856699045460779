// The headless command line end to end: real files in a temporary folder, the same entry point main() uses.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "app/cli_options.h"
#include "app/headless.h"
#include "io/mesh_file.h"
#include "io/obj_mesh.h"

namespace fs = std::filesystem;
using namespace sculpt;

namespace {

struct TempDir {
    fs::path path;
    TempDir() {
        static int counter = 0;
        path = fs::temp_directory_path() / ("sculpt_headless_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
        fs::remove_all(path);
        fs::create_directories(path);
    }
    ~TempDir() { fs::remove_all(path); }
    std::string file(const std::string& name) const { return (path / name).string(); }
};

void writeText(const std::string& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

std::string readText(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

// A closed octahedron-like test mesh, small enough to reason about.
std::string cubeObj() {
    return "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n"
           "f 1 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\nf 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n";
}

int run(const std::vector<std::string>& args) {
    std::vector<const char*> argv{"sculpt"};
    for (const auto& a : args) argv.push_back(a.c_str());
    app::CliOptions options;
    if (!app::parseCommandLine(static_cast<int>(argv.size()), argv.data(), options)) return app::kExitBadInput;
    return app::runHeadless(options, "sculpt");
}

}  // namespace

TEST_CASE("headless: a script deforms the mesh, writes it and a report", "[app]") {
    TempDir dir;
    writeText(dir.file("cube.obj"), cubeObj());
    writeText(dir.file("ops.json"), R"({
      "lattice": {"resolution": [6,6,6], "degree": [3,3,3], "padding": 0.1},
      "ops": [ {"op": "drag_vertex", "vertex": 6, "target": [1.3, 1.2, 1.1]},
               {"op": "drag", "constraints": [{"source": [-1,-1,-1], "target": [-1.2,-1,-1]},
                                              {"source": [1,-1,-1], "target": [1.2,-1.1,-1]}]},
               {"op": "move_control_point", "index": [3,3,3], "by": [0, 0.05, 0]},
               {"op": "undo"}, {"op": "redo"}, {"op": "redo"} ] })");
    REQUIRE(run({"--headless", "--input", dir.file("cube.obj"), "--script", dir.file("ops.json"), "--output",
                 dir.file("out.obj"), "--report", dir.file("report.json")}) == app::kExitOk);
    io::ObjMesh out;
    REQUIRE(io::loadObj(dir.file("out.obj"), out).ok);
    REQUIRE(out.positions.rows() == 8);
    const double diagonal = std::sqrt(12.0);
    // The drag_vertex target was met before the later ops; the drag's sources sit on their targets after it.
    const auto report = nlohmann::json::parse(readText(dir.file("report.json")));
    REQUIRE(report["ops"].size() == 6);
    for (int i = 0; i < 5; ++i) REQUIRE(report["ops"][i]["status"] == "applied");
    REQUIRE(report["ops"][5]["status"] == "no-op");
    REQUIRE(report["ops"][5]["reason"] == "nothing to redo");
    REQUIRE(report["ops"][1]["residuals"].size() == 2);
    REQUIRE(report["ops"][1]["max_residual"].get<double>() <= 1e-9 * diagonal);
    REQUIRE(report["ops"][0]["control_points_changed"].get<int>() == 64);
    REQUIRE(report["ops"][2]["control_points_changed"].get<int>() == 1);
    REQUIRE(report["ops"][0].contains("wall_ms"));
    // The vertex dragged first has since been moved a little by the later drags, but not far.
    REQUIRE((out.positions.row(6) - Eigen::RowVector3d(1.3, 1.2, 1.1)).norm() < 0.2);
}

TEST_CASE("headless: bad input exits 2, says why and writes nothing", "[app]") {
    TempDir dir;
    writeText(dir.file("cube.obj"), cubeObj());
    writeText(dir.file("out.obj"), "precious user data\n");
    const std::vector<std::pair<std::string, std::string>> scripts = {
        {"unknown op", R"({"ops": [{"op": "explode"}]})"},
        {"non-finite", R"({"ops": [{"op": "drag_vertex", "vertex": 1, "target": [1, 2, 1e999]}]})"},
        {"outside", R"({"ops": [{"op": "drag", "constraints": [{"source": [50,0,0], "target": [0,0,0]}]}]})"},
        {"vertex range", R"({"ops": [{"op": "drag_vertex", "vertex": 8, "target": [0,0,0]}]})"},
        {"degree", R"({"lattice": {"degree": [3,9,3]}, "ops": []})"},
        {"resolution", R"({"lattice": {"resolution": [2,8,8]}, "ops": []})"},
        {"control point", R"({"ops": [{"op": "move_control_point", "index": [8,0,0], "to": [0,0,0]}]})"},
        {"late failure", R"({"ops": [{"op": "drag_vertex", "vertex": 1, "target": [1.1,-1,-1]},
                                     {"op": "drag_vertex", "vertex": -3, "target": [0,0,0]}]})"},
        {"not json", "{ops: nope"},
        {"unknown field", R"({"ops": [], "colour": 3})"},
    };
    for (const auto& [name, text] : scripts) {
        INFO(name);
        writeText(dir.file("ops.json"), text);
        REQUIRE(run({"--headless", "--input", dir.file("cube.obj"), "--script", dir.file("ops.json"), "--output",
                     dir.file("out.obj"), "--report", dir.file("report.json")}) == app::kExitBadInput);
        REQUIRE(readText(dir.file("out.obj")) == "precious user data\n");
        REQUIRE_FALSE(fs::exists(dir.file("report.json")));
    }
    // A malformed mesh and a missing one are bad input too.
    writeText(dir.file("ops.json"), R"({"ops": []})");
    writeText(dir.file("bad.obj"), "v 0 0 0\nv 1 0 0\nf 1 2 3\n");
    REQUIRE(run({"--headless", "--input", dir.file("bad.obj"), "--script", dir.file("ops.json"), "--output", dir.file("out.obj")}) ==
            app::kExitBadInput);
    REQUIRE(run({"--headless", "--input", dir.file("missing.obj"), "--script", dir.file("ops.json"), "--output", dir.file("out.obj")}) ==
            app::kExitBadInput);
    REQUIRE(readText(dir.file("out.obj")) == "precious user data\n");
}

TEST_CASE("headless: an unwritable output exits 3 and leaves no partial file", "[app]") {
    TempDir dir;
    writeText(dir.file("cube.obj"), cubeObj());
    writeText(dir.file("ops.json"), R"({"ops": []})");
    REQUIRE(run({"--headless", "--input", dir.file("cube.obj"), "--script", dir.file("ops.json"), "--output",
                 dir.file("no/such/folder/out.obj")}) == app::kExitWriteFailed);
    REQUIRE_FALSE(fs::exists(dir.file("no")));
}

TEST_CASE("headless: command line errors name the argument", "[app]") {
    auto parse = [](std::vector<const char*> args) {
        args.insert(args.begin(), "sculpt");
        app::CliOptions options;
        return app::parseCommandLine(static_cast<int>(args.size()), args.data(), options);
    };
    REQUIRE(parse({"--headless", "--output", "x.obj"}).message.find("--script") != std::string::npos);
    REQUIRE(parse({"--headless", "--script", "x.json"}).message.find("--output") != std::string::npos);
    REQUIRE(parse({"--frobnicate"}).message.find("--frobnicate") != std::string::npos);
    REQUIRE(parse({"--headless", "--script", "a", "--output", "b", "--size", "12by4"}).message.find("--size") != std::string::npos);
    REQUIRE(parse({"--headless", "--script", "a", "--output", "b", "--camera", "1,2"}).message.find("--camera") != std::string::npos);
    REQUIRE(parse({"--headless", "--script", "a", "--output", "b", "--overlay", "xray"}).message.find("--overlay") != std::string::npos);
    REQUIRE(parse({"--headless", "--script"}).message.find("needs a value") != std::string::npos);
    REQUIRE(parse({"--headless", "--script", "a", "--output", "b", "--camera", "30,20,4", "--size", "640x480"}).ok);
}

TEST_CASE("headless: --save-session writes a script that replays to the same mesh", "[app]") {
    TempDir dir;
    writeText(dir.file("cube.obj"), cubeObj());
    writeText(dir.file("ops.json"), R"({
      "lattice": {"resolution": [5,5,5], "padding": 0.2},
      "injectivity": {"mode": "exact", "max_depth": 5},
      "ops": [ {"op": "drag_vertex", "vertex": 6, "target": [2.2, 1.9, 1.6]},
               {"op": "move_control_point", "indices": [[2,2,2],[1,2,2]], "by": [0, 0.1, 0]},
               {"op": "drag_vertex", "vertex": 0, "target": [-1.1, -1.0, -1.0]},
               {"op": "undo"},
               {"op": "setup_lattice", "lattice": {"resolution": [6,6,6]}},
               {"op": "drag_vertex", "vertex": 1, "target": [1.3, -1.2, -1.0]} ] })");
    REQUIRE(run({"--headless", "--input", dir.file("cube.obj"), "--script", dir.file("ops.json"), "--output",
                 dir.file("out.obj"), "--save-session", dir.file("session.json"), "--report", dir.file("report.json")}) == app::kExitOk);
    const auto report = nlohmann::json::parse(readText(dir.file("report.json")));
    REQUIRE(report["ops"][0]["sub_steps"].get<int>() >= 1);
    REQUIRE(report["ops"][0]["injectivity"] == "injective");
    REQUIRE(report["injectivity"]["mode"] == "exact");
    REQUIRE(run({"--headless", "--input", dir.file("cube.obj"), "--script", dir.file("session.json"), "--output",
                 dir.file("replayed.obj")}) == app::kExitOk);
    io::ObjMesh original, replayed;
    REQUIRE(io::loadObj(dir.file("out.obj"), original).ok);
    REQUIRE(io::loadObj(dir.file("replayed.obj"), replayed).ok);
    // The same mesh: the recorded steps are repeated, so the result is the same to the bit.
    REQUIRE(original.positions == replayed.positions);
    const auto session = nlohmann::json::parse(readText(dir.file("session.json")));
    REQUIRE(session["ops"].size() == 6);  // every command, the undone drag and the undo included
    REQUIRE(session["ops"][3]["op"] == "undo");
    REQUIRE(session["ops"][0].contains("applied"));
}

TEST_CASE("headless: PLY in, glTF out, and a session that names the PLY replays to the same vertices", "[app]") {
    TempDir dir;
    writeText(dir.file("cube.obj"), cubeObj());
    writeText(dir.file("empty.json"), R"({"ops": []})");
    // The cube as a PLY (through the command line itself), then sculpted from the PLY into a GLB.
    REQUIRE(run({"--headless", "--input", dir.file("cube.obj"), "--script", dir.file("empty.json"), "--output",
                 dir.file("cube.ply")}) == app::kExitOk);
    writeText(dir.file("ops.json"), R"({"lattice": {"resolution": [5,5,5], "padding": 0.2},
      "ops": [ {"op": "drag_vertex", "vertex": 6, "target": [1.6, 1.4, 1.3]} ] })");
    REQUIRE(run({"--headless", "--input", dir.file("cube.ply"), "--script", dir.file("ops.json"), "--output",
                 dir.file("out.glb"), "--save-session", dir.file("session.json")}) == app::kExitOk);
    const auto session = nlohmann::json::parse(readText(dir.file("session.json")));
    REQUIRE(session["mesh"] == "cube.ply");
    // Without --input the session's own mesh is loaded: the PLY.
    REQUIRE(run({"--headless", "--script", dir.file("session.json"), "--output", dir.file("replayed.glb")}) == app::kExitOk);
    CHECK(readText(dir.file("replayed.glb")) == readText(dir.file("out.glb")));
    io::ObjMesh out;
    REQUIRE(io::loadMesh(dir.file("out.glb"), out).ok);
    CHECK(out.vertexCount() == 8);
    CHECK((out.positions.row(6) - Eigen::RowVector3d(1.6, 1.4, 1.3)).norm() < 1e-6);  // the target, in float
    // An output extension no format has is refused before any work, and nothing is written.
    CHECK(run({"--headless", "--input", dir.file("cube.ply"), "--script", dir.file("ops.json"), "--output",
               dir.file("out.fbx")}) == app::kExitBadInput);
    CHECK_FALSE(fs::exists(dir.file("out.fbx")));
}

// Issue: triangle soups. A real mesh (CGAL's) written as a soup (three vertices per triangle, shuffled corners
// apart) loads as disconnected triangles: without --weld the program warns and keeps them; with --weld (or a
// script's "weld": true) it welds them back to exactly the original surface, vertices in the order of first use,
// and a session saved from it says "weld" and replays on the soup to the same vertices.
TEST_CASE("headless: --weld joins a triangle soup into the surface it came from, and a saved session welds again", "[app][weld]") {
    TempDir dir;
    std::mt19937 random(31);
    // A closed surface: an icosahedron refined by midpoints (every vertex shared by 5 or 6 triangles).
    io::ObjMesh source;
    REQUIRE(io::loadObj(SCULPT_SOURCE_DIR "/assets/default.obj", source).ok);
    const Positions& p = source.positions;
    const Triangles& t = source.triangles;
    std::string soup;
    for (Eigen::Index f = 0; f < t.rows(); ++f)
        for (int k = 0; k < 3; ++k) {
            char line[128];
            std::snprintf(line, sizeof line, "v %.17g %.17g %.17g\n", p(t(f, k), 0), p(t(f, k), 1), p(t(f, k), 2));
            soup += line;
        }
    for (Eigen::Index f = 0; f < t.rows(); ++f)
        soup += "f " + std::to_string(3 * f + 1) + " " + std::to_string(3 * f + 2) + " " + std::to_string(3 * f + 3) + "\n";
    writeText(dir.file("soup.obj"), soup);
    const int vertex = static_cast<int>(random() % static_cast<unsigned>(p.rows()));
    writeText(dir.file("ops.json"), R"({"ops": [ {"op": "drag_vertex", "vertex": )" + std::to_string(vertex) +
                                        R"(, "target": [0.1, 0.2, 0.3]} ]})");
    // Without --weld: kept as a soup of 3 #T vertices.
    REQUIRE(run({"--headless", "--input", dir.file("soup.obj"), "--script", dir.file("ops.json"), "--output", dir.file("kept.obj")}) == app::kExitOk);
    io::ObjMesh kept;
    REQUIRE(io::loadObj(dir.file("kept.obj"), kept).ok);
    CHECK(kept.positions.rows() == 3 * t.rows());
    // With --weld: the original surface, each vertex once, in the order the soup first uses it.
    REQUIRE(run({"--headless", "--input", dir.file("soup.obj"), "--weld", "--script", dir.file("ops.json"), "--output",
                 dir.file("welded.obj"), "--save-session", dir.file("session.json")}) == app::kExitOk);
    io::ObjMesh welded;
    REQUIRE(io::loadObj(dir.file("welded.obj"), welded).ok);
    REQUIRE(welded.positions.rows() == p.rows());
    REQUIRE(welded.triangles.rows() == t.rows());
    std::vector<int> order;  // first use of each original vertex in the soup
    std::vector<char> seen(static_cast<size_t>(p.rows()), 0);
    for (Eigen::Index f = 0; f < t.rows(); ++f)
        for (int k = 0; k < 3; ++k)
            if (!seen[static_cast<size_t>(t(f, k))]) seen[static_cast<size_t>(t(f, k))] = 1, order.push_back(t(f, k));
    // Same connectivity: welded triangle f is original triangle f renumbered by first use.
    std::vector<int> number(static_cast<size_t>(p.rows()));
    for (size_t w = 0; w < order.size(); ++w) number[static_cast<size_t>(order[w])] = static_cast<int>(w);
    for (Eigen::Index f = 0; f < t.rows(); ++f)
        for (int k = 0; k < 3; ++k) REQUIRE(welded.triangles(f, k) == number[static_cast<size_t>(t(f, k))]);
    // The saved session welds the soup again and replays to the same vertices.
    const auto session = nlohmann::json::parse(readText(dir.file("session.json")));
    CHECK(session["weld"] == true);
    REQUIRE(run({"--headless", "--input", dir.file("soup.obj"), "--script", dir.file("session.json"), "--output",
                 dir.file("replayed.obj")}) == app::kExitOk);
    io::ObjMesh replayed;
    REQUIRE(io::loadObj(dir.file("replayed.obj"), replayed).ok);
    CHECK(replayed.positions == welded.positions);
}
