// Private to the mesh_*.cpp files that implement mesh_file.h: the helpers one of them defines and another uses.
// Not part of the io library's interface: include it from nowhere else.
#pragma once

#include <cctype>
#include <functional>
#include <string>
#include <vector>

#include "io/mesh_file.h"

struct aiScene;

namespace sculpt::io::detail {

// --- What the writers share (mesh_file.cpp) ------------------------------------------------------------------

// The per-vertex attributes a PLY or glTF save writes besides positions and normals.
struct SaveAttributes {
    Texcoords texcoords;          // #V rows when writeTexcoords
    bool writeTexcoords = false;
    VertexColors colours;         // 0 or #V rows (RGBA in [0, 1])
    std::vector<std::vector<int>> primitives;  // glTF: primitiveGroups(mesh)
};

// Vertex normals for a save: the file's where no adjacent vertex moved, recomputed elsewhere.
VertexNormals saveNormals(const ObjMesh& mesh, const Positions& deformed);

// --- PLY (mesh_ply.cpp) --------------------------------------------------------------------------------------

// What a PLY header says, for the encoding, for warnings about what assimp does not read, and to check that the
// body holds every element it declares (assimp fills a short ASCII body with copies of the last face read).
struct PlyProperty {
    int size = 0;       // bytes of a scalar, or of a list's items
    int countSize = 0;  // bytes of a list's count; 0 for a scalar
};
struct PlyElement {
    std::string name;
    long long count = 0;
    std::vector<PlyProperty> properties;
};
struct PlyHeader {
    MeshEncoding encoding{MeshFormat::Ply, false, false};
    std::vector<std::string> notes;  // not kept / changed, without the file name
    std::vector<PlyElement> elements;
    size_t bodyStart = 0;            // offset of the first byte after the end_header line
};

// Reads a PLY header (format, elements, properties) into header, with notes on what assimp does not keep.
Status parsePlyHeader(const std::string& bytes, const std::string& name, PlyHeader& header);

// Checks the body holds every element the header declares; names the element the file ends in.
Status checkPlyBody(const std::string& bytes, const std::string& name, const PlyHeader& header);

// The bytes of a PLY file of mesh at deformed in encoding (our writer, not assimp's).
std::string writePly(const ObjMesh& mesh, const Positions& deformed, const MeshEncoding& encoding,
                     const SaveAttributes& attributes);

// --- STL (mesh_stl.cpp) --------------------------------------------------------------------------------------

// The offset of the first byte of bytes that is not white space (bytes.size() if none).
inline size_t firstNonBlank(const std::string& bytes) {
    size_t start = 0;
    while (start < bytes.size() && std::isspace(static_cast<unsigned char>(bytes[start]))) ++start;
    return start;
}

// Decides binary or ASCII STL from the file's structure, mending a binary one's facet count into mended.
Status checkStl(const std::string& bytes, const std::string& name, MeshEncoding& encoding, std::string& mended,
                std::vector<std::string>& notes);

// Fills scene with one mesh of separate facets, each corner carrying its facet's normal, for assimp's STL writer.
void buildStlScene(const ObjMesh& mesh, const Positions& deformed, aiScene& scene);

// --- Reading through the libraries (mesh_import.cpp) ---------------------------------------------------------

// The library part of a load, run in the reader process: the mesh without triangles, with the library's notes.
Status readInThisProcess(const std::string& bytes, const std::string* path, const char* hint, MeshFormat format,
                         const MeshEncoding& encoding, const std::string& name, const std::function<void(float)>& report,
                         ObjMesh& mesh, std::vector<std::string>& notes);

// The caller's part of a load: STL welding, the unused-vertex note, triangulation and the consistency check.
Status finishMesh(ObjMesh& mesh, const MeshEncoding& encoding, const std::string& name, std::vector<std::string>& notes);

// --- The reader process (mesh_reader_process.cpp) ------------------------------------------------------------

// Reads bytes (a glTF's buffers named as files are looked up beside path, when given) in a reader process.
Status importInReaderProcess(const std::string& bytes, const std::string* path, MeshFormat format, const std::string& name,
                             ObjMesh& out, std::vector<std::string>* warnings, ObjLoadProgress* progress);

// --- glTF writing (mesh_gltf_write.cpp) ----------------------------------------------------------------------

// The vertices of each glTF primitive: one list per group when groups are apart and consecutive, else one list.
std::vector<std::vector<int>> primitiveGroups(const ObjMesh& mesh);

// The bytes of a .gltf or .glb file of mesh at deformed (tinygltf, not assimp).
std::string writeGltf(const ObjMesh& mesh, const Positions& deformed, const MeshEncoding& encoding,
                      const SaveAttributes& attributes);

}  // namespace sculpt::io::detail
