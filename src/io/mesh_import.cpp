// The library part of a PLY, STL, glTF or OFF load (readInThisProcess, assimp's scene as an ObjMesh) and finishMesh.
#include "io/mesh_file_internal.h"

#include <assimp/DefaultLogger.hpp>
#include <assimp/LogStream.hpp>
#include <assimp/Importer.hpp>
#include <assimp/ProgressHandler.hpp>
#include <assimp/scene.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "io/gltf_read.h"
#include "io/huge_pages.h"
#include "io/load_checks.h"
#include "io/mesh_weld.h"
#include "io/off_mesh.h"

namespace sculpt::io {

namespace {

// Forwards assimp's progress (0..1) to the caller's process, at most every 1%.
class ProgressForwarder : public Assimp::ProgressHandler {
public:
    explicit ProgressForwarder(const std::function<void(float)>& report) : report_(report) {}
    bool Update(float percentage) override {
        if (percentage >= last_ + 0.01f) {
            last_ = percentage;
            report_(std::min(0.9f, 0.9f * percentage));
        }
        return true;
    }

private:
    const std::function<void(float)>& report_;
    float last_ = 0.0f;
};

// assimp's warnings and errors during one import (it skips bad indices, unknown chunks... and only logs it),
// collected so the load can pass them on: nothing is dropped without a word.
class CollectedLog : public Assimp::LogStream {
public:
    void write(const char* message) override {
        std::string line(message);
        // "Warn,  T0: text\n" -> "text"
        if (const size_t colon = line.find(": "); colon != std::string::npos && colon < 16) line.erase(0, colon + 2);
        while (!line.empty() && (line.back() == '\n' || line.back() == '\r')) line.pop_back();
        if (line.empty()) return;
        if (std::find(lines.begin(), lines.end(), line) == lines.end()) lines.push_back(line);
    }
    std::vector<std::string> lines;
};

std::string vectorText(double x, double y, double z) {
    std::ostringstream s;
    s << "(" << x << ", " << y << ", " << z << ")";
    return s.str();
}

// One mesh of the scene placed by a node: its vertices go through transform.
struct Placement {
    const aiMesh* mesh = nullptr;
    aiMatrix4x4 transform;
    std::string name;
};

Status collectPlacements(const aiScene& scene, const aiNode& node, const aiMatrix4x4& parent, int depth,
                         std::vector<Placement>& out, const std::string& name) {
    if (depth > 256) return Status::error(name + ": the node hierarchy is deeper than 256 levels (a cycle?)");
    const aiMatrix4x4 transform = parent * node.mTransformation;
    for (unsigned i = 0; i < node.mNumMeshes; ++i) {
        if (node.mMeshes[i] >= scene.mNumMeshes)
            return Status::error(name + ": node '" + node.mName.C_Str() + "' names a mesh that does not exist");
        const aiMesh* mesh = scene.mMeshes[node.mMeshes[i]];
        std::string meshName = mesh->mName.length > 0 ? mesh->mName.C_Str() : node.mName.C_Str();
        if (meshName.empty()) meshName = "mesh " + std::to_string(node.mMeshes[i]);
        out.push_back({mesh, transform, meshName});
    }
    for (unsigned c = 0; c < node.mNumChildren; ++c)
        if (node.mChildren[c])
            if (Status s = collectPlacements(scene, *node.mChildren[c], transform, depth + 1, out, name); !s) return s;
    return Status::success();
}

// The scene assimp read, as an ObjMesh (see mesh_file.h for what is kept).
Status sceneToMesh(const aiScene& scene, const MeshEncoding& encoding, const std::string& name, ObjMesh& out,
                   std::vector<std::string>& notes) {
    if (!scene.mRootNode) return Status::error(name + ": the file has no scene to place its meshes");
    std::vector<Placement> placements;
    if (Status s = collectPlacements(scene, *scene.mRootNode, aiMatrix4x4(), 0, placements, name); !s) return s;
    std::vector<int> uses(scene.mNumMeshes, 0);
    for (const Placement& p : placements)
        for (unsigned m = 0; m < scene.mNumMeshes; ++m)
            if (scene.mMeshes[m] == p.mesh) ++uses[m];
    const long long unplaced = std::count(uses.begin(), uses.end(), 0);
    if (unplaced > 0)
        notes.push_back(std::to_string(unplaced) + " mesh(es) no node of the scene places are not kept");
    if (std::any_of(uses.begin(), uses.end(), [](int u) { return u > 1; }))
        notes.push_back("meshes placed by several nodes are copied once per node");

    size_t vertexTotal = 0, surfaceFaces = 0, cornerTotal = 0;
    for (const Placement& p : placements) {
        vertexTotal += p.mesh->mNumVertices;
        for (unsigned f = 0; f < p.mesh->mNumFaces; ++f) {
            surfaceFaces += p.mesh->mFaces[f].mNumIndices >= 3;
            cornerTotal += p.mesh->mFaces[f].mNumIndices;
        }
    }
    // Said first: a point cloud's points are not checked (assimp misreads some, such as CGAL's oni.ply).
    if (surfaceFaces == 0) {
        size_t lines = 0;
        for (const Placement& p : placements)
            for (unsigned f = 0; f < p.mesh->mNumFaces; ++f) lines += p.mesh->mFaces[f].mNumIndices == 2;
        return noSurfaceError(name, lines > 0, vertexTotal);
    }
    if (Status s = checkVertexTotal(name, vertexTotal); !s) return s;

    ObjMesh mesh;
    mesh.groupNames = {std::string()};
    // Sized once (a 1M-vertex scan has 2M faces): the loops below write each face's entries in place.
    reserveWithHugePages(mesh.faceStart, surfaceFaces + 1);
    reserveWithHugePages(mesh.faceGroup, surfaceFaces);
    reserveWithHugePages(mesh.faceMaterial, surfaceFaces);
    reserveWithHugePages(mesh.cornerVertex, cornerTotal);
    reserveWithHugePages(mesh.cornerTexcoord, cornerTotal);
    reserveWithHugePages(mesh.cornerNormal, cornerTotal);
    mesh.faceStart.resize(surfaceFaces + 1);
    mesh.faceGroup.resize(surfaceFaces);
    mesh.faceMaterial.assign(surfaceFaces, -1);
    mesh.cornerVertex.resize(cornerTotal);
    mesh.cornerTexcoord.resize(cornerTotal);
    mesh.cornerNormal.assign(cornerTotal, -1);
    mesh.faceStart[0] = 0;
    size_t faceCount = 0, cornerCount = 0;
    mesh.positions.resize(static_cast<Eigen::Index>(vertexTotal), 3);
    adviseHugePages(mesh.positions.data(), static_cast<size_t>(mesh.positions.size()) * sizeof(double));
    bool anyColors = false, anyNormals = false, anyTexcoords = false;
    int texcoordColumns = 2;
    for (const Placement& p : placements) {
        anyColors |= p.mesh->HasVertexColors(0);
        anyNormals |= p.mesh->HasNormals();
        if (p.mesh->HasTextureCoords(0)) {
            anyTexcoords = true;
            texcoordColumns = std::max(texcoordColumns, static_cast<int>(std::min(3u, std::max(2u, p.mesh->mNumUVComponents[0]))));
        }
    }
    const bool stl = encoding.format == MeshFormat::Stl;
    if (anyColors && !stl) mesh.vertexColors = VertexColors::Ones(static_cast<Eigen::Index>(vertexTotal), 4);
    if (anyNormals && !stl) mesh.vertexNormals = VertexNormals::Zero(static_cast<Eigen::Index>(vertexTotal), 3);
    if (anyTexcoords) mesh.texcoords = Texcoords::Zero(static_cast<Eigen::Index>(vertexTotal), texcoordColumns);

    long long skippedPrimitives = 0, extraSets = 0, bones = 0, morphs = 0;
    int base = 0;
    for (size_t pi = 0; pi < placements.size(); ++pi) {
        const Placement& p = placements[pi];
        const aiMesh& m = *p.mesh;
        aiMatrix3x3 normalTransform(p.transform);
        if (!(std::abs(normalTransform.Determinant()) > 0.0f) || !std::isfinite(normalTransform.Determinant()))
            return Status::error(name + ": the node transform of " + p.name + " is singular or not finite");
        normalTransform.Inverse().Transpose();
        const bool identity = p.transform.IsIdentity();  // PLY and STL always, glTF mostly: no product per vertex
        for (unsigned v = 0; v < m.mNumVertices; ++v) {
            const aiVector3D position = identity ? m.mVertices[v] : p.transform * m.mVertices[v];
            const Eigen::Index row = base + static_cast<Eigen::Index>(v);
            mesh.positions.row(row) << position.x, position.y, position.z;
            if (!mesh.positions.row(row).allFinite())
                return Status::error(name + ": vertex " + std::to_string(row) + " of " +
                                     (stl ? std::string("facet ") + std::to_string(row / 3) : p.name) +
                                     " has a non-finite coordinate " +
                                     vectorText(position.x, position.y, position.z));
            if (mesh.vertexColors.rows() > 0 && m.HasVertexColors(0)) {
                const aiColor4D c = m.mColors[0][v];
                mesh.vertexColors.row(row) << c.r, c.g, c.b, c.a;
            }
            if (mesh.vertexNormals.rows() > 0 && m.HasNormals()) {
                aiVector3D n = identity ? m.mNormals[v] : normalTransform * m.mNormals[v];
                if (!identity && n.Length() > 0.0f) n.Normalize();
                mesh.vertexNormals.row(row) << n.x, n.y, n.z;
            }
            if (m.HasTextureCoords(0))
                for (int k = 0; k < texcoordColumns; ++k)
                    mesh.texcoords(row, k) = k < static_cast<int>(m.mNumUVComponents[0]) ? m.mTextureCoords[0][v][static_cast<unsigned>(k)] : 0.0;
        }
        for (unsigned s = 1; s < AI_MAX_NUMBER_OF_COLOR_SETS; ++s) extraSets += m.HasVertexColors(s);
        for (unsigned s = 1; s < AI_MAX_NUMBER_OF_TEXTURECOORDS; ++s) extraSets += m.HasTextureCoords(s);
        bones += m.mNumBones;
        morphs += m.mNumAnimMeshes;
        int group = 0;
        if (placements.size() > 1 || stl) {
            mesh.groupNames.push_back(p.name);
            group = static_cast<int>(mesh.groupNames.size()) - 1;
        }
        const bool texcoords = m.HasTextureCoords(0);
        for (unsigned f = 0; f < m.mNumFaces; ++f) {
            const aiFace& face = m.mFaces[f];
            if (face.mNumIndices < 3) {
                ++skippedPrimitives;
                continue;
            }
            for (unsigned c = 0; c < face.mNumIndices; ++c) {
                if (face.mIndices[c] >= m.mNumVertices)
                    return Status::error(name + ": face " + std::to_string(f) + " of " + p.name + " uses vertex " +
                                         std::to_string(face.mIndices[c]) + " of " + std::to_string(m.mNumVertices));
                const int vertex = base + static_cast<int>(face.mIndices[c]);
                mesh.cornerVertex[cornerCount] = vertex;
                mesh.cornerTexcoord[cornerCount] = texcoords ? vertex : -1;
                ++cornerCount;
            }
            mesh.faceGroup[faceCount] = group;
            mesh.faceStart[++faceCount] = static_cast<int>(cornerCount);
        }
        base += static_cast<int>(m.mNumVertices);
    }
    // Points and lines were counted as corners above but given none.
    mesh.cornerVertex.resize(cornerCount);
    mesh.cornerTexcoord.resize(cornerCount);
    mesh.cornerNormal.resize(cornerCount);
    if (skippedPrimitives > 0)
        notes.push_back(std::to_string(skippedPrimitives) + " point or line element(s) are not kept (not a surface)");
    if (extraSets > 0) notes.push_back("only the first colour and texture coordinate sets are kept");
    if (bones > 0) notes.push_back("the skin (" + std::to_string(bones) + " bone(s)) is not kept");
    if (morphs > 0) notes.push_back(std::to_string(morphs) + " morph target(s) are not kept");
    out = std::move(mesh);
    return Status::success();
}

}  // namespace

namespace detail {

// The library part of a load, run in the reader process: a glTF through readGltfDocument (tinygltf and checked
// accessors), PLY and STL through assimp, as a mesh without triangles (sceneToMesh), with assimp's own
// warnings and errors in notes.
Status readInThisProcess(const std::string& bytes, const std::string* path, const char* hint, MeshFormat format,
                         const MeshEncoding& encoding, const std::string& name, const std::function<void(float)>& report,
                         ObjMesh& mesh, std::vector<std::string>& notes) {
    if (format == MeshFormat::Off) {
        report(0.1f);
        return readOffDocument(bytes, name, mesh, notes);
    }
    if (format == MeshFormat::Gltf) {
        // A JSON glTF's buffers may be files beside it: looked up from the file's folder.
        const std::string folder = path != nullptr ? std::filesystem::path(*path).parent_path().string() : std::string();
        report(0.1f);
        return readGltfDocument(bytes, encoding.binary, path != nullptr ? &folder : nullptr, name, mesh, notes);
    }
    CollectedLog log;
    Assimp::DefaultLogger::create("", Assimp::Logger::NORMAL, 0);
    Assimp::DefaultLogger::get()->attachStream(&log, Assimp::Logger::Warn | Assimp::Logger::Err);
    Assimp::Importer importer;
    ProgressForwarder forward(report);
    importer.SetProgressHandler(&forward);
    // PLY and STL are whole in their bytes: read from memory (a mended STL is not the file on disk).
    const aiScene* scene = importer.ReadFileFromMemory(bytes.data(), bytes.size(), 0, hint);
    importer.SetProgressHandler(nullptr);
    // The log is ours (on this stack): detached before the logger goes, which would delete attached streams.
    Assimp::DefaultLogger::get()->detachStream(&log, Assimp::Logger::Warn | Assimp::Logger::Err);
    Assimp::DefaultLogger::kill();
    const size_t kShown = 5;
    for (size_t i = 0; i < log.lines.size() && i < kShown; ++i) notes.push_back("assimp: " + log.lines[i]);
    if (log.lines.size() > kShown) notes.push_back("assimp: " + std::to_string(log.lines.size() - kShown) + " more notes");
    if (!scene) {
        std::string why = importer.GetErrorString();
        if (why.empty()) why = "assimp could not read it";
        return Status::error(name + ": not a readable " + std::string(meshFormatName(format)) + " file: " + why);
    }
    if (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE)
        return Status::error(name + ": the " + std::string(meshFormatName(format)) + " file holds no complete mesh");
    return sceneToMesh(*scene, encoding, name, mesh, notes);
}

// The part of a load that runs in the caller's process, on what sceneToMesh made (faces, no triangles yet):
// STL welding, the unused-vertex note, triangulation and the final consistency check.
Status finishMesh(ObjMesh& mesh, const MeshEncoding& encoding, const std::string& name, std::vector<std::string>& notes) {
    if (encoding.format == MeshFormat::Stl) weldCoincidentVertices(mesh);  // STL stores every facet's corners apart
    std::vector<char> used(static_cast<size_t>(mesh.positions.rows()), 0);
    for (int c : mesh.cornerVertex)
        if (c >= 0 && c < mesh.positions.rows()) used[static_cast<size_t>(c)] = 1;
    const long long unused = std::count(used.begin(), used.end(), 0);
    if (unused > 0) notes.push_back(std::to_string(unused) + " vertices are used by no face (kept, not deformed by edits of faces)");
    mesh.triangles.resize(0, 3);
    mesh.triangleFace.clear();
    mesh.loadedAs = encoding;
    // Checked before triangulating, which trusts the faces (as loadObj does, the triangles it makes are not
    // checked again).
    if (Status s = checkObjMesh(mesh); !s) return Status::error(name + ": " + s.message);
    const ObjTriangulationReport triangulation = triangulateObjFaces(mesh);
    if (triangulation.fannedFaces > 0)
        notes.push_back(std::to_string(triangulation.fannedFaces) + " face(s) could not be triangulated exactly (" +
                        triangulation.firstReason + ", face " + std::to_string(triangulation.firstFannedFace) +
                        "): drawn as a fan");
    return Status::success();
}

}  // namespace detail

}  // namespace sculpt::io
