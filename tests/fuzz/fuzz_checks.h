// The invariants every mesh-loader fuzz target checks on a load (mesh_fuzz.cpp, gltf_fuzz.cpp).
#pragma once

#include <cmath>
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

// The format a fuzz target (and the unit test over its corpus) reads bytes as, picked the way a misnamed file
// would meet it: "ply" -> PLY, "glTF" or "{" -> glTF, "OFF", "COFF", "NOFF" -> OFF, anything else -> STL (whose
// reader takes any bytes that are not another format). name is the file name the load is told.
inline io::MeshFormat formatOfBytes(const std::string& bytes, std::string& name) {
    if (bytes.compare(0, 3, "ply") == 0) return name = "fuzz.ply", io::MeshFormat::Ply;
    if (bytes.compare(0, 3, "OFF") == 0 || bytes.compare(0, 4, "COFF") == 0 || bytes.compare(0, 4, "NOFF") == 0)
        return name = "fuzz.off", io::MeshFormat::Off;
    if (bytes.compare(0, 4, "glTF") == 0 || bytes.compare(0, 1, "{") == 0) return name = "fuzz.gltf", io::MeshFormat::Gltf;
    return name = "fuzz.stl", io::MeshFormat::Stl;
}

// What a loaded mesh must survive: a save in each of four encodings (PLY ASCII, PLY binary big-endian with its
// byte swap, binary STL, GLB) and a load of what was written, with the same vertex count (PLY, GLB), the same
// triangle count (STL, which welds), and for PLY the positions rounded to float (exactly from binary; ASCII
// through assimp's fast number parser, a unit or two off in float's last place, denormals may flush to zero).
// Returns "" when every one holds, else what broke and in which encoding. Every read runs a reader process.
inline std::string roundTripBreak(const io::ObjMesh& mesh) {
    using namespace io;
    const MeshEncoding encodings[] = {{MeshFormat::Ply, false, false}, {MeshFormat::Ply, true, true},
                                      {MeshFormat::Stl, true, false}, {MeshFormat::Gltf, true, false}};
    for (const MeshEncoding& encoding : encodings) {
        const std::string path = encoding.format == MeshFormat::Ply ? "out.ply" : encoding.format == MeshFormat::Stl ? "out.stl" : "out.glb";
        std::string written;
        // Positions outside float's range are the one refusal a loaded (float) mesh cannot meet.
        if (const Status saved = serializeMesh(path, mesh, mesh.positions, encoding, written); !saved)
            return "a loaded mesh could not be saved: " + saved.message;
        ObjMesh back;
        if (const Status reread = loadMeshFromMemory(written, encoding.format, path, back); !reread)
            return "a saved mesh did not load back: " + meshEncodingText(encoding) + ": " + reread.message;
        if (encoding.format == MeshFormat::Stl) {
            if (back.triangles.rows() != mesh.triangles.rows()) return "STL round trip changed the triangle count";
            continue;
        }
        if (back.positions.rows() != mesh.positions.rows()) return "round trip changed the vertex count: " + meshEncodingText(encoding);
        if (encoding.format != MeshFormat::Ply) continue;
        const auto expected = mesh.positions.cast<float>().cast<double>();
        const double tolerance = encoding.binary ? 0.0 : 1e-6;
        for (Eigen::Index v = 0; v < expected.rows(); ++v)
            for (int k = 0; k < 3; ++k)
                if (std::abs(back.positions(v, k) - expected(v, k)) > tolerance * std::abs(expected(v, k)) + (encoding.binary ? 0.0 : 1e-37))
                    return "PLY round trip changed positions or their order: " + meshEncodingText(encoding);
    }
    return "";
}

}  // namespace sculpt::fuzz
