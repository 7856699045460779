// PLY: the header and body checks made before assimp reads a file, and the PLY writer (writePly).
#include "io/mesh_file_internal.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <sstream>

#include "io/huge_pages.h"

namespace sculpt::io {

namespace {

// Bytes of a PLY scalar type, 0 for an unknown name.
int plyTypeSize(const std::string& type) {
    if (type == "char" || type == "uchar" || type == "int8" || type == "uint8") return 1;
    if (type == "short" || type == "ushort" || type == "int16" || type == "uint16") return 2;
    if (type == "int" || type == "uint" || type == "float" || type == "int32" || type == "uint32" || type == "float32") return 4;
    if (type == "double" || type == "float64") return 8;
    return 0;
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

}  // namespace

namespace detail {

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

}  // namespace detail

}  // namespace sculpt::io
