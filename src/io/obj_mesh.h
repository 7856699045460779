// Wavefront OBJ in and out: every file the format allows opens, and saving writes back what it holds.
//
// Reading parses the text once, with a strict reader of our own (obj_scan.h) that checks every line,
// reports "file:line: what is wrong" and keeps the exact digits: tinyobjloader's number parser is not
// correctly rounded (and keeps only two texture components). The reader mirrors tinyobjloader's reading
// of every statement; tinyobjloader (double build, no triangulation) reads the .mtl files, and the tests
// and the fuzzer parse with it too and check that it agrees face by face (crossCheckObjWithTinyobj).
// Until 2026-12 every load parsed twice; a 1M-vertex file took 4.8 s. Faces of any size, lines continued
// with a backslash, vertex colours and every statement the sculptor does not use (`l`, `p`, `vp`, `s`,
// free-form geometry...) are accepted.
//
// Each face is triangulated for the engine, the renderer and picking (polygon_triangulation.h); the
// file keeps the polygon. A loaded mesh keeps its source text, and saving it rewrites only the numbers
// that changed: the x y z of moved vertices and the normals (`vn`) of faces that changed shape. Every
// other byte (vertex colours, comments, formatting, line continuations, relative indices, all other
// statements) is written back unchanged and in order. A mesh built in code (no source) is written
// from its arrays instead, with recomputed per-vertex normals.
#pragma once

#include <atomic>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/mesh_types.h"
#include "core/status.h"
#include "io/mesh_format.h"

namespace sculpt::io {

// #VT x 2 or #VT x 3 texture coordinates, one row per `vt` line.
using Texcoords = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
// #V x 4 RGBA in [0, 1], one row per vertex (PLY and glTF store colours per vertex).
using VertexColors = Eigen::Matrix<float, Eigen::Dynamic, 4, Eigen::RowMajor>;
// #V x 3 normals as the file stored them, one row per vertex.
using VertexNormals = Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::RowMajor>;

// The text a mesh was loaded from, with where the numbers a save may replace are (byte offsets into text).
// Costs about the file's size in memory (plus 16 bytes per `v` and `vn` line) for as long as the mesh lives.
struct ObjSource {
    std::string text;                   // the file's bytes as read (byte order mark, CR LF and all)
    std::vector<size_t> positionSpans;  // 2 per `v` line in file order: [begin of x, end of z)
    std::vector<size_t> normalSpans;    // 2 per `vn` line in file order: [begin of x, end of z)
};

// A surface as the engine uses it (welded positions + triangles) plus the polygon data needed to write it
// back. Every format mesh_file.h reads loads into one (the name is from the first format; OBJ's model of
// polygons, groups and corner attributes holds what PLY, STL and glTF store). Invariants (checkObjMesh verifies them):
//   - faceStart has #F + 1 entries, faceStart[0] = 0, strictly increasing by >= 3 per face,
//     faceStart[#F] = #C (the corner count); cornerVertex/cornerTexcoord/cornerNormal have #C entries.
//   - triangles triangulate the faces in face order (triangulateObjFaces: triangulatePolygon, or the fan
//     (c0, ci, ci+1) for a face that has no exact triangulation); triangleFace[t] is the face triangle t
//     came from. A face of N corners gives N - 2 triangles, fewer only where its corners coincide.
//   - groupNames[0] is always "" (the default group of faces before any `g`/`o` line); the other
//     names appear in the order faces first use them, each once.
//   - materialNames appear in the order faces first use them, each once; faceMaterial -1 = none.
struct ObjMesh {
    Positions positions;            // #V x 3, one row per `v` line in file order (the welded vertices)
    Triangles triangles;            // #T x 3 indices into positions, fan triangulation of the faces
    std::vector<int> triangleFace;  // #T, face index of each triangle

    std::vector<int> faceStart;       // #F + 1 offsets into the corner arrays
    std::vector<int> cornerVertex;    // #C indices into positions
    std::vector<int> cornerTexcoord;  // #C indices into texcoords, -1 where the corner has none
    std::vector<int> cornerNormal;    // #C indices into the file's `vn` lines, -1 where none (normals
                                      // themselves are not kept: saveObj recomputes them)
    Texcoords texcoords;              // #VT x 2 or 3 (3 if any `vt` line had a w; missing ones are 0)

    std::vector<int> faceGroup;           // #F indices into groupNames
    std::vector<std::string> groupNames;  // see invariants; `o` names are kept as groups too
    std::vector<int> faceMaterial;        // #F indices into materialNames, -1 = no `usemtl` yet
    std::vector<std::string> materialNames;
    std::vector<std::string> materialLibraries;  // `mtllib` arguments as written, first use order

    // Per-vertex attributes of the formats that keep them per vertex (PLY, glTF: mesh_file.h); 0 rows when the
    // file had none (an OBJ keeps its colours and normals in its source text instead). A PLY or glTF file's
    // texture coordinates are per vertex too: texcoords then has one row per vertex and cornerTexcoord = cornerVertex.
    VertexColors vertexColors;    // 0 or #V rows
    VertexNormals vertexNormals;  // 0 or #V rows; a save recomputes those of vertices next to a moved one
    MeshEncoding loadedAs;        // the format and encoding the file was read in (OBJ for a mesh built in code)

    // The loaded file (null for a mesh built in code). When set, serializeObj writes this text back with
    // only the changed numbers replaced, so the arrays above must still describe it: code that changes the
    // faces, groups or materials of a loaded mesh must reset source. Shared, never modified: copies of a
    // mesh are cheap.
    std::shared_ptr<const ObjSource> source;

    int vertexCount() const { return static_cast<int>(positions.rows()); }
    int faceCount() const { return faceStart.empty() ? 0 : static_cast<int>(faceStart.size()) - 1; }
    int cornerCount() const { return static_cast<int>(cornerVertex.size()); }
};

// Progress of a load running on another thread. The loader raises `fraction` (0..1, monotonic) at phase
// boundaries and every MiB of tinyobjloader's pass (the longest one), and checks `cancel` as often: once the
// caller sets it the load stops soon with an error whose message ends in "cancelled" (out untouched).
// note: polled per MiB of text, never per line, so a load with progress is as fast as one without.
struct ObjLoadProgress {
    std::atomic<float> fraction{0.0f};
    std::atomic<bool> cancel{false};
};

// Reads the OBJ file at path into out. warnings (may be null) receives non-fatal notes such as a
// missing or refused .mtl, line/point elements and other statements kept in the file but not used,
// faces that could not be triangulated exactly (drawn as a fan) or unused vertices, each prefixed with path.
// Errors name the file and line: "mesh.obj:12: face index 7 is out of range (file has 5 vertices)".
// On failure out is left untouched; no exception escapes (out of memory becomes an error too).
// .mtl files are only opened when named by a plain file name in the OBJ's own folder.
// progress (may be null): see ObjLoadProgress.
Status loadObj(const std::string& path, ObjMesh& out, std::vector<std::string>* warnings = nullptr,
               ObjLoadProgress* progress = nullptr);

// Same as loadObj for OBJ text already in memory. displayName prefixes messages ("mesh.obj");
// baseDir is the folder `mtllib` names are looked up in ("" = never open any file).
Status loadObjFromText(const std::string& text, const std::string& displayName, const std::string& baseDir,
                       ObjMesh& out, std::vector<std::string>* warnings, ObjLoadProgress* progress = nullptr);

// For the tests and the fuzzer: parses text with tinyobjloader as well and checks that it reads every face,
// group and material exactly as the loader's own reader does (obj_scan.h mirrors it). Text the reader refuses
// passes (nothing to compare). Fails with "<displayName>: tinyobjloader rejected the file: ..." or
// "<displayName>[:line]: internal error: tinyobjloader and the validating reader disagree (...)".
// Opens no file (`mtllib` is not followed).
Status crossCheckObjWithTinyobj(const std::string& text, const std::string& displayName);

// What triangulateObjFaces could not triangulate exactly.
struct ObjTriangulationReport {
    int fannedFaces = 0;         // faces given the fan (c0, ci, ci+1) instead
    int firstFannedFace = -1;    // the first of them, -1 if none
    std::string firstReason;     // why, e.g. "the polygon crosses itself"
};

// Sets mesh.triangles and mesh.triangleFace from mesh.positions and the faces (faceStart, cornerVertex,
// which must be consistent): triangles stay triangles, larger faces go through triangulatePolygon with
// their vertex indices in place of corner indices, and a face it fails on gets the fan and is counted in
// the report. The loader calls this; code that builds an ObjMesh may too. Never throws except bad_alloc.
ObjTriangulationReport triangulateObjFaces(ObjMesh& mesh);

// Checks the ObjMesh invariants above plus what the writer needs (finite texcoords, names without
// line breaks, single-token material names, a source whose spans match the vertex and normal counts).
// Returns an error naming the first violation.
Status checkObjMesh(const ObjMesh& mesh);

// Serialises mesh with deformedPositions (#V x 3, same row count as mesh.positions, all finite) in
// place of mesh.positions. Numbers are printed in the shortest form that reads back to the identical
// double. On error text is left untouched.
//   - With mesh.source (a loaded file): the source text, in which the x y z of every vertex whose
//     position changed (bitwise) is replaced, and every `vn` used by a corner of a face with such a
//     vertex is replaced by the normalised sum of the (area-weighted) normals of the deformed faces of
//     the corners that use it (kept as it was if that sum is zero). Nothing else changes, byte for byte:
//     unmoved vertices keep their text, a mesh saved unchanged is the file it was loaded from.
//   - Without (a mesh built in code): written from the arrays, with normals recomputed from
//     deformedPositions, one `vn` per vertex (a corner's normal index equals its vertex index). Faces keep
//     their polygons, groups and materials.
Status serializeObj(const ObjMesh& mesh, const Positions& deformedPositions, std::string& text);

// serializeObj, then writeFileAtomically: on any error the file at path is left as it was.
Status saveObj(const std::string& path, const ObjMesh& mesh, const Positions& deformedPositions);

}  // namespace sculpt::io
