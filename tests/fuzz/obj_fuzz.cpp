// Fuzz target: any bytes either load into a consistent ObjMesh or fail with a message; whatever loads
// must serialise, unchanged to the very bytes it was read from, and the serialised text must load back to
// the same surface bit for bit (also after a deformation, and also when written from the arrays instead of
// the source text), so both writers are fuzzed through the reader.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "io/obj_mesh.h"

namespace {

[[noreturn]] void fail(const char* what, const std::string& detail) {
    std::fprintf(stderr, "obj_fuzz invariant broken: %s\n%s\n", what, detail.c_str());
    std::abort();
}

// Bitwise equality (so -0 vs 0 and every last bit count); empty matrices have null data.
template <typename Matrix>
bool sameBits(const Matrix& a, const Matrix& b) {
    return a.rows() == b.rows() && a.cols() == b.cols() &&
           (a.size() == 0 || std::memcmp(a.data(), b.data(), sizeof(double) * static_cast<size_t>(a.size())) == 0);
}

void requireSameSurface(const sculpt::io::ObjMesh& a, const sculpt::io::ObjMesh& b, const std::string& text) {
    if (a.faceStart != b.faceStart) fail("faceStart differs after a round trip", text);
    if (a.cornerVertex != b.cornerVertex) fail("corner vertices differ after a round trip", text);
    if (a.cornerTexcoord != b.cornerTexcoord) fail("corner texcoords differ after a round trip", text);
    if (!sameBits(a.texcoords, b.texcoords)) fail("texcoords differ after a round trip", text);
    if (a.faceGroup != b.faceGroup || a.groupNames != b.groupNames) fail("groups differ after a round trip", text);
    if (a.faceMaterial != b.faceMaterial || a.materialNames != b.materialNames)
        fail("materials differ after a round trip", text);
    if (a.materialLibraries != b.materialLibraries) fail("material libraries differ after a round trip", text);
    if (a.triangles != b.triangles || a.triangleFace != b.triangleFace)
        fail("triangles differ after a round trip", text);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    sculpt::io::ObjMesh mesh;
    std::vector<std::string> warnings;
    // baseDir "" : the fuzzer must never open files named by `mtllib`.
    const sculpt::Status loaded = sculpt::io::loadObjFromText(text, "fuzz.obj", "", mesh, &warnings);
    // The reader and tinyobjloader disagreeing is a bug in the reader's mirror of tinyobjloader, even where
    // the user sees a clean load or a clean error.
    const sculpt::Status agreed = sculpt::io::crossCheckObjWithTinyobj(text, "fuzz.obj");
    if (!agreed) {
        if (agreed.message.find("internal error") != std::string::npos) fail("readers disagree", agreed.message);
        fail("tinyobjloader rejected what the reader accepted", agreed.message);
    }
    if (!loaded) {
        if (loaded.message.rfind("fuzz.obj", 0) != 0) fail("error message does not name the file", loaded.message);
        if (mesh.faceStart.size() != 0 || mesh.positions.size() != 0)
            fail("out was modified on failure", loaded.message);
        return 0;
    }
    const sculpt::Status consistent = sculpt::io::checkObjMesh(mesh);
    if (!consistent) fail("loaded mesh is inconsistent", consistent.message);
    if (!mesh.positions.allFinite()) fail("loaded a non-finite position", text);

    std::string written;
    const sculpt::Status serialised = sculpt::io::serializeObj(mesh, mesh.positions, written);
    if (!serialised) fail("a loaded mesh does not serialise", serialised.message);
    if (written != text) fail("a mesh saved unchanged is not the file it was read from", written);

    // Written from the arrays (as a mesh built in code is).
    sculpt::io::ObjMesh plain = mesh;
    plain.source = nullptr;
    if (!sculpt::io::serializeObj(plain, plain.positions, written)) fail("the arrays do not serialise", "");
    sculpt::io::ObjMesh reread;
    const sculpt::Status reloaded = sculpt::io::loadObjFromText(written, "written.obj", "", reread, nullptr);
    if (!reloaded) fail("written text does not load back", reloaded.message + "\n" + written);
    if (!sameBits(mesh.positions, reread.positions)) fail("positions differ after a round trip", written);
    requireSameSurface(mesh, reread, written);

    // A deformation (halving keeps every finite value finite) must round-trip just as exactly.
    const sculpt::Positions deformed = mesh.positions * 0.5;
    if (!sculpt::io::serializeObj(mesh, deformed, written)) fail("a deformed mesh does not serialise", "");
    if (!sculpt::io::loadObjFromText(written, "deformed.obj", "", reread, nullptr))
        fail("written deformed text does not load back", written);
    if (!sameBits(deformed, reread.positions)) fail("deformed positions differ after a round trip", written);
    return 0;
}
