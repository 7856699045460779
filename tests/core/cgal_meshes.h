// Real meshes for the tests: CGAL's data (Debian package libcgal-demo, /usr/share/doc/libcgal-dev/data.tar.gz,
// data/meshes/*.off: scans and models), read here by a small OFF reader of the test's own (polygons fanned into
// triangles), so the engine's tests do not depend on the program's file readers.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <unistd.h>

#include "core/mesh_types.h"

namespace sculpt::test {

// Loads data/meshes/NAME (e.g. "elephant.off"); false with the reason in `error` when the archive or the file is
// missing or malformed.
inline bool loadCgalMesh(const std::string& name, Positions& positions, Triangles& triangles, std::string& error) {
    const std::string archive = "/usr/share/doc/libcgal-dev/data.tar.gz";
    if (!std::filesystem::exists(archive)) {
        error = "libcgal-demo is not installed (.ci/install-deps installs it)";
        return false;
    }
    const std::filesystem::path folder = std::filesystem::temp_directory_path() / ("sculpt_cgal_" + std::to_string(::getpid()));
    const std::filesystem::path file = folder / "data" / "meshes" / name;
    if (!std::filesystem::exists(file)) {
        std::filesystem::create_directories(folder);
        const std::string command = "tar -xzf " + archive + " -C '" + folder.string() + "' data/meshes/" + name;
        if (std::system(command.c_str()) != 0) {
            error = "cannot extract data/meshes/" + name + " from " + archive;
            return false;
        }
    }
    std::ifstream in(file);
    std::stringstream text;
    for (std::string line; std::getline(in, line);) text << line.substr(0, line.find('#')) << '\n';
    std::string magic;
    long vertices = 0, faces = 0, edges = 0;
    if (!(text >> magic >> vertices >> faces >> edges) || magic != "OFF" || vertices <= 0 || faces <= 0) {
        error = name + ": not a plain OFF file";
        return false;
    }
    positions.resize(vertices, 3);
    for (long v = 0; v < vertices; ++v)
        if (!(text >> positions(v, 0) >> positions(v, 1) >> positions(v, 2))) {
            error = name + ": vertex " + std::to_string(v) + " is incomplete";
            return false;
        }
    std::vector<std::array<int, 3>> tris;
    for (long f = 0; f < faces; ++f) {
        int count = 0;
        text >> count;
        std::vector<int> ids(static_cast<size_t>(std::max(count, 0)));
        for (int& id : ids) text >> id;
        std::string rest;
        std::getline(text, rest);  // colours
        if (!text || count < 3) {
            error = name + ": face " + std::to_string(f) + " is malformed";
            return false;
        }
        for (int k = 1; k + 1 < count; ++k) tris.push_back({ids[0], ids[static_cast<size_t>(k)], ids[static_cast<size_t>(k) + 1]});
    }
    triangles.resize(static_cast<Eigen::Index>(tris.size()), 3);
    for (size_t t = 0; t < tris.size(); ++t)
        for (int k = 0; k < 3; ++k) triangles(static_cast<Eigen::Index>(t), k) = tris[t][static_cast<size_t>(k)];
    return true;
}

}  // namespace sculpt::test
