// OFF in and out (io/off_mesh.h through loadMesh and saveMesh): every mesh of CGAL's data package, checked
// against an independent reading of its text here and round-tripped; random meshes in every header form
// (OFF, COFF, NOFF, CNOFF, counts on the header line, comments and blank lines anywhere, CRLF, polygons of 3-8
// corners, colours as bytes or 0-1); bad files refused naming the line, changing nothing.
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "io/mesh_file.h"
#include "io_test_support.h"

namespace sculpt::io {

namespace {

using test::TempFolder;

// An independent reading of an ASCII OFF's vertex positions and faces: the lines that are not blank or
// comments, split on white space, read with strtod and strtol.
struct PlainOff {
    std::vector<std::array<double, 3>> positions;
    std::vector<std::vector<int>> faces;  // those of 3 or more corners
};

bool readPlainOff(const std::string& path, PlainOff& out) {
    std::ifstream in(path);
    std::vector<std::vector<std::string>> lines;
    for (std::string line; std::getline(in, line);) {
        const size_t hash = line.find('#');
        if (hash != std::string::npos) line.erase(hash);
        std::istringstream words(line);
        std::vector<std::string> tokens;
        for (std::string w; words >> w;) tokens.push_back(w);
        if (!tokens.empty()) lines.push_back(tokens);
    }
    if (lines.empty()) return false;
    size_t at = 0;
    std::vector<std::string> counts = lines[0];
    counts.erase(counts.begin());
    if (counts.empty()) counts = lines[++at];
    const long vertices = std::strtol(counts[0].c_str(), nullptr, 10), faces = std::strtol(counts[1].c_str(), nullptr, 10);
    for (long v = 0; v < vertices; ++v) {
        const std::vector<std::string>& t = lines.at(++at);
        out.positions.push_back({std::strtod(t[0].c_str(), nullptr), std::strtod(t[1].c_str(), nullptr), std::strtod(t[2].c_str(), nullptr)});
    }
    for (long f = 0; f < faces; ++f) {
        const std::vector<std::string>& t = lines.at(++at);
        const long corners = std::strtol(t[0].c_str(), nullptr, 10);
        if (corners < 3) continue;
        std::vector<int> face;
        for (long c = 1; c <= corners; ++c) face.push_back(static_cast<int>(std::strtol(t[static_cast<size_t>(c)].c_str(), nullptr, 10)));
        out.faces.push_back(face);
    }
    return true;
}

std::vector<std::vector<int>> facesOf(const ObjMesh& mesh) {
    std::vector<std::vector<int>> faces;
    for (int f = 0; f < mesh.faceCount(); ++f)
        faces.emplace_back(mesh.cornerVertex.begin() + mesh.faceStart[static_cast<size_t>(f)],
                           mesh.cornerVertex.begin() + mesh.faceStart[static_cast<size_t>(f) + 1]);
    return faces;
}

void writeText(const std::string& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

}  // namespace

TEST_CASE("OFF: every mesh of CGAL's data opens in its header's order and round-trips with its colours",
          "[io][formats][off]") {
    const std::string archive = "/usr/share/doc/libcgal-dev/data.tar.gz";
    if (!std::filesystem::exists(archive)) FAIL("libcgal-demo is not installed (.ci/install-deps installs it)");
    TempFolder folder("off_cgal");
    REQUIRE(std::system(("tar -xzf " + archive + " -C '" + folder.path + "' data/meshes").c_str()) == 0);
    int opened = 0, coloured = 0;
    std::vector<std::string> refused;
    std::vector<std::filesystem::path> files;
    for (const auto& entry : std::filesystem::directory_iterator(folder.file("data/meshes")))
        if (entry.path().extension() == ".off") files.push_back(entry.path());
    std::sort(files.begin(), files.end());
    for (const std::filesystem::path& file : files) {
        INFO(file.filename().string());
        PlainOff plain;
        REQUIRE(readPlainOff(file.string(), plain));
        ObjMesh mesh;
        std::vector<std::string> warnings;
        const Status s = loadMesh(file.string(), mesh, &warnings);
        INFO(s.message);
        if (!s.ok) {
            refused.push_back(file.filename().string() + ": " + s.message);
            continue;
        }
        ++opened;
        CHECK(mesh.loadedAs.format == MeshFormat::Off);
        REQUIRE(mesh.positions.rows() == static_cast<Eigen::Index>(plain.positions.size()));
        bool same = true;
        for (size_t v = 0; v < plain.positions.size(); ++v)
            for (int k = 0; k < 3; ++k) same &= mesh.positions(static_cast<Eigen::Index>(v), k) == plain.positions[v][static_cast<size_t>(k)];
        CHECK(same);
        CHECK(facesOf(mesh) == plain.faces);
        coloured += mesh.vertexColors.rows() > 0;
        // Load, save (the positions moved, so the save writes new numbers), load: counts, order, faces, colours.
        Positions moved = mesh.positions;
        moved.col(0).array() += 0.25;
        const std::string saved = folder.file("round.off");
        REQUIRE(saveMesh(saved, mesh, moved).ok);
        ObjMesh back;
        REQUIRE(loadMesh(saved, back).ok);
        CHECK(back.positions == moved);
        CHECK(facesOf(back) == facesOf(mesh));
        REQUIRE(back.vertexColors.rows() == mesh.vertexColors.rows());
        if (mesh.vertexColors.rows() > 0) CHECK(back.vertexColors == mesh.vertexColors);
    }
    INFO(::Catch::Detail::stringify(refused));
    CHECK(refused.empty());
    CHECK(opened == static_cast<int>(files.size()));
    CHECK(opened >= 130);
    CHECK(coloured >= 3);
}

TEST_CASE("OFF: random meshes in every header form, with comments, colours and polygons, load exactly", "[io][formats][off]") {
    TempFolder folder("off_random");
    std::mt19937 rng(1990);
    std::uniform_real_distribution<double> coordinate(-100.0, 100.0);
    int files = 0;
    for (int trial = 0; trial < 40; ++trial) {
        const int vertices = std::uniform_int_distribution<int>(3, 300)(rng);
        const int faces = std::uniform_int_distribution<int>(1, 200)(rng);
        const bool colours = trial % 2 == 1, normals = trial % 4 >= 2, bytes = trial % 8 < 4;
        const bool countsOnHeader = trial % 3 == 0, crlf = trial % 5 == 0, comments = trial % 3 != 1;
        const std::string eol = crlf ? "\r\n" : "\n";
        std::string text;
        if (comments) text += "# written by the OFF test" + eol + eol;
        text += std::string(colours ? "C" : "") + (normals ? "N" : "") + "OFF";
        text += (countsOnHeader ? " " : eol) + std::to_string(vertices) + " " + std::to_string(faces) + " 0" + eol;
        std::vector<std::array<double, 3>> positions(static_cast<size_t>(vertices));
        std::vector<std::array<double, 4>> rgba(static_cast<size_t>(vertices), {1, 1, 1, 1});
        char number[64];
        for (int v = 0; v < vertices; ++v) {
            if (comments && v % 17 == 3) text += "  # vertex " + std::to_string(v) + eol;
            for (int k = 0; k < 3; ++k) {
                positions[static_cast<size_t>(v)][static_cast<size_t>(k)] = coordinate(rng);
                std::snprintf(number, sizeof number, "%.17g ", positions[static_cast<size_t>(v)][static_cast<size_t>(k)]);
                text += number;
            }
            if (normals) text += "0 0 1 ";
            if (colours) {
                const int channels = v % 2 == 0 ? 3 : 4;
                for (int k = 0; k < channels; ++k) {
                    if (bytes) {
                        const int b = std::uniform_int_distribution<int>(0, 255)(rng);
                        rgba[static_cast<size_t>(v)][static_cast<size_t>(k)] = b / 255.0;
                        text += std::to_string(b) + " ";
                    } else {
                        // Quarters: exact in float and in text; written with a point so they read as 0-1.
                        const double c = std::uniform_int_distribution<int>(0, 4)(rng) / 4.0;
                        rgba[static_cast<size_t>(v)][static_cast<size_t>(k)] = c;
                        std::snprintf(number, sizeof number, "%.2f ", c);
                        text += number;
                    }
                }
            }
            text += (comments && v % 11 == 5 ? "# a comment after a vertex" : "") + eol;
        }
        std::vector<std::vector<int>> expected;
        for (int f = 0; f < faces; ++f) {
            const int corners = std::uniform_int_distribution<int>(3, std::min(8, vertices))(rng);
            std::vector<int> pool(static_cast<size_t>(vertices));
            for (int v = 0; v < vertices; ++v) pool[static_cast<size_t>(v)] = v;
            std::shuffle(pool.begin(), pool.end(), rng);
            std::vector<int> face(pool.begin(), pool.begin() + corners);
            expected.push_back(face);
            text += std::to_string(corners);
            for (int c : face) text += " " + std::to_string(c);
            text += eol;
            if (comments && f % 13 == 7) text += eol + "# between faces" + eol;
        }
        const std::string path = folder.file("r.off");
        writeText(path, text);
        ObjMesh mesh;
        std::vector<std::string> warnings;
        const Status s = loadMesh(path, mesh, &warnings);
        INFO("trial " << trial << ": " << s.message << "\n" << text.substr(0, 300));
        REQUIRE(s.ok);
        ++files;
        REQUIRE(mesh.positions.rows() == vertices);
        for (int v = 0; v < vertices; ++v)
            for (int k = 0; k < 3; ++k) CHECK(mesh.positions(v, k) == positions[static_cast<size_t>(v)][static_cast<size_t>(k)]);
        CHECK(facesOf(mesh) == expected);
        CHECK((mesh.vertexNormals.rows() == vertices) == normals);
        REQUIRE((mesh.vertexColors.rows() == vertices) == colours);
        for (int v = 0; v < vertices && colours; ++v)
            for (int k = 0; k < 4; ++k)
                CHECK(mesh.vertexColors(v, k) == static_cast<float>(rgba[static_cast<size_t>(v)][static_cast<size_t>(k)]));
        // What the save writes reads back the same (colours as bytes or as 0-1 with a point).
        const std::string again = folder.file("again.off");
        REQUIRE(saveMesh(again, mesh, mesh.positions).ok);
        ObjMesh back;
        REQUIRE(loadMesh(again, back).ok);
        CHECK(back.positions == mesh.positions);
        CHECK(facesOf(back) == expected);
        CHECK(back.vertexColors == mesh.vertexColors);
    }
    CHECK(files == 40);
}

TEST_CASE("OFF: a bad file is refused naming its line, and changes nothing", "[io][formats][off]") {
    TempFolder folder("off_bad");
    struct Bad {
        std::string text, phrase;
    };
    const std::string square = "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n";
    const std::vector<Bad> cases = {
        {"PFF\n4 2 0\n", "line 1: not an OFF file"},
        {"", "holds no header"},
        {"OFF BINARY\n", "line 1: binary OFF is not read"},
        {"OFF\n4\n", "line 2: the counts line"},
        {"OFF\n4 2000000 0\n0 0 0\n", "line 2: the header declares 4 vertices and 2000000 faces"},
        {"OFF\n4 2 0\n0 0 0\n1 0 x\n", "line 4: vertex 1: 'x' is not a finite number"},
        {"OFF\n4 2 0\n0 0 0\n1 0 nan\n", "line 4: vertex 1: 'nan' is not a finite number"},
        {"OFF\n4 2 0\n0 0\n", "line 3: vertex 0 has 2 numbers"},
        {"COFF\n3 1 0\n0 0 0 255 0 0\n1 0 0 300 0 0\n0 1 0 0 0 0\n3 0 1 2\n", "line 4: vertex 1: colour 300 is outside 0-255"},
        {"COFF\n3 1 0\n0 0 0 1.5 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "line 3: vertex 0: colour 1.5 is outside 0-1"},
        {square + "3 0 1 2\n3 0 2 9\n", "line 8: face 1: '9' is not a vertex index (0 to 3)"},
        {square + "3 0 1 2\n3 0 2 -1\n", "line 8: face 1: '-1' is not a vertex index"},
        {square + "3 0 1 2\n3 0 2\n", "line 8: face 1 declares 3 vertices and lists 2"},
        {square + "3 0 1 2\n", "the file ends early: its header declares 2 faces, and it ends after 1"},
        {"OFF\n4 2 0\n0 0 0\n1 0 0\n# a comment long enough for the counts\n", "the file ends early: its header declares 4 vertices, and it ends after 2"},
        {square + "x 0 1 2\n3 0 2 3\n", "line 7: face 0: 'x' is not a vertex count"},
    };
    for (const Bad& bad : cases) {
        const std::string path = folder.file("bad.off");
        // A comment at the end, so that no short file is refused for its size before the fault it holds is met.
        writeText(path, bad.text + "\n# " + std::string(60, '-') + "\n");
        ObjMesh out;
        out.positions = Positions::Ones(2, 3);
        const Status s = loadMesh(path, out);
        INFO(bad.text << " -> " << s.message);
        CHECK_FALSE(s.ok);
        CHECK(s.message.rfind(path + ": ", 0) == 0);
        CHECK(s.message.find(bad.phrase) != std::string::npos);
        CHECK(out.positions == Positions::Ones(2, 3));
    }
    // What is not kept is named: face colours, faces of fewer than 3 vertices, lines after the last face.
    const std::string path = folder.file("notes.off");
    writeText(path, square + "3 0 1 2 255 0 0\n2 0 3\n3 0 2 3\n3 1 2 3\n");
    ObjMesh mesh;
    std::vector<std::string> warnings;
    REQUIRE(loadMesh(path, mesh, &warnings).ok);
    CHECK(mesh.faceCount() == 1);
    const auto said = [&warnings](const std::string& what) {
        return std::any_of(warnings.begin(), warnings.end(), [&](const std::string& w) { return w.find(what) != std::string::npos; });
    };
    CHECK(said("face colours are not kept (1 faces had one)"));
    CHECK(said("1 face(s) of fewer than 3 vertices"));
    CHECK(said("2 line(s) after the last face the header declares (from line 9) are not read"));
}

}  // namespace sculpt::io
