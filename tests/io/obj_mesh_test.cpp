// OBJ reading and writing: exact round trips, polygons, and every malformed input as a clean error.
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "io/obj_mesh.h"
#include "io_test_support.h"
#include "io/obj_scan.h"

using sculpt::Positions;
using sculpt::Status;
using sculpt::io::ObjMesh;

namespace {

const std::string kDataDir = std::string(SCULPT_SOURCE_DIR) + "/tests/io/data";

using sculpt::test::TempFolder;
using sculpt::test::readBytes;

void writeBytes(const std::string& path, const std::string& bytes) {
    std::ofstream out(path, std::ios::binary);
    out << bytes;
}

bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

bool sameBits(const Eigen::Ref<const Eigen::MatrixXd>& a, const Eigen::Ref<const Eigen::MatrixXd>& b) {
    if (a.rows() != b.rows() || a.cols() != b.cols()) return false;
    for (Eigen::Index i = 0; i < a.rows(); ++i)
        for (Eigen::Index j = 0; j < a.cols(); ++j)
            if (!sameBits(a(i, j), b(i, j))) return false;
    return true;
}

Status loadText(const std::string& text, ObjMesh& mesh, std::vector<std::string>* warnings = nullptr) {
    return sculpt::io::loadObjFromText(text, "test.obj", "", mesh, warnings);
}

bool anyContains(const std::vector<std::string>& lines, const std::string& fragment) {
    for (const std::string& line : lines)
        if (line.find(fragment) != std::string::npos) return true;
    return false;
}

// A copy without its source text: serializeObj then writes from the arrays (as for a mesh built in code).
ObjMesh withoutSource(ObjMesh mesh) {
    mesh.source = nullptr;
    return mesh;
}

// Everything a reader should get back from a written file (normals excepted: they are recomputed).
void requireSameSurface(const ObjMesh& a, const ObjMesh& b) {
    REQUIRE(sameBits(a.positions, b.positions));
    REQUIRE(a.faceStart == b.faceStart);
    REQUIRE(a.cornerVertex == b.cornerVertex);
    REQUIRE(a.cornerTexcoord == b.cornerTexcoord);
    REQUIRE(sameBits(a.texcoords, b.texcoords));
    REQUIRE(a.triangles == b.triangles);
    REQUIRE(a.triangleFace == b.triangleFace);
    REQUIRE(a.faceCount() == b.faceCount());
    for (int f = 0; f < a.faceCount(); ++f) {
        REQUIRE(a.groupNames[a.faceGroup[f]] == b.groupNames[b.faceGroup[f]]);
        const std::string materialA = a.faceMaterial[f] < 0 ? "" : a.materialNames[a.faceMaterial[f]];
        const std::string materialB = b.faceMaterial[f] < 0 ? "" : b.materialNames[b.faceMaterial[f]];
        REQUIRE(materialA == materialB);
    }
    REQUIRE(a.materialLibraries == b.materialLibraries);
}

// Doubles that stress shortest printing: ordinary, tiny, huge, subnormal, signed zero, random bits.
double randomDouble(std::mt19937_64& random) {
    std::uniform_int_distribution<int> kind(0, 6);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    switch (kind(random)) {
        case 0:
            return unit(random);
        case 1:
            return unit(random) * 1e-300;
        case 2:
            return unit(random) * 1e300;
        case 3:
            return unit(random) * 4.9e-324 * 1000.0;  // subnormal
        case 4:
            return std::uniform_int_distribution<int>(0, 1)(random) ? 0.0 : -0.0;
        case 5:
            return std::round(unit(random) * 1000.0) / 8.0;
        default: {
            for (;;) {  // any finite bit pattern
                const std::uint64_t bits = random();
                double value;
                std::memcpy(&value, &bits, sizeof value);
                if (std::isfinite(value)) return value;
            }
        }
    }
}

// A random polygon soup with texture coordinates, groups and materials, built as the reader would.
ObjMesh randomMesh(std::mt19937_64& random, int vertexCount, int faceCount) {
    ObjMesh mesh;
    mesh.positions.resize(vertexCount, 3);
    for (int v = 0; v < vertexCount; ++v)
        for (int k = 0; k < 3; ++k) mesh.positions(v, k) = randomDouble(random);
    const int texcoordColumns = std::uniform_int_distribution<int>(2, 3)(random);
    const int texcoordCount = std::uniform_int_distribution<int>(0, 1)(random) ? vertexCount : 0;
    mesh.texcoords.resize(texcoordCount, texcoordColumns);
    for (int t = 0; t < texcoordCount; ++t)
        for (int k = 0; k < texcoordColumns; ++k) mesh.texcoords(t, k) = randomDouble(random);
    mesh.groupNames = {"", "body", "left arm"};
    mesh.materialNames = {"skin", "cloth"};
    mesh.materialLibraries = {"figure.mtl"};
    mesh.faceStart = {0};
    std::uniform_int_distribution<int> anyVertex(0, vertexCount - 1);
    int group = 0, material = -1;
    for (int f = 0; f < faceCount; ++f) {
        const int corners = std::uniform_int_distribution<int>(3, 6)(random);
        for (int c = 0; c < corners; ++c) {
            mesh.cornerVertex.push_back(anyVertex(random));
            mesh.cornerTexcoord.push_back(texcoordCount > 0 ? mesh.cornerVertex.back() : -1);
            mesh.cornerNormal.push_back(-1);
        }
        mesh.faceStart.push_back(static_cast<int>(mesh.cornerVertex.size()));
        // Groups and materials change in runs, and the first use order is 0, 1, 2 as the reader has it.
        if (f > 0 && random() % 5 == 0) group = std::min(group + 1, 2);
        if (f > 0 && random() % 4 == 0) material = std::min(material + 1, 1);
        mesh.faceGroup.push_back(group);
        mesh.faceMaterial.push_back(material);
    }
    sculpt::io::triangulateObjFaces(mesh);  // as the reader does (random polygons: mostly fans)
    // Names only count once a face uses them (the reader's rule), so drop unused ones.
    auto used = [](const std::vector<int>& index, int i) {
        return std::find(index.begin(), index.end(), i) != index.end();
    };
    while (mesh.groupNames.size() > 1 && !used(mesh.faceGroup, static_cast<int>(mesh.groupNames.size()) - 1))
        mesh.groupNames.pop_back();
    while (!mesh.materialNames.empty() && !used(mesh.faceMaterial, static_cast<int>(mesh.materialNames.size()) - 1))
        mesh.materialNames.pop_back();
    return mesh;
}

ObjMesh sentinelMesh() {
    ObjMesh mesh;
    mesh.positions = Positions::Constant(2, 3, 42.0);
    mesh.groupNames = {"", "sentinel"};
    return mesh;
}

void requireSentinel(const ObjMesh& mesh) {
    REQUIRE(mesh.positions.rows() == 2);
    REQUIRE(mesh.positions(1, 2) == 42.0);
    REQUIRE(mesh.groupNames.size() == 2);
    REQUIRE(mesh.faceStart.empty());
}

}  // namespace

TEST_CASE("obj: a quad and a pentagon (convex) are fan-triangulated and written back as polygons") {
    const std::string text =
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2.5 1 0\nv 2 2 0\n"
        "f 1 2 3 4\n"
        "f 2 5 6 7 3\n";
    ObjMesh mesh;
    REQUIRE(loadText(text, mesh));
    REQUIRE(mesh.faceCount() == 2);
    REQUIRE(mesh.faceStart == std::vector<int>{0, 4, 9});
    REQUIRE(mesh.triangles.rows() == 2 + 3);
    sculpt::Triangles expected(5, 3);
    expected << 0, 1, 2, 0, 2, 3, 1, 4, 5, 1, 5, 6, 1, 6, 2;
    REQUIRE(mesh.triangles == expected);
    REQUIRE(mesh.triangleFace == std::vector<int>{0, 0, 1, 1, 1});
    REQUIRE(mesh.cornerTexcoord == std::vector<int>(9, -1));

    std::string written;
    REQUIRE(sculpt::io::serializeObj(mesh, mesh.positions, written));
    REQUIRE(written == text);  // a loaded mesh saved unchanged is its file
    // Written from the arrays: no texture coordinates in the input: v//vn corners, one normal per vertex.
    REQUIRE(sculpt::io::serializeObj(withoutSource(mesh), mesh.positions, written));
    REQUIRE(written.find("\nf 1//1 2//2 3//3 4//4\n") != std::string::npos);
    REQUIRE(written.find("\nf 2//2 5//5 6//6 7//7 3//3\n") != std::string::npos);
    size_t normalLines = 0;
    for (size_t at = written.find("\nvn "); at != std::string::npos; at = written.find("\nvn ", at + 1)) ++normalLines;
    REQUIRE(normalLines == 7);
    ObjMesh reread;
    REQUIRE(loadText(written, reread));
    requireSameSurface(mesh, reread);
    REQUIRE(reread.cornerNormal == reread.cornerVertex);
}

TEST_CASE("obj: written normals are the recomputed, outward normals of the deformed positions") {
    ObjMesh mesh;
    REQUIRE(loadText("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 1 0 0\nf 1//1 2//1 3//1\n", mesh));
    Positions lifted = mesh.positions;
    lifted.col(2).setConstant(3.0);
    std::string written;
    // The file's one normal, shared by the three moved corners, recomputed in its place.
    REQUIRE(sculpt::io::serializeObj(mesh, lifted, written));
    REQUIRE(written == "v 0 0 3\nv 1 0 3\nv 0 1 3\nvn 0 0 1\nf 1//1 2//1 3//1\n");
    // From the arrays: one recomputed normal per vertex.
    REQUIRE(sculpt::io::serializeObj(withoutSource(mesh), lifted, written));
    REQUIRE(written.find("\nv 0 0 3\n") != std::string::npos);
    REQUIRE(written.find("\nvn 0 0 1\nvn 0 0 1\nvn 0 0 1\n") != std::string::npos);
    REQUIRE(written.find("vn 1 0 0") == std::string::npos);
}

TEST_CASE("obj: numbers are read correctly rounded and written in shortest round-trip form") {
    ObjMesh mesh;
    REQUIRE(
        loadText("v 0.1 -0 +2.5e-3\nv 2.4703282292062328e-324 1.7976931348623157e308 .5\n"
                 "v 0.30000000000000004 1E2 -7.\nf 1 2 3\n",
                 mesh));
    REQUIRE(sameBits(mesh.positions(0, 0), 0.1));
    REQUIRE(sameBits(mesh.positions(0, 1), -0.0));
    REQUIRE(sameBits(mesh.positions(0, 2), 2.5e-3));
    REQUIRE(sameBits(mesh.positions(1, 0), 4.9406564584124654e-324));
    REQUIRE(sameBits(mesh.positions(1, 1), 1.7976931348623157e308));
    REQUIRE(sameBits(mesh.positions(2, 0), 0.1 + 0.2));
    std::string written;
    // Unmoved vertices keep their text; moved ones (and everything written from the arrays) are shortest.
    REQUIRE(sculpt::io::serializeObj(mesh, mesh.positions, written));
    REQUIRE(written.find("v 0.1 -0 +2.5e-3\n") == 0);
    Positions moved = mesh.positions;
    moved(2, 2) = -7.5;
    REQUIRE(sculpt::io::serializeObj(mesh, moved, written));
    REQUIRE(written.find("v 0.1 -0 +2.5e-3\n") == 0);
    REQUIRE(written.find("\nv 0.30000000000000004 100 -7.5\n") != std::string::npos);
    REQUIRE(sculpt::io::serializeObj(withoutSource(mesh), mesh.positions, written));
    REQUIRE(written.find("\nv 0.1 -0 0.0025\n") != std::string::npos);
    REQUIRE(written.find("\nv 0.30000000000000004 100 -7\n") != std::string::npos);
}

// A mesh built in code, written and read back: the same surface, bit for bit, and writing what was read gives
// the same bytes (nothing drifts over repeated saves).
void requireRoundTrip(const ObjMesh& mesh) {
    REQUIRE(sculpt::io::checkObjMesh(mesh));
    std::string written;
    REQUIRE(sculpt::io::serializeObj(mesh, mesh.positions, written));
    ObjMesh reread;
    const Status status = loadText(written, reread);
    INFO(status.message);
    REQUIRE(status);
    requireSameSurface(mesh, reread);
    std::string writtenAgain;
    REQUIRE(sculpt::io::serializeObj(reread, reread.positions, writtenAgain));
    REQUIRE(writtenAgain == written);
}

TEST_CASE("obj: round trip is bitwise exact for random meshes") {
    for (int size : {1, 3, 17, 200, 3000}) {
        std::mt19937_64 random(1234 + size);
        requireRoundTrip(randomMesh(random, size + 2, size));
    }
}

TEST_CASE("obj: round trip through saveObj and loadObj keeps deformed positions exactly") {
    TempFolder folder;
    std::mt19937_64 random(99);
    const ObjMesh mesh = randomMesh(random, 500, 400);
    Positions deformed = mesh.positions;
    for (Eigen::Index v = 0; v < deformed.rows(); ++v)
        deformed.row(v) = deformed.row(v) * 0.5 + Eigen::RowVector3d(0.1, -1e-7, 3.0);
    REQUIRE(deformed.allFinite());
    REQUIRE(sculpt::io::saveObj(folder.file("out.obj"), mesh, deformed));
    ObjMesh reread;
    std::vector<std::string> warnings;
    REQUIRE(sculpt::io::loadObj(folder.file("out.obj"), reread, &warnings));
    REQUIRE(sameBits(reread.positions, deformed));
    REQUIRE(reread.faceStart == mesh.faceStart);
    REQUIRE(reread.cornerVertex == mesh.cornerVertex);
    REQUIRE(anyContains(warnings, "figure.mtl"));  // not next to the file: a warning, not an error
}

TEST_CASE("obj: groups, materials and 3-component texture coordinates are kept") {
    ObjMesh mesh;
    std::vector<std::string> warnings;
    REQUIRE(
        loadText("mtllib  shop.mtl \n"
                 "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
                 "vt 0 0 0.5\nvt 1 0\nvt 0.25\n"
                 "f 1/1 2/2 3/3\n"
                 "o   head   part\nusemtl skin extra\nf 2/1 4/2 3/3\n"
                 "g tail\nf 1 2 4\n"
                 "g head part\nusemtl\nf 3 2 1\n",
                 mesh, &warnings));
    REQUIRE(mesh.groupNames == std::vector<std::string>{"", "head part", "tail"});
    REQUIRE(mesh.faceGroup == std::vector<int>{0, 1, 2, 1});
    REQUIRE(mesh.materialNames == std::vector<std::string>{"skin"});
    REQUIRE(mesh.faceMaterial == std::vector<int>{-1, 0, 0, -1});
    REQUIRE(mesh.materialLibraries == std::vector<std::string>{"shop.mtl"});
    REQUIRE(mesh.texcoords.cols() == 3);
    REQUIRE(mesh.texcoords.row(0) == Eigen::RowVector3d(0, 0, 0.5));
    REQUIRE(mesh.texcoords.row(2) == Eigen::RowVector3d(0.25, 0, 0));
    REQUIRE(mesh.cornerTexcoord == std::vector<int>{0, 1, 2, 0, 1, 2, -1, -1, -1, -1, -1, -1});
    REQUIRE(anyContains(warnings, "no folder to look in"));

    std::string written;
    REQUIRE(sculpt::io::serializeObj(withoutSource(mesh), mesh.positions, written));
    REQUIRE(written.find("mtllib shop.mtl\n") != std::string::npos);
    REQUIRE(written.find("\ng head part\nusemtl skin\nf 2/1/2 4/2/4 3/3/3\ng tail\nf 1//1 2//2 4//4\n"
                         "g head part\nusemtl\nf 3//3 2//2 1//1\n") != std::string::npos);
    REQUIRE(written.find("\nvt 0 0 0.5\nvt 1 0 0\nvt 0.25 0 0\n") != std::string::npos);
    ObjMesh reread;
    REQUIRE(loadText(written, reread));
    requireSameSurface(mesh, reread);
}

TEST_CASE("obj: relative indices and forward references resolve as the OBJ spec says") {
    ObjMesh mesh;
    REQUIRE(sculpt::io::loadObj(kDataDir + "/valid_relative.obj", mesh));
    REQUIRE(mesh.vertexCount() == 4);
    REQUIRE(mesh.cornerVertex == std::vector<int>{0, 1, 2, 0, 2, 3, 0, 1, 3});
}

TEST_CASE("obj: a closed box of quads with a roof loads, with CRLF line ends and face comments") {
    ObjMesh mesh;
    std::vector<std::string> warnings;
    const Status status = sculpt::io::loadObj(kDataDir + "/valid_polygons.obj", mesh, &warnings);
    INFO(status.message);
    REQUIRE(status);
    REQUIRE(mesh.vertexCount() == 9);
    REQUIRE(mesh.faceCount() == 9);
    REQUIRE(mesh.triangles.rows() == 5 * 2 + 4);
    REQUIRE(mesh.groupNames == std::vector<std::string>{"", "box", "roof"});
    REQUIRE(mesh.materialNames == std::vector<std::string>{"red", "blue"});
    REQUIRE(anyContains(warnings, "mtllib 'cube.mtl' not loaded"));
    // Closed: every directed edge has its opposite.
    std::vector<std::pair<int, int>> edges;
    for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t)
        for (int k = 0; k < 3; ++k) edges.emplace_back(mesh.triangles(t, k), mesh.triangles(t, (k + 1) % 3));
    for (const auto& edge : edges)
        REQUIRE(std::count(edges.begin(), edges.end(), std::make_pair(edge.second, edge.first)) == 1);
}

TEST_CASE("obj: every malformed file is an error naming the file and line, and out is untouched") {
    struct Case {
        const char* file;
        int line;  // 0 = the message names the file only
        const char* fragment;
    };
    const Case cases[] = {
        {"zero_index.obj", 8, "face index 0"},
        {"out_of_range.obj", 9, "face index 7 is out of range (file has 5 vertices)"},
        {"negative_out_of_range.obj", 7, "relative face index -9"},
        {"bad_index.obj", 6, "bad face corner 'x'"},
        {"fractional_index.obj", 6, "bad face corner '3.5'"},
        {"huge_index.obj", 6, "out of range (file has 5 vertices)"},
        {"two_corners.obj", 7, "at least 3 corners (found 2)"},
        {"too_many_slashes.obj", 8, "more than two '/'"},
        {"nan.obj", 2, "'nan' in a 'v' line is not a finite decimal number"},
        {"inf.obj", 3, "'-inf' in a 'v' line is not a finite"},
        {"huge.obj", 2, "'1e999' in a 'v' line is out of the range of a double"},
        {"junk_number.obj", 2, "'1.0abc'"},
        {"hex_number.obj", 2, "'0x10'"},
        {"missing_coordinate.obj", 2, "needs x y z (found 2 numbers)"},
        {"vt_nan.obj", 7, "'nan' in a 'vt' line"},
        {"vn_junk.obj", 7, "'zero' in a 'vn' line"},
        {"texcoord_out_of_range.obj", 8, "texture coordinate index 3 is out of range (file has 2 texture coordinates)"},
        {"normal_out_of_range.obj", 7, "normal index 2 is out of range (file has 1 normals)"},
        {"utf16.obj", 1, "UTF-16"},
        {"nul_byte.obj", 3, "NUL byte"},
        {"binary_junk.obj", 4, "control byte 0x01"},
        {"empty.obj", 0, "the file is empty"},
        {"no_vertices.obj", 0, "no vertices"},
        {"no_faces.obj", 0, "no faces"},
    };
    for (const Case& c : cases) {
        INFO(c.file);
        ObjMesh mesh = sentinelMesh();
        std::vector<std::string> warnings;
        const Status status = sculpt::io::loadObj(kDataDir + "/" + c.file, mesh, &warnings);
        INFO(status.message);
        REQUIRE_FALSE(status);
        const std::string where = std::string(c.file) + (c.line > 0 ? ":" + std::to_string(c.line) + ": " : ": ");
        REQUIRE(status.message.find(where) != std::string::npos);
        REQUIRE(status.message.find(c.fragment) != std::string::npos);
        requireSentinel(mesh);
    }
}

TEST_CASE("obj: a missing or unreadable file is an error naming it") {
    ObjMesh mesh = sentinelMesh();
    Status status = sculpt::io::loadObj(kDataDir + "/does_not_exist.obj", mesh);
    REQUIRE_FALSE(status);
    REQUIRE(status.message.find("does_not_exist.obj") != std::string::npos);
    REQUIRE(status.message.find("No such file") != std::string::npos);
    status = sculpt::io::loadObj(kDataDir, mesh);
    REQUIRE_FALSE(status);
    REQUIRE(status.message.find("folder") != std::string::npos);
    requireSentinel(mesh);
}

TEST_CASE("obj: line, point and unknown statements are ignored with a warning") {
    ObjMesh mesh;
    std::vector<std::string> warnings;
    REQUIRE(
        loadText("v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2 99\np -7\nt crease 2/0/0 1 2\nvw 0 -1 0.5\n"
                 "curv 0 1 1 2\ns 1\nf 1 2 3\n",
                 mesh, &warnings));
    REQUIRE(mesh.faceCount() == 1);
    REQUIRE(anyContains(warnings, "2 line/point element(s) not shown, kept in the file (first on line 4)"));
    REQUIRE(anyContains(warnings, "3 statement(s) the sculptor does not use, kept in the file (first on line 6: 't')"));
}

TEST_CASE("obj: a UTF-8 byte order mark does not hide the first line") {
    ObjMesh mesh;
    REQUIRE(loadText("\xEF\xBB\xBFv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", mesh));
    REQUIRE(mesh.vertexCount() == 3);
}

TEST_CASE("obj: faces with more than 255 corners load whole (tinyobjloader counts corners in a byte)") {
    std::string text;
    for (int i = 0; i < 300; ++i) text += "v " + std::to_string(i) + " " + std::to_string(i % 7) + " 0\n";
    text += "f";
    for (int i = 1; i <= 256; ++i) text += " " + std::to_string(i);
    text += "\nf 1 2 3\n";
    ObjMesh mesh;
    std::vector<std::string> warnings;
    const Status status = loadText(text, mesh, &warnings);
    INFO(status.message);
    REQUIRE(status);
    REQUIRE(mesh.faceStart == std::vector<int>{0, 256, 259});
    REQUIRE(mesh.triangleFace.size() == 254 + 1);
    // The zigzag crosses itself: drawn as a fan, and said so.
    REQUIRE(anyContains(warnings, "1 face(s) could not be triangulated exactly"));
    std::string written;
    REQUIRE(sculpt::io::serializeObj(withoutSource(mesh), mesh.positions, written));
    ObjMesh reread;
    REQUIRE(loadText(written, reread));
    requireSameSurface(mesh, reread);
}

TEST_CASE("obj: hostile mtllib paths are never opened and give a warning") {
    TempFolder outer;
    REQUIRE(::mkdir(outer.file("models").c_str(), 0755) == 0);
    const std::string folder = outer.file("models");
    // A real, valid .mtl one folder up: if the reader followed '..' it would load without complaint.
    writeBytes(outer.file("secret.mtl"), "newmtl red\nKd 1 0 0\n");
    REQUIRE(::mkfifo((folder + "/pipe.mtl").c_str(), 0644) == 0);  // opening it for reading would block
    const std::string geometry = "v 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl red\nf 1 2 3\n";
    struct Case {
        std::string mtllib;
        const char* fragment;
    };
    const Case cases[] = {
        {"../secret.mtl", "refused"},
        {"../../etc/passwd", "refused"},
        {"/dev/zero", "refused"},
        {outer.file("secret.mtl"), "refused"},
        {"..", "refused"},
        // tinyobjloader treats '\\' as an escape and asks for "sub....secret.mtl": harmless, not found.
        {"sub\\..\\..\\secret.mtl", "not loaded (No such file"},
        {"pipe.mtl", "not a regular file"},
        {"missing.mtl", "No such file"},
    };
    for (const Case& c : cases) {
        INFO(c.mtllib);
        writeBytes(folder + "/scene.obj", "mtllib " + c.mtllib + "\n" + geometry);
        ObjMesh mesh;
        std::vector<std::string> warnings;
        REQUIRE(sculpt::io::loadObj(folder + "/scene.obj", mesh, &warnings));
        for (const std::string& w : warnings) UNSCOPED_INFO(w);
        REQUIRE(anyContains(warnings, c.fragment));
        REQUIRE(mesh.materialNames == std::vector<std::string>{"red"});
    }
    // A device named by a plain name in the OBJ's folder is not a regular file either.
    ObjMesh mesh;
    std::vector<std::string> warnings;
    REQUIRE(sculpt::io::loadObjFromText("mtllib zero\n" + geometry, "scene.obj", "/dev", mesh, &warnings));
    REQUIRE(anyContains(warnings, "mtllib 'zero' not loaded (not a regular file)"));
}

TEST_CASE("obj: a .mtl next to the OBJ is loaded without warnings") {
    TempFolder folder;
    writeBytes(folder.file("shop.mtl"), "newmtl red\nKd 1 0 0\n");
    writeBytes(folder.file("scene.obj"), "mtllib shop.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl red\nf 1 2 3\n");
    ObjMesh mesh;
    std::vector<std::string> warnings;
    REQUIRE(sculpt::io::loadObj(folder.file("scene.obj"), mesh, &warnings));
    INFO((warnings.empty() ? std::string() : warnings[0]));
    REQUIRE(warnings.empty());
    REQUIRE(mesh.materialLibraries == std::vector<std::string>{"shop.mtl"});
}

TEST_CASE("obj: a failed save leaves the existing file byte-identical") {
    TempFolder folder;
    ObjMesh mesh;
    REQUIRE(loadText("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", mesh));
    const std::string target = folder.file("keep.obj");
    const std::string original = "# the user's precious file\nv 0 0 0\n";
    writeBytes(target, original);

    SECTION("non-finite position") {
        Positions bad = mesh.positions;
        bad(1, 1) = std::nan("");
        const Status status = sculpt::io::saveObj(target, mesh, bad);
        REQUIRE_FALSE(status);
        REQUIRE(status.message.find("vertex 2 has a non-finite position") != std::string::npos);
    }
    SECTION("row count mismatch") {
        const Status status = sculpt::io::saveObj(target, mesh, Positions::Zero(2, 3));
        REQUIRE_FALSE(status);
        REQUIRE(status.message.find("2 positions for a mesh with 3 vertices") != std::string::npos);
    }
    SECTION("target folder not writable") {
        REQUIRE(::chmod(folder.path.c_str(), 0555) == 0);
        const Status status = sculpt::io::saveObj(target, mesh, mesh.positions);
        ::chmod(folder.path.c_str(), 0755);
        if (::geteuid() == 0) {
            // root ignores permission bits: the save succeeds, so only the other cases apply here.
            WARN("running as root: permission denial cannot be tested");
            writeBytes(target, original);
        } else {
            REQUIRE_FALSE(status);
            REQUIRE(status.message.find("Permission denied") != std::string::npos);
        }
    }
    SECTION("path is a folder") {
        REQUIRE(::mkdir(folder.file("sub.obj").c_str(), 0755) == 0);
        const Status status = sculpt::io::saveObj(folder.file("sub.obj"), mesh, mesh.positions);
        REQUIRE_FALSE(status);
        REQUIRE(status.message.find("sub.obj") != std::string::npos);
    }
    SECTION("parent is a file") {
        const Status status = sculpt::io::saveObj(target + "/inner.obj", mesh, mesh.positions);
        REQUIRE_FALSE(status);
        REQUIRE(status.message.find("Not a directory") != std::string::npos);
    }
    REQUIRE(readBytes(target) == original);
    // No temporary file is left behind.
    const std::string listing = folder.file("listing.txt");
    std::system(("ls -A '" + folder.path + "' > '" + listing + "'").c_str());
    const std::string names = readBytes(listing);
    REQUIRE(names.find(".tmp") == std::string::npos);
}

TEST_CASE("obj: checkObjMesh and serializeObj refuse inconsistent meshes") {
    ObjMesh mesh;
    REQUIRE(loadText("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", mesh));
    std::string text = "unchanged";
    ObjMesh broken = mesh;
    broken.cornerVertex[1] = 7;
    REQUIRE_FALSE(sculpt::io::serializeObj(broken, broken.positions, text));
    broken = mesh;
    broken.groupNames[0] = "not default";
    REQUIRE_FALSE(sculpt::io::serializeObj(broken, broken.positions, text));
    broken = mesh;
    broken.materialNames = {"two words"};
    broken.faceMaterial = {0};
    REQUIRE_FALSE(sculpt::io::serializeObj(broken, broken.positions, text));
    broken = mesh;
    broken.groupNames.push_back("line\nbreak");
    broken.faceGroup = {1};
    REQUIRE_FALSE(sculpt::io::serializeObj(broken, broken.positions, text));
    REQUIRE(text == "unchanged");
}

TEST_CASE("obj: parseObjNumber accepts exactly the decimal grammar") {
    const char* good[] = {"0", "-0", "+1", "1.", ".5", "-.5", "1e5", "1E-5", "1.5e+300", "0001"};
    const char* bad[] = {"",         "-",     "+",   ".",     "e5",  "1e",  "1e+",   "nan",    "-inf",
                         "infinity", "0x1p3", "1,5", "1.2.3", "--1", "+-1", "1e999", "-1e999", "1e-400"};
    double value = 0.0;
    for (const char* s : good) {
        INFO(s);
        REQUIRE(sculpt::io::parseObjNumber(s, s + std::strlen(s), value));
    }
    for (const char* s : bad) {
        INFO(s);
        REQUIRE_FALSE(sculpt::io::parseObjNumber(s, s + std::strlen(s), value));
    }
}

// The loader parses once, with its own reader; tinyobjloader must read every file the same way
// (crossCheckObjWithTinyobj): the files shipped and handed over, the fuzz corpus and its regressions, and
// random meshes with groups, materials and texture coordinates, written plainly and then roughened with the
// statements and spellings the reader mirrors tinyobjloader on.
TEST_CASE("obj: tinyobjloader reads every file as the loader's reader does") {
    std::vector<std::string> folders = {std::string(SCULPT_SOURCE_DIR) + "/assets", std::string(SCULPT_SOURCE_DIR) + "/assets/examples",
                                        kDataDir, kDataDir + "/fuzz_regressions", std::string(SCULPT_SOURCE_DIR) + "/tests/fuzz/corpus",
                                        std::string(SCULPT_SOURCE_DIR) + "/../shared/cases"};
    int files = 0;
    for (const std::string& folder : folders) {
        std::error_code ec;
        for (const auto& entry : std::filesystem::recursive_directory_iterator(folder, ec)) {
            if (!entry.is_regular_file() || entry.file_size() > (8u << 20)) continue;
            const std::string path = entry.path().string();
            if (folder.find("/cases") != std::string::npos && entry.path().extension() != ".obj") continue;
            const Status agreed = sculpt::io::crossCheckObjWithTinyobj(readBytes(path), path);
            INFO(path << ": " << agreed.message);
            CHECK(agreed);
            ++files;
        }
    }
    CHECK(files >= 40);
    const std::vector<std::string> extras = {"usemtl skin\n", "usemtl\n", "g  head   part \n", "o thing\n", "# note\n", "s 1\n",
                                             "mtllib shop.mtl\n", "g\n", "l 1 2\n", "vp 0.5\n", "\n", "  \t\n"};
    for (int size : {1, 5, 40, 300}) {
        std::mt19937_64 random(77 + size);
        const ObjMesh mesh = randomMesh(random, size + 2, size);
        std::string written;
        REQUIRE(sculpt::io::serializeObj(mesh, mesh.positions, written));
        for (int variant = 0; variant < 20; ++variant) {
            // Insert extra statements between lines, and CR LF line ends in some variants.
            std::string text;
            std::istringstream lines(written);
            std::string line;
            while (std::getline(lines, line)) {
                if (std::uniform_int_distribution<int>(0, 4)(random) == 0)
                    text += extras[static_cast<size_t>(std::uniform_int_distribution<int>(0, static_cast<int>(extras.size()) - 1)(random))];
                text += line + (variant % 3 == 0 ? "\r\n" : "\n");
            }
            const Status agreed = sculpt::io::crossCheckObjWithTinyobj(text, "random.obj");
            INFO("size " << size << ", variant " << variant << ": " << agreed.message);
            CHECK(agreed);
        }
    }
}

TEST_CASE("obj: a material no .mtl defines is named in a warning, as tinyobjloader names it") {
    TempFolder folder("obj_usemtl");
    writeBytes(folder.file("shop.mtl"), "newmtl skin\nKd 1 0.5 0.5\n");
    const std::string geometry = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    for (const std::string& text : {"mtllib shop.mtl\nusemtl skin\n" + geometry, "usemtl skin\nmtllib shop.mtl\n" + geometry,
                                    "mtllib shop.mtl\nusemtl bone\n" + geometry, "mtllib other.mtl shop.mtl\nusemtl skin\n" + geometry}) {
        ObjMesh mesh;
        std::vector<std::string> warnings;
        REQUIRE(sculpt::io::loadObjFromText(text, "scene.obj", folder.path, mesh, &warnings));
        INFO(text);
        // Before the library is read, or not in it: said. A library that does not open: said, and the next one read.
        const bool early = text.rfind("usemtl skin\nmtllib", 0) == 0;
        CHECK(anyContains(warnings, "material [ 'skin' ] not found in .mtl") == early);
        CHECK(anyContains(warnings, "material [ 'bone' ] not found in .mtl") == (text.find("usemtl bone") != std::string::npos));
        CHECK(anyContains(warnings, "mtllib 'other.mtl' not loaded") == (text.find("other.mtl") != std::string::npos));
        CHECK(mesh.faceMaterial.size() == 1);
    }
}

// Big sections are formatted in parallel chunks: every group and material change, at chunk starts too, must
// come out as one serial writer would write it, which the reader then reads back exactly.
TEST_CASE("obj: a big mesh written from its arrays reads back exactly, groups and materials included") {
    for (int faces : {40000, 90001}) {
        std::mt19937_64 random(static_cast<unsigned>(faces));
        ObjMesh mesh = randomMesh(random, faces / 2 + 3, faces);
        mesh.groupNames = {"", "body", "left arm"};
        mesh.materialNames = {"skin", "cloth"};
        // Runs of 1 to 3000 faces: groups 0, 1, 2, 0, 1, ... and materials none, skin, cloth, none, ...
        int group = 0, material = -1, left = 1;
        for (int f = 0; f < faces; ++f) {
            if (--left == 0) {
                left = std::uniform_int_distribution<int>(1, 3000)(random);
                if (f > 0) group = (group + 1) % 3;
                if (f > 0 && random() % 2 == 0) material = material == 1 ? -1 : material + 1;
            }
            mesh.faceGroup[static_cast<size_t>(f)] = group;
            mesh.faceMaterial[static_cast<size_t>(f)] = material;
        }
        requireRoundTrip(mesh);
    }
}

// The one parse reports progress and stops on Cancel (the window's progress popup): a load of a few MB ends at
// 1, and a cancel asked before it starts stops it in the scan, with out untouched.
TEST_CASE("obj: a big load reports progress and stops on cancel") {
    std::mt19937_64 random(9);
    const ObjMesh mesh = randomMesh(random, 60000, 60000);
    std::string written;
    REQUIRE(sculpt::io::serializeObj(mesh, mesh.positions, written));
    REQUIRE(written.size() > (3u << 20));
    sculpt::io::ObjLoadProgress watched;
    ObjMesh loaded;
    REQUIRE(sculpt::io::loadObjFromText(written, "big.obj", "", loaded, nullptr, &watched));
    CHECK(watched.fraction.load() == 1.0f);
    CHECK(loaded.faceCount() == 60000);
    sculpt::io::ObjLoadProgress cancelled;
    cancelled.cancel = true;
    ObjMesh untouched = sentinelMesh();
    const Status status = sculpt::io::loadObjFromText(written, "big.obj", "", untouched, nullptr, &cancelled);
    CHECK_FALSE(status);
    CHECK(status.message == "big.obj: loading cancelled");
    CHECK(cancelled.fraction.load() < 0.5f);  // stopped in the scan, after its first MiB
    requireSentinel(untouched);
}
