// PLY, STL and glTF through assimp, and the format dispatch of loadMesh/saveMesh (mesh_file.h).
//
// Why assimp (Debian's libassimp 5.2): one maintained library reads all three formats (PLY in both byte orders,
// ASCII and binary STL, glTF 2.0 and GLB), keeps PLY's vertex order and polygons, and reads vertex colours,
// normals and texture coordinates. What it does not do is done here: the checks that give a message naming what
// is wrong (before assimp sees the file), running it in a child process (isolated_call.h) where it could crash or
// hang, welding STL facets, flattening glTF node transforms, warnings for what is not kept, atomic saves (every
// writer writes into memory first), and two of the writers: PLY (writePly: assimp 5.2's binary one is broken)
// and glTF (writeGltf, through tinygltf: assimp's merges vertices). assimp writes STL.
#include "io/mesh_file.h"

#include <assimp/DefaultLogger.hpp>
#include <assimp/Exporter.hpp>
#include <assimp/LogStream.hpp>
#include <assimp/Importer.hpp>
#include <assimp/ProgressHandler.hpp>
#include <assimp/scene.h>
#include <tiny_gltf.h>

#include <algorithm>
#include <charconv>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <deque>
#include <filesystem>
#include <functional>
#include <limits>
#include <memory>
#include <mutex>
#include <new>
#include <sstream>
#include <unordered_map>

#include <Eigen/Geometry>

#include "core/vertex_normals.h"
#include "io/atomic_file.h"
#include "io/gltf_read.h"
#include "io/huge_pages.h"
#include "io/isolated_call.h"
#include "io/load_checks.h"
#include "io/mesh_weld.h"
#include "io/off_mesh.h"
#include "io/obj_scan.h"
#include "io/obj_refine.h"
#include "io/script_json.h"

namespace sculpt::io {

namespace {

// --- Reading -------------------------------------------------------------------------------------------------

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

// Bytes of a PLY scalar type, 0 for an unknown name.
int plyTypeSize(const std::string& type) {
    if (type == "char" || type == "uchar" || type == "int8" || type == "uint8") return 1;
    if (type == "short" || type == "ushort" || type == "int16" || type == "uint16") return 2;
    if (type == "int" || type == "uint" || type == "float" || type == "int32" || type == "uint32" || type == "float32") return 4;
    if (type == "double" || type == "float64") return 8;
    return 0;
}

// The body holds every element the header declares: in ASCII one line per element item, in binary the sizes
// the properties give (walking the lists). Names the element the file ends in.
Status checkPlyBody(const std::string& bytes, const std::string& name, const PlyHeader& header) {
    const auto ended = [&](const PlyElement& e, long long item) {
        return Status::error(name + ": the file ends early: its header declares " + std::to_string(e.count) + " " + e.name +
                             " element(s), and it ends at " + e.name + " " + std::to_string(item) + " (truncated?)");
    };
    size_t at = header.bodyStart;
    if (!header.encoding.binary) {
        // One line per item, with a value per scalar and a count plus that many values per list.
        const auto isBlank = [](char c) { return c == ' ' || c == '\t' || c == '\r'; };
        std::vector<size_t> values;
        for (const PlyElement& e : header.elements)
            for (long long item = 0; item < e.count; ++item) {
                while (at < bytes.size() && (bytes[at] == '\n' || isBlank(bytes[at]))) ++at;
                if (at >= bytes.size()) return ended(e, item);
                size_t lineEnd = bytes.find('\n', at);
                if (lineEnd == std::string::npos) lineEnd = bytes.size();
                values.clear();  // where each value of the line starts
                for (size_t i = at; i < lineEnd;) {
                    while (i < lineEnd && isBlank(bytes[i])) ++i;
                    const size_t start = i;
                    while (i < lineEnd && !isBlank(bytes[i])) ++i;
                    if (i > start) values.push_back(start);
                }
                size_t used = 0;
                bool complete = true;
                for (const PlyProperty& p : e.properties) {
                    if (p.countSize == 0) {
                        complete = used < values.size();
                        ++used;
                    } else {
                        long long count = -1;
                        if (used < values.size()) count = std::strtoll(bytes.c_str() + values[used], nullptr, 10);
                        complete = count >= 0 && values.size() - used - 1 >= static_cast<size_t>(count);
                        used += 1 + (complete ? static_cast<size_t>(count) : 0);
                    }
                    if (!complete) break;
                }
                if (!complete) {
                    if (lineEnd >= bytes.size()) return ended(e, item);
                    return Status::error(name + ": " + e.name + " " + std::to_string(item) + " has fewer values than the PLY header declares");
                }
                at = lineEnd;
            }
        return Status::success();
    }
    for (const PlyElement& e : header.elements)
        for (long long item = 0; item < e.count; ++item)
            for (const PlyProperty& p : e.properties) {
                if (p.countSize == 0) {
                    if (bytes.size() - at < static_cast<size_t>(p.size)) return ended(e, item);
                    at += static_cast<size_t>(p.size);
                    continue;
                }
                if (bytes.size() - at < static_cast<size_t>(p.countSize)) return ended(e, item);
                unsigned char raw[8] = {0};
                std::memcpy(raw, bytes.data() + at, static_cast<size_t>(p.countSize));
                if (header.encoding.bigEndian) std::reverse(raw, raw + p.countSize);
                uint64_t count = 0;
                for (int k = p.countSize - 1; k >= 0; --k) count = (count << 8) | raw[k];
                if (p.countSize == 4 && (count & 0x80000000u)) count = 0;  // a negative int count: assimp's to judge
                at += static_cast<size_t>(p.countSize);
                if ((bytes.size() - at) / static_cast<size_t>(p.size) < count) return ended(e, item);
                at += count * static_cast<size_t>(p.size);
            }
    return Status::success();
}

// The vertex properties assimp's PLY reader uses (positions, normals, colours, texture coordinates).
bool plyVertexPropertyKept(const std::string& name) {
    static const char* const kept[] = {"x", "y", "z", "nx", "ny", "nz", "red", "green", "blue", "alpha",
                                       "r", "g", "b", "a", "diffuse_red", "diffuse_green", "diffuse_blue",
                                       "diffuse_alpha", "s", "t", "u", "v", "texture_s", "texture_t",
                                       "texture_u", "texture_v", "tx", "ty"};
    for (const char* k : kept)
        if (name == k) return true;
    return false;
}

Status parsePlyHeader(const std::string& bytes, const std::string& name, PlyHeader& header) {
    if (bytes.compare(0, 3, "ply") != 0 || bytes.size() < 4 || (bytes[3] != '\n' && bytes[3] != '\r'))
        return Status::error(name + ": not a PLY file (it does not start with \"ply\")");
    const size_t end = bytes.find("end_header");
    if (end == std::string::npos) return Status::error(name + ": the PLY header has no end_header line");
    std::istringstream lines(bytes.substr(0, end));
    std::string line, element;
    bool haveFormat = false;
    while (std::getline(lines, line)) {
        std::istringstream words(line);
        std::string keyword;
        words >> keyword;
        if (keyword == "format") {
            std::string kind;
            words >> kind;
            if (kind == "ascii") {
                header.encoding.binary = false;
            } else if (kind == "binary_little_endian") {
                header.encoding.binary = true;
            } else if (kind == "binary_big_endian") {
                header.encoding.binary = true;
                header.encoding.bigEndian = true;
            } else {
                return Status::error(name + ": unknown PLY format '" + kind +
                                     "' (expected ascii, binary_little_endian or binary_big_endian)");
            }
            haveFormat = true;
        } else if (keyword == "element") {
            long long count = -1;
            words >> element >> count;
            if (element.empty() || count < 0)
                return Status::error(name + ": the PLY header line '" + line + "' does not name an element and its count");
            header.elements.push_back({element, count, {}});
            if (element != "vertex" && element != "face" && count > 0)
                header.notes.push_back("PLY element '" + element + "' (" + std::to_string(count) +
                                       ") is not kept: only vertices and faces are read");
        } else if (keyword == "property") {
            std::string type, propertyName;
            words >> type;
            if (header.elements.empty())
                return Status::error(name + ": the PLY header has a property before any element");
            PlyProperty property;
            if (type == "list") {
                std::string countType, itemType;
                words >> countType >> itemType >> propertyName;
                property.countSize = plyTypeSize(countType);
                property.size = plyTypeSize(itemType);
                if (property.countSize == 0 || property.size == 0 || property.countSize == 8)
                    return Status::error(name + ": the PLY header line '" + line + "' has no valid list types");
                if (element == "face" && propertyName != "vertex_indices" && propertyName != "vertex_index")
                    header.notes.push_back("face property '" + propertyName + "' is not kept");
                if (element == "vertex") header.notes.push_back("vertex list property '" + propertyName + "' is not kept");
            } else {
                words >> propertyName;
                property.size = plyTypeSize(type);
                if (property.size == 0)
                    return Status::error(name + ": the PLY header line '" + line + "' has an unknown type '" + type + "'");
                if (element == "vertex" && !plyVertexPropertyKept(propertyName))
                    header.notes.push_back("vertex property '" + propertyName + "' is not kept");
                if (element == "vertex" && (propertyName == "x" || propertyName == "y" || propertyName == "z") &&
                    (type == "double" || type == "float64"))
                    header.notes.push_back("positions are stored as double and read in single precision");
                if (element == "face") header.notes.push_back("face property '" + propertyName + "' is not kept");
            }
            if (propertyName.empty()) return Status::error(name + ": the PLY header line '" + line + "' names no property");
            header.elements.back().properties.push_back(property);
        }
    }
    if (!haveFormat) return Status::error(name + ": the PLY header has no format line");
    const size_t lineEnd = bytes.find('\n', end);
    header.bodyStart = lineEnd == std::string::npos ? bytes.size() : lineEnd + 1;
    std::sort(header.notes.begin(), header.notes.end());
    header.notes.erase(std::unique(header.notes.begin(), header.notes.end()), header.notes.end());
    return Status::success();
}

// The offset of the first byte of bytes that is not white space (bytes.size() if none).
size_t firstNonBlank(const std::string& bytes) {
    size_t start = 0;
    while (start < bytes.size() && std::isspace(static_cast<unsigned char>(bytes[start]))) ++start;
    return start;
}

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

// A glTF file is binary (GLB: "glTF", a version and its length) or a JSON object, whatever its extension says.
Status checkGltf(const std::string& bytes, const std::string& name, bool binary) {
    if (binary) {
        uint32_t length = 0;
        if (bytes.size() >= 12) std::memcpy(&length, bytes.data() + 8, 4);
        if (bytes.size() < 12 || length > bytes.size())
            return Status::error(name + ": the file ends early: its GLB header declares " + std::to_string(length) +
                                 " bytes, the file has " + std::to_string(bytes.size()) + " (truncated?)");
        return Status::success();
    }
    const size_t start = firstNonBlank(bytes);
    if (start >= bytes.size() || bytes[start] != '{')
        return Status::error(name + ": not a glTF file (neither a binary GLB, which starts with \"glTF\", nor JSON)");
    return Status::success();
}

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

// How PayloadWriter::indices sent an array.
constexpr uint8_t kElementwise = 0, kOneValue = 1, kSameAsOther = 2;

// What the reader process sends back: its verdict, its notes and the mesh without triangles. Plain bytes in
// this program's own layout (both ends run the same binary). The writer and the reader share one list of the
// fields (payloadFields), so the two directions cannot drift apart.
// PayloadWriter builds the payload as pieces for IsolatedChannel::result: the small fields copied here, each
// large array referenced where it lies (the caller copies it out of the reader's memory once, with no copy
// here). The arrays referenced must outlive the result() call.
class PayloadWriter {
public:
    template <typename T>
    bool pod(const T& value) {
        raw(&value, sizeof value);
        return true;
    }
    template <typename T>
    bool array(const std::vector<T>& v) {
        pod(static_cast<uint64_t>(v.size()));
        bytes(v.data(), v.size() * sizeof(T));
        return true;
    }
    // An index array that is often one value throughout (PLY's corner normals, a single group) or a copy of
    // another (per-vertex texture coordinates: cornerTexcoord = cornerVertex): sent as that, not element by element.
    bool indices(const std::vector<int>& v, const std::vector<int>& likely) {
        if (v == likely) return pod(kSameAsOther) && pod(static_cast<uint64_t>(v.size()));
        if (!v.empty() && std::all_of(v.begin(), v.end(), [&](int i) { return i == v[0]; }))
            return pod(kOneValue) && pod(static_cast<uint64_t>(v.size())) && pod(v[0]);
        return pod(kElementwise) && array(v);
    }
    bool text(const std::string& s) {
        pod(static_cast<uint64_t>(s.size()));
        raw(s.data(), s.size());
        return true;
    }
    bool texts(const std::vector<std::string>& list) {
        pod(static_cast<uint64_t>(list.size()));
        for (const std::string& s : list) text(s);
        return true;
    }
    template <typename Matrix>
    bool matrix(const Matrix& m) {
        pod(static_cast<int64_t>(m.rows()));
        pod(static_cast<int64_t>(m.cols()));
        pod(static_cast<uint64_t>(m.size()));
        bytes(m.data(), static_cast<size_t>(m.size()) * sizeof(typename Matrix::Scalar));
        return true;
    }
    const std::vector<IsolatedPiece>& pieces() {
        seal();
        return pieces_;
    }

private:
    void raw(const void* data, size_t size) {
        if (!open_) small_.emplace_back();
        open_ = true;
        small_.back().append(static_cast<const char*>(data), size);
    }
    void bytes(const void* data, size_t size) {
        if (size < 65536) return raw(data, size);
        seal();
        pieces_.push_back({data, size});
    }
    void seal() {
        if (open_) pieces_.push_back({small_.back().data(), small_.back().size()});
        open_ = false;
    }
    std::deque<std::string> small_;  // a deque: a sealed string is never moved by the ones added after it
    std::vector<IsolatedPiece> pieces_;
    bool open_ = false;
};

class PayloadReader {
public:
    explicit PayloadReader(const std::string& bytes) : bytes_(bytes) {}
    template <typename T>
    bool pod(T& value) {
        if (bytes_.size() - at_ < sizeof value) return false;
        std::memcpy(&value, bytes_.data() + at_, sizeof value);
        at_ += sizeof value;
        return true;
    }
    template <typename T>
    bool array(std::vector<T>& out) {
        uint64_t count = 0;
        if (!pod(count) || count > (bytes_.size() - at_) / sizeof(T)) return false;
        reserveWithHugePages(out, count);
        out.resize(count);
        if (count > 0) std::memcpy(out.data(), bytes_.data() + at_, count * sizeof(T));
        at_ += count * sizeof(T);
        return true;
    }
    bool indices(std::vector<int>& v, const std::vector<int>& likely) {
        uint8_t how = 0;
        uint64_t count = 0;
        int value = 0;
        if (!pod(how)) return false;
        if (how == kElementwise) return array(v);
        if (how == kSameAsOther) {
            if (!pod(count) || count != likely.size()) return false;
            reserveWithHugePages(v, count);
            v.assign(likely.begin(), likely.end());
            return true;
        }
        // A count no bigger than the payload, as for arrays: a damaged payload never asks for unbounded memory.
        if (how != kOneValue || !pod(count) || count > bytes_.size() || !pod(value)) return false;
        reserveWithHugePages(v, count);
        v.assign(count, value);
        return true;
    }
    bool text(std::string& s) {
        std::vector<char> chars;
        if (!array(chars)) return false;
        s.assign(chars.begin(), chars.end());
        return true;
    }
    bool texts(std::vector<std::string>& list) {
        uint64_t count = 0;
        if (!pod(count) || count > bytes_.size() - at_) return false;
        list.resize(count);
        for (std::string& s : list)
            if (!text(s)) return false;
        return true;
    }
    template <typename Matrix>
    bool matrix(Matrix& m) {
        using Scalar = typename Matrix::Scalar;
        int64_t rows = 0, cols = 0;
        uint64_t count = 0;
        if (!pod(rows) || !pod(cols) || !pod(count) || rows < 0 || cols < 0 ||
            static_cast<uint64_t>(rows) * static_cast<uint64_t>(cols) != count || count > (bytes_.size() - at_) / sizeof(Scalar))
            return false;
        constexpr int64_t fixedCols = Matrix::ColsAtCompileTime;  // Eigen::Dynamic (-1) when not fixed
        if (fixedCols != Eigen::Dynamic && cols != fixedCols && rows > 0) return false;
        m.resize(rows, fixedCols != Eigen::Dynamic ? fixedCols : cols);
        adviseHugePages(m.data(), count * sizeof(Scalar));
        if (count > 0) std::memcpy(m.data(), bytes_.data() + at_, count * sizeof(Scalar));
        at_ += count * sizeof(Scalar);
        return true;
    }
    bool done() const { return at_ == bytes_.size(); }

private:
    const std::string& bytes_;
    size_t at_ = 0;
};

// The "likely" array of an index array that is expected to be one value throughout, or given element by element.
// (Each likely array comes earlier in payloadFields than the array it may equal: the reader has it by then.)
const std::vector<int> kNoIndices;

// The payload after the verdict and notes, in order (Mesh: ObjMesh to read into, const ObjMesh to write).
template <typename Channel, typename Mesh>
bool payloadFields(Channel& c, Mesh& mesh) {
    return c.matrix(mesh.positions) && c.array(mesh.faceStart) && c.array(mesh.cornerVertex) &&
           c.indices(mesh.cornerTexcoord, mesh.cornerVertex) && c.indices(mesh.cornerNormal, mesh.cornerTexcoord) &&
           c.matrix(mesh.texcoords) && c.indices(mesh.faceGroup, kNoIndices) && c.texts(mesh.groupNames) &&
           c.indices(mesh.faceMaterial, kNoIndices) &&
           c.texts(mesh.materialNames) && c.matrix(mesh.vertexColors) && c.matrix(mesh.vertexNormals);
}

// The whole payload into w (whose pieces reference mesh's arrays).
void encodePayload(const Status& status, const std::vector<std::string>& notes, const ObjMesh& mesh, PayloadWriter& w) {
    w.pod(static_cast<uint8_t>(status.ok));
    w.text(status.message);
    w.texts(notes);
    payloadFields(w, mesh);
}

bool decodePayload(const std::string& bytes, Status& status, std::vector<std::string>& notes, ObjMesh& mesh) {
    PayloadReader r(bytes);
    uint8_t ok = 0;
    const bool read = r.pod(ok) && r.text(status.message) && r.texts(notes) && payloadFields(r, mesh) && r.done();
    status.ok = ok != 0;
    return read;
}

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

Status finishImport(const Status& status, const std::vector<std::string>& readerNotes, ObjMesh& mesh,
                    const MeshEncoding& encoding, const std::string& name, ObjMesh& out, std::vector<std::string>& notes,
                    std::vector<std::string>* warnings, ObjLoadProgress* progress);

// Reads bytes (a glTF's buffers named as files are looked up beside path, when given) in a reader process.
Status importInReaderProcess(const std::string& bytes, const std::string* path, MeshFormat format, const std::string& name,
                        ObjMesh& out, std::vector<std::string>* warnings, ObjLoadProgress* progress) {
    MeshEncoding encoding{format, false, false};
    std::vector<std::string> notes;
    std::string mended;  // a binary STL whose facet count disagrees with its size, mended (checkStl)
    const char* hint = "";
    switch (format) {
        case MeshFormat::Ply: {
            PlyHeader header;
            if (Status s = parsePlyHeader(bytes, name, header); !s) return s;
            if (Status s = checkPlyBody(bytes, name, header); !s) return s;
            encoding = header.encoding;
            notes = header.notes;
            hint = "ply";
            break;
        }
        case MeshFormat::Stl:
            if (Status s = checkStl(bytes, name, encoding, mended, notes); !s) return s;
            hint = "stl";
            break;
        case MeshFormat::Gltf:
            encoding.binary = bytes.compare(0, 4, "glTF") == 0;
            if (Status s = checkGltf(bytes, name, encoding.binary); !s) return s;
            break;
        case MeshFormat::Off: break;  // ASCII only: readOffDocument refuses binary OFF
        case MeshFormat::Obj: return Status::error(name + ": OBJ is read by loadObj");
    }
    Status status;
    std::vector<std::string> childNotes;
    ObjMesh mesh;
    // assimp crashes on some malformed files (a null dereference and a double free in its PLY header handling,
    // found by tests/fuzz/mesh_fuzz) and loops on others (one a binary PLY whose header passed our checks): every
    // file is read in a child process, which sends the mesh back; a crash or a hang costs an error message, not
    // the program. The timeout allows 3 s plus 1 s per MB (a 1M-vertex GLB of 64 MB reads in about 1.2 s, the copy
    // back included).
    const std::string reader = "the " + std::string(meshFormatName(format)) + " reader (" +
                               (format == MeshFormat::Gltf ? "tinygltf" : format == MeshFormat::Off ? "ours" : "assimp") + ")";
    std::string payload;
    const double timeoutSeconds = 3.0 + static_cast<double>(bytes.size()) / 1e6;
    const Status isolated = runIsolated(
        reader,
        [&](IsolatedChannel& channel) {
            const std::function<void(float)> report = [&channel](float f) { channel.progress(f); };
            const Status read = readInThisProcess(mended.empty() ? bytes : mended, path, hint, format, encoding, name, report,
                                                  mesh, childNotes);
            PayloadWriter sent;
            encodePayload(read, childNotes, mesh, sent);
            channel.result(sent.pieces());
        },
        timeoutSeconds, progress, payload);
    if (!isolated) return Status::error(name + ": " + isolated.message);
    if (!decodePayload(payload, status, childNotes, mesh))
        return Status::error(name + ": " + reader + " sent back a damaged result");
    return finishImport(status, childNotes, mesh, encoding, name, out, notes, warnings, progress);
}

// The end of every assimp load, in the caller's process: the reader's verdict and notes, then finishMesh.
Status finishImport(const Status& status, const std::vector<std::string>& readerNotes, ObjMesh& mesh,
                    const MeshEncoding& encoding, const std::string& name, ObjMesh& out, std::vector<std::string>& notes,
                    std::vector<std::string>* warnings, ObjLoadProgress* progress) {
    notes.insert(notes.end(), readerNotes.begin(), readerNotes.end());
    if (!status) return status;
    if (Status s = finishMesh(mesh, encoding, name, notes); !s) return s;
    if (progress && progress->cancel.load()) return Status::error(name + ": loading cancelled");
    out = std::move(mesh);
    if (warnings)
        for (const std::string& note : notes) warnings->push_back(name + ": " + note);
    if (progress) progress->fraction = 1.0f;
    return Status::success();
}

// --- Writing -------------------------------------------------------------------------------------------------

// Texture coordinates per vertex (PLY, glTF), when every corner of each vertex has the same one (or none).
bool perVertexTexcoords(const ObjMesh& mesh, Texcoords& out) {
    if (mesh.texcoords.rows() == 0) return false;
    const Eigen::Index columns = mesh.texcoords.cols();
    out = Texcoords::Zero(mesh.positions.rows(), columns);
    std::vector<int> first(static_cast<size_t>(mesh.positions.rows()), -1);
    bool any = false;
    for (size_t c = 0; c < mesh.cornerVertex.size(); ++c) {
        const int t = mesh.cornerTexcoord[c], v = mesh.cornerVertex[c];
        if (t < 0) continue;
        any = true;
        int& seen = first[static_cast<size_t>(v)];
        if (seen < 0) {
            seen = t;
            out.row(v) = mesh.texcoords.row(t);
        } else if (seen != t && mesh.texcoords.row(seen) != mesh.texcoords.row(t)) {
            return false;
        }
    }
    return any;
}

// Vertex normals for a save: the file's where no adjacent vertex moved, recomputed (area-weighted) elsewhere
// or everywhere when the file had none.
VertexNormals saveNormals(const ObjMesh& mesh, const Positions& deformed) {
    Positions computed;
    core::computeVertexNormals(deformed, mesh.triangles, computed);
    VertexNormals normals = computed.cast<float>();
    if (mesh.vertexNormals.rows() != mesh.positions.rows()) return normals;
    std::vector<char> stale(static_cast<size_t>(mesh.positions.rows()), 0);
    for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
        bool moved = false;
        for (int k = 0; k < 3; ++k) {
            const int v = mesh.triangles(t, k);
            moved |= deformed.row(v) != mesh.positions.row(v);
        }
        if (moved)
            for (int k = 0; k < 3; ++k) stale[static_cast<size_t>(mesh.triangles(t, k))] = 1;
    }
    for (Eigen::Index v = 0; v < normals.rows(); ++v)
        if (!stale[static_cast<size_t>(v)]) normals.row(v) = mesh.vertexNormals.row(v);
    return normals;
}

// The vertices of each group when no vertex is shared between groups and each group's vertices are consecutive,
// else one list of all (glTF primitives).
std::vector<std::vector<int>> primitiveGroups(const ObjMesh& mesh) {
    std::vector<int> groupOf(static_cast<size_t>(mesh.positions.rows()), -1);
    bool shared = false;
    for (int f = 0; f < mesh.faceCount() && !shared; ++f)
        for (int c = mesh.faceStart[f]; c < mesh.faceStart[f + 1]; ++c) {
            int& g = groupOf[static_cast<size_t>(mesh.cornerVertex[c])];
            if (g >= 0 && g != mesh.faceGroup[f]) shared = true;
            g = mesh.faceGroup[f];
        }
    // A vertex no face uses belongs to no group: one primitive then, which keeps it (and the vertex order).
    shared = shared || std::find(groupOf.begin(), groupOf.end(), -1) != groupOf.end();
    std::vector<std::vector<int>> groups(shared ? 1 : mesh.groupNames.size());
    for (int v = 0; v < mesh.positions.rows(); ++v)
        groups[shared || groupOf[static_cast<size_t>(v)] < 0 ? 0 : static_cast<size_t>(groupOf[static_cast<size_t>(v)])].push_back(v);
    groups.erase(std::remove_if(groups.begin(), groups.end(), [](const std::vector<int>& g) { return g.empty(); }), groups.end());
    // Primitives one after another must give the vertices in their order: each group a run of consecutive
    // vertices. Otherwise one primitive keeps the order (the groups are then not written, like PLY's).
    std::sort(groups.begin(), groups.end(), [](const std::vector<int>& a, const std::vector<int>& b) { return a[0] < b[0]; });
    int next = 0;
    for (const std::vector<int>& g : groups)
        for (int v : g)
            if (v != next++) {
                std::vector<int> all(static_cast<size_t>(mesh.positions.rows()));
                for (size_t i = 0; i < all.size(); ++i) all[i] = static_cast<int>(i);
                return {all};
            }
    return groups;
}

// The per-vertex attributes a PLY or glTF save writes besides positions and normals.
struct SaveAttributes {
    Texcoords texcoords;          // #V rows when writeTexcoords
    bool writeTexcoords = false;
    VertexColors colours;         // 0 or #V rows (RGBA in [0, 1])
    std::vector<std::vector<int>> primitives;  // glTF: primitiveGroups(mesh)
};

// The colours of an OBJ's `v x y z r g b` lines (the common extension), read from the source text after each
// vertex's z: #V x 4 (alpha 1; white where a line has none), or 0 rows when no line has three more numbers.
VertexColors objVertexColours(const ObjMesh& mesh) {
    if (!mesh.source) return {};
    const ObjSource& source = *mesh.source;
    const Eigen::Index n = mesh.positions.rows();
    VertexColors colours;
    for (Eigen::Index v = 0; v < n; ++v) {
        const char* at = source.text.data() + source.positionSpans[2 * static_cast<size_t>(v) + 1];
        const char* end = source.text.data() + source.text.size();
        double rgb[3];
        int count = 0;
        while (count < 3) {
            while (at < end && (*at == ' ' || *at == '\t')) ++at;
            if (at >= end || *at == '\n' || *at == '\r' || *at == '#') break;
            const char* token = at;
            while (at < end && !std::isspace(static_cast<unsigned char>(*at))) ++at;
            if (!parseObjNumber(token, at, rgb[count])) break;
            ++count;
        }
        if (count != 3) continue;
        if (colours.rows() == 0) colours = VertexColors::Ones(n, 4);
        colours.row(v) << static_cast<float>(rgb[0]), static_cast<float>(rgb[1]), static_cast<float>(rgb[2]), 1.0f;
    }
    return colours;
}

// Checks deformed fits the format (single precision), gathers what a PLY or glTF writes per vertex (texture
// coordinates where each vertex has one, colours from the mesh or its OBJ text) and names in notes what the
// format cannot hold.
Status prepareSave(const ObjMesh& mesh, const Positions& deformed, const MeshEncoding& encoding,
                   SaveAttributes& attributes, std::vector<std::string>& notes) {
    const bool off = encoding.format == MeshFormat::Off;  // doubles, as text
    for (Eigen::Index v = 0; v < deformed.rows() && !off; ++v)
        for (int k = 0; k < 3; ++k)
            if (std::abs(deformed(v, k)) > static_cast<double>(FLT_MAX))
                return Status::error("vertex " + std::to_string(v) + " is outside single precision's range, which " +
                                     meshFormatName(encoding.format) + " stores");
    const bool ply = encoding.format == MeshFormat::Ply, stl = encoding.format == MeshFormat::Stl;
    attributes.writeTexcoords = !stl && !off && perVertexTexcoords(mesh, attributes.texcoords);
    const bool writeTexcoords = attributes.writeTexcoords;
    attributes.colours = meshVertexColours(mesh);
    const bool anyTexcoords = std::any_of(mesh.cornerTexcoord.begin(), mesh.cornerTexcoord.end(), [](int t) { return t >= 0; });
    if (!stl && !off && !writeTexcoords && mesh.texcoords.rows() > 0 && anyTexcoords)
        notes.push_back("texture coordinates are not written: they differ between the corners of a vertex, and " +
                        std::string(meshFormatName(encoding.format)) + " stores one per vertex");
    if ((stl || off) && anyTexcoords)
        notes.push_back(std::string("texture coordinates are not written: ") + (stl ? "STL" : "OFF") + " has none");
    if (stl && attributes.colours.rows() > 0) notes.push_back("vertex colours are not written: STL has none");
    if (stl) attributes.colours.resize(0, 4);
    // One group holding every face loses nothing but its name; several lose the split.
    const bool severalGroups = std::adjacent_find(mesh.faceGroup.begin(), mesh.faceGroup.end(), std::not_equal_to<int>()) !=
                               mesh.faceGroup.end();
    if ((ply || off) && severalGroups) notes.push_back(std::string("groups are not written: ") + (ply ? "PLY" : "OFF") + " has none");
    if (encoding.format == MeshFormat::Gltf) attributes.primitives = primitiveGroups(mesh);
    if (encoding.format == MeshFormat::Gltf && severalGroups && attributes.primitives.size() == 1)
        notes.push_back("groups are not written: they share or interleave vertices, and a glTF primitive holds its own");
    if (!ply && !off) {
        int polygons = 0;
        for (int f = 0; f < mesh.faceCount(); ++f) polygons += mesh.faceStart[f + 1] - mesh.faceStart[f] > 3;
        if (polygons > 0)
            notes.push_back(std::to_string(polygons) + " polygon(s) of more than 3 corners are written as their triangles");
    }
    if (!mesh.materialNames.empty()) notes.push_back("materials are not written");
    return Status::success();
}

// PLY is written here, not by assimp: assimp 5.2's binary PLY writer puts the texture coordinates and colours of
// the body in another order than its header declares (the file reads back as garbage), and writes no big-endian.
// Layout: float x y z [nx ny nz] [uchar red green blue alpha] [float s t], then faces as `list uchar int`
// (`list int int` when a face has more than 255 corners), the names MeshLab and Blender read.
std::string writePly(const ObjMesh& mesh, const Positions& deformed, const MeshEncoding& encoding,
                     const SaveAttributes& attributes) {
    const Texcoords& texcoords = attributes.texcoords;
    const bool writeTexcoords = attributes.writeTexcoords;
    const bool normals = mesh.vertexNormals.rows() > 0, colours = attributes.colours.rows() > 0;
    const VertexNormals n = normals ? saveNormals(mesh, deformed) : VertexNormals();
    int largest = 0;
    for (int f = 0; f < mesh.faceCount(); ++f) largest = std::max(largest, mesh.faceStart[f + 1] - mesh.faceStart[f]);
    const bool wideCount = largest > 255;
    std::string out = "ply\nformat ";
    out += !encoding.binary ? "ascii" : encoding.bigEndian ? "binary_big_endian" : "binary_little_endian";
    out += " 1.0\ncomment DMFFD Sculpt\nelement vertex " + std::to_string(deformed.rows()) +
           "\nproperty float x\nproperty float y\nproperty float z\n";
    if (normals) out += "property float nx\nproperty float ny\nproperty float nz\n";
    if (colours) out += "property uchar red\nproperty uchar green\nproperty uchar blue\nproperty uchar alpha\n";
    if (writeTexcoords) out += "property float s\nproperty float t\n";
    out += "element face " + std::to_string(mesh.faceCount()) + "\nproperty list " + (wideCount ? "int" : "uchar") +
           " int vertex_indices\nend_header\n";
    const bool swap = encoding.binary && encoding.bigEndian;
    const auto putBinary = [&out, swap](const void* value, size_t size) {
        char bytes[4];
        std::memcpy(bytes, value, size);
        if (swap) std::reverse(bytes, bytes + size);
        out.append(bytes, size);
    };
    const auto putFloat = [&](float value) {
        if (encoding.binary) return putBinary(&value, 4);
        char buffer[32];
        out.append(buffer, static_cast<size_t>(std::to_chars(buffer, buffer + sizeof buffer, value).ptr - buffer));
    };
    const auto putInt = [&](long long value, size_t size) {
        if (encoding.binary) {
            if (size == 1) {
                const unsigned char b = static_cast<unsigned char>(value);
                return putBinary(&b, 1);
            }
            const int32_t i = static_cast<int32_t>(value);
            return putBinary(&i, 4);
        }
        char buffer[24];
        out.append(buffer, static_cast<size_t>(std::to_chars(buffer, buffer + sizeof buffer, value).ptr - buffer));
    };
    const auto separator = [&](bool last) {
        if (!encoding.binary) out += last ? '\n' : ' ';
    };
    // One allocation, on huge pages, for the whole file.
    reserveWithHugePages(out, out.size() + static_cast<size_t>(deformed.rows()) * (encoding.binary ? 36 : 120) +
                                  mesh.cornerVertex.size() * (encoding.binary ? 4 : 9) + static_cast<size_t>(mesh.faceCount()) * 4);
    for (Eigen::Index v = 0; v < deformed.rows(); ++v) {
        for (int k = 0; k < 3; ++k) {
            putFloat(static_cast<float>(deformed(v, k)));
            separator(k == 2 && !normals && !colours && !writeTexcoords);
        }
        for (int k = 0; k < 3 && normals; ++k) {
            putFloat(n(v, k));
            separator(k == 2 && !colours && !writeTexcoords);
        }
        for (int k = 0; k < 4 && colours; ++k) {
            putInt(std::lround(std::clamp(attributes.colours(v, k), 0.0f, 1.0f) * 255.0f), 1);
            separator(k == 3 && !writeTexcoords);
        }
        for (int k = 0; k < 2 && writeTexcoords; ++k) {
            putFloat(static_cast<float>(texcoords(v, k)));
            separator(k == 1);
        }
    }
    for (int f = 0; f < mesh.faceCount(); ++f) {
        const int first = mesh.faceStart[f], end = mesh.faceStart[f + 1];
        putInt(end - first, wideCount ? 4 : 1);
        separator(false);
        for (int c = first; c < end; ++c) {
            putInt(mesh.cornerVertex[c], 4);
            separator(c + 1 == end);
        }
    }
    return out;
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

// glTF is written with tinygltf (Debian's libtinygltf), not assimp: assimp's glTF writer always merges vertices
// that are identical in every attribute (its JoinIdenticalVertices step cannot be turned off), which changes the
// vertex count and order. One mesh with one triangle primitive per group (primitiveGroups), each placed by its
// own node; POSITION (with its bounds, as the format requires), NORMAL, COLOR_0 (float RGBA), TEXCOORD_0 (v
// flipped: glTF's runs down the image, OBJ's and PLY's up), uint32 indices. A .gltf holds its buffer as a
// base64 data URI, so a save is one file, written atomically.
std::string writeGltf(const ObjMesh& mesh, const Positions& deformed, const MeshEncoding& encoding,
                      const SaveAttributes& attributes) {
    const Texcoords& texcoords = attributes.texcoords;
    const bool writeTexcoords = attributes.writeTexcoords;
    tinygltf::Model model;
    model.asset.version = "2.0";
    model.asset.generator = "DMFFD Sculpt";
    model.buffers.emplace_back();
    std::vector<unsigned char>& data = model.buffers[0].data;
    // Appends count elements of `components` floats or uint32 each, as a buffer view and an accessor.
    const auto addAccessor = [&](const std::vector<float>* floats, const std::vector<uint32_t>* indices, int components,
                                 int type, int target) {
        const size_t offset = data.size();
        const size_t bytes = floats ? floats->size() * 4 : indices->size() * 4;
        data.resize(offset + bytes);
        if (bytes > 0) std::memcpy(data.data() + offset, floats ? static_cast<const void*>(floats->data()) : indices->data(), bytes);
        tinygltf::BufferView view;
        view.buffer = 0;
        view.byteOffset = offset;
        view.byteLength = bytes;
        view.target = target;
        model.bufferViews.push_back(view);
        tinygltf::Accessor accessor;
        accessor.bufferView = static_cast<int>(model.bufferViews.size()) - 1;
        accessor.componentType = floats ? TINYGLTF_COMPONENT_TYPE_FLOAT : TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
        accessor.count = (floats ? floats->size() : indices->size()) / static_cast<size_t>(components);
        accessor.type = type;
        model.accessors.push_back(accessor);
        return static_cast<int>(model.accessors.size()) - 1;
    };
    const VertexNormals normals = saveNormals(mesh, deformed);
    const bool colours = attributes.colours.rows() > 0;
    const std::vector<std::vector<int>>& groups = attributes.primitives;
    std::vector<int> local(static_cast<size_t>(mesh.positions.rows()), -1);
    tinygltf::Scene scene;
    for (const std::vector<int>& vertices : groups) {
        for (size_t i = 0; i < vertices.size(); ++i) local[static_cast<size_t>(vertices[i])] = static_cast<int>(i);
        std::vector<float> position, normal, colour, uv;
        std::vector<double> low(3, std::numeric_limits<double>::infinity()), high(3, -std::numeric_limits<double>::infinity());
        for (int v : vertices) {
            for (int k = 0; k < 3; ++k) {
                const float x = static_cast<float>(deformed(v, k));
                position.push_back(x);
                low[static_cast<size_t>(k)] = std::min(low[static_cast<size_t>(k)], static_cast<double>(x));
                high[static_cast<size_t>(k)] = std::max(high[static_cast<size_t>(k)], static_cast<double>(x));
                normal.push_back(normals(v, k));
            }
            for (int k = 0; k < 4 && colours; ++k) colour.push_back(attributes.colours(v, k));
            if (writeTexcoords) {
                uv.push_back(static_cast<float>(texcoords(v, 0)));
                uv.push_back(static_cast<float>(1.0 - texcoords(v, 1)));
            }
        }
        std::vector<uint32_t> indices;
        int group = 0;
        for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
            if (local[static_cast<size_t>(mesh.triangles(t, 0))] < 0) continue;  // another primitive's triangle
            if (indices.empty()) group = mesh.faceGroup[static_cast<size_t>(mesh.triangleFace[static_cast<size_t>(t)])];
            for (int k = 0; k < 3; ++k) indices.push_back(static_cast<uint32_t>(local[static_cast<size_t>(mesh.triangles(t, k))]));
        }
        tinygltf::Primitive primitive;
        primitive.mode = TINYGLTF_MODE_TRIANGLES;
        primitive.attributes["POSITION"] = addAccessor(&position, nullptr, 3, TINYGLTF_TYPE_VEC3, TINYGLTF_TARGET_ARRAY_BUFFER);
        model.accessors.back().minValues = low;
        model.accessors.back().maxValues = high;
        primitive.attributes["NORMAL"] = addAccessor(&normal, nullptr, 3, TINYGLTF_TYPE_VEC3, TINYGLTF_TARGET_ARRAY_BUFFER);
        if (colours) primitive.attributes["COLOR_0"] = addAccessor(&colour, nullptr, 4, TINYGLTF_TYPE_VEC4, TINYGLTF_TARGET_ARRAY_BUFFER);
        if (writeTexcoords)
            primitive.attributes["TEXCOORD_0"] = addAccessor(&uv, nullptr, 2, TINYGLTF_TYPE_VEC2, TINYGLTF_TARGET_ARRAY_BUFFER);
        primitive.indices = addAccessor(nullptr, &indices, 1, TINYGLTF_TYPE_SCALAR, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
        tinygltf::Mesh gltfMesh;
        gltfMesh.name = groups.size() > 1 ? mesh.groupNames[static_cast<size_t>(group)] : std::string("mesh");
        gltfMesh.primitives.push_back(primitive);
        model.meshes.push_back(gltfMesh);
        tinygltf::Node node;
        node.mesh = static_cast<int>(model.meshes.size()) - 1;
        node.name = gltfMesh.name;
        model.nodes.push_back(node);
        scene.nodes.push_back(static_cast<int>(model.nodes.size()) - 1);
        for (int v : vertices) local[static_cast<size_t>(v)] = -1;
    }
    model.scenes.push_back(scene);
    model.defaultScene = 0;
    std::ostringstream out;
    tinygltf::TinyGLTF writer;
    writer.WriteGltfSceneToStream(&model, out, !encoding.binary, encoding.binary);
    return out.str();
}

}  // namespace

Status loadMesh(const std::string& path, ObjMesh& out, std::vector<std::string>* warnings, ObjLoadProgress* progress) {
    try {
        MeshEncoding encoding;
        if (Status s = meshEncodingForPath(path, encoding); !s) return s;
        if (encoding.format == MeshFormat::Obj) {
            ObjMesh mesh;
            if (Status s = loadObj(path, mesh, warnings, progress); !s) return s;
            mesh.loadedAs = encoding;
            out = std::move(mesh);
            return Status::success();
        }
        std::error_code ec;
        if (std::filesystem::is_directory(path, ec)) return Status::error(path + ": is a folder, not a mesh file");
        std::string bytes;
        if (Status s = readTextFile(path, bytes); !s) return s;
        if (progress && progress->cancel.load()) return Status::error(path + ": loading cancelled");
        // A glTF may name its buffers as files beside it, which are looked up from the file's folder.
        const bool fromFile = encoding.format == MeshFormat::Gltf;
        return importInReaderProcess(bytes, fromFile ? &path : nullptr, encoding.format, path, out, warnings, progress);
    } catch (const std::bad_alloc&) {
        return Status::error(path + ": not enough memory to load it");
    } catch (const std::exception& e) {
        return Status::error(path + ": " + e.what());
    }
}

Status loadMeshFromMemory(const std::string& bytes, MeshFormat format, const std::string& displayName, ObjMesh& out,
                          std::vector<std::string>* warnings) {
    try {
        if (format == MeshFormat::Obj) {
            ObjMesh mesh;
            if (Status s = loadObjFromText(bytes, displayName, "", mesh, warnings); !s) return s;
            mesh.loadedAs = MeshEncoding{};
            out = std::move(mesh);
            return Status::success();
        }
        return importInReaderProcess(bytes, nullptr, format, displayName, out, warnings, nullptr);
    } catch (const std::bad_alloc&) {
        return Status::error(displayName + ": not enough memory to load it");
    } catch (const std::exception& e) {
        return Status::error(displayName + ": " + e.what());
    }
}

VertexColors meshVertexColours(const ObjMesh& mesh, const std::vector<core::EdgeSplit>& splits) {
    VertexColors colours = mesh.vertexColors.rows() > 0 ? mesh.vertexColors : objVertexColours(mesh);
    if (colours.rows() == 0 || splits.empty()) return colours;
    for (size_t i = 0; i < splits.size(); ++i) {
        const Eigen::Index row = colours.rows() + static_cast<Eigen::Index>(i);
        if (splits[i].a < 0 || splits[i].b < 0 || splits[i].a >= row || splits[i].b >= row) return {};
    }
    core::appendSplitMidpoints(colours, splits);
    return colours;
}

Status saveEncodingFor(const std::string& path, const ObjMesh& mesh, MeshEncoding& out) {
    MeshEncoding encoding;
    if (Status s = meshEncodingForPath(path, encoding); !s) return s;
    // .gltf and .glb are one format with two encodings: the extension decides between them.
    if (encoding.format == mesh.loadedAs.format && encoding.format != MeshFormat::Gltf) encoding = mesh.loadedAs;
    out = encoding;
    return Status::success();
}

Status serializeMesh(const std::string& path, const ObjMesh& mesh, const Positions& deformedPositions,
                     const MeshEncoding& encoding, std::string& bytes, std::vector<std::string>* warnings) {
    try {
        if (encoding.format == MeshFormat::Obj) {
            std::string text;
            if (Status s = serializeObj(mesh, deformedPositions, text); !s) return Status::error(path + ": " + s.message);
            bytes.swap(text);
            return Status::success();
        }
        if (Status s = checkObjMesh(mesh); !s) return Status::error(path + ": " + s.message);
        if (deformedPositions.rows() != mesh.positions.rows() || !deformedPositions.allFinite())
            return Status::error(path + ": cannot write " + std::string(meshFormatName(encoding.format)) +
                                 ": the positions do not match the mesh or are not finite");
        std::vector<std::string> notes;
        SaveAttributes attributes;
        if (Status s = prepareSave(mesh, deformedPositions, encoding, attributes, notes); !s)
            return Status::error(path + ": " + s.message);
        std::string out;
        if (encoding.format == MeshFormat::Ply) {
            out = writePly(mesh, deformedPositions, encoding, attributes);
        } else if (encoding.format == MeshFormat::Gltf) {
            out = writeGltf(mesh, deformedPositions, encoding, attributes);
        } else if (encoding.format == MeshFormat::Off) {
            const VertexNormals normals = mesh.vertexNormals.rows() > 0 ? saveNormals(mesh, deformedPositions) : VertexNormals();
            out = writeOff(mesh, deformedPositions, attributes.colours, normals);
        } else {
            aiScene scene;
            buildStlScene(mesh, deformedPositions, scene);
            Assimp::Exporter exporter;
            const aiExportDataBlob* blob = exporter.ExportToBlob(&scene, encoding.binary ? "stlb" : "stl", 0);
            if (!blob) return Status::error(path + ": the STL writer failed: " + exporter.GetErrorString());
            out.assign(static_cast<const char*>(blob->data), blob->size);
        }
        if (out.empty()) return Status::error(path + ": the " + std::string(meshFormatName(encoding.format)) + " writer wrote nothing");
        bytes.swap(out);
        if (warnings)
            for (const std::string& note : notes) warnings->push_back(path + ": " + note);
        return Status::success();
    } catch (const std::bad_alloc&) {
        return Status::error(path + ": not enough memory to save");
    } catch (const std::exception& e) {
        return Status::error(path + ": " + e.what());
    }
}

Status saveMesh(const std::string& path, const ObjMesh& mesh, const Positions& deformedPositions,
                std::vector<std::string>* warnings) {
    MeshEncoding encoding;
    if (Status s = saveEncodingFor(path, mesh, encoding); !s) return s;
    std::string bytes;
    if (Status s = serializeMesh(path, mesh, deformedPositions, encoding, bytes, warnings); !s) return s;
    return writeFileAtomically(path, bytes);
}

Status saveRefinedMesh(const std::string& path, const ObjMesh& mesh, const std::vector<core::EdgeSplit>& splits,
                       const Positions& deformedPositions, std::vector<std::string>* warnings) {
    if (splits.empty()) return saveMesh(path, mesh, deformedPositions, warnings);
    ObjMesh refined;
    if (Status s = refineObjMesh(mesh, splits, refined); !s) return Status::error(path + ": " + s.message);
    return saveMesh(path, refined, deformedPositions, warnings);
}

}  // namespace sculpt::io
