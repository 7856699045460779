// PLY, STL and glTF through assimp, and the format dispatch of loadMesh/saveMesh (mesh_file.h).
//
// Why assimp (Debian's libassimp 5.2): one maintained library reads all three formats (PLY in both byte orders,
// ASCII and binary STL, glTF 2.0 and GLB), keeps PLY's vertex order and polygons, and reads vertex colours,
// normals and texture coordinates. What it does not do is done here: the checks that give a message naming what
// is wrong (before assimp sees the file), running it in a child process (isolated_call.h) where it could crash or
// hang, welding STL facets, flattening glTF node transforms, warnings for what is not kept, atomic saves (every
// writer writes into memory first), and two of the writers: PLY (writePly: assimp 5.2's binary one is broken)
// and glTF (writeGltf, through tinygltf: assimp's merges vertices). assimp writes STL.
//
// The pieces, each in its own file (mesh_file_internal.h declares what they share): the PLY checks and writer
// (mesh_ply.cpp), the STL checks and the scene its writer takes (mesh_stl.cpp), the libraries' read and the
// scene conversion (mesh_import.cpp), the reader process (mesh_reader_process.cpp) and the glTF writer
// (mesh_gltf_write.cpp). Here: the public functions, the dispatch between formats and what a save prepares.
#include "io/mesh_file.h"

#include <assimp/Exporter.hpp>
#include <assimp/scene.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <filesystem>
#include <functional>
#include <new>

#include "core/deform/vertex_normals.h"
#include "io/atomic_file.h"
#include "io/mesh_file_internal.h"
#include "io/off_mesh.h"
#include "io/obj_scan.h"
#include "io/obj_refine.h"
#include "io/script_json.h"

namespace sculpt::io {

// --- Writing -------------------------------------------------------------------------------------------------

namespace detail {

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

}  // namespace detail

namespace {

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
                   detail::SaveAttributes& attributes, std::vector<std::string>& notes) {
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
    if (encoding.format == MeshFormat::Gltf) attributes.primitives = detail::primitiveGroups(mesh);
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
        return detail::importInReaderProcess(bytes, fromFile ? &path : nullptr, encoding.format, path, out, warnings, progress);
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
        return detail::importInReaderProcess(bytes, nullptr, format, displayName, out, warnings, nullptr);
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
        detail::SaveAttributes attributes;
        if (Status s = prepareSave(mesh, deformedPositions, encoding, attributes, notes); !s)
            return Status::error(path + ": " + s.message);
        std::string out;
        if (encoding.format == MeshFormat::Ply) {
            out = detail::writePly(mesh, deformedPositions, encoding, attributes);
        } else if (encoding.format == MeshFormat::Gltf) {
            out = detail::writeGltf(mesh, deformedPositions, encoding, attributes);
        } else if (encoding.format == MeshFormat::Off) {
            const VertexNormals normals = mesh.vertexNormals.rows() > 0 ? detail::saveNormals(mesh, deformedPositions) : VertexNormals();
            out = writeOff(mesh, deformedPositions, attributes.colours, normals);
        } else {
            aiScene scene;
            detail::buildStlScene(mesh, deformedPositions, scene);
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
