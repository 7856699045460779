// Fuzz target for the PLY, STL, glTF and OFF readers (io/mesh_file.h) and the writers behind them.
// The format is picked from the bytes the way a misnamed file would meet it (fuzz_checks.h formatOfBytes). Any
// input either loads into a consistent mesh or fails with a message naming the file, leaving the output
// untouched; what loads must save in every encoding and load back (fuzz_checks.h roundTripBreak).
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
    std::string name;
    const MeshFormat format = sculpt::fuzz::formatOfBytes(bytes, name);
    ObjMesh mesh;
    std::vector<std::string> warnings;
    const sculpt::Status loaded = loadMeshFromMemory(bytes, format, name, mesh, &warnings);
    if (!sculpt::fuzz::checkLoad("mesh_fuzz", loaded, name, mesh, warnings)) return 0;
    // Four encodings (a fork each read) keep the fuzzer's pace up while covering every writer.
    if (const std::string broken = sculpt::fuzz::roundTripBreak(mesh); !broken.empty()) fail("a loaded mesh's save and load", broken);
    return 0;
}
