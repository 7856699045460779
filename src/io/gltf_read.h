// glTF 2.0 reading: tinygltf (Debian's libtinygltf) parses the JSON and loads the buffers; every accessor, buffer
// view, stride and sparse substitution is then checked here against the buffers before a byte of it is read, so
// every value returned is one the file holds as the glTF 2.0 specification defines it (section 3.6 "Binary
// data storage": accessors, buffer views, strides, sparse accessors, normalized integers). assimp's glTF
// importer, used before, read sparse accessors on interleaved views from the wrong places and past their
// buffer's end (values that changed from run to run).
#pragma once

#include <string>
#include <vector>

#include "core/status.h"
#include "io/obj_mesh.h"

namespace sculpt::io {

// Reads a glTF document into out, as faces without triangles (the caller triangulates and checks it, as for the
// other formats): bytes is the whole file, a JSON .gltf or a binary .glb (binary: true); a JSON file's buffers
// and images named by relative URIs are looked up in *baseDir (null: the document was read from memory, and a
// buffer it names as a file is an error).
// The default scene is placed (scene 0 when none is named; every root node when the file has no scene), node
// transforms (matrix or T * R * S) applied to positions and, inverse-transposed, to normals. Kept per vertex:
// POSITION, NORMAL, TEXCOORD_0 (v flipped to OBJ's convention, which runs up the image), COLOR_0 (RGB or RGBA;
// float or normalized integers). Triangles, strips and fans become triangle faces; point and line primitives,
// strip and fan triangles whose corners repeat a vertex (joins; a triangle list's are kept), materials, skins, morph targets, animations and the
// second colour and texture sets are not kept, and each is named in notes. Several placed primitives become
// groups named after their meshes.
// Fails with "name: what is wrong" (out untouched) for anything the file breaks: an accessor, view or buffer
// index that does not exist, a view past its buffer's end, an accessor past its view's end, a byteStride below
// the element size or above 252, sparse indices out of range or not increasing, an index beyond the vertices,
// non-finite values or transforms, an extension the file requires that changes geometry (Draco, meshopt).
Status readGltfDocument(const std::string& bytes, bool binary, const std::string* baseDir, const std::string& name,
                        ObjMesh& out, std::vector<std::string>& notes);

}  // namespace sculpt::io
