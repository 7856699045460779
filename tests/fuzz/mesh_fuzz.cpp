// Fuzz target for the PLY, STL, glTF and OFF readers (io/mesh_file.h) and the writers behind them.
// The format is picked from the bytes the way a misnamed file would meet it: "ply" -> PLY, "glTF" or "{" ->
// glTF, "OFF", "COFF", "NOFF" -> OFF, anything else -> STL (whose reader takes any bytes that are not another format). Any input either
// loads into a consistent mesh or fails with a message naming the file, leaving the output untouched; what
// loads must save in every encoding and load back with the same vertices (PLY and GLB: the same count; PLY:
// the positions rounded to float, exactly from binary; STL: the same triangles).
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "fuzz_checks.h"
#include "io/mesh_file.h"

namespace {

[[noreturn]] void fail(const char* what, const std::string& detail) { sculpt::fuzz::fail("mesh_fuzz", what, detail); }

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace sculpt::io;
    const std::string bytes(reinterpret_cast<const char*>(data), size);
    MeshFormat format = MeshFormat::Stl;
    std::string name = "fuzz.stl";
    if (bytes.compare(0, 3, "ply") == 0) {
        format = MeshFormat::Ply;
        name = "fuzz.ply";
    } else if (bytes.compare(0, 3, "OFF") == 0 || bytes.compare(0, 4, "COFF") == 0 || bytes.compare(0, 4, "NOFF") == 0) {
        format = MeshFormat::Off;
        name = "fuzz.off";
    } else if (bytes.compare(0, 4, "glTF") == 0 || bytes.compare(0, 1, "{") == 0) {
        format = MeshFormat::Gltf;
        name = "fuzz.gltf";
    }
    ObjMesh mesh;
    std::vector<std::string> warnings;
    const sculpt::Status loaded = loadMeshFromMemory(bytes, format, name, mesh, &warnings);
    if (!sculpt::fuzz::checkLoad("mesh_fuzz", loaded, name, mesh, warnings)) return 0;

    // Every read runs assimp in a child process (a fork each): four encodings keep the fuzzer's pace up while
    // covering every writer (PLY both ways, with the byte swap; STL; glTF).
    const MeshEncoding encodings[] = {{MeshFormat::Ply, false, false}, {MeshFormat::Ply, true, true},
                                      {MeshFormat::Stl, true, false}, {MeshFormat::Gltf, true, false}};
    for (const MeshEncoding& encoding : encodings) {
        const std::string path = encoding.format == MeshFormat::Ply ? "out.ply" : encoding.format == MeshFormat::Stl ? "out.stl" : "out.glb";
        std::string written;
        const sculpt::Status saved = serializeMesh(path, mesh, mesh.positions, encoding, written);
        if (!saved) {
            // Positions outside float's range are the one refusal a loaded (float) mesh cannot meet.
            fail("a loaded mesh could not be saved", saved.message);
        }
        ObjMesh back;
        const sculpt::Status reread = loadMeshFromMemory(written, encoding.format, path, back);
        if (!reread) fail("a saved mesh did not load back", meshEncodingText(encoding) + ": " + reread.message);
        if (encoding.format == MeshFormat::Stl) {
            if (back.triangles.rows() != mesh.triangles.rows()) fail("STL round trip changed the triangle count", name);
            continue;
        }
        if (back.positions.rows() != mesh.positions.rows()) fail("round trip changed the vertex count", meshEncodingText(encoding));
        if (encoding.format != MeshFormat::Ply) continue;
        // Binary PLY reads back bit for bit; ASCII through assimp's fast number parser, a unit or two off in
        // float's last place (and denormals may flush to zero).
        const auto expected = mesh.positions.cast<float>().cast<double>();
        const double tolerance = encoding.binary ? 0.0 : 1e-6;
        for (Eigen::Index v = 0; v < expected.rows(); ++v)
            for (int k = 0; k < 3; ++k)
                if (std::abs(back.positions(v, k) - expected(v, k)) > tolerance * std::abs(expected(v, k)) + (encoding.binary ? 0.0 : 1e-37))
                    fail("PLY round trip changed positions or their order", meshEncodingText(encoding));
    }
    return 0;
}
