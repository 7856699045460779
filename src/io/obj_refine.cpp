// Texture coordinates across a refinement (Coquillart 1990, section 3.4): a split at the rest-space midpoint
// of an edge puts the new vertex at barycentric (1/2, 1/2, 0) of every triangle it halves, so its texture
// coordinate in that triangle is the midpoint of the edge ends' coordinates there.
#include "io/obj_refine.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <map>
#include <new>

#include "io/mesh_file.h"

namespace sculpt::io {

Status refineObjMesh(const ObjMesh& mesh, const std::vector<core::EdgeSplit>& splits, ObjMesh& refined) {
    try {
        if (Status s = checkObjMesh(mesh); !s) return s;
        const int vertexCount = mesh.vertexCount();
        const int triangleCount = static_cast<int>(mesh.triangles.rows());
        Triangles triangles = mesh.triangles;
        std::vector<core::TriangleHalving> halvings;
        if (Status s = core::applyEdgeSplits(triangles, vertexCount, splits, &halvings); !s)
            return Status::error("the refinement does not fit the OBJ mesh: " + s.message);

        // Per triangle corner: its texture coordinate (from the face corner with that vertex) and its face.
        std::vector<std::array<int, 3>> cornerTexcoord(static_cast<size_t>(triangleCount));
        std::vector<int> faceOf(mesh.triangleFace);
        for (int t = 0; t < triangleCount; ++t) {
            const int f = mesh.triangleFace[static_cast<size_t>(t)];
            for (int k = 0; k < 3; ++k) {
                int texcoord = -1;
                for (int c = mesh.faceStart[static_cast<size_t>(f)]; c < mesh.faceStart[static_cast<size_t>(f) + 1]; ++c)
                    if (mesh.cornerVertex[static_cast<size_t>(c)] == mesh.triangles(t, k)) {
                        texcoord = mesh.cornerTexcoord[static_cast<size_t>(c)];
                        break;
                    }
                cornerTexcoord[static_cast<size_t>(t)][static_cast<size_t>(k)] = texcoord;
            }
        }
        // The halvings again, on the corners' texture coordinates (TriangleHalving: the kept half's corner
        // (k+1) and the appended half's corner k become the new vertex).
        std::vector<std::array<double, 3>> addedTexcoords;
        std::map<std::pair<int, int>, int> midpointOf;  // pair of texcoord ids -> the id of their midpoint
        const int texcoordCount = static_cast<int>(mesh.texcoords.rows());
        const int texcoordColumns = texcoordCount > 0 ? static_cast<int>(mesh.texcoords.cols()) : 2;
        const auto texcoordRow = [&](int id, int column) {
            return id < texcoordCount ? mesh.texcoords(id, column) : addedTexcoords[static_cast<size_t>(id - texcoordCount)][static_cast<size_t>(column)];
        };
        const auto midpoint = [&](int a, int b) {
            if (a < 0 || b < 0) return -1;
            if (a == b) return a;
            const std::pair<int, int> key = std::minmax(a, b);
            const auto found = midpointOf.find(key);
            if (found != midpointOf.end()) return found->second;
            std::array<double, 3> row{0.0, 0.0, 0.0};
            for (int column = 0; column < texcoordColumns; ++column)
                row[static_cast<size_t>(column)] = 0.5 * (texcoordRow(a, column) + texcoordRow(b, column));
            addedTexcoords.push_back(row);
            const int id = texcoordCount + static_cast<int>(addedTexcoords.size()) - 1;
            midpointOf.emplace(key, id);
            return id;
        };
        std::vector<char> faceSplit(static_cast<size_t>(mesh.faceCount()), 0);
        for (const core::TriangleHalving& h : halvings) {
            const size_t t = static_cast<size_t>(h.triangle);
            const int k = h.corner, next = (h.corner + 1) % 3;
            std::array<int, 3> half = cornerTexcoord[t];
            const int m = midpoint(half[static_cast<size_t>(k)], half[static_cast<size_t>(next)]);
            cornerTexcoord[t][static_cast<size_t>(next)] = m;
            half[static_cast<size_t>(k)] = m;
            cornerTexcoord.push_back(half);
            faceOf.push_back(faceOf[t]);
            faceSplit[static_cast<size_t>(faceOf[t])] = 1;
        }

        ObjMesh out;
        out.positions = mesh.positions;
        core::appendSplitMidpoints(out.positions, splits);
        out.texcoords.resize(texcoordCount + static_cast<Eigen::Index>(addedTexcoords.size()), texcoordColumns);
        if (texcoordCount > 0) out.texcoords.topRows(texcoordCount) = mesh.texcoords;
        for (size_t i = 0; i < addedTexcoords.size(); ++i)
            for (int column = 0; column < texcoordColumns; ++column)
                out.texcoords(texcoordCount + static_cast<Eigen::Index>(i), column) = addedTexcoords[i][static_cast<size_t>(column)];
        // Per-vertex colours (PLY, glTF, and an OBJ's `v x y z r g b`, which the result's arrays must now hold:
        // it has no source text) and normals: each new vertex gets its edge's midpoint, like its position.
        out.vertexColors = meshVertexColours(mesh, splits);
        out.vertexNormals = mesh.vertexNormals;
        if (out.vertexNormals.rows() > 0) core::appendSplitMidpoints(out.vertexNormals, splits);
        out.loadedAs = mesh.loadedAs;
        out.groupNames = mesh.groupNames;
        out.materialNames = mesh.materialNames;
        out.materialLibraries = mesh.materialLibraries;

        // Faces in their order; the triangles of each face after it (the ObjMesh invariant: face order).
        std::vector<std::vector<int>> trianglesOfFace(static_cast<size_t>(mesh.faceCount()));
        for (size_t t = 0; t < faceOf.size(); ++t) trianglesOfFace[static_cast<size_t>(faceOf[t])].push_back(static_cast<int>(t));
        std::vector<std::array<int, 3>> outTriangles;
        out.faceStart.push_back(0);
        const auto addFace = [&](int f) {
            out.faceGroup.push_back(mesh.faceGroup[static_cast<size_t>(f)]);
            out.faceMaterial.push_back(mesh.faceMaterial[static_cast<size_t>(f)]);
            out.faceStart.push_back(static_cast<int>(out.cornerVertex.size()));
        };
        for (int f = 0; f < mesh.faceCount(); ++f) {
            const std::vector<int>& own = trianglesOfFace[static_cast<size_t>(f)];
            if (!faceSplit[static_cast<size_t>(f)]) {
                for (int c = mesh.faceStart[static_cast<size_t>(f)]; c < mesh.faceStart[static_cast<size_t>(f) + 1]; ++c) {
                    out.cornerVertex.push_back(mesh.cornerVertex[static_cast<size_t>(c)]);
                    out.cornerTexcoord.push_back(mesh.cornerTexcoord[static_cast<size_t>(c)]);
                    out.cornerNormal.push_back(-1);  // recomputed on writing (no source)
                }
                const int face = static_cast<int>(out.faceStart.size()) - 1;
                for (int t : own) {
                    outTriangles.push_back({triangles(t, 0), triangles(t, 1), triangles(t, 2)});
                    out.triangleFace.push_back(face);
                }
                addFace(f);
                continue;
            }
            for (int t : own) {
                const int face = static_cast<int>(out.faceStart.size()) - 1;
                for (int k = 0; k < 3; ++k) {
                    out.cornerVertex.push_back(triangles(t, k));
                    out.cornerTexcoord.push_back(cornerTexcoord[static_cast<size_t>(t)][static_cast<size_t>(k)]);
                    out.cornerNormal.push_back(-1);
                }
                outTriangles.push_back({triangles(t, 0), triangles(t, 1), triangles(t, 2)});
                out.triangleFace.push_back(face);
                addFace(f);
            }
        }
        out.triangles.resize(static_cast<Eigen::Index>(outTriangles.size()), 3);
        for (size_t t = 0; t < outTriangles.size(); ++t)
            for (int k = 0; k < 3; ++k) out.triangles(static_cast<Eigen::Index>(t), k) = outTriangles[t][static_cast<size_t>(k)];
        if (Status s = checkObjMesh(out); !s) return s;
        refined = std::move(out);
        return Status::success();
    } catch (const std::bad_alloc&) {
        return Status::error("not enough memory to refine the OBJ mesh");
    }
}

Status saveRefinedObj(const std::string& path, const ObjMesh& mesh, const std::vector<core::EdgeSplit>& splits,
                      const Positions& deformedPositions) {
    if (splits.empty()) return saveObj(path, mesh, deformedPositions);
    ObjMesh refined;
    if (Status s = refineObjMesh(mesh, splits, refined); !s) return Status::error(path + ": " + s.message);
    return saveObj(path, refined, deformedPositions);
}

}  // namespace sculpt::io
