// Mesh formats on real files: CGAL's data, the fuzz corpus and its regressions, the reader run in a child process
// (isolated_call.h), and binary STL headers that lie. Round trips per format: mesh_formats_test.cpp.
// PLY, STL and glTF in and out (io/mesh_file.h): round trips of generated meshes of many sizes in every
// encoding, Debian's assimp-testmodels files, bad input, and saves that fail without touching the file.
#include <algorithm>
#include <chrono>
#include <csignal>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <set>

#include <catch2/catch.hpp>
#include <unistd.h>

#include "core/deform/vertex_normals.h"
#include "io/isolated_call.h"
#include "io/mesh_file.h"
#include "io/obj_refine.h"
#include "../fuzz/fuzz_checks.h"
#include "io_test_support.h"
#include "mesh_formats_support.h"

namespace sculpt::io {

using namespace formats_test;

// CGAL's data (Debian's libcgal-demo ships it as data.tar.gz): meshes and point clouds written by CGAL, with
// double-precision PLY properties, face colours, edges, and a binary STL of a scanned pig.
TEST_CASE("mesh formats: the meshes and point clouds of CGAL's data", "[io][formats]") {
    const std::string archive = "/usr/share/doc/libcgal-dev/data.tar.gz";
    if (!std::filesystem::exists(archive)) FAIL("libcgal-demo is not installed (.ci/install-deps installs it)");
    TempFolder folder("formats_cgal");
    REQUIRE(std::system(("tar -xzf " + archive + " -C '" + folder.path + "' data/meshes data/points_3").c_str()) == 0);
    const std::string meshes = folder.file("data/meshes/");
    struct Expect {
        std::string file;
        int vertices, triangles;  // -1: refused
    };
    for (const Expect& e : std::vector<Expect>{{"sphere.ply", 162, 320}, {"sphere.stl", 162, 320}, {"pig.stl", 8642, 16848},
                                               {"colored_tetra.ply", 4, 4}, {"b9.ply", -1, -1}}) {
        INFO(e.file);
        ObjMesh mesh;
        std::vector<std::string> warnings;
        const Status s = loadMesh(meshes + e.file, mesh, &warnings);
        INFO(s.message);
        if (e.vertices < 0) {
            CHECK_FALSE(s.ok);
            CHECK(s.message.find("a point cloud is not a surface") != std::string::npos);
            continue;
        }
        REQUIRE(s.ok);
        CHECK(mesh.vertexCount() == e.vertices);
        CHECK(mesh.triangles.rows() == e.triangles);
        for (const char* out : {"r.ply", "r.stl", "r.glb"}) {
            REQUIRE(saveMesh(folder.file(out), mesh, mesh.positions).ok);
            ObjMesh back;
            REQUIRE(loadMesh(folder.file(out), back).ok);
            CHECK(back.triangles.rows() == mesh.triangles.rows());
            if (std::string(out) != "r.stl") CHECK(back.positions == asFloat(mesh.positions));
        }
    }
    // What CGAL stores beyond positions and faces is named, not dropped in silence.
    ObjMesh tetra;
    std::vector<std::string> warnings;
    REQUIRE(loadMesh(meshes + "colored_tetra.ply", tetra, &warnings).ok);
    CHECK(tetra.vertexColors.rows() == 4);
    CHECK(tetra.vertexNormals.rows() == 4);
    const auto said = [&warnings](const std::string& what) {
        return std::any_of(warnings.begin(), warnings.end(), [&](const std::string& w) { return w.find(what) != std::string::npos; });
    };
    CHECK(said("PLY element 'edge' (6) is not kept"));
    CHECK(said("vertex property 'id' is not kept"));
    CHECK(said("face property 'label' is not kept"));
    CHECK(said("positions are stored as double and read in single precision"));
    // The same sphere in PLY and STL: the same surface (STL welded in the order of first use).
    ObjMesh ply, stl;
    REQUIRE(loadMesh(meshes + "sphere.ply", ply).ok);
    REQUIRE(loadMesh(meshes + "sphere.stl", stl).ok);
    std::set<std::array<double, 3>> a, b;
    for (Eigen::Index v = 0; v < ply.positions.rows(); ++v) a.insert({ply.positions(v, 0), ply.positions(v, 1), ply.positions(v, 2)});
    for (Eigen::Index v = 0; v < stl.positions.rows(); ++v) b.insert({stl.positions(v, 0), stl.positions(v, 1), stl.positions(v, 2)});
    CHECK(a.size() == 162);
    CHECK(b.size() == 162);
    CHECK(a == b);
    // Point clouds (no faces) are refused as such, whatever their properties.
    int clouds = 0;
    for (const auto& entry : std::filesystem::directory_iterator(folder.file("data/points_3"))) {
        if (entry.path().extension() != ".ply") continue;
        ObjMesh cloud;
        const Status s = loadMesh(entry.path().string(), cloud);
        INFO(entry.path() << ": " << s.message);
        CHECK_FALSE(s.ok);
        CHECK(s.message.find("point cloud is not a surface") != std::string::npos);
        ++clouds;
    }
    CHECK(clouds >= 5);
}

// The fuzz seed corpus (tests/fuzz/corpus_mesh) and what the fuzzer found (tests/io/data/fuzz_regressions_mesh,
// filled by tests/fuzz/run_fuzz.sh), read as mesh_fuzz reads them: each loads into a consistent mesh or fails
// with a message naming the file, and what loads survives mesh_fuzz's save and load in every encoding.
TEST_CASE("mesh formats: fuzz corpus and regressions load cleanly or fail with a message", "[io][formats]") {
    int files = 0;
    for (const char* folder : {"/tests/fuzz/corpus_mesh", "/tests/fuzz/corpus_gltf", "/tests/io/data/fuzz_regressions_mesh"}) {
        const std::string dir = std::string(SCULPT_SOURCE_DIR) + folder;
        if (!std::filesystem::exists(dir)) continue;
        for (const auto& entry : std::filesystem::directory_iterator(dir)) {
            const std::string bytes = test::readBytes(entry.path().string());
            std::string name;
            const MeshFormat format = fuzz::formatOfBytes(bytes, name);
            ObjMesh mesh;
            const Status s = loadMeshFromMemory(bytes, format, name, mesh);
            INFO(entry.path() << ": " << s.message);
            if (s.ok) {
                CHECK(checkObjMesh(mesh).ok);
                CHECK(fuzz::roundTripBreak(mesh) == "");
            } else {
                CHECK(s.message.rfind(name + ": ", 0) == 0);
            }
            ++files;
        }
    }
    CHECK(files >= 8);
}

}  // namespace sculpt::io

namespace sculpt::io {

// A reader that crashes or never returns costs an error message, not the program (isolated_call.h); assimp loops
// forever on this malformed PLY (found by mesh_fuzz), which passes every check of ours.
TEST_CASE("mesh formats: a reader that crashes or hangs is an error, not a crash, a cancelled load stops", "[io][formats]") {
    std::string bytes;
    const Status crashed = runIsolated("the test reader", [](IsolatedChannel&) { std::raise(SIGSEGV); }, 10.0, nullptr, bytes);
    CHECK_FALSE(crashed.ok);
    CHECK(crashed.message.rfind("the test reader crashed on this file (Segmentation fault)", 0) == 0);
    const Status hung = runIsolated("the test reader", [](IsolatedChannel&) { for (;;) ::pause(); }, 0.5, nullptr, bytes);
    CHECK_FALSE(hung.ok);
    CHECK(hung.message == "the test reader did not finish in 1 s (a malformed file?)");
    const Status answered = runIsolated("the test reader", [](IsolatedChannel& channel) {
        channel.progress(0.5f);
        channel.result(std::string(3 << 20, 'x'));  // larger than a pipe's buffer
    }, 10.0, nullptr, bytes);
    CHECK(answered.ok);
    CHECK(bytes == std::string(3 << 20, 'x'));

    const std::string hang = test::readBytes(std::string(SCULPT_SOURCE_DIR) +
                                             "/tests/io/data/fuzz_regressions_mesh/slow-unit-98db8f8c606e5ce89eab219967a25fa670965642");
    ObjMesh untouched;
    const auto start = std::chrono::steady_clock::now();
    const Status s = loadMeshFromMemory(hang, MeshFormat::Ply, "evil.ply", untouched);
    INFO(s.message);
    CHECK_FALSE(s.ok);
    CHECK(s.message.rfind("evil.ply: the PLY reader (assimp) did not finish in", 0) == 0);
    CHECK(std::chrono::steady_clock::now() - start < std::chrono::seconds(30));
    CHECK(untouched.positions.rows() == 0);
    // The same header made whole loads.
    TempFolder folder("formats_cancel");
    std::mt19937 rng(8);
    const ObjMesh mesh = randomSphere(rng, 30, 30, false, true, false, false);
    REQUIRE(saveMesh(folder.file("c.ply"), mesh, mesh.positions).ok);
    ObjLoadProgress progress;
    progress.cancel = true;
    ObjMesh out;
    const Status cancelled = loadMesh(folder.file("c.ply"), out, nullptr, &progress);
    CHECK_FALSE(cancelled.ok);
    CHECK(cancelled.message.size() >= 9);
    CHECK(cancelled.message.substr(cancelled.message.size() - 9) == "cancelled");
    CHECK(out.positions.rows() == 0);
    ObjLoadProgress watched;
    REQUIRE(loadMesh(folder.file("c.ply"), out, nullptr, &watched).ok);
    CHECK(watched.fraction.load() == 1.0f);
    CHECK(out.positions == mesh.positions);
}

// The reader's result is copied out of its memory (process_vm_readv), or sent through the pipe where the system
// does not allow that: both give the same bytes, for any number and size of pieces, and the same mesh.
// Trials first..last of random pieces sent back by a reader child, from its memory and through the pipe.
static void checkPiecesTransfer(unsigned seed, int first, int last) {
    std::mt19937 rng(seed);
    for (int trial = first; trial <= last; ++trial) {
        // Pieces of 0 bytes to 2 MB, up to 3000 of them (more than one process_vm_readv takes at once).
        const int count = std::uniform_int_distribution<int>(1, trial % 3 == 0 ? 3000 : 40)(rng);
        std::vector<std::string> pieces(static_cast<size_t>(count));
        std::string expected;
        for (std::string& piece : pieces) {
            const int size = std::uniform_int_distribution<int>(0, 3)(rng) == 0 ? std::uniform_int_distribution<int>(0, 2 << 20)(rng)
                                                                                : std::uniform_int_distribution<int>(0, 40)(rng);
            piece.resize(static_cast<size_t>(size));
            for (size_t c = 0; c < piece.size(); c += 4) {  // four random bytes a draw
                const uint32_t word = rng();
                std::memcpy(&piece[c], &word, std::min<size_t>(4, piece.size() - c));
            }
            expected += piece;
        }
        for (bool throughPipe : {false, true}) {
            setIsolatedResultsThroughPipe(throughPipe);
            std::string bytes;
            const Status s = runIsolated("the test reader", [&](IsolatedChannel& channel) {
                std::vector<IsolatedPiece> list;
                for (const std::string& piece : pieces) list.push_back({piece.data(), piece.size()});
                channel.result(list);
            }, 30.0, nullptr, bytes);
            setIsolatedResultsThroughPipe(false);
            INFO("trial " << trial << ", " << count << " pieces, through the pipe " << throughPipe << ": " << s.message);
            REQUIRE(s.ok);
            CHECK(bytes == expected);
        }
    }
}

TEST_CASE("mesh formats: a reader's result is the same read from its memory or sent through the pipe, part 1 of 3", "[io][formats]") {
    checkPiecesTransfer(31, 0, 5);
}
TEST_CASE("mesh formats: a reader's result is the same read from its memory or sent through the pipe, part 2 of 3", "[io][formats]") {
    checkPiecesTransfer(32, 6, 11);
}
TEST_CASE("mesh formats: a reader's result is the same read from its memory or sent through the pipe, part 3 of 3", "[io][formats]") {
    std::mt19937 rng(33);
    TempFolder folder("formats_transfer");
    for (int trial = 0; trial < 4; ++trial) {
        const ObjMesh mesh = randomSphere(rng, 20 + 30 * trial, 25 + 20 * trial, trial % 2 == 1, trial != 1, trial != 2, trial != 3);
        const std::string path = folder.file("t" + std::to_string(trial) + ".ply");
        REQUIRE(saveMesh(path, mesh, mesh.positions).ok);
        ObjMesh direct, piped;
        REQUIRE(loadMesh(path, direct).ok);
        setIsolatedResultsThroughPipe(true);
        const Status s = loadMesh(path, piped);
        setIsolatedResultsThroughPipe(false);
        REQUIRE(s.ok);
        CHECK(direct.positions == mesh.positions);
        CHECK(piped.positions == direct.positions);
        CHECK(piped.faceStart == direct.faceStart);
        CHECK(piped.cornerVertex == direct.cornerVertex);
        CHECK(piped.cornerTexcoord == direct.cornerTexcoord);
        CHECK(piped.cornerNormal == direct.cornerNormal);
        CHECK(piped.texcoords == direct.texcoords);
        CHECK(piped.faceGroup == direct.faceGroup);
        CHECK(piped.faceMaterial == direct.faceMaterial);
        CHECK(piped.groupNames == direct.groupNames);
        CHECK(piped.vertexColors == direct.vertexColors);
        CHECK(piped.vertexNormals == direct.vertexNormals);
        CHECK(piped.triangles == direct.triangles);
        CHECK(direct.vertexColors.rows() == (trial != 1 ? mesh.positions.rows() : 0));
        CHECK(direct.texcoords.rows() == (trial != 3 ? mesh.positions.rows() : 0));
    }
}

}  // namespace sculpt::io

namespace sculpt::io {
namespace {

// A binary STL of the mesh's triangles written here, record by record (an independent writer): header (80
// bytes, as given), count, then 50 bytes a facet. extra: facets appended after the mesh's.
std::string binaryStl(const ObjMesh& mesh, const std::string& header, uint32_t declared,
                      const std::vector<std::array<Eigen::Vector3f, 3>>& extra = {}) {
    std::string out = header.substr(0, 80);
    out.resize(80, ' ');
    out.append(reinterpret_cast<const char*>(&declared), 4);
    const auto facet = [&out](const std::array<Eigen::Vector3f, 3>& corners) {
        const float normal[3] = {0, 0, 0};
        out.append(reinterpret_cast<const char*>(normal), 12);
        for (const Eigen::Vector3f& c : corners) out.append(reinterpret_cast<const char*>(c.data()), 12);
        out.append(2, '\0');
    };
    for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
        std::array<Eigen::Vector3f, 3> corners;
        for (int k = 0; k < 3; ++k) corners[static_cast<size_t>(k)] = mesh.positions.row(mesh.triangles(t, k)).transpose().cast<float>();
        facet(corners);
    }
    for (const auto& corners : extra) facet(corners);
    return out;
}

}  // namespace

// Binary or ASCII is decided by the structure (size against count, then the ASCII grammar), not by a header
// that starts with "solid": a count that disagrees with the size reads what the size holds, with a warning.
TEST_CASE("mesh formats: a binary STL whose header starts with solid, or whose count is wrong, reads every facet it holds",
          "[io][formats]") {
    TempFolder folder("stl_structure");
    std::mt19937 rng(31);
    int cases = 0;
    for (int rings = 3; rings <= 12; rings += 3) {
        const ObjMesh mesh = randomSphere(rng, rings, rings + 2, false, false, false, false);
        const auto facets = static_cast<uint32_t>(mesh.triangles.rows());
        ObjMesh reference;
        const std::string plain = folder.file("plain.stl");
        std::ofstream(plain, std::ios::binary) << binaryStl(mesh, "binary", facets);
        REQUIRE(loadMesh(plain, reference).ok);
        REQUIRE(reference.triangles.rows() == facets);
        struct Variant {
            std::string header;
            uint32_t declared;
            size_t trailing;
            bool warned;
        };
        for (const Variant& v : std::vector<Variant>{{"solid exported by a CAD program", facets, 0, false},
                                                     {"solid part", 0, 0, true},
                                                     {"solid", facets / 2, 0, true},
                                                     {"binary", 0, 0, true},
                                                     {"solid x", facets, 17, true},
                                                     {"solid\nfacet", 1, 0, true}}) {
            INFO("rings " << rings << ", header '" << v.header << "', count " << v.declared << ", trailing " << v.trailing);
            std::string bytes = binaryStl(mesh, v.header, v.declared);
            bytes.append(v.trailing, '\x7f');
            const std::string path = folder.file("variant.stl");
            std::ofstream(path, std::ios::binary) << bytes;
            ObjMesh back;
            std::vector<std::string> warnings;
            const Status s = loadMesh(path, back, &warnings);
            INFO(s.message << " " << ::Catch::Detail::stringify(warnings));
            REQUIRE(s.ok);
            CHECK(back.loadedAs.binary);
            CHECK(back.positions == reference.positions);
            CHECK(back.triangles == reference.triangles);
            const bool said = std::any_of(warnings.begin(), warnings.end(), [&](const std::string& w) {
                return w.find("the header declares " + std::to_string(v.declared) + " facet(s) but the file holds " +
                              std::to_string(facets)) != std::string::npos;
            });
            CHECK(said == v.warned);
            ++cases;
        }
        // Cut short of what the count declares: refused, whatever the header says.
        std::string cut = binaryStl(mesh, "solid cut", facets);
        cut.resize(cut.size() - 30);
        ObjMesh none;
        const Status s = loadMeshFromMemory(cut, MeshFormat::Stl, "cut.stl", none);
        CHECK_FALSE(s.ok);
        CHECK(s.message.find("the file ends early") != std::string::npos);
        // ASCII stays ASCII.
        std::string ascii = "solid ascii\n";
        for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
            ascii += " facet normal 0 0 0\n  outer loop\n";
            for (int k = 0; k < 3; ++k) {
                char line[160];
                const Eigen::Vector3f p = mesh.positions.row(mesh.triangles(t, k)).transpose().cast<float>();
                std::snprintf(line, sizeof line, "   vertex %.9g %.9g %.9g\n", p.x(), p.y(), p.z());
                ascii += line;
            }
            ascii += "  endloop\n endfacet\n";
        }
        ascii += "endsolid ascii\n";
        ObjMesh fromText;
        REQUIRE(loadMeshFromMemory(ascii, MeshFormat::Stl, "a.stl", fromText).ok);
        CHECK_FALSE(fromText.loadedAs.binary);
        CHECK(fromText.triangles == reference.triangles);
    }
    CHECK(cases == 4 * 6);
}

}  // namespace sculpt::io
