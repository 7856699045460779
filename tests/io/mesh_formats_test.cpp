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
#include "io_test_support.h"
#include "mesh_formats_support.h"

namespace sculpt::io {
using namespace formats_test;

TEST_CASE("mesh formats: PLY keeps vertex order, polygons, colours, normals and texture coordinates in every encoding",
          "[io][formats]") {
    TempFolder folder("ply_test");
    std::mt19937 rng(1301);
    for (int size = 3; size <= 24; size += 7) {
        for (const bool quads : {false, true}) {
            const ObjMesh mesh = randomSphere(rng, size, size + 1, quads, true, true, true);
            Positions deformed = mesh.positions;
            deformed.topRows(deformed.rows() / 2).array() += 0.25;  // half the vertices moved
            for (const MeshEncoding encoding : {MeshEncoding{MeshFormat::Ply, false, false}, MeshEncoding{MeshFormat::Ply, true, false},
                                                MeshEncoding{MeshFormat::Ply, true, true}}) {
                INFO("size " << size << " quads " << quads << " " << meshEncodingText(encoding));
                const ObjMesh back = roundTrip(folder, "m.ply", mesh, deformed, encoding);
                REQUIRE(back.positions.rows() == mesh.positions.rows());
                // Same order, positions rounded to float.
                if (encoding.binary) {
                    CHECK(back.positions == asFloat(deformed));
                } else {
                    CHECK(largestDifference(back.positions, asFloat(deformed)) <= kAsciiReadTolerance * 2);
                }
                CHECK(facesOf(back) == facesOf(mesh));      // polygons kept as they are
                CHECK(trianglesOf(back) == trianglesOf(mesh));
                REQUIRE(back.vertexColors.rows() == mesh.vertexColors.rows());
                CHECK((back.vertexColors - mesh.vertexColors).cwiseAbs().maxCoeff() <= 0.5f / 255.0f);
                REQUIRE(back.vertexNormals.rows() == mesh.vertexNormals.rows());
                // Vertices next to no moved vertex keep the file's normal; the others get the deformed surface's.
                Positions recomputed;
                core::computeVertexNormals(deformed, mesh.triangles, recomputed);
                const Eigen::Index lastRow = mesh.positions.rows() - 1;  // the far pole: not moved, nor its ring
                CHECK(largestDifference(back.vertexNormals.row(lastRow), mesh.vertexNormals.row(lastRow)) <= (encoding.binary ? 0.0 : kAsciiReadTolerance));
                CHECK((back.vertexNormals.row(0).cast<double>() - recomputed.row(0)).norm() < 1e-6);
                REQUIRE(back.texcoords.rows() == mesh.positions.rows());
                CHECK(largestDifference(back.texcoords.leftCols(2), mesh.texcoords) <= (encoding.binary ? 0.0 : kAsciiReadTolerance));
                CHECK(back.cornerTexcoord == back.cornerVertex);
            }
        }
    }
}

TEST_CASE("mesh formats: a PLY byte order is kept by Save and the big-endian body is the byte-swapped little-endian one",
          "[io][formats]") {
    std::mt19937 rng(77);
    const ObjMesh mesh = randomSphere(rng, 5, 7, true, true, false, false);
    std::string little, big;
    REQUIRE(serializeMesh("x.ply", mesh, mesh.positions, {MeshFormat::Ply, true, false}, little).ok);
    REQUIRE(serializeMesh("x.ply", mesh, mesh.positions, {MeshFormat::Ply, true, true}, big).ok);
    CHECK(big.find("format binary_big_endian 1.0") != std::string::npos);
    CHECK(big.size() == little.size() + std::strlen("big") - std::strlen("little"));
    // Every number of the body is byte-reversed: the first x (float), and the first face's first index (int32
    // after its uchar count).
    const size_t l = little.find("end_header\n") + 11, b = big.find("end_header\n") + 11;
    std::string first = little.substr(l, 4);
    std::reverse(first.begin(), first.end());
    CHECK(big.substr(b, 4) == first);
    const size_t bodyVertices = static_cast<size_t>(mesh.positions.rows()) * (12 + 4);  // x y z + RGBA
    std::string index = little.substr(l + bodyVertices + 1, 4);
    std::reverse(index.begin(), index.end());
    CHECK(big.substr(b + bodyVertices + 1, 4) == index);

    ObjMesh loaded = mesh;
    loaded.loadedAs = {MeshFormat::Ply, true, true};
    MeshEncoding chosen;
    REQUIRE(saveEncodingFor("again.PLY", loaded, chosen).ok);
    CHECK(chosen.bigEndian);
    REQUIRE(saveEncodingFor("other.stl", loaded, chosen).ok);
    CHECK(chosen.format == MeshFormat::Stl);
    CHECK(chosen.binary);
    CHECK_FALSE(saveEncodingFor("other.fbx", loaded, chosen).ok);
}

TEST_CASE("mesh formats: STL is welded on load into the mesh that was written, facet by facet", "[io][formats]") {
    TempFolder folder("stl_test");
    std::mt19937 rng(2024);
    for (int size = 3; size <= 30; size += 9) {
        const ObjMesh mesh = randomSphere(rng, size, size + 2, false, false, false, false);
        Positions deformed = mesh.positions;
        deformed.col(0) *= 1.5;
        for (const bool binary : {false, true}) {
            INFO("size " << size << (binary ? " binary" : " ASCII"));
            const ObjMesh back = roundTrip(folder, "m.stl", mesh, deformed, {MeshFormat::Stl, binary, false});
            // One vertex per distinct position: the same count, numbered in order of first use by the facets.
            REQUIRE(back.positions.rows() == mesh.positions.rows());
            REQUIRE(back.triangles.rows() == mesh.triangles.rows());
            std::vector<int> firstUse;
            std::vector<int> seen(static_cast<size_t>(mesh.positions.rows()), -1);
            for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t)
                for (int k = 0; k < 3; ++k) {
                    const int v = mesh.triangles(t, k);
                    if (seen[static_cast<size_t>(v)] < 0) {
                        seen[static_cast<size_t>(v)] = static_cast<int>(firstUse.size());
                        firstUse.push_back(v);
                    }
                    CHECK(back.triangles(t, k) == seen[static_cast<size_t>(v)]);
                }
            Positions expected(back.positions.rows(), 3);
            for (size_t i = 0; i < firstUse.size(); ++i) expected.row(static_cast<Eigen::Index>(i)) = asFloat(deformed).row(firstUse[i]);
            CHECK(largestDifference(back.positions, expected) <= (binary ? 0.0 : 2 * kAsciiReadTolerance));
        }
    }
}

TEST_CASE("mesh formats: STL corners written as -0 in one facet and 0 in another are one vertex", "[io][formats]") {
    const std::string stl =
        "solid two\n"
        " facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n   vertex 0 1 0\n  endloop\n endfacet\n"
        " facet normal 0 0 1\n  outer loop\n   vertex 1 0 0\n   vertex 1 1 -0\n   vertex -0 1 0\n  endloop\n endfacet\n"
        "endsolid two\n";
    ObjMesh mesh;
    const Status s = loadMeshFromMemory(stl, MeshFormat::Stl, "zero.stl", mesh);
    INFO(s.message);
    REQUIRE(s.ok);
    CHECK(mesh.vertexCount() == 4);
    CHECK(mesh.triangles(1, 0) == 1);
    CHECK(mesh.triangles(1, 2) == 2);
}

TEST_CASE("mesh formats: glTF and GLB keep vertices, triangles, colours, normals, texture coordinates and groups",
          "[io][formats]") {
    TempFolder folder("gltf_test");
    std::mt19937 rng(99);
    for (int size = 3; size <= 20; size += 8) {
        ObjMesh mesh = randomSphere(rng, size, size, false, true, true, true);
        // Two primitives: a second sphere beside the first, its own vertices, its own group.
        ObjMesh second = randomSphere(rng, size + 1, size, false, true, true, true);
        const int offset = static_cast<int>(mesh.positions.rows());
        const int faceOffset = static_cast<int>(mesh.cornerVertex.size());
        Positions both(mesh.positions.rows() + second.positions.rows(), 3);
        both << mesh.positions, (second.positions.array() + 3.0).matrix();
        mesh.positions = both;
        VertexColors colours(both.rows(), 4);
        colours << mesh.vertexColors, second.vertexColors;
        mesh.vertexColors = colours;
        VertexNormals normals(both.rows(), 3);
        normals << mesh.vertexNormals, second.vertexNormals;
        mesh.vertexNormals = normals;
        Texcoords uv(both.rows(), 2);
        uv << mesh.texcoords, second.texcoords;
        mesh.texcoords = uv;
        mesh.groupNames = {"", "left", "right"};
        std::fill(mesh.faceGroup.begin(), mesh.faceGroup.end(), 1);
        for (int f = 0; f < second.faceCount(); ++f) {
            for (int c = second.faceStart[f]; c < second.faceStart[f + 1]; ++c) {
                mesh.cornerVertex.push_back(second.cornerVertex[c] + offset);
                mesh.cornerTexcoord.push_back(second.cornerTexcoord[c] + offset);
                mesh.cornerNormal.push_back(-1);
            }
            mesh.faceStart.push_back(static_cast<int>(mesh.cornerVertex.size()));
            mesh.faceGroup.push_back(2);
            mesh.faceMaterial.push_back(-1);
        }
        (void)faceOffset;
        triangulateObjFaces(mesh);
        REQUIRE(checkObjMesh(mesh).ok);
        for (const bool binary : {false, true}) {
            INFO("size " << size << (binary ? " .glb" : " .gltf"));
            const ObjMesh back = roundTrip(folder, binary ? "m.glb" : "m.gltf", mesh, mesh.positions, {MeshFormat::Gltf, binary, false});
            REQUIRE(back.positions.rows() == mesh.positions.rows());
            CHECK(back.positions == asFloat(mesh.positions));
            CHECK(trianglesOf(back) == trianglesOf(mesh));
            CHECK(back.groupNames == mesh.groupNames);
            CHECK(back.faceGroup == mesh.faceGroup);
            REQUIRE(back.vertexColors.rows() == mesh.vertexColors.rows());
            CHECK((back.vertexColors - mesh.vertexColors).cwiseAbs().maxCoeff() <= 1e-6f);
            REQUIRE(back.vertexNormals.rows() == mesh.vertexNormals.rows());
            CHECK(largestDifference(back.vertexNormals, mesh.vertexNormals) <= 1e-6);  // the writer renormalises
            REQUIRE(back.texcoords.rows() == mesh.positions.rows());
            // glTF's v runs down the image: it is flipped (1 - v) on the way in and out, which may round.
            CHECK(largestDifference(back.texcoords.leftCols(2), mesh.texcoords) <= 1e-7);
        }
    }
}

// mesh_fuzz found a binary STL whose facets each had two corners at one point: welded, every triangle repeated a
// vertex, and the GLB it saved loaded back as "no faces" (the glTF reader dropped such triangles as strip joins).
// A loaded mesh's triangles that repeat a vertex (no area) are faces the file held: every encoding writes them and
// reads them back, in order. Random spheres (fixed seed, several sizes) with a random share of their triangles
// collapsed that way, up to all of them.
TEST_CASE("mesh formats: triangles that repeat a vertex survive a save and load in every encoding", "[io][formats]") {
    TempFolder folder("repeated_corners");
    std::mt19937 rng(4242);
    const MeshEncoding encodings[] = {{MeshFormat::Obj, false, false}, {MeshFormat::Ply, false, false}, {MeshFormat::Ply, true, true},
                                      {MeshFormat::Gltf, false, false}, {MeshFormat::Gltf, true, false}, {MeshFormat::Off, false, false},
                                      {MeshFormat::Stl, true, false}, {MeshFormat::Stl, false, false}};
    const char* names[] = {"m.obj", "m.ply", "m.ply", "m.gltf", "m.glb", "m.off", "m.stl", "m.stl"};
    for (int size = 3; size <= 15; size += 4) {
        for (const double share : {0.1, 0.5, 1.0}) {
            ObjMesh mesh = randomSphere(rng, size, size + 1, false, false, false, false);
            std::uniform_real_distribution<double> unit(0.0, 1.0);
            for (int f = 0; f < mesh.faceCount(); ++f) {
                if (share < 1.0 && unit(rng) >= share) continue;
                const int to = static_cast<int>(rng() % 3u), from = (to + 1 + static_cast<int>(rng() % 2u)) % 3;  // another corner
                mesh.cornerVertex[static_cast<size_t>(mesh.faceStart[f] + to)] = mesh.cornerVertex[static_cast<size_t>(mesh.faceStart[f] + from)];
            }
            triangulateObjFaces(mesh);
            REQUIRE(checkObjMesh(mesh).ok);
            for (size_t e = 0; e < std::size(encodings); ++e) {
                INFO("size " << size << ", share " << share << ", " << meshEncodingText(encodings[e]));
                const ObjMesh back = roundTrip(folder, names[e], mesh, mesh.positions, encodings[e]);
                REQUIRE(back.triangles.rows() == mesh.triangles.rows());
                if (encodings[e].format == MeshFormat::Stl) {
                    // Welded by position: each triangle repeats a corner exactly where the one written did.
                    for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t)
                        for (int k = 0; k < 3; ++k)
                            CHECK((back.triangles(t, k) == back.triangles(t, (k + 1) % 3)) ==
                                  (mesh.triangles(t, k) == mesh.triangles(t, (k + 1) % 3)));
                } else {
                    CHECK(trianglesOf(back) == trianglesOf(mesh));
                }
            }
        }
    }
}

TEST_CASE("mesh formats: what a format cannot hold is named in a warning, never dropped in silence", "[io][formats]") {
    TempFolder folder("formats_notes");
    std::mt19937 rng(5);
    ObjMesh mesh = randomSphere(rng, 6, 6, true, true, false, true);
    mesh.groupNames = {"", "top", "bottom"};
    for (size_t f = 0; f < mesh.faceGroup.size(); ++f) mesh.faceGroup[f] = f < mesh.faceGroup.size() / 2 ? 1 : 2;
    mesh.cornerTexcoord[0] = mesh.cornerVertex[1];  // a seam: one corner of vertex 0 uses another coordinate
    std::vector<std::string> notes;
    std::string bytes;
    REQUIRE(serializeMesh("n.stl", mesh, mesh.positions, {MeshFormat::Stl, true, false}, bytes, &notes).ok);
    const auto said = [&notes](const std::string& what) {
        return std::any_of(notes.begin(), notes.end(), [&](const std::string& n) { return n.find(what) != std::string::npos; });
    };
    CHECK(said("texture coordinates are not written: STL"));
    CHECK(said("vertex colours are not written"));
    CHECK(said("polygon(s) of more than 3 corners are written as their triangles"));
    notes.clear();
    REQUIRE(serializeMesh("n.ply", mesh, mesh.positions, {MeshFormat::Ply, false, false}, bytes, &notes).ok);
    CHECK(said("groups are not written"));
    CHECK(said("they differ between the corners of a vertex"));
    for (const std::string& n : notes) CHECK(n.rfind("n.ply: ", 0) == 0);

    // A PLY with properties assimp does not read: each is named on load.
    const std::string ply =
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "property float quality\nelement face 1\nproperty list uchar int vertex_indices\nproperty uchar flags\n"
        "element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n"
        "0 0 0 1\n1 0 0 1\n0 1 0 1\n3 0 1 2 7\n0 1\n";
    ObjMesh back;
    std::vector<std::string> warnings;
    const Status s = loadMeshFromMemory(ply, MeshFormat::Ply, "q.ply", back, &warnings);
    INFO(s.message);
    REQUIRE(s.ok);
    notes = warnings;
    CHECK(said("q.ply: vertex property 'quality' is not kept"));
    CHECK(said("face property 'flags' is not kept"));
    CHECK(said("PLY element 'edge' (1) is not kept"));
}

TEST_CASE("mesh formats: an OBJ's vertex colours (v x y z r g b) are written to PLY and glTF", "[io][formats]") {
    const std::string obj = "v 0 0 0 1 0 0\nv 1 0 0 0 1 0.5\nv 0 1 0\nv 0 0 1 0.25 0.25 0.25 # grey\n"
                            "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
    ObjMesh mesh;
    REQUIRE(loadMeshFromMemory(obj, MeshFormat::Obj, "c.obj", mesh).ok);
    REQUIRE(mesh.vertexColors.rows() == 0);  // an OBJ keeps them in its text
    for (const MeshEncoding encoding : {MeshEncoding{MeshFormat::Ply, true, false}, MeshEncoding{MeshFormat::Gltf, true, false}}) {
        INFO(meshEncodingText(encoding));
        std::string bytes;
        REQUIRE(serializeMesh("c", mesh, mesh.positions, encoding, bytes).ok);
        ObjMesh back;
        REQUIRE(loadMeshFromMemory(bytes, encoding.format, "c", back).ok);
        REQUIRE(back.vertexColors.rows() == 4);
        VertexColors expected(4, 4);
        expected << 1, 0, 0, 1, 0, 1, 0.5f, 1, 1, 1, 1, 1, 0.25f, 0.25f, 0.25f, 1;  // white where a line has none
        CHECK((back.vertexColors - expected).cwiseAbs().maxCoeff() <= 0.5f / 255.0f + 1e-6f);
    }
}

TEST_CASE("mesh formats: the colours drawn follow refinement: a new vertex has its edge's midpoint colour", "[io][formats]") {
    // Random coloured spheres of several sizes, refined by random splits of edges of the current triangles (a
    // split vertex may be split again); the colours are checked against a plain recomputation in double and
    // against what a refined save carries (refineObjMesh).
    std::mt19937 rng(515);
    for (int trial = 0; trial < 12; ++trial) {
        const int rings = std::uniform_int_distribution<int>(3, 20)(rng);
        const int segments = std::uniform_int_distribution<int>(3, 24)(rng);
        const ObjMesh mesh = randomSphere(rng, rings, segments, false, true, false, false);
        Triangles triangles = mesh.triangles;
        std::vector<core::EdgeSplit> splits;
        const int splitCount = std::uniform_int_distribution<int>(0, 40)(rng);
        for (int k = 0; k < splitCount; ++k) {
            const int t = std::uniform_int_distribution<int>(0, static_cast<int>(triangles.rows()) - 1)(rng);
            const int c = std::uniform_int_distribution<int>(0, 2)(rng);
            const core::EdgeSplit split{triangles(t, c), triangles(t, (c + 1) % 3)};
            REQUIRE(core::applyEdgeSplits(triangles, mesh.vertexCount() + k, {split}).ok);
            splits.push_back(split);
        }
        const VertexColors colours = meshVertexColours(mesh, splits);
        REQUIRE(colours.rows() == mesh.vertexCount() + splitCount);
        std::vector<Eigen::Vector4d> expected;
        for (int v = 0; v < mesh.vertexCount(); ++v) expected.push_back(mesh.vertexColors.row(v).transpose().cast<double>());
        for (const core::EdgeSplit& split : splits) expected.push_back(0.5 * (expected[size_t(split.a)] + expected[size_t(split.b)]));
        for (Eigen::Index v = 0; v < colours.rows(); ++v)
            CHECK((colours.row(v).transpose().cast<double>() - expected[size_t(v)]).cwiseAbs().maxCoeff() < 1e-6);
        ObjMesh refined;
        REQUIRE(refineObjMesh(mesh, splits, refined).ok);
        CHECK(refined.vertexColors == colours);
    }
    // An OBJ's `v x y z r g b` colours (white where a line has none), split once.
    ObjMesh obj;
    REQUIRE(loadMeshFromMemory("v 0 0 0 1 0 0\nv 1 0 0 0 0 1\nv 0 1 0\nf 1 2 3\n", MeshFormat::Obj, "c.obj", obj).ok);
    const VertexColors objColours = meshVertexColours(obj, {{0, 1}});
    REQUIRE(objColours.rows() == 4);
    CHECK(objColours.row(2) == Eigen::RowVector4f(1, 1, 1, 1));
    CHECK(objColours.row(3) == Eigen::RowVector4f(0.5f, 0, 0.5f, 1));
    // A refined OBJ has no source text left to keep them in: its arrays carry them, and a save writes them.
    ObjMesh refinedObj;
    REQUIRE(refineObjMesh(obj, {{0, 1}}, refinedObj).ok);
    CHECK(refinedObj.vertexColors == objColours);
    std::string text;
    REQUIRE(serializeObj(refinedObj, refinedObj.positions, text).ok);
    ObjMesh reread;
    REQUIRE(loadMeshFromMemory(text, MeshFormat::Obj, "r.obj", reread).ok);
    CHECK(meshVertexColours(reread) == objColours);
    // No colours in the file: none to draw; splits that name vertices the mesh does not have: none either.
    REQUIRE(loadMeshFromMemory("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", MeshFormat::Obj, "p.obj", obj).ok);
    CHECK(meshVertexColours(obj, {{0, 1}}).rows() == 0);
    std::mt19937 again(516);
    const ObjMesh coloured = randomSphere(again, 4, 5, false, true, false, false);
    CHECK(meshVertexColours(coloured, {{0, coloured.vertexCount()}}).rows() == 0);
    CHECK(meshVertexColours(coloured, {{-1, 2}}).rows() == 0);
}

TEST_CASE("mesh formats: bad files get a message naming the file and what is wrong, and change nothing", "[io][formats]") {
    std::mt19937 rng(3);
    const ObjMesh keep = randomSphere(rng, 4, 5, false, false, false, false);
    struct Bad {
        MeshFormat format;
        std::string bytes, expected;
    };
    std::string nanStl(84 + 50, '\0');
    nanStl[80] = 1;
    const float nan = std::nanf("");
    std::memcpy(&nanStl[84 + 12], &nan, 4);
    std::string shortPly = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                           "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
    shortPly += std::string(20, '\0');
    const std::vector<Bad> cases = {
        {MeshFormat::Ply, "PLY\nformat ascii 1.0\n", "b.ply: not a PLY file"},
        {MeshFormat::Ply, "ply\nformat ascii 1.0\nelement vertex 1\n", "no end_header"},
        {MeshFormat::Ply, "ply\nformat weird 1.0\nend_header\n", "unknown PLY format 'weird'"},
        {MeshFormat::Ply, "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                          "end_header\n0 0 0\n1 0 0\n0 1 0\n", "no faces (3 points: a point cloud is not a surface)"},
        {MeshFormat::Ply, "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                          "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 9\n",
         "b.ply:"},
        {MeshFormat::Ply, shortPly, "b.ply:"},
        {MeshFormat::Stl, "hello", "not an STL file"},
        {MeshFormat::Stl, nanStl, "non-finite coordinate"},
        {MeshFormat::Gltf, "[1, 2]", "not a glTF file"},
        {MeshFormat::Gltf, std::string("glTF\x02\0\0\0\xff\0\0\0", 12), "the file ends early: its GLB header declares 255 bytes"},
        {MeshFormat::Gltf, "{\"asset\": {\"version\": \"2.0\"}, \"buffers\": [{\"uri\": \"missing.bin\", \"byteLength\": 8}]}", "b.gltf:"},
    };
    for (const Bad& bad : cases) {
        const std::string name = std::string("b.") + (bad.format == MeshFormat::Ply ? "ply" : bad.format == MeshFormat::Stl ? "stl" : "gltf");
        ObjMesh out = keep;
        std::vector<std::string> warnings;
        const Status s = loadMeshFromMemory(bad.bytes, bad.format, name, out, &warnings);
        INFO(bad.bytes.substr(0, 60) << " -> " << s.message);
        CHECK_FALSE(s.ok);
        CHECK(s.message.find(bad.expected) != std::string::npos);
        CHECK(s.message.rfind(name + ":", 0) == 0);
        CHECK(out.positions == keep.positions);
    }
}

// assimp reads a short ASCII PLY body as complete (repeating the last face read) and a short binary one as
// garbage indices: a file cut anywhere is refused with where it ends, in every encoding.
TEST_CASE("mesh formats: a file cut short anywhere is refused, naming where it ends", "[io][formats]") {
    std::mt19937 rng(404);
    const ObjMesh mesh = randomSphere(rng, 6, 7, true, true, true, false);
    for (const MeshEncoding encoding : {MeshEncoding{MeshFormat::Ply, false, false}, MeshEncoding{MeshFormat::Ply, true, false},
                                        MeshEncoding{MeshFormat::Ply, true, true}, MeshEncoding{MeshFormat::Stl, true, false},
                                        MeshEncoding{MeshFormat::Gltf, true, false}}) {
        std::string bytes;
        REQUIRE(serializeMesh("t", mesh, mesh.positions, encoding, bytes).ok);
        const size_t headerEnd = encoding.format == MeshFormat::Ply ? bytes.find("end_header\n") + 11 : 84;
        for (int cut = 0; cut < 12; ++cut) {
            // Cut inside the body: a random place, and just before the end (the last face's last index).
            // (ASCII: before the last value, since a number cut short is still a number.)
            const size_t keep = cut == 0 ? (encoding.binary ? bytes.size() - 2 : bytes.rfind(' '))
                                         : headerEnd + std::uniform_int_distribution<size_t>(0, bytes.size() - headerEnd - 3)(rng);
            INFO(meshEncodingText(encoding) << ", " << keep << " of " << bytes.size() << " bytes");
            ObjMesh out;
            const Status s = loadMeshFromMemory(bytes.substr(0, keep), encoding.format, "cut", out);
            INFO(s.message);
            CHECK_FALSE(s.ok);
            if (encoding.format != MeshFormat::Gltf || keep < 12) {
                CHECK(s.message.find("the file ends early") != std::string::npos);
            } else {
                CHECK(s.message.rfind("cut: ", 0) == 0);
            }
        }
    }
}

TEST_CASE("mesh formats: a failed save leaves the file as it was", "[io][formats]") {
    TempFolder folder("formats_save");
    std::mt19937 rng(11);
    const ObjMesh mesh = randomSphere(rng, 5, 6, false, false, false, false);
    for (const char* name : {"keep.ply", "keep.stl", "keep.glb", "keep.obj"}) {
        const std::string path = folder.file(name);
        { std::ofstream(path) << "precious"; }
        Positions bad = mesh.positions;
        bad(2, 1) = std::nan("");
        CHECK_FALSE(saveMesh(path, mesh, bad).ok);
        bad(2, 1) = 1e300;  // finite, but not a float
        const Status s = saveMesh(path, mesh, bad);
        if (std::string(name) != "keep.obj") {
            CHECK_FALSE(s.ok);
            CHECK(s.message.find("single precision") != std::string::npos);
        }
        if (!s.ok) CHECK(readBytes(path) == "precious");
        CHECK_FALSE(saveMesh(folder.file("no/such/folder/") + name, mesh, mesh.positions).ok);
    }
    CHECK_FALSE(saveMesh(folder.file("x.fbx"), mesh, mesh.positions).ok);
    CHECK_FALSE(std::filesystem::exists(folder.file("x.fbx")));
}

// Debian's assimp-testmodels: real files written by other tools. Each one either loads (and survives a round
// trip through every format) or is refused with a message; none crashes.
TEST_CASE("mesh formats: the PLY, STL and glTF files of assimp-testmodels", "[io][formats]") {
    const std::string root = "/usr/share/assimp/models/";
    if (!std::filesystem::exists(root)) FAIL("assimp-testmodels is not installed (.ci/install-deps installs it)");
    TempFolder folder("formats_real");
    struct Expect {
        std::string file;
        int vertices, faces;  // -1: refused
    };
    const std::vector<Expect> known = {
        {"PLY/cube.ply", 8, 6},              // quads kept as quads
        {"PLY/cube_binary.ply", 8, 12},
        {"PLY/cube_uv.ply", 24, 6},
        {"PLY/Wuson.ply", 11184, 3732},
        {"PLY/float-color.ply", 3, 1},
        {"PLY/points.ply", -1, -1},          // a point cloud
        {"STL/Spider_ascii.stl", 722, 1368},  // 4104 facet corners welded
        {"STL/Spider_binary.stl", 722, 1368},
        {"STL/triangle_with_two_solids.stl", 6, 2},
        {"glTF2/BoxTextured-glTF/BoxTextured.gltf", 24, 12},
        {"glTF2/BoxTextured-glTF-Binary/BoxTextured.glb", 24, 12},
        {"glTF2/BoxTextured-glTF-Embedded/BoxTextured.gltf", 24, 12},
        {"glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb", -2, -2},  // loads; counts checked below
        {"glTF2/IndexOutOfRange/IndexOutOfRange.gltf", -1, -1},  // an index beyond the vertices: refused, named below
        {"glTF2/MissingBin/BoxTextured.gltf", -1, -1},
    };
    for (const Expect& e : known) {
        INFO(e.file);
        ObjMesh mesh;
        std::vector<std::string> warnings;
        const Status s = loadMesh(root + e.file, mesh, &warnings);
        INFO(s.message);
        if (e.vertices == -1) {
            CHECK_FALSE(s.ok);
            CHECK(s.message.rfind(root + e.file + ": ", 0) == 0);
            continue;
        }
        REQUIRE(s.ok);
        if (e.vertices >= 0) {
            CHECK(mesh.vertexCount() == e.vertices);
            CHECK(mesh.faceCount() == e.faces);
        }
        for (const char* out : {"r.obj", "r.ply", "r.stl", "r.glb", "r.gltf"}) {
            INFO(out);
            std::vector<std::string> notes;
            Positions moved = mesh.positions;
            moved.array() += 0.5;
            REQUIRE(saveMesh(folder.file(out), mesh, moved, &notes).ok);
            ObjMesh back;
            const Status again = loadMesh(folder.file(out), back);
            INFO(again.message);
            REQUIRE(again.ok);
            const std::string o(out);
            if (o == "r.stl") {
                CHECK(back.vertexCount() <= mesh.vertexCount());  // coincident vertices weld
                CHECK(back.triangles.rows() == mesh.triangles.rows());
            } else {
                CHECK(back.vertexCount() == mesh.vertexCount());
                // OBJ keeps doubles; the others floats, read back exactly from binary and to assimp's ASCII parser.
                const double tolerance = o == "r.ply" && !mesh.loadedAs.binary ? 2 * kAsciiReadTolerance : 0.0;
                CHECK(largestDifference(back.positions, o == "r.obj" ? moved : asFloat(moved)) <= tolerance);
            }
        }
    }
    // The same surface in ASCII and binary STL welds to the same mesh.
    ObjMesh ascii, binary;
    REQUIRE(loadMesh(root + "STL/Spider_ascii.stl", ascii).ok);
    REQUIRE(loadMesh(root + "STL/Spider_binary.stl", binary).ok);
    CHECK((ascii.positions - binary.positions).cwiseAbs().maxCoeff() < 1e-5);
    CHECK(ascii.triangles == binary.triangles);
    // A glTF scene whose nodes move its meshes: the transforms are applied, and the load says so.
    ObjMesh engine;
    std::vector<std::string> warnings;
    REQUIRE(loadMesh(root + "glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb", engine, &warnings).ok);
    CHECK(std::any_of(warnings.begin(), warnings.end(), [](const std::string& w) { return w.find("node transforms are applied") != std::string::npos; }));
    CHECK(engine.groupNames.size() > 2);
    // An index beyond the vertices is named, not skipped (assimp used to drop that triangle with a note).
    ObjMesh skipped;
    const Status outOfRange = loadMesh(root + "glTF2/IndexOutOfRange/IndexOutOfRange.gltf", skipped);
    CHECK(outOfRange.message.find("is 255, beyond its 24 vertices") != std::string::npos);
    // The program's own GLB reloads with no warning at all (it writes no material, so none is reported).
    std::vector<std::string> reloadNotes;
    REQUIRE(saveMesh(folder.file("own.glb"), engine, engine.positions).ok);
    ObjMesh own;
    REQUIRE(loadMesh(folder.file("own.glb"), own, &reloadNotes).ok);
    INFO(::Catch::Detail::stringify(reloadNotes));
    CHECK(reloadNotes.empty());
    // Every other sample of the package either loads or is refused with a message; none crashes or hangs.
    for (const auto& entry : std::filesystem::recursive_directory_iterator(root)) {
        const std::string path = entry.path().string();
        if (!entry.is_regular_file() || !isMeshPath(path) || path.find("/OBJ/") != std::string::npos) continue;
        const std::string ext = entry.path().extension().string();
        if (ext == ".obj" || ext == ".OBJ") continue;
        ObjMesh any;
        const Status s = loadMesh(path, any);
        INFO(path << ": " << s.message);
        CHECK((s.ok || s.message.rfind(path + ": ", 0) == 0));
        if (s.ok) CHECK(any.positions.allFinite());
    }
}

}  // namespace sculpt::io
