// The invariants every mesh-loader fuzz target checks on a load (mesh_fuzz.cpp, gltf_fuzz.cpp).
#pragma once

#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "io/mesh_file.h"

namespace sculpt::fuzz {

[[noreturn]] inline void fail(const char* target, const char* what, const std::string& detail) {
    std::fprintf(stderr, "%s invariant broken: %s\n%s\n", target, what, detail.c_str());
    std::abort();
}

// A failed load names the file and leaves the output untouched; a load that succeeds gives a consistent mesh
// with finite positions, and each warning names the file. Returns whether it loaded.
inline bool checkLoad(const char* target, const sculpt::Status& loaded, const std::string& name, const io::ObjMesh& mesh,
                      const std::vector<std::string>& warnings) {
    if (!loaded) {
        if (loaded.message.rfind(name + ": ", 0) != 0) fail(target, "error message does not name the file", loaded.message);
        if (mesh.positions.size() != 0 || mesh.faceStart.size() != 0) fail(target, "out was modified on failure", loaded.message);
        return false;
    }
    if (sculpt::Status s = io::checkObjMesh(mesh); !s) fail(target, "loaded mesh is inconsistent", s.message);
    if (!mesh.positions.allFinite()) fail(target, "non-finite position loaded", name);
    for (const std::string& w : warnings)
        if (w.rfind(name + ": ", 0) != 0) fail(target, "warning does not name the file", w);
    return true;
}

}  // namespace sculpt::fuzz
