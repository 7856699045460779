// OBJ writing: shortest round-trip numbers, recomputed normals, the input's polygons/groups/materials.
#include <charconv>
#include <cmath>
#include <new>

#include "core/vertex_normals.h"
#include "io/atomic_file.h"
#include "io/obj_mesh.h"

namespace sculpt::io {

namespace {

// note: std::to_chars without a precision prints the shortest text that reads back to the very
// same double (Ryu), locale-independent; "%.17g" would also round-trip but is longer and obeys
// LC_NUMERIC (a German locale would write "0,5").
inline void appendNumber(std::string& text, double value) {
    char buffer[32];
    const std::to_chars_result result = std::to_chars(buffer, buffer + sizeof buffer, value);
    text.append(buffer, result.ptr);
}

inline void appendIndex(std::string& text, long long oneBased) {
    char buffer[24];
    const std::to_chars_result result = std::to_chars(buffer, buffer + sizeof buffer, oneBased);
    text.append(buffer, result.ptr);
}

bool hasLineBreak(const std::string& s) {
    for (char c : s)
        if (c == '\n' || c == '\r' || c == '\0') return true;
    return false;
}

bool isSingleToken(const std::string& s) {
    if (s.empty()) return false;
    for (char c : s)
        if (c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\0') return false;
    return true;
}

}  // namespace

Status checkObjMesh(const ObjMesh& mesh) {
    auto bad = [](const std::string& what) { return Status::error("invalid OBJ mesh: " + what); };
    const long long vertexCount = mesh.positions.rows();
    const long long texcoordCount = mesh.texcoords.rows();
    if (mesh.faceStart.empty() || mesh.faceStart[0] != 0) return bad("faceStart must start with 0");
    const size_t faceCount = mesh.faceStart.size() - 1;
    const size_t cornerCount = mesh.cornerVertex.size();
    if (static_cast<size_t>(mesh.faceStart.back()) != cornerCount) return bad("faceStart must end at the corner count");
    if (mesh.cornerTexcoord.size() != cornerCount || mesh.cornerNormal.size() != cornerCount)
        return bad("corner arrays differ in size");
    if (mesh.faceGroup.size() != faceCount || mesh.faceMaterial.size() != faceCount)
        return bad("per-face arrays differ from the face count");
    for (size_t f = 0; f < faceCount; ++f)
        if (mesh.faceStart[f + 1] - mesh.faceStart[f] < 3) return bad("face " + std::to_string(f) + " has < 3 corners");
    for (size_t c = 0; c < cornerCount; ++c) {
        if (mesh.cornerVertex[c] < 0 || mesh.cornerVertex[c] >= vertexCount) return bad("corner vertex out of range");
        if (mesh.cornerTexcoord[c] < -1 || mesh.cornerTexcoord[c] >= texcoordCount)
            return bad("corner texture coordinate out of range");
    }
    if (texcoordCount > 0 && mesh.texcoords.cols() != 2 && mesh.texcoords.cols() != 3)
        return bad("texcoords must have 2 or 3 columns");
    if (!mesh.texcoords.allFinite()) return bad("non-finite texture coordinate");
    if (mesh.triangles.size() > 0 && (mesh.triangles.minCoeff() < 0 || mesh.triangles.maxCoeff() >= vertexCount))
        return bad("triangle index out of range");
    if (mesh.triangleFace.size() != static_cast<size_t>(mesh.triangles.rows()))
        return bad("triangleFace differs from the triangle count");
    if (mesh.groupNames.empty() || !mesh.groupNames[0].empty()) return bad("groupNames[0] must be the unnamed group");
    for (int g : mesh.faceGroup)
        if (g < 0 || static_cast<size_t>(g) >= mesh.groupNames.size()) return bad("face group out of range");
    for (int m : mesh.faceMaterial)
        if (m < -1 || m >= static_cast<long long>(mesh.materialNames.size())) return bad("face material out of range");
    for (const std::string& name : mesh.groupNames)
        if (hasLineBreak(name)) return bad("group name with a line break");
    for (const std::string& name : mesh.materialNames)
        if (!isSingleToken(name)) return bad("material name '" + name + "' must be one word");
    for (const std::string& name : mesh.materialLibraries)
        if (name.empty() || hasLineBreak(name)) return bad("empty material library name or one with a line break");
    return Status::success();
}

Status serializeObj(const ObjMesh& mesh, const Positions& deformedPositions, std::string& text) {
    try {
        Status status = checkObjMesh(mesh);
        if (!status) return status;
        if (deformedPositions.rows() != mesh.positions.rows())
            return Status::error("cannot write OBJ: " + std::to_string(deformedPositions.rows()) +
                                 " positions for a mesh with " + std::to_string(mesh.positions.rows()) + " vertices");
        for (Eigen::Index v = 0; v < deformedPositions.rows(); ++v)
            if (!deformedPositions.row(v).allFinite())
                return Status::error("cannot write OBJ: vertex " + std::to_string(v + 1) +
                                     " has a non-finite position");

        Positions normals;
        core::computeVertexNormals(deformedPositions, mesh.triangles, normals);

        std::string out;
        // ~24 bytes per number, ~12 per corner index triple: one allocation for typical meshes.
        out.reserve(static_cast<size_t>(deformedPositions.rows()) * 150 + mesh.cornerVertex.size() * 24 +
                    static_cast<size_t>(mesh.texcoords.size()) * 25 + 256);
        out += "# DMFFD Sculpt\n";
        for (const std::string& library : mesh.materialLibraries) out += "mtllib " + library + "\n";
        for (Eigen::Index v = 0; v < deformedPositions.rows(); ++v) {
            out += "v";
            for (int k = 0; k < 3; ++k) {
                out += ' ';
                appendNumber(out, deformedPositions(v, k));
            }
            out += '\n';
        }
        for (Eigen::Index t = 0; t < mesh.texcoords.rows(); ++t) {
            out += "vt";
            for (Eigen::Index k = 0; k < mesh.texcoords.cols(); ++k) {
                out += ' ';
                appendNumber(out, mesh.texcoords(t, k));
            }
            out += '\n';
        }
        for (Eigen::Index v = 0; v < normals.rows(); ++v) {
            // computeVertexNormals promises finite unit normals; a NaN here would make the file unreadable.
            const bool finite = normals.row(v).allFinite();
            out += "vn";
            for (int k = 0; k < 3; ++k) {
                out += ' ';
                appendNumber(out, finite ? normals(v, k) : (k == 2 ? 1.0 : 0.0));
            }
            out += '\n';
        }

        int group = 0;  // faces before any `g` line are in the unnamed group 0
        int material = -1;
        for (int f = 0; f < mesh.faceCount(); ++f) {
            if (mesh.faceGroup[f] != group) {
                group = mesh.faceGroup[f];
                // note: "g " with a trailing blank is the unnamed group; a bare "g" is not a group line
                // to tinyobjloader and would be ignored.
                out += "g " + mesh.groupNames[group] + "\n";
            }
            if (mesh.faceMaterial[f] != material) {
                material = mesh.faceMaterial[f];
                out += material < 0 ? std::string("usemtl\n") : "usemtl " + mesh.materialNames[material] + "\n";
            }
            out += 'f';
            for (int c = mesh.faceStart[f]; c < mesh.faceStart[f + 1]; ++c) {
                const long long vertex = mesh.cornerVertex[c] + 1LL;
                out += ' ';
                appendIndex(out, vertex);
                out += '/';
                if (mesh.cornerTexcoord[c] >= 0) appendIndex(out, mesh.cornerTexcoord[c] + 1LL);
                out += '/';
                appendIndex(out, vertex);  // one recomputed normal per vertex
            }
            out += '\n';
        }
        text.swap(out);
        return Status::success();
    } catch (const std::bad_alloc&) {
        return Status::error("cannot write OBJ: not enough memory");
    }
}

Status saveObj(const std::string& path, const ObjMesh& mesh, const Positions& deformedPositions) {
    try {
        std::string text;
        Status status = serializeObj(mesh, deformedPositions, text);
        if (!status) return Status::error(path + ": " + status.message);
        return writeFileAtomically(path, text);
    } catch (const std::bad_alloc&) {
        return Status::error(path + ": not enough memory to save");
    }
}

}  // namespace sculpt::io
