// Mesh files in every format the program opens and saves: OBJ (obj_mesh.h, our own exact reader and writer)
// and PLY, STL, glTF 2.0 / GLB: PLY and STL read through assimp (Debian's libassimp), glTF parsed by tinygltf
// (Debian's libtinygltf) with every accessor checked and read here (gltf_read.h: assimp read sparse accessors
// wrong); written by assimp (STL), tinygltf (glTF) or here (PLY): see mesh_file.cpp for why. The format comes from the extension
// (mesh_format.h). Every format keeps OBJ's guarantees: bad input gets a message naming the file and what is
// wrong, nothing is dropped without a warning that says what, saves are atomic, and loads report progress and
// can be cancelled.
//
// What each format brings in (all into an ObjMesh):
//   - PLY, ASCII or binary in either byte order: vertices in file order, polygon faces, per-vertex colours,
//     normals and texture coordinates. Vertex properties and elements assimp does not read (quality,
//     confidence, edges...) are named in a warning; a file storing positions as double is read in single
//     precision (assimp's), with a warning.
//   - STL, ASCII or binary: facets welded on load (corners at identical positions, -0 = 0, become one vertex,
//     numbered in order of first use) so the surface is one connected mesh; each `solid` becomes a group.
//   - glTF 2.0 (.gltf with its buffers in files or data URIs, or .glb): every triangle primitive of every mesh placed by a node of the
//     scene, node transforms applied (the hierarchy is flattened, which the load warns about), one group per
//     primitive, with its colours (COLOR_0), normals and texture coordinates (TEXCOORD_0); sparse, interleaved and
//     normalized accessors read as the specification defines them, and one that breaks its bounds refused.
//     Materials, textures, skins, animations and point/line primitives are not kept, with a warning naming them.
// Positions in PLY, STL and glTF are single precision: a save rounds them, and one loaded is exactly its float.
#pragma once

#include <string>
#include <vector>

#include "core/deform/refinement.h"
#include "io/obj_mesh.h"

namespace sculpt::io {

// Reads the mesh file at path in the format of its extension. warnings (may be null) receives notes on what
// was not kept or was changed, each prefixed with path. Errors name the file and what is wrong ("scan.ply: not
// a PLY file (it does not start with \"ply\")", "part.stl: facet 12 has a non-finite coordinate"). On failure
// out is untouched; no exception escapes. progress (may be null): as for loadObj (assimp reports few steps, and
// a cancel is seen between them). out.loadedAs records the format and encoding read.
Status loadMesh(const std::string& path, ObjMesh& out, std::vector<std::string>* warnings = nullptr,
                ObjLoadProgress* progress = nullptr);

// loadMesh for the bytes of a file already in memory (tests, fuzzing). displayName prefixes messages. A .gltf
// whose buffers are separate files cannot be read this way (the error says so); OBJ never opens a .mtl.
Status loadMeshFromMemory(const std::string& bytes, MeshFormat format, const std::string& displayName, ObjMesh& out,
                          std::vector<std::string>* warnings = nullptr);

// The encoding saveMesh uses for path: the mesh's own (loadedAs) when path has the extension of the format
// it was loaded in (Save keeps a binary big-endian PLY binary big-endian), else the extension's default
// (meshEncodingForPath). Fails on an extension no format has.
Status saveEncodingFor(const std::string& path, const ObjMesh& mesh, MeshEncoding& out);

// Serialises mesh with deformedPositions (#V x 3, finite) in encoding as the bytes of the file a save at path
// writes (path only names the file in messages). OBJ: serializeObj. PLY: vertices in order with the polygons,
// and the colours, normals and texture coordinates the mesh has. STL: every triangle as a facet with its normal.
// glTF: one primitive per group when no vertex is shared between groups and each group's vertices are consecutive
// (else one, with a warning), triangles, normals,
// colours, texture coordinates; a .gltf holds its buffer as a data URI (one file). Normals of vertices next to a
// moved one are recomputed (area-weighted), the others are the file's. What the format cannot hold (groups in
// PLY, texture coordinates that differ between the corners of a vertex in PLY/glTF, colours and texture
// coordinates in STL, polygons in STL/glTF, which are written as their triangles, materials) is named in
// warnings, prefixed with path. Fails on a position outside single precision's range for PLY/STL/glTF;
// bytes is untouched on failure.
Status serializeMesh(const std::string& path, const ObjMesh& mesh, const Positions& deformedPositions,
                     const MeshEncoding& encoding, std::string& bytes, std::vector<std::string>* warnings = nullptr);

// serializeMesh in saveEncodingFor(path, mesh), then writeFileAtomically: on any error the file at path is
// left as it was.
Status saveMesh(const std::string& path, const ObjMesh& mesh, const Positions& deformedPositions,
                std::vector<std::string>* warnings = nullptr);

// The mesh's own per-vertex colours, to draw: a PLY's or glTF's (vertexColors), else an OBJ's `v x y z r g b`
// lines (read from its source text; white where a line has none). With splits (a refined mesh), one row more per
// split, in order: the midpoint of its edge's two vertices, as refineObjMesh gives a saved file. #V + #splits
// rows of RGBA in [0, 1] (sRGB, as the files store them), or 0 rows when the file had no colours. Split
// vertices out of range leave the colours out (0 rows): they are not this mesh's.
VertexColors meshVertexColours(const ObjMesh& mesh, const std::vector<core::EdgeSplit>& splits = {});

// saveMesh of refineObjMesh(mesh, splits) (obj_refine.h) with deformedPositions (#V + #splits rows); with no
// splits exactly saveMesh(path, mesh, deformedPositions).
Status saveRefinedMesh(const std::string& path, const ObjMesh& mesh, const std::vector<core::EdgeSplit>& splits,
                       const Positions& deformedPositions, std::vector<std::string>* warnings = nullptr);

}  // namespace sculpt::io
