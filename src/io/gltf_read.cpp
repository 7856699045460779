// glTF 2.0 reading with checked accessors (gltf_read.h). Section numbers are those of the glTF 2.0
// specification (Khronos, 2.0.1).
#include "io/gltf_read.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include <Eigen/Geometry>

#include "io/huge_pages.h"
#include "io/load_checks.h"

namespace sculpt::io {

namespace {

// Bytes of one component (section 3.6.2.2 "Accessor data types"), 0 for a type glTF does not define.
int componentBytes(int componentType) {
    switch (componentType) {
        case TINYGLTF_COMPONENT_TYPE_BYTE:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
        case TINYGLTF_COMPONENT_TYPE_SHORT:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
        default: return 0;
    }
}

// Components of an accessor type; 0 for the matrices and unknown types, which no attribute read here uses.
int typeComponents(int type) {
    switch (type) {
        case TINYGLTF_TYPE_SCALAR: return 1;
        case TINYGLTF_TYPE_VEC2: return 2;
        case TINYGLTF_TYPE_VEC3: return 3;
        case TINYGLTF_TYPE_VEC4: return 4;
        default: return 0;
    }
}

const char* typeName(int type) {
    switch (type) {
        case TINYGLTF_TYPE_SCALAR: return "SCALAR";
        case TINYGLTF_TYPE_VEC2: return "VEC2";
        case TINYGLTF_TYPE_VEC3: return "VEC3";
        case TINYGLTF_TYPE_VEC4: return "VEC4";
        case TINYGLTF_TYPE_MAT2: return "MAT2";
        case TINYGLTF_TYPE_MAT3: return "MAT3";
        case TINYGLTF_TYPE_MAT4: return "MAT4";
        default: return "an unknown type";
    }
}

// One component at p, as the value it stands for: floats as they are, normalized integers mapped to [0, 1] or
// [-1, 1] by the formulas of section 3.11 ("Animation"/"Meshes": c / (2^n - 1), max(c / (2^(n-1) - 1), -1)),
// other integers as integers.
double decodeComponent(const unsigned char* p, int componentType, bool normalized) {
    switch (componentType) {
        case TINYGLTF_COMPONENT_TYPE_BYTE: {
            int8_t c;
            std::memcpy(&c, p, 1);
            return normalized ? std::max(c / 127.0, -1.0) : c;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return normalized ? p[0] / 255.0 : p[0];
        case TINYGLTF_COMPONENT_TYPE_SHORT: {
            int16_t c;
            std::memcpy(&c, p, 2);
            return normalized ? std::max(c / 32767.0, -1.0) : c;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
            uint16_t c;
            std::memcpy(&c, p, 2);
            return normalized ? c / 65535.0 : c;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
            uint32_t c;
            std::memcpy(&c, p, 4);
            return c;
        }
        default: {
            float c;
            std::memcpy(&c, p, 4);
            return c;
        }
    }
}

// What an accessor's values are to be: the types and component types allowed, for the message and the checks.
struct AccessorUse {
    std::string what;                  // "POSITION of mesh 'x', primitive 0", for messages
    std::vector<int> types;            // TINYGLTF_TYPE_*
    std::vector<int> componentTypes;   // TINYGLTF_COMPONENT_TYPE_*
    bool integersOnly = false;         // indices: not normalized
};

// The byte range [offset, offset + length) of a buffer view, checked against its buffer.
Status viewRange(const tinygltf::Model& model, int viewIndex, const std::string& where, const unsigned char*& data,
                 size_t& length, size_t& stride) {
    if (viewIndex < 0 || static_cast<size_t>(viewIndex) >= model.bufferViews.size())
        return Status::error(where + " names buffer view " + std::to_string(viewIndex) + ", which does not exist (" +
                             std::to_string(model.bufferViews.size()) + " buffer views)");
    const tinygltf::BufferView& view = model.bufferViews[static_cast<size_t>(viewIndex)];
    const std::string viewName = "buffer view " + std::to_string(viewIndex);
    if (view.buffer < 0 || static_cast<size_t>(view.buffer) >= model.buffers.size())
        return Status::error(viewName + " names buffer " + std::to_string(view.buffer) + ", which does not exist (" +
                             std::to_string(model.buffers.size()) + " buffers)");
    const std::vector<unsigned char>& buffer = model.buffers[static_cast<size_t>(view.buffer)].data;
    if (view.byteOffset > buffer.size() || view.byteLength > buffer.size() - view.byteOffset)
        return Status::error(viewName + " (bytes " + std::to_string(view.byteOffset) + " to " +
                             std::to_string(view.byteOffset + view.byteLength) + ") runs past the end of buffer " +
                             std::to_string(view.buffer) + ", which holds " + std::to_string(buffer.size()) + " bytes");
    data = buffer.data() + view.byteOffset;
    length = view.byteLength;
    stride = view.byteStride;
    return Status::success();
}

// The accessor's values, count x components, row by row (section 3.6.2 "Accessors", 3.6.2.3 "Sparse accessors"):
// every byte read is checked to lie inside its view, and every view inside its buffer, before it is read.
Status readAccessor(const tinygltf::Model& model, int index, const AccessorUse& use, size_t& count, int& components,
                    std::vector<double>& out) {
    if (index < 0 || static_cast<size_t>(index) >= model.accessors.size())
        return Status::error(use.what + " names accessor " + std::to_string(index) + ", which does not exist (" +
                             std::to_string(model.accessors.size()) + " accessors)");
    const tinygltf::Accessor& a = model.accessors[static_cast<size_t>(index)];
    const std::string where = "accessor " + std::to_string(index) + " (" + use.what + ")";
    if (std::find(use.types.begin(), use.types.end(), a.type) == use.types.end())
        return Status::error(where + " is " + typeName(a.type) + ", which this attribute cannot be");
    const int bytes = componentBytes(a.componentType);
    if (bytes == 0 || std::find(use.componentTypes.begin(), use.componentTypes.end(), a.componentType) == use.componentTypes.end())
        return Status::error(where + " has component type " + std::to_string(a.componentType) + ", which this attribute cannot have");
    if (a.normalized && (use.integersOnly || a.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT ||
                         a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT))
        return Status::error(where + " is normalized, which its component type cannot be");
    components = typeComponents(a.type);
    count = a.count;
    const size_t element = static_cast<size_t>(components * bytes);
    // A limit below what an int vertex index can reach, and below any count a real buffer could hold.
    if (count > static_cast<size_t>(std::numeric_limits<int32_t>::max() / 4))
        return Status::error(where + " declares " + std::to_string(count) + " elements, more than this program handles");
    out.assign(count * static_cast<size_t>(components), 0.0);
    const auto decodeElement = [&](const unsigned char* p, size_t row) {
        for (int k = 0; k < components; ++k)
            out[row * static_cast<size_t>(components) + static_cast<size_t>(k)] =
                decodeComponent(p + static_cast<size_t>(k * bytes), a.componentType, a.normalized);
    };
    // No buffer view: all zeros (section 3.6.2.3), which sparse values may then replace.
    if (a.bufferView >= 0 || !a.sparse.isSparse) {
        const unsigned char* data = nullptr;
        size_t length = 0, stride = 0;
        if (Status s = viewRange(model, a.bufferView, where, data, length, stride); !s) return s;
        if (stride == 0) stride = element;
        if (stride < element || stride > 252)
            return Status::error("buffer view " + std::to_string(a.bufferView) + " of " + where + " has byteStride " +
                                 std::to_string(stride) + ": it must be at least the element's " + std::to_string(element) +
                                 " bytes and at most 252");
        // count < 2^29 and stride <= 252: the products below cannot overflow once byteOffset is inside the view.
        if (count > 0 && (a.byteOffset > length || a.byteOffset + (count - 1) * stride + element > length))
            return Status::error(where + ": " + std::to_string(count) + " elements of " + std::to_string(element) +
                                 " bytes every " + std::to_string(stride) + " from byte " + std::to_string(a.byteOffset) +
                                 " run past the end of buffer view " + std::to_string(a.bufferView) + " (" +
                                 std::to_string(length) + " bytes)");
        for (size_t i = 0; i < count; ++i) decodeElement(data + a.byteOffset + i * stride, i);
    }
    if (!a.sparse.isSparse) return Status::success();
    // Sparse substitution: count indices (strictly increasing, each below the accessor's count) and as many
    // values, both tightly packed in their views.
    const std::string sparseWhere = "the sparse part of " + where;
    if (a.sparse.count < 1 || static_cast<size_t>(a.sparse.count) > count)
        return Status::error(sparseWhere + " replaces " + std::to_string(a.sparse.count) + " elements of " + std::to_string(count));
    const size_t replaced = static_cast<size_t>(a.sparse.count);
    const int indexType = a.sparse.indices.componentType;
    if (indexType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && indexType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        indexType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
        return Status::error(sparseWhere + " has indices of component type " + std::to_string(indexType) +
                             " (unsigned byte, short or int are allowed)");
    const size_t indexBytes = static_cast<size_t>(componentBytes(indexType));
    const unsigned char* indexData = nullptr;
    const unsigned char* valueData = nullptr;
    size_t indexLength = 0, valueLength = 0, unusedStride = 0;
    if (Status s = viewRange(model, a.sparse.indices.bufferView, sparseWhere + "'s indices", indexData, indexLength, unusedStride); !s)
        return s;
    if (Status s = viewRange(model, a.sparse.values.bufferView, sparseWhere + "'s values", valueData, valueLength, unusedStride); !s)
        return s;
    const auto fits = [](long long offset, size_t items, size_t size, size_t length) {
        return offset >= 0 && static_cast<size_t>(offset) <= length && items <= (length - static_cast<size_t>(offset)) / size;
    };
    if (!fits(a.sparse.indices.byteOffset, replaced, indexBytes, indexLength))
        return Status::error(sparseWhere + ": " + std::to_string(replaced) + " indices from byte " +
                             std::to_string(a.sparse.indices.byteOffset) + " run past the end of buffer view " +
                             std::to_string(a.sparse.indices.bufferView) + " (" + std::to_string(indexLength) + " bytes)");
    if (!fits(a.sparse.values.byteOffset, replaced, element, valueLength))
        return Status::error(sparseWhere + ": " + std::to_string(replaced) + " values from byte " +
                             std::to_string(a.sparse.values.byteOffset) + " run past the end of buffer view " +
                             std::to_string(a.sparse.values.bufferView) + " (" + std::to_string(valueLength) + " bytes)");
    indexData += a.sparse.indices.byteOffset;
    valueData += a.sparse.values.byteOffset;
    double previous = -1.0;
    for (size_t i = 0; i < replaced; ++i) {
        const double target = decodeComponent(indexData + i * indexBytes, indexType, false);
        if (target >= static_cast<double>(count) || target <= previous)
            return Status::error(sparseWhere + ": index " + std::to_string(i) + " is " + std::to_string(static_cast<uint64_t>(target)) +
                                 (target >= static_cast<double>(count) ? ", beyond the accessor's " + std::to_string(count) + " elements"
                                                                       : std::string(", not above the index before it")));
        previous = target;
        decodeElement(valueData + i * element, static_cast<size_t>(target));
    }
    return Status::success();
}

// A node's own transform (section 3.5.3 "Transformations"): its matrix (column-major) or T * R * S.
Status localTransform(const tinygltf::Node& node, int index, Eigen::Matrix4d& out) {
    const std::string where = "node " + std::to_string(index) + (node.name.empty() ? "" : " ('" + node.name + "')");
    out.setIdentity();
    if (!node.matrix.empty()) {
        if (node.matrix.size() != 16) return Status::error(where + " has a matrix of " + std::to_string(node.matrix.size()) + " numbers, not 16");
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r) out(r, c) = node.matrix[static_cast<size_t>(c * 4 + r)];
    } else {
        if (!node.translation.empty() && node.translation.size() != 3) return Status::error(where + "'s translation is not 3 numbers");
        if (!node.rotation.empty() && node.rotation.size() != 4) return Status::error(where + "'s rotation is not 4 numbers");
        if (!node.scale.empty() && node.scale.size() != 3) return Status::error(where + "'s scale is not 3 numbers");
        Eigen::Affine3d t = Eigen::Affine3d::Identity();
        if (!node.translation.empty()) t.translate(Eigen::Vector3d(node.translation[0], node.translation[1], node.translation[2]));
        if (!node.rotation.empty()) {
            // (x, y, z, w); a unit quaternion by the specification, normalized here against rounding in the file.
            Eigen::Quaterniond q(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]);
            if (!(q.norm() > 0.0) || !std::isfinite(q.norm())) return Status::error(where + "'s rotation is not a rotation");
            t.rotate(q.normalized());
        }
        if (!node.scale.empty()) t.scale(Eigen::Vector3d(node.scale[0], node.scale[1], node.scale[2]));
        out = t.matrix();
    }
    if (!out.allFinite()) return Status::error(where + "'s transform is not finite");
    return Status::success();
}

// A primitive placed by a node.
struct GltfPlacement {
    int mesh = 0;
    Eigen::Matrix4d transform;
};

Status collectGltfPlacements(const tinygltf::Model& model, int index, const Eigen::Matrix4d& parent, std::vector<char>& onPath,
                         int depth, std::vector<GltfPlacement>& out, long long& skinJoints) {
    if (index < 0 || static_cast<size_t>(index) >= model.nodes.size())
        return Status::error("a scene or node names node " + std::to_string(index) + ", which does not exist (" +
                             std::to_string(model.nodes.size()) + " nodes)");
    if (onPath[static_cast<size_t>(index)] || depth > 256)
        return Status::error("node " + std::to_string(index) + " is its own ancestor (the node hierarchy has a cycle)");
    const tinygltf::Node& node = model.nodes[static_cast<size_t>(index)];
    Eigen::Matrix4d local;
    if (Status s = localTransform(node, index, local); !s) return s;
    const Eigen::Matrix4d transform = parent * local;
    if (node.mesh >= 0) {
        if (static_cast<size_t>(node.mesh) >= model.meshes.size())
            return Status::error("node " + std::to_string(index) + " names mesh " + std::to_string(node.mesh) + ", which does not exist");
        out.push_back({node.mesh, transform});
        if (node.skin >= 0 && static_cast<size_t>(node.skin) < model.skins.size())
            skinJoints += static_cast<long long>(model.skins[static_cast<size_t>(node.skin)].joints.size());
    }
    onPath[static_cast<size_t>(index)] = 1;
    for (int child : node.children)
        if (Status s = collectGltfPlacements(model, child, transform, onPath, depth + 1, out, skinJoints); !s) return s;
    onPath[static_cast<size_t>(index)] = 0;
    return Status::success();
}

// Images are not kept: their bytes are not decoded (a texture's only trace is the material note).
bool skipImage(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int, void*) { return true; }

// A document read from memory opens no file it names (its buffers must be in it).
bool noFileExists(const std::string&, void*) { return false; }
std::string samePath(const std::string& path, void*) { return path; }
bool noFileRead(std::vector<unsigned char>*, std::string* err, const std::string& path, void*) {
    if (err) *err += "'" + path + "' is a file beside the glTF, and this glTF was read from memory\n";
    return false;
}
bool noFileWrite(std::string*, const std::string&, const std::vector<unsigned char>&, void*) { return false; }
// The first few lines of tinygltf's error or warning text, as one line.
std::string firstLines(const std::string& text) {
    std::string line;
    int lines = 0;
    for (size_t at = 0; at < text.size() && lines < 3;) {
        size_t end = text.find('\n', at);
        if (end == std::string::npos) end = text.size();
        if (end > at) {
            line += (line.empty() ? "" : "; ") + text.substr(at, end - at);
            ++lines;
        }
        at = end + 1;
    }
    return line;
}

const std::vector<int> kFloatLike = {TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                                     TINYGLTF_COMPONENT_TYPE_SHORT, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT};

}  // namespace

Status readGltfDocument(const std::string& bytes, bool binary, const std::string* baseDir, const std::string& name,
                        ObjMesh& out, std::vector<std::string>& notes) {
    tinygltf::Model model;
    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(&skipImage, nullptr);
    // A file read from memory names no file it may open; from a path, tinygltf's own file access reads the
    // buffers beside it.
    if (baseDir == nullptr) loader.SetFsCallbacks({&noFileExists, &samePath, &noFileRead, &noFileWrite, nullptr});
    std::string err, warn;
    const std::string folder = baseDir != nullptr ? *baseDir : std::string();
    if (bytes.size() > std::numeric_limits<unsigned int>::max())
        return Status::error(name + ": the file is larger than 4 GiB, more than the glTF reader handles");
    const bool parsed = binary ? loader.LoadBinaryFromMemory(&model, &err, &warn, reinterpret_cast<const unsigned char*>(bytes.data()),
                                                             static_cast<unsigned int>(bytes.size()), folder)
                               : loader.LoadASCIIFromString(&model, &err, &warn, bytes.data(),
                                                            static_cast<unsigned int>(bytes.size()), folder);
    if (!parsed) return Status::error(name + ": not a readable glTF file: " + (err.empty() ? "tinygltf could not read it" : firstLines(err)));
    if (!warn.empty()) notes.push_back("tinygltf: " + firstLines(warn));
    for (const std::string& required : model.extensionsRequired)
        if (required == "KHR_draco_mesh_compression" || required == "EXT_meshopt_compression")
            return Status::error(name + ": the file's geometry is compressed (" + required + "), which this reader does not decode");
    const auto failed = [&name](const Status& s) { return Status::error(name + ": " + s.message); };

    // The scene placed (section 3.3 "Scenes").
    std::vector<int> roots;
    if (!model.scenes.empty()) {
        const int scene = model.defaultScene >= 0 ? model.defaultScene : 0;
        if (static_cast<size_t>(scene) >= model.scenes.size())
            return Status::error(name + ": the default scene " + std::to_string(scene) + " does not exist");
        roots = model.scenes[static_cast<size_t>(scene)].nodes;
        if (model.scenes.size() > 1) notes.push_back(std::to_string(model.scenes.size() - 1) + " other scene(s) are not kept");
    } else {
        std::vector<char> isChild(model.nodes.size(), 0);
        for (const tinygltf::Node& node : model.nodes)
            for (int child : node.children)
                if (child >= 0 && static_cast<size_t>(child) < isChild.size()) isChild[static_cast<size_t>(child)] = 1;
        for (size_t n = 0; n < model.nodes.size(); ++n)
            if (!isChild[n]) roots.push_back(static_cast<int>(n));
    }
    std::vector<GltfPlacement> placements;
    std::vector<char> onPath(model.nodes.size(), 0);
    long long skinJoints = 0;
    for (int root : roots)
        if (Status s = collectGltfPlacements(model, root, Eigen::Matrix4d::Identity(), onPath, 0, placements, skinJoints); !s) return failed(s);
    std::vector<int> uses(model.meshes.size(), 0);
    for (const GltfPlacement& p : placements) ++uses[static_cast<size_t>(p.mesh)];
    const long long unplaced = std::count(uses.begin(), uses.end(), 0);
    if (unplaced > 0) notes.push_back(std::to_string(unplaced) + " mesh(es) no node of the scene places are not kept");
    if (std::any_of(uses.begin(), uses.end(), [](int u) { return u > 1; }))
        notes.push_back("meshes placed by several nodes are copied once per node");
    if (std::any_of(placements.begin(), placements.end(), [](const GltfPlacement& p) { return !p.transform.isIdentity(0.0); }))
        notes.push_back("node transforms are applied to the vertices (the node hierarchy is flattened)");
    if (!model.animations.empty()) notes.push_back(std::to_string(model.animations.size()) + " animation(s) are not kept");
    if (!model.materials.empty()) notes.push_back(std::to_string(model.materials.size()) + " material(s) and their textures are not kept");
    if (skinJoints > 0) notes.push_back("the skin (" + std::to_string(skinJoints) + " joint(s)) is not kept");

    // Every placed triangle primitive's attributes and faces, read and checked before the mesh is assembled.
    struct Part {
        std::vector<double> positions, normals, texcoords, colours;
        int colourComponents = 0;
        std::vector<int> corners;  // 3 per kept triangle, local vertex numbers
        std::string name;
        const GltfPlacement* placement = nullptr;
    };
    std::vector<Part> parts;
    long long lineOrPointPrimitives = 0, repeatedCorners = 0, extraSets = 0, morphs = 0;
    for (const GltfPlacement& p : placements) {
        const tinygltf::Mesh& gltfMesh = model.meshes[static_cast<size_t>(p.mesh)];
        for (size_t pi = 0; pi < gltfMesh.primitives.size(); ++pi) {
            const tinygltf::Primitive& primitive = gltfMesh.primitives[pi];
            const std::string meshName = gltfMesh.name.empty() ? "mesh " + std::to_string(p.mesh) : gltfMesh.name;
            const std::string what = "mesh '" + meshName + "', primitive " + std::to_string(pi);
            if (primitive.mode >= TINYGLTF_MODE_POINTS && primitive.mode <= TINYGLTF_MODE_LINE_STRIP) {
                ++lineOrPointPrimitives;
                continue;
            }
            if (primitive.mode < TINYGLTF_MODE_TRIANGLES || primitive.mode > TINYGLTF_MODE_TRIANGLE_FAN)
                return Status::error(name + ": " + what + " has mode " + std::to_string(primitive.mode) + ", which glTF does not define");
            morphs += static_cast<long long>(primitive.targets.size());
            Part part;
            part.name = gltfMesh.primitives.size() > 1 ? meshName + "-" + std::to_string(pi) : meshName;
            part.placement = &p;
            const auto attribute = [&primitive](const char* key) {
                const auto it = primitive.attributes.find(key);
                return it == primitive.attributes.end() ? -1 : it->second;
            };
            for (const auto& [key, accessor] : primitive.attributes)
                if ((key.rfind("TEXCOORD_", 0) == 0 && key != "TEXCOORD_0") || (key.rfind("COLOR_", 0) == 0 && key != "COLOR_0")) ++extraSets;
            if (attribute("POSITION") < 0) return Status::error(name + ": " + what + " has no POSITION attribute");
            size_t count = 0;
            int components = 0;
            // One vertex attribute into values: read and checked, every value finite, and (but POSITION itself)
            // as many elements as POSITION has.
            const auto readAttribute = [&](const char* key, std::vector<int> types, std::vector<double>& values,
                                           int& valueComponents) -> Status {
                const bool position = std::strcmp(key, "POSITION") == 0;
                size_t elements = 0;
                if (Status s = readAccessor(model, attribute(key), {std::string(key) + " of " + what, std::move(types), kFloatLike},
                                            elements, valueComponents, values);
                    !s)
                    return failed(s);
                if (!position && elements != count)
                    return Status::error(name + ": accessor " + std::to_string(attribute(key)) + " (" + key + " of " + what + ") has " +
                                         std::to_string(elements) + " elements, POSITION " + std::to_string(count));
                if (position) count = elements;
                for (size_t i = 0; i < values.size(); ++i)
                    if (!std::isfinite(values[i]))
                        return Status::error(name + ": " + key + " of " + what + " has a non-finite value (element " +
                                             std::to_string(i / static_cast<size_t>(valueComponents)) + ")");
                return Status::success();
            };
            if (Status s = readAttribute("POSITION", {TINYGLTF_TYPE_VEC3}, part.positions, components); !s) return s;
            if (attribute("NORMAL") >= 0)
                if (Status s = readAttribute("NORMAL", {TINYGLTF_TYPE_VEC3}, part.normals, components); !s) return s;
            if (attribute("TEXCOORD_0") >= 0)
                if (Status s = readAttribute("TEXCOORD_0", {TINYGLTF_TYPE_VEC2}, part.texcoords, components); !s) return s;
            if (attribute("COLOR_0") >= 0)
                if (Status s = readAttribute("COLOR_0", {TINYGLTF_TYPE_VEC3, TINYGLTF_TYPE_VEC4}, part.colours, part.colourComponents); !s)
                    return s;
            // The vertex sequence the mode reads (section 3.7.2.1 "Topology types").
            std::vector<double> indexValues;
            size_t sequence = count;
            if (primitive.indices >= 0) {
                if (Status s = readAccessor(model, primitive.indices,
                                            {"indices of " + what, {TINYGLTF_TYPE_SCALAR},
                                             {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                                              TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT},
                                             true},
                                            sequence, components, indexValues);
                    !s)
                    return failed(s);
                for (size_t i = 0; i < sequence; ++i)
                    if (indexValues[i] >= static_cast<double>(count))
                        return Status::error(name + ": index " + std::to_string(i) + " of " + what + " is " +
                                             std::to_string(static_cast<uint64_t>(indexValues[i])) + ", beyond its " +
                                             std::to_string(count) + " vertices");
            }
            const auto vertexAt = [&](size_t i) { return primitive.indices >= 0 ? static_cast<int>(indexValues[i]) : static_cast<int>(i); };
            if (primitive.mode == TINYGLTF_MODE_TRIANGLES && sequence % 3 != 0)
                return Status::error(name + ": " + what + " lists triangles by " + std::to_string(sequence) +
                                     " vertices, which is not a multiple of 3");
            const size_t triangles = primitive.mode == TINYGLTF_MODE_TRIANGLES ? sequence / 3 : sequence >= 3 ? sequence - 2 : 0;
            part.corners.reserve(triangles * 3);
            for (size_t t = 0; t < triangles; ++t) {
                int c[3];
                if (primitive.mode == TINYGLTF_MODE_TRIANGLES) {
                    for (int k = 0; k < 3; ++k) c[k] = vertexAt(3 * t + static_cast<size_t>(k));
                } else if (primitive.mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
                    // p_i = {v_i, v_(i + 1 + i % 2), v_(i + 2 - i % 2)}
                    c[0] = vertexAt(t);
                    c[1] = vertexAt(t + 1 + t % 2);
                    c[2] = vertexAt(t + 2 - t % 2);
                } else {
                    // p_i = {v_(i + 1), v_(i + 2), v_0}
                    c[0] = vertexAt(t + 1);
                    c[1] = vertexAt(t + 2);
                    c[2] = vertexAt(0);
                }
                // A strip or fan repeats a vertex to join its runs: those triangles are joins, not faces. A triangle
                // list's triangle is a face the file holds, kept as every other reader keeps it (a save of a mesh
                // with such a face must load back as the same mesh).
                if (primitive.mode != TINYGLTF_MODE_TRIANGLES && (c[0] == c[1] || c[1] == c[2] || c[0] == c[2])) {
                    ++repeatedCorners;
                    continue;
                }
                part.corners.insert(part.corners.end(), c, c + 3);
            }
            parts.push_back(std::move(part));
        }
    }

    size_t vertexTotal = 0, faceTotal = 0;
    for (const Part& part : parts) {
        vertexTotal += part.positions.size() / 3;
        faceTotal += part.corners.size() / 3;
    }
    if (faceTotal == 0) return noSurfaceError(name, lineOrPointPrimitives > 0, vertexTotal);
    if (Status s = checkVertexTotal(name, vertexTotal); !s) return s;

    ObjMesh mesh;
    mesh.groupNames = {std::string()};
    const bool anyNormals = std::any_of(parts.begin(), parts.end(), [](const Part& p) { return !p.normals.empty(); });
    const bool anyColours = std::any_of(parts.begin(), parts.end(), [](const Part& p) { return !p.colours.empty(); });
    const bool anyTexcoords = std::any_of(parts.begin(), parts.end(), [](const Part& p) { return !p.texcoords.empty(); });
    const Eigen::Index rows = static_cast<Eigen::Index>(vertexTotal);
    mesh.positions.resize(rows, 3);
    adviseHugePages(mesh.positions.data(), static_cast<size_t>(mesh.positions.size()) * sizeof(double));
    if (anyNormals) mesh.vertexNormals = VertexNormals::Zero(rows, 3);
    if (anyColours) mesh.vertexColors = VertexColors::Ones(rows, 4);
    if (anyTexcoords) mesh.texcoords = Texcoords::Zero(rows, 2);
    reserveWithHugePages(mesh.faceStart, faceTotal + 1);
    reserveWithHugePages(mesh.cornerVertex, faceTotal * 3);
    reserveWithHugePages(mesh.cornerTexcoord, faceTotal * 3);
    mesh.faceStart.push_back(0);
    int base = 0;
    for (const Part& part : parts) {
        const Eigen::Matrix4d& m = part.placement->transform;
        const bool identity = m.isIdentity(0.0);
        const Eigen::Matrix3d linear = m.topLeftCorner<3, 3>();
        const double determinant = linear.determinant();
        if (!(std::abs(determinant) > 0.0) || !std::isfinite(determinant))
            return Status::error(name + ": the node transform of " + part.name + " is singular or not finite");
        const Eigen::Matrix3d normalTransform = linear.inverse().transpose();
        const Eigen::Index n = static_cast<Eigen::Index>(part.positions.size() / 3);
        for (Eigen::Index v = 0; v < n; ++v) {
            const size_t at = static_cast<size_t>(v) * 3;
            Eigen::Vector3d x(part.positions[at], part.positions[at + 1], part.positions[at + 2]);
            if (!identity) x = linear * x + m.topRightCorner<3, 1>();
            const Eigen::Index row = base + v;
            if (!x.allFinite()) return Status::error(name + ": vertex " + std::to_string(row) + " of " + part.name + " is not finite once placed");
            mesh.positions.row(row) = x.transpose();
            if (!part.normals.empty()) {
                Eigen::Vector3d normal(part.normals[at], part.normals[at + 1], part.normals[at + 2]);
                if (!identity) {
                    normal = normalTransform * normal;
                    if (normal.norm() > 0.0) normal.normalize();
                    if (!normal.allFinite())
                        return Status::error(name + ": the normal of vertex " + std::to_string(row) + " of " + part.name +
                                             " is not finite once placed");
                }
                mesh.vertexNormals.row(row) = normal.transpose().cast<float>();
            }
            if (!part.colours.empty()) {
                const size_t c = static_cast<size_t>(v) * static_cast<size_t>(part.colourComponents);
                for (int k = 0; k < part.colourComponents; ++k) mesh.vertexColors(row, k) = static_cast<float>(part.colours[c + static_cast<size_t>(k)]);
            }
            if (!part.texcoords.empty()) {
                mesh.texcoords(row, 0) = part.texcoords[static_cast<size_t>(v) * 2];
                mesh.texcoords(row, 1) = 1.0 - part.texcoords[static_cast<size_t>(v) * 2 + 1];
            }
        }
        int group = 0;
        if (parts.size() > 1) {
            mesh.groupNames.push_back(part.name);
            group = static_cast<int>(mesh.groupNames.size()) - 1;
        }
        for (size_t c = 0; c < part.corners.size(); c += 3) {
            for (int k = 0; k < 3; ++k) {
                const int vertex = base + part.corners[c + static_cast<size_t>(k)];
                mesh.cornerVertex.push_back(vertex);
                mesh.cornerTexcoord.push_back(part.texcoords.empty() ? -1 : vertex);
            }
            mesh.faceGroup.push_back(group);
            mesh.faceStart.push_back(static_cast<int>(mesh.cornerVertex.size()));
        }
        base += static_cast<int>(n);
    }
    mesh.faceMaterial.assign(mesh.faceGroup.size(), -1);
    mesh.cornerNormal.assign(mesh.cornerVertex.size(), -1);
    if (lineOrPointPrimitives > 0)
        notes.push_back(std::to_string(lineOrPointPrimitives) + " point or line primitive(s) are not kept (not a surface)");
    if (repeatedCorners > 0)
        notes.push_back(std::to_string(repeatedCorners) + " strip or fan triangle(s) whose corners repeat a vertex (joins, no area) are not kept");
    if (extraSets > 0) notes.push_back("only the first colour and texture coordinate sets are kept");
    if (morphs > 0) notes.push_back(std::to_string(morphs) + " morph target(s) are not kept");
    out = std::move(mesh);
    return Status::success();
}

}  // namespace sculpt::io
