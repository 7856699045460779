// What the mesh format tests share (mesh_formats_test.cpp: round trips per format; mesh_files_test.cpp: real
// files, fuzz regressions, the reader process): random meshes, round trips and comparisons.
#pragma once

#include <array>
#include <cmath>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "io/mesh_file.h"
#include "io_test_support.h"

namespace sculpt::io::formats_test {

using test::readBytes;
using test::TempFolder;

// A closed, randomly jittered sphere of `rings` x `segments` quads (triangles at the poles), every vertex at its
// own position, with the attributes asked for (values in float so they survive single precision exactly).
inline ObjMesh randomSphere(std::mt19937& rng, int rings, int segments, bool quads, bool colours, bool normals, bool uvs) {
    std::uniform_real_distribution<float> jitter(-0.02f, 0.02f), unit(0.0f, 1.0f);
    ObjMesh mesh;
    std::vector<Eigen::Vector3d> points;
    points.emplace_back(0, 0, 1);
    for (int r = 1; r < rings; ++r)
        for (int s = 0; s < segments; ++s) {
            const double theta = M_PI * r / rings, phi = 2 * M_PI * s / segments;
            points.emplace_back(static_cast<float>(std::sin(theta) * std::cos(phi) + jitter(rng)),
                                static_cast<float>(std::sin(theta) * std::sin(phi) + jitter(rng)),
                                static_cast<float>(std::cos(theta) + jitter(rng)));
        }
    points.emplace_back(0, 0, -1);
    const int last = static_cast<int>(points.size()) - 1;
    mesh.positions.resize(static_cast<Eigen::Index>(points.size()), 3);
    for (size_t i = 0; i < points.size(); ++i) mesh.positions.row(static_cast<Eigen::Index>(i)) = points[i].transpose();
    const auto ring = [&](int r, int s) { return 1 + (r - 1) * segments + (s % segments); };
    const auto face = [&](std::initializer_list<int> corners) {
        for (int c : corners) {
            mesh.cornerVertex.push_back(c);
            mesh.cornerTexcoord.push_back(uvs ? c : -1);
            mesh.cornerNormal.push_back(-1);
        }
        mesh.faceStart.push_back(static_cast<int>(mesh.cornerVertex.size()));
        mesh.faceGroup.push_back(0);
        mesh.faceMaterial.push_back(-1);
    };
    mesh.faceStart = {0};
    mesh.groupNames = {std::string()};
    for (int s = 0; s < segments; ++s) face({0, ring(1, s), ring(1, s + 1)});
    for (int r = 1; r + 1 < rings; ++r)
        for (int s = 0; s < segments; ++s) {
            const int a = ring(r, s), b = ring(r + 1, s), c = ring(r + 1, s + 1), d = ring(r, s + 1);
            if (quads) {
                face({a, b, c, d});
            } else {
                face({a, b, c});
                face({a, c, d});
            }
        }
    for (int s = 0; s < segments; ++s) face({last, ring(rings - 1, s + 1), ring(rings - 1, s)});
    const Eigen::Index n = mesh.positions.rows();
    if (colours) {
        mesh.vertexColors.resize(n, 4);
        for (Eigen::Index v = 0; v < n; ++v)
            for (int k = 0; k < 4; ++k) mesh.vertexColors(v, k) = static_cast<float>(std::uniform_int_distribution<int>(0, 255)(rng)) / 255.0f;
    }
    if (normals) {
        mesh.vertexNormals = mesh.positions.cast<float>();
        mesh.vertexNormals.rowwise().normalize();
    }
    if (uvs) {
        mesh.texcoords.resize(n, 2);
        for (Eigen::Index v = 0; v < n; ++v) mesh.texcoords.row(v) << unit(rng), unit(rng);
    }
    triangulateObjFaces(mesh);
    INFO(checkObjMesh(mesh).message);
    REQUIRE(checkObjMesh(mesh).ok);
    return mesh;
}

inline Positions asFloat(const Positions& p) { return p.cast<float>().cast<double>(); }

// assimp reads ASCII numbers with its fast parser (fast_atof), which can be a unit or two off in float's last
// place; binary files read back bit for bit.
template <typename A, typename B>
double largestDifference(const A& a, const B& b) {
    return (a.template cast<double>() - b.template cast<double>()).cwiseAbs().maxCoeff();
}
constexpr double kAsciiReadTolerance = 4e-7;

// Reads back what serializeMesh wrote for path (written to the folder first).
inline ObjMesh roundTrip(const TempFolder& folder, const std::string& name, const ObjMesh& mesh, const Positions& deformed,
                  const MeshEncoding& encoding, std::vector<std::string>* saveNotes = nullptr) {
    std::string bytes;
    const std::string path = folder.file(name);
    const Status saved = serializeMesh(path, mesh, deformed, encoding, bytes, saveNotes);
    INFO(saved.message);
    REQUIRE(saved.ok);
    std::ofstream(path, std::ios::binary) << bytes;
    ObjMesh back;
    std::vector<std::string> warnings;
    const Status loaded = loadMesh(path, back, &warnings);
    INFO(loaded.message);
    REQUIRE(loaded.ok);
    CHECK(back.loadedAs.format == encoding.format);
    CHECK(back.loadedAs.binary == encoding.binary);
    CHECK(back.loadedAs.bigEndian == encoding.bigEndian);
    return back;
}

inline std::vector<std::vector<int>> facesOf(const ObjMesh& mesh) {
    std::vector<std::vector<int>> faces;
    for (int f = 0; f < mesh.faceCount(); ++f)
        faces.emplace_back(mesh.cornerVertex.begin() + mesh.faceStart[f], mesh.cornerVertex.begin() + mesh.faceStart[f + 1]);
    return faces;
}

inline std::vector<std::array<int, 3>> trianglesOf(const ObjMesh& mesh) {
    std::vector<std::array<int, 3>> t;
    for (Eigen::Index i = 0; i < mesh.triangles.rows(); ++i) t.push_back({mesh.triangles(i, 0), mesh.triangles(i, 1), mesh.triangles(i, 2)});
    return t;
}

}  // namespace sculpt::io::formats_test
