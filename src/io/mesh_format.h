// Which file format a mesh is stored in, and how (text or binary, byte order): chosen from the file name's
// extension when opening or saving, and remembered by a loaded mesh so that Save writes it back the same way.
#pragma once

#include <string>
#include <vector>

#include "core/status.h"

namespace sculpt::io {

enum class MeshFormat { Obj, Ply, Stl, Gltf, Off };

struct MeshEncoding {
    MeshFormat format = MeshFormat::Obj;
    bool binary = false;     // PLY binary_*_endian, binary STL, .glb; false: ASCII PLY/STL, .gltf + .bin, OBJ, OFF
    bool bigEndian = false;  // PLY binary_big_endian only
};

// "OBJ", "PLY", "STL", "glTF", "OFF".
const char* meshFormatName(MeshFormat format);

// The encoding a new file at path is written in, from its extension (case-insensitive): .obj; .ply (binary,
// little-endian: what Blender and MeshLab write by default); .stl (binary); .gltf (JSON + a .bin buffer beside
// it); .glb (binary glTF); .off (ASCII OFF, COFF when the mesh has colours). Fails, naming the extension and the ones that work, for any other name.
Status meshEncodingForPath(const std::string& path, MeshEncoding& out);

// True when path ends in one of the extensions meshEncodingForPath accepts (the file browser's filter).
bool isMeshPath(const std::string& path);

// The extensions the program opens and saves (lower case, with the dot), for the file browser's filter.
const std::vector<std::string>& meshExtensions();

// The same as one string for messages: ".obj .ply .stl .gltf .glb .off".
std::string meshExtensionList();

// "PLY (binary, big-endian)", "STL (ASCII)", "glTF (.glb)", "OBJ": what a save or a load says it used.
std::string meshEncodingText(const MeshEncoding& encoding);

}  // namespace sculpt::io
