#include "io/mesh_format.h"

#include <algorithm>
#include <cctype>

namespace sculpt::io {

namespace {

std::string lowerExtension(const std::string& path) {
    const size_t slash = path.find_last_of('/');
    const size_t dot = path.find_last_of('.');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
    std::string ext = path.substr(dot);
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return ext;
}

}  // namespace

const char* meshFormatName(MeshFormat format) {
    switch (format) {
        case MeshFormat::Obj: return "OBJ";
        case MeshFormat::Ply: return "PLY";
        case MeshFormat::Stl: return "STL";
        case MeshFormat::Gltf: return "glTF";
        case MeshFormat::Off: return "OFF";
    }
    return "?";
}

const std::vector<std::string>& meshExtensions() {
    static const std::vector<std::string> extensions{".obj", ".ply", ".stl", ".gltf", ".glb", ".off"};
    return extensions;
}

std::string meshExtensionList() {
    std::string list;
    for (const std::string& extension : meshExtensions()) list += (list.empty() ? "" : " ") + extension;
    return list;
}

Status meshEncodingForPath(const std::string& path, MeshEncoding& out) {
    const std::string ext = lowerExtension(path);
    MeshEncoding e;
    if (ext == ".obj") {
        e.format = MeshFormat::Obj;
    } else if (ext == ".ply") {
        e.format = MeshFormat::Ply;
        e.binary = true;
    } else if (ext == ".stl") {
        e.format = MeshFormat::Stl;
        e.binary = true;
    } else if (ext == ".gltf") {
        e.format = MeshFormat::Gltf;
    } else if (ext == ".glb") {
        e.format = MeshFormat::Gltf;
        e.binary = true;
    } else if (ext == ".off") {
        e.format = MeshFormat::Off;
    } else {
        return Status::error(path + ": " +
                             (ext.empty() ? std::string("the file name has no extension")
                                          : "'" + ext + "' is not a mesh format this program reads or writes") +
                             " (use one of " + meshExtensionList() + ")");
    }
    out = e;
    return Status::success();
}

bool isMeshPath(const std::string& path) {
    MeshEncoding unused;
    return static_cast<bool>(meshEncodingForPath(path, unused));
}

std::string meshEncodingText(const MeshEncoding& encoding) {
    switch (encoding.format) {
        case MeshFormat::Obj: return "OBJ";
        case MeshFormat::Ply:
            return !encoding.binary ? "PLY (ASCII)" : encoding.bigEndian ? "PLY (binary, big-endian)"
                                                                         : "PLY (binary, little-endian)";
        case MeshFormat::Stl: return encoding.binary ? "STL (binary)" : "STL (ASCII)";
        case MeshFormat::Gltf: return encoding.binary ? "glTF (.glb)" : "glTF (.gltf + .bin)";
        case MeshFormat::Off: return "OFF";
    }
    return "?";
}

}  // namespace sculpt::io
