// STL: telling binary from ASCII before assimp reads a file (checkStl), and the scene assimp's STL writer writes.
#include "io/mesh_file_internal.h"

#include <assimp/scene.h>

#include <cstdint>
#include <cstring>

#include <Eigen/Geometry>

namespace sculpt::io::detail {

// Binary or ASCII, decided by the file's structure as other loaders do, not by its first word: many binary
// writers start the 80-byte header with "solid". In order:
//   1. 84 + 50 x the header's facet count bytes exactly: binary;
//   2. "solid" and text throughout (no NUL byte, which the ASCII grammar cannot hold): ASCII;
//   3. at least 84 bytes, more than the count says: binary, the whole facets the size holds read (fixed, a
//      copy of the bytes with the count mended, into `mended`), and a note says so (a writer that left the
//      count 0, or trailing bytes);
//   4. fewer bytes than the count needs: refused as cut short (a partial surface saved back would lose the rest).
Status checkStl(const std::string& bytes, const std::string& name, MeshEncoding& encoding, std::string& mended,
                std::vector<std::string>& notes) {
    uint32_t count = 0;
    if (bytes.size() >= 84) std::memcpy(&count, bytes.data() + 80, 4);
    const uint64_t declared = 84 + 50ull * count;
    encoding = {MeshFormat::Stl, bytes.size() >= 84 && bytes.size() == declared, false};
    if (encoding.binary) return Status::success();
    const size_t start = firstNonBlank(bytes);
    // ASCII STL is text: no NUL byte anywhere. A binary STL nearly always holds one (each facet's 2 attribute
    // bytes, every zero float), whatever its header says.
    if (bytes.compare(start, 5, "solid") == 0 && (bytes.size() < 84 || std::memchr(bytes.data(), 0, bytes.size()) == nullptr))
        return Status::success();
    if (bytes.size() < 84)
        return Status::error(name + ": not an STL file (neither \"solid\" text nor a binary file of 84 + 50 x facets bytes)");
    if (declared > bytes.size())
        return Status::error(name + ": the file ends early: a binary STL whose header declares " + std::to_string(count) +
                             " facets has " + std::to_string(declared) + " bytes, this one " + std::to_string(bytes.size()) +
                             " (truncated?)");
    const uint64_t facets = (bytes.size() - 84) / 50;
    const uint64_t trailing = (bytes.size() - 84) % 50;
    if (facets > UINT32_MAX) return Status::error(name + ": more facets than a binary STL can number");
    encoding.binary = true;
    mended = bytes.substr(0, 84 + 50 * facets);
    const uint32_t held = static_cast<uint32_t>(facets);
    std::memcpy(mended.data() + 80, &held, 4);
    std::string note = "the header declares " + std::to_string(count) + " facet(s) but the file holds " + std::to_string(facets) +
                       ": all " + std::to_string(facets) + " are read";
    if (trailing > 0) note += " (" + std::to_string(trailing) + " trailing byte(s) after them are not a facet, ignored)";
    notes.push_back(note);
    return Status::success();
}

// The scene assimp's STL writer writes: one mesh of separate facets, each corner carrying its facet's normal
// (the writer averages the corners' normals into the facet normal).
void buildStlScene(const ObjMesh& mesh, const Positions& deformed, aiScene& scene) {
    scene.mRootNode = new aiNode("root");
    scene.mMaterials = new aiMaterial*[1]{new aiMaterial()};
    scene.mNumMaterials = 1;
    scene.mMeshes = new aiMesh*[1]{new aiMesh()};
    scene.mNumMeshes = 1;
    scene.mRootNode->mMeshes = new unsigned[1]{0};
    scene.mRootNode->mNumMeshes = 1;
    aiMesh& out = *scene.mMeshes[0];
    out.mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
    const size_t triangles = static_cast<size_t>(mesh.triangles.rows());
    out.mNumVertices = static_cast<unsigned>(3 * triangles);
    out.mVertices = new aiVector3D[3 * triangles];
    out.mNormals = new aiVector3D[3 * triangles];
    out.mNumFaces = static_cast<unsigned>(triangles);
    out.mFaces = new aiFace[triangles];
    for (size_t t = 0; t < triangles; ++t) {
        const Eigen::Index row = static_cast<Eigen::Index>(t);
        const Eigen::Vector3d a = deformed.row(mesh.triangles(row, 0)), b = deformed.row(mesh.triangles(row, 1)),
                              c = deformed.row(mesh.triangles(row, 2));
        Eigen::Vector3d n = (b - a).cross(c - a);
        n = n.norm() > 0.0 ? n.normalized() : Eigen::Vector3d::Zero();
        const unsigned at = static_cast<unsigned>(3 * t);
        for (unsigned k = 0; k < 3; ++k) {
            const Eigen::Index v = mesh.triangles(row, static_cast<Eigen::Index>(k));
            out.mVertices[at + k] = aiVector3D(static_cast<float>(deformed(v, 0)), static_cast<float>(deformed(v, 1)),
                                               static_cast<float>(deformed(v, 2)));
            out.mNormals[at + k] = aiVector3D(static_cast<float>(n.x()), static_cast<float>(n.y()), static_cast<float>(n.z()));
        }
        out.mFaces[t].mNumIndices = 3;
        out.mFaces[t].mIndices = new unsigned[3]{at, at + 1, at + 2};
    }
}

}  // namespace sculpt::io::detail
